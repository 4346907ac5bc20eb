"""LandXML 1.2 design alignments: read and write.

What is read, per ``Alignments/Alignment`` (name, length, staStart):

* ``CoordGeom``: ``Line`` (Start, End), ``Spiral`` (length, radiusStart, radiusEnd
  - "INF" for a tangent end -, rot cw|ccw, spiType="clothoid"; Start, PI, End) and
  ``Curve`` (rot, radius, crvType="arc"; Start, Center, End). Point text is
  "north east [elevation]", as the schema says. The chain is rebuilt from the first
  element's start point and direction and the element lengths and radii; every
  element's Start, End and start direction must then agree with the chain within
  the tolerances (``position_tolerance_m``, ``azimuth_tolerance_rad``), else the
  error names the element (gap or kink). Directions come from the coordinates
  (Start->End of a line, Start->PI of a spiral, the radius at Start of a curve);
  The start direction of the whole chain may come from the first element's
  ``dir`` / ``dirStart`` (LandXML: counter-clockwise from north, in
  Units/@directionUnit) when it agrees with the coordinates within the tolerance -
  it is more precise than coordinates of a short element; programs that use
  another convention fail that check and the coordinates are used.
* ``StaEquation`` (staBack, staAhead; staInternal, when present, is checked).
* ``Profile/ProfAlign``: ``PVI``, ``ParaCurve`` (length) and ``CircCurve`` (radius;
  its length attribute is informative only), text "station elevation".
* ``Cant`` / ``CantStation`` (station, appliedCant in millimetres, curvature cw|ccw):
  the signed design cant is +appliedCant for cw (right-hand) curves, -appliedCant for
  ccw ones (see :mod:`insrail.track` for the sign convention).

All stations in the file are LandXML internal stations, i.e. the continuous measure
starting at staStart. Only metric files (linearUnit="meter") are accepted.

Errors are :class:`LandXMLError` (an InputError) naming the file, the line and the
element path, e.g. ``Alignments/Alignment[@name='main']/CoordGeom/Spiral[2]``.
Writing then reading a file gives back the same alignment: all numbers are written
with full precision (repr); the start azimuth passes through the counter-clockwise
``dir`` and cant through millimetres, so those agree to round-off (~1e-15).
"""

from __future__ import annotations

import datetime as _dt
import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path
from xml.parsers import expat

import numpy as np

import insrail
from insrail.io.errors import InputError, reason_of
from insrail.notices import Phrase
from insrail.io.atomic import atomic_write
from insrail.track.alignment import Arc, Clothoid, DesignAlignment, HorizontalAlignment, Line
from insrail.track.errors import DesignError
from insrail.track.profile import PVI, CantTable, VerticalProfile
from insrail.track.stationing import StationEquation, StationEquations

NAMESPACE = "http://www.landxml.org/schema/LandXML-1.2"
DEFAULT_POSITION_TOLERANCE_M = 0.001
DEFAULT_AZIMUTH_TOLERANCE_RAD = 5e-5
_STANDARD_GAUGE_M = 1.435  # Cant@gauge; insrail's cant is referred to the 1.5 m rail-centre base


class LandXMLError(InputError):
    """Bad LandXML: the file, the line, the element path and what was expected."""

    def __init__(self, path: str | Path, line: int | None, element_path: str, message: str | Phrase,
                 fields: dict | None = None):
        self.element_path = element_path
        phrase = message if isinstance(message, Phrase) else Phrase(message, fields or {})
        super().__init__(path, line, Phrase("{element_path}: {message}", {"element_path": element_path, "message": phrase})
                         if element_path else phrase)


# --------------------------------------------------------------------------- parsing
def _local(tag: str) -> str:
    return tag.rsplit("}", 1)[-1]


#: Deepest element nesting accepted (LandXML 1.2 alignments nest about 8 deep).
MAX_DEPTH = 200


class _Document:
    """A parsed file that knows every element's line and path."""

    def __init__(self, path: Path):
        self.path = path
        self.lines: dict[int, int] = {}
        self.paths: dict[int, str] = {}
        builder = ET.TreeBuilder()
        parser = expat.ParserCreate(namespace_separator="}")
        depth = [0]

        def start(tag, attributes):
            depth[0] += 1
            if depth[0] > MAX_DEPTH:  # a LandXML alignment is about 8 deep; the tree walks below recurse
                raise InputError(path, parser.CurrentLineNumber, "elements nested more than {max_depth} deep: "
                                 "not a LandXML alignment file", fields={"max_depth": MAX_DEPTH})
            element = builder.start(_local(tag), {_local(k): v for k, v in attributes.items()})
            self.lines[id(element)] = parser.CurrentLineNumber  # ids stay unique: the tree holds every element

        def end(tag):
            depth[0] -= 1
            builder.end(_local(tag))

        parser.StartElementHandler = start
        parser.EndElementHandler = end
        parser.CharacterDataHandler = builder.data
        try:
            with open(path, "rb") as stream:
                parser.ParseFile(stream)
        except OSError as err:
            raise InputError(path, None, "cannot read the LandXML file: {err}", fields={"err": err}) from None
        except expat.ExpatError as err:
            raise InputError(path, err.lineno, "not well-formed XML: {reason}", fields={"reason": expat.ErrorString(err.code)}) from None
        self.root = builder.close()
        self._name_paths(self.root, "")

    def _name_paths(self, element: ET.Element, parent_path: str) -> None:
        totals: dict[str, int] = {}
        for child in element:
            totals[child.tag] = totals.get(child.tag, 0) + 1
        counts: dict[str, int] = {}
        for child in element:
            counts[child.tag] = counts.get(child.tag, 0) + 1
            name = child.get("name")
            if child.tag == "Alignment" and name is not None:
                step = f"Alignment[@name='{name}']"
            elif totals[child.tag] > 1:
                step = f"{child.tag}[{counts[child.tag]}]"
            else:
                step = child.tag
            path = f"{parent_path}/{step}" if parent_path else step
            self.paths[id(child)] = path
            self._name_paths(child, path)

    def error(self, element: ET.Element, message: str | Phrase, fields: dict | None = None) -> LandXMLError:
        return LandXMLError(self.path, self.lines.get(id(element)), self.paths.get(id(element), element.tag), message,
                            fields)

    def attribute(self, element: ET.Element, name: str) -> str:
        value = element.get(name)
        if value is None:
            raise self.error(element, "missing attribute {name!r}", fields={"name": name})
        return value.strip()

    def number(self, element: ET.Element, name: str, *, allow_inf: bool = False, required: bool = True) -> float | None:
        if element.get(name) is None and not required:
            return None
        text = self.attribute(element, name)
        if allow_inf and text.upper() == "INF":
            return math.inf
        try:
            value = float(text)
        except ValueError:
            raise self.error(element, "attribute {name!r} is not a number: {text!r}", fields={"name": name, "text": text}) from None
        if not math.isfinite(value):
            raise self.error(element, "attribute {name!r} must be finite, got {text!r}", fields={"name": name, "text": text})
        return value

    def numbers(self, element: ET.Element, count: int, meaning: str) -> list[float]:
        fields = (element.text or "").split()
        if len(fields) < count:
            raise self.error(element, "expected {meaning}, found {text!r}", fields={"meaning": meaning, "text": element.text})
        try:
            values = [float(f) for f in fields[:count]]
        except ValueError:
            raise self.error(element, "expected {meaning} as numbers, found {text!r}", fields={"meaning": meaning, "text": element.text}) from None
        if not all(math.isfinite(v) for v in values):
            raise self.error(element, "expected finite {meaning}, found {text!r}", fields={"meaning": meaning, "text": element.text})
        return values

    def point(self, element: ET.Element, child: str, required: bool = True) -> np.ndarray | None:
        """(east, north) of a child point; the text is "north east [elevation]"."""
        found = [c for c in element if c.tag == child]
        if not found:
            if required:
                raise self.error(element, "missing child element <{child}>", fields={"child": child})
            return None
        north, east = self.numbers(found[0], 2, "'north east' coordinates")
        return np.array([east, north])

    def rotation(self, element: ET.Element) -> str:
        rot = self.attribute(element, "rot")
        if rot not in ("cw", "ccw"):
            raise self.error(element, "attribute 'rot' must be 'cw' or 'ccw', got {rot!r}", fields={"rot": rot})
        return "right" if rot == "cw" else "left"


def _azimuth(vector: np.ndarray) -> float:
    return math.atan2(vector[0], vector[1]) % (2 * math.pi)


def _angle_difference(a: float, b: float) -> float:
    return abs((a - b + math.pi) % (2 * math.pi) - math.pi)


@dataclass
class _ParsedElement:
    node: ET.Element
    element: object
    start: np.ndarray
    end: np.ndarray
    start_azimuth: float | None  # None when the file gives no independent direction


def _parse_element(doc: _Document, node: ET.Element, tolerance_m: float) -> _ParsedElement:
    start, end = doc.point(node, "Start"), doc.point(node, "End")
    try:
        if node.tag == "Line":
            chord = end - start
            length = float(np.hypot(*chord))
            given = doc.number(node, "length", required=False)
            if given is not None and abs(given - length) > tolerance_m:
                raise doc.error(node, "length {given} does not match the distance Start-End {length:.4f} m", fields={"given": given, "length": length})
            return _ParsedElement(node, Line(given if given is not None else length), start, end, _azimuth(chord))
        if node.tag == "Curve":
            turn = doc.rotation(node)
            crv_type = node.get("crvType", "arc")
            if crv_type != "arc":
                raise doc.error(node, "only crvType='arc' is supported, got {crv_type!r}", fields={"crv_type": crv_type})
            center = doc.point(node, "Center")
            radius = doc.number(node, "radius", required=False)
            radial = start - center
            distance = float(np.hypot(*radial))
            if radius is None:
                radius = distance
            elif abs(radius - distance) > tolerance_m:
                raise doc.error(node, "radius {radius} does not match the distance Center-Start {distance:.4f} m", fields={"radius": radius, "distance": distance})
            length = doc.number(node, "length", required=False)
            if length is None:
                swept = (_azimuth(end - center) - _azimuth(radial)) * (1 if turn == "right" else -1)
                length = radius * (swept % (2 * math.pi))
            # the tangent is the radius turned by 90 degrees towards the direction of travel
            tangent_azimuth = _azimuth(radial) + (math.pi / 2 if turn == "right" else -math.pi / 2)
            return _ParsedElement(node, Arc(length, radius, turn), start, end, tangent_azimuth % (2 * math.pi))
        if node.tag == "Spiral":
            spi_type = doc.attribute(node, "spiType")
            if spi_type != "clothoid":
                raise doc.error(node, "only spiType='clothoid' is supported, got {spi_type!r}", fields={"spi_type": spi_type})
            element = Clothoid(
                doc.number(node, "length"),
                doc.number(node, "radiusStart", allow_inf=True),
                doc.number(node, "radiusEnd", allow_inf=True),
                doc.rotation(node),
            )
            pi = doc.point(node, "PI", required=False)
            return _ParsedElement(node, element, start, end, None if pi is None else _azimuth(pi - start))
    except ValueError as err:
        if isinstance(err, LandXMLError):
            raise
        raise doc.error(node, reason_of(err)) from None
    raise doc.error(node, "unsupported geometry element <{tag}>; expected Line, Spiral or Curve", fields={"tag": node.tag})


_DIRECTION_UNITS = {"radians": 1.0, "decimal degrees": math.pi / 180.0, "grads": math.pi / 200.0}


def _direction_unit(doc: _Document) -> float | None:
    """Radians per unit of LandXML directions (None for units insrail does not read)."""
    for units in (c for c in doc.root if c.tag == "Units"):
        for system in units:
            if system.tag == "Metric":
                return _DIRECTION_UNITS.get(system.get("directionUnit", "radians"))
    return 1.0


def _start_azimuth(doc: _Document, first: _ParsedElement, tolerance_rad: float) -> float:
    """The first element's start azimuth: its direction attribute if it agrees with the coordinates."""
    attribute = "dir" if first.node.tag == "Line" else "dirStart"
    unit = _direction_unit(doc)
    value = doc.number(first.node, attribute, required=False)
    if value is None or unit is None:
        return first.start_azimuth
    clockwise = (-value * unit) % (2 * math.pi)
    return clockwise if _angle_difference(clockwise, first.start_azimuth) <= tolerance_rad else first.start_azimuth


def _horizontal(doc: _Document, alignment_node: ET.Element, position_tolerance_m: float,
                azimuth_tolerance_rad: float) -> HorizontalAlignment:
    geometry = [c for c in alignment_node if c.tag == "CoordGeom"]
    if len(geometry) != 1:
        raise doc.error(alignment_node, "expected one <CoordGeom>, found {count}", fields={"count": len(geometry)})
    parsed = [_parse_element(doc, node, position_tolerance_m) for node in geometry[0]]
    if not parsed:
        raise doc.error(geometry[0], "no Line, Spiral or Curve elements")
    first = parsed[0]
    if first.start_azimuth is None:
        raise doc.error(first.node, "the first element must give its start direction (a Spiral needs <PI>)")
    try:
        horizontal = HorizontalAlignment(
            start_east_m=float(first.start[0]),
            start_north_m=float(first.start[1]),
            start_azimuth_rad=_start_azimuth(doc, first, azimuth_tolerance_rad),
            start_station_m=doc.number(alignment_node, "staStart"),
            elements=tuple(p.element for p in parsed),
        )
    except DesignError as err:
        node = parsed[err.index].node if err.index is not None else geometry[0]
        raise doc.error(node, err.phrase) from None
    for item, placed in zip(parsed, horizontal.placed_elements):
        gap = float(np.hypot(item.start[0] - placed.start_east_m, item.start[1] - placed.start_north_m))
        if gap > position_tolerance_m:
            raise doc.error(item.node, "Start is {gap:.4f} m away from the end of the previous element (gap)", fields={"gap": gap})
        if item.start_azimuth is not None:
            kink = _angle_difference(item.start_azimuth, placed.start_azimuth_rad)
            if kink > azimuth_tolerance_rad:
                raise doc.error(item.node, "start direction differs from the previous element's end direction by "
                                "{kink:.3e} rad (kink)", fields={"kink": kink})
        miss = float(np.hypot(item.end[0] - placed.end_east_m, item.end[1] - placed.end_north_m))
        if miss > position_tolerance_m:
            raise doc.error(item.node, "End is {miss:.4f} m away from the end computed from the element's "
                            "length and radii", fields={"miss": miss})
    declared = doc.number(alignment_node, "length")
    if abs(declared - horizontal.length_m) > position_tolerance_m:
        raise doc.error(alignment_node, "length {declared} differs from the sum of the element lengths "
                        "{length_m:.4f} m", fields={"declared": declared, "length_m": horizontal.length_m})
    return horizontal


def _station_prefix(alignment_node: ET.Element) -> str:
    """The label prefix insrail keeps in a Feature/Property (LandXML has no field for it)."""
    for feature in (c for c in alignment_node if c.tag == "Feature" and c.get("code") == "insrail"):
        for prop in feature:
            if prop.tag == "Property" and prop.get("label") == "stationPrefix":
                return prop.get("value", "K")
    return "K"


def _station_equations(doc: _Document, alignment_node: ET.Element, start_station: float) -> StationEquations:
    nodes = [c for c in alignment_node if c.tag == "StaEquation"]
    equations = []
    for node in nodes:
        equations.append(StationEquation(doc.number(node, "staBack"), doc.number(node, "staAhead")))
    try:
        result = StationEquations(tuple(equations), prefix=_station_prefix(alignment_node))
    except DesignError as err:
        raise doc.error(nodes[err.index] if err.index is not None else alignment_node, err.phrase) from None
    for node, internal in zip(nodes, result.internal_stations_m):
        given = doc.number(node, "staInternal", required=False)
        if given is not None and abs(given - internal) > DEFAULT_POSITION_TOLERANCE_M:
            raise doc.error(node, "staInternal {given} does not match {internal:.4f} m implied by staStart "
                            "{start_station} and the equations before it", fields={"given": given, "internal": internal, "start_station": start_station})
    return result


def _profile(doc: _Document, alignment_node: ET.Element, profile_name: str | None) -> VerticalProfile | None:
    candidates = [a for p in alignment_node if p.tag == "Profile" for a in p if a.tag == "ProfAlign"]
    if profile_name is not None:
        candidates = [a for a in candidates if a.get("name") == profile_name]
        if not candidates:
            raise doc.error(alignment_node, "no <ProfAlign name={profile_name!r}>", fields={"profile_name": profile_name})
    if not candidates:
        return None
    if len(candidates) > 1:
        names = ", ".join(repr(a.get("name")) for a in candidates)
        raise doc.error(alignment_node, "several <ProfAlign> ({names}); choose one by name", fields={"names": names})
    profile = candidates[0]
    pvis, nodes = [], []
    for node in profile:
        if node.tag not in ("PVI", "ParaCurve", "CircCurve"):
            raise doc.error(node, "unsupported profile element <{tag}>; expected PVI, ParaCurve or CircCurve", fields={"tag": node.tag})
        station, elevation = doc.numbers(node, 2, "'station elevation'")
        try:
            if node.tag == "PVI":
                pvis.append(PVI(station, elevation))
            elif node.tag == "ParaCurve":
                pvis.append(PVI(station, elevation, "parabolic", curve_length_m=doc.number(node, "length")))
            else:
                pvis.append(PVI(station, elevation, "circular", curve_radius_m=doc.number(node, "radius")))
        except ValueError as err:
            if isinstance(err, LandXMLError):
                raise
            raise doc.error(node, reason_of(err)) from None
        nodes.append(node)
    try:
        return VerticalProfile(tuple(pvis))
    except DesignError as err:
        raise doc.error(nodes[err.index] if err.index is not None else profile, err.phrase) from None


def _cant(doc: _Document, alignment_node: ET.Element) -> CantTable | None:
    cants = [c for c in alignment_node if c.tag == "Cant"]
    if not cants:
        return None
    if len(cants) > 1:
        raise doc.error(alignment_node, "expected at most one <Cant>, found {count}", fields={"count": len(cants)})
    nodes = [c for c in cants[0] if c.tag == "CantStation"]
    stations, values = [], []
    for node in nodes:
        stations.append(doc.number(node, "station"))
        applied = doc.number(node, "appliedCant")
        curvature = doc.attribute(node, "curvature")
        if curvature not in ("cw", "ccw"):
            raise doc.error(node, "attribute 'curvature' must be 'cw' or 'ccw', got {curvature!r}", fields={"curvature": curvature})
        values.append((applied if curvature == "cw" else -applied) / 1000.0)
    try:
        return CantTable(stations, values)
    except DesignError as err:
        raise doc.error(nodes[err.index] if err.index is not None else cants[0], err.phrase) from None


def _check_units(doc: _Document) -> None:
    for units in (c for c in doc.root if c.tag == "Units"):
        for system in units:
            if system.tag == "Imperial":
                raise doc.error(system, "imperial units are not supported; export in metres")
            if system.tag == "Metric" and system.get("linearUnit", "meter") != "meter":
                raise doc.error(system, "linearUnit must be 'meter', got {unit!r}", fields={"unit": system.get('linearUnit')})


def read_landxml_alignments(
    path: str | Path,
    *,
    position_tolerance_m: float = DEFAULT_POSITION_TOLERANCE_M,
    azimuth_tolerance_rad: float = DEFAULT_AZIMUTH_TOLERANCE_RAD,
    profile_name: str | None = None,
) -> tuple[DesignAlignment, ...]:
    """Every ``Alignments/Alignment`` of a LandXML 1.2 file, in file order."""
    doc = _Document(Path(path))
    if doc.root.tag != "LandXML":
        raise doc.error(doc.root, "the root element is <{tag}>, expected <LandXML>", fields={"tag": doc.root.tag})
    _check_units(doc)
    nodes = [a for group in doc.root if group.tag == "Alignments" for a in group if a.tag == "Alignment"]
    if not nodes:
        raise LandXMLError(doc.path, None, "LandXML", "no Alignments/Alignment element")
    result = []
    for node in nodes:
        name = doc.attribute(node, "name")
        horizontal = _horizontal(doc, node, position_tolerance_m, azimuth_tolerance_rad)
        equations = _station_equations(doc, node, horizontal.start_station_m)
        try:
            result.append(
                DesignAlignment(horizontal, _profile(doc, node, profile_name), _cant(doc, node), equations, name)
            )
        except DesignError as err:
            equation_nodes = [c for c in node if c.tag == "StaEquation"]
            raise doc.error(equation_nodes[err.index] if err.index is not None else node, err.phrase) from None
    return tuple(result)


def read_landxml(path: str | Path, name: str | None = None, **options) -> DesignAlignment:
    """The alignment called ``name`` (or the only one) of a LandXML 1.2 file."""
    alignments = read_landxml_alignments(path, **options)
    if name is None:
        if len(alignments) > 1:
            names = ", ".join(repr(a.name) for a in alignments)
            raise InputError(path, None, "the file holds several alignments ({names}); choose one by name", fields={"names": names})
        return alignments[0]
    for alignment in alignments:
        if alignment.name == name:
            return alignment
    raise InputError(path, None, "no alignment named {name!r} (found {names})", fields={"name": name, "names": [a.name for a in alignments]})


# --------------------------------------------------------------------------- writing
def _fmt(value: float) -> str:
    return "INF" if math.isinf(value) else repr(float(value))


def _direction(azimuth_rad: float) -> str:
    """A LandXML direction: radians counter-clockwise from north (the Units we write)."""
    return _fmt((-azimuth_rad) % (2 * math.pi))


def _point_text(east: float, north: float) -> str:
    return f"{_fmt(north)} {_fmt(east)}"


def _spiral_pi(placed) -> tuple[float, float]:
    """Intersection of the start and end tangents of a spiral."""
    start = np.array([placed.start_east_m, placed.start_north_m])
    end = np.array([placed.end_east_m, placed.end_north_m])
    t0 = np.array([math.sin(placed.start_azimuth_rad), math.cos(placed.start_azimuth_rad)])
    t1 = np.array([math.sin(placed.end_azimuth_rad), math.cos(placed.end_azimuth_rad)])
    # start + a t0 = end - b t1
    a, _ = np.linalg.solve(np.column_stack((t0, t1)), end - start)
    east, north = start + a * t0
    return float(east), float(north)


def _coord_geom(parent: ET.Element, horizontal: HorizontalAlignment) -> None:
    geometry = ET.SubElement(parent, "CoordGeom")
    for placed in horizontal.placed_elements:
        element = placed.element
        length = _fmt(element.length_m)
        if isinstance(element, Line):
            node = ET.SubElement(geometry, "Line", dir=_direction(placed.start_azimuth_rad), length=length)
        elif isinstance(element, Arc):
            rot = "cw" if element.turn == "right" else "ccw"
            node = ET.SubElement(geometry, "Curve", rot=rot, crvType="arc", radius=_fmt(element.radius_m),
                                 length=length)
        else:
            rot = "cw" if element.turn == "right" else "ccw"
            node = ET.SubElement(geometry, "Spiral", length=length, radiusStart=_fmt(element.radius_start_m),
                                 radiusEnd=_fmt(element.radius_end_m), rot=rot, spiType="clothoid")
        if not isinstance(element, Line):
            node.set("dirStart", _direction(placed.start_azimuth_rad))
            node.set("dirEnd", _direction(placed.end_azimuth_rad))
        ET.SubElement(node, "Start").text = _point_text(placed.start_east_m, placed.start_north_m)
        if isinstance(element, Arc):
            sign = 1.0 if element.turn == "right" else -1.0
            # the centre lies on the inside: to the right of the tangent for a right-hand curve
            east = placed.start_east_m + sign * element.radius_m * math.cos(placed.start_azimuth_rad)
            north = placed.start_north_m - sign * element.radius_m * math.sin(placed.start_azimuth_rad)
            ET.SubElement(node, "Center").text = _point_text(east, north)
        elif isinstance(element, Clothoid):
            ET.SubElement(node, "PI").text = _point_text(*_spiral_pi(placed))
        ET.SubElement(node, "End").text = _point_text(placed.end_east_m, placed.end_north_m)


def _profile_element(parent: ET.Element, vertical: VerticalProfile) -> None:
    profile = ET.SubElement(ET.SubElement(parent, "Profile"), "ProfAlign", name="design")
    lengths, radii = vertical.curve_lengths_m, vertical.curve_radii_m
    for index, pvi in enumerate(vertical.pvis):
        text = f"{_fmt(pvi.station_m)} {_fmt(pvi.elevation_m)}"
        if pvi.curve == "parabolic":
            node = ET.SubElement(profile, "ParaCurve", length=_fmt(lengths[index]))
        elif pvi.curve == "circular":
            node = ET.SubElement(profile, "CircCurve", length=_fmt(lengths[index]), radius=_fmt(radii[index]))
        else:
            node = ET.SubElement(profile, "PVI")
        node.text = text


def _cant_element(parent: ET.Element, cant: CantTable) -> None:
    node = ET.SubElement(parent, "Cant", name="design", gauge=_fmt(_STANDARD_GAUGE_M))
    for station, value in zip(cant.stations_m, cant.cant_m):
        ET.SubElement(node, "CantStation", station=_fmt(station), appliedCant=_fmt(abs(value) * 1000.0),
                      curvature="ccw" if value < 0 else "cw")


def format_landxml(alignments: DesignAlignment | tuple[DesignAlignment, ...] | list[DesignAlignment]) -> str:
    """LandXML 1.2 text for one or several design alignments."""
    if isinstance(alignments, DesignAlignment):
        alignments = (alignments,)
    now = _dt.datetime.now()
    root = ET.Element("LandXML", xmlns=NAMESPACE, version="1.2", date=now.strftime("%Y-%m-%d"),
                      time=now.strftime("%H:%M:%S"))
    ET.SubElement(root, "Units").append(
        ET.Element("Metric", areaUnit="squareMeter", linearUnit="meter", volumeUnit="cubicMeter",
                   temperatureUnit="celsius", pressureUnit="HPA", angularUnit="radians", directionUnit="radians")
    )
    ET.SubElement(root, "Application", name="insrail", version=insrail.__version__)
    group = ET.SubElement(root, "Alignments")
    for alignment in alignments:
        h = alignment.horizontal
        node = ET.SubElement(group, "Alignment", name=alignment.name, length=_fmt(h.length_m),
                             staStart=_fmt(h.start_station_m))
        _coord_geom(node, h)
        for equation, internal in zip(alignment.station_equations.equations,
                                      alignment.station_equations.internal_stations_m):
            ET.SubElement(node, "StaEquation", staBack=_fmt(equation.back_m), staAhead=_fmt(equation.ahead_m),
                          staInternal=_fmt(internal))
        feature = ET.SubElement(node, "Feature", code="insrail")
        ET.SubElement(feature, "Property", label="stationPrefix", value=alignment.station_equations.prefix)
        if alignment.vertical is not None:
            _profile_element(node, alignment.vertical)
        if alignment.cant is not None:
            _cant_element(node, alignment.cant)
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def write_landxml(path: str | Path, alignments) -> None:
    """Write one or several design alignments to a LandXML 1.2 file (atomically)."""
    text = format_landxml(alignments)
    with atomic_write(path) as stream:
        stream.write(text)
