"""What both reports show, gathered once from a project and its stored results.

Reports format; they compute no track geometry. Every number comes from the result files
(:mod:`insrail.project.results`) in the unit its column names, converted only for display:
ratios (gauge change rates) are shown in per mille (‰), lengths stay in mm or m.

The sleeper columns follow the thesis's sleeper table (Chen 2016, Figure 5-7): deviations
(measured − design or − fitted line, as the results were processed: :mod:`insrail.report.labels`) per rail, gauge and cross-level, design cant, gauge change to the neighbour
and over 2.5 m, twist over 3 m, guiding rail, the 30 m / 5 m and 300 m / 150 m differential
versines; then every other check of the tolerance profile, then the adjustment amounts. Where
the profile checks a quantity the column shows the check's channel, carries its limits, and the
sleepers inside one of the pipeline's exceedance runs are marked: exceedances.csv is the verdict,
never a re-evaluation of rounded numbers.

The settings a report states (coordinate system, heights, IMU, tolerance profile, design) are the
ones the results were processed with (summary.toml's ``[settings]``,
:mod:`insrail.project.run_settings`), not today's project.toml; what the project says differently
now is listed in :attr:`ReportContent.settings_changes` ("processed with ...; the project now
says ...: process again").
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field, replace
from functools import cached_property

import numpy as np

from insrail import __version__
from insrail.names import (
    channel_name,
    check_name,
    check_unit,
    column_name,
    in_language,
    joined,
    rail_direction,
    t,
)
from insrail.nav.mounting import why_of
from insrail.geodesy.crs import EngineeringCRS
from insrail.project.model import Project
from insrail.report.labels import deviation_group
from insrail.project.results import (
    GAUGE_CHANGE_BASE_M,
    TWIST_BASE_M,
    ExceedanceRow,
    StoredResults,
    check_column,
)
from insrail.project.run_settings import RecordedSettings, report_language
from insrail.project.sleeper_integrity import said_per_sleeper
from insrail.track.adjustment import FastenerType, load_fastener_type
from insrail.track.adjustment_parts import PartTable, materials, parts_text
from insrail.track.events import KIND_NAMES
from insrail.track.exceedance import RAILS
from insrail.track.stationing import StationEquations
from insrail.track.tolerance import (
    DIRECTIONS,
    Check,
    ToleranceProfile,
    limit_unit,
    load_tolerance_profile,
)

PER_MILLE = 1e3  # ratio -> ‰
#: checks with one channel per rail and direction
RAIL_KINDS = ("versine", "differential_versine", "band_peak", "deviation_change_rate")


def _display_scale(kind: str) -> tuple[float, str]:
    """(factor from SI to the displayed unit, number format) of a check kind's values and limits."""
    return (PER_MILLE, "0.00") if limit_unit(kind) == "ratio" else (1e3, "0.0")


@dataclass(frozen=True)
class Column:
    """One column of the sleeper table as displayed.

    ``values`` are in ``unit`` (float; NaN shows as an empty cell) or text; ``limits`` (lower,
    upper) in the same unit when a check of the profile judges the column; ``exceeding`` marks
    the sleepers of the pipeline's exceedance runs of that check channel.
    """

    key: str  # the sleepers.csv column shown (or a derived name)
    group: str
    title: str
    unit: str
    values: np.ndarray
    number_format: str = "0.0"
    width: float = 8.0
    limits: tuple[float, float] | None = None
    exceeding: np.ndarray | None = None
    check: str | None = None
    name: str = ""  # the column's display name on its own (insrail.names), where ``title`` needs its group


@dataclass(frozen=True)
class EventRow:
    """One event of summary.toml's ``[[events]]`` as the reports show it."""

    kind: str  # display name ("level crossing")
    station_from_m: float
    station_to_m: float
    text: str
    assessment: str  # "not assessed", "assessed with <profile>: N exceedances", "marked"
    sleepers: int
    source: str

    @classmethod
    def of(cls, row: dict) -> EventRow:
        assessment = (t("not assessed") if row["not_assessed"] else
                      t("assessed with {profile}: {count} exceedances").format(profile=row["profile"],
                                                                                count=row.get("exceedances", 0))
                      if row["profile"] else t("marked only"))
        return cls(t(KIND_NAMES[row["kind"]]), row["station_from_m"], row["station_to_m"], row["text"], assessment,
                   row["sleepers"], row["source"])

    @property
    def name(self) -> str:
        return f"{self.kind} {self.text}".strip()


@dataclass(frozen=True)
class ReportContent:
    """Everything the workbook and the PDF present, in display units."""

    project: Project
    results: StoredResults
    profile: ToleranceProfile
    fastener: FastenerType | None
    columns: tuple[Column, ...]
    valid: np.ndarray  # (n,) bool
    station_m: np.ndarray
    software: str = f"insrail {__version__}"
    notes: tuple[str, ...] = field(default_factory=tuple)
    recorded: RecordedSettings = field(default_factory=lambda: RecordedSettings({}))
    #: what the project now says differently from the recorded settings, one line each
    settings_changes: tuple[str, ...] = ()

    @property
    def crs(self) -> EngineeringCRS:
        """The CRS the results are in: the recorded one (the project's for results that predate the record)."""
        return self.recorded.crs or self.project.crs

    @property
    def design(self) -> str | None:
        """The design the results were processed with (None: fitted lines)."""
        return self.recorded.record.get("design", {}).get("file", self.project.design) or None

    @property
    def summary(self) -> dict:
        return self.results.summary

    @property
    def survey(self) -> str:
        return self.results.survey

    @property
    def chainage_range(self) -> str:
        if not len(self.results):
            return t("no sleepers")
        return f"{self.results.label[0]} – {self.results.label[-1]}"

    @cached_property
    def chainage(self) -> ChainageAxis:
        """K-chainage of any station of this survey (chart axes)."""
        return ChainageAxis.from_labels(self.station_m, self.results.label)

    @cached_property
    def adjustment(self) -> AdjustmentWork:
        """The adjustment's rows and parts (:func:`adjustment_work`), made once for every sheet and table listing them."""
        return adjustment_work(self)

    @property
    def events(self) -> tuple[EventRow, ...]:
        """The survey's events (turnouts, level crossings, ...) as the processing placed them."""
        return tuple(EventRow.of(row) for row in self.summary.get("events", []))

    def column(self, key: str) -> Column:
        for column in self.columns:
            if column.key == key:
                return column
        raise KeyError(key)


_PREFIX = re.compile(r"^\s*([^\d+\-]*)")


@dataclass(frozen=True)
class ChainageAxis:
    """The chainage labels of a survey ("DK1+695.917") for any station, read from its sleepers' labels.

    Between station equations the displayed chainage is the station plus a constant; each station takes
    the offset of its nearest sleeper, so a chart tick is labelled as the sleeper table labels that
    stretch. Labels that do not read as chainage (no design, another format) leave the axis in metres."""

    station_m: np.ndarray
    offset_m: np.ndarray  # displayed chainage - station, per sleeper
    prefix: str | None  # None: the labels are not chainage; ticks in metres of station

    @classmethod
    def from_labels(cls, station_m: np.ndarray, labels: tuple[str, ...]) -> ChainageAxis:
        station_m = np.asarray(station_m, dtype=float)
        if not labels:
            return cls(station_m, np.zeros(0), None)
        prefix = _PREFIX.match(labels[0]).group(1).strip()
        try:
            reader = StationEquations(prefix=prefix)
            displayed = reader.parse_labels(labels)
        except ValueError:  # not chainage labels (or mixed prefixes): metres of station
            return cls(station_m, np.zeros(len(labels)), None)
        return cls(station_m, np.round(displayed - station_m, 3), prefix)

    @property
    def title(self) -> str:
        return t("chainage") if self.prefix is not None else t("station m")

    def _offset(self, station: float) -> float:
        if not self.station_m.size:
            return 0.0
        index = int(np.clip(np.searchsorted(self.station_m, station), 1, self.station_m.size - 1)) \
            if self.station_m.size > 1 else 0
        if index and abs(self.station_m[index - 1] - station) <= abs(self.station_m[index] - station):
            index -= 1
        return float(self.offset_m[index])

    def label(self, station: float) -> str:
        """A tick label: "DK1+350" (whole metres), or the station in metres."""
        if self.prefix is None:
            return f"{station:.0f}"
        return StationEquations(prefix=self.prefix).label(station + self._offset(station), decimals=0)

    def ticks(self, station_from: float, station_to: float, step: float) -> list[tuple[float, str]]:
        """(station, label) at round chainage every ``step`` metres within [station_from, station_to]: per
        stretch of one offset, so ticks stay on round chainage across a station equation."""
        inside = (self.station_m >= station_from) & (self.station_m <= station_to)
        offsets = np.unique(self.offset_m[inside]) if inside.any() else np.array([self._offset(station_from)])
        ticks = []
        for offset in offsets:
            stations = self.station_m[inside & (self.offset_m == offset)] if inside.any() else np.array([station_from,
                                                                                                            station_to])
            low = station_from if offset == offsets[0] else float(stations.min())
            high = station_to if offset == offsets[-1] else float(stations.max())
            first = math.ceil((low + offset) / step - 1e-9) * step
            for displayed in np.arange(first, high + offset + 1e-9, step):
                ticks.append((float(displayed - offset), self.label(float(displayed - offset))))
        return ticks


def sleeper_repair_text(summary: dict) -> str:
    """How the numbering repaired the sleeper detector's pulses, in words ("" for results without the figures)."""
    pulses = summary.get("track", {}).get("sleeper_pulses")
    if not pulses:
        return ""
    if not pulses["pulses"]:
        return t("no detector pulses: a regular grid")
    return t("{pulses} pulses: {missed} missed sleepers inserted, {false} false pulses rejected").format(
        pulses=pulses["pulses"], missed=pulses["missed_inserted"], false=pulses["false_rejected"])


def limits_text(check: Check) -> str:
    """A check's limits as a reader writes them: ±2.0 mm, ±0.67 ‰, >= -5.0 and <= 35.0 mm (Helvetica
    in the PDF has ± and ‰ but no ≥)."""
    scale, unit = _display_scale(check.kind)[0], check_unit(check.kind)
    lower, upper = scale * check.lower, scale * check.upper
    digits = 2 if unit == "‰" else 1
    if np.isfinite(lower) and np.isfinite(upper) and np.isclose(-lower, upper):
        return f"±{upper:.{digits}f} {unit}"
    parts = ([f">= {lower:.{digits}f}"] if np.isfinite(lower) else []) + ([f"<= {upper:.{digits}f}"] if np.isfinite(upper) else [])
    return t(" and ").join(parts) + f" {unit}"


def check_description(check: Check) -> str:
    """What a check measures, in words (for the header block and the PDF)."""
    kind = check.kind
    if kind == "versine":
        return (t("versine, {chord_m:g} m chord").format(chord_m=check.chord_m)
                + (t(" ({back_m:g} m back)").format(back_m=check.back_m) if check.back_m else ""))
    if kind == "differential_versine":
        return t("differential versine, {chord_m:g} m chord / {pair_m:g} m pairs").format(chord_m=check.chord_m,
                                                                                          pair_m=check.pair_m)
    if kind == "band_peak":
        return t("band-passed peak, band {band}").format(band=check.band)
    if kind == "twist":
        return (t("twist over {base_m:g} m").format(base_m=check.base_m)
                + (t(" (design cant ramp removed)") if check.relative_to_design else ""))
    if kind == "gauge_change_rate":
        return (t("gauge change rate over {base_m:g} m").format(base_m=check.base_m) if check.base_m
                else t("gauge change rate sleeper to sleeper"))
    if kind == "cant_change_rate":
        return t("cant change rate over {base_m:g} m").format(base_m=check.base_m)
    if kind == "cant_deficiency_rate":
        return t("cant deficiency rate over {base_m:g} m").format(base_m=check.base_m)
    if kind == "deviation_change_rate":
        return t("alignment / height change rate over {base_m:g} m").format(base_m=check.base_m)
    return t({"gauge_deviation": "gauge deviation from nominal", "cross_level": "cross-level (measured - design cant)",
              "cant_deficiency": "cant deficiency at line speed"}[kind])


def load_report_content(project: Project, results: StoredResults) -> ReportContent:
    """Collect the columns and settings the reports show (see the module docstring)."""
    profile = load_tolerance_profile(project.resource(project.tolerance_profile))
    stored_profile = results.summary.get("assessment", {}).get("tolerance_profile")
    recorded = RecordedSettings.of(results.summary)
    notes = []
    # the columns and limits come from the profile: one other than the results' cannot print them
    if stored_profile is not None and (stored_profile != profile.name or not recorded.same_tolerance_profile(profile)):
        raise ValueError(f"{results.folder}: results were assessed with tolerance profile {stored_profile!r}, the project "
                         f"now names {profile.name!r}{'' if stored_profile != profile.name else ' with other contents'}: "
                         "process the survey again before reporting")
    try:
        fastener = load_fastener_type(project.resource(project.fastener))
    except ValueError as error:  # a fastener file edited since processing: the amounts are still in the results
        fastener = None
        notes.append(t("fastener type not readable: {error}").format(error=error))
    columns = _sleeper_columns(results, profile)
    valid = results.columns["valid"] > 0
    return ReportContent(project, results, profile, fastener, tuple(columns), valid, results.columns["station_m"],
                         notes=tuple(notes), recorded=recorded,
                         # the standard sentence translated; a change's own line names settings as project.toml does
                         settings_changes=tuple(line.said() for line in recorded.changes(project, _first_survey(results))))


def report_content(project: Project, results: StoredResults) -> ReportContent:
    """:func:`load_report_content` in the project's report language, as each writer makes it: one content for
    both reports written in one process (its columns, chainage axis and adjustment work made once)."""
    with in_language(report_language(project)):
        return load_report_content(project, results)


def _first_survey(results: StoredResults) -> str:
    """The survey whose settings the results carry (a joined section's: its first run's)."""
    return results.summary.get("section", {}).get("surveys", [results.survey])[0]


# --------------------------------------------------------------------------- columns

def _exceeding(results: StoredResults, check: str, rail: str, direction: str) -> np.ndarray:
    """Sleepers inside the pipeline's exceedance runs of one check channel."""
    mask = np.zeros(len(results), dtype=bool)
    runs = [(e.first_sleeper, e.last_sleeper) for e in results.exceedances
            if (e.check, e.rail, e.direction) == (check, rail, direction)]
    if not runs:
        return mask
    # a sleeper number's row (the last one where a number repeats), found by a sorted search: a look-up
    # table of every sleeper per channel cost more than the rest of the columns
    number = np.asarray(results.number)
    order = np.argsort(number, kind="stable")
    ends = np.asarray(runs, dtype=number.dtype)
    rows = order[np.searchsorted(number[order], ends, side="right") - 1]
    if not np.array_equal(number[rows], ends):
        raise KeyError(f"an exceedance of {check} names a sleeper not in the results")
    for first, last in rows:
        mask[first:last + 1] = True
    return mask


def _lower_first(name: str) -> str:
    """A display name as a column title under its group ("Gauge deviation" -> "gauge deviation")."""
    return name[:1].lower() + name[1:] if name[1:2].islower() else name


def _named(key: str, group: str, values: np.ndarray, number_format: str = "0.0", title: str | None = None,
           **options) -> Column:
    """A column of a stored (or report-derived) quantity, named by :mod:`insrail.names`."""
    name = column_name(key)
    return Column(key, t(group), title if title is not None else _lower_first(name.name), name.unit, values, number_format,
                  name=name.name, **options)


def _check_column(results: StoredResults, check: Check, rail: str, direction: str, group: str, title: str) -> Column:
    key = check_column(check.name, check.kind, rail, direction)
    scale, number_format = _display_scale(check.kind)  # limits in SI; the stored values in the column's unit
    stored = PER_MILLE if limit_unit(check.kind) == "ratio" else 1.0
    return Column(key, t(group), title, check_unit(check.kind), stored * results.columns[key],
                  number_format, limits=(scale * check.lower, scale * check.upper),
                  exceeding=_exceeding(results, check.name, rail, direction), check=check.name,
                  name=channel_name(check, rail, direction))


def _channels(results: StoredResults, check: Check, group: str) -> list[Column]:
    """The columns of one check: one per rail and direction under the check's own group, or the one
    track channel titled with the check's name (in ``group``)."""
    if check.kind in RAIL_KINDS:
        return [_check_column(results, check, rail, direction, group, rail_direction(rail, direction))
                for direction in DIRECTIONS if direction in check.directions for rail in RAILS]
    return [_check_column(results, check, "track", "", group, _lower_first(check_name(check)))]


def _find(profile: ToleranceProfile, used: set[str], kind: str, **parameters) -> Check | None:
    for check in profile.checks:
        if check.name not in used and check.kind == kind and all(
                getattr(check, name) is not None and np.isclose(getattr(check, name), value) if isinstance(value, float)
                else getattr(check, name) == value for name, value in parameters.items()):
            used.add(check.name)
            return check
    return None


#: Group titles of the sleeper table (a check with a channel per rail has its own group: its name).
SLEEPER_GROUP = "Sleeper"
PARAMETER_GROUP = "Track parameters"
#: Gauge against the nominal gauge and cross level against the design cant (whatever the deviations' reference).
GAUGE_LEVEL_GROUP = "Gauge and cross level [measured − nominal / design cant]"
OTHER_CHECKS_GROUP = "Other checks of the tolerance profile"
ADJUSTMENT_GROUP = "Adjustment (move the rail by)"


def _said_reasons(results: StoredResults) -> np.ndarray:
    """Each sleeper's reasons for not being assessed in the report's language (sleepers.csv keeps the English)."""
    return np.array(said_per_sleeper(results.not_assessed or ("",) * len(results), results.summary), dtype=object)


def _sleeper_columns(results: StoredResults, profile: ToleranceProfile) -> list[Column]:
    c = results.columns
    n = len(results)
    used: set[str] = set()
    columns = [
        _named("row", SLEEPER_GROUP, np.arange(1, n + 1), "0", width=6),
        _named("number", SLEEPER_GROUP, results.number, "0", t("number"), width=8),
        _named("label", SLEEPER_GROUP, np.array(results.label, dtype=object), "@", width=13),
        _named("station_m", SLEEPER_GROUP, c["station_m"], "0.000", width=11),
        *([_named("chain_zone", SLEEPER_GROUP, c["chain_zone"], "0", width=8)] if "chain_zone" in c else []),
        _named("not_assessed", SLEEPER_GROUP, _said_reasons(results), "@", width=18),
    ]
    sources = [k for k in c if k.startswith("source_")]  # a joined line section (insrail.project.section)
    if sources:
        runs = [" + ".join(k.removeprefix("source_") for k in sources if c[k][i] > 0) for i in range(n)]
        columns.append(_named("runs", SLEEPER_GROUP, np.array(runs, dtype=object), "@", width=14))
    for direction in DIRECTIONS:
        for rail in RAILS:
            key = f"{direction}_deviation_{rail}_mm"
            columns.append(_named(key, deviation_group(results.summary), c[key], title=rail_direction(rail, direction)))
    gauge = _find(profile, used, "gauge_deviation")
    columns += (_channels(results, gauge, GAUGE_LEVEL_GROUP) if gauge else
                [_named("gauge_deviation_mm", GAUGE_LEVEL_GROUP, c["gauge_mm"] - 1e3 * profile.nominal_gauge_m)])
    cross_level = _find(profile, used, "cross_level")
    columns += (_channels(results, cross_level, GAUGE_LEVEL_GROUP) if cross_level else
                [_named("cross_level_mm", GAUGE_LEVEL_GROUP, c["cant_mm"] - c["design_cant_mm"])])
    columns += [_named("gauge_mm", PARAMETER_GROUP, c["gauge_mm"], width=9),
                _named("cant_mm", PARAMETER_GROUP, c["cant_mm"]),
                _named("design_cant_mm", PARAMETER_GROUP, c["design_cant_mm"]),
                _named("gauge_change_mm", PARAMETER_GROUP, c["gauge_change_mm"], width=11)]
    rate = _find(profile, used, "gauge_change_rate", base_m=GAUGE_CHANGE_BASE_M)
    columns += (_channels(results, rate, PARAMETER_GROUP) if rate else
                [_named("gauge_change_rate_2_5m_ratio", PARAMETER_GROUP, PER_MILLE * c["gauge_change_rate_2_5m_ratio"],
                        "0.00", width=10)])
    twist = _find(profile, used, "twist", base_m=TWIST_BASE_M, relative_to_design=True)
    columns += (_channels(results, twist, PARAMETER_GROUP) if twist else
                [_named("twist_3m_mm", PARAMETER_GROUP, c["twist_3m_mm"])])
    columns += _running_parameter_columns(results, profile, used)
    columns.append(_named("guiding_rail", PARAMETER_GROUP,
                          np.where(c["guiding_rail_right"] > 0, t("R"), t("L")).astype(object), "@", width=8))
    # the thesis's short- and long-wave columns first, then the profile's other checks in file order
    for chord, pair in ((30.0, 5.0), (300.0, 150.0)):
        check = _find(profile, used, "differential_versine", chord_m=chord, pair_m=pair)
        if check:
            columns += _channels(results, check, check_name(check))
    for check in profile.checks:
        if check.name not in used:
            columns += _channels(results, check, check_name(check) if check.kind in RAIL_KINDS else OTHER_CHECKS_GROUP)
    for direction in DIRECTIONS:
        for rail in RAILS:
            key = f"adjust_{direction}_{rail}_mm"
            columns.append(_named(key, ADJUSTMENT_GROUP, c[key], title=rail_direction(rail, direction)))
    unresolved = np.zeros(n, dtype=bool)
    for direction in DIRECTIONS:
        for rail in RAILS:
            unresolved |= c[f"unresolved_{direction}_{rail}"] > 0
    notes = results.adjustment_notes  # why: fastener range exhausted, conflicting checks (older results: none)
    flag = (np.array([adjustment_note(note) or (t("yes") if u else "") for note, u in zip(notes, unresolved)],
                     dtype=object) if notes
            else np.where(unresolved, t("yes"), "").astype(object))
    columns.append(_named("unresolved", ADJUSTMENT_GROUP, flag, "@", width=9))
    return columns


ADJUSTMENT_KEYS = ("adjust_lateral_left_mm", "adjust_lateral_right_mm", "adjust_vertical_left_mm",
                   "adjust_vertical_right_mm")


@dataclass(frozen=True)
class AdjustmentWork:
    """The adjustment sheet's rows: the sleepers with an amount, in working order (increasing
    chainage), their amounts [mm] (m, 4) in :data:`ADJUSTMENT_KEYS` order and the parts per rail."""

    order: np.ndarray  # sleeper indices
    amounts_mm: np.ndarray
    parts: tuple[tuple[str, ...], ...]  # per row the parts of each amount, in ADJUSTMENT_KEYS order
    materials: tuple[tuple[str, str, int, int], ...]  # (part, size, left rails, right rails)
    notes: tuple[str, ...]  # how a direction is adjusted without parts


def adjustment_work(content: ReportContent) -> AdjustmentWork:
    amounts = np.column_stack([np.nan_to_num(content.column(key).values) for key in ADJUSTMENT_KEYS])
    moving = np.flatnonzero(np.any(amounts != 0, axis=1))
    order = moving[np.argsort(content.station_m[moving], kind="stable")]
    amounts = amounts[order]
    tables = _in_language(content.fastener.parts) if content.fastener is not None else {}
    places = [(key.split("_")[1], RAILS.index(key.split("_")[2])) for key in ADJUSTMENT_KEYS]
    texts: dict[tuple[str, int, float], str] = {}  # a few distinct amounts, many sleepers

    def text(direction: str, rail: int, amount: float) -> str:
        key = (direction, rail, amount)
        if key not in texts:
            texts[key] = parts_text(tables, direction, rail, amount)
        return texts[key]

    parts = tuple(tuple(text(direction, rail, amount) for (direction, rail), amount in zip(places, row))
                  for row in amounts.tolist())
    listed = tuple(materials(tables, amounts[:, :2], amounts[:, 2:]))
    notes = tuple(f"{direction}: {table.note}" for direction, table in tables.items() if table.note)
    return AdjustmentWork(order, amounts, parts, listed, notes)


def _in_language(tables: dict[str, PartTable]) -> dict[str, PartTable]:
    """A fastener's part tables with their parts' names and notes in the report's language."""
    return {direction: replace(table, note=t(table.note),
                               positions=tuple(replace(p, name=t(p.name)) for p in table.positions))
            for direction, table in tables.items()}


#: Two sleepers with work further apart than this [m] belong to different work sections, and a section
#: spans at most WORK_SECTION_M of chainage (the crew's sheet starts a new page for each: a stretch a crew
#: takes on in one go, on its own sheets of paper).
WORK_SECTION_GAP_M = 30.0
WORK_SECTION_M = 100.0


@dataclass(frozen=True)
class CrewRow:
    """One line of the crew's sheet: one rail of one sleeper with an amount [mm] (+ right / + up)."""

    sleeper: int  # index into the sleeper table
    count: int  # the sleeper's place in working order (1, 2, ...)
    rail: int  # 0 left, 1 right
    lateral_mm: float
    vertical_mm: float
    lateral_parts: str
    vertical_parts: str
    failing: str  # why a check still fails at this rail after the adjustment ("" where none)

    @property
    def parts(self) -> tuple[str, ...]:
        """The parts of each amount, named by its direction ("lateral: outer block No. 9→7; ...")."""
        return tuple(f"{t(direction)}: {text}" for direction, text in (("lateral", self.lateral_parts),
                                                                      ("vertical", self.vertical_parts)) if text)


@dataclass(frozen=True)
class WorkSection:
    """Consecutive crew rows of one work site: sleepers with work no more than WORK_SECTION_GAP_M apart,
    over at most WORK_SECTION_M."""

    number: int
    rows: tuple[CrewRow, ...]


def crew_sections(content: ReportContent) -> list[WorkSection]:
    """The adjustment as the crew's sheet lists it: per sleeper in working order each rail with an
    amount, split into work sections (every amount exactly as in sleepers.csv)."""
    work = content.adjustment
    keys = {key: k for k, key in enumerate(ADJUSTMENT_KEYS)}
    notes = content.results.adjustment_notes or content.column("unresolved").values  # as the results word them
    rows: list[list[CrewRow]] = []
    previous = first = None
    for position, sleeper in enumerate(work.order):
        station = float(content.station_m[sleeper])
        if previous is None or station - previous > WORK_SECTION_GAP_M or station - first >= WORK_SECTION_M:
            rows.append([])
            first = station
        previous = station
        for rail, name in enumerate(RAILS):
            lateral = work.amounts_mm[position, keys[f"adjust_lateral_{name}_mm"]]
            vertical = work.amounts_mm[position, keys[f"adjust_vertical_{name}_mm"]]
            if lateral or vertical:
                rows[-1].append(CrewRow(int(sleeper), position + 1, rail, float(lateral), float(vertical),
                                        work.parts[position][keys[f"adjust_lateral_{name}_mm"]],
                                        work.parts[position][keys[f"adjust_vertical_{name}_mm"]],
                                        adjustment_note(rail_note(str(notes[sleeper]), name))))
    return [WorkSection(number, tuple(section)) for number, section in enumerate(rows, start=1)]


def rail_note(note: str, rail: str) -> str:
    """The parts of a sleeper's "checks still failed" note about one rail ("lateral left: ..."; "yes" stays)."""
    if note in ("", "yes", t("yes")):
        return note
    return "; ".join(part for part in note.split("; ") if f" {rail}:" in part)


_NOTE_PART = re.compile(r"^(lateral|vertical) (left|right): (.*)$")


def adjustment_note(note: str) -> str:
    """A sleeper's "checks still failed" note of the results ("lateral left: conflicting checks; ...", the
    reasons of :data:`insrail.track.adjustment.REASONS`) in the report's language."""
    parts = []
    for part in note.split("; ") if note else ():
        match = _NOTE_PART.match(part)
        if match is None:  # "yes" (results without reasons) or a wording of another version: as written
            parts.append(t(part))
            continue
        direction, rail, why = match.groups()
        reasons = " + ".join(t(reason) for reason in why.split(" + "))
        parts.append(f"{joined((t(direction), t(rail + ' rail')))}: {reasons}")
    return "; ".join(parts)


def threshold_text(summary: dict) -> str:
    """The action threshold and the amounts below it that the checks needed ("" for older results)."""
    adjustment = summary.get("adjustment", {})
    if "threshold_mm" not in adjustment:
        return ""
    kept = adjustment.get("below_threshold_sleepers", 0)
    return (t("Action threshold {threshold:g} mm: every amount is 0 or at least this").format(
                threshold=adjustment["threshold_mm"])
            + (t(", except at {count} sleepers where a smaller amount is needed to keep the checks").format(count=kept)
               if kept else ""))


def after_adjustment_text(summary: dict) -> str:
    """The re-assessment of the adjusted geometry in one sentence ("" for results of older versions)."""
    adjustment = summary.get("adjustment", {})
    after = adjustment.get("after")
    if after is None:
        return ""
    reasons = joined(f"{t(name.replace('_', ' '))}: {count}" for name, count in  # REASONS' words, as ids
                     adjustment.get("unresolved_reasons", {}).items() if count)
    before = sum(after.get("by_check_before", {}).values())
    return (t("After adjustment: {after} exceedances (before {before}), {new} where the track passed before").format(
                after=after["exceedances"], before=before, new=after.get("new_exceedances", 0))
            + (t("; sleepers still failing: {reasons}").format(reasons=reasons) if reasons else ""))


def _running_parameter_columns(results: StoredResults, profile: ToleranceProfile, used: set[str]) -> list[Column]:
    """Cant change rate, cant deficiency and its rate: the profile's channel where it checks one on the
    base sleepers.csv used, else the stored column; absent in results of older versions."""
    c = results.columns
    bases = results.summary.get("track", {}).get("parameters", {})
    columns = []
    for key, kind, base_key, factor, number_format in (
            ("cant_change_rate_ratio", "cant_change_rate", "cant_change_rate_base_m", PER_MILLE, "0.00"),
            ("cant_deficiency_mm", "cant_deficiency", None, 1.0, "0.0"),
            ("cant_deficiency_rate_mm_per_s", "cant_deficiency_rate", "cant_deficiency_rate_base_m", 1.0, "0.0")):
        if key not in c:
            continue
        base = bases.get(base_key) if base_key else None
        check = (_find(profile, used, kind) if base_key is None
                 else _find(profile, used, kind, base_m=float(base)) if base is not None else None)
        if check:
            columns += _channels(results, check, PARAMETER_GROUP)
        elif np.isfinite(c[key]).any():  # no line speed: no cant deficiency column, not an empty one
            title = _lower_first(column_name(key).name) + (f" {base:g} m" if base is not None else "")
            columns.append(_named(key, PARAMETER_GROUP, factor * c[key], number_format, title, width=10))
    return columns


# --------------------------------------------------------------------------- statistics

@dataclass(frozen=True)
class ParameterStatistics:
    column: Column
    valid_count: int
    minimum: float
    maximum: float
    mean: float
    standard_deviation: float
    exceeding_sleepers: int
    exceedances: int


def parameter_statistics(content: ReportContent) -> list[ParameterStatistics]:
    """Statistics of every numeric measured column over the valid sleepers, with its exceedances."""
    statistics = []
    for column in content.columns:
        if column.values.dtype == object or column.group == t(SLEEPER_GROUP) or column.key.startswith("adjust_"):
            continue
        values = column.values[content.valid]
        values = values[np.isfinite(values)]
        runs = sum(1 for e in content.results.exceedances
                   if column.check is not None and check_column(e.check, e.kind, e.rail, e.direction) == column.key)
        exceeding = int(column.exceeding.sum()) if column.exceeding is not None else 0
        if values.size:
            statistics.append(ParameterStatistics(column, int(values.size), float(values.min()), float(values.max()),
                                                  float(values.mean()), float(values.std(ddof=1)) if values.size > 1 else 0.0,
                                                  exceeding, runs))
        else:
            statistics.append(ParameterStatistics(column, 0, np.nan, np.nan, np.nan, np.nan, exceeding, runs))
    return statistics


def sections(content: ReportContent, length_m: float) -> list[tuple[float, float, np.ndarray]]:
    """(start, end, row indices) of consecutive ``length_m`` sections of station from the first sleeper."""
    station = content.station_m
    if not station.size:
        return []
    index = np.floor((station - station[0]) / length_m).astype(int)
    return [(station[0] + k * length_m, station[0] + (k + 1) * length_m, np.flatnonzero(index == k))
            for k in range(index.max() + 1) if np.any(index == k)]


#: Severity of an exceedance: how far its peak lies beyond the limit, as a share of the limit (the
#: profiles have one limit per check; this grades the runs beyond it for the reader, largest first).
SEVERITIES = (("severe", 1.0), ("major", 0.25), ("minor", 0.0))
SEVERITY_RULE = "severity by how far the peak lies beyond the limit: minor up to 25 %, major 25 - 100 %, severe over 100 % of the limit"


def excess_share(row: ExceedanceRow) -> float:
    """How far the peak lies beyond the limit, as a share of the limit (inf for a limit of 0)."""
    return abs(row.peak - row.limit) / abs(row.limit) if row.limit else np.inf


def severity(row: ExceedanceRow) -> str:
    share = excess_share(row)
    return next(name for name, floor in SEVERITIES if share > floor or floor == 0.0)


def exceedances_by_severity(content: ReportContent) -> list[tuple[str, list[ExceedanceRow]]]:
    """(severity, its exceedances in chainage order), the most severe first; severities without one left out."""
    groups = [(name, [e for e in content.results.exceedances if severity(e) == name]) for name, _ in SEVERITIES]
    return [(name, sorted(rows, key=lambda e: e.station_from_m)) for name, rows in groups if rows]


def exceedance_check(content: ReportContent, row: ExceedanceRow) -> str:
    """The display name of an exceedance's channel ("30 m / 5 m short wave, left rail, lateral")."""
    check = next((c for c in content.profile.checks if c.name == row.check), None)
    if check is None:
        raise ValueError(f"{content.results.folder}: exceedance of check {row.check!r}, which tolerance profile "
                         f"{content.profile.name!r} does not hold: process the survey again before reporting")
    return channel_name(check, row.rail, row.direction)


def exceedance_display(row: ExceedanceRow) -> tuple[float, float, str]:
    """(peak, limit, unit) of an exceedance as displayed (ratios in ‰)."""
    if row.unit == "ratio":
        return PER_MILLE * row.peak, PER_MILLE * row.limit, "‰"
    return row.peak, row.limit, row.unit  # mm, mm/s


GPS_EPOCH = np.datetime64("1980-01-06T00:00:00", "s")


#: what a relative survey (summary.toml ``[survey] kind = "relative"``) measures, on every report
RELATIVE_SURVEY_TEXT = ("relative survey: no GNSS, no prism fixes (IMU, odometer and stops); gauge, cant, twist and "
                        "the chord checks are measured, coordinates and deviations from the design are not")


def is_relative(summary: dict) -> bool:
    return summary.get("survey", {}).get("kind") == "relative"


def survey_title(content: ReportContent) -> str:
    """The survey's name, with "(relative survey)" after it for a relative one."""
    return t("{survey} (relative survey)").format(survey=content.survey) if is_relative(content.summary) else content.survey


def mounting_text(summary: dict) -> str | None:
    """The IMU mounting the survey was processed with and the survey's estimate (summary.toml
    ``[fusion.mounting]``), or None for results without it."""
    mounting = summary.get("fusion", {}).get("mounting")
    if not mounting:
        return None
    parts = []
    for axis in ("roll", "pitch", "yaw"):
        entry = mounting[axis]
        if "estimate_deg" in entry:
            estimate = t("{axis} {estimate:+.3f}° ± {sigma:.3f}°").format(
                axis=t(axis), estimate=entry["estimate_deg"], sigma=entry["sigma_deg"])
            parts.append(estimate + (t(" (applied)") if entry["applied"] else ""))
        else:
            parts.append(t("{axis} not estimated ({reason})").format(axis=t(axis), reason=why_of(entry).said()))
    applied = ", ".join(f"{v:+.3f}" for v in mounting["applied_rpy_deg"])
    given = ", ".join(f"{v:+.3f}" for v in mounting["given_rpy_deg"])
    return t("processed with roll, pitch, yaw [{applied}]° (survey.toml [{given}]°); estimated from the survey: "
             "{estimates}").format(applied=applied, given=given, estimates=t("; ").join(parts))


def odometer_pair_text(summary: dict) -> str | None:
    """The two odometers compared (summary.toml ``[fusion.odometer_pair]``, ``insrail.nav.odometer_pair``):
    their relative scale and each slipping stretch; None for a survey with one odometer."""
    pair = summary.get("fusion", {}).get("odometer_pair")
    if not pair:
        return None
    parts = [t("the right wheel counts {scale:+.2f} per mille against the left one (put on its scale)").format(
        scale=1e3 * pair["relative_scale"])]
    for slip in pair.get("slips", []):
        where = dict(slip=abs(slip["slip_percent"]), start=slip["start_s"], end=slip["end_s"], low=slip["from_m"],
                     high=slip["to_m"])
        if slip["wheel"] == "either":
            parts.append(t("the wheels disagree by {slip:.1f} % from {start:.1f} to {end:.1f} s ({low:.0f}-{high:.0f} m "
                           "travelled): both left out there").format(**where))
        else:
            parts.append(t("{wheel} slipped {slip:.1f} % from {start:.1f} to {end:.1f} s ({low:.0f}-{high:.0f} m "
                           "travelled): left out there, bridged by the other wheel").format(
                wheel=t(f"{slip['wheel']} wheel"), **where))
    if len(parts) == 1:
        parts.append(t("no slip found"))
    return t("; ").join(parts)


def survey_start(content: ReportContent) -> str:
    """Date and GPS time of the first sleeper ("2025-08-21 16:05 GPST"), or "" without the GPS week."""
    week = content.summary.get("survey", {}).get("gps_week")
    time = content.results.columns.get("time_s")
    if week is None or time is None or not np.isfinite(time).any():
        return ""
    moment = GPS_EPOCH + np.timedelta64(int(week) * 7 * 86400 + int(np.nanmin(time)), "s")
    return str(moment).replace("T", " ")[:16] + " GPST"


# --------------------------------------------------------------------------- tamping re-design (insrail redesign)

#: tamping.csv's marks of the re-designed line's key points (insrail.track.alignment's joint labels) in words.
TAMPING_MARKS = {"TS": "TS (tangent to spiral)", "SC": "SC (spiral to curve)", "CS": "CS (curve to spiral)",
                 "ST": "ST (spiral to tangent)", "PC": "PC (tangent to curve)", "PT": "PT (curve to tangent)",
                 "SS": "SS (spiral to spiral)", "POT": "POT (tangent to tangent)", "PVI": "PVI (vertical intersection)"}
#: the bounds a re-design's active stretches name (insrail.track.redesign._active), as summary.toml writes them
REDESIGN_BOUNDS = ("lift at max_lift", "slew at max_slew", "lift at min_lift", "fixed stretch")


def fixed_source_name(source: str) -> str:
    """Where a fixed stretch came from: a key of project.toml as written (``redesign.fixed[0]``), or an event
    of the survey (its kind's name and its text)."""
    from insrail.track.events import KIND_NAMES

    kind, _, text = source.partition(" ")
    return f"{t(KIND_NAMES[kind])} {text}".strip() if kind in KIND_NAMES else source


def tamping_mark_name(mark: str) -> str:
    """A mark of tamping.csv (``TS``, ``PVI``, ``fixed start (turnout W12)``) in the report's language."""
    if mark.endswith(")"):
        if mark.startswith("fixed start ("):
            return t("fixed start ({source})").format(source=fixed_source_name(mark[len("fixed start ("):-1]))
        if mark.startswith("fixed end ("):
            return t("fixed end ({source})").format(source=fixed_source_name(mark[len("fixed end ("):-1]))
    return t(TAMPING_MARKS[mark]) if mark in TAMPING_MARKS else mark


def redesign_bound_name(what: str, profile: ToleranceProfile) -> str:
    """What holds a stretch of a re-design (a bound of REDESIGN_BOUNDS) or fails there after the job (summary.toml
    writes "<check id> <rail> <direction>"): the display name."""
    if what in REDESIGN_BOUNDS:
        return t(what)
    name, *channel = what.split(" ")
    check = next((c for c in profile.checks if c.name == name), None)
    if check is None or len(channel) > 2:
        return what  # a profile changed since the re-design: the id as written
    return channel_name(check, *(channel + ["", ""])[:2]) if channel else check_name(check)



#: Per check and rail, up to this many stretches passing by less than their uncertainty are listed one by one in the
#: reports; more as one row from the first to the last (summary.toml lists each).
LISTED_UNCERTAIN = 5


def redesign_not_passing(summary: dict, profile: ToleranceProfile) -> list[tuple[str, float, float, float]]:
    """Where the re-design does not say the track passes after the job (redesign/summary.toml), as
    (what, from [m], to [m], value [mm]) rows: each stretch that cannot pass under the constraints; per
    check and rail, the stretches that pass by less than the survey's uncertainty (first to last, the
    largest value, how many: summary.toml lists each); each check the survey cannot assess there
    (its stated 1-sigma as the value). Summaries of before the survey's accuracy was taken: the first."""
    rows = [(t("cannot pass: {what}").format(what=redesign_bound_name(c["what"], profile)), c["from_m"], c["to_m"],
             c["value_mm"]) for c in summary["cannot_pass"]]
    close: dict[str, list[dict]] = {}
    for stretch in summary.get("uncertain", []):
        close.setdefault(stretch["what"], []).append(stretch)
    for what, stretches in close.items():
        name = redesign_bound_name(what, profile)
        if len(stretches) <= LISTED_UNCERTAIN:
            rows += [(t("passes by less than its uncertainty: {what}").format(what=name), s["from_m"], s["to_m"],
                      s["value_mm"]) for s in stretches]
        else:
            rows.append((t("passes by less than its uncertainty ({count} stretches): {what}").format(
                count=len(stretches), what=name), stretches[0]["from_m"], stretches[-1]["to_m"],
                max((s["value_mm"] for s in stretches), key=abs)))
    for item in summary.get("not_assessed", []):
        what = redesign_bound_name(f"{item['check']} track {item['direction']}".strip(), profile)
        for start, end in item["stretches_m"]:
            rows.append((t("not assessed: {what} (stated 1-sigma {sigma_mm:.2f} mm against the limit {limit_mm:.1f} mm)")
                         .format(what=what, sigma_mm=item["sigma_mm"], limit_mm=item["limit_mm"]), start, end,
                         item["sigma_mm"]))
    return sorted(rows, key=lambda row: row[1])