"""Design alignment: horizontal elements (line, clothoid, arc), and the whole design.

A horizontal alignment is a chain of elements whose curvature varies linearly with
station inside each element (constant on lines and arcs, linear on clothoids). The
chain starts at a given point, azimuth and station; every element starts where the
previous one ends, with the same azimuth, so the chain is tangent-continuous by
construction. A clothoid must also match its neighbours' curvature (that is what a
transition is for); lines and arcs may meet with a jump in curvature, as on old
lines without transitions.

Coordinates are exact to floating-point round-off: lines and arcs by the closed-form
chord, clothoids by 6-point Gauss-Legendre quadrature of (sin, cos)(azimuth) over
knots at most 20 m (and 0.2 rad of azimuth change) apart, whose error is far below
1e-12 m. All evaluation methods are vectorised over arrays of stations. Sign and
unit conventions: see :mod:`insrail.track`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import cached_property

from typing import TYPE_CHECKING

import numpy as np

from insrail.track.errors import DesignError
from insrail.track.profile import CantTable, VerticalProfile
from insrail.track.stationing import StationEquations

if TYPE_CHECKING:
    from scipy.spatial import cKDTree

# scipy is imported where it is used: the project model and the results reader import this module, and
# every command reading a project (insrail report, export) would pay for scipy's imports otherwise.

TURNS = ("left", "right")

_STATION_TOLERANCE_M = 1e-6
"""Stations this close outside an alignment's ends still count as on it."""

_KNOT_SPACING_M = 20.0
_KNOT_AZIMUTH_CHANGE_RAD = 0.2

_GL_ABSCISSAE, _GL_WEIGHTS = np.polynomial.legendre.leggauss(6)
_GL_FRACTIONS = 0.5 * (_GL_ABSCISSAE + 1.0)  # nodes mapped to [0, 1]
_GL_WEIGHTS = 0.5 * _GL_WEIGHTS

_NEWTON_MAX_ITERATIONS = 30
_NEWTON_TOLERANCE_M = 1e-8


def _turn_sign(turn: str) -> float:
    return 1.0 if turn == "right" else -1.0


def _check_length(kind: str, length_m: float) -> None:
    if not (math.isfinite(length_m) and length_m > 0.0):
        raise DesignError("horizontal", None, "{kind}: length must be a positive number of metres, got {length!r}",
                          {"kind": kind, "length": length_m})


def _check_turn(kind: str, turn: str) -> None:
    if turn not in TURNS:
        raise DesignError("horizontal", None, "{kind}: turn must be 'left' or 'right', got {turn!r}",
                          {"kind": kind, "turn": turn})


def _format_radius(radius_m: float) -> str:
    return "inf" if math.isinf(radius_m) else f"{radius_m:g} m"


@dataclass(frozen=True)
class Line:
    """A straight (tangent) of the given length [m]."""

    length_m: float

    def __post_init__(self):
        _check_length("Line", self.length_m)

    @property
    def curvature_start(self) -> float:
        return 0.0

    @property
    def curvature_end(self) -> float:
        return 0.0

    def describe(self) -> str:
        return f"Line {self.length_m:g} m"


@dataclass(frozen=True)
class Arc:
    """A circular arc of the given length and radius [m], turning "left" or "right"."""

    length_m: float
    radius_m: float
    turn: str

    def __post_init__(self):
        _check_length("Arc", self.length_m)
        if not (math.isfinite(self.radius_m) and self.radius_m > 0.0):
            raise DesignError("horizontal", None, "Arc: radius must be a positive finite number of metres, got {radius!r}",
                              {"radius": self.radius_m})
        _check_turn("Arc", self.turn)

    @property
    def curvature_start(self) -> float:
        return _turn_sign(self.turn) / self.radius_m

    @property
    def curvature_end(self) -> float:
        return self.curvature_start

    def describe(self) -> str:
        return f"Arc {self.length_m:g} m, R {_format_radius(self.radius_m)}, {self.turn}"


@dataclass(frozen=True)
class Clothoid:
    """A clothoid (curvature linear in station) from radius_start_m to radius_end_m.

    A radius may be ``math.inf`` (a tangent end): inf -> R is an entry spiral,
    R -> inf an exit spiral, R1 -> R2 a compound ("egg") spiral. Both ends curve
    towards the same side, ``turn``.
    """

    length_m: float
    radius_start_m: float
    radius_end_m: float
    turn: str

    def __post_init__(self):
        _check_length("Clothoid", self.length_m)
        for name in ("radius_start_m", "radius_end_m"):
            radius = getattr(self, name)
            if math.isnan(radius) or radius <= 0.0:
                raise DesignError("horizontal", None, "Clothoid: {name} must be a positive number of metres or inf, got "
                                  "{radius!r}", {"name": name, "radius": radius})
        if math.isinf(self.radius_start_m) and math.isinf(self.radius_end_m):
            raise DesignError("horizontal", None, "Clothoid: both radii are infinite; that is a Line")
        if self.radius_start_m == self.radius_end_m:
            raise DesignError("horizontal", None, "Clothoid: both radii are equal; that is an Arc")
        _check_turn("Clothoid", self.turn)

    @property
    def curvature_start(self) -> float:
        return _turn_sign(self.turn) / self.radius_start_m

    @property
    def curvature_end(self) -> float:
        return _turn_sign(self.turn) / self.radius_end_m

    def describe(self) -> str:
        return (
            f"Clothoid {self.length_m:g} m, R {_format_radius(self.radius_start_m)} -> "
            f"{_format_radius(self.radius_end_m)}, {self.turn}"
        )


HorizontalElement = Line | Clothoid | Arc


@dataclass(frozen=True)
class PlacedElement:
    """One element of a horizontal alignment with where it starts and ends."""

    index: int
    element: HorizontalElement
    start_station_m: float
    end_station_m: float
    start_east_m: float
    start_north_m: float
    start_azimuth_rad: float
    end_east_m: float
    end_north_m: float
    end_azimuth_rad: float


@dataclass(frozen=True)
class KeyPoint:
    """A labelled element boundary (TS, SC, CS, ST, PC, PT, ...) at a station."""

    station_m: float
    label: str


_JOINT_LABELS = {
    ("Line", "Clothoid"): "TS",
    ("Clothoid", "Arc"): "SC",
    ("Arc", "Clothoid"): "CS",
    ("Clothoid", "Line"): "ST",
    ("Line", "Arc"): "PC",
    ("Arc", "Line"): "PT",
    ("Clothoid", "Clothoid"): "SS",
    ("Line", "Line"): "POT",
}


def _joint_label(before: HorizontalElement, after: HorizontalElement) -> str:
    if isinstance(before, Arc) and isinstance(after, Arc):
        return "PCC" if before.turn == after.turn else "PRC"
    return _JOINT_LABELS[type(before).__name__, type(after).__name__]


def _same_curvature(a: float, b: float) -> bool:
    return abs(a - b) <= 1e-12 + 1e-6 * max(abs(a), abs(b))


def advance_along_curve(east, north, azimuth, curvature, curvature_rate, distance):
    """Position after ``distance`` [m] along a curve whose curvature varies linearly.

    The curve starts at (east, north) [m] with ``azimuth`` [rad], ``curvature``
    [1/m] and d(curvature)/d(station) ``curvature_rate`` [1/m^2]. Vectorised over
    broadcastable arrays; returns (east, north). Constant curvature uses the exact
    chord, varying curvature 6-point Gauss-Legendre quadrature, which is exact to
    round-off while the azimuth changes by well under a radian over ``distance``.
    """
    arrays = np.broadcast_arrays(
        *(np.asarray(v, dtype=float) for v in (east, north, azimuth, curvature, curvature_rate, distance))
    )
    shape = arrays[0].shape
    east, north, azimuth, curvature, curvature_rate, distance = (a.ravel() for a in arrays)
    half_turn = 0.5 * curvature * distance
    chord = distance * np.sinc(half_turn / np.pi)
    chord_direction = azimuth + half_turn
    d_east = chord * np.sin(chord_direction)
    d_north = chord * np.cos(chord_direction)
    varying = curvature_rate != 0.0
    if np.any(varying):
        d = distance[varying]
        along = d[:, None] * _GL_FRACTIONS
        heading = (
            azimuth[varying][:, None]
            + curvature[varying][:, None] * along
            + 0.5 * curvature_rate[varying][:, None] * along * along
        )
        d_east[varying] = d * (np.sin(heading) @ _GL_WEIGHTS)
        d_north[varying] = d * (np.cos(heading) @ _GL_WEIGHTS)
    return (east + d_east).reshape(shape), (north + d_north).reshape(shape)


@dataclass(frozen=True)
class _Knots:
    """States at knots along the chain: every element start plus clothoid interior points."""

    station_m: np.ndarray
    east_m: np.ndarray
    north_m: np.ndarray
    azimuth_rad: np.ndarray  # unwrapped
    curvature: np.ndarray
    curvature_rate: np.ndarray
    placed: tuple[PlacedElement, ...]


def _build_knots(alignment: HorizontalAlignment) -> _Knots:
    east, north = alignment.start_east_m, alignment.start_north_m
    azimuth = alignment.start_azimuth_rad
    rows = []
    placed = []
    lengths = np.array([element.length_m for element in alignment.elements])
    element_starts = alignment.start_station_m + np.concatenate(([0.0], np.cumsum(lengths)))
    for index, element in enumerate(alignment.elements):
        k0, k1 = element.curvature_start, element.curvature_end
        rate = (k1 - k0) / element.length_m
        if rate == 0.0:
            pieces = 1
        else:
            spacing = min(_KNOT_SPACING_M, _KNOT_AZIMUTH_CHANGE_RAD / max(abs(k0), abs(k1)))
            pieces = math.ceil(element.length_m / spacing)
        step = element.length_m / pieces
        start_state = (east, north, azimuth)
        for piece in range(pieces):
            curvature = k0 + rate * piece * step
            rows.append((element_starts[index] + piece * step, east, north, azimuth, curvature, rate))
            e, n = advance_along_curve(east, north, azimuth, curvature, rate, step)
            east, north = float(e), float(n)
            azimuth = azimuth + curvature * step + 0.5 * rate * step * step
        placed.append(
            PlacedElement(
                index=index,
                element=element,
                start_station_m=float(element_starts[index]),
                end_station_m=float(element_starts[index + 1]),
                start_east_m=start_state[0],
                start_north_m=start_state[1],
                start_azimuth_rad=start_state[2] % (2 * math.pi),
                end_east_m=east,
                end_north_m=north,
                end_azimuth_rad=azimuth % (2 * math.pi),
            )
        )
    table = np.array(rows, dtype=float)
    return _Knots(*(np.ascontiguousarray(table[:, i]) for i in range(6)), placed=tuple(placed))


@dataclass(frozen=True)
class HorizontalAlignment:
    """A chain of horizontal elements from a start point, azimuth and station.

    start_east_m, start_north_m : start point, engineering grid [m]
    start_azimuth_rad           : azimuth at the start, clockwise from grid north
    start_station_m             : station of the start (continuous measure)
    elements                    : Line / Clothoid / Arc, in order of increasing station
    """

    start_east_m: float
    start_north_m: float
    start_azimuth_rad: float
    start_station_m: float
    elements: tuple[HorizontalElement, ...]
    _knots: _Knots = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        object.__setattr__(self, "elements", tuple(self.elements))
        for name in ("start_east_m", "start_north_m", "start_azimuth_rad", "start_station_m"):
            if not math.isfinite(getattr(self, name)):
                raise DesignError("horizontal", None, "{name} must be a finite number, got {value!r}",
                                  {"name": name, "value": getattr(self, name)})
        if not self.elements:
            raise DesignError("horizontal", None, "a horizontal alignment needs at least one element")
        for index, element in enumerate(self.elements):
            if not isinstance(element, (Line, Clothoid, Arc)):
                raise DesignError("horizontal", index, "element {number} is not a Line, Clothoid or Arc: {element}",
                                  {"number": index + 1, "element": repr(element)})
        for index in range(1, len(self.elements)):
            before, after = self.elements[index - 1], self.elements[index]
            if (isinstance(before, Clothoid) or isinstance(after, Clothoid)) and not _same_curvature(
                before.curvature_end, after.curvature_start
            ):
                raise DesignError(
                    "horizontal",
                    index,
                    "element {number} ({after}) does not continue the curvature of element {previous} ({before}): a "
                    "clothoid must join its neighbours without a jump in curvature (check the radii and turn directions)",
                    {"number": index + 1, "after": after.describe(), "previous": index, "before": before.describe()},
                )
        object.__setattr__(self, "_knots", _build_knots(self))

    # ----------------------------------------------------------------- layout
    @property
    def length_m(self) -> float:
        return self.end_station_m - self.start_station_m

    @property
    def end_station_m(self) -> float:
        return self._knots.placed[-1].end_station_m

    @property
    def placed_elements(self) -> tuple[PlacedElement, ...]:
        return self._knots.placed

    @property
    def boundary_stations_m(self) -> np.ndarray:
        """Stations of the start, every element joint (TS/SC/CS/ST ...) and the end."""
        placed = self._knots.placed
        return np.array([p.start_station_m for p in placed] + [placed[-1].end_station_m])

    def key_points(self) -> tuple[KeyPoint, ...]:
        """Start ("POB"), labelled element joints, end ("POE")."""
        placed = self._knots.placed
        joints = [
            KeyPoint(after.start_station_m, _joint_label(before.element, after.element))
            for before, after in zip(placed[:-1], placed[1:])
        ]
        return (KeyPoint(placed[0].start_station_m, "POB"), *joints, KeyPoint(placed[-1].end_station_m, "POE"))

    def element_index_at(self, station_m) -> np.ndarray:
        """0-based index of the element holding each station (a joint belongs to the next element)."""
        stations = self._checked(station_m)
        starts = self.boundary_stations_m[:-1]
        return np.clip(np.searchsorted(starts, stations, side="right") - 1, 0, len(starts) - 1)

    def element_at(self, station_m: float) -> PlacedElement:
        """The placed element holding ``station_m`` (a joint belongs to the next element)."""
        return self._knots.placed[int(self.element_index_at(float(station_m)))]

    # ------------------------------------------------------------- evaluation
    def _checked(self, station_m) -> np.ndarray:
        stations = np.asarray(station_m, dtype=float)
        low = self.start_station_m - _STATION_TOLERANCE_M
        high = self.end_station_m + _STATION_TOLERANCE_M
        outside = (stations < low) | (stations > high)
        if np.any(outside):
            first = stations[outside].flat[0]
            raise ValueError(
                f"station {first:.6f} m is outside the horizontal alignment "
                f"[{self.start_station_m:.6f}, {self.end_station_m:.6f}] m"
            )
        return stations

    def _locate(self, stations: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Index of the knot at or before each station and the distance from it."""
        knot_stations = self._knots.station_m
        index = np.clip(np.searchsorted(knot_stations, stations, side="right") - 1, 0, len(knot_stations) - 1)
        return index, stations - knot_stations[index]

    def _state(self, stations: np.ndarray):
        """(east, north, unwrapped azimuth, curvature) at any station, extrapolating the end elements."""
        knots = self._knots
        index, distance = self._locate(stations)
        curvature = knots.curvature[index]
        rate = knots.curvature_rate[index]
        azimuth = knots.azimuth_rad[index]
        east, north = advance_along_curve(
            knots.east_m[index], knots.north_m[index], azimuth, curvature, rate, distance
        )
        azimuth_here = azimuth + curvature * distance + 0.5 * rate * distance * distance
        return east, north, azimuth_here, curvature + rate * distance

    def point_at(self, station_m, offset_m=0.0) -> tuple[np.ndarray, np.ndarray]:
        """(east_m, north_m) of the point at ``station_m``, ``offset_m`` to the right (vectorised)."""
        stations = self._checked(station_m)
        east, north, azimuth, _ = self._state(stations)
        offset = np.asarray(offset_m, dtype=float)
        return east + offset * np.cos(azimuth), north - offset * np.sin(azimuth)

    def azimuth_at(self, station_m) -> np.ndarray:
        """Azimuth of the tangent [rad, clockwise from grid north, in [0, 2 pi)]."""
        index, distance = self._locate(self._checked(station_m))
        knots = self._knots
        azimuth = knots.azimuth_rad[index] + distance * (
            knots.curvature[index] + 0.5 * knots.curvature_rate[index] * distance
        )
        return np.mod(azimuth, 2 * np.pi)

    def curvature_at(self, station_m) -> np.ndarray:
        """Signed curvature [1/m], positive turning right; at a joint, the next element's."""
        index, distance = self._locate(self._checked(station_m))
        return self._knots.curvature[index] + self._knots.curvature_rate[index] * distance

    # ------------------------------------------------------------- projection
    @cached_property
    def _projection_index(self) -> tuple[cKDTree, np.ndarray, float]:
        from scipy.spatial import cKDTree

        spacing = max(1.0, self.length_m / 200_000)
        count = math.ceil(self.length_m / spacing) + 1
        stations = np.linspace(self.start_station_m, self.end_station_m, count)
        east, north, _, _ = self._state(stations)
        return cKDTree(np.column_stack((east, north))), stations, self.length_m / (count - 1)

    def station_offset(self, east_m, north_m, carry: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(station_m, offset_m) of points: the foot of the perpendicular and the signed distance.

        Offsets are positive to the right. Points whose foot lies beyond the ends of the
        alignment, and points with no perpendicular foot nearby (at a curve's centre),
        get NaN for both: test with ``np.isnan(station)``. Exact to ~1e-10 m.
        ``carry``: :func:`projection_carry`, updated in place, to project a long series of points
        in consecutive parts with the same result, to the bit, as in one call (each point starts
        from where the one before it ended).
        """
        east, north = np.broadcast_arrays(np.asarray(east_m, dtype=float), np.asarray(north_m, dtype=float))
        shape = east.shape
        east, north = np.ascontiguousarray(east.ravel()), np.ascontiguousarray(north.ravel())
        station = np.full(east.shape, np.nan)
        offset = np.full(east.shape, np.nan)
        from insrail.track._projection import project_points  # compiled: imported when first needed

        tree, sample_stations, spacing = self._projection_index
        knots = self._knots
        curve = (knots.station_m, knots.east_m, knots.north_m, knots.azimuth_rad, knots.curvature, knots.curvature_rate,
                 _GL_FRACTIONS, _GL_WEIGHTS, sample_stations, tree.data[:, 0].copy(), tree.data[:, 1].copy())
        limits = (max(spacing, 10.0), self.start_station_m - _STATION_TOLERANCE_M,
                  self.end_station_m + _STATION_TOLERANCE_M, _NEWTON_MAX_ITERATIONS, _NEWTON_TOLERANCE_M)
        previous = projection_carry() if carry is None else carry
        first, cold_sample = 0, -1
        # each point starts from the sample nearest to it: walked to from the one before it, or
        # (the first point, one after a gap or a jump) looked up in the index
        while (first := project_points(*curve, east, north, first, cold_sample, *limits, station, offset,
                                       previous)) >= 0:
            cold_sample = int(tree.query((east[first], north[first]))[1])
        return station.reshape(shape), offset.reshape(shape)


def projection_carry() -> np.ndarray:
    """What :meth:`HorizontalAlignment.station_offset` carries from one point to the next (the
    previous point's nearest sample and position), before the first point."""
    return np.zeros(4)


@dataclass(frozen=True)
class DesignAlignment:
    """The whole design of one track: plan, profile, cant and chainage.

    ``vertical`` and ``cant`` may be None (a plan-only alignment, e.g. fresh from
    line-type fitting). Everything works on the continuous station measure;
    ``station_equations`` maps it to the displayed (broken) chainage.
    """

    horizontal: HorizontalAlignment
    vertical: VerticalProfile | None = None
    cant: CantTable | None = None
    station_equations: StationEquations = field(default_factory=StationEquations)
    name: str = "alignment"

    def __post_init__(self):
        start, end = self.horizontal.start_station_m, self.horizontal.end_station_m
        for index, internal in enumerate(self.station_equations.internal_stations_m):
            if not start <= internal <= end:
                raise DesignError(
                    "station_equations",
                    index,
                    "station equation {number} falls at station {station:.4f} m, outside the alignment "
                    "[{start:.4f}, {end:.4f}] m",
                    {"number": index + 1, "station": internal, "start": start, "end": end},
                )
