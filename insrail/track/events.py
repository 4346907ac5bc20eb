"""Track events placed on the chainage, and the sleepers they take out of the assessment.

An event (:mod:`insrail.io.events`) is written in chainage, in the survey's time or in its
odometer distance; :func:`place_event` turns each one into a chainage range on the survey's
reconstructed track (time -> the reference rail's station at that time; odometer distance ->
the time the odometer read it -> station). :func:`not_assessed_reasons` gives each sleeper the
reasons it is not assessed: inside a level crossing, a "do not assess" stretch, or a turnout
that names no tolerance profile of its own (plain-track limits do not apply to a turnout's
geometry). A turnout with a profile is assessed with that profile instead
(:func:`turnouts_with_profiles`). Bridges, joints and notes only mark the track. The ranges are
closed: a sleeper exactly at an event's end is inside.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from insrail.io.events import Event
from insrail.io.types import OdometerData
from insrail.notices import Phrase
from insrail.track.sleeper_table import SleeperTable
from insrail.track.sleepers import StationTrack

#: Shown to the user (workbook, PDF, GUI) for each kind.
KIND_NAMES = {"turnout": "turnout", "level_crossing": "level crossing", "bridge": "bridge", "joint": "joint",
              "no_assess": "not assessed", "note": "note"}


@dataclass(frozen=True)
class TrackEvent:
    """An event on the chainage: ``station_from_m`` <= ``station_to_m`` (equal for a point event)."""

    kind: str
    station_from_m: float
    station_to_m: float
    text: str = ""
    profile: str = ""
    source: str = ""  # file and line it was written on

    @property
    def excluded(self) -> bool:
        """The sleepers inside are left out of the assessment with the track's profile."""
        return self.kind in ("level_crossing", "no_assess") or self.kind == "turnout"

    @property
    def description(self) -> str:
        """How a sleeper's "not assessed" column names it: "turnout W12", "level crossing LC 3"."""
        return str(self.described())

    def described(self) -> Phrase:
        """:meth:`description` as a phrase (the kind's name in the report's language, the event's own text verbatim)."""
        name = Phrase(KIND_NAMES[self.kind])
        if self.kind == "no_assess":
            text = Phrase("{text}", {"text": self.text}) if self.text else name
        else:
            text = Phrase("{kind} {text}", {"kind": name, "text": self.text.rstrip()}) if self.text.strip() else name
        return Phrase("{event} (assessed with {profile})", {"event": text, "profile": self.profile}) if self.profile \
            else text


def place_event(event: Event, epoch_time_s: np.ndarray, epoch_station_m: np.ndarray,
                odometer: OdometerData | None = None, source: str = "") -> TrackEvent:
    """The event as a chainage range on the survey's track (see the module docstring).

    ``epoch_time_s``/``epoch_station_m``: the reference rail's station over time. Raises
    ValueError for a time or odometer reading outside the survey, or an odometer event without
    odometer data.
    """
    finite = np.isfinite(epoch_station_m)
    return place_event_on(event, StationTrack.of(epoch_time_s[finite], epoch_station_m[finite]), odometer, source)


def place_event_on(event: Event, track: StationTrack, odometer: OdometerData | None = None,
                   source: str = "") -> TrackEvent:
    """:func:`place_event` on the reference rail's station over time as a
    :class:`~insrail.track.sleepers.StationTrack` (e.g. interpolated by parts)."""
    if event.unit == "station_m":
        start, end = event.start, event.end
    else:
        positions = np.array([event.start, event.end])
        times = positions
        if event.unit == "odometer_m":
            if odometer is None or len(odometer.time_s) < 2:
                raise ValueError(Phrase("an event in odometer distance needs the survey's odometer data"))
            distance = odometer.distance_m
            if np.any((positions < distance.min()) | (positions > distance.max())):
                raise ValueError(Phrase("odometer distance {start:g}..{end:g} m lies outside the odometer record "
                                        "({first:.3f}..{last:.3f} m)", {"start": event.start, "end": event.end,
                                                                        "first": distance.min(), "last": distance.max()}))
            order = np.argsort(distance, kind="stable")
            times = np.interp(positions, distance[order], odometer.time_s[order])
        first, last = track.first_time_s, track.last_time_s
        if np.any((times < first) | (times > last)):
            raise ValueError(Phrase("time {start:.3f}..{end:.3f} s lies outside the survey's time on the track "
                                    "({first:.3f}..{last:.3f} s)", {"start": times[0], "end": times[1], "first": first,
                                                                    "last": last}))
        start, end = np.sort(track.station_at(times))
    return TrackEvent(event.kind, float(start), float(end), event.text, event.profile, source)


def inside(event: TrackEvent, station_m: np.ndarray) -> np.ndarray:
    return (station_m >= event.station_from_m) & (station_m <= event.station_to_m)


def not_assessed_reasons(events: tuple[TrackEvent, ...], station_m: np.ndarray) -> tuple[str, ...]:
    """Per sleeper: the events that leave it out of the assessment, joined by "; " ("" for none)."""
    reasons: list[list[str]] = [[] for _ in range(len(station_m))]
    for event in events:
        if event.excluded:
            for row in np.flatnonzero(inside(event, station_m)):
                reasons[row].append(event.description)
    return tuple("; ".join(r) for r in reasons)


def mark_not_assessed(table: SleeperTable, events: tuple[TrackEvent, ...]) -> SleeperTable:
    """The table with the sleepers inside excluding events invalid for the assessment and their
    reasons in ``not_assessed`` (reasons already there, e.g. from integrity checks, are kept)."""
    reasons = not_assessed_reasons(events, table.station_m)
    before = table.not_assessed or ("",) * len(table)
    joined = tuple("; ".join(r for r in (old, new) if r) for old, new in zip(before, reasons))
    excluded = np.array([bool(r) for r in reasons], dtype=bool)
    return replace(table, valid=table.valid & ~excluded, not_assessed=joined)


def turnouts_with_profiles(events: tuple[TrackEvent, ...]) -> tuple[TrackEvent, ...]:
    return tuple(e for e in events if e.kind == "turnout" and e.profile)
