"""Track parameters per sleeper: gauge deviation and change rate, cross-level, twist, cant change,
alignment and height change rates, cant deficiency and its rate.

Inputs are plain arrays at the sleepers (``station_m`` increasing; NaN marks an invalid
sleeper). Cant is positive when the left rail is higher (see :mod:`insrail.track`); all
values are in metres, rates are dimensionless (1/1500 = 0.000667) except the cant deficiency
rate [m/s]. Curvature is signed, positive turning right (:mod:`insrail.track.alignment`), so a
right-hand curve wants the left rail higher: the equilibrium cant has the sign of the curvature.

Cant deficiency (thesis §5.6 lists it with the change rates; EN 13803 defines it) at line
speed v on a curve of radius R: the equilibrium cant e = b·v²/(g·R) on the cant base b
(11.8·v²/R mm for v in km/h, R in m, b = 1.5 m, g = 9.81 m/s²) minus the cant applied on the
curve's side, D = |e| − sign(κ)·c: positive when the track is under-canted for that speed,
negative for cant excess. On straight track (κ = 0) D = −|c|. Its rate is the change of D a
vehicle at line speed meets per second, dD/ds·v over a base.

Quantities over a base length b (twist, gauge change rate) are anchored at a measured sleeper:
the base ends at the sleeper, f(s) - f(s - b), or starts there, f(s + b) - f(s); the sleeper
gets the one of larger magnitude. The far end is interpolated linearly (sleepers are not
exactly b apart), but the sleeper's own value is never diluted, so a defect at one sleeper
shows its full size. NaN where neither base fits inside valid data.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from insrail.track.irregularity import (
    DEFAULT_MAX_GAP_M,
    check_series,
    interpolate_valid,
)

NOMINAL_GAUGE_M = 1.435
#: The gravity of railway cant formulas (11.8·v²/R with v in km/h: 1500 / (3.6² · 9.81) = 11.80).
CANT_GRAVITY_MPS2 = 9.81
#: The cant base of the 11.8 formula (rail centre spacing of standard gauge) [m].
CANT_FORMULA_BASE_M = 1.5


def difference_over_base(
    station_m: np.ndarray, values: np.ndarray, base_m: float, max_gap_m: float = DEFAULT_MAX_GAP_M
) -> np.ndarray:
    """Signed difference of ``values`` over a base ending or starting at each station, whichever
    is larger in magnitude (same unit as ``values``; forward difference sign in both cases)."""
    station, data = check_series(station_m, values, "difference_over_base")
    if base_m <= 0:
        raise ValueError(f"base length must be positive, found {base_m} m")
    ending = data - interpolate_valid(station, data, station - base_m, max_gap_m)
    starting = interpolate_valid(station, data, station + base_m, max_gap_m) - data
    take_starting = np.isnan(ending) | (np.abs(starting) > np.abs(ending))
    return np.where(take_starting, starting, ending)


def change_to_previous(station_m: np.ndarray, values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(change from the previous sleeper, that change divided by the sleeper spacing); NaN at the first."""
    station, data = check_series(station_m, values, "change_to_previous")
    change = np.full(data.shape, np.nan)
    rate = np.full(data.shape, np.nan)
    change[1:] = np.diff(data)
    rate[1:] = change[1:] / np.diff(station)
    return change, rate


@dataclass(frozen=True)
class TrackParameters:
    """Per-sleeper parameters [m unless stated]; bases in ``*_base_m``."""

    station_m: np.ndarray
    gauge_deviation_m: np.ndarray  # measured - nominal gauge
    gauge_change_m: np.ndarray  # to the previous sleeper (thesis column 轨距邻点递变)
    gauge_change_rate_sleeper: np.ndarray  # gauge_change_m / sleeper spacing, dimensionless
    gauge_change_rate: np.ndarray  # over gauge_change_base_m, dimensionless
    gauge_change_base_m: float
    cross_level_m: np.ndarray  # measured - design cant
    twist_m: np.ndarray  # measured cant difference over twist_base_m (design cant ramp included)
    twist_from_design_m: np.ndarray  # cross-level difference over twist_base_m (design ramp removed)
    twist_base_m: float
    cant_change_rate: np.ndarray  # measured cant change to the previous sleeper / spacing


def track_parameters(
    station_m: np.ndarray,
    gauge_m: np.ndarray,
    cant_m: np.ndarray,
    design_cant_m: np.ndarray | None = None,
    nominal_gauge_m: float = NOMINAL_GAUGE_M,
    gauge_change_base_m: float = 2.5,
    twist_base_m: float = 3.0,
    max_gap_m: float = DEFAULT_MAX_GAP_M,
) -> TrackParameters:
    """Gauge, cross-level and twist parameters at every sleeper (design cant 0 when None)."""
    station, gauge = check_series(station_m, gauge_m, "gauge_m")
    _, cant = check_series(station, cant_m, "cant_m")
    design = np.zeros_like(cant) if design_cant_m is None else check_series(station, design_cant_m, "design_cant_m")[1]
    gauge_change, gauge_rate_sleeper = change_to_previous(station, gauge)
    cross_level = cant - design
    return TrackParameters(
        station_m=station,
        gauge_deviation_m=gauge - nominal_gauge_m,
        gauge_change_m=gauge_change,
        gauge_change_rate_sleeper=gauge_rate_sleeper,
        gauge_change_rate=difference_over_base(station, gauge, gauge_change_base_m, max_gap_m) / gauge_change_base_m,
        gauge_change_base_m=float(gauge_change_base_m),
        cross_level_m=cross_level,
        twist_m=difference_over_base(station, cant, twist_base_m, max_gap_m),
        twist_from_design_m=difference_over_base(station, cross_level, twist_base_m, max_gap_m),
        twist_base_m=float(twist_base_m),
        cant_change_rate=change_to_previous(station, cant)[1],
    )


def rate_over_base(station_m: np.ndarray, values: np.ndarray, base_m: float,
                   max_gap_m: float = DEFAULT_MAX_GAP_M) -> np.ndarray:
    """Change rate of ``values`` over ``base_m`` (:func:`difference_over_base` / base; dimensionless
    for lengths): the cant change rate from cant, the alignment / height change rate from a rail's
    lateral / vertical deviation."""
    return difference_over_base(station_m, values, base_m, max_gap_m) / base_m


def equilibrium_cant_m(curvature_1pm: np.ndarray, speed_mps: np.ndarray,
                       cant_base_m: float = CANT_FORMULA_BASE_M) -> np.ndarray:
    """Signed cant that balances the centripetal acceleration v²κ: b·v²·κ/g (+ left rail higher)."""
    return cant_base_m * np.asarray(speed_mps, dtype=float) ** 2 * np.asarray(curvature_1pm, dtype=float) \
        / CANT_GRAVITY_MPS2


def cant_deficiency_m(curvature_1pm: np.ndarray, speed_mps: np.ndarray, cant_m: np.ndarray,
                      cant_base_m: float = CANT_FORMULA_BASE_M) -> np.ndarray:
    """D = |e| − sign(κ)·c (see the module docstring); NaN where curvature, speed or cant is unknown."""
    curvature = np.asarray(curvature_1pm, dtype=float)
    cant = np.asarray(cant_m, dtype=float)
    side = np.where(curvature != 0.0, np.sign(curvature), np.sign(cant))
    return np.abs(equilibrium_cant_m(curvature, speed_mps, cant_base_m)) - side * cant


def cant_deficiency_rate_mps(station_m: np.ndarray, deficiency_m: np.ndarray, speed_mps: np.ndarray,
                             base_m: float, max_gap_m: float = DEFAULT_MAX_GAP_M) -> np.ndarray:
    """Change of the cant deficiency per second at line speed: D's rate over ``base_m`` times v [m/s]."""
    return rate_over_base(station_m, deficiency_m, base_m, max_gap_m) * np.asarray(speed_mps, dtype=float)


@dataclass(frozen=True)
class LineSpeed:
    """The line speed over a range of stations (``from_m`` inclusive, ``to_m`` exclusive)."""

    from_m: float
    to_m: float
    kmh: float


def line_speed_mps(ranges: tuple[LineSpeed, ...], station_m: np.ndarray) -> np.ndarray:
    """Line speed [m/s] at each station; NaN where no range covers it (later ranges win an overlap)."""
    station = np.asarray(station_m, dtype=float)
    speed = np.full(station.shape, np.nan)
    for entry in ranges:
        speed[(station >= entry.from_m) & (station < entry.to_m)] = entry.kmh / 3.6
    return speed


def guiding_rail_is_right(design_cant_m: np.ndarray) -> np.ndarray:
    """The guiding rail per sleeper (thesis Fig. 5-7 column 导向轨), True where it is the right rail.

    Chinese fine-adjustment practice lines a curve up on its outer, higher rail; on straight track
    (design cant 0) the left rail in the direction of increasing chainage guides. [U]: the thesis
    prints the flag without defining it; this is the rule of the adjustment crews' handbooks.
    """
    return np.asarray(design_cant_m, dtype=float) < 0.0  # cant + when the left rail is higher
