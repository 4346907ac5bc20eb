"""Run a scenario: build the true track and motion, generate every sensor, write the survey.

``simulate(config, seed, out_dir)`` writes a survey folder (the raw files in the formats of
``insrail.io`` and ``survey.toml``) with a ``truth/`` sub-folder. The folder is built under a
temporary name and renamed when complete, so a cancelled or failed run leaves nothing
half-written.
"""

from __future__ import annotations

import math
import os
import shutil
import tempfile
from dataclasses import asdict, dataclass, replace
from pathlib import Path

import numpy as np
import tomli_w

from insrail import __version__
from insrail.geodesy import EngineeringCRS
from insrail.io.atomic import save_npy
from insrail.io.control import write_benchmarks, write_prism_enu
from insrail.io.imu import write_imu_kfgins, write_imu_npy
from insrail.io.odometer import write_odometer_distance, write_odometer_pulses
from insrail.io.rtklib import write_rtklib_pos
from insrail.io.survey import SurveyFile, SurveyManifest, write_manifest
from insrail.io.track_sensors import write_gauge_mm, write_sleeper_times
from insrail.io.types import (
    Benchmarks,
    GaugeData,
    GnssSolution,
    ImuIncrements,
    OdometerData,
    PrismObservations,
    SleeperPulses,
)
from insrail.nav import earth
from insrail.nav.imu_profile import load_imu_profile
from insrail.nav.rotation import euler_to_dcm
from insrail.notices import Phrase
from insrail.progress import CancelToken, ProgressFn, StepProgress, check_cancel
from insrail.sim import sensors
from insrail.sim.design import design_alignment
from insrail.sim.irregularity import random_irregularity
from insrail.sim.kinematics import TrolleyKinematics
from insrail.sim.motion import walking_profile
from insrail.sim.scenario import ScenarioConfig, TrolleyPlaySpec
from insrail.sim.track import TrueTrack
from insrail.sim.truth import ANTENNA_TRUTH_DTYPE, NAV_TRUTH_DTYPE, write_sleeper_truth

#: IMU epochs per vectorised chunk: bounds memory (about 60 MB of temporaries) for any length.
CHUNK_EPOCHS = 50_000


@dataclass(frozen=True)
class SimulationResult:
    folder: Path
    imu_epochs: int
    gnss_epochs: int
    sleepers: int
    duration_s: float
    length_m: float
    files: dict[str, Path]


def height_anomaly(config: ScenarioConfig, east_m, north_m):
    """The scenario's true height anomaly zeta = h - H [m] at plane coordinates."""
    g = config.geodetic
    de = np.asarray(east_m) - config.design.start_east_m
    dn = np.asarray(north_m) - config.design.start_north_m
    return g.zeta0_m + g.zeta_gradient[0] * de + g.zeta_gradient[1] * dn + g.zeta_curvature_per_m * (de**2 + dn**2)


def true_track(config: ScenarioConfig, rng: np.random.Generator) -> TrueTrack:
    irr = config.irregularities
    band = dict(shortest_wavelength_m=irr.band_m[0], longest_wavelength_m=irr.band_m[1])
    gauge_band = dict(shortest_wavelength_m=irr.gauge_band_m[0], longest_wavelength_m=irr.gauge_band_m[1])
    lateral = random_irregularity(rng, irr.lateral_rms_m, bumps=irr.lateral_bumps, **band)
    vertical = random_irregularity(rng, irr.vertical_rms_m, bumps=irr.vertical_bumps, **band)
    gauge = random_irregularity(rng, irr.gauge_rms_m, bumps=irr.gauge_bumps, **gauge_band)
    cross_level = random_irregularity(rng, irr.cross_level_rms_m, bumps=irr.cross_level_bumps, **gauge_band)
    long_band = dict(shortest_wavelength_m=irr.long_wave_band_m[0], longest_wavelength_m=irr.long_wave_band_m[1],
                     components=60)
    if irr.long_wave_lateral_rms_m > 0.0:
        lateral = lateral.plus(random_irregularity(rng, irr.long_wave_lateral_rms_m, **long_band))
    if irr.long_wave_vertical_rms_m > 0.0:
        vertical = vertical.plus(random_irregularity(rng, irr.long_wave_vertical_rms_m, **long_band))
    return TrueTrack(
        design=design_alignment(config.design),
        lateral=lateral,
        vertical=vertical,
        gauge=gauge,
        cross_level=cross_level,
        nominal_gauge_m=irr.nominal_gauge_m,
        cant_base_m=config.trolley.rail_centre_spacing_m,
    )


def trolley_play(spec: TrolleyPlaySpec, rng: np.random.Generator, station_m: np.ndarray) -> np.ndarray | None:
    """Pitch and yaw of the trolley frame against the rail tangent at ``station_m`` [rad],
    (n, 2); None when the play is off."""
    if spec.pitch_rms_rad == 0.0 and spec.yaw_rms_rad == 0.0:
        return None
    band = {"shortest_wavelength_m": spec.shortest_wavelength_m, "longest_wavelength_m": spec.longest_wavelength_m,
            "components": spec.components, "spectral_slope": -0.5}  # flat PSD over log-uniform wavelengths
    return np.column_stack([random_irregularity(rng, rms, **band).evaluate(station_m)
                            for rms in (spec.pitch_rms_rad, spec.yaw_rms_rad)])


def _station_inverse(times_s: np.ndarray, stations_m: np.ndarray, targets_m: np.ndarray) -> np.ndarray:
    """First time the trolley reaches each target station (stations non-decreasing in time)."""
    idx = np.searchsorted(stations_m, targets_m, side="left")
    idx = np.clip(idx, 1, len(stations_m) - 1)
    s0, s1 = stations_m[idx - 1], stations_m[idx]
    frac = np.where(s1 > s0, (targets_m - s0) / np.where(s1 > s0, s1 - s0, 1.0), 0.0)
    return times_s[idx - 1] + frac * (times_s[idx] - times_s[idx - 1])


def simulate(
    config: ScenarioConfig,
    seed: int,
    out_dir: str | Path,
    imu_format: str = "text",
    overwrite: bool = False,
    progress: ProgressFn | None = None,
    cancel: CancelToken = None,
    track_seed: int | None = None,
) -> SimulationResult:
    """Simulate ``config`` with random ``seed`` into the survey folder ``out_dir``.

    ``track_seed`` (default: ``seed``) draws the track's irregularities alone: two runs over one
    track with independent sensor noise (a repeat run, a return pass) share it and differ in ``seed``.
    """
    out_dir = Path(out_dir)
    if out_dir.exists() and not overwrite and any(out_dir.iterdir()):
        raise FileExistsError(f"{out_dir} exists and is not empty (use overwrite=True / --force to replace it)")
    if imu_format not in ("text", "npy"):
        raise ValueError("imu_format must be 'text' or 'npy'")
    step = StepProgress(progress)
    if config.odometer.second and config.trolley.imu_to_odometer_right_m is None:  # the second wheel's lever arm
        config = replace(config, trolley=replace(config.trolley,
                                                 imu_to_odometer_right_m=np.array(config.odometer.right_lever_arm_m)))
    # a ninth stream for the trolley play leaves the first eight (and older truths) unchanged
    streams = np.random.SeedSequence(seed).spawn(9)
    rng_track, rng_motion, rng_imu, rng_gnss, rng_odo, rng_sleeper, rng_misc, rng_noise, rng_play = (
        np.random.default_rng(s) for s in streams
    )
    if track_seed is not None:
        rng_track = np.random.default_rng(np.random.SeedSequence(track_seed).spawn(9)[0])

    # --- true track and trolley path -------------------------------------------------
    step(0.0, "building the track")
    track = true_track(config, rng_track)
    crs = EngineeringCRS.from_settings(config.geodetic.crs)
    ell = crs.reference_ellipsoid
    motion = config.motion
    # The motion runs in a path coordinate growing with travel: the station itself, or for a
    # reverse run the station mirrored about the stretch's middle (the map is its own inverse).
    def path_of(station):
        return motion.start_station_m + motion.end_station_m - np.asarray(station) if motion.reverse else np.asarray(station)

    # a fix at the run's first or last station is taken during its static start or end: no stop of its own
    ends = (motion.start_station_m, motion.end_station_m)
    prism_stops = tuple((float(path_of(s)), config.prism.duration_s) for s in config.prism.stations_m
                        if min(abs(float(path_of(s)) - end) for end in ends) > 1e-6)
    profile = walking_profile(
        rng_motion,
        config.start_time_s,
        motion.start_station_m,
        motion.end_station_m,
        motion.cruise_speed_mps,
        motion.speed_variation,
        motion.speed_change_interval_s,
        motion.ramp_s,
        motion.static_start_s,
        motion.static_end_s,
        stops=tuple(sorted({(float(path_of(s)), d) for s, d in motion.stops} | set(prism_stops))),
    )
    trolley = config.trolley
    c_vb = euler_to_dcm(*trolley.mounting_rpy_rad)
    margin = 5.0  # the trolley's points reach about a metre beyond the reference point
    grid = np.arange(motion.start_station_m - margin, motion.end_station_m + margin, config.station_grid_m)
    sections = track.sections(path_of(grid))
    # A trolley facing against the stationing has the stationing's right rail on its left.
    other = {"left": "right", "right": "left"}
    rail = sections.rail(other[trolley.reference_rail] if motion.reverse else trolley.reference_rail)
    lat, lon = crs.to_geodetic(rail[:, 0], rail[:, 1])
    h = rail[:, 2] + height_anomaly(config, rail[:, 0], rail[:, 1])
    kin = TrolleyKinematics(
        grid,
        earth.geodetic_to_ecef(lat, lon, h, ell),
        -sections.cross_slope_rad if motion.reverse else sections.cross_slope_rad,
        trolley.imu_to_reference_rail_m,
        c_vb,
        profile,
        ell,
        play_pitch_yaw_rad=trolley_play(config.play, rng_play, grid),
    )
    check_cancel(cancel)

    # --- IMU, navigation truth and odometer path at the IMU rate ----------------------
    profile_imu = load_imu_profile(config.imu_profile)
    dt = 1.0 / config.imu_rate_hz
    n = int(np.floor((profile.end_time_s - config.start_time_s) / dt)) + 1
    t = config.start_time_s + dt * np.arange(n)
    imu_errors = sensors.draw_imu_errors(rng_imu, profile_imu, n, dt)
    if config.accel_bias_turn_on_mps2 is not None:  # drawn all the same: the other errors stay the seed's
        imu_errors = replace(imu_errors, accel_bias_turn_on=np.array(config.accel_bias_turn_on_mps2, dtype=float))
    dtheta = np.empty((n, 3))
    dvel = np.empty((n, 3))
    wheels = (np.stack([trolley.imu_to_odometer_m, trolley.imu_to_odometer_right_m]) if config.odometer.second
              else trolley.imu_to_odometer_m)
    wheel = np.empty((n, 2) if config.odometer.second else n)
    truth = np.empty(n, dtype=NAV_TRUTH_DTYPE)
    imu_step = step.sub(0.05, 0.85)
    for start in range(0, n, CHUNK_EPOCHS):
        check_cancel(cancel)
        sl = slice(start, min(start + CHUNK_EPOCHS, n))
        tt = t[sl]
        d_theta, d_vel, d_wheel = kin.increments(tt, dt, wheels)
        dtheta[sl], dvel[sl] = sensors.corrupt_increments(
            rng_noise, profile_imu, imu_errors, sl, np.full(len(tt), dt), d_theta, d_vel
        )
        wheel[sl] = d_wheel
        la, lo, hh, v_ned, roll, pitch, heading = kin.navigation_truth(tt)
        truth["time_s"][sl] = tt
        truth["lat_rad"][sl], truth["lon_rad"][sl], truth["height_m"][sl] = la, lo, hh
        truth["vel_ned_mps"][sl] = v_ned
        truth["rpy_rad"][sl] = np.column_stack([roll, pitch, heading])
        truth["station_m"][sl] = path_of(profile.evaluate(tt)[0])
        imu_step(sl.stop / n, Phrase("IMU {done}/{epochs} epochs", {"done": sl.stop, "epochs": n}))
    wheel[0] = 0.0
    # true distance of the odometer wheel (and of the second one) since the first epoch
    wheel_distance = np.cumsum(wheel, axis=0)
    wheel_distance, right_distance = ((wheel_distance[:, 0], wheel_distance[:, 1]) if config.odometer.second
                                      else (wheel_distance, None))
    station_at_imu = truth["station_m"]
    path_at_imu = path_of(station_at_imu)  # non-decreasing in time: invertible
    joint_station, joint_time = _joint_passings(config, t, path_at_imu, path_of)
    _add_joint_shocks(config.joints, t, dt, joint_time, dvel)

    # --- GNSS ----------------------------------------------------------------------
    step(0.86, "GNSS")
    gcfg = config.gnss
    t_gnss = np.arange(np.ceil(t[0]), t[-1], 1.0 / gcfg.rate_hz)
    outage_intervals = []
    for start_station, duration in gcfg.outages:
        t_out = float(_station_inverse(t, path_at_imu, path_of(np.array([start_station])))[0])
        outage_intervals.append((t_out, t_out + duration))
    t_gnss = t_gnss[~sensors.in_intervals(t_gnss, outage_intervals)]
    ant_pos, ant_vel = kin.point_ecef(t_gnss, trolley.imu_to_antenna_m)
    a_lat, a_lon, a_h = earth.ecef_to_geodetic(ant_pos, ell)
    sig_white = np.array([gcfg.white_horizontal_m, gcfg.white_horizontal_m, gcfg.white_vertical_m])
    sig_gm = np.array([gcfg.gm_horizontal_m, gcfg.gm_horizontal_m, gcfg.gm_vertical_m])
    # The correlated part evolves on the full 1 Hz clock (outages included) so it decorrelates over gaps.
    full_clock = np.arange(np.ceil(t[0]), t[-1], 1.0 / gcfg.rate_hz)
    gm_full = sensors.gauss_markov(rng_gnss, len(full_clock), 1.0 / gcfg.rate_hz, sig_gm, gcfg.gm_tau_s)
    gm = gm_full[np.searchsorted(full_clock, t_gnss)]
    antenna_truth = np.empty(len(full_clock), dtype=ANTENNA_TRUTH_DTYPE)
    antenna_truth["time_s"] = full_clock
    antenna_truth["ecef_m"] = kin.point_ecef(full_clock, trolley.imu_to_antenna_m)[0]
    err_ned = gm + rng_gnss.standard_normal((len(t_gnss), 3)) * sig_white
    d_lat, d_lon, d_h = earth.ned_to_geodetic_delta(err_ned, a_lat, a_h, ell)
    sigma = np.sqrt(sig_white**2 + sig_gm**2)
    vel_ned = sig_vel = None
    if gcfg.with_velocity:
        c_en = np.swapaxes(earth.dcm_ecef_from_ned(a_lat, a_lon), -1, -2)
        vel_ned = np.einsum("nij,nj->ni", c_en, ant_vel) + rng_gnss.standard_normal((len(t_gnss), 3)) * gcfg.velocity_sigma_mps
        sig_vel = np.full((len(t_gnss), 3), gcfg.velocity_sigma_mps)
    gnss = GnssSolution(
        time_s=t_gnss,
        lat_rad=a_lat + d_lat,
        lon_rad=a_lon + d_lon,
        height_m=a_h + d_h,
        sigma_ned_m=np.tile(sigma, (len(t_gnss), 1)),
        quality=np.ones(len(t_gnss), dtype=int),
        num_sats=rng_gnss.integers(14, 24, len(t_gnss)),
        ratio=np.round(rng_gnss.uniform(8.0, 60.0, len(t_gnss)), 1),
        vel_ned_mps=vel_ned,
        sigma_vel_ned_mps=sig_vel,
        gps_week=config.gps_week,
    )
    check_cancel(cancel)

    # --- odometer, gauge, sleepers, prism -------------------------------------------------
    step(0.88, "odometer, gauge, sleepers")
    ocfg = config.odometer
    t_odo = t[0] + np.arange(0.0, t[-1] - t[0], 1.0 / ocfg.rate_hz)
    odo_true = np.interp(t_odo, t, wheel_distance)
    slip_station = np.interp(t_odo, t, station_at_imu)
    odo_reported = sensors.quantise((1.0 + ocfg.scale_factor_error) * _slipped(odo_true, slip_station, ocfg.slip, "left"),
                                    ocfg.pulse_length_m)
    odometer = OdometerData(time_s=t_odo, distance_m=odo_reported, pulse_length_m=ocfg.pulse_length_m)
    slip_time_s = () if ocfg.slip is None else _station_inverse(
        t, path_at_imu, np.sort(path_of(np.array([ocfg.slip.from_station_m, ocfg.slip.to_station_m]))))
    odometer_right = None
    if right_distance is not None:
        right_true = _slipped(np.interp(t_odo, t, right_distance), slip_station, ocfg.slip, "right")
        odometer_right = OdometerData(time_s=t_odo, pulse_length_m=ocfg.pulse_length_m, distance_m=sensors.quantise(
            (1.0 + ocfg.right_scale_factor_error) * right_true, ocfg.pulse_length_m))

    gc = config.gauge
    t_gauge = t[0] + np.arange(0.0, t[-1] - t[0], 1.0 / gc.rate_hz)
    gauge_true = track.sections(np.interp(t_gauge, t, station_at_imu)).gauge_m
    gauge = GaugeData(
        time_s=t_gauge,
        gauge_m=sensors.quantise(gauge_true + rng_misc.normal(0.0, gc.noise_m, len(t_gauge)) + 0.5 * gc.resolution_m, gc.resolution_m),
    )

    sc = config.sleepers
    detector_ahead_m = float((c_vb @ (trolley.imu_to_sleeper_detector_m - trolley.imu_to_reference_rail_m))[0])
    first = motion.start_station_m + detector_ahead_m + 1.0
    nominal = np.arange(np.ceil(first / sc.spacing_m) * sc.spacing_m, motion.end_station_m + detector_ahead_m - 1.0, sc.spacing_m)
    sleeper_station = nominal + rng_sleeper.normal(0.0, sc.spacing_jitter_m, len(nominal))
    pass_time = _station_inverse(t, path_at_imu, path_of(sleeper_station) - detector_ahead_m)
    pulse_times, detected, false_times = sensors.sleeper_pulse_times(
        rng_sleeper, pass_time, sc.missed_fraction, sc.false_fraction, sc.timing_jitter_s
    )
    sleepers = SleeperPulses(time_s=pulse_times)

    prism = None
    if config.prism.stations_m:
        # in the order the trolley reaches them (a reverse run meets the highest station first): the
        # prism file's time stamps must increase
        fix_paths = np.sort(path_of(np.array(config.prism.stations_m)))
        times = _station_inverse(t, path_at_imu, fix_paths) + 0.5 * config.prism.duration_s
        p_pos, _ = kin.point_ecef(times, trolley.imu_to_prism_m)
        p_lat, p_lon, p_h = earth.ecef_to_geodetic(p_pos, ell)
        p_e, p_n = crs.to_plane(p_lat, p_lon)
        p_hn = p_h - height_anomaly(config, p_e, p_n)
        noise = rng_misc.normal(0.0, config.prism.sigma_m, (len(times), 3))
        prism = PrismObservations(
            time_s=times,
            east_m=p_e + noise[:, 0],
            north_m=p_n + noise[:, 1],
            height_m=p_hn + noise[:, 2],
            sigma_m=np.full(len(times), config.prism.sigma_m),
            point_id=np.array([f"CP{i + 1:03d}" for i in range(len(times))]),
        )

    benchmarks = _benchmarks(config, track, crs, rng_misc)
    check_cancel(cancel)

    # --- write -----------------------------------------------------------------------
    step(0.9, "writing files")
    imu = ImuIncrements(time_s=t, dtheta_rad=dtheta, dvel_mps=dvel, gps_week=config.gps_week)
    sleeper_truth = track.sections(sleeper_station)
    out_dir.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{out_dir.name}.", dir=out_dir.parent))
    os.chmod(tmp, 0o755)  # mkdtemp makes it private; the survey is an ordinary folder
    try:
        files = _write_survey(
            tmp, config, seed, imu, imu_format, gnss, odometer, gauge, sleepers, prism, benchmarks, odometer_right
        )
        truth_dir = tmp / "truth"
        truth_dir.mkdir()
        save_npy(truth_dir / "nav.npy", truth)
        files["truth_nav"] = truth_dir / "nav.npy"
        save_npy(truth_dir / "antenna.npy", antenna_truth)
        files["truth_antenna"] = truth_dir / "antenna.npy"
        files["truth_sleepers"] = write_sleeper_truth(
            truth_dir / "sleepers.csv", sleeper_truth, np.arange(len(nominal)), pass_time, detected
        )
        files["truth_errors"] = _write_error_truth(truth_dir, config, imu_errors, t, outage_intervals, false_times,
                                                    (joint_station, joint_time), slip_time_s)
        files.update(_write_design(truth_dir, track.design))
        files["scenario"] = _write_scenario(truth_dir / "scenario.toml", config, seed, crs, track_seed)
        if out_dir.exists():
            shutil.rmtree(out_dir)
        tmp.rename(out_dir)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    step(1.0, "done")
    return SimulationResult(
        folder=out_dir,
        imu_epochs=n,
        gnss_epochs=len(t_gnss),
        sleepers=len(sleeper_station),
        duration_s=float(t[-1] - t[0]),
        length_m=motion.end_station_m - motion.start_station_m,
        files={k: out_dir / v.relative_to(tmp) for k, v in files.items()},
    )


def _benchmarks(config: ScenarioConfig, track: TrueTrack, crs, rng: np.random.Generator) -> Benchmarks:
    """GNSS-levelling benchmarks beside the line: true h and H plus measurement noise.

    A pair (one each side of the line) at both ends of the design and about every
    ``benchmark_spacing_m`` between, as a railway's levelling network lies along the corridor:
    their convex hull holds the whole track, so the height anomaly is interpolated, never
    extrapolated (a 500 m chord of a 2 km curve bulges 16 m, less than the closest offset)."""
    g = config.geodetic
    design = track.design
    first, last = design.horizontal.start_station_m, design.horizontal.end_station_m
    stations = np.repeat(np.linspace(first, last, max(2, math.ceil((last - first) / g.benchmark_spacing_m) + 1)), 2)
    offsets = rng.uniform(*g.benchmark_offset_m, len(stations)) * np.tile([-1.0, 1.0], len(stations) // 2)
    east, north = design.horizontal.point_at(stations, offsets)
    normal_height = design.vertical.elevation_at(stations) + rng.uniform(-2.0, 2.0, len(stations))
    h = normal_height + height_anomaly(config, east, north)
    lat, lon = crs.to_geodetic(east, north)
    return Benchmarks(
        point_id=tuple(f"BM{i + 1:02d}" for i in range(len(stations))),
        lat_rad=lat,
        lon_rad=lon,
        h_m=h + rng.normal(0.0, g.benchmark_sigma_h_m, len(stations)),
        normal_height_m=normal_height + rng.normal(0.0, g.benchmark_sigma_normal_height_m, len(stations)),
    )


def _slipped(distance_m: np.ndarray, station_m: np.ndarray, slip, wheel: str) -> np.ndarray:
    """A wheel's counted distance: its rolled ``distance_m`` less what it did not count while slipping
    (``OdometerSlip``: between its stations, by the reference point's ``station_m``) when it is this ``wheel``."""
    if slip is None or slip.wheel != wheel:
        return distance_m
    low, high = sorted((slip.from_station_m, slip.to_station_m))
    inside = (station_m[1:] > low) & (station_m[1:] <= high)
    lost = np.concatenate([[0.0], np.cumsum(slip.fraction * np.diff(distance_m) * inside)])
    return distance_m - lost


def _write_survey(folder, config, seed, imu, imu_format, gnss, odometer, gauge, sleepers, prism, benchmarks,
                  odometer_right=None):
    """Write the raw files and survey.toml; returns {role: path}."""
    if imu_format == "text":
        entries = {"imu": SurveyFile("imu.txt", "kfgins-imu")}
        write_imu_kfgins(folder / "imu.txt", imu)
    else:
        entries = {"imu": SurveyFile("imu.npy", "imu-npy")}
        write_imu_npy(folder / "imu.npy", imu)
    if len(gnss):  # a survey without any GNSS (the `tunnel-no-gnss` preset) has no GNSS file, as a user's has none
        entries["gnss"] = SurveyFile("gnss.pos", "rtklib-pos")
        write_rtklib_pos(folder / "gnss.pos", gnss)
    if config.odometer.form == "pulses":
        entries["odometer"] = SurveyFile("odometer.txt", "odometer-pulses", {"pulse_length_m": config.odometer.pulse_length_m})
        write_odometer_pulses(folder / "odometer.txt", odometer)
    else:
        entries["odometer"] = SurveyFile("odometer.txt", "odometer-distance")
        write_odometer_distance(folder / "odometer.txt", odometer)
    if odometer_right is not None:
        entries["odometer_right"] = SurveyFile("odometer_right.txt", "odometer-distance")
        write_odometer_distance(folder / "odometer_right.txt", odometer_right)
    entries["gauge"] = SurveyFile("gauge.txt", "gauge-mm")
    write_gauge_mm(folder / "gauge.txt", gauge)
    entries["sleepers"] = SurveyFile("sleepers.txt", "sleeper-times")
    write_sleeper_times(folder / "sleepers.txt", sleepers)
    entries["benchmarks"] = SurveyFile("benchmarks.txt", "benchmarks")
    write_benchmarks(folder / "benchmarks.txt", benchmarks)
    if prism is not None:
        entries["prism"] = SurveyFile("prism.txt", "prism-enu")
        write_prism_enu(folder / "prism.txt", prism)
    manifest = SurveyManifest(
        name=f"{config.name}-seed{seed}",
        files=entries,
        trolley=config.trolley,
        imu_profile=config.imu_profile,
        gps_week=config.gps_week,
        description=f"Simulated by insrail {__version__}: scenario {config.name}, seed {seed}",
    )
    files = {role: folder / entry.path for role, entry in entries.items()}
    files["manifest"] = write_manifest(folder, manifest)
    return files


def _joint_passings(config: ScenarioConfig, t: np.ndarray, path_at_imu: np.ndarray, path_of):
    """The rail joints inside the run (stations) and when the trolley's reference point passes them."""
    joints, motion = config.joints, config.motion
    if joints.spacing_m <= 0.0:
        return np.zeros(0), np.zeros(0)
    low, high = sorted((motion.start_station_m, motion.end_station_m))
    first = joints.first_station_m + np.ceil((low - joints.first_station_m) / joints.spacing_m) * joints.spacing_m
    stations = np.arange(first, high, joints.spacing_m)
    times = _station_inverse(t, path_at_imu, path_of(stations))
    order = np.argsort(times)
    return stations[order], times[order]


#: Sub-steps per IMU interval over which a joint's shock is integrated into the velocity increment
#: (a 40 Hz wavelet spans five 200 Hz intervals).
_SHOCK_SUBSTEPS = 32


def _add_joint_shocks(joints, t: np.ndarray, dt: float, joint_time_s: np.ndarray, dvel: np.ndarray) -> None:
    """Adds each joint's shock (:meth:`JointSpec.shock_mps2`) to the velocity increments ``dvel`` in place
    (increment k integrates over (t_k - dt, t_k])."""
    reach = 4.0 / joints.frequency_hz if len(joint_time_s) else 0.0
    fractions = (np.arange(_SHOCK_SUBSTEPS) + 0.5) / _SHOCK_SUBSTEPS
    for passing in joint_time_s:
        k = np.arange(np.searchsorted(t, passing - reach), min(np.searchsorted(t, passing + reach + dt), len(t)))
        sub = t[k, None] - dt + dt * fractions[None, :] - passing
        dvel[k] += joints.shock_mps2(sub.ravel()).reshape(len(k), _SHOCK_SUBSTEPS, 3).mean(axis=1) * dt


def _write_error_truth(folder: Path, config, errors, t, outages, false_times, joints, slip_time_s=()) -> Path:
    deg_h = np.rad2deg(1.0) * 3600.0
    content = {
        "gyro_bias_turn_on_deg_per_h": (errors.gyro_bias_turn_on * deg_h).tolist(),
        "accel_bias_turn_on_mgal": (errors.accel_bias_turn_on * 1e5).tolist(),
        "gyro_scale_factor_ppm": (errors.gyro_scale_factor * 1e6).tolist(),
        "accel_scale_factor_ppm": (errors.accel_scale_factor * 1e6).tolist(),
        "odometer_scale_factor_error": config.odometer.scale_factor_error,
        **({"odometer_right_scale_factor_error": config.odometer.right_scale_factor_error} if config.odometer.second
           else {}),
        **({"odometer_slip": {"wheel": config.odometer.slip.wheel, "fraction": config.odometer.slip.fraction,
                              "from_station_m": config.odometer.slip.from_station_m,
                              "to_station_m": config.odometer.slip.to_station_m,
                              "time_s": [float(v) for v in slip_time_s]}}
           if config.odometer.slip is not None else {}),
        "gnss_outages_s": [list(o) for o in outages],
        "false_sleeper_pulse_times_s": false_times.tolist(),
        "joint_stations_m": joints[0].tolist(),
        "joint_times_s": joints[1].tolist(),
    }
    path = folder / "errors.toml"
    path.write_text(tomli_w.dumps(content), encoding="utf-8")
    every = max(int(round(1.0 * config.imu_rate_hz)), 1)
    gm = np.zeros(len(t[::every]), dtype=[("time_s", "f8"), ("gyro_radps", "f8", (3,)), ("accel_mps2", "f8", (3,))])
    gm["time_s"] = t[::every]
    gm["gyro_radps"] = errors.gyro_bias_gm[::every]
    gm["accel_mps2"] = errors.accel_bias_gm[::every]
    save_npy(folder / "imu_bias_gm.npy", gm)
    return path


def _write_design(folder: Path, design) -> dict[str, Path]:
    from insrail.track import alignment_csv, landxml

    alignment_csv.write_alignment_csv(folder / "design.csv", design)
    landxml.write_landxml(folder / "design.xml", design)
    return {"design_csv": folder / "design.csv", "design_landxml": folder / "design.xml"}


def _plain(value):
    """TOML-ready copy of a scenario value (tuples to lists, inf to a string; a None left out)."""
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items() if v is not None}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, float) and not np.isfinite(value):
        return "inf" if value > 0 else "-inf"
    return value


def _write_scenario(path: Path, config: ScenarioConfig, seed: int, crs, track_seed: int | None = None) -> Path:
    content = {"seed": seed, "track_seed": seed if track_seed is None else track_seed,
               "insrail_version": __version__, "engineering_crs": crs.to_settings()}
    content["scenario"] = _plain(asdict(config))
    path.write_text(tomli_w.dumps(content), encoding="utf-8")
    return path
