"""Compiled (numba) projection of points on a horizontal alignment: the Newton iteration of
:meth:`insrail.track.alignment.HorizontalAlignment.station_offset`, point by point.

Each point's iteration starts from the alignment's sample (every metre or so) nearest to it. A
survey's points come in order along the track, 200 per second: the nearest sample of a point
within :data:`WARM_START_M` of the one before it is found by walking from that one's nearest
sample downhill in distance (a step or none), not by a search of the whole index; any other
point (the first, one after a gap or a jump) is handed back to the caller, which finds its
nearest sample on the index (a k-d tree). The start, and so every Newton step, is the one the
index gives, and nothing per point is allocated: projecting the 2 million epochs of 10 km of
rails needs no memory beyond the results.

The alignment is passed as its knot table (``_Knots``: station, east, north, unwrapped
azimuth, curvature and curvature rate at each knot) and the Gauss-Legendre nodes and
weights; the state at a station is the one :meth:`HorizontalAlignment._state` computes with
``advance_along_curve`` (the same formulae, evaluated per point; equal to round-off, tested).
"""

from __future__ import annotations

import math

import numpy as np

from insrail.jit import cached_njit

#: nogil: no Python object is touched, so the threads making the next parts' rails run on meanwhile
#: (insrail.track.streamed)
compiled = cached_njit(nogil=True, error_model="numpy")

#: a point this close [m] to the one projected before it starts from that one's station
WARM_START_M = 1.0


@compiled
def _last_not_above(ascending, value):
    """np.searchsorted(ascending, value, side="right") - 1, written out (a NaN value, as numpy's, after every
    knot): numba's searchsorted compiles for seconds on a first run, and its module (numba.np.arraymath, with
    scipy.linalg) would be imported when the cached kernel is loaded (insrail.jit)."""
    low, high = 0, ascending.shape[0]
    while low < high:
        middle = (low + high) // 2
        if not value < ascending[middle]:
            low = middle + 1
        else:
            high = middle
    return low - 1


@compiled
def knot_state(k_station, k_east, k_north, k_azimuth, k_curvature, k_rate, gl_fractions, gl_weights, s):
    """(east, north, unwrapped azimuth, curvature) at station ``s`` (the end elements extrapolated)."""
    i = _last_not_above(k_station, s)
    i = min(max(i, 0), k_station.shape[0] - 1)
    d = s - k_station[i]
    azimuth, curvature, rate = k_azimuth[i], k_curvature[i], k_rate[i]
    if rate == 0.0:  # the exact chord
        half_turn = 0.5 * curvature * d
        chord = d * (math.sin(half_turn) / half_turn if half_turn != 0.0 else 1.0)
        direction = azimuth + half_turn
        d_east, d_north = chord * math.sin(direction), chord * math.cos(direction)
    else:  # Gauss-Legendre quadrature of (sin, cos) of the azimuth
        sum_sin = 0.0
        sum_cos = 0.0
        for g in range(gl_fractions.shape[0]):
            along = d * gl_fractions[g]
            heading = azimuth + curvature * along + 0.5 * rate * along * along
            sum_sin += math.sin(heading) * gl_weights[g]
            sum_cos += math.cos(heading) * gl_weights[g]
        d_east, d_north = d * sum_sin, d * sum_cos
    return (k_east[i] + d_east, k_north[i] + d_north, azimuth + curvature * d + 0.5 * rate * d * d,
            curvature + rate * d)


@compiled
def _distance2(sample_east, sample_north, j, pe, pn):
    return (sample_east[j] - pe) ** 2 + (sample_north[j] - pn) ** 2


@compiled
def project_points(k_station, k_east, k_north, k_azimuth, k_curvature, k_rate, gl_fractions, gl_weights,
                   sample_station, sample_east, sample_north, east, north, first, cold_sample, max_step, low, high,
                   max_iterations, tolerance, station, offset, previous):
    """Project points ``first``, ``first + 1``, ... into ``station`` and ``offset`` (left NaN for
    a point without a foot on the alignment). Point ``first`` starts from sample ``cold_sample``
    when that is >= 0; the others from the nearest sample found from the previous point's
    (``previous`` = [its nearest sample, east, north, 1 when set], carried from call to call).
    Returns -1 when done, else the index of the first point that needs a cold start."""
    last = sample_station.shape[0] - 1
    for i in range(first, east.shape[0]):
        pe, pn = east[i], north[i]
        if not (math.isfinite(pe) and math.isfinite(pn)):
            continue
        if i == first and cold_sample >= 0:
            j = cold_sample
        elif previous[3] == 1.0 and math.hypot(pe - previous[1], pn - previous[2]) < WARM_START_M:
            j = int(previous[0])
            while j < last and _distance2(sample_east, sample_north, j + 1, pe, pn) < _distance2(
                    sample_east, sample_north, j, pe, pn):
                j += 1
            while j > 0 and _distance2(sample_east, sample_north, j - 1, pe, pn) < _distance2(
                    sample_east, sample_north, j, pe, pn):
                j -= 1
        else:
            return i
        previous[0], previous[1], previous[2], previous[3] = j, pe, pn, 1.0
        s = sample_station[j]
        converged = False
        for _ in range(max_iterations):
            ce, cn, az, k = knot_state(k_station, k_east, k_north, k_azimuth, k_curvature, k_rate,
                                       gl_fractions, gl_weights, s)
            de, dn = pe - ce, pn - cn
            along = de * math.sin(az) + dn * math.cos(az)
            across = de * math.cos(az) - dn * math.sin(az)
            # d(along)/ds = -(1 - k * across): Newton on the tangential component
            step = along / (1.0 - k * across)
            if step > max_step:
                step = max_step
            elif step < -max_step:
                step = -max_step
            s += step
            if abs(step) < tolerance:
                converged = True
                break
        if not converged:
            continue  # no foot nearby: NaN
        ce, cn, az, k = knot_state(k_station, k_east, k_north, k_azimuth, k_curvature, k_rate,
                                   gl_fractions, gl_weights, s)
        across = (pe - ce) * math.cos(az) - (pn - cn) * math.sin(az)
        if low <= s <= high and 1.0 - k * across > 0.0:
            station[i] = s
            offset[i] = across
    return -1
