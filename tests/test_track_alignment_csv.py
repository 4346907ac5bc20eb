"""The CSV element table: documented example, round trip, errors with line numbers."""

import math
import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings

from insrail.io.errors import InputError
from insrail.track.alignment import Arc, Clothoid, DesignAlignment, HorizontalAlignment, Line
from insrail.track.alignment_csv import format_alignment_csv, read_alignment_csv, write_alignment_csv
from insrail.track.profile import PVI, CantTable, VerticalProfile
from insrail.track.stationing import StationEquation, StationEquations
from track_alignment_strategies import design_alignments

DOCS = Path(__file__).resolve().parents[1] / "docs" / "alignment.md"


def documented_example() -> str:
    blocks = re.findall(r"```text\n(.*?)```", DOCS.read_text(encoding="utf-8"), flags=re.S)
    return blocks[0]


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "design.csv"
    path.write_text(text, encoding="utf-8")
    return path


def test_documented_example_reads(tmp_path):
    design = read_alignment_csv(write(tmp_path, documented_example()))
    h = design.horizontal
    assert design.name == "up line"
    assert h.elements == (Line(300.0), Clothoid(120.0, math.inf, 2800.0, "right"), Arc(400.0, 2800.0, "right"),
                          Clothoid(120.0, 2800.0, math.inf, "right"), Line(300.0))
    assert (h.start_east_m, h.start_north_m, h.start_station_m) == (512345.678, 3380512.345, 10000.0)
    assert h.start_azimuth_rad == math.radians(60.0)
    assert design.vertical.pvis[1] == PVI(10600.0, 54.8, "parabolic", curve_radius_m=15000.0)  # from DK10+600.000
    assert float(design.cant.cant_at(10360.0)) == pytest.approx(0.075)
    assert design.station_equations == StationEquations((StationEquation(11000.0, 11010.0),), prefix="DK")
    assert design.station_equations.label(11100.0) == "DK11+110.000"


def sample_design() -> DesignAlignment:
    horizontal = HorizontalAlignment(
        500123.456, 3000456.789, math.radians(123.4567), 2000.0,
        (Line(150.25), Clothoid(90.0, math.inf, 650.0, "left"), Arc(210.5, 650.0, "left"),
         Clothoid(60.0, 650.0, 1100.0, "left"), Arc(80.0, 1100.0, "left"), Clothoid(70.0, 1100.0, math.inf, "left"),
         Line(40.0), Arc(30.0, 4000.0, "right")),
    )
    vertical = VerticalProfile((PVI(2000.0, 12.5), PVI(2300.0, 15.5, "circular", curve_radius_m=12000.0),
                                PVI(2500.0, 14.0, "parabolic", curve_length_m=80.0), PVI(2730.75, 16.0)))
    cant = CantTable([2000.0, 2150.25, 2240.25, 2450.75, 2730.75], [0.0, 0.0, -0.095, -0.095, 0.004])
    equations = StationEquations((StationEquation(2400.0, 2412.345),), prefix="DK")
    return DesignAlignment(horizontal, vertical, cant, equations, "down line")


def test_write_then_read_gives_the_same_alignment(tmp_path):
    design = sample_design()
    path = tmp_path / "out.csv"
    write_alignment_csv(path, design)
    assert read_alignment_csv(path) == design
    assert list(tmp_path.iterdir()) == [path]  # no temporary file left behind
    # an azimuth that is not a round number of degrees survives to 1e-13 rad
    plan_only = DesignAlignment(HorizontalAlignment(1.0, 2.0, 0.7, 0.0, (Line(10.0),)), name="x")
    path.write_text(format_alignment_csv(plan_only), encoding="utf-8")
    back = read_alignment_csv(path)
    assert back.horizontal.start_azimuth_rad == pytest.approx(0.7, abs=1e-13)
    assert back.vertical is None and back.cant is None


def test_gon_azimuth_and_column_order(tmp_path):
    text = """[alignment]
start_station_m,0
start_east_m,10
start_north_m,20
start_azimuth_gon,100
[horizontal]
turn,type,length_m,radius_start_m
right,arc,50,500
"""
    design = read_alignment_csv(write(tmp_path, text))
    assert design.horizontal.start_azimuth_rad == pytest.approx(math.pi / 2)
    assert design.horizontal.elements == (Arc(50.0, 500.0, "right"),)
    assert design.name == "design"  # the file name when the table gives none
    east, north = design.horizontal.point_at(0.0)
    assert (float(east), float(north)) == (10.0, 20.0)


def error_for(tmp_path, text) -> InputError:
    with pytest.raises(InputError) as err:
        read_alignment_csv(write(tmp_path, text))
    return err.value


HEAD = """[alignment]
start_station_m,0
start_east_m,0
start_north_m,0
start_azimuth_deg,0
[horizontal]
type,length_m,radius_start_m,radius_end_m,turn
"""


@pytest.mark.parametrize(
    "text, line, message",
    [
        (HEAD + "line,l20,,,\n", 8, "length_m: expected a number, found 'l20'"),
        (HEAD + "spiral,20,,,\n", 8, "type: expected line, clothoid or arc"),
        (HEAD + "arc,20,,,right\n", 8, "an arc needs radius_start_m"),
        (HEAD + "line,20,,,\nclothoid,30,inf,500,right\narc,40,600,,right\n", 10,
         "element 3 .* does not continue the curvature"),
        (HEAD + "line,20,,,\nline,20,,,right,extra\n", 9, "at most 5 fields"),
        (HEAD + "line,20,,,\n[profile]\nstation_m,elevation_m,curve,curve_length_m\n0,1,none,\n"
         "50,2,parabolic,120\n100,1,none,\n", 12, "begins at station -10.0000 m, before PVI 1 at 0.0000 m"),
        (HEAD + "line,20,,,\n[cant]\nstation_m,cant_mm\n0,0\n0,5\n", 12, "cant row 2 .* is not after row 1"),
        (HEAD + "line,20,,,\n[cant]\nstation_m\n", 10, "lacks column\\(s\\) cant_mm"),
        (HEAD + "line,20,,,\n[elevations]\n", 9, "unknown section \\[elevations\\]"),
        (HEAD + "line,20,,,\n[horizontal]\n", 9, "appears twice"),
        (HEAD + "line,20,,,\n[profile]\nstation_m,elevation_m\nK0+0x,1\n", 11, "not a station label"),
        ("start_station_m,0\n", 1, "section header"),
        (HEAD.replace("start_azimuth_deg,0\n", ""), 1, "exactly one of start_azimuth_deg"),
        (HEAD.replace("start_east_m,0\n", "start_east_m,nan\n"), 3, "start_east_m: expected a finite number"),
    ],
)
def test_bad_tables_name_the_line(tmp_path, text, line, message):
    err = error_for(tmp_path, text)
    assert err.line == line
    assert re.search(message, err.message), err.message
    assert str(err).startswith(f"{tmp_path / 'design.csv'}, line {line}: ")


def test_missing_sections_and_files(tmp_path):
    err = error_for(tmp_path, "[alignment]\nstart_station_m,0\n")
    assert err.line is None and "[horizontal] is missing" in err.message
    with pytest.raises(InputError, match="cannot read"):
        read_alignment_csv(tmp_path / "absent.csv")


def test_station_equation_outside_alignment_names_its_line(tmp_path):
    err = error_for(tmp_path, HEAD + "line,20,,,\n[station_equations]\nback_m,ahead_m\n50,60\n")
    assert err.line == 11 and "outside the alignment" in err.message


def test_written_table_matches_documented_layout():
    text = format_alignment_csv(sample_design())
    sections = re.findall(r"^\[(\w+)\]$", text, flags=re.M)
    assert sections == ["alignment", "horizontal", "profile", "cant", "station_equations"]
    assert "clothoid,90.0,inf,650.0,left" in text
    assert "2240.25,-95.0" in text
    np.testing.assert_equal(sample_design().cant.cant_m[2], -0.095)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(design=design_alignments())
def test_random_alignments_round_trip(tmp_path, design):
    path = tmp_path / "random.csv"
    write_alignment_csv(path, design)
    back = read_alignment_csv(path)
    assert back.horizontal.elements == design.horizontal.elements
    assert back.horizontal.start_azimuth_rad == pytest.approx(design.horizontal.start_azimuth_rad, abs=1e-13)
    assert (back.vertical, back.cant, back.station_equations, back.name) == (
        design.vertical, design.cant, design.station_equations, design.name)
