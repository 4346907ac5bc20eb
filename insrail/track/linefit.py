"""Line-type fitting: recover a design alignment from a measured centreline (thesis 5.3.2.3-6).

Plan. The heading of the centreline is constant on straights, linear in station on
circular arcs and a parabola in station on clothoids, so its derivative, the
curvature, is a trapezoid per curve. The pipeline:

1. heading from chords of +-``chord_half_m`` (interpolated, so uneven spacing is fine);
   curvature = heading change over ``curvature_window_m``, which averages out the
   short-wave irregularities (3-70 m) the fit must not chase;
2. segmentation: every run of |curvature| above 1/``max_radius_m`` is one curve;
   its plateau gives the arc curvature, the 10 %/50 %/90 % crossings of the plateau
   give the clothoid midpoints and lengths; straights lie in between;
3. total least squares on the orthogonal distances of all points to the element
   chain (:class:`HorizontalAlignment`), with unknowns the start point's offset
   across the initial tangent, the start azimuth, every element length but the last
   and the arcs' curvatures. The chain is built from curvature, so tangent and
   curvature continuity hold by construction (the digest's recommendation rather than
   the thesis's per-element fits and its eq. 5.7, which minimises sum d^4).

Profile. Grade lines meet at PVIs carrying circular vertical curves. A PVI shows up
as a jump between the grades of least-squares lines fitted over ``window_m`` before
and after a station; the peaks of |jump| above ``min_grade_change`` seed the PVIs,
then least squares on the heights refines PVI stations, elevations and radii.

The fit is global (one chain for the whole run). Residual RMS values in the report
say how well it holds; eq. 5.24's overlapping windows, needed when the centreline
carries GNSS-level long-wave errors, are not implemented here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from insrail.track.alignment import (
    Arc,
    Clothoid,
    DesignAlignment,
    HorizontalAlignment,
    Line,
)
from insrail.track.profile import PVI, VerticalProfile

_END_MARGIN_M = 5.0
"""The fitted chain reaches this far beyond the data, so every point has a perpendicular foot."""

_NEWTON_STEPS_COLD = 8
_NEWTON_STEPS_WARM = 2
"""Newton steps to the perpendicular feet from the input stations, and from the previous solution's feet."""
_MIN_ELEMENT_M = 1e-3
"""Elements the fit shrinks below this length are dropped (e.g. a curve without transitions)."""

_MIN_CURVE_RUN_M = 20.0


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
    """Unwrapped azimuth [rad] of the chord centred on each station (stations near the ends dropped)."""
    inner = (station >= station[0] + chord_half_m) & (station <= station[-1] - chord_half_m)
    s = station[inner]
    d_east = np.interp(s + chord_half_m, station, east) - np.interp(s - chord_half_m, station, east)
    d_north = np.interp(s + chord_half_m, station, north) - np.interp(s - chord_half_m, station, north)
    return s, np.unwrap(np.arctan2(d_east, d_north))


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) index pairs of the True runs of ``mask``."""
    edges = np.diff(np.concatenate(([0], mask.astype(np.int8), [0])))
    return list(zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1))


def _crossing(s, value, level, first: bool) -> float:
    """Station where ``value`` first (or last) reaches ``level``, interpolated."""
    above = np.flatnonzero(value >= level)
    i = above[0] if first else above[-1]
    j = i - 1 if first else i + 1
    if j < 0 or j >= len(s):
        return float(s[i])
    return float(np.interp(level, [value[j], value[i]], [s[j], s[i]]))


def _transition(s, magnitude, plateau, window_m, entry: bool) -> tuple[float, float]:
    """Midpoint and length of the entry (or exit) ramp of a curve's smoothed curvature magnitude."""
    spread = abs(_crossing(s, magnitude, 0.9 * plateau, entry) - _crossing(s, magnitude, 0.1 * plateau, entry)) / 0.8
    # a boxcar of width w stretches a ramp of length L to about L + w/2 between 10 and 90 %
    return _crossing(s, magnitude, 0.5 * plateau, entry), max(spread - 0.5 * window_m, 10.0)


@dataclass(frozen=True)
class _CurveSeed:
    """One curve as found on the curvature diagram: TS, SC, CS, ST stations and arc curvature."""

    ts_m: float
    sc_m: float
    cs_m: float
    st_m: float
    curvature: float


def _seed_curves(station, east, north, chord_half_m, window_m, max_radius_m) -> list[_CurveSeed]:
    s, heading = _heading(station, east, north, chord_half_m)
    grid = np.arange(s[0] + 0.5 * window_m, s[-1] - 0.5 * window_m, 1.0)
    if grid.size < 2:
        return []
    curvature = (np.interp(grid + 0.5 * window_m, s, heading) - np.interp(grid - 0.5 * window_m, s, heading)) / window_m
    seeds = []
    for first, last in _runs(np.abs(curvature) > 1.0 / max_radius_m):
        if first == 0 or last == grid.size - 1:
            raise LineFitError(
                f"line fitting: the centreline {'starts' if first == 0 else 'ends'} inside a curve; the "
                "data must begin and end on a straight (extend the survey or cut it at a tangent)"
            )
        if grid[last] - grid[first] < _MIN_CURVE_RUN_M:
            continue
        piece = curvature[first : last + 1]
        sign = np.sign(np.median(piece))
        magnitude = sign * piece
        plateau = float(np.median(magnitude[magnitude >= 0.8 * magnitude.max()]))
        # widen the run to where the curvature leaves zero, so the 10 % crossings are inside it
        lo = max(first - int(window_m), 0)
        hi = min(last + int(window_m), grid.size - 1)
        g, m = grid[lo : hi + 1], sign * curvature[lo : hi + 1]
        entry_mid, entry_length = _transition(g, m, plateau, window_m, entry=True)
        exit_mid, exit_length = _transition(g, m, plateau, window_m, entry=False)
        ts, sc = entry_mid - 0.5 * entry_length, entry_mid + 0.5 * entry_length
        cs, st = exit_mid - 0.5 * exit_length, exit_mid + 0.5 * exit_length
        if cs - sc < 1.0:
            continue
        seeds.append(_CurveSeed(ts, sc, cs, st, float(sign * plateau)))
    return seeds


# --------------------------------------------------------------- chain model
@dataclass(frozen=True)
class _Chain:
    """Element pattern line, (clothoid, arc, clothoid, line) per curve, and its parameter vector.

    x = [start offset across the initial tangent, start azimuth, lengths of every element
    but the last, arc curvatures]; the last length closes the chain at ``end_station``.
    """

    start_station: float
    end_station: float
    reference_east: float
    reference_north: float
    curves: int

    @property
    def element_count(self) -> int:
        return 1 + 4 * self.curves

    def elements(self, x: np.ndarray):
        lengths = np.append(x[2 : 2 + self.element_count - 1], 0.0)
        lengths[-1] = self.end_station - self.start_station - lengths[:-1].sum()
        curvatures = x[2 + self.element_count - 1 :]
        elements = []
        for index, length in enumerate(lengths):
            if length < _MIN_ELEMENT_M:
                continue
            position = (index - 1) % 4  # 0 entry clothoid, 1 arc, 2 exit clothoid, 3 line
            if index == 0 or position == 3:
                elements.append(Line(float(length)))
                continue
            k = float(curvatures[(index - 1) // 4])
            turn = "right" if k > 0 else "left"
            radius = 1.0 / abs(k)
            if position == 1:
                elements.append(Arc(float(length), radius, turn))
            elif position == 0:
                elements.append(Clothoid(float(length), math.inf, radius, turn))
            else:
                elements.append(Clothoid(float(length), radius, math.inf, turn))
        return tuple(elements), lengths

    def alignment(self, x: np.ndarray) -> HorizontalAlignment:
        elements, lengths = self.elements(x)
        if lengths[-1] < _MIN_ELEMENT_M:
            raise LineFitError("line fitting: the fitted elements are longer than the data")
        offset, azimuth = x[0], x[1]
        return HorizontalAlignment(
            start_east_m=self.reference_east + offset * math.cos(azimuth),
            start_north_m=self.reference_north - offset * math.sin(azimuth),
            start_azimuth_rad=float(azimuth),
            start_station_m=self.start_station,
            elements=elements,
        )


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

    Curves flatter than ``max_radius_m`` count as straight. Each curve is fitted as
    clothoid-arc-clothoid; a clothoid whose shift L^2/(24 R) stays below
    ``min_transition_shift_m`` is not supported by the data and is dropped (the arc then
    meets the line directly, PC/PT).
    """
    station, east, north = _checked_series(station_m, east_m, north_m, names=("east_m", "north_m"))
    if station[-1] - station[0] < 2 * chord_half_m + curvature_window_m:
        raise LineFitError(
            f"line fitting: the centreline spans {station[-1] - station[0]:.1f} m; at least "
            f"{2 * chord_half_m + curvature_window_m:.1f} m are needed"
        )
    seeds = _seed_curves(station, east, north, chord_half_m, curvature_window_m, max_radius_m)
    start, end = station[0] - _END_MARGIN_M, station[-1] + _END_MARGIN_M
    _, heading = _heading(station, east, north, chord_half_m)
    azimuth0 = float(heading[0])
    reference_east = east[0] - _END_MARGIN_M * math.sin(azimuth0)
    reference_north = north[0] - _END_MARGIN_M * math.cos(azimuth0)
    chain = _Chain(start, end, reference_east, reference_north, len(seeds))
    boundaries = [start] + [b for c in seeds for b in (c.ts_m, c.sc_m, c.cs_m, c.st_m)] + [end]
    lengths = np.maximum(np.diff(boundaries), 1.0)
    x0 = np.concatenate(([0.0, azimuth0], lengths[:-1], [c.curvature for c in seeds]))
    lower = np.concatenate(([-np.inf, -np.inf], np.zeros(lengths.size - 1), [-np.inf] * len(seeds)))

    def solve(x_start, free):
        # the feet move little while the solver refines the seed, so each evaluation starts from these
        start_feet = _foot(chain.alignment(x_start), station, east, north)[0]

        def residuals(x_free):
            x = x_start.copy()
            x[free] = x_free
            try:
                alignment = chain.alignment(x)
            except ValueError:  # lengths beyond the data: a large residual pushes the solver back
                return np.full(station.size, 10.0)
            return _foot(alignment, start_feet, east, north, _NEWTON_STEPS_WARM)[1]

        solution = least_squares(residuals, x_start[free], bounds=(lower[free], np.inf), x_scale="jac")
        x = x_start.copy()
        x[free] = solution.x
        return x

    free = np.ones(x0.size, dtype=bool)
    x = solve(x0, free)
    # A clothoid shifts its arc by L^2 / (24 R); below min_transition_shift_m the data cannot tell it
    # from none, so it is removed and the rest refitted (an arc meeting its straights directly).
    clothoid = np.array([j for j in range(1, chain.element_count - 1) if (j - 1) % 4 in (0, 2)], dtype=int)
    arc_curvature = np.abs(x[2 + chain.element_count - 1 + (clothoid - 1) // 4])
    unsupported = 2 + clothoid[x[2 + clothoid] ** 2 * arc_curvature / 24.0 < min_transition_shift_m]
    if unsupported.size:
        x[unsupported] = 0.0
        free[unsupported] = False
        x = solve(x, free)
    with_margins = chain.alignment(x)
    feet = _foot(with_margins, station, east, north)[0]
    # cut where the outermost points' perpendiculars fall, so the plan spans exactly the data
    alignment = _without_margins(with_margins, float(feet.min()), float(feet.max()))
    feet, offsets = _foot(alignment, feet, east, north)
    return HorizontalFit(alignment, feet, offsets)


def _without_margins(alignment: HorizontalAlignment, first: float, last: float) -> HorizontalAlignment:
    """The alignment cut to [first, last] where its end elements are lines (as the fit builds them)."""
    elements = list(alignment.elements)
    head, tail = elements[0], elements[-1]
    cut_head = first - alignment.start_station_m
    cut_tail = alignment.end_station_m - last
    if not (isinstance(head, Line) and isinstance(tail, Line)):
        return alignment
    if len(elements) == 1:
        elements[0] = Line(head.length_m - cut_head - cut_tail)
    elif head.length_m > cut_head and tail.length_m > cut_tail:
        elements[0] = Line(head.length_m - cut_head)
        elements[-1] = Line(tail.length_m - cut_tail)
    else:
        return alignment
    east, north = alignment.point_at(first)
    return HorizontalAlignment(
        start_east_m=float(east),
        start_north_m=float(north),
        start_azimuth_rad=float(alignment.azimuth_at(first)),
        start_station_m=float(first),
        elements=tuple(elements),
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
    by more than ``min_grade_change``; PVIs closer than ``window_m`` merge.
    """
    station, height = _checked_series(station_m, height_m, names=("height_m",))
    if station[-1] - station[0] < 2 * window_m:
        raise LineFitError(
            f"line fitting: the profile spans {station[-1] - station[0]:.1f} m; at least {2 * window_m:.1f} m "
            "are needed"
        )
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

    solution = least_squares(residuals, x0, bounds=(lower, upper), x_scale="jac", method="trf")
    profile = _profile(solution.x, station[0], station[-1], count)
    return VerticalFit(profile, height - profile.elevation_at(station))


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

    def report(self) -> str:
        """Residuals, element table and PVI table as plain text (stations in m, residuals in mm)."""
        lateral, vertical = self.horizontal.offset_m, self.vertical.residual_m
        lines = [
            f"line-type fit of {lateral.size} points",
            f"  plan residuals:    RMS {1e3 * self.horizontal.rms_m:.2f} mm, max {1e3 * np.abs(lateral).max():.2f} mm",
            f"  profile residuals: RMS {1e3 * self.vertical.rms_m:.2f} mm, max {1e3 * np.abs(vertical).max():.2f} mm",
            "  element   start [m]      end [m]   length [m]   R start [m]     R end [m]  turn",
        ]
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


def fit_alignment(station_m, east_m, north_m, height_m, *, name: str = "fitted", **options) -> AlignmentFit:
    """Fit plan and profile of a centreline; the profile is fitted on the fitted plan's stations.

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
    design = DesignAlignment(horizontal=plan, vertical=vertical.profile, name=name)
    return AlignmentFit(design, horizontal, vertical)
