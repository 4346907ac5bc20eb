"""Compiled (numba) ECEF -> geodetic conversion, point by point: what
:func:`insrail.nav.earth.ecef_to_geodetic` computes, the same operations on each point in the
same order (the same doubles as numpy's whole-array version of the formulae: tested), without
numpy's temporary arrays (the track's rails convert three points per trajectory epoch)."""

from __future__ import annotations

import math

from insrail.jit import cached_njit


@cached_njit(nogil=True, error_model="numpy")
def ecef_to_geodetic_points(x, y, z, a, b, e2, lat_out, lon_out, h_out):
    """Bowring's start and four fixed-point iterations (:func:`insrail.nav.earth.ecef_to_geodetic`)
    of the points (x, y, z) [m] into lat_out, lon_out [rad] and h_out [m], ended at the first
    latitude that gives itself again, whose height the iteration has just computed (the same
    doubles as all four: each iteration depends on the latitude alone)."""
    ep2 = e2 / (1.0 - e2)
    for i in range(x.shape[0]):
        xi, yi, zi = x[i], y[i], z[i]
        p = math.hypot(xi, yi)
        beta = math.atan2(zi * a, p * b)
        lat = math.atan2(zi + ep2 * b * math.sin(beta) ** 3.0, p - e2 * a * math.cos(beta) ** 3.0)
        for _ in range(4):
            r_n = a / math.sqrt(1.0 - e2 * math.sin(lat) ** 2.0)
            h = p * math.cos(lat) + zi * math.sin(lat) - a**2.0 / r_n
            before, lat = lat, math.atan2(zi, p * (1.0 - e2 * r_n / (r_n + h)))
            if lat == before:  # a fixed point: the iterations left give it again (most points: after the first)
                break  # and h is already the height at it
        else:
            r_n = a / math.sqrt(1.0 - e2 * math.sin(lat) ** 2.0)
            h = p * math.cos(lat) + zi * math.sin(lat) - a**2.0 / r_n
        lat_out[i] = lat
        lon_out[i] = math.atan2(yi, xi)
        h_out[i] = h
