"""Reference ellipsoid, radii of curvature, normal gravity and frame rates.

All functions are vectorised over numpy arrays. Latitude ``lat`` and longitude
``lon`` are geodetic, in radians; heights ``h`` are ellipsoidal, in metres.
The ellipsoid is an :class:`insrail.geodesy.ellipsoid.Ellipsoid` object (the
project's, from its CRS; which datum that is: that module's docstring). The gravity
model is the WGS84 Somigliana normal gravity with the second-order free-air height
correction; its direction is taken along the ellipsoid normal
(n-frame z, down), the usual convention for strapdown navigation, deflection of
the vertical being ignored (thesis 2.4.1.3).
"""

from __future__ import annotations

import numpy as np

# The one ellipsoid type of the package (geodesy's): the fusion takes the project's as an object.
from insrail.geodesy.ellipsoid import CGCS2000, WGS84, Ellipsoid

__all__ = ["CGCS2000", "WGS84", "Ellipsoid", "dcm_ecef_from_ned", "earth_rate_ned", "ecef_to_geodetic",
           "geodetic_to_ecef", "gravity_ned", "ned_to_geodetic_delta", "normal_gravity", "radii", "transport_rate_ned"]


def radii(lat, ell: Ellipsoid = WGS84):
    """Meridian radius R_M and prime-vertical radius R_N [m] (thesis 2.8, 2.9)."""
    s2 = np.sin(lat) ** 2
    w = 1.0 - ell.e2 * s2
    r_n = ell.a / np.sqrt(w)
    r_m = ell.a * (1.0 - ell.e2) / (w * np.sqrt(w))
    return r_m, r_n


def normal_gravity(lat, h, ell: Ellipsoid = WGS84):
    """Magnitude of normal gravity [m/s^2] at geodetic latitude and ellipsoidal height."""
    s2 = np.sin(lat) ** 2
    g0 = ell.gamma_e * (1.0 + ell.k_somigliana * s2) / np.sqrt(1.0 - ell.e2 * s2)
    a = ell.a
    return g0 * (1.0 - 2.0 * h / a * (1.0 + ell.f + ell.m - 2.0 * ell.f * s2) + 3.0 * h**2 / a**2)


def gravity_ned(lat, h, ell: Ellipsoid = WGS84):
    """Normal gravity vector in the n-frame, shape (..., 3): [0, 0, g]."""
    g = np.asarray(normal_gravity(lat, h, ell), dtype=float)
    out = np.zeros(g.shape + (3,))
    out[..., 2] = g
    return out


def earth_rate_ned(lat, ell: Ellipsoid = WGS84):
    """omega_ie^n [rad/s], shape (..., 3) (thesis 2.6)."""
    lat = np.asarray(lat, dtype=float)
    out = np.zeros(lat.shape + (3,))
    out[..., 0] = ell.omega * np.cos(lat)
    out[..., 2] = -ell.omega * np.sin(lat)
    return out


def transport_rate_ned(lat, h, vel_ned, ell: Ellipsoid = WGS84):
    """omega_en^n [rad/s] from NED ground velocity, shape (..., 3) (thesis 2.7)."""
    vel_ned = np.asarray(vel_ned, dtype=float)
    r_m, r_n = radii(lat, ell)
    out = np.empty(np.broadcast_shapes(np.shape(lat), vel_ned.shape[:-1]) + (3,))
    out[..., 0] = vel_ned[..., 1] / (r_n + h)
    out[..., 1] = -vel_ned[..., 0] / (r_m + h)
    out[..., 2] = -vel_ned[..., 1] * np.tan(lat) / (r_n + h)
    return out


def geodetic_to_ecef(lat, lon, h, ell: Ellipsoid = WGS84):
    """Geodetic (rad, rad, m) to ECEF, shape (..., 3) [m]."""
    lat = np.asarray(lat, dtype=float)
    _, r_n = radii(lat, ell)
    cl = np.cos(lat)
    out = np.empty(np.broadcast_shapes(lat.shape, np.shape(lon), np.shape(h)) + (3,))
    out[..., 0] = (r_n + h) * cl * np.cos(lon)
    out[..., 1] = (r_n + h) * cl * np.sin(lon)
    out[..., 2] = (r_n * (1.0 - ell.e2) + h) * np.sin(lat)
    return out


def ecef_to_geodetic(xyz, ell: Ellipsoid = WGS84):
    """ECEF (..., 3) [m] to geodetic (lat [rad], lon [rad], h [m]).

    Bowring's starting value then fixed-point iteration; for points within a few
    hundred km of the surface four iterations reach 1e-12 rad and 1e-9 m. Compiled, point by
    point (:mod:`insrail.nav._ecef_kernels`).
    """
    from insrail.nav._ecef_kernels import ecef_to_geodetic_points  # compiled: imported when first needed

    xyz = np.asarray(xyz, dtype=float)
    shape = xyz.shape[:-1]
    points = xyz.reshape(-1, 3)
    lat, lon, h = (np.empty(points.shape[0]) for _ in range(3))
    ecef_to_geodetic_points(np.ascontiguousarray(points[:, 0]), np.ascontiguousarray(points[:, 1]),
                            np.ascontiguousarray(points[:, 2]), ell.a, ell.b, ell.e2, lat, lon, h)
    if not shape:  # one point: numbers, as numpy's scalar arithmetic gives them
        return lat[0], lon[0], h[0]
    return lat.reshape(shape), lon.reshape(shape), h.reshape(shape)


def dcm_ecef_from_ned(lat, lon):
    """C_n^e, shape (..., 3, 3) (thesis 2.4)."""
    lat = np.asarray(lat, dtype=float)
    lon = np.asarray(lon, dtype=float)
    sl, cl = np.sin(lat), np.cos(lat)
    so, co = np.sin(lon), np.cos(lon)
    c = np.empty(np.broadcast_shapes(lat.shape, lon.shape) + (3, 3))
    c[..., 0, 0] = -sl * co
    c[..., 0, 1] = -so
    c[..., 0, 2] = -cl * co
    c[..., 1, 0] = -sl * so
    c[..., 1, 1] = co
    c[..., 1, 2] = -cl * so
    c[..., 2, 0] = cl
    c[..., 2, 1] = 0.0
    c[..., 2, 2] = -sl
    return c


def ned_to_geodetic_delta(d_ned, lat, h, ell: Ellipsoid = WGS84):
    """Small NED displacement [m] to (dlat, dlon, dh) [rad, rad, m] (thesis D_R^-1)."""
    d_ned = np.asarray(d_ned, dtype=float)
    r_m, r_n = radii(lat, ell)
    return (d_ned[..., 0] / (r_m + h), d_ned[..., 1] / ((r_n + h) * np.cos(lat)), -d_ned[..., 2])
