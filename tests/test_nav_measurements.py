"""Each aiding measurement's Jacobian H matches its innovation's response to small errors.

A true navigation state is perturbed by an error vector x (in the filter's conventions:
navigation errors computed minus true, sensor errors residual = true minus estimate) and
the change of the innovation is compared with H x. A wrong sign or a missing term in any
block of H fails this.
"""

import math
from dataclasses import replace

import numpy as np
import pytest

from insrail.nav import earth
from insrail.nav.error_model import ATT, BG, N_STATES, ODO, POS, SG, VEL
from insrail.nav.measurements import GnssPosition, GnssVelocity, NavSnapshot, OdometerNhc, Zupt
from insrail.nav.rotation import euler_to_dcm, rotvec_to_dcm

RNG = np.random.default_rng(42)


def true_state():
    c_bn = euler_to_dcm(0.03, -0.01, 1.2)
    omega = np.array([0.002, -0.003, 0.02])
    vel = c_bn @ np.array([1.3, 0.0, 0.0])
    return NavSnapshot(
        time_s=1000.0, lat=0.53, lon=1.99, h=40.0, vel_ned=vel, c_bn=c_bn, omega_ib_b=omega,
        f_b=np.array([0.1, 0.05, -9.79]), mean_vel_ned=vel * 0.999, mean_omega_ib_b=omega * 1.01,
        segment_s=0.1, odometer_scale=0.0012, rate_span_s=0.005,
    )


def perturbed(nav: NavSnapshot, x: np.ndarray) -> NavSnapshot:
    r_m, r_n = earth.radii(nav.lat)
    c_hat = rotvec_to_dcm(-x[ATT : ATT + 3]) @ nav.c_bn  # C_hat = (I - phi x) C
    omega_hat = nav.omega_ib_b + x[BG : BG + 3] + nav.omega_ib_b * x[SG : SG + 3]
    mean_omega_hat = nav.mean_omega_ib_b + x[BG : BG + 3] + nav.mean_omega_ib_b * x[SG : SG + 3]
    return NavSnapshot(
        time_s=nav.time_s,
        lat=nav.lat + x[POS] / (r_m + nav.h),
        lon=nav.lon + x[POS + 1] / ((r_n + nav.h) * np.cos(nav.lat)),
        h=nav.h - x[POS + 2],
        vel_ned=nav.vel_ned + x[VEL : VEL + 3],
        c_bn=c_hat,
        omega_ib_b=omega_hat,
        f_b=nav.f_b,
        mean_vel_ned=nav.mean_vel_ned + x[VEL : VEL + 3],
        mean_omega_ib_b=mean_omega_hat,
        segment_s=nav.segment_s,
        odometer_scale=nav.odometer_scale - x[ODO],
        rate_span_s=nav.rate_span_s,
    )


def small_error(scale=1.0):
    x = np.zeros(N_STATES)
    x[POS : POS + 3] = RNG.normal(0, 0.02, 3)
    x[VEL : VEL + 3] = RNG.normal(0, 0.01, 3)
    x[ATT : ATT + 3] = RNG.normal(0, 2e-4, 3)
    x[BG : BG + 3] = RNG.normal(0, 1e-5, 3)
    x[SG : SG + 3] = RNG.normal(0, 1e-3, 3)
    x[ODO] = RNG.normal(0, 2e-3)
    return x * scale


def check_linearisation(measurement, i=0):
    nav = true_state()
    z0, H, R = measurement.model(nav, i)
    assert R.shape == (len(z0), len(z0)) and np.all(np.linalg.eigvalsh(R) > 0)
    for _ in range(5):
        x = small_error()
        z1, _, _ = measurement.model(perturbed(nav, x), i)
        predicted = H @ x
        # Second-order terms (e.g. phi^2 v, or the odometer scale error times the velocity error)
        # stay below 0.5 % of the largest first-order response; where a single row's first-order
        # response nearly cancels they may not, and then the residual must shrink as the square of
        # the error (a quarter of x: a sixteenth), which a wrong or missing term in H, shrinking
        # only as x, cannot do.
        residual = np.abs(z1 - z0 - predicted).max()
        if residual > 5e-3 * np.abs(predicted).max():
            z4, _, _ = measurement.model(perturbed(nav, x / 4), i)
            quarter = np.abs(z4 - z0 - predicted / 4).max()
            assert quarter < residual / 10, (z1 - z0, predicted, residual, quarter)
        # And each block matters: errors in one block alone are also reproduced.
        for block in (slice(POS, POS + 3), slice(VEL, VEL + 3), slice(ATT, ATT + 3), slice(BG, BG + 3), slice(SG, SG + 3), slice(ODO, ODO + 1)):
            xb = np.zeros(N_STATES)
            xb[block] = x[block]
            zb, _, _ = measurement.model(perturbed(nav, xb), i)
            response = H @ xb
            scale = max(np.abs(response).max(), np.abs(zb - z0).max())
            # Couplings the models neglect (error of the earth rate with position) are
            # below 1e-6 of the full response; a missing or wrong block is not.
            # Attitude enters through rotations: phi^2 (|v|, |l| ~ 1) terms remain; the odometer
            # scale through 1 / (1 + s): s^2 |v| terms remain.
            second_order = 10.0 * max(np.abs(xb[ATT : ATT + 3]).max(), abs(xb[ODO])) ** 2
            assert np.allclose(zb - z0, response, rtol=0,
                               atol=5e-3 * scale + 1e-6 * np.abs(predicted).max() + second_order), block


def test_gnss_position_jacobian():
    nav = true_state()
    check_linearisation(GnssPosition(np.array([nav.time_s + 0.002]), np.array([nav.lat + 1e-7]), np.array([nav.lon]),
                                     np.array([nav.h + 1.0]), np.array([[0.01, 0.01, 0.02]]), np.array([0.1, 0.2, -1.3])))


def test_gnss_velocity_jacobian():
    check_linearisation(GnssVelocity(np.array([1000.0]), np.array([[0.5, 1.0, 0.0]]), np.array([[0.01] * 3]), np.array([0.1, 0.2, -1.3])))


@pytest.mark.parametrize("use_odometer, use_nhc", [(True, True), (True, False), (False, True)])
def test_odometer_nhc_jacobian(use_odometer, use_nhc):
    m = OdometerNhc(np.array([1000.0]), np.array([1.31]), euler_to_dcm(0.001, -0.002, 0.003), np.array([0.45, -0.6, 0.31]),
                    np.array([0.1, -0.6, 0.31]), np.array([0.004]), use_odometer=use_odometer, use_nhc=use_nhc)
    check_linearisation(m)
    z, H, R = m.model(true_state(), 0)
    assert len(z) == int(use_odometer) + 2 * int(use_nhc)


def test_the_nhc_and_odometer_rows_noise_holds_the_gyros_white_noise_through_the_lever_arm():
    """The NHC point's and the wheel's velocity take the last IMU record's rate through their lever arms: its
    white noise (a tactical unit's 0.1 deg/sqrt(h) over a 5 ms record) moves the rows by what their R adds to
    the play's and the odometer's 1-sigma, measured here on 20000 noisy rates."""
    arw, span = math.radians(0.1) / 60.0, 0.005
    m = OdometerNhc(np.array([1000.0]), np.array([1.31]), np.eye(3), np.array([0.45, -0.6, 0.31]),
                    np.array([0.1, -0.6, 0.31]), np.array([0.004]), sigma_nhc_mps=0.0001, gyro_white_noise=arw)
    nav = true_state()
    z0, _, R = m.model(nav, 0)
    rates = nav.omega_ib_b + RNG.normal(0.0, arw / math.sqrt(span), (20000, 3))
    z = np.array([m.model(replace(nav, omega_ib_b=w), 0)[0] for w in rates])
    np.testing.assert_allclose(np.var(z, axis=0), np.diag(R) - np.array([0.004, 0.0001, 0.0001])**2, rtol=0.05)
    assert 0.2e-3 < math.sqrt(np.diag(R)[0] - 0.004**2) < 0.3e-3  # the wheel 0.75 m from the IMU
    assert 0.2e-3 < math.sqrt(np.diag(R)[2] - 0.0001**2) < 0.3e-3  # vertical, the rail point 0.6 m beside the IMU
    assert np.diag(m.model(replace(nav, rate_span_s=0.02), 0)[2])[2] < np.diag(R)[2]  # a rate over a longer record


def test_zupt_jacobian():
    check_linearisation(Zupt(np.array([1000.0])))


def test_gnss_position_is_zero_for_a_consistent_observation():
    nav = true_state()
    lever = np.array([0.1, 0.2, -1.3])
    d_lat, d_lon, d_h = earth.ned_to_geodetic_delta(nav.c_bn @ lever, nav.lat, nav.h)
    m = GnssPosition(np.array([nav.time_s]), np.array([nav.lat + d_lat]), np.array([nav.lon + d_lon]),
                     np.array([nav.h + d_h]), np.array([[0.01, 0.01, 0.02]]), lever)
    z, _, R = m.model(nav, 0)
    assert np.abs(z).max() < 1e-6
    assert np.allclose(np.diag(R), [1e-4, 1e-4, 4e-4])


def test_a_prism_fix_in_the_stop_a_survey_starts_from_or_ends_in_holds_where_the_run_leaves_or_arrives():
    """A fix in the stop holding the first update epochs (a survey without GNSS starts from it) is
    applied at the stop's last epoch, one in the stop holding the last epoch at that stop's first,
    with their times moved there; one before the start's stop, or at the start while moving, is not
    applied; the others as every time-stamped source, at the first epoch at or after them."""
    from insrail.nav.measurements import PositionFix, schedule

    grid = 10.0 + 0.1 * np.arange(1000)  # 10.0 .. 109.9 s
    times = np.array([5.0, 10.0, 20.0, 50.05, 105.0, 120.0])
    fixes = PositionFix(times, *np.zeros((3, 6)), np.full(6, 0.001), np.zeros(3))
    plan = schedule(grid, [fixes], [(8.0, 40.0), (45.0, 55.0), (100.0, 130.0)])
    assert list(zip(plan.epoch, plan.observation)) == [(300, 1), (300, 2), (401, 3), (900, 4), (900, 5)]
    np.testing.assert_allclose(plan.measurements[0].time_s, [5.0, 40.0, 40.0, 50.05, 100.0, 100.0])
    moving = schedule(grid, [fixes], [(10.05, 40.0), (45.0, 55.0)])
    assert list(zip(moving.epoch, moving.observation)) == [(100, 2), (401, 3), (950, 4)]
    np.testing.assert_array_equal(moving.measurements[0].time_s, times)
