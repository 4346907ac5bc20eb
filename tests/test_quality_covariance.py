"""The covariance-only filter and smoother against the exact covariance of a stacked linear system."""

import numpy as np
import pytest

from insrail.quality import covariance
from insrail.quality.covariance import analyse

N = 9  # enough states for the position (0-2) and attitude (6-8) blocks the analysis reads


def _system(seed: int, m: int):
    """A random time-varying linear system, 0, 1 or 2 measurements per epoch."""
    rng = np.random.default_rng(seed)
    segments = [None]
    for j in range(1, m):
        phi = np.eye(N) + 0.15 * rng.standard_normal((N, N))
        g = 0.1 * rng.standard_normal((N, N))
        q = g @ g.T + 1e-4 * np.eye(N)
        updates = []
        for _ in range(rng.integers(0, 3)):
            rows = int(rng.integers(1, 4))
            H = rng.standard_normal((rows, N))
            r = 0.3 * rng.standard_normal((rows, rows))
            updates.append((H, r @ r.T + 0.05 * np.eye(rows)))
        segments.append((phi, q, updates))
    a = rng.standard_normal((N, N))
    return a @ a.T / N + 0.1 * np.eye(N), segments


def _exact(P0, segments, m):
    """Error covariances of the forward (E[x_j | y_1..j]) and smoothed (E[x_j | all y])
    estimates, from the joint Gaussian of all states and measurements."""
    sources = [P0] + [s[1] for s in segments[1:]] + [R for s in segments[1:] for _, R in s[2]]
    sizes = [c.shape[0] for c in sources]
    total = sum(sizes)
    cov_s = np.zeros((total, total))
    offsets = np.cumsum([0] + sizes)
    for c, o in zip(sources, offsets):
        cov_s[o : o + len(c), o : o + len(c)] = c
    tx = np.zeros((m * N, total))
    tx[:N, :N] = np.eye(N)
    ty_rows, y_epoch = [], []
    v = m  # index of the next measurement-noise source
    for j in range(1, m):
        phi, _, updates = segments[j]
        tx[j * N : (j + 1) * N] = phi @ tx[(j - 1) * N : j * N]
        tx[j * N : (j + 1) * N, offsets[j] : offsets[j] + N] += np.eye(N)
        for H, _ in updates:
            rows = H @ tx[j * N : (j + 1) * N]
            rows[:, offsets[v] : offsets[v + 1]] += np.eye(H.shape[0])
            ty_rows.append(rows)
            y_epoch += [j] * H.shape[0]
            v += 1
    ty = np.vstack(ty_rows)
    y_epoch = np.array(y_epoch)
    sxx, sxy, syy = tx @ cov_s @ tx.T, tx @ cov_s @ ty.T, ty @ cov_s @ ty.T
    gains = np.zeros((m * N, len(ty)))  # forward estimator: x_j|j = L_j y (data up to j)
    for j in range(m):
        seen = np.flatnonzero(y_epoch <= j)
        if seen.size:
            gains[j * N : (j + 1) * N, seen] = np.linalg.solve(syy[np.ix_(seen, seen)], sxy[j * N : (j + 1) * N, seen].T).T
    forward = sxx - sxy @ gains.T - gains @ sxy.T + gains @ syy @ gains.T
    smoothed = sxx - sxy @ np.linalg.solve(syy, sxy.T)
    return forward, smoothed


def _lag_sigma(cov, j, k, state, sign=1.0):
    a, b = j * N + state, k * N + state
    return np.sqrt(cov[a, a] + cov[b, b] - 2.0 * cov[a, b])


@pytest.mark.parametrize("seed", [1, 2, 3])
@pytest.mark.parametrize("checkpoint", [1, 5, 32, 1000])  # the smoother's columns through the gains' product
def test_lag_differences_equal_the_stacked_exact_covariance(seed, checkpoint, monkeypatch):
    monkeypatch.setattr(covariance, "CHECKPOINT_EPOCHS", checkpoint)
    m = 40
    P0, segments = _system(seed, m)
    station = np.arange(m, dtype=float) * 0.5
    # a stop: epochs 10-14 at the same station, so pairs span different numbers of epochs
    station[10:15] = station[10]
    station[15:] -= 2.0
    station = np.maximum.accumulate(station)
    heading = np.zeros(m)  # lateral = state 1 (east), vertical = -state 2
    result = analyse(P0, lambda j: segments[j], np.arange(m, dtype=float), station, heading,
                     anchors=np.arange(m), lags_m=[1.5, 6.0])
    forward, smoothed = _exact(P0, segments, m)
    for exact, computed in ((forward, result.forward), (smoothed, result.smoothed)):
        np.testing.assert_allclose(computed.sigma_lateral_m, np.sqrt(np.diag(exact)[1::N]), rtol=1e-7)
        np.testing.assert_allclose(computed.sigma_vertical_m, np.sqrt(np.diag(exact)[2::N]), rtol=1e-7)
        np.testing.assert_allclose(computed.sigma_roll_rad, np.sqrt(np.diag(exact)[6::N]), rtol=1e-7)
        for lag in (1.5, 6.0):
            item = computed.lag(lag)
            assert len(item.first_epoch) > 10
            assert np.all(station[item.second_epoch] - station[item.first_epoch] >= lag - 1e-9)
            want_lat = [_lag_sigma(exact, j, k, 1) for j, k in zip(item.first_epoch, item.second_epoch)]
            want_ver = [_lag_sigma(exact, j, k, 2) for j, k in zip(item.first_epoch, item.second_epoch)]
            np.testing.assert_allclose(item.sigma_lateral_m, want_lat, rtol=1e-6)
            np.testing.assert_allclose(item.sigma_vertical_m, want_ver, rtol=1e-6)
    # the smoother is never worse than the filter, and the cross term matters
    assert np.all(result.smoothed.sigma_lateral_m <= result.forward.sigma_lateral_m + 1e-12)
    short = result.forward.lag(1.5)
    naive = np.hypot(result.forward.sigma_lateral_m[short.first_epoch], result.forward.sigma_lateral_m[short.second_epoch])
    assert np.max(np.abs(naive / short.sigma_lateral_m - 1.0)) > 0.05


def test_forward_only_leaves_the_smoother_out():
    P0, segments = _system(4, 12)
    result = analyse(P0, lambda j: segments[j], np.arange(12.0), np.arange(12.0), np.zeros(12),
                     anchors=np.arange(12), lags_m=[2.0], smoother=False)
    assert result.smoothed is None
    assert len(result.forward.lag(2.0).sigma_lateral_m) == 10
