"""The compiled ECEF -> geodetic conversion against the whole-array numpy formulae it replaced."""

import numpy as np

from insrail.nav import earth


def numpy_ecef_to_geodetic(xyz, ell):
    """The reference: Bowring's start and four fixed-point iterations on whole arrays."""
    x, y, z = xyz[..., 0], xyz[..., 1], xyz[..., 2]
    e2 = ell.e2
    lon = np.arctan2(y, x)
    p = np.hypot(x, y)
    b = ell.b
    ep2 = e2 / (1.0 - e2)
    beta = np.arctan2(z * ell.a, p * b)
    lat = np.arctan2(z + ep2 * b * np.sin(beta) ** 3, p - e2 * ell.a * np.cos(beta) ** 3)
    for _ in range(4):
        _, r_n = earth.radii(lat, ell)
        h = p * np.cos(lat) + z * np.sin(lat) - ell.a**2 / r_n
        lat = np.arctan2(z, p * (1.0 - e2 * r_n / (r_n + h)))
    _, r_n = earth.radii(lat, ell)
    h = p * np.cos(lat) + z * np.sin(lat) - ell.a**2 / r_n
    return lat, lon, h


def test_ecef_to_geodetic_is_the_numpy_formulae_to_the_last_bit():
    """The same formulae in the same order: the kernel's libm calls and numpy's agree to the bit where numpy
    runs the same scalar routines, and to one unit in the last place where it has vector routines of its own
    (AVX-512 builds of sin, cos and arctan2 differ from libm in some 4 % of values by one ulp). The height, a
    difference of numbers the size of the Earth's radius, then differs by that radius's last bit (2e-9 m)."""
    rng = np.random.default_rng(7)
    n = 20_000
    lat = np.concatenate([rng.uniform(-np.pi / 2, np.pi / 2, n), rng.uniform(0.3, 0.8, n)])
    lon = np.concatenate([rng.uniform(-np.pi, np.pi, n), rng.uniform(1.8, 2.2, n)])
    h = np.concatenate([rng.uniform(-500.0, 9000.0, n), rng.uniform(0.0, 100.0, n)])
    for ell in (earth.WGS84, earth.CGCS2000):
        xyz = earth.geodetic_to_ecef(lat, lon, h, ell)
        (lat_got, lon_got, h_got), (lat_want, lon_want, h_want) = (earth.ecef_to_geodetic(xyz, ell),
                                                                    numpy_ecef_to_geodetic(xyz, ell))
        np.testing.assert_array_max_ulp(lat_got, lat_want, maxulp=1)
        np.testing.assert_array_max_ulp(lon_got, lon_want, maxulp=1)
        np.testing.assert_allclose(h_got, h_want, rtol=0.0, atol=2.0 * np.spacing(ell.a))


def test_ecef_to_geodetic_keeps_the_shape_and_gives_numbers_for_one_point():
    xyz = earth.geodetic_to_ecef(np.full((2, 3), 0.5), np.full((2, 3), 2.0), np.full((2, 3), 40.0))
    lat, lon, h = earth.ecef_to_geodetic(xyz)
    assert lat.shape == lon.shape == h.shape == (2, 3)
    one = earth.ecef_to_geodetic(xyz[0, 0])
    assert all(np.ndim(value) == 0 for value in one)
    np.testing.assert_allclose(one, (0.5, 2.0, 40.0), atol=1e-9)


def test_ecef_to_geodetic_ends_at_the_fixed_point_with_the_doubles_of_all_four_iterations():
    """The kernel stops iterating at the first latitude that gives itself again: the same doubles as
    all four iterations, compiled the same way (numba; Python's ``math`` rounds the powers
    differently), for points near the surface (most converged after one iteration, a few
    alternating between neighbouring doubles)."""
    import math

    from numba import njit

    @njit(error_model="numpy")
    def four_iterations(x, y, z, a, b, e2, out):
        ep2 = e2 / (1.0 - e2)
        for i in range(x.shape[0]):
            p = math.hypot(x[i], y[i])
            beta = math.atan2(z[i] * a, p * b)
            lat = math.atan2(z[i] + ep2 * b * math.sin(beta) ** 3.0, p - e2 * a * math.cos(beta) ** 3.0)
            for _ in range(4):
                r_n = a / math.sqrt(1.0 - e2 * math.sin(lat) ** 2.0)
                h = p * math.cos(lat) + z[i] * math.sin(lat) - a**2.0 / r_n
                lat = math.atan2(z[i], p * (1.0 - e2 * r_n / (r_n + h)))
            r_n = a / math.sqrt(1.0 - e2 * math.sin(lat) ** 2.0)
            out[i] = lat, math.atan2(y[i], x[i]), p * math.cos(lat) + z[i] * math.sin(lat) - a**2.0 / r_n

    rng = np.random.default_rng(11)
    n = 20_000
    ell = earth.CGCS2000
    xyz = earth.geodetic_to_ecef(rng.uniform(0.3, 0.8, n), rng.uniform(1.8, 2.2, n), rng.uniform(0.0, 100.0, n), ell)
    want = np.empty((n, 3))
    four_iterations(*(np.ascontiguousarray(xyz[:, k]) for k in range(3)), ell.a, ell.b, ell.e2, want)
    np.testing.assert_array_equal(np.column_stack(earth.ecef_to_geodetic(xyz, ell)), want)
