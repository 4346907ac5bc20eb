"""The end-to-end processing of one survey of a project, and its result files.

``process`` runs read_survey -> fuse -> engineering coordinates (CRS + fitted height anomaly)
-> reconstruct_track (on the design, else along the path from the start station) -> assess
(tolerance profile) -> adjustment (fastener type) and writes ``<project>/results/<survey>/``
(the files and how they are swapped in: :mod:`insrail.project.results`).

The fusion, the slow stage, is cached in ``<project>/results/.cache/`` under a hash of what
determines it (the raw survey files' contents, trolley, IMU profile, fusion options,
ellipsoid): changing the tolerance profile, fastener, design or height model reuses it.

A survey with raw GNSS observations (``[gnss_raw]``) first goes through the cached GNSS stage
(:mod:`insrail.project.gnss_stage`: PPK with RTKLIB); its solution's hash joins the fusion key.
"""

from __future__ import annotations

import hashlib
import json
import time
import tomllib
from dataclasses import asdict, dataclass, replace
from pathlib import Path

import numpy as np
import tomli_w

from insrail.geodesy.height_anomaly import HeightAnomalyFit, fit_height_anomaly
from insrail.io.atomic import atomic_write
from insrail.io.control import read_benchmarks
from insrail.io.errors import InputError
from insrail.io.survey import MANIFEST_NAME, SurveyData, read_manifest, read_survey
from insrail.nav.earth import Ellipsoid
from insrail.nav.fusion import fuse
from insrail.nav.imu_profile import load_imu_profile
from insrail.nav.trajectory import Trajectory, load_trajectory, save_trajectory
from insrail.progress import CancelToken, ProgressFn, StepProgress, check_cancel
from insrail.project.gnss_stage import GNSS_POS_FILE, GNSS_QC_FILE, run_gnss_stage
from insrail.project.model import Project
from insrail.project.results import (
    EXCEEDANCES_FILE,
    RESULTS_FOLDER,
    SLEEPERS_FILE,
    SUMMARY_FILE,
    TRAJECTORY_FILE,
    exceedances_csv,
    sleepers_csv,
    summary_toml,
    write_results,
)
from insrail.track.adjustment import Adjustment, load_fastener_type, optimise_adjustment
from insrail.track.alignment import DesignAlignment
from insrail.track.alignment_csv import read_alignment_csv
from insrail.track.exceedance import Assessment, SleeperGeometry, assess
from insrail.track.landxml import read_landxml
from insrail.track.sleeper_table import (
    SleeperTable,
    TrackReconstruction,
    reconstruct_track,
)
from insrail.track.tolerance import load_tolerance_profile

CACHE_FOLDER = ".cache"
#: Bumped when the meaning of a cached stage changes, so stale caches are never reused.
CACHE_VERSION = 1


@dataclass(frozen=True)
class SurveyResults:
    """What ``process`` produced for one survey (arrays in SI units)."""

    survey: str
    folder: Path  # <project>/results/<survey>
    trajectory: Trajectory
    height_fit: HeightAnomalyFit | None
    reconstruction: TrackReconstruction
    assessment: Assessment
    adjustment: Adjustment
    fusion_from_cache: bool
    summary: dict

    @property
    def table(self) -> SleeperTable:
        return self.reconstruction.table


def read_design(path: Path) -> DesignAlignment:
    """A design alignment from an alignment CSV or a LandXML file (by extension)."""
    return read_landxml(path) if path.suffix.lower() == ".xml" else read_alignment_csv(path)


def ellipsoid_of(project: Project) -> Ellipsoid:
    """The navigation ellipsoid matching the project's CRS (fusion and CRS must agree)."""
    return Ellipsoid(project.crs.ellipsoid, project.crs.semi_major_axis_m, 1.0 / project.crs.inverse_flattening_value)


def fusion_key(project: Project, survey: SurveyData, gnss_sha256: str = "") -> str:
    """Hash of everything the fused trajectory depends on (``gnss_sha256``: a computed GNSS solution's)."""
    digest = hashlib.sha256(gnss_sha256.encode())
    for role in sorted(survey.manifest.files):
        digest.update(role.encode())
        with open(survey.folder / survey.manifest.files[role].path, "rb") as handle:
            for block in iter(lambda: handle.read(1 << 20), b""):
                digest.update(block)
    trolley = {k: np.asarray(v).tolist() if not isinstance(v, str) else v
               for k, v in asdict(survey.manifest.trolley).items()}
    profile = load_imu_profile(project.resource(project.imu_profile or survey.manifest.imu_profile))
    settings = {"version": CACHE_VERSION, "gps_week": survey.manifest.gps_week, "trolley": trolley, "imu_profile": repr(profile),
                "fusion": repr(project.fusion), "ellipsoid": repr(ellipsoid_of(project)),
                "files": {r: asdict(f) for r, f in survey.manifest.files.items()}}
    digest.update(json.dumps(settings, sort_keys=True, default=str).encode())
    return digest.hexdigest()[:32]


def _fused_trajectory(project: Project, survey: SurveyData, progress: StepProgress,
                      cancel: CancelToken, gnss_sha256: str = "") -> tuple[Trajectory, Path, bool, dict]:
    """The fused trajectory, its cache file, whether it came from the cache, fusion statistics."""
    cache = project.folder / RESULTS_FOLDER / CACHE_FOLDER
    path = cache / f"fusion-{fusion_key(project, survey, gnss_sha256)}.npy"
    info_path = path.with_suffix(".toml")
    if path.is_file() and info_path.is_file():
        progress(1.0, "fusion reused from the cache")
        info = tomllib.loads(info_path.read_text(encoding="utf-8"))
        return load_trajectory(path, gps_week=survey.manifest.gps_week), path, True, info
    profile = load_imu_profile(project.resource(project.imu_profile or survey.manifest.imu_profile))
    result = fuse(survey, project.fusion, profile, ellipsoid_of(project), progress=progress, cancel=cancel)
    check_cancel(cancel)
    cache.mkdir(parents=True, exist_ok=True)
    info = {"rejections": len(result.rejections), "stops": len(result.stops),
            "imu_epochs": len(survey.imu), "trajectory_epochs": len(result.trajectory)}
    save_trajectory(path, result.trajectory)
    with atomic_write(info_path, "wb") as handle:
        tomli_w.dump(info, handle)
    return result.trajectory, path, False, info


def fit_heights(project: Project) -> HeightAnomalyFit | None:
    """ζ fitted on the project's benchmarks (None without benchmarks: heights stay ellipsoidal)."""
    if project.height.benchmarks is None:
        return None
    benchmarks = read_benchmarks(project.resolve(project.height.benchmarks))
    east, north = project.crs.to_plane(benchmarks.lat_rad, benchmarks.lon_rad)
    anomaly = project.height.anomaly
    if anomaly.geoid_grid not in (None, "egm96"):  # a grid file named relative to the project
        anomaly = replace(anomaly, geoid_grid=str(project.resolve(anomaly.geoid_grid)))
    return fit_height_anomaly(np.column_stack([east, north]), benchmarks.height_anomaly_m,
                              anomaly.model, geoid=anomaly.plane_geoid(project.crs))


def process(project: Project, survey_name: str, progress: ProgressFn | None = None,
            cancel: CancelToken = None) -> SurveyResults:
    """Process one survey of ``project`` end to end and write its result files (see the module docstring)."""
    step = StepProgress(progress)
    started = time.monotonic()
    entry = project.survey(survey_name)
    folder = project.resolve(entry.folder)
    manifest = read_manifest(folder)
    gnss = None  # the GNSS stage (PPK), for a survey with raw observations
    if manifest.raw_gnss is not None:
        gnss = run_gnss_stage(project, folder, manifest, project.folder / RESULTS_FOLDER / CACHE_FOLDER,
                              step.sub(0.0, 0.04), cancel)
    survey = read_survey(folder, progress=step.sub(0.04, 0.05), gnss=gnss.solution if gnss else None)
    trolley = project.trolley()
    if trolley is not None:
        survey = replace(survey, manifest=replace(survey.manifest, trolley=trolley))
    if survey.gauge is None:
        raise InputError(survey.folder / MANIFEST_NAME, None,
                         "files.gauge: missing; the track reconstruction needs the gauge record")
    check_cancel(cancel)
    trajectory, trajectory_file, cached, fusion_info = _fused_trajectory(project, survey, step.sub(0.05, 0.8), cancel,
                                                                         gnss.pos_sha256 if gnss else "")
    check_cancel(cancel)

    step(0.8, "height model")
    height_fit = fit_heights(project)

    def to_engineering(lat, lon, h):
        east, north = project.crs.to_plane(lat, lon)
        zeta = height_fit.zeta_m(east, north) if height_fit is not None else 0.0
        return east, north, h - zeta

    design = read_design(project.resolve(project.design)) if project.design is not None else None
    step(0.82, "rails, chainage and sleepers")
    recon = reconstruct_track(trajectory, survey.manifest.trolley, survey.gauge, to_engineering, design=design,
                              pulses=survey.sleepers, start_station_m=project.start_station_m,
                              first_number=project.first_sleeper_number)
    check_cancel(cancel)
    step(0.88, "irregularities and exceedances")
    table = recon.table
    measured = table.valid
    height_warnings = (height_fit.warnings_for(table.centre_enh_m[measured, 0], table.centre_enh_m[measured, 1])
                       if height_fit is not None else [])
    geometry = SleeperGeometry.from_arrays(table.station_m, table.lateral_deviation_m, table.vertical_deviation_m,
                                           table.gauge_m, table.cant_m, table.design_cant_m, valid=table.valid,
                                           sleeper_number=table.number)
    profile = load_tolerance_profile(project.resource(project.tolerance_profile))
    assessment = assess(geometry, profile)
    check_cancel(cancel)
    step(0.92, "adjustment amounts")
    adjustment = optimise_adjustment(geometry, profile, load_fastener_type(project.resource(project.fastener)))
    check_cancel(cancel)

    step(0.97, "writing results")
    summary = _summary(project, entry.name, survey, fusion_info, cached, height_fit, height_warnings, table,
                       assessment, adjustment, time.monotonic() - started)
    if gnss is not None:
        summary["gnss"] = gnss.summary(project.fusion.gnss_quality_policy)
        summary["files"].update(gnss=GNSS_POS_FILE, gnss_qc=GNSS_QC_FILE)
    folder = write_results(project.folder / RESULTS_FOLDER, entry.name, {
        TRAJECTORY_FILE: trajectory_file, SLEEPERS_FILE: sleepers_csv(table, assessment, adjustment),
        EXCEEDANCES_FILE: exceedances_csv(assessment), SUMMARY_FILE: summary_toml(summary),
        **(gnss.result_files() if gnss else {})}, cancel)
    step(1.0, "done")
    return SurveyResults(entry.name, folder, trajectory, height_fit, recon, assessment, adjustment, cached, summary)


# --------------------------------------------------------------------------- result files

def _summary(project, name, survey, fusion_info, cached, height_fit, height_warnings, table, assessment, adjustment,
             elapsed) -> dict:
    counts: dict[str, int] = {}
    for e in assessment.exceedances:
        counts[e.check] = counts.get(e.check, 0) + 1
    summary = {
        "survey": {"name": name, "folder": project.survey(name).folder, "imu_epochs": len(survey.imu),
                   **({"gps_week": survey.manifest.gps_week} if survey.manifest.gps_week is not None else {}),
                   "processing_time_s": round(elapsed, 2)},
        "fusion": {"from_cache": cached, **fusion_info},
        "heights": ({"model": height_fit.model_name, "internal_rms_mm": 1e3 * height_fit.internal_rms_m,
                     "loo_rms_mm": 1e3 * height_fit.loo_rms_m if np.isfinite(height_fit.loo_rms_m) else -1.0,
                     "warnings": height_warnings}
                    if height_fit is not None else {"model": "none (ellipsoidal heights)"}),
        "track": {"design": project.design or "", "sleepers": len(table), "valid_sleepers": int(table.valid.sum()),
                  "station_from_m": float(table.station_m[0]) if len(table) else 0.0,
                  "station_to_m": float(table.station_m[-1]) if len(table) else 0.0},
        "assessment": {"tolerance_profile": assessment.profile, "exceedances": len(assessment.exceedances),
                       "by_check": counts},
        "adjustment": {"fastener": adjustment.fastener, "total_movement_mm": 1e3 * adjustment.total_movement_m,
                       "max_lateral_mm": 1e3 * float(np.abs(adjustment.lateral_m).max(initial=0.0)),
                       "max_vertical_mm": 1e3 * float(np.abs(adjustment.vertical_m).max(initial=0.0)),
                       "unresolved_sleepers": int(np.any(adjustment.unresolved_lateral | adjustment.unresolved_vertical,
                                                         axis=1).sum())},
        "files": {"trajectory": TRAJECTORY_FILE, "sleepers": SLEEPERS_FILE, "exceedances": EXCEEDANCES_FILE},
    }
    return summary
