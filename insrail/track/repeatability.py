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

Values are in the units given (the project passes metres); stations in metres.
"""

from __future__ import annotations

import warnings
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
    across a gap wider than ``max_gap_m`` or next to a NaN value."""
    station_m, values, at_m = (np.asarray(a, dtype=float) for a in (station_m, values, at_m))
    out = np.full(at_m.shape, np.nan)
    if station_m.size < 2:
        return out
    right = np.clip(np.searchsorted(station_m, at_m), 1, station_m.size - 1)
    left = right - 1
    s0, s1 = station_m[left], station_m[right]
    inside = (at_m >= station_m[0]) & (at_m <= station_m[-1]) & (s1 - s0 <= max_gap_m)
    weight = np.where(s1 > s0, (at_m - s0) / np.where(s1 > s0, s1 - s0, 1.0), 0.0)
    out[inside] = ((1.0 - weight) * values[left] + weight * values[right])[inside]
    return out


def _statistics(name: str, difference: np.ndarray) -> ParameterRepeatability:
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
    return ParameterRepeatability(name, difference, count, mean, std, rms, p95, largest, float(pooled / np.sqrt(2.0)))


def repeatability(runs: dict[str, tuple[np.ndarray, dict[str, np.ndarray]]], reference: str | None = None,
                  max_gap_m: float = MAX_GAP_M) -> Repeatability:
    """Compare repeated runs: ``runs`` maps a run's name to (stations [m], {parameter: values});
    the parameters compared are those every run has. ``reference`` (default: the first run)
    gives the stations and is subtracted from the others."""
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
    common = [p for p in runs[reference][1] if all(p in runs[name][1] for name in compared)]
    at = np.asarray(runs[reference][0], dtype=float)
    parameters = []
    for parameter in common:
        base = np.asarray(runs[reference][1][parameter], dtype=float)
        difference = np.array([on_stations(runs[name][0], runs[name][1][parameter], at, max_gap_m) - base
                               for name in compared])
        parameters.append(_statistics(parameter, difference))
    return Repeatability(reference, compared, at, tuple(parameters))
