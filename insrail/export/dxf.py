"""The CAD drawing of a processed survey (DXF R2013, written with ezdxf), in the engineering CRS.

Layers (``docs/formats.md``, "DXF drawing"):

* ``INSRAIL_RAIL_LEFT``, ``INSRAIL_RAIL_RIGHT``, ``INSRAIL_CENTRELINE``: 3D polylines through the
  sleepers' rail (top of rail, gauge face) and centreline points, E, N, normal H; broken where sleepers
  are not valid (one polyline per run of valid sleepers)
* ``INSRAIL_SLEEPERS``: a line from the left to the right rail point at every valid sleeper
* ``INSRAIL_SLEEPER_NUMBERS``: the sleeper number as text beside the right rail, along the track
* ``INSRAIL_EXCEEDANCE_<CHECK>``: per exceedance of a tolerance check, a circle (radius 1 m) at the
  centreline of the run's middle sleeper and a text "check peak unit"
* ``INSRAIL_INFO``: one text at the first sleeper naming project, survey, CRS and heights

Drawing units are metres ($INSUNITS 6). Nothing is projected or shifted: the coordinates are those
of sleepers.csv.
"""

from __future__ import annotations

import io
import re

import numpy as np

from insrail.project.run_settings import processed_crs_text

RAIL_LAYERS = {"left": "INSRAIL_RAIL_LEFT", "right": "INSRAIL_RAIL_RIGHT"}
CENTRELINE_LAYER = "INSRAIL_CENTRELINE"
SLEEPER_LAYER = "INSRAIL_SLEEPERS"
NUMBER_LAYER = "INSRAIL_SLEEPER_NUMBERS"
INFO_LAYER = "INSRAIL_INFO"
EXCEEDANCE_PREFIX = "INSRAIL_EXCEEDANCE_"
TEXT_HEIGHT_M = 0.15
MARKER_RADIUS_M = 1.0
# AutoCAD colour indices
_COLOURS = {RAIL_LAYERS["left"]: 5, RAIL_LAYERS["right"]: 3, CENTRELINE_LAYER: 2, SLEEPER_LAYER: 8,
            NUMBER_LAYER: 7, INFO_LAYER: 7}


def exceedance_layer(check: str) -> str:
    """The layer of one tolerance check's exceedances (DXF layer names: letters, digits, _ and -)."""
    return EXCEEDANCE_PREFIX + re.sub(r"[^A-Za-z0-9_-]", "_", check).upper()


def _runs(valid: np.ndarray) -> list[tuple[int, int]]:
    """(first, stop) of each run of consecutive True."""
    edges = np.flatnonzero(np.diff(np.concatenate([[0], valid.astype(np.int8), [0]])))
    return [(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2])]


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
    for layer in (*RAIL_LAYERS.values(), CENTRELINE_LAYER, SLEEPER_LAYER, NUMBER_LAYER, INFO_LAYER,
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
        label = f"{e.check} {'/'.join(p for p in (e.rail, e.direction) if p and p != 'track')} {peak:.2f} {unit}"
        space.add_text(" ".join(label.split()), height=2 * TEXT_HEIGHT_M, dxfattribs={"layer": layer}).set_placement(
            (centre[middle] + [MARKER_RADIUS_M, MARKER_RADIUS_M, 0.0]).tolist())
    if valid.any():
        first = int(np.flatnonzero(valid)[0])
        heights = "normal heights" if results.summary.get("heights", {}).get("model", "none").split()[0] != "none" \
            else "ellipsoidal heights"
        space.add_text(f"insrail: {project.name}, survey {results.survey}; {processed_crs_text(project, results.summary)}; {heights}; m",
                       height=2 * TEXT_HEIGHT_M, dxfattribs={"layer": INFO_LAYER}).set_placement(
            (centre[first] + [2.0, 2.0, 0.0]).tolist())
    return doc


def format_dxf(project, results) -> str:
    """``insrail export --format dxf``: the drawing as DXF text."""
    stream = io.StringIO()
    dxf_document(project, results).write(stream)
    return stream.getvalue()
