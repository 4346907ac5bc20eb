"""Chainage (station) of the measured rail points, and the trolley turned to the stationing.

Direction of travel and facing: a survey may run with or against the stationing and the
trolley may face either way. :func:`rails_from_pose` gives the rails in the trolley's own
frame (its left and right, cant + when ITS left rail is higher); everything reported
follows the stationing instead (see :mod:`insrail.track`). :func:`in_stationing_frame`
turns the rail points over when the trolley's x axis points against the stationing
(``facing`` -1): left and right rails (and which one is the reference) swap, the cant,
cross slope and forward axis change sign. The facing comes from the design's tangent
(:func:`facing_on_design`) or, without a design, from the project's stationing direction
(:func:`facing_along_path`).

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
Which way the stations grow is the project's choice (:data:`WITH_TRAVEL` or a grid azimuth).
"""

from __future__ import annotations

from concurrent.futures import Executor
from dataclasses import dataclass, replace

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


def reference_stations_on_design(rails: RailPoints, design: DesignAlignment,
                                 carry: np.ndarray | None = None) -> np.ndarray:
    """Stations of the reference rail's points by projection on the design's plan (the same in
    either naming of the rails: :func:`in_stationing_frame` keeps the reference rail's points);
    ``carry``: the projection's carry (:meth:`HorizontalAlignment.station_offset`) for rails
    given in consecutive parts."""
    return design.horizontal.station_offset(rails.reference_rail_enh_m[:, 0], rails.reference_rail_enh_m[:, 1],
                                            carry)[0]


def stations_on_design(rails: RailPoints, design: DesignAlignment,
                       reference_station_m: np.ndarray | None = None,
                       carries: dict[str, np.ndarray] | None = None, executor: Executor | None = None) -> RailStations:
    """Stations of the centreline and both rails by projection on the design's plan;
    ``reference_station_m``: the reference rail's, when already projected
    (:func:`reference_stations_on_design`: each projection of 10 km of epochs takes seconds);
    ``carries``: the projections' carries ("centre", "left", "right") for rails given in parts;
    ``executor``: the centreline is projected there meanwhile (the compiled projection runs without
    the GIL; each series has its own carry, so the numbers are the same)."""
    h = design.horizontal
    carries = carries or {}
    centre_args = (h.station_offset, rails.centre_enh_m[:, 0], rails.centre_enh_m[:, 1], carries.get("centre"))
    centre_future = executor.submit(*centre_args) if executor is not None else None

    def projected(rail: str, points: np.ndarray) -> np.ndarray:
        if reference_station_m is not None and rail == rails.reference_rail:
            return reference_station_m
        return h.station_offset(points[:, 0], points[:, 1], carries.get(rail))[0]

    left, right = projected("left", rails.left_rail_enh_m), projected("right", rails.right_rail_enh_m)
    reference = left if rails.reference_rail == "left" else right
    centre, offset = centre_future.result() if centre_future is not None else centre_args[0](*centre_args[1:])
    return RailStations(centre, left, right, reference, offset, from_design=True)


#: Why a track cannot be stationed.
NO_STATIONS = "fewer than two epochs have a station: does the trajectory lie along the design?"

#: Without a design the stations grow in the direction of travel unless an azimuth is given.
WITH_TRAVEL = "travel"


def track_and_forward(rails: RailPoints) -> tuple[np.ndarray, np.ndarray]:
    """(track points E, N; unit forward axes E, N) per epoch. The centreline of epochs without
    gauge is bridged by the reference rail's motion."""
    centre = rails.centre_enh_m[:, :2]
    reference = rails.reference_rail_enh_m[:, :2]
    track = np.where(np.isnan(centre), reference, centre)
    forward = rails.forward_enh[:, :2]
    return track, forward / np.linalg.norm(forward, axis=1)[:, None]


def along_steps(track: np.ndarray, forward: np.ndarray) -> np.ndarray:
    """The plane distance of each step between consecutive track points along the trolley's x axis."""
    mid_forward = 0.5 * (forward[1:] + forward[:-1])
    return np.einsum("ij,ij->i", np.diff(track, axis=0), mid_forward)


def _along_path(rails: RailPoints) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(:func:`track_and_forward`; plane distance travelled along the trolley's x axis since the first epoch)."""
    track, forward = track_and_forward(rails)
    return track, forward, np.concatenate([[0.0], np.cumsum(along_steps(track, forward))])


def finite_ends(track: np.ndarray) -> np.ndarray | None:
    """The first and last track points with a position ((2, 2)), None when fewer than two have one."""
    finite = np.flatnonzero(np.all(np.isfinite(track), axis=1))
    return track[[finite[0], finite[-1]]] if finite.size >= 2 else None


def facing_from(travelled_m: float, ends: np.ndarray | None, stationing: str | float = WITH_TRAVEL) -> float:
    """:func:`facing_along_path` from the distance travelled along the x axis over the whole run
    and the run's :func:`finite_ends`."""
    along_x = 1.0 if travelled_m >= 0.0 else -1.0
    if stationing == WITH_TRAVEL:
        return along_x
    azimuth = np.radians(float(stationing))
    if ends is None:
        raise ValueError("fewer than two epochs have a position: the stationing direction cannot be found")
    travel = ends[1] - ends[0]
    with_travel = 1.0 if travel @ np.array([np.sin(azimuth), np.cos(azimuth)]) >= 0.0 else -1.0
    return along_x * with_travel


def facing_along_path(rails: RailPoints, stationing: str | float = WITH_TRAVEL) -> float:
    """+1 when the stations grow along the trolley's x axis, -1 when against it, for a track
    without a design: ``stationing`` is :data:`WITH_TRAVEL` (stations grow in the direction of
    travel) or the grid azimuth [deg] towards which they grow (within 90 degrees: the run's
    overall direction from its first to its last point decides)."""
    track, _, travelled = _along_path(rails)
    return facing_from(travelled[-1], finite_ends(track), stationing)


def facing_on_design(rails: RailPoints, design: DesignAlignment, reference_station_m: np.ndarray | None = None) -> float:
    """+1 when the trolley's x axis points towards increasing design station, -1 against it
    (the median over the epochs projecting on the design; +1 when none does);
    ``reference_station_m`` as in :func:`stations_on_design`."""
    station = reference_stations_on_design(rails, design) if reference_station_m is None else reference_station_m
    cosine = design_cosines(rails, design, station)
    if not cosine.size:
        return 1.0
    return 1.0 if np.median(cosine) >= 0.0 else -1.0


def design_cosines(rails: RailPoints, design: DesignAlignment, reference_station_m: np.ndarray) -> np.ndarray:
    """Per epoch projecting on the design, the cosine between the trolley's x axis and the design's
    tangent at the reference rail's station (what :func:`facing_on_design` takes the median of)."""
    on = np.isfinite(reference_station_m)
    azimuth = design.horizontal.azimuth_at(reference_station_m[on])
    return rails.forward_enh[on, 0] * np.sin(azimuth) + rails.forward_enh[on, 1] * np.cos(azimuth)


def in_stationing_frame(rails: RailPoints, facing: float) -> RailPoints:
    """The rail points named by the stationing: unchanged for ``facing`` +1; for -1 (the trolley
    faces against the stationing) its left rail is the stationing's right one, so the rails
    (and the reference rail's name) swap and cant, cross slope and forward axis change sign."""
    if facing > 0:
        return rails
    return replace(
        rails,
        reference_rail="right" if rails.reference_rail == "left" else "left",
        left_rail_enh_m=rails.right_rail_enh_m,
        right_rail_enh_m=rails.left_rail_enh_m,
        forward_enh=-rails.forward_enh,
        cross_slope_rad=-rails.cross_slope_rad,
        cant_m=-rails.cant_m,
    )


def stations_along_path(rails: RailPoints, start_station_m: float, stationing: str | float = WITH_TRAVEL) -> RailStations:
    """Stations as travelled plane distance along the centreline from ``start_station_m`` at the
    first epoch, growing in the direction ``stationing`` names (see :func:`facing_along_path`):
    a run against that direction gets decreasing stations.
    """
    track, forward, travelled = _along_path(rails)
    direction = facing_from(travelled[-1], finite_ends(track), stationing)
    return stations_from_travelled(rails, track, forward, travelled, start_station_m, direction)


def stations_from_travelled(rails: RailPoints, track: np.ndarray, forward: np.ndarray, travelled: np.ndarray,
                            start_station_m: float, direction: float) -> RailStations:
    """:func:`stations_along_path` from :func:`track_and_forward`, the distance travelled and the
    direction in which the stations grow (+1 along the x axis): pointwise, for rails in parts."""
    centre_station = start_station_m + direction * travelled

    def shifted(points: np.ndarray) -> np.ndarray:
        along = np.einsum("ij,ij->i", points[:, :2] - track, forward)
        return centre_station + direction * along

    left, right = shifted(rails.left_rail_enh_m), shifted(rails.right_rail_enh_m)
    ref = left if rails.reference_rail == "left" else right
    centre_station = np.where(np.isnan(rails.centre_enh_m[:, 0]), np.nan, centre_station)
    return RailStations(centre_station, left, right, ref, np.full(len(rails), np.nan), from_design=False)


def epoch_station_track(time_s: np.ndarray, station_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(time, station) of the epochs with a finite station, the station made monotonic in the
    direction of travel (non-decreasing with the stationing, non-increasing against it).

    Sensor events (sleeper pulses, gauge readings) get their station by interpolating this in
    time; the running maximum (minimum) removes the sub-millimetre back-and-forth of a standing
    trolley so that time <-> station stays invertible.
    """
    finite = np.isfinite(station_m)
    if finite.sum() < 2:
        raise ValueError(NO_STATIONS)
    t, s = np.asarray(time_s)[finite], np.asarray(station_m)[finite]
    if s[-1] < s[0]:
        return t, np.minimum.accumulate(s)
    return t, np.maximum.accumulate(s)
