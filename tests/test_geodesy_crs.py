"""EngineeringCRS: round trips, EPSG agreement, projection-height conventions, factors, settings."""

import math
import pickle

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from pyproj import Transformer

from insrail.geodesy import ELLIPSOIDS, EngineeringCRS, GeodesyError, SettingsError

CM = 117.5
LAT = math.radians(31.8)


def kruger_tm(lat_rad, dlon_rad, a, rf, k0):
    """Independent transverse Mercator: Krüger n-series to n³ (Karney 2011 eqs.; error < 0.02 mm
    within a few degrees), conformal latitude via atanh. Returns (x east from CM, y north from equator)."""
    f = 1.0 / rf
    n = f / (2.0 - f)
    big_a = a / (1.0 + n) * (1.0 + n**2 / 4.0 + n**4 / 64.0)
    alpha = [n / 2 - 2 * n**2 / 3 + 5 * n**3 / 16, 13 * n**2 / 48 - 3 * n**3 / 5, 61 * n**3 / 240]
    c = 2.0 * math.sqrt(n) / (1.0 + n)
    t = np.sinh(np.arctanh(np.sin(lat_rad)) - c * np.arctanh(c * np.sin(lat_rad)))
    xi_p = np.arctan2(t, np.cos(dlon_rad))
    eta_p = np.arctanh(np.sin(dlon_rad) / np.sqrt(1.0 + t * t))
    xi = xi_p + sum(al * np.sin(2 * j * xi_p) * np.cosh(2 * j * eta_p) for j, al in enumerate(alpha, 1))
    eta = eta_p + sum(al * np.cos(2 * j * xi_p) * np.sinh(2 * j * eta_p) for j, al in enumerate(alpha, 1))
    return k0 * big_a * eta, k0 * big_a * xi


def metres_between(lat1, lon1, lat2, lon2):
    """Approximate ground distance [m] between nearby geodetic points (for round-trip checks)."""
    r = 6_371_000.0
    return r * np.hypot(lat2 - lat1, (lon2 - lon1) * np.cos(lat1))


CONFIGS = [
    EngineeringCRS(central_meridian_deg=CM),
    EngineeringCRS(central_meridian_deg=CM, projection_height_m=500.0),
    EngineeringCRS(central_meridian_deg=CM, projection_height_m=500.0,
                   projection_height_convention="semi_major_axis"),
    EngineeringCRS(ellipsoid="Krassovsky", central_meridian_deg=119.0, projection_height_m=170.0,
                   false_northing_m=-3_000_000.0, scale_factor=0.9999),
    EngineeringCRS(ellipsoid="custom", a_m=6378140.0, inverse_flattening=298.257, central_meridian_deg=CM,
                   latitude_of_origin_deg=30.0),
    EngineeringCRS(epsg=4549),
    EngineeringCRS(epsg=4527),
]


@pytest.mark.parametrize("crs", CONFIGS, ids=lambda c: c.describe())
@settings(max_examples=30, deadline=None)
@given(lat_deg=st.floats(18.0, 53.0), dlon_deg=st.floats(-3.0, 3.0))
def test_round_trip_geodetic_plane_geodetic_within_0_1_mm(crs, lat_deg, dlon_deg):
    lat = np.radians(np.array([lat_deg, lat_deg + 0.01]))
    lon = np.radians(np.array([crs.central_meridian_deg + dlon_deg] * 2))
    east, north = crs.to_plane(lat, lon)
    lat2, lon2 = crs.to_geodetic(east, north)
    assert np.all(metres_between(lat, lon, lat2, lon2) < 1e-4)
    east2, north2 = crs.to_plane(lat2, lon2)
    assert np.all(np.hypot(east2 - east, north2 - north) < 1e-4)


def test_round_trip_plane_geodetic_plane_is_smooth_and_exact():
    # The simulator places a track defined in the plane on the ellipsoid: to_geodetic must be
    # exact and smooth, so second differences along a straight plane line must vanish.
    crs = CONFIGS[2]
    east = 500_000.0 + np.linspace(-20_000.0, 20_000.0, 4001)
    north = 3_520_000.0 + 0.3 * (east - 500_000.0)
    lat, lon = crs.to_geodetic(east, north)
    east2, north2 = crs.to_plane(lat, lon)
    assert np.max(np.hypot(east2 - east, north2 - north)) < 1e-6
    # geodetic coordinates of equally spaced points: smooth to far below a micrometre
    second_difference_m = np.diff(lat, 2) * 6.37e6
    assert np.max(np.abs(np.diff(second_difference_m))) < 1e-6


@pytest.mark.parametrize("epsg, geographic", [(4549, "EPSG:4490"), (4527, "EPSG:4490"), (4502, "EPSG:4490"),
                                               (32650, "EPSG:4326")])
def test_epsg_zone_matches_pyproj_directly(epsg, geographic):
    crs = EngineeringCRS(epsg=epsg)
    lat_deg = np.array([22.0, 31.8, 45.0])
    lon_deg = crs.central_meridian_deg + np.array([-1.4, 0.2, 1.3])
    expected_e, expected_n = Transformer.from_crs(geographic, f"EPSG:{epsg}", always_xy=True).transform(
        lon_deg, lat_deg)
    east, north = crs.to_plane(np.radians(lat_deg), np.radians(lon_deg))
    np.testing.assert_allclose(east, expected_e, atol=1e-6, rtol=0)
    np.testing.assert_allclose(north, expected_n, atol=1e-6, rtol=0)


def test_epsg_fields_come_from_the_definition():
    crs = EngineeringCRS(epsg=4527)  # CGCS2000 3-degree GK zone 39: CM 117E, zone prefix in FE
    assert (crs.ellipsoid, crs.central_meridian_deg, crs.false_easting_m, crs.scale_factor) == (
        "CGCS2000", 117.0, 39_500_000.0, 1.0)
    assert EngineeringCRS(epsg=32650).ellipsoid == "WGS84"
    assert EngineeringCRS(epsg=32650).scale_factor == 0.9996


def test_digest_projection_height_examples():
    # geodesy.md: 31.8N on the central meridian, H0 = 500 m, CGCS2000.
    base = EngineeringCRS(central_meridian_deg=CM).to_plane(LAT, math.radians(CM))[1]
    by_scale = EngineeringCRS(central_meridian_deg=CM, projection_height_m=500.0).to_plane(
        LAT, math.radians(CM))[1]
    by_axis = EngineeringCRS(central_meridian_deg=CM, projection_height_m=500.0,
                             projection_height_convention="semi_major_axis").to_plane(LAT, math.radians(CM))[1]
    assert base == pytest.approx(3_519_675.42, abs=0.005)
    assert by_scale == pytest.approx(3_519_951.65, abs=0.005)
    assert by_axis == pytest.approx(3_519_951.34, abs=0.005)


@pytest.mark.parametrize("convention", ["scale_factor", "semi_major_axis"])
@pytest.mark.parametrize("h0", [0.0, 120.0, 2300.0])
def test_projection_height_conventions_match_independent_series(convention, h0):
    crs = EngineeringCRS(central_meridian_deg=CM, projection_height_m=h0, projection_height_convention=convention,
                         false_easting_m=500_000.0, false_northing_m=-3_000_000.0)
    a, rf = ELLIPSOIDS["CGCS2000"].a, ELLIPSOIDS["CGCS2000"].inverse_flattening
    if convention == "scale_factor":
        k0, a_used = 1.0 + h0 / 6_371_000.0, a
    else:
        k0, a_used = 1.0, a + h0
    lat = np.radians(np.array([25.0, 31.8, 40.0, 48.0]))
    dlon = np.radians(np.array([-2.5, 0.7, 1.5, 2.9]))
    x, y = kruger_tm(lat, dlon, a_used, rf, k0)
    east, north = crs.to_plane(lat, np.radians(CM) + dlon)
    np.testing.assert_allclose(east, x + 500_000.0, atol=1e-4, rtol=0)
    np.testing.assert_allclose(north, y - 3_000_000.0, atol=1e-4, rtol=0)


@pytest.mark.parametrize("crs", CONFIGS[:4] + [CONFIGS[5]], ids=lambda c: c.describe())
def test_scale_factor_and_convergence_agree_with_finite_differences(crs):
    lat = np.radians(np.array([24.0, 31.8, 41.0]))
    lon = np.radians(crs.central_meridian_deg + np.array([-2.0, 0.5, 2.5]))
    step = 1e-7  # rad, about 0.6 m: finite-difference error far below the tolerances
    e0, n0 = crs.to_plane(lat, lon)
    e1, n1 = crs.to_plane(lat + step, lon)
    a, rf = crs.semi_major_axis_m, crs.inverse_flattening_value
    e2 = (2 - 1 / rf) / rf
    meridian_radius = a * (1 - e2) / (1 - e2 * np.sin(lat) ** 2) ** 1.5
    k_numeric = np.hypot(e1 - e0, n1 - n0) / (meridian_radius * step)
    np.testing.assert_allclose(crs.point_scale_factor(lat, lon), k_numeric, rtol=0, atol=2e-8)
    # Grid bearing of true north is -γ (γ = grid north minus true north).
    bearing_of_true_north = np.arctan2(e1 - e0, n1 - n0)
    np.testing.assert_allclose(crs.meridian_convergence_rad(lat, lon), -bearing_of_true_north, atol=1e-8)
    east_of_meridian = np.sign(lon - np.radians(crs.central_meridian_deg))
    assert np.all(np.sign(crs.meridian_convergence_rad(lat, lon)) == east_of_meridian)


def test_scale_factor_on_central_meridian_includes_projection_height():
    lon = math.radians(CM)
    by_scale = EngineeringCRS(central_meridian_deg=CM, projection_height_m=800.0, mean_radius_m=6_370_000.0)
    by_axis = EngineeringCRS(central_meridian_deg=CM, projection_height_m=800.0,
                             projection_height_convention="semi_major_axis")
    assert by_scale.point_scale_factor(LAT, lon) == pytest.approx(1 + 800 / 6_370_000, abs=1e-10)
    assert by_axis.point_scale_factor(LAT, lon) == pytest.approx(1 + 800 / 6_378_137, abs=1e-10)


def test_length_distortion_follows_tb10601_rules_of_thumb():
    crs = EngineeringCRS(central_meridian_deg=CM)
    # 28.5 km from the central meridian at sea level: y²/(2R²) ≈ 10 mm/km.
    lat, lon = crs.to_geodetic(500_000.0 + 28_500.0, 3_520_000.0)
    assert crs.length_distortion_mm_per_km(lat, lon, 0.0) == pytest.approx(10.0, abs=0.1)
    # on the meridian, 64 m above the projection surface: ΔH/R ≈ -10 mm/km
    assert crs.length_distortion_mm_per_km(LAT, math.radians(CM), 64.0) == pytest.approx(-10.0, abs=0.05)
    # a projection height at the track's height removes the height reduction
    raised = EngineeringCRS(central_meridian_deg=CM, projection_height_m=1500.0,
                            projection_height_convention="semi_major_axis")
    distortion = raised.length_distortion_mm_per_km(LAT, math.radians(CM) + np.zeros(3), np.array([1400.0, 1500.0,
                                                                                                    1600.0]))
    # what remains is H0/a - H0/R_gauss (the expanded ellipsoid uses a, not the local radius)
    assert distortion[1] == pytest.approx(-0.35, abs=0.02)
    assert distortion[0] > 0 > distortion[2]


def test_points_far_from_the_central_meridian_are_refused():
    with pytest.raises(GeodesyError, match="from the central meridian"):
        EngineeringCRS(central_meridian_deg=CM).to_plane(LAT, math.radians(CM + 12.0))


def test_settings_round_trip_and_pickle():
    for crs in CONFIGS:
        again = EngineeringCRS.from_settings(crs.to_settings())
        assert again == crs
        assert pickle.loads(pickle.dumps(crs)) == crs
    assert CONFIGS[5].to_settings() == {"epsg": 4549}


def test_settings_report_every_problem_with_its_key_path():
    with pytest.raises(SettingsError) as err:
        EngineeringCRS.from_settings({
            "ellipsoid": "Bessel", "central_meridan_deg": 117.5, "scale_factor": 2.0,
            "projection_height_m": 50_000.0, "projection_height_convention": "k", "false_easting_m": "500000",
        }, key_path="geodesy.crs")
    text = str(err.value)
    for expected in ["geodesy.crs.ellipsoid: expected one of", "geodesy.crs.central_meridan_deg: unknown key "
                     "(did you mean 'central_meridian_deg'?)", "geodesy.crs.central_meridian_deg: missing",
                     "geodesy.crs.scale_factor: 2 is outside the plausible range",
                     "geodesy.crs.projection_height_m: 50000 m is outside",
                     "geodesy.crs.projection_height_convention: expected one of",
                     "geodesy.crs.false_easting_m: expected a number in m, got '500000'"]:
        assert expected in text
    assert len(err.value.problems) == 7


@pytest.mark.parametrize("bad, message", [
    ({"ellipsoid": "custom", "central_meridian_deg": 117.0, "a_m": 6378.137, "inverse_flattening": 298.0},
     "a_m: 6378.14 m is outside"),
    ({"ellipsoid": "custom", "central_meridian_deg": 117.0}, "inverse_flattening: missing"),
    ({"ellipsoid": "WGS84", "central_meridian_deg": 117.0, "a_m": 6378137.0}, "only used with ellipsoid = 'custom'"),
    ({"central_meridian_deg": 400.0}, "central_meridian_deg: 400 degrees is outside"),
    ({"central_meridian_deg": 117.0, "mean_radius_m": 6371.0}, "mean_radius_m: 6371 m is outside"),
    ({"epsg": 3857}, "EPSG:3857 (WGS 84 / Pseudo-Mercator) is Popular Visualisation Pseudo Mercator"),
    ({"epsg": 4490}, "not a projected CRS"),
    ({"epsg": 99999}, "EPSG:99999 is not in the PROJ database"),
    ({"epsg": "4549"}, "expected an integer EPSG code"),
    ({"epsg": 4549, "central_meridian_deg": 120.0}, "an EPSG zone defines the whole projection"),
])
def test_absurd_or_inconsistent_settings_are_refused(bad, message):
    with pytest.raises(SettingsError, match=None) as err:
        EngineeringCRS.from_settings(bad)
    assert message in str(err.value)
    assert str(err.value).count("geodesy.crs.") >= 1


def test_direct_construction_validates_too():
    with pytest.raises(SettingsError, match="contradicts EPSG:4549, which defines 120.0"):
        EngineeringCRS(epsg=4549, central_meridian_deg=117.0)
    with pytest.raises(SettingsError, match="projection_height_m"):
        EngineeringCRS(epsg=4549, projection_height_m=300.0)
    with pytest.raises(SettingsError, match="central_meridian_deg: missing"):
        EngineeringCRS()
