"""The desktop application driven through its real main window (pytest-qt, offscreen).

One processed demo project is shared by the tests (the core runs once per session); the GUI's
own processing run reuses its fusion cache, so each test stays a few seconds.
"""

from __future__ import annotations

import os
import shutil
import tomllib

import numpy as np
import openpyxl
import pytest
from shared_build import built_once

pytest.importorskip("pytestqt")
from PySide6.QtCore import QSettings, Qt, QUrl
from PySide6.QtGui import QDesktopServices
from PySide6.QtWidgets import QDialogButtonBox, QFileDialog, QMessageBox, QWizard

from insrail.gui.bands import EnvelopeLine
from insrail.gui.event_dialog import EventDialog
from insrail.gui.importer import ImportWidget
from insrail.gui.main_window import MainWindow
from insrail.gui.settings import recent_projects
from insrail.io.events import read_events
from insrail.io.survey import read_manifest
from insrail.project import load_project, process
from insrail.project.demo import project_for_simulated_survey
from insrail.project.plotdata import exceedance_window
from insrail.track.tolerance import load_tolerance_profile
from tests.test_gui_track import scroll_to
from tests.test_project_lock import hold_in_child

RAW_FILES = ("imu.npy", "gnss.pos", "odometer.txt", "gauge.txt", "sleepers.txt", "benchmarks.txt")


def wait_views(window, qtbot) -> None:
    """The results are read in a worker: wait until the views hold what was asked for."""
    qtbot.waitUntil(lambda: window.loader is None, timeout=60_000)


def link_tree(source, destination) -> None:
    shutil.copytree(source, destination, copy_function=os.link)


@pytest.fixture(scope="session")
def demo_project(short_nav_survey):
    """The demo project around the simulated `short` survey, processed once per test run (read-only)."""

    def build(root):
        link_tree(short_nav_survey, root / "surveys" / "short")
        process(project_for_simulated_survey(root, root / "surveys" / "short"), "short")

    return built_once("gui-demo", build)


def test_wizard_import_process_views_and_exceedance_zoom(window, qtbot, demo_project, tmp_path):
    raw = tmp_path / "raw"
    raw.mkdir()
    survey = demo_project / "surveys" / "short"
    for name in RAW_FILES:
        os.link(survey / name, raw / name)
    project_folder = tmp_path / "project"
    # The same raw data, trolley and settings: the fusion cache of the shared demo applies.
    link_tree(demo_project / "results" / ".cache", project_folder / "results" / ".cache")
    assert window.open_project(demo_project)  # another project's results are on screen first
    wait_views(window, qtbot)
    assert window.track.plots.plots

    wizard = window.new_project()
    wizard.name.setText("GUI test")
    wizard.folder.setText(str(project_folder))
    wizard.set_crs_settings(tomllib.loads((survey / "truth" / "scenario.toml").read_text())["engineering_crs"])
    wizard.benchmarks.setText(str(raw / "benchmarks.txt"))
    wizard.set_trolley(read_manifest(survey).trolley)
    wizard.design.setText(str(survey / "truth" / "design.csv"))
    wizard.survey.add_files([raw / name for name in RAW_FILES])
    assert [role for _, role, _ in wizard.survey.entries()] == ["imu", "gnss", "odometer", "gauge", "sleepers",
                                                                "benchmarks"]
    wizard.survey.name.setText("short")
    assert "records" in wizard.survey.preview.toPlainText() or wizard.survey.preview.toPlainText()
    while wizard.currentId() != wizard.pageIds()[-1]:
        wizard.next()
    wizard.button(QWizard.FinishButton).click()
    assert wizard.problems.text() == ""
    assert window.project is not None and window.project.name == "GUI test"
    assert load_project(project_folder).surveys[0].folder == "../raw"
    assert str((project_folder / "project.toml").resolve()) in recent_projects(window.settings)
    # Nothing of the previous project stays: the new one has no results yet and says so.
    wait_views(window, qtbot)
    assert_nothing_shown(window)
    assert window.empty_state.isVisible() and window.empty_state.process_button.text() == "Process short"

    worker = window.process()
    assert worker is not None and not window.process_action.isEnabled()
    qtbot.waitUntil(lambda: window.worker is None, timeout=120_000)
    wait_views(window, qtbot)  # the new results are read in a worker: the window never waits for them
    assert "short" in window.results
    stored = window.results["short"]
    assert window.progress.isHidden() and "exceedances" in window.log.toPlainText()

    # Every view holds data.
    track_plots = window.track.plots.plots
    assert {"lateral_deviation", "vertical_deviation", "gauge", "cant"} <= set(track_plots)
    for item in track_plots.values():
        curve = next(curve for curve in item.items if isinstance(curve, EnvelopeLine))
        assert len(curve.parts[0].x) == len(stored)
    assert window.plan.stale and window.navigation.stale  # hidden tabs draw when shown
    window.tabs.setCurrentWidget(window.plan)
    assert len(window.plan.curves["centreline"].getOriginalDataset()[0]) == len(stored)
    assert len(window.plan.curves["gnss"].getOriginalDataset()[0]) > 100
    window.tabs.setCurrentWidget(window.navigation)
    assert window.navigation.items and all(any(isinstance(curve, EnvelopeLine) for curve in i.items)
                                           for i in window.navigation.items.values())
    window.tabs.setCurrentWidget(window.repeatability)
    residuals = next(s for s in window.navigation._series if s.key == "gnss_residuals")
    assert len(residuals.time_s) > 100 and np.sqrt(np.mean(residuals.values**2)) < 20.0  # mm: PPK-level agreement
    assert window.repeatability.parameter.count() > 10 and window.repeatability.item.listDataItems()
    assert window.track.exceedances.model().rowCount() == len(stored.exceedances) > 0
    window.tabs.setCurrentWidget(window.track)

    # A click on an exceedance zooms every plot there; the table starts in chainage order.
    table = window.track.exceedances
    model = table.model()
    shown_from = [float(model.index(r, 3).data()) for r in range(model.rowCount())]
    assert shown_from == sorted(shown_from)
    row = model.rowCount() // 2
    table.scrollTo(table.model().index(row, 0))
    qtbot.mouseClick(table.viewport(), Qt.LeftButton, pos=table.visualRect(table.model().index(row, 0)).center())
    exceedance = stored.exceedances[model.index(row, 0).data(Qt.UserRole)]
    assert f"{exceedance.station_from_m:.3f}" == model.index(row, 3).data()
    expected = exceedance_window(exceedance.station_from_m, exceedance.station_to_m)
    # The plots in view follow at once; each of the others when scrolled into view.
    qtbot.waitUntil(lambda: np.allclose(window.track.plots.x_range(), expected, atol=1e-6), timeout=3000)
    for item in track_plots.values():
        scroll_to(window.track, item)
        assert np.allclose(item.vb.viewRange()[0], expected, atol=1e-6)
    centre = 0.5 * (exceedance.station_from_m + exceedance.station_to_m)
    nearest = int(np.argmin(np.abs(stored.columns["station_m"] - centre)))
    assert f"sleeper {stored.number[nearest]} " in window.track.readout.text()
    window.tabs.setCurrentWidget(window.plan)
    marked = window.plan.curves["marker"].getOriginalDataset()[0]
    assert len(marked) == exceedance.last_sleeper - exceedance.first_sleeper + 1  # ringed in the plan too

    # Sorted by peak, the top row is the largest exceedance, and a click still zooms to it.
    window.tabs.setCurrentWidget(window.track)
    table.sortByColumn(5, Qt.DescendingOrder)
    qtbot.mouseClick(table.viewport(), Qt.LeftButton, pos=table.visualRect(table.model().index(0, 0)).center())
    largest = max(stored.exceedances, key=lambda e: abs(e.peak))
    expected = exceedance_window(largest.station_from_m, largest.station_to_m)
    assert np.allclose(window.track.plots.x_range(), expected, atol=1e-6)

    # The explorer offers to process one survey again.
    results_item = window.explorer.findItems("Results", Qt.MatchRecursive)[0].child(0)
    assert [text for text, _ in window.explorer.context_actions(results_item)] == [
        "Show results of short", "Process short again"]


def assert_nothing_shown(window) -> None:
    """No view holds any survey's data."""
    assert not window.track.plots.plots and window.track.exceedances.model().rowCount() == 0
    assert window.track.readout.text() == ""
    assert window.plan.data is None and not window.plan.curves
    assert not window.navigation._series and not window.navigation.items
    assert not window.repeatability._runs
    assert window.shown_survey is None and not window.export_pdf_action.isEnabled()


def test_the_shown_results_are_frozen_out_of_the_cyclic_collector_until_the_next_load(window, qtbot, demo_project,
                                                                                     tmp_path, monkeypatch):
    """A full cyclic collection over the loaded results took 30-180 ms, now and then inside a pan frame:
    once loaded they are frozen (the collector skips them), and released when the next load starts."""
    import gc

    calls = []
    for name in ("freeze", "unfreeze"):
        real = getattr(gc, name)
        monkeypatch.setattr(gc, name, lambda real=real, name=name: (calls.append(name), real())[1])
    assert window.open_project(demo_project)
    wait_views(window, qtbot)
    assert calls[-2:] == ["unfreeze", "freeze"] and gc.get_freeze_count() > 10_000
    root = tmp_path / "unprocessed"
    link_tree(demo_project / "surveys", root / "surveys")
    shutil.copy(demo_project / "project.toml", root / "project.toml")
    calls.clear()
    assert window.open_project(root)
    assert calls[0] == "unfreeze"  # the previous project's leftovers are collectable again
    wait_views(window, qtbot)
    assert calls[-1] == "freeze"


def test_an_unprocessed_project_shows_nothing_of_the_previous_one(window, qtbot, demo_project, tmp_path):
    assert window.open_project(demo_project)
    wait_views(window, qtbot)
    for view in (window.plan, window.navigation, window.repeatability, window.track):
        window.tabs.setCurrentWidget(view)  # every view drawn with the demo's results
    assert window.track.plots.plots and window.plan.curves and window.navigation.items
    root = tmp_path / "unprocessed"
    link_tree(demo_project / "surveys", root / "surveys")
    shutil.copy(demo_project / "project.toml", root / "project.toml")
    assert window.open_project(root)
    wait_views(window, qtbot)
    assert_nothing_shown(window)
    for view in (window.plan, window.navigation, window.repeatability):
        window.tabs.setCurrentWidget(view)
    assert_nothing_shown(window)
    assert window.empty_state.isVisible() and "short has no results yet" in window.empty_state.message.text()
    assert window.windowTitle() == f"{window.project.name} — {root.resolve()} — insrail"
    started = []
    window.process = lambda surveys=None: started.append(surveys)
    window.empty_state.process_button.click()  # the empty state offers Process
    assert started == [["short"]]


def test_cancel_stops_the_run_and_keeps_the_previous_results(window, qtbot, demo_project, tmp_path):
    root = tmp_path / "copy"
    link_tree(demo_project / "surveys", root / "surveys")
    shutil.copy(demo_project / "project.toml", root / "project.toml")
    link_tree(demo_project / "results" / "short", root / "results" / "short")  # results without the fusion cache
    before = (root / "results" / "short" / "summary.toml").read_bytes()
    assert window.open_project(root)
    wait_views(window, qtbot)
    assert window.track.exceedances.model().rowCount() > 0  # previous results shown

    window.process()
    qtbot.waitUntil(lambda: window.progress.value() > 60, timeout=30_000)  # inside the fusion
    assert window.cancel_button.isVisible()
    window.cancel_button.click()
    qtbot.waitUntil(lambda: window.worker is None, timeout=30_000)
    assert "cancelled" in window.log.toPlainText()
    assert (root / "results" / "short" / "summary.toml").read_bytes() == before
    assert not list((root / "results").glob(".short.*"))  # no half-written result folder


def test_reader_errors_show_file_line_and_problem(qtbot, tmp_path):
    widget = ImportWidget()
    qtbot.addWidget(widget)
    bad = tmp_path / "gauge.txt"
    bad.write_text("# format: gauge-mm\n230400.0 1435.1\n230400.1 1435.2\n230400.2 abc\n")
    widget.add_files([bad])
    problems = widget.check()
    located = [p for p in problems if p.file == "gauge.txt"]
    assert located and located[0].line == 4
    assert widget.problems.item([p.file for p in problems].index("gauge.txt"), 1).text() == "4"
    assert any("imu" in p.message for p in problems)  # required roles missing
    assert widget.write_survey(None) is None and not (tmp_path / "survey.toml").exists()


def test_unsaved_changes_prompt_before_they_are_lost(window, demo_project, monkeypatch):
    assert window.open_project(demo_project)
    window.modified = True
    asked = []
    monkeypatch.setattr(QMessageBox, "question", lambda *a, **k: asked.append(a) or QMessageBox.Cancel)
    assert not window.open_project(demo_project)  # the user cancelled: the project stays open
    assert asked and window.modified
    monkeypatch.setattr(QMessageBox, "question", lambda *a, **k: QMessageBox.Discard)
    assert window.open_project(demo_project) and not window.modified


def test_window_layout_and_recent_projects_are_remembered(qtbot, demo_project, tmp_path):
    settings = QSettings(str(tmp_path / "settings.ini"), QSettings.IniFormat)
    first = MainWindow(settings)
    qtbot.addWidget(first)
    first.show()
    first.resize(701, 555)  # the offscreen screen is 800 x 800
    first.open_project(demo_project)
    first.close()
    second = MainWindow(QSettings(str(tmp_path / "settings.ini"), QSettings.IniFormat))
    qtbot.addWidget(second)
    second.show()
    assert (second.width(), second.height()) == (701, 555)
    assert [a.text() for a in second.recent_menu.actions()] == [str((demo_project / "project.toml").resolve())]


def test_repeatability_overlays_plain_arrays_of_several_runs(qtbot):
    from insrail.gui.views.repeatability import RepeatabilityView

    view = RepeatabilityView()
    qtbot.addWidget(view)
    station = np.linspace(0.0, 100.0, 161)
    runs = {f"run{k}": (station, {"gauge_mm": 1435.0 + 0.1 * k + np.sin(station), "time_s": station,
                                  "check_versine_10m_left_lateral_mm": np.cos(station)}) for k in range(3)}
    view.set_runs(runs, load_tolerance_profile("cn_hsr_ballastless").checks)
    assert view.stale and not view.item.listDataItems()  # drawn when shown
    view.show()
    # display names, never the columns' ids
    assert [view.parameter.itemText(i) for i in range(view.parameter.count())] == [
        "Gauge (mm)", "10 m versine, left rail, lateral (mm)"]
    curves = view.item.listDataItems()
    assert len(curves) == 3
    assert np.allclose(curves[2].getOriginalDataset()[1], runs["run2"][1]["gauge_mm"])


def test_void_qt_calls_do_not_exhaust_none():
    """The installed shiboken6 returns None without a reference on Python 3.11 (see _binding_fix):
    a long session of painter calls must not deallocate None."""
    import sys

    from PySide6.QtGui import QImage, QPainter, QPen

    image = QImage(8, 8, QImage.Format_ARGB32)
    painter = QPainter(image)
    pen = QPen()
    before = sys.getrefcount(None)
    for _ in range(20_000):
        painter.setPen(pen)
    painter.end()
    assert sys.getrefcount(None) > 2**39 or sys.getrefcount(None) >= before


def broken_gauge_project(demo_project, tmp_path):
    """The demo project with a gauge record whose line 10 holds "1435.x"."""
    root = tmp_path / "broken"
    link_tree(demo_project / "surveys", root / "surveys")
    shutil.copy(demo_project / "project.toml", root / "project.toml")
    gauge = root / "surveys" / "short" / "gauge.txt"
    lines = gauge.read_text().splitlines()
    gauge.unlink()  # a hard link to the shared demo: replace it, never write through it
    lines[9] = "230400.4 1435.x"
    gauge.write_text("\n".join(lines) + "\n")
    return root


def test_a_reader_error_while_processing_is_reported_with_file_and_line(window, qtbot, demo_project, tmp_path,
                                                                       monkeypatch):
    root = broken_gauge_project(demo_project, tmp_path)
    shown = []
    monkeypatch.setattr(QMessageBox, "warning", lambda *args: shown.append(args[2]))
    assert window.open_project(root)
    window.process()
    qtbot.waitUntil(lambda: window.worker is None, timeout=30_000)
    assert shown and "gauge.txt, line 10" in shown[0]
    assert "error: survey short:" in window.log.toPlainText()
    assert not (root / "results" / "short").exists()


def test_a_chinese_window_says_a_reader_error_in_chinese_with_the_file_name_as_it_is(window, qtbot, demo_project,
                                                                                     tmp_path, monkeypatch):
    from PySide6.QtWidgets import QApplication

    from insrail.gui.translation import install_language

    root = broken_gauge_project(demo_project, tmp_path)
    shown = []
    monkeypatch.setattr(QMessageBox, "warning", lambda *args: shown.append(args[2]))
    install_language(QApplication.instance(), "zh-CN")
    try:
        assert window.open_project(root)
        window.process()
        qtbot.waitUntil(lambda: window.worker is None, timeout=30_000)
    finally:
        install_language(QApplication.instance(), "en")
    assert shown and "gauge.txt，第 10 行：第 2 列" in shown[0], shown
    assert "应为数值，实为 '1435.x'" in shown[0] and "expected" not in shown[0]
    assert "gauge.txt，第 10 行" in window.log.toPlainText()
    assert not (root / "results" / "short").exists()


def test_wizard_lists_the_project_problems_in_words(window, demo_project, tmp_path):
    wizard = window.new_project()
    wizard.folder.setText(str(tmp_path / "p"))
    wizard.benchmarks.setText(str(tmp_path / "missing.txt"))
    wizard.set_trolley(read_manifest(demo_project / "surveys" / "short").trolley)
    manifest = demo_project / "surveys" / "short" / "survey.toml"
    before = manifest.read_bytes()
    wizard.survey.load_survey_folder(manifest.parent)
    assert wizard.survey.name.text() == "short" and wizard.survey.gps_week.value() == 2380
    assert not wizard.create_project()
    assert "Benchmarks file: file not found" in wizard.problems.text()
    assert "geodesy." not in wizard.problems.text()  # words, not key paths
    assert window.project is None and not (tmp_path / "p" / "project.toml").exists()
    assert manifest.read_bytes() == before  # a rejected project writes nothing


def pages_of(wizard):
    return {wizard.page(i).title(): i for i in wizard.pageIds()}


def test_wizard_checks_each_page_creates_the_folder_and_copies_the_raw_files(window, qtbot, demo_project, tmp_path):
    assert window.open_project(demo_project)  # a recent project: its trolley is offered
    wait_views(window, qtbot)
    raw = tmp_path / "raw"
    raw.mkdir()
    for name in RAW_FILES:
        os.link(demo_project / "surveys" / "short" / name, raw / name)
    survey = demo_project / "surveys" / "short"
    folder = tmp_path / "new" / "deeper"  # does not exist yet
    wizard = window.new_project()
    wizard.show()
    pages = pages_of(wizard)
    wizard.name.setText("Wizard test")
    wizard.folder.setText(str(folder))
    wizard.next()
    assert folder.is_dir() and wizard.currentId() == pages["Coordinate system"]
    assert "created the folder" in wizard.notes["folder"].text()
    wizard.set_crs_settings(tomllib.loads((survey / "truth" / "scenario.toml").read_text())["engineering_crs"])
    wizard.next()

    wizard.benchmarks.setText(str(tmp_path / "missing.txt"))
    wizard.next()  # checked as it is left: the problem beside its field
    assert wizard.currentId() == pages["Benchmarks"]
    note = wizard.notes["geodesy.height.benchmarks"]
    assert note.isVisible() and note.text().startswith("file not found")
    wizard.benchmarks.setText(str(raw / "benchmarks.txt"))
    wizard.next()
    assert wizard.currentId() == pages["Trolley geometry"] and not note.isVisible()

    wizard.next()  # every lever arm at 0 m: named, and confirmed before going on
    assert wizard.currentId() == pages["Trolley geometry"]
    assert "IMU → GNSS antenna" in wizard.page_notes[3].text() and wizard.zero_arms_ok.isVisible()
    assert wizard.notes["trolley.imu_to_odometer_m"].text() == "0 m: is this lever arm measured?"
    assert wizard.earlier.isEnabled() and wizard.earlier.itemText(1) == str((demo_project / "project.toml").resolve())
    wizard.earlier.activated.emit(1)  # the trolley of the earlier project
    expected = read_manifest(survey).trolley
    assert [box.value() for box in wizard.lever_arms["imu_to_antenna_m"]] == pytest.approx(expected.imu_to_antenna_m)
    wizard.next()
    assert wizard.currentId() == pages["Processing and assessment"]
    wizard.design.setText(str(survey / "truth" / "design.csv"))
    wizard.next()

    wizard.survey.add_files([raw / name for name in RAW_FILES])
    wizard.survey.name.setText("short")
    assert f"raw-data folder {raw}" in wizard.raw_note.text()  # says where survey.toml would go
    wizard.copy_raw.setChecked(True)
    assert str(folder / "surveys" / "short") in wizard.raw_note.text()
    wizard.button(QWizard.FinishButton).click()
    assert wizard.problems.text() == ""
    assert window.project is not None and window.project.name == "Wizard test"
    assert sorted(p.name for p in raw.iterdir()) == sorted(RAW_FILES)  # the raw-data folder untouched
    copied = folder / "surveys" / "short"
    assert (copied / "survey.toml").is_file() and all((copied / name).is_file() for name in RAW_FILES)
    assert load_project(folder).surveys[0].folder == "surveys/short"
    wait_views(window, qtbot)
    assert_nothing_shown(window)  # the previous project's results are gone


def test_a_cancelled_wizard_removes_the_folder_it_created(window, tmp_path):
    wizard = window.new_project()
    folder = tmp_path / "not yet"
    wizard.folder.setText(str(folder))
    wizard.next()
    assert folder.is_dir()
    wizard.reject()
    assert not folder.exists() and window.project is None


def test_import_adds_a_survey_to_the_open_project(window, demo_project, tmp_path, monkeypatch):
    warnings = []
    monkeypatch.setattr(QMessageBox, "warning", lambda *args: warnings.append(args[2]))
    root = tmp_path / "project"
    link_tree(demo_project / "surveys", root / "surveys")
    shutil.copy(demo_project / "project.toml", root / "project.toml")
    raw = root / "second-run"
    raw.mkdir()
    for name in RAW_FILES:
        os.link(demo_project / "surveys" / "short" / name, raw / name)
    assert window.open_project(root)
    dialog = window.import_survey()
    dialog.widget.add_files(sorted(raw.iterdir()))
    dialog.widget.name.setText("second-run")
    dialog.accept()
    assert not warnings and dialog.folder == raw.resolve()
    assert [s.name for s in window.project.surveys] == ["short", "second-run"]
    assert window.modified and window.windowTitle().startswith(f"{window.project.name} * ")
    # The project has no trolley of its own: the first survey's geometry went into survey.toml.
    assert read_manifest(raw).trolley.reference_rail == read_manifest(root / "surveys" / "short").trolley.reference_rail
    assert window.save_project() and not window.modified
    assert [s.name for s in load_project(root).surveys] == ["short", "second-run"]


def processed_copy(demo_project, root):
    """The demo project with its results (hard links; new files land in the copy only)."""
    link_tree(demo_project / "surveys", root / "surveys")
    shutil.copy(demo_project / "project.toml", root / "project.toml")
    link_tree(demo_project / "results" / "short", root / "results" / "short")
    return root


def test_a_turnout_marked_on_the_track_plot_is_placed_and_assessed_after_processing_again(window, qtbot, demo_project,
                                                                                           tmp_path):
    root = processed_copy(demo_project, tmp_path / "copy")
    link_tree(demo_project / "results" / ".cache", root / "results" / ".cache")  # only the assessment reruns
    assert window.open_project(root)
    wait_views(window, qtbot)
    window.tabs.setCurrentWidget(window.track)
    track = window.track
    assert window.project.events is None and not track._events and window.events_banner.isHidden()
    track.measure_button.setChecked(True)

    def inside(rows):
        return [e for e in rows if low <= min(e.station_from_m, e.station_to_m)
                and max(e.station_from_m, e.station_to_m) <= high]

    first = track._rows[0]  # a turnout over an exceedance: not assessed there once processed again
    low = min(first.station_from_m, first.station_to_m) - 3.0
    high = max(first.station_from_m, first.station_to_m) + 3.0
    assert inside(track._rows)
    for point in (high, low):
        track.measure(track._specs[0].key, point)
    low, high = track.measured_span()  # the sleepers nearest to the clicks
    editor = window.edit_settings()  # open on the settings as they were: saving it must keep the new file
    track.mark_event_button.click()
    dialog = window.findChild(EventDialog)
    assert dialog.isVisible() and float(dialog.start.text()) == pytest.approx(low, abs=1e-3)
    dialog.set_kind("turnout")
    dialog.text.setText("W12")
    dialog.buttons.button(QDialogButtonBox.Ok).click()
    assert read_project_events(root) == [("turnout", pytest.approx(low, abs=1e-3), pytest.approx(high, abs=1e-3), "W12")]
    assert tomllib.loads((root / "project.toml").read_text())["track"]["events"] == "events.txt"
    # The results are now older than their events: said over the views, with Process.
    assert window.events_banner.isVisible() and "short" in window.events_banner.message.text()
    assert track._events == ()  # nothing drawn that processing has not placed
    assert editor.document["track"]["events"] == "events.txt" and not editor.save_button.isEnabled()
    # A level crossing further on: appended to the file the project now names.
    crossing = [float(track._station[-200]), float(track._station[-180])]
    for point in crossing:
        track.measure(track._specs[0].key, point)
    track.mark_event_button.click()
    dialog = [d for d in window.findChildren(EventDialog) if d.isVisible()][-1]
    dialog.set_kind("level_crossing")
    dialog.text.setText("LC 3")
    dialog.buttons.button(QDialogButtonBox.Ok).click()
    assert [e[0] for e in read_project_events(root)] == ["turnout", "level_crossing"]

    window.events_banner.process_button.click()
    qtbot.waitUntil(lambda: window.worker is None, timeout=600_000)
    wait_views(window, qtbot)
    assert window.events_banner.isHidden()
    span, level_crossing = sorted(window.track._events, key=lambda e: e.station_from_m)
    assert span.name == "turnout W12" and span.not_assessed
    assert (span.station_from_m, span.station_to_m) == pytest.approx((low, high), abs=1e-3)
    assert level_crossing.name == "level crossing LC 3" and level_crossing.not_assessed
    assert (level_crossing.station_from_m, level_crossing.station_to_m) == pytest.approx(crossing, abs=1e-3)
    summary = tomllib.loads((root / "results" / "short" / "summary.toml").read_text())
    assert summary["assessment"]["not_assessed_sleepers"] > 0
    assert window.track._rows and not inside(window.track._rows)


def read_project_events(root):
    return [(e.kind, e.start, e.end, e.text) for e in read_events(root / "events.txt").events]


def test_export_both_reports_and_open_their_folder(window, qtbot, demo_project, tmp_path, monkeypatch):
    root = processed_copy(demo_project, tmp_path / "copy")
    assert not window.export_pdf_action.isEnabled()  # no results yet
    assert window.open_project(root)
    wait_views(window, qtbot)
    assert window.export_xlsx_action.isEnabled() and window.export_pdf_action.isEnabled()
    assert not window.tabs.isTabVisible(window.tabs.indexOf(window.gnss))  # no raw GNSS in the demo
    suggested = []
    monkeypatch.setattr(QFileDialog, "getSaveFileName", lambda parent, title, path, filter: (
        suggested.append(path) or path, filter))
    opened = []
    monkeypatch.setattr(QDesktopServices, "openUrl", lambda url: opened.append(url) or True)
    folder = root / "reports"

    window.export_xlsx_action.trigger()
    assert window.progress.isVisible() and not window.export_pdf_action.isEnabled()  # one job at a time
    qtbot.waitUntil(lambda: window.worker is None, timeout=30_000)
    workbook = folder / "track_geometry_short.xlsx"
    assert suggested == [str(workbook)]
    assert workbook.read_bytes()[:4] == b"PK\x03\x04" and "Sleepers" in openpyxl.load_workbook(workbook).sheetnames
    assert window.status.text() == f"Written {workbook.name} in {folder.resolve()}"
    assert window.open_folder_button.isVisible()
    window.open_folder_button.click()
    assert opened == [QUrl.fromLocalFile(str(folder.resolve()))]

    window.export_pdf_action.trigger()
    assert window.open_folder_button.isHidden()  # belongs to the previous export
    qtbot.waitUntil(lambda: window.worker is None, timeout=30_000)
    report = folder / "track_geometry_short.pdf"
    assert suggested[1] == str(report) and report.read_bytes()[:5] == b"%PDF-"
    assert f"written {report.resolve()}" in window.log.toPlainText()


def test_reports_older_than_the_results_are_marked_and_written_again_in_one_click(window, qtbot, demo_project,
                                                                                   tmp_path):
    root = processed_copy(demo_project, tmp_path / "copy")
    assert window.open_project(root)
    wait_views(window, qtbot)
    assert window.stale_banner.isHidden()  # no report written yet: nothing out of date
    reports = [root / "reports" / f"track_geometry_short.{kind}" for kind in ("xlsx", "pdf")]
    reports[0].parent.mkdir()
    for kind, path in zip(("xlsx", "pdf"), reports):
        window.export_report(kind, path)
        qtbot.waitUntil(lambda: window.worker is None, timeout=120_000)
    assert window.stale_banner.isHidden()
    results_item = window.explorer.findItems("Results", Qt.MatchRecursive)[0].child(0)
    assert [results_item.child(k).text(0) for k in range(results_item.childCount())] == [p.name for p in reports]

    # The survey was processed again since (its summary, written last, is newer than the reports).
    summary = root / "results" / "short" / "summary.toml"
    for path in reports:
        os.utime(path, (summary.stat().st_mtime - 60, summary.stat().st_mtime - 60))
    assert window.open_project(root)
    wait_views(window, qtbot)
    assert window.stale_banner.isVisible()
    assert "track_geometry_short.xlsx and track_geometry_short.pdf of survey short" in window.stale_banner.message.text()
    results_item = window.explorer.findItems("Results", Qt.MatchRecursive)[0].child(0)
    assert all(results_item.child(k).text(0).startswith("⚠") for k in range(results_item.childCount()))
    assert "Write the out-of-date reports of short again" in [t for t, _ in window.explorer.context_actions(results_item)]

    window.stale_banner.rewrite_button.click()  # one click: both written again at their places
    qtbot.waitUntil(lambda: window.worker is None, timeout=120_000)
    assert all(path.stat().st_mtime >= summary.stat().st_mtime for path in reports)
    assert window.stale_banner.isHidden()
    results_item = window.explorer.findItems("Results", Qt.MatchRecursive)[0].child(0)
    assert [results_item.child(k).text(0) for k in range(results_item.childCount())] == [p.name for p in reports]


def test_an_export_while_another_process_holds_the_survey_waits_in_its_worker(window, qtbot, demo_project, tmp_path,
                                                                              monkeypatch):
    root = processed_copy(demo_project, tmp_path / "copy")
    assert window.open_project(root)
    wait_views(window, qtbot)
    shown = []
    monkeypatch.setattr(QMessageBox, "warning", lambda *args: shown.append(args[1:]))
    target = tmp_path / "report.xlsx"
    holder = hold_in_child(root, "short")  # a command-line run of the survey
    try:
        assert window.export_report("xlsx", target) is not None
        # the GUI thread runs these waits' event loops: it is never the one waiting for the lock
        qtbot.waitUntil(lambda: f"by PID {holder.pid}" in window.status.text(), timeout=30_000)
        assert window.status.text().startswith("waiting for the run started at ")
        qtbot.wait(500)
        assert window.worker is not None and not target.exists()
    finally:
        holder.kill()
        holder.wait()
    qtbot.waitUntil(lambda: window.worker is None, timeout=120_000)
    assert target.read_bytes()[:4] == b"PK\x03\x04" and shown == []


def test_cancel_an_export_writes_nothing(window, qtbot, demo_project, tmp_path):
    root = processed_copy(demo_project, tmp_path / "copy")
    assert window.open_project(root)
    wait_views(window, qtbot)
    target = tmp_path / "out" / "report.pdf"
    target.parent.mkdir()
    assert window.export_report("pdf", target) is not None
    window.cancel_button.click()  # the report takes far longer than this click
    qtbot.waitUntil(lambda: window.worker is None, timeout=30_000)
    assert "export cancelled; nothing written" in window.log.toPlainText()
    assert list(target.parent.iterdir()) == []  # neither the report nor its temporary file
    assert window.open_folder_button.isHidden() and window.status.text() == "Ready"


def test_export_error_names_the_file_and_the_problem(window, qtbot, demo_project, tmp_path, monkeypatch):
    root = processed_copy(demo_project, tmp_path / "copy")
    assert window.open_project(root)
    wait_views(window, qtbot)
    shown = []
    monkeypatch.setattr(QMessageBox, "warning", lambda parent, title, text: shown.append((title, text)))
    target = tmp_path / "no such folder" / "short"  # the suffix is added
    window.export_report("xlsx", target)
    qtbot.waitUntil(lambda: window.worker is None, timeout=30_000)
    assert shown == [("Export failed", (f"Excel workbook {target}.xlsx: cannot write the file: "
                                       "No such file or directory"))]


def test_about_shows_the_version_and_actions_have_shortcuts(window, monkeypatch):
    from insrail import __version__

    shown = []
    monkeypatch.setattr(QMessageBox, "about", lambda parent, title, text: shown.append(text))
    window.about_action.trigger()
    assert shown and f"insrail {__version__}" in shown[0]
    for action, keys in ((window.export_xlsx_action, "Ctrl+E"), (window.export_pdf_action, "Ctrl+Shift+E"),
                         (window.plan_survey_action, "Ctrl+Shift+P"), (window.ppk_action, "F6")):
        assert action.shortcut().toString() == keys and keys in action.toolTip()


def test_views_come_back_as_they_were_left_per_project(qtbot, demo_project, tmp_path):
    settings = tmp_path / "settings.ini"
    first = MainWindow(QSettings(str(settings), QSettings.IniFormat))
    qtbot.addWidget(first)
    first.show()
    assert first.open_project(demo_project)
    wait_views(first, qtbot)
    first.track.set_plot_visible("cant", False)
    first.track.plots.set_x_range(1100.0, 1150.0)
    first.tabs.setCurrentWidget(first.plan)
    first.close()

    second = MainWindow(QSettings(str(settings), QSettings.IniFormat))
    qtbot.addWidget(second)
    second.show()
    assert second.open_project(demo_project)
    wait_views(second, qtbot)
    assert second.tabs.currentWidget() is second.plan
    second.tabs.setCurrentWidget(second.track)
    assert "cant" not in second.track.plots.plots and "gauge" in second.track.plots.plots
    assert np.allclose(second.track.plots.x_range(), (1100.0, 1150.0), atol=1e-6)
    second.close()


def test_export_for_machines_and_cad_from_the_file_menu(window, qtbot, demo_project, tmp_path, monkeypatch):
    """File > Export > DXF drawing / Lift/lining table: the same files as `insrail export`."""
    import ezdxf

    from insrail.export.liftlining import read_lift_lining

    root = processed_copy(demo_project, tmp_path / "copy")
    assert not any(a.isEnabled() for a in window.export_file_actions)  # nothing shown yet
    assert window.open_project(root)
    wait_views(window, qtbot)
    texts = [a.text() for a in window.export_file_actions]
    assert texts == ["&Lift/lining table…", "&DXF drawing…", "Measured lines as &LandXML…", "Sleeper &coordinates…"]
    assert all(a.isEnabled() for a in window.export_file_actions)
    suggested = []
    monkeypatch.setattr(QFileDialog, "getSaveFileName", lambda parent, title, path, filter: (
        suggested.append(path) or path, filter))
    window.export_file_actions[1].trigger()
    qtbot.waitUntil(lambda: window.worker is None, timeout=30_000)
    drawing = root / "reports" / "short.dxf"
    assert suggested == [str(drawing)] and window.status.text() == f"Written {drawing.name} in {drawing.parent.resolve()}"
    assert len(ezdxf.readfile(drawing).modelspace().query('LINE[layer=="INSRAIL_SLEEPERS"]')) > 1000
    window.export_file_actions[0].trigger()
    qtbot.waitUntil(lambda: window.worker is None, timeout=30_000)
    assert len(read_lift_lining(root / "reports" / "short_lift_lining.csv")) > 1000


def test_the_first_window_fits_the_screen_it_opens_on(qtbot, tmp_path):
    """No saved geometry: the window fits the available area of its screen (a 1366 x 768 laptop must
    see the go-to field, the log and the status bar)."""
    main = MainWindow(QSettings(str(tmp_path / "settings.ini"), QSettings.IniFormat))
    qtbot.addWidget(main)
    main.show()
    qtbot.waitExposed(main)
    available = main.screen().availableGeometry()
    assert available.width() < 1400 or available.height() < 900  # the offscreen screen is smaller
    # (the offscreen platform's pretend frame shifts the window by 2 px: the sizes are compared)
    assert main.width() <= available.width() and main.height() <= available.height()
    assert main.statusBar().geometry().bottom() < available.height()
    main.close()
