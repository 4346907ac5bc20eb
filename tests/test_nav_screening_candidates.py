"""The compiled candidate search of the IMU screening against the whole-array numpy form it replaced."""

import numpy as np
import pytest

from insrail.io.types import GAP_FACTOR
from insrail.nav.imu_screening import _candidates, _intervals


def numpy_candidates(time_s, increments, nominal, full_range, jump, first, stop):
    """The reference: rates, their range and the steps between neighbours on whole arrays."""
    n = len(time_s)
    stop = min(stop, n)
    lo, hi = max(first - 1, 0), min(stop + 1, n)
    with np.errstate(invalid="ignore", over="ignore"):
        values = increments[lo:hi] / _intervals(time_s, np.arange(lo, hi), nominal)[:, None]
        finite = np.isfinite(values)
        beyond = finite & (np.abs(values) > full_range)
        clean = np.where(finite & ~beyond, values, np.nan)
        edge = (np.abs(np.diff(clean, axis=0)) > jump).any(axis=1)
    candidate = (~finite.all(axis=1) | beyond.any(axis=1) | np.concatenate([edge, [False]])
                 | np.concatenate([[False], edge]))
    found = np.flatnonzero(candidate) + lo
    return found[(found >= first) & (found < stop)]


@pytest.mark.parametrize("seed", range(4))
def test_candidates_are_the_numpy_forms(seed):
    rng = np.random.default_rng(seed)
    n, nominal = 5000, 0.005
    time_s = np.cumsum(np.full(n, nominal) + rng.normal(0, 1e-5, n))
    time_s[rng.integers(1, n, 5)] += GAP_FACTOR * nominal * 3  # dropouts: the nominal interval there
    time_s = np.sort(time_s)
    increments = rng.normal(0, 1.0, (n, 3)) * nominal
    rows = rng.integers(0, n, 60)
    increments[rows[:15], rng.integers(0, 3, 15)] = np.nan
    increments[rows[15:25], rng.integers(0, 3, 10)] = np.inf
    increments[rows[25:], rng.integers(0, 3, 35)] *= rng.choice([8.0, 40.0], 35)
    for first, stop in ((0, n), (0, 1000), (1000, 2000), (4990, 6000), (2500, 2501)):
        np.testing.assert_array_equal(_candidates(time_s, increments, nominal, 5.0, 3.0, first, stop),
                                      numpy_candidates(time_s, increments, nominal, 5.0, 3.0, first, stop))
