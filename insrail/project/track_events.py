"""A survey's track events: its own event file (``[files.events]`` in survey.toml: time, odometer
distance or chainage) and the project's (``[track] events``: chainage only), placed on the
survey's reconstructed chainage, applied to its sleeper table, and the turnouts that name a
tolerance profile assessed with it (their exceedances in ``turnout_exceedances.csv``).

Events take no part in the fusion or the track reconstruction (their caches stay valid when the
events are edited); only the assessment, the adjustment and the result files are redone.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from insrail.io.errors import InputError, reason_of
from insrail.io.events import Event, EventList, read_events
from insrail.io.survey import SurveyManifest
from insrail.project.model import Project
from insrail.track.events import (
    TrackEvent,
    inside,
    mark_not_assessed,
    place_event_on,
    turnouts_with_profiles,
)
from insrail.track.exceedance import Exceedance, SleeperGeometry, assess
from insrail.track.sleeper_table import TrackReconstruction
from insrail.track.tolerance import load_tolerance_profile

EVENTS_ROLE = "events"
TURNOUT_EXCEEDANCES_FILE = "turnout_exceedances.csv"


def survey_events(project: Project, manifest: SurveyManifest, folder: Path,
                  recon: TrackReconstruction) -> tuple[TrackEvent, ...]:
    """The survey's and the project's events on the survey's chainage, in order of chainage.
    A bad file or an event outside the survey raises InputError naming the file and line."""
    lists: list[EventList] = []
    if EVENTS_ROLE in manifest.files:
        entry = manifest.files[EVENTS_ROLE]
        lists.append(entry.read(folder))
    if project.events is not None:
        lists.append(read_events(project.resolve(project.events)))
    if not any(len(events) for events in lists):
        return ()
    track = recon.epochs.station_track()
    odometer = None
    if any(e.unit == "odometer_m" for events in lists for e in events.events) and "odometer" in manifest.files:
        entry = manifest.files["odometer"]
        odometer = entry.read(folder)
    placed = []
    for events in lists:
        for event in events.events:
            source = f"{Path(events.source).name}, line {event.line}"
            try:
                placed.append(place_event_on(event, track, odometer, source))
            except ValueError as error:
                raise InputError(events.source, event.line, reason_of(error)) from None
            if event.profile:
                try:
                    load_tolerance_profile(project.resource(event.profile))
                except (ValueError, OSError) as error:
                    raise InputError(events.source, event.line, "profile: {error}", fields={"error": error}) from None
    return tuple(sorted(placed, key=lambda e: (e.station_from_m, e.station_to_m)))


#: Where a detected joint's event says it came from (summary.toml ``[[events]] source``).
DETECTED_JOINT_SOURCE = "IMU shock"


def detected_joints(shocks: dict, recon: TrackReconstruction) -> tuple[TrackEvent, ...]:
    """The rail joints the fusion stage found as IMU shocks (``shocks``: its ``time_s`` and
    ``peak_mps2``, :mod:`insrail.nav.shocks`) as ``joint`` events on the survey's chainage; a shock
    outside the time on the track (during the static start) is none."""
    track = recon.epochs.station_track()
    events = []
    for time_s, peak in zip(shocks.get("time_s", []), shocks.get("peak_mps2", [])):
        if track.first_time_s <= time_s <= track.last_time_s:
            event = Event("joint", time_s, time_s, "time_s", text=f"detected: vertical shock {peak:+.1f} m/s^2")
            events.append(place_event_on(event, track, None, DETECTED_JOINT_SOURCE))
    return tuple(events)


def apply_events(recon: TrackReconstruction, events: tuple[TrackEvent, ...]) -> TrackReconstruction:
    """The reconstruction with the sleepers inside a turnout, level crossing or "do not assess"
    stretch left out of the assessment (``valid``) and their reasons in ``not_assessed``."""
    if not events:
        return recon
    return replace(recon, table=mark_not_assessed(recon.table, events))


def assess_turnouts(project: Project, geometry: SleeperGeometry, measured: np.ndarray,
                    events: tuple[TrackEvent, ...]) -> tuple[tuple[Exceedance, ...], dict[str, int]]:
    """Each turnout that names a tolerance profile assessed with it on its own measured sleepers
    (``measured``: before the events took any out): the exceedances of all of them in chainage
    order (``turnout_exceedances.csv``, apart from the plain track's), and the count per turnout
    (by its source) for the summary."""
    counts: dict[str, int] = {}
    found: list[Exceedance] = []
    for turnout in turnouts_with_profiles(events):
        rows = measured & inside(turnout, geometry.station_m)
        own = SleeperGeometry.from_arrays(geometry.station_m, geometry.lateral_deviation_m, geometry.vertical_deviation_m,
                                          geometry.gauge_m, geometry.cant_m, geometry.design_cant_m, valid=rows,
                                          sleeper_number=geometry.sleeper_number)
        exceedances = assess(own, load_tolerance_profile(project.resource(turnout.profile))).exceedances
        counts[turnout.source] = len(exceedances)
        found += exceedances
    return tuple(sorted(found, key=lambda e: (e.station_from_m, e.check))), counts


def events_section(events: tuple[TrackEvent, ...], station_m: np.ndarray, turnout_exceedances: dict[str, int]) -> list[dict]:
    """summary.toml's ``[[events]]``: each event's kind, chainage range, text, profile, whether its
    sleepers are assessed, how many sleepers it covers and where it was written."""
    rows = []
    for e in events:
        row = {"kind": e.kind, "station_from_m": round(e.station_from_m, 4), "station_to_m": round(e.station_to_m, 4),
               "text": e.text, "profile": e.profile, "not_assessed": e.excluded and not e.profile,
               "sleepers": int(inside(e, station_m).sum()), "source": e.source}
        if e.source in turnout_exceedances:
            row["exceedances"] = turnout_exceedances[e.source]
        rows.append(row)
    return rows
