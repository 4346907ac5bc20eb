"""Sleepers the fusion cannot vouch for: flagged, not assessed, with the reason.

The fusion's integrity verdict (``insrail.nav.integrity``, kept in the fusion's cached info as
``integrity``) names the times where the solution was inconsistent with its 1-sigma (not-valid
sections), suspect (around a filter reset, and between two resets that undid each other) or where the
trajectory misses a position fix. A
sleeper the trolley passed inside one of them is
marked not valid, so no exceedance is assessed there and no adjustment amount computed from it,
and sleepers.csv says why in its ``not_assessed`` column (reasons joined by "; ", with those of
the track events).

Languages: sleepers.csv keeps the reasons in English, as it keeps its column names: it is the
results' store (insrail reads it back for a line section, a report written later in either
language, the GUI) and a machine's input, so its text does not change with a project's language.
Every reason is made as a :class:`~insrail.notices.Phrase`; :func:`reasons_section` lists the
survey's reasons beside their English in summary.toml (``[assessment] not_assessed_reasons``), and
:func:`said_reasons` gives a sleeper's column in the report's language (the workbook's "not
assessed because" column).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import replace

import numpy as np

from insrail.names import t
from insrail.notices import Phrase, phrase_of
from insrail.track.sleeper_table import SleeperTable

#: where the fusion's integrity verdict lists its intervals (``insrail.nav.integrity.FusionIntegrity.to_dict``)
INTEGRITY_INTERVALS = ("not_valid", "suspect", "detours", "missed_fixes")


def fusion_reasons(integrity: dict | None) -> list[tuple[float, float, Phrase]]:
    """(start, end [s of week], reason) of every interval the fusion's integrity verdict cannot vouch for."""
    return [(s["time_from_s"], s["time_to_s"],
             Phrase("fusion: {reason}", {"reason": phrase_of(s["why"]) if "why" in s else Phrase(s["reason"])}))
            for key in INTEGRITY_INTERVALS for s in (integrity or {}).get(key, [])]


def written(reason: Phrase) -> str:
    """A reason as sleepers.csv's column holds it: its English, with no comma of its own (the column joins a
    sleeper's reasons by "; ")."""
    return str(reason).replace(",", ";")


def flag_sleepers(table: SleeperTable, integrity: dict | None) -> SleeperTable:
    """The table with ``valid`` cleared where the fusion is not valid and the reason added to
    ``not_assessed`` (reasons already there are kept)."""
    if not integrity or not len(table):
        return table
    reasons = list(table.not_assessed or ("",) * len(table))
    flagged = np.zeros(len(table), dtype=bool)
    for start, end, reason in fusion_reasons(integrity):
        inside = (table.time_s >= start) & (table.time_s <= end)
        why = written(reason)
        for k in np.flatnonzero(inside):
            reasons[k] = f"{reasons[k]}; {why}" if reasons[k] else why
        flagged |= inside
    return replace(table, valid=np.asarray(table.valid, dtype=bool) & ~flagged, not_assessed=tuple(reasons))


def reasons_section(reasons: Iterable[Phrase]) -> list[dict]:
    """summary.toml's ``[assessment] not_assessed_reasons``: each reason's English as sleepers.csv writes it
    (``text``) and its template and fields, once each."""
    section = {}
    for reason in reasons:
        section.setdefault(written(reason), {"text": written(reason), **reason.to_dict()})
    return list(section.values())


def reasons_of(summary: Mapping) -> dict[str, Phrase]:
    """The reasons a survey's (or a section's) summary lists: sleepers.csv's English -> its phrase."""
    return {entry["text"]: Phrase.from_dict(entry)
            for entry in summary.get("assessment", {}).get("not_assessed_reasons", [])}


def said_reasons(column: str, reasons: Mapping[str, Phrase]) -> str:
    """A sleeper's ``not_assessed`` column (English reasons joined by "; ") in the language in use: each reason
    :func:`reasons_of` knows said, any other (results of an older insrail) as written."""
    said, rest = [], column
    known = sorted(reasons, key=len, reverse=True)  # a reason that begins another one is tried after it
    while rest:
        match = next((text for text in known if rest == text or rest.startswith(text + "; ")), None)
        if match is None:
            said.append(rest)
            break
        said.append(reasons[match].said())
        rest = rest[len(match) + 2:]
    return t("; ").join(said)


def said_per_sleeper(not_assessed: tuple[str, ...], summary: Mapping) -> tuple[str, ...]:
    """Each sleeper's ``not_assessed`` column (sleepers.csv's English) in the language in use (the workbook's "not
    assessed because" column, the GUI's read-out)."""
    reasons = reasons_of(summary)
    said = {column: said_reasons(column, reasons) for column in set(not_assessed)}  # a few texts, many sleepers
    return tuple(said[column] for column in not_assessed)
