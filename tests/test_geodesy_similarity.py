"""4-parameter and 7-parameter similarity fits: recovery, statistics, checks and refusals."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from insrail.geodesy import (
    FitError,
    Helmert7,
    SettingsError,
    Similarity2D,
    fit_helmert_7,
    fit_similarity_2d,
)
from insrail.geodesy.similarity import ARCSEC
from insrail.nav.earth import geodetic_to_ecef

TRUE_2D = Similarity2D(translation_east_m=-123.456, translation_north_m=789.012, rotation_rad=2.5 * ARCSEC,
                       scale=1.0 + 3.7e-6)
TRUE_7 = Helmert7(tx_m=-50.3, ty_m=80.1, tz_m=20.7, rx_rad=1.2 * ARCSEC, ry_rad=-2.3 * ARCSEC, rz_rad=3.1 * ARCSEC,
                  scale_ppm=3.2)


def plane_points(rng, n=10):
    """Control points of a 10 km by 10 km site in a Gauss-Krüger zone."""
    return np.c_[rng.uniform(495_000.0, 505_000.0, n), rng.uniform(3_515_000.0, 3_525_000.0, n)]


def ecef_points(rng, n=10):
    lat = np.radians(31.8 + rng.uniform(-0.05, 0.05, n))
    lon = np.radians(117.5 + rng.uniform(-0.05, 0.05, n))
    return geodetic_to_ecef(lat, lon, rng.uniform(0.0, 200.0, n))


@pytest.mark.parametrize("seed", range(5))
def test_4_parameter_fit_recovers_known_parameters(seed):
    rng = np.random.default_rng(seed)
    src = plane_points(rng)
    dst = TRUE_2D.apply(src) + rng.normal(0.0, 1e-3, src.shape)
    fit = fit_similarity_2d(src, dst)
    p = fit.parameters
    assert abs(p.scale_ppm - TRUE_2D.scale_ppm) < 1.0
    assert abs(p.rotation_rad - TRUE_2D.rotation_rad) < 0.1 * ARCSEC
    # translations are correlated with rotation over the 3.5e6 m lever arm; the transformed
    # coordinates are what must agree
    assert np.max(np.abs(fit.apply(src) - TRUE_2D.apply(src))) < 2e-3
    assert 0.5e-3 < fit.sigma0_m < 1.6e-3
    assert fit.residuals_m.shape == fit.loo_residuals_m.shape == (10, 2)
    assert fit.loo_rms_m > fit.rms_m  # a point predicted without itself is never better on average


@pytest.mark.parametrize("seed", range(5))
def test_7_parameter_fit_recovers_known_parameters(seed):
    rng = np.random.default_rng(100 + seed)
    src = ecef_points(rng)
    dst = TRUE_7.apply(src) + rng.normal(0.0, 1e-3, src.shape)
    fit = fit_helmert_7(src, dst)
    p = fit.parameters
    assert abs(p.scale_ppm - TRUE_7.scale_ppm) < 1.0
    for got, true in [(p.rx_rad, TRUE_7.rx_rad), (p.ry_rad, TRUE_7.ry_rad), (p.rz_rad, TRUE_7.rz_rad)]:
        assert abs(got - true) < 0.1 * ARCSEC
    assert np.max(np.abs(fit.apply(src) - TRUE_7.apply(src))) < 2e-3
    assert fit.loo_rms_m > fit.rms_m
    assert fit.warnings == ()


def test_parameter_standard_deviations_match_monte_carlo():
    rng = np.random.default_rng(42)
    src2, src3 = plane_points(rng), ecef_points(rng)
    sigma = 2e-3
    fits2 = [fit_similarity_2d(src2, TRUE_2D.apply(src2) + rng.normal(0, sigma, src2.shape)) for _ in range(150)]
    fits7 = [fit_helmert_7(src3, TRUE_7.apply(src3) + rng.normal(0, sigma, src3.shape)) for _ in range(150)]
    for fits, names in [(fits2, ["rotation_rad", "scale", "translation_east_m"]),
                        (fits7, ["rx_rad", "rz_rad", "scale_ppm", "tz_m"])]:
        for name in names:
            empirical = np.std([getattr(f.parameters, name) for f in fits])
            predicted = np.sqrt(np.mean([f.parameter_std[name] ** 2 for f in fits]))
            assert predicted == pytest.approx(empirical, rel=0.25), name


def test_leave_one_out_points_at_the_disturbed_control_point():
    rng = np.random.default_rng(3)
    src = plane_points(rng, 8)
    dst = TRUE_2D.apply(src) + rng.normal(0.0, 1e-3, src.shape)
    dst[5] += [0.012, -0.009]  # a disturbed control point
    fit = fit_similarity_2d(src, dst)
    loo_norm = np.hypot(*fit.loo_residuals_m.T)
    assert np.argmax(loo_norm) == 5
    assert loo_norm[5] > np.hypot(*fit.residuals_m[5])  # the blunder partly hides in its own residual


def test_leave_one_out_equals_explicit_refit():
    rng = np.random.default_rng(5)
    src = ecef_points(rng, 6)
    dst = TRUE_7.apply(src) + rng.normal(0.0, 1e-3, src.shape)
    fit = fit_helmert_7(src, dst)
    keep = np.arange(6) != 2
    refit = fit_helmert_7(src[keep], dst[keep])
    np.testing.assert_allclose(fit.loo_residuals_m[2], dst[2] - refit.apply(src[2]), atol=1e-9)


@settings(max_examples=40, deadline=None)
@given(te=st.floats(-1e5, 1e5), tn=st.floats(-1e5, 1e5), rot=st.floats(-math.pi, math.pi),
       ppm=st.floats(-500.0, 500.0))
def test_2d_inverse_and_settings_round_trip(te, tn, rot, ppm):
    t = Similarity2D(te, tn, rot, 1.0 + ppm * 1e-6)
    pts = np.array([[500_000.0, 3_500_000.0], [510_000.0, 3_490_000.0]])
    np.testing.assert_allclose(t.inverse().apply(t.apply(pts)), pts, atol=1e-6)
    again = Similarity2D.from_settings(t.to_settings())
    np.testing.assert_allclose(again.apply(pts), t.apply(pts), atol=1e-6)


def test_helmert_settings_round_trip():
    again = Helmert7.from_settings(TRUE_7.to_settings())
    pts = ecef_points(np.random.default_rng(0), 3)
    np.testing.assert_allclose(again.apply(pts), TRUE_7.apply(pts), atol=1e-6)


def test_absurd_parameters_in_settings_are_refused():
    with pytest.raises(SettingsError) as err:
        Similarity2D.from_settings({"translation_east_m": 1.0, "translation_north_m": "x", "rotation_arcsec": 1.0,
                                    "scale_ppm": 1.5e6})
    assert "translation_north_m: expected a number in m" in str(err.value)
    assert "scale_ppm: 1.5e+06 ppm is outside the plausible range" in str(err.value)
    with pytest.raises(SettingsError, match="rx_arcsec: 3600 arc-seconds is outside"):
        Helmert7.from_settings({**TRUE_7.to_settings(), "rx_arcsec": 3600.0})
    with pytest.raises(SettingsError, match=r"scale: unknown key \(did you mean 'scale_ppm'\?\)"):
        Helmert7.from_settings({**TRUE_7.to_settings(), "scale": 1.0})


def test_too_few_points_are_refused():
    rng = np.random.default_rng(0)
    src = plane_points(rng, 2)
    with pytest.raises(FitError, match="2 common point.*at least 3 are needed"):
        fit_similarity_2d(src, TRUE_2D.apply(src))
    src3 = ecef_points(rng, 3)
    with pytest.raises(FitError, match="at least 4 are needed"):
        fit_helmert_7(src3, TRUE_7.apply(src3))


def test_collinear_and_coincident_points_are_refused():
    t = np.linspace(0.0, 1.0, 6)[:, None]
    line = np.array([-2.0e6, 5.0e6, 3.3e6]) + t * np.array([1000.0, -500.0, 200.0])
    with pytest.raises(FitError, match="collinear"):
        fit_helmert_7(line, TRUE_7.apply(line))
    same = np.tile([[500_000.0, 3_500_000.0]], (4, 1))
    with pytest.raises(FitError, match="source points coincide"):
        fit_similarity_2d(same, same)


def test_leave_one_out_reports_points_that_cannot_be_checked():
    # three collinear points and one off the line: without the off-line point no rotation
    t = np.array([0.0, 0.4, 1.0])[:, None]
    src = np.vstack([np.array([-2.0e6, 5.0e6, 3.3e6]) + t * [1000.0, -500.0, 200.0],
                     [[-2.0e6 + 300.0, 5.0e6 + 400.0, 3.3e6 - 100.0]]])
    fit = fit_helmert_7(src, TRUE_7.apply(src))
    assert np.isnan(fit.loo_residuals_m[3]).all() and np.isfinite(fit.loo_residuals_m[:3]).all()
    assert "points [3] cannot be checked" in fit.warnings[0]


def test_implausible_fits_are_refused_with_a_diagnosis():
    rng = np.random.default_rng(9)
    src = plane_points(rng)
    with pytest.raises(FitError, match="scale differs from 1 by .* ppm"):
        fit_similarity_2d(src, src * 1.002 + 10.0)  # source in a different unit or scale
    with pytest.raises(FitError, match="easting and northing swapped"):
        fit_similarity_2d(src, TRUE_2D.apply(src)[:, ::-1])
    src3 = ecef_points(rng)
    big = Helmert7(0.0, 0.0, 0.0, 0.0, 0.0, math.radians(1.0), 0.0)
    with pytest.raises(FitError, match="rotation of 3600.0″ exceeds"):
        fit_helmert_7(src3, big.apply(src3))
    fit = fit_helmert_7(src3, big.apply(src3), max_rotation_rad=math.radians(2.0))
    assert fit.parameters.rz_rad == pytest.approx(math.radians(1.0), abs=1e-12)


@pytest.mark.parametrize("src, dst, message", [
    (np.zeros((4, 3)), np.zeros((4, 2)), r"source points must have shape \(n, 2\), got \(4, 3\)"),
    (np.zeros((4, 2)), np.zeros((5, 2)), "4 source points but 5 target points"),
    (np.array([[0.0, 0.0], [1.0, np.nan], [2.0, 3.0]]), np.zeros((3, 2)), r"points \[1\] have missing"),
])
def test_malformed_input_is_refused(src, dst, message):
    with pytest.raises(FitError, match=message):
        fit_similarity_2d(src, dst)
