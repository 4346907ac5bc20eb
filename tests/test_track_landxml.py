"""LandXML 1.2: write-then-read, a hand-made file, malformed input."""

import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings

from insrail.io.errors import InputError
from insrail.track.alignment import Arc, Clothoid, DesignAlignment, HorizontalAlignment, Line
from insrail.track.landxml import LandXMLError, read_landxml, read_landxml_alignments, write_landxml
from insrail.track.profile import PVI, CantTable, VerticalProfile
from insrail.track.stationing import StationEquation, StationEquations
from track_alignment_strategies import design_alignments

HANDMADE = Path(__file__).resolve().parent / "data" / "landxml" / "handmade_spiral_arc.xml"
NS = {"lx": "http://www.landxml.org/schema/LandXML-1.2"}


def sample_design(name="main") -> DesignAlignment:
    horizontal = HorizontalAlignment(
        512345.6789, 3380512.3456, 0.7, 1000.0,
        (Line(300.0), Clothoid(120.0, math.inf, 2800.0, "right"), Arc(400.0, 2800.0, "right"),
         Clothoid(120.0, 2800.0, math.inf, "right"), Line(300.0), Clothoid(80.0, math.inf, 900.0, "left"),
         Arc(100.0, 900.0, "left"), Clothoid(50.0, 900.0, 1500.0, "left"), Arc(30.0, 1500.0, "left")),
    )
    vertical = VerticalProfile((PVI(1000.0, 100.0), PVI(1500.0, 105.0, "parabolic", curve_radius_m=10000.0),
                                PVI(2000.0, 103.0, "circular", curve_radius_m=15000.0), PVI(2500.0, 104.0)))
    cant = CantTable([1000.0, 1300.0, 1420.0, 1820.0, 1940.0, 2240.0, 2320.0, 2500.0],
                     [0.0, 0.0, 0.15, 0.15, 0.0, 0.0, -0.1234567, -0.1234567])
    equations = StationEquations((StationEquation(1500.0, 1520.0), StationEquation(2000.0, 1990.0)), prefix="DK")
    return DesignAlignment(horizontal, vertical, cant, equations, name)


def assert_same_design(a: DesignAlignment, b: DesignAlignment) -> None:
    assert a.name == b.name
    ha, hb = a.horizontal, b.horizontal
    assert ha.elements == hb.elements
    assert (ha.start_east_m, ha.start_north_m, ha.start_station_m) == (hb.start_east_m, hb.start_north_m,
                                                                       hb.start_station_m)
    assert ha.start_azimuth_rad == pytest.approx(hb.start_azimuth_rad, abs=1e-12)
    assert a.station_equations == b.station_equations
    np.testing.assert_array_equal(a.vertical.stations_m, b.vertical.stations_m)
    np.testing.assert_array_equal(a.vertical.elevations_m, b.vertical.elevations_m)
    assert [p.curve for p in a.vertical.pvis] == [p.curve for p in b.vertical.pvis]
    np.testing.assert_allclose(a.vertical.curve_lengths_m, b.vertical.curve_lengths_m, rtol=1e-14)
    np.testing.assert_allclose(a.vertical.curve_radii_m, b.vertical.curve_radii_m, rtol=1e-14)
    np.testing.assert_array_equal(a.cant.stations_m, b.cant.stations_m)
    np.testing.assert_allclose(a.cant.cant_m, b.cant.cant_m, rtol=0, atol=1e-15)


def test_written_file_reads_back_identical(tmp_path):
    design = sample_design()
    path = tmp_path / "design.xml"
    write_landxml(path, design)
    back = read_landxml(path)
    assert_same_design(back, design)
    stations = np.linspace(1000.0, 2500.0, 3001)
    ea, na = back.horizontal.point_at(stations)
    eb, nb = design.horizontal.point_at(stations)
    assert np.max(np.hypot(ea - eb, na - nb)) < 1e-8  # the start azimuth differs by round-off
    np.testing.assert_allclose(back.vertical.elevation_at(stations), design.vertical.elevation_at(stations),
                               atol=1e-12)


def test_written_file_is_landxml_with_north_east_order(tmp_path):
    design = sample_design()
    path = tmp_path / "design.xml"
    write_landxml(path, design)
    root = ET.parse(path).getroot()
    assert root.tag == "{http://www.landxml.org/schema/LandXML-1.2}LandXML" and root.get("version") == "1.2"
    first_start = root.find("lx:Alignments/lx:Alignment/lx:CoordGeom/lx:Line/lx:Start", NS).text
    assert first_start == "3380512.3456 512345.6789"  # north first
    spiral = root.find("lx:Alignments/lx:Alignment/lx:CoordGeom/lx:Spiral", NS)
    assert (spiral.get("radiusStart"), spiral.get("rot"), spiral.get("spiType")) == ("INF", "cw", "clothoid")
    cant_rows = root.findall("lx:Alignments/lx:Alignment/lx:Cant/lx:CantStation", NS)
    assert (cant_rows[-1].get("appliedCant"), cant_rows[-1].get("curvature")) == ("123.4567", "ccw")


def test_several_alignments_and_selection_by_name(tmp_path):
    path = tmp_path / "two.xml"
    write_landxml(path, [sample_design("up"), sample_design("down")])
    assert [a.name for a in read_landxml_alignments(path)] == ["up", "down"]
    assert read_landxml(path, "down").name == "down"
    with pytest.raises(InputError, match="several alignments"):
        read_landxml(path)
    with pytest.raises(InputError, match="no alignment named 'side'"):
        read_landxml(path, "side")


def test_handmade_file_reads_correctly():
    design = read_landxml(HANDMADE)
    h = design.horizontal
    assert design.name == "DK main"
    assert h.elements == (Line(250.0), Clothoid(100.0, math.inf, 1200.0, "right"), Arc(300.0, 1200.0, "right"),
                          Clothoid(100.0, 1200.0, math.inf, "right"), Line(200.0))
    assert (h.start_east_m, h.start_north_m, h.start_station_m) == (512345.6789, 3380512.3456, 10000.0)
    assert h.start_azimuth_rad == pytest.approx(math.radians(60.0), abs=1e-14)  # from dir="300.0"
    assert [k.label for k in h.key_points()] == ["POB", "TS", "SC", "CS", "ST", "POE"]
    # the file's element ends (computed independently with the clothoid series) are reproduced
    root = ET.parse(HANDMADE).getroot()
    ends = [tuple(map(float, e.text.split())) for e in root.iterfind(".//lx:CoordGeom/*/lx:End", NS)]
    for placed, (north, east) in zip(h.placed_elements, ends):
        assert math.hypot(placed.end_east_m - east, placed.end_north_m - north) < 2e-4
    assert float(h.azimuth_at(10950.0)) == pytest.approx(math.radians(60.0) + 100.0 / 1200.0 + 300.0 / 1200.0,
                                                         abs=1e-6)
    # station equation: a 20 m short chain at 10600
    assert design.station_equations.label(10700.0) == "K10+720.000"
    # profile: parabola L 120 at 10400 (0.008 -> -0.004), circle R 20000 at 10700 (-0.004 -> 0.004)
    v = design.vertical
    assert float(v.elevation_at(10400.0)) == pytest.approx(53.2 - 0.012 * 120.0 / 8, abs=1e-12)
    assert float(v.grade_at(10200.0)) == pytest.approx(0.008)
    a = math.atan(0.004)
    tangent = 20000.0 * math.tan(a)
    assert v.curve_lengths_m[2] == pytest.approx(2 * tangent * math.cos(a))
    # symmetric grades: the lowest point of the circle is at the PVI, R (sec(a) - 1) above it
    assert float(v.elevation_at(10700.0)) == pytest.approx(52.0 + 20000.0 * (1 / math.cos(a) - 1), abs=1e-9)
    assert float(v.vertical_curvature_at(10700.0)) == pytest.approx(1 / 20000.0)
    # cant ramps on the clothoids, positive (right-hand curve)
    np.testing.assert_allclose(design.cant.cant_at([10100.0, 10300.0, 10500.0, 10700.0, 10900.0]),
                               [0.0, 0.075, 0.150, 0.075, 0.0])


def mutated(tmp_path, old: str, new: str, count: int = 1) -> Path:
    text = HANDMADE.read_text(encoding="utf-8")
    assert text.count(old) >= count, old
    path = tmp_path / "broken.xml"
    path.write_text(text.replace(old, new, count), encoding="utf-8")
    return path


def line_of(text: str, fragment: str) -> int:
    return text[: text.index(fragment)].count("\n") + 1


ALIGNMENT_PATH = "Alignments/Alignment[@name='DK main']"


@pytest.mark.parametrize(
    "old, new, element_path, message",
    [
        ('rot="cw" spiType="clothoid">\n          <Start>3380790', 'spiType="clothoid">\n          <Start>3380790',
         "/CoordGeom/Spiral[2]", "missing attribute 'rot'"),
        ('radiusEnd="1200.0"', 'radiusEnd="twelve hundred"', "/CoordGeom/Spiral[1]",
         "attribute 'radiusEnd' is not a number"),
        ("<Start>3380686.1343 512649.4671</Start>\n          <Center>", "<Start>3380686.1343 east</Start>\n"
         "          <Center>", "/CoordGeom/Curve/Start", "'north east' coordinates as numbers"),
        ("<Start>3380790.6819 512929.8276</Start>\n          <PI>", "<Start>3380790.6819 512929.8776</Start>\n"
         "          <PI>", "/CoordGeom/Spiral[2]", "Start is 0.0[45]\\d+ m away .* \\(gap\\)"),
        ("<PI>3380798.3451 512962.2738</PI>", "<PI>3380798.3451 512962.3738</PI>", "/CoordGeom/Spiral[2]",
         "\\(kink\\)"),
        ('<Curve rot="cw" crvType="arc" radius="1200.0" length="300.0">',
         '<Curve rot="cw" crvType="arc" radius="1200.0" length="310.0">', "/CoordGeom/Curve",
         "End is .* m away from the end computed"),
        ('<Curve rot="cw" crvType="arc" radius="1200.0"', '<Curve rot="cw" crvType="arc" radius="1300.0"',
         "/CoordGeom/Curve", "radius 1300.0 does not match"),
        ('radiusEnd="1200.0" rot="cw"', 'radiusEnd="1250.0" rot="cw"', "/CoordGeom/Curve",
         "does not continue the curvature"),
        ('<ParaCurve length="120.0">', '<ParaCurve length="700.0">', "/Profile/ProfAlign/ParaCurve",
         "ends at station 10750.0000 m, beyond PVI 3"),
        ('<CantStation station="10350.0" appliedCant="150" curvature="cw"/>',
         '<CantStation station="10350.0" appliedCant="150" curvature="left"/>', "/Cant/CantStation[3]",
         "'curvature' must be 'cw' or 'ccw'"),
        ('staInternal="10600.0"', 'staInternal="10610.0"', "/StaEquation", "staInternal 10610.0 does not match"),
        ('length="950.0"', 'length="960.0"', "", "length 960.0 differs from the sum"),
        ('<Line length="200.0">', '<IrregularLine length="200.0">', "/CoordGeom/IrregularLine",
         "unsupported geometry element"),
    ],
)
def test_malformed_landxml_names_the_element(tmp_path, old, new, element_path, message):
    path = mutated(tmp_path, old, new)
    if new.startswith("<IrregularLine"):
        path.write_text(path.read_text().replace("</Line>\n      </CoordGeom>", "</IrregularLine>\n      </CoordGeom>"))
    with pytest.raises(LandXMLError) as err:
        read_landxml(path)
    assert err.value.element_path == ALIGNMENT_PATH + element_path
    assert re.search(message, err.value.message), err.value.message
    assert str(err.value).startswith(f"{path}, line {err.value.line}: {ALIGNMENT_PATH}")
    assert isinstance(err.value.line, int)


def test_error_line_points_at_the_element(tmp_path):
    path = mutated(tmp_path, 'radiusEnd="1200.0"', 'radiusEnd="x"')
    with pytest.raises(LandXMLError) as err:
        read_landxml(path)
    assert err.value.line == line_of(path.read_text(), 'radiusEnd="x"')


def test_not_well_formed_and_foreign_files(tmp_path):
    path = mutated(tmp_path, "</Spiral>", "</Spiralx>")
    with pytest.raises(InputError, match="not well-formed XML") as err:
        read_landxml(path)
    assert err.value.line == line_of(path.read_text(), "</Spiralx>")
    path = mutated(tmp_path, '<Metric areaUnit="squareMeter" linearUnit="meter"',
                   '<Metric areaUnit="squareMeter" linearUnit="foot"')
    with pytest.raises(LandXMLError, match="linearUnit must be 'meter'"):
        read_landxml(path)
    (tmp_path / "other.xml").write_text("<gpx><trk/></gpx>")
    with pytest.raises(LandXMLError, match="expected <LandXML>"):
        read_landxml(tmp_path / "other.xml")
    with pytest.raises(InputError, match="cannot read"):
        read_landxml(tmp_path / "absent.xml")


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(design=design_alignments())
def test_random_alignments_round_trip(tmp_path, design):
    path = tmp_path / "random.xml"
    write_landxml(path, design)
    assert_same_design(read_landxml(path), design)


def test_curve_length_and_spiral_pi_are_optional(tmp_path):
    path = mutated(tmp_path, 'radius="1200.0" length="300.0"', 'radius="1200.0"')
    path.write_text(path.read_text().replace("<PI>3380798.3451 512962.2738</PI>", ""))
    design = read_landxml(path)
    arc = design.horizontal.elements[2]
    assert (type(arc), arc.radius_m, arc.turn) == (Arc, 1200.0, "right")
    assert arc.length_m == pytest.approx(300.0, abs=1e-4)  # from the angle at the Center (0.1 mm coordinates)
    assert design.horizontal.elements[3] == Clothoid(100.0, 1200.0, math.inf, "right")


def test_direction_in_another_convention_falls_back_to_coordinates(tmp_path):
    design = read_landxml(mutated(tmp_path, 'dir="300.0"', 'dir="60.0"'))  # clockwise: not LandXML's convention
    difference = abs(design.horizontal.start_azimuth_rad - math.radians(60.0))
    assert 1e-9 < difference < 1e-6  # the coordinates, rounded to 0.1 mm, give the direction
    with pytest.raises(LandXMLError, match="attribute 'dir' is not a number"):
        read_landxml(mutated(tmp_path, 'dir="300.0"', 'dir="NNW"'))


def test_a_file_nested_100000_deep_is_refused_naming_the_line(tmp_path):
    path = tmp_path / "deep.xml"
    path.write_text('<?xml version="1.0"?>\n<LandXML>\n' + "<a>\n" * 100_000 + "</a>\n" * 100_000 + "</LandXML>\n")
    with pytest.raises(InputError, match=r"deep\.xml, line 202: elements nested more than 200 deep"):
        read_landxml(path)
