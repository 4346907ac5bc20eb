"""A shaded band (1-sigma around a curve), or a curve, drawn at screen resolution.

pyqtgraph's FillBetweenItem builds one polygon over every sample of both edges on each change: over
the 280 905 epochs of a 1.2 km survey it held the GUI thread for most of a minute. This item asks
the core's :class:`~insrail.project.plotdata.Envelope` for the min/max of the band per pixel column
of the visible range whenever the view moves or is resized, so a frame draws a few thousand points
whatever the length of the survey.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pyqtgraph as pg
from PySide6.QtCore import QRectF, Qt
from PySide6.QtGui import QPainterPath

from insrail.project.plotdata import Envelope

#: Bins asked for when the view box fits its range to the band (any coarse figure will do).
BOUNDS_COLUMNS = 256


class EnvelopeItem(pg.GraphicsObject):
    """The band of one or more contiguous runs (``parts``: one per run between gaps)."""

    def __init__(self, parts: Sequence[Envelope], brush):
        super().__init__()
        self.parts = tuple(p for p in parts if len(p.x))
        self.brush = pg.mkBrush(brush)
        self.path = QPainterPath()
        self._drawn_for: tuple | None = None
        self.drawn_points = 0  # points of the last path (what a frame costs; the benchmark reads it)

    # the view box tells the item when its range or size changes
    def viewRangeChanged(self) -> None:
        self._rebuild()

    def viewTransformChanged(self) -> None:
        super().viewTransformChanged()
        self._rebuild()

    def _rebuild(self) -> None:
        view = self.getViewBox()
        if not isinstance(view, pg.ViewBox) or not self.parts:  # not yet (or no longer) in a plot
            return
        (x_from, x_to), _ = view.viewRange()
        columns = max(int(view.width()), 1)
        key = (x_from, x_to, columns)
        if key == self._drawn_for:
            return
        self._drawn_for = key
        path = QPainterPath()
        points = 0
        for part in self.parts:
            x, low, high = part.visible(x_from, x_to, columns)
            if len(x) < 2:
                continue
            outline, drawn = self._outline(x, low, high)
            path.addPath(outline)
            points += drawn
        self.prepareGeometryChange()
        self.path = path
        self.drawn_points = points
        self.update()

    def _outline(self, x: np.ndarray, low: np.ndarray, high: np.ndarray) -> tuple[QPainterPath, int]:
        """The path of the visible bins and its number of points (a band: around its finite bins)."""
        keep = np.isfinite(low) & np.isfinite(high)
        x, low, high = x[keep], low[keep], high[keep]
        outline = pg.arrayToQPath(np.concatenate([x, x[::-1]]), np.concatenate([high, low[::-1]]))
        if len(x) >= 2:
            outline.closeSubpath()
        return outline, 2 * len(x)

    def boundingRect(self) -> QRectF:
        return self.path.boundingRect()

    def paint(self, painter, *_args) -> None:
        painter.setPen(Qt.NoPen)
        painter.setBrush(self.brush)
        painter.drawPath(self.path)

    def dataBounds(self, axis: int, frac: float = 1.0, orthoRange=None):
        """The band's extent, so that fitting the view to the data shows the whole band."""
        if not self.parts:
            return None, None
        if axis == 0:
            return min(float(p.x[0]) for p in self.parts), max(float(p.x[-1]) for p in self.parts)
        x_from, x_to = orthoRange if orthoRange is not None else (-np.inf, np.inf)
        lows, highs = [], []
        for part in self.parts:
            _, low, high = part.visible(x_from, x_to, BOUNDS_COLUMNS)
            if len(low):
                lows.append(np.nanmin(low))
                highs.append(np.nanmax(high))
        finite = [v for v in lows + highs if np.isfinite(v)]
        if not finite:
            return None, None
        return float(np.nanmin(lows)), float(np.nanmax(highs))


class EnvelopeLine(EnvelopeItem):
    """A curve (an envelope of ``low == high``: the series itself) drawn through the min and the max
    of each pixel column, as pyqtgraph's peak downsampling would, but from the core's pyramid: the
    cost of a frame follows the plot's width, not the survey's millions of epochs (nor its length:
    a pan asks for a slice of one level, where pyqtgraph's PlotDataItem clips, downsamples and
    searches the bounds of the visible samples again)."""

    def __init__(self, parts: Sequence[Envelope], pen):
        super().__init__(parts, (0, 0, 0, 0))
        self.pen = pg.mkPen(pen)

    def _outline(self, x: np.ndarray, low: np.ndarray, high: np.ndarray) -> tuple[QPainterPath, int]:
        """Through the min and the max of each bin, or through each sample once where the view is
        zoomed in so far that it gets the samples themselves (min = max: half the points to stroke);
        a bin without a finite value breaks the line (a stretch without values, e.g. where a chord
        reaches past the data, draws nothing)."""
        if np.array_equal(low, high, equal_nan=True):
            y = low
        else:
            x, y = np.repeat(x, 2), np.column_stack([low, high]).ravel()
        return pg.arrayToQPath(x, y, connect="finite"), int(np.count_nonzero(np.isfinite(y)))

    def paint(self, painter, *_args) -> None:
        painter.setPen(self.pen)
        painter.setBrush(Qt.NoBrush)
        painter.drawPath(self.path)
