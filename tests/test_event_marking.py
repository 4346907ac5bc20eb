"""Marking a track event: appended to the project's event file (created and named when missing),
read back by the event reader, a bad value refused with nothing written."""

from __future__ import annotations

import os

import pytest

from insrail.io.errors import InputError
from insrail.io.events import Event, append_event, event_problems, read_events
from insrail.project import load_project, save_project
from insrail.project.event_marking import (
    DEFAULT_EVENTS_FILE,
    mark_event,
    results_older_than_events,
)
from insrail.project.results import RESULTS_FOLDER, SUMMARY_FILE
from tests.test_project_model import make_folder, sample_project


def test_append_keeps_the_lines_there_and_reads_back(tmp_path):
    path = tmp_path / "events.txt"
    path.write_text("# crew notes, 14 March\njoint, 1800.2, , station_m, , insulated joint")  # no final newline
    listed = append_event(path, Event("turnout", 1450.0, 1520.25, "station_m", text="W12 No. 18, right-hand"))
    assert path.read_text().startswith("# crew notes, 14 March\n")
    assert [(e.kind, e.start, e.end, e.text) for e in listed.events] == [
        ("joint", 1800.2, 1800.2, "insulated joint"), ("turnout", 1450.0, 1520.25, "W12 No. 18, right-hand")]
    assert read_events(path) == listed


@pytest.mark.parametrize("event, field", [
    (Event("turnout", 1520.0, 1450.0, "station_m"), "to"),
    (Event("level_crossing", 1700.0, 1700.0, "station_m"), "to"),
    (Event("bridge", float("nan"), 640.0, "station_m"), "from"),
    (Event("culvert", 1.0, 2.0, "station_m"), "kind"),
    (Event("note", 1.0, 1.0, "station_m", text="two\nlines"), "text"),
    (Event("note", 1.0, 1.0, "station_m", text="# not a comment"), "text"),
    (Event("joint", 1.0, 1.0, "station_m", profile="cn_hsr_ballastless"), "profile"),
])
def test_a_bad_value_is_refused_and_nothing_is_written(tmp_path, event, field):
    assert field in event_problems(event)
    path = tmp_path / "events.txt"
    with pytest.raises(ValueError, match=f"{field}:"):
        append_event(path, event)
    assert not path.exists()


def test_a_broken_event_file_is_reported_never_extended(tmp_path):
    path = tmp_path / "events.txt"
    path.write_text("turnout, 10, 5, station_m, , reversed\n")
    with pytest.raises(InputError, match="line 1"):
        append_event(path, Event("note", 1.0, 1.0, "station_m"))
    assert path.read_text() == "turnout, 10, 5, station_m, , reversed\n"


def test_a_project_without_an_event_file_gets_one_and_names_it(tmp_path):
    project = sample_project(make_folder(tmp_path))
    save_project(project)
    summary = tmp_path / RESULTS_FOLDER / "a" / SUMMARY_FILE
    summary.parent.mkdir(parents=True)
    summary.write_text("")
    os.utime(summary, ns=(1, 1))  # processed long ago
    assert not results_older_than_events(project, "a")
    marked, listed = mark_event(project, Event("level_crossing", 1700.0, 1712.0, "station_m", text="LC 3"))
    assert marked.events == DEFAULT_EVENTS_FILE
    assert load_project(tmp_path).events == DEFAULT_EVENTS_FILE  # project.toml names it, and it loads
    assert [(e.kind, e.start, e.end) for e in read_events(tmp_path / DEFAULT_EVENTS_FILE).events] == [
        ("level_crossing", 1700.0, 1712.0)] == [(e.kind, e.start, e.end) for e in listed.events]
    assert results_older_than_events(marked, "a") and not results_older_than_events(marked, "b")
    marked, listed = mark_event(marked, Event("turnout", 1450.0, 1520.0, "station_m"))
    assert [e.kind for e in listed.events] == ["level_crossing", "turnout"]
    with pytest.raises(ValueError, match="chainage"):
        mark_event(marked, Event("note", 231250.5, 231250.5, "time_s"))
