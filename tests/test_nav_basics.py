"""Earth model and rotation utilities against independent values."""

import hypothesis.strategies as st
import numpy as np
import pytest
from hypothesis import given
from hypothesis.extra.numpy import arrays

from insrail.nav import earth, rotation


def test_normal_gravity_matches_published_values():
    # WGS84 normal gravity on the ellipsoid: equator and pole are defining values.
    assert earth.normal_gravity(0.0, 0.0) == pytest.approx(9.7803253359, abs=1e-10)
    assert earth.normal_gravity(np.pi / 2, 0.0) == pytest.approx(9.8321849378, abs=1e-9)
    # Free-air gradient about -3.086e-6 s^-2 near the surface.
    grad = (earth.normal_gravity(0.5, 100.0) - earth.normal_gravity(0.5, 0.0)) / 100.0
    assert grad == pytest.approx(-3.086e-6, rel=2e-3)


def test_geodetic_ecef_roundtrip():
    rng = np.random.default_rng(1)
    lat = rng.uniform(-1.5, 1.5, 500)
    lon = rng.uniform(-np.pi, np.pi, 500)
    h = rng.uniform(-500.0, 9000.0, 500)
    lat2, lon2, h2 = earth.ecef_to_geodetic(earth.geodetic_to_ecef(lat, lon, h))
    assert np.abs(lat2 - lat).max() < 1e-13
    assert np.abs(np.angle(np.exp(1j * (lon2 - lon)))).max() < 1e-13
    assert np.abs(h2 - h).max() < 1e-7


def test_radii_at_equator_and_pole():
    r_m, r_n = earth.radii(0.0)
    assert r_n == pytest.approx(6378137.0)
    assert r_m == pytest.approx(6378137.0 * (1 - earth.WGS84.e2))
    r_m, r_n = earth.radii(np.pi / 2)
    assert r_m == pytest.approx(r_n)


def test_dcm_ecef_from_ned_columns_are_north_east_down():
    lat, lon = 0.6, 2.0
    c = earth.dcm_ecef_from_ned(lat, lon)
    x0 = earth.geodetic_to_ecef(lat, lon, 0.0)
    # Down is minus the outward normal; north points along increasing latitude.
    north = earth.geodetic_to_ecef(lat + 1e-7, lon, 0.0) - x0
    assert np.allclose(c[:, 0], north / np.linalg.norm(north), atol=1e-6)
    up = earth.geodetic_to_ecef(lat, lon, 1.0) - x0
    assert np.allclose(c[:, 2], -up, atol=1e-9)
    assert np.allclose(c @ c.T, np.eye(3), atol=1e-15)


def test_rotation_conversions_roundtrip():
    rng = np.random.default_rng(2)
    e = rng.uniform(-1, 1, (200, 3)) * [3.0, 1.5, 3.0]
    c = rotation.euler_to_dcm(*e.T)
    assert np.allclose(np.stack(rotation.dcm_to_euler(c), -1), e, atol=1e-12)
    q = rotation.dcm_to_quat(c)
    assert np.allclose(rotation.quat_to_dcm(q), c, atol=1e-14)
    phi = rotation.dcm_to_rotvec(c)
    assert np.allclose(rotation.rotvec_to_dcm(phi), c, atol=1e-13)
    assert np.allclose(rotation.quat_to_dcm(rotation.rotvec_to_quat(phi)), c, atol=1e-13)
    # Composition: quaternion product equals DCM product.
    q2 = rotation.dcm_to_quat(c[::-1])
    assert np.allclose(rotation.quat_to_dcm(rotation.quat_multiply(q, q2)), c @ c[::-1], atol=1e-13)


def test_euler_rates_match_numerical_derivative_of_dcm():
    rng = np.random.default_rng(3)
    e0 = rng.uniform(-0.5, 0.5, 3)
    rates = rng.uniform(-0.1, 0.1, 3)
    dt = 1e-6
    c0 = rotation.euler_to_dcm(*(e0 - rates * dt))
    c1 = rotation.euler_to_dcm(*(e0 + rates * dt))
    # C_b^n' = C_b^n (w_nb^b x)  =>  w from the rotation between the two attitudes.
    w_num = rotation.dcm_to_rotvec(c0.T @ c1) / (2 * dt)
    w = rotation.euler_rates_to_body_rate(e0[0], e0[1], *rates)
    assert np.allclose(w, w_num, atol=1e-9)


vectors = arrays(float, 3, elements=st.floats(-1e6, 1e6, allow_nan=False))


@given(vectors, vectors)
def test_single_vector_cross_and_skew_are_numpys_exactly(a, b):
    """The filter's fast paths for one 3-vector compute what the general ones compute, bit for bit."""
    assert np.array_equal(rotation.cross(a, b), np.cross(a, b))
    assert np.array_equal(rotation.skew(a), rotation.skew(a[None])[0])
    assert np.array_equal(np.signbit(rotation.skew(a)), np.signbit(rotation.skew(a[None])[0]))


def test_the_play_noise_is_across_the_track_and_the_part_of_its_drift_the_nhc_noise_does_not_carry():
    from insrail.nav.error_model import play_noise
    from insrail.nav.fusion import FusionOptions, play_drift
    from insrail.nav.measurements import OdometerNhc, Zupt

    along, across = np.array([0.6, 0.8, 0.0]), np.array([-0.8, 0.6, 0.0])
    play = np.array([2e-8, 3e-8, 1e-8])  # per metre run lateral, vertical; the NHC's drift per second
    q = play_noise(1.2 * along + [0.0, 0.0, 0.01], 0.1, play)  # 1.2 m in 0.1 s
    assert across @ q @ across == pytest.approx(2e-8 * 1.2 - 1e-8 * 0.1)
    assert along @ q @ along == pytest.approx(0.0, abs=1e-24)
    assert q[2, 2] == pytest.approx(3e-8 * 1.2 - 1e-8 * 0.1) and q[0, 2] == q[1, 2] == 0.0
    np.testing.assert_array_equal(q, q.T)
    assert not play_noise(np.zeros(3), 0.1, play).any()  # standing still
    assert not play_noise(0.03 * along, 0.1, play).any()  # 0.3 m/s: the NHC noise carries more than the play
    # only where an NHC holds the trolley to the rail (not a hand-held unit's ZUPT-only run), with its sigma
    options = FusionOptions()
    assert not play_drift(options, [Zupt(np.array([1.0]), 0.001, 2e-6)]).any()
    nhc = OdometerNhc(np.array([1.0]), np.array([1.2]), np.eye(3), np.zeros(3), np.zeros(3), np.array([0.001]),
                      sigma_nhc_mps=options.nhc_sigma_mps)
    np.testing.assert_allclose(play_drift(options, [nhc]), [*options.play_drift_m2_per_m,
                                                          options.nhc_sigma_mps**2 / options.update_rate_hz])
