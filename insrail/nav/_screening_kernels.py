"""Compiled (numba) moving medians of the IMU screening's below-envelope test
(:func:`insrail.nav.imu_screening._spikes_below_envelope`).

np.median over a (records, 3, 10) window view sorts a copy of every window and was about a tenth
of `insrail fuse`'s CPU time. Here the ten neighbours of a record are kept sorted as the record
advances (two values leave, two enter), and their absolute departures from the median are taken in
order outwards from it (the sorted values on either side of the median give them sorted). The values
are np.median's: the mean of the two middle values ((a + b) / 2, as np.mean of two), NaN where a
window holds a NaN (the sign of a median of exactly zero between a -0.0 and a 0.0 aside: numpy's
partition orders such ties its own way).

Scalar tests and magnitudes are math's and the builtin abs, not numpy's ufuncs (the same values): a ufunc
on a scalar, like a slice assignment between arrays, adds to the compiling of a first run.
"""

from __future__ import annotations

import math

import numpy as np

from insrail.jit import cached_njit


@cached_njit(inline="always")
def _insert(window: np.ndarray, size: int, value: float) -> None:
    """``value`` into the sorted ``window[:size]`` (NaN kept as +inf: counted apart by the caller)."""
    v = np.inf if math.isnan(value) else value
    j = size - 1
    while j >= 0 and window[j] > v:
        window[j + 1] = window[j]
        j -= 1
    window[j + 1] = v


@cached_njit(inline="always")
def _remove(window: np.ndarray, size: int, value: float) -> None:
    """One entry equal to ``value`` (bit for bit, so a -0.0 is not taken for a 0.0) out of ``window[:size]``."""
    v = np.inf if math.isnan(value) else value
    negative = np.signbit(v)
    at = size - 1
    for i in range(size):
        if window[i] == v and np.signbit(window[i]) == negative:
            at = i
            break
    for i in range(at, size - 1):
        window[i] = window[i + 1]


@cached_njit(inline="always")
def _middle(window: np.ndarray, count: int) -> float:
    half = count // 2
    if count % 2:
        return window[half]
    return (window[half - 1] + window[half]) / 2.0


@cached_njit(nogil=True)  # nogil: the two quantities' medians are made side by side (screen_imu)
def neighbour_median_and_spread(rates: np.ndarray, neighbours: int) -> tuple[np.ndarray, np.ndarray]:
    """For each record r of ``rates`` (m, 3) with ``neighbours`` records on either side (rows
    ``neighbours`` .. m - neighbours - 1) and each axis: the median of the 2 x ``neighbours``
    records around it (itself left out) and 1.4826 x their median absolute departure from it;
    (m - 2 neighbours, 3) each."""
    m = rates.shape[0] - 2 * neighbours
    count = 2 * neighbours
    reference = np.empty((max(m, 0), 3))
    spread = np.empty((max(m, 0), 3))
    window = np.empty(count + 1)
    departures = np.empty(count)
    for axis in range(3):
        size, nans = 0, 0
        for r in range(m):
            centre = r + neighbours
            if r == 0:
                for i in range(centre - neighbours, centre + neighbours + 1):
                    if i != centre:
                        nans += math.isnan(rates[i, axis])
                        _insert(window, size, rates[i, axis])
                        size += 1
            else:  # the window moves by one: its first record and the new centre leave, the old centre and the next enter
                for leaving in (centre - neighbours - 1, centre):
                    nans -= math.isnan(rates[leaving, axis])
                    _remove(window, size, rates[leaving, axis])
                    size -= 1
                for entering in (centre - 1, centre + neighbours):
                    nans += math.isnan(rates[entering, axis])
                    _insert(window, size, rates[entering, axis])
                    size += 1
            if nans:
                reference[r, axis] = np.nan
                spread[r, axis] = np.nan
                continue
            ref = _middle(window, count)
            # |x - ref| in increasing order: from the middle outwards, the nearer of the two sides first
            lo, hi = count // 2 - 1, count // 2
            for k in range(count):
                if lo < 0:
                    departures[k] = abs(window[hi] - ref)
                    hi += 1
                elif hi >= count:
                    departures[k] = abs(window[lo] - ref)
                    lo -= 1
                else:
                    below, above = abs(window[lo] - ref), abs(window[hi] - ref)
                    if below <= above:
                        departures[k] = below
                        lo -= 1
                    else:
                        departures[k] = above
                        hi += 1
            reference[r, axis] = ref
            spread[r, axis] = 1.4826 * _middle(departures, count)
    return reference, spread


@cached_njit(nogil=True)
def candidate_rows(time_s: np.ndarray, increments: np.ndarray, nominal: float, gap: float, full_range: float,
                   jump: float, lo: int, hi: int) -> np.ndarray:
    """The rows ``lo`` .. ``hi`` - 1 among which the screening's candidates are (``_candidates``): the
    rate of each (its increment over the interval since the row before, ``nominal`` for row 0 and
    after more than ``gap`` s) not finite on an axis, beyond ``full_range``, or a step larger than
    ``jump`` from the row before or to the row after among the finite rates inside the range; row
    indices, increasing. One pass, the same divisions and differences as the whole-array form."""
    found = np.empty(hi - lo, np.int64)
    count = 0
    previous = np.empty(3)  # the clean rates of the row before (NaN: not finite or beyond)
    clean = np.empty(3)
    for axis in range(3):  # not np.full: one more of numpy's functions compiled on a first run
        previous[axis] = np.nan
    for i in range(lo, hi):
        step = time_s[i] - time_s[max(i - 1, 0)]
        interval = nominal if i == 0 or step > gap else step
        bad = False
        for axis in range(3):
            rate = increments[i, axis] / interval
            if not math.isfinite(rate) or abs(rate) > full_range:
                bad = True
                clean[axis] = np.nan
            else:
                clean[axis] = rate
        edge = False
        if i > lo:
            for axis in range(3):
                if abs(clean[axis] - previous[axis]) > jump:
                    edge = True
            if edge:  # the row before is a candidate too (once)
                if count == 0 or found[count - 1] != i - 1:
                    found[count] = i - 1
                    count += 1
        if bad or edge:
            found[count] = i
            count += 1
        for axis in range(3):  # not previous[:] = clean: that compiles numba's message of a shape mismatch
            previous[axis] = clean[axis]
    return found[:count]
