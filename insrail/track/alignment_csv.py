"""The design element table: a comma-separated text file a surveyor can type from the drawings.

Layout (documented with an example in docs/alignment.md)::

    # comment lines start with '#'; blank lines are ignored
    [alignment]                      key, value rows
    name, main
    start_station_m, 1000.0          continuous station of the start
    start_east_m, 500000.0
    start_north_m, 3000000.0
    start_azimuth_deg, 30.0          clockwise from grid north (or start_azimuth_gon)
    station_prefix, DK               optional, default K
    [horizontal]                     a header row, then one row per element
    type, length_m, radius_start_m, radius_end_m, turn
    [profile]                        optional
    station_m, elevation_m, curve, curve_length_m, curve_radius_m
    [cant]                           optional; cant_mm > 0: left rail higher
    station_m, cant_mm
    [station_equations]              optional
    back_m, ahead_m

Columns of a table may come in any order (the header names them). Station cells of
[profile] and [cant] take a continuous station in metres or a label such as
"DK1+234.567", which the station equations turn into the continuous station.
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from pathlib import Path

from insrail.io.errors import InputError, reason_of
from insrail.io.atomic import atomic_write
from insrail.track.alignment import Arc, Clothoid, DesignAlignment, HorizontalAlignment, Line
from insrail.track.errors import DesignError
from insrail.track.profile import PVI, CantTable, VerticalProfile
from insrail.track.stationing import StationEquation, StationEquations

_ALIGNMENT_KEYS = ("name", "start_station_m", "start_east_m", "start_north_m", "start_azimuth_deg",
                   "start_azimuth_gon", "station_prefix")
_TABLE_COLUMNS = {
    "horizontal": ("type", "length_m", "radius_start_m", "radius_end_m", "turn"),
    "profile": ("station_m", "elevation_m", "curve", "curve_length_m", "curve_radius_m"),
    "cant": ("station_m", "cant_mm"),
    "station_equations": ("back_m", "ahead_m"),
}
_REQUIRED_COLUMNS = {
    "horizontal": ("type", "length_m"),
    "profile": ("station_m", "elevation_m"),
    "cant": ("station_m", "cant_mm"),
    "station_equations": ("back_m", "ahead_m"),
}


@dataclass
class _Row:
    line: int
    cells: dict[str, str]


@dataclass
class _Section:
    name: str
    line: int
    rows: list[_Row]


def _split_sections(path: Path, text: str) -> dict[str, _Section]:
    sections: dict[str, _Section] = {}
    current: _Section | None = None
    header: list[str] | None = None
    for number, cells in enumerate(csv.reader(io.StringIO(text)), start=1):
        cells = [c.strip() for c in cells]
        while cells and cells[-1] == "":
            cells.pop()
        if not cells or cells[0].startswith("#"):
            continue
        if len(cells) == 1 and cells[0].startswith("[") and cells[0].endswith("]"):
            name = cells[0][1:-1].strip().lower()
            if name != "alignment" and name not in _TABLE_COLUMNS:
                raise InputError(path, number, "unknown section [{name}]; expected [alignment], {sections}",
                                 fields={"name": name, "sections": [f"[{s}]" for s in _TABLE_COLUMNS]})
            if name in sections:
                raise InputError(path, number, "section [{name}] appears twice (first on line {line})", fields={"name": name, "line": sections[name].line})
            current = sections[name] = _Section(name, number, [])
            header = None
            continue
        if current is None:
            raise InputError(path, number, "expected a section header such as [alignment] before any data")
        if current.name == "alignment":
            if len(cells) != 2:
                raise InputError(path, number, "expected 'key, value' in [alignment], found {count} fields", fields={"count": len(cells)})
            key = cells[0].lower()
            if key not in _ALIGNMENT_KEYS:
                expected = ", ".join(_ALIGNMENT_KEYS)
                raise InputError(path, number, "unknown key {key!r}; expected one of {expected}", fields={"key": cells[0], "expected": expected})
            if any(row.cells.get("key") == key for row in current.rows):
                raise InputError(path, number, "key {key!r} given twice", fields={"key": key})
            current.rows.append(_Row(number, {"key": key, "value": cells[1]}))
            continue
        if header is None:
            header = [c.lower() for c in cells]
            allowed = _TABLE_COLUMNS[current.name]
            for column in header:
                if column not in allowed:
                    raise InputError(path, number, "unknown column {column!r} in [{section}]; expected {allowed}",
                                     fields={"column": column, "section": current.name, "allowed": list(allowed)})
            if len(set(header)) != len(header):
                raise InputError(path, number, "a column is named twice in the header of [{file}]", fields={"file": current.name})
            missing = [c for c in _REQUIRED_COLUMNS[current.name] if c not in header]
            if missing:
                raise InputError(path, number, "[{file}] header lacks column(s) {missing}", fields={"file": current.name, "missing": list(missing)})
            continue
        if len(cells) > len(header):
            raise InputError(path, number, "expected at most {count} fields ({header}), "
                             "found {found}", fields={"count": len(header), "header": list(header), "found": len(cells)})
        current.rows.append(_Row(number, dict(zip(header, cells + [""] * (len(header) - len(cells))))))
    return sections


def _number(path: Path, line: int, column: str, text: str, *, allow_inf: bool = False) -> float:
    try:
        value = float(text)
    except ValueError:
        raise InputError(path, line, "{column}: expected a number, found {text!r}", fields={"column": column, "text": text}) from None
    if math.isnan(value) or (math.isinf(value) and not allow_inf):
        raise InputError(path, line, "{column}: expected a finite number, found {text!r}", fields={"column": column, "text": text})
    return value


def _optional_number(path: Path, line: int, column: str, text: str, *, allow_inf: bool = False) -> float | None:
    return None if text == "" else _number(path, line, column, text, allow_inf=allow_inf)


def _horizontal_element(path: Path, row: _Row):
    cells, line = row.cells, row.line
    kind = cells.get("type", "").lower()
    length = _number(path, line, "length_m", cells.get("length_m", ""))
    radius_start = _optional_number(path, line, "radius_start_m", cells.get("radius_start_m", ""), allow_inf=True)
    radius_end = _optional_number(path, line, "radius_end_m", cells.get("radius_end_m", ""), allow_inf=True)
    turn = cells.get("turn", "").lower()
    if kind == "line" and (radius_start is not None or radius_end is not None or turn):
        raise InputError(path, line, "a line takes no radius and no turn")
    if kind == "arc" and radius_start is None:
        raise InputError(path, line, "an arc needs radius_start_m (its radius)")
    if kind == "arc" and radius_end is not None and radius_end != radius_start:
        raise InputError(path, line, "an arc has one radius: leave radius_end_m empty or equal to radius_start_m")
    if kind == "clothoid" and (radius_start is None or radius_end is None):
        raise InputError(path, line, "a clothoid needs radius_start_m and radius_end_m ('inf' at a tangent end)")
    try:
        if kind == "line":
            return Line(length)
        if kind == "arc":
            return Arc(length, radius_start, turn)
        if kind == "clothoid":
            return Clothoid(length, radius_start, radius_end, turn)
    except ValueError as err:  # the element's own checks (DesignError)
        raise InputError(path, line, reason_of(err)) from None
    raise InputError(path, line, "type: expected line, clothoid or arc, found {type!r}", fields={"type": cells.get('type', '')})


def _station(path: Path, line: int, column: str, text: str, equations: StationEquations) -> float:
    if "+" in text:
        try:
            return equations.parse_label(text)
        except ValueError as err:
            raise InputError(path, line, "{column}: {err}", fields={"column": column, "err": reason_of(err)}) from None
    return _number(path, line, column, text)


def read_alignment_csv(path: str | Path) -> DesignAlignment:
    """Read a design element table; InputError names the line of anything wrong."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8-sig")
    except (OSError, UnicodeDecodeError) as err:
        raise InputError(path, None, "cannot read the element table: {err}", fields={"err": err}) from None
    sections = _split_sections(path, text)
    for required in ("alignment", "horizontal"):
        if required not in sections:
            raise InputError(path, None, "section [{required}] is missing", fields={"required": required})

    head = sections["alignment"]
    values = {row.cells["key"]: row for row in head.rows}
    for key in ("start_station_m", "start_east_m", "start_north_m"):
        if key not in values:
            raise InputError(path, head.line, "[alignment] lacks {key}", fields={"key": key})
    if ("start_azimuth_deg" in values) == ("start_azimuth_gon" in values):
        raise InputError(path, head.line, "[alignment] needs exactly one of start_azimuth_deg or start_azimuth_gon")

    def value(key: str) -> float:
        return _number(path, values[key].line, key, values[key].cells["value"])

    if "start_azimuth_deg" in values:
        azimuth = math.radians(value("start_azimuth_deg"))
    else:
        azimuth = value("start_azimuth_gon") * math.pi / 200.0

    line_of = {name: [row.line for row in section.rows] for name, section in sections.items()}

    def design_error(err: DesignError) -> InputError:
        section = sections.get(err.part)
        if section is None:
            return InputError(path, None, err.phrase)
        line = line_of[err.part][err.index] if err.index is not None else section.line
        return InputError(path, line, err.phrase)

    try:
        equation_rows = sections["station_equations"].rows if "station_equations" in sections else []
        prefix_row = values.get("station_prefix")
        equations = StationEquations(
            tuple(
                StationEquation(
                    _number(path, row.line, "back_m", row.cells["back_m"]),
                    _number(path, row.line, "ahead_m", row.cells["ahead_m"]),
                )
                for row in equation_rows
            ),
            prefix=prefix_row.cells["value"] if prefix_row else "K",
        )
        horizontal = HorizontalAlignment(
            start_east_m=value("start_east_m"),
            start_north_m=value("start_north_m"),
            start_azimuth_rad=azimuth,
            start_station_m=value("start_station_m"),
            elements=tuple(_horizontal_element(path, row) for row in sections["horizontal"].rows),
        )
        vertical = None
        if "profile" in sections:
            pvis = []
            for row in sections["profile"].rows:
                cells = row.cells
                numbers = (
                    _station(path, row.line, "station_m", cells["station_m"], equations),
                    _number(path, row.line, "elevation_m", cells["elevation_m"]),
                    cells.get("curve", "").lower() or "none",
                    _optional_number(path, row.line, "curve_length_m", cells.get("curve_length_m", "")),
                    _optional_number(path, row.line, "curve_radius_m", cells.get("curve_radius_m", "")),
                )
                try:
                    pvis.append(PVI(*numbers))
                except ValueError as err:
                    raise InputError(path, row.line, reason_of(err)) from None
            vertical = VerticalProfile(tuple(pvis))
        cant = None
        if "cant" in sections:
            rows = sections["cant"].rows
            cant = CantTable(
                [_station(path, row.line, "station_m", row.cells["station_m"], equations) for row in rows],
                [_number(path, row.line, "cant_mm", row.cells["cant_mm"]) / 1000.0 for row in rows],
            )
        name_row = values.get("name")
        return DesignAlignment(
            horizontal=horizontal,
            vertical=vertical,
            cant=cant,
            station_equations=equations,
            name=name_row.cells["value"] if name_row else path.stem,
        )
    except DesignError as err:
        raise design_error(err) from None


def _fmt(value: float) -> str:
    return "inf" if math.isinf(value) else repr(float(value))


def _element_row(element) -> list[str]:
    if isinstance(element, Line):
        return ["line", _fmt(element.length_m), "", "", ""]
    if isinstance(element, Arc):
        return ["arc", _fmt(element.length_m), _fmt(element.radius_m), _fmt(element.radius_m), element.turn]
    return ["clothoid", _fmt(element.length_m), _fmt(element.radius_start_m), _fmt(element.radius_end_m), element.turn]


def format_alignment_csv(alignment: DesignAlignment) -> str:
    """The element-table text of a design alignment (what write_alignment_csv writes)."""
    h = alignment.horizontal
    out = io.StringIO()
    writer = csv.writer(out, lineterminator="\n")
    out.write("# insrail design alignment element table (docs/alignment.md)\n")
    out.write("# stations: continuous measure [m]; azimuth clockwise from grid north; cant > 0: left rail higher\n")
    writer.writerow(["[alignment]"])
    writer.writerow(["name", alignment.name])
    writer.writerow(["start_station_m", _fmt(h.start_station_m)])
    writer.writerow(["start_east_m", _fmt(h.start_east_m)])
    writer.writerow(["start_north_m", _fmt(h.start_north_m)])
    # 12 decimals of a degree (5e-15 rad) reads better than repr's 29.999999999999996
    writer.writerow(["start_azimuth_deg", f"{math.degrees(h.start_azimuth_rad):.12f}".rstrip("0").rstrip(".")])
    writer.writerow(["station_prefix", alignment.station_equations.prefix])
    out.write("\n")
    writer.writerow(["[horizontal]"])
    writer.writerow(_TABLE_COLUMNS["horizontal"])
    writer.writerows(_element_row(e) for e in h.elements)
    if alignment.vertical is not None:
        out.write("\n")
        writer.writerow(["[profile]"])
        writer.writerow(_TABLE_COLUMNS["profile"])
        for p in alignment.vertical.pvis:
            writer.writerow([
                _fmt(p.station_m), _fmt(p.elevation_m), p.curve,
                "" if p.curve_length_m is None else _fmt(p.curve_length_m),
                "" if p.curve_radius_m is None else _fmt(p.curve_radius_m),
            ])
    if alignment.cant is not None:
        out.write("\n")
        writer.writerow(["[cant]"])
        writer.writerow(_TABLE_COLUMNS["cant"])
        writer.writerows(
            [_fmt(s), _fmt(c * 1000.0)] for s, c in zip(alignment.cant.stations_m, alignment.cant.cant_m)
        )
    if alignment.station_equations.equations:
        out.write("\n")
        writer.writerow(["[station_equations]"])
        writer.writerow(_TABLE_COLUMNS["station_equations"])
        writer.writerows([_fmt(e.back_m), _fmt(e.ahead_m)] for e in alignment.station_equations.equations)
    return out.getvalue()


def write_alignment_csv(path: str | Path, alignment: DesignAlignment) -> None:
    """Write the element table of ``alignment`` to ``path`` (atomically)."""
    text = format_alignment_csv(alignment)
    with atomic_write(path) as stream:
        stream.write(text)
