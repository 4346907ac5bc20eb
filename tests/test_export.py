"""insrail export: the lift/lining table (documented layout, read back), the DXF drawing read with
ezdxf's own reader, the LandXML lines and the coordinate CSV, from the CLI as a user runs it."""

import os
import stat
import xml.etree.ElementTree as ET

import ezdxf
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from report_support import INVALID, SURVEY, saved_project, stored

from insrail.cli.main import main
from insrail.export.dxf import (
    CENTRELINE_LAYER,
    NUMBER_LAYER,
    RAIL_LAYERS,
    SLEEPER_LAYER,
    exceedance_layer,
)
from insrail.export.liftlining import LiftLiningTable, format_table, read_lift_lining
from insrail.io.errors import InputError
from insrail.project.model import save_project


@pytest.fixture(scope="module")
def project(tmp_path_factory):
    return saved_project(tmp_path_factory)


def export(project, fmt, path, capsys):
    assert main(["export", str(project.folder), "--format", fmt, "--out", str(path)]) == 0
    assert str(path.resolve()) in capsys.readouterr().out
    return path


def test_lift_lining_carries_the_amounts_and_the_deviations_and_reads_back(project, tmp_path, capsys):
    path = export(project, "lift-lining", tmp_path / "ll.csv", capsys)
    table = read_lift_lining(path)
    results = stored(project)
    c = results.columns
    valid = c["valid"] > 0
    assert len(table) == len(results) and not valid[INVALID].any()
    np.testing.assert_array_equal(table.number, results.number)
    np.testing.assert_array_equal(table.valid, valid)
    for rail, side in (("left", 0), ("right", 1)):
        # the planned amounts (whole steps, exactly as stored), and the deviations as measured
        np.testing.assert_array_equal(table.lift_mm[:, side], c[f"adjust_vertical_{rail}_mm"])
        np.testing.assert_array_equal(table.lining_mm[:, side], c[f"adjust_lateral_{rail}_mm"])
        np.testing.assert_allclose(table.vertical_deviation_mm[valid, side], c[f"vertical_deviation_{rail}_mm"][valid],
                                   atol=0.051)
        np.testing.assert_allclose(table.lateral_deviation_mm[valid, side], c[f"lateral_deviation_{rail}_mm"][valid],
                                   atol=0.051)
    assert np.isnan(table.vertical_deviation_mm[~valid]).all() and np.isnan(table.lateral_deviation_mm[~valid]).all()
    np.testing.assert_allclose(table.station_m, c["station_m"], atol=5e-5)
    assert table.metadata["survey"] == SURVEY and table.metadata["reference"].startswith("the line fitted")
    assert "lift + up" in table.metadata["convention"]
    # the file is what docs/formats.md shows, and writing what was read gives the same file
    text = path.read_text()
    assert text.splitlines()[0] == "# insrail lift-lining 2"
    assert format_table(table) == text


_amount = st.one_of(st.just(np.nan), st.floats(-99.9, 99.9).map(lambda v: round(v, 1)))


@settings(max_examples=30, deadline=None)
@given(rows=st.lists(st.tuples(st.integers(1, 10**6), st.floats(-1e5, 1e6).map(lambda v: round(v, 4)),
                               st.booleans(), *[_amount] * 9), min_size=0, max_size=20),
       reference=st.text(st.characters(blacklist_categories=("Cc", "Cs", "Zl", "Zp")), max_size=30))
def test_any_table_round_trips(tmp_path_factory, rows, reference):
    n = len(rows)
    columns = list(zip(*rows)) if rows else [()] * 12

    def pair(k):
        return np.column_stack([columns[k], columns[k + 1]]).reshape(n, 2).astype(float)

    table = LiftLiningTable({"reference": " ".join(reference.split())}, np.array(columns[0], dtype=int),
                            tuple(f"{s:.4f}" for s in columns[1]), np.array(columns[1], dtype=float),
                            np.array(columns[2], dtype=bool), pair(3), pair(5), pair(7), pair(9),
                            np.array(columns[11], dtype=float))
    path = tmp_path_factory.mktemp("ll") / "t.csv"
    path.write_text(format_table(table))
    back = read_lift_lining(path)
    assert back.metadata == table.metadata and back.chainage == table.chainage
    for name in ("number", "station_m", "valid", "lift_mm", "lining_mm", "vertical_deviation_mm",
                 "lateral_deviation_mm", "design_cant_mm"):
        np.testing.assert_array_equal(getattr(back, name), getattr(table, name), err_msg=name)


@pytest.mark.parametrize("damage, line, expected", [
    (lambda lines: ["number,chainage"] + lines[1:], 1, "expected the first line"),
    (lambda lines: ["# insrail lift-lining 1"] + lines[1:], 1, "a version 1 table (amounts = -deviation"),
    (lambda lines: lines[:8] + ["number,chainage,station_m"] + lines[9:], 9, "expected the header"),
    (lambda lines: lines[:11] + [lines[11].replace(",1,", ",x,", 1)] + lines[12:], 12, "valid: expected 0 or 1"),
    (lambda lines: lines[:11] + [lines[11] + ",3"] + lines[12:], 12, "expected 13 fields"),
    (lambda lines: lines[:11] + [",".join(["7", "x", "1.2.3", *lines[11].split(",")[3:]])] + lines[12:], 12,
     "expected a whole sleeper number and numbers"),
])
def test_a_damaged_table_is_refused_naming_the_line(project, tmp_path, capsys, damage, line, expected):
    lines = export(project, "lift-lining", tmp_path / "ll.csv", capsys).read_text().splitlines()
    bad = tmp_path / "bad.csv"
    bad.write_text("\n".join(damage(lines)) + "\n")
    with pytest.raises(InputError) as error:
        read_lift_lining(bad)
    assert error.value.line == line and expected in str(error.value)


def test_dxf_opens_in_ezdxf_with_the_layers_and_counts_expected(project, tmp_path, capsys):
    path = export(project, "dxf", tmp_path / "track.dxf", capsys)
    doc = ezdxf.readfile(path)
    assert not doc.audit().has_errors
    results = stored(project)
    c = results.columns
    valid = c["valid"] > 0
    space = doc.modelspace()
    checks = sorted({e.check for e in results.exceedances})
    assert len(checks) >= 2
    expected_layers = {*RAIL_LAYERS.values(), CENTRELINE_LAYER, SLEEPER_LAYER, NUMBER_LAYER,
                       *(exceedance_layer(check) for check in checks)}
    assert expected_layers <= {layer.dxf.name for layer in doc.layers}
    runs = 2  # the invalid sleepers of the level crossing break every line
    for layer in (*RAIL_LAYERS.values(), CENTRELINE_LAYER):
        lines = space.query(f'POLYLINE[layer=="{layer}"]')
        assert len(lines) == runs and sum(len(list(p.points())) for p in lines) == valid.sum()
    assert len(space.query(f'LINE[layer=="{SLEEPER_LAYER}"]')) == valid.sum()
    numbers = space.query(f'TEXT[layer=="{NUMBER_LAYER}"]')
    assert sorted(int(t.dxf.text) for t in numbers) == sorted(results.number[valid].tolist())
    for check in checks:
        count = sum(e.check == check for e in results.exceedances)
        assert len(space.query(f'CIRCLE[layer=="{exceedance_layer(check)}"]')) == count
    # engineering coordinates, exactly those of sleepers.csv (top of the left rail of the first sleeper)
    first = next(iter(space.query(f'POLYLINE[layer=="{RAIL_LAYERS["left"]}"]'))).points()
    np.testing.assert_allclose(list(next(iter(first))), [c[f"left_{a}_m"][0] for a in "ENH"], atol=1e-9)
    assert doc.header["$INSUNITS"] == 6


def test_landxml_and_csv_carry_the_measured_lines(project, tmp_path, capsys):
    results = stored(project)
    c = results.columns
    valid = c["valid"] > 0
    root = ET.parse(export(project, "landxml", tmp_path / "lines.xml", capsys)).getroot()
    ns = {"l": "http://www.landxml.org/schema/LandXML-1.2"}
    features = root.findall("l:PlanFeatures/l:PlanFeature", ns)
    assert len(features) == 3 * 2
    centre = [f for f in features if "centreline" in f.get("name")]
    points = np.concatenate([np.array(f.find("l:CoordGeom/l:IrregularLine/l:PntList3D", ns).text.split(), float)
                             .reshape(-1, 3) for f in centre])
    expected = 0.5 * np.column_stack([c[f"left_{a}_m"] + c[f"right_{a}_m"] for a in "NEH"])[valid]
    np.testing.assert_allclose(points, expected, atol=6e-5)  # northing easting elevation, as LandXML orders them

    csv = np.genfromtxt(export(project, "csv", tmp_path / "points.csv", capsys), delimiter=",", names=True,
                        dtype=None, encoding="utf-8", filling_values=np.nan)
    np.testing.assert_array_equal(csv["number"], results.number)
    np.testing.assert_allclose(csv["right_E_m"][valid], c["right_E_m"][valid], atol=6e-5)
    np.testing.assert_array_equal(csv["valid"] > 0, valid)


def test_export_without_results_or_with_an_unknown_survey_fails_clearly(project, tmp_path, capsys):
    assert main(["export", str(project.folder), "--survey", "nope", "--format", "dxf"]) == 1
    assert "no survey named nope" in capsys.readouterr().err
    empty = tmp_path / "empty"
    (empty / "surveys" / "a").mkdir(parents=True)
    (empty / "surveys" / "a" / "survey.toml").touch()
    from dataclasses import replace

    from insrail.project.model import SurveyEntry

    save_project(replace(project, folder=empty, surveys=(SurveyEntry("a", "surveys/a"),)))
    assert main(["export", str(empty), "--format", "lift-lining"]) == 1
    err = capsys.readouterr().err
    assert "no results for survey 'a'" in err and "Traceback" not in err
    assert not (empty / "reports").exists()


@pytest.mark.parametrize("make", ["fifo", "chardev", "folder"])
def test_export_refuses_a_device_fifo_or_folder_and_leaves_it(project, tmp_path, capsys, make):
    target = tmp_path / f"out-{make}"
    if make == "fifo":
        os.mkfifo(target)
    elif make == "chardev":
        if os.geteuid() != 0:
            pytest.skip("mknod of a character device needs root")
        os.mknod(target, 0o666 | stat.S_IFCHR, os.makedev(1, 7))  # a copy of /dev/full
    else:
        target.mkdir()
    before = os.lstat(target)
    assert main(["export", str(project.folder), "--format", "csv", "--out", str(target)]) == 1
    err = capsys.readouterr().err
    assert str(target) in err and "not a regular file" in err
    after = os.lstat(target)
    assert (after.st_ino, after.st_mode, after.st_rdev) == (before.st_ino, before.st_mode, before.st_rdev)
    assert sorted(p.name for p in tmp_path.iterdir()) == [target.name]  # no temporary left beside it
