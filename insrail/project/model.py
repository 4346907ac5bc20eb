"""The project file: ``project.toml`` in a project folder, and its validated model.

Layout (all tables but [geodesy.crs] and [[surveys]] optional; paths relative to the project
folder; a tolerance profile, fastener type or IMU profile is a shipped name or a ``.toml`` path)::

    [project]            name, description
    [geodesy.crs]        EngineeringCRS settings (insrail.geodesy.crs)
    [geodesy.height]     benchmarks = "benchmarks.txt" (GNSS levelling, h and H), model = "auto" |
                         "constant" | "plane" | "quadratic", geoid_grid = path or "egm96" (remove-restore).
                         Without benchmarks heights stay ellipsoidal (H = h).
    [geodesy.control_points.<name>]  lat_deg, lon_deg, ellipsoidal_height_m, or east_m, north_m,
                         normal_height_m (insrail.project.control_points): e.g. the GNSS base's mark
    [geodesy.local]      model = "4-parameter" | "7-parameter", [geodesy.local.points.<name>] common points in
                         the engineering CRS and the railway's local grid (insrail.project.local_control): every
                         output coordinate (and the design) in the local grid
    [trolley]            as in survey.toml; when absent each survey's own [trolley] is used, when given it
                         replaces theirs (which may then be left out); each lever arm is required only
                         by a survey whose data use it (checked per survey before its fusion)
    [processing]         imu_profile (default: each survey's), a subset of FusionOptions
    [track]              design (alignment CSV or LandXML), start_station_m (needed without a design:
                         the station where each survey starts), stationing_direction (without a
                         design: "travel", the default, stations grow in each survey's direction of
                         travel; or a grid azimuth in degrees towards which they grow, so that runs
                         in both directions share one stationing), events (an event file in
                         chainage for every survey: turnouts, level crossings, ..., docs/formats.md),
                         first_sleeper_number, sleeper_anchor = {number = 1234, station_m = 1500.0}
                         (or time_s: the field number of the sleeper there; replaces first_sleeper_number),
                         tolerance_profile, fastener, line_speed_kmh = 250 or a
                         table of ranges [{from_m = 0, to_m = 4200, kmh = 250}, ...] (for the cant deficiency)
    [adjustment]         how the fastener adjustment amounts are computed (:class:`AdjustmentSettings`):
                         strategy = "least_movement" (default) | "guiding_rail_first", threshold_mm = 2
                         (the action threshold: each amount 0 or at least this; default one fastener step)
    [redesign]           the tamping re-design (:class:`RedesignTable`, docs/tamping.md): lift_only = true,
                         min_lift_mm = 0, max_lift_mm = 50, max_slew_mm = 30, margin_mm = 0.5, fix_events = true
                         (turnouts, level crossings and bridges of the events are fixed), and
                         [[redesign.fixed]] from_m, to_m, tolerance_mm (optional): stretches not to move
    [[surveys]]          name, folder (holding a survey.toml)
    [[sections]]         name, surveys = ["run1", "run2"], from_m, to_m (optional), overlap = "best" | "mean":
                         a line section joined from several runs (insrail.project.section)
    [report]             what the reports' first page states and how they print (:class:`ReportSettings`):
                         client, line_section, track_name, operator, checked_by, approved_by, trolley,
                         trolley_calibrated, imu, imu_calibrated (dates: 2026-03-14), paper = "A3" | "A4" (the
                         workbook's and the PDF's pages, landscape; the crews' adjustment sheet is A4 portrait),
                         language = "en" | "zh-CN" (the workbook's, the PDF's and the exports' texts)

Loading checks everything and raises :class:`ProjectError` listing every problem with its key
path (``surveys[2].folder: not found: runs/x``). Nothing in the file is executed or unpickled.
Saving writes the whole file atomically (a crash leaves the previous file intact), keeping the
comments and layout of the file the user wrote.
"""

from __future__ import annotations

import datetime
import re
import tomllib
from collections.abc import MutableMapping
from dataclasses import asdict, dataclass, field, fields, replace
from pathlib import Path
from typing import Any

import numpy as np
import tomli_w

from insrail.geodesy.crs import EngineeringCRS
from insrail.geodesy.errors import GeoidGridError, SettingsError
from insrail.geodesy.geoid import GeoidGrid
from insrail.geodesy.height_anomaly import HeightAnomalySettings
from insrail.io.atomic import atomic_write
from insrail.io.errors import InputError, ProblemsError
from insrail.io.events import read_events
from insrail.io.survey import MANIFEST_NAME, SurveyManifest, TrolleyGeometry, parse_trolley, read_manifest
from insrail.io.tomlfile import read_toml
from insrail.names import DEFAULT_LANGUAGE, LANGUAGES
from insrail.notices import Phrase, one_after_another
from insrail.nav.fusion_options import FusionOptions
from insrail.nav.imu_profile import load_imu_profile
from insrail.project.control_points import ControlPoint, parse_control_points
from insrail.project.local_control import LocalControl, parse_local_control
from insrail.track.adjustment import (
    DEFAULT_FASTENER,
    DEFAULT_STRATEGY,
    STRATEGIES,
    load_fastener_type,
)
from insrail.track.chainage import WITH_TRAVEL
from insrail.track.parameters import LineSpeed
from insrail.track.sleepers import SleeperAnchor
from insrail.track.tolerance import DEFAULT_PROFILE, load_tolerance_profile

PROJECT_FILE = "project.toml"
#: Surface models only: a spline in chainage needs benchmark chainages the benchmarks file lacks.
HEIGHT_MODELS = ("auto", "constant", "plane", "quadratic")
#: The FusionOptions a project may set (the rest keep their defaults).
FUSION_FLAGS = ("use_gnss_velocity", "use_odometer", "use_nhc", "use_zupt", "smoother")
FUSION_NUMBERS = ("update_rate_hz", "gnss_sigma_scale", "gnss_sigma_floor_m", "gnss_correlated_tau_s",
                  "odometer_sigma_mps", "nhc_sigma_mps", "zupt_sigma_mps", "min_static_s")
_TOP_LEVEL = ("project", "geodesy", "trolley", "processing", "track", "adjustment", "redesign", "surveys", "sections",
              "report")
#: How a line section joins its runs where they overlap (insrail.project.section).
OVERLAP_RULES = ("best", "mean")
#: Paper sizes of the workbook's printout (landscape).
PAPER_SIZES = ("A3", "A4")
_SURVEY_NAME = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]*$")  # used as a results folder name


class ProjectError(ProblemsError):
    """``project.toml`` has problems; ``problems`` lists every one, each starting with its key path."""


@dataclass(frozen=True)
class SurveyEntry:
    name: str
    folder: str  # relative to the project folder


@dataclass(frozen=True)
class SectionEntry:
    """A line section: one result joined from several surveys on the stationing (insrail.project.section)."""

    name: str
    surveys: tuple[str, ...]
    from_m: float | None = None  # the section's station range (None: what the surveys cover)
    to_m: float | None = None
    overlap: str = "best"  # "best": the run with the better predicted accuracy; "mean": weighted mean

    def to_settings(self) -> dict[str, Any]:
        entry: dict[str, Any] = {"name": self.name, "surveys": list(self.surveys), "overlap": self.overlap}
        entry |= {k: getattr(self, k) for k in ("from_m", "to_m") if getattr(self, k) is not None}
        return entry


@dataclass(frozen=True)
class HeightSettings:
    """How normal heights are obtained: ζ fitted on ``benchmarks`` (None: H = h)."""

    benchmarks: str | None = None
    anomaly: HeightAnomalySettings = field(default_factory=HeightAnomalySettings)


@dataclass(frozen=True)
class ReportSettings:
    """The ``[report]`` table: who and what the reports name on their first page, and the paper.

    Texts are as the client writes them ("" when not given: the report leaves a blank to fill in);
    the instruments default to the IMU profile's name when ``imu`` is empty. Dates are calendar dates.
    """

    client: str = ""
    line_section: str = ""  # e.g. "Wuhan - Xianning, K12 - K18"
    track_name: str = ""  # the track surveyed as the railway names it, e.g. "down line"
    operator: str = ""
    checked_by: str = ""
    approved_by: str = ""
    trolley: str = ""  # make, model and serial number
    trolley_calibrated: datetime.date | None = None
    imu: str = ""
    imu_calibrated: datetime.date | None = None
    paper: str = "A3"  # the workbook's sheets, landscape
    language: str = DEFAULT_LANGUAGE  # of the workbook, the PDF and the exports (insrail.names.LANGUAGES)

    def to_settings(self) -> dict[str, Any]:
        """The non-default entries (an untouched project writes no [report] table)."""
        default = ReportSettings()
        return {f.name: getattr(self, f.name) for f in fields(self) if getattr(self, f.name) != getattr(default, f.name)}


_REPORT_DATES = ("trolley_calibrated", "imu_calibrated")


@dataclass(frozen=True)
class AdjustmentSettings:
    """The ``[adjustment]`` table: how the optimisation shares the movement between the rails
    (:data:`insrail.track.adjustment.STRATEGIES`) and the action threshold [mm]: each amount is 0
    or at least this much where the checks allow it (None: one fastener step, i.e. every amount)."""

    strategy: str = DEFAULT_STRATEGY
    threshold_mm: float | None = None

    @property
    def threshold_m(self) -> float | None:
        return None if self.threshold_mm is None else 1e-3 * self.threshold_mm

    def to_settings(self) -> dict[str, Any]:
        """The non-default entries (an untouched project writes no [adjustment] table)."""
        default = AdjustmentSettings()
        return {f.name: getattr(self, f.name) for f in fields(self) if getattr(self, f.name) != getattr(default, f.name)}
@dataclass(frozen=True)
class FixedTable:
    """One ``[[redesign.fixed]]`` entry as written: a stretch of chainage the tamping must not move."""

    from_m: float
    to_m: float
    tolerance_mm: float = 0.0


@dataclass(frozen=True)
class RedesignTable:
    """The ``[redesign]`` table as written (millimetres); :func:`insrail.project.redesign.resolve_settings`
    resolves it with the survey's events into :class:`insrail.track.redesign.RedesignSettings`."""

    lift_only: bool = True
    min_lift_mm: float = 0.0
    max_lift_mm: float = 50.0
    max_slew_mm: float = 30.0
    margin_mm: float = 0.5
    fix_events: bool = True
    fixed: tuple[FixedTable, ...] = ()

    def to_settings(self) -> dict[str, Any]:
        """The non-default entries (an untouched project writes no [redesign] table)."""
        default = RedesignTable()
        out = {f.name: getattr(self, f.name) for f in fields(self)
               if f.name != "fixed" and getattr(self, f.name) != getattr(default, f.name)}
        if self.fixed:
            out["fixed"] = [{k: v for k, v in asdict(f).items() if k != "tolerance_mm" or v} for f in self.fixed]
        return out


_REPORT_TEXTS = tuple(f.name for f in fields(ReportSettings) if f.name not in _REPORT_DATES + ("paper", "language"))


@dataclass(frozen=True)
class Project:
    folder: Path
    name: str
    crs: EngineeringCRS
    height: HeightSettings
    surveys: tuple[SurveyEntry, ...]
    description: str = ""
    trolley_settings: dict | None = None  # the [trolley] table as written; None: each survey's own
    imu_profile: str | None = None  # None: each survey's own
    fusion: FusionOptions = field(default_factory=FusionOptions)
    design: str | None = None
    start_station_m: float | None = None
    stationing_direction: str | float = WITH_TRAVEL
    events: str | None = None
    first_sleeper_number: int = 1
    sleeper_anchor: SleeperAnchor | None = None
    tolerance_profile: str = DEFAULT_PROFILE
    fastener: str = DEFAULT_FASTENER
    control_points: tuple[ControlPoint, ...] = ()
    report: ReportSettings = field(default_factory=ReportSettings)
    adjustment: AdjustmentSettings = field(default_factory=AdjustmentSettings)
    redesign: RedesignTable = field(default_factory=RedesignTable)
    local_control: LocalControl | None = None
    sections: tuple[SectionEntry, ...] = ()
    line_speeds: tuple[LineSpeed, ...] = ()  # one range from -inf to inf: a single line speed

    @property
    def path(self) -> Path:
        return self.folder / PROJECT_FILE

    def resolve(self, relative: str) -> Path:
        return self.folder / relative

    def resource(self, name_or_path: str) -> str | Path:
        """A shipped resource name as is, a ``.toml`` path relative to the project resolved."""
        return self.resolve(name_or_path) if name_or_path.endswith(".toml") else name_or_path

    def survey(self, name: str) -> SurveyEntry:
        for entry in self.surveys:
            if entry.name == name:
                return entry
        raise KeyError(f"{self.path}: no survey named {name!r} (surveys: {', '.join(s.name for s in self.surveys)})")

    def section(self, name: str) -> SectionEntry:
        for entry in self.sections:
            if entry.name == name:
                return entry
        raise KeyError(f"{self.path}: no section named {name!r} (sections: "
                       f"{', '.join(s.name for s in self.sections) or 'none'})")

    def control_point(self, name: str) -> ControlPoint | None:
        return next((p for p in self.control_points if p.name == name), None)

    def manifest(self, survey_name: str) -> SurveyManifest:
        """The survey.toml of one of the project's surveys, read as the project uses it (with a project
        ``[trolley]`` the survey's own may be left out)."""
        return read_manifest(self.resolve(self.survey(survey_name).folder),
                             trolley_from_project=self.trolley_settings is not None)

    def trolley(self, roles: set[str] | None = None) -> TrolleyGeometry | None:
        """The project's trolley geometry, or None when each survey brings its own.

        ``roles``: the file roles of the survey it is used for; a lever arm that survey's data
        need in the fusion but the project's ``[trolley]`` leaves out is then an error (``InputError``
        naming project.toml), never a missing offset reaching the fusion (those of the track are
        checked before the fusion too: ``plausibility.check_trolley``). Without roles no lever arm
        is required."""
        if self.trolley_settings is None:
            return None
        problems: list[str] = []
        trolley = parse_trolley(self.trolley_settings, set() if roles is None else roles, problems)
        if roles is not None and problems:
            raise InputError(self.path, None, one_after_another(problems))
        return trolley

    def to_settings(self) -> dict[str, Any]:
        """The TOML document as plain data; ``load_project`` of it gives an equal project."""
        height = {**self.height.anomaly.to_settings()}
        if self.height.benchmarks is not None:
            height["benchmarks"] = self.height.benchmarks
        processing: dict[str, Any] = {name: getattr(self.fusion, name) for name in FUSION_FLAGS + FUSION_NUMBERS}
        if self.imu_profile is not None:
            processing["imu_profile"] = self.imu_profile
        track: dict[str, Any] = {"first_sleeper_number": self.first_sleeper_number,
                                 "tolerance_profile": self.tolerance_profile, "fastener": self.fastener}
        if self.design is not None:
            track["design"] = self.design
        if self.start_station_m is not None:
            track["start_station_m"] = self.start_station_m
        if self.stationing_direction != WITH_TRAVEL:
            track["stationing_direction"] = self.stationing_direction
        if len(self.line_speeds) == 1 and not np.isfinite([self.line_speeds[0].from_m, self.line_speeds[0].to_m]).any():
            track["line_speed_kmh"] = self.line_speeds[0].kmh
        elif self.line_speeds:
            track["line_speed_kmh"] = [{"from_m": r.from_m, "to_m": r.to_m, "kmh": r.kmh} for r in self.line_speeds]
        if self.events is not None:
            track["events"] = self.events
        if self.sleeper_anchor is not None:
            track["sleeper_anchor"] = {k: v for k, v in asdict(self.sleeper_anchor).items() if v is not None}
        document: dict[str, Any] = {
            "project": {"name": self.name, "description": self.description},
            "geodesy": {"crs": self.crs.to_settings(), "height": height},
        }
        if self.control_points:
            document["geodesy"]["control_points"] = {p.name: p.to_settings() for p in self.control_points}
        if self.local_control is not None:
            document["geodesy"]["local"] = self.local_control.to_settings()
        if self.trolley_settings is not None:
            document["trolley"] = self.trolley_settings
        document["processing"] = processing
        document["track"] = track
        if self.adjustment.to_settings():
            document["adjustment"] = self.adjustment.to_settings()
        if self.redesign.to_settings():
            document["redesign"] = self.redesign.to_settings()
        document["surveys"] = [{"name": s.name, "folder": s.folder} for s in self.surveys]
        if self.sections:
            document["sections"] = [s.to_settings() for s in self.sections]
        if self.report.to_settings():
            document["report"] = self.report.to_settings()
        return document


def save_project(project: Project, path: str | Path | None = None) -> Path:
    """Write ``project.toml`` atomically (to ``path`` or the project's own file).

    The file the user wrote keeps its comments, order and layout: the settings are merged into it
    (:func:`_merge`), only the values that changed rewritten. Should the merged text not read back as
    the settings (a layout tomlkit cannot edit), the plain document is written instead."""
    import tomlkit  # here only: some 20 ms of the start of every command that reads a project
    import tomlkit.exceptions

    path = Path(path) if path is not None else project.path
    settings = tomllib.loads(tomli_w.dumps(project.to_settings()))  # tuples as lists: as they read back
    try:
        document = tomlkit.parse(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, tomlkit.exceptions.TOMLKitError):  # new, or not ours to edit
        document = tomlkit.document()
    _merge(document, settings)
    text = tomlkit.dumps(document)
    if tomllib.loads(text) != settings:
        text = tomli_w.dumps(settings)
    with atomic_write(path) as handle:
        handle.write(text)
    return path


def _merge(document: MutableMapping, settings: dict) -> None:
    """Make the tomlkit ``document`` hold ``settings``, leaving equal values (and their comments) alone."""
    for key in [key for key in document if key not in settings]:
        del document[key]
    for key, value in settings.items():
        kept = document.get(key)
        if isinstance(value, dict) and isinstance(kept, MutableMapping):
            _merge(kept, value)
        elif key not in document or getattr(kept, "unwrap", lambda: kept)() != value:  # a bool comes plain
            document[key] = value


def load_project(path: str | Path) -> Project:
    """Read and validate a project (``project.toml`` or the folder holding it)."""
    path = Path(path)
    if path.is_dir():
        path = path / PROJECT_FILE
    if not path.is_file():
        raise InputError(path, None, "project file not found")
    document = read_toml(path)
    return project_from_settings(document, path.parent, path)


def project_from_settings(document: dict, folder: Path, path: Path | None = None) -> Project:
    """Validate a project document (paths relative to ``folder``); every problem is reported at once."""
    reader = _Reader(Path(folder))
    for key in document:
        if key not in _TOP_LEVEL:
            reader.add(key, Phrase("unknown table (expected {tables})", {"tables": list(_TOP_LEVEL)}))
    meta = reader.table(document, "project")
    reader.known(meta, "project", ("name", "description"))
    name = reader.text(meta, "project.name", Path(folder).resolve().name)
    description = reader.text(meta, "project.description", "")

    geodesy = reader.table(document, "geodesy")
    reader.known(geodesy, "geodesy", ("crs", "height", "control_points", "local"))
    crs = None
    if "crs" not in geodesy:
        reader.add("geodesy.crs", Phrase("missing table (the engineering coordinate system)"))
    else:
        try:
            crs = EngineeringCRS.from_settings(geodesy["crs"], "geodesy.crs")
        except SettingsError as err:
            reader.problems.extend(err.problems)
    height = _height(reader, reader.table(geodesy, "height", "geodesy.height"))
    control_points = parse_control_points(geodesy.get("control_points", {}), "geodesy.control_points", reader.problems)
    local_control = parse_local_control(geodesy.get("local"), "geodesy.local", reader.problems)

    trolley_settings = document.get("trolley")
    if trolley_settings is not None:
        trolley_problems: list[str] = []
        parse_trolley(trolley_settings, set(), trolley_problems)  # which lever arms a survey needs: per survey
        reader.problems.extend(trolley_problems)

    processing = reader.table(document, "processing")
    reader.known(processing, "processing", ("imu_profile",) + FUSION_FLAGS + FUSION_NUMBERS)
    imu_profile = processing.get("imu_profile")
    if imu_profile is not None:
        reader.loadable(processing, "processing.imu_profile", load_imu_profile, resolve=True)
    options = {}
    for key in FUSION_FLAGS:
        if key in processing:
            if isinstance(processing[key], bool):
                options[key] = processing[key]
            else:
                reader.add(f"processing.{key}", Phrase("expected true or false, found {processing!r}", {"processing": processing[key]}))
    for key in FUSION_NUMBERS:
        if key in processing:
            value = reader.number(processing, f"processing.{key}", positive=True)
            if value is not None:
                options[key] = value

    track = reader.table(document, "track")
    reader.known(track, "track", ("design", "start_station_m", "stationing_direction", "events",
                                  "first_sleeper_number", "sleeper_anchor", "tolerance_profile", "fastener", "line_speed_kmh"))
    line_speeds = _line_speeds(reader, track.get("line_speed_kmh"))
    events = reader.file(track, "track.events")
    if events is not None:
        _check_events(reader, events)
    anchor = _sleeper_anchor(reader, track.get("sleeper_anchor"))
    design = reader.file(track, "track.design")
    if design is not None:
        _check_design(reader, design)
    start_station = reader.number(track, "track.start_station_m") if "start_station_m" in track else None
    if design is None and "design" not in track and "start_station_m" not in track:
        reader.add("track.start_station_m", Phrase("missing: without a design alignment the start station is needed"))
    stationing = track.get("stationing_direction", WITH_TRAVEL)
    if stationing != WITH_TRAVEL:
        if "stationing_direction" in track and reader.number(track, "track.stationing_direction") is None:
            stationing = WITH_TRAVEL
            reader.problems[-1] = Phrase('{problem} or "{with_travel}"', {"problem": reader.problems[-1],
                                                                        "with_travel": WITH_TRAVEL})
        else:
            stationing = float(stationing)
    first_number = track.get("first_sleeper_number", 1)
    if not isinstance(first_number, int) or isinstance(first_number, bool):
        reader.add("track.first_sleeper_number", Phrase("expected a whole number, found {first_number!r}", {"first_number": first_number}))
    tolerance = reader.loadable(track, "track.tolerance_profile", load_tolerance_profile, DEFAULT_PROFILE)
    fastener = reader.loadable(track, "track.fastener", load_fastener_type, DEFAULT_FASTENER)

    surveys = _surveys(reader, document.get("surveys"))
    sections = _sections(reader, document.get("sections", []), surveys)
    report = _report(reader, reader.table(document, "report"))
    adjustment = _adjustment(reader, reader.table(document, "adjustment"))
    redesign = _redesign(reader, reader.table(document, "redesign"))
    reader.raise_if_any(path or Path(folder) / PROJECT_FILE)
    return Project(
        folder=Path(folder), name=name, description=description, crs=crs, height=height, surveys=surveys,
        trolley_settings=trolley_settings, imu_profile=imu_profile, fusion=FusionOptions(**options),
        design=design, start_station_m=start_station, stationing_direction=stationing, events=events,
        sleeper_anchor=anchor,
        first_sleeper_number=first_number,
        tolerance_profile=tolerance, fastener=fastener, control_points=control_points, report=report,
        line_speeds=line_speeds, local_control=local_control, sections=sections, adjustment=adjustment,
        redesign=redesign,
    )


def _sections(reader: _Reader, table, surveys: tuple[SurveyEntry, ...]) -> tuple[SectionEntry, ...]:
    """``[[sections]]``: name, surveys (of this project), optional from_m/to_m, overlap = "best" | "mean"."""
    if not isinstance(table, list):
        reader.add("sections", Phrase("expected [[sections]] entries with name and surveys"))
        return ()
    known = {s.name for s in surveys}
    entries, seen = [], set()
    for i, entry in enumerate(table):
        key = f"sections[{i}]"
        if not isinstance(entry, dict):
            reader.add(key, Phrase("expected a table with name and surveys"))
            continue
        reader.known(entry, key, ("name", "surveys", "from_m", "to_m", "overlap"))
        name, runs = entry.get("name"), entry.get("surveys")
        ok = True
        if not isinstance(name, str) or not _SURVEY_NAME.match(name):
            reader.add(f"{key}.name", Phrase("expected a name of letters, digits, '.', '_' or '-', found {name!r}", {"name": name}))
            ok = False
        elif name in known or name in seen:
            reader.add(f"{key}.name", Phrase("{name!r} is already the name of a {kind} "
                                      "(both name a results folder)", {"name": name, "kind": 'survey' if name in known else 'section'}))
            ok = False
        seen.add(name)
        if not isinstance(runs, list) or not runs or not all(isinstance(r, str) for r in runs):
            reader.add(f"{key}.surveys", Phrase("expected a list of the project's survey names"))
            ok = False
        else:
            for run in runs:
                if run not in known:
                    reader.add(f"{key}.surveys", Phrase("no survey named {run!r} (surveys: {known})", {"run": run, "known": sorted(known)}))
                    ok = False
            if len(set(runs)) != len(runs):
                reader.add(f"{key}.surveys", Phrase("a survey is named twice"))
                ok = False
        bounds = {k: reader.number(entry, f"{key}.{k}") for k in ("from_m", "to_m") if k in entry}
        if None in bounds.values():
            ok = False
        elif len(bounds) == 2 and not bounds["from_m"] < bounds["to_m"]:
            reader.add(key, Phrase("from_m ({bounds}) must be below to_m ({bounds2})", {"bounds": bounds['from_m'], "bounds2": bounds['to_m']}))
            ok = False
        overlap = entry.get("overlap", "best")
        if overlap not in OVERLAP_RULES:
            reader.add(f"{key}.overlap", Phrase("expected one of {overlap_rules}, found {overlap!r}", {"overlap_rules": list(OVERLAP_RULES), "overlap": overlap}))
            ok = False
        if ok:
            entries.append(SectionEntry(name, tuple(runs), bounds.get("from_m"), bounds.get("to_m"), overlap))
    return tuple(entries)


def _adjustment(reader: _Reader, table: dict) -> AdjustmentSettings:
    reader.known(table, "adjustment", tuple(f.name for f in fields(AdjustmentSettings)))
    strategy = table.get("strategy", DEFAULT_STRATEGY)
    if strategy not in STRATEGIES:
        reader.add("adjustment.strategy", Phrase("expected {strategies}, found {strategy!r}", {"strategies": ' or '.join(repr(s) for s in STRATEGIES), "strategy": strategy}))
        strategy = DEFAULT_STRATEGY
    threshold = reader.number(table, "adjustment.threshold_mm", positive=True) if "threshold_mm" in table else None
    if threshold is not None and threshold > MAX_THRESHOLD_MM:
        reader.add("adjustment.threshold_mm", Phrase("expected at most {max_threshold_mm:g} mm, found {threshold:g}", {"max_threshold_mm": MAX_THRESHOLD_MM, "threshold": threshold}))
        threshold = None
    return AdjustmentSettings(strategy=strategy, threshold_mm=threshold)


def _redesign(reader: _Reader, table: dict) -> RedesignTable:
    reader.known(table, "redesign", tuple(f.name for f in fields(RedesignTable)))
    values: dict[str, Any] = {}
    for key in ("lift_only", "fix_events"):
        if key in table:
            if isinstance(table[key], bool):
                values[key] = table[key]
            else:
                reader.add(f"redesign.{key}", Phrase("expected true or false, found {table!r}", {"table": table[key]}))
    for key in ("min_lift_mm", "max_lift_mm", "max_slew_mm", "margin_mm"):
        if key in table:
            value = reader.number(table, f"redesign.{key}")
            if value is not None and value < 0:
                reader.add(f"redesign.{key}", Phrase("expected a distance of 0 mm or more, found {value:g}", {"value": value}))
            elif value is not None:
                values[key] = value
    settings = RedesignTable(**values)
    if settings.min_lift_mm > settings.max_lift_mm:
        reader.add("redesign.min_lift_mm", Phrase("{min_lift_mm:g} mm is more than max_lift_mm "
                                           "({max_lift_mm:g} mm)", {"min_lift_mm": settings.min_lift_mm, "max_lift_mm": settings.max_lift_mm}))
    entries = table.get("fixed", [])
    if not isinstance(entries, list):
        reader.add("redesign.fixed", Phrase("expected [[redesign.fixed]] entries with from_m and to_m"))
        entries = []
    fixed = []
    for i, entry in enumerate(entries):
        key = f"redesign.fixed[{i}]"
        if not isinstance(entry, dict):
            reader.add(key, Phrase("expected a table with from_m, to_m and optionally tolerance_mm"))
            continue
        reader.known(entry, key, ("from_m", "to_m", "tolerance_mm"))
        missing = [k for k in ("from_m", "to_m") if k not in entry]
        if missing:
            reader.add(key, Phrase("missing {keys}", {"keys": ' and '.join(missing)}))
            continue
        start, end = reader.number(entry, f"{key}.from_m"), reader.number(entry, f"{key}.to_m")
        tolerance = reader.number(entry, f"{key}.tolerance_mm") if "tolerance_mm" in entry else 0.0
        if None in (start, end, tolerance):
            continue
        if not start < end:
            reader.add(key, Phrase("from_m ({start:g}) must be below to_m ({end:g})", {"start": start, "end": end}))
        elif tolerance < 0:
            reader.add(f"{key}.tolerance_mm", Phrase("expected 0 mm or more, found {tolerance:g}", {"tolerance": tolerance}))
        else:
            fixed.append(FixedTable(start, end, tolerance))
    return replace(settings, fixed=tuple(fixed))


#: The largest action threshold [mm] the settings accept (beyond it hardly any amount could be listed).
MAX_THRESHOLD_MM = 10.0


def _report(reader: _Reader, table: dict) -> ReportSettings:
    reader.known(table, "report", tuple(f.name for f in fields(ReportSettings)))
    values: dict[str, Any] = {key: reader.text(table, f"report.{key}", "") for key in _REPORT_TEXTS}
    for key in _REPORT_DATES:
        value = table.get(key)
        if isinstance(value, str):
            try:
                value = datetime.date.fromisoformat(value)
            except ValueError:
                reader.add(f"report.{key}", Phrase("expected a date like 2026-03-14, found {value!r}", {"value": value}))
                value = None
        elif isinstance(value, datetime.datetime):
            value = value.date()
        elif value is not None and not isinstance(value, datetime.date):
            reader.add(f"report.{key}", Phrase("expected a date like 2026-03-14, found {value!r}", {"value": value}))
            value = None
        values[key] = value
    paper = table.get("paper", "A3")
    if paper not in PAPER_SIZES:
        reader.add("report.paper", Phrase("expected one of {paper_sizes}, found {paper!r}", {"paper_sizes": list(PAPER_SIZES), "paper": paper}))
        paper = "A3"
    language = table.get("language", DEFAULT_LANGUAGE)
    if language not in LANGUAGES:
        reader.add("report.language", Phrase("expected one of {languages}, found {language!r}", {"languages": list(map(repr, LANGUAGES)), "language": language}))
        language = DEFAULT_LANGUAGE
    return ReportSettings(**values, paper=paper, language=language)


def _line_speeds(reader: _Reader, value) -> tuple[LineSpeed, ...]:
    """``[track] line_speed_kmh``: a number (everywhere) or a list of {from_m, to_m, kmh} ranges."""
    key = "track.line_speed_kmh"
    if value is None:
        return ()
    if not isinstance(value, list):
        speed = reader.number({"line_speed_kmh": value}, key, positive=True)
        return () if speed is None else (LineSpeed(-np.inf, np.inf, speed),)
    ranges = []
    for i, entry in enumerate(value):
        where = f"{key}[{i}]"
        if not isinstance(entry, dict) or set(entry) != {"from_m", "to_m", "kmh"}:
            reader.add(where, Phrase("expected a table {{from_m = ..., to_m = ..., kmh = ...}}, found {entry!r}", {"entry": entry}))
            continue
        start, end = reader.number(entry, f"{where}.from_m"), reader.number(entry, f"{where}.to_m")
        speed = reader.number(entry, f"{where}.kmh", positive=True)
        if None in (start, end, speed):
            continue
        if not start < end:
            reader.add(where, Phrase("from_m ({start}) must be below to_m ({end})", {"start": start, "end": end}))
            continue
        ranges.append(LineSpeed(start, end, speed))
    return tuple(ranges)


def _height(reader: _Reader, table: dict) -> HeightSettings:
    reader.known(table, "geodesy.height", ("benchmarks", "model", "geoid_grid"))
    benchmarks = reader.file(table, "geodesy.height.benchmarks")
    model = table.get("model", "auto")
    if model not in HEIGHT_MODELS:
        reader.add("geodesy.height.model", Phrase("expected one of {height_models}, found {model!r}", {"height_models": list(HEIGHT_MODELS), "model": model}))
        model = "auto"
    anomaly = HeightAnomalySettings()
    try:
        anomaly = HeightAnomalySettings.from_settings(
            {k: v for k, v in table.items() if k in ("model", "geoid_grid")} | {"model": model}, "geodesy.height")
    except SettingsError as err:
        reader.problems.extend(err.problems)
    if anomaly.geoid_grid not in (None, "egm96") and reader.file(table, "geodesy.height.geoid_grid") is not None:
        try:  # a grid PROJ cannot read is named here, not when the heights are fitted
            GeoidGrid(reader.folder / anomaly.geoid_grid)
        except GeoidGridError as err:
            reader.add("geodesy.height.geoid_grid", str(err))
    return HeightSettings(benchmarks, anomaly)


def _check_design(reader: _Reader, design: str) -> None:
    from insrail.project.design_file import read_design

    try:
        read_design(reader.folder / design)
    except (InputError, ValueError) as err:
        reader.add("track.design", str(err))


def _sleeper_anchor(reader: _Reader, table) -> SleeperAnchor | None:
    """``[track] sleeper_anchor = {number = 1234, station_m = 1500.0}`` (or ``time_s``)."""
    if table is None:
        return None
    key = "track.sleeper_anchor"
    if not isinstance(table, dict):
        reader.add(key, Phrase("expected a table {{number = ..., station_m = ...}} or {{number = ..., time_s = ...}}, found {table!r}", {"table": table}))
        return None
    reader.known(table, key, ("number", "station_m", "time_s"))
    number = table.get("number")
    if not isinstance(number, int) or isinstance(number, bool):
        reader.add(f"{key}.number", Phrase("expected a whole number, found {number!r}", {"number": number}))
        return None
    given = [name for name in ("station_m", "time_s") if name in table]
    if len(given) != 1:
        reader.add(key, Phrase("give exactly one of station_m (chainage) or time_s (GPS seconds of week)"))
        return None
    value = reader.number(table, f"{key}.{given[0]}")
    return None if value is None else SleeperAnchor(number, **{given[0]: value})


def _check_events(reader: _Reader, events: str) -> None:
    """A project's event file: readable, in chainage (times and odometer readings belong to one survey)."""
    try:
        listed = read_events(reader.folder / events)
    except InputError as err:
        reader.add("track.events", str(err))
        return
    for event in listed.events:
        if event.unit != "station_m":
            reader.add("track.events", Phrase("{events}, line {line}: a project's events are in chainage (station_m); "
                       "an event in {unit} belongs in its survey's event file", {"events": events, "line": event.line, "unit": event.unit}))


def _surveys(reader: _Reader, table) -> tuple[SurveyEntry, ...]:
    if not isinstance(table, list) or not table:
        reader.add("surveys", Phrase("expected at least one [[surveys]] entry with name and folder"))
        return ()
    entries, seen = [], set()
    for i, entry in enumerate(table):
        key = f"surveys[{i}]"
        if not isinstance(entry, dict):
            reader.add(key, Phrase("expected a table with name and folder"))
            continue
        reader.known(entry, key, ("name", "folder"))
        name, folder = entry.get("name"), entry.get("folder")
        if not isinstance(name, str) or not _SURVEY_NAME.match(name):
            reader.add(f"{key}.name", Phrase("expected a name of letters, digits, '.', '_' or '-', found {name!r}", {"name": name}))
        elif name in seen:
            reader.add(f"{key}.name", Phrase("duplicate survey name {name!r}", {"name": name}))
        seen.add(name)
        if not isinstance(folder, str) or not folder:
            reader.add(f"{key}.folder", Phrase("expected a folder path relative to the project"))
        elif not (reader.folder / folder).is_dir():
            reader.add(f"{key}.folder", Phrase("not found: {folder}", {"folder": folder}))
        elif not (reader.folder / folder / MANIFEST_NAME).is_file():
            reader.add(f"{key}.folder", Phrase("no {manifest_name} in {folder}", {"manifest_name": MANIFEST_NAME, "folder": folder}))
        if isinstance(name, str) and isinstance(folder, str):
            entries.append(SurveyEntry(name, folder))
    return tuple(entries)


class _Reader:
    """Collects problems as ``key.path: message`` while reading a document."""

    def __init__(self, folder: Path):
        self.folder = folder
        self.problems: list[str] = []

    def add(self, key: str, message: str) -> None:
        self.problems.append(Phrase("{key}: {message}", {"key": key, "message": message}))

    def raise_if_any(self, path: Path) -> None:
        if self.problems:
            raise ProjectError(path, self.problems)

    def table(self, parent: dict, key: str, key_path: str | None = None) -> dict:
        value = parent.get(key, {})
        if not isinstance(value, dict):
            self.add(key_path or key, f"expected a table, found {value!r}")
            return {}
        return value

    def known(self, table: dict, key_path: str, keys: tuple[str, ...]) -> None:
        for key in table:
            if key not in keys:
                self.add(f"{key_path}.{key}", f"unknown key (expected {', '.join(keys)})")

    def text(self, table: dict, key_path: str, default: str) -> str:
        value = table.get(key_path.rsplit(".", 1)[1], default)
        if not isinstance(value, str):
            self.add(key_path, f"expected text, found {value!r}")
            return default
        return value

    def number(self, table: dict, key_path: str, positive: bool = False) -> float | None:
        value = table[key_path.rsplit(".", 1)[1]]
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not np.isfinite(value):
            self.add(key_path, f"expected a number, found {value!r}")
            return None
        if positive and value <= 0:
            self.add(key_path, f"expected a positive number, found {value!r}")
            return None
        return float(value)

    def file(self, table: dict, key_path: str) -> str | None:
        value = table.get(key_path.rsplit(".", 1)[1])
        if value is None:
            return None
        if not isinstance(value, str) or not value:
            self.add(key_path, f"expected a file path relative to the project, found {value!r}")
        elif not (self.folder / value).is_file():
            self.add(key_path, f"file not found: {value}")
        else:
            return value
        return None

    def loadable(self, table: dict, key_path: str, load, default: str | None = None, resolve: bool = True):
        """A shipped name or ``.toml`` path that ``load`` accepts; the value as written."""
        value = table.get(key_path.rsplit(".", 1)[1], default)
        if not isinstance(value, str) or not value:
            self.add(key_path, f"expected a shipped name or a .toml path, found {value!r}")
            return default
        try:
            load(self.folder / value if resolve and value.endswith(".toml") else value)
        except (ValueError, OSError) as err:
            self.add(key_path, str(err).replace("\n", " "))
        return value


__all__ = [
    "HEIGHT_MODELS",
    "PAPER_SIZES",
    "PROJECT_FILE",
    "HeightSettings",
    "Project",
    "ProjectError",
    "ReportSettings",
    "SurveyEntry",
    "load_project",
    "project_from_settings",
    "save_project",
]
