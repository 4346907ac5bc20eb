"""The CAD drawing of a processed survey (DXF R2013, written with ezdxf), in the engineering CRS.

Layers (``docs/formats.md``, "DXF drawing"):

* ``INSRAIL_RAIL_LEFT``, ``INSRAIL_RAIL_RIGHT``, ``INSRAIL_CENTRELINE``: 3D polylines through the
  sleepers' rail (top of rail, gauge face) and centreline points, E, N, normal H; broken where sleepers
  are not valid (one polyline per run of valid sleepers)
* ``INSRAIL_SLEEPERS``: a line from the left to the right rail point at every valid sleeper
* ``INSRAIL_SLEEPER_NUMBERS``: the sleeper number as text beside the right rail, along the track
* ``INSRAIL_ADJUSTMENT``: at every rail to move, beside it (the left rail's on its left, the right rail's on
  its right) a text "lining +2 lift -1" [mm]: the adjustment amounts exactly as sleepers.csv, the workbook
  and the lift/lining table carry them (lining + right, lift + up; :mod:`insrail.report.labels`)
* ``INSRAIL_EXCEEDANCE_<CHECK>``: per exceedance of a tolerance check, a circle (radius 1 m) at the
  centreline of the run's middle sleeper and a text "<channel's display name> peak unit"
* ``INSRAIL_INFO``: texts at the first sleeper naming project, survey, CRS and heights, what the
  amounts bring the rail to, and the tolerance profile

Drawing units are metres ($INSUNITS 6). Nothing is projected or shifted: the coordinates are those
of sleepers.csv.
"""

from __future__ import annotations

import io
import re

import numpy as np

from insrail.names import channel_name, t
from insrail.report.labels import amounts_text, deviation_reference
from insrail.track.adjustment import load_fastener_type
from insrail.track.tolerance import load_tolerance_profile
from insrail.project.run_settings import processed_crs_text

RAIL_LAYERS = {"left": "INSRAIL_RAIL_LEFT", "right": "INSRAIL_RAIL_RIGHT"}
CENTRELINE_LAYER = "INSRAIL_CENTRELINE"
SLEEPER_LAYER = "INSRAIL_SLEEPERS"
NUMBER_LAYER = "INSRAIL_SLEEPER_NUMBERS"
ADJUSTMENT_LAYER = "INSRAIL_ADJUSTMENT"
INFO_LAYER = "INSRAIL_INFO"
EXCEEDANCE_PREFIX = "INSRAIL_EXCEEDANCE_"
TEXT_HEIGHT_M = 0.15
MARKER_RADIUS_M = 1.0
# AutoCAD colour indices
_COLOURS = {RAIL_LAYERS["left"]: 5, RAIL_LAYERS["right"]: 3, CENTRELINE_LAYER: 2, SLEEPER_LAYER: 8,
            NUMBER_LAYER: 7, INFO_LAYER: 7, ADJUSTMENT_LAYER: 6}


def exceedance_layer(check: str) -> str:
    """The layer of one tolerance check's exceedances (DXF layer names: letters, digits, _ and -)."""
    return EXCEEDANCE_PREFIX + re.sub(r"[^A-Za-z0-9_-]", "_", check).upper()


def _runs(valid: np.ndarray) -> list[tuple[int, int]]:
    """(first, stop) of each run of consecutive True."""
    edges = np.flatnonzero(np.diff(np.concatenate([[0], valid.astype(np.int8), [0]])))
    return [(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2])]


def amount_text(lining_mm: float, lift_mm: float) -> str:
    """One rail's amounts as the drawing writes them: "lining +2 lift -1" (an amount of 0 left out)."""
    return " ".join(f"{word} {value:+.0f}" for word, value in ((t("lining"), lining_mm), (t("lift"), lift_mm))
                    if np.isfinite(value) and round(value) != 0)


def _points(columns: dict, prefix: str) -> np.ndarray:
    return np.column_stack([columns[f"{prefix}_{axis}_m"] for axis in "ENH"])


def dxf_document(project, results):
    """The ezdxf document of a processed survey's stored results."""
    import ezdxf

    c = results.columns
    valid = (c["valid"] > 0) & np.isfinite(_points(c, "left")).all(axis=1) & np.isfinite(_points(c, "right")).all(axis=1)
    doc = ezdxf.new("R2013", setup=True)
    doc.header["$INSUNITS"] = 6  # metres
    checks = sorted({e.check for e in results.exceedances})
    profile = load_tolerance_profile(project.resource(project.tolerance_profile))
    by_name = {check.name: check for check in profile.checks}
    for layer in (*RAIL_LAYERS.values(), CENTRELINE_LAYER, SLEEPER_LAYER, NUMBER_LAYER, ADJUSTMENT_LAYER, INFO_LAYER,
                  *(exceedance_layer(check) for check in checks)):
        doc.layers.add(layer, color=_COLOURS.get(layer, 1))
    space = doc.modelspace()
    left, right = _points(c, "left"), _points(c, "right")
    centre = _points(c, "centre") if "centre_E_m" in c else 0.5 * (left + right)
    for points, layer in ((left, RAIL_LAYERS["left"]), (right, RAIL_LAYERS["right"]), (centre, CENTRELINE_LAYER)):
        for first, stop in _runs(valid):
            if stop - first >= 2:
                space.add_polyline3d(points[first:stop].tolist(), dxfattribs={"layer": layer})
    across = right - left
    angle = np.degrees(np.arctan2(across[:, 0], -across[:, 1]))  # along the track: the left->right normal turned
    for i in np.flatnonzero(valid):
        space.add_line(left[i].tolist(), right[i].tolist(), dxfattribs={"layer": SLEEPER_LAYER})
        anchor = right[i] + 0.3 * across[i] / max(np.linalg.norm(across[i]), 1e-9)
        space.add_text(str(int(results.number[i])), height=TEXT_HEIGHT_M, dxfattribs={
            "layer": NUMBER_LAYER, "rotation": float(angle[i])}).set_placement(anchor.tolist())
    # outside each rail, the right rail's beyond the sleeper numbers
    for name, points, offset_m in (("left", left, -0.3), ("right", right, 0.3 + 3 * TEXT_HEIGHT_M)):
        lining, lift = c[f"adjust_lateral_{name}_mm"], c[f"adjust_vertical_{name}_mm"]
        for i in np.flatnonzero(np.isfinite(points).all(axis=1)):
            label = amount_text(lining[i], lift[i])
            if not label:
                continue
            anchor = points[i] + offset_m * across[i] / max(np.linalg.norm(across[i]), 1e-9)
            space.add_text(label, height=TEXT_HEIGHT_M, dxfattribs={
                "layer": ADJUSTMENT_LAYER, "rotation": float(angle[i])}).set_placement(anchor.tolist())
    row_of = {int(n): row for row, n in enumerate(results.number)}
    for e in results.exceedances:
        rows = [row_of[n] for n in (e.first_sleeper, e.last_sleeper) if n in row_of]
        if not rows:
            continue
        middle = (rows[0] + rows[-1]) // 2
        if not np.isfinite(centre[middle]).all():
            continue
        layer = exceedance_layer(e.check)
        space.add_circle(centre[middle].tolist(), MARKER_RADIUS_M, dxfattribs={"layer": layer})
        unit = "‰" if e.unit == "ratio" else e.unit
        peak = 1e3 * e.peak if e.unit == "ratio" else e.peak
        if e.check not in by_name:
            raise ValueError(f"{results.folder}: exceedance of check {e.check!r}, which tolerance profile "
                             f"{profile.name!r} does not hold: process the survey again before exporting")
        label = f"{channel_name(by_name[e.check], e.rail, e.direction)} {peak:.2f} {unit}"
        space.add_text(label, height=2 * TEXT_HEIGHT_M, dxfattribs={"layer": layer}).set_placement(
            (centre[middle] + [MARKER_RADIUS_M, MARKER_RADIUS_M, 0.0]).tolist())
    if valid.any():
        first = int(np.flatnonzero(valid)[0])
        heights = (t("normal heights") if results.summary.get("heights", {}).get("model", "none").split()[0] != "none"
                   else t("ellipsoidal heights"))
        try:
            fastener = load_fastener_type(project.resource(project.fastener))
        except ValueError:  # edited since processing: the amounts are in the results, the file only names it
            fastener = None
        for line, text in enumerate((
                t("insrail: {project}, survey {survey}; {crs}; {heights}; m").format(
                    project=project.name, survey=results.survey, crs=processed_crs_text(project, results.summary),
                    heights=heights),
                f"{ADJUSTMENT_LAYER} [mm]: {amounts_text(results.summary, profile, fastener)}",
                t("deviations (not drawn): {reference}").format(reference=deviation_reference(results.summary)))):
            space.add_text(text, height=2 * TEXT_HEIGHT_M, dxfattribs={"layer": INFO_LAYER}).set_placement(
                (centre[first] + [2.0, 2.0 - 3 * TEXT_HEIGHT_M * line, 0.0]).tolist())
    return doc


def format_dxf(project, results) -> str:
    """``insrail export --format dxf``: the drawing as DXF text."""
    stream = io.StringIO()
    dxf_document(project, results).write(stream)
    return stream.getvalue()
