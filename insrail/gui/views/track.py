"""Track view: plots stacked along chainage on one shared x axis, a crosshair read-out of every
value at the sleeper under the cursor, and the exceedance table (a click zooms every plot there)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np
import pyqtgraph as pg
from PySide6.QtCore import Qt, Signal
from PySide6.QtWidgets import (
    QAbstractItemView,
    QHBoxLayout,
    QHeaderView,
    QLabel,
    QMenu,
    QSplitter,
    QTableWidget,
    QTableWidgetItem,
    QToolButton,
    QVBoxLayout,
    QWidget,
)

from insrail.gui import plotstyle
from insrail.gui.lazy import DrawWhenShown
from insrail.project.plotdata import (
    BAND_SIGMAS,
    ChainagePlot,
    QualityBand,
    exceedance_window,
)
from insrail.project.results import ExceedanceRow

#: Checks whose plot starts hidden: each repeats what another plot shows (gauge, cant) or is a
#: shorter-chord version of one shown; the Plots menu brings them back.
HIDDEN_KINDS = ("gauge_deviation", "gauge_change_rate", "versine", "cross_level")
READOUT_HINT = "Move the mouse over the plots to read every value at a sleeper."
EXCEEDANCE_COLUMNS = ("Check", "Rail", "Direction", "From [m]", "To [m]", "Peak", "Limit", "Unit", "Sleepers")


class SortableItem(QTableWidgetItem):
    """A cell that sorts by a number (peaks by magnitude) when it has one, else by its text."""

    def __init__(self, text: str, key: float | None):
        super().__init__(text)
        self.key = key

    def __lt__(self, other) -> bool:
        if self.key is not None and getattr(other, "key", None) is not None:
            return self.key < other.key
        return self.text() < other.text()


class ChainagePlots(pg.GraphicsLayoutWidget):
    """Stacked plots along chainage sharing the x axis of the top one, with a crosshair."""

    cursorMoved = Signal(float)

    def __init__(self, parent=None):
        super().__init__(parent)
        self.plots: dict[str, pg.PlotItem] = {}
        self._crosshairs: list[pg.InfiniteLine] = []
        self._regions: list[pg.LinearRegionItem] = []
        self._mouse = pg.SignalProxy(self.scene().sigMouseMoved, rateLimit=60, slot=self._mouse_moved)

    def set_data(self, station_m: np.ndarray, columns: Mapping[str, np.ndarray], plots: Sequence[ChainagePlot],
                 visible: set[str], bands: Mapping[str, QualityBand] | None = None) -> None:
        self.clear()
        self.plots.clear()
        self._crosshairs.clear()
        self._regions.clear()
        shown = [p for p in plots if p.key in visible]
        for row, spec in enumerate(shown):
            item = self.addPlot(row=row, col=0)
            plotstyle.make_fluid(item)
            # A zero line instead of a grid: pyqtgraph's grid triples the time per frame.
            item.addItem(pg.InfiniteLine(0.0, angle=0, pen=plotstyle.ZERO_PEN), ignoreBounds=True)
            band = (bands or {}).get(spec.key)
            item.setTitle(plotstyle.titled(f"{spec.title} [{spec.unit}]", [label for label, _ in spec.curves],
                                           f"±{BAND_SIGMAS:g}σ predicted" if band is not None else ""), size="8pt")
            if band is not None:
                edges = [pg.PlotCurveItem(band.station_m, sign * band.half_width, pen=None) for sign in (1.0, -1.0)]
                fill = pg.FillBetweenItem(*edges, brush=plotstyle.BAND_BRUSH)
                fill.setZValue(-5)
                item.addItem(fill, ignoreBounds=True)  # the data, not the band, set the view
            item.getAxis("left").setWidth(48)
            for index, (label, column) in enumerate(spec.curves):
                item.plot(station_m, spec.scale * columns[column], pen=plotstyle.pen(index),
                          autoDownsampleFactor=plotstyle.SAMPLES_PER_PIXEL)
            for limit in (spec.lower, spec.upper):
                if limit is not None:
                    item.addItem(pg.InfiniteLine(limit, angle=0, pen=plotstyle.LIMIT_PEN))
            crosshair = pg.InfiniteLine(angle=90, pen=plotstyle.CROSSHAIR_PEN)
            item.addItem(crosshair, ignoreBounds=True)
            region = pg.LinearRegionItem(movable=False, brush=(255, 200, 0, 60), pen=pg.mkPen(None))
            region.setZValue(-10)
            region.hide()
            item.addItem(region, ignoreBounds=True)
            self._crosshairs.append(crosshair)
            self._regions.append(region)
            item.vb.setAutoVisible(y=True)  # y fits what is visible after a zoom along chainage
            if row:
                item.setXLink(next(iter(self.plots.values())))
            is_bottom = row == len(shown) - 1
            item.getAxis("bottom").setStyle(showValues=is_bottom)
            if is_bottom:
                item.setLabel("bottom", "chainage [m]")
            self.plots[spec.key] = item

    def x_range(self) -> tuple[float, float]:
        first = next(iter(self.plots.values()))
        return tuple(first.vb.viewRange()[0])

    def set_x_range(self, low: float, high: float) -> None:
        if self.plots:
            next(iter(self.plots.values())).setXRange(low, high, padding=0.0)

    def highlight(self, low: float, high: float) -> None:
        for region in self._regions:
            region.setRegion((low, high))
            region.show()

    def set_cursor(self, station: float) -> None:
        for line in self._crosshairs:
            line.setPos(station)

    def _mouse_moved(self, event) -> None:
        position = event[0]
        for item in self.plots.values():
            if item.sceneBoundingRect().contains(position):
                station = item.vb.mapSceneToView(position).x()
                self.set_cursor(station)
                self.cursorMoved.emit(station)
                return


class TrackView(DrawWhenShown, QWidget):
    """The chainage plots, their read-out line and the exceedance table under them."""

    exceedanceSelected = Signal(int, int)  # first and last sleeper number of the exceedance shown

    def __init__(self, parent=None):
        super().__init__(parent)
        self.plots = ChainagePlots()
        self.readout = QLabel(READOUT_HINT)
        self.readout.setTextFormat(Qt.RichText)
        self.readout.setWordWrap(True)
        self.readout.setTextInteractionFlags(Qt.TextSelectableByMouse)
        self.choose_plots = QToolButton(text="Plots")
        self.choose_plots.setPopupMode(QToolButton.InstantPopup)
        self.choose_plots.setMenu(QMenu(self.choose_plots))
        self.exceedances = QTableWidget(0, len(EXCEEDANCE_COLUMNS))
        self.exceedances.setHorizontalHeaderLabels(EXCEEDANCE_COLUMNS)
        self.exceedances.setSelectionBehavior(QAbstractItemView.SelectRows)
        self.exceedances.setEditTriggers(QAbstractItemView.NoEditTriggers)
        self.exceedances.verticalHeader().setVisible(False)
        self.exceedances.horizontalHeader().setSectionResizeMode(QHeaderView.ResizeToContents)
        self.exceedances.horizontalHeader().setStretchLastSection(True)
        self.exceedances.cellClicked.connect(lambda row, _column: self.zoom_to_exceedance(self._exceedance_at(row)))
        self.exceedances.currentCellChanged.connect(lambda row, *_: self.zoom_to_exceedance(self._exceedance_at(row)))

        top = QHBoxLayout()
        top.addWidget(self.readout, 1)
        top.addWidget(self.choose_plots, 0, Qt.AlignTop)
        upper = QWidget()
        upper_layout = QVBoxLayout(upper)
        upper_layout.setContentsMargins(0, 0, 0, 0)
        upper_layout.addLayout(top)
        upper_layout.addWidget(self.plots, 1)
        splitter = QSplitter(Qt.Vertical)
        splitter.addWidget(upper)
        splitter.addWidget(self.exceedances)
        splitter.setStretchFactor(0, 4)
        splitter.setStretchFactor(1, 1)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(2, 2, 2, 2)
        layout.addWidget(splitter)

        self._station = np.zeros(0)
        self._labels: tuple[str, ...] = ()
        self._numbers = np.zeros(0, int)
        self._columns: Mapping[str, np.ndarray] = {}
        self._specs: tuple[ChainagePlot, ...] = ()
        self._visible: set[str] = set()
        self._rows: tuple[ExceedanceRow, ...] = ()
        self._bands: dict[str, QualityBand] = {}
        self.plots.cursorMoved.connect(self.show_values_at)

    def set_results(self, station_m: np.ndarray, number: np.ndarray, label: Sequence[str],
                    columns: Mapping[str, np.ndarray], plots: Sequence[ChainagePlot],
                    exceedances: Sequence[ExceedanceRow], bands: Mapping[str, QualityBand] | None = None) -> None:
        """Plain arrays (one per sleeper, in chainage order), the plots to draw from them and the
        predicted-accuracy bands of some plots (by plot key)."""
        self._station, self._numbers, self._labels = np.asarray(station_m), np.asarray(number), tuple(label)
        self._columns, self._specs, self._rows = columns, tuple(plots), tuple(exceedances)
        self._bands = dict(bands or {})
        self._visible = {p.key for p in plots if p.kind not in HIDDEN_KINDS}
        menu = self.choose_plots.menu()
        menu.clear()
        for spec in self._specs:
            action = menu.addAction(spec.title)
            action.setCheckable(True)
            action.setChecked(spec.key in self._visible)
            action.toggled.connect(lambda on, key=spec.key: self.set_plot_visible(key, on))
        self.request_draw(now=not len(self._station))
        self._fill_table()
        self.readout.setText(READOUT_HINT if len(self._station) else "")

    def clear_results(self) -> None:
        """Nothing shown: another project, or a survey without results."""
        self.set_results(np.zeros(0), np.zeros(0, int), (), {}, (), ())

    def set_plot_visible(self, key: str, visible: bool) -> None:
        x_range = self.plots.x_range() if self.plots.plots else None
        (self._visible.add if visible else self._visible.discard)(key)
        self.request_draw()
        if x_range is not None:
            self.plots.set_x_range(*x_range)

    def _draw(self) -> None:
        self.plots.set_data(self._station, self._columns, self._specs, self._visible, self._bands)

    def _fill_table(self) -> None:
        table = self.exceedances
        table.setSortingEnabled(False)
        table.setRowCount(len(self._rows))
        for row, e in enumerate(self._rows):
            digits = 3 if e.unit == "mm" else 6
            cells = ((e.check, None), (e.rail, None), (e.direction, None),
                     (f"{e.station_from_m:.3f}", e.station_from_m), (f"{e.station_to_m:.3f}", e.station_to_m),
                     (f"{e.peak:.{digits}f}", abs(e.peak)), (f"{e.limit:.{digits}f}", abs(e.limit)), (e.unit, None),
                     (f"{e.first_sleeper}–{e.last_sleeper}", e.first_sleeper))
            for column, (text, key) in enumerate(cells):
                item = SortableItem(text, key)
                item.setData(Qt.UserRole, row)  # the exceedance's index, whatever the sort order
                if key is not None:
                    item.setTextAlignment(Qt.AlignRight | Qt.AlignVCenter)
                table.setItem(row, column, item)
        table.horizontalHeader().setSortIndicator(3, Qt.AscendingOrder)  # along the track, as walked
        table.setSortingEnabled(True)

    def _exceedance_at(self, table_row: int) -> int:
        item = self.exceedances.item(table_row, 0)
        return -1 if item is None else int(item.data(Qt.UserRole))

    def zoom_to_exceedance(self, index: int) -> None:
        """Zoom every plot to exceedance ``index`` (in the order of the results, not of the table)."""
        if not 0 <= index < len(self._rows):
            return
        e = self._rows[index]
        low, high = exceedance_window(e.station_from_m, e.station_to_m)
        self.plots.set_x_range(low, high)
        self.plots.highlight(min(e.station_from_m, e.station_to_m), max(e.station_from_m, e.station_to_m))
        centre = 0.5 * (e.station_from_m + e.station_to_m)
        self.plots.set_cursor(centre)
        self.show_values_at(centre)
        self.exceedanceSelected.emit(e.first_sleeper, e.last_sleeper)

    def show_values_at(self, station: float) -> None:
        if not len(self._station):
            return
        i = int(np.clip(np.searchsorted(self._station, station), 1, len(self._station) - 1))
        i -= abs(self._station[i - 1] - station) < abs(self._station[i] - station)
        parts = [f"<b>{self._labels[i]}</b> sleeper {self._numbers[i]} ({self._station[i]:.3f} m)"]
        for spec in self._specs:
            if spec.key not in self._visible:
                continue
            values = " / ".join(f"{spec.scale * self._columns[column][i]:+.2f}" for _, column in spec.curves)
            parts.append(f"{spec.title}: {values} {spec.unit}")
        self.readout.setText(" &nbsp;|&nbsp; ".join(parts))
