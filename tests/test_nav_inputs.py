"""Fusion integrity at its inputs: sensor-level screening, gaps bridged once, start-up for every IMU class.

Synthetic data (fast); the simulator cases with the truth are in test_nav_fusion.py and the figures
in benchmarks/imu_integrity.py.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from insrail.io.imu import read_imu_rates_csv
from insrail.io.types import ImuIncrements
from insrail.nav.alignment import detect_stops, gyrocompass_sigma_rad, stop_motion_sigma, stop_thresholds
from insrail.nav.imu_gaps import bridge_gaps
from insrail.nav.imu_profile import load_imu_profile
from insrail.nav.imu_screening import ImuUnitError, screen_imu
from insrail.nav.startup import track_heading

RATE_HZ = 200.0
T0 = 230400.0


def walking_imu(seconds: float = 20.0, rng_seed: int = 3) -> ImuIncrements:
    """A trolley's increments: gravity, a slow sway and sensor noise, at 200 Hz."""
    rng = np.random.default_rng(rng_seed)
    n = int(seconds * RATE_HZ)
    t = T0 + np.arange(1, n + 1) / RATE_HZ
    f = np.column_stack([0.05 * np.sin(0.7 * t), 0.08 * np.sin(1.3 * t), np.full(n, -9.79)]) + rng.normal(0, 0.01, (n, 3))
    w = np.column_stack([0.01 * np.sin(2.1 * t), 0.01 * np.cos(1.7 * t), 0.002 * np.ones(n)]) + rng.normal(0, 1e-4, (n, 3))
    return ImuIncrements(t, w / RATE_HZ, f / RATE_HZ, source="imu.txt")


# --------------------------------------------------------------------------- screening


@pytest.mark.parametrize("value, reason", [(0.5, "spike"), (1.0, "beyond range"), (1e300, "beyond range"),
                                           (np.nan, "not finite"), (np.inf, "not finite")])
def test_a_corrupt_record_is_removed_listed_and_bridged(value, reason):
    imu = walking_imu()
    dvel = imu.dvel_mps.copy()
    k = 1234
    dvel[k, 0] = dvel[k, 0] + value if value < 2.0 else value  # +0.5 m/s in 5 ms: 10 g; +1 m/s beyond 20 g
    bad = ImuIncrements(imu.time_s, imu.dtheta_rad, dvel, source=imu.source)
    screened, outliers, notices = screen_imu(bad, load_imu_profile("nav"))
    assert [o.index for o in outliers] == [k] and outliers[0].reason == reason
    assert outliers[0].quantity == "specific force" and outliers[0].axis == "x"
    assert len(screened) == len(imu) - 1
    assert len(notices) == 1 and f"record {k + 1} at t = {imu.time_s[k]:.4f} s removed as an outlier" in notices[0].message
    assert notices[0].time_s == pytest.approx(imu.time_s[k]) and notices[0].message.startswith("imu.txt: ")
    bridged, warnings = bridge_gaps(screened)
    assert len(bridged) == len(imu) and np.allclose(bridged.time_s, imu.time_s)
    # the bridged record is the mean of its neighbours: within the sway and noise of the true one
    assert abs(bridged.dvel_mps[k, 0] - imu.dvel_mps[k, 0]) < 5 * 0.01 / RATE_HZ
    assert len(warnings) == 1


def test_clean_motion_and_steps_are_not_outliers():
    imu = walking_imu()
    dvel = imu.dvel_mps.copy()
    dvel[2000:, 0] += 5.0 / RATE_HZ  # a step of 0.5 g (a real change, kept on both sides)
    screened, outliers, notices = screen_imu(ImuIncrements(imu.time_s, imu.dtheta_rad, dvel), load_imu_profile("nav"))
    assert outliers == () and notices == [] and len(screened) == len(imu)


@pytest.mark.parametrize("quantity, axis, added", [("angular rate", 0, 3e-3), ("specific force", 2, 0.07)])
def test_a_spike_inside_the_envelope_but_far_outside_the_noise_is_removed_and_bridged(quantity, axis, added):
    """3 mrad in one 5 ms angle increment (0.6 rad/s, below 50 deg/s) or 0.07 m/s in one velocity increment
    (1.4 g, below 2 g): thousands of times the sway and noise of its neighbours (issue 33)."""
    imu = walking_imu()
    k = 2345
    dtheta, dvel = imu.dtheta_rad.copy(), imu.dvel_mps.copy()
    (dtheta if quantity == "angular rate" else dvel)[k, axis] += added
    screened, outliers, notices = screen_imu(ImuIncrements(imu.time_s, dtheta, dvel, source=imu.source),
                                             load_imu_profile("nav"))
    assert [(o.index, o.quantity, o.axis, o.reason) for o in outliers] == [(k, quantity, "xyz"[axis],
                                                                             "spike below the envelope")]
    assert len(notices) == 1 and "spike below the envelope" in notices[0].message
    bridged, _ = bridge_gaps(screened)
    true, got = (imu.dtheta_rad, bridged.dtheta_rad) if quantity == "angular rate" else (imu.dvel_mps, bridged.dvel_mps)
    assert abs(got[k, axis] - true[k, axis]) < 0.01 * added


@pytest.mark.parametrize("chunk", [1 << 18, 997])
def test_spikes_of_both_quantities_are_found_alike_side_by_side_and_one_after_the_other(monkeypatch, chunk):
    """The angular rates' below-envelope test runs in a thread beside the specific force's: the same
    outliers in the same order, a record spiking in both listed once, by its specific force (as serially)."""
    from functools import partial

    from insrail.background import BackgroundJob
    from insrail.nav import imu_screening

    imu = walking_imu()
    dtheta, dvel = imu.dtheta_rad.copy(), imu.dvel_mps.copy()
    dtheta[[1500, 2345, 3100], 0] += 3e-3
    dvel[[700, 2345, 3600], 2] += 0.07
    spiked = ImuIncrements(imu.time_s, dtheta, dvel, source=imu.source)
    runs = {}
    for threaded in (False, True):
        monkeypatch.setattr(imu_screening, "BackgroundJob", partial(BackgroundJob, threaded=threaded))
        screened, outliers, notices = screen_imu(spiked, load_imu_profile("nav"), chunk=chunk)
        runs[threaded] = (screened.time_s.tobytes(), outliers, [n.message for n in notices])
    assert runs[True] == runs[False]
    assert [(o.index, o.quantity) for o in runs[True][1]] == [(700, "specific force"), (1500, "angular rate"),
                                                               (2345, "specific force"), (3100, "angular rate"),
                                                               (3600, "specific force")]


def test_motion_too_rough_for_the_below_envelope_test_removes_nothing_by_it_and_says_so():
    imu = walking_imu()
    dtheta = imu.dtheta_rad.copy()
    dtheta[7::40, 1] += 0.05 / RATE_HZ  # 2.5 % of the records jolted by 0.05 rad/s: a rough ride, not faults
    screened, outliers, notices = screen_imu(ImuIncrements(imu.time_s, dtheta, imu.dvel_mps, source=imu.source),
                                             load_imu_profile("nav"))
    assert outliers == () and len(screened) == len(imu)
    assert len(notices) == 1 and "too rough to tell a single faulty record" in notices[0].message


def test_the_compiled_neighbour_medians_are_numpys_with_ties_and_nans():
    """The below-envelope test's compiled moving medians (10 neighbours: the mean of the middle two) equal
    np.median's, NaN where a window holds one (a zero's sign aside: numpy orders -0.0/0.0 ties its own way)."""
    from insrail.nav._screening_kernels import neighbour_median_and_spread

    rng = np.random.default_rng(7)
    rates = np.round(rng.normal(size=(3000, 3)), 1)  # rounded: many ties
    rates[rng.integers(0, 3000, 40)] = np.nan
    rates[rng.integers(0, 3000, 40), 2] = np.nan
    windows = np.lib.stride_tricks.sliding_window_view(rates, 11, axis=0)
    neighbours = np.concatenate([windows[..., :5], windows[..., 6:]], axis=-1)
    reference = np.median(neighbours, axis=-1)
    spread = 1.4826 * np.median(np.abs(neighbours - reference[..., None]), axis=-1)
    got_reference, got_spread = neighbour_median_and_spread(rates, 5)
    assert np.isnan(reference).any()
    assert np.array_equal(got_reference, reference, equal_nan=True)
    assert np.array_equal(got_spread, spread, equal_nan=True)


def test_a_file_far_outside_the_envelope_is_an_error_naming_it():
    imu = walking_imu()
    wrong_unit = ImuIncrements(imu.time_s, imu.dtheta_rad * 100.0, imu.dvel_mps, source=imu.source)  # deg as rad
    noisy = wrong_unit.dtheta_rad.copy()
    noisy[::10] *= 400.0
    with pytest.raises(ValueError, match=r"imu.txt: \d+ of 4000 records .* not a few corrupt records but a wrong unit"):
        screen_imu(ImuIncrements(imu.time_s, noisy, imu.dvel_mps, source=imu.source), load_imu_profile("nav"))


def resting_then_walking_imu(profile: str, seconds_at_rest: float = 10.0, rng_seed: int = 5) -> ImuIncrements:
    """A trolley at rest (gravity, the earth rate and a bias of the profile's size, the profile's
    noise) for ``seconds_at_rest``, then walking (:func:`walking_imu`)."""
    p = load_imu_profile(profile)
    rng = np.random.default_rng(rng_seed)
    n = int(seconds_at_rest * RATE_HZ)
    lat = math.radians(30.0)
    earth = 7.292115e-5 * np.array([math.cos(lat), 0.0, -math.sin(lat)])
    bias = rng.normal(0.0, max(p.gyro_bias_turn_on, 1e-12), 3)
    w = earth + bias + rng.normal(0.0, p.gyro_arw * math.sqrt(RATE_HZ), (n, 3))
    f = np.array([0.0, 0.0, -9.79]) + rng.normal(0.0, p.accel_vrw * math.sqrt(RATE_HZ), (n, 3))
    walk = walking_imu(rng_seed=rng_seed)
    t = T0 - seconds_at_rest + np.arange(n) / RATE_HZ
    return ImuIncrements(np.concatenate([t, walk.time_s]), np.vstack([w / RATE_HZ, walk.dtheta_rad]),
                         np.vstack([f / RATE_HZ, walk.dvel_mps]), source="imu.npy")


UNIT_FAULTS = {  # what the logger wrote: (change of the file, what the message must say)
    "degrees": (lambda th, dv: (np.degrees(th), dv), "angle increments look like degrees, not radians"),
    "deg/s": (lambda th, dv: (np.degrees(th) * RATE_HZ, dv), "angular rates in deg/s, not angle increments"),
    "angle sums": (lambda th, dv: (np.cumsum(th, axis=0), dv), "running sums of the angle increments"),
    "g": (lambda th, dv: (th, dv / 9.80665), "velocity increments look like velocity increments in g*s"),
    "specific force": (lambda th, dv: (th, dv * RATE_HZ), "specific force in m/s^2 (rates), not velocity increments"),
    "velocity sums": (lambda th, dv: (th, np.cumsum(dv, axis=0)), "running sums of the velocity increments"),
    "mm/s": (lambda th, dv: (th, 1e3 * dv), "velocity increments in mm/s"),
}


@pytest.mark.parametrize("profile", ["nav", "tactical_fog", "mems"])
@pytest.mark.parametrize("fault", UNIT_FAULTS)
def test_an_imu_file_in_another_unit_is_named_with_its_likely_unit(profile, fault):
    imu = resting_then_walking_imu(profile)
    screen_imu(imu, load_imu_profile(profile))  # the clean file passes, in any profile
    change, says = UNIT_FAULTS[fault]
    dtheta, dvel = change(imu.dtheta_rad, imu.dvel_mps)
    with pytest.raises(ImuUnitError, match="^imu.npy: ") as error:
        screen_imu(ImuIncrements(imu.time_s, dtheta, dvel, source=imu.source), load_imu_profile(profile))
    assert says in str(error.value)


def test_without_a_rest_the_gyro_unit_is_not_judged_and_motion_is_not_mistaken_for_it():
    imu = walking_imu()  # turning at up to 0.01 rad/s all the time: no rest, no verdict on the gyro
    screen_imu(imu, load_imu_profile("nav"))
    screen_imu(ImuIncrements(imu.time_s, np.degrees(imu.dtheta_rad), imu.dvel_mps), load_imu_profile("nav"))


def test_many_outliers_are_summed_up_after_the_first_ten():
    imu = walking_imu()
    dvel = imu.dvel_mps.copy()
    dvel[100:3700:200, 2] += 1.0  # 18 records
    _, outliers, notices = screen_imu(ImuIncrements(imu.time_s, imu.dtheta_rad, dvel), load_imu_profile("nav"))
    assert len(outliers) == 18 and len(notices) == 11
    assert "8 more IMU records removed as outliers" in notices[-1].message


# --------------------------------------------------------------------------- gaps


def test_gaps_are_bridged_evenly_and_long_ones_refused():
    imu = walking_imu()
    keep = np.ones(len(imu), dtype=bool)
    keep[1000:1400] = False  # 2 s
    holed = ImuIncrements(imu.time_s[keep], imu.dtheta_rad[keep], imu.dvel_mps[keep], source=imu.source)
    bridged, warnings = bridge_gaps(holed)
    assert np.allclose(bridged.time_s, imu.time_s) and len(bridged.gaps) == 1
    assert "IMU gap of 2.005 s" in warnings[0] and "rests on the aiding" in warnings[0]
    # what the interpolation misses: the noise of its two end records over 400 records
    assert bridged.dvel_mps[:, 2].sum() == pytest.approx(imu.dvel_mps[:, 2].sum(), abs=400 * 3 * 0.01 / RATE_HZ)
    keep[2000:3300] = False  # 6.5 s
    with pytest.raises(ValueError, match=r"imu.txt: IMU data gap of 6\.505 s after t = .* cannot be bridged"):
        bridge_gaps(ImuIncrements(imu.time_s[keep], imu.dtheta_rad[keep], imu.dvel_mps[keep], source=imu.source))


def test_an_uneven_gap_keeps_the_rates():
    """A gap of 2.5 nominal intervals: one record inserted at 1.25 intervals, rates kept."""
    t = T0 + np.concatenate([np.arange(10), 11.5 + np.arange(10)]) * 0.005
    f = np.tile([0.0, 0.0, -9.8], (len(t), 1))
    bridged, _ = bridge_gaps(ImuIncrements(t, np.zeros((len(t), 3)), f * 0.005))
    dt = np.diff(bridged.time_s)
    assert len(bridged) == len(t) + 1
    np.testing.assert_allclose(bridged.dvel_mps[1:, 2] / dt, -9.8)


def test_rates_csv_dropout_is_bridged_once(tmp_path):
    """The rates reader does not integrate across a dropout; bridge_gaps fills it: the velocity
    increments at rest add up to g x time with or without the dropout (they counted it twice)."""
    t = T0 + np.arange(2001) / RATE_HZ
    rows = np.column_stack([t, np.zeros_like(t), np.zeros_like(t), np.full_like(t, -9.79), np.zeros((len(t), 3))])
    np.savetxt(tmp_path / "clean.csv", rows, delimiter=",", fmt="%.6f")
    keep = (t < t[0] + 4.0) | (t >= t[0] + 5.0)
    np.savetxt(tmp_path / "holed.csv", rows[keep], delimiter=",", fmt="%.6f")
    clean = read_imu_rates_csv(tmp_path / "clean.csv")
    holed = read_imu_rates_csv(tmp_path / "holed.csv")
    assert len(holed.gaps) == 1
    assert holed.dvel_mps[:, 2].max() == pytest.approx(-9.79 / RATE_HZ)  # no record spans the dropout
    bridged, warnings = bridge_gaps(holed)
    assert len(warnings) == 1 and len(bridged) == len(clean)
    assert bridged.dvel_mps[:, 2].sum() == pytest.approx(clean.dvel_mps[:, 2].sum(), rel=1e-9)


# --------------------------------------------------------------------------- start-up


def test_gyrocompass_accuracy_follows_the_profile():
    lat = math.radians(40.0)
    sigma = {}
    for name in ("nav", "tactical_fog", "tactical", "mems"):
        p = load_imu_profile(name)
        sigma[name] = gyrocompass_sigma_rad(math.hypot(p.gyro_bias_turn_on, p.gyro_bias_gm_sigma), p.gyro_arw, 300.0, lat)
    assert math.degrees(sigma["nav"]) < 0.1
    assert math.degrees(sigma["tactical_fog"]) > 5.0 and math.degrees(sigma["tactical"]) > 3.0
    assert sigma["mems"] == math.pi  # no north at all


def test_stop_thresholds_come_from_the_profile_noise():
    nav = load_imu_profile("nav")
    mems = load_imu_profile("mems")
    assert stop_thresholds(nav.gyro_arw, nav.accel_vrw, 200.0)[0] == pytest.approx(2e-4)  # the trolley floor
    gyro, accel = stop_thresholds(mems.gyro_arw, mems.accel_vrw, 200.0)
    assert gyro > 5 * mems.gyro_arw * math.sqrt(200.0) * 0.99 and gyro > 2e-3
    # A MEMS unit at rest (its own noise) is found still without an odometer.
    rng = np.random.default_rng(1)
    n = 4000
    t = T0 + np.arange(1, n + 1) / RATE_HZ
    w = rng.normal(0.0, mems.gyro_arw * math.sqrt(RATE_HZ), (n, 3))
    f = np.array([0.0, 0.0, -9.79]) + rng.normal(0.0, mems.accel_vrw * math.sqrt(RATE_HZ), (n, 3))
    # sets off after 10 s: a pushed trolley accelerates and rocks
    f[2000:, 0] += np.minimum(np.linspace(0.0, 1.0, n - 2000), 0.2) + rng.normal(0.0, 0.05, n - 2000)
    w[2000:] += rng.normal(0.0, 0.01, (n - 2000, 3))
    imu = ImuIncrements(t, w / RATE_HZ, f / RATE_HZ)
    assert detect_stops(imu, None) == []  # the navigation-grade limit never fires on a MEMS unit
    stops = detect_stops(imu, None, max_gyro_std_radps=gyro, max_accel_std_mps2=accel)
    assert len(stops) == 1 and stops[0][0] <= t[0] + 1.0 and t[0] + 8.0 < stops[0][1] <= t[0] + 10.0


@pytest.mark.parametrize("rocking_mps", [0.0, 1e-4, 1e-3])
def test_a_stops_zupt_noise_is_the_motion_its_accelerometers_show_beyond_their_noise(rocking_mps):
    """A platform standing perfectly still (the accelerometers' white noise and an in-run bias
    drifting by twice its 1-sigma over the stop) shows no motion; one rocking at 0.5 Hz with a velocity
    amplitude of 0.1 or 1 mm/s shows its velocity's standard deviation (amplitude / sqrt 2)."""
    nav = load_imu_profile("nav")
    rng = np.random.default_rng(7)
    n = int(60 * RATE_HZ)
    t = T0 + np.arange(1, n + 1) / RATE_HZ
    f = np.array([0.0, 0.0, -9.79]) + rng.normal(0.0, nav.accel_vrw * math.sqrt(RATE_HZ), (n, 3))
    f[:, 0] += np.linspace(0.0, 2.0 * nav.accel_bias_gm_sigma, n)  # the bias drifting
    f[:, 1] += rocking_mps * 2.0 * math.pi * 0.5 * np.cos(2.0 * math.pi * 0.5 * (t - T0))
    imu = ImuIncrements(t, np.zeros((n, 3)), f / RATE_HZ)
    sigma = stop_motion_sigma(imu, [(t[10], t[-10]), (t[0], t[5])], nav.accel_vrw)
    assert sigma[1] == 0.0  # too short to tell
    if rocking_mps == 0.0:
        assert sigma[0] == 0.0
    else:
        assert sigma[0] == pytest.approx(rocking_mps / math.sqrt(2.0), rel=0.1)


@pytest.mark.parametrize("radius_m", [30.0, 300.0, np.inf])
def test_track_heading_on_a_curve_has_an_honest_sigma(radius_m):
    rng = np.random.default_rng(int(radius_m) if np.isfinite(radius_m) else 0)
    s = np.arange(0.0, 100.0, 0.25)  # 1 m/s at 4 Hz
    start_heading = math.radians(30.0)
    if np.isfinite(radius_m):
        psi = start_heading + s / radius_m
        north = radius_m * (np.sin(psi) - math.sin(start_heading))
        east = radius_m * (math.cos(start_heading) - np.cos(psi))
    else:
        north, east = s * math.cos(start_heading), s * math.sin(start_heading)
    errors = []
    for _ in range(40):
        ned = np.column_stack([north, east, np.zeros_like(s)]) + rng.normal(0.0, 0.01, (len(s), 3))
        result = track_heading(ned, np.full(len(s), 0.01), 0)
        errors.append((result.heading_rad - start_heading) / result.sigma_heading_rad)
        assert math.degrees(result.sigma_heading_rad) < 2.0
    assert np.sqrt(np.mean(np.square(errors))) < 1.5  # the 1-sigma is not optimistic


def test_profiles_ship_for_every_class_and_the_range_table_is_checked(tmp_path):
    mems = load_imu_profile("mems")
    assert mems.specific_force_range_mps2 == pytest.approx(8 * 9.80665)
    assert load_imu_profile("tactical_fog").gyro_arw < load_imu_profile("tactical").gyro_arw
    text = (tmp_path / "x.toml")
    from insrail.resources import resource

    text.write_text(resource("imu_profiles", "nav.toml").read_text().replace("rate_deg_per_s = 400.0",
                                                                              "rate_deg_per_s = -1\nspeed = 3"))
    with pytest.raises(ValueError, match=r"range.speed: unknown key[\s\S]*range.rate_deg_per_s: expected a positive"):
        load_imu_profile(text)


# --------------------------------------------------------------------------- failures reach the user as messages


def test_cli_fuse_says_what_to_do_when_the_start_fails(tmp_path, capsys):
    """10 s at rest (too short to gyrocompass) that never moves: no traceback, a message naming the
    survey and what to give; the same survey with a 6 s IMU dropout names the file and the time."""
    from test_io_survey import make_manifest, make_survey_files

    from insrail.cli.main import main
    from insrail.io.imu import read_imu_kfgins, write_imu_kfgins
    from insrail.io.survey import write_manifest

    write_manifest(tmp_path, make_manifest(make_survey_files(tmp_path)))
    assert main(["fuse", str(tmp_path), "--out", str(tmp_path / "out")]) == 1
    err = capsys.readouterr().err
    assert "insrail fuse: survey Line 3 down track" in err and "give the initial heading (--heading)" in err
    assert "Traceback" not in err and not (tmp_path / "out" / "trajectory.npy").exists()

    imu = read_imu_kfgins(tmp_path / "imu.txt")
    keep = (imu.time_s < imu.time_s[0] + 2.0) | (imu.time_s > imu.time_s[0] + 8.0)
    write_imu_kfgins(tmp_path / "imu.txt", ImuIncrements(imu.time_s[keep], imu.dtheta_rad[keep], imu.dvel_mps[keep],
                                                          gps_week=imu.gps_week))
    assert main(["fuse", str(tmp_path), "--out", str(tmp_path / "out")]) == 1
    err = capsys.readouterr().err
    assert "imu.txt: IMU data gap of 6.0" in err and "cannot be bridged - split the survey there" in err


def test_cli_fuse_reads_the_survey_beside_its_imports_and_names_a_bad_line_as_before(tmp_path, capsys, monkeypatch):
    """`insrail fuse` reads the survey in a thread of its own while the filter's modules are imported; what
    it finds wrong in a file is the same input error (file, line, expected), exit code 1, nothing written."""
    import threading

    from test_io_survey import make_manifest, make_survey_files

    from insrail import background
    from insrail.cli.main import main
    from insrail.io import survey as survey_io

    monkeypatch.setattr(background, "cpu_budget", lambda: 2)  # also with one CPU
    write_manifest = survey_io.write_manifest
    write_manifest(tmp_path, make_manifest(make_survey_files(tmp_path)))
    lines = (tmp_path / "imu.txt").read_text().splitlines(keepends=True)
    lines[6] = "230400.5 0.1 x 0.3\n"
    (tmp_path / "imu.txt").write_text("".join(lines))
    read_in = []
    read_survey = survey_io.read_survey
    monkeypatch.setattr(survey_io, "read_survey",
                        lambda *a, **k: (read_in.append(threading.current_thread().name), read_survey(*a, **k))[1])
    assert main(["fuse", str(tmp_path), "--out", str(tmp_path / "out")]) == 1
    err = capsys.readouterr().err
    assert "insrail: input error:" in err and "imu.txt" in err and "line 7" in err and "Traceback" not in err
    assert read_in == ["insrail-reading"] and not (tmp_path / "out").exists()


def test_a_bridged_gap_tells_the_filter_what_the_interpolation_may_miss():
    """The interpolation's error on the stretches beside a gap stands for the gap's: the sway the
    logger lost is of that size, and the filter gets it as process noise on the gap's segment."""
    from insrail.nav.error_model import ATT, POS, VEL
    from insrail.nav.imu_gaps import bridge_uncertainty, bridged_process_noise

    imu = walking_imu(seconds=40.0)
    keep = (imu.time_s <= imu.time_s[0] + 20.0) | (imu.time_s > imu.time_s[0] + 22.0)
    bridged, _ = bridge_gaps(ImuIncrements(imu.time_s[keep], imu.dtheta_rad[keep], imu.dvel_mps[keep]))
    [(gap, sigma_theta, sigma_vel)] = bridge_uncertainty(bridged)
    missed_vel = np.abs((bridged.dvel_mps - imu.dvel_mps).sum(axis=0))
    assert gap.duration_s == pytest.approx(2.005)
    assert np.max(sigma_vel) > 0.3 * np.max(missed_vel) and np.max(sigma_vel) < 10 * np.max(missed_vel)
    epochs = np.arange(0, len(bridged), 20)  # a 10 Hz update grid
    extra = bridged_process_noise(bridged, epochs)
    [(j, q)] = extra.items()
    k_end = int(np.searchsorted(bridged.time_s, gap.end_s))
    assert epochs[j - 1] < k_end <= epochs[j]
    assert q[ATT, ATT] == pytest.approx(np.max(sigma_theta) ** 2) and q[VEL, VEL] == pytest.approx(np.max(sigma_vel) ** 2)
    assert q[POS, POS] == pytest.approx(np.max(sigma_vel) ** 2 * (0.5 * gap.duration_s) ** 2)
    assert bridged_process_noise(walking_imu(), epochs) == {}


def test_sleepers_around_a_long_bridged_gap_are_not_assessed():
    from dataclasses import replace as replaced

    from report_support import START_TIME_S, synthetic_table

    from insrail.project.gap_sleepers import MARGIN_M, flag_gap_sleepers

    table = synthetic_table()
    table = replaced(table, not_assessed=("turnout",) + ("",) * (len(table) - 1))
    gap = [START_TIME_S + 100.0, START_TIME_S + 102.0]  # 1 m/s: stations 100 to 102 m from the start
    flagged = flag_gap_sleepers(table, [gap, [START_TIME_S + 300.0, START_TIME_S + 300.1]])  # 0.1 s: kept
    s0, s1 = np.interp(gap, table.time_s, table.station_m)
    near = (table.station_m >= s0 - MARGIN_M) & (table.station_m <= s1 + MARGIN_M)
    assert near.sum() >= 18 and not flagged.valid[near].any()
    assert (flagged.valid[~near] == table.valid[~near]).all()
    assert all(flagged.not_assessed[k] == "IMU gap of 2.00 s bridged" for k in np.flatnonzero(near))
    assert flagged.not_assessed[0] == "turnout" and flagged.not_assessed[np.flatnonzero(~near)[-1]] == ""
    assert flag_gap_sleepers(table, []) is table
