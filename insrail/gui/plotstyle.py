"""One look for every plot: white background, a colour cycle that survives print, shared pens."""

from __future__ import annotations

import pyqtgraph as pg
from PySide6.QtCore import Qt
from PySide6.QtGui import QBrush, QColor

#: Colour-blind-safe cycle (Okabe-Ito), in the order the curves of a plot are drawn.
COLOURS = ("#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000")
LIMIT_PEN = pg.mkPen("#C00000", width=1, style=Qt.DashLine)
ZERO_PEN = pg.mkPen("#C8C8C8", width=1)
CROSSHAIR_PEN = pg.mkPen("#606060", width=1)
INVISIBLE_PEN = pg.mkPen((0, 0, 0, 0))
# The survey's predicted accuracy (+-3 sigma per section) behind the curves.
BAND_BRUSH = pg.mkBrush(110, 110, 110, 55)
#: sleepers not valid (not assessed), behind everything: hatched in grey, apart from the predicted-accuracy band's
#: flat grey (the PDF's charts and the workbook's rows grey them)
INVALID_BRUSH = QBrush(QColor("#9a9a9a"), Qt.BDiagPattern)
BAND_LEGEND_COLOUR = "#8a8a8a"


def configure() -> None:
    pg.setConfigOptions(background="w", foreground="k", antialias=False)


def pen(index: int, width: float = 1.0):
    return pg.mkPen(COLOURS[index % len(COLOURS)], width=width)


def make_fluid(item: pg.PlotItem) -> None:
    """Large data stays interactive: draw only what is visible, peak-preserving downsampling."""
    item.setDownsampling(auto=True, mode="peak")
    item.setClipToView(True)
    for side in ("left", "bottom", "right", "top"):  # no automatic "(x1000)" scaling: it also re-renders the label every frame
        item.getAxis(side).enableAutoSIPrefix(False)
    # Major and minor ticks only on the value axis: its third level put some 35 ticks on a 150 px
    # plot, and laying them out is most of what a zoom costs an axis (once per plot in view).
    item.getAxis("left").setStyle(maxTickLevel=1)


def titled(title: str, labels, band: str = "") -> str:
    """A plot title naming its curves in their colours (a legend box would cover short plots) and,
    if given, the shaded band."""
    keys = "&nbsp;&nbsp;".join(f"<span style='color:{COLOURS[i % len(COLOURS)]}'>━ {label}</span>"
                               for i, label in enumerate(labels) if label)  # one unnamed curve: the title names it
    shaded = f"&nbsp;&nbsp;<span style='color:{BAND_LEGEND_COLOUR}'>▮ {band}</span>" if band else ""
    return f"<b>{title}</b>&nbsp;&nbsp;&nbsp;{keys}{shaded}"
