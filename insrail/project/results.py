"""The result files of one processed survey: written by the pipeline, read back by reports, GUI and batch.

``<project>/results/<survey>/`` holds

* ``trajectory.npy``   the fused trajectory (insrail.nav.trajectory.TRAJECTORY_DTYPE records)
* ``sleepers.csv``     one row per sleeper: ``number``, ``label`` (the broken-chainage label), then the
  columns of :func:`sleeper_columns`, each name ending in its unit (``_m``, ``_mm``, ``_ratio``) or a
  0/1 flag; an empty cell is a value that cannot be computed there (NaN)
* ``exceedances.csv``  one row per run of sleepers beyond a tolerance (:data:`EXCEEDANCE_HEADER`)
* ``quality.csv``      predicted 1-sigma accuracy per 200 m section of chainage (:data:`QUALITY_HEADER`:
  stations in m, sigmas in mm; empty where a section has no value); absent in results of older versions
* ``summary.toml``     settings used, headline numbers (``[trajectory]``: the trajectory's figures the PDF
  states, :func:`trajectory_section`), file list

A result folder is assembled beside the old one (``.<survey>.XXXX.new``) and swapped in only when
complete (:func:`write_results`), so a cancelled, failed or killed run leaves the previous results (or
none) and never a mixture. The swap is one atomic exchange of the two folders where the system has it
(Linux ``renameat2(RENAME_EXCHANGE)``): there is no moment without results. Elsewhere the old folder
is renamed aside (``.<survey>.old-PID``) and the new one into place; a crash between the two renames
is repaired by the next reader or run (:func:`recover_results` puts the old folder back), and staging
and old folders left by killed runs are removed then. Result files are copies, never links into the
cache. Readers see the files exactly as a user opening them in a spreadsheet would:
:func:`load_results` is the one way back.
"""

from __future__ import annotations

import csv
import ctypes
import ctypes.util
import io
import itertools
import os
import re
import shutil
import sys
import tempfile
import tomllib
import warnings
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import tomli_w

from insrail.io.errors import InputError
from insrail.nav.trajectory import Trajectory, load_trajectory, read_trajectory_fields, trajectory_records
from insrail.progress import CancelToken, check_cancel
from insrail.project import table_cache
from insrail.quality.section_quality import SectionQuality, weakness
from insrail.track.adjustment import REASONS, Adjustment, FastenerType, below_threshold_count, threshold_steps
from insrail.track.exceedance import Assessment, SleeperGeometry, track_quality
from insrail.track.parameters import guiding_rail_is_right, track_parameters
from insrail.track.sleeper_table import SleeperTable
from insrail.track.tolerance import limit_unit

#: A check kind's stored unit -> (column suffix, factor from SI, number format, exceedances.csv unit)
_UNITS = {"ratio": ("_ratio", 1.0, "%.6f", "ratio"), "mm": ("_mm", 1e3, "%.3f", "mm"),
          "mm_per_s": ("_mm_per_s", 1e3, "%.3f", "mm/s")}

RESULTS_FOLDER = "results"
TRAJECTORY_FILE = "trajectory.npy"
#: The sleepers.csv text column of reasons a measured sleeper is not assessed (joined by "; ").
NOT_ASSESSED_COLUMN = "not_assessed"
#: The sleepers.csv text column (after ``not_assessed``) of why a check still fails after the adjustment.
ADJUSTMENT_NOTE_COLUMN = "adjustment_note"
SLEEPERS_FILE = "sleepers.csv"
EXCEEDANCES_FILE = "exceedances.csv"
SUMMARY_FILE = "summary.toml"
# Without a design alignment: the fitted one (usable as a design) and the fit's report.
FITTED_ALIGNMENT_CSV = "fitted_alignment.csv"
FITTED_ALIGNMENT_XML = "fitted_alignment.xml"
LINE_FIT_REPORT = "line_fit.txt"
#: The reports' default folder in the project and name (`insrail report`, the GUI's export).
REPORTS_FOLDER = "reports"
REPORT_STEM = "track_geometry"
QUALITY_FILE = "quality.csv"

#: Columns of quality.csv: the section's chainage, then the 1-sigma of the lateral and vertical position and of
#: their 5 m and 150 m lag differences (behind the 30 m/5 m and 300 m/150 m checks), of the cross-level (cant) and of
#: the along-track position.
QUALITY_HEADER = ["station_from_m", "station_to_m", "sigma_lateral_mm", "sigma_vertical_mm", "sigma_lag5_lateral_mm",
                  "sigma_lag5_vertical_mm", "sigma_lag150_lateral_mm", "sigma_lag150_vertical_mm", "sigma_cross_level_mm",
                  "sigma_along_track_mm"]
#: a quality.csv of an older version holds the first of these columns (the others read empty)
QUALITY_HEADER_OLDEST = QUALITY_HEADER[:8]
EXCEEDANCE_HEADER = ["check", "kind", "rail", "direction", "unit", "station_from_m", "station_to_m", "peak",
                     "limit", "first_sleeper", "last_sleeper"]


# --------------------------------------------------------------------------- writing

#: Figure 5-7 parameters stored whatever the tolerance profile checks: base lengths of the thesis's table.
GAUGE_CHANGE_BASE_M = 2.5
TWIST_BASE_M = 3.0
#: Section length of the track quality index (TQI) in summary.toml.
TQI_SECTION_M = 200.0


def check_column(check: str, kind: str, rail: str, direction: str) -> str:
    """The sleepers.csv column of one channel of a check (``check_`` + check, rail, direction, unit)."""
    parts = [check] + [p for p in (rail, direction) if p and p != "track"]
    return "check_" + "_".join(parts) + _UNITS[limit_unit(kind)][0]


def _channel_column(channel) -> tuple[str, float, str]:
    """Column name, factor from SI, number format."""
    name = check_column(channel.check, channel.kind, channel.rail, channel.direction)
    _, factor, fmt, _ = _UNITS[limit_unit(channel.kind)]
    return name, factor, fmt


def _figure_5_7_columns(table: SleeperTable) -> dict[str, tuple[np.ndarray, str]]:
    """Gauge change to the neighbour and over 2.5 m, twist over 3 m (cross-level, the design cant ramp
    removed) and the guiding rail (1 = right), as in the thesis's sleeper table; NaN at invalid sleepers."""
    invalid = ~np.asarray(table.valid, dtype=bool)
    gauge, cant = table.gauge_m.copy(), table.cant_m.copy()
    gauge[invalid] = np.nan
    cant[invalid] = np.nan
    parameters = track_parameters(table.station_m, gauge, cant, table.design_cant_m,
                                  gauge_change_base_m=GAUGE_CHANGE_BASE_M, twist_base_m=TWIST_BASE_M)
    return {"gauge_change_mm": (1e3 * parameters.gauge_change_m, "%.3f"),
            "gauge_change_rate_2_5m_ratio": (parameters.gauge_change_rate, "%.6f"),
            "twist_3m_mm": (1e3 * parameters.twist_from_design_m, "%.3f"),
            "guiding_rail_right": (guiding_rail_is_right(table.design_cant_m), "%d")}


def sleeper_columns(table: SleeperTable, assessment: Assessment, adjustment: Adjustment,
                    extra: dict[str, tuple[np.ndarray, str]] | None = None) -> dict[str, tuple[np.ndarray, str]]:
    """The columns of sleepers.csv after number and label, in file order: name -> (values, format);
    ``extra`` (:func:`insrail.project.sleeper_parameters.parameter_columns`) after the thesis's columns."""
    columns: dict[str, tuple[np.ndarray, str]] = {
        "station_m": (table.station_m, "%.4f"), "time_s": (table.time_s, "%.4f"),
        "detected": (table.detected, "%d"), "valid": (table.valid, "%d"),
        "chain_zone": (np.zeros(len(table), int) if table.chain_zone is None else table.chain_zone, "%d"),
    }
    for rail, points in (("left", table.left_rail_enh_m), ("right", table.right_rail_enh_m)):
        for axis, values in zip("ENH", points.T):
            columns[f"{rail}_{axis}_m"] = (values, "%.4f")
    columns |= {"gauge_mm": (1e3 * table.gauge_m, "%.3f"), "cant_mm": (1e3 * table.cant_m, "%.3f"),
                "design_cant_mm": (1e3 * table.design_cant_m, "%.3f")}
    columns |= _figure_5_7_columns(table)
    columns |= extra or {}
    for direction, deviation in (("lateral", table.lateral_deviation_m), ("vertical", table.vertical_deviation_m)):
        for side, rail in enumerate(("left", "right")):
            columns[f"{direction}_deviation_{rail}_mm"] = (1e3 * deviation[:, side], "%.3f")
    columns |= sleeper_check_columns(assessment, adjustment)
    return columns


def sleeper_check_columns(assessment: Assessment, adjustment: Adjustment) -> dict[str, tuple[np.ndarray, str]]:
    """The check channels of the tolerance profile and the adjustment amounts (sleepers.csv's last columns)."""
    columns: dict[str, tuple[np.ndarray, str]] = {}
    for channel in assessment.channels:
        name, factor, fmt = _channel_column(channel)
        columns[name] = (factor * channel.values, fmt)
    for direction, amounts, flags in (("lateral", adjustment.lateral_m, adjustment.unresolved_lateral),
                                      ("vertical", adjustment.vertical_m, adjustment.unresolved_vertical)):
        for side, rail in enumerate(("left", "right")):
            # + 0.0: an amount of no millimetres is printed 0.0, never -0.0 (the sign of a zero the optimiser
            # left negative is no instruction to a crew)
            columns[f"adjust_{direction}_{rail}_mm"] = (1e3 * amounts[:, side] + 0.0, "%.1f")
            columns[f"unresolved_{direction}_{rail}"] = (flags[:, side], "%d")
    return columns


def sleepers_csv(table: SleeperTable, assessment: Assessment, adjustment: Adjustment,
                 extra: dict[str, tuple[np.ndarray, str]] | None = None) -> Iterator[str]:
    """number, label, then the columns of :func:`sleeper_columns`, then ``not_assessed`` (why a
    measured sleeper is left out of the assessment, reasons joined by "; ", quoted as CSV when
    they hold a comma), then ``adjustment_note`` (why a check still fails at the sleeper after the
    adjustment, :meth:`Adjustment.reasons`); NaN (not computable) as empty. In blocks of rows
    (:func:`columns_csv`)."""
    return columns_csv(table.number, table.label, sleeper_columns(table, assessment, adjustment, extra),
                       table.not_assessed, tuple(adjustment.reasons()))


#: Rows of a result file formatted at once (the file's text is written block by block, never held whole).
CSV_BLOCK_ROWS = 4096


def columns_csv(number: np.ndarray, label: tuple[str, ...], columns: dict[str, tuple[np.ndarray, str]],
                not_assessed: tuple[str, ...] = (), notes: tuple[str, ...] | None = None) -> Iterator[str]:
    """A sleeper table as sleepers.csv: number, label, then ``columns`` (name -> (values, format)), then
    ``not_assessed`` (() for none) and, when ``notes`` are given, ``adjustment_note``; NaN as empty.
    The text in blocks (the header, then :data:`CSV_BLOCK_ROWS` rows at a time), to be written one
    after the other (:func:`write_results`) or joined."""
    texts = [NOT_ASSESSED_COLUMN] + ([ADJUSTMENT_NOTE_COLUMN] if notes is not None else [])
    yield ",".join(["number", "label", *columns, *texts]) + "\n"
    row_format = ",".join(fmt for _, fmt in columns.values()) + "\n"
    for start in range(0, len(number), CSV_BLOCK_ROWS):
        rows = slice(start, start + CSV_BLOCK_ROWS)
        numeric = np.column_stack([np.asarray(values[rows], dtype=float) for values, _ in columns.values()])
        # the block's rows by one % of Python floats: np.savetxt's text (row by row, of numpy scalars),
        # in 60 % of its time
        lines = ((row_format * len(numeric)) % tuple(numeric.ravel().tolist())).replace("nan", "").splitlines()
        reasons = not_assessed[rows] if not_assessed else ("",) * len(lines)
        if notes is None:
            yield "".join(f"{n},{lbl},{line},{_csv_text(reason)}\n"
                          for n, lbl, line, reason in zip(number[rows], label[rows], lines, reasons))
        else:
            yield "".join(f"{n},{lbl},{line},{_csv_text(reason)},{_csv_text(note)}\n"
                          for n, lbl, line, reason, note in zip(number[rows], label[rows], lines, reasons, notes[rows]))


def _csv_text(text: str) -> str:
    if not any(c in text for c in ',"\n'):
        return text
    return '"' + text.replace("\n", " ").replace('"', '""') + '"'


def adjustment_section(adjustment: Adjustment, before: Assessment, after: Assessment, settings,
                       fastener: FastenerType) -> dict:
    """summary.toml's ``[adjustment]``: the amounts' headline numbers and the re-assessment of the
    adjusted geometry, per check: exceedance runs before and after, and how many of the after
    runs lie where that check channel did not fail before (``new``). ``settings``: the project's
    :class:`insrail.project.model.AdjustmentSettings` (strategy, action threshold)."""
    moved = np.any(np.abs(adjustment.lateral_m) > 1e-9, axis=1) | np.any(np.abs(adjustment.vertical_m) > 1e-9, axis=1)
    failing = np.any(adjustment.unresolved_lateral | adjustment.unresolved_vertical, axis=1)
    failed_before: dict[tuple, np.ndarray] = {}
    for e in before.exceedances:
        key = (e.check, e.rail, e.direction)
        failed_before.setdefault(key, np.zeros(adjustment.lateral_m.shape[0], bool))[e.first_index:e.last_index + 1] = True
    by_check_before: dict[str, int] = {}
    by_check_after: dict[str, int] = {}
    new: dict[str, int] = {}
    for e in before.exceedances:
        by_check_before[e.check] = by_check_before.get(e.check, 0) + 1
    for e in after.exceedances:
        by_check_after[e.check] = by_check_after.get(e.check, 0) + 1
        mask = failed_before.get((e.check, e.rail, e.direction))
        if mask is None or not mask[e.first_index:e.last_index + 1].any():
            new[e.check] = new.get(e.check, 0) + 1
    reasons = {}
    for bit, text in REASONS.items():
        count = int(np.any((adjustment.reason_lateral & bit) | (adjustment.reason_vertical & bit), axis=1).sum())
        reasons[text.replace(" ", "_")] = count
    return {"fastener": adjustment.fastener, "strategy": settings.strategy,
            "threshold_mm": 1e3 * fastener.step_m * threshold_steps(fastener, settings.threshold_m),
            "below_threshold_sleepers": below_threshold_count(adjustment, fastener, settings.threshold_m),
            "total_movement_mm": round(1e3 * adjustment.total_movement_m, 1),
            "max_lateral_mm": 1e3 * float(np.abs(adjustment.lateral_m).max(initial=0.0)),
            "max_vertical_mm": 1e3 * float(np.abs(adjustment.vertical_m).max(initial=0.0)),
            "sleepers_to_work_on": int(moved.sum()),
            "unresolved_sleepers": int(failing.sum()),
            "unresolved_reasons": reasons,
            "after": {"exceedances": len(after.exceedances), "new_exceedances": sum(new.values()),
                      "by_check_before": by_check_before, "by_check": by_check_after, "new_by_check": new}}


def exceedances_csv(assessment: Assessment) -> Iterator[str]:
    """One row per exceedance; lengths and values in mm, rates as ratios (the ``unit`` column says which).
    In blocks of rows, as :func:`columns_csv`."""
    def row(e) -> str:
        _, factor, fmt, unit = _UNITS[limit_unit(e.kind)]
        return ",".join([e.check, e.kind, e.rail, e.direction, unit, f"{e.station_from_m:.3f}", f"{e.station_to_m:.3f}",
                         fmt % (factor * e.peak), fmt % (factor * e.limit), str(e.first_sleeper),
                         str(e.last_sleeper)]) + "\n"

    yield ",".join(EXCEEDANCE_HEADER) + "\n"
    exceedances = assessment.exceedances
    for start in range(0, len(exceedances), CSV_BLOCK_ROWS):
        yield "".join(row(e) for e in exceedances[start:start + CSV_BLOCK_ROWS])


def write_results(results: Path, name: str, files: dict[str, str | bytes | Path | Iterable[str]],
                  cancel: CancelToken = None) -> Path:
    """Write ``results/<name>/`` from ``files`` (file name -> text, bytes, a file to copy, or the text
    in blocks written one after the other: :func:`sleepers_csv`) into a staging folder, then swap it
    for the previous results (see the module docstring)."""
    results.mkdir(parents=True, exist_ok=True)
    recover_results(results, name)
    final = results / name
    staging = Path(tempfile.mkdtemp(prefix=f".{name}.", suffix=".new", dir=results))
    try:
        for file_name, content in files.items():
            target = staging / file_name
            try:
                if isinstance(content, Path):
                    _copy(content, target, final / file_name)
                elif isinstance(content, bytes):
                    target.write_bytes(content)
                else:
                    with open(target, "w", encoding="utf-8") as handle:
                        for block in [content] if isinstance(content, str) else content:
                            check_cancel(cancel)
                            handle.write(block)
            except OSError as err:  # a full disk names no file: name the one being written
                if err.filename:
                    raise
                raise OSError(err.errno, err.strerror, str(final / file_name)) from None
        check_cancel(cancel)
        for file in staging.iterdir():  # on disk before the swap makes them the results
            with open(file, "rb") as handle:
                os.fsync(handle.fileno())
        os.chmod(staging, 0o755)
        old = _swap_in(staging, final, results / f".{name}.old-{os.getpid()}")
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)
    return final


def _copy(source: Path, target: Path, previous: Path) -> None:
    """``target`` a copy of ``source`` (a copy: editing a result never changes the cache) with its
    modification time. When the previous results' file is such a copy (same size and time: a
    rerun's trajectory of 0.4 GB) it is linked instead; the previous folder goes once swapped out."""
    stat = source.stat()
    try:
        kept = previous.stat()
        if (kept.st_size, kept.st_mtime_ns) == (stat.st_size, stat.st_mtime_ns) and kept.st_ino != stat.st_ino:
            os.link(previous, target)
            return
    except OSError:  # no previous results, or a file system without links: copied
        pass
    shutil.copyfile(source, target)
    os.utime(target, ns=(stat.st_atime_ns, stat.st_mtime_ns))


def _swap_in(staging: Path, final: Path, aside: Path) -> Path | None:
    """Make ``staging`` the results folder ``final``; returns the folder now holding the old results."""
    if not final.exists():
        os.replace(staging, final)
        return None
    if _exchange(staging, final):
        return staging
    os.replace(final, aside)
    os.replace(staging, final)  # a crash before this line: recover_results puts ``aside`` back
    return aside


_RENAME_EXCHANGE = 2
_AT_FDCWD = -100


def _exchange(a: Path, b: Path) -> bool:
    """Swap two folders in one atomic step (Linux renameat2); False where the system cannot."""
    if not sys.platform.startswith("linux"):
        return False
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
        renameat2 = libc.renameat2
    except (OSError, AttributeError):
        return False
    renameat2.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
    return renameat2(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE) == 0


def recover_results(results: Path, name: str, clean: bool = True) -> None:
    """Repair what a killed run left for survey ``name``: the previous results put back when a crash
    came between the renames of the swap; with ``clean`` (a run writing results, not a reader who
    might meet a run in progress) staging (``.new``) and old folders removed."""
    final = results / name
    if not results.is_dir():
        return
    olds = sorted(results.glob(f".{glob_escape(name)}.old-*"), key=lambda p: p.stat().st_mtime, reverse=True)
    if not final.exists() and olds:
        try:
            os.replace(olds.pop(0), final)
        except OSError:  # a read-only project: read the old folder where it is
            return
    if not clean:
        return
    for leftover in [*olds, *results.glob(f".{glob_escape(name)}.*.new")]:
        shutil.rmtree(leftover, ignore_errors=True)


def glob_escape(name: str) -> str:
    """``name`` matched literally in a glob pattern."""
    return "".join(f"[{c}]" if c in "*?[" else c for c in name)


def track_quality_section(geometry: SleeperGeometry, section_m: float = TQI_SECTION_M) -> dict:
    """summary.toml's ``[track_quality]``: standard deviations [mm] of the 7 TQI channels per section
    (EN 13848 D1 band for level and alignment) and their sum, the TQI; -1 where a section has too
    few valid sleepers (TOML files are read by spreadsheets and scripts that choke on nan)."""
    if len(geometry.station_m) < 2:
        return {"section_m": section_m, "band": "D1", "start_m": [], "channels": [], "tqi_mm": []}
    statistics = track_quality(geometry, section_m=section_m)

    def listed(values: np.ndarray) -> list[float]:
        return [round(float(v), 4) if np.isfinite(v) else -1.0 for v in 1e3 * values]

    return {"section_m": section_m, "band": "D1", "start_m": [round(float(s), 3) for s in statistics.start_m],
            "channels": list(statistics.channels),
            **{f"sd_{name}_mm": listed(statistics.standard_deviation_m[:, i])
               for i, name in enumerate(statistics.channels)},
            "tqi_mm": listed(statistics.track_quality_index_m)}


def gnss_section(gnss_time_s: np.ndarray, quality: np.ndarray, start_s: float, end_s: float,
                 outage_s: float = 3.0) -> dict:
    """summary.toml's ``[gnss]``: solutions inside the survey span, how many fixed (RTKLIB Q = 1), and
    every outage (no solution for more than ``outage_s``) as [from, to] GPS seconds of week."""
    time = np.asarray(gnss_time_s, dtype=float)
    inside = (time >= start_s) & (time <= end_s)
    time, quality = time[inside], np.asarray(quality)[inside]
    edges = np.concatenate([[start_s], time, [end_s]])
    gaps = np.flatnonzero(np.diff(edges) > outage_s)
    outages = [[round(float(edges[i]), 3), round(float(edges[i + 1]), 3)] for i in gaps]
    return {"solutions": int(time.size), "fixed": int(np.count_nonzero(quality == 1)),
            "interval_s": float(np.median(np.diff(time))) if time.size > 1 else 0.0,
            "span_s": [float(start_s), float(end_s)], "outages": outages,
            "outage_total_s": round(float(sum(b - a for a, b in outages)), 3)}


def quality_csv(quality: SectionQuality) -> Iterator[str]:
    """quality.csv: one row per section (:data:`QUALITY_HEADER`), NaN as an empty cell; the header,
    then the rows (one per 200 m: few), as :func:`columns_csv` gives its blocks."""
    def cell(value: float) -> str:
        return f"{value:.3f}" if np.isfinite(value) else ""

    yield ",".join(QUALITY_HEADER) + "\n"
    yield "".join(",".join(cell(row[name]) for name in QUALITY_HEADER) + "\n" for row in quality.to_rows())


def quality_section(quality: SectionQuality) -> dict:
    """summary.toml's ``[quality]``: the pass, the weakest section (``SectionQuality.weakest_section``)
    with its figures, and the median of each figure over the sections [mm]; -1 for no value."""
    rows = quality.to_rows()
    weakest = quality.weakest_section()
    figures = QUALITY_HEADER[2:]

    def value(v: float) -> float:
        return round(float(v), 3) if np.isfinite(v) else -1.0

    median = {name: value(np.nanmedian([row[name] for row in rows])) if any(np.isfinite(row[name]) for row in rows)
              else -1.0 for name in figures}
    return {"pass": "smoothed" if quality.smoothed else "forward", "file": QUALITY_FILE, "sections": len(rows),
            "weakest": {"station_from_m": rows[weakest]["station_from_m"],
                        "station_to_m": rows[weakest]["station_to_m"],
                        **{name: value(rows[weakest][name]) for name in figures}},
            "median": median}


def summary_toml(summary: dict) -> bytes:
    return tomli_w.dumps(summary).encode("utf-8")


#: Records of trajectory.npy read at a time for its statistics (tests shrink it to a prime).
STATISTICS_CHUNK_RECORDS = 1 << 14
#: A bin of :class:`ExactQuantiles` holding at most this many values is sorted; a fuller one is split again.
SELECTION_SORT_LIMIT = 1 << 16
_BIN_BITS = 16
_SIGN = np.uint64(1 << 63)


def _sortable_keys(values: np.ndarray) -> np.ndarray:
    """uint64 keys ordered as the (non-NaN) float64 ``values``: the bit pattern with the sign bit
    set for a positive value, all bits flipped for a negative one (-0.0 is taken as 0.0)."""
    bits = (values + 0.0).view(np.uint64)
    return np.where(bits >= _SIGN, ~bits, bits | _SIGN)


def _key_value(key: int) -> float:
    bits = np.uint64(key) ^ _SIGN if key >= 1 << 63 else ~np.uint64(key)
    return float(bits.view(np.float64))


class ExactQuantiles:
    """The median, percentiles (numpy's default "linear" method) and largest of float64 values fed a
    chunk at a time (:meth:`feed`), in as many passes over them as the selection needs (:meth:`more`;
    2 usually, at most 4); the same numbers as ``np.median``, ``np.percentile`` and ``np.max`` of all
    the values at once, NaN when one is NaN. Memory: a few bins of counts, never the values.

    Pass 1 counts the values by the top 16 bits of their ordered bit patterns (:func:`_sortable_keys`).
    Each later pass takes the values of every bin holding a wanted rank: sorted when the bin holds
    at most :data:`SELECTION_SORT_LIMIT`, else counted again by their next 16 bits (a bin of the
    last 16 bits holds equal values: its rank needs no values)."""

    def __init__(self, percentiles: tuple[float, ...]):
        self.percentiles = percentiles
        self.count = self.nans = 0
        self.largest = -np.inf
        self.passes = 0
        self._keys: dict[int, int] = {}  # wanted rank -> its key, once known
        self._open: dict[tuple[int, int], dict] = {(0, 0): {"ranks": {}, "histogram": np.zeros(1 << _BIN_BITS, np.int64)}}

    def feed(self, values: np.ndarray) -> None:
        """The next chunk of values (every pass feeds the same values in the same chunks)."""
        if self.passes == 0:
            nan = np.isnan(values)
            self.nans += int(nan.sum())
            values = values[~nan]
            self.count += values.size
            if values.size:
                self.largest = max(self.largest, float(values.max()))
        else:
            values = values[~np.isnan(values)]
        if self.nans or not values.size:
            return
        keys = _sortable_keys(values)
        for (level, prefix), group in self._open.items():
            shift = 64 - _BIN_BITS * level
            inside = keys if level == 0 else keys[keys >> np.uint64(shift) == np.uint64(prefix)]
            if "histogram" in group:
                group["histogram"] += np.bincount((inside >> np.uint64(shift - _BIN_BITS)) & np.uint64(0xFFFF),
                                                  minlength=1 << _BIN_BITS)
            else:
                group["values"].append(inside)

    def more(self) -> bool:
        """End a pass: True when the values are to be fed once more."""
        if self.passes == 0:
            self._open[0, 0]["ranks"] = {rank: rank for rank in self._ranks()} if self.count and not self.nans else {}
        self.passes += 1
        groups, self._open = self._open, {}
        for (level, prefix), group in groups.items():
            if "values" in group:
                ordered = np.sort(np.concatenate(group["values"]))
                self._keys.update({rank: int(ordered[within]) for rank, within in group["ranks"].items()})
                continue
            ends = np.cumsum(group["histogram"])
            for rank, within in group["ranks"].items():
                index = int(np.searchsorted(ends, within, side="right"))
                key, within = (prefix << _BIN_BITS) | index, within - (int(ends[index - 1]) if index else 0)
                if level + 1 == 64 // _BIN_BITS:  # all 64 bits known: the value itself
                    self._keys[rank] = key
                    continue
                below = self._open.setdefault((level + 1, key), {"ranks": {}, "size": int(group["histogram"][index])})
                below["ranks"][rank] = within
        for group in self._open.values():
            if group.pop("size") <= SELECTION_SORT_LIMIT:
                group["values"] = []
            else:
                group["histogram"] = np.zeros(1 << _BIN_BITS, np.int64)
        return bool(self._open)

    def _ranks(self) -> set[int]:
        n = self.count
        ranks = {(n - 1) // 2, n // 2}
        for q in self.percentiles:
            virtual = (n - 1) * (q / 100)
            ranks |= {n - 1} if virtual >= n - 1 else {int(np.floor(virtual)), int(np.floor(virtual)) + 1}
        return ranks

    def _value(self, rank: int) -> float:
        return _key_value(self._keys[rank])

    def median(self) -> float:
        """``np.median``: the middle value, or the mean of the two middle ones."""
        if self.nans or not self.count:
            return np.nan
        n = self.count
        if n % 2:
            return self._value(n // 2)
        return float(np.mean(np.array([self._value(n // 2 - 1), self._value(n // 2)])))

    def percentile(self, q: float) -> float:
        """``np.percentile(values, q)`` (numpy's linear interpolation between the neighbouring ranks)."""
        if self.nans or not self.count:
            return np.nan
        n = self.count
        virtual = (n - 1) * np.true_divide(q, 100)
        below = np.floor(virtual) if virtual < n - 1 else np.float64(-1.0)  # numpy's index -1: the last value
        a, b = (np.float64(self._value(int(below))), np.float64(self._value(int(below) + 1))) if below >= 0 else \
            (np.float64(self._value(n - 1)),) * 2
        gamma = virtual - below
        difference = b - a
        return float(b - difference * (1 - gamma) if gamma >= 0.5 else a + difference * gamma)

    def maximum(self) -> float:
        return np.nan if self.nans or not self.count else self.largest


def _trajectory_chunks(path: Path, names, chunk: int) -> Iterator[dict[str, np.ndarray]]:
    """The named fields of a trajectory.npy, ``chunk`` records at a time (plain reads, no memory map)."""
    total = trajectory_records(path)
    for start in range(0, total, chunk):
        yield read_trajectory_fields(path, names, start=start, count=chunk)


def trajectory_section(path: Path) -> dict:
    """summary.toml's ``[trajectory]``: the fused trajectory's epochs, first and last time [s of week],
    the median, 95 % and largest of its horizontal and vertical position 1-sigma [mm], and the
    odometer scale error (a ratio) at the end, smallest and largest, ``used`` when it is not 0
    throughout (the filter's state stays 0 without an odometer). Exact (the whole-array numpy
    figures), read :data:`STATISTICS_CHUNK_RECORDS` records at a time; NaN where a value is."""
    horizontal, vertical = ExactQuantiles((95.0,)), ExactQuantiles((95.0,))
    epochs, first_s, last_s, scale = 0, np.nan, np.nan, {"last": np.nan, "min": np.inf, "max": -np.inf, "used": False}
    while True:
        for records in _trajectory_chunks(path, ("time_s", "sigma_pos_ned_m", "odometer_scale"), STATISTICS_CHUNK_RECORDS):
            sigma = records["sigma_pos_ned_m"]
            horizontal.feed(1e3 * np.hypot(sigma[:, 0], sigma[:, 1]))
            vertical.feed(1e3 * sigma[:, 2])
            if horizontal.passes == 0:  # the first pass
                first_s = float(records["time_s"][0]) if not epochs else first_s
                epochs += len(records["time_s"])
                last_s = float(records["time_s"][-1])
                odometer = records["odometer_scale"]  # min/max as numpy's: NaN when one is NaN
                scale = {"last": float(odometer[-1]), "min": float(np.minimum(scale["min"], odometer.min())),
                         "max": float(np.maximum(scale["max"], odometer.max())),
                         "used": scale["used"] or bool(np.any(odometer != 0))}
        if not (horizontal.more() | vertical.more()):
            break
    if not epochs:
        return {"epochs": 0}

    def figures(values: ExactQuantiles) -> dict:
        return {"median": values.median(), "p95": values.percentile(95.0), "max": values.maximum()}

    return {"epochs": epochs, "start_s": first_s, "end_s": last_s, "sigma_horizontal_mm": figures(horizontal),
            "sigma_vertical_mm": figures(vertical), "odometer_scale": scale}


# --------------------------------------------------------------------------- reading

@dataclass(frozen=True)
class ExceedanceRow:
    """One row of exceedances.csv; ``peak`` and ``limit`` in ``unit`` (``mm`` or ``ratio``)."""

    check: str
    kind: str
    rail: str
    direction: str
    unit: str
    station_from_m: float
    station_to_m: float
    peak: float
    limit: float
    first_sleeper: int
    last_sleeper: int


@dataclass(frozen=True)
class StoredQuality:
    """quality.csv read back: predicted 1-sigma per section of chainage, in the file's units.
    ``smoothed``: the pass the figures describe (summary.toml's ``[quality] pass``)."""

    smoothed: bool
    station_from_m: np.ndarray
    station_to_m: np.ndarray
    sigma_lateral_mm: np.ndarray
    sigma_vertical_mm: np.ndarray
    sigma_lag5_lateral_mm: np.ndarray
    sigma_lag5_vertical_mm: np.ndarray
    sigma_lag150_lateral_mm: np.ndarray
    sigma_lag150_vertical_mm: np.ndarray
    sigma_cross_level_mm: np.ndarray
    sigma_along_track_mm: np.ndarray

    def __len__(self) -> int:
        return len(self.station_from_m)

    def weakest(self, figure: str = "sigma_lag5_lateral_mm") -> int:
        """Index of the section with the largest ``figure``."""
        if figure not in QUALITY_HEADER[2:]:
            raise ValueError(f"unknown figure {figure!r}; choose one of {', '.join(QUALITY_HEADER[2:])}")
        return int(np.nanargmax(getattr(self, figure)))

    def weakest_sections(self, count: int = 1) -> np.ndarray:
        """Indices of the ``count`` weakest sections, weakest first (:func:`insrail.quality.survey.weakness`:
        the irregularity figures furthest above the survey's median); ``[0]`` is summary.toml's
        ``[quality.weakest]``."""
        score = weakness(self.sigma_lag5_lateral_mm, self.sigma_lag5_vertical_mm, self.sigma_lag150_lateral_mm,
                         self.sigma_lag150_vertical_mm)
        return np.argsort(-score, kind="stable")[:count]


@dataclass(frozen=True)
class StoredResults:
    """A survey's result files read back (values in the files' units, as named by each column)."""

    survey: str
    folder: Path
    summary: dict
    number: np.ndarray  # (n,) int sleeper numbers as printed for the crews
    label: tuple[str, ...]  # broken-chainage label per sleeper
    columns: dict[str, np.ndarray]  # sleepers.csv columns after number and label; NaN where empty
    exceedances: tuple[ExceedanceRow, ...]
    quality: StoredQuality | None = None  # None: results written before quality.csv existed
    not_assessed: tuple[str, ...] = ()  # per sleeper, why it is not assessed ("" when it is); () none stored
    adjustment_notes: tuple[str, ...] = ()  # per sleeper, why a check still fails after the adjustment

    def __len__(self) -> int:
        return len(self.number)

    def trajectory(self) -> Trajectory:
        """The fused trajectory (read on demand: it is the large file)."""
        return load_trajectory(self.folder / TRAJECTORY_FILE, gps_week=self.summary.get("survey", {}).get("gps_week"))


def load_results(project_folder: Path, survey: str) -> StoredResults:
    """Read ``<project_folder>/results/<survey>/``; a missing or damaged file raises InputError naming it."""
    folder = Path(project_folder) / RESULTS_FOLDER / survey
    recover_results(folder.parent, survey, clean=False)
    summary_path = folder / SUMMARY_FILE
    if not summary_path.is_file():
        raise InputError(folder, None, "no results for survey {survey!r}: process it first", fields={"survey": survey})
    try:
        summary = tomllib.loads(summary_path.read_text(encoding="utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as error:
        raise InputError(summary_path, None, "not a valid summary file ({error})", fields={"error": error}) from None
    number, label, columns, not_assessed, notes = _read_sleepers(folder / SLEEPERS_FILE)
    quality_path = folder / QUALITY_FILE
    quality = (_read_quality(quality_path, summary.get("quality", {}).get("pass", "smoothed") == "smoothed")
               if quality_path.is_file() else None)
    return StoredResults(survey, folder, summary, number, label, columns,
                         _read_exceedances(folder / EXCEEDANCES_FILE), quality, not_assessed, notes)


def report_path(project_folder: Path, survey: str, suffix: str) -> Path:
    """The default place of a survey's report: ``<project>/reports/track_geometry_<survey>.<suffix>``.

    Not in ``results/<survey>/``: that folder belongs to the pipeline and is replaced whole when the
    survey is processed again, and a report a surveyor saved must never go with it."""
    return Path(project_folder) / REPORTS_FOLDER / f"{REPORT_STEM}_{survey}.{suffix}"


def _lines(path: Path) -> list[str]:
    try:
        return path.read_text(encoding="utf-8").splitlines()
    except FileNotFoundError:
        raise InputError(path, None, "result file missing: process the survey again") from None


def _read_sleepers(path: Path) -> table_cache.SleeperTableParse:
    """The sleeper table, from the user's cache of parsed tables when this very file was parsed before."""
    try:
        data = path.read_bytes()
    except FileNotFoundError:
        raise InputError(path, None, "result file missing: process the survey again") from None
    table = table_cache.load(data)
    if table is None:
        table = _parse_sleepers(path, data)
        table_cache.store(data, table)
    return table


def _text_lines(data: bytes) -> Iterator[str]:
    """The lines of the UTF-8 text ``data`` one at a time, as ``str.splitlines()`` of the text read
    with universal newlines gives them (the text is never split whole)."""
    for line in io.TextIOWrapper(io.BytesIO(data), encoding="utf-8"):
        yield from line.splitlines()


def _parse_sleepers(path: Path, data: bytes | None = None) -> table_cache.SleeperTableParse:
    """sleepers.csv (its bytes ``data``, else read), :data:`CSV_BLOCK_ROWS` lines at a time into one
    array of values."""
    data = path.read_bytes() if data is None else data
    lines = _text_lines(data)
    header = next(lines, None)
    if header is None or not header.startswith("number,label,"):
        raise InputError(path, 1, "expected the header 'number,label,...' of an insrail sleeper table")
    names = header.split(",")[2:]
    texts = 0  # trailing text columns (results of older versions have fewer)
    for text_names in ([NOT_ASSESSED_COLUMN, ADJUSTMENT_NOTE_COLUMN], [NOT_ASSESSED_COLUMN]):
        if names[-len(text_names):] == text_names:
            texts = len(text_names)
            break
    if texts:
        names = names[:-texts]
    capacity = data.count(b"\n") + data.count(b"\r")  # line ends: at least the rows
    values = np.empty((capacity, len(names)))
    number, labels, not_assessed, notes = [], [], [], []
    rows = 0
    while block := list(itertools.islice(lines, CSV_BLOCK_ROWS)):
        fast = _regular_rows(block, len(names), texts)
        if fast is None or rows + len(block) > capacity:
            return _parse_rows(path, names, texts)
        values[rows:rows + len(block)] = fast[2]
        number.append(fast[0])
        for held, part in zip((labels, not_assessed, notes), (fast[1], fast[3], fast[4])):
            held.extend(part)
        rows += len(block)
    if not rows:
        return _parse_rows(path, names, texts)
    values.resize((rows, len(names)), refcheck=False)  # in place: no second copy of the table
    return (np.concatenate(number), tuple(labels), {name: values[:, i] for i, name in enumerate(names)},
            tuple(not_assessed), tuple(notes))


def _parse_rows(path: Path, names: list[str], texts: int) -> table_cache.SleeperTableParse:
    """A file that is not as written (or holds a mistake): row by row, naming the line at fault."""
    lines = _lines(path)
    if texts:  # quoted text columns: the csv module splits these lines
        rows = list(csv.reader(lines[1:]))
    else:
        rows = [line.split(",") for line in lines[1:]]
    width = len(names) + 2 + texts
    for line_number, row in enumerate(rows, start=2):
        if len(row) != width:
            raise InputError(path, line_number, "expected {width} fields, found {count}", fields={"width": width, "count": len(row)})
    if not rows:
        return np.zeros(0, int), (), {name: np.zeros(0) for name in names}, (), ()
    cells = np.array([row[2:len(names) + 2] for row in rows])
    cells[cells == ""] = "nan"
    try:
        values = cells.astype(float)
        number = np.array([row[0] for row in rows]).astype(int)
    except ValueError:
        bad = next(i for i, row in enumerate(rows) if not _numeric(row[:len(names) + 2]))
        raise InputError(path, bad + 2, "expected numbers in every column but the label") from None
    not_assessed = tuple(row[len(names) + 2] for row in rows) if texts else ()
    notes = tuple(row[len(names) + 3] for row in rows) if texts > 1 else ()
    return (number, tuple(row[1] for row in rows), {name: values[:, i] for i, name in enumerate(names)},
            not_assessed, notes)


_EMPTY_CELL = re.compile(r"(?<![^,])(?![^,])")  # between two commas, or a comma and an end: an empty cell


def _regular_rows(body: list[str], count: int, texts: int):
    """(number, labels, values (rows x count), not_assessed, notes) of sleepers.csv lines as the pipeline
    writes them, with numpy's own number parser over all cells at once (a 10 km table: a third of
    the time of parsing cell by cell); None at the first thing out of the ordinary (the caller's row
    by row reading then names the line)."""
    if not body or count < 1:
        return None
    heads, tails = [], []
    for line in body:
        if '"' in line:  # a quoted text cell (a reason holding a comma)
            row = next(csv.reader([line]))
            if len(row) != count + 2 + texts:
                return None
            heads.append(",".join(row[:count + 2]))
            tails.append(row[count + 2:])
        elif texts:
            head, *tail = line.rsplit(",", texts)
            heads.append(head)
            tails.append(tail)
        else:
            heads.append(line)
    parts = [head.split(",", 2) for head in heads]
    if any(len(p) != 3 or p[2].count(",") != count - 1 for p in parts):
        return None
    try:
        number = np.array([int(p[0]) for p in parts])
    except ValueError:
        return None
    with warnings.catch_warnings(record=True) as caught:  # older numpy warns of a cell that is no number
        warnings.simplefilter("always")
        try:
            values = np.fromstring(_EMPTY_CELL.sub("nan", ",".join(p[2] for p in parts)), sep=",")
        except ValueError:  # a cell that is no number
            return None
    if caught or values.size != len(parts) * count:
        return None
    not_assessed = tuple(tail[0] for tail in tails) if texts else ()
    notes = tuple(tail[1] for tail in tails) if texts > 1 else ()
    return number, tuple(p[1] for p in parts), values.reshape(len(parts), count), not_assessed, notes


def _numeric(row: list[str]) -> bool:
    try:
        int(row[0])
        [float(cell) for cell in row[2:] if cell]
    except ValueError:
        return False
    return True


def _read_exceedances(path: Path) -> tuple[ExceedanceRow, ...]:
    lines = _lines(path)
    if not lines or lines[0].split(",") != EXCEEDANCE_HEADER:
        raise InputError(path, 1, "expected the header {header}", fields={"header": ','.join(EXCEEDANCE_HEADER)})
    rows = []
    for line_number, line in enumerate(lines[1:], start=2):
        fields = line.split(",")
        try:
            check, kind, rail, direction, unit, s0, s1, peak, limit, first, last = fields
            rows.append(ExceedanceRow(check, kind, rail, direction, unit, float(s0), float(s1), float(peak),
                                      float(limit), int(first), int(last)))
        except ValueError:
            raise InputError(path, line_number, "expected {count} fields: "
                                                "{header}", fields={"count": len(EXCEEDANCE_HEADER), "header": ','.join(EXCEEDANCE_HEADER)}) from None
    return tuple(rows)


def _read_quality(path: Path, smoothed: bool) -> StoredQuality:
    lines = _lines(path)
    header = lines[0].split(",") if lines else []
    if len(header) < len(QUALITY_HEADER_OLDEST) or header != QUALITY_HEADER[: len(header)]:
        raise InputError(path, 1, "expected the header {header}", fields={"header": ','.join(QUALITY_HEADER)})
    values = np.full((len(lines) - 1, len(QUALITY_HEADER)), np.nan)
    for row, line in enumerate(lines[1:]):
        fields = line.split(",")
        try:
            if len(fields) != len(header):
                raise ValueError
            values[row, : len(header)] = [float(cell) if cell else np.nan for cell in fields]
        except ValueError:
            raise InputError(path, row + 2, "expected {count} numbers (or empty cells): "
                                            "{header}", fields={"count": len(header), "header": ','.join(header)}) from None
    return StoredQuality(smoothed, *(values[:, i] for i in range(len(QUALITY_HEADER))))
