"""The end-to-end processing of one survey of a project, and its result files.

``process`` runs read_survey -> fuse -> engineering coordinates (CRS + fitted height anomaly)
-> reconstruct_track (on the design, else along the path from the start station) -> assess
(tolerance profile) -> adjustment (fastener type) and writes ``<project>/results/<survey>/``:

* ``trajectory.npy``   the fused trajectory (insrail.nav.trajectory.TRAJECTORY_DTYPE records)
* ``sleepers.csv``     one row per sleeper; the header names every column with its unit
* ``exceedances.csv``  one row per exceedance run
* ``summary.toml``     settings used, headline numbers, file list

The result folder is assembled beside the old one and swapped in at the end, so a cancelled
or failed run leaves the previous results (or none) and never a mixture.

The fusion, the slow stage, is cached in ``<project>/results/.cache/`` under a hash of what
determines it (the raw survey files' contents, trolley, IMU profile, fusion options,
ellipsoid): changing the tolerance profile, fastener, design or height model reuses it.
"""

from __future__ import annotations

import hashlib
import io
import json
import os
import shutil
import tempfile
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
from insrail.io.survey import MANIFEST_NAME, SurveyData, read_survey
from insrail.nav.earth import Ellipsoid
from insrail.nav.fusion import fuse
from insrail.nav.imu_profile import load_imu_profile
from insrail.nav.trajectory import Trajectory, load_trajectory, save_trajectory
from insrail.progress import CancelToken, ProgressFn, StepProgress, check_cancel
from insrail.project.model import Project
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

RESULTS_FOLDER = "results"
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


def fusion_key(project: Project, survey: SurveyData) -> str:
    """Hash of everything the fused trajectory depends on."""
    digest = hashlib.sha256()
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
                      cancel: CancelToken) -> tuple[Trajectory, Path, bool, dict]:
    """The fused trajectory, its cache file, whether it came from the cache, fusion statistics."""
    cache = project.folder / RESULTS_FOLDER / CACHE_FOLDER
    path = cache / f"fusion-{fusion_key(project, survey)}.npy"
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
    survey = read_survey(project.resolve(entry.folder), progress=step.sub(0.0, 0.05))
    trolley = project.trolley()
    if trolley is not None:
        survey = replace(survey, manifest=replace(survey.manifest, trolley=trolley))
    if survey.gauge is None:
        raise InputError(survey.folder / MANIFEST_NAME, None,
                         "files.gauge: missing; the track reconstruction needs the gauge record")
    check_cancel(cancel)
    trajectory, trajectory_file, cached, fusion_info = _fused_trajectory(project, survey, step.sub(0.05, 0.8), cancel)
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
    folder = _write_results(project, entry.name, trajectory_file, table, assessment, adjustment, summary, cancel)
    step(1.0, "done")
    return SurveyResults(entry.name, folder, trajectory, height_fit, recon, assessment, adjustment, cached, summary)


# --------------------------------------------------------------------------- result files

def _channel_column(channel) -> tuple[str, float, str]:
    """Column name (``check_`` + check, rail, direction, unit), factor from SI, number format."""
    parts = [channel.check] + [p for p in (channel.rail, channel.direction) if p and p != "track"]
    name = "check_" + "_".join(parts)
    return (f"{name}_ratio", 1.0, "%.6f") if channel.kind.endswith("rate") else (f"{name}_mm", 1e3, "%.3f")


def sleeper_columns(table: SleeperTable, assessment: Assessment,
                    adjustment: Adjustment) -> dict[str, tuple[np.ndarray, str]]:
    """The columns of sleepers.csv after number and label, in file order: name -> (values, format)."""
    columns: dict[str, tuple[np.ndarray, str]] = {
        "station_m": (table.station_m, "%.4f"), "time_s": (table.time_s, "%.4f"),
        "detected": (table.detected, "%d"), "valid": (table.valid, "%d"),
    }
    for rail, points in (("left", table.left_rail_enh_m), ("right", table.right_rail_enh_m)):
        for axis, values in zip("ENH", points.T):
            columns[f"{rail}_{axis}_m"] = (values, "%.4f")
    columns |= {"gauge_mm": (1e3 * table.gauge_m, "%.3f"), "cant_mm": (1e3 * table.cant_m, "%.3f"),
                "design_cant_mm": (1e3 * table.design_cant_m, "%.3f")}
    for direction, deviation in (("lateral", table.lateral_deviation_m), ("vertical", table.vertical_deviation_m)):
        for side, rail in enumerate(("left", "right")):
            columns[f"{direction}_deviation_{rail}_mm"] = (1e3 * deviation[:, side], "%.3f")
    for channel in assessment.channels:
        name, factor, fmt = _channel_column(channel)
        columns[name] = (factor * channel.values, fmt)
    for direction, amounts, flags in (("lateral", adjustment.lateral_m, adjustment.unresolved_lateral),
                                      ("vertical", adjustment.vertical_m, adjustment.unresolved_vertical)):
        for side, rail in enumerate(("left", "right")):
            columns[f"adjust_{direction}_{rail}_mm"] = (1e3 * amounts[:, side], "%.1f")
            columns[f"unresolved_{direction}_{rail}"] = (flags[:, side], "%d")
    return columns


def _sleepers_csv(table: SleeperTable, assessment: Assessment, adjustment: Adjustment) -> str:
    """number, label, then the columns of :func:`sleeper_columns`; NaN (not computable) as empty."""
    columns = sleeper_columns(table, assessment, adjustment)
    header = ",".join(["number", "label", *columns]) + "\n"
    if not len(table):
        return header
    block = io.StringIO()
    numeric = np.column_stack([np.asarray(values, dtype=float) for values, _ in columns.values()])
    np.savetxt(block, numeric, fmt=[fmt for _, fmt in columns.values()], delimiter=",")
    lines = block.getvalue().replace("nan", "").splitlines()
    return header + "".join(f"{n},{label},{line}\n" for n, label, line in zip(table.number, table.label, lines))


EXCEEDANCE_HEADER = ["check", "kind", "rail", "direction", "unit", "station_from_m", "station_to_m", "peak",
                     "limit", "first_sleeper", "last_sleeper"]


def _exceedances_csv(assessment: Assessment) -> str:
    rows = [",".join([e.check, e.kind, e.rail, e.direction, *(
        ("ratio", f"{e.station_from_m:.3f}", f"{e.station_to_m:.3f}", f"{e.peak:.6f}", f"{e.limit:.6f}")
        if e.kind.endswith("rate") else
        ("mm", f"{e.station_from_m:.3f}", f"{e.station_to_m:.3f}", f"{1e3 * e.peak:.3f}", f"{1e3 * e.limit:.3f}")),
        str(e.first_sleeper), str(e.last_sleeper)]) for e in assessment.exceedances]
    return "\n".join([",".join(EXCEEDANCE_HEADER), *rows]) + "\n"


def _summary(project, name, survey, fusion_info, cached, height_fit, height_warnings, table, assessment, adjustment,
             elapsed) -> dict:
    counts: dict[str, int] = {}
    for e in assessment.exceedances:
        counts[e.check] = counts.get(e.check, 0) + 1
    summary = {
        "survey": {"name": name, "folder": project.survey(name).folder, "imu_epochs": len(survey.imu),
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
        "files": {"trajectory": "trajectory.npy", "sleepers": "sleepers.csv", "exceedances": "exceedances.csv"},
    }
    return summary


def _write_results(project, name, trajectory_file, table, assessment, adjustment, summary, cancel) -> Path:
    """Write every file into a staging folder, then swap it for the previous results."""
    results = project.folder / RESULTS_FOLDER
    results.mkdir(parents=True, exist_ok=True)
    final = results / name
    staging = Path(tempfile.mkdtemp(prefix=f".{name}.", suffix=".new", dir=results))
    try:
        _link_or_copy(trajectory_file, staging / "trajectory.npy")
        (staging / "sleepers.csv").write_text(_sleepers_csv(table, assessment, adjustment), encoding="utf-8")
        (staging / "exceedances.csv").write_text(_exceedances_csv(assessment), encoding="utf-8")
        with open(staging / "summary.toml", "wb") as handle:
            tomli_w.dump(summary, handle)
        check_cancel(cancel)
        os.chmod(staging, 0o755)
        old = None
        if final.exists():
            old = results / f".{name}.old-{os.getpid()}"
            os.replace(final, old)
        os.replace(staging, final)
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)
    return final


def _link_or_copy(source: Path, destination: Path) -> None:
    """Share the cached trajectory (files are only ever replaced, never modified in place)."""
    try:
        os.link(source, destination)
    except OSError:
        shutil.copyfile(source, destination)
