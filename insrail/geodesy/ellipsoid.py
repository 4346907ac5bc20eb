"""The one earth ellipsoid type of the package, and the named ellipsoids a project may choose.

An :class:`Ellipsoid` is built once, from the project's engineering CRS
(:attr:`insrail.geodesy.crs.EngineeringCRS.reference_ellipsoid`), and handed as an object to
every stage that needs it: the fusion (radii of curvature, normal gravity, earth rate), the
track stage (lever arms through ECEF), the control points, the simulator. Nothing passes an
ellipsoid by name; a name is looked up once, here (:data:`ELLIPSOIDS`), or a custom ellipsoid
is given by its semi-major axis and inverse flattening (``ellipsoid = "custom"``, ``a_m``,
``inverse_flattening`` in ``[geodesy.crs]``).

Which ellipsoid the geodetic coordinates are on (the datum): the GNSS positions are taken as
geodetic coordinates in the engineering CRS's datum, so the fusion, the rails and the
projection all work on the CRS's ellipsoid and no datum step is made anywhere. That holds for
the usual railway survey: the GNSS base stands on a network point (CPI/CPII) whose coordinates
are given in that datum (``[geodesy.control_points]``), and the rover's relative solution is
the base's coordinates plus the baseline. A solution in another frame (PPP or a CORS network in
ITRF/WGS84/CGCS2000 while the CRS is on Xian80 or Krassovsky, two non-geocentric datums) lies
tens of metres off in that datum: it needs common points in ``[geodesy.local]`` (a 4- or
7-parameter fit onto the railway's grid), see docs/formats.md. A base solution computed with
WGS84's formulas (RTKLIB) reads baselines longer by :func:`wgs84_baseline_scale_ppm` in a datum
with another semi-major axis: beyond 1 ppm (Krassovsky: 17 ppm, 85 mm at 5 km from the base) the
processing says so in a notice.

The normal gravity field keeps the WGS84 defining constants (GM, omega, gamma at equator and
pole) whatever the geometric ellipsoid: on Xian80 or Krassovsky that changes normal gravity by
less than 1e-5 m/s^2, far below an IMU's accelerometer bias.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Ellipsoid:
    """An earth ellipsoid with the constants the navigation needs."""

    name: str
    a: float  #: semi-major axis [m]
    inverse_flattening: float  #: 1/f, the defining constant as published
    gm: float = 3.986004418e14  #: geocentric gravitational constant [m^3/s^2]
    omega: float = 7.292115e-5  #: earth rotation rate [rad/s] (WGS84 defining value)
    gamma_e: float = 9.7803253359  #: normal gravity at the equator [m/s^2]
    gamma_p: float = 9.8321849378  #: normal gravity at the pole [m/s^2]

    @property
    def f(self) -> float:
        """Flattening."""
        return 1.0 / self.inverse_flattening

    @property
    def b(self) -> float:
        return self.a * (1.0 - self.f)

    @property
    def e2(self) -> float:
        return self.f * (2.0 - self.f)

    @property
    def m(self) -> float:
        """omega^2 a^2 b / GM, used in the height correction of normal gravity."""
        return self.omega**2 * self.a**2 * self.b / self.gm

    @property
    def k_somigliana(self) -> float:
        return (self.b * self.gamma_p) / (self.a * self.gamma_e) - 1.0

    def describe(self) -> str:
        """Name and defining constants, for reports and error messages."""
        return f"{self.name} (a = {self.a:.3f} m, 1/f = {self.inverse_flattening:.9g})"


WGS84 = Ellipsoid("WGS84", 6378137.0, 298.257223563)
#: CGCS2000 differs from WGS84 only in the flattening (0.1 mm in b).
CGCS2000 = Ellipsoid("CGCS2000", 6378137.0, 298.257222101)
#: Beijing 1954.
KRASSOVSKY = Ellipsoid("Krassovsky", 6378245.0, 298.3)
#: IAG 1975, Xi'an 1980.
XIAN80 = Ellipsoid("Xian80", 6378140.0, 298.257)

def wgs84_baseline_scale_ppm(ellipsoid: Ellipsoid) -> float:
    """How much longer [ppm] a GNSS baseline computed with WGS84's formulas reads in a datum on
    ``ellipsoid`` when the base's coordinates in that datum are carried over (see the module
    docstring): (a / a_WGS84 - 1), 0.5 ppm on Xian80, 17 ppm on Krassovsky."""
    return (ellipsoid.a / WGS84.a - 1.0) * 1e6


#: The named ellipsoids a project may choose (``[geodesy.crs] ellipsoid``), by name.
ELLIPSOIDS: dict[str, Ellipsoid] = {ell.name: ell for ell in (CGCS2000, WGS84, KRASSOVSKY, XIAN80)}
