"""Deviations of each rail from its design position.

The design rails at station s are built exactly like the true rails of the simulator
(docs/simulator.md): design centre D(s) = plan point + design height; cross slope phi_d with
sin(phi_d) = design cant / cant base (1.5 m); cross axis y_d = cos(phi_d) n - sin(phi_d) up
(n = horizontal unit normal to the RIGHT of the design tangent); design left rail
D - (g0 / 2) y_d, design right rail D + (g0 / 2) y_d, g0 = the design (nominal) gauge.

A measured rail point is projected on the design's plan, giving its own station s_r and
horizontal offset o_r (+ right). Then, per rail:

* lateral deviation  = o_r - design rail offset at s_r   (+ = the rail lies to the RIGHT of
  its design position, looking towards increasing station);
* vertical deviation = H_r - design rail height at s_r   (+ = the rail lies ABOVE its design
  position).

With a measured centreline C = D + l n + v up, gauge g and cant c (sin(phi) = c / 1.5 m) the
rails are C -/+ (g / 2) y, so the deviations are, with G = g cos(phi) - g0 cos(phi_d) and
V = g sin(phi) - g0 sin(phi_d):  left lateral = l - G / 2, right lateral = l + G / 2,
left vertical = v + V / 2, right vertical = v - V / 2. A wide gauge moves both rails
outwards; a cant excess lifts the left rail and lowers the right one.

When the "design" is a fitted (best-line) alignment the same numbers are the deviations
from the best fit ("measured - optimal" of the thesis's sleeper table).
"""

from __future__ import annotations

import numpy as np

from insrail.track.alignment import DesignAlignment

NOMINAL_GAUGE_M = 1.435
CANT_BASE_M = 1.5


def design_cant_m(design: DesignAlignment, station_m) -> np.ndarray:
    """Design cant [m] at the stations; 0 where the design has no cant table."""
    s = np.asarray(station_m, dtype=float)
    if design.cant is None:
        return np.zeros_like(s)
    stations = design.cant.stations_m
    return _evaluate_inside(design.cant.cant_at, s, stations[0], stations[-1])


def _evaluate_inside(function, station_m: np.ndarray, first_m: float, last_m: float) -> np.ndarray:
    """A design function (profile, cant table) at the stations inside its range [first_m, last_m],
    NaN elsewhere: a measurement running past the end of the design's profile or cant table is
    not assessed, like one projecting beyond the plan's ends (the design functions refuse both)."""
    out = np.full(station_m.shape, np.nan)
    inside = np.isfinite(station_m) & (station_m >= first_m) & (station_m <= last_m)
    if inside.any():
        out[inside] = function(station_m[inside])
    return out


def design_rail_offsets(design: DesignAlignment, station_m, design_gauge_m: float = NOMINAL_GAUGE_M,
                        cant_base_m: float = CANT_BASE_M):
    """(horizontal offset [m, + right], height above the design centre [m]) of the left and
    right design rails at the stations: arrays (n, 2) = [left, right]."""
    return _rail_offsets(design_cant_m(design, station_m), design_gauge_m, cant_base_m)


def _rail_offsets(cant_m, design_gauge_m: float, cant_base_m: float):
    sin_slope = np.asarray(cant_m, dtype=float) / cant_base_m
    half = 0.5 * design_gauge_m
    horizontal = half * np.sqrt(1.0 - sin_slope**2)
    vertical = half * sin_slope
    return np.column_stack([-horizontal, horizontal]), np.column_stack([vertical, -vertical])


def rail_deviations(
    design: DesignAlignment,
    left_rail_enh_m: np.ndarray,
    right_rail_enh_m: np.ndarray,
    design_gauge_m: float = NOMINAL_GAUGE_M,
    cant_base_m: float = CANT_BASE_M,
) -> tuple[np.ndarray, np.ndarray]:
    """(lateral, vertical) deviations [m], arrays (n, 2) = [left, right] (see the module docstring).

    Vertical deviations are NaN when the design has no profile; points projecting beyond the
    design's ends (of the plan, the profile or the cant table) give NaN.
    """
    lateral = np.empty((len(left_rail_enh_m), 2))
    vertical = np.empty_like(lateral)
    for column, rail in enumerate((left_rail_enh_m, right_rail_enh_m)):
        station, offset = design.horizontal.station_offset(rail[:, 0], rail[:, 1])
        design_offset, design_rise = design_rail_offsets(design, station, design_gauge_m, cant_base_m)
        lateral[:, column] = offset - design_offset[:, column]
        if design.vertical is None:
            vertical[:, column] = np.nan
        else:
            pvi_stations = design.vertical.stations_m
            design_height = (_evaluate_inside(design.vertical.elevation_at, station, pvi_stations[0], pvi_stations[-1])
                             + design_rise[:, column])
            vertical[:, column] = rail[:, 2] - design_height
    return lateral, vertical


def rail_deviations_from_reference(
    reference_enh_m: np.ndarray,
    reference_azimuth_rad: np.ndarray,
    reference_cant_m: np.ndarray,
    left_rail_enh_m: np.ndarray,
    right_rail_enh_m: np.ndarray,
    design_gauge_m: float = NOMINAL_GAUGE_M,
    cant_base_m: float = CANT_BASE_M,
) -> tuple[np.ndarray, np.ndarray]:
    """(lateral, vertical) deviations [m], (n, 2) = [left, right], from a pointwise reference line.

    For a reference given only at the sections (the windowed best fit of
    :mod:`insrail.track.linefit_windows`): centre point E, N, H, tangent azimuth and cant of
    each section, whose rails sit where the module docstring puts the design rails. A rail's
    lateral deviation is its offset across the reference tangent minus its reference rail's,
    its vertical deviation its height minus its reference rail's.
    """
    reference = np.asarray(reference_enh_m, dtype=float)
    normal = np.column_stack([np.cos(reference_azimuth_rad), -np.sin(reference_azimuth_rad)])  # to the right
    offsets, rises = _rail_offsets(reference_cant_m, design_gauge_m, cant_base_m)
    lateral = np.empty((len(reference), 2))
    vertical = np.empty_like(lateral)
    for column, rail in enumerate((left_rail_enh_m, right_rail_enh_m)):
        lateral[:, column] = np.sum((rail[:, :2] - reference[:, :2]) * normal, axis=1) - offsets[:, column]
        vertical[:, column] = rail[:, 2] - reference[:, 2] - rises[:, column]
    return lateral, vertical
