"""The lift/lining table: per sleeper, how far to lift and line each rail, for a tamping machine's guidance
computer or the crews, and where each rail is.

Layout (``docs/formats.md``, "Lift/lining table")::

    # insrail lift-lining 2
    # project = demo
    # survey = short
    # amounts = lift_*_mm, lining_*_mm: move the rail by the amount (...): planned by insrail for fastener WJ-8 ...
    # deviations = *_deviation_*_mm: measured − design (design.csv), where the rail is; not an instruction
    # reference = design alignment surveys/short/truth/design.csv
    # crs = Transverse Mercator ...
    # convention = mm; lift + up, lining + to the right looking towards increasing chainage; empty = not measured
    number,chainage,station_m,valid,lift_left_mm,lift_right_mm,lining_left_mm,lining_right_mm,vertical_deviation_left_mm,...
    1,DK1+051.250,1051.2500,1,1.0,1.0,0.0,0.0,2.4,2.2,-0.3,-0.1,0.0

The amounts are the project's adjustment (sleepers.csv ``adjust_*_mm``, :mod:`insrail.track.adjustment`), the
same numbers as the workbook, the PDF and the DXF (:mod:`insrail.report.labels`): they bring the track within
the tolerance profile, not the rail onto its reference. The deviations are measured − reference of each rail
(the design alignment with its gauge and cant, or without a design the line fitted to the measured
centreline). An empty cell is a value that does not exist there (no measurement at the sleeper).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from insrail.io.errors import InputError
from insrail.names import t
from insrail.report.labels import amounts_text, deviation_reference
from insrail.track.adjustment import load_fastener_type
from insrail.track.tolerance import load_tolerance_profile
from insrail.project.run_settings import processed_crs_text

MAGIC = "# insrail lift-lining 2"
AMOUNT_COLUMNS = ["lift_left_mm", "lift_right_mm", "lining_left_mm", "lining_right_mm"]
DEVIATION_COLUMNS = ["vertical_deviation_left_mm", "vertical_deviation_right_mm", "lateral_deviation_left_mm",
                     "lateral_deviation_right_mm"]
HEADER = ["number", "chainage", "station_m", "valid", *AMOUNT_COLUMNS, *DEVIATION_COLUMNS, "design_cant_mm"]
CONVENTION = "mm; lift + up, lining + to the right looking towards increasing chainage; empty = not measured"


@dataclass(frozen=True)
class LiftLiningTable:
    """A lift/lining table (millimetres as in the file; NaN where empty)."""

    metadata: dict[str, str]  # the "# key = value" lines: project, survey, amounts, deviations, reference, crs, convention
    number: np.ndarray
    chainage: tuple[str, ...]
    station_m: np.ndarray
    valid: np.ndarray
    lift_mm: np.ndarray  # (n, 2) [left, right], + up: the planned amounts
    lining_mm: np.ndarray  # (n, 2) [left, right], + right: the planned amounts
    vertical_deviation_mm: np.ndarray  # (n, 2) measured - reference, + up
    lateral_deviation_mm: np.ndarray  # (n, 2) measured - reference, + right
    design_cant_mm: np.ndarray

    def __len__(self) -> int:
        return len(self.number)


def reference_text(project, results) -> str:
    """What the deviations are taken against, from the results' summary."""
    design = results.summary.get("track", {}).get("design", "")
    if design:
        return t("design alignment {design}").format(design=design)
    return t("the line fitted to the measured centreline (no design alignment; thesis eq. 5.24)")


def lift_lining_table(project, results) -> LiftLiningTable:
    """The table of a processed survey's stored results (:class:`~insrail.project.results.StoredResults`);
    a relative survey's results have no amounts to give (an error saying why)."""
    if "withheld" in results.summary.get("adjustment", {}):
        raise InputError(results.folder / "summary.toml", None,
                         "no lift/lining table: {summary}", fields={"summary": results.summary['adjustment']['withheld']})
    c = results.columns
    valid = c["valid"] > 0

    def pair(pattern: str) -> np.ndarray:
        return np.column_stack([c[pattern.format(rail=rail)] for rail in ("left", "right")])

    profile = load_tolerance_profile(project.resource(project.tolerance_profile))
    try:
        fastener = load_fastener_type(project.resource(project.fastener))
    except ValueError:  # edited since processing: the amounts are in the results, the file only names it
        fastener = None
    metadata = {"project": project.name, "survey": results.survey,
                "amounts": f"{', '.join(AMOUNT_COLUMNS)}: {amounts_text(results.summary, profile, fastener)}",
                "deviations": t("{columns}: {reference}, where the rail is (not an instruction)").format(
                    columns=", ".join(DEVIATION_COLUMNS), reference=deviation_reference(results.summary)),
                "reference": reference_text(project, results), "crs": processed_crs_text(project, results.summary),
                "convention": t(CONVENTION)}
    return LiftLiningTable(metadata, np.asarray(results.number), tuple(results.label), c["station_m"], valid,
                           pair("adjust_vertical_{rail}_mm"), pair("adjust_lateral_{rail}_mm"),
                           pair("vertical_deviation_{rail}_mm"), pair("lateral_deviation_{rail}_mm"),
                           c["design_cant_mm"])


def _cell(value: float, digits: int) -> str:
    return f"{value:.{digits}f}" if np.isfinite(value) else ""


def format_table(table: LiftLiningTable) -> str:
    """The file text of a table (see the module docstring)."""
    lines = [MAGIC] + [f"# {key} = {' '.join(str(value).split())}" for key, value in table.metadata.items()]
    lines.append(",".join(HEADER))
    for i in range(len(table)):
        label = table.chainage[i] or f"{table.station_m[i]:.4f}"
        lines.append(",".join([str(int(table.number[i])), label, _cell(table.station_m[i], 4), str(int(table.valid[i])),
                               *(_cell(v, 1) for v in (*table.lift_mm[i], *table.lining_mm[i],
                                                       *table.vertical_deviation_mm[i], *table.lateral_deviation_mm[i])),
                               _cell(table.design_cant_mm[i], 1)]))
    return "\n".join(lines) + "\n"


def format_lift_lining(project, results) -> str:
    """``insrail export --format lift-lining``."""
    return format_table(lift_lining_table(project, results))


def read_lift_lining(path: str | Path) -> LiftLiningTable:
    """Read a lift/lining table; InputError naming the file, the line and what was expected."""
    path = Path(path)
    try:
        lines = path.read_text(encoding="utf-8").splitlines()
    except (OSError, UnicodeDecodeError) as error:
        raise InputError(path, None, "cannot read the lift/lining table: {error}", fields={"error": error}) from None
    if lines and lines[0] == "# insrail lift-lining 1":
        raise InputError(path, 1, "a version 1 table (amounts = -deviation, from an insrail before the amounts were "
                                  "the planned adjustment): export it again")
    if not lines or lines[0] != MAGIC:
        raise InputError(path, 1, "expected the first line {magic!r}", fields={"magic": MAGIC})
    metadata: dict[str, str] = {}
    row = 1
    while row < len(lines) and lines[row].startswith("#"):
        key, equals, value = lines[row][1:].partition("=")
        if not equals:
            raise InputError(path, row + 1, "expected a comment line '# key = value'")
        metadata[key.strip()] = value.strip()
        row += 1
    if row >= len(lines) or lines[row].split(",") != HEADER:
        raise InputError(path, row + 1, "expected the header {header}", fields={"header": ','.join(HEADER)})
    numbers, chainages, values = [], [], []
    for line_number, line in enumerate(lines[row + 1:], start=row + 2):
        fields = line.split(",")
        if len(fields) != len(HEADER):
            raise InputError(path, line_number, "expected {count} fields ({header}), found {found}", fields={"count": len(HEADER), "header": ','.join(HEADER), "found": len(fields)})
        if fields[3] not in ("0", "1"):
            raise InputError(path, line_number, "valid: expected 0 or 1, found {valid!r}", fields={"valid": fields[3]})
        try:
            numbers.append(int(fields[0]))
            values.append([float(cell) if cell else np.nan for cell in fields[2:]])
        except ValueError:
            raise InputError(path, line_number, "expected a whole sleeper number and numbers (or empty cells) "
                                                "after the chainage") from None
        chainages.append(fields[1])
    data = np.array(values, dtype=float).reshape(-1, len(HEADER) - 2)
    return LiftLiningTable(metadata, np.array(numbers, dtype=int), tuple(chainages), data[:, 0], data[:, 1] > 0,
                           data[:, 2:4], data[:, 4:6], data[:, 6:8], data[:, 8:10], data[:, 10])
