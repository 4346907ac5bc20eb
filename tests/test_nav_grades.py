"""Every IMU grade starts and fuses on a trolley survey (issue 32): `insrail fuse` end to end on short
simulated surveys (a few hundred metres) that the unit check and the static levelling once refused.

* a tactical-grade trolley pushed smoothly through a curve has accelerometers as quiet as at rest and
  turns at v / R, above the earth rate plus the gyro bias: the unit check took it for a file in degrees;
* a MEMS unit whose accelerometers read 15 mg off is within what the `mems_handheld` profile's bias
  allows (10 mg 1-sigma); the static levelling accepted 9.7-9.9 m/s^2 only, whatever the profile.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest
import shared_build

from insrail.cli.main import main
from insrail.io.types import ImuIncrements, OdometerData
from insrail.nav.alignment import aiding_still, gravity_tolerance_mps2, static_levelling
from insrail.nav.imu_profile import load_imu_profile
from insrail.nav.imu_screening import ImuUnitError, check_units

G_MPS2 = 9.80665


def _survey_toml(profile: str, odometer: bool = True) -> str:
    """survey.toml as a user writes it: the files the fusion reads and their lever arms, nothing else
    (the simulator's trolley, :func:`insrail.sim.scenario.default_trolley`)."""
    text = f"""[survey]
name = "grade {profile}"
imu_profile = "{profile}"

[files.imu]
path = "imu.npy"
format = "imu-npy"

[files.gnss]
path = "gnss.pos"
format = "rtklib-pos"
"""
    if odometer:
        text += '\n[files.odometer]\npath = "odometer.txt"\nformat = "odometer-distance"\n'
    text += """
[trolley]
imu_to_antenna_m = [0.02, 0.18, -1.35]
imu_to_odometer_m = [0.45, -0.60, 0.31]
imu_to_reference_rail_m = [0.10, -0.60, 0.31]
reference_rail = "left"
mounting_rpy_deg = [0.05, -0.08, 0.12]
"""
    return text


def _curve_survey(grade: str, speed_mps: float, accel_bias_mg: float | None = None):
    """200 m of an R = 600 m arc with 100 mm cant (a metro's curve) pushed smoothly at ``speed_mps``
    (a trolley without play), a minute at rest before it, GNSS throughout."""
    from insrail.sim.scenario import INF, preset
    from insrail.sim.simulate import simulate

    config = preset("short", imu_profile=grade)
    design = replace(config.design, horizontal=(("line", 40.0), ("clothoid", 60.0, INF, 600.0, "right"),
                                                ("arc", 300.0, 600.0, "right"), ("line", 100.0)),
                     pvis=((1000.0, 28.40, 0.0), (1500.0, 29.40, 0.0)),
                     cant=((1000.0, 0.0), (1040.0, 0.0), (1100.0, 0.100), (1400.0, 0.100), (1500.0, 0.100)))
    config = replace(config, design=design, irregularities=replace(config.irregularities, lateral_bumps=(),
                                                                   vertical_bumps=()),
                     motion=replace(config.motion, start_station_m=1150.0, end_station_m=1350.0, stops=(),
                                    static_start_s=60.0, static_end_s=10.0, cruise_speed_mps=speed_mps),
                     gnss=replace(config.gnss, outages=()),
                     play=replace(config.play, pitch_rms_rad=0.0, yaw_rms_rad=0.0))
    if accel_bias_mg is not None:
        config = replace(config, accel_bias_turn_on_mps2=(accel_bias_mg * 1e-3 * G_MPS2,) * 3)
    name = f"curve-{grade}-{speed_mps:g}-{accel_bias_mg}"
    return shared_build.built_once(name, lambda out: simulate(config, seed=3, out_dir=out, imu_format="npy"))


def _fuse(survey, tmp_path, profile: str, odometer: bool = True) -> int:
    (survey / "survey.toml").write_text(_survey_toml(profile, odometer), encoding="utf-8")
    return main(["fuse", str(survey), "--out", str(tmp_path / "out")])


def _copy(folder, tmp_path):
    import shutil

    return shutil.copytree(folder, tmp_path / "survey", ignore=shutil.ignore_patterns("truth"))


@pytest.mark.parametrize("speed_mps, odometer", [(0.5, True), (1.5, False)])
def test_a_tactical_trolley_pushed_smoothly_through_a_curve_fuses(speed_mps, odometer, tmp_path, capsys):
    """At 0.5 m/s on R = 600 m the curve turns at 8.3e-4 rad/s, at 1.5 m/s 2.5e-3: both above the
    tactical profile's rest limit (earth rate + 5 sigma of bias and noise, 3.3e-4 rad/s) for minutes of
    quiet accelerometers. The odometer (or without one the GNSS track) says the trolley moves."""
    survey = _copy(_curve_survey("tactical", speed_mps), tmp_path)
    assert _fuse(survey, tmp_path, "tactical", odometer) == 0
    out = capsys.readouterr()
    assert "look like degrees" not in out.err and "filter reset" not in out.err
    assert "integrity: 1 of 1 sections of 200 m consistent" in out.out


def test_a_mems_unit_15_mg_off_fuses_with_a_profile_that_allows_it(tmp_path, capsys):
    """15 mg on each accelerometer axis (a mean specific force 9.65 m/s^2 at rest): the mems_handheld
    profile's turn-on bias (10 mg) allows it; the static levelling then holds it in its level angles,
    which the filter knows (no GNSS rejected once the trolley moves). The `mems` profile (2 mg) does
    not: the levelling says so and names the profile's bias."""
    survey = _copy(_curve_survey("mems", 1.0, accel_bias_mg=15.0), tmp_path)
    assert _fuse(survey, tmp_path, "mems_handheld") == 0
    out = capsys.readouterr()
    assert "filter reset" not in out.err and " 0 measurements rejected" in out.out
    assert _fuse(survey, tmp_path, "mems") == 1
    err = capsys.readouterr().err
    assert "mean specific force 9.64" in err and "is the IMU profile's bias too small for this unit?" in err


def _at_rest(seconds: float, f_b: np.ndarray, rate_hz: float = 200.0) -> ImuIncrements:
    n = int(seconds * rate_hz)
    t = 230400.0 + np.arange(n) / rate_hz
    return ImuIncrements(t, np.zeros((n, 3)), np.tile(f_b / rate_hz, (n, 1)), source="imu.npy")


@pytest.mark.parametrize("profile", ["nav", "tactical", "tactical_fog", "mems", "mems_handheld"])
def test_static_levelling_accepts_the_profiles_bias_and_refuses_other_units(profile):
    p = load_imu_profile(profile)
    tolerance = gravity_tolerance_mps2(p)
    allowed_mg = 1e3 * (tolerance - 0.03) / G_MPS2  # beyond the spread of normal gravity
    assert allowed_mg >= 1e3 * 3.0 * p.accel_bias_turn_on / G_MPS2 - 1e-9
    within = np.array([0.0, 0.0, -(9.79 + 0.9 * (tolerance - 0.03))])
    static_levelling(_at_rest(2.0, within), 0, 400, tolerance)
    for wrong in (within / G_MPS2, within / 0.3048, within * 1.5):  # in g, in ft/s^2, not at rest
        with pytest.raises(ValueError, match="is not gravity"):
            static_levelling(_at_rest(2.0, wrong), 0, 400, tolerance)
    if profile == "mems_handheld":  # the walk's unit, 12.7 mg, and the 14 mg
        static_levelling(_at_rest(2.0, np.array([0.0, 0.0, -(9.79 + 0.014 * G_MPS2)])), 0, 400, tolerance)


def _pushed_then_resting(rate_hz: float = 200.0):
    """A tactical trolley pushed at 1 m/s through a curve of R = 1500 m for 100 s (accelerometers
    quiet, the gyro turning at 6.7e-4 rad/s about the vertical) then at rest for 20 s (the earth rate):
    increments and the odometer."""
    rng = np.random.default_rng(4)
    p = load_imu_profile("tactical")
    moving, resting = 100.0, 20.0
    n = int((moving + resting) * rate_hz)
    t = 230400.0 + np.arange(1, n + 1) / rate_hz
    lat = math.radians(34.0)
    earth = 7.292115e-5 * np.array([math.cos(lat), 0.0, -math.sin(lat)])
    w = np.tile(earth, (n, 1)) + rng.normal(0.0, p.gyro_arw * math.sqrt(rate_hz), (n, 3))
    w[t < t[0] + moving, 2] += 1.0 / 1500.0
    f = np.array([0.0, 0.0, -9.79]) + rng.normal(0.0, p.accel_vrw * math.sqrt(rate_hz), (n, 3))
    distance = np.minimum(t - t[0], moving)
    odometer = OdometerData(t[::20], distance[::20])
    return ImuIncrements(t, w / rate_hz, f / rate_hz, source="imu.npy"), odometer


def test_the_unit_check_tells_a_smooth_push_from_rest_by_the_odometer():
    imu, odometer = _pushed_then_resting()
    profile = load_imu_profile("tactical")
    with pytest.raises(ImuUnitError, match="look like degrees"):  # the IMU alone cannot tell
        check_units(imu, profile)

    def odometer_says(times, window):
        return aiding_still(times, window, odometer)

    check_units(imu, profile, odometer_says)  # the odometer moves through the curve: only its 20 s at rest count
    degrees = ImuIncrements(imu.time_s, np.degrees(imu.dtheta_rad), imu.dvel_mps, source=imu.source)
    with pytest.raises(ImuUnitError, match="look like degrees, not radians"):  # a file in degrees still is one
        check_units(degrees, profile, odometer_says)
