"""``insrail redesign``: a processed survey's tamping re-design (:mod:`insrail.track.redesign`) and its
files in ``results/<survey>/redesign/``.

* ``tamping.csv`` (:mod:`insrail.export.tamping` reads it back): one row per sleeper and one at each
  key point of the re-designed line (TS/SC/CS/ST, PVI) and at each fixed stretch's ends.
* ``design.csv`` and ``design.xml``: the line types fitted to the track as it will be after the job
  (the measured centreline moved by the corrections; :func:`insrail.track.linefit.fit_alignment`),
  an element table and LandXML that ``[track] design`` of the next survey can name.
* ``exceedances_after.csv``: the profile's checks on the measured rails moved by the amounts (the
  checks the survey can assess there: the processing's rule).
* ``summary.toml``: the settings (with the fixed stretches and where each came from, and how far
  inside its limit each check was held), the largest lift and slew, where the bounds hold, and the
  stretches where the track is not predicted to pass after the job: those that cannot pass under
  the constraints, those that pass by less than the survey's uncertainty of the check, and the
  checks the survey cannot assess there (``not_assessed``); the exceedances before and after.

What the survey's accuracy allows (quality.csv, :mod:`insrail.project.assessable`): a check is
assessed where three of its stated 1-sigma fit within its limit, as in the processing; where it is
assessed, the re-design holds it that far (three 1-sigma, at least ``margin_mm``) inside its limit,
so that the true track moved by the amounts passes too, and a value after the job closer to its
limit is listed as passing by less than its uncertainty.

The settings are resolved once (:func:`resolve_settings`): project.toml's ``[redesign]`` with, by
default, every turnout, level crossing and bridge of the survey's events (summary.toml ``[[events]]``,
already placed on the survey's chainage) as a fixed stretch.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from pathlib import Path

import numpy as np

from insrail.io.atomic import atomic_write
from insrail.progress import CancelToken, ProgressFn, StepProgress, check_cancel
from insrail.project import assessable
from insrail.project.assessable import NotAssessable
from insrail.project.model import Project, RedesignTable
from insrail.project.results import StoredQuality, exceedances_csv, load_results, summary_toml
from insrail.quality.section_quality import SectionQuality
from insrail.track.alignment_csv import format_alignment_csv
from insrail.track.exceedance import SleeperGeometry, assess
from insrail.track.landxml import format_landxml
from insrail.track.linefit import AlignmentFit, LineFitError, fit_alignment
from insrail.track.redesign import FixedStretch, Redesign, RedesignSettings, judged_only, moved, redesign
from insrail.track.stationing import StationEquations
from insrail.track.tolerance import ToleranceProfile, load_tolerance_profile

REDESIGN_FOLDER = "redesign"
TAMPING_FILE = "tamping.csv"
DESIGN_CSV = "design.csv"
DESIGN_XML = "design.xml"
EXCEEDANCES_AFTER_FILE = "exceedances_after.csv"
SUMMARY_FILE = "summary.toml"
#: The events whose track the machine must not move unless ``[redesign]`` says otherwise.
FIXED_EVENT_KINDS = ("turnout", "level_crossing", "bridge")


def resolve_settings(table: RedesignTable, events: list[dict]) -> RedesignSettings:
    """``[redesign]`` (millimetres as written) with the survey's fixed events, in metres."""
    fixed = [FixedStretch(f.from_m, f.to_m, 1e-3 * f.tolerance_mm, f"redesign.fixed[{i}]")
             for i, f in enumerate(table.fixed)]
    if table.fix_events:
        fixed += [FixedStretch(float(e["station_from_m"]), float(e["station_to_m"]), 0.0,
                               f"{e['kind']} {e.get('text', '')}".strip())
                  for e in events if e.get("kind") in FIXED_EVENT_KINDS]
    return RedesignSettings(lift_only=table.lift_only, min_lift_m=1e-3 * table.min_lift_mm,
                            max_lift_m=1e-3 * table.max_lift_mm, max_slew_m=1e-3 * table.max_slew_mm,
                            margin_m=1e-3 * table.margin_mm, fixed=tuple(fixed))


@dataclass(frozen=True)
class TampingRow:
    """One row of tamping.csv (millimetres, + up / + right / + left rail higher)."""

    station_m: float
    label: str
    lift_left_mm: float
    lift_right_mm: float
    slew_mm: float
    cant_mm: float
    mark: str


@dataclass(frozen=True)
class RedesignRun:
    survey: str
    folder: Path
    result: Redesign
    fit: AlignmentFit | None
    fit_problem: str  # why no design was fitted ("" when it was)
    rows: tuple[TampingRow, ...]
    summary: dict


def measured_geometry(columns: dict[str, np.ndarray], number: np.ndarray) -> tuple[SleeperGeometry, np.ndarray]:
    """The measured geometry of every sleeper with a measurement (those inside events too: the chords
    read them) and which sleepers the profile judges (``valid``)."""
    pair = lambda name: 1e-3 * np.column_stack([columns[f"{name}_left_mm"], columns[f"{name}_right_mm"]])  # noqa: E731
    geometry = SleeperGeometry.from_arrays(
        columns["station_m"], pair("lateral_deviation"), pair("vertical_deviation"), 1e-3 * columns["gauge_mm"],
        1e-3 * columns["cant_mm"], 1e-3 * np.nan_to_num(columns["design_cant_mm"]), sleeper_number=number)
    return geometry, columns["valid"] > 0


def section_quality(stored: StoredQuality | None) -> SectionQuality | None:
    """quality.csv as read back (millimetres) as the figures the assessable rule takes (metres)."""
    if stored is None:
        return None
    sigmas = {f.name: 1e-3 * getattr(stored, f.name[:-2] + "_mm") for f in fields(SectionQuality)
              if f.name.startswith("sigma_")}
    return SectionQuality(stored.station_from_m, stored.station_to_m, smoothed=stored.smoothed, **sigmas)


@dataclass(frozen=True)
class SurveyUncertainty:
    """What the survey's stated accuracy allows the re-design to promise: per (check name, direction)
    how far inside its limit a value must be for the true track to pass (three stated 1-sigma, per
    sleeper [m]), and the checks it cannot assess where (:mod:`insrail.project.assessable`)."""

    within_m: dict[tuple[str, str], np.ndarray]
    not_assessable: list[NotAssessable]

    def masks(self) -> dict[tuple[str, str], np.ndarray]:
        return assessable.masks(self.not_assessable)


def survey_uncertainty(profile: ToleranceProfile, quality: StoredQuality | None, station_m: np.ndarray) -> SurveyUncertainty:
    """The one assessable rule applied to a re-design (none stated: nothing to draw in, all assessed)."""
    figures = section_quality(quality)
    sigmas = assessable.sleeper_sigmas(profile, figures, station_m)
    return SurveyUncertainty({key: assessable.RESOLVE_SIGMAS * sigma for key, sigma in sigmas.items()},
                             assessable.not_assessable(profile, figures, station_m))


def _labeller(project: Project):
    """Station -> displayed chainage, with the design's station equations (K-chainage without one)."""
    from insrail.project.pipeline import read_design  # the processing's filter: not for the reports' tamping names

    equations = read_design(project.resolve(project.design)).station_equations if project.design else StationEquations()
    return lambda stations: list(equations.label(np.atleast_1d(stations)))


def _centre_after(columns: dict[str, np.ndarray], result: Redesign) -> tuple[np.ndarray, ...]:
    """The centreline moved by the corrections: slewed along the track's own normal (from the
    neighbouring sleepers), lifted by the mean of the rails' lifts."""
    east, north, height = columns["centre_E_m"], columns["centre_N_m"], columns["centre_H_m"]
    ok = np.isfinite(east) & np.isfinite(north) & np.isfinite(height) & np.isfinite(result.slew_m)
    ok &= np.all(np.isfinite(result.lift_m), axis=1)
    e, n, h = east[ok], north[ok], height[ok]
    de, dn = np.gradient(e), np.gradient(n)
    length = np.hypot(de, dn)
    right = np.column_stack([dn / length, -de / length])  # the right normal of the direction of the stationing
    slew, lift = result.slew_m[ok], result.lift_m[ok].mean(axis=1)
    cant = 1e-3 * columns["cant_mm"][ok] + result.cant_change_m()[ok]
    return columns["station_m"][ok], e + slew * right[:, 0], n + slew * right[:, 1], h + lift, cant


def _marks(result: Redesign, fit: AlignmentFit | None) -> list[tuple[float, str]]:
    """(station, mark) of the re-designed line's key points and the fixed stretches' ends."""
    marks = []
    if fit is not None:
        marks += [(k.station_m, k.label) for k in fit.alignment.horizontal.key_points() if k.label not in ("POB", "POE")]
        marks += [(p.station_m, "PVI") for p in fit.alignment.vertical.pvis[1:-1]]
    for stretch in result.settings.fixed:
        marks += [(stretch.from_m, f"fixed start ({stretch.source})"), (stretch.to_m, f"fixed end ({stretch.source})")]
    first, last = np.nanmin(result.station_m), np.nanmax(result.station_m)
    return sorted((s, m) for s, m in marks if first <= s <= last)


def tamping_rows(result: Redesign, cant_after_m: np.ndarray, labels, fit: AlignmentFit | None) -> tuple[TampingRow, ...]:
    """One row per sleeper with a correction, and one at each mark with the corrections interpolated."""
    station = result.station_m
    ok = np.all(np.isfinite(result.lift_m), axis=1) & np.isfinite(result.slew_m) & np.isfinite(cant_after_m)
    values = np.column_stack([result.lift_m, result.slew_m, cant_after_m])[ok] * 1e3
    rows = [(s, "", *v) for s, v in zip(station[ok], values)]
    for s, mark in _marks(result, fit):
        rows.append((s, mark, *(np.interp(s, station[ok], values[:, c]) for c in range(4))))
    rows.sort(key=lambda r: (r[0], r[1] != ""))
    label = labels(np.array([r[0] for r in rows]))
    return tuple(TampingRow(float(s), text, float(a), float(b), float(c), float(d), mark)
                 for (s, mark, a, b, c, d), text in zip(rows, label))


def _stretches(stretches) -> list[dict]:
    return [{"from_m": round(s.station_from_m, 3), "to_m": round(s.station_to_m, 3), "what": s.what,
             "value_mm": round(1e3 * s.value_m, 2)} for s in stretches]


def _summary(survey: str, profile_name: str, result: Redesign, fit_problem: str, not_assessed: list[dict]) -> dict:
    lift, slew = result.lift_m, result.slew_m
    at = lambda values: float(result.station_m[int(np.nanargmax(np.abs(values)))])  # noqa: E731
    settings = result.settings
    return {
        "survey": survey,
        "profile": profile_name,
        "settings": {"lift_only": settings.lift_only, "min_lift_mm": 1e3 * settings.min_lift_m,
                     "max_lift_mm": 1e3 * settings.max_lift_m, "max_slew_mm": 1e3 * settings.max_slew_m,
                     "margin_mm": 1e3 * settings.margin_m,
                     "held_inside_mm": [{"check": check, "direction": direction, "margin_mm": round(1e3 * margin, 3)}
                                        for (check, direction), margin in result.margin_m.items()],
                     "fixed": [{"from_m": f.from_m, "to_m": f.to_m, "tolerance_mm": 1e3 * f.tolerance_m, "source": f.source}
                               for f in settings.fixed]},
        "movement": {"largest_lift_mm": round(1e3 * float(np.nanmax(lift)), 2), "largest_lift_at_m": at(np.nanmax(lift, axis=1)),
                     "smallest_lift_mm": round(1e3 * float(np.nanmin(lift)), 2),
                     "largest_slew_mm": round(1e3 * float(np.nanmax(np.abs(slew))), 2), "largest_slew_at_m": at(slew),
                     "total_movement_m": round(result.total_movement_m, 4),
                     "sleepers_moved": int(np.sum((np.nanmax(np.abs(lift), axis=1) > 5e-4) | (np.abs(slew) > 5e-4)))},
        "exceedances": {"before": len(result.before.exceedances), "after": len(result.after.exceedances),
                        "uncertain_after": len(result.uncertain), "checks_not_assessed": len(not_assessed)},
        "active": _stretches(result.active),
        "binding_check_values": result.binding_rows,
        "cannot_pass": _stretches(result.cannot_pass),
        "uncertain": _stretches(result.uncertain),
        "not_assessed": not_assessed,
        "design": {"fitted": not fit_problem, "problem": fit_problem,
                   "files": [DESIGN_CSV, DESIGN_XML] if not fit_problem else []},
        "files": {"tamping": TAMPING_FILE, "exceedances_after": EXCEEDANCES_AFTER_FILE},
    }


#: tamping.csv's notes for people (the reports give them in their language: insrail.names_zh has them)
TAMPING_AMOUNTS = ("lift_left_mm, lift_right_mm, slew_mm: move the rail (the track) by the amount after which the "
                   "track passes the profile's chord checks by at least the survey's uncertainty (docs/tamping.md), "
                   "except in the stretches summary.toml lists (cannot pass, passes by less than its uncertainty, "
                   "not assessed); cant_mm = the cant after the job")
TAMPING_CONVENTION = ("mm; lift + up; slew + to the right looking towards increasing chainage; cant + left rail higher; "
                      "mark: TS/SC/CS/ST, PVI of the re-designed line, fixed start/end")
TAMPING_HEADER = ["station_m", "label", "lift_left_mm", "lift_right_mm", "slew_mm", "cant_mm", "mark"]


def tamping_csv_text(rows: tuple[TampingRow, ...], survey: str, profile_name: str) -> str:
    """tamping.csv: a ``#`` header with the sign conventions, then one row per sleeper and mark."""
    lines = [
        "# insrail tamping 1",
        f"# survey = {survey}",
        f"# profile = {profile_name}",
        f"# amounts = {TAMPING_AMOUNTS}",
        f"# convention = {TAMPING_CONVENTION}",
        ",".join(TAMPING_HEADER),
    ]
    for r in rows:
        mark = f'"{r.mark}"' if "," in r.mark else r.mark
        lines.append(f"{r.station_m:.4f},{r.label},{r.lift_left_mm:.1f},{r.lift_right_mm:.1f},{r.slew_mm:.1f},"
                     f"{r.cant_mm:.1f},{mark}")
    return "\n".join(lines) + "\n"


def run_redesign(project: Project, survey: str, progress: ProgressFn | None = None,
                 cancel: CancelToken = None) -> RedesignRun:
    """Re-design ``survey`` (processed) and write ``results/<survey>/redesign/`` (nothing when cancelled)."""
    step = StepProgress(progress)
    step(0.0, "reading the results")
    stored = load_results(project.folder, survey)
    geometry, assessed = measured_geometry(stored.columns, stored.number)
    profile = load_tolerance_profile(project.resource(project.tolerance_profile))
    settings = resolve_settings(project.redesign, stored.summary.get("events", []))
    uncertainty = survey_uncertainty(profile, stored.quality, geometry.station_m)
    result = redesign(geometry, profile, settings, assessed, StepProgress(progress, 0.05, 0.7), cancel,
                      uncertainty=uncertainty.within_m, not_assessed=uncertainty.masks())
    check_cancel(cancel)
    step(0.7, "fitting the line types to the track after the job")
    station, east, north, height, cant = _centre_after(stored.columns, result)
    fit, problem = None, ""
    try:
        fit = fit_alignment(station, east, north, height, cant_m=cant, name=f"{survey} after tamping")
    except (LineFitError, ValueError) as error:
        problem = f"no design fitted to the track after the job: {error}"
    check_cancel(cancel)
    step(0.95, "writing the re-design")
    cant_after = 1e-3 * stored.columns["cant_mm"] + result.cant_change_m()
    rows = tamping_rows(result, cant_after, _labeller(project), fit)
    folder = stored.folder / REDESIGN_FOLDER
    folder.mkdir(exist_ok=True)
    everything = assess(judged_only(moved(geometry, result.lift_m, result.slew_m), assessed), profile)
    found = uncertainty.not_assessable
    summary = _summary(survey, profile.name, result, problem,
                       assessable.summary_section(found, assessable.left_out(found, everything, result.after)))
    files = {TAMPING_FILE: tamping_csv_text(rows, survey, profile.name),
             EXCEEDANCES_AFTER_FILE: "".join(exceedances_csv(result.after))}
    if fit is not None:
        files |= {DESIGN_CSV: format_alignment_csv(fit.alignment), DESIGN_XML: format_landxml([fit.alignment])}
    for name, text in files.items():
        with atomic_write(folder / name) as handle:
            handle.write(text)
    with atomic_write(folder / SUMMARY_FILE, "wb", encoding=None, newline=None) as handle:
        handle.write(summary_toml(summary))
    return RedesignRun(survey, folder, result, fit, problem, rows, summary)
