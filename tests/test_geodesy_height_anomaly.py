"""Height-anomaly fitting on synthetic GNSS-levelling benchmarks along a 10 km corridor."""

import numpy as np
import pytest

from insrail.geodesy import (
    EngineeringCRS,
    FitError,
    GeodesyError,
    GeoidGrid,
    GeoidGridError,
    HeightAnomalySettings,
    PlaneGeoid,
    SettingsError,
    fit_height_anomaly,
)

RADIUS_M = 8000.0  # the corridor is a circular arc, so benchmarks are not all on one line
LENGTH_M = 10_000.0


def corridor_point(chainage_m, offset_m):
    angle = np.asarray(chainage_m) / RADIUS_M
    east = 495_000.0 + (RADIUS_M + offset_m) * np.sin(angle)
    north = 3_520_000.0 + RADIUS_M - (RADIUS_M + offset_m) * np.cos(angle)
    return east, north


def benchmarks(rng, n):
    """n benchmarks about evenly along the corridor, alternately 80-250 m left and right of it."""
    chainage = np.sort(np.clip(np.linspace(0.0, LENGTH_M, n) + rng.uniform(-150.0, 150.0, n), 0.0, LENGTH_M))
    offset = np.where(np.arange(n) % 2 == 0, 1.0, -1.0) * rng.uniform(80.0, 250.0, n)
    east, north = corridor_point(chainage, offset)
    return np.c_[east, north], chainage


def km(east, north):
    return (east - 500_000.0) / 1000.0, (north - 3_521_000.0) / 1000.0


# Known ζ surfaces [m], one per model family; the spline case varies along the line only.
SURFACES = {
    "constant": lambda e, n, s: 12.345 + 0.0 * e,
    "plane": lambda e, n, s: 10.0 + 0.05 * km(e, n)[0] - 0.12 * km(e, n)[1],
    "quadratic": lambda e, n, s: (10.0 + 0.05 * km(e, n)[0] - 0.12 * km(e, n)[1] + 0.01 * km(e, n)[0] ** 2
                                  - 0.008 * km(e, n)[0] * km(e, n)[1] + 0.015 * km(e, n)[1] ** 2),
    "spline": lambda e, n, s: 8.0 + 0.2 * np.sin(2.0 * np.pi * s / 12_000.0) + 0.02 * s / 1000.0,
}


@pytest.mark.parametrize("n_benchmarks, seed", [(8, 1), (10, 2), (12, 3)])
@pytest.mark.parametrize("model", list(SURFACES))
def test_each_model_recovers_its_surface_inside_the_hull(model, n_benchmarks, seed):
    rng = np.random.default_rng(seed)
    en, chainage = benchmarks(rng, n_benchmarks)
    truth = SURFACES[model]
    zeta = truth(en[:, 0], en[:, 1], chainage) + rng.normal(0.0, 1e-3, n_benchmarks)  # 1 mm levelling noise
    fit = fit_height_anomaly(en, zeta, model=model, chainage_m=chainage)
    assert fit.model_name == model

    check_chainage = np.linspace(0.0, LENGTH_M, 400)
    check_e, check_n = corridor_point(check_chainage, 0.0)
    inside = ~fit.extrapolation_mask(check_e, check_n, check_chainage)
    assert inside.sum() > 250
    error = fit.zeta_m(check_e, check_n, check_chainage) - truth(check_e, check_n, check_chainage)
    assert np.max(np.abs(error[inside])) <= 0.005


@pytest.mark.parametrize("model", list(SURFACES))
def test_auto_chooses_the_generating_model_by_leave_one_out(model):
    rng = np.random.default_rng(11)
    en, chainage = benchmarks(rng, 10)
    zeta = SURFACES[model](en[:, 0], en[:, 1], chainage) + rng.normal(0.0, 1e-3, 10)
    fit = fit_height_anomaly(en, zeta, chainage_m=chainage)
    assert fit.model_name == model
    assert {c.name for c in fit.candidates} == set(SURFACES)
    best_loo = min(c.loo_rms_m for c in fit.candidates)
    assert fit.loo_rms_m <= best_loo + max(0.1 * best_loo, 0.0005)
    report = fit.report()
    assert "<- chosen" in report.splitlines()[2 + [c.name for c in fit.candidates].index(model)]
    assert "leave-one-out RMS" in report


def test_without_chainage_auto_skips_the_spline_and_internal_rms_is_reported():
    rng = np.random.default_rng(4)
    en, chainage = benchmarks(rng, 9)
    zeta = SURFACES["plane"](en[:, 0], en[:, 1], chainage) + rng.normal(0.0, 1e-3, 9)
    fit = fit_height_anomaly(en, zeta)
    assert [c.name for c in fit.candidates] == ["constant", "plane", "quadratic"]
    assert 0.2e-3 < fit.internal_rms_m < 2e-3
    np.testing.assert_allclose(fit.chosen.residuals_m, zeta - fit.zeta_m(en[:, 0], en[:, 1]), atol=1e-12)


def test_leave_one_out_residual_equals_explicit_refit():
    rng = np.random.default_rng(6)
    en, chainage = benchmarks(rng, 9)
    zeta = SURFACES["quadratic"](en[:, 0], en[:, 1], chainage) + rng.normal(0.0, 1e-3, 9)
    fit = fit_height_anomaly(en, zeta, model="quadratic")
    keep = np.arange(9) != 4
    refit = fit_height_anomaly(en[keep], zeta[keep], model="quadratic")
    assert fit.chosen.loo_residuals_m[4] == pytest.approx(zeta[4] - refit.zeta_m(en[4, 0], en[4, 1]), abs=1e-10)


def test_warnings_for_points_outside_hull_and_chainage_span():
    rng = np.random.default_rng(8)
    en, chainage = benchmarks(rng, 10)
    zeta = SURFACES["plane"](en[:, 0], en[:, 1], chainage)
    plane = fit_height_anomaly(en, zeta, model="plane")
    far_e, far_n = corridor_point(np.array([5000.0, 5000.0]), np.array([0.0, 2000.0]))
    assert plane.warnings_for(far_e[:1], far_n[:1]) == []
    (message,) = plane.warnings_for(far_e, far_n)
    assert "1 of 2 points" in str(message) and "convex hull" in str(message)

    spline = fit_height_anomaly(en, zeta, model="spline", chainage_m=chainage)
    beyond = np.array([chainage[0] + 10.0, chainage[-1] + 500.0])
    e, n = corridor_point(beyond, 0.0)
    (message,) = spline.warnings_for(e, n, beyond)
    assert "1 of 2 points" in str(message) and "outside the benchmarks' span" in str(message)
    # beyond the end benchmarks the spline continues along its end tangent, not as a cubic
    s = chainage[-1] + np.array([100.0, 200.0, 300.0])
    assert np.diff(spline.zeta_m(None, None, s), 2) == pytest.approx(0.0, abs=1e-12)


def test_too_few_points_for_a_model_are_refused_and_auto_says_why():
    rng = np.random.default_rng(2)
    en, chainage = benchmarks(rng, 6)
    zeta = SURFACES["plane"](en[:, 0], en[:, 1], chainage)
    with pytest.raises(FitError, match="quadratic model needs at least 7 benchmarks .* 6 given"):
        fit_height_anomaly(en, zeta, model="quadratic")
    with pytest.raises(FitError, match="spline needs at least 4 benchmarks, 3 given"):
        fit_height_anomaly(en[:3], zeta[:3], model="spline", chainage_m=chainage[:3])
    fit = fit_height_anomaly(en, zeta)
    assert "needs at least 7" in fit.not_fitted["quadratic"]
    assert "quadratic  not fitted" in fit.report()
    with pytest.raises(FitError, match="no height-anomaly model can be fitted"):
        fit_height_anomaly(en[:1], zeta[:1])


def test_collinear_benchmarks_are_refused_for_surfaces():
    chainage = np.linspace(0.0, 10_000.0, 9)
    en = np.c_[500_000.0 + 0.6 * chainage, 3_520_000.0 + 0.8 * chainage]  # a straight line
    zeta = 10.0 + 1e-5 * chainage
    with pytest.raises(FitError, match="collinear"):
        fit_height_anomaly(en, zeta, model="plane")
    fit = fit_height_anomaly(en, zeta, chainage_m=chainage)
    assert set(fit.not_fitted) == {"plane", "quadratic"}
    # benchmarks all on the centreline of a circular section lie on a conic
    e, n = corridor_point(chainage, 0.0)
    with pytest.raises(FitError, match="conic"):
        fit_height_anomaly(np.c_[e, n], zeta, model="quadratic")
    # extrapolation check when the benchmarks have no 2-D hull
    constant = fit_height_anomaly(en, zeta, model="constant")
    assert "no 2-D hull" in constant.warnings_for([500_100.0], [3_520_000.0])[0]


@pytest.mark.parametrize("kwargs, error, message", [
    ({"model": "cubic"}, GeodesyError, "unknown height-anomaly model 'cubic'"),
    ({"model": "spline"}, FitError, "give chainage_m"),
    ({"zeta_scale": 1000.0}, FitError, r"ζ = h − H = .* is impossible"),
    ({"duplicate_chainage": True}, FitError, "two benchmarks share chainage"),
    ({"nan": True}, GeodesyError, r"benchmarks \[2\] have missing"),
])


def test_bad_input_is_refused(kwargs, error, message):
    rng = np.random.default_rng(0)
    en, chainage = benchmarks(rng, 8)
    zeta = SURFACES["plane"](en[:, 0], en[:, 1], chainage) * kwargs.pop("zeta_scale", 1.0)
    if kwargs.pop("duplicate_chainage", False):
        chainage[3] = chainage[2]
        kwargs["model"], kwargs["chainage_m"] = "spline", chainage
    if kwargs.pop("nan", False):
        en[2, 1] = np.nan
    with pytest.raises(error, match=message):
        fit_height_anomaly(en, zeta, **kwargs)


def test_spline_model_needs_chainage_when_evaluated():
    rng = np.random.default_rng(0)
    en, chainage = benchmarks(rng, 8)
    fit = fit_height_anomaly(en, SURFACES["spline"](en[:, 0], en[:, 1], chainage), model="spline",
                             chainage_m=chainage)
    with pytest.raises(GeodesyError, match="give chainage_m"):
        fit.zeta_m(en[:, 0], en[:, 1])


def test_settings_validation_and_missing_grid():
    assert HeightAnomalySettings.from_settings({"model": "plane"}).model == "plane"
    settings = HeightAnomalySettings(model="auto", geoid_grid="/nonexistent/geoid.gtx")
    assert HeightAnomalySettings.from_settings(settings.to_settings()) == settings
    with pytest.raises(SettingsError) as err:
        HeightAnomalySettings.from_settings({"model": "cubic", "geoid_grid": 3, "grid": "x"})
    assert len(err.value.problems) == 3
    with pytest.raises(GeoidGridError, match="geoid grid file not found"):
        settings.plane_geoid(EngineeringCRS(central_meridian_deg=117.5))


def test_remove_restore_with_egm96():
    geoid = PlaneGeoid(GeoidGrid.egm96(), EngineeringCRS(central_meridian_deg=117.5))
    rng = np.random.default_rng(12)
    en, chainage = benchmarks(rng, 10)
    # ζ = EGM96 undulation + a small local plane: after removing EGM96 the plane fits exactly
    local = lambda e, n: 0.15 + 0.01 * km(e, n)[0] - 0.02 * km(e, n)[1]  # noqa: E731
    zeta = geoid.undulation_m(en[:, 0], en[:, 1]) + local(en[:, 0], en[:, 1]) + rng.normal(0.0, 1e-3, 10)
    fit = fit_height_anomaly(en, zeta, model="plane", geoid=geoid)
    e, n = corridor_point(np.linspace(1000.0, 9000.0, 50), 0.0)
    truth = geoid.undulation_m(e, n) + local(e, n)
    assert np.max(np.abs(fit.zeta_m(e, n) - truth)) < 0.003
    assert "remove-restore with egm96_15.gtx" in fit.report()
    assert np.all(np.abs(geoid.undulation_m(e, n) + 3.7) < 0.5)  # EGM96 is about -3.7 m here
