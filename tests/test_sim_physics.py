"""The simulator is physically right: its increments, truth and geometry agree.

One `short` survey with an error-free IMU is simulated once per test session; the
checks below would fail on a wrong sign of earth rate, gravity or Coriolis, a lever
arm applied in the wrong frame, a coning/sculling error in the increments, or a
geometry inconsistent with the design.
"""

import numpy as np
import pytest

from ecef_strapdown import integrate_ecef
from insrail.nav import earth
from insrail.nav.rotation import euler_to_dcm
from insrail.sim.truth import read_nav_truth, read_sleeper_truth


@pytest.fixture(scope="module")
def nav_truth(short_perfect_survey):
    return read_nav_truth(short_perfect_survey / "truth" / "nav.npy")


@pytest.fixture(scope="module")
def imu(short_perfect_survey):
    from insrail.io.imu import read_imu_kfgins

    return read_imu_kfgins(short_perfect_survey / "imu.txt")


def test_at_rest_accelerometers_sense_normal_gravity_and_gyros_earth_rate(imu, nav_truth):
    # The first minutes are the static alignment period. The nominal interval, not a
    # difference of two times of week (off by up to 3e-11 s, i.e. 1e-9 m/s^2 here).
    dt = round(float(np.median(np.diff(imu.time_s))), 9)
    rest = slice(1, int(200 / dt))
    f = np.linalg.norm(imu.dvel_mps[rest], axis=1) / dt
    w = np.linalg.norm(imu.dtheta_rad[rest], axis=1) / dt
    g = earth.normal_gravity(nav_truth["lat_rad"][rest], nav_truth["height_m"][rest])
    assert np.abs(f - g).max() < 1e-12
    assert np.abs(w - earth.WGS84.omega).max() < 1e-16
    # And the direction: specific force points up (-z in a level FRD body).
    assert np.all(imu.dvel_mps[rest, 2] < 0)


def test_reference_strapdown_reproduces_truth_over_ten_minutes(imu, nav_truth):
    dt = np.diff(imu.time_s)[0]
    k0 = int(150 / dt)  # 150 s before the trolley moves off, then 450 s of walking, stops and curve
    k1 = k0 + int(600 / dt)
    row = nav_truth[k0]
    r0 = earth.geodetic_to_ecef(row["lat_rad"], row["lon_rad"], row["height_m"], earth.CGCS2000)
    c_ne = earth.dcm_ecef_from_ned(row["lat_rad"], row["lon_rad"])  # the same on both ellipsoids
    v0 = c_ne @ row["vel_ned_mps"]
    c_be = c_ne @ euler_to_dcm(*row["rpy_rad"])
    positions = integrate_ecef(
        imu.time_s[k0 : k1 + 1], imu.dtheta_rad[k0 : k1 + 1], imu.dvel_mps[k0 : k1 + 1],
        r0, v0, c_be, imu.dtheta_rad[k0], imu.dvel_mps[k0], earth.CGCS2000.f,
    )
    truth = nav_truth[k0 + 1 : k1 + 1]
    true_ecef = earth.geodetic_to_ecef(truth["lat_rad"], truth["lon_rad"], truth["height_m"], earth.CGCS2000)
    error = np.linalg.norm(positions - true_ecef, axis=1)
    travelled = truth["station_m"][-1] - row["station_m"]
    assert travelled > 400.0  # the window really covers motion
    assert error.max() < 0.0001  # the issue asks "a few mm over 10 minutes"; measured 5 micrometres


def test_arc_radius_recovered_from_truth_coordinates(short_perfect_survey):
    sleepers = read_sleeper_truth(short_perfect_survey / "truth" / "sleepers.csv")
    # The short design's arc: stations 1360-1780 m, R = 2000 m.
    on_arc = (sleepers["station"] > 1370) & (sleepers["station"] < 1770)
    x, y = sleepers["centre_e"][on_arc], sleepers["centre_n"][on_arc]
    x0, y0 = x.mean(), y.mean()
    u, v = x - x0, y - y0
    # Algebraic circle fit then Gauss-Newton on the geometric distance.
    a = np.column_stack([u, v, np.ones_like(u)])
    c = np.linalg.lstsq(a, u**2 + v**2, rcond=None)[0]
    centre = c[:2] / 2
    radius = np.sqrt(c[2] + centre @ centre)
    for _ in range(10):
        d = np.hypot(u - centre[0], v - centre[1])
        jac = np.column_stack([-(u - centre[0]) / d, -(v - centre[1]) / d, -np.ones_like(d)])
        step = np.linalg.lstsq(jac, -(d - radius), rcond=None)[0]
        centre, radius = centre + step[:2], radius + step[2]
    assert radius == pytest.approx(2000.0, abs=0.5)


def test_rail_geometry_is_consistent_with_gauge_and_cant(short_perfect_survey):
    s = read_sleeper_truth(short_perfect_survey / "truth" / "sleepers.csv")
    left = np.column_stack([s["left_e"], s["left_n"], s["left_h"]])
    right = np.column_stack([s["right_e"], s["right_n"], s["right_h"]])
    centre = np.column_stack([s["centre_e"], s["centre_n"], s["centre_h"]])
    assert np.allclose(np.linalg.norm(right - left, axis=1), s["gauge"], atol=2e-6)
    assert np.allclose(0.5 * (left + right), centre, atol=1e-6)
    # cant = 1.5 m * sin(cross slope); the rail tops (gauge apart) differ by gauge * sin(slope).
    assert np.allclose((left[:, 2] - right[:, 2]) / s["gauge"] * 1.5, s["cant"], atol=2e-6)
    assert np.allclose(s["cant"] - s["design_cant"], s["cross_level"], atol=1e-9)
    # Injected irregularities have the requested size.
    assert 0.6e-3 < np.std(s["lateral"]) < 1.8e-3
    assert np.max(np.abs(s["design_cant"])) == pytest.approx(0.120, abs=1e-9)


def test_ned_mechanization_reproduces_the_simulator_truth(imu, nav_truth):
    """insrail.nav's compiled NED strapdown (independent of the simulator's e-frame kinematics)
    on the error-free increments: micrometres over 10 minutes."""
    from insrail.io.types import ImuIncrements
    from insrail.nav.mechanization import NavState, integrate

    dt = np.diff(imu.time_s)[0]
    k0 = int(150 / dt)
    k1 = k0 + int(600 / dt)
    sub = ImuIncrements(imu.time_s[k0 : k1 + 1], imu.dtheta_rad[k0 : k1 + 1], imu.dvel_mps[k0 : k1 + 1])
    row = nav_truth[k0]
    start = NavState.from_euler(row["time_s"], row["lat_rad"], row["lon_rad"], row["height_m"], row["vel_ned_mps"], *row["rpy_rad"])
    solution = integrate(sub, start, ellipsoid=earth.CGCS2000)
    truth = nav_truth[k0 : k1 + 1]
    r_m, r_n = earth.radii(truth["lat_rad"])
    north = (solution.lat_rad - truth["lat_rad"]) * r_m
    east = (solution.lon_rad - truth["lon_rad"]) * r_n * np.cos(truth["lat_rad"])
    assert np.abs(north).max() < 1e-4 and np.abs(east).max() < 1e-4
    assert np.abs(solution.height_m - truth["height_m"]).max() < 1e-4
    assert np.abs(np.angle(np.exp(1j * (solution.heading_rad - truth["rpy_rad"][:, 2])))).max() < 1e-9
