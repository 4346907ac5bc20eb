"""Windowed line-type fitting (thesis 5.3.2.6, eq. 5.24): the best-fit reference of a centreline.

A fused GNSS/INS centreline follows GNSS at long wavelengths: a few millimetres over
hundreds of metres. One fit over kilometres (:func:`insrail.track.linefit.fit_alignment`)
cannot follow them, so its residuals carry them on top of the real deviations. The thesis
therefore fits each stretch in overlapping windows no shorter than the long-wave chord
(300 m; shorter windows would absorb real long-wave irregularities and make the deviations
look better than they are) and blends the two fits in each overlap linearly (eq. 5.24):

    y_k = (1 - dL_k / dL) y_k,1 + (dL_k / dL) y_k,2,

dL the overlap's length and dL_k the distance of point k from the overlap's start.

Each window is refitted with the global fit's element machinery: the window's chain is the
global plan cut to the window (so a window holding part of a clothoid or arc keeps its
element types and the curvature continuity), its profile the global PVIs whose vertical
curves reach into it; the free parameters are the window's start offset and azimuth, its
element lengths, arc curvatures, PVI stations, elevations and vertical radii. Weak priors
tie every parameter to its global value, so one the window's points cannot see (an element
boundary or a PVI just outside it) stays where the global fit put it.

Defaults: 500 m windows overlapping by 150 m. 500 m is well above the 300 m floor, so the
300 m-chord (150 m pair) irregularities survive, while a few-mm GNSS wave of 1-2 km
wavelength is mostly absorbed; 150 m of overlap, half the long-wave chord, spreads the
change from one window's fit to the next over enough sleepers that it adds no step.

Which to use for what: the global :class:`~insrail.track.linefit.AlignmentFit` is the
fitted *alignment* (element table, CSV, LandXML, the design of the next survey); the
:class:`WindowedReference` is the *reference line* for "measured - best" deviations.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from insrail.track.alignment import Arc, HorizontalAlignment, Line
from insrail.track.linefit import (
    _PRIOR_UNIT_M,
    ARC,
    CLOTHOID,
    LINE,
    AlignmentFit,
    LineFitError,
    _Chain,
    _checked_series,
    _foot,
    _profile,
    _solve_chain,
)
from insrail.track.profile import VerticalProfile

DEFAULT_WINDOW_M = 500.0
DEFAULT_OVERLAP_M = 150.0
MIN_WINDOW_M = 300.0
"""Thesis 5.3.2.6: windows shorter than the long-wave chord make the deviations optimistic."""

_MARGIN_M = 5.0
"""A window's chain and profile reach this far beyond its points, so every point has a foot."""

# prior sigmas: far looser than the points determine any parameter they see
_SIGMA_OFFSET_M = 1.0
_SIGMA_AZIMUTH_RAD = 1e-2
_SIGMA_LENGTH_M = 10.0
_SIGMA_CURVATURE = 1e-5
_SIGMA_PVI_STATION_M = 10.0
_SIGMA_ELEVATION_M = 1.0
_SIGMA_VERTICAL_RADIUS = 0.5
"""Relative to the global radius."""


@dataclass(frozen=True)
class WindowFit:
    """One window's fit: its station range, its points and their offsets from its own fit.

    first/last: indices of its first and last point (points sorted by their global feet).
    """

    start_m: float
    end_m: float
    first: int
    last: int
    alignment: HorizontalAlignment
    profile: VerticalProfile
    lateral_m: np.ndarray
    vertical_m: np.ndarray


@dataclass(frozen=True)
class WindowedReference:
    """The blended best-fit reference at every centreline point (arrays in the input's order).

    station_m          station of the point's foot on the global fitted plan
    reference_enh_m    (n, 3) blended best-fit position E, N, H
    azimuth_rad        azimuth of the reference line at the point
    lateral_m          measured - reference across the track [m, + right]
    vertical_m         measured - reference height [m, + up]
    windows            the window fits, in station order
    """

    station_m: np.ndarray
    reference_enh_m: np.ndarray
    azimuth_rad: np.ndarray
    lateral_m: np.ndarray
    vertical_m: np.ndarray
    windows: tuple[WindowFit, ...]


def window_ranges(first_m: float, last_m: float, window_m: float, overlap_m: float) -> np.ndarray:
    """(k, 2) station ranges of windows of at least ``window_m`` covering [first_m, last_m],
    consecutive ones overlapping by exactly ``overlap_m`` (one window when the data are shorter)."""
    if not (overlap_m > 0.0 and window_m >= 2.0 * overlap_m):
        raise LineFitError(
            f"windowed line fitting: the overlap ({overlap_m} m) must be positive and at most half the "
            f"window ({window_m} m), so that only neighbouring windows overlap"
        )
    span = last_m - first_m
    count = max(1, math.floor((span - overlap_m) / (window_m - overlap_m)))
    if count == 1:
        return np.array([[first_m, last_m]])
    length = (span - overlap_m) / count + overlap_m
    starts = first_m + np.arange(count) * (length - overlap_m)
    ranges = np.column_stack([starts, starts + length])
    ranges[-1, 1] = last_m  # exact, whatever the round-off
    return ranges


def blend_weights(station_m: np.ndarray, ranges: np.ndarray) -> np.ndarray:
    """(k, n) weights of the windows at the stations: eq. 5.24's linear ramps in each overlap
    (rising over the overlap with the previous window, falling over the one with the next)."""
    weights = np.zeros((len(ranges), station_m.size))
    for i, (start, end) in enumerate(ranges):
        w = ((station_m >= start) & (station_m <= end)).astype(float)
        if i > 0:
            overlap = ranges[i - 1, 1] - start
            w = np.where(station_m < start + overlap, np.clip((station_m - start) / overlap, 0.0, 1.0), w)
        if i < len(ranges) - 1:
            overlap = end - ranges[i + 1, 0]
            w = np.where(station_m > end - overlap, np.clip((end - station_m) / overlap, 0.0, 1.0), w)
        weights[i] = w
    return weights


# ------------------------------------------------------------------- plan
def _window_chain(plan: HorizontalAlignment, start: float, end: float):
    """The global plan cut to [start, end] as a chain, its parameters and their prior sigmas."""
    kinds, lengths, curvatures = [], [], []
    for placed in plan.placed_elements:
        length = min(placed.end_station_m, end) - max(placed.start_station_m, start)
        if length <= 0.0:
            continue
        element = placed.element
        kinds.append(LINE if isinstance(element, Line) else ARC if isinstance(element, Arc) else CLOTHOID)
        lengths.append(length)
        if isinstance(element, Arc):
            curvatures.append(element.curvature_start)
    east, north = plan.point_at(start)
    chain = _Chain(
        start, end, float(east), float(north), tuple(kinds),
        start_curvature=float(plan.curvature_at(start)) if kinds[0] == CLOTHOID else 0.0,
        end_curvature=float(plan.curvature_at(end)) if kinds[-1] == CLOTHOID else 0.0,
    )
    x0 = np.concatenate(([0.0, float(plan.azimuth_at(start))], lengths[:-1], curvatures))
    sigma = np.concatenate(
        ([_SIGMA_OFFSET_M, _SIGMA_AZIMUTH_RAD], np.full(len(lengths) - 1, _SIGMA_LENGTH_M),
         np.full(len(curvatures), _SIGMA_CURVATURE))
    )
    return chain, x0, sigma


def _window_plan(chain, x0, sigma, station, east, north) -> HorizontalAlignment:
    """The window's refitted plan: all its parameters free; where that solution is no valid
    alignment (an element shrunk to nothing leaving a clothoid without its neighbour's
    curvature), its lengths held at the global fit's; else the global fit's piece itself (valid,
    as a piece of a valid chain is)."""
    lengths_fixed = np.ones(x0.size, dtype=bool)
    lengths_fixed[chain.length_index] = False
    for free in (None, lengths_fixed):
        x = _solve_chain(chain, x0, station, east, north, free=free, prior_sigma=sigma)
        try:
            return chain.alignment(x)
        except ValueError:
            continue
    return chain.alignment(x0)


# ---------------------------------------------------------------- profile
def _window_profile_seed(profile: VerticalProfile, start: float, end: float):
    """The global profile over [start, end]: (first, last station, interior PVI count, x0, prior sigma).

    The interior PVIs are those whose vertical curves reach into the range; the ends lie on
    the grade lines beyond them, so the seed equals the global profile over the range.
    """
    stations, elevations = profile.stations_m, profile.elevations_m
    grades, halves = profile.grades, 0.5 * profile.curve_lengths_m + 1.0
    inner = [
        i for i in range(1, len(stations) - 1)
        if stations[i] + halves[i] >= start and stations[i] - halves[i] <= end
    ]
    if inner:
        first = min(start, stations[inner[0]] - halves[inner[0]])
        last = max(end, stations[inner[-1]] + halves[inner[-1]])
        before, after = inner[0] - 1, inner[-1]
    else:
        first, last = start, end
        before = after = int(np.clip(np.searchsorted(stations, start, side="right") - 1, 0, len(grades) - 1))
    # ends on the grade lines (extrapolated when beyond the global profile's ends)
    z_first = elevations[before] + grades[before] * (first - stations[before])
    z_last = elevations[after] + grades[after] * (last - stations[after])
    radii = profile.curve_radii_m[inner]
    x0 = np.concatenate((stations[inner], [z_first], elevations[inner], [z_last], radii))
    sigma = np.concatenate(
        (np.full(len(inner), _SIGMA_PVI_STATION_M), np.full(len(inner) + 2, _SIGMA_ELEVATION_M),
         _SIGMA_VERTICAL_RADIUS * radii)
    )
    return first, last, len(inner), x0, sigma


def _fit_window_profile(profile: VerticalProfile, start: float, end: float, station, height) -> VerticalProfile:
    first, last, count, x0, sigma = _window_profile_seed(profile, start, end)
    prior_weight = _PRIOR_UNIT_M / sigma

    def residuals(x):
        try:
            heights = _profile(x, first, last, count).elevation_at(station)
        except ValueError:  # PVIs out of order or curves overlapping: push the solver back
            heights = np.full(station.size, 10.0 + height)
        return np.concatenate((height - heights, prior_weight * (x - x0)))

    lower = np.concatenate((np.full(count, first), np.full(count + 2, -np.inf), np.zeros(count)))
    upper = np.concatenate((np.full(count, last), np.full(2 * count + 2, np.inf)))
    # scipy.optimize imported when a line is fitted (a survey on a design never fits one): 0.1 s of CPU beyond
    # the pipeline's own imports
    from scipy.optimize import least_squares

    solution = least_squares(residuals, x0, bounds=(lower, upper), x_scale="jac", method="trf")
    try:
        return _profile(solution.x, first, last, count)
    except ValueError:  # no valid profile found: the global fit's over the window (valid)
        return _profile(x0, first, last, count)


# ------------------------------------------------------------------ windows
def fit_windows(
    fit: AlignmentFit,
    station_m,
    east_m,
    north_m,
    height_m,
    *,
    window_m: float = DEFAULT_WINDOW_M,
    overlap_m: float = DEFAULT_OVERLAP_M,
) -> WindowedReference:
    """Refit ``fit`` (from :func:`~insrail.track.linefit.fit_alignment` on the same points) in
    overlapping windows and blend the fits by eq. 5.24 (see the module docstring).

    ``window_m`` must be at least 300 m (thesis 5.3.2.6); data shorter than one window get one
    window (the global fit refitted, which then equals it).
    """
    if window_m < MIN_WINDOW_M:
        raise LineFitError(
            f"windowed line fitting: windows of {window_m} m would absorb the 300 m-chord irregularities; "
            f"use at least {MIN_WINDOW_M:.0f} m"
        )
    _, east, north, height = _checked_series(
        station_m, east_m, north_m, height_m, names=("east_m", "north_m", "height_m")
    )
    feet = fit.horizontal.station_m
    if feet.size != east.size:
        raise LineFitError(
            f"windowed line fitting: the fit has {feet.size} points but {east.size} were given; pass the "
            "points the fit was made from"
        )
    plan, profile = fit.alignment.horizontal, fit.alignment.vertical
    order = np.argsort(feet, kind="stable")
    sorted_feet = feet[order]
    ranges = window_ranges(plan.start_station_m, plan.end_station_m, window_m, overlap_m)
    weights = blend_weights(sorted_feet, ranges)
    lateral, vertical, azimuth = (np.zeros(feet.size) for _ in range(3))
    windows = []
    for (start, end), weight in zip(ranges, weights):
        first = int(np.searchsorted(sorted_feet, start, side="left"))
        last = int(np.searchsorted(sorted_feet, end, side="right")) - 1
        index = order[first : last + 1]
        chain, x0, sigma = _window_chain(
            plan, max(start - _MARGIN_M, plan.start_station_m), min(end + _MARGIN_M, plan.end_station_m)
        )
        window_plan = _window_plan(chain, x0, sigma, feet[index], east[index], north[index])
        window_feet, offsets = _foot(window_plan, feet[index], east[index], north[index])
        window_profile = _fit_window_profile(profile, start - _MARGIN_M, end + _MARGIN_M, window_feet,
                                             height[index])
        residuals = height[index] - window_profile.elevation_at(window_feet)
        w = weight[first : last + 1]
        lateral[index] += w * offsets
        vertical[index] += w * residuals
        azimuth[index] += w * window_plan.azimuth_at(window_feet)
        windows.append(WindowFit(float(start), float(end), first, last, window_plan, window_profile,
                                 offsets, residuals))
    reference = np.column_stack([
        east - lateral * np.cos(azimuth), north + lateral * np.sin(azimuth), height - vertical
    ])
    return WindowedReference(feet, reference, azimuth, lateral, vertical, tuple(windows))
