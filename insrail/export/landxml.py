"""The measured centreline and rails as LandXML 1.2: one ``PlanFeature`` per line with a 3D
``IrregularLine`` (``PntList3D``: "northing easting elevation" per point, as the schema orders them),
in the engineering CRS, metres, normal heights; broken into one feature per run of valid sleepers.

The design-alignment reader and writer are :mod:`insrail.track.landxml` (without a design the fitted
alignment of the measured centreline is already in the results as ``fitted_alignment.xml``).
"""

from __future__ import annotations

import datetime as _dt
import xml.etree.ElementTree as ET

import numpy as np

from insrail import __version__
from insrail.export.dxf import _points, _runs
from insrail.project.run_settings import processed_crs_text

NAMESPACE = "http://www.landxml.org/schema/LandXML-1.2"


def format_landxml_lines(project, results) -> str:
    """``insrail export --format landxml``."""
    c = results.columns
    valid = c["valid"] > 0
    now = _dt.datetime.now(_dt.UTC)
    root = ET.Element("LandXML", {"xmlns": NAMESPACE, "version": "1.2", "date": now.strftime("%Y-%m-%d"),
                                  "time": now.strftime("%H:%M:%S")})
    ET.SubElement(root, "Units").append(ET.Element("Metric", {
        "linearUnit": "meter", "areaUnit": "squareMeter", "volumeUnit": "cubicMeter", "angularUnit": "decimal degrees",
        "directionUnit": "decimal degrees"}))
    ET.SubElement(root, "Project", {"name": project.name, "desc": processed_crs_text(project, results.summary)})
    ET.SubElement(root, "Application", {"name": "insrail", "version": __version__, "manufacturer": "insrail"})
    features = ET.SubElement(root, "PlanFeatures", {"name": f"{results.survey} measured"})
    lines = {"centreline": _points(c, "centre") if "centre_E_m" in c else 0.5 * (_points(c, "left") + _points(c, "right")),
             "left rail": _points(c, "left"), "right rail": _points(c, "right")}
    for name, points in lines.items():
        ok = valid & np.isfinite(points).all(axis=1)
        for part, (first, stop) in enumerate(_runs(ok), start=1):
            if stop - first < 2:
                continue
            station = c["station_m"]
            feature = ET.SubElement(features, "PlanFeature", {
                "name": f"{results.survey} {name} {part}",
                "desc": f"measured {name}, stations {station[first]:.3f} to {station[stop - 1]:.3f} m"})
            geometry = ET.SubElement(ET.SubElement(feature, "CoordGeom"), "IrregularLine")
            ET.SubElement(geometry, "Start").text = f"{points[first, 1]:.4f} {points[first, 0]:.4f}"
            ET.SubElement(geometry, "End").text = f"{points[stop - 1, 1]:.4f} {points[stop - 1, 0]:.4f}"
            ET.SubElement(geometry, "PntList3D").text = " ".join(
                f"{n:.4f} {e:.4f} {h:.4f}" for e, n, h in points[first:stop])
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"
