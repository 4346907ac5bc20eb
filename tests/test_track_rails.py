"""Rails from pose and chainage, on the simulator's navigation truth (no navigation error)."""

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from insrail.geodesy.ellipsoid import ELLIPSOIDS, Ellipsoid
from insrail.io.types import Gap, GaugeData
from insrail.nav import earth
from insrail.nav.rotation import euler_to_dcm
from insrail.track.chainage import stations_along_path
from insrail.track.rails import gauge_at_times, gauge_curve_correction_m, rails_from_pose
from track_truth import truth_reconstruction

MM = 1e-3


@pytest.fixture(scope="module")
def recon(short_perfect_survey):
    return truth_reconstruction(short_perfect_survey)


def test_reference_rail_and_its_station_match_the_truth(recon):
    truth = recon.track.sections(recon.nav["station_m"][::20])
    rails = recon.rails
    assert np.abs(rails.left_rail_enh_m[::20] - truth.left_rail_enh_m).max() < 0.01 * MM
    assert np.abs(recon.stations.reference_m - recon.nav["station_m"]).max() < 0.001 * MM


def test_other_rail_lies_on_the_true_rail_at_its_own_station(recon):
    # The trolley's cross axis is not square to the design (yaw, pitch x cant): the right rail
    # point lands up to a few mm ahead of or behind the reference section, at its own station.
    rails, stations = recon.rails, recon.stations
    along_shift = np.abs(stations.right_m - stations.reference_m)
    assert along_shift.max() > 1 * MM
    truth = recon.track.sections(stations.right_m[::20])
    error = rails.right_rail_enh_m[::20] - truth.right_rail_enh_m
    # The simulator lays the gauge out in the grid, rails-from-pose as a true length: the
    # projection's residual scale (a few 1e-6 at this site) leaves ~5 um across.
    assert np.abs(error[:, :2]).max() < 0.02 * MM
    # Vertically: the trolley rolls against the ellipsoid normal, the truth against normal heights;
    # the height-anomaly gradient (about 1e-5) over the gauge leaves ~15 um.
    assert np.abs(error[:, 2]).max() < 0.03 * MM


def test_cant_and_gauge_per_epoch(recon):
    truth = recon.track.sections(recon.nav["station_m"][::20])
    assert np.abs(recon.rails.cant_m[::20] - truth.cant_m).max() < 0.05 * MM
    assert np.allclose(recon.rails.gauge_m, recon.gauge.gauge_m, rtol=0, atol=1e-12)
    horizontal_gauge = np.linalg.norm(recon.rails.right_rail_enh_m - recon.rails.left_rail_enh_m, axis=1)
    # Plane distances carry the projection's scale (~1e-5 here): gauge agrees to 0.05 mm.
    assert np.abs(horizontal_gauge - recon.rails.gauge_m).max() < 0.05 * MM


def test_station_along_the_path_without_design(recon):
    start = recon.nav["station_m"][0]
    path = stations_along_path(recon.rails, start)
    error = path.reference_m - recon.nav["station_m"]
    # Plane length along the wavy centreline vs the design station: a few tenths of a mm per 100 m.
    assert np.abs(error).max() < 5 * MM
    assert np.all(np.diff(path.centre_m[::200]) >= -1e-6)


def test_stations_increase_with_travel_when_the_trolley_faces_backwards(recon):
    rails = recon.rails
    flipped = type(rails)(**{**rails.__dict__, "forward_enh": -rails.forward_enh})
    a = stations_along_path(rails, 100.0).centre_m
    b = stations_along_path(flipped, 100.0).centre_m
    assert np.allclose(a, b, atol=1e-9)


# ---------------------------------------------------------------- gauge
def test_gauge_curve_correction_signs_and_size():
    radius, spacing = 2000.0, 0.6
    versine = radius - np.sqrt(radius**2 - spacing**2 / 4)
    right_curve, left_curve = 1 / radius, -1 / radius
    assert gauge_curve_correction_m(right_curve, spacing, "left") == pytest.approx(versine, rel=1e-9)  # outer rail
    assert gauge_curve_correction_m(right_curve, spacing, "right") == pytest.approx(-versine, rel=1e-9)
    assert gauge_curve_correction_m(left_curve, spacing, "right") == pytest.approx(versine, rel=1e-9)
    assert gauge_curve_correction_m(left_curve, spacing, "left") == pytest.approx(-versine, rel=1e-9)
    assert gauge_curve_correction_m(0.0, spacing, "right") == 0.0
    assert np.all(gauge_curve_correction_m(np.array([1e-3, -1e-3]), 0.0, "left") == 0.0)
    with pytest.raises(ValueError, match="beam_rail"):
        gauge_curve_correction_m(1e-3, spacing, "middle")
    with pytest.raises(ValueError, match="beam_wheel_spacing_m"):
        gauge_curve_correction_m(1e-3, -0.1, "left")


@given(radius=st.floats(5.0, 1e6), spacing=st.floats(0.0, 2.0))
def test_gauge_curve_correction_is_the_versine(radius, spacing):
    expected = radius - np.sqrt(radius**2 - spacing**2 / 4)
    # The textbook form loses ~eps * R to cancellation; the function uses a stable form.
    assert abs(gauge_curve_correction_m(1 / radius, spacing, "left") - expected) <= 4e-16 * radius + 1e-9 * expected


def test_curve_correction_in_rails_from_pose_follows_the_curve(recon):
    spacing = 0.8
    sub = slice(None, None, 10)
    traj = type(recon.trajectory)(**{name: (value[sub] if isinstance(value, np.ndarray) else value)
                                     for name, value in recon.trajectory.__dict__.items()})
    corrected = rails_from_pose(traj, recon.trolley, recon.gauge, recon.to_engineering, beam_wheel_spacing_m=spacing)
    correction = corrected.gauge_m - recon.rails.gauge_m[sub]
    expected = gauge_curve_correction_m(recon.design.horizontal.curvature_at(recon.stations.reference_m[sub]),
                                        spacing, recon.trolley.reference_rail)
    assert np.abs(expected).max() > 30e-6  # the 2000 m curve: 40 um
    # Curvature from the measured path carries the rail's own irregularity curvature (1 mm
    # lateral waves: ~1e-4 1/m over the 10 m base, ~10 um of correction; up to ~25 um at the
    # 3 mm isolated bumps; the trolley play's few microradians of yaw per metre add a little), and
    # is exact on average on the circular arc.
    assert np.abs(correction - expected).max() < 0.035 * MM
    on_arc = np.abs(expected) > 0.999 * np.abs(expected).max()
    assert on_arc.sum() > 1000
    assert np.mean(correction[on_arc]) == pytest.approx(np.mean(expected[on_arc]), rel=0.05)
    given_curvature = recon.design.horizontal.curvature_at(recon.stations.reference_m[sub])
    with_design = rails_from_pose(traj, recon.trolley, recon.gauge, recon.to_engineering,
                                  beam_wheel_spacing_m=spacing, curvature_per_m=given_curvature)
    assert np.allclose(with_design.gauge_m - recon.rails.gauge_m[sub], expected, rtol=0, atol=1e-15)


def test_gauge_at_times_blanks_gaps_and_outside():
    gauge = GaugeData(np.array([0.0, 1.0, 2.0, 3.0]), np.array([1.435, 1.436, 1.437, 1.438]),
                      gaps=(Gap(1.0, 2.0),))
    values = gauge_at_times(gauge, np.array([-0.5, 0.5, 1.5, 2.5, 3.5]))
    assert np.isnan(values[[0, 2, 4]]).all()
    assert values[1] == pytest.approx(1.4355) and values[3] == pytest.approx(1.4375)


def test_rails_from_pose_refuses_a_bad_reference_rail(recon):
    bad = type(recon.trolley)(**{**recon.trolley.__dict__, "reference_rail": "centre"})
    with pytest.raises(ValueError, match="reference_rail"):
        rails_from_pose(recon.trajectory, bad, recon.gauge, recon.to_engineering)


@pytest.mark.parametrize("ellipsoid", [*ELLIPSOIDS.values(), Ellipsoid("custom", 6_378_300.0, 297.0)],
                         ids=[*ELLIPSOIDS, "custom"])
def test_rails_from_pose_works_on_the_trajectorys_ellipsoid(recon, ellipsoid):
    """Every ellipsoid a project may choose (issue 32: Xian80 and Krassovsky were refused by name):
    the lever arm goes through ECEF on the trajectory's own ellipsoid, so with ECEF on that
    ellipsoid as the 'engineering' frame the reference rail is the IMU plus C_e^b l exactly."""
    trajectory = replace(recon.trajectory, ellipsoid=ellipsoid)

    def ecef(lat, lon, h):
        return tuple(earth.geodetic_to_ecef(lat, lon, h, ellipsoid).T)

    rails = rails_from_pose(trajectory, recon.trolley, recon.gauge, ecef)
    part = slice(0, 2000, 50)
    lat, lon, h = trajectory.lat_rad[part], trajectory.lon_rad[part], trajectory.height_m[part]
    c_eb = earth.dcm_ecef_from_ned(lat, lon) @ euler_to_dcm(*trajectory.rpy_rad[part].T)
    expected = earth.geodetic_to_ecef(lat, lon, h, ellipsoid) + c_eb @ np.asarray(recon.trolley.imu_to_reference_rail_m)
    assert np.abs(rails.reference_rail_enh_m[part] - expected).max() < 1e-6
    across = np.linalg.norm(rails.right_rail_enh_m[part] - rails.left_rail_enh_m[part], axis=1)
    assert np.allclose(across, rails.gauge_m[part], rtol=0, atol=1e-6)


@settings(max_examples=25, deadline=None)
@given(reference=st.sampled_from(["left", "right"]), roll=st.floats(-0.1, 0.1), heading=st.floats(-3.1, 3.1),
       gauge=st.floats(1.40, 1.47))
def test_rails_from_pose_geometry(recon, reference, roll, heading, gauge):
    """One epoch in a local frame: other rail at the gauge across the trolley, cant from the roll."""
    traj = type(recon.trajectory)(**{name: (value[:3].copy() if isinstance(value, np.ndarray) else value)
                                     for name, value in recon.trajectory.__dict__.items()})
    traj.rpy_rad[:] = [roll, 0.0, heading]
    trolley = type(recon.trolley)(**{**recon.trolley.__dict__, "reference_rail": reference,
                                     "mounting_rpy_rad": np.zeros(3)})
    rails = rails_from_pose(traj, trolley, GaugeData(traj.time_s, np.full(3, gauge)), recon.to_engineering)
    across = rails.right_rail_enh_m - rails.left_rail_enh_m
    assert np.linalg.norm(across, axis=1) == pytest.approx(gauge, abs=2e-5 * gauge)
    assert rails.cant_m == pytest.approx(1.5 * np.sin(roll), abs=1e-9)
    # Left rail higher for positive roll (right side down); cross slope from the rail heights.
    assert np.allclose(-across[:, 2] / gauge, np.sin(roll), atol=2e-5)
    assert np.allclose(rails.centre_enh_m, 0.5 * (rails.left_rail_enh_m + rails.right_rail_enh_m))
