"""The end-to-end processing of one survey of a project, and its result files.

``process`` runs read_survey -> fuse (GNSS, odometer, ..., and the total-station prism fixes on
CPIII points when the survey has them, placed by the project's CRS and height model) ->
engineering coordinates (CRS + fitted height anomaly) -> reconstruct_track (on the design, else
along the path from the start station) -> assess (tolerance profile) -> adjustment (fastener
type) and writes ``<project>/results/<survey>/`` (the files and how they are swapped in:
:mod:`insrail.project.results`).

``process`` resolves the project once, at its start, into the run's settings
(:class:`~insrail.project.run_settings.RunSettings`: CRS and its ellipsoid, height model,
trolley, profiles, design, fusion and adjustment options, with their files' hashes); the stages
take their settings from it, the cache keys below hash its parts, and summary.toml records it
(``[settings]``), which the reports and exports state.

Three stages are cached in ``<project>/results/.cache/``, each under a hash of what determines it:

* ``fusion-<key>.npy``       the raw survey files' contents, trolley, IMU profile, fusion options,
  ellipsoid (and with prism fixes the geodesy placing them). A cached fusion reads no raw file.
  Beside it ``fusion-<key>.quality.npz``: the covariance analysis of the fusion's timeline
  (:func:`insrail.quality.epoch_quality`, per update epoch), computed right after the fusion
  while its timeline, the survey and (smoothed) the filter's own record of Phi, P-, P+ are at hand
  (from the record: in a thread beside the track reconstruction, which reads only the trajectory
  file; the entry is sealed once the analysis is saved, :class:`FusionEntry`). The per-section table in ``quality.csv`` is
  formed from it on the reconstructed chainage (which depends on the track settings).
* ``track-<key>.npz``        the sleepers and the epochs' stations (not the rails: what the later
  stages take from them, :class:`~insrail.track.sleeper_table.EpochStations`): the fusion key plus CRS, height model,
  design alignment (contents) and stationing settings. Beside it ``track-<key>.extras.npz``
  (:class:`TrackExtras`): the fused attitude at every sleeper and, without a design, what the
  line-type fit gave the results (the fitted alignment's files, its summary section and the
  curvature at every sleeper), so a rerun neither reads the trajectory nor fits a line again.
* ``adjustment-<key>.npz``   the deviations, the differential-versine limits and the fastener.

Changing only the tolerance profile therefore recomputes the assessment (and the adjustment
when its limits changed) and rewrites the result files; nothing else.

A survey with raw GNSS observations (``[gnss_raw]``) first goes through the cached GNSS stage
(:mod:`insrail.project.gnss_stage`: PPK with RTKLIB); its solution's hash joins the fusion key
(``ppk-<key>.pos``/``.toml`` in the same cache).
"""

from __future__ import annotations

import hashlib
import json
import time
import tomllib
from collections.abc import Callable
from dataclasses import asdict, dataclass, replace
from functools import cached_property, partial
from pathlib import Path

import numpy as np
import tomli_w

from insrail.background import BackgroundJob
from insrail.geodesy.height_anomaly import HeightAnomalyFit, fit_height_anomaly
from insrail.io.atomic import atomic_write
from insrail.io.control import read_benchmarks
from insrail.io.errors import InputError
from insrail.io.formats import get_format
from insrail.io.textparse import checked_once
from insrail.io.survey import (
    MANIFEST_NAME,
    SurveyManifest,
    TrolleyGeometry,
    read_survey,
)
from insrail.io.types import GaugeData, GnssSolution, PrismObservations, SleeperPulses
from insrail.memory import release_free_memory
from insrail.nav.fusion import SmootherStore, aiding_for, fuse
from insrail.nav.integrity import UntrustedSolution
from insrail.nav.measurements import PositionFix
from insrail.nav.mounting import MountingEstimate, not_estimated
from insrail.nav.pass_memo import PassMemo
from insrail.nav.self_calibration import fuse_consistent
from insrail.nav.shocks import NHC_RELAXED_S, detect_shocks
from insrail.nav.trajectory import Trajectory, load_trajectory
from insrail.notices import Notice, Phrase
from insrail.progress import CancelToken, ProgressFn, StepProgress, check_cancel, is_cancelled
from insrail.project import assessable
from insrail.project.design_file import read_design
from insrail.project.design_heading import design_azimuth_for, relative_frame, uses_design
from insrail.project.design_start import known_start
from insrail.project.mounting_stage import (
    fused_with_mounting,
    mounting_notices,
    roll_check,
    with_mounting,
    yaw_pitch_pass,
)
from insrail.project.odometer_pair_stage import slip_events, with_odometer_pair
from insrail.project.relative_survey import (
    absolute_notice,
    relative_notices,
    relative_section,
    no_amounts,
    withheld_adjustment_section,
    without_deviations,
)
from insrail.project.gap_sleepers import flag_gap_sleepers, gap_reason, long_gaps_of
from insrail.project.gnss_stage import GNSS_POS_FILE, GNSS_QC_FILE, run_gnss_stage
from insrail.project.local_control import LocalFit, fit_local
from insrail.project.lock import cache_entry, project_run
from insrail.project.model import Project
from insrail.project.clocks import ClockCheck
from insrail.project.plausibility import (
    check_benchmarks,
    check_imu_profile,
    check_survey,
    check_trolley,
    clean_gauge,
    describe,
    file_labels,
    nominal_gauge_m,
    trolley_source,
)
from insrail.project.run_settings import SETTINGS_SECTION, RunSettings, resolve_run_settings
from insrail.project.results import (
    EXCEEDANCES_FILE,
    FITTED_ALIGNMENT_CSV,
    FITTED_ALIGNMENT_XML,
    LINE_FIT_REPORT,
    QUALITY_FILE,
    RESULTS_FOLDER,
    SLEEPERS_FILE,
    SUMMARY_FILE,
    TQI_SECTION_M,
    TRAJECTORY_FILE,
    adjustment_section,
    exceedances_csv,
    gnss_section,
    quality_csv,
    quality_section,
    sleepers_csv,
    summary_toml,
    track_quality_section,
    trajectory_section,
    write_results,
)
from insrail.project.sleeper_integrity import flag_sleepers, fusion_reasons, reasons_section
from insrail.project.sleeper_parameters import (
    line_curvature_1pm,
    parameter_bases,
    parameter_columns,
    parameters_section,
    speed_notices,
)
from insrail.project.stagecache import (
    cached_dataclass,
    clean_leftovers,
    collect_cache_notices,
    file_sha256,
    intact,
    load_dataclass,
    save_dataclass,
    seal,
)
from insrail.project.total_station import gnss_free_run_notices, with_total_station_fixes
from insrail.project.track_events import (
    EVENTS_ROLE,
    TURNOUT_EXCEEDANCES_FILE,
    apply_events,
    assess_turnouts,
    detected_joints,
    events_section,
    survey_events,
)
from insrail.quality.survey import (
    EpochQuality,
    SectionQuality,
    UpdateEpochs,
    epoch_quality,
    recorded_quality,
    sections_along,
)
from insrail.track.adjustment import (
    Adjustment,
    optimise_amounts,
    programme_settings,
    reassess,
)
from insrail.track.alignment_csv import format_alignment_csv
from insrail.track.exceedance import Assessment, SleeperGeometry, assess
from insrail.track.landxml import format_landxml
from insrail.track.linefit import element_table
from insrail.track.parameters import line_speed_mps
from insrail.track.sleeper_table import (
    EpochStationsFile,
    SleeperTable,
    TrackReconstruction,
    finished_reconstruction,
)
from insrail.track.by_parts import chunked_interp
from insrail.track.streamed import reconstruct_track_streamed
from insrail.track.sleepers import AnchorError

CACHE_FOLDER = ".cache"
#: Bumped when the meaning of a cached stage changes, so stale caches are never reused.
CACHE_VERSION = 26  # 6: IMU screening, start-up for every IMU class, optional gnss and odometer roles; 7: filter resets, integrity; 8: the prism fix a survey starts from is applied; 9: ZUPT noise per stop, re-alignment at a reset, the odometer scale's exact Jacobian; 10: the notices of a run held by prism fixes (its 1-sigma there, a run beyond them); 11: the trolley play as position process noise; 12: the static start's level angles hold the horizontal accelerometer errors (P0), the unit check's rest by the aiding; 13: the trolley play estimated from the NHC innovations (a second pass); 14: the cross-level 1-sigma in the quality analysis and quality.csv; 15: the along-track 1-sigma; 16: a track heading's 1-sigma holds the trolley's yaw against the chord; 17: the NHC relaxed over rail joints' shocks, listed in the fusion's info; 18: the IMU mounting estimated (a pass without the NHC), a reset after a gap a last resort (the gap's error grown), relative surveys; 19: a gap return accepted far off grown as a reset's; 20: notices as templates and fields (read in the report's language); 21: the odometer's, the ZUPT's and the GNSS classes' noise estimated from the innovations (the fusion info's calibration); 22: sparse prism fixes back after their usual interval are no gap return (no growth over it); 23: the NHC rows' noise holds the gyro's white noise through the lever arm, the play's upper confidence limit where the filter's own part is most of the NHC innovations; 24: the integrity intervals' and the mounting's reasons as phrases (said in the report's language); 25: a sensor bias's turn-on part not forgotten (one Gauss-Markov state of the bias's whole variance), the start position's error holds the attitude's through the lever arm of the fix it came from; 26: a detour of a source between two filter resets (its sleepers not assessed)
#: What a cached track holds: 2, the epochs' stations instead of the rails (a 10 km survey's
#: entry 52 MB instead of 370 MB, read back in a rerun); 3, the epochs' stations in their own
#: file (track-<key>.epochs.npy), read by parts; 4, without a design the line-type fit always
#: valid and leaving out the sleepers the fusion marks not valid; 5, the line-type fit over gaps in the
#: data (no chord across them) and with data beginning or ending a few metres before a curve.
TRACK_CACHE_LAYOUT = 5


@dataclass(frozen=True)
class SurveyResults:
    """What ``process`` produced for one survey (arrays in SI units)."""

    survey: str
    folder: Path  # <project>/results/<survey>
    gps_week: int | None
    height_fit: HeightAnomalyFit | None
    reconstruction: TrackReconstruction
    assessment: Assessment
    adjustment: Adjustment
    fusion_from_cache: bool
    summary: dict
    quality: SectionQuality

    @property
    def table(self) -> SleeperTable:
        return self.reconstruction.table

    @cached_property
    def trajectory(self) -> Trajectory:
        """The fused trajectory (read from the result folder on first use: it is the large array)."""
        return load_trajectory(self.folder / TRAJECTORY_FILE, gps_week=self.gps_week)


@dataclass(frozen=True)
class FittedLine:
    """What the results take from the line-type fit of a survey without a design (the fit itself,
    element objects, is not kept in the stage cache): the fitted alignment as CSV and LandXML and
    the fit's report (empty when there is no fit), summary.toml's ``[track.line_fit]`` (JSON) and
    the fitted line's curvature at each sleeper of the table (None without a fit)."""

    alignment_csv: str
    alignment_landxml: str
    report: str
    section_json: str
    curvature_1pm: np.ndarray | None = None

    @classmethod
    def of(cls, recon: TrackReconstruction) -> FittedLine:
        if recon.fitted is None:
            return cls("", "", "", json.dumps(_line_fit_section(recon)))
        alignment = recon.fitted.alignment
        return cls(format_alignment_csv(alignment), format_landxml([alignment]), recon.fitted.report() + "\n",
                   json.dumps(_line_fit_section(recon)), line_curvature_1pm(alignment, recon.table.station_m))

    def files(self) -> dict[str, str]:
        """The result files of the fit: usable as the design of a later survey (CSV element table and
        LandXML 1.2), and the fit's residual and element report; none without a fit."""
        if not self.alignment_csv:
            return {}
        return {FITTED_ALIGNMENT_CSV: self.alignment_csv, FITTED_ALIGNMENT_XML: self.alignment_landxml,
                LINE_FIT_REPORT: self.report}

    def section(self) -> dict:
        return json.loads(self.section_json)


@dataclass(frozen=True)
class TrackExtras:
    """What the results take from the track stage beyond the reconstruction, cached with it: the
    fused attitude (roll, pitch, heading [rad]) at every sleeper of the table and, without a
    design, the line-type fit."""

    attitude_rad: np.ndarray
    line: FittedLine | None = None


@dataclass(frozen=True)
class FreshFusion:
    """What the track reconstruction needs from a fusion just computed beyond its trajectory file,
    which it reads by parts (the 200 Hz IMU data and the fusion's covariances are dropped here:
    they dominate the memory of a long survey)."""

    gauge: GaugeData
    pulses: SleeperPulses | None


def _geodesy_settings(run: RunSettings) -> dict:
    """What the engineering coordinates depend on: CRS, benchmarks (contents) and height model."""
    settings = {"crs": run.crs.to_settings(), "height": run.height.anomaly.to_settings()}
    if run.height.benchmarks is not None:
        settings["benchmarks"] = run.benchmarks_sha256
    return settings


def fusion_key(project: Project, manifest: SurveyManifest, folder: Path, gnss_sha256: str = "",
               run: RunSettings | None = None) -> str:
    """Hash of everything the fused trajectory of the survey in ``folder`` depends on (its
    manifest with the project's trolley applied): raw files, the parts of the run settings the
    fusion reads (``run``; None: resolved from the project now) and, when prism fixes aid the
    fusion, the geodesy that places them; ``gnss_sha256``: the hash of a GNSS solution computed by
    the GNSS stage (PPK)."""
    run = run or resolve_run_settings(project, manifest)
    digest = hashlib.sha256(gnss_sha256.encode())
    fused = {role: entry for role, entry in manifest.files.items() if role != EVENTS_ROLE}  # events: assessment only
    for role in sorted(fused):
        digest.update(role.encode())
        get_format(fused[role].format).scan(folder / fused[role].path, digest.update)  # refused before hashed whole
    # the beam's wheel spacing corrects the gauge after the fusion: the track key holds it
    trolley = {k: np.asarray(v).tolist() if not isinstance(v, str) else v
               for k, v in asdict(run.trolley).items() if k != "beam_wheel_spacing_m"}
    settings = {"version": CACHE_VERSION, "gps_week": manifest.gps_week, "trolley": trolley,
                "imu_profile": repr(run.imu_profile), "fusion": repr(run.fusion), "ellipsoid": repr(run.ellipsoid),
                "files": {r: asdict(f) for r, f in fused.items()}}
    if "prism" in manifest.files or "total_station" in manifest.files:
        settings["prism_geodesy"] = _geodesy_settings(run)
    if uses_design(project, run.imu_profile):  # its azimuth may give the start heading
        settings["design"] = [run.design_sha256, _geodesy_settings(run)["crs"]]
    if manifest.relative:  # its frame starts on the design at the start station, or on the CRS's meridian
        settings["relative_frame"] = [run.design_sha256, _geodesy_settings(run)["crs"], project.start_station_m]
    if manifest.start is not None:  # the filter starts on the design there (design_start)
        settings["start"] = [asdict(manifest.start), run.design_sha256, _geodesy_settings(run)]
    digest.update(json.dumps(settings, sort_keys=True, default=str).encode())
    return digest.hexdigest()[:32]


def track_key(project: Project, run: RunSettings, fusion: str, events_sha256: str = "") -> str:
    """Hash of everything the track reconstruction depends on beyond the fusion (whose key holds
    the raw files, gauge and sleeper pulses included, and the trolley): the run settings' geodesy
    and design, the project's stationing and, without a design, the event files (``events_sha256``,
    :func:`events_sha256`: their stretches are left out of the line fit)."""
    digest = hashlib.sha256(fusion.encode())
    settings = {"version": CACHE_VERSION, "layout": TRACK_CACHE_LAYOUT, "geodesy": _geodesy_settings(run),
                "start_station_m": project.start_station_m, "first_sleeper_number": project.first_sleeper_number,
                "stationing_direction": project.stationing_direction, "sleeper_anchor": repr(project.sleeper_anchor)}
    if run.trolley.beam_wheel_spacing_m:
        settings["beam_wheel_spacing_m"] = run.trolley.beam_wheel_spacing_m
    if project.local_control is not None:
        settings["local_control"] = project.local_control.to_settings()
    if run.design is not None:
        settings["design"] = [run.design, run.design_sha256]
    else:
        settings["events"] = events_sha256
    digest.update(json.dumps(settings, sort_keys=True, default=str).encode())
    return digest.hexdigest()[:32]


def events_sha256(project: Project, manifest: SurveyManifest, folder: Path) -> str:
    """The contents of the survey's and the project's event files ("" without either)."""
    paths = ([folder / manifest.files[EVENTS_ROLE].path] if EVENTS_ROLE in manifest.files else []) + (
        [project.resolve(project.events)] if project.events is not None else [])
    return hashlib.sha256("".join(file_sha256(path) for path in paths).encode()).hexdigest() if paths else ""


def prism_fixes(project: Project, prism: PrismObservations, trolley: TrolleyGeometry,
                height_fit: HeightAnomalyFit | None) -> PositionFix:
    """Total-station fixes (project CRS, normal heights) as geodetic position fixes of the prism."""
    def to_geodetic(east, north, normal_height):
        lat, lon = project.crs.to_geodetic(east, north)
        zeta = height_fit.zeta_m(east, north) if height_fit is not None else 0.0
        return lat, lon, normal_height + zeta

    return PositionFix.from_prism(prism, trolley.lever_arm_m("imu_to_prism_m"), to_geodetic)


def quality_cache_file(trajectory_file: Path) -> Path:
    """The covariance analysis cached beside a fused trajectory (``fusion-<key>.quality.npz``)."""
    return trajectory_file.with_suffix(".quality.npz")


class FusionEntry:
    """The fusion stage's cache entry (``fusion-<key>``): the fused trajectory's cache file, the
    fusion statistics (``info``, what the ``.toml`` beside it holds) and, for a fusion just computed,
    what it leaves for the track (``fresh``) and its covariance analysis, which may still be running
    (:class:`~insrail.background.BackgroundJob`, beside the track reconstruction).

    A context manager: a fresh entry is sealed (:meth:`seal`: the analysis awaited and saved, the
    statistics written, the checksums last) only once all its files are complete; when the block
    fails or is cancelled first, the analysis is stopped and waited for and the trajectory file
    removed, so no unsealed entry is left (:mod:`insrail.project.stagecache`)."""

    def __init__(self, path: Path, info: dict, fresh: FreshFusion | None = None,
                 quality: BackgroundJob[EpochQuality] | None = None, store: SmootherStore | None = None):
        self.path, self.fresh = path, fresh
        self._info, self._quality, self._store = info, quality, store

    @property
    def info(self) -> dict:
        """The fusion statistics, with ``from_cache`` (a copy: the caller takes items out)."""
        return {"from_cache": self.fresh is None} | self._info

    def relay(self, progress: ProgressFn | None) -> None:
        """Say the running analysis's progress through ``progress`` (the calling thread's step)."""
        if self._quality is not None:
            self._quality.relay(progress)

    def seal(self, progress: ProgressFn | None = None) -> None:
        """The analysis awaited (its progress said through ``progress``) and cached, the statistics
        written and the entry's checksums written last; nothing to do for an entry already sealed."""
        if self._quality is None:
            return
        try:
            save_dataclass(quality_cache_file(self.path), self._quality.result(progress))
            with atomic_write(self.path.with_suffix(".toml"), "wb") as handle:
                tomli_w.dump(self._info, handle)
            seal(self.path, self.path.with_suffix(".toml"))
        except BaseException:
            self._discard()
            raise
        self._quality = None
        self._close_store()

    def _discard(self) -> None:
        """The analysis stopped and waited for, the trajectory file removed (the entry's checksums
        are written last: none is there yet)."""
        self._quality.stop()
        self._quality = None
        self._close_store()
        self.path.unlink(missing_ok=True)

    def _close_store(self) -> None:
        if self._store is not None:
            self._store.close()
            self._store = None

    def __enter__(self) -> FusionEntry:
        return self

    def __exit__(self, kind, error, traceback) -> bool:
        if self._quality is not None:  # not sealed yet
            if kind is None:
                self.seal()
            else:  # failed or cancelled while the entry was open: no unsealed entry left
                self._discard()
        return False


def _fused_trajectory(project: Project, run: RunSettings, manifest: SurveyManifest, folder: Path, key: str,
                      height_fit: HeightAnomalyFit | None, gnss: GnssSolution | None,
                      progress: StepProgress, cancel: CancelToken) -> FusionEntry:
    """The fusion stage's cache entry: the fused trajectory's cache file and the fusion statistics,
    from the cache (reading no raw file) or computed. ``gnss``: the solution of the GNSS stage for a
    survey with raw observations. A fresh fusion is followed by its covariance analysis (cached in
    :func:`quality_cache_file`), which runs on beside the caller until the entry is sealed."""
    cache = project.folder / RESULTS_FOLDER / CACHE_FOLDER
    path = cache / f"fusion-{key}.npy"
    info_path = path.with_suffix(".toml")
    if intact("fusion", path, info_path, quality_cache_file(path)):
        progress(1.0, "fusion reused from the cache")
        return FusionEntry(path, tomllib.loads(info_path.read_text(encoding="utf-8")))
    # the trolley in force is the manifest's, checked before the fusion (the project's or the survey's)
    survey, placed = with_total_station_fixes(read_survey(folder, progress=progress.sub(0.0, 0.05), cancel=cancel,
                                                          gnss=gnss, trolley_from_project=True))
    survey = replace(survey, manifest=manifest)
    # first: a time-scale mix-up also upsets the other checks (checked beside them and the fusion's start)
    clocks = ClockCheck(survey, file_labels(survey))
    # The smoother's record of the filter (Phi, P-, P+ per update epoch, on disk) outlives the
    # fusion so that the covariance analysis needs only its backward pass, not a replay.
    store = None
    try:  # fused again where the first pass shows the NHC or the GNSS sigmas do not hold (self_calibration)
        survey, checked = check_survey(survey, nominal_gauge_m(project))
        survey, pair_notices, odometer_pair = with_odometer_pair(survey, file_labels(survey))
        free_run = gnss_free_run_notices(survey)
        fixes = (prism_fixes(project, survey.prism, manifest.trolley, height_fit)
                 if survey.prism is not None and len(survey.prism) else None)
        profile = run.imu_profile
        # rail joints: the NHC does not hold over their shocks (thesis 5.3.1.2); listed as events later
        shocks = detect_shocks(survey.imu)
        cache.mkdir(parents=True, exist_ok=True)
        alignment = read_design(project.resolve(run.design)) if run.design else None
        design = design_azimuth_for(project, alignment, profile)
        frame = (relative_frame(project, alignment, run.crs, manifest.start, manifest.trolley, height_fit)
                 if manifest.relative else None)
        known = (known_start(project, alignment, run.crs, manifest.start, manifest.trolley, height_fit)
                 if manifest.start is not None and not manifest.relative else None)

        def aiding_builder(survey):
            return lambda options: replace(aiding_for(survey, options, profile, fixes, shocks.nhc_relaxed_s()),
                                           design_azimuth=design, relative=frame, known_start=known)

        # every pass screens the same IMU records: once for all (the screened records dropped after the passes)
        memo = PassMemo()
        fuse_pass = partial(fuse, memo=memo)

        def estimated_mounting(survey, progress, cancel):
            return yaw_pitch_pass(survey, aiding_builder(survey), profile, run.fusion, run.ellipsoid, fuse_pass,
                                  progress=progress, cancel=cancel)

        def fused(survey, progress, cancel):  # the trajectory streamed into the cache as it is made (sealed below)
            return fuse_consistent(survey.imu, aiding_builder(survey), profile, run.fusion, run.ellipsoid,
                                   new_store=SmootherStore if run.fusion.smoother else None, fuse=fuse_pass,
                                   progress=progress, cancel=cancel, trajectory_file=path)

        def discarded(outcome):  # a main fusion with a mounting the pass did not confirm
            if outcome is not None and outcome[2] is not None:
                outcome[2].close()
            path.unlink(missing_ok=True)

        def fusion_cancel():  # the clocks' error comes first: the fusion stops for it
            return is_cancelled(cancel) or clocks.failed()

        # the IMU's mounting from the survey (where GNSS gives the direction of travel), applied where it
        # differs from the given one beyond 3 sigma: the NHC then holds the right axes to the rail
        if run.fusion.use_nhc:
            mounting, survey, (result, options, store, _) = fused_with_mounting(
                survey, estimated_mounting, fused, discarded, progress.sub(0.05, 0.87), fusion_cancel)
        else:
            mounting = not_estimated(manifest.trolley.mounting_rpy_rad, Phrase("the NHC is off"))
            survey = replace(survey, manifest=with_mounting(survey.manifest, mounting.applied_rpy_rad()))
            result, options, store, _ = fused(survey, progress.sub(0.05, 0.87), fusion_cancel)
        checked = [*placed, *free_run, *clocks.notices(), *checked, *pair_notices,
                   *mounting_notices(mounting, "survey.toml")]
        memo.clear()
        check_cancel(cancel)
        if not result.integrity.trusted:
            raise UntrustedSolution(result.integrity.failure())
        imu_epochs, imu_span_s = len(survey.imu), (float(survey.imu.time_s[0]), float(survey.imu.time_s[-1]))
        info = {"rejections": len(result.rejections), "stops": len(result.stops), "imu_epochs": imu_epochs,
                "trajectory_epochs": len(result.trajectory), "prism_fixes": 0 if fixes is None else len(fixes.time_s),
                "notices": [*(n.to_dict() for n in checked), *(n.to_dict() for n in result.info["notices"])],
                "alignment": result.info["alignment"],
                "resets": len(result.resets), "integrity": result.integrity.to_dict(), "mounting": mounting.to_dict(),
                "calibration": result.info["calibration"],
                "along_track_scale": "odometer" if survey.odometer is not None else "GNSS positions only (no odometer)",
                **({"odometer_pair": odometer_pair} if odometer_pair is not None else {}),
                "imu_gaps_s": [[gap.start_s, gap.end_s] for gap in result.info["imu_gaps"]],
                "shocks": {"time_s": shocks.time_s.tolist(), "peak_mps2": shocks.peak_mps2.tolist(),
                           "threshold_mps2": shocks.threshold_mps2}}
        # about 15 % of the fusion's time with the record (a forward-only fusion: 40 %, a replay)
        if store is not None and result.trajectory.smoothed:
            # the analysis of the record reads neither the 200 Hz IMU record nor the fusion's result
            # (its forward solution and innovations, ~0.3 kB per update epoch): both go first. It
            # runs beside the track reconstruction, which needs only the trajectory file
            epochs = UpdateEpochs.of(survey.odometer, result)
            survey, result = replace(survey, imu=None), None
            quality = BackgroundJob(lambda said, stop: recorded_quality(epochs, store, progress=said, cancel=stop),
                                    progress.sub(0.87, 1.0), cancel, "covariance analysis")
        else:  # the replay needs the IMU record: done now, before the track takes its memory
            quality = BackgroundJob(lambda said, stop: epoch_quality(survey, result, options, profile, run.ellipsoid,
                                                                     progress=said, cancel=stop),
                                    progress.sub(0.87, 1.0), cancel, "covariance analysis", threaded=False)
    except BaseException as error:  # untrusted, cancelled or failed once the streamed trajectory is complete:
        path.unlink(missing_ok=True)  # no unsealed entry left
        if store is not None:
            store.close()
        clocks.first(error)  # as when the clocks were checked before all else
        raise
    if survey.gnss is not None:
        info["gnss"] = gnss_section(survey.gnss.time_s, survey.gnss.quality, *imu_span_s)
    # the track reads the trajectory from the file by parts, as from the cache
    return FusionEntry(path, info, FreshFusion(survey.gauge, survey.sleepers), quality, store)


def _reconstructed_track(project: Project, run: RunSettings, manifest: SurveyManifest, folder: Path,
                         fresh: FreshFusion | None,
                         trajectory_file: Path, key: str, height_fit: HeightAnomalyFit | None,
                         cancel: CancelToken, local: LocalFit | None = None, fusion_info: dict | None = None,
                         relay: Callable[[], None] | None = None) -> tuple[TrackReconstruction, TrackExtras, bool]:
    """Rails, chainage and sleepers and their :class:`TrackExtras` (from the cache when nothing
    they depend on changed; a reconstruction from the cache carries no ``fitted`` and
    ``reference`` objects, only their :class:`FittedLine`); with local control every coordinate
    from here on is in the local grid. Without a design the line-type fit leaves out the
    sleepers ``fusion_info`` marks not valid (fusion not consistent, IMU gaps bridged): they are
    not measurements of the line (the fusion key, part of this stage's, determines them). ``relay``:
    called per part of the trajectory read (it says the progress of what runs beside the stage)."""
    path = project.folder / RESULTS_FOLDER / CACHE_FOLDER / f"track-{key}.npz"
    extras_path, epochs_path = path.with_suffix(".extras.npz"), path.with_suffix(".epochs.npy")
    cached = (cached_dataclass("track reconstruction", path, TrackReconstruction)
              if intact("track reconstruction", epochs_path) else None)
    extras = cached_dataclass("track reconstruction", extras_path, TrackExtras) if cached is not None else None
    if extras is not None and (extras.line is not None or run.design is not None):
        return replace(cached, epochs=EpochStationsFile(epochs_path)), extras, True

    def to_engineering(lat, lon, h):
        east, north = run.crs.to_plane(lat, lon)
        zeta = height_fit.zeta_m(east, north) if height_fit is not None else 0.0
        return (east, north, h - zeta) if local is None else local.apply(east, north, h - zeta)

    if fresh is None:
        gauge, _ = clean_gauge(_read_role(folder, manifest, "gauge"), nominal_gauge_m(project),  # as the fusion did
                               describe(folder / manifest.files["gauge"].path, manifest.files["gauge"].format))
        fresh = FreshFusion(gauge, _read_role(folder, manifest, "sleepers"))
    design = read_design(project.resolve(run.design)) if run.design is not None else None
    check_cancel(cancel)

    def check() -> None:  # per part: the cancel, and the progress of what runs beside
        check_cancel(cancel)
        if relay is not None:
            relay()

    try:
        # the file does not say on which ellipsoid the fusion ran: the run's; read by parts, the
        # rails and stations (25 doubles per epoch) are never held whole
        recon, attitude = reconstruct_track_streamed(
            trajectory_file, run.ellipsoid, manifest.trolley, fresh.gauge, to_engineering, design=design,
            pulses=fresh.pulses, start_station_m=project.start_station_m, first_number=project.first_sleeper_number,
            stationing=project.stationing_direction, anchor=project.sleeper_anchor,
            beam_wheel_spacing_m=manifest.trolley.beam_wheel_spacing_m, spool_folder=path.parent,
            epochs_file=epochs_path, check=check, fit_line=False)
    except AnchorError as error:
        raise InputError(project.path, None, "track.sleeper_anchor: {error}", fields={"error": error}) from None
    if design is None:
        info = fusion_info or {}
        flagged = flag_gap_sleepers(flag_sleepers(recon.table, info.get("integrity")), info.get("imu_gaps_s", []))
        # a turnout, a level crossing or a stretch not to assess is no part of the line's geometry either
        flagged = apply_events(replace(recon, table=flagged), survey_events(project, manifest, folder, recon)).table
        recon = finished_reconstruction(recon.sleepers, recon.table, {"epochs": recon.epochs}, True,
                                        cant_base_m=manifest.trolley.rail_centre_spacing_m, fit_rows=flagged.valid)
    extras = TrackExtras(attitude, FittedLine.of(recon) if run.design is None else None)
    save_dataclass(extras_path, extras)
    seal(epochs_path)
    save_dataclass(path, replace(recon, epochs=None, fitted=None, reference=None))  # the epochs: in their own file
    return recon, extras, False


def joints_section(joints: tuple, shocks: dict) -> dict:
    """summary.toml's ``[joints]``: the rail joints found as IMU shocks (each also an event), the
    median spacing between neighbours [m] and the shock threshold [m/s^2]."""
    stations = np.sort([joint.station_from_m for joint in joints])
    spacing = float(np.median(np.diff(stations))) if len(stations) >= 2 else float("nan")
    section = {"detected": len(joints), "threshold_mps2": round(float(shocks["threshold_mps2"]), 3),
               "nhc_relaxed_s": NHC_RELAXED_S}
    if np.isfinite(spacing):
        section["median_spacing_m"] = round(spacing, 3)
    return section


def _read_role(folder: Path, manifest: SurveyManifest, role: str):
    """One raw file of the survey by its role (None when the survey has none)."""
    entry = manifest.files.get(role)
    return None if entry is None else entry.read(folder)


def _adjustment(project: Project, run: RunSettings, geometry: SleeperGeometry, progress,
                cancel, not_assessed: dict[tuple[str, str], np.ndarray]) -> tuple[Assessment, Adjustment]:
    """The optimised adjustment and the assessment of the geometry it leaves (every check of the
    profile where the survey can assess it: ``not_assessed``; sleepers still failing flagged with the
    reason). The amounts come from the cache when the geometry, the checks the optimisation holds and
    where, the fastener and the strategy are those of an earlier run."""
    fastener, profile = run.fastener, run.tolerance_profile
    strategy = run.adjustment.strategy
    digest = hashlib.sha256(json.dumps({"version": CACHE_VERSION, "fastener": repr(fastener), "strategy": strategy,
                                        "threshold_mm": run.adjustment.threshold_mm,
                                        "programme": programme_settings(profile)}).encode())
    for values in (geometry.lateral_deviation_m, geometry.vertical_deviation_m, geometry.gauge_m, geometry.cant_m,
                   geometry.design_cant_m, geometry.station_m):
        digest.update(np.ascontiguousarray(values).tobytes())
    for key in sorted(not_assessed):
        digest.update(repr(key).encode() + np.packbits(not_assessed[key]).tobytes())
    path = project.folder / RESULTS_FOLDER / CACHE_FOLDER / f"adjustment-{digest.hexdigest()[:32]}.npz"
    with cache_entry(project.folder, path.stem, progress, cancel):
        cached = cached_dataclass("adjustment", path, Adjustment)
        if cached is not None:
            lateral, vertical = cached.lateral_m, cached.vertical_m
        else:
            lateral, vertical = optimise_amounts(geometry, profile, fastener, strategy, progress=progress,
                                                 cancel=cancel, threshold_m=run.adjustment.threshold_m,
                                                 not_assessed=not_assessed)
        after, adjustment = reassess(geometry, lateral, vertical, profile, fastener, not_assessed)
        if cached is None:
            save_dataclass(path, adjustment)
    return after, adjustment


def fit_heights(project: Project) -> HeightAnomalyFit | None:
    """ζ fitted on the project's benchmarks (None without benchmarks: heights stay ellipsoidal)."""
    if project.height.benchmarks is None:
        return None
    benchmarks = read_benchmarks(project.resolve(project.height.benchmarks))
    check_benchmarks(benchmarks)
    east, north = project.crs.to_plane(benchmarks.lat_rad, benchmarks.lon_rad)
    anomaly = project.height.anomaly
    if anomaly.geoid_grid not in (None, "egm96"):  # a grid file named relative to the project
        anomaly = replace(anomaly, geoid_grid=str(project.resolve(anomaly.geoid_grid)))
    return fit_height_anomaly(np.column_stack([east, north]), benchmarks.height_anomaly_m,
                              anomaly.model, geoid=anomaly.plane_geoid(project.crs))


def process(project: Project, survey_name: str, progress: ProgressFn | None = None,
            cancel: CancelToken = None) -> SurveyResults:
    """Process one survey of ``project`` end to end and write its result files (see the module docstring)."""
    results = project.folder / RESULTS_FOLDER

    def clean() -> None:  # no other run of the project is going on: whatever is left, killed runs left
        for folder in (results / CACHE_FOLDER, results):
            clean_leftovers(folder)

    # the raw files hashed for the fusion's key are checked as text once, not again when they are read
    with project_run(project.folder, [survey_name], progress, cancel, when_alone=clean), \
            collect_cache_notices() as cache_notices, checked_once():
        return _process_survey(project, survey_name, progress, cancel, cache_notices)


def _process_survey(project: Project, survey_name: str, progress: ProgressFn | None, cancel: CancelToken,
                    cache_notices: list[Notice]) -> SurveyResults:
    step = StepProgress(progress)
    started = time.monotonic()
    entry = project.survey(survey_name)
    folder = project.resolve(entry.folder)
    manifest = project.manifest(survey_name)
    roles = set(manifest.files) | ({"gnss"} if manifest.raw_gnss is not None else set())
    trolley = project.trolley(roles)
    if trolley is not None:
        manifest = replace(manifest, trolley=trolley)
    check_trolley(manifest.trolley, trolley_source(project.path, folder, trolley is not None), nominal_gauge_m(project),
                  roles)
    if project.imu_profile is None:  # the project's own is checked when the project is loaded
        check_imu_profile(manifest.imu_profile, folder / MANIFEST_NAME, "survey.imu_profile")
    if "gauge" not in manifest.files:
        raise InputError(folder / MANIFEST_NAME, None,
                         "files.gauge: missing; the track reconstruction needs the gauge record")
    run = resolve_run_settings(project, manifest)  # what every stage takes, recorded in summary.toml
    gnss = None  # the GNSS stage (PPK), for a survey with raw observations: after the settings' checks
    if manifest.raw_gnss is not None:
        gnss = run_gnss_stage(project, folder, manifest, project.folder / RESULTS_FOLDER / CACHE_FOLDER,
                              step.sub(0.0, 0.04), cancel)
    check_cancel(cancel)
    step(0.04, "height model")
    # the benchmarks' fit beside the hashing of the raw files for the fusion's key (hashlib, without the
    # GIL); a failure of the fit is said first, as when it ran first
    with BackgroundJob(lambda said, stop: fit_heights(project), None, cancel, "height model") as fitting:
        try:
            key = fusion_key(project, manifest, folder, gnss.pos_sha256 if gnss else "", run)
        except BaseException:
            fitting.result()
            raise
        height_fit = fitting.result()
    # the fusion's entry stays open (locked, not sealed) while its covariance analysis runs beside the
    # track reconstruction, which reads only the trajectory file; it is sealed before the quality is used
    with cache_entry(project.folder, f"fusion-{key}", step.sub(0.04, 0.8), cancel), \
            _fused_trajectory(project, run, manifest, folder, key, height_fit, gnss.solution if gnss else None,
                              step.sub(0.04, 0.8), cancel) as fusion:
        fresh, trajectory_file, fusion_info = fusion.fresh, fusion.path, fusion.info
        release_free_memory()
        check_cancel(cancel)
        mounting = MountingEstimate.from_dict(fusion_info.get("mounting"), manifest.trolley.mounting_rpy_rad)
        manifest = with_mounting(manifest, mounting.applied_rpy_rad())  # the fusion's, for the rails

        step(0.82, "rails, chainage and sleepers")
        beside = step.sub(0.82, 0.88)  # the analysis's progress, said by this thread
        local = fit_local(project.local_control) if project.local_control is not None else None
        events_key = events_sha256(project, manifest, folder)
        reconstruction_key = track_key(project, run, key, events_key)
        with cache_entry(project.folder, f"track-{reconstruction_key}", step.sub(0.82, 0.88), cancel):
            recon, extras, track_cached = _reconstructed_track(project, run, manifest, folder, fresh, trajectory_file,
                                                               reconstruction_key, height_fit, cancel, local,
                                                               fusion_info, relay=partial(fusion.relay, beside))
        fusion.seal(beside)
    # the roll of the mounting from the cant against the design's: beyond 3 sigma the rails are placed again
    roll = roll_check(manifest, recon.table, run.design is not None)
    if roll.significant[0]:
        manifest = with_mounting(manifest, roll.applied_rpy_rad())
        reconstruction_key = track_key(project, run, f"{key}-roll-{roll.applied_rpy_rad()[0]:.9f}", events_key)
        with cache_entry(project.folder, f"track-{reconstruction_key}", step.sub(0.82, 0.88), cancel):
            recon, extras, track_cached = _reconstructed_track(project, run, manifest, folder, fresh, trajectory_file,
                                                               reconstruction_key, height_fit, cancel, local,
                                                               fusion_info)
    mounting = mounting.combined(roll)
    del fresh
    release_free_memory()
    check_cancel(cancel)
    step(0.88, "irregularities and exceedances")
    measured = recon.table.valid
    recon = replace(recon, table=flag_sleepers(recon.table, fusion_info.get("integrity")))
    shocks = fusion_info.pop("shocks")  # listed as joints, not in summary.toml's [fusion]
    joints = detected_joints(shocks, recon)
    events = tuple(sorted(survey_events(project, manifest, folder, recon) + joints
                          + slip_events(fusion_info.get("odometer_pair"), recon),
                          key=lambda e: (e.station_from_m, e.station_to_m)))
    recon = apply_events(recon, events)
    recon = replace(recon, table=flag_gap_sleepers(recon.table, fusion_info.get("imu_gaps_s", [])))
    table = recon.table
    centre = table.centre_enh_m[measured]
    if local is not None:  # the height model lives in the engineering CRS
        centre = np.column_stack(local.to_engineering(*centre.T))
    height_warnings = height_fit.warnings_for(centre[:, 0], centre[:, 1]) if height_fit is not None else []
    curvature = (line_curvature_1pm(read_design(project.resolve(run.design)), table.station_m)
                 if run.design is not None else extras.line.curvature_1pm)
    speed = line_speed_mps(project.line_speeds, table.station_m) if project.line_speeds else None
    geometry = SleeperGeometry.from_arrays(table.station_m, table.lateral_deviation_m, table.vertical_deviation_m,
                                           table.gauge_m, table.cant_m, table.design_cant_m, valid=table.valid,
                                           sleeper_number=table.number, curvature_1pm=curvature, line_speed_mps=speed)
    profile = run.tolerance_profile
    quality = _section_quality(trajectory_file, recon)
    unresolved = assessable.not_assessable(profile, quality, table.station_m)
    everything = assessment = assess(geometry, profile)
    if unresolved:
        assessment = assess(geometry, profile, not_assessed=assessable.masks(unresolved))
    not_listed = assessable.left_out(unresolved, everything, assessment)
    in_turnouts, turnout_counts = assess_turnouts(project, geometry, measured, events)
    release_free_memory()
    check_cancel(cancel)
    step(0.9, "adjustment amounts")
    # the report's figures of the trajectory, read from its file by parts (numpy, mostly without the GIL),
    # and of the track quality (the band-pass filters' first import of scipy.signal) beside the adjustment,
    # whose programmes HiGHS solves without the GIL
    with BackgroundJob(lambda said, stop: (trajectory_section(trajectory_file), track_quality_section(geometry)),
                       None, cancel, "figures") as figures:
        if manifest.relative:  # its deviations hold the IMU's drift: no amounts to plan (relative_survey)
            adjustment, after_adjustment = no_amounts(len(table.station_m), run.fastener.name), assessment
        else:
            after_adjustment, adjustment = _adjustment(project, run, geometry, step.sub(0.9, 0.97), cancel,
                                                       assessable.masks(unresolved))
        trajectory_figures, track_quality = figures.result()
    release_free_memory()
    check_cancel(cancel)

    step(0.97, "writing results")
    gnss_summary = fusion_info.pop("gnss", None)  # cached with the fusion: the GNSS file is not re-read
    summary = _summary(project, run, entry.name, manifest, fusion_info, track_cached, height_fit, height_warnings,
                       table, assessment, adjustment, after_adjustment, time.monotonic() - started)
    summary["fusion"]["mounting"] = mounting.to_dict()
    if gnss_summary is not None:
        summary["gnss"] = gnss_summary
    if gnss is not None:
        summary["ppk"] = gnss.summary(run.fusion.gnss_quality_policy)
        summary["files"].update(gnss=GNSS_POS_FILE, gnss_qc=GNSS_QC_FILE)
    bases = parameter_bases(profile)
    summary["track"]["parameters"] = parameters_section(
        bases, project.line_speeds, "design" if run.design is not None else "fitted" if curvature is not None else "none")
    summary["notices"] = [n.to_dict() for n in [*outside_notices(project, folder, manifest), *cache_notices, *run.notices(),
                                                *_notices(fusion_info, height_warnings, gnss.warnings() if gnss is not None else []),
                                                *(local.notices() if local is not None else []),
                                                *speed_notices(profile, table, curvature, speed),
                                                *assessable.notices(unresolved, not_listed),
                                                *(mounting_notices(roll, "survey.toml", "track")
                                                  if np.isfinite(roll.sigma_rad[0]) else []),
                                                *_line_fit_notices(extras.line, table)]]
    if local is not None:
        summary["local_control"] = local.summary()
    summary["track_quality"] = track_quality
    summary["events"] = events_section(events, table.station_m, turnout_counts)
    summary["joints"] = joints_section(joints, shocks)
    summary["track"]["sleeper_pulses"] = recon.sleepers.repair_counts()
    event_files = {}
    if turnout_counts:  # turnouts assessed with their own profiles
        event_files[TURNOUT_EXCEEDANCES_FILE] = exceedances_csv(replace(assessment, exceedances=in_turnouts))
        summary["files"]["turnout_exceedances"] = TURNOUT_EXCEEDANCES_FILE
    summary["assessment"]["not_assessed_sleepers"] = int((measured & ~table.valid).sum())
    summary["assessment"]["not_assessed_reasons"] = reasons_section(  # sleepers.csv's reasons, for a report's language
        [*(reason for _, _, reason in fusion_reasons(fusion_info.get("integrity"))),
         *(event.described() for event in events if event.excluded),
         *(gap_reason(*gap) for gap in long_gaps_of(fusion_info.get("imu_gaps_s", [])))])
    line_fit_files = extras.line.files() if extras.line is not None else {}
    if extras.line is not None:
        summary["track"]["line_fit"] = extras.line.section()
        summary["files"].update(dict(zip(("fitted_alignment_csv", "fitted_alignment_landxml", "line_fit_report"),
                                          line_fit_files)))
    summary["assessment"]["not_assessable"] = assessable.summary_section(unresolved, not_listed)
    summary["quality"] = quality_section(quality)
    if manifest.relative:  # every output says so; the chord checks where the error growth allows
        summary["survey"]["kind"] = "relative"
        frame = relative_frame(project, read_design(project.resolve(run.design)) if run.design else None, run.crs,
                               manifest.start, manifest.trolley, height_fit)
        summary["relative"] = relative_section(frame, profile, quality)
        summary["notices"] += [n.to_dict() for n in (*relative_notices(profile, quality),
                                                     *absolute_notice(frame, quality))]
        table = without_deviations(table)
        recon = replace(recon, table=table)
    summary["files"]["quality"] = QUALITY_FILE
    summary["trajectory"] = trajectory_figures
    results_folder = write_results(project.folder / RESULTS_FOLDER, entry.name, {
        TRAJECTORY_FILE: trajectory_file, SLEEPERS_FILE: sleepers_csv(table, assessment, adjustment, parameter_columns(
            table, extras.attitude_rad, curvature, speed, bases)),
        QUALITY_FILE: quality_csv(quality),
        EXCEEDANCES_FILE: exceedances_csv(assessment), SUMMARY_FILE: summary_toml(summary),
        **line_fit_files, **event_files, **(gnss.result_files() if gnss else {})}, cancel)
    release_free_memory()
    step(1.0, "done")
    return SurveyResults(entry.name, results_folder, manifest.gps_week, height_fit, recon, assessment, adjustment,
                         fusion_info["from_cache"], summary, quality)


def _section_quality(trajectory_file: Path, recon: TrackReconstruction) -> SectionQuality:
    """The cached covariance analysis per section of chainage: each update epoch takes the chainage
    of the reconstructed centreline at its time (the reference rail's where the centreline has
    none); sections of TQI_SECTION_M start at the first sleeper, like the ``[track_quality]`` ones."""
    epochs = load_dataclass(quality_cache_file(trajectory_file), EpochQuality)
    lowest = [np.inf]

    def known_chainage():  # the epochs with a chainage, by parts
        for part in recon.epochs.chunks():
            chainage = np.where(np.isfinite(part.centre_m), part.centre_m, part.reference_m)
            known = np.isfinite(chainage)
            if known.any():
                lowest[0] = min(lowest[0], float(np.min(chainage[known])))
            yield part.time_s[known], chainage[known]

    try:  # np.interp(update times, epoch times, chainage) of the epochs with one
        at_epochs = chunked_interp(epochs.time_s, known_chainage())
    except ValueError:  # none has one
        raise InputError(trajectory_file, None, "no epoch of the reconstructed track has a chainage") from None
    table = recon.table
    start = float(table.station_m[0]) if len(table) else lowest[0]
    return sections_along(epochs, at_epochs, start, TQI_SECTION_M)


# --------------------------------------------------------------------------- result files

def _line_fit_section(recon: TrackReconstruction) -> dict:
    """summary.toml's ``[track.line_fit]``: the fitted elements and residuals, or why there is no fit."""
    if recon.fitted is None:
        return {"fitted": False, "error": recon.line_fit_error or "line fitting off"}
    fit = recon.fitted
    kinds: dict[str, int] = {}
    for row in element_table(fit.alignment.horizontal):
        kinds[row.kind] = kinds.get(row.kind, 0) + 1
    return {"fitted": True, "elements": kinds, "pvis": len(fit.vertical.profile.pvis),
            "plan_rms_mm": round(1e3 * fit.horizontal.rms_m, 3), "profile_rms_mm": round(1e3 * fit.vertical.rms_m, 3),
            "windows": 0 if recon.reference is None else len(recon.reference.windows)}


def outside_notices(project: Project, folder: Path, manifest: SurveyManifest) -> list[Notice]:
    """A notice for each data file of the survey that lies outside the project and the survey folder
    (``/etc/passwd`` or ``../../other/imu.txt`` in a survey.toml someone handed over): read, and named."""
    inside = (project.folder.resolve(), folder.resolve())
    notices = []
    for role, entry in manifest.files.items():
        path = (folder / entry.path).resolve()
        if not any(path.is_relative_to(place) for place in inside):
            notices.append(Notice("survey", "files.{role}: {entry} lies outside the project and the survey folder "
                                  "({path}): check that it is the file meant", file=str(path),
                                  fields={"role": role, "entry": str(entry.path), "path": str(path)}))
    return notices


def _line_fit_notices(line: FittedLine | None, table: SleeperTable) -> list[Notice]:
    """A warning where a line-type fit was asked for (no design) and failed: over which stations the
    results hold no fitted alignment and no deviations, and why."""
    if line is None or line.section().get("fitted", True):
        return []
    stations = table.station_m[np.isfinite(table.station_m)]
    where = (Phrase("stations {from_m:.1f} to {to_m:.1f} m", {"from_m": stations.min(), "to_m": stations.max()})
             if stations.size else Phrase("the whole survey"))
    return [Notice("track", "no line-type fit over {where} (no fitted alignment, no deviations \"measured - best\"): "
                            "{error}", station_m=float(stations.min()) if stations.size else None,
                   fields={"where": where, "error": line.section()["error"]})]


def _notices(fusion_info: dict, height_warnings: list[Phrase], ppk_warnings: list[Phrase]) -> list[Notice]:
    """Every stage's notices, in pipeline order (:mod:`insrail.notices`)."""
    notices = [Notice("gnss", w) for w in ppk_warnings]
    notices += [Notice.from_dict(table) for table in fusion_info.get("notices", [])]
    notices += [Notice("heights", w) for w in height_warnings]
    return notices


def _summary(project, run, name, manifest, fusion_info, track_cached, height_fit, height_warnings, table, assessment,
             adjustment, after_adjustment, elapsed) -> dict:
    counts: dict[str, int] = {}
    for e in assessment.exceedances:
        counts[e.check] = counts.get(e.check, 0) + 1
    summary = {
        "survey": {"name": name, "folder": project.survey(name).folder, "imu_epochs": fusion_info["imu_epochs"],
                   **({"gps_week": manifest.gps_week} if manifest.gps_week is not None else {}),
                   "processing_time_s": round(elapsed, 2)},
        "fusion": {"prism_fixes": 0, **{k: v for k, v in fusion_info.items() if k != "notices"}},
        "heights": ({"model": height_fit.model_name, "internal_rms_mm": 1e3 * height_fit.internal_rms_m,
                     "loo_rms_mm": 1e3 * height_fit.loo_rms_m if np.isfinite(height_fit.loo_rms_m) else -1.0,
                     "warnings": [str(w) for w in height_warnings]}
                    if height_fit is not None else {"model": "none (ellipsoidal heights)"}),
        "track": {"design": run.design or "", "from_cache": track_cached, "sleepers": len(table), "valid_sleepers": int(table.valid.sum()),
                  "station_from_m": float(table.station_m[0]) if len(table) else 0.0,
                  "station_to_m": float(table.station_m[-1]) if len(table) else 0.0},
        "assessment": {"tolerance_profile": assessment.profile, "exceedances": len(assessment.exceedances),
                       "by_check": counts},
        "adjustment": (withheld_adjustment_section(adjustment) if manifest.relative else
                       adjustment_section(adjustment, assessment, after_adjustment, run.adjustment, run.fastener)),
        "files": {"trajectory": TRAJECTORY_FILE, "sleepers": SLEEPERS_FILE, "exceedances": EXCEEDANCES_FILE},
        SETTINGS_SECTION: run.record(),
    }
    return summary
