"""Sleepers the fusion cannot vouch for: flagged, not assessed, with the reason.

The fusion's integrity verdict (``insrail.nav.integrity``, kept in the fusion's cached info as
``integrity``) names the times where the solution was inconsistent with its 1-sigma (not-valid
sections), suspect (around a filter reset) or where the trajectory misses a position fix. A
sleeper the trolley passed inside one of them is
marked not valid, so no exceedance is assessed there and no adjustment amount computed from it,
and sleepers.csv says why in its ``not_assessed`` column (reasons joined by "; ", with those of
the track events).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from insrail.track.sleeper_table import SleeperTable


def flag_sleepers(table: SleeperTable, integrity: dict | None) -> SleeperTable:
    """The table with ``valid`` cleared where the fusion is not valid and the reason added to
    ``not_assessed`` (reasons already there are kept)."""
    if not integrity or not len(table):
        return table
    intervals = [(s["time_from_s"], s["time_to_s"], s["reason"]) for s in integrity.get("not_valid", [])]
    intervals += [(s["time_from_s"], s["time_to_s"], s["reason"]) for s in integrity.get("suspect", [])]
    intervals += [(s["time_from_s"], s["time_to_s"], s["reason"]) for s in integrity.get("missed_fixes", [])]
    reasons = list(table.not_assessed or ("",) * len(table))
    flagged = np.zeros(len(table), dtype=bool)
    for start, end, why in intervals:
        inside = (table.time_s >= start) & (table.time_s <= end)
        why = "fusion: " + why.replace(",", ";")
        for k in np.flatnonzero(inside):
            reasons[k] = f"{reasons[k]}; {why}" if reasons[k] else why
        flagged |= inside
    return replace(table, valid=np.asarray(table.valid, dtype=bool) & ~flagged, not_assessed=tuple(reasons))
