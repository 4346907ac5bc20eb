"""Repeat runs of a project compared (thesis §5.4.2): ``results/repeatability.csv`` and ``.toml``.

Each survey's stored results (``load_results``) give its sleeper stations and values; the
deviations of both rails, gauge, cant and every irregularity check in millimetres are compared
by chainage with :func:`insrail.track.repeatability.repeatability` (the first survey named is
the reference). Invalid sleepers take no part.

* ``repeatability.csv``  one row per reference sleeper: ``station_m``, ``label``, then per
  parameter and compared run ``<run>_minus_<reference>_<parameter>`` (mm; empty where not comparable)
* ``repeatability.toml`` per parameter and run: count, mean, std, RMS, 95th percentile and
  maximum of |difference| in mm, and the single-run repeatability (pooled std / sqrt 2); per
  parameter ``compared`` = "signed" or "magnitude": the differential-versine checks (30 m/5 m,
  300 m/150 m) are compared by |value|, because the sign of their worst value over the chord
  placements flips between runs wherever two placements tie, and only where both runs reach a
  chord length either side (:mod:`insrail.track.repeatability`)
"""

from __future__ import annotations

import csv
import io
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import tomli_w

from insrail.io.atomic import atomic_write
from insrail.io.errors import InputError
from insrail.notices import Phrase
from insrail.progress import CancelToken, ProgressFn, StepProgress, check_cancel
from insrail.project.model import Project
from insrail.project.results import RESULTS_FOLDER, load_results
from insrail.track.repeatability import Repeatability, repeatability
from insrail.track.tolerance import load_tolerance_profile

#: Check kinds whose value per sleeper is the signed worst over several chord placements.
WORST_OVER_PLACEMENTS = frozenset({"differential_versine"})

REPEATABILITY_FILE = "repeatability.csv"
REPEATABILITY_SUMMARY = "repeatability.toml"
#: Compared in this order, then every ``check_*_mm`` irregularity column.
BASE_PARAMETERS = ("lateral_deviation_left_mm", "lateral_deviation_right_mm", "vertical_deviation_left_mm",
                   "vertical_deviation_right_mm", "gauge_mm", "cant_mm")


def compared_parameters(columns) -> list[str]:
    """The sleepers.csv columns worth comparing between runs (values in mm)."""
    return [c for c in BASE_PARAMETERS if c in columns] + [c for c in columns if c.startswith("check_") and c.endswith("_mm")]


def worst_over_placements(project: Project, columns) -> dict[str, float]:
    """The check columns whose value is the worst over chord placements (the project's differential
    versines, 30 m/5 m and 300 m/150 m), each with its chord length [m]: compared by magnitude where
    both runs are complete a chord length either side (:mod:`insrail.track.repeatability`)."""
    profile = load_tolerance_profile(project.resource(project.tolerance_profile))
    chords = {f"check_{check.name}_": float(check.chord_m) for check in profile.checks
              if check.kind in WORST_OVER_PLACEMENTS}
    return {c: chord for c in compared_parameters(columns) for prefix, chord in chords.items() if c.startswith(prefix)}


def compare_surveys(project: Project, names: list[str] | None = None, progress: ProgressFn | None = None,
                    cancel: CancelToken = None) -> tuple[Repeatability, Path]:
    """Compare the processed surveys ``names`` (default: every survey of the project, the first
    being the reference); writes the two files into ``<project>/results/`` and returns the
    comparison (values in metres) and the CSV's path."""
    names = list(names) if names else [s.name for s in project.surveys]
    if len(names) < 2:
        raise ValueError(f"{project.path}: comparing runs needs at least two surveys, got {', '.join(names) or 'none'}")
    step = StepProgress(progress)
    runs, labels, placements = {}, (), {}
    for index, name in enumerate(names):
        check_cancel(cancel)
        step(index / len(names), Phrase("reading the results of {survey}", {"survey": name}))
        project.survey(name)  # an unknown name fails here, listing the project's surveys
        stored = load_results(project.folder, name)
        valid = (stored.columns["valid"] > 0) & np.isfinite(stored.columns["station_m"])
        runs[name] = (stored.columns["station_m"][valid],
                      {column: 1e-3 * stored.columns[column][valid] for column in compared_parameters(stored.columns)})
        if index == 0:
            labels = tuple(label for label, ok in zip(stored.label, valid) if ok)
            placements = worst_over_placements(project, stored.columns)
    step(0.9, "comparing")
    result = repeatability(runs, placements_m=placements)
    folder = project.folder / RESULTS_FOLDER
    with atomic_write(folder / REPEATABILITY_FILE) as handle:
        handle.write(_csv(result, labels))
    with atomic_write(folder / REPEATABILITY_SUMMARY, "wb") as handle:
        tomli_w.dump(_summary(result), handle)
    step(1.0, "done")
    return result, folder / REPEATABILITY_FILE


def _csv(result: Repeatability, labels: tuple[str, ...]) -> str:
    names = [f"{run}_minus_{result.reference}_{p.name}" for p in result.parameters for run in result.compared]
    header = ",".join(["station_m", "label", *names]) + "\n"
    if not result.station_m.size:
        return header
    values = np.column_stack([result.station_m] + [1e3 * row for p in result.parameters for row in p.difference])
    block = io.StringIO()
    np.savetxt(block, values, fmt=["%.4f"] + ["%.3f"] * len(names), delimiter=",")
    rows = block.getvalue().replace("nan", "").splitlines()
    return header + "".join(f"{row.split(',', 1)[0]},{label},{row.split(',', 1)[1] if names else ''}\n"
                            for row, label in zip(rows, labels))


def _mm(value: float) -> float:
    return round(1e3 * float(value), 4)


def _summary(result: Repeatability) -> dict:
    parameters = {}
    for p in result.parameters:
        entry: dict = {"single_run_std_mm": _mm(p.single_run_std), "compared": "magnitude" if p.by_magnitude else "signed"}
        for k, run in enumerate(result.compared):
            entry[run] = {"count": int(p.count[k]), "mean_mm": _mm(p.mean[k]), "std_mm": _mm(p.std[k]),
                          "rms_mm": _mm(p.rms[k]), "p95_abs_mm": _mm(p.p95_abs[k]), "max_abs_mm": _mm(p.max_abs[k])}
        parameters[p.name.removesuffix("_mm")] = entry
    return {"reference": result.reference, "compared": list(result.compared), "stations": int(result.station_m.size),
            "file": REPEATABILITY_FILE, "parameters": parameters}


# --------------------------------------------------------------------------- reading back

@dataclass(frozen=True)
class StoredRepeatability:
    """A comparison as ``compare_surveys`` wrote it (values in mm, as in the files).

    difference_mm : sleepers.csv column (``gauge_mm``, ...) -> (len(compared), n) run minus reference
                    at the reference stations, NaN where not comparable
    statistics    : repeatability.toml's ``parameters`` table (per parameter and run)
    written_s     : modification time of repeatability.toml (POSIX seconds), to tell a stale comparison
    """

    reference: str
    compared: tuple[str, ...]
    station_m: np.ndarray
    label: tuple[str, ...]
    difference_mm: dict[str, np.ndarray]
    statistics: dict
    written_s: float

    def includes(self, survey: str) -> bool:
        return survey == self.reference or survey in self.compared


def load_repeatability(project_folder: Path) -> StoredRepeatability | None:
    """The last comparison of repeat runs in ``<project_folder>/results/`` (None when there is none);
    damaged files raise InputError naming them."""
    folder = Path(project_folder) / RESULTS_FOLDER
    summary_path, csv_path = folder / REPEATABILITY_SUMMARY, folder / REPEATABILITY_FILE
    if not summary_path.is_file():
        return None
    try:
        summary = tomllib.loads(summary_path.read_text(encoding="utf-8"))
        reference, compared = summary["reference"], tuple(summary["compared"])
        statistics = summary["parameters"]
    except (tomllib.TOMLDecodeError, KeyError, TypeError) as error:
        raise InputError(summary_path, None, "not a repeatability summary written by insrail compare ({error})", fields={"error": error}) from None
    if not csv_path.is_file():
        raise InputError(csv_path, None, "missing: run insrail compare again")
    with open(csv_path, newline="", encoding="utf-8") as handle:
        rows = list(csv.reader(handle))
    header, body = rows[0], rows[1:]
    try:
        values = np.array([[float(v) if v else np.nan for i, v in enumerate(row) if i != 1] for row in body],
                          dtype=float).reshape(len(body), len(header) - 1)
    except ValueError as error:
        raise InputError(csv_path, None, "expected numbers after the label column ({error})", fields={"error": error}) from None
    column = {name: i for i, name in enumerate(header[:1] + header[2:])}
    difference = {}
    for parameter in statistics:
        name = parameter + "_mm"
        keys = [f"{run}_minus_{reference}_{name}" for run in compared]
        missing = [k for k in keys if k not in column]
        if missing:
            raise InputError(csv_path, 1, "no column {missing!r} although repeatability.toml lists {parameter!r}", fields={"missing": missing[0], "parameter": parameter})
        difference[name] = np.array([values[:, column[k]] for k in keys])
    return StoredRepeatability(reference, compared, values[:, 0], tuple(row[1] for row in body), difference,
                               statistics, summary_path.stat().st_mtime)
