"""One amount per sleeper and rail: sleepers.csv, the lift/lining export, the workbook (its crew sheet and its
sleeper table), the PDF and the DXF give the crew the same instruction, each file says what it brings the rail
to, and the deviations are labelled with the reference the results were processed against. Every file is read
back the way its user reads it (csv, openpyxl, pdftotext, ezdxf), never through insrail's own readers."""

import csv
import re
import shutil
import subprocess
from dataclasses import replace

import ezdxf
import numpy as np
import pytest
from openpyxl import load_workbook
from report_support import SURVEY, saved_project, stored

from insrail.cli.main import main
from insrail.export.dxf import ADJUSTMENT_LAYER, INFO_LAYER
from insrail.report import write_pdf, write_workbook

RAILS = ("left", "right")
BRINGS = "after it the track passes every check of tolerance profile"
needs_poppler = pytest.mark.skipif(shutil.which("pdftotext") is None, reason="poppler-utils (pdftotext) not installed")


@pytest.fixture(scope="module")
def project(tmp_path_factory):
    return saved_project(tmp_path_factory)


def _number(text: str) -> float:
    return float(text) if text else 0.0


@pytest.fixture(scope="module")
def truth(project):
    """sleepers.csv as a spreadsheet user reads it: {(number, rail): (lateral, vertical)} of every rail with an
    amount, and the chainage of each sleeper."""
    with open(project.folder / "results" / SURVEY / "sleepers.csv", newline="", encoding="utf-8") as handle:
        rows = list(csv.DictReader(handle))
    amounts = {}
    for row in rows:
        for rail in RAILS:
            pair = (_number(row[f"adjust_lateral_{rail}_mm"]), _number(row[f"adjust_vertical_{rail}_mm"]))
            if any(pair):
                amounts[(int(row["number"]), rail)] = pair
    assert len(amounts) > 50 and {rail for _, rail in amounts} == set(RAILS)
    return amounts, {int(row["number"]): row["label"] for row in rows}


def test_the_lift_lining_export_carries_the_planned_amounts(project, truth, tmp_path, capsys):
    path = tmp_path / "ll.csv"
    assert main(["export", str(project.folder), "--format", "lift-lining", "--out", str(path)]) == 0
    lines = path.read_text(encoding="utf-8").splitlines()
    header = {line[2:].split(" = ")[0]: line.split(" = ", 1)[1] for line in lines if line.startswith("# ") and " = " in line}
    assert BRINGS in header["amounts"] and "does not put the rail onto the line fitted" in header["amounts"]
    assert header["deviations"].startswith("vertical_deviation_left_mm") and "measured − fitted line" in header["deviations"]
    found = {}
    for row in csv.DictReader([line for line in lines if not line.startswith("#")]):
        for rail in RAILS:
            pair = (_number(row[f"lining_{rail}_mm"]), _number(row[f"lift_{rail}_mm"]))
            if any(pair):
                found[(int(row["number"]), rail)] = pair
    assert found == truth[0]


def test_the_workbook_carries_the_same_amounts_on_both_sheets(project, truth, tmp_path):
    book = load_workbook(write_workbook(project, stored(project), tmp_path / "w.xlsx"))
    sheet = book["Adjustment"]
    header = next(row[0].row for row in sheet.iter_rows() if row[0].value == "no.")
    crew = {}
    for row in sheet.iter_rows(min_row=header + 1, max_col=6, values_only=True):
        if isinstance(row[0], int):
            assert (row[1], row[3]) not in crew
            assert row[2] == truth[1][row[1]]
            crew[(row[1], row[3])] = (row[4] or 0.0, row[5] or 0.0)
    assert crew == truth[0]
    above = " ".join(str(row[0]) for row in sheet.iter_rows(max_row=header - 1, values_only=True) if row and row[0])
    assert BRINGS in above
    # the sleeper table's adjustment columns, read by their titles
    sheet = book["Sleepers"]
    header = next(row[0].row for row in sheet.iter_rows() if row[0].value == "row")
    groups, titles = [c.value for c in sheet[header - 2]], [c.value for c in sheet[header]]
    first = groups.index("Adjustment (move the rail by)")
    columns = {titles[k]: k for k in range(first, first + 4)}
    table = {}
    for row in sheet.iter_rows(min_row=header + 1, values_only=True):
        for rail in RAILS:
            pair = (row[columns[f"{rail} rail, lateral (mm)"]] or 0.0, row[columns[f"{rail} rail, vertical (mm)"]] or 0.0)
            if any(pair):
                table[(row[1], rail)] = pair
    assert table == truth[0]
    labels = " ".join(str(v) for row in sheet.iter_rows(max_row=header, values_only=True) for v in row if v)
    assert "Deviation [measured − fitted line]" in labels and BRINGS in labels


@needs_poppler
def test_the_pdf_carries_the_same_amounts(project, truth, tmp_path):
    path = write_pdf(project, stored(project), tmp_path / "r.pdf")
    extracted = subprocess.run(["pdftotext", "-layout", str(path), "-"], capture_output=True, text=True, check=True).stdout
    part = extracted[extracted.index("Adjustment amounts"):]
    assert BRINGS in " ".join(part.split())
    found = {}
    row = re.compile(r"^\s*\d+\s+(\d+)\s+(\S+)" + r"\s+([+-]?\d+)" * 4 + r"(\s|$)")  # lateral, vertical: left, right
    for line in part.splitlines():
        match = row.match(line)
        if match:
            number, label = int(match[1]), match[2]
            assert label == truth[1][number]
            for side, rail in enumerate(RAILS):
                pair = (float(match[3 + side]), float(match[5 + side]))
                if any(pair):
                    assert (number, rail) not in found
                    found[(number, rail)] = pair
    assert found == truth[0]
    assert "Lateral deviation, measured − fitted line (mm)" in extracted


def test_the_dxf_carries_the_same_amounts_beside_each_rail(project, truth, tmp_path, capsys):
    path = tmp_path / "d.dxf"
    assert main(["export", str(project.folder), "--format", "dxf", "--out", str(path)]) == 0
    space = ezdxf.readfile(path).modelspace()
    c = stored(project).columns
    numbers = stored(project).number
    rails = {rail: np.column_stack([c[f"{rail}_E_m"], c[f"{rail}_N_m"]]) for rail in RAILS}
    found = {}
    for text in space.query(f'TEXT[layer=="{ADJUSTMENT_LAYER}"]'):
        at = np.array(text.dxf.insert)[:2]
        rail, index = min(((rail, int(np.nanargmin(np.hypot(*(points - at).T)))) for rail, points in rails.items()),
                          key=lambda item: np.hypot(*(rails[item[0]][item[1]] - at)))
        words = dict(zip(text.dxf.text.split()[::2], map(float, text.dxf.text.split()[1::2])))
        assert (int(numbers[index]), rail) not in found
        found[(int(numbers[index]), rail)] = (words.get("lining", 0.0), words.get("lift", 0.0))
    assert found == truth[0]
    info = " ".join(t.dxf.text for t in space.query(f'TEXT[layer=="{INFO_LAYER}"]'))
    assert BRINGS in info and "measured − fitted line" in info
    assert "_" not in " ".join(t.dxf.text for t in space.query("TEXT") if t.dxf.layer.startswith("INSRAIL_EXCEEDANCE"))


@needs_poppler
def test_with_a_design_the_deviations_name_it(project, tmp_path):
    """Results processed against a design: the charts and the sleeper table say "measured − design (<file>)"."""
    folder = tmp_path / "designed"
    shutil.copytree(project.folder, folder)
    summary = folder / "results" / SURVEY / "summary.toml"
    text = summary.read_text(encoding="utf-8")
    assert 'design = ""' in text
    summary.write_text(text.replace('design = ""', 'design = "alignment/down line.csv"', 1), encoding="utf-8")
    designed = replace(project, folder=folder, design="alignment/down line.csv")
    results = stored(designed)
    book = load_workbook(write_workbook(designed, results, tmp_path / "d.xlsx"), read_only=True)
    cells = {v for row in book["Sleepers"].iter_rows(max_row=20, values_only=True) for v in row if isinstance(v, str)}
    assert "Deviation [measured − design (down line.csv)]" in cells
    pdf = write_pdf(designed, results, tmp_path / "d.pdf")
    extracted = subprocess.run(["pdftotext", str(pdf), "-"], capture_output=True, text=True, check=True).stdout
    assert "Vertical deviation, measured − design (down line.csv) (mm)" in extracted
    assert "does not put the rail onto the design alignment down line.csv" in " ".join(extracted.split())


def test_results_without_the_re_assessment_claim_no_verdict():
    from insrail.report.labels import amounts_text
    from insrail.track.tolerance import load_tolerance_profile

    profile = load_tolerance_profile("cn_hsr_ballastless")
    old = amounts_text({"adjustment": {"fastener": "wj8"}, "track": {"design": "d/x.xml"}}, profile, None)
    assert BRINGS not in old and "not re-assessed" in old and "onto the design alignment x.xml" in old
    failing = amounts_text({"adjustment": {"fastener": "wj8", "unresolved_sleepers": 3, "after": {}}}, profile, None)
    assert f"{BRINGS} High-speed" in failing and "except at 3 sleepers" in failing and "WJ-8" in failing
