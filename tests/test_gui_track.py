"""The track view on plain arrays (pytest-qt, offscreen): names, read-out, navigation, tools; the plan view's dots."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("pytestqt")
from PySide6.QtCore import QPoint, QPointF, Qt
from PySide6.QtGui import QWheelEvent
from PySide6.QtWidgets import QDialog, QDialogButtonBox

from insrail.gui.event_dialog import EventDialog
from insrail.gui.views.track import MIN_PLOT_HEIGHT, PAN_MARGIN_M, TrackView
from insrail.io.events import read_events
from insrail.project import load_project, save_project
from insrail.project.event_marking import DEFAULT_EVENTS_FILE
from insrail.project.plotdata import chainage_plots
from insrail.project.results import ExceedanceRow
from insrail.track.tolerance import load_tolerance_profile
from tests.test_project_model import make_folder, sample_project

SLEEPERS = 800


def columns(sleepers: int = SLEEPERS):
    station = 1000.0 + 0.625 * np.arange(sleepers)
    wave = np.sin(station / 7.0)
    data = {"station_m": station, "gauge_mm": 1435.0 + 0.5 * wave, "cant_mm": 2.0 * wave,
            "design_cant_mm": np.zeros(sleepers), "check_versine_10m_left_lateral_mm": 0.3 * wave}
    for direction in ("lateral", "vertical"):
        data[f"{direction}_deviation_left_mm"] = 1.0 + wave
        data[f"{direction}_deviation_right_mm"] = -1.0 - 2.0 * wave
        for rail in ("left", "right"):
            data[f"check_short_wave_30m_5m_{rail}_{direction}_mm"] = 0.1 * wave
    return data


@pytest.fixture
def view(qtbot):
    data = columns()
    station = data["station_m"]
    plots = chainage_plots(data, load_tolerance_profile("cn_hsr_ballastless"))
    versine = ExceedanceRow("versine_10m", "versine", "left", "lateral", "mm", 1100.0, 1101.0, 2.5, 2.0, 161, 163)
    widget = TrackView()
    qtbot.addWidget(widget)
    widget.resize(1366, 740)
    widget.show()
    labels = [f"K{int(s // 1000)}+{s % 1000:07.3f}" for s in station]
    widget.set_results(station, np.arange(1, SLEEPERS + 1), labels, data, plots, (versine,), survey="run")
    return widget


def test_plots_have_human_names_and_a_readable_height(view):
    titles = [spec.title for spec in view._specs]
    assert "30 m / 5 m short wave" in titles and "10 m versine" in titles
    assert not any("_" in title for title in titles)  # no profile ids on screen
    # the 10 m versine starts shown because it has an exceedance
    assert "check_versine_10m" in view.plots.plots
    assert view.plots.minimumHeight() >= MIN_PLOT_HEIGHT * len(view.plots.plots)
    assert view.scroll.verticalScrollBar().maximum() > 0  # more plots than fit: the stack scrolls
    menu = [action.text() for action in view.choose_plots.menu().actions()]
    assert len({name.lower() for name in menu}) == len(menu)  # never "gauge" and "Gauge"


def test_the_cursor_readout_names_rail_and_direction_of_every_value(view):
    view.show_values_at(1100.0)
    text = view.readout.text()
    row = int(np.argmin(np.abs(view._station - 1100.0)))
    assert f"sleeper {row + 1} " in text
    left, right = (view._columns[f"lateral_deviation_{rail}_mm"][row] for rail in ("left", "right"))
    assert f"<b>Lateral deviation</b>: left rail {left:+.2f}, right rail {right:+.2f} mm" in text
    wave = view._columns["check_short_wave_30m_5m_left_lateral_mm"][row]
    assert f"left rail, lateral {wave:+.2f}" in text and f"right rail, vertical {wave:+.2f}" in text
    gauge = view._columns["gauge_mm"][row]
    assert f"<b>Gauge</b>: {gauge:+.2f} mm" in text


def test_sleepers_not_valid_are_greyed_in_every_plot_and_the_readout_says_why(qtbot):
    """As the PDF's charts grey them: a run of sleepers the fusion cannot vouch for (the values drawn are
    no measurement of the track) is shaded behind every plot, and the read-out there says why."""
    import pyqtgraph as pg

    from insrail.gui import plotstyle
    from insrail.project.plotdata import INVALID_PAD_M, invalid_spans

    data = columns()
    station = data["station_m"]
    valid = np.ones(SLEEPERS, bool)
    valid[[5]] = False
    valid[300:340] = False
    spans = invalid_spans(station, valid)
    assert spans == ((station[5] - INVALID_PAD_M, station[5] + INVALID_PAD_M),
                     (station[300] - INVALID_PAD_M, station[339] + INVALID_PAD_M))
    assert invalid_spans(station, np.ones(SLEEPERS, bool)) == ()
    why = "fusion: between the filter resets at t = 1.0 s and 41.0 s the solution followed gnss_position"
    reasons = tuple(why if not ok else "" for ok in valid)
    widget = TrackView()
    qtbot.addWidget(widget)
    widget.resize(1366, 740)
    widget.show()
    widget.set_results(station, np.arange(1, SLEEPERS + 1), [f"{s:.1f}" for s in station], data,
                       chainage_plots(data, load_tolerance_profile("cn_hsr_ballastless")), (), survey="run",
                       invalid=spans, not_assessed=reasons)
    widget._draw()
    for item in widget.plots.plots.values():
        grey = [region.getRegion() for region in item.items if isinstance(region, pg.LinearRegionItem)
                and region.brush.style() == plotstyle.INVALID_BRUSH.style()]
        assert sorted(grey) == sorted(spans)
    widget.show_values_at(float(station[320]))
    assert f"<b>not assessed</b>: {why}" in widget.readout.text()
    widget.show_values_at(float(station[100]))
    assert "not assessed" not in widget.readout.text()


def test_panning_stays_on_the_data_and_the_wheel_zooms_along_chainage_only(view, qtbot):
    first = next(iter(view.plots.plots.values()))
    station = view._station
    view.plots.set_x_range(station[0] - 500.0, station[0] + 100.0)  # asked to show far before the start
    low, high = view.plots.x_range()
    assert low >= station[0] - PAN_MARGIN_M - 1e-6 and high <= station[-1] + PAN_MARGIN_M + 1e-6
    view.plots.set_x_range(station[-1] - 50.0, station[-1] + 400.0)
    assert view.plots.x_range()[1] <= station[-1] + PAN_MARGIN_M + 1e-6
    first.vb.translateBy(x=1e4)  # a drag far past the end
    assert view.plots.x_range()[1] <= station[-1] + PAN_MARGIN_M + 1e-6

    view.plots.set_x_range(1100.0, 1200.0)
    qtbot.waitUntil(lambda: np.allclose(view.plots.x_range(), (1100.0, 1200.0)))
    y_before = first.vb.viewRange()[1]
    centre = view.plots.mapFromScene(first.vb.mapViewToScene(QPointF(1150.0, 0.0)))
    event = QWheelEvent(QPointF(centre), QPointF(view.plots.mapToGlobal(centre)), QPoint(0, 0), QPoint(0, 240),
                        Qt.NoButton, Qt.NoModifier, Qt.NoScrollPhase, False)
    view.plots.viewport().setFocus()
    from PySide6.QtWidgets import QApplication
    QApplication.sendEvent(view.plots.viewport(), event)
    low, high = view.plots.x_range()
    assert high - low < 100.0 - 1.0  # zoomed in along chainage
    assert first.vb.state["mouseEnabled"] == [True, False]  # y follows the data, never the wheel
    y_after = first.vb.viewRange()[1]
    assert y_after[1] - y_after[0] <= (y_before[1] - y_before[0]) + 1e-9  # y fits the (narrower) visible data


def scroll_to(view, item) -> None:
    """Scroll the stack until ``item`` (a plot) is in the scroll area's viewport."""
    rect = view.plots.mapFromScene(item.vb.sceneBoundingRect()).boundingRect()
    view.scroll.ensureVisible(rect.center().x(), rect.center().y(), 0, rect.height() // 2)


def test_each_plot_fits_its_height_to_what_is_visible_and_to_its_limits(view, qtbot):
    """A narrow window shows its own values full height (not the survey's extremes), limits included."""
    view.plots.set_x_range(1010.0, 1012.0)  # the wave rises from about +0.9 to +1.0 here
    station = view._station
    shown = (station >= 1010.0 - 0.7) & (station <= 1012.0 + 0.7)
    for spec in view._specs:
        if spec.key not in view.plots.plots:
            continue
        scroll_to(view, view.plots.plots[spec.key])  # a plot out of view is fitted when it comes into view
        bottom, top = view.plots.plots[spec.key].vb.viewRange()[1]
        values = np.concatenate([spec.scale * view._columns[column][shown] for _, column in spec.curves])
        limits = [limit for limit in (spec.lower, spec.upper) if limit is not None]
        wanted = np.concatenate([values, limits])
        assert bottom <= wanted.min() and top >= wanted.max(), spec.key
        assert top - bottom <= 1.2 * np.ptp(wanted) + 1e-6, spec.key  # a margin, not the whole survey's range


def test_a_pan_moves_the_plots_in_view_and_a_plot_scrolled_into_view_catches_up(view, qtbot):
    """Only the plots in the scroll area's viewport follow a pan at once (a frame costs what is seen);
    a plot scrolled into view shows the window, its height fitted to it, before it is painted."""
    items = list(view.plots.plots.values())
    view.scroll.verticalScrollBar().setValue(0)
    view.plots.set_x_range(1100.0, 1130.0)
    top, bottom = items[0], items[-1]
    assert np.allclose(top.vb.viewRange()[0], (1100.0, 1130.0))
    assert not np.allclose(bottom.vb.viewRange()[0], (1100.0, 1130.0))  # out of view: not moved
    top.vb.translateBy(x=5.0)  # a drag in the top plot
    assert np.allclose(view.plots.x_range(), (1105.0, 1135.0))
    scroll_to(view, bottom)
    assert np.allclose(bottom.vb.viewRange()[0], (1105.0, 1135.0))
    spec = next(s for s in view._specs if view.plots.plots.get(s.key) is bottom)
    station = view._station
    shown = (station >= 1105.0 - 0.7) & (station <= 1135.0 + 0.7)
    values = np.concatenate([spec.scale * view._columns[column][shown] for _, column in spec.curves]
                            + [[limit for limit in (spec.lower, spec.upper) if limit is not None]])
    low, high = bottom.vb.viewRange()[1]
    assert low <= values.min() and high >= values.max() and high - low <= 1.2 * np.ptp(values) + 1e-6
    bottom.vb.scaleBy(x=0.5)  # the wheel in the bottom plot: the plots now in view follow it
    window = view.plots.x_range()
    assert np.allclose(window, (1112.5, 1127.5))
    in_view = [item for item in items if np.allclose(item.vb.viewRange()[0], window)]
    assert bottom in in_view and top not in in_view
    view.scroll.verticalScrollBar().setValue(0)
    assert np.allclose(top.vb.viewRange()[0], window)


def test_a_one_sleeper_spike_is_drawn_in_the_first_frame_of_every_zoom_level(qtbot):
    """Over a long survey a frame draws the min and max per pixel column from a level of the
    pyramid; the first frame after a zoom to any width (a new level each time) still reaches a
    spike of one sleeper, and the plot's height shows it. A window beside it does not draw it."""
    from insrail.gui.bands import EnvelopeLine
    from insrail.project.plotdata import FIRST_LEVEL

    data = columns(100_000)  # 62.5 km
    spike_at, spike_mm = 54_321, 25.0
    data["lateral_deviation_left_mm"][spike_at] = spike_mm
    station = data["station_m"]
    plots = chainage_plots(data, load_tolerance_profile("cn_hsr_ballastless"))
    view = TrackView()
    qtbot.addWidget(view)
    view.resize(1366, 740)
    view.show()
    view.set_results(station, np.arange(1, len(station) + 1), [f"{s:.3f}" for s in station], data, plots, ())
    spec = next(s for s in view._specs if any(c == "lateral_deviation_left_mm" for _, c in s.curves))
    item, drawn = view.plots.plots[spec.key], spec.scale * spike_mm
    scroll_to(view, item)
    line = next(c for c in item.items if isinstance(c, EnvelopeLine))
    columns_px = int(item.vb.width())
    at = station[spike_at]
    for width in (station[-1] - station[0], 20_000.0, 5_000.0, 1_000.0, 100.0):
        low = max(station[0], at - 0.3 * width)
        view.plots.set_x_range(low, low + width)
        assert line.boundingRect().bottom() >= drawn, width  # the path's largest y (Qt's y runs down)
        assert item.vb.viewRange()[1][1] >= drawn, width  # the height fitted to it
        assert line.drawn_points <= 2 * 2 ** FIRST_LEVEL * columns_px + 8, width  # per pixel column, not per sleeper
    view.plots.set_x_range(at + 10.0, at + 110.0)  # beside the spike: not drawn there
    assert line.boundingRect().bottom() < drawn


def test_go_to_a_sleeper_a_chainage_or_a_station(view):
    assert view.go_to("#321")
    assert abs(np.mean(view.plots.x_range()) - view._station[320]) < 1e-6
    assert "sleeper 321 " in view.readout.text()
    assert view.go_to("K1+250")
    row = int(np.argmin(np.abs(view._station - 1250.0)))
    assert f"sleeper {row + 1} " in view.readout.text()
    assert view.go_to("1300.2")
    assert not view.go_to("K9+000") and not view.go_to("#99999") and not view.go_to("north")
    assert "background" in view.goto.styleSheet()  # the field says it found nothing
    assert view.go_to("#1") and view.goto.styleSheet() == ""


def test_measuring_tool_gives_chainage_and_value_differences(view):
    view.measure_button.setChecked(True)
    assert view.measure_label.isVisible()
    view.measure("lateral_deviation", 1100.1)
    assert "second point" in view.measure_label.text()
    view.measure("lateral_deviation", 1112.6)
    a, b = (int(np.argmin(np.abs(view._station - s))) for s in (1100.1, 1112.6))
    text = view.measure_label.text()
    assert f"Δ chainage <b>{view._station[b] - view._station[a]:+.3f} m</b>" in text
    left = view._columns["lateral_deviation_left_mm"]
    assert f"left rail Δ {left[b] - left[a]:+.2f}" in text
    lines = view.plots._measure_lines[0]
    assert all(line.isVisible() for line in lines) and lines[1].value() == view._station[b]
    view.measure_button.setChecked(False)
    assert not any(line.isVisible() for line in lines)


def test_a_measured_span_is_marked_as_a_turnout_in_the_project_event_file(view, qtbot, tmp_path):
    view.measure_button.setChecked(True)
    view.measure("lateral_deviation", 1112.6)
    assert not view.mark_event_button.isVisible()  # one point is no span
    view.measure("lateral_deviation", 1100.1)  # the second point before the first: the span is sorted
    assert view.mark_event_button.isVisible()
    low, high = (float(view._station[int(np.argmin(np.abs(view._station - s)))]) for s in (1100.1, 1112.6))
    with qtbot.waitSignal(view.markEventRequested) as requested:
        qtbot.mouseClick(view.mark_event_button, Qt.LeftButton)
    assert requested.args == [low, high]

    project = sample_project(make_folder(tmp_path))
    save_project(project)
    dialog = EventDialog(project, *requested.args)
    qtbot.addWidget(dialog)
    kinds = [dialog.kind.itemText(k) for k in range(dialog.kind.count())]
    assert "Level crossing" in kinds and not any("_" in kind for kind in kinds)  # display names, no ids
    assert (float(dialog.start.text()), float(dialog.end.text())) == pytest.approx((low, high), abs=1e-3)
    dialog.set_kind("turnout")
    mark = dialog.buttons.button(QDialogButtonBox.Ok)
    dialog.end.setText("1090")  # before from: said beside the field, Mark disabled
    assert not mark.isEnabled() and dialog.problems["to"].isVisibleTo(dialog)
    assert "before from" in dialog.problems["to"].text()
    dialog.end.setText("12o0")
    assert not mark.isEnabled() and "station in metres" in dialog.problems["to"].text()
    dialog.end.setText(f"{high + 20.0:.3f}")  # the turnout's extent, edited
    dialog.text.setText("W12 No. 18, right-hand")
    assert mark.isEnabled() and not dialog.problems["to"].isVisibleTo(dialog)
    qtbot.mouseClick(mark, Qt.LeftButton)
    assert dialog.result() == QDialog.Accepted
    assert load_project(tmp_path).events == DEFAULT_EVENTS_FILE  # the project names its new event file
    [event] = read_events(tmp_path / DEFAULT_EVENTS_FILE).events
    assert (event.kind, event.unit, event.text) == ("turnout", "station_m", "W12 No. 18, right-hand")
    assert (event.start, event.end) == pytest.approx((low, high + 20.0), abs=1e-3)


def test_the_same_survey_again_keeps_window_and_plots(view):
    view.plots.set_x_range(1200.0, 1260.0)
    view.set_plot_visible("gauge", False)
    data = {name: values for name, values in view._columns.items()}
    view.set_results(view._station, view._numbers, view._labels, data, view._specs, view._rows, survey="run")
    assert np.allclose(view.plots.x_range(), (1200.0, 1260.0)) and "gauge" not in view.plots.plots
    view.set_results(view._station, view._numbers, view._labels, data, view._specs, view._rows, survey="other")
    assert "gauge" in view.plots.plots  # another survey starts afresh


def test_navigation_curves_draw_a_few_points_per_pixel_column_and_keep_a_spike(qtbot):
    """A series of a million epochs costs a frame what its plot's width costs; its one-sample spike
    still shows (min and max per pixel column), and no line runs across a gap in its own epochs."""
    from insrail.gui.bands import EnvelopeLine
    from insrail.gui.views.navigation import NavigationView
    from insrail.project.plotdata import NavSeries

    time = np.arange(1_000_000) * 0.005
    values = np.sin(time / 50.0)[:, None].copy()
    values[612_345, 0] = 7.0  # one epoch
    gnss_time = np.concatenate([np.arange(0.0, 1000.0), np.arange(2000.0, 5000.0)])
    series = (NavSeries("position", "Position", "m", ("north",), values, None),
              NavSeries("gnss_residuals", "GNSS residuals", "mm", ("north",), np.zeros((4000, 1)), None, gnss_time))
    view = NavigationView()
    qtbot.addWidget(view)
    view.resize(1000, 600)
    view.show()
    view.set_series(time, series)
    for entry in range(view.choice.count()):
        view.choice.item(entry).setCheckState(Qt.Checked)
    qtbot.waitUntil(lambda: len(view.items) == 2)
    line = next(c for c in view.items["position"].items if isinstance(c, EnvelopeLine))
    width = int(line.getViewBox().width())
    assert 0 < line.drawn_points <= 4 * width + 8
    assert line.boundingRect().bottom() >= 7.0 or line.boundingRect().top() >= 7.0  # the spike's column kept
    gaps = next(c for c in view.items["gnss_residuals"].items if isinstance(c, EnvelopeLine))
    assert [(p.x[0], p.x[-1]) for p in gaps.parts] == [(0.0, 999.0), (2000.0, 4999.0)]


def test_the_exceedance_model_sorts_by_magnitude_and_keeps_the_selection(qtbot):
    """Thousands of rows, nothing built per cell: the model formats what is shown, sorts peaks by magnitude,
    keeps the selected exceedance selected through a sort, and names checks by their display names."""
    from PySide6.QtWidgets import QTableView

    from insrail.gui.views.exceedances import ExceedanceModel

    rows = [ExceedanceRow("short_wave_30m_5m", "differential_versine", "left", "lateral", "mm", 10.0 * k,
                          10.0 * k + 2.0, (-1) ** k * (2.0 + k % 7), 2.0, 3 * k, 3 * k + 2) for k in range(5000)]
    rows.append(ExceedanceRow("gauge_change_rate", "gauge_change_rate", "track", "", "ratio", 5.0, 6.0, 0.0015,
                              0.001, 9, 10))
    model = ExceedanceModel()
    model.set_rows(rows, {"short_wave_30m_5m": "30 m / 5 m short wave"})
    view = QTableView()
    qtbot.addWidget(view)
    view.setModel(model)
    assert model.rowCount() == 5001 and model.index(0, 3).data() == "0.000"  # along the track first
    assert model.index(0, 0).data() == "30 m / 5 m short wave" and model.index(0, 1).data() == "left rail"
    ratio = model.row_of(5000)
    assert [model.index(ratio, c).data() for c in (5, 6, 7)] == ["1.500", "1.000", "‰"]  # per mille, not a ratio
    view.selectRow(model.row_of(4321))
    model.sort(5, Qt.DescendingOrder)
    peaks = [abs(rows[model.exceedance_at(r)].peak) for r in range(model.rowCount())]
    assert peaks == sorted(peaks, reverse=True)
    assert model.exceedance_at(view.selectionModel().selectedRows()[0].row()) == 4321  # the selection followed
    widths = model.column_widths(len)
    assert widths[0] >= len("30 m / 5 m short wave") and widths[8] >= len("Sleepers")


def test_plan_dots_one_per_pixel_and_an_isolated_fix_still_drawn(qtbot):
    """The GNSS fixes of a long survey cost a plan frame what the pixels they cover cost; a lone
    fix far from the others is still drawn."""
    import pyqtgraph as pg

    from insrail.gui.views.plan import PointsItem

    x = np.concatenate([np.linspace(0.0, 100.0, 50_000), [200.0]])
    y = np.concatenate([np.zeros(50_000), [50.0]])
    widget = pg.PlotWidget(background="w")
    qtbot.addWidget(widget)
    widget.resize(400, 300)
    points = PointsItem(x, y, "#009E73", 5)
    widget.addItem(points)
    widget.setRange(xRange=(0.0, 210.0), yRange=(-60.0, 60.0), padding=0.0)
    widget.show()
    qtbot.waitExposed(widget)
    image = widget.grab().toImage()
    assert 0 < points.drawn_points <= 400  # one dot per pixel column of the line, not 50 000
    lone = widget.mapFromScene(widget.getPlotItem().vb.mapViewToScene(pg.Point(200.0, 50.0)))
    assert image.pixelColor(lone.x(), lone.y()).name() == "#009e73"
    widget.setRange(xRange=(40.0, 41.0), yRange=(10.0, 20.0), padding=0.0)  # inside their bounds, no fix on the screen
    widget.grab()  # (an empty set of dots once crashed Qt's painter)
    assert points.drawn_points == 0


def test_the_readout_bar_keeps_its_height_and_the_plots_stay_put(view, qtbot):
    """A read-out of every plot's values is long: it must not wrap into a taller bar that pushes the
    plots down under the mouse."""
    from PySide6.QtWidgets import QApplication

    QApplication.processEvents()
    top, height = view.scroll.mapTo(view, QPoint(0, 0)).y(), view.readout.height()
    for name in view._specs:  # every plot shown: the longest read-out
        view.set_plot_visible(name.key, True)
    view.show_values_at(1100.0)
    assert len(view.readout.text()) > 400
    QApplication.processEvents()
    assert view.readout.height() == height and view.scroll.mapTo(view, QPoint(0, 0)).y() == top
    assert view.readout.toolTip() == view.readout.text()  # all of it, where the bar cuts it


def test_a_click_in_the_exceedance_table_scrolls_to_the_plot_it_names(view, qtbot):
    from PySide6.QtWidgets import QApplication

    view.resize(1366, 560)  # a laptop's track view: a few plots in view
    QApplication.processEvents()
    item = view.plots.plots["check_versine_10m"]
    viewport, bar = view.scroll.viewport().rect(), view.scroll.verticalScrollBar()

    def in_view() -> bool:
        rect = view.plots.scroll_rect("check_versine_10m").translated(view.plots.pos())
        return viewport.contains(rect.center())

    bar.setValue(bar.maximum())  # the last plots
    if in_view():
        bar.setValue(bar.minimum())
    assert not in_view()
    index = view.exceedance_model.index(0, 0)
    view.exceedances.clicked.emit(index)
    assert in_view()
    low, high = item.vb.viewRange()[0]
    assert low <= 1100.0 and 1101.0 <= high and high - low < 100.0  # zoomed there


def test_the_chainage_ruler_prints_k_chainage_wherever_the_stack_is_scrolled(qtbot):
    from PySide6.QtWidgets import QApplication

    from insrail.report.content import ChainageAxis

    data = columns()
    station = data["station_m"]
    # a station equation at 1200 m: 1200 m of station is K2+000 from there on (800 m short chain)
    labels = [f"K{int(d // 1000)}+{d % 1000:07.3f}" for d in np.where(station < 1200.0, station, station + 800.0)]
    widget = TrackView()
    qtbot.addWidget(widget)
    widget.resize(1366, 560)
    widget.show()
    widget.set_results(station, np.arange(1, SLEEPERS + 1), labels, data,
                       chainage_plots(data, load_tolerance_profile("cn_hsr_ballastless")), (), survey="run",
                       chainage=ChainageAxis.from_labels(station, tuple(labels)))
    bar = widget.scroll.verticalScrollBar()
    assert bar.maximum() > 0
    axis = widget.ruler.axis
    for scrolled in (bar.minimum(), (bar.minimum() + bar.maximum()) // 2, bar.maximum()):
        bar.setValue(scrolled)
        widget.plots.set_x_range(1150.0 + scrolled * 1e-3, 1250.0)
        QApplication.processEvents()
        assert widget.ruler.isVisible() and axis.range == list(widget.plots.x_range())
        low, high = axis.range
        (step, ticks), = axis.tickValues(low, high, axis.width())
        texts = axis.tickStrings(ticks, 1.0, step)
        assert all(text.startswith(("K1+", "K2+")) for text in texts)
        assert "K2+000" in texts or "K2+010" in texts  # round chainage after the equation
        assert any(text.startswith("K1+1") for text in texts)  # and before it
    assert not axis.label.isVisible()  # "K1+200" says what it is
    # the ruler's axis spans the plots' data area
    view = next(iter(widget.plots.plots.values())).vb
    area = widget.plots.mapFromScene(view.sceneBoundingRect()).boundingRect()
    data_left = widget.plots.mapTo(widget, area.topLeft()).x()
    axis_left = widget.ruler.mapTo(widget, widget.ruler.mapFromScene(axis.sceneBoundingRect().topLeft())).x()
    assert abs(axis_left - data_left) <= 1 and abs(axis.width() - area.width()) <= 2
