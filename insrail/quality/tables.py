"""A prediction as the surveyor reads it: each figure in mm, its 3 sigma against the limit of its check.

One source for every shell: ``insrail predict`` prints :func:`accuracy_table` and
:func:`sweep_table`; the GUI's Plan survey dialog shows :func:`accuracy_rows` and
:func:`sweep_rows` in a table widget. A figure passes when its 3 sigma is within the limit
of the check it stands for (2 mm for the 30 m/5 m chords and cant, 10 mm for 300 m/150 m).
The labels, verdicts and headings are in the language in use (:func:`insrail.names.t`: the
desktop application's; the command line's is English).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

from insrail.names import t

if TYPE_CHECKING:  # the command line parser reads SWEEP_VALUES without loading the fusion
    from insrail.quality.prediction import AccuracyFigures, Prediction
    from insrail.quality.sweep import SweepTable

#: figure -> (label, tolerance [mm] of the check it stands for, or None)
ROWS = {
    "position_lateral_m": ("absolute position, lateral", None),
    "position_vertical_m": ("absolute position, vertical", None),
    "cant_m": ("cant (1500 mm x roll)", 2.0),
    "lag5_lateral_m": ("30 m/5 m alignment (5 m lag)", 2.0),
    "lag5_vertical_m": ("30 m/5 m vertical (5 m lag)", 2.0),
    "lag150_lateral_m": ("300 m/150 m alignment (150 m lag)", 10.0),
    "lag150_vertical_m": ("300 m/150 m vertical (150 m lag)", 10.0),
    "outage_growth_lateral_m": ("outage: lateral sigma growth", None),
    "outage_growth_vertical_m": ("outage: vertical sigma growth", None),
}
#: A typical range of each sweep parameter, in the units of ``insrail.quality.sweep.PARAMETERS``.
SWEEP_VALUES = {
    "gyro_bias": (0.005, 0.01, 0.1, 1.0),
    "accel_bias": (10.0, 25.0, 100.0, 300.0),
    "arw": (0.0022, 0.01, 0.05, 0.1),
    "vrw": (0.00075, 0.003, 0.01, 0.03),
    "gnss_sigma": (0.005, 0.01, 0.02, 0.05),
    "speed": (0.25, 0.5, 1.0, 2.0, 5.0),
}
EXCEEDS = "exceeds the limit at 3 sigma"


@dataclass(frozen=True)
class FigureRow:
    """One figure of the table: ``sigma_m`` is 1 sigma [m], NaN where it does not apply."""

    name: str
    label: str
    sigma_m: float
    limit_mm: float | None

    @property
    def sigma_mm(self) -> float:
        return 1e3 * self.sigma_m

    @property
    def three_sigma_mm(self) -> float:
        return 3e3 * self.sigma_m

    @property
    def within_limit(self) -> bool | None:
        """None for a figure without a limit."""
        return None if self.limit_mm is None else self.three_sigma_mm <= self.limit_mm

    @property
    def verdict(self) -> str:
        return {None: "", True: t("ok"), False: t(EXCEEDS)}[self.within_limit]


def figure_names(with_outage: bool, relative: bool = False) -> list[str]:
    """The figures a table shows: the outage rows only when the run has an outage, no absolute position
    for a relative survey (its position is its start's frame)."""
    return [name for name in ROWS if (with_outage or not name.startswith("outage"))
            and not (relative and name.startswith("position"))]


def accuracy_rows(figures: AccuracyFigures, with_outage: bool, relative: bool = False) -> list[FigureRow]:
    values = figures.as_dict()
    return [FigureRow(name, t(ROWS[name][0]), values[name], ROWS[name][1])
            for name in figure_names(with_outage, relative)]


def prediction_heading(prediction: Prediction, smoothed: bool) -> str:
    """What was predicted: pass, IMU, GNSS sigmas, speed, length and outages."""
    inputs = prediction.inputs
    gnss = inputs["gnss"]
    source = (t("relative survey (no GNSS, no prism: odometer, NHC and stops)") if gnss is None else
              f"GNSS {1e3 * gnss.white_horizontal_m:g}/{1e3 * gnss.white_vertical_m:g} mm")
    text = t("Predicted accuracy, {solution} solution: IMU {imu}, {source}, {speed_mps:g} m/s, {length_m:g} m").format(
        solution=t("smoothed") if smoothed else t("forward"), imu=inputs["imu"], source=source,
        speed_mps=inputs["speed_mps"], length_m=inputs["length_m"])
    if gnss is None and inputs["stops"]:
        spacing = inputs["stops"][1][0] - inputs["stops"][0][0] if len(inputs["stops"]) > 1 else inputs["stops"][0][0]
        text += t(", a {stop_s:g} s stop every {spacing_m:g} m").format(stop_s=inputs["stops"][0][1], spacing_m=spacing)
    for station, duration in inputs["outages"]:
        text += t(", {duration_s:g} s outage at {station_m:g} m").format(duration_s=duration, station_m=station)
    return text


def _mm(value_mm: float) -> str:
    return f"{'-':>8}" if math.isnan(value_mm) else f"{value_mm:8.3f}"


def accuracy_table(rows: list[FigureRow]) -> list[str]:
    """The rows as text lines (header first): label, 1 sigma, 3 sigma, limit [mm] and the verdict."""
    lines = [f"{'figure':<36} {'1 sigma':>8} {'3 sigma':>8} {'limit':>8}  [mm]"]
    for row in rows:
        limit = f"{row.limit_mm:8.1f}" if row.limit_mm is not None else " " * 8
        verdict = f"  {row.verdict}" if row.verdict else ""
        lines.append(f"{row.label:<36} {_mm(row.sigma_mm)} {_mm(row.three_sigma_mm)} {limit}{verdict}")
    return lines


def sweep_rows(table: SweepTable, smoothed: bool, with_outage: bool) -> list[tuple[float, list[FigureRow]]]:
    """(parameter value, its rows) for each value of a sweep."""
    passes = table.smoothed if smoothed else table.forward
    return [(value, accuracy_rows(figures, with_outage)) for value, figures in zip(table.values, passes)]


def sweep_table(table: SweepTable, smoothed: bool, with_outage: bool) -> list[str]:
    """A sweep as text lines: a heading, then one line per value with every figure's 1 sigma [mm]."""
    names = figure_names(with_outage)
    lines = [f"{'smoothed' if smoothed else 'forward'} solution, 1 sigma [mm], {table.parameter} in {table.unit}",
             f"{table.parameter:>12} " + " ".join(f"{n.replace('_m', ''):>20}" for n in names)]
    for value, rows in sweep_rows(table, smoothed, with_outage):
        lines.append(f"{value:12g} " + " ".join(f"{row.sigma_mm:20.3f}" for row in rows))
    return lines
