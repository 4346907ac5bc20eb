"""The fusion engine on the simulated benchmark survey, and its handling of bad input.

The bounds are regression bounds a little looser than the figures benchmarks/fusion.py
measures (seed 1: smoothed 150 m-lag 0.7 / 1.2 mm, 5 m-lag 0.10 / 0.10 mm).
"""

import tomllib
from dataclasses import replace

import numpy as np
import pytest

from insrail.io.survey import read_survey
from insrail.nav.earth import CGCS2000
from insrail.nav.fusion import FusionOptions, fuse_survey
from insrail.nav.imu_gaps import bridge_gaps
from insrail.sim.evaluation import trajectory_errors
from insrail.sim.truth import read_nav_truth

JUMP_TIME_OFFSET_S = 900.0  # after the start of the survey: the trolley is walking


@pytest.fixture(scope="module")
def survey(short_nav_survey):
    return read_survey(short_nav_survey)


@pytest.fixture(scope="module")
def fused(survey):
    """Fusion of the survey with one GNSS epoch moved 5 m north (an outlier to reject)."""
    gnss = survey.gnss
    k = int(np.searchsorted(gnss.time_s, gnss.time_s[0] + JUMP_TIME_OFFSET_S))
    lat = gnss.lat_rad.copy()
    lat[k] += 5.0 / 6.35e6
    bad = replace(survey, gnss=replace(gnss, lat_rad=lat))
    return fuse_survey(bad, FusionOptions(), ellipsoid=CGCS2000, output_every=2), float(gnss.time_s[k])


def test_smoothed_solution_meets_the_accuracy_bars(short_nav_survey, fused):
    result, _ = fused
    truth = read_nav_truth(short_nav_survey / "truth" / "nav.npy")
    outages = tomllib.loads((short_nav_survey / "truth" / "errors.toml").read_text())["gnss_outages_s"]
    smoothed = trajectory_errors(result.trajectory, truth, CGCS2000)
    forward = trajectory_errors(result.forward, truth, CGCS2000)
    assert smoothed.rms_horizontal_m() < 0.010 and smoothed.rms_vertical_m() < 0.015
    assert np.all(np.rad2deg(smoothed.rms_attitude_rad()) < [0.003, 0.003, 0.01])
    assert max(smoothed.max_in(outages)) < 0.020
    lat5, ver5 = smoothed.lag_difference_sigma_m(5.0)
    lat150, ver150 = smoothed.lag_difference_sigma_m(150.0)
    assert lat5 < 0.25e-3 and ver5 < 0.25e-3
    assert lat150 < 1.5e-3 and ver150 < 2.0e-3
    # The smoother is what gets the short-wave accuracy: forward alone is several times worse.
    assert forward.lag_difference_sigma_m(5.0)[0] > 3 * lat5
    # Odometer scale: +0.15 % simulated (the wheel on the outer rail adds about 0.02 %).
    assert result.trajectory.odometer_scale[-1] == pytest.approx(0.0015, abs=4e-4)
    # Normalised innovations near their degrees of freedom: the noise model fits the data.
    nis = result.statistics["gnss_position"]["mean_nis"]
    assert 1.0 < nis < 6.0


def test_a_gnss_jump_is_rejected_and_listed(short_nav_survey, fused):
    result, jump_time = fused
    rejected = [r for r in result.rejections if r.measurement == "gnss_position"]
    assert [round(r.time_s, 3) for r in rejected] == [round(jump_time, 3)]
    assert rejected[0].innovation[0] == pytest.approx(-5.0, abs=0.05)
    assert result.statistics["gnss_position"]["rejected"] == 1
    truth = read_nav_truth(short_nav_survey / "truth" / "nav.npy")
    errors = trajectory_errors(result.trajectory, truth, CGCS2000)
    near = np.abs(errors.time_s - jump_time) < 5.0
    assert np.abs(errors.ned_m[near, 0]).max() < 0.02


def test_gnss_that_does_not_overlap_the_imu_is_a_clear_error(survey):
    shifted = replace(survey, gnss=replace(survey.gnss, time_s=survey.gnss.time_s + 2 * 86400.0))
    with pytest.raises(ValueError, match="no GNSS epoch lies within the IMU data"):
        fuse_survey(shifted)


def test_imu_gaps_are_bridged_with_a_warning_and_too_long_ones_refused(survey):
    imu = survey.imu
    keep = np.ones(len(imu), dtype=bool)
    keep[100_000:100_012] = False  # 12 samples (60 ms) lost by the logger
    holed = replace(imu, time_s=imu.time_s[keep], dtheta_rad=imu.dtheta_rad[keep], dvel_mps=imu.dvel_mps[keep])
    bridged, warnings = bridge_gaps(holed)
    assert len(bridged) == len(imu) and np.allclose(bridged.time_s, imu.time_s)
    assert len(warnings) == 1 and "0.065 s" in warnings[0] and "12 missing samples" in warnings[0]
    # Interpolated rates are close to the lost ones (the trolley moves smoothly).
    assert np.abs(bridged.dvel_mps[100_000:100_012] - imu.dvel_mps[100_000:100_012]).max() < 1e-4
    keep[200_000:201_200] = False  # 6 s
    with pytest.raises(ValueError, match=r"IMU data gap of 6\.005 s after t = .* cannot be bridged"):
        bridge_gaps(replace(imu, time_s=imu.time_s[keep], dtheta_rad=imu.dtheta_rad[keep], dvel_mps=imu.dvel_mps[keep]))


def test_cli_fuse_writes_the_results(short_nav_survey, tmp_path, capsys):
    from insrail.cli.main import main
    from insrail.nav.trajectory import load_trajectory

    assert main(["fuse", str(short_nav_survey), "--out", str(tmp_path), "--gnss-only", "--no-smoother", "--rate", "10",
                 "--text"]) == 0
    out = capsys.readouterr().out
    assert "Fused" in out and "gnss_position" in out and "odometer_nhc" not in out
    traj = load_trajectory(tmp_path / "trajectory.npy")
    assert np.median(np.diff(traj.time_s)) == pytest.approx(0.1)
    log = tomllib.loads((tmp_path / "fusion_log.toml").read_text())
    assert log["options"]["use_nhc"] is False and "gnss_position" in log["measurements"]
    nav_lines = (tmp_path / "trajectory.nav").read_text().splitlines()
    assert len(nav_lines) == len(traj) + 2 and len(nav_lines[2].split()) == 11


def test_cli_fuse_streams_the_trajectory_and_writes_text_and_forward_only_when_asked(short_nav_survey, survey, tmp_path):
    from insrail.cli.main import main
    from insrail.nav.trajectory import load_trajectory

    assert main(["fuse", str(short_nav_survey), "--out", str(tmp_path), "--rate", "20", "--forward"]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["forward_trajectory.npy", "fusion_log.toml", "trajectory.npy"]
    streamed = load_trajectory(tmp_path / "trajectory.npy")
    forward = load_trajectory(tmp_path / "forward_trajectory.npy", smoothed=False)
    in_memory = fuse_survey(survey, FusionOptions(), ellipsoid=CGCS2000, output_every=10)
    assert len(streamed) == len(in_memory.trajectory) == len(forward)
    for name in ("time_s", "lat_rad", "height_m", "rpy_rad", "sigma_pos_ned_m", "odometer_scale"):
        np.testing.assert_array_equal(getattr(streamed, name), getattr(in_memory.trajectory, name))
    assert np.abs(forward.height_m - streamed.height_m).max() > 1e-4  # the forward solution, not a copy
    streamed_result = fuse_survey(survey, FusionOptions(smoother=False), ellipsoid=CGCS2000, output_every=50,
                                  trajectory_file=tmp_path / "again.npy")
    assert streamed_result.trajectory.ellipsoid.name == "CGCS2000" and not streamed_result.trajectory.smoothed
    # without --forward the forward solution is kept at the update epochs only
    assert len(in_memory.forward) == in_memory.info["update_epochs"]


@pytest.fixture(scope="module")
def tunnel_survey(tmp_path_factory):
    """`short` with a 400 s GNSS outage (a tunnel) and two total-station prism fixes inside it."""
    from insrail.sim.scenario import PrismSpec, preset
    from insrail.sim.simulate import simulate

    base = preset("short")
    config = replace(base, gnss=replace(base.gnss, outages=((1500.0, 400.0),)),
                     prism=PrismSpec(stations_m=(1680.0, 1820.0)))
    out = tmp_path_factory.mktemp("sim") / "tunnel"
    simulate(config, seed=5, out_dir=out, imu_format="npy")
    return out, config


def test_prism_fixes_on_cpiii_bound_the_error_in_a_gnss_outage(tunnel_survey):
    from insrail.geodesy import EngineeringCRS
    from insrail.nav.measurements import PositionFix
    from insrail.sim.simulate import height_anomaly

    folder, config = tunnel_survey
    survey = read_survey(folder)
    assert len(survey.prism) == 2
    crs = EngineeringCRS.from_settings(config.geodetic.crs)

    def to_geodetic(east, north, normal_height):
        lat, lon = crs.to_geodetic(east, north)
        return lat, lon, normal_height + height_anomaly(config, east, north)

    fixes = PositionFix.from_prism(survey.prism, survey.manifest.trolley.imu_to_prism_m, to_geodetic)
    truth = read_nav_truth(folder / "truth" / "nav.npy")
    outage = tomllib.loads((folder / "truth" / "errors.toml").read_text())["gnss_outages_s"]
    options = FusionOptions(use_nhc=False)  # a weaker INS makes the fixes' effect plain
    without = trajectory_errors(fuse_survey(survey, options, ellipsoid=CGCS2000, output_every=4).trajectory, truth, CGCS2000)
    result = fuse_survey(survey, options, ellipsoid=CGCS2000, output_every=4, position_fixes=fixes)
    with_fixes = trajectory_errors(result.trajectory, truth, CGCS2000)
    assert result.statistics["position_fix"]["used"] == 2
    assert max(with_fixes.max_in(outage)) < 0.5 * max(without.max_in(outage))
    at_fix = np.abs(with_fixes.time_s[:, None] - survey.prism.time_s).min(axis=1) < 0.05
    assert np.abs(with_fixes.ned_m[at_fix]).max() < 0.004


def test_a_survey_that_starts_moving_is_aligned_on_the_gnss_track(tmp_path):
    from insrail.sim.scenario import preset
    from insrail.sim.simulate import simulate

    base = preset("short")
    config = replace(base, motion=replace(base.motion, static_start_s=5.0, end_station_m=1650.0, stops=((1450.0, 20.0),)))
    simulate(config, seed=2, out_dir=tmp_path / "moving", imu_format="npy")
    result = fuse_survey(read_survey(tmp_path / "moving"), ellipsoid=CGCS2000, output_every=4)
    assert result.info["alignment"] == "track"
    errors = trajectory_errors(result.trajectory, read_nav_truth(tmp_path / "moving" / "truth" / "nav.npy"), CGCS2000)
    assert np.all(np.rad2deg(errors.rms_attitude_rad()) < [0.004, 0.004, 0.01])
    assert errors.rms_horizontal_m() < 0.012
    assert max(errors.lag_difference_sigma_m(5.0)) < 0.3e-3


def test_gnss_quality_policy_inflates_float_and_excludes_single(survey):
    from insrail.nav.fusion import gnss_by_quality

    gnss = survey.gnss
    quality = np.ones(len(gnss), dtype=int)
    quality[100:150] = 2
    quality[300:310] = 5
    mixed = replace(gnss, quality=quality)
    kept, counts = gnss_by_quality(mixed, FusionOptions().gnss_quality_policy)
    assert counts == {"fix": {"epochs": len(gnss) - 60, "sigma_factor": 1.0, "used": True},
                      "float": {"epochs": 50, "sigma_factor": 3.0, "used": True},
                      "single": {"epochs": 10, "sigma_factor": None, "used": False}}
    assert len(kept) == len(gnss) - 10
    assert np.allclose(kept.sigma_ned_m[100:150], 3.0 * gnss.sigma_ned_m[100:150])
    assert not np.isin(gnss.time_s[300:310], kept.time_s).any()


def _first_seconds(survey, seconds):
    imu = survey.imu
    keep = imu.time_s < imu.time_s[0] + seconds
    return replace(survey, imu=replace(imu, time_s=imu.time_s[keep], dtheta_rad=imu.dtheta_rad[keep],
                                       dvel_mps=imu.dvel_mps[keep]))


def test_a_survey_without_odometer_fuses_on_gnss_nhc_and_zupt(short_nav_survey, survey):
    """Roles imu + gnss (the first 700 s: 5 min static start, a stop, no GNSS outage): stops come
    from the IMU and the GNSS alone, and the result says where its along-track scale comes from."""
    truth = read_nav_truth(short_nav_survey / "truth" / "nav.npy")
    result = fuse_survey(replace(_first_seconds(survey, 700.0), odometer=None), ellipsoid=CGCS2000, output_every=4)
    assert result.info["alignment"] == "static" and len(result.stops) == 2
    assert result.statistics["zupt"]["used"] > 2000 and result.statistics["zupt"]["rejected"] == 0
    assert result.statistics["gnss_position"]["rejected"] == 0
    assert any("no odometer" in n.message and "GNSS positions only" in n.message for n in result.info["notices"])
    errors = trajectory_errors(result.trajectory, truth, CGCS2000)
    assert errors.rms_horizontal_m() < 0.008 and errors.rms_vertical_m() < 0.008
    # the NHC without an odometer at 2 mm/s (fusion.NHC_SIGMA_WITHOUT_ODOMETER_MPS: an outage's along-track
    # sigma honest) costs a tenth of a millimetre here (0.40 / 0.34 mm; at the odometer's 0.45 mm/s < 0.3 mm)
    assert max(errors.lag_difference_sigma_m(5.0)) < 0.45e-3


def test_a_survey_without_gnss_starts_from_the_prism_fixes(short_nav_survey, survey):
    """No GNSS (a tunnel): a total-station fix during the static start and one every 60 m give the
    position; the nav-grade unit gyrocompasses; the odometer and NHC carry between the fixes."""
    from insrail.nav.measurements import PositionFix

    truth = read_nav_truth(short_nav_survey / "truth" / "nav.npy")
    station = truth["station_m"]
    rows = np.unique(np.concatenate([[np.searchsorted(truth["time_s"], truth["time_s"][0] + 20.0)],
                                     np.searchsorted(station, np.arange(station[0] + 60.0, station[-1], 60.0))]))
    rows = rows[truth["time_s"][rows] < truth["time_s"][0] + 700.0]
    fixes = PositionFix(truth["time_s"][rows], truth["lat_rad"][rows], truth["lon_rad"][rows], truth["height_m"][rows],
                        np.full(len(rows), 0.001), np.zeros(3))
    result = fuse_survey(replace(_first_seconds(survey, 700.0), gnss=None), ellipsoid=CGCS2000, output_every=4,
                  position_fixes=fixes)
    assert result.info["alignment"] == "static" and "gnss_position" not in result.statistics
    # the first one starts the filter (5 mm) and, the trolley standing still, counts with its own 1 mm too
    assert result.statistics["position_fix"]["used"] == len(rows)
    errors = trajectory_errors(result.trajectory, truth, CGCS2000)
    assert errors.rms_horizontal_m() < 0.004 and errors.rms_vertical_m() < 0.003
    assert max(errors.lag_difference_sigma_m(5.0)) < 0.3e-3
    with pytest.raises(ValueError, match="neither GNSS nor total-station prism fixes"):
        fuse_survey(replace(survey, gnss=None))


def test_cli_fuse_places_prism_fixes_by_the_project_and_refuses_them_without(tunnel_survey, tmp_path, capsys):
    """`insrail fuse --project` uses the survey's prism fixes as `insrail process` does; without a project
    a survey whose fixes are its only position source is refused, naming --project."""
    import shutil

    from insrail.cli.main import main
    from insrail.io.survey import read_manifest, write_manifest
    from insrail.project.demo import project_for_simulated_survey

    folder, _ = tunnel_survey
    survey = tmp_path / "project" / "surveys" / "tunnel"
    shutil.copytree(folder, survey)
    project_for_simulated_survey(tmp_path / "project", survey, name="tunnel")
    assert main(["fuse", str(survey), "--project", str(tmp_path / "project"), "--out", str(tmp_path / "with"),
                 "--no-smoother", "--rate", "10"]) == 0
    out = capsys.readouterr().out
    assert "note: fuse: 2 total-station prism fix(es) placed by project tunnel" in out
    log = tomllib.loads((tmp_path / "with" / "fusion_log.toml").read_text())
    assert log["prism_fixes"] == 2 and log["measurements"]["position_fix"]["used"] == 2
    assert main(["fuse", str(survey), "--project", str(tmp_path / "project"), "--ellipsoid", "WGS84",
                 "--out", str(tmp_path / "other")]) == 2  # the fixes' geodetic coordinates are on the project's
    assert "conflicts with the project's CRS on CGCS2000" in capsys.readouterr().err
    manifest = read_manifest(survey)  # the same survey without GNSS: the fixes are all it has
    write_manifest(survey, replace(manifest, files={r: e for r, e in manifest.files.items() if r != "gnss"}))
    assert main(["fuse", str(survey), "--out", str(tmp_path / "without"), "--no-smoother"]) == 1
    err = capsys.readouterr().err
    assert "2 total-station observation(s) are its only position source" in err and "--project PROJECT" in err
    assert not (tmp_path / "without" / "trajectory.npy").exists()


@pytest.mark.parametrize("chunk", [2, 65536])
def test_summed_records_start_at_the_filters_first_record_and_keep_every_increment(chunk, monkeypatch):
    from insrail.io.types import ImuIncrements
    from insrail.nav import fusion
    from insrail.nav.fusion import summed_records

    monkeypatch.setattr(fusion, "SUMMED_CHUNK_GROUPS", chunk)  # by chunks of 2 groups: the same sums

    rng = np.random.default_rng(3)
    n = 23
    imu = ImuIncrements(np.arange(n) * 0.005 + 100.0, rng.normal(size=(n, 3)), rng.normal(size=(n, 3)), gps_week=2380)
    coarse = summed_records(imu, 2, 4)  # record 2, then 3-6, 7-10, 11-14, 15-18, 19-22
    assert len(coarse) == 6 and coarse.gps_week == 2380
    np.testing.assert_array_equal(coarse.time_s, imu.time_s[[2, 6, 10, 14, 18, 22]])
    np.testing.assert_array_equal(coarse.dtheta_rad[0], imu.dtheta_rad[2])
    np.testing.assert_allclose(coarse.dvel_mps[1], imu.dvel_mps[3:7].sum(axis=0), rtol=1e-14)
    np.testing.assert_allclose(coarse.dtheta_rad[1:].sum(axis=0), imu.dtheta_rad[3:].sum(axis=0), rtol=1e-12)
    shorter = summed_records(replace(imu, time_s=imu.time_s[:21], dtheta_rad=imu.dtheta_rad[:21],
                                     dvel_mps=imu.dvel_mps[:21]), 2, 4)
    np.testing.assert_array_equal(shorter.time_s, imu.time_s[[2, 6, 10, 14, 18]])  # 19, 20: no whole group


def test_a_pass_on_summed_records_keeps_the_velocity_direction(short_nav_survey, survey):
    """The mounting's pass (insrail.project.mounting_stage): the IMU summed 4 at a time (200 -> 50 Hz), no NHC.
    The direction of travel in the body frame, what the pass is for, stays within 0.001 deg of the same pass's
    on every record; the trajectory within a millimetre of its accuracy."""
    from insrail.nav.fusion import aiding_for, fuse
    from insrail.nav.imu_profile import load_imu_profile
    from insrail.nav.rotation import euler_to_dcm

    options = FusionOptions(use_nhc=False, estimate_play=False)
    profile = load_imu_profile(survey.manifest.imu_profile)
    part = _first_seconds(survey, 1200.0)
    result = fuse(part.imu, aiding_for(part, options, profile), profile, options, CGCS2000, output_every=5,
                  imu_every=4)
    trajectory = result.trajectory
    assert np.all(np.isin(trajectory.time_s, part.imu.time_s))  # stamped with the full-rate records' times
    assert np.median(np.diff(trajectory.time_s)) == pytest.approx(0.1)
    assert result.integrity.trusted and result.statistics["gnss_position"]["rejected"] == 0
    truth = read_nav_truth(short_nav_survey / "truth" / "nav.npy")
    errors = trajectory_errors(trajectory, truth, CGCS2000)
    c_bn = euler_to_dcm(*np.asarray(trajectory.rpy_rad).T)
    v_b = np.einsum("kji,kj->ki", c_bn, np.asarray(trajectory.vel_ned_mps))
    moving = np.linalg.norm(v_b, axis=1) > 0.3
    assert moving.sum() > 1000
    yaw = np.degrees(np.mean(np.arctan2(v_b[moving, 1], v_b[moving, 0])))
    pitch = np.degrees(np.mean(np.arctan2(v_b[moving, 2], v_b[moving, 0])))
    full = fuse(part.imu, aiding_for(part, options, profile), profile, options, CGCS2000, output_every=20)
    c_full = euler_to_dcm(*np.asarray(full.trajectory.rpy_rad).T)
    v_full = np.einsum("kji,kj->ki", c_full, np.asarray(full.trajectory.vel_ned_mps))
    on = np.linalg.norm(v_full, axis=1) > 0.3
    # the same pass on every record: 10.4 / 12.7 mm, attitude (0.0022, 0.0011, 0.0012) deg; summed: 10.3 / 12.7 mm,
    # (0.0022, 0.0011, 0.0013) deg; the directions of travel 0.00006 deg (yaw) and 0.000002 deg (pitch) apart
    full_errors = trajectory_errors(full.trajectory, truth, CGCS2000)
    assert errors.rms_horizontal_m() < full_errors.rms_horizontal_m() + 0.001
    assert errors.rms_vertical_m() < full_errors.rms_vertical_m() + 0.001
    assert np.all(np.degrees(errors.rms_attitude_rad()) < 0.003)
    assert yaw == pytest.approx(np.degrees(np.mean(np.arctan2(v_full[on, 1], v_full[on, 0]))), abs=0.001)
    assert pitch == pytest.approx(np.degrees(np.mean(np.arctan2(v_full[on, 2], v_full[on, 0]))), abs=0.001)
