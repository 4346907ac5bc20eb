"""Engineering plane coordinate systems: transverse Mercator zones with a projection height.

Railway control networks (CPI/CPII/CPIII) live in an engineering plane system chosen so
that a length measured on the track's height is distorted by at most 10 mm/km on the
grid (TB 10601): a Gauss-Krüger (transverse Mercator) zone with its own central
meridian, and a *projection height* H0 that moves the mapping surface up to the track.
Two conventions for H0 are in use and give northings that differ by decimetres, so the
convention is always an explicit parameter, never guessed:

* ``"scale_factor"``: the central scale factor becomes ``k * (1 + H0 / R)`` with a mean
  earth radius R (``mean_radius_m``, 6 371 000 m unless the project says otherwise);
* ``"semi_major_axis"``: the "expanded ellipsoid" (thesis §5.3.2.1, 膨胀椭球): the
  semi-major axis becomes ``a + H0`` with the flattening kept, latitude and longitude
  carried over unchanged.

``projection_height_m`` is the *ellipsoidal* height of the projection surface. Projects
that quote a normal height H0 and a mean height anomaly ζ0 enter H0 + ζ0.

Coordinates: latitude/longitude in radians (geodetic, on the CRS's ellipsoid), easting
and northing in metres, always in (east, north) order whatever the EPSG axis order.
The projection is PROJ's exact transverse Mercator (Poder/Engsager), so geodetic ->
plane -> geodetic round trips agree to nanometres within a zone.

Meridian convergence γ is *grid north minus true north*: the azimuth of grid north
measured clockwise from true (geodetic) north. East of the central meridian in the
northern hemisphere γ > 0, and a grid azimuth is ``geodetic azimuth - γ``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, fields
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np

from insrail.geodesy._validation import Problems
from insrail.geodesy.ellipsoid import ELLIPSOIDS, Ellipsoid
from insrail.geodesy.errors import GeodesyError, SettingsError

if TYPE_CHECKING:
    from pyproj import CRS, Proj, Transformer

# pyproj is imported where PROJ is asked: the project model holds an EngineeringCRS, and commands that
# only read a project's results (insrail report) would pay for pyproj's imports otherwise.

CUSTOM_ELLIPSOID = "custom"
PROJECTION_HEIGHT_CONVENTIONS = ("scale_factor", "semi_major_axis")
DEFAULT_MEAN_RADIUS_M = 6_371_000.0
#: EPSG method code of "Transverse Mercator" (Gauss-Krüger and UTM zones use it).
_EPSG_METHOD_TRANSVERSE_MERCATOR = 9807

# Plausible ranges; anything outside is a typo or a unit mix-up (mm, feet, gon...).
_SEMI_MAJOR_RANGE_M = (6_300_000.0, 6_400_000.0)
_INVERSE_FLATTENING_RANGE = (250.0, 350.0)
_SCALE_FACTOR_RANGE = (0.99, 1.01)
_FALSE_EASTING_RANGE_M = (-1e7, 1e8)  # zone prefixes reach 45 500 000 m
_FALSE_NORTHING_RANGE_M = (-2e7, 2e7)
_PROJECTION_HEIGHT_RANGE_M = (-1000.0, 9000.0)
_MEAN_RADIUS_RANGE_M = (6_350_000.0, 6_400_000.0)
_MAX_DEGREES_FROM_CENTRAL_MERIDIAN = 10.0

_DEFAULTS = {
    "ellipsoid": "CGCS2000",
    "latitude_of_origin_deg": 0.0,
    "scale_factor": 1.0,
    "false_easting_m": 500000.0,
    "false_northing_m": 0.0,
    "projection_height_m": 0.0,
    "projection_height_convention": "scale_factor",
    "mean_radius_m": DEFAULT_MEAN_RADIUS_M,
}


@dataclass(frozen=True)
class EngineeringCRS:
    """A transverse Mercator engineering plane system, or an EPSG transverse Mercator zone.

    Either give ``epsg`` alone (e.g. 4549 = CGCS2000 3° Gauss-Krüger CM 120E; the other
    fields are then filled from the EPSG definition), or ``central_meridian_deg`` and the
    rest of the zone. ``a_m`` and ``inverse_flattening`` are used only with
    ``ellipsoid="custom"``; ``mean_radius_m`` only with the ``"scale_factor"``
    projection-height convention. Invalid values raise ``SettingsError`` listing every
    problem.
    """

    ellipsoid: str = "CGCS2000"
    central_meridian_deg: float | None = None
    latitude_of_origin_deg: float = 0.0
    scale_factor: float = 1.0
    false_easting_m: float = 500000.0
    false_northing_m: float = 0.0
    projection_height_m: float = 0.0
    projection_height_convention: str = "scale_factor"
    mean_radius_m: float = DEFAULT_MEAN_RADIUS_M
    a_m: float | None = None
    inverse_flattening: float | None = None
    epsg: int | None = None

    def __post_init__(self) -> None:
        if self.epsg is not None:
            for name, value in _fields_from_epsg(self).items():
                object.__setattr__(self, name, value)
        problems = Problems()
        _check_values({f.name: getattr(self, f.name) for f in fields(self)}, problems)
        problems.raise_if_any()

    # -- settings ---------------------------------------------------------------------
    def to_settings(self) -> dict[str, Any]:
        """Plain dict for the project TOML; ``from_settings(to_settings())`` gives an equal CRS."""
        if self.epsg is not None:
            return {"epsg": self.epsg}
        out: dict[str, Any] = {"ellipsoid": self.ellipsoid}
        if self.ellipsoid == CUSTOM_ELLIPSOID:
            out["a_m"] = self.a_m
            out["inverse_flattening"] = self.inverse_flattening
        out.update(
            central_meridian_deg=self.central_meridian_deg,
            latitude_of_origin_deg=self.latitude_of_origin_deg,
            scale_factor=self.scale_factor,
            false_easting_m=self.false_easting_m,
            false_northing_m=self.false_northing_m,
            projection_height_m=self.projection_height_m,
            projection_height_convention=self.projection_height_convention,
        )
        if self.projection_height_convention == "scale_factor":
            out["mean_radius_m"] = self.mean_radius_m
        return out

    @classmethod
    def from_settings(cls, settings: Mapping[str, Any], key_path: str = "geodesy.crs") -> EngineeringCRS:
        """Build from a settings table, reporting every problem with its key path at once."""
        problems = Problems(key_path)
        if not problems.check_mapping(settings):
            problems.raise_if_any()
        problems.unknown_keys(settings, [f.name for f in fields(cls)])
        if "epsg" in settings:
            extra = sorted(k for k in settings if k != "epsg" and k in {f.name for f in fields(cls)})
            if extra:
                problems.add("epsg", "an EPSG zone defines the whole projection; remove "
                             + ", ".join(extra) + " or remove epsg")
        elif "central_meridian_deg" not in settings:
            problems.add("central_meridian_deg", "missing; give the zone's central meridian in degrees "
                         "(or an epsg code instead)")
        _check_values(dict(settings), problems)
        problems.raise_if_any()
        try:
            return cls(**{k: settings[k] for k in settings})
        except SettingsError as err:  # EPSG look-up problems found only on construction
            raise SettingsError([problems.path(p) for p in err.problems]) from None

    # -- pyproj objects (built lazily, dropped when pickled) ---------------------------
    @property
    def reference_ellipsoid(self) -> Ellipsoid:
        """The CRS's ellipsoid as the one object every stage takes (fusion, rails, control points)."""
        if self.ellipsoid in ELLIPSOIDS:
            return ELLIPSOIDS[self.ellipsoid]
        return Ellipsoid(self.ellipsoid, float(self.a_m), float(self.inverse_flattening))

    @property
    def semi_major_axis_m(self) -> float:
        return self.reference_ellipsoid.a

    @property
    def inverse_flattening_value(self) -> float:
        return self.reference_ellipsoid.inverse_flattening

    @property
    def effective_scale_factor(self) -> float:
        """Central scale factor PROJ uses, projection height included for ``"scale_factor"``."""
        if self.projection_height_convention == "scale_factor":
            return self.scale_factor * (1.0 + self.projection_height_m / self.mean_radius_m)
        return self.scale_factor

    @property
    def projection_semi_major_axis_m(self) -> float:
        """Semi-major axis PROJ uses, projection height included for ``"semi_major_axis"``."""
        if self.projection_height_convention == "semi_major_axis":
            return self.semi_major_axis_m + self.projection_height_m
        return self.semi_major_axis_m

    @cached_property
    def pyproj_crs(self) -> CRS:
        """The projected CRS as pyproj sees it (with the projection height folded in)."""
        from pyproj import CRS

        if self.epsg is not None:
            return CRS.from_epsg(self.epsg)
        return CRS.from_proj4(
            f"+proj=tmerc +lat_0={self.latitude_of_origin_deg!r} +lon_0={self.central_meridian_deg!r} "
            f"+k={self.effective_scale_factor!r} +x_0={self.false_easting_m!r} +y_0={self.false_northing_m!r} "
            f"+a={self.projection_semi_major_axis_m!r} +rf={self.inverse_flattening_value!r} +units=m +no_defs"
        )

    @cached_property
    def _transformer(self) -> Transformer:
        # Geographic CRS on the *projection's* ellipsoid: latitude/longitude pass through
        # unchanged (the expanded-ellipsoid convention), and PROJ sees one datum, so no
        # datum step - in particular no silent "ballpark" - can sneak in.
        from pyproj import Transformer

        transformer = Transformer.from_crs(self.pyproj_crs.geodetic_crs, self.pyproj_crs, always_xy=True)
        if "ballpark" in transformer.description.lower():
            raise GeodesyError(f"PROJ offers only a ballpark transformation for {self.describe()}: "
                               f"{transformer.description}")
        return transformer

    @cached_property
    def _proj(self) -> Proj:
        from pyproj import Proj

        return Proj(self.pyproj_crs)

    def __getstate__(self) -> dict[str, Any]:
        return {f.name: getattr(self, f.name) for f in fields(self)}

    def __setstate__(self, state: dict[str, Any]) -> None:
        for name, value in state.items():
            object.__setattr__(self, name, value)

    def describe(self) -> str:
        """One line a surveyor recognises, for reports and error messages."""
        if self.epsg is not None:
            return f"EPSG:{self.epsg} ({self.pyproj_crs.name})"
        ellipsoid = self.ellipsoid if self.ellipsoid in ELLIPSOIDS else self.reference_ellipsoid.describe()
        return (f"TM {ellipsoid} CM {self.central_meridian_deg:g}° k {self.scale_factor:.9g} "
                f"FE {self.false_easting_m:.3f} FN {self.false_northing_m:.3f} "
                f"H0 {self.projection_height_m:.3f} m ({self.projection_height_convention})")

    # -- conversions --------------------------------------------------------------------
    def to_plane(self, lat_rad, lon_rad) -> tuple[np.ndarray, np.ndarray]:
        """Geodetic latitude/longitude [rad] to (east_m, north_m)."""
        lat, lon = _as_float_arrays(lat_rad, lon_rad)
        self._require_near_central_meridian(lon)
        east, north = self._transformer.transform(lon, lat, radians=True)
        _require_finite_where_input_is(east, north, lat, lon, "project", "latitude/longitude")
        return np.asarray(east, dtype=float), np.asarray(north, dtype=float)

    def _require_near_central_meridian(self, lon: np.ndarray) -> None:
        # PROJ's exact tmerc happily maps half the globe; an engineering zone used tens of
        # degrees off its meridian (distortion of percent) means a wrong central meridian.
        # the angle to the meridian wrapped into [-180°, 180°) (a remainder: the track's rails ask this
        # of three points per trajectory epoch, a complex exponential took five times as long)
        offset = np.degrees(np.abs(np.remainder(lon - math.radians(self.central_meridian_deg) + math.pi, 2 * math.pi)
                                   - math.pi))
        far = np.isfinite(offset) & (offset > _MAX_DEGREES_FROM_CENTRAL_MERIDIAN)
        if far.any():
            raise GeodesyError(f"{int(far.sum())} point(s) lie up to {offset[far].max():.2f}° from the central "
                               f"meridian {self.central_meridian_deg:g}° of {self.describe()}; a transverse "
                               f"Mercator zone is usable within a few degrees (limit "
                               f"{_MAX_DEGREES_FROM_CENTRAL_MERIDIAN:g}°): check the central meridian and that "
                               "longitudes are in radians")

    def to_geodetic(self, east_m, north_m) -> tuple[np.ndarray, np.ndarray]:
        """(east_m, north_m) to geodetic latitude/longitude [rad]."""
        east, north = _as_float_arrays(east_m, north_m)
        lon, lat = self._transformer.transform(east, north, radians=True, direction="INVERSE")
        _require_finite_where_input_is(lat, lon, east, north, "unproject", "easting/northing")
        return np.asarray(lat, dtype=float), np.asarray(lon, dtype=float)

    def point_scale_factor(self, lat_rad, lon_rad) -> np.ndarray:
        """Grid length / length on the reference ellipsoid, at each point (conformal: any direction)."""
        lat, lon = _as_float_arrays(lat_rad, lon_rad)
        factors = self._proj.get_factors(lon, lat, radians=True)
        # For the expanded ellipsoid PROJ reports the scale against the enlarged surface;
        # lengths on it are (a + H0)/a times those on the reference ellipsoid.
        enlargement = self.projection_semi_major_axis_m / self.semi_major_axis_m
        return np.asarray(factors.meridional_scale, dtype=float) * enlargement

    def meridian_convergence_rad(self, lat_rad, lon_rad) -> np.ndarray:
        """γ = grid north minus true north [rad] (see module docstring for the sign)."""
        lat, lon = _as_float_arrays(lat_rad, lon_rad)
        factors = self._proj.get_factors(lon, lat, radians=True)
        return np.radians(np.asarray(factors.meridian_convergence, dtype=float))

    def length_distortion_mm_per_km(self, lat_rad, lon_rad, h_m) -> np.ndarray:
        """Grid length minus ground length [mm per km], for a horizontal length at ellipsoidal height h.

        A ground length at height h shrinks by R / (R + h) onto the reference ellipsoid
        (R = Gaussian mean radius sqrt(M N) at the point), then the projection scales it by
        the point scale factor. TB 10601 asks for |distortion| <= 10 mm/km on the track.
        """
        lat, lon = _as_float_arrays(lat_rad, lon_rad)
        h = np.asarray(h_m, dtype=float)
        a = self.semi_major_axis_m
        e2 = (2.0 - 1.0 / self.inverse_flattening_value) / self.inverse_flattening_value
        w = 1.0 - e2 * np.sin(lat) ** 2
        gaussian_radius = a * np.sqrt(1.0 - e2) / w
        combined = self.point_scale_factor(lat, lon) * gaussian_radius / (gaussian_radius + h)
        return (combined - 1.0) * 1e6


def _as_float_arrays(*values) -> list[np.ndarray]:
    arrays = [np.asarray(v, dtype=float) for v in values]
    try:
        shape = np.broadcast_shapes(*(a.shape for a in arrays))
    except ValueError:
        raise GeodesyError("coordinate arrays have incompatible shapes "
                           + " and ".join(str(a.shape) for a in arrays)) from None
    return [np.broadcast_to(a, shape) for a in arrays]


def _require_finite_where_input_is(out_a, out_b, in_a, in_b, verb: str, what: str) -> None:
    bad = np.isfinite(in_a) & np.isfinite(in_b) & ~(np.isfinite(out_a) & np.isfinite(out_b))
    if np.any(bad):
        first = int(np.flatnonzero(bad.ravel())[0])
        raise GeodesyError(f"cannot {verb} {int(bad.sum())} point(s) (first at index {first}): "
                           f"{what} lie outside the transverse Mercator domain of this zone")


def _check_values(values: Mapping[str, Any], problems: Problems) -> None:
    """Range and consistency checks shared by construction and ``from_settings``."""
    if "epsg" in values and values["epsg"] is not None:
        epsg = values["epsg"]
        if isinstance(epsg, bool) or not isinstance(epsg, int):
            problems.add("epsg", f"expected an integer EPSG code such as 4549, got {epsg!r}")
        return
    ellipsoid = problems.choice(values, "ellipsoid", _DEFAULTS["ellipsoid"], [*ELLIPSOIDS, CUSTOM_ELLIPSOID])
    if ellipsoid == CUSTOM_ELLIPSOID:
        problems.number(values, "a_m", None, *_SEMI_MAJOR_RANGE_M, "m")
        problems.number(values, "inverse_flattening", None, *_INVERSE_FLATTENING_RANGE, "")
    elif ellipsoid is not None:
        for key in ("a_m", "inverse_flattening"):
            if values.get(key) is not None:
                problems.add(key, f"only used with ellipsoid = 'custom' (the {ellipsoid} constants are fixed)")
    if values.get("central_meridian_deg") is None:
        if "central_meridian_deg" in values:
            problems.add("central_meridian_deg", "missing; give the zone's central meridian in degrees "
                         "(or an epsg code instead)")
    else:
        problems.number(values, "central_meridian_deg", None, -180.0, 180.0, "degrees")
    problems.number(values, "latitude_of_origin_deg", 0.0, -89.0, 89.0, "degrees")
    problems.number(values, "scale_factor", 1.0, *_SCALE_FACTOR_RANGE, "")
    problems.number(values, "false_easting_m", 500000.0, *_FALSE_EASTING_RANGE_M, "m")
    problems.number(values, "false_northing_m", 0.0, *_FALSE_NORTHING_RANGE_M, "m")
    problems.number(values, "projection_height_m", 0.0, *_PROJECTION_HEIGHT_RANGE_M, "m")
    problems.choice(values, "projection_height_convention", "scale_factor", PROJECTION_HEIGHT_CONVENTIONS)
    problems.number(values, "mean_radius_m", DEFAULT_MEAN_RADIUS_M, *_MEAN_RADIUS_RANGE_M, "m")


def _fields_from_epsg(crs: EngineeringCRS) -> dict[str, Any]:
    """Field values of an EPSG transverse Mercator zone; conflicting explicit values raise."""
    import pyproj
    from pyproj import CRS
    from pyproj.exceptions import CRSError

    problems = Problems()
    _check_values({"epsg": crs.epsg}, problems)
    problems.raise_if_any()
    try:
        definition = CRS.from_epsg(crs.epsg)
    except CRSError:
        raise SettingsError([f"epsg: EPSG:{crs.epsg} is not in the PROJ database "
                             f"(pyproj {pyproj.__version__}, PROJ {pyproj.proj_version_str})"]) from None
    operation = definition.coordinate_operation if definition.is_projected else None
    if operation is None or operation.method_code != str(_EPSG_METHOD_TRANSVERSE_MERCATOR):
        kind = operation.method_name if operation is not None else "not a projected CRS"
        raise SettingsError([f"epsg: EPSG:{crs.epsg} ({definition.name}) is {kind}; an engineering "
                             "system must be a transverse Mercator (Gauss-Krüger/UTM) zone"])
    params = {int(p.code): p.value for p in operation.params if p.code}
    a, rf = definition.ellipsoid.semi_major_metre, definition.ellipsoid.inverse_flattening
    named = next((name for name, ell in ELLIPSOIDS.items()
                  if ell.a == a and abs(ell.inverse_flattening - rf) < 1e-9), None)
    from_epsg = {
        "ellipsoid": named or CUSTOM_ELLIPSOID,
        "a_m": None if named else a,
        "inverse_flattening": None if named else rf,
        "latitude_of_origin_deg": params[8801],
        "central_meridian_deg": params[8802],
        "scale_factor": params[8805],
        "false_easting_m": params[8806],
        "false_northing_m": params[8807],
        "projection_height_m": 0.0,
        "projection_height_convention": "scale_factor",
        "mean_radius_m": DEFAULT_MEAN_RADIUS_M,
    }
    for name, value in from_epsg.items():
        given = getattr(crs, name)
        default = _DEFAULTS.get(name)
        if given is not None and given != default and given != value:
            problems.add(name, f"{given!r} contradicts EPSG:{crs.epsg}, which defines {value!r}; "
                         "give epsg alone")
    problems.raise_if_any()
    return from_epsg
