"""Sleeper numbering from the sleeper-detector pulses (thesis 5.2.2.5).

Each pulse gets the station of the detector at its time: the trolley's reference-point
station interpolated in time, plus the detector's along-track distance ahead of that point
(negative station-wise when the trolley faces against the stationing). Working in station
rather than time makes the numbering indifferent to speed changes, stops and the direction
of travel: numbers grow with the station, whichever way the trolley ran. Pulses are then
walked in order of station from an anchor (the first pulse followed by
two regular gaps) in both directions; each next pulse is compared with the last accepted
one:

* gap ~ k * spacing (k >= 1, within ``tolerance_m``): a sleeper k numbers on; the k - 1
  sleepers in between were missed and are inserted at equal steps;
* otherwise (too short, or half-way between whole spacings): a false pulse, rejected.

For a gap of k > 2 sleepers the tolerance is scaled by k / 2: the local spacing error
accumulates over a run of missed sleepers.

The spacing is the nominal one, replaced by the median of the recent regular gaps once there
are enough of them, so that a track laid at 0.6 m, or a station scale off by a few per mille,
still numbers correctly. The tolerance must stay below half the smallest offset of a false
pulse from a true sleeper; the default (12 % of the spacing, 75 mm at 0.625 m) is far above
the station noise of a fused trajectory over a few sleepers (millimetres).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from insrail.io.survey import TrolleyGeometry
from insrail.nav.rotation import euler_to_dcm

#: Number of recent regular gaps whose median replaces the nominal spacing.
SPACING_MEMORY = 15


@dataclass(frozen=True)
class SleeperNumbering:
    """Numbered sleepers and what the repair did.

    Per sleeper (length m, ordered by station, numbers growing with it): ``number``,
    ``station_m`` (of the detector's sensing point over it), ``time_s`` (when the detector
    passed it: decreasing for a run against the stationing), ``detected`` (False: missed by the
    detector, inserted). Per pulse within the trajectory's time span (length p, sorted by
    time): ``pulse_time_s``, ``pulse_station_m``, ``pulse_accepted`` (False: rejected as false).
    """

    number: np.ndarray
    station_m: np.ndarray
    time_s: np.ndarray
    detected: np.ndarray
    pulse_time_s: np.ndarray
    pulse_station_m: np.ndarray
    pulse_accepted: np.ndarray

    @property
    def missed_numbers(self) -> np.ndarray:
        return self.number[~self.detected]

    @property
    def false_pulse_times_s(self) -> np.ndarray:
        return self.pulse_time_s[~self.pulse_accepted]

    def repair_counts(self) -> dict[str, int]:
        """What the repair did, for the summary: pulses used, missed sleepers inserted, false pulses
        rejected (a regular grid without pulses: pulses 0 and nothing repaired)."""
        if not len(self.pulse_time_s):
            return {"pulses": 0, "missed_inserted": 0, "false_rejected": 0}
        return {"pulses": len(self.pulse_time_s), "missed_inserted": len(self.missed_numbers),
                "false_rejected": int((~self.pulse_accepted).sum())}

    def summary(self) -> str:
        return (f"{len(self.number)} sleepers numbered {self.number[0]}..{self.number[-1]} "
                f"from {len(self.pulse_time_s)} pulses: {len(self.missed_numbers)} missed sleepers inserted, "
                f"{int((~self.pulse_accepted).sum())} false pulses rejected")


def sleeper_detector_ahead_m(trolley: TrolleyGeometry) -> float:
    """Along-track distance [m] of the sleeper detector ahead of the reference-rail point
    (x component in the trolley frame v of the lever-arm difference)."""
    c_vb = euler_to_dcm(*np.asarray(trolley.mounting_rpy_rad, dtype=float))
    lever = trolley.lever_arm_m("imu_to_sleeper_detector_m") - trolley.lever_arm_m("imu_to_reference_rail_m")
    return float((c_vb @ lever)[0])


def _walk(stations: np.ndarray, anchor: int, spacing_m: float, tolerance_m: float):
    """Accept/reject pulses after ``anchor`` (stations increasing); returns (accepted mask, step counts).

    steps[i] is how many sleepers accepted pulse i lies beyond the previously accepted one.
    """
    accepted = np.zeros(len(stations), dtype=bool)
    steps = np.zeros(len(stations), dtype=int)
    # Python floats (the same doubles): a pulse at a time, numpy's scalars would cost most of the walk
    at = stations.tolist()
    accepted[anchor] = True
    last = at[anchor]
    regular_gaps: list[float] = []
    spacing = spacing_m
    i = anchor + 1
    while i < len(at):
        gap = at[i] - last
        k = int(round(gap / spacing))  # half to even, as np.rint
        window = tolerance_m * max(1.0, 0.5 * k)
        if k < 1 or abs(gap - k * spacing) > window:
            i += 1
            continue
        # Several pulses can fit the same sleeper (a false pulse beside it, e.g. while the trolley
        # stands): the one closest to where the sleeper is expected is the sleeper's.
        expected = last + k * spacing
        best = i
        for j in range(i + 1, len(at)):
            if at[j] - expected > window:
                break
            if abs(at[j] - expected) < abs(at[best] - expected):
                best = j
        gap = at[best] - last
        accepted[best], steps[best], last = True, k, at[best]
        if k == 1:
            regular_gaps.append(gap)
            if len(regular_gaps) >= SPACING_MEMORY:
                spacing = _median(regular_gaps[-SPACING_MEMORY:])
        i = best + 1
    return accepted, steps


def _median(values: list[float]) -> float:
    """``float(np.median(values))`` of a short list, to the bit (the middle value, or the mean of the
    two middle ones as numpy's: their sum halved), without numpy's per-call cost."""
    ordered = sorted(values)
    middle = len(ordered) // 2
    return ordered[middle] if len(ordered) % 2 else (ordered[middle - 1] + ordered[middle]) / 2.0


def _anchor(stations: np.ndarray, spacing_m: float, tolerance_m: float) -> int:
    gaps = np.diff(stations)
    regular = np.abs(gaps - spacing_m) <= tolerance_m
    both = np.flatnonzero(regular[:-1] & regular[1:])
    if both.size == 0:
        raise ValueError(
            f"no two consecutive regular gaps of {spacing_m:.3f} m +/- {tolerance_m:.3f} m between sleeper pulses: "
            "check the sleeper spacing and the detector lever arm")
    return int(both[0])


@dataclass(frozen=True)
class StationTrack:
    """The trolley reference point's station over time, monotonic in the direction of travel
    (:func:`insrail.track.chainage.epoch_station_track`), as the numbering uses it: its first and
    last time, its lowest and highest station, whether it runs against the stationing, and the
    interpolations both ways (``np.interp``: in time; in station, the epochs in order of station).
    The whole-run arrays give them in :meth:`of`; a streamed track computes the same values by parts."""

    first_time_s: float
    last_time_s: float
    low_station_m: float
    high_station_m: float
    against: bool
    station_at: Callable[[np.ndarray], np.ndarray]
    time_at: Callable[[np.ndarray], np.ndarray]

    @classmethod
    def of(cls, epoch_time_s: np.ndarray, epoch_station_m: np.ndarray) -> StationTrack:
        against = bool(epoch_station_m[-1] < epoch_station_m[0])
        by_station = slice(None, None, -1) if against else slice(None)
        epoch_t, epoch_s = epoch_time_s[by_station], epoch_station_m[by_station]
        return cls(float(epoch_time_s[0]), float(epoch_time_s[-1]), float(epoch_s[0]), float(epoch_s[-1]), against,
                   lambda t: np.interp(t, epoch_time_s, epoch_station_m), lambda s: np.interp(s, epoch_s, epoch_t))


def number_sleepers(
    pulse_time_s,
    epoch_time_s: np.ndarray,
    epoch_station_m: np.ndarray,
    detector_ahead_m: float,
    spacing_m: float = 0.625,
    tolerance_m: float | None = None,
    first_number: int = 1,
) -> SleeperNumbering:
    """Number the sleepers from detector pulse times (see the module docstring).

    ``epoch_time_s``/``epoch_station_m``: the trolley reference point's station over time
    (monotonic in the direction of travel, e.g. from
    :func:`insrail.track.chainage.epoch_station_track`); ``detector_ahead_m``: station offset
    of the detector from the reference point (its along-track distance ahead of it, negated
    when the trolley faces against the stationing); ``first_number``: the number given to the
    sleeper of lowest station.
    """
    return number_on_track(pulse_time_s, StationTrack.of(epoch_time_s, epoch_station_m), detector_ahead_m,
                           spacing_m, tolerance_m, first_number)


def number_on_track(
    pulse_time_s,
    track: StationTrack,
    detector_ahead_m: float,
    spacing_m: float = 0.625,
    tolerance_m: float | None = None,
    first_number: int = 1,
) -> SleeperNumbering:
    """:func:`number_sleepers` on a :class:`StationTrack`."""
    if not spacing_m > 0.0:
        raise ValueError(f"sleeper spacing must be positive, not {spacing_m!r}")
    tolerance = 0.12 * spacing_m if tolerance_m is None else float(tolerance_m)
    times = np.sort(np.asarray(pulse_time_s, dtype=float))
    inside = (times >= track.first_time_s) & (times <= track.last_time_s)
    times = times[inside]
    if len(times) < 3:
        raise ValueError(f"{len(times)} sleeper pulses fall within the trajectory; at least 3 are needed")
    pulse_stations = track.station_at(times) + detector_ahead_m
    # The walk runs in order of station: reversed time order for a run against the stationing.
    by_station = slice(None, None, -1) if track.against else slice(None)
    stations = pulse_stations[by_station]

    anchor = _anchor(stations, spacing_m, tolerance)
    fwd_accepted, fwd_steps = _walk(stations, anchor, spacing_m, tolerance)
    # Backwards: the same walk on the mirrored stations before the anchor.
    back_accepted, back_steps = _walk(-stations[anchor::-1], 0, spacing_m, tolerance)
    accepted = fwd_accepted.copy()
    accepted[:anchor + 1] |= back_accepted[::-1]
    steps = fwd_steps.copy()
    steps[:anchor] = 0
    # Mirrored walk: its cumulative steps count the sleepers from the anchor down to each pulse.
    back_offsets = np.cumsum(back_steps)[::-1]
    numbers = np.zeros(len(stations), dtype=int)
    numbers[anchor:] = np.cumsum(steps[anchor:])
    numbers[:anchor + 1] = -back_offsets
    good = np.flatnonzero(accepted)
    numbers_good, stations_good = numbers[good] - numbers[good[0]] + first_number, stations[good]
    times_good = times[by_station][good]

    # Insert the missed sleepers between consecutive accepted pulses, at equal station steps.
    all_numbers = np.arange(numbers_good[0], numbers_good[-1] + 1)
    detected = np.isin(all_numbers, numbers_good)
    all_stations = np.interp(all_numbers, numbers_good, stations_good)
    all_times = track.time_at(all_stations - detector_ahead_m)
    all_times[detected] = times_good
    return SleeperNumbering(
        number=all_numbers,
        station_m=all_stations,
        time_s=all_times,
        detected=detected,
        pulse_time_s=times,
        pulse_station_m=pulse_stations,
        pulse_accepted=accepted[by_station],
    )


class AnchorError(ValueError):
    """The sleeper anchor lies at no sleeper of the survey."""


@dataclass(frozen=True)
class SleeperAnchor:
    """A field sleeper number at a known place: the sleeper at ``station_m`` (its detector station),
    or the one the detector passed at ``time_s`` (GPS seconds of week), is number ``number``."""

    number: int
    station_m: float | None = None
    time_s: float | None = None

    def __post_init__(self):
        if (self.station_m is None) == (self.time_s is None):
            raise ValueError("a sleeper anchor gives exactly one of station_m or time_s")


def anchor_numbering(numbering: SleeperNumbering, anchor: SleeperAnchor, spacing_m: float = 0.625) -> SleeperNumbering:
    """The numbering shifted so that the anchor's sleeper carries the anchor's number (numbers still
    grow with the station). Raises ValueError when no sleeper of the survey lies within half a
    spacing of the anchor's station (or of the detector's station at its time): AnchorError."""
    if anchor.station_m is not None:
        distance = np.abs(numbering.station_m - anchor.station_m)
        where = f"station {anchor.station_m:.3f} m"
    else:  # the detector's station at that time, between the sleepers it passed
        order = np.argsort(numbering.time_s)
        at = np.interp(anchor.time_s, numbering.time_s[order], numbering.station_m[order])
        distance = np.abs(numbering.station_m - at)
        where = f"time {anchor.time_s:.3f} s"
    row = int(np.argmin(distance))
    inside = numbering.time_s.min() <= anchor.time_s <= numbering.time_s.max() if anchor.time_s is not None else True
    if not inside or distance[row] > 0.5 * spacing_m:
        raise AnchorError(f"no sleeper of this survey at {where} (sleepers "
                         f"{numbering.station_m[0]:.3f} .. {numbering.station_m[-1]:.3f} m, "
                         f"times {numbering.time_s.min():.3f} .. {numbering.time_s.max():.3f} s)")
    return replace(numbering, number=numbering.number + (anchor.number - int(numbering.number[row])))
