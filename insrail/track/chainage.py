"""Chainage (station) of the measured rail points.

With a design alignment every point gets the station of the foot of its perpendicular on
the design's plan (:meth:`HorizontalAlignment.station_offset`): each rail and the centreline
are projected separately, so a rail point that the trolley's cross axis put a little ahead
of or behind the centreline (pitch times cant, yaw of the trolley against the track) still
gets its own exact station.

Without a design the centreline's station is the plane distance travelled along it from a
given start station (thesis 5.3.2.1). The distance is accumulated as the projection of each
step on the trolley's forward axis, so position noise while the trolley stands still adds up
to zero instead of growing like a random walk, and reversing decreases the station. The rail
points get the centreline station plus their own along-track offset from the centreline.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from insrail.track.alignment import DesignAlignment
from insrail.track.rails import RailPoints


@dataclass(frozen=True)
class RailStations:
    """Stations [m] (continuous measure, see :mod:`insrail.track`) of each epoch's points.

    ``centre_offset_m`` is the centreline's horizontal offset from the design (+ right), NaN
    without a design. NaN stations: the point projects beyond the design's ends, or has no
    gauge (non-reference rail and centreline).
    """

    centre_m: np.ndarray
    left_m: np.ndarray
    right_m: np.ndarray
    reference_m: np.ndarray
    centre_offset_m: np.ndarray
    from_design: bool


def stations_on_design(rails: RailPoints, design: DesignAlignment) -> RailStations:
    """Stations of the centreline and both rails by projection on the design's plan."""
    h = design.horizontal
    centre, offset = h.station_offset(rails.centre_enh_m[:, 0], rails.centre_enh_m[:, 1])
    left, _ = h.station_offset(rails.left_rail_enh_m[:, 0], rails.left_rail_enh_m[:, 1])
    right, _ = h.station_offset(rails.right_rail_enh_m[:, 0], rails.right_rail_enh_m[:, 1])
    reference = left if rails.reference_rail == "left" else right
    return RailStations(centre, left, right, reference, offset, from_design=True)


def stations_along_path(rails: RailPoints, start_station_m: float) -> RailStations:
    """Stations as travelled plane distance along the centreline from ``start_station_m`` at the
    first epoch, increasing in the direction of travel.

    The centreline of epochs without gauge is bridged by the reference rail's motion.
    """
    centre = rails.centre_enh_m[:, :2]
    reference = rails.reference_rail_enh_m[:, :2]
    track = np.where(np.isnan(centre), reference, centre)
    forward = rails.forward_enh[:, :2]
    forward = forward / np.linalg.norm(forward, axis=1)[:, None]
    mid_forward = 0.5 * (forward[1:] + forward[:-1])
    along_steps = np.einsum("ij,ij->i", np.diff(track, axis=0), mid_forward)
    travelled = np.concatenate([[0.0], np.cumsum(along_steps)])
    # Stations grow in the direction of travel, whichever way the trolley's x axis points.
    direction = 1.0 if travelled[-1] >= 0.0 else -1.0
    centre_station = start_station_m + direction * travelled

    def shifted(points: np.ndarray) -> np.ndarray:
        along = np.einsum("ij,ij->i", points[:, :2] - track, forward)
        return centre_station + direction * along

    left, right = shifted(rails.left_rail_enh_m), shifted(rails.right_rail_enh_m)
    ref = left if rails.reference_rail == "left" else right
    centre_station = np.where(np.isnan(rails.centre_enh_m[:, 0]), np.nan, centre_station)
    return RailStations(centre_station, left, right, ref, np.full(len(rails), np.nan), from_design=False)


def epoch_station_track(time_s: np.ndarray, station_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(time, station) of the epochs with a finite station, the station made non-decreasing.

    Sensor events (sleeper pulses, gauge readings) get their station by interpolating this in
    time; the running maximum removes the sub-millimetre back-and-forth of a standing trolley
    so that time <-> station stays invertible.
    """
    finite = np.isfinite(station_m)
    if finite.sum() < 2:
        raise ValueError("fewer than two epochs have a station: does the trajectory lie along the design?")
    t, s = np.asarray(time_s)[finite], np.asarray(station_m)[finite]
    if s[-1] < s[0]:
        raise ValueError("the trolley runs against the stationing; reverse the alignment or the survey")
    return t, np.maximum.accumulate(s)
