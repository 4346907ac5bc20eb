"""Track view: plots stacked along chainage on one shared x axis (a scrollable stack: each plot
keeps a readable height), a crosshair read-out of every value at the sleeper under the cursor
with the rail and direction of each, a go-to field (sleeper number, K-chainage or station), a
two-point measuring tool (its span can be marked as a track event: turnout, level crossing, ...),
and the exceedance table (a click scrolls to the check's plot and zooms every plot there). The
chainage axis, in K-chainage as the sleeper table prints it, is a ruler under the scrolled stack,
in sight wherever the stack is scrolled. The read-out sits in a bar of fixed height: a long read-out never moves the plots under the mouse.

Navigation: the wheel zooms along chainage only (the y axes fit what is visible, and keep their
range during a pan while it shows all of that at 80 % of the height or more), dragging pans along
chainage, and neither can leave the surveyed chainage."""

from __future__ import annotations

import math
from html import escape
from collections.abc import Mapping, Sequence

import numpy as np
import pyqtgraph as pg
from PySide6.QtCore import QLineF, QPoint, QRectF, Qt, Signal
from PySide6.QtGui import QTextDocument
from PySide6.QtWidgets import (
    QAbstractItemView,
    QHBoxLayout,
    QLabel,
    QLineEdit,
    QMenu,
    QScrollArea,
    QSplitter,
    QTableView,
    QToolButton,
    QVBoxLayout,
    QWidget,
)

from insrail.gui import plotstyle
from insrail.gui.bands import EnvelopeLine
from insrail.gui.chainage_axis import ChainageRuler
from insrail.gui.lazy import DrawWhenShown
from insrail.gui.views.exceedances import START_COLUMN, ExceedanceModel
from insrail.project.plotdata import (
    BAND_SIGMAS,
    ChainagePlot,
    Envelope,
    EventSpan,
    QualityBand,
    exceedance_window,
    locate,
    nearest_sleeper,
    plot_values,
)
from insrail.project.results import ExceedanceRow
from insrail.report.content import ChainageAxis
from insrail.gui.translation import tr, tr_noop

#: Checks whose plot starts hidden unless they have exceedances: each repeats what another plot
#: shows (gauge, cant) or is a shorter-chord version of one shown; the Plots menu brings them back.
HIDDEN_KINDS = ("gauge_deviation", "gauge_change_rate", "versine", "cross_level")
READOUT_HINT = tr_noop("Move the mouse over the plots to read every value at a sleeper.")  # tr() where shown
#: Each plot keeps at least this height [px]; more plots than fit scroll.
MIN_PLOT_HEIGHT = 150
#: Panning and zooming stop this far beyond the first and last sleeper [m].
PAN_MARGIN_M = 10.0
#: The narrowest window a zoom reaches [m] (a few sleepers).
MIN_WINDOW_M = 2.0
#: The y range keeps this fraction of its span free above and below the values shown.
Y_MARGIN = 0.05
#: A pan keeps a plot's y range while it holds what is shown and is at most this many times the
#: fitted one: the value axis (whose tick labels are laid out again at each change) stays put
#: instead of twitching at every frame.
Y_SLACK = 1.25
#: The window a go-to shows when the current one is wider [m].
GOTO_WINDOW_M = 100.0
#: Lines of text the read-out bar holds (a longer read-out is cut there; its tooltip has all of it).
READOUT_LINES = 3
MEASURE_PENS = (pg.mkPen("#7B3294", width=1, style=Qt.DashDotLine), pg.mkPen("#008837", width=1, style=Qt.DashDotLine))


#: Events along the chainage plots: not assessed (their sleepers greyed in the reports) or only marked.
EVENT_NOT_ASSESSED_BRUSH = pg.mkBrush(123, 94, 167, 45)
EVENT_BRUSH = pg.mkBrush(123, 94, 167, 18)
EVENT_PEN = pg.mkPen("#7b5ea7", width=1, style=Qt.DotLine)
EVENT_TEXT = "#7b5ea7"


def _add_invalid(item: pg.PlotItem, invalid: Sequence[tuple[float, float]]) -> None:
    """The runs of sleepers that are not valid, greyed behind everything (their values are drawn: the
    reports grey the same runs; the read-out says why a sleeper is not assessed)."""
    for low, high in invalid:
        span = pg.LinearRegionItem((low, high), movable=False, brush=plotstyle.INVALID_BRUSH, pen=pg.mkPen(None))
        span.setZValue(-9)
        item.addItem(span, ignoreBounds=True)


def _add_events(item: pg.PlotItem, events: Sequence[EventSpan], named: bool) -> None:
    """Event spans behind the curves (a point event as a line); their names on the top plot."""
    for event in events:
        brush = EVENT_NOT_ASSESSED_BRUSH if event.not_assessed else EVENT_BRUSH
        if event.station_to_m > event.station_from_m:
            span = pg.LinearRegionItem((event.station_from_m, event.station_to_m), movable=False, brush=brush,
                                       pen=pg.mkPen(None))
        else:
            span = pg.InfiniteLine(event.station_from_m, angle=90, pen=EVENT_PEN)
        span.setZValue(-8)
        item.addItem(span, ignoreBounds=True)
        if named:
            text = pg.TextItem(event.name, color=EVENT_TEXT, anchor=(0, 0))
            text.setPos(event.station_from_m, 0.0)
            item.addItem(text, ignoreBounds=True)


class Rules(pg.GraphicsObject):
    """Horizontal lines along the whole surveyed chainage (a plot's zero line and tolerance limits)
    with bounds fixed when made. pyqtgraph's InfiniteLine spans the view, so it computes its bounds
    again from the view transform at every pan or zoom (some 40 times a frame over the plots in view);
    these never move, and the view box clips them to what is shown."""

    def __init__(self, lines: Sequence[tuple[float, object]], x_from: float, x_to: float):
        super().__init__()
        self.lines = tuple((float(y), pg.mkPen(pen)) for y, pen in lines)
        bottom, top = min(y for y, _ in self.lines), max(y for y, _ in self.lines)
        pad = max(top - bottom, 1.0)  # never without height: Qt skips an item whose bounds have none
        self._bounds = QRectF(x_from, bottom - pad, x_to - x_from, top - bottom + 2.0 * pad)

    def boundingRect(self) -> QRectF:
        return self._bounds

    def paint(self, painter, *_args) -> None:
        for y, pen in self.lines:
            painter.setPen(pen)
            painter.drawLine(QLineF(self._bounds.left(), y, self._bounds.right(), y))


class ChainagePlots(pg.GraphicsLayoutWidget):
    """Stacked plots along chainage sharing one chainage window, with a crosshair.

    The stack is taller than the scroll area that shows it. A pan or zoom moves only the plots in
    the scroll area's viewport (pyqtgraph's x-link would move, downsample and fit every plot each
    frame); a plot scrolled or shown into view catches up with the window before it is painted."""

    cursorMoved = Signal(float)
    clicked = Signal(str, float)  # plot key, station [m]
    windowShown = Signal(float, float)  # the chainage window of the plots in view [m]
    plotResized = Signal()  # a plot's data area moved or changed its size
    _window: tuple[float, float] | None = None  # the chainage window every plot follows [m] (none before data)

    def __init__(self, parent=None):
        super().__init__(parent)
        self.plots: dict[str, pg.PlotItem] = {}
        self._crosshairs: list[pg.InfiniteLine] = []
        self._regions: list[pg.LinearRegionItem] = []
        self._measure_lines: list[tuple[pg.InfiniteLine, pg.InfiniteLine]] = []
        # Every plot item made so far, in row order: the next survey's plots reuse them (making a
        # pyqtgraph plot costs tens of ms: most of a project switch); those not needed leave the layout.
        self._pool: list[pg.PlotItem] = []
        self._laid_out = 0  # how many of the pool are in the layout (the first ones)
        self._station = np.zeros(0)
        self._fits: dict[pg.ViewBox, tuple[list[Envelope], list[float]]] = {}  # per plot: curves, limits
        self._synced: set[pg.ViewBox] = set()  # the plots that show the window (x, and y fitted to it)
        self._following = False  # the window is being handed to the plots in view
        self._mouse = pg.SignalProxy(self.scene().sigMouseMoved, rateLimit=60, slot=self._mouse_moved)
        self.scene().sigMouseClicked.connect(self._mouse_clicked)

    def set_data(self, station_m: np.ndarray, columns: Mapping[str, np.ndarray], plots: Sequence[ChainagePlot],
                 visible: set[str], bands: Mapping[str, QualityBand] | None = None,
                 events: Sequence[EventSpan] = (), invalid: Sequence[tuple[float, float]] = ()) -> None:
        self.plots.clear()
        self._crosshairs.clear()
        self._regions.clear()
        self._measure_lines.clear()
        shown = [p for p in plots if p.key in visible]
        self._station, self._fits, self._window, self._synced = np.asarray(station_m), {}, None, set()
        self._following = True  # a reused plot's old window, clamped to the new limits, is no pan
        try:
            self._add_plots(shown, columns, bands or {}, events, invalid)
        finally:
            self._following = False
        self.follow()

    def _add_plots(self, shown: Sequence[ChainagePlot], columns: Mapping[str, np.ndarray],
                   bands: Mapping[str, QualityBand], events: Sequence[EventSpan],
                   invalid: Sequence[tuple[float, float]]) -> None:
        station_m = self._station
        self._lay_out(len(shown))
        self.setMinimumHeight(MIN_PLOT_HEIGHT * len(shown))
        for row, spec in enumerate(shown):
            item = self._pool[row]
            band = bands.get(spec.key)
            item.setTitle(plotstyle.titled(f"{spec.title} [{spec.unit}]", [label for label, _ in spec.curves],
                                           tr("±{sigmas:g}σ predicted").format(sigmas=BAND_SIGMAS) if band is not None else ""), size="8pt")
            if band is not None:
                edges = [pg.PlotCurveItem(band.station_m, sign * band.half_width, pen=None) for sign in (1.0, -1.0)]
                fill = pg.FillBetweenItem(*edges, brush=plotstyle.BAND_BRUSH)  # a step per 200 m: a few points
                fill.setZValue(-5)
                item.addItem(fill, ignoreBounds=True)  # the data, not the band, set the view
            # min/max per pixel column from a pyramid made once: a pan slices one level of it
            curves = [Envelope.of(station_m, values, values)
                      for values in (spec.scale * columns[column] for _, column in spec.curves)]
            for index, curve in enumerate(curves):
                item.addItem(EnvelopeLine((curve,), plotstyle.pen(index)))
            limits = [limit for limit in (spec.lower, spec.upper) if limit is not None]
            if len(station_m):
                # A zero line instead of a grid (pyqtgraph's grid triples the time per frame), and the limits.
                rules = Rules([(0.0, plotstyle.ZERO_PEN)] + [(limit, plotstyle.LIMIT_PEN) for limit in limits],
                              float(station_m[0]) - PAN_MARGIN_M, float(station_m[-1]) + PAN_MARGIN_M)
                rules.setZValue(-1)
                item.addItem(rules, ignoreBounds=True)
            self._fits[item.vb] = (curves, limits)
            crosshair = pg.InfiniteLine(angle=90, pen=plotstyle.CROSSHAIR_PEN)
            item.addItem(crosshair, ignoreBounds=True)
            self._crosshairs.append(crosshair)
            _add_invalid(item, invalid)
            _add_events(item, events, named=not row)
            if len(station_m):
                low, high = float(station_m[0]) - PAN_MARGIN_M, float(station_m[-1]) + PAN_MARGIN_M
                item.vb.setLimits(xMin=low, xMax=high, minXRange=MIN_WINDOW_M, maxXRange=high - low)
                self._window = (low, high)  # the whole survey; a reused plot drops the previous one's window
            item.hideAxis("bottom")  # the chainage ruler under the stack is the plots' one axis
            self.plots[spec.key] = item

    def in_view(self) -> list[pg.ViewBox]:
        """The plots' view boxes that show at least a pixel row in the scroll area's viewport."""
        shown = self.viewport().visibleRegion().boundingRect()  # empty while hidden
        if shown.isEmpty():
            return []
        return [view for view in self._fits
                if self.mapFromScene(view.sceneBoundingRect()).boundingRect().intersects(shown)]

    def follow(self, *_args) -> None:
        """The plots in view catch up with the chainage window (after a scroll, a resize, a show)."""
        if self._window is not None:
            self._hand_on(None, self._window)

    def _x_changed(self, view: pg.ViewBox, window: tuple[float, float]) -> None:
        """A plot's chainage window changed (a drag, the wheel, a go-to): the others in view follow."""
        if not self._following and view in self._fits:
            self._hand_on(view, (float(window[0]), float(window[1])))

    def _hand_on(self, source: pg.ViewBox | None, window: tuple[float, float]) -> None:
        """``window`` to the plots in view that do not show it yet (``source`` has it: it moved)."""
        if window != self._window:
            self._window, self._synced = window, set()
        catching_up = [view for view in self.in_view() if view not in self._synced and view is not source]
        self._following = True
        try:
            for view in catching_up:
                view.setXRange(*window, padding=0.0)
        finally:
            self._following = False
        if source is not None and source not in self._synced:
            catching_up.append(source)
        self._fit_y(catching_up)
        self._synced.update(catching_up)
        self.windowShown.emit(*window)

    def _fit_y(self, views: Sequence[pg.ViewBox]) -> None:
        """Each plot's y range fitted to what is visible along chainage and to its limits, from the
        min/max per pixel column its curves draw: pyqtgraph's own fit (auto-visible) searched every
        curve's bounds several times per frame, a third of the CPU of a pan frame."""
        if not views or self._window is None:
            return
        low, high = self._window
        for view in views:
            curves, limits = self._fits[view]
            extremes = list(limits)
            for curve in curves:  # what is drawn: the min and max of each pixel column (±1 sample or column)
                _, lows, highs = curve.visible(low, high, max(int(view.width()), 1))
                if np.isfinite(lows).any():
                    extremes += [float(np.nanmin(lows)), float(np.nanmax(highs))]
            if not extremes:
                continue
            bottom, top = min(extremes), max(extremes)
            if top - bottom < 1e-9:
                bottom, top = bottom - 0.5, top + 0.5
            margin = Y_MARGIN * (top - bottom)
            bottom, top = bottom - margin, top + margin
            shown_bottom, shown_top = view.viewRange()[1]
            if shown_bottom <= bottom and top <= shown_top and shown_top - shown_bottom <= Y_SLACK * (top - bottom):
                continue  # still shows all of it at nearly full height: no new axis to lay out this frame
            view.setYRange(bottom, top, padding=0.0)

    def _lay_out(self, count: int) -> None:
        """The first ``count`` plot items of the pool in the layout, emptied; the others out of it."""
        while len(self._pool) < count:
            item = pg.PlotItem()
            plotstyle.make_fluid(item)
            item.getAxis("left").setWidth(48)
            item.vb.setMouseEnabled(x=True, y=False)  # the wheel zooms along chainage; y fits what is visible
            item.vb.enableAutoRange(x=False, y=False)  # the window is set; no bounds searched during pans
            item.vb.sigXRangeChanged.connect(self._x_changed)
            item.vb.sigResized.connect(self.follow)  # laid out (or out) after a change of the stack
            item.vb.sigResized.connect(self.plotResized)
            self._pool.append(item)
        for item in self._pool:
            item.clear()  # the previous survey's curves and lines
        for item in self._pool[count:self._laid_out]:
            self.removeItem(item)
        for row in range(self._laid_out, count):
            self.addItem(self._pool[row], row=row, col=0)
        self._laid_out = count

    def x_range(self) -> tuple[float, float]:
        return self._window

    def set_x_range(self, low: float, high: float) -> None:
        """Show ``low..high`` (within the limits: the window the plot in view, or the first, took)."""
        if self.plots:
            view = (self.in_view() or [next(iter(self.plots.values())).vb])[0]
            view.setXRange(low, high, padding=0.0)  # a change is handed on to the others in view
            window = tuple(float(v) for v in view.viewRange()[0])
            if window != self._window:  # no change of a plot out of view that had the window asked for
                self._hand_on(view, window)

    # a scroll moves the stack in the scroll area; the plots that come into view catch up
    def moveEvent(self, event) -> None:
        super().moveEvent(event)
        self.follow()

    def resizeEvent(self, event) -> None:
        super().resizeEvent(event)
        self.follow()

    def showEvent(self, event) -> None:
        super().showEvent(event)
        self.follow()

    def scroll_rect(self, key: str):
        """Where plot ``key`` is in this widget (what the scroll area scrolls into view)."""
        return self.mapFromScene(self.plots[key].sceneBoundingRect()).boundingRect()

    def highlight(self, low: float, high: float) -> None:
        if not self._regions:  # made at the first use: each item in a plot costs every pan frame
            for item in self.plots.values():
                region = pg.LinearRegionItem(movable=False, brush=(255, 200, 0, 60), pen=pg.mkPen(None))
                region.setZValue(-10)
                item.addItem(region, ignoreBounds=True)
                self._regions.append(region)
        for region in self._regions:
            region.setRegion((low, high))

    def set_cursor(self, station: float) -> None:
        for line in self._crosshairs:
            line.setPos(station)

    def mark_measure(self, points: Sequence[float]) -> None:
        """The measuring tool's points (none, one or two stations) as lines in every plot."""
        if points and not self._measure_lines:  # made at the first use, as the highlight
            for item in self.plots.values():
                lines = tuple(pg.InfiniteLine(angle=90, pen=pen) for pen in MEASURE_PENS)
                for line in lines:
                    item.addItem(line, ignoreBounds=True)
                self._measure_lines.append(lines)
        for lines in self._measure_lines:
            for k, line in enumerate(lines):
                line.setVisible(k < len(points))
                if k < len(points):
                    line.setPos(points[k])

    def _plot_at(self, position) -> tuple[str, float] | None:
        for key, item in self.plots.items():
            if item.sceneBoundingRect().contains(position):
                return key, item.vb.mapSceneToView(position).x()
        return None

    def _mouse_moved(self, event) -> None:
        found = self._plot_at(event[0])
        if found is not None:
            self.set_cursor(found[1])
            self.cursorMoved.emit(found[1])

    def _mouse_clicked(self, event) -> None:
        if event.button() != Qt.LeftButton:
            return
        found = self._plot_at(event.scenePos())
        if found is not None:
            self.clicked.emit(*found)


class TrackView(DrawWhenShown, QWidget):
    """The chainage plots, their read-out line and the exceedance table under them."""

    exceedanceSelected = Signal(int, int)  # first and last sleeper number of the exceedance shown
    markEventRequested = Signal(float, float)  # the measured span's stations [m], smaller first

    def __init__(self, parent=None):
        super().__init__(parent)
        self.plots = ChainagePlots()
        self.readout = QLabel()  # the hint once there is something to read
        self.readout.setTextFormat(Qt.RichText)
        self.readout.setWordWrap(True)
        self.readout.setAlignment(Qt.AlignLeft | Qt.AlignTop)
        self.readout.setTextInteractionFlags(Qt.TextSelectableByMouse)
        self.readout.setFixedHeight(self._readout_height())
        self.goto = QLineEdit()
        self.goto.setPlaceholderText(tr("Go to: #sleeper, K1+234.5 or station"))
        self.goto.setToolTip(tr("Go to a sleeper (#123), a chainage as printed on the sleepers (K1+234.5) or a "
                             "station in metres; Enter"))
        self.goto.setMaximumWidth(260)
        self.goto.returnPressed.connect(lambda: self.go_to(self.goto.text()))
        self.measure_button = QToolButton(text=tr("Measure"))
        self.measure_button.setCheckable(True)
        self.measure_button.setToolTip(tr("Measuring tool: click two points of a plot to read the chainage and "
                                       "value differences between them"))
        self.measure_button.toggled.connect(self._measure_toggled)
        self.measure_label = QLabel()
        self.measure_label.setTextFormat(Qt.RichText)
        self.measure_label.setWordWrap(True)
        self.measure_label.setTextInteractionFlags(Qt.TextSelectableByMouse)
        self.measure_label.hide()
        self.mark_event_button = QToolButton(text=tr("Mark as track event…"))
        self.mark_event_button.setToolTip(tr("Mark the span between the two measured points as a turnout, level "
                                          "crossing, bridge, joint, stretch not to assess or note in the "
                                          "project's event file"))
        self.mark_event_button.clicked.connect(self.request_mark_event)
        self.mark_event_button.hide()
        self.choose_plots = QToolButton(text=tr("Plots"))
        self.choose_plots.setPopupMode(QToolButton.InstantPopup)
        self.choose_plots.setMenu(QMenu(self.choose_plots))
        self.exceedance_model = ExceedanceModel(self)
        self.exceedances = QTableView()
        self.exceedances.setModel(self.exceedance_model)
        self.exceedances.setSortingEnabled(True)
        self.exceedances.horizontalHeader().setSortIndicator(START_COLUMN, Qt.AscendingOrder)
        self.exceedances.setSelectionBehavior(QAbstractItemView.SelectRows)
        self.exceedances.setSelectionMode(QAbstractItemView.SingleSelection)
        self.exceedances.setEditTriggers(QAbstractItemView.NoEditTriggers)
        self.exceedances.verticalHeader().setVisible(False)
        self.exceedances.horizontalHeader().setStretchLastSection(True)
        self.exceedances.verticalHeader().setDefaultSectionSize(self.fontMetrics().height() + 6)
        self.exceedances.setMinimumHeight(5 * self.exceedances.verticalHeader().defaultSectionSize())
        self.exceedances.clicked.connect(lambda index: self.zoom_to_exceedance(self._exceedance_at(index.row())))
        self.exceedances.selectionModel().currentRowChanged.connect(
            lambda index, _previous: self.zoom_to_exceedance(self._exceedance_at(index.row())))

        top = QHBoxLayout()
        top.addWidget(self.readout, 1)
        for tool in (self.goto, self.measure_button, self.mark_event_button, self.choose_plots):
            top.addWidget(tool, 0, Qt.AlignTop)
        self.scroll = QScrollArea()
        self.scroll.setWidgetResizable(True)
        self.scroll.setHorizontalScrollBarPolicy(Qt.ScrollBarAlwaysOff)
        self.scroll.setWidget(self.plots)
        self.ruler = ChainageRuler()
        self.plots.windowShown.connect(self.ruler.set_window)
        self.plots.plotResized.connect(self._place_ruler)
        upper = QWidget()
        upper_layout = QVBoxLayout(upper)
        upper_layout.setContentsMargins(0, 0, 0, 0)
        upper_layout.addLayout(top)
        upper_layout.addWidget(self.measure_label)
        upper_layout.addWidget(self.scroll, 1)
        upper_layout.addWidget(self.ruler)
        splitter = QSplitter(Qt.Vertical)
        splitter.addWidget(upper)
        splitter.addWidget(self.exceedances)
        splitter.setStretchFactor(0, 4)
        splitter.setStretchFactor(1, 1)
        splitter.setSizes([4000, 1000])
        splitter.setChildrenCollapsible(False)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(2, 2, 2, 2)
        layout.addWidget(splitter)

        self.survey = ""
        self._station = np.zeros(0)
        self._labels: tuple[str, ...] = ()
        self._numbers = np.zeros(0, int)
        self._columns: Mapping[str, np.ndarray] = {}
        self._specs: tuple[ChainagePlot, ...] = ()
        self._visible: set[str] = set()
        self._rows: tuple[ExceedanceRow, ...] = ()
        self._bands: dict[str, QualityBand] = {}
        self._measured: list[tuple[str, float]] = []  # (plot key, station) of the measuring tool's points
        self._pending_range: tuple[float, float] | None = None  # a range to apply once drawn
        self._events: tuple[EventSpan, ...] = ()
        self._invalid: tuple[tuple[float, float], ...] = ()
        self._not_assessed: tuple[str, ...] = ()
        self._chainage: ChainageAxis | None = None
        self._pending_scroll: str | None = None  # the plot to scroll to once drawn
        self.plots.cursorMoved.connect(self.show_values_at)
        self.plots.clicked.connect(self._plot_clicked)

    def set_results(self, station_m: np.ndarray, number: np.ndarray, label: Sequence[str],
                    columns: Mapping[str, np.ndarray], plots: Sequence[ChainagePlot],
                    exceedances: Sequence[ExceedanceRow], bands: Mapping[str, QualityBand] | None = None,
                    survey: str = "", events: Sequence[EventSpan] = (), chainage: ChainageAxis | None = None,
                    invalid: Sequence[tuple[float, float]] = (), not_assessed: Sequence[str] = ()) -> None:
        """Plain arrays (one per sleeper, in chainage order), the plots to draw from them, the
        predicted-accuracy bands of some plots (by plot key), the survey's events, its chainage
        axis (None: the axis in metres of station), the runs of sleepers not valid and per sleeper why it
        is not assessed ("": it is). The same
        ``survey`` again (processed once more) keeps the chainage window and the plots shown."""
        same = bool(survey) and survey == self.survey and bool(self._specs)
        state = self.view_state() if same else None
        self.survey = survey
        self._station, self._numbers, self._labels = np.asarray(station_m), np.asarray(number), tuple(label)
        self._columns, self._specs, self._rows = columns, tuple(plots), tuple(exceedances)
        self._bands = dict(bands or {})
        self._events = tuple(events)
        self._invalid = tuple(invalid)
        self._not_assessed = tuple(not_assessed)
        self._chainage = chainage
        self._pending_scroll = None
        failing = {f"check_{e.check}" for e in self._rows}
        self._visible = {p.key for p in plots if p.kind not in HIDDEN_KINDS or p.key in failing}
        self._measured = []
        self.measure_label.clear()
        self.mark_event_button.hide()
        self._pending_range = None
        self._fill_plots_menu()
        self.request_draw(now=not len(self._station))
        self._fill_table()
        self._set_readout(tr(READOUT_HINT) if len(self._station) else "")
        if state is not None:
            self.restore_state(state)

    def clear_results(self) -> None:
        """Nothing shown: another project, or a survey without results."""
        self.survey = ""
        self.set_results(np.zeros(0), np.zeros(0, int), (), {}, (), ())

    def _fill_plots_menu(self) -> None:
        menu = self.choose_plots.menu()
        menu.clear()
        for spec in self._specs:
            action = menu.addAction(spec.title)
            action.setCheckable(True)
            action.setChecked(spec.key in self._visible)
            action.toggled.connect(lambda on, key=spec.key: self.set_plot_visible(key, on))

    # ------------------------------------------------------------------ view state

    def view_state(self) -> dict:
        """What the surveyor set up: the chainage window and the plots shown (kept across
        reprocessing, and per project by the main window)."""
        window = self._pending_range or (self.plots.x_range() if self.plots.plots and not self.stale else None)
        return {"x_range": list(window) if window is not None else None, "visible": sorted(self._visible)}

    def restore_state(self, state: Mapping) -> None:
        visible = {key for key in state.get("visible") or () if any(s.key == key for s in self._specs)}
        if visible and visible != self._visible:
            self._visible = visible
            self._fill_plots_menu()
            self.request_draw()
        window = state.get("x_range")
        if window and len(self._station):
            self._pending_range = (float(window[0]), float(window[1]))
            if not self.stale:
                self._apply_pending_range()

    def _apply_pending_range(self) -> None:
        if self._pending_range is not None and self.plots.plots:
            self.plots.set_x_range(*self._pending_range)
            self._pending_range = None

    def set_plot_visible(self, key: str, visible: bool) -> None:
        if self.plots.plots and not self.stale and self._pending_range is None:
            self._pending_range = self.plots.x_range()
        (self._visible.add if visible else self._visible.discard)(key)
        self.request_draw()

    def _draw(self) -> None:
        self.ruler.set_chainage(self._chainage)
        self.plots.set_data(self._station, self._columns, self._specs, self._visible, self._bands, self._events,
                            self._invalid)
        self.ruler.setVisible(bool(self.plots.plots))
        self._place_ruler()
        self.plots.mark_measure([station for _, station in self._measured])
        pending, self._pending_scroll = self._pending_scroll, None
        if pending in self.plots.plots:
            self._scroll_to_plot(pending)
        self._apply_pending_range()

    # ------------------------------------------------------------------ exceedances

    def _fill_table(self) -> None:
        titles = {spec.key.removeprefix("check_"): spec.title for spec in self._specs}  # display names, not ids
        self.exceedance_model.set_rows(self._rows, titles)
        header = self.exceedances.horizontalHeader()
        self.exceedance_model.sort(header.sortIndicatorSection(), header.sortIndicatorOrder())
        metrics, padding = self.exceedances.fontMetrics(), 3 * self.exceedances.fontMetrics().averageCharWidth()
        for column, width in enumerate(self.exceedance_model.column_widths(metrics.horizontalAdvance)):
            header.resizeSection(column, width + padding)  # + room for the sort indicator

    def _exceedance_at(self, table_row: int) -> int:
        return self.exceedance_model.exceedance_at(table_row)

    def zoom_to_exceedance(self, index: int) -> None:
        """Scroll to the plot of exceedance ``index`` (in the order of the results, not of the table),
        shown again if it was hidden, and zoom every plot to the exceedance."""
        if not 0 <= index < len(self._rows):
            return
        e = self._rows[index]
        key = f"check_{e.check}"
        if key not in self._visible and any(spec.key == key for spec in self._specs):
            self.set_plot_visible(key, True)
            self._fill_plots_menu()
        if key in self.plots.plots and not self.stale:
            self._scroll_to_plot(key)  # first: the window goes to the plots then in view
        else:
            self._pending_scroll = key
        low, high = exceedance_window(e.station_from_m, e.station_to_m)
        if self.stale:  # drawn later (hidden, or a plot shown again): the window waits for it
            self._pending_range = (low, high)
        else:
            self.plots.set_x_range(low, high)
        self.plots.highlight(min(e.station_from_m, e.station_to_m), max(e.station_from_m, e.station_to_m))
        centre = 0.5 * (e.station_from_m + e.station_to_m)
        self.plots.set_cursor(centre)
        self.show_values_at(centre)
        self.exceedanceSelected.emit(e.first_sleeper, e.last_sleeper)

    def _place_ruler(self) -> None:
        """The ruler's axis under the plots' data area (their view boxes share one left edge)."""
        if not self.plots.plots:
            return
        view = next(iter(self.plots.plots.values())).vb
        area = self.plots.mapFromScene(view.sceneBoundingRect()).boundingRect()
        left = self.plots.mapTo(self, area.topLeft()).x() - self.ruler.mapTo(self, QPoint(0, 0)).x()
        self.ruler.place(left, area.width())

    def resizeEvent(self, event) -> None:
        super().resizeEvent(event)
        self._place_ruler()

    def _scroll_to_plot(self, key: str) -> None:
        rect = self.plots.scroll_rect(key)
        self.scroll.ensureVisible(rect.center().x(), rect.center().y(), 0, rect.height() // 2)

    # ------------------------------------------------------------------ reading values

    def _readout_height(self) -> int:
        """READOUT_LINES lines of the read-out as it is set (bold names), and no more: a cut line
        would show half its letters."""
        lines = QTextDocument()
        lines.setDefaultFont(self.readout.font())
        lines.setDocumentMargin(0)
        lines.setHtml("<br>".join(["<b>K1+000.000</b> sleeper 1"] * READOUT_LINES))
        return math.ceil(lines.size().height()) + 2 * self.readout.margin()

    def _set_readout(self, text: str) -> None:
        self.readout.setText(text)
        self.readout.setToolTip(text)  # all of it, where the bar cuts a long one

    def go_to(self, text: str) -> bool:
        """Centre the plots on the sleeper ``text`` names (see :func:`insrail.project.plotdata.locate`);
        False (and the field marked) when it names none."""
        row = locate(text, self._station, self._numbers, self._labels)
        if row is None:
            self.goto.setStyleSheet("background: #FFE0E0;")
            self.goto.setToolTip(tr("{text} is no sleeper number, chainage or station of this survey").format(text=repr(text)))
            return False
        self.goto.setStyleSheet("")
        station = float(self._station[row])
        low, high = self.plots.x_range() if self.plots.plots else (station, station)
        half = 0.5 * min(high - low, GOTO_WINDOW_M) if high > low else 0.5 * GOTO_WINDOW_M
        self.plots.set_x_range(station - half, station + half)
        self.plots.set_cursor(station)
        self.show_values_at(station)
        return True

    def show_values_at(self, station: float) -> None:
        if not len(self._station):
            return
        i = nearest_sleeper(self._station, station)
        parts = [tr("<b>{label}</b> sleeper {number} ({station:.3f} m)").format(label=self._labels[i], number=self._numbers[i],
                                                                    station=self._station[i])]
        for spec in self._specs:
            if spec.key not in self._visible:
                continue
            values = ", ".join(f"{label} {value:+.2f}" if label else f"{value:+.2f}"
                               for label, value in plot_values(spec, self._columns, i))
            parts.append(f"<b>{spec.title}</b>: {values} {spec.unit}")
        if i < len(self._not_assessed) and self._not_assessed[i]:
            parts.insert(1, tr("<b>not assessed</b>: {why}").format(why=escape(self._not_assessed[i])))
        self._set_readout(" &nbsp;|&nbsp; ".join(parts))

    def _measure_toggled(self, on: bool) -> None:
        self._measured = []
        self.plots.mark_measure([])
        self.mark_event_button.hide()
        self.measure_label.setVisible(on)
        self.measure_label.setText(tr("Measuring: click the first point in a plot.") if on else "")

    def _plot_clicked(self, key: str, station: float) -> None:
        if self.measure_button.isChecked():
            self.measure(key, station)

    def measure(self, key: str, station: float) -> None:
        """One point of the measuring tool, in plot ``key`` at ``station``: the first, the second
        (the differences are shown), or a new first after two."""
        if not len(self._station):
            return
        if len(self._measured) == 2:
            self._measured = []
        self._measured.append((key, float(self._station[nearest_sleeper(self._station, station)])))
        self.plots.mark_measure([s for _, s in self._measured])
        self.mark_event_button.setVisible(len(self._measured) == 2)
        if len(self._measured) == 1:
            self.measure_label.setText(tr("Measuring: click the second point."))
            return
        (_, a), (key, b) = self._measured
        spec = next(s for s in self._specs if s.key == key)
        first, second = (nearest_sleeper(self._station, s) for s in (a, b))
        deltas = ", ".join(f"{label} Δ {vb - va:+.2f}" if label else f"Δ {vb - va:+.2f}"
                           for (label, va), (_, vb) in zip(plot_values(spec, self._columns, first),
                                                           plot_values(spec, self._columns, second)))
        self.measure_label.setText(
            tr("Δ chainage <b>{length:+.3f} m</b> (sleeper {first} {first_label} → {second} {second_label})").format(
                length=b - a, first=self._numbers[first], first_label=self._labels[first],
                second=self._numbers[second], second_label=self._labels[second])
            + f" &nbsp;|&nbsp; <b>{spec.title}</b>: {deltas} {spec.unit}")

    def measured_span(self) -> tuple[float, float] | None:
        """The stations of the measuring tool's two points, smaller first; None before two are set."""
        if len(self._measured) != 2:
            return None
        low, high = sorted(station for _, station in self._measured)
        return low, high

    def request_mark_event(self) -> None:
        span = self.measured_span()
        if span is not None:
            self.markEventRequested.emit(*span)
