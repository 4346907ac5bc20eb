"""The crews' workbook: exact values of the result files, red fill on exactly the exceedance cells,
LibreOffice opens it, the adjustment sheet in walking order, atomic and cancellable writing."""

import re
import shutil
import subprocess
import threading
import zipfile
from dataclasses import replace

import numpy as np
import pytest
from openpyxl import load_workbook
from openpyxl.utils import get_column_letter
from memory_support import peak_growth_bytes
from report_support import INVALID, SURVEY, processed_project, shared_project, stored, with_profile

from insrail.names import channel_name
from insrail.progress import Cancelled
from insrail.project.results import check_column
from insrail.report import excel, write_workbook
from insrail.report.content import SEVERITIES, load_report_content
from insrail.report.excel import (
    BOLD_CHARACTER_WIDTH,
    LINE_HEIGHT_PT,
    PAPER_CODES,
    _wrapped_lines,
)

RED, GREY = "00FFC7CE", "00D9D9D9"


@pytest.fixture(scope="module")
def project(tmp_path_factory):
    return shared_project(tmp_path_factory)


@pytest.fixture(scope="module")
def workbook(project, tmp_path_factory):
    path = write_workbook(project, stored(project), tmp_path_factory.mktemp("xlsx") / "crews.xlsx")
    return path, load_workbook(path)


def sleeper_table(sheet):
    """(header row number, {title: column index} (the last of equal titles), data rows as lists of cells)."""
    header = next(row[0].row for row in sheet.iter_rows() if row[0].value == "row")
    titles = {cell.value: cell.column - 1 for cell in sheet[header] if cell.value}
    width = max(titles.values()) + 1  # the header block above may reach further right
    rows = list(sheet.iter_rows(min_row=header + 1, max_col=width))
    return header, titles, rows


def column_values(rows, index):
    return [row[index].value for row in rows]


def as_cells(values):
    """What a cell holds for a value of the result files: NaN is an empty cell."""
    return [None if isinstance(v, float) and np.isnan(v) else v for v in values]


def test_the_sleeper_sheet_holds_the_exact_values_of_the_result_files(project, workbook):
    results = stored(project)
    _, titles, rows = sleeper_table(workbook[1]["Sleepers"])
    assert len(rows) == len(results)
    assert column_values(rows, titles["number"]) == results.number.tolist()
    assert column_values(rows, titles["chainage"]) == list(results.label)
    assert column_values(rows, titles["station (m)"]) == results.columns["station_m"].tolist()
    for title, key in (("gauge (mm)", "gauge_mm"), ("design cant (mm)", "design_cant_mm"),
                       ("gauge change to the previous sleeper (mm)", "gauge_change_mm")):
        assert column_values(rows, titles[title]) == as_cells(results.columns[key].tolist()), title
    # every check channel and every deviation and adjustment column appears, value for value
    shown = [column_values(rows, index) for index in range(len(rows[0]))]
    for key, values in results.columns.items():
        if key.startswith(("check_", "lateral_deviation", "vertical_deviation", "adjust_")):
            expected = as_cells((values * (1e3 if key.endswith("_ratio") else 1.0)).tolist())
            assert any(column == expected or (key.endswith("_ratio") and _close(column, expected)) for column in shown), key


def _close(column, expected):
    return len(column) == len(expected) and all(
        (a is None and b is None) or (isinstance(a, float) and b is not None and np.isclose(a, b, rtol=1e-12, atol=0))
        for a, b in zip(column, expected))


def test_red_fill_on_exactly_the_exceedance_cells_and_grey_on_invalid_rows(project, workbook):
    results = stored(project)
    header, _, rows = sleeper_table(workbook[1]["Sleepers"])
    row_of = {number: i for i, number in enumerate(results.number.tolist())}
    expected_red = set()
    for e in results.exceedances:
        values = results.columns[check_column(e.check, e.kind, e.rail, e.direction)]
        scale = 1e3 if e.unit == "ratio" else 1.0
        target = as_cells((scale * values).tolist())
        matches = [i for i in range(len(rows[0])) if column_values(rows, i) == target or _close(column_values(rows, i), target)]
        assert len(matches) == 1, e
        expected_red |= {(r, matches[0]) for r in range(row_of[e.first_sleeper], row_of[e.last_sleeper] + 1)}
    assert expected_red
    red, grey, other = set(), set(), set()
    for r, row in enumerate(rows):
        for cell in row:
            if cell.fill.fill_type is None:
                continue
            colour = cell.fill.fgColor.rgb
            (red if colour == RED else grey if colour == GREY else other).add((r, cell.column - 1))
    assert red == expected_red
    assert not other
    invalid_rows = set(range(len(results))[INVALID])
    assert {r for r, _ in grey} == invalid_rows
    assert grey == {(r, c) for r in invalid_rows for c in range(len(rows[0]))}
    # above the table only header styling and the legend's two sample cells are filled
    legend = [cell for row in workbook[1]["Sleepers"].iter_rows(max_row=header - 3) for cell in row
              if cell.fill.fill_type is not None]
    assert sorted(cell.fill.fgColor.rgb for cell in legend) == sorted([RED, GREY])


def test_layout_for_the_crews(project, workbook):
    sheets = workbook[1]
    assert sheets.sheetnames == ["Summary", "Sleepers", "Adjustment", "Materials", "Exceedances", "Processing log"]
    sheet = sheets["Sleepers"]
    header, titles, rows = sleeper_table(sheet)
    assert sheet.freeze_panes == f"E{header + 1}"
    assert sheet.auto_filter.ref == f"A{header}:{sheet.cell(header, len(rows[0])).column_letter}{header + len(rows)}"
    assert sheet.print_title_rows == f"${header - 2}:${header}"
    assert rows[0][titles["left rail, lateral (mm)"]].number_format == "0.0"
    assert rows[0][titles["gauge change rate 2.5 m (‰)"]].number_format == "0.00"
    assert "Limits" in [row[0].value for row in sheet.iter_rows(max_row=header)]
    # units in headers; the Figure 5-7 groups present, each title merged over exactly its columns
    content = load_report_content(project, stored(project))
    merged = {str(r) for r in sheet.merged_cells.ranges}
    first = 0
    for group in dict.fromkeys(c.group for c in content.columns):
        span = sum(1 for c in content.columns if c.group == group)
        assert sheet.cell(header - 2, first + 1).value == group
        if span > 1:
            assert f"{get_column_letter(first + 1)}{header - 2}:{get_column_letter(first + span)}{header - 2}" in merged
        first += span
    groups = {cell.value for cell in sheet[header - 2] if cell.value}
    assert {"Deviation [measured − fitted line]", "30 m / 5 m short wave", "300 m / 150 m long wave",
            "Adjustment (move the rail by)"} <= groups
    assert {"twist 3 m (mm)", "guiding rail", "cross level (mm)", "gauge (mm)", "gauge deviation (mm)"} <= set(titles)
    # one name per column: within a group no two titles alike, and no internal id anywhere in the header
    for group in groups:
        in_group = [c.title for c in content.columns if c.group == group]
        assert len(set(in_group)) == len(in_group), group
    # (the profile's file name is what a user types in project.toml: it may be shown beside its description)
    header_text = [cell.value.replace(content.profile.name, "") for r in range(1, header + 1) for cell in sheet[r]
                   if isinstance(cell.value, str)]
    assert not [text for text in header_text if re.search(r"[a-z]_[a-z0-9]", text)]


def test_headers_fit_and_every_page_is_headed_and_numbered(project, workbook):
    """No header word wider than its column (what LibreOffice clipped as "guidin g rail"), header rows as high
    as their wrapped titles; print header with project and survey, footer with page x of y; the project's paper."""
    sheets = workbook[1]
    for sheet in sheets:
        crew = sheet.title == "Adjustment"  # A4 portrait whatever the project's paper
        assert sheet.page_setup.paperSize == PAPER_CODES["A4" if crew else project.report.paper]
        assert project.report.paper == "A3"
        assert sheet.page_setup.orientation == ("portrait" if crew else "landscape")
        assert sheet.oddHeader.left.text == project.name
        assert SURVEY in sheet.oddHeader.center.text
        assert sheet.oddFooter.right.text == "page &P of &N"
    sheet = sheets["Sleepers"]
    header, _, _ = sleeper_table(sheet)
    for row in (header - 1, header):
        for cell in sheet[row]:
            if not cell.value:
                continue
            width = sheet.column_dimensions[cell.column_letter].width
            assert max(len(word) for word in cell.value.split()) * BOLD_CHARACTER_WIDTH <= width, cell.value
    tallest = max(_wrapped_lines(cell.value, sheet.column_dimensions[cell.column_letter].width)
                  for cell in sheet[header] if cell.value)
    assert tallest >= 3 and sheet.row_dimensions[header].height >= tallest * LINE_HEIGHT_PT
    # a header row below a sheet's first table (the Summary's per-section table) is fitted too
    summary = sheets["Summary"]
    below = next(row[0].row for row in summary.iter_rows() if row[0].value == "from (m)")
    lines = max(_wrapped_lines(cell.value, summary.column_dimensions[cell.column_letter].width)
                for cell in summary[below] if cell.value)
    assert lines >= 3 and summary.row_dimensions[below].height >= lines * LINE_HEIGHT_PT
    for cell in summary[below]:
        if cell.value:
            width = summary.column_dimensions[cell.column_letter].width
            assert max(len(word) for word in cell.value.split()) * BOLD_CHARACTER_WIDTH <= width, cell.value


def test_the_paper_is_the_projects(project, tmp_path):
    a4 = replace(project, report=replace(project.report, paper="A4"))
    sheets = load_workbook(write_workbook(a4, stored(project), tmp_path / "a4.xlsx"))
    assert {sheet.page_setup.paperSize for sheet in sheets} == {PAPER_CODES["A4"]}


def test_guiding_rail_is_the_high_rail_of_the_curve(project, workbook):
    results = stored(project)
    _, titles, rows = sleeper_table(workbook[1]["Sleepers"])
    guide = np.array(column_values(rows, titles["guiding rail"]))
    right_high = results.columns["design_cant_mm"] < 0
    assert right_high.any() and (~right_high).any()
    assert np.all(guide[right_high] == "R") and np.all(guide[~right_high] == "L")


def test_adjustment_sheet_lists_the_rails_to_move_in_order_with_parts(project, workbook):
    results = stored(project)
    c = results.columns
    sheet = workbook[1]["Adjustment"]
    header = next(row[0].row for row in sheet.iter_rows() if row[0].value == "no.")
    assert [cell.value for cell in sheet[header]] == list(excel.CREW_TITLES)
    rows = [[c.value for c in row] for row in sheet.iter_rows(min_row=header + 1, max_col=len(excel.CREW_TITLES))]
    lines = [row for row in rows if not isinstance(row[0], str)]
    # one line per rail to move, in working order, with exactly the amounts of sleepers.csv
    expected = [[int(results.number[i]), results.label[i], rail, c[f"adjust_lateral_{rail}_mm"][i],
                 c[f"adjust_vertical_{rail}_mm"][i]]
                for i in np.argsort(c["station_m"], kind="stable") for rail in ("left", "right")
                if c[f"adjust_lateral_{rail}_mm"][i] or c[f"adjust_vertical_{rail}_mm"][i]]
    assert expected and [row[1:6] for row in lines] == expected
    sleepers = list(dict.fromkeys(row[1] for row in lines))
    assert [row[0] for row in lines] == [sleepers.index(row[1]) + 1 for row in lines]  # the running count
    # every amount names its WJ-8 parts beside it, and only an amount does
    for row in lines:
        assert bool(row[4]) == ("lateral: " in (row[6] or "")) and bool(row[5]) == ("vertical: " in (row[6] or ""))
    # Annex 8 table 8-2: a rail moved outwards (left rail to the left, right rail to the right) gets smaller
    # field-side and larger gauge-side parts
    outwards = {1: "outer block No. 9→8; inner block No. 9→10",
                2: "outer block No. 9→7; inner block No. 9→11",
                3: "outer apron No. 7→4; inner apron No. 7→10"}
    checked = 0
    for row in lines:
        if row[4] and (-row[4] if row[3] == "left" else row[4]) in outwards:
            assert f"lateral: {outwards[-row[4] if row[3] == 'left' else row[4]]}" in row[6]
            checked += 1
    assert checked
    assert {part for row in lines if row[5] == 1 for part in row[6].split("\n") if part.startswith("vertical")} \
        == {"vertical: shims under the rail* 1 mm"}  # assumed sizes marked
    # work sections: each a heading and a page of its own
    headings = [header + 1 + k for k, row in enumerate(rows) if isinstance(row[0], str)]
    assert len(headings) > 1 and all(rows[h - header - 1][0].startswith("Work section ") for h in headings)
    assert [b.id for b in sheet.row_breaks.brk] == [h - 1 for h in headings[1:]]
    # what the amounts bring the rail to, and the re-assessment of the adjusted geometry, above the table
    above = [row[0].value for row in sheet.iter_rows(max_row=header - 1) if row and isinstance(row[0].value, str)]
    assert any(text.startswith("Amounts: move the rail by the amount") and "does not put the rail onto the line "
               "fitted to the measured centreline" in text and "Cn hsr" not in text for text in above)
    after = results.summary["adjustment"]["after"]
    assert any(text.startswith(f"After adjustment: {after['exceedances']} exceedances") for text in above)
    assert any(text.startswith("Action threshold 1 mm") for text in above)


def test_the_crew_sheet_prints_on_a4_portrait_at_a_readable_size(project, workbook):
    sheet = workbook[1]["Adjustment"]
    setup = sheet.page_setup
    assert (setup.orientation, setup.paperSize) == ("portrait", PAPER_CODES["A4"])
    # one page wide, which the columns fill at 100 %: the body font prints at its size
    assert sheet.sheet_properties.pageSetUpPr.fitToPage and setup.fitToWidth == 1 and setup.fitToHeight == 0
    widths = [sheet.column_dimensions[get_column_letter(k + 1)].width for k in range(len(excel.CREW_TITLES))]
    assert sum(excel.column_width_mm(w) for w in widths) <= excel.printable_width_mm("A4", "portrait")
    assert excel.BODY_FONT_PT >= excel.READABLE_PT


@pytest.mark.parametrize("paper", ["A3", "A4"])
def test_the_sleeper_table_prints_in_readable_column_groups(project, tmp_path, paper):
    project = replace(project, report=replace(project.report, paper=paper))
    sheet = load_workbook(write_workbook(project, stored(project), tmp_path / "p.xlsx"))["Sleepers"]
    setup = sheet.page_setup
    assert setup.orientation == "landscape" and setup.paperSize == PAPER_CODES[paper]
    assert excel.BODY_FONT_PT * int(setup.scale) / 100 >= excel.READABLE_PT
    header, titles, rows = sleeper_table(sheet)
    count = len(rows[0])
    widths = [sheet.column_dimensions[get_column_letter(k + 1)].width for k in range(count)]
    starts = [b.id for b in sheet.col_breaks.brk]
    assert starts and sheet.print_title_cols == "$A:$D"
    groups = [sheet.cell(header - 2, k + 1).value for k in range(count)]
    room = excel.printable_width_mm(paper, "landscape") * 100 / int(setup.scale)
    for first, stop in zip([4] + starts, starts + [count]):
        page = sum(excel.column_width_mm(w) for w in widths[:4] + widths[first:stop])
        assert page <= room
    assert all(groups[first] is not None for first in starts)  # a page starts where a group does (merged titles
    # sit in a group's first cell)
    assert len(starts) >= (3 if paper == "A4" else 1)


def test_the_materials_list_sums_the_parts_of_the_adjustment_sheet(project, workbook):
    from insrail.track.adjustment import load_fastener_type
    from insrail.track.adjustment_parts import table_amount

    results = stored(project)
    sheet = workbook[1]["Materials"]
    header = next(row[0].row for row in sheet.iter_rows() if row[0].value == "part")
    listed = {(r[0], r[1]): r[2:] for r in sheet.iter_rows(min_row=header + 1, values_only=True)}
    assert listed and all(left + right == total for left, right, total in listed.values())
    # counted again from the amounts, independently of the sheet: WJ-8 lateral parts by table 8-2
    fastener = load_fastener_type("wj8")
    table = fastener.parts["lateral"]
    expected = {}
    for rail, key in enumerate(("adjust_lateral_left_mm", "adjust_lateral_right_mm")):
        for amount in results.columns[key][results.columns[key] != 0]:
            index = table.amounts_mm.index(table_amount("lateral", rail, amount))
            for position in table.positions:
                if position.sizes[index] != position.as_built:
                    name = (position.name, f"No. {position.sizes[index]:g}")
                    expected[name] = expected.get(name, 0) + 1
    assert expected
    assert {k: v[2] for k, v in listed.items() if k[1].startswith("No.")} == expected


def test_exceedance_and_summary_sheets(project, workbook):
    results = stored(project)
    sheet = workbook[1]["Exceedances"]
    header = next(row[0].row for row in sheet.iter_rows() if row[0].value == "no.")
    rows = [[c.value for c in row] for row in sheet.iter_rows(min_row=header + 1)]
    assert len(rows) == len(results.exceedances)
    # the most severe first, each severity in chainage order; every run exactly once, named for people
    order = [name for name, _ in SEVERITIES]
    ranks = [order.index(row[1]) for row in rows]
    assert ranks == sorted(ranks) and len(set(ranks)) > 1
    for rank in set(ranks):
        starts = [row[6] for row, r in zip(rows, ranks) if r == rank]
        assert starts == sorted(starts)
    by_key = {(e.station_from_m, e.first_sleeper, e.last_sleeper, e.rail, e.direction, e.check): e
              for e in results.exceedances}
    checks = {c.name: c for c in load_report_content(project, results).profile.checks}
    for row in rows:
        e = next(e for key, e in by_key.items() if key[:3] == (row[6], row[13], row[14])
                 and row[2] == channel_name(checks[e.check], e.rail, e.direction))
        by_key.pop((e.station_from_m, e.first_sleeper, e.last_sleeper, e.rail, e.direction, e.check))
        assert "_" not in row[2]
        assert row[9] == pytest.approx(e.peak * (1e3 if e.unit == "ratio" else 1.0), rel=1e-12)
        share = abs(e.peak - e.limit) / abs(e.limit)
        assert row[12] == pytest.approx(100 * share)
        assert row[1] == ("severe" if share > 1.0 else "major" if share > 0.25 else "minor")
    assert not by_key
    summary = [[c.value for c in row] for row in workbook[1]["Summary"].iter_rows()]
    tqi = results.summary["track_quality"]["tqi_mm"]
    tqi_column = next(row.index("TQI (mm)") for row in summary if "TQI (mm)" in row)
    first = next(i for i, row in enumerate(summary) if "TQI (mm)" in row) + 1
    assert [row[tqi_column] for row in summary[first:first + len(tqi)]] == [v if v >= 0 else None for v in tqi]
    log = {row[0]: row[1] for row in workbook[1]["Processing log"].iter_rows(values_only=True) if row and row[0]}
    assert log["fusion.rejections"] == 3
    assert log["gnss.outages"].startswith(str(results.summary["gnss"]["outages"][0][0]))


def test_a_profile_without_the_wave_checks_leaves_their_columns_out(tmp_path_factory, tmp_path):
    """en13848_5_template has no 30 m / 5 m or 300 m / 150 m check and an EN twist (not relative to
    design): the Figure 5-7 twist comes from the stored column, the profile's checks follow."""
    other = shared_project(tmp_path_factory, "en13848_5_template")
    path = write_workbook(other, stored(other), tmp_path / "en.xlsx")
    sheet = load_workbook(path, read_only=True)["Sleepers"]
    rows = list(sheet.iter_rows(values_only=True))
    header = next(i for i, row in enumerate(rows) if row and row[0] == "row")
    groups = {v for v in rows[header - 2] if v}
    assert not any("short wave" in g or "long wave" in g for g in groups)
    assert {"Alignment D1", "Longitudinal level D1", "Other checks of the tolerance profile"} <= groups
    assert "twist 3 m (mm)" in rows[header] and "twist 3 m of the measured cant (mm)" in rows[header]


def test_a_changed_tolerance_profile_is_refused(project, tmp_path):
    with pytest.raises(ValueError, match="process the survey again"):
        write_workbook(with_profile(project, "fra_class_1"), stored(project), tmp_path / "x.xlsx")
    assert not list(tmp_path.iterdir())


def test_cancelling_leaves_no_file(project, tmp_path):
    path = tmp_path / "crews.xlsx"
    path.write_bytes(b"previous")
    event = threading.Event()
    calls = []

    def progress(fraction, message):
        calls.append(fraction)
        if fraction > 0.3:
            event.set()

    with pytest.raises(Cancelled):
        write_workbook(project, stored(project), path, progress=progress, cancel=event)
    assert path.read_bytes() == b"previous"
    assert [p.name for p in tmp_path.iterdir()] == ["crews.xlsx"]
    assert calls == sorted(calls)


@pytest.mark.skipif(shutil.which("soffice") is None, reason="LibreOffice (soffice) is not installed; .ci/run installs it")
def test_libreoffice_opens_the_workbook(workbook, tmp_path):
    path, _ = workbook
    sleepers = 2  # the sheet's number (the Summary comes first); LibreOffice >= 7.2 exports one sheet by number
    result = subprocess.run(["soffice", f"-env:UserInstallation=file://{tmp_path}/profile", "--headless", "--convert-to",
                             f"csv:Text - txt - csv (StarCalc):44,34,76,1,,0,false,true,false,false,false,{sleepers}",
                             "--outdir", str(tmp_path), str(path)],
                            capture_output=True, text=True, timeout=120, check=False)
    assert result.returncode == 0, result.stderr
    exported = list(tmp_path.glob("crews*.csv"))  # "crews-Sleepers.csv" (LibreOffice names a sheet export by the sheet)
    assert len(exported) == 1
    csv = exported[0].read_text(encoding="utf-8", errors="replace").splitlines()
    assert csv[0].startswith("Track geometry per sleeper")
    assert any(line.startswith("1,1,DK1+000.000,1000") for line in csv)
    materials = 4  # the materials list opens too, its parts summed
    result = subprocess.run(["soffice", f"-env:UserInstallation=file://{tmp_path}/profile", "--headless", "--convert-to",
                             f"csv:Text - txt - csv (StarCalc):44,34,76,1,,0,false,true,false,false,false,{materials}",
                             "--outdir", str(tmp_path / "materials"), str(path)],
                            capture_output=True, text=True, timeout=120, check=False)
    assert result.returncode == 0, result.stderr
    lines = next((tmp_path / "materials").glob("crews*.csv")).read_text(encoding="utf-8").splitlines()
    assert lines[0].startswith("Materials list")
    assert any(line.split(",")[:2] == ["outer block", "No. 7"] for line in lines)


def _members(path) -> dict[str, bytes]:
    """The workbook's XML members, the moment it was written (document properties, the log's minute) left out."""
    with zipfile.ZipFile(path) as xlsx:
        members = {name: xlsx.read(name) for name in xlsx.namelist() if name != "docProps/core.xml"}
    return {name: re.sub(rb"\d{4}-\d\d-\d\d \d\d:\d\d UTC", b"", data) for name, data in members.items()}


def test_a_table_written_in_blocks_is_the_whole_table(project, workbook, tmp_path, monkeypatch):
    """The sleeper and adjustment tables go to the workbook a block of rows at a time (through a
    temporary file): every sheet's XML is the same as written in one block."""
    monkeypatch.setattr(excel, "TABLE_BLOCK_ROWS", 97)
    monkeypatch.setattr(excel, "SPOOL_COPY_BYTES", 4099)
    blocks = write_workbook(project, stored(project), tmp_path / "blocks.xlsx")
    monkeypatch.setattr(excel, "TABLE_BLOCK_ROWS", 10**9)
    whole = write_workbook(project, stored(project), tmp_path / "whole.xlsx")
    written = _members(blocks)
    assert written == _members(whole)
    sleepers = written["xl/worksheets/sheet2.xml"].decode("utf-8")
    assert sleepers.count("<row ") > len(stored(project)) and sleepers.endswith("</worksheet>")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["blocks.xlsx", "whole.xlsx"]


def test_the_workbook_writer_holds_no_more_for_a_longer_survey(tmp_path_factory, monkeypatch):
    """Memory bounded for any survey length: the traced peak of writing the workbook of 550 and of
    1100 sleepers differs by less than 1 kB a sleeper (the sleeper columns read from the results;
    the table's text, 8 kB a sleeper before it was spooled, is never held whole)."""
    monkeypatch.setattr(excel, "TABLE_BLOCK_ROWS", 97)
    projects = {n: processed_project(tmp_path_factory.mktemp(f"length-{n}"), n=n) for n in (550, 1100)}
    results = {n: stored(project) for n, project in projects.items()}
    out = tmp_path_factory.mktemp("length-xlsx")

    def run(n):
        return write_workbook(projects[n], results[n], out / f"{n}.xlsx")

    short, long = peak_growth_bytes(run, 550)
    assert long - short < 1024 * 550 + 64 * 1024, (short, long)


def test_work_sections_are_work_sites_of_at_most_100_m(project):
    from insrail.report.content import WORK_SECTION_GAP_M, WORK_SECTION_M, crew_sections

    content = load_report_content(project, stored(project))
    station = content.station_m
    sections = crew_sections(content)
    assert len(sections) > 1 and [s.number for s in sections] == list(range(1, len(sections) + 1))
    for section in sections:
        stations = station[[row.sleeper for row in section.rows]]
        assert np.all(np.diff(stations) >= 0) and stations[-1] - stations[0] < WORK_SECTION_M
        assert np.all(np.diff(stations) <= WORK_SECTION_GAP_M)
    for before, after in zip(sections, sections[1:]):
        first = station[before.rows[0].sleeper]
        gap = station[after.rows[0].sleeper] - station[before.rows[-1].sleeper]
        assert gap > WORK_SECTION_GAP_M or station[after.rows[0].sleeper] - first >= WORK_SECTION_M
