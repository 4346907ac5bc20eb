"""Line-type fitting: recover a design alignment from a measured centreline (thesis 5.3.2.3-6).

Plan. The heading of the centreline is constant on straights, linear in station on
circular arcs and a parabola in station on clothoids, so its derivative, the
curvature, is a trapezoid per curve. The pipeline:

1. heading from chords of +-``chord_half_m`` (interpolated, so uneven spacing is fine; not from
   a chord ending in a gap in the data, interpolated across it);
   curvature = heading change over ``curvature_window_m``, which averages out the
   short-wave irregularities (3-70 m) the fit must not chase;
2. segmentation: every run of |curvature| above 1/``max_radius_m`` is one curve group
   (a sign change starts a new group: reverse curves). Inside a group the flat stretches of
   the curvature are its arcs (two or more: a compound curve); the 10 %/50 %/90 % crossings
   of each ramp between neighbouring levels (0 on the straights) give the clothoids'
   midpoints and lengths; straights lie between groups;
3. total least squares on the orthogonal distances of all points to the element
   chain (:class:`HorizontalAlignment`), with unknowns the start point's offset
   across the initial tangent, the start azimuth, every element length but the last
   and the arcs' curvatures. The chain is built from curvature, so tangent and
   curvature continuity hold by construction (the digest's recommendation rather than
   the thesis's per-element fits and its eq. 5.7, which minimises sum d^4). Elements the
   solution leaves degenerate are removed and the rest refitted until none is
   (:func:`_simplified`): clothoids the data cannot tell from none, straights under 1 m
   between two curves, a curve collapsed to a lone clothoid (merged into the straight), so an
   arc may meet a straight or another arc directly and two clothoids may meet at an
   inflection (S-curve), and the result always passes the alignment's validator. Data that
   begin or end inside a curve begin or end with the piece of a clothoid, its curvature at
   the data's edge fitted (removed when it is an arc's).

Profile. Grade lines meet at PVIs carrying circular vertical curves. A PVI shows up
as a jump between the grades of least-squares lines fitted over ``window_m`` before
and after a station; the peaks of |jump| above ``min_grade_change`` seed the PVIs,
then least squares on the heights refines PVI stations, elevations and radii.

The fit is global (one chain for the whole run): that is the exportable alignment (element
table, CSV, LandXML, usable as the design of the next survey). Deviations "measured - best"
come from :mod:`insrail.track.linefit_windows`, which refits it in overlapping windows
(thesis eq. 5.24) so that the GNSS-level long waves of a fused centreline stay out of them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from insrail.track.alignment import (
    Arc,
    Clothoid,
    DesignAlignment,
    HorizontalAlignment,
    Line,
)
from insrail.track.profile import PVI, CantTable, VerticalProfile

_END_MARGIN_M = 5.0
"""The fitted chain reaches this far beyond the data, so every point has a perpendicular foot."""

_NEWTON_STEPS_COLD = 8
_NEWTON_STEPS_WARM = 2
"""Newton steps to the perpendicular feet from the input stations, and from the previous solution's feet."""
_PRIOR_UNIT_M = 1e-3
"""Residual [m] a parameter's weak prior is worth at one prior sigma (see :func:`_solve_chain`)."""
_MIN_ELEMENT_M = 1e-3
"""Elements the fit shrinks below this length are dropped (e.g. a curve without transitions)."""

_GAP_CHORD_FRACTION, _GAP_SPACING_FACTOR = 0.5, 4.0
"""A gap in the data: points farther apart than both this fraction of the heading chord's half
and this many times their median spacing. A chord end interpolated across half a chord's half
(5 m) is off an R 300 m curve by 10 mm, 0.5 mrad of the chord's heading: noise to the curvature
window's averaging. Data sparser than that (a point every few metres) have a gap only where their
points lie four times farther apart than usual."""

_MIN_CURVE_RUN_M = 20.0
_MIN_FLAT_M = 10
"""Shortest flat stretch [m, grid steps of 1 m] of the smoothed curvature that seeds an arc."""
_MIN_INTERIOR_LINE_M = 1.0
"""A straight between two curves shorter than this is not supported by 10 m chords: it is removed
and the curves meet directly (a reverse curve through an inflection point)."""


_MIN_PROFILE_M = 40.0
"""Shortest profile fitted: two 20 m grade windows."""


class LineFitError(ValueError):
    """The centreline cannot be fitted: bad input, or too short to hold its elements."""


# ---------------------------------------------------------------------------- input
def _checked_series(station_m, *values, names) -> tuple[np.ndarray, ...]:
    arrays = [np.asarray(v, dtype=float) for v in (station_m, *values)]
    for name, array in zip(("station_m", *names), arrays):
        if array.ndim != 1:
            raise LineFitError(f"line fitting: {name} must be a 1-D array, got shape {array.shape}")
        if array.shape != arrays[0].shape:
            raise LineFitError(
                f"line fitting: {name} has {array.size} values but station_m has {arrays[0].size}"
            )
        bad = np.flatnonzero(~np.isfinite(array))
        if bad.size:
            raise LineFitError(f"line fitting: {name}[{bad[0]}] is {array[bad[0]]!r}; every value must be finite")
    steps = np.diff(arrays[0])
    if np.any(steps <= 0.0):
        index = int(np.flatnonzero(steps <= 0.0)[0]) + 1
        raise LineFitError(
            f"line fitting: station_m[{index}] = {arrays[0][index]:.4f} m does not increase on "
            f"station_m[{index - 1}] = {arrays[0][index - 1]:.4f} m"
        )
    return tuple(arrays)


# ----------------------------------------------------------------- segmentation
def _heading(station, east, north, chord_half_m):
    """Unwrapped azimuth [rad] of the chord centred on each station (stations near the ends dropped).

    Stations whose chord ends inside a gap in the data (between points farther apart than
    :func:`_gap_m`) are dropped too: the end interpolated across the gap lies on the gap's chord,
    off a curve by its sagitta (31 cm for 50 m at R 1000 m), and the curvature diagram would show
    arcs that are not there. Between the kept headings the diagram interpolates linearly, which on
    an arc is exact.
    """
    inner = (station >= station[0] + chord_half_m) & (station <= station[-1] - chord_half_m)
    s = station[inner]
    gap_m = _gap_m(station, chord_half_m)
    s = s[_known(station, s - chord_half_m, gap_m) & _known(station, s + chord_half_m, gap_m)]
    if s.size < 2:
        raise LineFitError(f"line fitting: no two chords of {2 * chord_half_m:.0f} m have both ends on the data, "
                           f"points more than {gap_m:.1f} m apart being a gap")
    d_east = np.interp(s + chord_half_m, station, east) - np.interp(s - chord_half_m, station, east)
    d_north = np.interp(s + chord_half_m, station, north) - np.interp(s - chord_half_m, station, north)
    return s, np.unwrap(np.arctan2(d_east, d_north))


def _gap_m(station, chord_half_m) -> float:
    """Spacing [m] of neighbouring points above which they have a gap between them (_GAP_CHORD_FRACTION)."""
    return max(_GAP_CHORD_FRACTION * chord_half_m, _GAP_SPACING_FACTOR * float(np.median(np.diff(station))))


def _known(samples, at, gap_m) -> np.ndarray:
    """Whether each station ``at`` lies between neighbouring ``samples`` at most ``gap_m`` apart
    (outside a gap, where interpolating them holds)."""
    spacing = np.diff(samples)
    return spacing[np.clip(np.searchsorted(samples, at) - 1, 0, spacing.size - 1)] <= gap_m


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) index pairs of the True runs of ``mask``."""
    edges = np.diff(np.concatenate(([0], mask.astype(np.int8), [0])))
    return list(zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1))


def _crossing(s, u, level, entry: bool) -> float:
    """Station where the ramp ``u`` (0 -> 1 along ``s``) crosses ``level``, interpolated.

    An entry ramp rises into the flat at the end of ``s``: its crossing nearest that end is
    taken; an exit ramp leaves the flat at the start: the crossing nearest the start. Noise
    or a neighbouring curve farther away cannot then move it.
    """
    if entry:
        below = np.flatnonzero(u < level)
        if below.size == 0:
            return float(s[0])
        i = below[-1]
        if i == len(s) - 1:
            return float(s[-1])
        return float(np.interp(level, [u[i], u[i + 1]], [s[i], s[i + 1]]))
    above = np.flatnonzero(u >= level)
    if above.size == 0:
        return float(s[-1])
    i = above[0]
    if i == 0:
        return float(s[0])
    return float(np.interp(level, [u[i - 1], u[i]], [s[i - 1], s[i]]))


def _ramp(s, curvature, k_from, k_to, window_m, entry: bool) -> tuple[float, float]:
    """Midpoint and length of the ramp of the smoothed curvature from ``k_from`` to ``k_to``."""
    u = (curvature - k_from) / (k_to - k_from)
    spread = abs(_crossing(s, u, 0.9, entry) - _crossing(s, u, 0.1, entry)) / 0.8
    # a boxcar of width w stretches a ramp of length L to about L + w/2 between 10 and 90 %
    return _crossing(s, u, 0.5, entry), max(spread - 0.5 * window_m, 10.0)


@dataclass(frozen=True)
class _CurveSeed:
    """One curve group as found on the curvature diagram.

    kinds: its elements between the straights around it: clothoid, then (arc, clothoid) per
    arc; a group cut by the data's start (end) begins (ends) with the piece of a clothoid the
    data hold, ``start_curvature`` (``end_curvature``) the seed of its curvature at the data's
    edge, None when the group is whole there; boundaries_m: the stations of its joints, the
    straights' joints included (TS ... ST; a group cut by the start has no TS, one cut by the
    end no ST); curvatures: signed curvature of each of its arcs [1/m].
    """

    kinds: tuple[str, ...]
    boundaries_m: tuple[float, ...]
    curvatures: tuple[float, ...]
    start_curvature: float | None = None
    end_curvature: float | None = None


def _plateaus(g, magnitude, known, window_m) -> list[tuple[int, int, float]]:
    """(first, last, level) of the flat stretches of one curve's smoothed curvature magnitude.

    Flat: the magnitude changes by less than 10 % of its peak over ``window_m`` (a clothoid
    changes it by its whole step over its length, arcs not at all), judged only where it and the
    samples a window away are ``known`` (measured, not interpolated across a gap in the data:
    interpolated, a clothoid's curvature looks flat). Neighbouring flats within 5 % of each other
    are one arc interrupted by noise or a gap. A curve without a flat stretch (an arc shorter than
    the smoothing) gets one plateau at its peak.
    """
    half = round(0.5 * window_m)
    peak = float(magnitude.max())
    change = np.full(magnitude.size, np.inf)
    change[half:-half] = np.abs(magnitude[2 * half :] - magnitude[: -2 * half])
    measured = known.copy()
    measured[half:-half] &= known[2 * half :] & known[: -2 * half]
    flats = []
    for first, last in _runs((change < 0.1 * peak) & (magnitude > 0.25 * peak) & measured):
        if last - first < _MIN_FLAT_M:
            continue
        level = float(np.median(magnitude[first : last + 1]))
        if flats and abs(level - flats[-1][2]) < 0.05 * max(level, flats[-1][2]):
            first = flats.pop()[0]
            level = float(np.median(magnitude[first : last + 1]))
        flats.append((first, last, level))
    if not flats:
        top = np.flatnonzero(magnitude >= 0.8 * peak)
        flats = [(int(top[0]), int(top[-1]), float(np.median(magnitude[top])))]
    return flats


_CLOSED = (math.nan, None)
"""How :func:`_open_ramp` describes a curve group's end inside the data."""


def _open_ramp(g, magnitude, level, flat_index, edge, data_edge, start: bool):
    """How a curve group cut by the data's start (end) begins (ends): (station of the straight's
    joint, None) when its ramp, extrapolated, reaches zero inside the data (a whole clothoid);
    else (None, seed of the curvature at the data's edge): the data start (end) on its
    transition or its arc, fitted as the piece of a clothoid whose curvature there is free (a
    piece that turns out to be an arc's is then removed by :func:`_simplified`)."""
    at_edge = magnitude[edge]
    slope = max(level - at_edge, 0.0) / max(abs(g[flat_index] - g[edge]), 1.0)
    if slope > 0.0:
        zero = g[edge] - at_edge / slope if start else g[edge] + at_edge / slope
        if (zero > data_edge + 1.0) if start else (zero < data_edge - 1.0):
            return zero, None
    return None, min(max(at_edge - slope * abs(g[edge] - data_edge), 0.05 * level), 0.95 * level)


def _seed_curves(station, east, north, chord_half_m, window_m, max_radius_m) -> list[_CurveSeed]:
    s, heading = _heading(station, east, north, chord_half_m)
    grid = np.arange(s[0] + 0.5 * window_m, s[-1] - 0.5 * window_m, 1.0)
    if grid.size < 2:
        return []
    curvature = (np.interp(grid + 0.5 * window_m, s, heading) - np.interp(grid - 0.5 * window_m, s, heading)) / window_m
    gap_m = _gap_m(station, chord_half_m)
    known = _known(s, grid - 0.5 * window_m, gap_m) & _known(s, grid + 0.5 * window_m, gap_m)
    seeds = []
    reach = int(window_m)
    for first, last in _runs(np.abs(curvature) > 1.0 / max_radius_m):
        if grid[last] - grid[first] < _MIN_CURVE_RUN_M:
            continue
        sign = float(np.sign(np.median(curvature[first : last + 1])))
        # widen the run to where the curvature leaves zero, so the 10 % crossings are inside it
        lo, hi = max(first - reach, 0), min(last + reach, grid.size - 1)
        g, magnitude = grid[lo : hi + 1], sign * curvature[lo : hi + 1]
        flats = _plateaus(g, np.where((g >= grid[first]) & (g <= grid[last]), magnitude, 0.0), known[lo : hi + 1],
                          window_m)
        levels = [0.0] + [level for _, _, level in flats] + [0.0]
        arcs = [sign * level for level in levels[1:-1]]
        # a group the data cut: how it begins and ends (module docstring)
        head = _open_ramp(g, magnitude, levels[1], flats[0][0], 0, station[0], True) if first == 0 else _CLOSED
        tail = (_open_ramp(g, magnitude, levels[-2], flats[-1][1], -1, station[-1], False)
                if last == grid.size - 1 else _CLOSED)
        kinds = [CLOTHOID]
        for i in range(len(flats)):
            kinds += [ARC] if i == len(flats) - 1 else [ARC, CLOTHOID]
        kinds += [CLOTHOID]
        # ramp i runs from the end of flat i - 1 (or the widened start) to the start of flat i
        starts = [0] + [f_last for _, f_last, _ in flats]
        stops = [f_first for f_first, _, _ in flats] + [g.size - 1]
        boundaries = []
        for i, (a, b) in enumerate(zip(starts, stops)):
            edge = head if i == 0 else tail if i == len(flats) else _CLOSED
            if edge[1] is not None:  # on this clothoid: it begins (ends) with the chain
                boundaries += [g[b]] if i == 0 else [g[a]]
                continue
            if not math.isnan(edge[0]):  # the ramp extrapolated to zero inside the data
                boundaries += [edge[0], g[b]] if i == 0 else [g[a], edge[0]]
                continue
            entry = levels[i + 1] > levels[i]
            mid, length = _ramp(g[a : b + 1], magnitude[a : b + 1], levels[i], levels[i + 1], window_m, entry)
            boundaries += [mid - 0.5 * length, mid + 0.5 * length]
        # boundaries: TS, SC, (CS, SC)*, CS, ST -- pairs are the clothoids' ends
        if np.any(np.diff(boundaries) < 1.0):
            continue
        seeds.append(_CurveSeed(tuple(kinds), tuple(boundaries), tuple(arcs),
                                None if head[1] is None else sign * head[1], None if tail[1] is None else sign * tail[1]))
    return seeds


# --------------------------------------------------------------- chain model
LINE, ARC, CLOTHOID = "line", "arc", "clothoid"


def _element(kind: str, length: float, k_start: float, k_end: float):
    """A Line, Arc or Clothoid of ``length`` from the signed curvatures at its ends [1/m]."""
    if kind == LINE:
        return Line(length)
    if kind == ARC:
        if k_start == 0.0:
            raise ValueError("an arc of zero curvature")
        return Arc(length, 1.0 / abs(k_start), "right" if k_start > 0 else "left")
    if k_start * k_end < 0.0:
        raise ValueError("a clothoid cannot change the side it turns to")
    turn = "right" if k_start + k_end > 0 else "left"
    radius_start = math.inf if k_start == 0.0 else 1.0 / abs(k_start)
    radius_end = math.inf if k_end == 0.0 else 1.0 / abs(k_end)
    return Clothoid(length, radius_start, radius_end, turn)


@dataclass(frozen=True)
class _Chain:
    """A pattern of element kinds from ``start_station`` to ``end_station`` and its parameter vector.

    x = [start offset across the initial tangent, start azimuth, lengths of every element but
    the last, arc curvatures, then the start (end) curvature when ``free_start_curvature``
    (``free_end_curvature``)]; the last length closes the chain at ``end_station``. Lines have
    curvature 0, arcs their own; a clothoid runs from its predecessor's curvature to its
    successor's, so tangent and curvature continuity hold by construction. Two clothoids meet at
    curvature 0 (an inflection, through a zero-length line); a clothoid cut by the chain's start
    (end) starts (ends) at ``start_curvature`` (``end_curvature``), or at a fitted one when it
    is free (data beginning or ending on a transition curve).
    """

    start_station: float
    end_station: float
    reference_east: float
    reference_north: float
    kinds: tuple[str, ...]
    start_curvature: float = 0.0
    end_curvature: float = 0.0
    free_start_curvature: bool = False
    free_end_curvature: bool = False

    @property
    def element_count(self) -> int:
        return len(self.kinds)

    @property
    def length_index(self) -> np.ndarray:
        """Indices in x of the free element lengths (all but the last element's)."""
        return 2 + np.arange(self.element_count - 1)

    @property
    def arc_elements(self) -> np.ndarray:
        return np.array([i for i, kind in enumerate(self.kinds) if kind == ARC], dtype=int)

    def lengths(self, x: np.ndarray) -> np.ndarray:
        lengths = np.append(x[self.length_index], 0.0)
        lengths[-1] = self.end_station - self.start_station - lengths[:-1].sum()
        return lengths

    @property
    def edge_index(self) -> int:
        """Index in x of the first free edge curvature (after the arcs' curvatures)."""
        return 2 + self.element_count - 1 + self.arc_elements.size

    def edge_curvatures(self, x: np.ndarray) -> tuple[float, float]:
        """Curvature at the chain's start and end where a clothoid is cut there."""
        start = x[self.edge_index] if self.free_start_curvature else self.start_curvature
        end = x[self.edge_index + self.free_start_curvature] if self.free_end_curvature else self.end_curvature
        return float(start), float(end)

    def curvatures(self, x: np.ndarray) -> np.ndarray:
        """Signed curvature at the start and end of every element, shape (m, 2)."""
        level = np.zeros(self.element_count)
        level[self.arc_elements] = x[2 + self.element_count - 1 : self.edge_index]
        ends = np.column_stack([level, level])
        first, last = self.edge_curvatures(x)
        for i, kind in enumerate(self.kinds):
            if kind != CLOTHOID:
                continue
            if i == 0:
                ends[i, 0] = first
            elif self.kinds[i - 1] == ARC:
                ends[i, 0] = level[i - 1]
            if i == self.element_count - 1:
                ends[i, 1] = last
            elif self.kinds[i + 1] == ARC:
                ends[i, 1] = level[i + 1]
        return ends

    def alignment(self, x: np.ndarray) -> HorizontalAlignment:
        lengths = self.lengths(x)
        if lengths[-1] < _MIN_ELEMENT_M:
            raise LineFitError("line fitting: the fitted elements are longer than the data")
        offset, azimuth = x[0], x[1]
        return HorizontalAlignment(
            start_east_m=self.reference_east + offset * math.cos(azimuth),
            start_north_m=self.reference_north - offset * math.sin(azimuth),
            start_azimuth_rad=float(azimuth),
            start_station_m=self.start_station,
            elements=self.elements(x, 0, self.element_count - 1),
        )

    def elements(self, x: np.ndarray, first: int, last: int) -> tuple:
        """Elements ``first`` to ``last`` (those of at least _MIN_ELEMENT_M)."""
        lengths, ends = self.lengths(x), self.curvatures(x)
        return tuple(
            _element(self.kinds[i], float(lengths[i]), float(ends[i, 0]), float(ends[i, 1]))
            for i in range(first, last + 1)
            if lengths[i] >= _MIN_ELEMENT_M
        )

    def affected_elements(self, parameter: int) -> tuple[int, int]:
        """First and last element whose shape parameter ``parameter`` (a length or an arc
        curvature) changes; the elements after them only move rigidly."""
        count = self.element_count
        if parameter < 2 + count - 1:
            return parameter - 2, parameter - 2
        if parameter >= self.edge_index:  # an edge curvature: the clothoid at that edge
            edge = 0 if self.free_start_curvature and parameter == self.edge_index else count - 1
            return edge, edge
        arc = int(self.arc_elements[parameter - (2 + count - 1)])
        return max(arc - 1, 0), min(arc + 1, count - 1)


def _foot(alignment: HorizontalAlignment, stations, east, north, steps=_NEWTON_STEPS_COLD):
    """Feet stations and perpendicular offsets [m] of the points, ``steps`` Newton steps from ``stations``.

    A fixed step count keeps the residual a smooth function of the parameters.
    """
    low, high = alignment.start_station_m, alignment.end_station_m
    s = np.clip(stations, low, high)
    for _ in range(steps):
        ce, cn = alignment.point_at(s)
        az = alignment.azimuth_at(s)
        k = alignment.curvature_at(s)
        de, dn = east - ce, north - cn
        along = de * np.sin(az) + dn * np.cos(az)
        across = de * np.cos(az) - dn * np.sin(az)
        s = np.clip(s + along / (1.0 - k * across), low, high)
    ce, cn = alignment.point_at(s)
    az = alignment.azimuth_at(s)
    return s, (east - ce) * np.cos(az) - (north - cn) * np.sin(az)


@dataclass(frozen=True)
class HorizontalFit:
    """Fitted plan: the alignment, the points' stations on it and their offsets [m, + right]."""

    alignment: HorizontalAlignment
    station_m: np.ndarray
    offset_m: np.ndarray

    @property
    def rms_m(self) -> float:
        return float(np.sqrt(np.mean(self.offset_m**2)))


_JACOBIAN_STEP = {"length": 1e-4, "curvature": 1e-9}
"""Finite-difference steps [m, 1/m] for the shape parameters' Jacobian columns."""


def _chain_jacobian(chain: _Chain, x: np.ndarray, free: np.ndarray, feet_seed, east, north) -> np.ndarray:
    """d(offsets)/d(x[free]), semi-analytically.

    Offset and azimuth move the whole chain rigidly, so their columns are exact:
    d(offset) = -n . d(foot point), n the unit normal to the right. A length or an arc
    curvature reshapes only its own elements (and an arc's clothoids); everything after them
    moves rigidly with the pose at their end. So the column is a finite difference over the
    reshaped elements' points alone (a short alignment from the pose at their start) and the
    rigid motion for the points after them: a few metres of geometry instead of the whole chain.
    """
    alignment = chain.alignment(x)
    feet = _foot(alignment, feet_seed, east, north, _NEWTON_STEPS_WARM)[0]
    foot_east, foot_north = alignment.point_at(feet)
    azimuth = alignment.azimuth_at(feet)
    normal_east, normal_north = np.cos(azimuth), -np.sin(azimuth)

    def column(shift_east, shift_north):
        return -(normal_east * shift_east + normal_north * shift_north)

    def rotation(pivot_east, pivot_north):
        # moving azimuth clockwise by 1 rad moves a point (dE, dN) from the pivot by (dN, -dE)
        return foot_north - pivot_north, -(foot_east - pivot_east)

    bounds = chain.start_station + np.concatenate(([0.0], np.cumsum(chain.lengths(x))))
    columns = []
    for parameter in np.flatnonzero(free):
        if parameter == 0:
            columns.append(column(math.cos(x[1]), -math.sin(x[1])))
            continue
        if parameter == 1:
            east_turn, north_turn = rotation(alignment.start_east_m, alignment.start_north_m)
            # the start point itself sits x[0] across the initial tangent from the reference point
            columns.append(column(east_turn - x[0] * math.sin(x[1]), north_turn - x[0] * math.cos(x[1])))
            continue
        first, last = chain.affected_elements(parameter)
        is_length = parameter < 2 + chain.element_count - 1
        step = _JACOBIAN_STEP["length" if is_length else "curvature"]
        begin, end = bounds[first], bounds[last + 1]
        moved = x.copy()
        moved[parameter] += step
        reshaped = chain.elements(moved, first, last)
        if not reshaped:
            step = -step
            moved[parameter] = x[parameter] + step
            reshaped = chain.elements(moved, first, last)
        start_east, start_north = alignment.point_at(begin)
        local = HorizontalAlignment(float(start_east), float(start_north), float(alignment.azimuth_at(begin)), begin,
                                    reshaped)
        # pose at the end of the reshaped stretch, before and after
        end_east, end_north = alignment.point_at(end)
        new_east, new_north = local.point_at(local.end_station_m)
        turn = (float(local.azimuth_at(local.end_station_m)) - float(alignment.azimuth_at(end))) / step
        derivative = np.zeros(feet.size)
        inside = (feet >= begin) & (feet <= end)
        if inside.any():
            feet_inside = np.clip(feet[inside], local.start_station_m, local.end_station_m)
            before = _foot(alignment, feet[inside], east[inside], north[inside], _NEWTON_STEPS_WARM)[1]
            after = _foot(local, feet_inside, east[inside], north[inside], _NEWTON_STEPS_WARM)[1]
            derivative[inside] = (after - before) / step
        beyond = feet > end
        east_turn, north_turn = rotation(end_east, end_north)
        shift = column((new_east - end_east) / step + turn * east_turn, (new_north - end_north) / step + turn * north_turn)
        derivative[beyond] = shift[beyond]
        columns.append(derivative)
    return np.column_stack(columns)


def _solve_chain(chain: _Chain, x_start, station, east, north, free=None, prior_sigma=None, max_evaluations=None):
    """Total least squares of the points' perpendicular offsets to the chain over the ``free`` parameters.

    ``prior_sigma`` (one per parameter) adds weak pseudo-observations x = x_start, each worth
    one 1 mm residual at that sigma: it holds parameters the points cannot see (an element just
    outside a window) where they were, and does not move the ones they determine.
    ``max_evaluations`` caps the solver's residual evaluations (None: scipy's default).
    """
    free = np.ones(x_start.size, dtype=bool) if free is None else free
    lower = np.full(x_start.size, -np.inf)
    lower[chain.length_index] = 0.0
    # the feet move little while the solver refines the seed, so each evaluation starts from these
    start_feet = _foot(chain.alignment(x_start), station, east, north)[0]
    prior_weight = None if prior_sigma is None else _PRIOR_UNIT_M / prior_sigma[free]

    def full(x_free):
        x = x_start.copy()
        x[free] = x_free
        return x

    def residuals(x_free):
        try:
            offsets = _foot(chain.alignment(full(x_free)), start_feet, east, north, _NEWTON_STEPS_WARM)[1]
        except ValueError:  # lengths beyond the data, a clothoid turning both ways: push the solver back
            offsets = np.full(station.size, 10.0)
        if prior_weight is None:
            return offsets
        return np.concatenate((offsets, prior_weight * (x_free - x_start[free])))

    def jacobian(x_free):
        try:
            matrix = _chain_jacobian(chain, full(x_free), free, start_feet, east, north)
        except ValueError:  # outside the valid region the residuals are constant
            matrix = np.zeros((station.size, int(free.sum())))
        if prior_weight is None:
            return matrix
        return np.vstack((matrix, np.diag(prior_weight)))

    # scipy.optimize imported when a line is fitted (a survey on a design never fits one): 0.1 s of CPU beyond
    # the pipeline's own imports
    from scipy.optimize import least_squares

    solution = least_squares(residuals, x_start[free], jac=jacobian, bounds=(lower[free], np.inf), x_scale="jac",
                             max_nfev=max_evaluations)
    return full(solution.x)


def _simplified(chain: _Chain, x: np.ndarray, min_transition_shift_m: float, max_radius_m: float,
                edge_reach_m: tuple[float, float] = (math.inf, math.inf)):
    """The chain without the elements its solution ``x`` leaves degenerate, and the matching x
    (None when there are none), so that the refitted chain is an alignment a designer would lay
    and the validator accepts (every clothoid continuing its neighbours' curvature):

    * an arc flatter than ``max_radius_m`` is a straight, and so is a clothoid piece the chain's
      end cuts (its curvature there fitted) that is that flat there or reaches farther into the
      data than ``edge_reach_m`` (start, end: a probe's, where the curvature diagram saw no curve);
    * a line or clothoid shorter than _MIN_ELEMENT_M, an interior clothoid whose shift
      L^2 |k2 - k1| / 24 is below ``min_transition_shift_m`` (the data cannot tell it from none;
      also one the chain's end cuts, with its curvature there fitted) and an interior straight
      under _MIN_INTERIOR_LINE_M between two curves go; so does an arc shorter than
      _MIN_ELEMENT_M unless clothoids meet on both its sides (a spiral-spiral curve), and one
      shorter than the shortest arc the curvature diagram seeds (_MIN_FLAT_M) meeting another
      arc directly, or between two clothoids through which the curvature keeps growing
      (shrinking): a step of a compound curve's transition, not an element (the two clothoids
      join into one);
    * a clothoid then left without an arc to take its curvature from (a lone spiral after a
      collapsed curve: a jump in curvature, e.g. R 15 km -> inf right after a line) goes too, so
      its curve is merged into the straight; one between arcs turning opposite ways splits at
      an inflection; neighbouring straights join.

    A removed element's length goes half to each kept neighbour, so the other joints keep their
    stations for the refit. Before all that, a clothoid piece the chain's end cuts that is that flat
    there but leads into an arc is the whole transition after a straight (:func:`_with_straight_end`).
    """
    straightened = _with_straight_end(chain, x, max_radius_m)
    if straightened is not None:
        return straightened
    lengths, ends = chain.lengths(x), chain.curvatures(x)
    count = chain.element_count
    edge_start, edge_end = chain.edge_curvatures(x)
    items = [[kind, float(length), float(k)] for kind, length, k in zip(chain.kinds, lengths, ends[:, 0])]
    changed = False
    for item in items:
        if item[0] == ARC and abs(item[2]) < 1.0 / max_radius_m:
            item[0], item[2], changed = LINE, 0.0, True
    interior = (np.arange(count) > 0) & (np.arange(count) < count - 1)
    # a clothoid cut by the chain's end with its curvature there fitted is judged like an interior one
    judged = interior.copy()
    judged[0] |= chain.free_start_curvature
    judged[-1] |= chain.free_end_curvature
    shift = lengths**2 * np.abs(ends[:, 1] - ends[:, 0]) / 24.0
    flat_edge = np.zeros(count, dtype=bool)
    flat_edge[0] |= chain.free_start_curvature and (abs(edge_start) < 1.0 / max_radius_m or lengths[0] > edge_reach_m[0])
    flat_edge[-1] |= chain.free_end_curvature and (abs(edge_end) < 1.0 / max_radius_m or lengths[-1] > edge_reach_m[1])
    gone = [
        (kind != ARC and lengths[i] < _MIN_ELEMENT_M)
        or (kind == CLOTHOID and flat_edge[i])
        or (judged[i] and kind == CLOTHOID and shift[i] < min_transition_shift_m)
        or (interior[i] and kind == LINE and lengths[i] < _MIN_INTERIOR_LINE_M)
        for i, kind in enumerate(item[0] for item in items)
    ]
    items, dropped = _without(items, gone)
    changed |= dropped
    gone = [
        kind == ARC and (
            (length < _MIN_ELEMENT_M
             and not (0 < i < len(items) - 1 and items[i - 1][0] == CLOTHOID and items[i + 1][0] == CLOTHOID))
            or (length < _MIN_FLAT_M and ARC in [items[j][0] for j in (i - 1, i + 1) if 0 <= j < len(items)])
        )
        for i, (kind, length, _) in enumerate(items)
    ]
    items, dropped = _without(items, gone)
    changed |= dropped

    def start_of(i):  # a clothoid's curvature at its start (end), by the chain's rule
        return edge_start if i == 0 else items[i - 1][2] if items[i - 1][0] == ARC else 0.0

    def end_of(i):
        return edge_end if i == len(items) - 1 else items[i + 1][2] if items[i + 1][0] == ARC else 0.0

    while True:
        edited = False
        for i in range(1, len(items) - 1):
            kind, length, k = items[i]
            if kind != ARC or length >= _MIN_FLAT_M or items[i - 1][0] != CLOTHOID or items[i + 1][0] != CLOTHOID:
                continue
            before, after = abs(start_of(i - 1)), abs(end_of(i + 1))
            if before < abs(k) < after or before > abs(k) > after:  # a step inside one transition
                items[i - 1 : i + 2] = [[CLOTHOID, items[i - 1][1] + length + items[i + 1][1], 0.0]]
                edited = True
                break
        for i, (kind, length, _) in enumerate(items):
            if edited or kind != CLOTHOID:
                continue
            k_start, k_end = start_of(i), end_of(i)
            if k_start * k_end < 0.0:  # an inflection between them
                items[i : i + 1] = [[CLOTHOID, 0.5 * length, 0.0], [CLOTHOID, 0.5 * length, 0.0]]
                edited = True
                break
            if abs(k_end - k_start) <= 1e-12 + 1e-6 * max(abs(k_start), abs(k_end)):
                items, edited = _without(items, [j == i for j in range(len(items))])
                break
        for i in range(len(items) - 1):
            if items[i][0] == LINE and items[i + 1][0] == LINE:
                items[i : i + 2] = [[LINE, items[i][1] + items[i + 1][1], 0.0]]
                edited = True
                break
        if not edited:
            break
        changed = True
    if not changed:
        return None
    kinds = tuple(kind for kind, _, _ in items)
    new_lengths = [length for _, length, _ in items]
    curvatures = [k for kind, _, k in items if kind == ARC]
    # a clothoid still cut by the chain's start (end) keeps its fitted curvature there
    free_start = chain.free_start_curvature and kinds[0] == CLOTHOID
    free_end = chain.free_end_curvature and kinds[-1] == CLOTHOID
    edges = [edge_start] * free_start + [edge_end] * free_end
    return (replace(chain, kinds=kinds, free_start_curvature=free_start, free_end_curvature=free_end),
            np.concatenate((x[:2], new_lengths[:-1], curvatures, edges)))


def _with_straight_end(chain: _Chain, x: np.ndarray, max_radius_m: float):
    """The chain with a clothoid piece cut by its start (end), its curvature at the data's edge
    fitted flatter than ``max_radius_m`` and an arc after (before) it, split into a straight and
    the whole clothoid, and the matching x; None when there is none.

    The data then begin (end) a few metres before (after) the transition: closer than the curvature
    diagram's blind end, so the seed took them for a run beginning inside it. A piece held to begin
    at curvature 0 cannot bend like the straight and the clothoid after it (it stretches over both),
    and removed like a probe's, it would leave the curve's arc running to the data's edge. The
    straight is seeded over the end margin (the transition beginning at the data's edge); the refit
    moves it.
    """
    edge_start, edge_end = chain.edge_curvatures(x)
    start = (chain.free_start_curvature and abs(edge_start) < 1.0 / max_radius_m and chain.element_count > 1
             and chain.kinds[1] == ARC)
    end = (chain.free_end_curvature and abs(edge_end) < 1.0 / max_radius_m and chain.element_count > 1
           and chain.kinds[-2] == ARC)
    if not (start or end):
        return None
    kinds, lengths = list(chain.kinds), list(chain.lengths(x))
    if start:
        kinds.insert(0, LINE)
        lengths[0:1] = [_END_MARGIN_M, max(lengths[0] - _END_MARGIN_M, 1.0)]
    if end:
        kinds.append(LINE)
        lengths[-1:] = [max(lengths[-1] - _END_MARGIN_M, 1.0), _END_MARGIN_M]
    free_start, free_end = chain.free_start_curvature and not start, chain.free_end_curvature and not end
    edges = [edge_start] * free_start + [edge_end] * free_end
    return (replace(chain, kinds=tuple(kinds), free_start_curvature=free_start, free_end_curvature=free_end),
            np.concatenate((x[:2], lengths[:-1], x[2 + chain.element_count - 1 : chain.edge_index], edges)))


def _without(items: list, gone: list) -> tuple[list, bool]:
    """``items`` without those marked ``gone``, each one's length given half to each kept neighbour
    (all to the one there is at an end); and whether any went."""
    if not any(gone):
        return items, False
    if all(gone):  # nothing to keep: one straight over the whole chain
        return [[LINE, sum(item[1] for item in items), 0.0]], True
    kept = [list(item) for item, out in zip(items, gone) if not out]
    position = np.cumsum([not out for out in gone]) - 1  # index in kept of the last kept item at or before each
    for i, (item, out) in enumerate(zip(items, gone)):
        if not out:
            continue
        before = int(position[i]) if position[i] >= 0 else None
        after = int(position[i]) + 1 if int(position[i]) + 1 < len(kept) else None
        if before is None or after is None:
            kept[before if after is None else after][1] += item[1]
        else:
            kept[before][1] += 0.5 * item[1]
            kept[after][1] += 0.5 * item[1]
    return kept, True


_PROBE_OFFSET_M = 1e-3
"""Mean offset [m] of the points within the curvature diagram's reach of a straight end of the data
above which a transition beginning there is tried (:func:`_with_edge_probes`)."""


def _with_edge_probes(chain: _Chain, x: np.ndarray, station, east, north, reach_m: float):
    """The chain with a clothoid piece, its curvature at the data's edge free, over the last
    ``reach_m`` of each straight end along which the points lean to one side (the curvature
    diagram, a window wide, does not see that far: a curve beginning there), its x and which
    ends (start, end) got one; None when no end does. :func:`_simplified` removes a piece the
    data do not support."""
    offsets = _foot(chain.alignment(x), station, east, north)[1]
    lengths = chain.lengths(x)
    at_start = station <= station[0] + reach_m
    at_end = station >= station[-1] - reach_m
    piece = reach_m + _END_MARGIN_M
    probe_start = bool(chain.kinds[0] == LINE and lengths[0] > 2.0 * piece
                   and abs(np.mean(offsets[at_start])) > _PROBE_OFFSET_M)
    probe_end = bool(chain.kinds[-1] == LINE and lengths[-1] > 2.0 * piece
                 and abs(np.mean(offsets[at_end])) > _PROBE_OFFSET_M)
    if not (probe_start or probe_end):
        return None
    # seed curvature: of the sign of the points' lean (offsets and curvature both + to the right),
    # of the size that leaves a few times their mean offset over the reach
    kinds, lengths = list(chain.kinds), list(lengths)
    arcs = list(x[2 + chain.element_count - 1 : chain.edge_index])
    edges = list(chain.edge_curvatures(x))
    if probe_start:
        kinds.insert(0, CLOTHOID)
        lengths[0:1] = [piece, lengths[0] - piece]
        edges[0] = 24.0 * float(np.mean(offsets[at_start])) / reach_m**2
    if probe_end:
        kinds.append(CLOTHOID)
        lengths[-1:] = [lengths[-1] - piece, piece]
        edges[1] = 24.0 * float(np.mean(offsets[at_end])) / reach_m**2
    free_start = chain.free_start_curvature or probe_start
    free_end = chain.free_end_curvature or probe_end
    x_edges = [edges[0]] * free_start + [edges[1]] * free_end
    return (replace(chain, kinds=tuple(kinds), free_start_curvature=free_start, free_end_curvature=free_end),
            np.concatenate((x[:2], lengths[:-1], arcs, x_edges)), (probe_start, probe_end))


_PROBE_EVALUATIONS = 8
"""Solver evaluations an edge probe gets (:func:`_solve_edge_probes`): a curve the data need
shows in a few; one they do not need only slides its piece along a long wave (and costs a
full alignment per evaluation). A probe kept is refitted with the whole chain."""


def _solve_edge_probes(chain: _Chain, x: np.ndarray, sides, station, east, north, window_m) -> np.ndarray:
    """``x`` with the edge probes' parameters solved over the points within ``window_m`` (start,
    end) of the data's edges only, the rest of the chain held: whether the data need a probe
    shows there, and a full solve of a long chain per probe would cost many times the fit."""
    count = chain.element_count
    edge_end = chain.edge_index + chain.free_start_curvature
    for side, window, params in (
        (sides[0], window_m[0], [0, 1, 2, chain.edge_index]),  # start: the chain's anchor, the piece's length
        (sides[1], window_m[1], [2 + count - 2, edge_end]),  # end: the straight before the piece
    ):
        if not side:
            continue
        near = station <= station[0] + window if params[0] == 0 else station >= station[-1] - window
        free = np.zeros(x.size, dtype=bool)
        free[params] = True
        x = _solve_chain(chain, x, station[near], east[near], north[near], free=free,
                         max_evaluations=_PROBE_EVALUATIONS)
    return x


_MAX_PLAN_RMS_M = 0.02
"""Plan residual RMS [m] above which a fit does not follow its data: a track's lateral
irregularities, a trolley's noise and a GNSS long wave leave a few mm (the benchmark's 5 mm long
wave about 3 mm); tens of mm mean a seed that led the solver to a wrong chain (e.g. a curve laid
elsewhere), and deviations against it would be wrong numbers."""


_MAX_SIMPLIFICATIONS = 10
"""Rounds of :func:`_simplified` and refit; each removes at least one element, so few are ever needed."""


def fit_horizontal(
    station_m,
    east_m,
    north_m,
    *,
    chord_half_m: float = 10.0,
    curvature_window_m: float = 50.0,
    max_radius_m: float = 50_000.0,
    min_transition_shift_m: float = 1e-3,
) -> HorizontalFit:
    """Fit lines, clothoids and arcs to a centreline given at increasing stations [m].

    Curves flatter than ``max_radius_m`` count as straight. Each curve group is fitted as
    clothoid, then (arc, clothoid) per arc (a group the data's start or end cuts begins or
    ends with the piece of a clothoid the data hold, its curvature at the data's edge fitted:
    removed when it is an arc's); elements the solution
    leaves degenerate are removed and the rest refitted (:func:`_simplified`), e.g. a clothoid
    whose shift L^2 |1/R2 - 1/R1| / 24 stays below ``min_transition_shift_m`` (the arc then
    meets the line, PC/PT, or the next arc directly). The result always passes the
    alignment's own validator (curvature continuous at every clothoid).
    """
    station, east, north = _checked_series(station_m, east_m, north_m, names=("east_m", "north_m"))
    if station[-1] - station[0] < 2 * chord_half_m + curvature_window_m:
        raise LineFitError(
            f"line fitting: the centreline from {station[0]:.1f} to {station[-1]:.1f} m spans "
            f"{station[-1] - station[0]:.1f} m; at least {2 * chord_half_m + curvature_window_m:.1f} m are needed"
        )
    try:  # any refusal while the chain is solved names the stretch (a chain solved past its data: an element cut
        # to nothing)
        seeds = _seed_curves(station, east, north, chord_half_m, curvature_window_m, max_radius_m)
        start, end = station[0] - _END_MARGIN_M, station[-1] + _END_MARGIN_M
        _, heading = _heading(station, east, north, chord_half_m)
        azimuth0 = float(heading[0])
        reference_east = east[0] - _END_MARGIN_M * math.sin(azimuth0)
        reference_north = north[0] - _END_MARGIN_M * math.cos(azimuth0)
        # data beginning (ending) on a curve: its curvature at the chain's start (end) is fitted
        open_start = bool(seeds) and seeds[0].start_curvature is not None
        open_end = bool(seeds) and seeds[-1].end_curvature is not None
        kinds = [] if open_start else [LINE]
        for seed in seeds:
            kinds += list(seed.kinds) + ([] if seed.end_curvature is not None else [LINE])
        edges = ([seeds[0].start_curvature] if open_start else []) + ([seeds[-1].end_curvature] if open_end else [])
        chain = _Chain(start, end, reference_east, reference_north, tuple(kinds), free_start_curvature=open_start,
                       free_end_curvature=open_end)
        boundaries = [start] + [b for seed in seeds for b in seed.boundaries_m] + [end]
        lengths = np.maximum(np.diff(boundaries), 1.0)
        x0 = np.concatenate(([0.0, azimuth0], lengths[:-1], [k for seed in seeds for k in seed.curvatures], edges))
        x = _solve_chain(chain, x0, station, east, north)
        reach = chord_half_m + 0.5 * curvature_window_m
        probed_reach = (math.inf, math.inf)
        for probe in (False, True):
            if probe:  # a curve beginning where the curvature diagram does not reach: try a transition there
                probed = _with_edge_probes(chain, x, station, east, north, reach)
                if probed is None:
                    break
                probe_chain, probe_x, sides = probed
                # a probe reaching far beyond the diagram's blind end is no curve it missed
                probed_reach = tuple(2.0 * (reach + _END_MARGIN_M) if side else math.inf for side in sides)
                probe_x = _solve_edge_probes(probe_chain, probe_x, sides, station, east, north, probed_reach)
                kept = _simplified(probe_chain, probe_x, min_transition_shift_m, max_radius_m, probed_reach)
                if kept is not None and kept[0].kinds == chain.kinds:
                    break  # the data do not need the probes: the solution without them stands as it was
                chain, x = probe_chain, _solve_chain(probe_chain, probe_x, station, east, north)
            for _ in range(_MAX_SIMPLIFICATIONS):
                simpler = _simplified(chain, x, min_transition_shift_m, max_radius_m, probed_reach)
                if simpler is None:
                    break
                chain, x = simpler
                x = _solve_chain(chain, x, station, east, north)
        with_margins = chain.alignment(x)
    except ValueError as error:  # the validator's refusal (DesignError) or an element it cannot form
        reason = str(error).removeprefix("line fitting: ")
        raise LineFitError(
            f"line fitting: no valid alignment between {station[0]:.1f} and {station[-1]:.1f} m ({reason})"
        ) from None
    feet = _foot(with_margins, station, east, north)[0]
    # cut where the outermost points' perpendiculars fall, so the plan spans exactly the data
    alignment = _cut(with_margins, float(feet.min()), float(feet.max()))
    feet, offsets = _foot(alignment, feet, east, north)
    rms = float(np.sqrt(np.mean(offsets**2)))
    if rms > _MAX_PLAN_RMS_M:
        raise LineFitError(
            f"line fitting: the fitted plan between {station[0]:.1f} and {station[-1]:.1f} m does not follow "
            f"the centreline (residual RMS {1e3 * rms:.0f} mm, at most {1e3 * _MAX_PLAN_RMS_M:.0f} mm expected)"
        )
    _check_local_follow(station, offsets)
    return HorizontalFit(alignment, feet, offsets)


_FOLLOW_WINDOW_M = 35.0
"""Length [m] of the stretches whose residuals are checked against the fit's noise: the curvature
diagram's blind end (chord half + half its window), where a wrong end piece can hide."""
_FOLLOW_STEP_M = 5.0
"""Spacing [m] of the windows' starts along the data."""
_MIN_WINDOW_POINTS = 10
"""Fewer points in a window (a gap in the data) say too little about its residuals."""
_LOCAL_MEDIAN_FACTOR, _LOCAL_MEDIAN_FLOOR_M = 3.0, 1e-3
"""A window's median absolute residual may reach max(floor, factor x noise): noise alone gives
0.67 x noise, a plan leaving its data over most of a window (a clothoid laid where an arc runs)
exceeds it; the median ignores a lateral defect of a few sleepers, which the deviations must show,
and a track's lateral irregularities raise the noise estimate itself."""
_END_MAX_FACTOR, _END_MAX_FLOOR_M = 8.0, 3e-3
"""At the data's two end windows, no point may lie farther than max(floor, factor x noise) from the
plan: 8 sigma never happens by noise, and a wrong end piece bends away fastest at the data's edge,
where the curvature diagram cannot see it. (A real defect there of more than the bound is refused
too: loud rather than a wrong plan.)"""


def _check_local_follow(station: np.ndarray, offsets: np.ndarray) -> None:
    """Refuse (LineFitError) a plan valid and close on the whole but leaving its data locally.

    The noise is a robust scale of all residuals (1.4826 x MAD), so a short misfit does not hide
    itself in it; windows of ``_FOLLOW_WINDOW_M`` along the data are compared with it by their
    median absolute residual, the two end windows also by their largest residual."""
    noise = 1.4826 * float(np.median(np.abs(offsets - np.median(offsets))))
    median_bound = max(_LOCAL_MEDIAN_FLOOR_M, _LOCAL_MEDIAN_FACTOR * noise)
    max_bound = max(_END_MAX_FLOOR_M, _END_MAX_FACTOR * noise)
    starts = np.append(np.arange(station[0], station[-1] - _FOLLOW_WINDOW_M, _FOLLOW_STEP_M),
                       station[-1] - _FOLLOW_WINDOW_M)
    first = np.searchsorted(station, starts, side="left")
    last = np.searchsorted(station, starts + _FOLLOW_WINDOW_M, side="right")
    for index, (begin, end) in enumerate(zip(first, last)):
        if end - begin < _MIN_WINDOW_POINTS:
            continue
        window = np.abs(offsets[begin:end])
        at_end = index in (0, len(first) - 1)
        if np.median(window) > median_bound or (at_end and window.max() > max_bound):
            raise LineFitError(
                f"line fitting: the fitted plan between {station[0]:.1f} and {station[-1]:.1f} m does not follow "
                f"the centreline between {station[begin]:.1f} and {station[end - 1]:.1f} m: max residual "
                f"{1e3 * window.max():.1f} mm (median {1e3 * np.median(window):.1f} mm) against a noise of "
                f"{1e3 * noise:.1f} mm"
            )


def _cut(alignment: HorizontalAlignment, first: float, last: float) -> HorizontalAlignment:
    """The alignment from station ``first`` to ``last``: the elements wholly outside go, the end
    ones are shortened (a clothoid keeps its curvature where it is cut); joints stay valid, as a
    piece of a valid chain is."""
    pieces = []
    for placed in alignment.placed_elements:
        begin, finish = max(placed.start_station_m, first), min(placed.end_station_m, last)
        if finish - begin < _MIN_ELEMENT_M:
            continue
        element = placed.element
        if isinstance(element, Line):
            pieces.append(Line(finish - begin))
        elif isinstance(element, Arc):
            pieces.append(Arc(finish - begin, element.radius_m, element.turn))
        else:
            rate = (element.curvature_end - element.curvature_start) / element.length_m
            k_begin = element.curvature_start + rate * (begin - placed.start_station_m)
            k_finish = (element.curvature_end if finish == placed.end_station_m
                        else element.curvature_start + rate * (finish - placed.start_station_m))
            pieces.append(_element(CLOTHOID, finish - begin, k_begin, k_finish))
    if not pieces:
        return alignment
    east, north = alignment.point_at(first)
    return HorizontalAlignment(
        start_east_m=float(east),
        start_north_m=float(north),
        start_azimuth_rad=float(alignment.azimuth_at(first)),
        start_station_m=float(first),
        elements=tuple(pieces),
    )


# -------------------------------------------------------------------- profile
def _window_slopes(station, height, centres, window_m, before: bool) -> np.ndarray:
    """Slopes of least-squares lines through the points in [c - w, c] (or [c, c + w]) for each centre c."""
    origin = station - station[0]
    sums = [np.concatenate(([0.0], np.cumsum(v))) for v in (np.ones_like(origin), origin, origin * origin,
                                                          height, origin * height)]
    lo = np.searchsorted(station, centres - window_m if before else centres, side="left")
    hi = np.searchsorted(station, centres if before else centres + window_m, side="right")
    n, sx, sxx, sz, sxz = (c[hi] - c[lo] for c in sums)
    with np.errstate(invalid="ignore", divide="ignore"):
        return (n * sxz - sx * sz) / (n * sxx - sx * sx)


@dataclass(frozen=True)
class VerticalFit:
    """Fitted profile and the height residuals [m, measured - fitted, + up] at the points."""

    profile: VerticalProfile
    residual_m: np.ndarray

    @property
    def rms_m(self) -> float:
        return float(np.sqrt(np.mean(self.residual_m**2)))


def _profile(x: np.ndarray, first: float, last: float, count: int) -> VerticalProfile:
    """x = [interior PVI stations, all PVI elevations, interior curve radii]."""
    stations = np.concatenate(([first], x[:count], [last]))
    elevations = x[count : 2 * count + 2]
    radii = x[2 * count + 2 :]
    pvis = [PVI(float(stations[0]), float(elevations[0]))]
    pvis += [
        PVI(float(s), float(z), curve="circular", curve_radius_m=float(r))
        for s, z, r in zip(stations[1:-1], elevations[1:-1], radii)
    ]
    pvis.append(PVI(float(stations[-1]), float(elevations[-1])))
    return VerticalProfile(tuple(pvis))


def fit_vertical(
    station_m,
    height_m,
    *,
    window_m: float = 200.0,
    min_grade_change: float = 5e-4,
) -> VerticalFit:
    """Fit grade lines joined at PVIs with circular vertical curves to heights at increasing stations [m].

    A PVI is found where the grades over ``window_m`` before and after a station differ
    by more than ``min_grade_change``; PVIs closer than ``window_m`` merge. Data shorter than two
    windows are searched with windows of half their span (at least _MIN_PROFILE_M in all).
    """
    station, height = _checked_series(station_m, height_m, names=("height_m",))
    span = station[-1] - station[0]
    if span < _MIN_PROFILE_M:
        raise LineFitError(
            f"line fitting: the profile from {station[0]:.1f} to {station[-1]:.1f} m spans {span:.1f} m; at least "
            f"{_MIN_PROFILE_M:.1f} m are needed"
        )
    window_m = min(window_m, 0.5 * span)
    grid = np.arange(station[0] + window_m, station[-1] - window_m, 1.0)
    change = _window_slopes(station, height, grid, window_m, False) - _window_slopes(
        station, height, grid, window_m, True
    )
    pvi_stations, changes = [], []
    for first, last in _runs(np.abs(change) > min_grade_change):
        peak = first + int(np.argmax(np.abs(change[first : last + 1])))
        if pvi_stations and grid[peak] - pvi_stations[-1] < window_m:
            if abs(change[peak]) <= abs(changes[-1]):
                continue
            pvi_stations.pop()
            changes.pop()
        pvi_stations.append(float(grid[peak]))
        changes.append(float(change[peak]))
    count = len(pvi_stations)
    knots = np.concatenate(([station[0]], pvi_stations, [station[-1]]))
    # seed elevations: the measured heights, off at a curved PVI by its external distance (cm)
    elevations = np.interp(knots, station, height)
    # a seed curve half as long as the window leaves room between neighbouring PVIs
    radii = [0.5 * window_m / abs(c) for c in changes]
    x0 = np.concatenate((pvi_stations, elevations, radii))
    lower = np.concatenate((np.full(count, station[0]), np.full(count + 2, -np.inf), np.zeros(count)))
    upper = np.concatenate((np.full(count, station[-1]), np.full(count + 2 + count, np.inf)))

    def residuals(x):
        try:
            profile = _profile(x, station[0], station[-1], count)
        except ValueError:
            return np.full(station.size, 10.0)
        return height - profile.elevation_at(station)

    from scipy.optimize import least_squares  # imported when a line is fitted (see _solve_chain)

    solution = least_squares(residuals, x0, bounds=(lower, upper), x_scale="jac", method="trf")
    profile = _profile(solution.x, station[0], station[-1], count)
    return VerticalFit(profile, height - profile.elevation_at(station))


# ------------------------------------------------------------------- cant
def fit_cant(plan: HorizontalAlignment, station_m, cant_m) -> CantTable:
    """The design cant of ``plan`` that best fits measured cant [m] at stations on it.

    One cant per arc, ramped linearly along the clothoids (0 on the straights, the mean of
    the two arcs where arcs meet directly): a linear least-squares problem over the arcs.
    """
    station, cant = _checked_series(station_m, cant_m, names=("cant_m",))
    boundaries = plan.boundary_stations_m
    elements = plan.elements
    arcs = [i for i, element in enumerate(elements) if isinstance(element, Arc)]
    # knot k joins elements k - 1 and k; each arc's cant sits on both its knots
    knots = np.zeros((len(arcs), boundaries.size))
    for j, i in enumerate(arcs):
        for k in (i, i + 1):
            neighbours = sum(1 for e in (k - 1, k) if 0 <= e < len(elements) and isinstance(elements[e], Arc))
            knots[j, k] = 1.0 / neighbours
    if not arcs:
        return CantTable(boundaries[[0, -1]], np.zeros(2))
    basis = np.column_stack([np.interp(station, boundaries, row) for row in knots])
    per_arc = np.linalg.lstsq(basis, cant, rcond=None)[0]
    return CantTable(boundaries, per_arc @ knots)


# ---------------------------------------------------------------- whole design
@dataclass(frozen=True)
class ElementRow:
    """One row of the fitted element table (radii inf on straights; turn "" on straights)."""

    kind: str
    start_station_m: float
    end_station_m: float
    length_m: float
    radius_start_m: float
    radius_end_m: float
    turn: str


def element_table(alignment: HorizontalAlignment) -> tuple[ElementRow, ...]:
    rows = []
    for placed in alignment.placed_elements:
        element = placed.element
        if isinstance(element, Line):
            radii, turn = (math.inf, math.inf), ""
        elif isinstance(element, Arc):
            radii, turn = (element.radius_m, element.radius_m), element.turn
        else:
            radii, turn = (element.radius_start_m, element.radius_end_m), element.turn
        rows.append(
            ElementRow(type(element).__name__, placed.start_station_m, placed.end_station_m, element.length_m,
                       *radii, turn)
        )
    return tuple(rows)


@dataclass(frozen=True)
class AlignmentFit:
    """A fitted design (plan and profile; no cant) with the fits it came from."""

    alignment: DesignAlignment
    horizontal: HorizontalFit
    vertical: VerticalFit
    cant_residual_m: np.ndarray | None = None
    """Measured - fitted cant [m] when cant was fitted."""

    def report(self) -> str:
        """Residuals, element table and PVI table as plain text (stations in m, residuals in mm)."""
        lateral, vertical = self.horizontal.offset_m, self.vertical.residual_m
        lines = [
            f"line-type fit of {lateral.size} points",
            f"  plan residuals:    RMS {1e3 * self.horizontal.rms_m:.2f} mm, max {1e3 * np.abs(lateral).max():.2f} mm",
            f"  profile residuals: RMS {1e3 * self.vertical.rms_m:.2f} mm, max {1e3 * np.abs(vertical).max():.2f} mm",
        ]
        if self.cant_residual_m is not None:
            cant = self.cant_residual_m
            lines.append(f"  cant residuals:    RMS {1e3 * np.sqrt(np.mean(cant**2)):.2f} mm, "
                         f"max {1e3 * np.abs(cant).max():.2f} mm")
        lines.append("  element   start [m]      end [m]   length [m]   R start [m]     R end [m]  turn")
        for row in element_table(self.alignment.horizontal):
            lines.append(
                f"  {row.kind:<8}{row.start_station_m:>11.3f}{row.end_station_m:>13.3f}{row.length_m:>13.3f}"
                f"{row.radius_start_m:>14.2f}{row.radius_end_m:>14.2f}  {row.turn}"
            )
        lines.append("  PVI  station [m]  elevation [m]  grade out  curve radius [m]")
        profile = self.vertical.profile
        grades = np.append(profile.grades, np.nan)
        for i, (pvi, grade, radius) in enumerate(zip(profile.pvis, grades, profile.curve_radii_m)):
            lines.append(f"  {i + 1:>3}{pvi.station_m:>13.3f}{pvi.elevation_m:>15.4f}{grade:>11.5f}{radius:>18.1f}")
        return "\n".join(lines)


def fit_alignment(station_m, east_m, north_m, height_m, *, cant_m=None, name: str = "fitted",
                  **options) -> AlignmentFit:
    """Fit plan and profile of a centreline; the profile is fitted on the fitted plan's stations,
    and so is the cant (:func:`fit_cant`) when the measured ``cant_m`` is given.

    ``options`` go to :func:`fit_horizontal` (chord_half_m, curvature_window_m,
    max_radius_m, min_transition_shift_m) and :func:`fit_vertical` (window_m, min_grade_change).
    """
    vertical_keys = {"window_m", "min_grade_change"}
    horizontal_keys = {"chord_half_m", "curvature_window_m", "max_radius_m", "min_transition_shift_m"}
    unknown = set(options) - vertical_keys - horizontal_keys
    if unknown:
        raise TypeError(f"fit_alignment: unknown option(s) {', '.join(sorted(unknown))}")
    station, east, north, height = _checked_series(
        station_m, east_m, north_m, height_m, names=("east_m", "north_m", "height_m")
    )
    horizontal = fit_horizontal(
        station, east, north, **{k: v for k, v in options.items() if k in horizontal_keys}
    )
    plan = horizontal.alignment
    # the outermost feet lie on the plan's ends (to round-off): pinning them there gives the profile the plan's range
    feet = np.clip(horizontal.station_m, plan.start_station_m, plan.end_station_m)
    order = np.argsort(feet, kind="stable")
    keep = np.concatenate(([True], np.diff(feet[order]) > 0.0))
    vertical = fit_vertical(
        feet[order][keep], height[order][keep], **{k: v for k, v in options.items() if k in vertical_keys}
    )
    cant_table = cant_residual = None
    if cant_m is not None:
        cant = _checked_series(station, cant_m, names=("cant_m",))[1]
        cant_table = fit_cant(plan, feet[order][keep], cant[order][keep])
        cant_residual = cant - cant_table.cant_at(feet)
    design = DesignAlignment(horizontal=plan, vertical=vertical.profile, cant=cant_table, name=name)
    return AlignmentFit(design, horizontal, vertical, cant_residual)
