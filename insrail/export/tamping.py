"""Machine files of a tamping re-design (``insrail redesign``): ``results/<survey>/redesign/tamping.csv``
in the generic layout, or in a layout a user describes in a template.

No tamping guidance computer's input layout is publicly documented well enough to write (the public
material found -- Plasser & Theurer's WinALC "Nominal Geometry" operating instruction, IRICEN's
"Mechanised Tamping & Stabilisation" -- describes entering the nominal geometry and the lift and slew
values in the program's tables, not a file's bytes; ``docs/formats.md``). So:

* ``tamping``: insrail's generic layout, ``tamping.csv`` itself with the project named (read back
  by :func:`read_tamping`);
* ``tamping-template``: a layout from a TOML template (``--template FILE``): column order, titles,
  units (station in m or km; amounts in mm, cm or m), a sign per column, the separator, the
  decimals, a header line or not, and a spacing (one row every ``spacing_m`` of station,
  interpolated, the marks kept); read back by :func:`read_template_export`.

Every file states its sign conventions in its first lines (``#`` lines, or the template's
``comment`` prefix); a template's lines are in the report language, tamping.csv's (insrail's own
file, read back) in English.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from insrail.io.errors import InputError
from insrail.names import t
from insrail.project.redesign import REDESIGN_FOLDER, TAMPING_FILE, TAMPING_HEADER

#: Fields a template column may take, and the unit each is converted from (station m, amounts mm).
FIELDS = {"station": "m", "label": "", "lift_left": "mm", "lift_right": "mm", "slew": "mm", "cant": "mm", "mark": ""}
UNITS = {"m": {"m": 1.0, "km": 1e-3}, "mm": {"mm": 1.0, "cm": 0.1, "m": 1e-3}}


@dataclass(frozen=True)
class TampingTable:
    """tamping.csv read back (mm as in the file)."""

    metadata: dict[str, str]
    station_m: np.ndarray
    label: tuple[str, ...]
    values: dict[str, np.ndarray]  # lift_left, lift_right, slew, cant [mm]
    mark: tuple[str, ...]


def read_tamping(path: str | Path) -> TampingTable:
    """tamping.csv (or the generic export); an error names the file, the line and what was expected."""
    path = Path(path)
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except FileNotFoundError:
        raise InputError(path, None, "not found: re-design the survey first (insrail redesign)") from None
    if not lines or lines[0] != "# insrail tamping 1":
        raise InputError(path, 1, "expected '# insrail tamping 1' (a tamping.csv of insrail redesign)")
    metadata, rows, header_seen = {}, [], False
    for number, line in enumerate(lines[1:], start=2):
        if line.startswith("#"):
            key, _, value = line[1:].partition("=")
            metadata[key.strip()] = value.strip()
        elif not header_seen:
            if line.split(",") != TAMPING_HEADER:
                raise InputError(path, number, "expected the header {header}", fields={"header": ','.join(TAMPING_HEADER)})
            header_seen = True
        else:
            parts = line.split(",", 6)
            if len(parts) != 7:
                raise InputError(path, number, "expected 7 fields, found {count}", fields={"count": len(parts)})
            try:
                rows.append((float(parts[0]), parts[1], *map(float, parts[2:6]), parts[6].strip('"')))
            except ValueError:
                raise InputError(path, number, "expected numbers in station_m and the amounts") from None
    if not rows:
        raise InputError(path, None, "no rows")
    columns = list(zip(*rows))
    return TampingTable(metadata, np.array(columns[0]), tuple(columns[1]),
                        {name: np.array(columns[i]) for i, name in enumerate(("lift_left", "lift_right", "slew", "cant"), 2)},
                        tuple(columns[6]))


def _tamping_file(results) -> Path:
    return Path(results.folder) / REDESIGN_FOLDER / TAMPING_FILE


def format_generic(project, results) -> str:
    """The generic layout: tamping.csv with the project named after its first line."""
    lines = _tamping_file(results).read_text(encoding="utf-8").splitlines(keepends=True)
    read_tamping(_tamping_file(results))  # refuses a file that is not one
    return "".join([lines[0], f"# project = {project.name}\n", *lines[1:]])


@dataclass(frozen=True)
class Column:
    field: str
    title: str
    unit: str
    sign: float


@dataclass(frozen=True)
class Template:
    """A user's machine layout (module docstring); ``path`` for errors."""

    path: Path
    name: str
    columns: tuple[Column, ...]
    separator: str = ","
    decimals: int = 1
    header: bool = True
    comment: str = "#"
    spacing_m: float = 0.0  # 0: every row of tamping.csv


def load_template(path: str | Path) -> Template:
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InputError(path, None, "template not found") from None
    except tomllib.TOMLDecodeError as error:
        raise InputError(path, None, "not valid TOML: {error}", fields={"error": error}) from None
    entries = data.get("columns")
    if not isinstance(entries, list) or not entries:
        raise InputError(path, None, "columns: expected [[columns]] entries with field (and title, unit, sign)")
    columns = []
    for i, entry in enumerate(entries):
        field = entry.get("field") if isinstance(entry, dict) else None
        if field not in FIELDS:
            raise InputError(path, None, "columns[{i}].field: expected one of {known}, found {field!r}", fields={"i": i, "known": list(FIELDS), "field": field})
        base = FIELDS[field]
        unit = entry.get("unit", base)
        if (base and unit not in UNITS[base]) or (not base and unit):
            allowed = ", ".join(UNITS[base]) if base else "no unit"
            raise InputError(path, None, "columns[{i}].unit: expected {allowed} for {field}, found {unit!r}", fields={"i": i, "allowed": allowed, "field": field, "unit": unit})
        sign = entry.get("sign", 1)
        if sign not in (1, -1) or (not base and sign != 1):
            raise InputError(path, None, "columns[{i}].sign: expected 1 or -1 (numbers only), found {sign!r}", fields={"i": i, "sign": sign})
        columns.append(Column(field, str(entry.get("title", field)), unit, float(sign)))
    comment = data.get("comment", "#")
    if not isinstance(comment, str) or not comment.strip():
        raise InputError(path, None, "comment: expected the prefix of the lines that state the sign conventions")
    spacing = data.get("spacing_m", 0.0)
    decimals = data.get("decimals", 1)
    if not isinstance(spacing, (int, float)) or spacing < 0:
        raise InputError(path, None, "spacing_m: expected 0 (every row) or a positive distance, found {spacing!r}", fields={"spacing": spacing})
    if not isinstance(decimals, int) or not 0 <= decimals <= 4:
        raise InputError(path, None, "decimals: expected 0 to 4, found {decimals!r}", fields={"decimals": decimals})
    return Template(path, str(data.get("name", path.stem)), tuple(columns), str(data.get("separator", ",")),
                    decimals, bool(data.get("header", True)), comment, float(spacing))


def _resampled(table: TampingTable, spacing_m: float) -> TampingTable:
    """One row every ``spacing_m`` of station (amounts interpolated) and the marked rows."""
    if spacing_m <= 0:
        return table
    plain = np.array([not m for m in table.mark])
    grid = np.arange(np.ceil(table.station_m[0] / spacing_m) * spacing_m, table.station_m[-1] + 1e-9, spacing_m)
    marked = np.flatnonzero(~plain)
    station = np.concatenate([grid, table.station_m[marked]])
    order = np.argsort(station, kind="stable")
    values = {k: np.concatenate([np.interp(grid, table.station_m[plain], v[plain]), v[marked]])[order]
              for k, v in table.values.items()}
    mark = tuple(np.concatenate([np.full(grid.size, "", object), np.array(table.mark, object)[marked]])[order])
    label = tuple(np.concatenate([np.full(grid.size, "", object), np.array(table.label, object)[marked]])[order])
    return TampingTable(table.metadata, station[order], label, values, mark)


def _conventions(template: Template) -> list[str]:
    """Each column's unit and sign in words (the report language's: these lines are for people)."""
    meanings = {"lift_left": t("{sign} = rail up"), "lift_right": t("{sign} = rail up"),
                "slew": t("{sign} = track to the right looking towards increasing chainage"),
                "cant": t("{sign} = left rail higher")}
    parts = []
    for c in template.columns:
        if c.field in meanings:
            parts.append(f"{c.title} [{c.unit}]: " + meanings[c.field].format(sign="+" if c.sign > 0 else "-"))
        elif c.field == "station":
            parts.append(f"{c.title} [{c.unit}]: " + (t("station (negated)") if c.sign < 0 else t("station")))
    return parts


def _number(value: float, decimals: int) -> str:
    """``value`` to ``decimals``; a value that rounds to zero is "0", never "-0"."""
    return f"{round(value, decimals) + 0.0:.{decimals}f}"


def format_template(project, results, template: Template) -> str:
    """tamping.csv in the template's layout."""
    table = _resampled(read_tamping(_tamping_file(results)), template.spacing_m)
    lines = [f"{template.comment} " + t("{template}: tamping amounts of {project}, survey {survey} (insrail)").format(
        template=template.name, project=project.name, survey=results.survey)]
    lines += [f"{template.comment} {part}" for part in _conventions(template)]
    if template.header:
        lines.append(template.separator.join(c.title for c in template.columns))
    for i in range(table.station_m.size):
        fields = []
        for c in template.columns:
            if c.field == "label":
                fields.append(table.label[i])
            elif c.field == "mark":
                fields.append(table.mark[i])
            elif c.field == "station":
                fields.append(_number(c.sign * table.station_m[i] * UNITS['m'][c.unit], template.decimals + 3))
            else:
                fields.append(_number(c.sign * table.values[c.field][i] * UNITS['mm'][c.unit], template.decimals))
        lines.append(template.separator.join(fields))
    return "\n".join(lines) + "\n"


def read_template_export(path: str | Path, template: Template) -> dict[str, np.ndarray | tuple[str, ...]]:
    """A file written with ``template`` read back into insrail's units and signs (station m, amounts mm)."""
    path = Path(path)
    lines = [line for line in path.read_text(encoding="utf-8").splitlines() if not line.startswith(template.comment)]
    if template.header:
        lines = lines[1:]
    fields = [line.split(template.separator) for line in lines]
    out: dict[str, np.ndarray | tuple[str, ...]] = {}
    for j, c in enumerate(template.columns):
        column = [f[j] for f in fields]
        if c.field in ("label", "mark"):
            out[c.field] = tuple(column)
        else:
            base = "m" if c.field == "station" else "mm"
            out[c.field] = c.sign * np.array(column, float) / UNITS[base][c.unit]
    return out
