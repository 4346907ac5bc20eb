"""Vertical profile (grade lines joined at PVIs by vertical curves) and design cant.

A PVI (point of vertical intersection) may carry a vertical curve, parabolic or
circular, given by its length or its radius:

* parabolic: length L is the horizontal (station) extent, symmetric about the PVI;
  radius R = L / |g2 - g1| (the radius at the vertex of the parabola).
* circular: a true circle of radius R tangent to both grade lines; the tangent
  length is T = R tan(|a2 - a1| / 2), a = atan(g), so the curve spans
  T cos(a1) before and T cos(a2) after the PVI; its "length" is that station extent.

Stations are the continuous measure; elevations normal heights [m]; grades are
dimensionless; vertical curvature is the geometric curvature of the profile line,
positive for a sag. See :mod:`insrail.track` for the conventions.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from insrail.track.errors import DesignError

CURVE_KINDS = ("none", "parabolic", "circular")

_STATION_TOLERANCE_M = 1e-6


def _check_range(what: str, stations: np.ndarray, first: float, last: float) -> None:
    outside = (stations < first - _STATION_TOLERANCE_M) | (stations > last + _STATION_TOLERANCE_M)
    if np.any(outside):
        station = stations[outside].flat[0]
        raise ValueError(f"station {station:.6f} m is outside the {what} [{first:.6f}, {last:.6f}] m")


@dataclass(frozen=True)
class PVI:
    """A point of vertical intersection and the vertical curve it carries.

    curve is "none", "parabolic" or "circular"; a curve is given by exactly one of
    curve_length_m (station extent) or curve_radius_m.
    """

    station_m: float
    elevation_m: float
    curve: str = "none"
    curve_length_m: float | None = None
    curve_radius_m: float | None = None

    def __post_init__(self):
        for name in ("station_m", "elevation_m"):
            if not math.isfinite(getattr(self, name)):
                raise DesignError("profile", None, "PVI: {name} must be a finite number, got {value!r}",
                                  {"name": name, "value": getattr(self, name)})
        if self.curve not in CURVE_KINDS:
            raise DesignError("profile", None, "PVI: curve must be one of {kinds}, got {curve!r}",
                              {"kinds": ", ".join(CURVE_KINDS), "curve": self.curve})
        given = [v for v in (self.curve_length_m, self.curve_radius_m) if v is not None]
        if self.curve == "none":
            if given:
                raise DesignError("profile", None, "PVI: a curve length or radius is given but the curve kind is 'none'")
            return
        if len(given) != 1:
            raise DesignError("profile", None, "PVI: a {curve} curve needs exactly one of curve_length_m or curve_radius_m",
                              {"curve": self.curve})
        value = given[0]
        if not (math.isfinite(value) and value >= 0.0):
            raise DesignError("profile", None, "PVI: the curve length or radius must be a finite number >= 0, got "
                              "{value!r}", {"value": value})


@dataclass(frozen=True)
class _Curves:
    """Resolved vertical curves, sorted by station (arrays of equal length)."""

    pvi_index: np.ndarray
    begin_m: np.ndarray
    end_m: np.ndarray
    length_m: np.ndarray  # resolved directly, not end - begin, which loses digits to cancellation
    pvi_station_m: np.ndarray
    pvi_elevation_m: np.ndarray
    grade_in: np.ndarray
    grade_out: np.ndarray
    circular: np.ndarray
    radius_m: np.ndarray
    centre_station_m: np.ndarray
    centre_elevation_m: np.ndarray
    sag_sign: np.ndarray


@dataclass(frozen=True)
class VerticalProfile:
    """Grade lines through PVIs (at least two, stations increasing) with vertical curves."""

    pvis: tuple[PVI, ...]
    _curves: _Curves = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        object.__setattr__(self, "pvis", tuple(self.pvis))
        if len(self.pvis) < 2:
            raise DesignError("profile", None, "a vertical profile needs at least two PVIs")
        stations = np.array([p.station_m for p in self.pvis])
        for i in range(1, len(stations)):
            if not stations[i] > stations[i - 1]:
                raise DesignError(
                    "profile",
                    i,
                    "PVI {number} at station {station:.4f} m is not after PVI {previous} at station {before:.4f} m; "
                    "PVI stations must increase",
                    {"number": i + 1, "station": stations[i], "previous": i, "before": stations[i - 1]},
                )
        for i in (0, len(self.pvis) - 1):
            if self.pvis[i].curve != "none":
                raise DesignError("profile", i, "PVI {number} is an end of the profile and cannot carry a vertical curve",
                                  {"number": i + 1})
        object.__setattr__(self, "_curves", self._resolve_curves(stations))

    @property
    def stations_m(self) -> np.ndarray:
        return np.array([p.station_m for p in self.pvis])

    @property
    def elevations_m(self) -> np.ndarray:
        return np.array([p.elevation_m for p in self.pvis])

    @property
    def grades(self) -> np.ndarray:
        """Grades of the straight grade lines between consecutive PVIs."""
        return np.diff(self.elevations_m) / np.diff(self.stations_m)

    @property
    def curve_lengths_m(self) -> np.ndarray:
        """Station extent of each PVI's curve (0 where there is none)."""
        lengths = np.zeros(len(self.pvis))
        lengths[self._curves.pvi_index] = self._curves.length_m
        return lengths

    @property
    def curve_radii_m(self) -> np.ndarray:
        """Radius of each PVI's curve (inf where there is none or the grades are equal)."""
        radii = np.full(len(self.pvis), np.inf)
        radii[self._curves.pvi_index] = self._curves.radius_m
        return radii

    def _resolve_curves(self, stations: np.ndarray) -> _Curves:
        elevations = np.array([p.elevation_m for p in self.pvis])
        grades = np.diff(elevations) / np.diff(stations)
        rows = []
        previous_end, previous_pvi = stations[0], 0
        for i, pvi in enumerate(self.pvis):
            if pvi.curve == "none":
                continue
            g1, g2 = grades[i - 1], grades[i]
            sag = 1.0 if g2 >= g1 else -1.0
            if pvi.curve == "parabolic":
                if pvi.curve_length_m is not None:
                    length = pvi.curve_length_m
                else:
                    length = pvi.curve_radius_m * abs(g2 - g1)
                radius = length / abs(g2 - g1) if g2 != g1 else math.inf
                before = after = 0.5 * length
                centre_s = centre_z = math.nan
            else:
                a1, a2 = math.atan(g1), math.atan(g2)
                half_deflection = math.tan(0.5 * abs(a2 - a1))
                if pvi.curve_radius_m is not None:
                    radius = pvi.curve_radius_m
                elif half_deflection == 0.0:
                    raise DesignError("profile", i, "PVI {number}: the grades in and out are equal, so a circular curve "
                                      "length cannot define a radius", {"number": i + 1})
                else:
                    radius = pvi.curve_length_m / (half_deflection * (math.cos(a1) + math.cos(a2)))
                tangent = radius * half_deflection
                before, after = tangent * math.cos(a1), tangent * math.cos(a2)
                begin_s, begin_z = pvi.station_m - before, pvi.elevation_m - tangent * math.sin(a1)
                centre_s = begin_s - sag * radius * math.sin(a1)
                centre_z = begin_z + sag * radius * math.cos(a1)
            begin, end = pvi.station_m - before, pvi.station_m + after
            if begin < previous_end - _STATION_TOLERANCE_M:
                if previous_pvi == 0:
                    raise DesignError("profile", i, "the vertical curve of PVI {number} begins at station {begin:.4f} m, "
                                      "before PVI 1 at {end:.4f} m", {"number": i + 1, "begin": begin, "end": previous_end})
                raise DesignError("profile", i, "the vertical curve of PVI {number} begins at station {begin:.4f} m, before "
                                  "the end of the vertical curve of PVI {previous} at {end:.4f} m: curves overlap by "
                                  "{overlap:.4f} m", {"number": i + 1, "begin": begin, "previous": previous_pvi + 1,
                                                       "end": previous_end, "overlap": previous_end - begin})
            if end > stations[i + 1] + _STATION_TOLERANCE_M:
                raise DesignError(
                    "profile",
                    i,
                    "the vertical curve of PVI {number} ends at station {end:.4f} m, beyond PVI {next} at {station:.4f} m",
                    {"number": i + 1, "end": end, "next": i + 2, "station": stations[i + 1]},
                )
            rows.append(
                (i, begin, end, before + after, pvi.station_m, pvi.elevation_m, g1, g2, pvi.curve == "circular",
                 radius, centre_s, centre_z, sag)
            )
            previous_end, previous_pvi = end, i
        table = np.array(rows, dtype=float).reshape(len(rows), 13)
        columns = [np.ascontiguousarray(table[:, j]) for j in range(13)]
        columns[0] = columns[0].astype(int)
        columns[8] = columns[8].astype(bool)
        return _Curves(*columns)

    def _evaluate(self, station_m):
        shape = np.shape(station_m)
        stations = np.asarray(station_m, dtype=float).reshape(-1)
        pvi_s = self.stations_m
        _check_range("vertical profile", stations, pvi_s[0], pvi_s[-1])
        pvi_z, grades = self.elevations_m, self.grades
        segment = np.clip(np.searchsorted(pvi_s, stations, side="right") - 1, 0, len(grades) - 1)
        elevation = pvi_z[segment] + grades[segment] * (stations - pvi_s[segment])
        grade = grades[segment].astype(float)
        curvature = np.zeros_like(elevation)
        c = self._curves
        if c.begin_m.size:
            k = np.searchsorted(c.begin_m, stations, side="right") - 1
            inside = (k >= 0) & (stations <= c.end_m[np.maximum(k, 0)])
            k, s = k[inside], stations[inside]
            g1, g2 = c.grade_in[k], c.grade_out[k]
            with np.errstate(invalid="ignore", divide="ignore"):
                # parabola z = z_pvi + g1 (s - s_pvi) + (g2 - g1) x^2 / (2 L), x = s - begin
                length = c.length_m[k]
                x = s - c.begin_m[k]
                bend = np.where(length > 0, (g2 - g1) / np.where(length > 0, length, 1.0), 0.0)
                z_para = c.pvi_elevation_m[k] + g1 * (s - c.pvi_station_m[k]) + 0.5 * bend * x * x
                g_para = g1 + bend * x
                k_para = bend / (1.0 + g_para * g_para) ** 1.5
                # circle z = zc - sag sqrt(R^2 - (s - sc)^2)
                dx = s - c.centre_station_m[k]
                root = np.sqrt(np.maximum(c.radius_m[k] ** 2 - dx * dx, 0.0))
                sag = c.sag_sign[k]
                z_circ = c.centre_elevation_m[k] - sag * root
                g_circ = sag * dx / root
                k_circ = sag / c.radius_m[k]
            circular = c.circular[k]
            elevation[inside] = np.where(circular, z_circ, z_para)
            grade[inside] = np.where(circular, g_circ, g_para)
            curvature[inside] = np.where(circular, k_circ, k_para)
        return elevation.reshape(shape), grade.reshape(shape), curvature.reshape(shape)

    def elevation_at(self, station_m) -> np.ndarray:
        """Design height [m] at the stations (vectorised)."""
        return self._evaluate(station_m)[0]

    def grade_at(self, station_m) -> np.ndarray:
        """Design grade dz/ds at the stations."""
        return self._evaluate(station_m)[1]

    def vertical_curvature_at(self, station_m) -> np.ndarray:
        """Signed curvature of the profile line [1/m], positive for a sag."""
        return self._evaluate(station_m)[2]


@dataclass(frozen=True, eq=False)
class CantTable:
    """Signed design cant [m] at stations, linear between rows (ramps along the clothoids).

    Positive cant: left rail higher (a right-hand curve). Stations strictly increase;
    the table is defined between its first and last row.
    """

    stations_m: np.ndarray
    cant_m: np.ndarray

    def __post_init__(self):
        stations = np.array(self.stations_m, dtype=float).reshape(-1)
        cant = np.array(self.cant_m, dtype=float).reshape(-1)
        if stations.size != cant.size:
            raise DesignError("cant", None, "{stations} stations but {values} cant values",
                              {"stations": stations.size, "values": cant.size})
        if stations.size < 2:
            raise DesignError("cant", None, "a cant table needs at least two rows")
        for values, what in ((stations, "station"), (cant, "cant")):
            bad = np.flatnonzero(~np.isfinite(values))
            if bad.size:
                raise DesignError("cant", int(bad[0]), "cant row {row}: {what} is not a finite number",
                                  {"row": int(bad[0]) + 1, "what": what})
        steps = np.flatnonzero(np.diff(stations) <= 0.0)
        if steps.size:
            i = int(steps[0]) + 1
            raise DesignError("cant", i, "cant row {row} at station {station:.4f} m is not after row {previous} at "
                              "{before:.4f} m; stations must increase",
                              {"row": i + 1, "station": stations[i], "previous": i, "before": stations[i - 1]})
        stations.setflags(write=False)
        cant.setflags(write=False)
        object.__setattr__(self, "stations_m", stations)
        object.__setattr__(self, "cant_m", cant)

    def cant_at(self, station_m) -> np.ndarray:
        """Signed design cant [m] at the stations (vectorised)."""
        stations = np.asarray(station_m, dtype=float)
        _check_range("cant table", stations, self.stations_m[0], self.stations_m[-1])
        return np.interp(stations, self.stations_m, self.cant_m)

    def __eq__(self, other) -> bool:
        if not isinstance(other, CantTable):
            return NotImplemented
        return np.array_equal(self.stations_m, other.stations_m) and np.array_equal(self.cant_m, other.cant_m)
