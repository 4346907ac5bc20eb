"""Repeatability of repeated surveys of the same track (thesis §5.4.2, "内符合精度").

The thesis surveys one stretch three times and plots, per parameter (lateral and vertical
deviations, cant, gauge, short- and long-wave irregularities), the second and third runs minus
the first at every chainage; it reports how small those differences are (deviations mostly
below 0.2 mm with a few points near 0.4 mm, cant and gauge below 0.2 mm). This module does the
same: every run is aligned on the reference run's stations by chainage (linear interpolation
between neighbouring sleepers, never across a gap), and per parameter and compared run it gives
the differences and their mean, standard deviation, RMS, 95th percentile and maximum of the
absolute value.

A run minus the reference holds the noise of both, so the repeatability of one run is
``std / sqrt(2)`` when the runs are alike (``single_run_std``: pooled over the compared runs).
A mean clearly away from zero is a systematic shift between runs (a height-model change, a
trolley set the other way round, a mislabelled survey), not noise.

Checks whose value is the worst over several chord placements (the differential versines,
30 m/5 m and 300 m/150 m; ``placements_m`` gives each one's chord length) are compared
differently, for two reasons:

* by magnitude. Each sleeper carries the signed value of largest magnitude over every chord
  placement containing its pair (:func:`insrail.track.irregularity.differential_versine`); where
  placements of either sign reach nearly the same magnitude, the sign of that worst value is
  decided by noise far below a micrometre, and two runs carry +x and -x at the same sleeper. On
  simulated repeat runs of the `short` preset 8-10 % of the sleepers flip between runs, each flip
  a difference of about 1 mm (twice the ~0.5 mm magnitude there), which raised the 1-sigma of the
  signed differences from 0.23-0.26 mm to 0.37-0.42 mm. What the check assesses is the magnitude
  against a symmetric limit (thesis eq. 2.2 defines the irregularity as |dV|), and the magnitude
  of a worst value moves by no more than the errors of the placements do. The plain (linear)
  checks and the deviations stay signed, so a sign error between runs still shows.
* only where complete: within a chord length of a run's end or of a gap in it, fewer placements
  fit, so the value is the worst of a part of them; where the other run goes on (the two ends of
  a section's overlap, a run started later, a stretch one run could not assess) the two values
  are different quantities. They are compared only where both runs have sleepers a chord length
  either side without a gap of more than ``max_gap_m``.

Values are in the units given (the project passes metres); stations in metres.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

#: Largest station gap [m] bridged when a run is interpolated onto the reference stations
#: (a missing sleeper or two; beyond that the comparison is left out there).
MAX_GAP_M = 2.0


@dataclass(frozen=True)
class ParameterRepeatability:
    """One parameter: per compared run (first axis, ``Repeatability.compared`` order) the
    difference from the reference run at the reference stations (NaN where not comparable),
    and its statistics."""

    name: str
    difference: np.ndarray  # (runs - 1, n)
    count: np.ndarray  # (runs - 1,) stations compared
    mean: np.ndarray
    std: np.ndarray
    rms: np.ndarray
    p95_abs: np.ndarray
    max_abs: np.ndarray
    single_run_std: float  # pooled std of the differences / sqrt(2)
    by_magnitude: bool = False  # a worst-over-placements check: magnitudes compared where complete (module docstring)


@dataclass(frozen=True)
class Repeatability:
    reference: str
    compared: tuple[str, ...]
    station_m: np.ndarray  # (n,) the reference run's stations
    parameters: tuple[ParameterRepeatability, ...]

    def parameter(self, name: str) -> ParameterRepeatability:
        for parameter in self.parameters:
            if parameter.name == name:
                return parameter
        raise KeyError(f"no parameter {name!r} (have {', '.join(p.name for p in self.parameters)})")


def on_stations(station_m: np.ndarray, values: np.ndarray, at_m: np.ndarray, max_gap_m: float = MAX_GAP_M) -> np.ndarray:
    """``values`` given at increasing ``station_m`` interpolated at ``at_m``; NaN outside the run,
    across a gap wider than ``max_gap_m`` or between a NaN value and another (a station met
    exactly keeps its value)."""
    station_m, values, at_m = (np.asarray(a, dtype=float) for a in (station_m, values, at_m))
    out = np.full(at_m.shape, np.nan)
    if station_m.size < 2:
        return out
    right = np.clip(np.searchsorted(station_m, at_m), 1, station_m.size - 1)
    left = right - 1
    s0, s1 = station_m[left], station_m[right]
    inside = (at_m >= station_m[0]) & (at_m <= station_m[-1]) & (s1 - s0 <= max_gap_m)
    weight = np.where(s1 > s0, (at_m - s0) / np.where(s1 > s0, s1 - s0, 1.0), 0.0)
    with np.errstate(invalid="ignore"):
        blend = (1.0 - weight) * values[left] + weight * values[right]
    # a station met exactly takes its own value, whatever its neighbour holds
    blend = np.where(weight == 0.0, values[left], np.where(weight == 1.0, values[right], blend))
    out[inside] = blend[inside]
    return out


def _statistics(name: str, difference: np.ndarray, by_magnitude: bool = False) -> ParameterRepeatability:
    finite = np.isfinite(difference)
    count = finite.sum(axis=1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN rows: statistics NaN, count 0 says why
        mean = np.nanmean(difference, axis=1)
        std = np.nanstd(difference, axis=1, ddof=1)
        rms = np.sqrt(np.nanmean(difference**2, axis=1))
        p95 = np.nanpercentile(np.abs(difference), 95, axis=1)
        largest = np.nanmax(np.abs(difference), axis=1)
    usable = count > 1
    pooled = (np.sqrt(np.sum((count[usable] - 1) * std[usable] ** 2) / np.sum(count[usable] - 1))
              if usable.any() else float("nan"))
    return ParameterRepeatability(name, difference, count, mean, std, rms, p95, largest, float(pooled / np.sqrt(2.0)),
                                  by_magnitude)


def complete_over(station_m: np.ndarray, reach_m: float, max_gap_m: float = MAX_GAP_M) -> np.ndarray:
    """Stations (increasing) with stations ``reach_m`` either side without a gap wider than ``max_gap_m``."""
    station_m = np.asarray(station_m, dtype=float)
    if station_m.size == 0:
        return np.zeros(0, dtype=bool)
    block = np.concatenate([[0], np.cumsum(np.diff(station_m) > max_gap_m)])
    first = np.flatnonzero(np.diff(np.concatenate([[-1], block])))
    last = np.concatenate([first[1:] - 1, [station_m.size - 1]])
    return (station_m - station_m[first[block]] >= reach_m - 1e-9) & (station_m[last[block]] - station_m >= reach_m - 1e-9)


def repeatability(runs: dict[str, tuple[np.ndarray, dict[str, np.ndarray]]], reference: str | None = None,
                  max_gap_m: float = MAX_GAP_M, placements_m: Mapping[str, float] | None = None) -> Repeatability:
    """Compare repeated runs: ``runs`` maps a run's name to (stations [m], {parameter: values});
    the parameters compared are those every run has. ``reference`` (default: the first run)
    gives the stations and is subtracted from the others. ``placements_m`` maps the parameters
    whose value is the worst over chord placements to their chord length [m]: those are compared
    by magnitude where both runs are complete a chord length either side (module docstring)."""
    if len(runs) < 2:
        raise ValueError(f"repeatability needs at least two runs, got {len(runs)}")
    names = list(runs)
    reference = names[0] if reference is None else reference
    if reference not in runs:
        raise ValueError(f"reference run {reference!r} is not among the runs ({', '.join(names)})")
    compared = tuple(name for name in names if name != reference)
    for name, (stations, values) in runs.items():
        stations = np.asarray(stations, dtype=float)
        if stations.ndim != 1 or np.any(np.diff(stations) <= 0):
            raise ValueError(f"run {name!r}: stations must be one strictly increasing array")
        for parameter, column in values.items():
            if np.shape(column) != stations.shape:
                raise ValueError(f"run {name!r}: {parameter} has {np.shape(column)} values for {stations.size} stations")
    placements_m = dict(placements_m or {})
    common = [p for p in runs[reference][1] if all(p in runs[name][1] for name in compared)]
    at = np.asarray(runs[reference][0], dtype=float)

    def values(name: str, parameter: str) -> np.ndarray:
        stations, columns = runs[name]
        column = np.asarray(columns[parameter], dtype=float)
        if parameter not in placements_m:
            return column
        # magnitudes before interpolating: the signed worst value jumps where its sign flips
        return np.where(complete_over(stations, placements_m[parameter], max_gap_m), np.abs(column), np.nan)

    parameters = []
    for parameter in common:
        base = values(reference, parameter)
        difference = np.array([on_stations(runs[name][0], values(name, parameter), at, max_gap_m) - base
                               for name in compared])
        parameters.append(_statistics(parameter, difference, parameter in placements_m))
    return Repeatability(reference, compared, at, tuple(parameters))
