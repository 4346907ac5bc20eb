"""[geodesy.local]: the 4- and 7-parameter transformation onto local control fitted from common points
(residuals, leave-one-out), the project settings and their errors."""

import math

import numpy as np
import pytest

from insrail.geodesy.similarity import Helmert7, Similarity2D
from insrail.project.local_control import LocalControl, LocalPoint, fit_local
from insrail.project.model import ProjectError, project_from_settings


def simulated_points(count=7, seed=4):
    """Common points along 3 km of line, a few tens of metres either side, engineering E, N, H."""
    rng = np.random.default_rng(seed)
    along = np.linspace(0.0, 3000.0, count)
    east = 512000.0 + 0.8 * along + rng.uniform(-40, 40, count)
    north = 3374000.0 + 0.6 * along + rng.uniform(-40, 40, count)
    return np.column_stack([east, north, 30.0 + 0.004 * along + rng.uniform(-1, 1, count)])


def control(model, engineering, local):
    return LocalControl(model, tuple(LocalPoint(f"CP{i}", tuple(e), tuple(q)) for i, (e, q) in
                                     enumerate(zip(engineering, local))))


def test_the_4_parameter_fit_reproduces_a_known_transformation():
    truth = Similarity2D(-509_100.0, -3_372_550.0, math.radians(-1.7), 1.0 + 14e-6)
    points = simulated_points()
    local = np.column_stack([truth.apply(points[:, :2]), points[:, 2] + 0.137])
    fit = fit_local(control("4-parameter", points, local))
    check = simulated_points(200, seed=9)  # anywhere along the line, not only at the common points
    east, north, height = fit.apply(*check.T)
    np.testing.assert_allclose(np.column_stack([east, north]), truth.apply(check[:, :2]), rtol=0, atol=1e-4)
    np.testing.assert_allclose(height, check[:, 2] + 0.137, atol=1e-4)
    assert np.abs(np.column_stack([east, north]) - truth.apply(check[:, :2])).max() < 1e-6  # far below 0.1 mm
    back = fit.to_engineering(east, north, height)
    np.testing.assert_allclose(np.column_stack(back), check, atol=1e-6)
    summary = fit.summary()
    assert summary["rms_mm"] < 1e-3 and summary["parameters"]["scale_ppm"] == pytest.approx(14.0, abs=1e-3)
    assert summary["parameters"]["rotation_deg"] == pytest.approx(-1.7, abs=1e-9) and not fit.notices()


def test_with_0_1_mm_noise_the_residuals_show_it_and_the_transformation_stays_within_0_1_mm():
    rng = np.random.default_rng(2)
    truth = Similarity2D(1520.0, -890.0, math.radians(0.4), 1.0 - 8e-6)
    points = simulated_points(12)
    local = np.column_stack([truth.apply(points[:, :2]) + rng.normal(0, 0.1e-3, (12, 2)), points[:, 2]])
    fit = fit_local(control("4-parameter", points, local))
    check = simulated_points(200, seed=5)
    east, north, _ = fit.apply(*check.T)
    error = np.hypot(east - truth.apply(check[:, :2])[:, 0], north - truth.apply(check[:, :2])[:, 1])
    assert error.max() < 1e-4
    assert 0.05 < fit.summary()["rms_mm"] < 0.25 and fit.summary()["loo_rms_mm"] > fit.summary()["rms_mm"]


def test_the_7_parameter_fit_reproduces_a_known_transformation():
    truth = Helmert7(-1200.0, 850.0, -12.5, 2e-5, -3e-5, math.radians(25.0), 6.0)
    points = simulated_points(8)
    fit = fit_local(control("7-parameter", points, truth.apply(points)))
    check = simulated_points(200, seed=11)
    np.testing.assert_allclose(np.column_stack(fit.apply(*check.T)), truth.apply(check), rtol=0, atol=1e-4)
    np.testing.assert_allclose(np.column_stack(fit.to_engineering(*truth.apply(check).T)), check, atol=1e-6)
    assert fit.summary()["parameters"]["rz_arcsec"] == pytest.approx(25.0 * 3600, rel=1e-9)


def test_a_wrong_point_is_a_notice_naming_it():
    truth = Similarity2D(100.0, 200.0, 0.01, 1.0)
    points = simulated_points(6)
    local = np.column_stack([truth.apply(points[:, :2]), np.full(6, np.nan)])
    local[3, 0] += 0.02  # a mistyped easting
    fit = fit_local(control("4-parameter", points, local))
    (notice,) = fit.notices()
    assert "CP3" in notice.message and "leave-one-out" in notice.message
    assert "height_mm" not in fit.summary()["residuals"][0]  # no local heights: none invented


BASE = {"track": {"start_station_m": 0.0}, "surveys": [{"name": "s", "folder": "s"}]}


def settings(local):
    return BASE | {"geodesy": {"crs": {"central_meridian_deg": 117.0}, "local": local}}


def point(e, n, h=30.0, **extra):
    return {"east_m": e, "north_m": n, "height_m": h, "local_east_m": e - 500000.0, "local_north_m": n - 3e6, **extra}


def test_project_settings_round_trip_and_apply(tmp_path):
    (tmp_path / "s").mkdir()
    (tmp_path / "s" / "survey.toml").touch()
    local = {"model": "4-parameter", "points": {"A": point(500100.0, 3000100.0), "B": point(501000.0, 3000900.0),
                                                "C": point(502000.0, 3000200.0)}}
    project = project_from_settings(settings(local), tmp_path)
    assert project.local_control.model == "4-parameter" and len(project.local_control.points) == 3
    again = project_from_settings(project.to_settings(), tmp_path)
    assert again.local_control == project.local_control
    east, north, _ = fit_local(again.local_control).apply(np.array([500500.0]), np.array([3000500.0]), np.array([1.0]))
    assert east[0] == pytest.approx(500.0, abs=1e-6) and north[0] == pytest.approx(500.0, abs=1e-6)


@pytest.mark.parametrize("local, message", [
    ({"model": "9-parameter", "points": {}}, "geodesy.local.model: expected one of 4-parameter, 7-parameter"),
    ({"points": {}}, "geodesy.local.points: expected [geodesy.local.points.<name>] tables"),
    ({"points": {"A": point(1.0, 2.0), "B": {"east_m": 1.0}}}, "geodesy.local.points.B: missing north_m"),
    ({"points": {"A": point(1.0, 2.0), "B": point(5.0, 9.0)}}, "at least 3 are needed"),
    ({"points": {"A": point(1.0, 2.0, local_height_m=3.0), "B": point(5.0, 9.0), "C": point(9.0, 1.0)}},
     "local_height_m is given for some points only"),
    ({"points": {"A": point(1.0, 2.0, oops=1), "B": point(5.0, 9.0), "C": point(9.0, 1.0)}},
     "geodesy.local.points.A.oops: unknown key"),
    ({"model": "7-parameter", "points": {"A": point(1.0, 2.0), "B": point(5.0, 9.0), "C": point(9.0, 1.0),
                                         "D": point(3.0, 3.0)}}, "missing local_height_m"),
    ({"points": {"A": point(1.0, 2.0) | {"north_m": "x"}, "B": point(5.0, 9.0), "C": point(9.0, 1.0)}},
     "geodesy.local.points.A.north_m: expected a number of metres"),
])
def test_bad_local_control_is_refused_with_its_key(tmp_path, local, message):
    (tmp_path / "s").mkdir()
    (tmp_path / "s" / "survey.toml").touch()
    with pytest.raises(ProjectError) as error:
        project_from_settings(settings(local), tmp_path)
    assert message in str(error.value)
