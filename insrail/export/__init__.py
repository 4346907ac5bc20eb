"""Files for the machines and CAD, written from a processed survey's stored results.

Every export reads the result files (:func:`insrail.project.results.load_results`), never
recomputes geometry, and writes its file atomically:

* ``lift-lining``  per sleeper the planned lift and lining of each rail (the adjustment amounts, as the
  workbook and the PDF carry them) and each rail's deviations from its reference, for a tamping machine's
  guidance computer or the crews (:mod:`insrail.export.liftlining`; layout in ``docs/formats.md``, read
  back by :func:`~insrail.export.liftlining.read_lift_lining`)
* ``dxf``          rails, centreline, sleepers with their numbers, the adjustment amounts, exceedance
  markers, one layer each, in the engineering CRS (:mod:`insrail.export.dxf`, with ezdxf)
* ``landxml``      the measured centreline and rails as LandXML 1.2 3D lines (:mod:`insrail.export.landxml`)
* ``csv``          per-sleeper coordinates of centreline and rails (:mod:`insrail.export.points`)
* ``tamping``, ``tamping-template``  the tamping re-design's lift and slew (``insrail redesign``) in the
  generic layout or a user's template (:mod:`insrail.export.tamping`)

Coordinates are easting, northing and normal height of the engineering CRS; lengths in the
files are metres, amounts millimetres. Frames and signs as in :mod:`insrail.track`. The texts for
people (the notes of the lift/lining table, the drawing's labels) are in the project's report language
(``[report] language``); the column names a machine reads are the same in every language.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from insrail.io.atomic import atomic_write


@dataclass(frozen=True)
class ExportFormat:
    name: str
    suffix: str  # of the default file name: <project>/reports/<survey><suffix>
    description: str
    render: Callable  # (project, results) -> str | bytes


def export_formats() -> dict[str, ExportFormat]:
    """Every export format by its name (``insrail export --format NAME``)."""
    from insrail.export import dxf, landxml, liftlining, points, tamping

    return {f.name: f for f in (
        ExportFormat("lift-lining", "_lift_lining.csv", "planned lift/lining and deviations per sleeper and rail",
                     liftlining.format_lift_lining),
        ExportFormat("dxf", ".dxf", "CAD drawing: rails, centreline, sleepers, amounts, exceedances", dxf.format_dxf),
        ExportFormat("landxml", "_centreline.xml", "measured centreline and rails, LandXML 1.2", landxml.format_landxml_lines),
        ExportFormat("csv", "_points.csv", "per-sleeper coordinates of centreline and rails", points.format_points),
        ExportFormat("tamping", "_tamping.csv", "the tamping re-design's lift and slew, generic layout",
                     tamping.format_generic),
        ExportFormat("tamping-template", "_tamping.txt", "the tamping re-design's lift and slew in a template's layout",
                     tamping.format_template),
    )}


def write_export(project, results, format_name: str, path: Path, **options) -> Path:
    """Render one export of ``results`` (a :class:`~insrail.project.results.StoredResults`) to ``path``;
    ``options`` go to the format's renderer (``template`` of ``tamping-template``)."""
    formats = export_formats()
    if format_name not in formats:
        raise ValueError(f"unknown export format {format_name!r} (expected {', '.join(formats)})")
    from insrail.names import in_language
    from insrail.project.run_settings import report_language

    with in_language(report_language(project)):  # the texts for people; the column ids stay for the machines
        content = formats[format_name].render(project, results, **options)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if isinstance(content, bytes):
        with atomic_write(path, "wb", encoding=None) as handle:
            handle.write(content)
    else:
        with atomic_write(path, "w") as handle:
            handle.write(content)
    return path


def default_export_path(project_folder: Path, name: str, format_name: str) -> Path:
    """``<project>/reports/<name><suffix>``: beside the reports, never inside ``results/`` (replaced whole
    when the survey is processed again)."""
    from insrail.project.results import REPORTS_FOLDER

    return Path(project_folder) / REPORTS_FOLDER / f"{name}{export_formats()[format_name].suffix}"
