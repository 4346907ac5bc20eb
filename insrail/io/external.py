"""Reference surveys an insrail result is checked against (thesis §5.4.3, the external check).

* levelling line: ``point, chainage, H`` — a levelled rail-top (or centreline) height [m, normal
  height] at a chainage [m, the continuous station of the design or the fitted line];
* another trolley's per-sleeper coordinates: ``point, chainage, E, N, H`` [m, the project's
  engineering frame, normal heights].

Comma- or whitespace-separated, an optional header row, ``#`` comments (the common text layout of
docs/formats.md). A point id is any text without whitespace or commas; the same id twice is an error.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from insrail.io.textparse import read_token_table

LEVELLING_COLUMNS = ("point", "chainage", "H")
TROLLEY_POINT_COLUMNS = ("point", "chainage", "E", "N", "H")


@dataclass(frozen=True)
class ReferencePoints:
    """Points of a reference survey: id, chainage [m] and, per point, E, N (NaN for a levelling
    line, which has heights only) and H [m]."""

    point_id: tuple[str, ...]
    chainage_m: np.ndarray
    enh_m: np.ndarray  # (n, 3)
    source: Path

    @property
    def has_plan(self) -> bool:
        return bool(np.all(np.isfinite(self.enh_m[:, :2])))

    def __len__(self) -> int:
        return len(self.point_id)


def read_levelling_line(path: str | Path) -> ReferencePoints:
    """``point, chainage, H`` -> ReferencePoints (E, N NaN)."""
    table = read_token_table(path, min_columns=3, max_columns=3, column_names=LEVELLING_COLUMNS)
    ids = table.unique_ids("point")
    height = table.numbers(2)
    enh = np.column_stack([np.full(len(ids), np.nan), np.full(len(ids), np.nan), height])
    return ReferencePoints(ids, table.numbers(1), enh, table.path)


def read_trolley_points(path: str | Path) -> ReferencePoints:
    """``point, chainage, E, N, H`` -> ReferencePoints."""
    table = read_token_table(path, min_columns=5, max_columns=5, column_names=TROLLEY_POINT_COLUMNS)
    ids = table.unique_ids("point")
    return ReferencePoints(ids, table.numbers(1), np.column_stack([table.numbers(c) for c in (2, 3, 4)]), table.path)
