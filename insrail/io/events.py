"""Track events: turnouts, level crossings, bridges, joints, stretches not to assess, notes.

A comma-separated text file (``docs/formats.md``, "Events"), one event per line::

    # kind, from, to, unit, profile, text
    kind, from, to, unit, profile, text                 optional header row
    turnout, 1450.0, 1520.0, station_m, , W12 No. 18 right-hand
    level_crossing, 1700.0, 1712.0, station_m, , LC 3
    no_assess, 231250.5, 231262.0, time_s, , trolley lifted over a tool
    joint, 1800.2, , station_m, , insulated joint

``from``/``to`` are a position in ``unit``: ``station_m`` (chainage, continuous measure; the only
unit a project's event file may use), ``time_s`` (GPS seconds of week, the survey's clock) or
``odometer_m`` (the survey's odometer distance); ``to`` empty for a point event (a joint, a note).
``profile``: a tolerance profile (shipped name or ``.toml`` path) a turnout is assessed with;
empty: the turnout is not assessed. ``text``: the rest of the line (may hold commas). Lines
starting with ``#`` are comments. Values are read exactly as written; nothing is guessed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from insrail.io.atomic import atomic_write
from insrail.io.errors import InputError
from insrail.io.textparse import quoted

#: Event kinds; the second element says whether the sleepers inside are left out of the assessment.
EVENT_KINDS = {
    "turnout": "not assessed unless the event names a tolerance profile for it",
    "level_crossing": "not assessed",
    "bridge": "marked",
    "joint": "marked",
    "no_assess": "not assessed",
    "note": "marked",
}
UNITS = ("station_m", "time_s", "odometer_m")
HEADER = ("kind", "from", "to", "unit", "profile", "text")


@dataclass(frozen=True)
class Event:
    """One event as written: ``start``/``end`` in ``unit`` (end = start for a point event)."""

    kind: str
    start: float
    end: float
    unit: str
    profile: str = ""
    text: str = ""
    line: int = 0  # where it was written, for messages


@dataclass(frozen=True)
class EventList:
    events: tuple[Event, ...]
    source: str = ""

    def __len__(self) -> int:
        return len(self.events)


def _number(path: Path, line: int, column: str, text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise InputError(path, line, "{column}: expected a number, found {quoted}", fields={"column": column, "quoted": quoted(text)}) from None
    if not math.isfinite(value):
        raise InputError(path, line, "{column}: expected a finite number, found {quoted}", fields={"column": column, "quoted": quoted(text)})
    return value


def read_events(path: str | Path) -> EventList:
    """The events of ``path`` (see the module docstring); InputError names the line and what was expected."""
    path = Path(path)
    if not path.is_file():
        raise InputError(path, None, "file not found" if not path.exists() else "is a folder, expected a file")
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except UnicodeDecodeError as error:
        raise InputError(path, None, "not UTF-8 text ({reason} at byte {start})", fields={"reason": error.reason, "start": error.start}) from None
    events = []
    for number, raw in enumerate(lines, start=1):
        if not raw.strip() or raw.lstrip().startswith("#"):
            continue
        fields = [f.strip() for f in raw.split(",", len(HEADER) - 1)]
        if tuple(f.lower() for f in fields) == HEADER:
            continue
        if len(fields) < 4:
            raise InputError(path, number, "expected at least 4 fields ({header}), found {count}", fields={"header": list(HEADER), "count": len(fields)})
        fields += [""] * (len(HEADER) - len(fields))
        kind, start_text, end_text, unit, profile, text = fields
        if kind not in EVENT_KINDS:
            raise InputError(path, number, "kind: expected one of {event_kinds}, found {quoted}", fields={"event_kinds": list(EVENT_KINDS), "quoted": quoted(kind)})
        if unit not in UNITS:
            raise InputError(path, number, "unit: expected one of {units}, found {quoted}", fields={"units": list(UNITS), "quoted": quoted(unit)})
        start = _number(path, number, "from", start_text)
        end = start if end_text == "" else _number(path, number, "to", end_text)
        if end < start:
            raise InputError(path, number, "to ({end:g}) is before from ({start:g}): give the smaller value first", fields={"end": end, "start": start})
        if profile and kind != "turnout":
            raise InputError(path, number, "profile: only a turnout is assessed with a profile of its own, not a {kind}", fields={"kind": kind})
        events.append(Event(kind, start, end, unit, profile, text, number))
    return EventList(tuple(events), str(path))


#: Kinds that cover a stretch of track (``to`` beyond ``from``); the others may be a point.
EXTENT_KINDS = ("turnout", "level_crossing", "bridge", "no_assess")


def _row(e: Event) -> str:
    end = "" if e.end == e.start and e.kind in ("joint", "note") else repr(e.end)
    return ", ".join([e.kind, repr(e.start), end, e.unit, e.profile, e.text])


def write_events(path: str | Path, events: EventList) -> None:
    """Write ``events`` in the format :func:`read_events` reads (atomically)."""
    rows = ["# insrail events", ", ".join(HEADER)] + [_row(e) for e in events.events]
    with atomic_write(Path(path)) as handle:
        handle.write("\n".join(rows) + "\n")


def event_problems(event: Event) -> dict[str, str]:
    """What is wrong with ``event`` before it is written, by field (``kind``, ``from``, ``to``, ``unit``,
    ``profile``, ``text``); {} when :func:`read_events` will read it back as it is."""
    problems: dict[str, str] = {}
    if event.kind not in EVENT_KINDS:
        problems["kind"] = f"expected one of {', '.join(EVENT_KINDS)}, found {event.kind!r}"
    if event.unit not in UNITS:
        problems["unit"] = f"expected one of {', '.join(UNITS)}, found {event.unit!r}"
    for name, value in (("from", event.start), ("to", event.end)):
        if not math.isfinite(value):
            problems[name] = f"expected a finite number, found {value!r}"
    if "from" not in problems and "to" not in problems:
        if event.end < event.start:
            problems["to"] = f"{event.end:g} is before from ({event.start:g}): give the smaller value first"
        elif event.end == event.start and event.kind in EXTENT_KINDS:
            problems["to"] = "a stretch of track: to must be beyond from"
    if event.profile and event.kind != "turnout":
        problems["profile"] = f"only a turnout is assessed with a profile of its own, not a {event.kind}"
    for name, value in (("profile", event.profile), ("text", event.text)):
        if "\n" in value or "\r" in value:
            problems[name] = "one line only: a line break would end the event"
    if "," in event.profile:
        problems["profile"] = "a profile name holds no comma"
    if event.text.lstrip().startswith("#"):
        problems["text"] = "may not start with # (it would make the line a comment)"
    return problems


def append_event(path: str | Path, event: Event) -> EventList:
    """Add ``event`` at the end of the event file ``path`` (created with a header when it does not
    exist), keeping every line already there (comments too); written atomically. The file must read
    as it is first; ValueError (naming the fields) for an event :func:`event_problems` refuses.
    Returns the events as read back."""
    path = Path(path)
    problems = event_problems(event)
    if problems:
        raise ValueError("; ".join(f"{name}: {message}" for name, message in problems.items()))
    if path.exists():
        read_events(path)  # a broken file is reported, never extended
        text = path.read_text(encoding="utf-8")
        text = text if not text or text.endswith("\n") else text + "\n"
    else:
        text = "# insrail events\n" + ", ".join(HEADER) + "\n"
    with atomic_write(path) as handle:
        handle.write(text + _row(event) + "\n")
    return read_events(path)
