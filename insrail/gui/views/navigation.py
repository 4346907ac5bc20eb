"""Navigation view: the trajectory's time series with their 1-sigma bands, one plot per quantity."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import pyqtgraph as pg
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QHBoxLayout, QListWidget, QListWidgetItem, QWidget

from insrail.gui import plotstyle
from insrail.gui.bands import EnvelopeItem, EnvelopeLine
from insrail.gui.lazy import DrawWhenShown
from insrail.project.plotdata import (
    Envelope,
    NavSeries,
    series_bands,
    series_lines,
)
from insrail.gui.translation import tr

DEFAULT_SERIES = ("position", "velocity", "attitude", "position_sigma")


class NavigationView(DrawWhenShown, QWidget):
    """Drawn when shown (a hidden tab costs nothing); the curves and their 1-sigma bands at screen
    resolution (a frame draws a few points per pixel column, not the survey's epochs)."""

    def __init__(self, parent=None):
        super().__init__(parent)
        self.choice = QListWidget()
        self.choice.setMaximumWidth(220)
        self.plots = pg.GraphicsLayoutWidget()
        self.items: dict[str, pg.PlotItem] = {}
        layout = QHBoxLayout(self)
        layout.setContentsMargins(2, 2, 2, 2)
        layout.addWidget(self.choice)
        layout.addWidget(self.plots, 1)
        self._time = np.zeros(0)
        self._series: tuple[NavSeries, ...] = ()
        self._bands: dict[str, tuple[tuple[Envelope, ...], ...]] = {}
        self._lines: dict[str, tuple[tuple[Envelope, ...], ...]] = {}
        self.choice.itemChanged.connect(lambda _item: self.request_draw())

    def set_series(self, time_s: np.ndarray, series: Sequence[NavSeries],
                   bands: Mapping[str, tuple[tuple[Envelope, ...], ...]] | None = None,
                   lines: Mapping[str, tuple[tuple[Envelope, ...], ...]] | None = None) -> None:
        """The series to offer, their 1-sigma envelopes (:func:`series_bands`) and the series as
        envelopes (:func:`series_lines`), computed here if not given: the main window computes them
        in its loader thread."""
        self._time, self._series = np.asarray(time_s), tuple(series)
        self._bands = dict(bands) if bands is not None else series_bands(self._time, self._series)
        self._lines = dict(lines) if lines is not None else series_lines(self._time, self._series)
        self.choice.blockSignals(True)
        self.choice.clear()
        for s in self._series:
            entry = QListWidgetItem(f"{s.title} [{s.unit}]")
            entry.setData(Qt.UserRole, s.key)
            entry.setCheckState(Qt.Checked if s.key in DEFAULT_SERIES else Qt.Unchecked)
            self.choice.addItem(entry)
        self.choice.blockSignals(False)
        self.request_draw(now=not self._series)

    def clear(self) -> None:
        """Nothing shown (another project or a survey without results)."""
        self.set_series(np.zeros(0), (), {}, {})

    def shown(self) -> list[str]:
        return [self.choice.item(i).data(Qt.UserRole) for i in range(self.choice.count())
                if self.choice.item(i).checkState() == Qt.Checked]

    def _draw(self) -> None:
        self.plots.clear()
        self.items.clear()
        shown = [s for s in self._series if s.key in self.shown()]
        for row, s in enumerate(shown):
            item = self.plots.addPlot(row=row, col=0)
            plotstyle.make_fluid(item)
            title = f"{s.title} [{s.unit}]" + (tr(", 1σ band") if s.sigma is not None else "")
            item.setTitle(plotstyle.titled(title, s.labels), size="8pt")
            item.setLabel("left", s.unit)
            item.getAxis("left").setWidth(56)
            for k in range(len(s.labels)):
                if s.sigma is not None:
                    colour = pg.mkColor(plotstyle.COLOURS[k % len(plotstyle.COLOURS)])
                    colour.setAlpha(70)
                    band = EnvelopeItem(self._bands[s.key][k], colour)
                    band.setZValue(-5)
                    item.addItem(band)
                # no line (and no band) across a gap in the series' own epochs (a GNSS outage): one envelope a run
                item.addItem(EnvelopeLine(self._lines[s.key][k], plotstyle.pen(k)))
            if row:
                item.setXLink(self.items[shown[0].key])
            item.getAxis("bottom").setStyle(showValues=row == len(shown) - 1)
            if row == len(shown) - 1:
                item.setLabel("bottom", tr("GPS time of week [s]"))
            self.items[s.key] = item
