"""What the filter's error model believes where nothing observes a state (issue 33: a MEMS trolley in a tunnel
held by sparse prism fixes stated its rails' lateral position 2x better than it was)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from insrail.nav.error_model import ATT, BA, POS, ErrorModelNoise, discretise, dynamics_matrix, noise_matrix
from insrail.nav.fusion import FusionOptions, initial_covariance
from insrail.nav.imu_profile import load_imu_profile
from insrail.nav.rotation import euler_to_dcm, skew

LAT, HEIGHT = math.radians(30.5), 30.0
PRISM_LEVER_M = np.array([-0.05, 0.25, -1.48])  # the matrix's calibrated trolley: the prism 1.5 m above the IMU


def _at_rest(profile, c_bn):
    noise = ErrorModelNoise.from_profile(profile)
    f_b = c_bn.T @ np.array([0.0, 0.0, -9.79])
    return dynamics_matrix(LAT, HEIGHT, np.zeros(3), c_bn, f_b, np.zeros(3), noise), noise_matrix(noise)


@pytest.mark.parametrize("grade", ["mems", "tactical", "nav"])
def test_a_bias_nothing_observes_keeps_its_turn_on_part(grade):
    """A bias is a constant from power-up plus an in-run wander: 600 s without a measurement leave its variance
    at turn-on^2 + in-run^2, and over a second it wanders by the in-run part's noise alone. With the in-run
    part's 300 s as the state's correlation time a MEMS unit's 2 mg turn-on bias across the track fell to
    0.3 mg in 600 s, and the roll that balances it with it."""
    profile = load_imu_profile(grade)
    F, gqg = _at_rest(profile, np.eye(3))
    P = np.zeros((len(F), len(F)))
    P[BA + 1, BA + 1] = profile.accel_bias_turn_on**2 + profile.accel_bias_gm_sigma**2
    phi, q = discretise(F, gqg, 0.1)
    for _ in range(6000):
        P = phi @ P @ phi.T + q
    assert P[BA + 1, BA + 1] == pytest.approx(profile.accel_bias_turn_on**2 + profile.accel_bias_gm_sigma**2, rel=0.02)
    assert q[BA + 1, BA + 1] / 0.1 == pytest.approx(
        2.0 * profile.accel_bias_gm_sigma**2 / profile.accel_bias_gm_tau_s, rel=0.01)


def test_a_fix_of_the_point_the_start_came_from_tells_nothing_of_the_attitude():
    """A static start takes the IMU's position from the prism fix less the lever turned by the levelled attitude,
    whose roll holds the accelerometer's 2 mg turn-on bias (2 mrad): applied again, that fix must leave the
    roll where it was. Taken as independent (the start position's own sigma only) the same fix 'measured' the
    roll through the 1.5 m lever arm."""
    profile = load_imu_profile("mems")
    c_bn = euler_to_dcm(0.002, -0.001, math.radians(32.0))
    lever_n = c_bn @ PRISM_LEVER_M
    start = dict(sigma_pos_ned_m=np.full(3, 0.005), sigma_vel_mps=0.005, sigma_level_rad=math.radians(0.01),
                 sigma_heading_rad=0.0017, levelled_at=(LAT, HEIGHT, c_bn))
    H = np.zeros((3, 25))
    H[:, POS : POS + 3] = np.eye(3)
    H[:, ATT : ATT + 3] = skew(lever_n)  # insrail.nav.measurements: a position of the point at the lever
    R = np.eye(3) * 0.001**2

    def roll_sigma_before_and_after(P):
        gain = P @ H.T @ np.linalg.inv(H @ P @ H.T + R)
        after = P - gain @ H @ P
        return math.sqrt(P[ATT, ATT]), math.sqrt(after[ATT, ATT])

    before, after = roll_sigma_before_and_after(initial_covariance(profile, FusionOptions(), **start,
                                                                   position_lever_ned_m=lever_n))
    assert before > 1.9e-3 and after == pytest.approx(before, rel=1e-6)
    before, after = roll_sigma_before_and_after(initial_covariance(profile, FusionOptions(), **start))
    assert after < 0.9 * before  # the start position taken as independent of the attitude
