"""The filter's building blocks: the gated update, the reset, the RTS step, and the one schedule
that the fusion and the accuracy prediction share."""

import numpy as np
import pytest
from scipy.stats import chi2

from insrail.nav import kalman
from insrail.nav.measurements import GnssPosition, OdometerNhc, Zupt, at_rest, schedule


def test_gated_update_is_the_kalman_update_and_rejects_beyond_the_gate():
    rng = np.random.default_rng(3)
    A = rng.normal(size=(4, 4))
    P = A @ A.T + np.eye(4)
    x = rng.normal(size=4)
    H = rng.normal(size=(2, 4))
    R = np.diag([0.5, 0.2])
    z = H @ x + np.array([0.3, -0.2])
    x1, P1, nu, nis, ok = kalman.gated_update(x, P, z, H, R, gate=chi2.ppf(0.9999, 2))
    S = H @ P @ H.T + R
    K = P @ H.T @ np.linalg.inv(S)
    assert ok
    np.testing.assert_allclose(nu, [0.3, -0.2])
    assert nis == pytest.approx(nu @ np.linalg.inv(S) @ nu)
    np.testing.assert_allclose(x1, x + K @ nu)
    np.testing.assert_allclose(P1, P - K @ H @ P, atol=1e-12)  # Joseph form equals the optimal-gain form
    x2, P2, _, nis2, ok2 = kalman.gated_update(x, P, z + 100.0, H, R, gate=chi2.ppf(0.9999, 2))
    assert not ok2 and nis2 > chi2.ppf(0.9999, 2)
    assert x2 is x and P2 is P
    assert not kalman.gated_update(x, P, np.array([np.nan, 0.0]), H, R, gate=10.0)[4]


def test_inflate_raises_the_chosen_variances_by_adding_noise():
    P = np.array([[4.0, 1.0, 0.5], [1.0, 1.0, 0.2], [0.5, 0.2, 1e-6]])
    out = kalman.inflate(P, np.array([0, 2]), np.array([1.0, 0.1]))
    assert out[0, 0] == 4.0  # already wider than the floor
    assert out[2, 2] == pytest.approx(0.01)
    np.testing.assert_array_equal(out - np.diag(np.diag(out)), P - np.diag(np.diag(P)))
    assert np.all(np.linalg.eigvalsh(out - P) >= 0.0)  # added noise: positive semi-definite
    assert P[2, 2] == 1e-6  # the input is left alone


def test_rts_step_matches_the_smoother_of_a_random_walk():
    # x_{k+1} = x_k + w (q), observed at k = 0, 1 (r): the smoothed variance at 0 is 1/(1/p0+1/r+1/(q+r)).
    q, r, p0 = 0.5, 1.0, 4.0
    p_plus0 = 1.0 / (1.0 / p0 + 1.0 / r)
    p_minus1 = p_plus0 + q
    p_plus1 = 1.0 / (1.0 / p_minus1 + 1.0 / r)
    e, P_s = kalman.rts_step(np.array([0.2]), np.array([[p_plus1]]), np.eye(1), np.array([[p_minus1]]),
                             np.array([[p_plus0]]))
    assert P_s[0, 0] == pytest.approx(1.0 / (1.0 / p0 + 1.0 / r + 1.0 / (q + r)))
    assert e[0] == pytest.approx(0.2 * p_plus0 / p_minus1)


def test_the_smoother_gain_and_step_are_numbas_solve_and_products_to_the_bit():
    # the kernels write out what numba's np.linalg.solve and array expressions did (no slice assignment
    # compiled): the same LAPACK call and the same sums give the same bits
    from numba import njit

    @njit
    def by_arrays(phi_next, p_minus_next, p_plus, e_next, P_s_next):
        A = np.ascontiguousarray(np.linalg.solve(np.ascontiguousarray(p_minus_next.T),
                                                 np.ascontiguousarray((p_plus @ phi_next.T).T)).T)
        return A, A @ e_next, p_plus + A @ np.ascontiguousarray(P_s_next - p_minus_next) @ np.ascontiguousarray(A.T)

    rng = np.random.default_rng(7)
    n = 25
    phi = np.eye(n) + 0.01 * rng.standard_normal((n, n))
    root = rng.standard_normal((n, n))
    p_plus, p_minus, P_s = (m @ m.T + n * np.eye(n) for m in (root, root + 0.1, root - 0.1))
    e_next = rng.standard_normal(n)
    A, e, smoothed = by_arrays(phi, p_minus, p_plus, e_next, P_s)
    gain = kalman.rts_gain(phi, p_minus, p_plus)
    assert gain.flags.c_contiguous
    np.testing.assert_array_equal(gain, A)
    got_e, got_smoothed = kalman.rts_smoothed(gain, e_next, P_s, p_minus, p_plus)
    np.testing.assert_array_equal(got_e, e)
    np.testing.assert_array_equal(got_smoothed, smoothed)


def test_solve_transposed_solves_in_place_and_raises_as_solve():
    a = np.array([[4.0, 1.0], [2.0, 3.0]])
    b = np.array([[1.0, 0.0, 2.0], [0.0, 1.0, 1.0]])
    a_t, b_t = a.T.copy(), b.T.copy()
    kalman.solve_transposed(a_t, b_t)
    np.testing.assert_allclose(b_t.T, np.linalg.solve(a, b), rtol=1e-15)
    with pytest.raises(np.linalg.LinAlgError, match="singular"):
        kalman.solve_transposed(np.ones((2, 2)), b.T.copy())
    with pytest.raises(np.linalg.LinAlgError, match="infs or NaNs"):
        kalman.solve_transposed(a.T.copy(), np.full((1, 2), np.nan))


def test_one_schedule_orders_sources_by_epoch_then_list_order():
    times = np.arange(0.0, 2.01, 0.1)  # update epochs 0..20
    gnss = GnssPosition(np.array([-1.0, 0.0, 0.5, 1.0, 1.05, 9.0]), np.zeros(6), np.zeros(6), np.zeros(6),
                        np.full((6, 3), 0.01), np.zeros(3))
    odometer = OdometerNhc.from_distance(np.array([0.0, 1.55]), np.array([0.0, 1.55]), np.eye(3), np.zeros(3),
                                         np.zeros(3), 0.001, 0.001)
    zupt = Zupt(np.zeros(0))
    plan = schedule(times, [gnss, odometer, zupt], stops=[(0.95, 1.32)])
    entries = lambda j: [(plan.measurements[plan.source[e]].name, int(plan.observation[e])) for e in plan.at(j)]
    # GNSS at or before the first epoch or after the last is not applied; 1.05 s closes at 1.1 s
    assert entries(0) == []
    assert entries(5) == [("gnss_position", 2), ("odometer_nhc", 4)]
    assert entries(10) == [("gnss_position", 3), ("odometer_nhc", 9)]  # 0.9 s is not at rest yet
    assert entries(11) == [("gnss_position", 4), ("odometer_nhc", 10), ("zupt", 11)]
    assert entries(13) == [("odometer_nhc", 12), ("zupt", 13)]
    assert entries(15) == [("odometer_nhc", 14)]  # past the stop
    assert entries(16) == []  # past the odometer's record
    bound = plan.measurements[1]
    assert bound.speed_mps[4] == pytest.approx(1.0) and len(bound.time_s) == len(times) - 1
    assert plan.first[-1] == len(plan.epoch)
    np.testing.assert_array_equal(at_rest([(1.0, 2.0), (3.0, 4.0)], [0.5, 1.0, 2.5, 4.0, 4.1]),
                                  [False, False, False, True, False])
