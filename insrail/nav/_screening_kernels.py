"""Compiled (numba) moving medians of the IMU screening's below-envelope test
(:func:`insrail.nav.imu_screening._spikes_below_envelope`).

np.median over a (records, 3, 10) window view sorts a copy of every window and was about a tenth
of `insrail fuse`'s CPU time; here each window's ten values are sorted in registers. The values are
exactly np.median's: the mean of the two middle values ((a + b) / 2, as np.mean of two) and NaN where
a window holds a NaN.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True, inline="always")
def _median_sorted(values: np.ndarray, count: int) -> float:
    """The median of ``values[:count]`` (sorted in place), NaN if one of them is NaN."""
    for i in range(count):
        if np.isnan(values[i]):
            return np.nan
    for i in range(1, count):  # insertion sort: ten values
        v = values[i]
        j = i - 1
        while j >= 0 and values[j] > v:
            values[j + 1] = values[j]
            j -= 1
        values[j + 1] = v
    half = count // 2
    if count % 2:
        return values[half]
    return (values[half - 1] + values[half]) / 2.0


@njit(cache=True)
def neighbour_median_and_spread(rates: np.ndarray, neighbours: int) -> tuple[np.ndarray, np.ndarray]:
    """For each record r of ``rates`` (m, 3) with ``neighbours`` records on either side (rows
    ``neighbours`` .. m - neighbours - 1) and each axis: the median of the 2 x ``neighbours``
    records around it (itself left out) and 1.4826 x their median absolute departure from it;
    (m - 2 neighbours, 3) each."""
    m = rates.shape[0] - 2 * neighbours
    count = 2 * neighbours
    reference = np.empty((max(m, 0), 3))
    spread = np.empty((max(m, 0), 3))
    work = np.empty(count)
    for r in range(m):
        for axis in range(3):
            for i in range(neighbours):
                work[i] = rates[r + i, axis]
                work[neighbours + i] = rates[r + neighbours + 1 + i, axis]
            ref = _median_sorted(work, count)
            for i in range(neighbours):
                work[i] = np.abs(rates[r + i, axis] - ref)
                work[neighbours + i] = np.abs(rates[r + neighbours + 1 + i, axis] - ref)
            reference[r, axis] = ref
            spread[r, axis] = 1.4826 * _median_sorted(work, count)
    return reference, spread
