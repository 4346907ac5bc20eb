"""Control points of a project (``[geodesy.control_points.<name>]`` in project.toml), e.g. the CPII
point a GNSS base receiver stands on.

A point is given either geodetically or in the project's engineering system::

    [geodesy.control_points.CP2-017]
    lat_deg = 30.512345678            # on the CRS's ellipsoid (the GNSS frame of the network)
    lon_deg = 114.301234567
    ellipsoidal_height_m = 18.432

    [geodesy.control_points.CP2-018]
    east_m = 512410.123               # engineering plane (geodesy.crs)
    north_m = 3374250.456
    normal_height_m = 30.781          # engineering (normal) height H

A GNSS base needs the ellipsoidal height: an engineering point goes back through the CRS
(plane -> latitude/longitude) and the project's height model, h = H + zeta(E, N), zeta fitted
on the project's benchmarks. A project without benchmarks works with ellipsoidal heights
(H = h) and takes the normal height as ellipsoidal.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from insrail.geodesy.crs import EngineeringCRS
from insrail.geodesy.errors import GeodesyError
from insrail.geodesy.height_anomaly import HeightAnomalyFit
from insrail.notices import Phrase

GEODETIC_KEYS = ("lat_deg", "lon_deg", "ellipsoidal_height_m")
ENGINEERING_KEYS = ("east_m", "north_m", "normal_height_m")


@dataclass(frozen=True)
class ControlPoint:
    """A named point: ``geodetic`` (lat_deg, lon_deg, ellipsoidal height m) or ``engineering``
    (east m, north m, normal height m); exactly one of the two is set."""

    name: str
    geodetic: tuple[float, float, float] | None = None
    engineering: tuple[float, float, float] | None = None

    def to_settings(self) -> dict[str, float]:
        keys, values = (GEODETIC_KEYS, self.geodetic) if self.geodetic is not None else (ENGINEERING_KEYS,
                                                                                         self.engineering)
        return dict(zip(keys, values))


@dataclass(frozen=True)
class ResolvedPoint:
    """A control point in the CRS's datum: latitude/longitude [rad] and ellipsoidal height [m] on
    its ellipsoid, and how it was obtained (for the processing log)."""

    name: str
    lat_rad: float
    lon_rad: float
    height_m: float
    derivation: Phrase
    warnings: tuple[Phrase, ...] = ()  # e.g. the height anomaly extrapolated at the point


def parse_control_points(table: Any, key_path: str, problems: list[str]) -> tuple[ControlPoint, ...]:
    """Validate ``[<key_path>.<name>]`` tables; every problem with its key path goes to ``problems``."""
    if not isinstance(table, dict):
        problems.append(Phrase("{key_path}: expected tables [{key_path}.<name>]", {"key_path": key_path}))
        return ()
    points = []
    for name, entry in table.items():
        key = f"{key_path}.{name}"
        if not isinstance(entry, dict):
            problems.append(Phrase("{key}: expected a table with {geodetic_keys} or {engineering_keys}", {"key": key, "geodetic_keys": list(GEODETIC_KEYS), "engineering_keys": list(ENGINEERING_KEYS)}))
            continue
        unknown = [k for k in entry if k not in GEODETIC_KEYS + ENGINEERING_KEYS]
        for k in unknown:
            problems.append(Phrase("{key}.{k}: unknown key (expected {geodetic_keys} or "
                            "{engineering_keys})", {"key": key, "k": k, "geodetic_keys": list(GEODETIC_KEYS), "engineering_keys": list(ENGINEERING_KEYS)}))
        kinds = [keys for keys in (GEODETIC_KEYS, ENGINEERING_KEYS) if any(k in entry for k in keys)]
        if len(kinds) != 1:
            problems.append(Phrase("{key}: give either {geodetic_keys} (geodetic) or "
                            "{engineering_keys} (engineering system)", {"key": key, "geodetic_keys": list(GEODETIC_KEYS), "engineering_keys": list(ENGINEERING_KEYS)}))
            continue
        keys = kinds[0]
        values = []
        for k in keys:
            value = entry.get(k)
            if value is None:
                problems.append(Phrase("{key}.{k}: missing", {"key": key, "k": k}))
            elif isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                problems.append(Phrase("{key}.{k}: expected a number, found {value!r}", {"key": key, "k": k, "value": value}))
            else:
                values.append(float(value))
        if len(values) != 3:
            continue
        if keys is GEODETIC_KEYS and not (abs(values[0]) <= 90.0 and abs(values[1]) <= 180.0):
            problems.append(Phrase("{key}: latitude {lat} / longitude {lon} out of range (degrees)", {"key": key, "lat": values[0], "lon": values[1]}))
            continue
        point = ControlPoint(name, geodetic=tuple(values)) if keys is GEODETIC_KEYS else ControlPoint(
            name, engineering=tuple(values))
        points.append(point)
    return tuple(points)


def resolve_control_point(point: ControlPoint, crs: EngineeringCRS,
                          height_fit: HeightAnomalyFit | None) -> ResolvedPoint:
    """The point on the ellipsoid (see the module docstring for the height path)."""
    if point.geodetic is not None:
        lat, lon, h = math.radians(point.geodetic[0]), math.radians(point.geodetic[1]), point.geodetic[2]
        derivation = Phrase("geodetic coordinates from the project")
        warnings = ()
    else:
        east, north, normal_height = point.engineering
        lat_a, lon_a = crs.to_geodetic(east, north)
        lat, lon = float(lat_a), float(lon_a)
        if height_fit is not None:
            zeta = float(np.asarray(height_fit.zeta_m(np.array([east]), np.array([north])))[0])
            derivation = Phrase("engineering E/N through the CRS; h = H + zeta = {normal_m:.4f} m {zeta_m:+.4f} m (height "
                                "anomaly model {model})",
                                {"normal_m": normal_height, "zeta_m": zeta, "model": height_fit.model_name})
            try:  # a surface model says when the point lies outside the benchmarks' hull
                warnings = tuple(Phrase("control point {point}: {warning}", {"point": point.name, "warning": w})
                                 for w in height_fit.warnings_for(np.array([east]), np.array([north])))
            except GeodesyError:  # a spline in chainage: the point's chainage is not known here
                warnings = ()
        else:
            zeta, warnings = 0.0, ()
            derivation = Phrase("engineering E/N through the CRS; no benchmarks in the project: H taken as ellipsoidal")
        h = normal_height + zeta
    return ResolvedPoint(point.name, lat, lon, h, derivation, warnings)
