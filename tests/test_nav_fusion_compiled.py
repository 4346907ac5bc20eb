"""The compiled fusion engine gives what the Python engine it replaced gave (tests/reference_fusion.py):
the same trajectory to 0.01 mm at every IMU epoch of the `short` survey, the same rejections, filter
resets, per-source statistics and NIS; and its block-structured Phi and covariance propagation are
error_model's dense ones."""

import math
from dataclasses import replace

import numpy as np
import pytest
from reference_fusion import python_fusion

from insrail.io.survey import read_survey
from insrail.nav import fusion
from insrail.nav import measurements as meas
from insrail.nav.earth import CGCS2000
from insrail.nav.error_model import (
    N_STATES,
    ErrorModelNoise,
    discretise,
    dynamics_matrix,
    noise_matrix,
    play_noise,
)
from insrail.nav.imu_profile import load_imu_profile
from insrail.nav.mechanization import q_ne_from_lat_lon
from insrail.nav.rotation import dcm_to_quat, euler_to_dcm
from insrail.sim import gnss_faults
from insrail.sim.truth import read_nav_truth


@pytest.fixture(scope="module")
def both(short_nav_survey):
    """The survey started wrong (its first fix 1 m off, the heading 5 deg off: the filter resets
    itself) and with a 2 m GNSS outlier later: rejections, a reset and ordinary updates."""
    survey = read_survey(short_nav_survey)
    truth = read_nav_truth(short_nav_survey / "truth" / "nav.npy")
    first = survey.gnss.time_s[0]
    gnss = gnss_faults.outliers(survey.gnss, [first, first + 700.0], [(0.8, 0.6, 0.0), (2.0, 0.0, 0.0)])
    heading = float(truth["rpy_rad"][int(np.searchsorted(truth["time_s"], first)), 2]) + math.radians(5.0)
    survey = replace(survey, gnss=gnss)
    options = fusion.FusionOptions(initial_heading_rad=heading)
    profile = load_imu_profile(survey.manifest.imu_profile)
    aiding = fusion.aiding_for(survey, options, profile)
    compiled = fusion.fuse(survey.imu, aiding, profile, options, CGCS2000, full_forward=True)
    return compiled, python_fusion(survey.imu, aiding, profile, options, CGCS2000)


def test_same_trajectory_at_every_epoch(both):
    compiled, python = both
    for mine, theirs in ((compiled.trajectory, python.trajectory), (compiled.forward, python.forward)):
        assert len(mine) == len(theirs["time_s"]) > 250_000
        np.testing.assert_array_equal(mine.time_s, theirs["time_s"])
        lat = theirs["lat_rad"]
        north = (mine.lat_rad - lat) * 6.36e6
        east = (mine.lon_rad - theirs["lon_rad"]) * 6.39e6 * np.cos(lat)
        up = mine.height_m - theirs["height_m"]
        assert np.abs(np.column_stack([north, east, up])).max() < 1e-5  # 0.01 mm
        assert np.abs(mine.rpy_rad - theirs["rpy_rad"]).max() < 1e-9
        assert np.abs(mine.vel_ned_mps - theirs["vel_ned_mps"]).max() < 1e-7
        np.testing.assert_allclose(mine.sigma_pos_ned_m, theirs["sigma_pos_ned_m"], rtol=1e-6)
        np.testing.assert_allclose(mine.odometer_scale, theirs["odometer_scale"], atol=1e-9)


def test_same_rejections_resets_and_statistics(both):
    compiled, python = both
    assert len(compiled.resets) >= 1 and len(compiled.rejections) >= 2
    assert compiled.resets == tuple(python.resets) or all(
        (a.time_s, a.source, a.rejected, a.states) == (b.time_s, b.source, b.rejected, b.states)
        and np.allclose(a.sigma, b.sigma) for a, b in zip(compiled.resets, python.resets, strict=True))
    assert [(r.time_s, r.measurement) for r in compiled.rejections] == [(r.time_s, r.measurement) for r in python.rejections]
    for a, b in zip(compiled.rejections, python.rejections):
        np.testing.assert_allclose(a.innovation, b.innovation, atol=1e-6)
        assert a.test_statistic == pytest.approx(b.test_statistic, rel=1e-6)
    np.testing.assert_array_equal(compiled.innovations.accepted, python.accepted)
    np.testing.assert_allclose(compiled.innovations.nis, python.nis, rtol=1e-4, atol=1e-9)  # printed to 0.01
    assert list(compiled.statistics) == list(python.statistics)
    for name, st in compiled.statistics.items():
        ref = python.statistics[name]
        assert (st["used"], st["rejected"]) == (ref["used"], ref["rejected"])
        assert st["mean_nis"] == pytest.approx(ref["mean_nis"], rel=1e-6)
        np.testing.assert_allclose(st["innovation_rms"], ref["innovation_rms"], rtol=1e-6)


def _snapshot_context(rng):
    """A random compiled snapshot and the equivalent NavSnapshot."""
    ell = CGCS2000
    earth_c = fusion._kernels.earth_constants(ell)
    lat, lon, h = 0.53, 1.99, 40.0
    c_bn = euler_to_dcm(0.03, -0.01, 1.2)
    nav = np.zeros(15)
    nav[0:4] = q_ne_from_lat_lon(lat, lon)
    nav[4] = h
    nav[5:8] = c_bn @ [1.3, 0.01, -0.02]
    nav[8:12] = dcm_to_quat(c_bn)
    sums = rng.normal(size=16)
    sums[9] = 0.1
    gnss_error = rng.normal(0, 0.003, 3)
    ctx = np.zeros(meas.CTX_SIZE)
    meas.fill_context(ctx, nav, sums, 0.005, 0.0012, gnss_error, 1000.0, earth_c)
    lat_c, lon_c = ctx[meas.CTX_LAT], ctx[meas.CTX_LON]
    snap = meas.NavSnapshot(
        time_s=1000.0, lat=lat_c, lon=lon_c, h=h, vel_ned=nav[5:8].copy(), c_bn=c_bn, omega_ib_b=sums[10:13] / 0.005,
        f_b=sums[13:16] / 0.005, mean_vel_ned=sums[0:3] / 0.1, mean_omega_ib_b=sums[3:6] / 0.1, segment_s=0.1,
        odometer_scale=0.0012, rate_span_s=0.005, ellipsoid=ell, gnss_error_ned_m=gnss_error)
    return ctx, snap, earth_c


def test_each_compiled_model_is_its_python_model():
    rng = np.random.default_rng(5)
    ctx, snap, _ = _snapshot_context(rng)
    lever = np.array([0.3, -0.2, -1.1])
    sources = [
        meas.GnssPosition(np.array([1000.002]), np.array([snap.lat + 1e-7]), np.array([snap.lon - 2e-7]), np.array([40.3]),
                          np.array([[0.01, 0.012, 0.02]]), lever, 1.5, 0.002, (0.005, 0.005, 0.01)),
        meas.PositionFix(np.array([999.99]), np.array([snap.lat]), np.array([snap.lon]), np.array([39.8]),
                         np.array([0.001]), lever),
        meas.GnssVelocity(np.array([1000.0]), np.array([[1.0, 0.5, 0.0]]), np.array([[0.01, 0.001, 0.02]]), lever),
        meas.OdometerNhc(np.array([1000.0]), np.array([1.31]), euler_to_dcm(0.001, -0.002, 0.003), lever,
                         np.array([0.1, 0.7, 0.4]), np.array([0.0011]), gyro_white_noise=3e-5),
        replace(meas.OdometerNhc(np.array([1000.0]), np.array([1.31]), np.eye(3), lever, lever, np.array([0.001])),
                use_odometer=False),
        # its speed left out there (a slipping wheel, nav.odometer_pair): the NHC rows alone
        replace(meas.OdometerNhc(np.array([1000.0]), np.array([1.31]), np.eye(3), lever, lever, np.array([0.001])),
                speed_used=np.array([False])),
        meas.Zupt(np.array([1000.0]), 0.001, 2e-6),
    ]
    z, H, r = np.zeros(meas.MAX_ROWS), np.zeros((meas.MAX_ROWS, N_STATES)), np.zeros(meas.MAX_ROWS)
    for source in sources:
        form = source.compiled()
        m = meas.evaluate(form.kind, ctx, form.params, form.rows[0], z, H, r)
        z_ref, H_ref, R_ref = source.model(snap, 0)
        assert m == len(z_ref), source.name
        np.testing.assert_allclose(z[:m], z_ref, rtol=1e-9, atol=1e-12, err_msg=source.name)
        np.testing.assert_allclose(H[:m], H_ref, rtol=1e-9, atol=1e-12, err_msg=source.name)
        np.testing.assert_allclose(r[:m], np.diag(R_ref), rtol=1e-12, err_msg=source.name)
        assert np.count_nonzero(R_ref - np.diag(np.diag(R_ref))) == 0


def test_block_structured_propagation_is_the_dense_one():
    rng = np.random.default_rng(8)
    ctx, snap, earth_c = _snapshot_context(rng)
    profile = load_imu_profile("nav")
    noise = ErrorModelNoise.from_profile(profile)
    f_b, w_b = np.array([0.1, 0.05, -9.79]), np.array([0.002, -0.003, 0.02])
    F = dynamics_matrix(snap.lat, snap.h, snap.vel_ned, snap.c_bn, f_b, w_b, noise, CGCS2000)
    gqg = noise_matrix(noise)
    phi, q = discretise(F, gqg, 0.1)
    A = rng.normal(size=(N_STATES, N_STATES)) * 1e-3
    P = A @ A.T + np.diag(np.full(N_STATES, 1e-6))
    top = np.zeros((fusion.N_NAV, N_STATES))
    fusion.dynamics_rows(ctx, f_b, w_b, earth_c, top)
    np.testing.assert_allclose(top, F[: fusion.N_NAV], rtol=1e-9, atol=1e-15)
    assert np.count_nonzero(F[fusion.N_NAV :] - np.diag(np.diag(F))[fusion.N_NAV :]) == 0  # the rest is diagonal
    phi_top, phi_diag, P_minus = np.zeros((fusion.N_NAV, N_STATES)), np.ones(N_STATES), np.zeros((N_STATES, N_STATES))
    disp, play = np.array([0.08, -0.09, 0.002]), np.array([2.5e-8, 1.5e-8, 2e-9])
    fusion._transition(top, np.diag(F).copy(), np.diag(gqg).copy(), 0.1, disp, play, phi_top, phi_diag, P, P_minus)
    np.testing.assert_allclose(phi_top, phi[: fusion.N_NAV], rtol=1e-12, atol=1e-18)
    np.testing.assert_allclose(phi_diag[fusion.N_NAV :], np.diag(phi)[fusion.N_NAV :], rtol=1e-14)
    q[:3, :3] += play_noise(disp, 0.1, play)
    np.testing.assert_allclose(P_minus, phi @ P @ phi.T + q, rtol=1e-9, atol=1e-18)
    assert np.array_equal(P_minus, P_minus.T)
