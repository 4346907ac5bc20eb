"""Sleepers around a bridged IMU gap: flagged, not assessed, with the reason.

Across a bridged IMU dropout the trajectory rests on interpolated increments and the aiding; the
fusion widens its 1-sigma there (``insrail.nav.imu_gaps.bridged_process_noise``), but the
short-wave geometry around the gap is not what the survey's accuracy says elsewhere
(benchmarks/imu_integrity.py, simulator `short`, nav grade: the 1-sigma of the 5 m lag
difference touching a 0.5 s gap while moving 0.31 / 0.39 mm lateral / vertical, a 2 s gap
2.0 / 4.9 mm, against 0.25 / 0.23 mm elsewhere). The sleepers within ``MARGIN_M`` of a gap
longer than ``FLAG_GAP_S`` are therefore left out of the assessment (``valid``) with the reason
in ``not_assessed``; shorter gaps (a few lost records) leave the geometry as it is.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from insrail.notices import Phrase
from insrail.track.sleeper_table import SleeperTable

#: gaps at least this long [s] flag their sleepers
FLAG_GAP_S = 0.25
#: the stretch [m] either side of a gap whose 5 m chords reach into it
MARGIN_M = 5.0


def long_gaps_of(gaps_s) -> list[tuple[float, float]]:
    """The gaps ``[start, end]`` [s of week] long enough to flag their sleepers."""
    return [(float(a), float(b)) for a, b in gaps_s if b - a >= FLAG_GAP_S]


def gap_reason(start: float, end: float) -> Phrase:
    """Why the sleepers around a bridged gap are not assessed (sleepers.csv's ``not_assessed``)."""
    return Phrase("IMU gap of {gap_s:.2f} s bridged", {"gap_s": end - start})


def flag_gap_sleepers(table: SleeperTable, gaps_s) -> SleeperTable:
    """``table`` with the sleepers within :data:`MARGIN_M` of each bridged gap ``[start, end]``
    [s of week] of at least :data:`FLAG_GAP_S` not valid, reason "IMU gap of ... s bridged"."""
    long_gaps = long_gaps_of(gaps_s)
    if not long_gaps or len(table) < 2:
        return table
    order = np.argsort(table.time_s)
    reasons = list(table.not_assessed or ("",) * len(table))
    flagged = np.zeros(len(table), dtype=bool)
    for start, end in long_gaps:
        s0, s1 = np.interp([start, end], table.time_s[order], table.station_m[order])
        near = (table.station_m >= min(s0, s1) - MARGIN_M) & (table.station_m <= max(s0, s1) + MARGIN_M)
        why = str(gap_reason(start, end))
        for k in np.flatnonzero(near):
            reasons[k] = why if not reasons[k] else f"{reasons[k]}; {why}"
        flagged |= near
    return replace(table, valid=np.asarray(table.valid, dtype=bool) & ~flagged, not_assessed=tuple(reasons))
