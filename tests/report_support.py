"""A processed survey without the fusion: a synthetic sleeper table run through the real
assessment, adjustment and result-file writers, so report tests take seconds.

The track: a straight, then a right-hand curve (negative design cant: the right rail is the
high one) ramped in and out; waves on every deviation, a few bumps beyond the limits, a
crossing of invalid sleepers; stations 0.625 m apart; a GNSS outage in the summary.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
from shared_build import computed_once

from insrail.geodesy.crs import EngineeringCRS
from insrail.nav.trajectory import TRAJECTORY_DTYPE, Trajectory, save_trajectory
from insrail.project.model import AdjustmentSettings, HeightSettings, Project, SurveyEntry
from insrail.project.results import (
    EXCEEDANCES_FILE,
    RESULTS_FOLDER,
    SLEEPERS_FILE,
    SUMMARY_FILE,
    TRAJECTORY_FILE,
    adjustment_section,
    exceedances_csv,
    gnss_section,
    load_results,
    sleepers_csv,
    summary_toml,
    track_quality_section,
    write_results,
)
from insrail.track.adjustment import Adjustment, load_fastener_type, optimise_adjustment, reassess
from insrail.track.exceedance import Assessment, SleeperGeometry, assess
from insrail.track.sleeper_table import SleeperTable
from insrail.track.stationing import StationEquations
from insrail.track.tolerance import load_tolerance_profile

CRS = {"ellipsoid": "CGCS2000", "central_meridian_deg": 114.3, "false_easting_m": 500000.0, "projection_height_m": 30.0}
SURVEY = "run1"
START_TIME_S = 230000.0
SPEED_MPS = 1.0
INVALID = slice(300, 330)  # a level crossing


def synthetic_table(n: int = 1100, seed: int = 3) -> SleeperTable:
    rng = np.random.default_rng(seed)
    station = 1000.0 + 0.625 * np.arange(n)
    s = station - station[0]
    curvature = -np.clip((s - 250.0) / 100.0, 0.0, 1.0) / 1500.0  # right-hand curve, R 1500 m
    heading = 0.7 + np.concatenate([[0.0], np.cumsum(curvature[1:] * np.diff(s))])
    east = 512000.0 + np.concatenate([[0.0], np.cumsum(np.sin(heading[1:]) * 0.625)])
    north = 3374000.0 + np.concatenate([[0.0], np.cumsum(np.cos(heading[1:]) * 0.625)])
    height = 28.0 + 0.002 * s
    right = np.column_stack([np.cos(heading), -np.sin(heading)])  # (E, N) of the right-hand normal
    design_cant = -0.09 * np.clip((s - 250.0) / 100.0, 0.0, 1.0)

    def waves(amplitude_m):
        return amplitude_m * (np.sin(2 * np.pi * s / 37.0 + rng.uniform(0, 6)) + 0.4 * np.sin(2 * np.pi * s / 9.0)) \
            + rng.normal(0.0, 0.1e-3, n)

    lateral = np.column_stack([waves(1.0e-3), waves(1.0e-3)])
    vertical = np.column_stack([waves(0.8e-3), waves(0.8e-3)])
    lateral[500:506, :] += 3.0e-3  # an alignment defect the 30 m / 5 m check must catch
    vertical[800:803, 1] -= 2.5e-3
    gauge = 1.435 + 0.3e-3 * np.sin(2 * np.pi * s / 17.0) + rng.normal(0.0, 0.1e-3, n)
    gauge[650:652] += 1.6e-3  # beyond +-1 mm
    cant = design_cant + 0.3e-3 * np.sin(2 * np.pi * s / 23.0)
    cant[900:903] += 1.4e-3  # a cross-level defect
    valid = np.ones(n, dtype=bool)
    valid[INVALID] = False
    for array in (lateral, vertical, gauge, cant):
        array[INVALID] = np.nan
    centre = np.column_stack([east, north, height])
    offset = 0.7175 * np.column_stack([right, np.zeros(n)])
    return SleeperTable(
        number=np.arange(1, n + 1), station_m=station,
        label=tuple(StationEquations(prefix="DK").label(station)), time_s=START_TIME_S + s / SPEED_MPS,
        detected=np.ones(n, dtype=bool), centre_enh_m=centre, left_rail_enh_m=centre - offset,
        right_rail_enh_m=centre + offset, gauge_m=gauge, cant_m=cant, design_cant_m=design_cant,
        lateral_deviation_m=lateral, vertical_deviation_m=vertical, sigma_pos_ned_m=np.full((n, 3), 0.005),
        sigma_roll_rad=np.full(n, 1e-5), valid=valid)


def synthetic_trajectory(start_s: float, end_s: float) -> Trajectory:
    time = np.arange(start_s, end_s, 0.1)
    records = np.zeros(len(time), dtype=TRAJECTORY_DTYPE)
    fields = {name: np.ascontiguousarray(records[name]) for name in TRAJECTORY_DTYPE.names}
    fields["time_s"] = time
    fields["lat_rad"] = np.full(len(time), np.radians(30.5))
    fields["lon_rad"] = np.full(len(time), np.radians(114.4))
    fields["sigma_pos_ned_m"] = np.full((len(time), 3), 0.006)
    fields["odometer_scale"] = np.full(len(time), 1.5e-3)
    return Trajectory(**fields, smoothed=True, gps_week=2380)


def _assessed(geometry: SleeperGeometry, profile) -> tuple[Assessment, Assessment, Adjustment]:
    """The assessment, the adjusted assessment and the adjustment (seconds of HiGHS: made once per
    test run, `shared_build`, the table being the same for every caller)."""
    adjustment = optimise_adjustment(geometry, profile, load_fastener_type("wj8"))
    after, adjustment = reassess(geometry, adjustment.lateral_m, adjustment.vertical_m, profile, load_fastener_type("wj8"))
    return assess(geometry, profile), after, adjustment


def processed_project(root: Path, profile_name: str = "cn_hsr_ballastless", n: int = 1100) -> Project:
    """``root`` as a project folder holding the results of survey ``run1``."""
    table = synthetic_table(n)
    profile = load_tolerance_profile(profile_name)
    geometry = SleeperGeometry.from_arrays(table.station_m, table.lateral_deviation_m, table.vertical_deviation_m,
                                           table.gauge_m, table.cant_m, table.design_cant_m, valid=table.valid,
                                           sleeper_number=table.number)
    assessment, after, adjustment = computed_once(f"synthetic-assessment-{profile_name}-{n}",
                                                  lambda: _assessed(geometry, profile))
    start, end = float(table.time_s[0]) - 30.0, float(table.time_s[-1]) + 30.0
    gnss_time = np.arange(start, end, 1.0)
    gnss_time = gnss_time[(gnss_time < start + 400) | (gnss_time > start + 460)]  # a 60 s outage
    summary = {
        "survey": {"name": SURVEY, "folder": f"surveys/{SURVEY}", "imu_epochs": int(200 * (end - start)), "gps_week": 2380,
                   "processing_time_s": 1.0},
        "fusion": {"from_cache": False, "rejections": 3, "stops": 2, "imu_epochs": int(200 * (end - start)),
                   "trajectory_epochs": int(10 * (end - start))},
        "heights": {"model": "none (ellipsoidal heights)"},
        "track": {"design": "", "sleepers": len(table), "valid_sleepers": int(table.valid.sum()),
                  "station_from_m": float(table.station_m[0]), "station_to_m": float(table.station_m[-1])},
        "assessment": {"tolerance_profile": profile.name, "exceedances": len(assessment.exceedances), "by_check": {}},
        "adjustment": adjustment_section(adjustment, assessment, after, AdjustmentSettings(), load_fastener_type("wj8")),
        "gnss": gnss_section(gnss_time, np.ones(len(gnss_time), dtype=int), start, end),
        "track_quality": track_quality_section(geometry),
    }
    for e in assessment.exceedances:
        summary["assessment"]["by_check"][e.check] = summary["assessment"]["by_check"].get(e.check, 0) + 1
    trajectory_path = root / "trajectory-source.npy"
    root.mkdir(parents=True, exist_ok=True)
    save_trajectory(trajectory_path, synthetic_trajectory(start, end))
    write_results(root / RESULTS_FOLDER, SURVEY, {
        TRAJECTORY_FILE: trajectory_path, SLEEPERS_FILE: sleepers_csv(table, assessment, adjustment),
        EXCEEDANCES_FILE: exceedances_csv(assessment), SUMMARY_FILE: summary_toml(summary)})
    return Project(folder=root, name="Synthetic line", description="Test line, down track", crs=EngineeringCRS.from_settings(
        CRS, "geodesy.crs"), height=HeightSettings(), surveys=(SurveyEntry(SURVEY, f"surveys/{SURVEY}"),),
        start_station_m=1000.0, tolerance_profile=profile_name, fastener="wj8")


_BUILT: dict[str, Project] = {}


def shared_project(tmp_path_factory, profile_name: str = "cn_hsr_ballastless") -> Project:
    """One processed synthetic project per profile and test session (reports write elsewhere)."""
    if profile_name not in _BUILT:
        _BUILT[profile_name] = processed_project(tmp_path_factory.mktemp(f"report-{profile_name}"), profile_name)
    return _BUILT[profile_name]


def saved_project(tmp_path_factory) -> Project:
    """The shared project as a folder the CLI opens: its project.toml and the survey's folder written."""
    from insrail.project.model import save_project

    project = shared_project(tmp_path_factory)
    (project.folder / "surveys" / SURVEY).mkdir(parents=True, exist_ok=True)
    (project.folder / "surveys" / SURVEY / "survey.toml").touch()
    save_project(project)
    return project


def stored(project: Project):
    return load_results(project.folder, SURVEY)


def with_profile(project: Project, profile_name: str) -> Project:
    return replace(project, tolerance_profile=profile_name)
