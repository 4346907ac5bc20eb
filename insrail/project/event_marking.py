"""Marking a track event in a project (the GUI's "Mark as track event…" on a measured span).

The event goes to the end of the project's event file (``[track] events``, chainage only: it applies
to every survey, docs/formats.md "Track events"), written atomically; a project without one gets
``events.txt`` in its folder, in the documented format, and ``project.toml`` names it. Events take
part only in the assessment, so a survey processed before its event file last changed describes
events that are no longer the file's: :func:`results_older_than_events` says so, and processing
again places the new event.
"""

from __future__ import annotations

from dataclasses import replace

from insrail.io.events import Event, EventList, append_event
from insrail.project.model import Project, load_project, save_project
from insrail.project.results import RESULTS_FOLDER, SUMMARY_FILE

#: The event file a project without one gets, in its folder.
DEFAULT_EVENTS_FILE = "events.txt"


def mark_event(project: Project, event: Event) -> tuple[Project, EventList]:
    """Append ``event`` (in chainage, ``station_m``) to the project's event file, creating the file
    and naming it in project.toml when the project has none. Returns the project naming its event
    file and the events as read back. ValueError for an event that would not read back
    (:func:`insrail.io.events.event_problems`), InputError for an event file that does not read as
    it is, OSError when a file cannot be written: nothing is changed then."""
    if event.unit != "station_m":
        raise ValueError(f"unit: a project's events are in chainage (station_m), not {event.unit}")
    if project.events is not None:
        return project, append_event(project.resolve(project.events), event)
    listed = append_event(project.resolve(DEFAULT_EVENTS_FILE), event)
    # Only [track] events changes on disk: settings edited in the window and not saved stay unsaved.
    on_disk = load_project(project.path) if project.path.is_file() else project
    save_project(replace(on_disk, events=DEFAULT_EVENTS_FILE))
    return replace(project, events=DEFAULT_EVENTS_FILE), listed


def results_older_than_events(project: Project, survey: str) -> bool:
    """True when ``survey`` has results written before the project's event file last changed."""
    summary = project.folder / RESULTS_FOLDER / survey / SUMMARY_FILE
    if project.events is None or not summary.is_file():
        return False
    events = project.resolve(project.events)
    return events.is_file() and events.stat().st_mtime_ns > summary.stat().st_mtime_ns
