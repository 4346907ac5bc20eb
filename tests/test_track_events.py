"""Track events: the event file reader, placing events on the chainage, the sleepers they take
out of the assessment."""

import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from insrail.io.errors import InputError
from insrail.io.events import EVENT_KINDS, Event, EventList, read_events, write_events
from insrail.io.types import OdometerData
from insrail.track.events import TrackEvent, not_assessed_reasons, place_event

GOOD = """# events
kind, from, to, unit, profile, text
turnout, 1480.0, 1550.0, station_m, cn_conventional_160, W12 No. 18, right-hand
level_crossing, 1700, 1712, station_m, , LC 3
joint, 1800.2, , station_m, , insulated joint
no_assess, 230900.5, 230950.0, time_s
bridge, 600, 640, odometer_m, , Xiaohe bridge
"""


def test_reader_reads_every_kind_and_unit(tmp_path):
    path = tmp_path / "events.txt"
    path.write_text(GOOD)
    events = read_events(path).events
    assert [e.kind for e in events] == ["turnout", "level_crossing", "joint", "no_assess", "bridge"]
    assert events[0].text == "W12 No. 18, right-hand" and events[0].profile == "cn_conventional_160"
    assert events[0].line == 3
    assert events[2].start == events[2].end == 1800.2  # a point event
    assert events[3].unit == "time_s" and events[3].text == ""
    assert events[4].unit == "odometer_m"


@pytest.mark.parametrize("line, message", [
    ("crossing, 1, 2, station_m, , x", "kind: expected one of turnout"),
    ("turnout, 1, 2, km, , x", "unit: expected one of station_m"),
    ("turnout, one, 2, station_m, , x", "from: expected a number, found 'one'"),
    ("turnout, 1, nan, station_m, , x", "to: expected a finite number"),
    ("turnout, 5, 2, station_m, , x", "to (2) is before from (5)"),
    ("bridge, 1, 2, station_m, fra_class_1, x", "profile: only a turnout"),
    ("turnout, 1", "expected at least 4 fields"),
])
def test_reader_names_the_line_and_what_was_expected(tmp_path, line, message):
    path = tmp_path / "events.txt"
    path.write_text("# events\njoint, 10, , station_m, , ok\n" + line + "\n")
    with pytest.raises(InputError, match=re.escape(message)) as error:
        read_events(path)
    assert error.value.line == 3 and error.value.path == path
    with pytest.raises(InputError, match="file not found"):
        read_events(tmp_path / "none.txt")


texts = st.text(st.characters(blacklist_categories=("Cc", "Cs"), blacklist_characters="\r\n\x85\u2028\u2029"),
                max_size=30).map(str.strip).filter(lambda t: not t.startswith("#"))


@settings(max_examples=40, deadline=None)
@given(rows=st.lists(st.tuples(st.sampled_from(sorted(EVENT_KINDS)), st.floats(-1e6, 1e6), st.floats(0, 1e3),
                               st.sampled_from(["station_m", "time_s", "odometer_m"]), texts), max_size=8))
def test_written_events_read_back(tmp_path_factory, rows):
    events = EventList(tuple(Event(kind, start, start + length, unit, "p.toml" if kind == "turnout" else "", text)
                             for kind, start, length, unit, text in rows))
    path = tmp_path_factory.mktemp("events") / "events.txt"
    write_events(path, events)
    back = read_events(path).events
    assert [(e.kind, e.start, e.end, e.unit, e.profile, e.text) for e in back] == \
           [(e.kind, e.start, e.end, e.unit, e.profile, e.text) for e in events.events]


def test_events_in_time_and_odometer_distance_are_placed_on_the_chainage():
    time_s = np.linspace(100.0, 200.0, 101)
    station = 2000.0 - 5.0 * (time_s - 100.0)  # a run against the stationing
    odometer = OdometerData(time_s=time_s, distance_m=5.0 * (time_s - 100.0))
    by_time = place_event(Event("no_assess", 120.0, 130.0, "time_s"), time_s, station)
    assert (by_time.station_from_m, by_time.station_to_m) == pytest.approx((1850.0, 1900.0))
    by_distance = place_event(Event("bridge", 50.0, 60.0, "odometer_m"), time_s, station, odometer)
    assert (by_distance.station_from_m, by_distance.station_to_m) == pytest.approx((1940.0, 1950.0))
    with pytest.raises(ValueError, match="outside the survey's time"):
        place_event(Event("no_assess", 90.0, 130.0, "time_s"), time_s, station)
    with pytest.raises(ValueError, match="outside the odometer record"):
        place_event(Event("bridge", 50.0, 600.0, "odometer_m"), time_s, station, odometer)
    with pytest.raises(ValueError, match="needs the survey's odometer"):
        place_event(Event("bridge", 50.0, 60.0, "odometer_m"), time_s, station)


def test_reasons_per_sleeper():
    station = np.arange(0.0, 20.0, 0.625)
    events = (TrackEvent("turnout", 2.0, 8.0, "W1"), TrackEvent("level_crossing", 7.0, 9.0, "LC 3"),
              TrackEvent("bridge", 0.0, 20.0, "B"), TrackEvent("no_assess", 15.0, 15.0),
              TrackEvent("turnout", 12.0, 13.0, "W2", profile="fra_class_1"))
    reasons = not_assessed_reasons(events, station)
    assert reasons[0] == "" and reasons[4] == "turnout W1"  # 2.5 m
    assert reasons[12] == "turnout W1; level crossing LC 3"  # 7.5 m
    assert reasons[24] == "not assessed"  # 15.0 m: a point event covers its sleeper
    assert reasons[20] == "turnout W2 (assessed with fra_class_1)"
    assert sum(bool(r) for r in reasons) == 9 + 2 + 1 + 1  # W1, LC 3 beyond W1, the point, W2
