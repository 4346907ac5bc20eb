"""The second odometer (thesis 5.2.2.3): ``[files.odometer_right]`` in a user's survey.toml, the two wheels
compared through the gyros, a slipping wheel found, left out over its stretch and bridged by the other,
and the result against the simulator's truth through `insrail process`."""

from __future__ import annotations

import contextlib
import io
import shutil
import tomllib
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from insrail.cli.main import main
from insrail.io import ManifestError, read_manifest
from insrail.io.survey import read_survey
from insrail.io.types import ImuIncrements, OdometerData
from insrail.nav.odometer_pair import compare_odometers
from insrail.report.content import odometer_pair_text
from insrail.sim.scenario import OdometerSlip
from survey_builder import SURVEY_NAME, Cell, build_cell, rms, scenario, truth_errors

CELL = Cell(imu="nav", position="rtklib-pos", ellipsoid="CGCS2000", design="csv", direction="with",
            left_out="none", trolley="minimal")
RIGHT_WHEEL_M = (0.45, 0.90, 0.31)  # the minimal trolley's first wheel is at y = -0.60: the rails 1.5 m apart
SLIP = OdometerSlip(wheel="right", from_station_m=1150.0, to_station_m=1300.0, fraction=0.05)


def _insrail(*args: str) -> tuple[int, str]:
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
        code = main(list(args))
    return code, out.getvalue()


# --- the comparison alone, on records made here ------------------------------------------------

def _straight_run(slip_wheel: str | None, slip: float = 0.05, speed_mps: float = 1.2):
    """IMU and two odometers on a straight run then a 300 m curve (yaw rate speed / 300 m): the
    wheels 1.5 m apart, the right one 0.2 % long; one wheel slipping over 40-70 s."""
    t = 1000.0 + np.arange(0.0, 120.0, 0.005)
    yaw_rate = np.where(t > 1060.0, speed_mps / 300.0, 0.0)
    dtheta = np.zeros((len(t), 3))
    dtheta[:, 2] = yaw_rate * 0.005
    dvel = np.zeros((len(t), 3))
    imu = ImuIncrements(t, dtheta, dvel)
    t_odo = t[::20]
    rate = np.where(t_odo > 1060.0, speed_mps / 300.0, 0.0)
    left_speed, right_speed = speed_mps + 0.75 * rate, speed_mps - 0.75 * rate  # right-hand curve: left outer
    slipping = (t_odo > 1040.0) & (t_odo < 1070.0)
    left_speed = left_speed * np.where(slipping & (slip_wheel == "left"), 1 - slip, 1.0)
    right_speed = right_speed * np.where(slipping & (slip_wheel == "right"), 1 - slip, 1.0)

    def record(speed, scale):
        distance = np.concatenate([[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * 0.1)]) * scale
        return OdometerData(t_odo, np.round(distance / 0.001) * 0.001, pulse_length_m=0.001)

    return imu, record(left_speed, 1.0), record(right_speed, 1.002)


@pytest.mark.parametrize("wheel", ["left", "right"])
def test_the_slipping_wheel_is_found_and_left_out_over_its_stretch(wheel):
    imu, left, right = _straight_run(wheel)
    pair = compare_odometers(imu, left, right, np.array([0.4, -0.75, 0.3]), np.array([0.4, 0.75, 0.3]), np.eye(3))
    assert pair.relative_scale == pytest.approx(0.002, abs=2e-4)
    assert pair.spacing_m == pytest.approx(1.5)
    assert len(pair.slips) == 1, pair.slips
    slip = pair.slips[0]
    assert slip.wheel == wheel
    assert slip.slip == pytest.approx(0.05, abs=0.005)
    assert 1038.0 < slip.start_s <= 1040.0 and 1070.0 <= slip.end_s < 1072.0
    bad, good = (pair.left, pair.right) if wheel == "left" else (pair.right, pair.left)
    assert [(g.start_s, g.end_s) for g in bad.left_out] == [(slip.start_s, slip.end_s)] and good.left_out == ()
    # the right record on the left one's scale
    assert pair.right.distance_m[300] == pytest.approx(right.distance_m[300] / (1 + pair.relative_scale))


def test_two_good_wheels_in_a_curve_say_nothing():
    imu, left, right = _straight_run(None)
    pair = compare_odometers(imu, left, right, np.array([0.4, -0.75, 0.3]), np.array([0.4, 0.75, 0.3]), np.eye(3))
    assert pair.slips == ()


def test_the_heading_rate_from_the_wheels_is_far_noisier_than_the_gyro():
    """Why the difference is not a heading-rate measurement (module docstring of nav.odometer_pair): over the
    filter's 0.1 s segments the 1 mm pulses alone make (v_R - v_L) / 1.5 m a few mrad/s noisy, against the
    gyro's white noise of a few microradians per second at 10 Hz for a navigation-grade unit."""
    imu, left, right = _straight_run(None)
    rate = np.diff(right.distance_m / 1.002 - left.distance_m) / 0.1 / -1.5
    truth = np.where(left.time_s[1:] > 1060.0, 1.2 / 300.0, 0.0)
    noise = float(np.std((rate - truth)[left.time_s[1:] > 1065.0]))
    assert 1e-3 < noise < 1e-2  # rad/s: ~4 mrad/s; a nav-grade gyro's ARW 0.002 deg/sqrt(h) is 4e-6 rad/s at 10 Hz


# --- survey.toml -------------------------------------------------------------------------------

def _folder(tmp_path: Path, files: str, trolley: str) -> Path:
    for name in ("imu.txt", "gnss.pos", "odometer.txt", "odometer_right.txt"):
        (tmp_path / name).write_text("0 0\n")
    (tmp_path / "survey.toml").write_text(
        '[survey]\nname = "r"\n\n[files.imu]\npath = "imu.txt"\nformat = "kfgins-imu"\n\n'
        '[files.gnss]\npath = "gnss.pos"\nformat = "rtklib-pos"\n\n' + files +
        "\n[trolley]\nimu_to_antenna_m = [0.0, 0.0, -1.3]\n" + trolley)
    return tmp_path


LEFT = '[files.odometer_left]\npath = "odometer.txt"\nformat = "odometer-distance"\n'
FIRST = '[files.odometer]\npath = "odometer.txt"\nformat = "odometer-distance"\n'
RIGHT = '[files.odometer_right]\npath = "odometer_right.txt"\nformat = "odometer-distance"\n'


def test_left_and_right_names_in_survey_toml(tmp_path):
    manifest = read_manifest(_folder(tmp_path, LEFT + RIGHT, "imu_to_odometer_left_m = [0.4, -0.75, 0.3]\n"
                                     "imu_to_odometer_right_m = [0.4, 0.75, 0.3]\n"))
    assert set(manifest.files) == {"imu", "gnss", "odometer", "odometer_right"}
    assert manifest.files["odometer"].path == "odometer.txt"
    assert list(manifest.trolley.imu_to_odometer_m) == [0.4, -0.75, 0.3]
    assert list(manifest.trolley.imu_to_odometer_right_m) == [0.4, 0.75, 0.3]


@pytest.mark.parametrize("files, trolley, says", [
    (RIGHT, "imu_to_odometer_right_m = [0.4, 0.75, 0.3]\n", "files.odometer_right: a second odometer needs the first"),
    (FIRST + RIGHT, "imu_to_odometer_m = [0.4, -0.75, 0.3]\n", "trolley.imu_to_odometer_right_m: missing (required with "
     "files.odometer_right"),
    (FIRST + LEFT, "imu_to_odometer_m = [0.4, -0.75, 0.3]\n", "files.odometer_left: the same as files.odometer"),
    (FIRST, "imu_to_odometer_m = [0.4, -0.75, 0.3]\nimu_to_odometer_left_m = [0.4, -0.75, 0.3]\n",
     "trolley.imu_to_odometer_left_m: the same as trolley.imu_to_odometer_m"),
])
def test_a_second_odometer_without_what_it_needs_is_named(tmp_path, files, trolley, says):
    with pytest.raises(ManifestError) as error:
        read_manifest(_folder(tmp_path, files, trolley))
    assert any(p.startswith(says) for p in error.value.problems), error.value.problems


# --- end to end against the truth --------------------------------------------------------------

def _with_second_odometer(project: Path, simulated: Path, right_lever: tuple[float, float, float]) -> None:
    """The simulator's second odometer added to the user's survey as a user adds it: the file copied in
    their own form, two blocks typed into survey.toml."""
    survey = project / "survey"
    record = np.loadtxt(simulated / "odometer_right.txt", comments="#")
    np.savetxt(survey / "odometer_right.txt", record, fmt="%.3f %.3f")
    text = (survey / "survey.toml").read_text()
    text = text.replace("[trolley]\n", '[files.odometer_right]\npath = "odometer_right.txt"\n'
                        'format = "odometer-distance"\n\n[trolley]\n')
    text += f"imu_to_odometer_right_m = [{right_lever[0]}, {right_lever[1]}, {right_lever[2]}]\n"
    (survey / "survey.toml").write_text(text)


def _errors(project: Path, built) -> dict[str, float]:
    """RMS errors [mm] against the truth: the 30 m/5 m check per rail and axis, gauge and cross-level."""
    comparison = truth_errors(project / "results" / SURVEY_NAME / "sleepers.csv", built, normal_heights=False)
    errors = {}
    for side in ("left", "right"):
        lateral, vertical = comparison.rails[side].check_30m_5m_m()
        errors |= {f"30m5m_{side}_lateral": 1e3 * rms(lateral), f"30m5m_{side}_vertical": 1e3 * rms(vertical)}
    return errors | {"gauge": 1e3 * rms(comparison.gauge_error_m), "cross_level": 1e3 * rms(comparison.cant_error_m)}


def _summary(project: Path) -> dict:
    return tomllib.loads((project / "results" / SURVEY_NAME / "summary.toml").read_text())


def _variant(built, tmp_path: Path, name: str) -> Path:
    project = tmp_path / name
    shutil.copytree(built.project, project, ignore=shutil.ignore_patterns("results"))
    return project


def _as_single(project: Path, simulated: Path, right_lever: tuple[float, float, float]) -> None:
    """The survey with the (slipping) right wheel's record as its only odometer."""
    survey = project / "survey"
    record = np.loadtxt(simulated / "odometer_right.txt", comments="#")
    np.savetxt(survey / "odometer.txt", record, fmt="%.3f %.3f")
    lines = (survey / "survey.toml").read_text().splitlines()
    lines = [f"imu_to_odometer_m = [{right_lever[0]}, {right_lever[1]}, {right_lever[2]}]"
             if line.startswith("imu_to_odometer_m") else line for line in lines]
    (survey / "survey.toml").write_text("\n".join(lines) + "\n")


@pytest.fixture(scope="module")
def slipping_run(tmp_path_factory):
    """One simulated run (420 m, navigation grade, GNSS), its right wheel slipping 5 % over stations
    1150-1300, as the user's project with the left (good) odometer alone."""
    folder = tmp_path_factory.mktemp("slipping")
    config = scenario(CELL)
    config = replace(config, odometer=replace(config.odometer, second=True, slip=SLIP))
    return build_cell(CELL, folder, seed=7, config=config), folder / "sim"


def test_a_slipping_wheel_is_named_and_bridged_by_the_other_through_insrail_process(slipping_run, tmp_path):
    built, simulated = slipping_run
    truth = tomllib.loads((built.truth / "errors.toml").read_text())
    assert truth["odometer_slip"]["wheel"] == "right" and truth["odometer_slip"]["fraction"] == 0.05
    pair = _variant(built, tmp_path, "pair")
    _with_second_odometer(pair, simulated, RIGHT_WHEEL_M)
    code, out = _insrail("process", str(pair))
    assert code == 0, out
    assert "odometer_right.txt" in out and "slipped" in out, out
    summary = _summary(pair)
    slips = summary["fusion"]["odometer_pair"]["slips"]
    assert len(slips) == 1 and slips[0]["wheel"] == "right", slips
    assert slips[0]["slip_percent"] == pytest.approx(5.0, abs=0.5)
    start, end = truth["odometer_slip"]["time_s"]
    assert slips[0]["start_s"] <= start + 0.2 and slips[0]["end_s"] >= end - 0.2
    assert slips[0]["end_s"] - slips[0]["start_s"] < end - start + 3.0  # no more than the slip is left out
    notices = [n for n in summary.get("notices", []) if n["stage"] == "odometer"]
    assert len(notices) == 1 and notices[0]["file"].endswith("odometer_right.txt"), notices
    assert f"{slips[0]['slip_percent']:.1f} % less than it rolled" in notices[0]["message"]
    assert "right wheel slipped" in odometer_pair_text(summary)  # the PDF's "Two odometers" row
    # on the chainage: a note event over the stretch (150 m from station 1150), as on the charts
    events = [e for e in summary["events"] if e["source"] == "odometer comparison"]
    assert len(events) == 1 and events[0]["kind"] == "note", summary["events"]
    assert events[0]["station_from_m"] <= 1150.5 and events[0]["station_to_m"] >= 1299.5
    assert events[0]["station_to_m"] - events[0]["station_from_m"] < 155


@pytest.mark.slow
def test_with_the_other_wheel_bridging_the_result_is_a_good_odometers(slipping_run, tmp_path):
    """The slipping run processed four ways against the truth (the numbers in docs/fusion.md, "Two
    odometers"): the left (good) odometer alone; both, the right slipping; the same run with both wheels
    good; the slipping wheel alone. Bridged, the result is the good odometer's; the slipping wheel alone
    is not silent (the filter rejects it and says so; fewer sleepers are valid)."""
    built, simulated = slipping_run
    single = built.project
    assert _insrail("process", str(single))[0] == 0
    pair = _variant(built, tmp_path, "pair")
    _with_second_odometer(pair, simulated, RIGHT_WHEEL_M)
    assert _insrail("process", str(pair))[0] == 0
    good_config = replace(built.config, odometer=replace(built.config.odometer, slip=None))
    good_built = build_cell(CELL, tmp_path / "good", seed=7, config=good_config)
    good_pair = good_built.project
    _with_second_odometer(good_pair, tmp_path / "good" / "sim", RIGHT_WHEEL_M)
    assert _insrail("process", str(good_pair))[0] == 0
    assert _summary(good_pair)["fusion"]["odometer_pair"]["slips"] == []
    slipping_alone = _variant(built, tmp_path, "slipping")
    _as_single(slipping_alone, simulated, RIGHT_WHEEL_M)
    code, out = _insrail("process", str(slipping_alone))
    assert code == 0, out

    errors = {name: _errors(project, built) for name, project in
              (("one good", single), ("two good", good_pair), ("two, right slipping", pair),
               ("slipping alone", slipping_alone))}
    for name, values in errors.items():
        valid = _summary({"one good": single, "two good": good_pair, "two, right slipping": pair,
                          "slipping alone": slipping_alone}[name])["track"]["valid_sleepers"]
        print(name, {k: round(v, 4) for k, v in values.items()}, "valid sleepers", valid)
    good, bridged = errors["one good"], errors["two, right slipping"]
    for key in good:
        assert bridged[key] <= 1.05 * good[key] + 0.005, (key, good, bridged)
    alone = [n["message"] for n in _summary(slipping_alone).get("notices", [])]
    print("slipping alone:", alone)
    assert any("odometer_nhc rejected" in message for message in alone), alone
