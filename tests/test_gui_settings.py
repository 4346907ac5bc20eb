"""The project settings editor (pytest-qt, offscreen): edit, validate, undo/redo, save."""

from __future__ import annotations

import shutil

import pytest

pytest.importorskip("pytestqt")
from insrail.gui.settings_editor import stages_to_rerun
from insrail.project import load_project
from insrail.project.demo import project_for_simulated_survey
from insrail.sim.scenario import preset
from insrail.sim.simulate import simulate


@pytest.fixture(scope="module")
def small_project(tmp_path_factory):
    """A demo project around a 300 m survey (not processed: the editor needs none)."""
    root = tmp_path_factory.mktemp("settings")
    config = preset("short")
    from dataclasses import replace
    config = replace(config, motion=replace(config.motion, end_station_m=config.motion.start_station_m + 300.0,
                                            stops=()))
    simulate(config, seed=3, out_dir=root / "surveys" / "short", imu_format="npy")
    project_for_simulated_survey(root, root / "surveys" / "short")
    return root


def copy_of(small_project, tmp_path):
    root = tmp_path / "project"
    shutil.copytree(small_project, root)
    return root


def test_edit_undo_redo_and_save_round_trip(window, small_project, tmp_path):
    root = copy_of(small_project, tmp_path)
    assert window.open_project(root)
    before = (root / "project.toml").read_bytes()
    editor = window.edit_settings()
    assert editor.isVisible() and window.undo_group.activeStack() is editor.undo_stack
    assert editor.rerun.text() == "" and not editor.save_button.isEnabled()

    editor.set_field("track.tolerance_profile", "cn_conventional_160")
    assert "Tolerance profile" in editor.rerun.text() and "will run: assessment, adjustment" in editor.rerun.text()
    editor.set_field("processing.gnss_sigma_floor_m", 0.004)
    assert "will run: fusion, track reconstruction, assessment, adjustment" in editor.rerun.text()
    assert window.undo_action.isEnabled() and "Undo" in window.undo_action.text()
    window.undo_action.trigger()  # the Edit menu's Undo: the sigma floor goes back
    assert editor.editors["processing.gnss_sigma_floor_m"][1].value() == pytest.approx(
        load_project(root).fusion.gnss_sigma_floor_m)
    assert "will run: assessment, adjustment" in editor.rerun.text()
    window.redo_action.trigger()
    assert editor.editors["processing.gnss_sigma_floor_m"][1].value() == pytest.approx(0.004)
    window.undo_action.trigger()

    # A problem is shown beside its field, in words, and Save waits until it is corrected.
    editor.set_field("track.design", "no-such-design.csv")
    note = editor.notes["track.design"]
    assert not note.isHidden() and note.text() == "file not found: no-such-design.csv"  # on the Track tab
    assert not editor.save_button.isEnabled() and not editor.save()
    assert (root / "project.toml").read_bytes() == before  # nothing written while there is a problem
    window.undo_action.trigger()
    assert note.isHidden()

    assert editor.save()
    saved = load_project(root)
    assert saved.tolerance_profile == "cn_conventional_160" and saved.design == load_project(small_project).design
    assert window.project.tolerance_profile == "cn_conventional_160"  # the window works on the saved project
    assert "settings saved" in window.log.toPlainText()
    assert not list(root.glob("*.tmp*")) and not list(root.glob(".project*"))  # written atomically


def test_settings_of_another_project_do_not_stay_open(window, small_project, tmp_path):
    first = copy_of(small_project, tmp_path)
    second = tmp_path / "second"
    shutil.copytree(first, second)
    assert window.open_project(first)
    editor = window.edit_settings()
    assert window.open_project(second)
    assert not editor.isVisible() and window.settings_editor is None


def test_which_stages_a_setting_reruns():
    assert stages_to_rerun(["project.name"]) == ()
    assert stages_to_rerun(["track.fastener"]) == ("adjustment",)
    assert stages_to_rerun(["geodesy.crs.scale_factor", "track.fastener"])[0] == "track reconstruction"
    assert stages_to_rerun(["trolley.imu_to_antenna_m"])[0] == "fusion"


def test_report_fields_are_edited_checked_and_saved(window, small_project, tmp_path):
    """The first page's names and dates, and the paper, in the settings editor: a bad date is named
    beside its field; Save writes them; the paper's default leaves no key in project.toml."""
    import datetime

    root = copy_of(small_project, tmp_path)
    assert window.open_project(root)
    editor = window.edit_settings()
    assert [editor.tabs.tabText(k) for k in range(editor.tabs.count())][-1] == "Report"
    assert editor.editors["report.paper"][1].currentText() == "A3"  # the default shown, not a blank
    editor.set_field("report.client", "Wuhan Railway Bureau")
    editor.set_field("report.operator", "L. Wang")
    editor.set_field("report.imu_calibrated", "2026-13-01")
    note = editor.notes["report.imu_calibrated"]
    assert not note.isHidden() and "expected a date like 2026-03-14" in note.text()
    assert not editor.save_button.isEnabled()
    editor.set_field("report.imu_calibrated", "2026-03-14")
    assert note.isHidden() and "Nothing is processed again" in editor.rerun.text()
    editor.set_field("report.paper", "A4")
    window.undo_action.trigger()  # the paper back to A3
    assert editor.editors["report.paper"][1].currentText() == "A3"
    assert editor.save()
    report = load_project(root).report
    assert (report.client, report.operator, report.imu_calibrated, report.paper) == (
        "Wuhan Railway Bureau", "L. Wang", datetime.date(2026, 3, 14), "A3")
    assert "paper" not in (root / "project.toml").read_text(encoding="utf-8")
    editor.set_field("report.paper", "A4")
    assert editor.save() and load_project(root).report.paper == "A4"
