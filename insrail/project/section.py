"""A line section: several processed runs joined into one result on the stationing.

``[[sections]]`` in project.toml names the runs (and optionally a station range). The joined
result is written like a survey's, into ``<project>/results/<section>/`` (sleepers.csv,
exceedances.csv, quality.csv, summary.toml; no trajectory), so the workbook, the PDF and the
exports take it as they take a survey (:func:`insrail.project.results.load_results`).

Joining (runs in the order of their first station, each folded into the table so far):

* Each sleeper of a run is matched to the table's sleeper within half a sleeper spacing
  (:data:`MATCH_M`); unmatched sleepers (outside the overlap) are taken as they are, so outside
  an overlap the joined rows are the run's own rows.
* In an overlap a matched pair becomes one row: ``overlap = "best"`` takes the run with the
  better predicted accuracy at that station (quality.csv: the smaller hypot of the 5 m lag
  figures), or the valid one; ``"mean"`` takes, where both are valid, the mean of the measured
  quantities weighted by 1/σ² (σ: that figure), flags and times from the heavier run.
* ``source_<survey>`` columns give each row's weight of each run (1 taken, 0 not, a fraction in a
  weighted mean): every row says which run(s) it came from.
* Except where the track is: the coordinates and the deviations from the line carry each run's absolute
  error (a few millimetres, the GNSS's), so two runs differ by that much in an overlap, and a switch from
  one run to the other row by row would be a step that the chord checks read as track (a 13.6 mm step
  between two runs inside their 3 sigma gave false 10 m and 30 m / 5 m exceedances and a needless
  adjustment). These columns go over from the table's run to the new run across the stretch of the overlap
  where both are valid, along a half cosine (:func:`_position_taper`), whatever the rule: the difference is
  spread without a kink over the overlap and, where it is shorter, over :data:`SEAM_CHORDS` times the profile's
  longest chord centred on it, each run's rows there moved by their share of the difference held at its end
  values (8 mm over 187 m moved a 10 m versine by 0.02 mm and the 30 m / 5 m check by up to 0.6 mm, against 8 mm
  row by row; 14 mm over a 100 m overlap read 7 mm in the 300 m / 150 m check, over 1200 m 0.5 mm;
  tests/test_project_section.py). Where one of the two is not valid inside the taper, the row kept is moved by
  its share of the runs' difference interpolated from the rows around, so no row steps out of the taper.
* Sleepers are numbered continuously from the project's first sleeper number; the assessment
  (tolerance profile) and the adjustment are computed again on the joined table, so a chord
  across the seam uses both runs.
* A check a run cannot assess (its quality.csv, by the processing's rule: :mod:`insrail.project.assessable`)
  is not assessed, nor held by the adjustment, at the rows holding that run's values: those its ``source_``
  column takes (in a weighted mean: either run's) and every row of its overlaps, whatever the rule (the
  position columns go over from one run to the other there row by row). summary.toml
  ``[[assessment.not_assessable]]`` and a warning (CLI, PDF, workbook) say which checks were left out where,
  as a survey's do, and by which runs' figures (``surveys``, per stretch): the section says no more than its
  runs, and says it once (the runs' own warnings of it are not copied into the section's summary; their others are).

The overlap's run-to-run differences are computed as ``insrail compare`` computes them
(:func:`insrail.track.repeatability.repeatability`) and written to summary.toml
``[[section.overlaps]]``; a parameter whose RMS difference exceeds 3× the predicted σ of a
difference of two runs (√(σa² + σb²) of quality.csv's figure for it: position for the deviations,
5 m lag for 30 m / 5 m, 150 m lag for 300 m / 150 m) is a notice. The differential-versine checks
are compared by magnitude and not within a chord of the overlap's ends, where one run's value is the
worst of fewer chord placements (:mod:`insrail.track.repeatability`); a check the overlap is too
short for (the 300 m chord in a 500 m overlap) is left out.
"""

from __future__ import annotations

import math
import time
from concurrent.futures import Executor
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import tomli_w

from insrail.io.errors import InputError
from insrail.notices import Notice, Phrase
from insrail.progress import CancelToken, ProgressFn, StepProgress, check_cancel
from insrail.project import assessable, relative_survey
from insrail.project.compare import worst_over_placements
from insrail.project.lock import project_run
from insrail.project.assessable import NotAssessable
from insrail.project.model import Project, SectionEntry
from insrail.project.redesign import section_quality
from insrail.project.sleeper_integrity import reasons_of, reasons_section
from insrail.project.results import (
    EXCEEDANCES_FILE,
    QUALITY_FILE,
    QUALITY_HEADER,
    RESULTS_FOLDER,
    SLEEPERS_FILE,
    SUMMARY_FILE,
    StoredQuality,
    StoredResults,
    adjustment_section,
    columns_csv,
    exceedances_csv,
    load_results,
    sleeper_check_columns,
    track_quality_section,
    write_results,
)
from insrail.project.run_settings import SETTINGS_SECTION
from insrail.track.adjustment import load_fastener_type, optimise_amounts, reassess
from insrail.track.exceedance import SleeperGeometry, assess
from insrail.track.repeatability import repeatability
from insrail.track.tolerance import ToleranceProfile, load_tolerance_profile

#: A run's sleeper and the table's are the same sleeper when their stations differ by less than this
#: (half the 0.625 m spacing; the chainage of two runs agrees to centimetres).
MATCH_M = 0.3
#: Two runs' difference is spread over at least this many of the profile's longest chord: 14 mm between two
#: runs over a 100 m overlap read 7 mm in the 300 m / 150 m check (15 false exceedances in a 4-run section,
#: session 13), over 4 x 300 m 0.5 mm.
SEAM_CHORDS = 4.0
#: Overlap differences beyond this multiple of their predicted 1-sigma are a notice.
NOTICE_SIGMAS = 3.0
_RECOMPUTED = ("check_", "adjust_", "unresolved_", "source_")


@dataclass
class _Table:
    """The joined rows so far: columns (n,) each, per-row sigma and per-run weights."""

    columns: dict[str, np.ndarray]
    label: list[str]
    not_assessed: list[str]  # why a row is left out of the assessment ("" when it is not)
    sigma_mm: np.ndarray  # the accuracy figure of the row (for later folds)
    weights: dict[str, np.ndarray]
    # per run, the rows holding its values: its weight's, and over an overlap both runs' (the position columns go
    # over from one to the other there, row by row, whichever run the weights take)
    sources: dict[str, np.ndarray]


def _accuracy_mm(quality: StoredQuality | None, station_m: np.ndarray) -> np.ndarray:
    """hypot of the 5 m lag figures of the quality section holding each station (inf: unknown)."""
    if quality is None or not len(quality):
        return np.full(station_m.shape, np.inf)
    figure = np.hypot(quality.sigma_lag5_lateral_mm, quality.sigma_lag5_vertical_mm)
    index = np.clip(np.searchsorted(quality.station_from_m, station_m, side="right") - 1, 0, len(quality) - 1)
    values = figure[index]
    return np.where(np.isfinite(values), values, np.inf)


def _is_measured(name: str) -> bool:
    """Columns averaged in a weighted mean (flags, times and angles are taken from the heavier run)."""
    return name.endswith(("_m", "_mm", "_ratio", "_mm_per_s")) and name != "time_s"


def _run_table(results: StoredResults, names: list[str], columns: list[str], window: tuple[float, float]) -> _Table:
    c = results.columns
    keep = (c["station_m"] >= window[0]) & (c["station_m"] <= window[1])
    weights = {name: np.zeros(int(keep.sum())) for name in names}
    weights[results.survey][:] = 1.0
    reasons = results.not_assessed or ("",) * len(results)
    return _Table({k: c[k][keep].copy() for k in columns}, [lbl for lbl, k in zip(results.label, keep) if k],
                  [r for r, k in zip(reasons, keep) if k], _accuracy_mm(results.quality, c["station_m"][keep]), weights,
                  {name: weight > 0 for name, weight in weights.items()})


def _is_position(name: str) -> bool:
    """Columns saying where the track is (the module docstring: tapered across an overlap)."""
    return name.endswith(("_E_m", "_N_m", "_H_m")) or "_deviation_" in name


def _position_taper(station_m: np.ndarray, start: float, end: float, rises: bool, falls: bool) -> np.ndarray:
    """The new run's share (0..1) of the position columns at ``station_m`` in the taper ``start``..``end``: 0
    where the table's run goes on before it, rising along a half cosine (no kink at either end) to 1 where the new
    run goes on after it (``rises``); a run inside the table's (``rises`` and ``falls``): rising, then falling
    back."""
    length = max(end - start, 1e-9)
    rise = (station_m - start) / length if rises else np.ones_like(station_m)
    fall = (end - station_m) / length if falls else np.ones_like(station_m)
    return 0.5 * (1.0 - np.cos(np.pi * np.clip(np.minimum(rise, fall), 0.0, 1.0)))


def _fold(table: _Table, run: _Table, rule: str, seam_m: float) -> _Table:
    """Join ``run`` into ``table`` (see the module docstring); ``seam_m``: the shortest length the runs' difference
    is spread over (:func:`seam_length_m`)."""
    s, r = table.columns["station_m"], run.columns["station_m"]
    nearest = np.clip(np.searchsorted(s, r), 1, max(len(s) - 1, 1)) if len(s) else np.zeros(len(r), int)
    if len(s):
        candidates = np.stack([nearest - 1, np.minimum(nearest, len(s) - 1)])
        pick = np.argmin(np.abs(s[candidates] - r), axis=0)
        nearest = candidates[pick, np.arange(len(r))]
        matched = np.abs(s[nearest] - r) < MATCH_M
    else:
        matched = np.zeros(len(r), dtype=bool)
    columns = {k: v.copy() for k, v in table.columns.items()}
    sigma = table.sigma_mm.copy()
    weights = {k: v.copy() for k, v in table.weights.items()}
    sources = {k: v.copy() for k, v in table.sources.items()}
    label = np.array(table.label + [""], dtype=object)[:-1]  # an object array even when empty
    run_label = np.array(run.label + [""], dtype=object)[:-1]
    reason = np.array(table.not_assessed + [""], dtype=object)[:-1]
    run_reason = np.array(run.not_assessed + [""], dtype=object)[:-1]
    j = np.flatnonzero(matched)
    i = nearest[j]
    run_valid, table_valid = run.columns["valid"][j] > 0, table.columns["valid"][i] > 0
    if rule == "mean":
        mix, take = run_valid & table_valid, run_valid & ~table_valid
    else:
        mix, take = np.zeros(len(j), dtype=bool), run_valid & (~table_valid | (run.sigma_mm[j] < sigma[i]))
    for mine, theirs in ((columns, run.columns), (weights, run.weights), (sources, run.sources)):
        for k, values in mine.items():
            values[i[take]] = theirs[k][j[take]]
    sigma[i[take]], label[i[take]], reason[i[take]] = run.sigma_mm[j[take]], run_label[j[take]], run_reason[j[take]]
    if mix.any():
        im, jm = i[mix], j[mix]
        with np.errstate(divide="ignore"):
            wt, wr = 1.0 / np.maximum(sigma[im], 1e-6) ** 2, 1.0 / np.maximum(run.sigma_mm[jm], 1e-6) ** 2
        unknown = (wt == 0.0) | (wr == 0.0)  # no predicted accuracy: an equal mean
        share = np.where(unknown, 0.5, wr / np.where(unknown, 1.0, wt + wr))
        heavier_is_run = share > 0.5
        for k, values in columns.items():
            theirs = run.columns[k][jm]
            values[im] = ((1 - share) * values[im] + share * theirs if _is_measured(k)
                          else np.where(heavier_is_run, theirs, values[im]))
        for k, values in weights.items():
            values[im] = (1 - share) * values[im] + share * run.weights[k][jm]
        for k, values in sources.items():
            values[im] |= run.sources[k][jm]
        sigma[im] = np.where(unknown, np.minimum(sigma[im], run.sigma_mm[jm]), 1.0 / np.sqrt(wt + wr))
        label[im] = np.where(heavier_is_run, run_label[jm], label[im])
        reason[im] = np.where(heavier_is_run, run_reason[jm], reason[im])
    both = run_valid & table_valid
    label, reason = list(label), list(reason)
    extra = np.flatnonzero(~matched)
    columns = {k: np.concatenate([v, run.columns[k][extra]]) for k, v in columns.items()}
    sources = {k: np.concatenate([v, run.sources[k][extra]]) for k, v in sources.items()}
    if both.any():
        _taper_positions(columns, table, run, i, j, both, run_valid, table_valid, seam_m)
        # over the overlap the position columns take the runs' difference row by row (its noise too); beyond it, held
        # at its end values (smooth): there each row holds its own run's values only
        station = columns["station_m"]
        lo, hi = min(s[i[both]].min(), r[j[both]].min()), max(s[i[both]].max(), r[j[both]].max())
        overlap = (station >= lo) & (station <= hi)
        for k, values in sources.items():
            values[overlap] |= table.sources[k][i[both]].any() | run.sources[k][j[both]].any()
    weights = {k: np.concatenate([v, run.weights[k][extra]]) for k, v in weights.items()}
    sigma = np.concatenate([sigma, run.sigma_mm[extra]])
    label += [run.label[j] for j in extra]
    reason += [run.not_assessed[j] for j in extra]
    order = np.argsort(columns["station_m"], kind="stable")
    return _Table({k: v[order] for k, v in columns.items()}, [label[i] for i in order], [reason[i] for i in order],
                  sigma[order],
                  {k: v[order] for k, v in weights.items()}, {k: v[order] for k, v in sources.items()})


def _not_assessable(profile: ToleranceProfile, runs: list[StoredResults], table: _Table) -> list[NotAssessable]:
    """The checks the joined table leaves out where (:mod:`insrail.project.assessable`): at a row, those that a run
    whose values it holds (``_Table.sources``) cannot assess there, by the processing's rule on that run's
    quality.csv (as ``insrail redesign`` applies it), so the section says no more than its runs. A row of a
    weighted mean holds both runs' values, and one run's noise in a mean is still noise the limit cannot tell
    from the track: not assessable where either run could not assess it. Stretches: the rows left out."""
    station = table.columns["station_m"]
    found: dict[tuple[str, str], dict[str, NotAssessable]] = {}
    for run in runs:
        held = np.where(table.sources[run.survey], station, np.nan)  # a NaN station: no sleeper of this run
        for n in assessable.not_assessable(profile, section_quality(run.quality), held):
            found.setdefault((n.check, n.direction), {})[run.survey] = n
    joined = []
    for (check, direction), per_run in found.items():
        sleepers = np.logical_or.reduce([n.sleepers for n in per_run.values()])
        edges = np.flatnonzero(np.diff(np.r_[0, sleepers.astype(np.int8), 0]))
        stretches = tuple((float(station[a]), float(station[b - 1])) for a, b in zip(edges[::2], edges[1::2]))
        surveys = tuple(tuple(survey for survey, n in per_run.items() if n.sleepers[a:b].any())
                        for a, b in zip(edges[::2], edges[1::2]))
        joined.append(NotAssessable(check, direction, sleepers, max(n.sigma_m for n in per_run.values()),
                                    next(iter(per_run.values())).limit_m, stretches, surveys))
    return joined


def seam_length_m(profile: ToleranceProfile) -> float:
    """The shortest length two runs' difference is spread over: :data:`SEAM_CHORDS` of the profile's longest chord."""
    return SEAM_CHORDS * max((c.chord_m for c in profile.checks if c.chord_m), default=0.0)


def _taper_positions(columns: dict[str, np.ndarray], table: _Table, run: _Table, i: np.ndarray, j: np.ndarray,
                     both: np.ndarray, run_valid: np.ndarray, table_valid: np.ndarray, seam_m: float) -> None:
    """Move the joined position columns (``columns``: the table's rows, then the run's unmatched rows) from the
    table's run to the new run along a half cosine (the module docstring). ``i``/``j``: the matched rows of table
    and run; ``both``: of those, where both are valid. The runs' difference there is carried, held at its end
    values, over the rows of the taper where one is not. The taper spans the overlap, and where the table goes on
    before it and the run after it, at least ``seam_m`` centred on it: a few millimetres between two runs
    spread over a 100 m overlap are a long wave the 300 m / 150 m check reads as track."""
    s, r = table.columns["station_m"], run.columns["station_m"]
    start, end = r[j[both]].min(), r[j[both]].max()
    rises, falls = bool((s < start).any()), bool((s > end).any())
    if rises and not falls and (r > end).any() and end - start < seam_m:
        centre = 0.5 * (start + end)
        start, end = centre - 0.5 * seam_m, centre + 0.5 * seam_m
    station = columns["station_m"]
    from_run = np.ones(len(station), dtype=bool)  # the run's unmatched rows, and matched rows only it has valid
    from_run[: len(s)] = False
    from_run[i] = run_valid & ~table_valid
    rows = np.flatnonzero((station >= start) & (station <= end))
    share = _position_taper(station[rows], start, end, rises, falls)
    moved_from_run = from_run[rows]
    table_row = np.minimum(rows, len(s) - 1)
    for k, values in columns.items():
        if not _is_position(k):
            continue
        difference = run.columns[k][j[both]] - table.columns[k][i[both]]
        known = np.isfinite(difference)
        if not known.any():
            continue
        between = np.interp(station[rows], r[j[both]][known], difference[known])
        moved = np.where(moved_from_run, values[rows] - (1.0 - share) * between,
                         table.columns[k][table_row] + share * between)
        values[rows] = np.where(np.isfinite(moved), moved, values[rows])


# --------------------------------------------------------------------------- overlaps

#: The quality.csv figures behind the predicted sigma of a difference of two runs.
def _predicted_figure(parameter: str) -> tuple[str, str] | None:
    direction = "lateral" if "lateral" in parameter else "vertical" if "vertical" in parameter else None
    if direction is None:
        return None
    if parameter.startswith(("lateral_deviation", "vertical_deviation")):
        return f"sigma_{direction}_mm", direction
    if parameter.startswith("check_") and ("30m_5m" in parameter or "short_wave" in parameter):
        return f"sigma_lag5_{direction}_mm", direction
    if parameter.startswith("check_") and ("300m_150m" in parameter or "long_wave" in parameter):
        return f"sigma_lag150_{direction}_mm", direction
    return None


def _median_figure(quality: StoredQuality | None, figure: str, start: float, end: float) -> float:
    if quality is None:
        return math.nan
    inside = (quality.station_to_m > start) & (quality.station_from_m < end)
    values = getattr(quality, figure)[inside]
    values = values[np.isfinite(values)]
    return float(np.median(values)) if values.size else math.nan


def overlap_differences(a: StoredResults, b: StoredResults, placements_m: dict[str, float] | None = None) -> dict | None:
    """The run-to-run differences of two runs where both have valid sleepers (None without an overlap);
    ``placements_m``: the worst-over-placements checks and their chords, compared by magnitude and not
    within a chord of the overlap's ends, where one run's values are the worst of fewer placements
    (:mod:`insrail.track.repeatability`, :func:`insrail.project.compare.worst_over_placements`)."""
    from insrail.project.compare import compared_parameters

    runs, bounds = {}, []
    for run in (a, b):
        valid = (run.columns["valid"] > 0) & np.isfinite(run.columns["station_m"])
        bounds.append((float(run.columns["station_m"][valid].min()), float(run.columns["station_m"][valid].max())))
    start, end = max(bounds[0][0], bounds[1][0]), min(bounds[0][1], bounds[1][1])
    if not end > start:
        return None
    for run in (a, b):
        c = run.columns
        keep = (c["valid"] > 0) & (c["station_m"] >= start) & (c["station_m"] <= end)
        runs[run.survey] = (c["station_m"][keep], {p: 1e-3 * c[p][keep] for p in compared_parameters(c)})
    result = repeatability(runs, placements_m=placements_m)
    parameters = {}
    for p in result.parameters:
        if not p.count[0]:  # not comparable here (a 300 m chord in a shorter overlap): left out
            continue
        entry = {"compared": "magnitude" if p.by_magnitude else "signed",
                 "count": int(p.count[0]), "mean_mm": round(1e3 * float(p.mean[0]), 4),
                 "std_mm": round(1e3 * float(p.std[0]), 4), "rms_mm": round(1e3 * float(p.rms[0]), 4),
                 "max_abs_mm": round(1e3 * float(p.max_abs[0]), 4)}
        figure = _predicted_figure(p.name)
        if figure is not None:
            sigma = math.hypot(_median_figure(a.quality, figure[0], start, end),
                               _median_figure(b.quality, figure[0], start, end))
            if math.isfinite(sigma):
                entry["predicted_sigma_mm"] = round(sigma, 4)
                entry["exceeds"] = bool(entry["rms_mm"] > NOTICE_SIGMAS * sigma)
        parameters[p.name] = {k: v for k, v in entry.items() if not (isinstance(v, float) and not math.isfinite(v))}
    return {"runs": [a.survey, b.survey], "from_m": start, "to_m": end, "sleepers": int(result.station_m.size),
            "parameters": parameters}


# --------------------------------------------------------------------------- the joined result

@dataclass(frozen=True)
class SectionResult:
    name: str
    folder: Path
    summary: dict
    overlaps: tuple[dict, ...]
    notices: tuple[Notice, ...]  # the join's own (the overlaps', the checks left out); summary's also has the runs'
    # (but their checks not assessable, which the join's name the runs of)


def _format(name: str) -> str:
    if name in ("detected", "valid", "guiding_rail_right") or name.startswith("unresolved_"):
        return "%d"
    if name.startswith(("adjust_", "line_speed")):
        return "%.1f"
    if name.endswith(("_ratio", "_deg", "per_km")) or name.startswith("source_"):
        return "%.6f"
    if name.endswith(("_mm", "_mm_per_s")):
        return "%.3f"
    return "%.4f"


def _joined_quality(runs: list[StoredResults]) -> str:
    """quality.csv of the section: each run's sections beyond the stations the earlier runs cover."""
    rows, covered = [], -math.inf
    for run in runs:
        q = run.quality
        if q is None:
            continue
        for i in range(len(q)):
            if q.station_from_m[i] >= covered:
                rows.append([getattr(q, name)[i] for name in QUALITY_HEADER])
        covered = max(covered, float(np.nanmax(q.station_to_m)) if len(q) else covered)
    body = [",".join(f"{v:.3f}" if np.isfinite(v) else "" for v in row) for row in rows]
    return "\n".join([",".join(QUALITY_HEADER), *body]) + "\n"


def join_section(project: Project, name: str, progress: ProgressFn | None = None,
                 cancel: CancelToken = None, executor: Executor | None = None) -> SectionResult:
    """Join the section's processed runs and write ``<project>/results/<name>/`` (module docstring);
    the section's and its surveys' results locked meanwhile (:mod:`insrail.project.lock`).
    ``executor``: where the adjustment's independent parts are solved (a Dask cluster's, see
    :func:`insrail.track.adjustment.optimise_amounts`; default: threads here), the same amounts either way."""
    entry = project.section(name)
    with project_run(project.folder, [name, *entry.surveys], progress, cancel):
        return _join_section(project, entry, name, progress, cancel, executor)


def _join_section(project: Project, entry: SectionEntry, name: str, progress: ProgressFn | None, cancel: CancelToken,
                  executor: Executor | None) -> SectionResult:
    step = StepProgress(progress)
    started = time.monotonic()
    runs = []
    for i, survey in enumerate(entry.surveys):
        step(0.3 * i / len(entry.surveys), Phrase("reading the results of {survey}", {"survey": survey}))
        results = load_results(project.folder, survey)
        if results.quality is None and entry.overlap == "best":
            raise InputError(results.folder / QUALITY_FILE, None, "missing: the section's overlap rule 'best' needs the "
                                                                  "predicted accuracy; process the survey again")
        if not (results.columns["valid"] > 0).any():
            raise ValueError(Phrase("section {name}: survey {survey} has no valid sleeper", {"name": name, "survey": survey}))
        runs.append(results)
        check_cancel(cancel)
    profiles = {r.summary.get("assessment", {}).get("tolerance_profile") for r in runs}
    runs.sort(key=lambda r: float(np.nanmin(r.columns["station_m"][r.columns["valid"] > 0])))
    common = [k for k in runs[0].columns if all(k in r.columns for r in runs) and not k.startswith(_RECOMPUTED)]
    window = (entry.from_m if entry.from_m is not None else -math.inf, entry.to_m if entry.to_m is not None else math.inf)
    names = [r.survey for r in runs]
    table = _run_table(runs[0], names, common, window)
    profile = load_tolerance_profile(project.resource(project.tolerance_profile))
    seam_m = seam_length_m(profile)
    for run in runs[1:]:
        table = _fold(table, _run_table(run, names, common, window), entry.overlap, seam_m)
    if not len(table.label):
        raise ValueError(Phrase("section {name}: no sleeper of {surveys} lies between {start} and {end} m",
                                {"name": name, "surveys": ", ".join(names), "start": window[0], "end": window[1]}))
    step(0.4, "overlaps")
    placements = worst_over_placements(project, runs[0].columns)
    overlaps = tuple(o for o in (overlap_differences(a, b, placements) for i, a in enumerate(runs) for b in runs[i + 1:])
                     if o)
    check_cancel(cancel)

    step(0.5, "assessment on the joined table")
    c = table.columns
    n = len(table.label)
    number = project.first_sleeper_number + np.arange(n)
    geometry = SleeperGeometry.from_arrays(
        c["station_m"], 1e-3 * np.column_stack([c["lateral_deviation_left_mm"], c["lateral_deviation_right_mm"]]),
        1e-3 * np.column_stack([c["vertical_deviation_left_mm"], c["vertical_deviation_right_mm"]]),
        1e-3 * c["gauge_mm"], 1e-3 * c["cant_mm"], 1e-3 * c["design_cant_mm"], valid=c["valid"] > 0,
        sleeper_number=number,
        curvature_1pm=1e-3 * c["curvature_per_km"] if "curvature_per_km" in c else None,
        line_speed_mps=c["line_speed_kmh"] / 3.6 if "line_speed_kmh" in c and np.isfinite(c["line_speed_kmh"]).any()
        else None)
    unresolved = _not_assessable(profile, runs, table)
    not_assessed = assessable.masks(unresolved)
    everything = assessment = assess(geometry, profile)
    if unresolved:
        assessment = assess(geometry, profile, not_assessed=not_assessed)
    not_listed = assessable.left_out(unresolved, everything, assessment)
    check_cancel(cancel)
    step(0.6, "adjustment amounts")
    fastener = load_fastener_type(project.resource(project.fastener))
    strategy = project.adjustment.strategy
    lateral, vertical = optimise_amounts(geometry, profile, fastener, strategy, progress=step.sub(0.6, 0.95),
                                         cancel=cancel, threshold_m=project.adjustment.threshold_m, executor=executor,
                                         not_assessed=not_assessed)
    after_adjustment, adjustment = reassess(geometry, lateral, vertical, profile, fastener, not_assessed)
    columns = {k: (v, _format(k)) for k, v in c.items()}
    columns |= sleeper_check_columns(assessment, adjustment)
    columns |= {f"source_{run}": (table.weights[run], "%.6f") for run in names}

    notices = []
    for overlap in overlaps:
        for parameter, values in overlap["parameters"].items():
            if values.get("exceeds"):
                notices.append(Notice("section", "runs {runs} differ by {rms_mm:.2f} mm RMS in {parameter} over their "
                                                 "overlap ({from_m:.0f}-{to_m:.0f} m), more than {sigmas:g} x the "
                                                 "predicted {predicted_mm:.2f} mm", station_m=overlap["from_m"],
                                      fields={"runs": Phrase("{first} and {second}", dict(zip(("first", "second"),
                                                                                               overlap["runs"])))
                                              if len(overlap["runs"]) == 2 else list(overlap["runs"]),
                                              "rms_mm": values["rms_mm"],
                                              "parameter": parameter, "from_m": overlap["from_m"],
                                              "to_m": overlap["to_m"], "sigmas": NOTICE_SIGMAS,
                                              "predicted_mm": values["predicted_sigma_mm"]}))
    notices += assessable.notices(unresolved, not_listed)
    own = tuple(notices)
    # but their checks not assessable (an absolute run's, a relative run's by sections): the section's own
    # warning says where, naming the runs
    own_checks = (assessable.NOTICE, relative_survey.NOTICE)
    for run in runs:
        notices += [n for n in map(Notice.from_dict, run.summary.get("notices", [])) if n.template not in own_checks]
    counts: dict[str, int] = {}
    for e in assessment.exceedances:
        counts[e.check] = counts.get(e.check, 0) + 1
    first = runs[0].summary
    valid = c["valid"] > 0
    summary = {
        "survey": {"name": name, "folder": "", "imu_epochs": sum(r.summary.get("survey", {}).get("imu_epochs", 0)
                                                               for r in runs),
                   **({"gps_week": first["survey"]["gps_week"]} if "gps_week" in first.get("survey", {}) else {}),
                   "processing_time_s": round(time.monotonic() - started, 2)},
        "section": {"surveys": names, "overlap": entry.overlap, "overlaps": list(overlaps),
                    "from_m": float(c["station_m"][0]), "to_m": float(c["station_m"][-1]),
                    "profiles": sorted(p for p in profiles if p)},
        "heights": first.get("heights", {}),
        "track": {"design": first.get("track", {}).get("design", ""), "sleepers": n, "valid_sleepers": int(valid.sum()),
                  "station_from_m": float(c["station_m"][0]), "station_to_m": float(c["station_m"][-1]),
                  **({"parameters": first["track"]["parameters"]} if "parameters" in first.get("track", {}) else {})},
        "assessment": {"tolerance_profile": assessment.profile, "exceedances": len(assessment.exceedances),
                       "by_check": counts,  # the surveys' reasons its sleepers carry, for a report's language
                       "not_assessed_reasons": reasons_section(
                           reason for run in runs for reason in reasons_of(run.summary).values()),
                       "not_assessable": assessable.summary_section(unresolved, not_listed)},
        "adjustment": adjustment_section(adjustment, assessment, after_adjustment, project.adjustment, fastener),
        "track_quality": track_quality_section(geometry),
        "notices": [n.to_dict() for n in notices],
        "files": {"sleepers": SLEEPERS_FILE, "exceedances": EXCEEDANCES_FILE, "quality": QUALITY_FILE},
    }
    if "local_control" in first:
        summary["local_control"] = first["local_control"]
    if SETTINGS_SECTION in first:  # the runs share the project: the first run's settings stand for the section
        summary[SETTINGS_SECTION] = first[SETTINGS_SECTION]
    step(0.97, "writing the section's results")
    folder = write_results(project.folder / RESULTS_FOLDER, name, {
        SLEEPERS_FILE: columns_csv(number, tuple(table.label), columns, tuple(table.not_assessed)), EXCEEDANCES_FILE: exceedances_csv(assessment),
        QUALITY_FILE: _joined_quality(runs), SUMMARY_FILE: tomli_w.dumps(summary).encode("utf-8")}, cancel)
    step(1.0, "done")
    return SectionResult(name, folder, summary, overlaps, own)
