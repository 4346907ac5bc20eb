"""Assess per-sleeper track geometry against a tolerance profile: values and exceedance runs.

Inputs are the plain arrays of the sleeper table: ``station_m`` (n), ``lateral_deviation_m``
and ``vertical_deviation_m`` (n, 2) with columns [left, right] (lateral + right, vertical + up),
``gauge_m``, ``cant_m``, ``design_cant_m`` (n) and an optional ``valid`` mask (invalid
sleepers become NaN before anything is computed, so no chord or base uses them).

Every check of the profile produces one or more *channels* (a check on both rails and two
directions gives four). An exceedance is a run of consecutive sleepers whose value lies
outside the check's limits; it carries the chainage range, the signed peak, the limit the peak
crosses and the first and last sleeper numbers.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from insrail.track.irregularity import (
    SectionStatistics,
    band_pass,
    check_series,
    differential_versine,
    section_statistics,
    versine,
)
from insrail.track.parameters import (
    cant_deficiency_m,
    cant_deficiency_rate_mps,
    change_to_previous,
    difference_over_base,
    rate_over_base,
)
from insrail.track.tolerance import Check, ToleranceProfile

RAILS = ("left", "right")
#: How far beyond a limit [the check's unit] a value must lie to exceed it (floating-point noise).
LIMIT_TOLERANCE = 1e-12


@dataclass(frozen=True)
class SleeperGeometry:
    """The per-sleeper arrays an assessment needs (SI units; NaN where not measured)."""

    station_m: np.ndarray
    lateral_deviation_m: np.ndarray  # (n, 2) [left, right], + right
    vertical_deviation_m: np.ndarray  # (n, 2) [left, right], + up
    gauge_m: np.ndarray
    cant_m: np.ndarray  # + when the left rail is higher
    design_cant_m: np.ndarray
    sleeper_number: np.ndarray  # (n) int, as printed for the crews
    # for the cant deficiency checks; None (unknown: those channels are NaN) without a line speed
    curvature_1pm: np.ndarray | None = None  # + turning right, of the design (or fitted) line
    line_speed_mps: np.ndarray | None = None

    @classmethod
    def from_arrays(
        cls,
        station_m,
        lateral_deviation_m,
        vertical_deviation_m,
        gauge_m,
        cant_m,
        design_cant_m=None,
        valid=None,
        sleeper_number=None,
        curvature_1pm=None,
        line_speed_mps=None,
    ) -> SleeperGeometry:
        station = np.asarray(station_m, dtype=float)
        n = station.size
        check_series(station, np.zeros(n), "station_m")
        arrays = {}
        for name, raw, shape in (
            ("lateral_deviation_m", lateral_deviation_m, (n, 2)),
            ("vertical_deviation_m", vertical_deviation_m, (n, 2)),
            ("gauge_m", gauge_m, (n,)),
            ("cant_m", cant_m, (n,)),
            ("design_cant_m", np.zeros(n) if design_cant_m is None else design_cant_m, (n,)),
        ):
            array = np.array(raw, dtype=float)
            if array.shape != shape:
                raise ValueError(f"{name}: expected shape {shape} (one row per sleeper), found {array.shape}")
            arrays[name] = array
        if valid is not None:
            mask = np.asarray(valid, dtype=bool)
            if mask.shape != (n,):
                raise ValueError(f"valid: expected one flag per sleeper ({n}), found shape {mask.shape}")
            for name in ("lateral_deviation_m", "vertical_deviation_m", "gauge_m", "cant_m"):
                arrays[name][~mask] = np.nan
        numbers = np.arange(1, n + 1) if sleeper_number is None else np.asarray(sleeper_number, dtype=int)
        if numbers.shape != (n,):
            raise ValueError(f"sleeper_number: expected one number per sleeper ({n}), found shape {numbers.shape}")
        for name, raw in (("curvature_1pm", curvature_1pm), ("line_speed_mps", line_speed_mps)):
            if raw is not None:
                arrays[name] = np.array(raw, dtype=float)
                if arrays[name].shape != (n,):
                    raise ValueError(f"{name}: expected one value per sleeper ({n}), found {arrays[name].shape}")
        return cls(station_m=station, sleeper_number=numbers, **arrays)

    def cant_deficiency_m(self) -> np.ndarray:
        """Cant deficiency at line speed (:func:`insrail.track.parameters.cant_deficiency_m`); NaN
        without a line speed or a curvature."""
        if self.curvature_1pm is None or self.line_speed_mps is None:
            return np.full(self.station_m.shape, np.nan)
        return cant_deficiency_m(self.curvature_1pm, self.line_speed_mps, self.cant_m)


@dataclass(frozen=True)
class Channel:
    """Per-sleeper values of one check on one rail/direction (``rail`` "track" for both rails)."""

    check: str
    kind: str
    rail: str
    direction: str
    values: np.ndarray  # m, or a ratio for rates
    lower: float
    upper: float


@dataclass(frozen=True)
class Exceedance:
    check: str
    kind: str
    rail: str
    direction: str
    station_from_m: float
    station_to_m: float
    peak: float  # signed value of largest excess, m (ratio for rates)
    limit: float  # the bound the peak crosses, same unit
    first_index: int
    last_index: int
    first_sleeper: int
    last_sleeper: int


@dataclass(frozen=True)
class Assessment:
    profile: str
    channels: tuple[Channel, ...]
    exceedances: tuple[Exceedance, ...]

    def channel(self, check: str, rail: str = "track", direction: str = "") -> Channel:
        for channel in self.channels:
            if (channel.check, channel.rail, channel.direction) == (check, rail, direction):
                return channel
        raise KeyError(f"no channel {check}/{rail}/{direction}")


def _rail_signals(geometry: SleeperGeometry, check: Check, signal: Callable[[np.ndarray], np.ndarray]):
    deviations = {"lateral": geometry.lateral_deviation_m, "vertical": geometry.vertical_deviation_m}
    for direction in check.directions:
        for column, rail in enumerate(RAILS):
            yield rail, direction, signal(deviations[direction][:, column])


def _track_signal(values: np.ndarray):
    yield "track", "", values


def _cross_level(geometry: SleeperGeometry) -> np.ndarray:
    return geometry.cant_m - geometry.design_cant_m


def _gauge_change_rate(geometry: SleeperGeometry, check: Check, nominal_gauge_m: float):
    s, gauge = geometry.station_m, geometry.gauge_m
    if check.base_m is None:
        return _track_signal(change_to_previous(s, gauge)[1])
    return _track_signal(difference_over_base(s, gauge, check.base_m) / check.base_m)


def _twist(geometry: SleeperGeometry, check: Check, nominal_gauge_m: float):
    cant = _cross_level(geometry) if check.relative_to_design else geometry.cant_m
    return _track_signal(difference_over_base(geometry.station_m, cant, check.base_m))


def _cant_deficiency_rate(geometry: SleeperGeometry, check: Check, nominal_gauge_m: float):
    speed = geometry.line_speed_mps if geometry.line_speed_mps is not None else np.nan
    return _track_signal(cant_deficiency_rate_mps(geometry.station_m, geometry.cant_deficiency_m(), speed,
                                                  check.base_m))


# kind -> function(geometry, check, nominal gauge) yielding (rail, direction, values) per channel
SIGNALS = {
    "gauge_deviation": lambda g, check, nominal: _track_signal(g.gauge_m - nominal),
    "gauge_change_rate": _gauge_change_rate,
    "cross_level": lambda g, check, nominal: _track_signal(_cross_level(g)),
    "twist": _twist,
    "versine": lambda g, check, nominal: _rail_signals(
        g, check, lambda d: versine(g.station_m, d, check.chord_m, check.back_m)
    ),
    "differential_versine": lambda g, check, nominal: _rail_signals(
        g, check, lambda d: differential_versine(g.station_m, d, check.chord_m, check.pair_m)
    ),
    "band_peak": lambda g, check, nominal: _rail_signals(g, check, lambda d: band_pass(g.station_m, d, check.band)),
    "cant_change_rate": lambda g, check, nominal: _track_signal(rate_over_base(g.station_m, g.cant_m, check.base_m)),
    "deviation_change_rate": lambda g, check, nominal: _rail_signals(
        g, check, lambda d: rate_over_base(g.station_m, d, check.base_m)
    ),
    "cant_deficiency": lambda g, check, nominal: _track_signal(g.cant_deficiency_m()),
    "cant_deficiency_rate": _cant_deficiency_rate,
}


def exceedance_runs(values: np.ndarray, lower: float, upper: float) -> list[tuple[int, int, int]]:
    """(first, last, peak index) of every run of consecutive entries outside [lower, upper]."""
    with np.errstate(invalid="ignore"):
        excess = np.fmax(values - upper, lower - values)
    # a value on the limit is inside: the rounding noise of e.g. 1.435 m + 1 mm - 1.435 m is not an excess
    outside = excess > LIMIT_TOLERANCE
    edges = np.flatnonzero(np.diff(np.concatenate([[0], outside.astype(np.int8), [0]])))
    runs = []
    for first, stop in zip(edges[::2], edges[1::2]):  # one iteration per run, not per sleeper
        runs.append((int(first), int(stop - 1), int(first + np.argmax(excess[first:stop]))))
    return runs


def assess(geometry: SleeperGeometry, profile: ToleranceProfile,
           not_assessed: Mapping[tuple[str, str], np.ndarray] | None = None) -> Assessment:
    """Every check of ``profile`` on ``geometry``: channel values and exceedances in station order.
    ``not_assessed``: (check name, direction) -> the sleepers (n,) where that check cannot be told
    (its values there NaN, no exceedance found there); direction "" for a check of the whole track."""
    channels = []
    exceedances = []
    for check in profile.checks:
        for rail, direction, values in SIGNALS[check.kind](geometry, check, profile.nominal_gauge_m):
            left_out = (not_assessed or {}).get((check.name, direction))
            if left_out is not None:
                values = np.where(left_out, np.nan, values)
            channels.append(Channel(check.name, check.kind, rail, direction, values, check.lower, check.upper))
            for first, last, peak in exceedance_runs(values, check.lower, check.upper):
                exceedances.append(
                    Exceedance(
                        check=check.name,
                        kind=check.kind,
                        rail=rail,
                        direction=direction,
                        station_from_m=float(geometry.station_m[first]),
                        station_to_m=float(geometry.station_m[last]),
                        peak=float(values[peak]),
                        limit=check.upper if values[peak] > check.upper else check.lower,
                        first_index=first,
                        last_index=last,
                        first_sleeper=int(geometry.sleeper_number[first]),
                        last_sleeper=int(geometry.sleeper_number[last]),
                    )
                )
    exceedances.sort(key=lambda e: (e.station_from_m, e.check, e.rail, e.direction))
    return Assessment(profile.name, tuple(channels), tuple(exceedances))


def track_quality(
    geometry: SleeperGeometry, band: str | tuple[float, float] = "D1", section_m: float = 200.0, twist_base_m: float = 3.0
) -> SectionStatistics:
    """Standard deviations of the 7 TQI channels per ``section_m`` section; their sum per section
    (``track_quality_index_m``) is the Chinese TQI (轨道质量指数). Level and alignment are the
    deviations band-passed to ``band`` (EN 13848 D1 by default; inspection cars use about
    1.5-42 m); gauge is the deviation from nominal, twist is over ``twist_base_m`` of cross-level."""
    s = geometry.station_m
    cross_level = _cross_level(geometry)
    channels = {}
    for direction, deviation in (("level", geometry.vertical_deviation_m), ("alignment", geometry.lateral_deviation_m)):
        for column, rail in enumerate(RAILS):
            channels[f"{rail}_{direction}"] = band_pass(s, deviation[:, column], band)
    channels["gauge"] = geometry.gauge_m  # a standard deviation: the nominal value drops out
    channels["cross_level"] = cross_level
    channels["twist"] = difference_over_base(s, cross_level, twist_base_m)
    return section_statistics(s, channels, section_m)
