"""The project settings editor (pytest-qt, offscreen): edit, validate, undo/redo, save."""

from __future__ import annotations

import shutil

import pytest
from PySide6.QtWidgets import QLabel

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


def type_into(box, text: str) -> None:
    """Type ``text`` into a number field KEY BY KEY as a surveyor does: select what it shows, type,
    then Return commits the edit."""
    from PySide6.QtCore import Qt
    from PySide6.QtTest import QTest

    box.setFocus()
    QTest.keyClick(box, Qt.Key_A, Qt.ControlModifier)
    QTest.keyClicks(box, text)
    QTest.keyClick(box, Qt.Key_Return)


def test_numbers_typed_key_by_key_are_saved_exactly_as_typed(window, small_project, tmp_path):
    """Every kind of number field (the coordinate system, a lever arm, the mounting angles, a
    processing threshold, an integer): what is typed is what project.toml holds; each committed edit
    is one undo step."""
    import tomllib

    root = copy_of(small_project, tmp_path)
    assert window.open_project(root)
    editor = window.edit_settings()
    editor.own_trolley.click()  # the project's own trolley table: its fields become editable
    steps = editor.undo_stack.count()
    field = {key: widget for key, (_spec, widget) in editor.editors.items()}
    typed = [(field["geodesy.crs.false_northing_m"], "45.5"),
             (field["geodesy.crs.false_easting_m"], "500123.125"),
             (field["trolley.imu_to_prism_m"].boxes[0], "0.125"),
             (field["trolley.imu_to_prism_m"].boxes[2], "-1.45"),
             (field["trolley.imu_to_odometer_right_m"].boxes[1], "0.7425"),
             (field["trolley.mounting_rpy_deg"].boxes[1], "-0.25"),
             (field["processing.gnss_sigma_floor_m"], "0.0125"),
             (field["track.first_sleeper_number"], "1201")]
    before = (root / "project.toml").read_bytes()
    for box, text in typed:
        type_into(box, text)
    assert editor.undo_stack.count() == steps + len(typed)  # one step per committed edit, none per key
    assert (root / "project.toml").read_bytes() == before  # Return commits the field, Save writes
    assert editor.save() and not editor.isWindowModified()
    saved = tomllib.loads((root / "project.toml").read_text(encoding="utf-8"))
    crs, trolley = saved["geodesy"]["crs"], saved["trolley"]
    assert (crs["false_northing_m"], crs["false_easting_m"]) == (45.5, 500123.125)
    assert (trolley["imu_to_prism_m"][0], trolley["imu_to_prism_m"][2]) == (0.125, -1.45)
    assert trolley["imu_to_odometer_right_m"] == [0.0, 0.7425, 0.0]  # the second odometer's wheel
    assert trolley["mounting_rpy_deg"][1] == -0.25
    assert saved["processing"]["gnss_sigma_floor_m"] == 0.0125
    assert saved["track"]["first_sleeper_number"] == 1201

    editor.undo_stack.undo()  # the last committed edit back, as one step
    assert field["track.first_sleeper_number"].value() != 1201
    assert field["processing.gnss_sigma_floor_m"].value() == 0.0125


def test_a_field_left_without_a_change_changes_nothing(window, small_project, tmp_path):
    """Values are compared at the field's precision: a value of project.toml with more decimals than
    its field shows stays as it is when the field (or another of its vector) is only visited."""
    root = copy_of(small_project, tmp_path)
    text = (root / "project.toml").read_text(encoding="utf-8")
    (root / "project.toml").write_text(text + "\n[trolley]\nimu_to_prism_m = [0.123456, 0.0, -1.2]\n"
                                       "imu_to_antenna_m = [0.1, 0.0, -1.0]\nimu_to_odometer_m = [0.0, 0.3, 0.2]\n"
                                       "imu_to_reference_rail_m = [0.0, -0.7, 0.3]\n"
                                       "imu_to_sleeper_detector_m = [0.2, 0.0, 0.3]\n", encoding="utf-8")
    assert window.open_project(root)
    editor = window.edit_settings()
    prism = editor.editors["trolley.imu_to_prism_m"][1].boxes
    type_into(prism[0], prism[0].cleanText())  # what it shows, typed again
    assert editor.undo_stack.count() == 0 and not editor.isWindowModified()
    type_into(prism[1], "0.05")
    assert editor.document["trolley"]["imu_to_prism_m"] == [0.123456, 0.05, -1.2]
    editor.set_field("trolley.imu_to_prism_m", [0.1, 0.2, -1.3])  # a whole vector: one step
    assert editor.undo_stack.count() == 2 and editor.document["trolley"]["imu_to_prism_m"] == [0.1, 0.2, -1.3]


def test_a_setting_not_given_shows_no_number(window, small_project, tmp_path):
    """The demo project has no trolley table: its fields say "not given" instead of a sentinel, and the
    lever arms' columns are named in the trolley's frame (forward, right, down)."""
    root = copy_of(small_project, tmp_path)
    assert window.open_project(root)
    editor = window.edit_settings()
    spacing = editor.editors["trolley.rail_centre_spacing_m"][1]
    assert spacing.text() == "not given" and "1000000000" not in spacing.text()
    assert all(box.text() == "not given" for box in editor.editors["trolley.imu_to_prism_m"][1].boxes)
    headings = [label.text() for label in editor.findChildren(QLabel)]
    assert "forward" in headings and "right" in headings and "down" in headings


def test_the_main_window_undo_offers_no_settings_edit_of_a_closed_editor(window, small_project, tmp_path):
    root = copy_of(small_project, tmp_path)
    assert window.open_project(root)
    editor = window.edit_settings()
    editor.set_field("report.client", "Wuhan Railway Bureau")
    assert window.undo_action.isEnabled()
    assert editor.isWindowModified() and "[*]" in editor.windowTitle()  # Qt shows it as "*" while unsaved
    editor.close()
    assert not window.undo_action.isEnabled()  # nothing invisible is undone
    assert window.edit_settings() is editor and window.undo_action.isEnabled()


def test_lists_and_the_properties_show_names_not_ids(window, small_project, tmp_path):
    """The tolerance profile, the fastener type and the projection height convention are listed in
    words (a shipped file's own description), and project.toml still gets the ids."""
    import tomllib

    root = copy_of(small_project, tmp_path)
    assert window.open_project(root)
    editor = window.edit_settings()
    lists = {key: editor.editors[key][1] for key in ("track.tolerance_profile", "track.fastener",
                                                     "geodesy.crs.projection_height_convention",
                                                     "geodesy.height.model")}
    shown = {key: [box.itemText(i) for i in range(box.count())] for key, box in lists.items()}
    assert not any("_" in text or text in ("wj7", "wj8", "auto") for texts in shown.values() for text in texts)
    assert "Conventional main line > 160 km/h, maintenance work acceptance" in shown["track.tolerance_profile"]
    assert any(text.startswith("WJ-7") for text in shown["track.fastener"])
    box = lists["track.tolerance_profile"]
    box.setCurrentIndex(box.findText("Conventional main line > 160 km/h, maintenance work acceptance"))
    editor.set_field("track.fastener", "wj8")
    assert editor.save()
    saved = tomllib.loads((root / "project.toml").read_text(encoding="utf-8"))
    assert (saved["track"]["tolerance_profile"], saved["track"]["fastener"]) == ("cn_conventional_160", "wj8")
    window.explorer.setCurrentItem(window.explorer.topLevelItem(0))  # the project: its properties
    texts = [value for _key, value in window.properties.rows()]
    assert "wj8" not in texts and "scale_factor" not in texts and "cn_conventional_160" not in texts
    assert "Scale factor k × (1 + H0 / R)" in texts


def test_the_properties_of_a_survey_are_in_words(window, small_project, tmp_path):
    root = copy_of(small_project, tmp_path)
    assert window.open_project(root)
    project_item = window.explorer.topLevelItem(0)
    surveys = next(project_item.child(k) for k in range(project_item.childCount())
                   if project_item.child(k).text(0) == "Surveys")
    window.explorer.setCurrentItem(surveys.child(0))
    rows = window.properties.rows()
    assert len(rows) > 5 and not any("_" in key or "." in key for key, _value in rows)
    assert ("Survey: imu profile", "Navigation grade (RLG, quartz accelerometers), thesis Table 3-2") in rows
