"""Plan view: trajectory, centreline, GNSS points and outages, benchmarks; equal aspect."""

from __future__ import annotations

import numpy as np
import pyqtgraph as pg
from PySide6.QtCore import QRectF, Qt
from PySide6.QtGui import QTransform
from PySide6.QtWidgets import QGraphicsItem, QGraphicsSimpleTextItem

from insrail.gui import plotstyle
from insrail.gui.lazy import DrawWhenShown
from insrail.project.plotdata import PlanData
from insrail.gui.translation import tr

#: The GNSS fixes' dots [px].
GNSS_DOT_PX = 5


class PointsItem(pg.GraphicsObject):
    """Many points of one colour as dots of a fixed size in pixels, painted in one QPainter call.
    pyqtgraph's scatter item rebuilds a symbol per point whenever the zoom changes: with the GNSS
    fixes of a 10 km survey (9 000) that was 100-150 ms of CPU per zoom frame."""

    def __init__(self, x: np.ndarray, y: np.ndarray, colour: str, size_px: float):
        super().__init__()
        self._x, self._y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
        self._pen = pg.mkPen(colour, width=size_px)
        self._pen.setCosmetic(True)  # the width in pixels, whatever the zoom
        self._pen.setCapStyle(Qt.RoundCap)
        self.drawn_points = 0  # dots of the last paint (one per pixel at most)
        finite = np.isfinite(self._x) & np.isfinite(self._y)
        if finite.any():
            x, y = self._x[finite], self._y[finite]
            self._bounds = QRectF(x.min(), y.min(), x.max() - x.min(), y.max() - y.min())
        else:
            self._bounds = QRectF()

    def getOriginalDataset(self) -> tuple[np.ndarray, np.ndarray]:
        return self._x, self._y

    def dataBounds(self, axis: int, frac: float = 1.0, orthoRange=None):
        if self._bounds.isNull():
            return None, None
        return ((self._bounds.left(), self._bounds.right()) if axis == 0
                else (self._bounds.top(), self._bounds.bottom()))

    def boundingRect(self) -> QRectF:
        return self._bounds

    def paint(self, painter, *_args) -> None:
        """One dot per pixel the points fall on, and none off the screen: drawing the 9 000 fixes of a
        10 km survey as dots of 5 px each frame cost most of a plan frame."""
        painter.setPen(self._pen)
        t, screen = painter.transform(), painter.viewport()  # the rectangle painted, in pixels
        column = np.rint(t.m11() * self._x + t.m21() * self._y + t.dx())
        row = np.rint(t.m12() * self._x + t.m22() * self._y + t.dy())
        margin = self._pen.widthF()
        on_screen = ((column >= -margin) & (column <= screen.width() + margin)
                     & (row >= -margin) & (row <= screen.height() + margin))
        index = np.flatnonzero(on_screen)
        _, first = np.unique(column[index] * (screen.height() + 2 * margin + 1) + (row[index] + margin),
                             return_index=True)
        shown = index[first]
        self.drawn_points = len(shown)
        if not len(shown):
            return
        painter.drawPoints(pg.functions.arrayToQPolygonF(self._x[shown], self._y[shown]))


class PlanView(DrawWhenShown, pg.PlotWidget):
    """Coordinates are drawn relative to a whole-kilometre origin (named in the axis labels):
    engineering eastings and northings of millions of metres lose precision in Qt's float painter.
    Drawn when shown; sleepers marked meanwhile are ringed then."""

    def __init__(self, parent=None):
        super().__init__(parent)
        self.item = self.getPlotItem()
        self.item.setAspectLocked(True)
        # no grid: pyqtgraph's grid cost 3x the time of a frame over a 10 km survey (46 -> 15 ms CPU)
        # no clip-to-view or downsampling: both assume x sorted, a line in the plane is not (the core thins it)
        self.origin = np.zeros(2)
        self.curves: dict[str, pg.PlotDataItem] = {}
        self._labels: list[QGraphicsSimpleTextItem] = []  # the benchmarks' names
        self.data: PlanData | None = None
        self._marked = np.zeros(0, int)

    def set_data(self, data: PlanData | None) -> None:
        """The survey to draw (None: nothing, another project or a survey without results)."""
        self.data = data
        self._marked = np.zeros(0, int)
        self.request_draw(now=data is None)

    def clear_data(self) -> None:
        self.set_data(None)

    def _draw(self) -> None:
        item, data = self.item, self.data
        item.clear()
        self.curves, self._labels = {}, []
        if item.legend is not None:
            item.legend.clear()
        else:
            item.addLegend(offset=(10, 10), brush=(255, 255, 255, 200))
        if data is None:
            return
        self.origin = np.floor(data.trajectory_en_m[0] / 1000.0) * 1000.0

        def local(points: np.ndarray) -> np.ndarray:  # display offset only
            return points - self.origin

        self.curves = {"trajectory": item.plot(*local(data.trajectory_en_m).T, pen=pg.mkPen("#A0A0A0", width=1),
                                               name=tr("trajectory (IMU)")),
                       "gnss": PointsItem(*local(data.gnss_en_m).T, plotstyle.COLOURS[2], GNSS_DOT_PX)}
        item.addItem(self.curves["gnss"])
        item.legend.addItem(pg.ScatterPlotItem(symbol="o", size=GNSS_DOT_PX, pen=None, brush=plotstyle.COLOURS[2]),
                            "GNSS")  # the legend's sample only
        self.curves["centreline"] = item.plot(*local(data.centreline_en_m).T, pen=plotstyle.pen(0, 2),
                                              name="centreline")
        for index, outage in enumerate(data.outages_en_m):
            self.curves[f"outage{index}"] = item.plot(*local(outage).T, pen=pg.mkPen("#C00000", width=4),
                                                      name=tr("GNSS outage") if index == 0 else None)
        if len(data.benchmark_en_m):
            self.curves["benchmarks"] = item.plot(*local(data.benchmark_en_m).T, pen=None, symbol="t1", symbolSize=12,
                                                  symbolBrush=plotstyle.COLOURS[4], name="benchmarks")
            for name, (east, north) in zip(data.benchmark_ids, local(data.benchmark_en_m)):
                # placed by Qt at every zoom (a pyqtgraph TextItem recomputes its transform in Python
                # each frame: 44 of them were a third of a plan frame)
                text = QGraphicsSimpleTextItem(name)
                text.setFlag(QGraphicsItem.ItemIgnoresTransformations)
                text.setTransform(QTransform.fromTranslate(0.0, -text.boundingRect().height()))  # above the mark
                text.setPos(east, north)
                item.addItem(text, ignoreBounds=True)
                self._labels.append(text)  # not a QObject: kept alive from Python while shown
        item.setLabel("bottom", f"E − {self.origin[0]:.0f} m")
        item.setLabel("left", f"N − {self.origin[1]:.0f} m")
        item.autoRange()
        if len(self._marked):
            self._ring(self._marked)

    def mark_sleepers(self, rows: np.ndarray) -> None:
        """Ring the centreline at the given sleeper rows (an exceedance picked in the track view)."""
        if not len(rows):
            return
        self._marked = np.asarray(rows)
        if not self.stale and "centreline" in self.curves:
            self._ring(self._marked)

    def _ring(self, rows: np.ndarray) -> None:
        east, north = self.curves["centreline"].getOriginalDataset()
        if "marker" not in self.curves:
            self.curves["marker"] = self.item.plot([], [], pen=pg.mkPen("#C00000", width=6), symbol="o",
                                                   symbolSize=16, symbolBrush=None,
                                                   symbolPen=pg.mkPen("#C00000", width=2))
            self.curves["marker"].setZValue(10)
        self.curves["marker"].setData(east[rows], north[rows])
