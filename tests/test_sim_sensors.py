"""The simulated sensors carry the errors the scenario asks for, and nothing else."""

import numpy as np
import pytest

from insrail.io.survey import read_survey
from insrail.nav import earth
from insrail.nav.imu_profile import load_imu_profile
from insrail.nav.rotation import euler_to_dcm
from insrail.sim import sensors
from insrail.sim.scenario import preset
from insrail.sim.simulate import height_anomaly
from insrail.sim.truth import read_nav_truth, read_sleeper_truth


@pytest.fixture(scope="module")
def survey(short_perfect_survey):
    return read_survey(short_perfect_survey)


@pytest.fixture(scope="module")
def truth(short_perfect_survey):
    return read_nav_truth(short_perfect_survey / "truth" / "nav.npy")


def test_survey_folder_loads_with_the_io_readers(survey):
    assert len(survey.imu) > 250_000
    assert survey.imu.rate_hz == pytest.approx(200.0)
    assert survey.gauge is not None and survey.sleepers is not None and survey.benchmarks is not None
    assert survey.manifest.trolley.reference_rail == "left"


def test_gnss_errors_and_outage(survey, truth):
    g = survey.gnss
    # Antenna truth from the IMU truth and the lever arm (b frame).
    k = np.searchsorted(truth["time_s"], g.time_s)
    assert np.allclose(truth["time_s"][k - 1] + 0.0025, g.time_s)  # GNSS seconds fall mid-interval
    row0, row1 = truth[k - 1], truth[k]
    lat = 0.5 * (row0["lat_rad"] + row1["lat_rad"])
    lon = 0.5 * (row0["lon_rad"] + row1["lon_rad"])
    h = 0.5 * (row0["height_m"] + row1["height_m"])
    c_bn = euler_to_dcm(*(0.5 * (row0["rpy_rad"] + row1["rpy_rad"])).T)
    lever_n = c_bn @ survey.manifest.trolley.imu_to_antenna_m
    r_m, r_n = earth.radii(lat)
    err_n = (g.lat_rad - lat) * (r_m + h) - lever_n[:, 0]
    err_e = (g.lon_rad - lon) * (r_n + h) * np.cos(lat) - lever_n[:, 1]
    err_d = -(g.height_m - h) - lever_n[:, 2]
    # white 10/20 mm plus Gauss-Markov 5/10 mm (300 s): total 11.2 / 22.4 mm
    assert 0.008 < np.std(err_n) < 0.015 and 0.008 < np.std(err_e) < 0.015
    assert 0.016 < np.std(err_d) < 0.030
    assert abs(np.mean(err_n)) < 0.008 and abs(np.mean(err_d)) < 0.015
    # One 120 s outage, starting when the trolley passes station 1600 m.
    long_gaps = [gap for gap in g.gaps if gap.duration_s > 5]
    assert len(long_gaps) == 1 and long_gaps[0].duration_s == pytest.approx(121.0, abs=1.0)
    station_at_gap = np.interp(long_gaps[0].start_s + 1.0, truth["time_s"], truth["station_m"])
    assert station_at_gap == pytest.approx(1600.0, abs=1.5)


def test_odometer_scale_and_quantisation(survey, truth):
    odo = survey.odometer
    travelled = truth["station_m"][-1] - truth["station_m"][0]
    # The wheel runs on the left (outer) rail of the right-hand curve: a little longer
    # than the centreline; the scale error is +0.15 %.
    assert odo.distance_m[-1] / 1.0015 == pytest.approx(travelled + 0.18, abs=0.1)
    assert np.allclose(np.round(odo.distance_m / 0.001) * 0.001, odo.distance_m, atol=1e-9)
    assert np.all(np.diff(odo.distance_m) >= 0)


def test_gauge_noise(short_perfect_survey, survey, truth):
    sleepers = read_sleeper_truth(short_perfect_survey / "truth" / "sleepers.csv")
    gauge = survey.gauge
    station = np.interp(gauge.time_s, truth["time_s"], truth["station_m"])
    moving = (station > sleepers["station"][0]) & (station < sleepers["station"][-1])
    true_gauge = np.interp(station[moving], sleepers["station"], sleepers["gauge"])
    noise = gauge.gauge_m[moving] - true_gauge
    # Sleeper-spaced linear interpolation of the true gauge adds a few micrometres at most.
    assert np.std(noise) == pytest.approx(0.1e-3, rel=0.15)
    assert abs(np.mean(noise)) < 0.02e-3


def test_sleeper_pulses_missed_and_false(short_perfect_survey, survey):
    sleepers = read_sleeper_truth(short_perfect_survey / "truth" / "sleepers.csv")
    pulses = survey.sleepers.time_s
    detected = sleepers["detected"] == 1
    assert 0.97 < detected.mean() < 1.0
    assert len(pulses) > detected.sum()  # some false pulses too
    nearest = np.abs(pulses[np.clip(np.searchsorted(pulses, sleepers["pass_time"][detected]), 0, len(pulses) - 1)]
                     - sleepers["pass_time"][detected])
    nearest = np.minimum(nearest, np.abs(pulses[np.clip(np.searchsorted(pulses, sleepers["pass_time"][detected]) - 1, 0, None)]
                                         - sleepers["pass_time"][detected]))
    assert np.all(nearest < 0.006)
    spacing = np.diff(sleepers["station"])
    assert np.mean(spacing) == pytest.approx(0.625, abs=1e-3)


def test_benchmarks_carry_the_height_anomaly(survey):
    from insrail.geodesy import EngineeringCRS

    config = preset("short")
    bm = survey.benchmarks
    crs = EngineeringCRS.from_settings(config.geodetic.crs)
    east, north = crs.to_plane(bm.lat_rad, bm.lon_rad)
    assert np.allclose(bm.height_anomaly_m, height_anomaly(config, east, north), atol=0.012)


def test_gauss_markov_is_stationary_with_the_right_correlation():
    rng = np.random.default_rng(3)
    x = sensors.gauss_markov(rng, 400_000, 1.0, [2.0], 20.0)[:, 0]
    assert np.std(x) == pytest.approx(2.0, rel=0.05)
    lag = 20
    corr = np.corrcoef(x[:-lag], x[lag:])[0, 1]
    assert corr == pytest.approx(np.exp(-1.0), abs=0.03)


def test_imu_noise_and_bias_match_the_profile():
    profile = load_imu_profile("tactical")
    rng = np.random.default_rng(5)
    n, dt = 200_000, 0.005
    errors = sensors.draw_imu_errors(rng, profile, n, dt)
    zeros = np.zeros((n, 3))
    dtheta, dvel = sensors.corrupt_increments(rng, profile, errors, slice(0, n), np.full(n, dt), zeros, zeros)
    bias = errors.gyro_bias_turn_on + errors.gyro_bias_gm
    white = dtheta / dt - bias
    assert np.std(white) == pytest.approx(profile.gyro_arw / np.sqrt(dt), rel=0.02)
    assert np.mean(dvel / dt - errors.accel_bias_turn_on - errors.accel_bias_gm, axis=0) == pytest.approx(
        np.zeros(3), abs=5 * profile.accel_vrw / np.sqrt(n * dt))
    # Scale factors act on the true increments.
    ones = np.ones((n, 3))
    dtheta2, _ = sensors.corrupt_increments(rng, load_imu_profile("perfect"), errors, slice(0, n), np.full(n, dt), ones, zeros)
    assert np.allclose(dtheta2 - bias * dt, 1.0 + errors.gyro_scale_factor, atol=1e-12)
