"""survey.toml round trip, validation that lists every problem, loading a survey folder, detection."""

from __future__ import annotations

import threading
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from insrail.io import (
    InputError,
    ManifestError,
    detect_format,
    read_any,
    read_manifest,
    read_survey,
    write_gauge_mm,
    write_imu_kfgins,
    write_manifest,
    write_odometer_pulses,
    write_prism_enu,
    write_rtklib_pos,
    write_sleeper_times,
)
from insrail.io.survey import SurveyFile, SurveyManifest, TrolleyGeometry, track_lever_arm_problems
from insrail.io.types import GaugeData, GnssSolution, ImuIncrements, OdometerData, PrismObservations, SleeperPulses
from insrail.progress import Cancelled

T0 = 345_600.0


def make_survey_files(folder: Path) -> dict[str, SurveyFile]:
    n = 2001  # 10 s at 200 Hz
    t = T0 + np.arange(n) * 0.005
    dvel = np.tile([0.0, 0.0, -9.8 * 0.005], (n, 1))
    write_imu_kfgins(folder / "imu.txt", ImuIncrements(t, np.full((n, 3), 1e-7), dvel, gps_week=2381))
    tg = T0 + np.arange(11.0)
    write_rtklib_pos(folder / "gnss.pos", GnssSolution(
        tg, np.full(11, 0.53), np.full(11, 1.99), np.full(11, 30.0), np.full((11, 3), 0.01),
        np.ones(11, int), np.full(11, 20), np.full(11, 5.0), gps_week=2381))
    to = T0 + np.arange(101) * 0.1
    write_odometer_pulses(folder / "odo.txt", OdometerData(to, np.arange(101) * 0.01, pulse_length_m=0.001))
    write_gauge_mm(folder / "gauge.txt", GaugeData(to, np.full(101, 1.4352)))
    write_sleeper_times(folder / "sleepers.txt", SleeperPulses(T0 + np.arange(1.0, 9.0)))
    write_prism_enu(folder / "prism.txt", PrismObservations(
        T0 + np.array([1.0, 5.0]), np.array([500.0, 501.0]), np.array([3000.0, 3001.0]), np.array([12.0, 12.1]),
        np.array([0.001, 0.001]), np.array(["CP1", "CP2"])))
    return {
        "imu": SurveyFile("imu.txt", "kfgins-imu"),
        "gnss": SurveyFile("gnss.pos", "rtklib-pos"),
        "odometer": SurveyFile("odo.txt", "odometer-pulses", {"pulse_length_m": 0.001}),
        "gauge": SurveyFile("gauge.txt", "gauge-mm"),
        "sleepers": SurveyFile("sleepers.txt", "sleeper-times"),
        "prism": SurveyFile("prism.txt", "prism-enu"),
    }


def make_manifest(files) -> SurveyManifest:
    trolley = TrolleyGeometry(
        imu_to_antenna_m=np.array([0.1, -0.2, -1.3]), imu_to_odometer_m=np.array([0.3, 0.7, 0.25]),
        imu_to_prism_m=np.array([0.0, 0.0, -1.1]), imu_to_sleeper_detector_m=np.array([0.2, 0.0, 0.3]),
        imu_to_reference_rail_m=np.array([0.0, -0.72, 0.35]), reference_rail="right",
        mounting_rpy_rad=np.radians([0.5, -0.25, 180.0]), rail_centre_spacing_m=1.5)
    return SurveyManifest(name="Line 3 down track", files=files, trolley=trolley, imu_profile="nav",
                          gps_week=2381, description="km 12.3 - 14.0")


@pytest.fixture()
def survey_folder(tmp_path) -> Path:
    write_manifest(tmp_path, make_manifest(make_survey_files(tmp_path)))
    return tmp_path


def test_manifest_round_trip(survey_folder):
    expected = make_manifest(make_survey_files(survey_folder))
    manifest = read_manifest(survey_folder)
    assert manifest.files == expected.files
    assert (manifest.name, manifest.gps_week, manifest.imu_profile, manifest.description) == (
        expected.name, expected.gps_week, expected.imu_profile, expected.description)
    for field in ("imu_to_antenna_m", "imu_to_odometer_m", "imu_to_prism_m", "imu_to_sleeper_detector_m",
                  "imu_to_reference_rail_m", "mounting_rpy_rad"):
        np.testing.assert_allclose(getattr(manifest.trolley, field), getattr(expected.trolley, field),
                                   rtol=1e-15, atol=1e-15)
    assert manifest.trolley.reference_rail == "right"
    text = (survey_folder / "survey.toml").read_text()
    assert "mounting_rpy_deg = [\n    0.5," in text or "mounting_rpy_deg = [0.5," in text


def test_read_survey_loads_every_role(survey_folder):
    fractions = []
    data = read_survey(survey_folder, progress=lambda f, message: fractions.append(f))
    assert len(data.imu) == 2001 and data.imu.gps_week == 2381
    assert len(data.gnss) == 11 and data.gnss.gps_week == 2381
    assert data.odometer.pulse_length_m == 0.001
    assert data.odometer.distance_m[-1] == pytest.approx(1.0)
    assert data.gauge.gauge_m[0] == pytest.approx(1.4352)
    assert len(data.sleepers) == 8 and list(data.prism.point_id) == ["CP1", "CP2"]
    assert data.benchmarks is None
    assert fractions == sorted(fractions) and fractions[-1] == 1.0


def test_read_survey_can_be_cancelled(survey_folder):
    stop = threading.Event()
    stop.set()
    with pytest.raises(Cancelled):
        read_survey(survey_folder, cancel=stop)


BROKEN = """
[survey]
name = "broken"
gps_week = -3
colour = "red"

[files.imu]
path = "imu.txt"
format = "kfgins-imu"

[files.gnss]
path = "gnss.pos"
format = "rtklib-pos"

[files.odometer]
path = "odo.txt"
format = "odometer-pulses"
pulse_lenght_m = 0.001

[files.gauge]
path = "gauge.txt"
format = "kfgins-gnss"

[files.sleepers]
path = "sleepers.txt"
format = "sleeper-times"

[files.wheels]
path = "x.txt"
format = "gauge-mm"

[trolley]
imu_to_antenna_m = [0.1, 0.2]
imu_to_odometer_m = [0.0, 0.0, 0.1]
reference_rail = "middle"
"""


def test_broken_manifest_lists_every_problem(tmp_path):
    (tmp_path / "imu.txt").write_text("1 0 0 0 0 0 0\n")
    (tmp_path / "odo.txt").write_text("1 0\n")
    (tmp_path / "gauge.txt").write_text("1 1435\n")
    (tmp_path / "survey.toml").write_text(BROKEN)
    with pytest.raises(ManifestError) as info:
        read_manifest(tmp_path)
    problems = info.value.problems
    expected = [
        "survey.gps_week: expected a whole GPS week number",
        "survey.colour: unknown key",
        "files.gnss.path: file not found: gnss.pos",
        "files.odometer.pulse_lenght_m: unknown option for format odometer-pulses (known: pulse_length_m)",
        "files.gauge.format: kfgins-gnss does not hold gauge data (use one of gauge-mm, gauge-volts)",
        "files.sleepers.path: file not found: sleepers.txt",
        "files.wheels: unknown role",
        "trolley.imu_to_antenna_m: expected 3 numbers",
        "trolley.reference_rail: expected \"left\" or \"right\"",
    ]
    for fragment in expected:
        assert any(p.startswith(fragment) for p in problems), (fragment, problems)
    assert len(problems) == len(expected)
    assert "imu_to_prism_m" not in str(info.value)  # no prism file, so no prism lever arm needed
    assert str(info.value).startswith(f"{tmp_path / 'survey.toml'}: 9 problems:")


def test_manifest_option_types_are_checked(survey_folder):
    path = survey_folder / "survey.toml"
    text = path.read_text().replace("pulse_length_m = 0.001", 'pulse_length_m = "one mm"')
    path.write_text(text)
    with pytest.raises(ManifestError, match="files.odometer.pulse_length_m: expected float"):
        read_manifest(survey_folder)


def test_toml_syntax_error_names_the_line(tmp_path):
    (tmp_path / "survey.toml").write_text('[survey]\nname = "x"\nname = \n')
    with pytest.raises(InputError) as info:
        read_manifest(tmp_path)
    assert info.value.line == 3 and "not valid TOML" in info.value.message


def test_missing_manifest(tmp_path):
    with pytest.raises(InputError, match="needs a survey.toml"):
        read_manifest(tmp_path)


def test_one_bad_file_raises_its_own_error(survey_folder):
    with open(survey_folder / "gauge.txt", "a") as handle:
        handle.write("999.0 1435\n")
    with pytest.raises(InputError) as info:
        read_survey(survey_folder)
    assert info.value.path == survey_folder / "gauge.txt" and "earlier than" in info.value.message


def test_several_bad_files_are_all_reported(survey_folder):
    for name in ("gauge.txt", "sleepers.txt"):
        with open(survey_folder / name, "a") as handle:
            handle.write("abc\n")
    with pytest.raises(ManifestError) as info:
        read_survey(survey_folder)
    assert len(info.value.problems) == 2
    assert all("expected" in p for p in info.value.problems)


def test_time_scale_mix_up_is_reported(survey_folder):
    odo = OdometerData(np.arange(10.0) + 1.7e9, np.arange(10.0), pulse_length_m=0.001)
    write_odometer_pulses(survey_folder / "odo.txt", odo)
    with pytest.raises(ManifestError, match=r"files.odometer \(odo.txt\): time span .* does not overlap the IMU"):
        read_survey(survey_folder)


def test_a_time_offset_is_taken_off_the_files_time_stamps(survey_folder):
    path = survey_folder / "survey.toml"
    text = path.read_text()
    plain = read_survey(survey_folder)
    path.write_text(text.replace('path = "sleepers.txt"\n', 'path = "sleepers.txt"\ntime_offset_s = 0.25\n'))
    manifest = read_manifest(survey_folder)
    assert manifest.files["sleepers"].time_offset_s == 0.25 and manifest.files["sleepers"].options == {}
    shifted = read_survey(survey_folder)
    np.testing.assert_array_equal(shifted.sleepers.time_s, plain.sleepers.time_s - 0.25)
    np.testing.assert_array_equal(shifted.odometer.time_s, plain.odometer.time_s)
    write_manifest(survey_folder, manifest)  # kept when written back
    assert read_manifest(survey_folder).files["sleepers"].time_offset_s == 0.25


@pytest.mark.parametrize(("table", "value", "problem"), [
    ("imu", "0.1", "files.imu.time_offset_s: only the files of gnss, odometer"),
    ("gauge", '"0.1"', "files.gauge.time_offset_s: expected the seconds the file's time stamps run late"),
    ("gauge", "86400.0", "files.gauge.time_offset_s: expected the seconds"),
])
def test_a_time_offset_that_cannot_be_one_is_a_problem(survey_folder, table, value, problem):
    path = survey_folder / "survey.toml"
    text = path.read_text()
    anchor = {"imu": 'path = "imu.txt"\n', "gauge": 'path = "gauge.txt"\n'}[table]
    path.write_text(text.replace(anchor, f"{anchor}time_offset_s = {value}\n"))
    with pytest.raises(ManifestError) as info:
        read_manifest(survey_folder)
    assert any(problem in p for p in info.value.problems), info.value.problems


def test_week_conflict_is_reported(survey_folder):
    path = survey_folder / "survey.toml"
    path.write_text(path.read_text().replace("gps_week = 2381", "gps_week = 2380"))
    with pytest.raises(ManifestError) as info:
        read_survey(survey_folder)
    assert any("files.gnss: data is from GPS week 2381, survey.gps_week says 2380" in p
               for p in info.value.problems)


def test_detect_format_of_foreign_files(tmp_path):
    cases = {
        "imu.txt": ("456300.005 1.2e-6 -3.1e-7 2.2e-6 1.1e-4 -2.0e-5 -0.04903\n"
                    "456300.010 1.1e-6 -3.0e-7 2.1e-6 1.0e-4 -2.1e-5 -0.04904\n", "kfgins-imu"),
        "GNSS-RTK.txt": ("456300.000 30.4447 114.4718 20.91 0.005 0.004 0.010\n", "kfgins-gnss"),
        "GNSS-POSVEL.txt": ("116454 30.52 114.35 22.3 0.01 0.01 0.02 1.0 0.5 0.0 0.01 0.01 0.02\n",
                            "kfgins-gnss"),
        "odo_m.txt": ("1.0 0.152\n2.0 1.377\n", "odometer-distance"),
        "odo_pulses.txt": ("1.0 152\n2.0 1377\n", "odometer-pulses"),
        "gauge.txt": ("1.0 1435.21\n2.0 1435.80\n", "gauge-mm"),
        "sleepers.txt": ("1.0\n1.6\n", "sleeper-times"),
        "cpiii.txt": ("1.0 500.0 3000.0 12.0 0.001 CP1\n", "prism-enu"),
        "bm.csv": ("id,lat,lon,h,H\nBM1,30.5,114.2,25.3,36.1\n", "benchmarks"),
        "notes.txt": ("hello world\nthis is text\n", None),
    }
    for name, (content, expected) in cases.items():
        (tmp_path / name).write_text(content)
        assert detect_format(tmp_path / name) == expected, name
    assert detect_format(tmp_path / "absent.txt") is None
    with pytest.raises(InputError, match="format not recognised"):
        read_any(tmp_path / "notes.txt")
    with pytest.raises(InputError, match="unknown option 'speed'"):
        read_any(tmp_path / "gauge.txt", speed=3)
    with pytest.raises(InputError, match="file not found"):
        read_any(tmp_path / "absent.txt")


def test_gnss_and_odometer_are_optional_roles(tmp_path):
    """A tunnel survey (prism fixes, no GNSS) and a survey without an odometer read; their lever
    arms are then not required, and a survey with no position source at all is refused."""
    files = make_survey_files(tmp_path)
    del files["gnss"], files["odometer"]
    manifest = make_manifest(files)
    trolley = replace(manifest.trolley, imu_to_antenna_m=None, imu_to_odometer_m=None)
    write_manifest(tmp_path, replace(manifest, trolley=trolley))  # lever arms not given are left out
    assert "imu_to_antenna_m" not in (tmp_path / "survey.toml").read_text()
    data = read_survey(tmp_path)
    assert data.gnss is None and data.odometer is None and len(data.prism) == 2
    assert data.manifest.trolley.imu_to_antenna_m is None

    del files["prism"]
    write_manifest(tmp_path, make_manifest(files))
    with pytest.raises(ManifestError, match="files: no position source: give a GNSS solution"):
        read_manifest(tmp_path)


def test_antenna_lever_arm_is_required_with_gnss(tmp_path):
    manifest = make_manifest(make_survey_files(tmp_path))
    write_manifest(tmp_path, replace(manifest, trolley=replace(manifest.trolley, imu_to_antenna_m=None)))
    with pytest.raises(ManifestError, match=r"trolley.imu_to_antenna_m: missing \(required with files.gnss"):
        read_manifest(tmp_path)


def test_lever_arms_of_the_track_are_not_required_to_read_a_survey(tmp_path):
    """A survey that is only fused (a walk, a road test) gives no rail or sleeper-detector lever arm:
    survey.toml reads without them; the track reconstruction names each with why it needs it."""
    manifest = make_manifest(make_survey_files(tmp_path))
    write_manifest(tmp_path, replace(manifest, trolley=replace(manifest.trolley, imu_to_reference_rail_m=None,
                                                                   imu_to_sleeper_detector_m=None)))
    text = (tmp_path / "survey.toml").read_text()
    assert "imu_to_reference_rail_m" not in text and "imu_to_sleeper_detector_m" not in text
    trolley = read_manifest(tmp_path).trolley
    assert trolley.imu_to_reference_rail_m is None and trolley.imu_to_sleeper_detector_m is None
    assert list(map(str, track_lever_arm_problems(trolley, {"imu", "gnss"}))) == [
        "trolley.imu_to_reference_rail_m: missing; insrail process needs it because the rails are placed from the "
        "reference rail's point (3 numbers [m], IMU body frame FRD)"]
    assert str(track_lever_arm_problems(trolley, {"imu", "gnss", "sleepers"})[1]).startswith(
        "trolley.imu_to_sleeper_detector_m: missing; insrail process needs it because files.sleepers is given")
    with pytest.raises(ValueError, match="trolley.imu_to_reference_rail_m: not given, but used"):
        trolley.lever_arm_m("imu_to_reference_rail_m")


def test_relative_imu_profile_is_resolved_from_the_survey_folder(tmp_path, monkeypatch):
    from insrail.nav.imu_profile import load_imu_profile
    from insrail.resources import resource

    folder = tmp_path / "survey"
    folder.mkdir()
    (folder / "profiles").mkdir()
    (folder / "profiles" / "my_unit.toml").write_text(
        resource("imu_profiles", "tactical.toml").read_text().replace('name = "tactical"', 'name = "my unit"'))
    manifest = replace(make_manifest(make_survey_files(folder)), imu_profile="profiles/my_unit.toml")
    write_manifest(folder, manifest)
    monkeypatch.chdir(tmp_path)  # elsewhere than the survey folder
    read = read_manifest("survey")
    assert Path(read.imu_profile) == (folder / "profiles" / "my_unit.toml").resolve()
    assert load_imu_profile(read.imu_profile).name == "my unit"
    write_manifest(folder, read)  # written back relative to the folder
    assert 'imu_profile = "profiles/my_unit.toml"' in (folder / "survey.toml").read_text()

    (folder / "profiles" / "my_unit.toml").unlink()
    with pytest.raises(ManifestError, match=r"survey.imu_profile: file not found: profiles/my_unit.toml \(a .toml "
                                            r"path is relative to the survey folder"):
        read_manifest(folder)
