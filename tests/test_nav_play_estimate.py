"""The trolley's play estimated from the survey itself (issue 33): a trolley without play is fused again
with the play its NHC innovations show, and its stated accuracy shrinks with it while still covering the
actual error; one with the profile's play keeps the profile's (no second pass)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
import shared_build

from insrail.io.survey import read_survey
from insrail.nav.earth import CGCS2000
from insrail.nav.fusion import FusionOptions, aiding_for
from insrail.nav.imu_profile import load_imu_profile
from insrail.nav.self_calibration import fuse_consistent, play_from_innovations
from insrail.quality.survey import survey_quality
from insrail.sim.evaluation import trajectory_errors
from insrail.sim.truth import read_nav_truth


def _survey(play: bool):
    """300 m of the `short` line (straight into its clothoid), navigation grade, pushed at 1 m/s."""
    from insrail.sim.scenario import preset
    from insrail.sim.simulate import simulate

    config = preset("short")
    config = replace(config, motion=replace(config.motion, start_station_m=1100.0, end_station_m=1400.0, stops=(),
                                            static_start_s=60.0, static_end_s=10.0, cruise_speed_mps=1.0),
                     gnss=replace(config.gnss, outages=()))
    if not play:
        config = replace(config, play=replace(config.play, pitch_rms_rad=0.0, yaw_rms_rad=0.0))
    return shared_build.built_once(f"play-{play}", lambda out: simulate(config, seed=3, out_dir=out, imu_format="npy"))


def _fused(folder, estimate: bool):
    survey = read_survey(folder)
    profile = load_imu_profile(survey.manifest.imu_profile)
    result, options, _, calibration = fuse_consistent(
        survey.imu, lambda o: aiding_for(survey, o, profile, None), profile, FusionOptions(estimate_play=estimate),
        CGCS2000)
    quality = survey_quality(survey, result, options, profile, CGCS2000)
    errors = trajectory_errors(result.trajectory, read_nav_truth(folder / "truth" / "nav.npy"), CGCS2000)
    stated = float(np.sqrt(np.nanmean(quality.sigma_lag5_lateral_m**2)))
    return result, options, calibration, stated, errors.lag_difference_sigma_m(5.0)[0]


def test_a_trolley_without_play_is_fused_with_the_play_its_innovations_show():
    folder = _survey(play=False)
    profile_result, _, _, profile_stated, profile_actual = _fused(folder, estimate=False)
    lateral, vertical = play_from_innovations(profile_result)
    assert lateral < 0.1 * 0.025e-6 and vertical < 0.1 * 0.025e-6  # six times smaller innovations than the profile's

    result, options, calibration, stated, actual = _fused(folder, estimate=True)
    assert calibration.play_estimated and calibration.passes >= 2
    assert max(options.play_drift_m2_per_m) < 0.1 * 0.025e-6 and options.nhc_sigma_mps < 0.45e-3
    logged = calibration.to_dict()
    assert logged["profile_play_drift_mm2_per_m"] == [0.025, 0.025] and max(logged["play_drift_mm2_per_m"]) < 0.0025
    assert any("trolley play estimated from the NHC innovations" in n.message for n in result.info["notices"])
    # the stated 5 m lag follows: smaller, and still no smaller than the error it states
    assert stated < 0.5 * profile_stated and actual <= 1.25 * stated and actual <= profile_actual


def test_a_trolley_with_the_profiles_play_keeps_it():
    """...and the odometer's and the GNSS's noise as the profile states them: one pass."""
    _, options, calibration, stated, actual = _fused(_survey(play=True), estimate=True)
    assert not calibration.play_estimated and calibration.passes == 1
    noise = calibration.to_dict()["noise"]
    assert {key: found["applied_factor"] for key, found in noise.items()} == {"odometer": 1.0, "gnss_fix": 1.0}
    assert options.play_drift_m2_per_m == pytest.approx((0.025e-6, 0.025e-6))
    assert actual <= 1.25 * stated


def _tiny_with_a_fault(tmp_path):
    """The `tiny` stretch (150 m of the `short` line, navigation grade, with the simulator's play) and a copy
    of it whose one IMU record 35 ms before a sleeper carries 3 mrad more roll and 0.07 m/s more vertical
    velocity: below the screening (its test of single records switched off by the caller), seen by the
    aiding only, which resets the filter."""
    import shutil

    from insrail.sim.scenario import GnssSpec, preset
    from insrail.sim.simulate import simulate
    from insrail.sim.truth import read_sleeper_truth

    short = preset("short")
    config = replace(short, name="tiny", gnss=GnssSpec(),
                     motion=replace(short.motion, start_station_m=1100.0, end_station_m=1250.0, stops=(),
                                    static_start_s=60.0, static_end_s=10.0))
    clean = shared_build.built_once("play-tiny", lambda out: simulate(config, seed=1, out_dir=out, imu_format="npy"))
    faulty = tmp_path / "fault"
    shutil.copytree(clean, faulty)
    records = np.load(faulty / "imu.npy")
    fault = int(np.searchsorted(records["time_s"], read_sleeper_truth(faulty / "truth" / "sleepers.csv")["pass_time"][20]
                                - 0.035))
    records["dtheta_rad"][fault, 0] += 3e-3
    records["dvel_mps"][fault, 2] += 0.07
    np.save(faulty / "imu.npy", records)
    return clean, faulty


def test_a_fault_seen_by_the_aiding_does_not_change_the_estimated_play(tmp_path, monkeypatch):
    """Before, the NHC innovations of the filter converging again after the fault's reset made the play
    estimated 25-30 x the profile's, and the whole survey was smoothed with it: now the rows of the reset's
    suspect time and the outliers are left out, and the estimate is the clean survey's."""
    from insrail.nav import imu_screening
    from insrail.nav.fusion import fuse

    monkeypatch.setattr(imu_screening, "QUIET_SPIKE_SIGMAS", np.inf)
    estimates = []
    for folder in _tiny_with_a_fault(tmp_path):
        survey = read_survey(folder)
        profile = load_imu_profile(survey.manifest.imu_profile)
        options = FusionOptions(estimate_play=False)
        result = fuse(survey.imu, aiding_for(survey, options, profile, None), profile, options, CGCS2000)
        estimates.append(np.array(play_from_innovations(result)))
    clean, faulty = estimates
    assert len(result.resets) >= 1  # the fault was seen
    assert np.all(clean > 0.5 * 0.025e-6) and np.all(clean < 2 * 0.025e-6)  # the simulator's play
    assert np.all(faulty / clean < 1.5) and np.all(faulty / clean > 1 / 1.5)


def test_the_odometers_and_the_gnss_noise_come_from_the_survey():
    """The odometer stated 4x too good: the innovations show it, the survey is fused again with the noise
    they show, the calibration and a notice say so, and the covariance analysis runs on it. The GNSS fixes
    stated 3x too poor (a class's factor): the estimate says so, but a noise is only ever widened (the stated
    accuracy stays on the safe side). The ZUPT's noise hides under the filter's own uncertainty: not estimated."""
    folder = _survey(play=True)
    survey = read_survey(folder)
    profile = load_imu_profile(survey.manifest.imu_profile)
    policy = tuple((q, None if f is None else (3.0 * f if q == 1 else f)) for q, f in FusionOptions().gnss_quality_policy)
    told = FusionOptions(odometer_sigma_scale=0.25, gnss_quality_policy=policy)
    result, options, _, calibration = fuse_consistent(
        survey.imu, lambda o: aiding_for(survey, o, profile, None), profile, told, CGCS2000)
    assert 1 / 1.5 <= options.odometer_sigma_scale <= 1.5
    assert dict(options.gnss_quality_policy)[1] == 3.0
    noise = calibration.to_dict()["noise"]
    assert set(noise) == {"odometer", "gnss_fix"}
    assert 2.5 < noise["odometer"]["applied_factor"] < 6.0 and noise["gnss_fix"]["applied_factor"] == 1.0
    assert noise["gnss_fix"]["estimated_sigma_mm"] < 0.5 * noise["gnss_fix"]["profile_sigma_mm"]
    assert noise["odometer"]["estimated_sigma_mm_per_s"] == pytest.approx(4.1, rel=0.3)  # the pulses' 1 mm per 0.1 s
    said = [n.message for n in result.info["notices"]]
    assert any(m.startswith("odometer noise estimated from its innovations") for m in said)
    odometer = result.timeline.measurements["odometer_nhc"]
    assert odometer.sigma_speed_scale == options.odometer_sigma_scale  # what the covariance replay reads


def test_where_the_filters_own_part_is_most_of_the_innovations_the_play_is_bounded_by_what_the_survey_shows():
    """A tactical trolley without play: the NHC rows' innovations are the filter's own part and the gyro's
    noise through the lever arm, correlated over seconds. The plain upper bound took all of them for play
    (0.02 mm^2/m, the stated 5 m lags 1.2x pessimistic); the upper confidence limit of the difference is
    near the floor, and with a play under that filter it still covers it."""
    from insrail.nav.self_calibration import PLAY_BLOCK_ROWS, play_upper_limit, variance_component

    rng = np.random.default_rng(7)
    rows = 2000
    unit = np.full(rows, 2 * 2.0 * 1.0**2)  # 2 B v^2 at 1 m/s: the play's variance per row per m^2/m
    own, other = np.full(rows, 0.25e-3**2), np.full(rows, 0.25e-3**2)  # H P- H^T, the gyro's noise [m^2/s^2]
    # innovations correlated over some rows (an AR(1) at 10 Hz) with that variance
    white = rng.standard_normal(rows)
    correlated = np.empty(rows)
    correlated[0] = white[0]
    for k in range(1, rows):
        correlated[k] = 0.5 * correlated[k - 1] + np.sqrt(1 - 0.5**2) * white[k]
    nu2 = (own + other) * correlated**2
    plain = variance_component(nu2, unit, other)
    limit = play_upper_limit(nu2, unit, own + other)
    assert plain > 0.5 * 0.025e-6 and limit < 0.2 * plain and limit < 0.2 * 0.025e-6
    true_play = 0.3 * own[0] / unit[0]  # 30 % of the filter's own part: mostly own still
    covered = [play_upper_limit((own + other + true_play * unit) * rng.chisquare(1, rows), unit, own + other)
               for _ in range(20)]
    assert np.mean(np.array(covered) >= true_play) >= 0.9 and np.median(covered) < 2 * true_play
    assert play_upper_limit(nu2[: PLAY_BLOCK_ROWS], unit[: PLAY_BLOCK_ROWS], own[: PLAY_BLOCK_ROWS]) == pytest.approx(
        variance_component(nu2[: PLAY_BLOCK_ROWS], unit[: PLAY_BLOCK_ROWS]))  # one block: the plain bound
