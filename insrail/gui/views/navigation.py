"""Navigation view: the trajectory's time series with their 1-sigma bands, one plot per quantity."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pyqtgraph as pg
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QHBoxLayout, QListWidget, QListWidgetItem, QWidget

from insrail.gui import plotstyle
from insrail.project.plotdata import NavSeries

DEFAULT_SERIES = ("position", "velocity", "attitude", "position_sigma")


class NavigationView(QWidget):
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
        self.choice.itemChanged.connect(lambda _item: self._draw())

    def set_series(self, time_s: np.ndarray, series: Sequence[NavSeries]) -> None:
        self._time, self._series = np.asarray(time_s), tuple(series)
        self.choice.blockSignals(True)
        self.choice.clear()
        for s in self._series:
            entry = QListWidgetItem(f"{s.title} [{s.unit}]")
            entry.setData(Qt.UserRole, s.key)
            entry.setCheckState(Qt.Checked if s.key in DEFAULT_SERIES else Qt.Unchecked)
            self.choice.addItem(entry)
        self.choice.blockSignals(False)
        self._draw()

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
            title = f"{s.title} [{s.unit}]" + (", 1σ band" if s.sigma is not None else "")
            item.setTitle(plotstyle.titled(title, s.labels), size="8pt")
            item.setLabel("left", s.unit)
            item.getAxis("left").setWidth(56)
            time = self._time if s.time_s is None else s.time_s
            # no line across a gap in the series' own epochs (a GNSS outage)
            step = np.diff(time)
            connect = (np.append(step <= 3.0 * np.median(step), False) if s.time_s is not None and len(time) > 2
                       else "all")
            for k in range(len(s.labels)):
                value = s.values[:, k]
                if s.sigma is not None:
                    # the band's edges are drawn (invisibly): a fill between hidden curves is empty
                    below, above = (item.plot(time, value + sign * s.sigma[:, k], pen=plotstyle.INVISIBLE_PEN,
                                              connect=connect, autoDownsampleFactor=plotstyle.SAMPLES_PER_PIXEL)
                                    for sign in (-1, 1))
                    colour = pg.mkColor(plotstyle.COLOURS[k % len(plotstyle.COLOURS)])
                    colour.setAlpha(70)
                    item.addItem(pg.FillBetweenItem(below, above, brush=colour))
                item.plot(time, value, pen=plotstyle.pen(k), connect=connect,
                          autoDownsampleFactor=plotstyle.SAMPLES_PER_PIXEL)
            if row:
                item.setXLink(self.items[shown[0].key])
            item.getAxis("bottom").setStyle(showValues=row == len(shown) - 1)
            if row == len(shown) - 1:
                item.setLabel("bottom", "GPS time of week [s]")
            self.items[s.key] = item
