"""Spatial down-sampling of dense (epoch-rate) track points to a station list (thesis 5.3.2.2).

Coordinates are resampled by a sliding-window fit: for each output station s_k, every point
with |s - s_k| <= window / 2 enters a least-squares polynomial in (s - s_k) (degree 2 by
default), and the fit's value at s_k is the result. The fit averages the noise of the
~100 epochs per window of a walking trolley, and a quadratic follows a curve's arc and a
vertical curve exactly, so only wavelengths shorter than a few windows are smoothed: in a
0.625 m window a 3 m sinusoid is off by 0.06 % of its amplitude, a 2 m one by 0.3 %, a 1 m one
by 5 %. A standing trolley simply
adds many points at one station: they weigh in as the average of that station.

The fit is vectorised over all windows at once: (window, point) pairs are enumerated from
the sorted stations, the centred power sums are accumulated with ``np.bincount`` and the small
normal-equation systems solved together.
"""

from __future__ import annotations

import numpy as np

DEFAULT_WINDOW_M = 0.625


def window_pairs(sorted_station_m: np.ndarray, at_station_m: np.ndarray, half_window_m: float):
    """(window index, point index) of every point within ``half_window_m`` of each output station."""
    start = np.searchsorted(sorted_station_m, at_station_m - half_window_m, side="left")
    stop = np.searchsorted(sorted_station_m, at_station_m + half_window_m, side="right")
    counts = stop - start
    window = np.repeat(np.arange(len(at_station_m)), counts)
    first_pair = np.cumsum(counts) - counts
    point = np.repeat(start - first_pair, counts) + np.arange(counts.sum())
    return window, point, counts


#: Output stations fitted at a time by :func:`sliding_window_fit` (bounds its memory).
FIT_CHUNK_STATIONS = 2000


def _fit_windows(s_sorted: np.ndarray, v_sorted: np.ndarray, at: np.ndarray, half: float, degree: int) -> np.ndarray:
    """The local fits of :func:`sliding_window_fit` at stations ``at`` from the sorted points."""
    window, point, counts = window_pairs(s_sorted, at, half)
    m, n_terms = len(at), degree + 1
    # Scaled, centred abscissa in [-1, 1] keeps the normal equations well conditioned.
    u = (s_sorted[point] - at[window]) / half
    # u**0 and u**1 are u's own 1 and u (what numpy's power gives them, exactly); the higher powers by it
    powers = np.empty((len(u), 2 * degree + 1))
    powers[:, 0] = 1.0
    powers[:, 1] = u
    powers[:, 2:] = u[:, None] ** np.arange(2, 2 * degree + 1)
    moments = np.stack([np.bincount(window, powers[:, p], minlength=m) for p in range(2 * degree + 1)], axis=1)
    normal = moments[:, np.add.outer(np.arange(n_terms), np.arange(n_terms))]
    values = v_sorted[point]
    rhs = np.stack(
        [np.stack([np.bincount(window, powers[:, p] * values[:, c], minlength=m) for p in range(n_terms)], axis=1)
         for c in range(v_sorted.shape[1])],
        axis=2,
    )
    u_min = np.full(m, np.inf)
    u_max = np.full(m, -np.inf)
    np.minimum.at(u_min, window, u)
    np.maximum.at(u_max, window, u)
    ok = (counts >= degree + 2) & (u_min < 0.0) & (u_max > 0.0)
    result = np.full((m, v_sorted.shape[1]), np.nan)
    if ok.any():
        normal_ok = normal[ok]
        well_posed = np.linalg.cond(normal_ok) < 1e12
        solved = np.linalg.solve(normal_ok[well_posed], rhs[ok][well_posed])
        rows = np.flatnonzero(ok)[well_posed]
        result[rows] = solved[:, 0, :]
    return result


def sliding_window_fit(
    station_m: np.ndarray,
    values: np.ndarray,
    at_station_m: np.ndarray,
    window_m: float = DEFAULT_WINDOW_M,
    degree: int = 2,
) -> np.ndarray:
    """Values (n,) or (n, k) at stations ``station_m`` -> the local fits (m,) or (m, k) at ``at_station_m``.

    NaN stations or values are ignored. An output is NaN when its window holds fewer than
    degree + 2 points or its points do not reach both halves of the window (the fit would
    extrapolate).
    """
    if not window_m > 0.0:
        raise ValueError(f"window must be positive, not {window_m!r} m")
    station_m = np.asarray(station_m, dtype=float)
    values = np.asarray(values, dtype=float)
    flat = values.ndim == 1
    values2 = values[:, None] if flat else values
    if values2.shape[0] != station_m.shape[0]:
        raise ValueError(f"{values2.shape[0]} values for {station_m.shape[0]} stations")
    at = np.asarray(at_station_m, dtype=float)
    keep = np.isfinite(station_m) & np.all(np.isfinite(values2), axis=1)
    order = np.argsort(station_m[keep], kind="stable")
    s_sorted = station_m[keep][order]
    v_sorted = values2[keep][order]

    half = 0.5 * window_m
    result = np.full((len(at), values2.shape[1]), np.nan)
    # a bounded number of output stations at a time: the (window, point) pairs of 10 km at 200 Hz
    # would take hundreds of MB; each window's sums are formed exactly as in one pass
    for first in range(0, len(at), FIT_CHUNK_STATIONS):
        part = slice(first, first + FIT_CHUNK_STATIONS)
        result[part] = _fit_windows(s_sorted, v_sorted, at[part], half, degree)
    return result[:, 0] if flat else result


def interpolate_in_station(station_m: np.ndarray, values: np.ndarray, at_station_m: np.ndarray) -> np.ndarray:
    """Linear interpolation of a scalar (gauge, cant) in station; NaN outside the data.

    Where the trolley stood, the readings at one station are averaged first.
    """
    station_m = np.asarray(station_m, dtype=float)
    values = np.asarray(values, dtype=float)
    keep = np.isfinite(station_m) & np.isfinite(values)
    s, v = station_m[keep], values[keep]
    unique, inverse = np.unique(s, return_inverse=True)
    mean = np.bincount(inverse, v) / np.bincount(inverse)
    return np.interp(at_station_m, unique, mean, left=np.nan, right=np.nan)
