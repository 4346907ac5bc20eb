"""The import dialog with a survey folder a user wrote by hand (pytest-qt, offscreen): what its
survey.toml says and the form does not show is never lost on the way into a project, and the
optional start on the design is shown and edited."""

from __future__ import annotations

import os

import pytest

pytest.importorskip("pytestqt")
from insrail.gui.importer import ImportWidget
from insrail.io.survey import read_manifest

RAW = ("imu.npy", "gnss.pos", "odometer.txt", "gauge.txt", "sleepers.txt")

# As a surveyor writes it: the documented required keys, a comment, the gauge sensor's known latency,
# a description and the start on a station of the design.
HAND_WRITTEN = """# night 3, up line; gauge sensor runs 0.3 s late (its logger's buffer)
[survey]
name = "night3"
imu_profile = "nav"
description = "up line, night 3"

[files.imu]
path = "imu.npy"
format = "imu-npy"

[files.gnss]
path = "gnss.pos"
format = "rtklib-pos"

[files.odometer]
path = "odometer.txt"
format = "odometer-distance"

[files.gauge]
path = "gauge.txt"
format = "gauge-mm"
time_offset_s = 0.3

[files.sleepers]
path = "sleepers.txt"
format = "sleeper-times"

[trolley]
imu_to_antenna_m = [0.0, 0.0, -1.2]
imu_to_odometer_m = [0.0, -0.75, 0.25]
imu_to_reference_rail_m = [0.0, -0.7175, 0.25]
imu_to_sleeper_detector_m = [0.0, -0.75, 0.25]
reference_rail = "left"
mounting_rpy_deg = [0.0, 0.0, 0.0]
rail_centre_spacing_m = 1.5

[start]
station_m = 1021.5
offset_m = 0.004
sigma_m = 0.01
facing = "decreasing"
"""


@pytest.fixture
def night3(short_nav_survey, tmp_path):
    folder = tmp_path / "night3"
    folder.mkdir()
    for name in RAW:
        os.link(short_nav_survey / name, folder / name)
    (folder / "survey.toml").write_text(HAND_WRITTEN, encoding="utf-8")
    return folder


def test_a_survey_folder_imported_unchanged_keeps_its_file_as_written(qtbot, night3):
    widget = ImportWidget()
    qtbot.addWidget(widget)
    widget.load_survey_folder(night3)
    assert widget.start.isChecked()
    assert (widget.start_station.value(), widget.start_offset.value(), widget.start_sigma.value()) == (1021.5, 0.004,
                                                                                                       0.01)
    assert widget.start_facing.currentData() is False
    assert widget.write_survey(widget.folder_trolley) == night3.resolve()
    assert (night3 / "survey.toml").read_text(encoding="utf-8") == HAND_WRITTEN  # comments and all


def test_a_copy_into_the_project_keeps_the_latency_the_description_and_the_start(qtbot, night3, tmp_path):
    widget = ImportWidget()
    qtbot.addWidget(widget)
    widget.load_survey_folder(night3)
    widget.start_height.setValue(-0.002)  # edited in the form
    into = tmp_path / "project" / "surveys" / "night3"
    assert widget.write_survey(widget.folder_trolley, into=into) == into
    copied = read_manifest(into)
    assert copied.files["gauge"].time_offset_s == 0.3  # a lost latency would shift every gauge value
    assert copied.files["imu"].time_offset_s == 0.0
    assert copied.description == "up line, night 3"
    assert (copied.start.station_m, copied.start.offset_m, copied.start.height_m, copied.start.sigma_m,
            copied.start.facing_increasing) == (1021.5, 0.004, -0.002, 0.01, False)
    assert sorted(p.name for p in into.iterdir()) == sorted([*RAW, "survey.toml"])


def test_the_start_is_given_only_when_asked_for(qtbot, night3, short_nav_survey, tmp_path):
    widget = ImportWidget()
    qtbot.addWidget(widget)
    widget.load_survey_folder(night3)
    widget.start.setChecked(False)  # the survey waits for its first position fix
    assert widget.write_survey(widget.folder_trolley) is not None
    assert read_manifest(night3).start is None
    assert read_manifest(night3).files["gauge"].time_offset_s == 0.3  # rewritten, still kept

    fresh = ImportWidget()  # raw files added one by one: nothing to keep, no start unless asked for
    qtbot.addWidget(fresh)
    loose = tmp_path / "loose"
    loose.mkdir()
    for name in RAW:
        os.link(short_nav_survey / name, loose / name)
    fresh.add_files(sorted(loose.iterdir()))
    fresh.name.setText("loose")
    assert not fresh.start.isChecked()
    fresh.start.setChecked(True)
    fresh.start_station.setValue(1000.0)
    assert fresh.write_survey(read_manifest(night3).trolley) == loose.resolve()
    manifest = read_manifest(loose)
    assert manifest.start.station_m == 1000.0 and manifest.start.facing_increasing
    assert all(f.time_offset_s == 0.0 for f in manifest.files.values())


def test_a_raw_gnss_survey_is_imported_with_its_observation_files(qtbot, night3, tmp_path):
    """[gnss_raw] (RINEX to be processed by the PPK) gives the position instead of a gnss file: the
    import accepts it and copies the observation files with the others."""
    text = HAND_WRITTEN.replace('[files.gnss]\npath = "gnss.pos"\nformat = "rtklib-pos"\n\n', "")
    text += ('\n[gnss_raw]\nrover = "rinex/rover.obs"\nbase = "rinex/base.obs"\nnavigation = ["rinex/brdc.nav"]\n'
             'base_point = "rinex-header"\n')
    (night3 / "gnss.pos").unlink()
    (night3 / "rinex").mkdir()
    for name in ("rover.obs", "base.obs", "brdc.nav"):
        (night3 / "rinex" / name).write_text("observations\n")
    (night3 / "survey.toml").write_text(text, encoding="utf-8")
    widget = ImportWidget()
    qtbot.addWidget(widget)
    widget.load_survey_folder(night3)
    assert not [p for p in widget.check() if "position" in p.message]
    into = tmp_path / "copied"
    assert widget.write_survey(widget.folder_trolley, into=into) == into
    raw = read_manifest(into).raw_gnss
    assert (raw.rover, raw.base, raw.navigation) == ("rinex/rover.obs", "rinex/base.obs", ("rinex/brdc.nav",))
    assert (into / "rinex" / "brdc.nav").read_text() == "observations\n"
