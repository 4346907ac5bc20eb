"""Repeatability view: one parameter of several runs overlaid along chainage."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pyqtgraph as pg
from PySide6.QtWidgets import QComboBox, QHBoxLayout, QLabel, QVBoxLayout, QWidget

from insrail.gui import plotstyle
from insrail.gui.lazy import DrawWhenShown

#: Columns worth overlaying: values in mm or ratios (not coordinates, times, flags).
_UNITS = ("_mm", "_ratio")


class RepeatabilityView(DrawWhenShown, QWidget):
    """``set_runs({run name: (station_m, {column: values})})``: plain arrays per run; drawn when shown."""

    def __init__(self, parent=None):
        super().__init__(parent)
        self.parameter = QComboBox()
        self.parameter.setMinimumWidth(320)
        self.note = QLabel()
        self.plot = pg.PlotWidget()
        self.item = self.plot.getPlotItem()
        plotstyle.make_fluid(self.item)
        # no grid: pyqtgraph's grid triples the time of a frame
        self.item.setLabel("bottom", "chainage [m]")
        top = QHBoxLayout()
        top.addWidget(QLabel("Parameter:"))
        top.addWidget(self.parameter)
        top.addWidget(self.note, 1)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(2, 2, 2, 2)
        layout.addLayout(top)
        layout.addWidget(self.plot, 1)
        self._runs: Mapping[str, tuple[np.ndarray, Mapping[str, np.ndarray]]] = {}
        self.parameter.currentTextChanged.connect(lambda _text: self.request_draw())

    def set_runs(self, runs: Mapping[str, tuple[np.ndarray, Mapping[str, np.ndarray]]]) -> None:
        self._runs = runs
        common = None
        for _station, columns in runs.values():
            names = [n for n in columns if n.endswith(_UNITS)]
            common = names if common is None else [n for n in common if n in names]
        current = self.parameter.currentText()
        self.parameter.blockSignals(True)
        self.parameter.clear()
        self.parameter.addItems(common or [])
        self.parameter.blockSignals(False)
        if current and current in (common or []):
            self.parameter.setCurrentText(current)
        self.note.setText(f"{len(runs)} run{'s' if len(runs) != 1 else ''}"
                          + ("" if len(runs) > 1 else ": process more surveys of this track to compare them"))
        self.request_draw(now=not runs)

    def _draw(self) -> None:
        item = self.item
        item.clear()
        if item.legend is None:
            item.addLegend(offset=(-4, 2), brush=(255, 255, 255, 200))
        item.legend.clear()
        column = self.parameter.currentText()
        if not column:
            return
        for index, (name, (station, columns)) in enumerate(self._runs.items()):
            item.plot(station, columns[column], pen=plotstyle.pen(index), name=name)
        item.setLabel("left", column)
        item.autoRange()
