"""The true track: design alignment plus injected irregularities, evaluated at stations.

Geometry of a cross-section at design station s (engineering plane E, N; normal
height H; see ``insrail.track`` for the sign conventions):

* centreline C = design point + lateral(s) * n + (0, 0, design H + vertical(s)),
  n = the design's horizontal unit normal to the right;
* running-plane cross slope phi with sin(phi) = cant(s) / 1.5 m, cant = design cant
  + cross-level irregularity (positive: left rail higher);
* cross axis y = cos(phi) n - sin(phi) up (to the right, down the slope when the
  left rail is high);
* rail points (top of rail above the gauge face): left = C - g/2 y, right = C + g/2 y,
  g = nominal gauge + gauge irregularity. So the gauge between them is exactly g and
  the rail-top height difference is g sin(phi).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from insrail.sim.irregularity import Irregularity


@dataclass(frozen=True)
class TrackSections:
    """Cross-sections of the true track at ``station_m`` (arrays (n,) or (n, 3) = E, N, H)."""

    station_m: np.ndarray
    centre_enh_m: np.ndarray
    left_rail_enh_m: np.ndarray
    right_rail_enh_m: np.ndarray
    gauge_m: np.ndarray
    cant_m: np.ndarray  # measured-equivalent cant, 1.5 m * sin(cross slope)
    cross_slope_rad: np.ndarray
    design_centre_enh_m: np.ndarray
    design_cant_m: np.ndarray
    design_azimuth_rad: np.ndarray
    lateral_m: np.ndarray  # injected centreline irregularities
    vertical_m: np.ndarray
    gauge_deviation_m: np.ndarray
    cross_level_m: np.ndarray

    def rail(self, side: str) -> np.ndarray:
        return self.left_rail_enh_m if side == "left" else self.right_rail_enh_m


@dataclass(frozen=True)
class TrueTrack:
    design: object  # insrail.track.alignment.DesignAlignment
    lateral: Irregularity
    vertical: Irregularity
    gauge: Irregularity
    cross_level: Irregularity
    nominal_gauge_m: float = 1.435
    cant_base_m: float = 1.5

    def sections(self, station_m) -> TrackSections:
        s = np.asarray(station_m, dtype=float)
        h = self.design.horizontal
        east, north = h.point_at(s)
        azimuth = h.azimuth_at(s)
        normal = np.column_stack([np.cos(azimuth), -np.sin(azimuth)])  # right of the tangent
        height = self.design.vertical.elevation_at(s)
        design_cant = self.design.cant.cant_at(s)

        lateral = self.lateral.evaluate(s)
        vertical = self.vertical.evaluate(s)
        gauge_dev = self.gauge.evaluate(s)
        cross_level = self.cross_level.evaluate(s)

        centre = np.column_stack([east + lateral * normal[:, 0], north + lateral * normal[:, 1], height + vertical])
        cant = design_cant + cross_level
        slope = np.arcsin(cant / self.cant_base_m)
        cross_axis = np.column_stack([np.cos(slope) * normal[:, 0], np.cos(slope) * normal[:, 1], -np.sin(slope)])
        gauge = self.nominal_gauge_m + gauge_dev
        half = 0.5 * gauge[:, None] * cross_axis
        return TrackSections(
            station_m=s,
            centre_enh_m=centre,
            left_rail_enh_m=centre - half,
            right_rail_enh_m=centre + half,
            gauge_m=gauge,
            cant_m=cant,
            cross_slope_rad=slope,
            design_centre_enh_m=np.column_stack([east, north, height]),
            design_cant_m=design_cant,
            design_azimuth_rad=azimuth,
            lateral_m=lateral,
            vertical_m=vertical,
            gauge_deviation_m=gauge_dev,
            cross_level_m=cross_level,
        )
