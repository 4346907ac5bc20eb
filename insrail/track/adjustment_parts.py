"""The fastener parts that make an adjustment amount, per rail and sleeper, and the materials list.

A fastener type file (``resources/fastener_types/*.toml``) may hold per direction a table of
parts as the maintenance rules print it: ``[lateral_parts]`` / ``[vertical_parts]`` with
``amounts_mm`` (every whole amount of the range) and ``[[...positions]]``, each a place in the
fastening (``name``; ``unit`` "No." for numbered parts or "mm" for thicknesses; the ``as_built``
size; ``sizes`` one per amount; ``stock_mm`` where a thickness is made of several pieces, e.g.
shims; ``assumed = true`` where the sizes are not from published figures). A lateral table's
amounts are in the rule book's sign, ``positive = "field side"``: + moves the rail away from the
track centre. The adjustment's own sign is + to the right (:mod:`insrail.track.adjustment`), so
the left rail's amount enters the table negated. A table with a ``note`` and no positions says
how the amount is made without parts (e.g. "shift the base plate").
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from insrail.track.tolerance import SettingsFileError, read_number

#: The sign of a part table's amounts: lateral + moves the rail to the field side, vertical + raises it.
POSITIVE = {"lateral_parts": "field side", "vertical_parts": "up"}
#: Marks a part whose sizes are not published figures (the sheets explain it).
ASSUMED = "*"


@dataclass(frozen=True)
class PartPosition:
    """One place in the fastening and its part size per amount."""

    name: str
    unit: str  # "No." or "mm"
    as_built: float
    sizes: tuple[float, ...]
    stock_mm: tuple[float, ...] = ()
    assumed: bool = False

    def label(self, size: float) -> str:
        text = f"{size:g}"
        return f"No. {text}" if self.unit == "No." else f"{text} mm"

    def pieces(self, size: float) -> list[float]:
        """The pieces a size is made of: itself, or for stock sizes the fewest pieces (largest first)."""
        if not self.stock_mm:
            return [size] if size else []
        left, out = size, []
        for piece in sorted(self.stock_mm, reverse=True):
            count = int(left // piece + 1e-9)
            out += [piece] * count
            left -= count * piece
        return out


@dataclass(frozen=True)
class PartTable:
    """The parts of one direction per whole amount [mm] in the table's sign."""

    amounts_mm: tuple[int, ...]
    positions: tuple[PartPosition, ...]
    note: str = ""

    def changes(self, amount_mm: int) -> list[tuple[PartPosition, float]]:
        """(position, size) of every position whose part differs from the as-built one."""
        index = self.amounts_mm.index(amount_mm)
        return [(p, p.sizes[index]) for p in self.positions if p.sizes[index] != p.as_built]


def table_amount(direction: str, rail: int, amount_mm: float) -> int:
    """An amount in the adjustment's sign (lateral + right) in a part table's sign (lateral + field side)."""
    sign = -1 if direction == "lateral" and rail == 0 else 1
    return int(round(sign * amount_mm))


def read_part_table(path: Path, key: str, table: object, low_mm: float, high_mm: float) -> PartTable:
    """``[lateral_parts]`` / ``[vertical_parts]`` of a fastener type file, checked: every whole
    amount of the range (both rails' signs) has a size at every position."""
    if not isinstance(table, dict):
        raise SettingsFileError(path, key, "expected a table")
    positive = POSITIVE[key]
    if table.get("positive") != positive:
        raise SettingsFileError(path, f"{key}.positive", f'expected "{positive}" (the sign the amounts are written in)')
    amounts = table.get("amounts_mm")
    if not isinstance(amounts, list) or not all(isinstance(a, int) and not isinstance(a, bool) for a in amounts):
        raise SettingsFileError(path, f"{key}.amounts_mm", "expected a list of whole millimetres")
    wanted = set(range(int(np.ceil(low_mm)), int(np.floor(high_mm)) + 1))
    if key == "lateral_parts":
        wanted |= {-a for a in wanted}
    missing = sorted(wanted - set(amounts))
    if missing:
        raise SettingsFileError(path, f"{key}.amounts_mm", f"the fastener's range needs the amounts {missing}")
    positions = []
    for index, raw in enumerate(table.get("positions", [])):
        where = f"{key}.positions[{index}]"
        if not isinstance(raw, dict) or not isinstance(raw.get("name"), str) or raw.get("unit") not in ("No.", "mm"):
            raise SettingsFileError(path, where, 'expected name = "...", unit = "No." or "mm", as_built and sizes')
        sizes = raw.get("sizes")
        if not isinstance(sizes, list) or len(sizes) != len(amounts):
            raise SettingsFileError(path, f"{where}.sizes", f"expected {len(amounts)} sizes, one per amount")
        stock = tuple(read_number(path, f"{where}.stock_mm", s, positive=True) for s in raw.get("stock_mm", []))
        position = PartPosition(raw["name"], raw["unit"], read_number(path, f"{where}.as_built", raw.get("as_built")),
                                tuple(read_number(path, f"{where}.sizes", s) for s in sizes), stock,
                                bool(raw.get("assumed", False)))
        for size in position.sizes:
            if stock and abs(sum(position.pieces(size)) - size) > 1e-9:
                raise SettingsFileError(path, f"{where}.sizes", f"{size:g} mm cannot be made of {list(stock)}")
        positions.append(position)
    return PartTable(tuple(amounts), tuple(positions), str(table.get("note", "")))


def parts_text(tables: dict[str, PartTable], direction: str, rail: int, amount_mm: float) -> str:
    """What to fit for one amount at one rail, e.g. WJ-8 lateral +2 mm at the right rail "outer
    block No. 9→7; inner block No. 9→11" ("" where the amount is 0 or the
    fastener type has no parts table for the direction). Sizes not from published figures end in
    :data:`ASSUMED`."""
    table = tables.get(direction)
    if table is None or not np.isfinite(amount_mm) or round(amount_mm) == 0:
        return ""
    changes = table.changes(table_amount(direction, rail, amount_mm))
    return "; ".join(f"{_part_name(p)} {_change(p, size)}" for p, size in changes) or table.note


def _change(position: PartPosition, size: float) -> str:
    if not position.as_built:  # parts added
        return "+".join(f"{p:g}" for p in position.pieces(size)) + " mm"
    as_built = position.label(position.as_built).removesuffix(" mm")
    return f"{as_built}→{position.label(size).removeprefix('No. ')}"


def materials(tables: dict[str, PartTable], lateral_mm: np.ndarray,
              vertical_mm: np.ndarray) -> list[tuple[str, str, int, int]]:
    """The parts to bring: (part, size, pieces at left rails, at right rails) per position and size,
    in the order of the fastener file; ``*_mm`` the amounts (n, 2) [left, right]."""
    counts: Counter = Counter()
    rank: dict[str, int] = {}  # part name -> its place in the file
    for direction, amounts in (("lateral", lateral_mm), ("vertical", vertical_mm)):
        table = tables.get(direction)
        if table is None:
            continue
        for position in table.positions:
            rank.setdefault(_part_name(position), len(rank))
        for rail in (0, 1):
            values, number = np.unique(np.round(np.nan_to_num(amounts[:, rail])).astype(int), return_counts=True)
            for value, count in zip(values, number):
                if value == 0:
                    continue
                for position, size in table.changes(table_amount(direction, rail, value)):
                    for piece in position.pieces(size) if position.stock_mm else [size]:
                        counts[(_part_name(position), position.label(piece), rail)] += int(count)
    keys = sorted({key[:2] for key in counts}, key=lambda key: (rank[key[0]], _size_key(key[1])))
    return [(name, size, counts[(name, size, 0)], counts[(name, size, 1)]) for name, size in keys]


def _part_name(position: PartPosition) -> str:
    return position.name + (ASSUMED if position.assumed else "")


def _size_key(label: str) -> float:
    return float(label.removeprefix("No. ").removesuffix(" mm"))
