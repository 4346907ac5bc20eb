"""Repeatability view: one parameter of several runs overlaid along chainage, chosen by its
display name (:func:`insrail.names.column_name`; the check channels named from the project's
tolerance profile)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import pyqtgraph as pg
from PySide6.QtWidgets import QComboBox, QHBoxLayout, QLabel, QVBoxLayout, QWidget

from insrail.gui import plotstyle
from insrail.gui.lazy import DrawWhenShown
from insrail.names import CheckLike, UnknownName, column_name
from insrail.gui.translation import tr

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
        self.item.setLabel("bottom", tr("chainage [m]"))
        top = QHBoxLayout()
        top.addWidget(QLabel(tr("Parameter:")))
        top.addWidget(self.parameter)
        top.addWidget(self.note, 1)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(2, 2, 2, 2)
        layout.addLayout(top)
        layout.addWidget(self.plot, 1)
        self._runs: Mapping[str, tuple[np.ndarray, Mapping[str, np.ndarray]]] = {}
        self.parameter.currentIndexChanged.connect(lambda _index: self.request_draw())

    def set_runs(self, runs: Mapping[str, tuple[np.ndarray, Mapping[str, np.ndarray]]],
                 checks: Sequence[CheckLike] = ()) -> None:
        """``checks``: the tolerance profile's checks, which name the check channels' columns."""
        self._runs = runs
        common = None
        for _station, columns in runs.values():
            names = [n for n in columns if n.endswith(_UNITS)]
            common = names if common is None else [n for n in common if n in names]
        current = self.parameter.currentData()
        self.parameter.blockSignals(True)
        self.parameter.clear()
        for column in common or []:
            try:
                text = column_name(column, checks).with_unit
            except UnknownName:  # a check the profile no longer has: still comparable, by its column
                text = column
            self.parameter.addItem(text, column)
        self.parameter.blockSignals(False)
        if current is not None and self.parameter.findData(current) >= 0:
            self.parameter.setCurrentIndex(self.parameter.findData(current))
        self.note.setText((tr("{count} runs") if len(runs) != 1 else tr("{count} run")).format(count=len(runs))
                          + ("" if len(runs) > 1 else tr(": process more surveys of this track to compare them")))
        self.request_draw(now=not runs)

    def _draw(self) -> None:
        item = self.item
        item.clear()
        if item.legend is None:
            item.addLegend(offset=(-4, 2), brush=(255, 255, 255, 200))
        item.legend.clear()
        column = self.parameter.currentData()
        if not column:
            return
        for index, (name, (station, columns)) in enumerate(self._runs.items()):
            item.plot(station, columns[column], pen=plotstyle.pen(index), name=name)
        item.setLabel("left", self.parameter.currentText())
        item.autoRange()
