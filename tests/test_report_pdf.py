"""The PDF survey report: it renders, holds what it promises page by page, and its charts
keep every peak while drawing a fraction of the points."""

import itertools
import re
import shutil
import subprocess
import threading
import tomllib
from pathlib import Path
from dataclasses import replace

import numpy as np
import pytest
import tomli_w
from hypothesis import given, settings
from hypothesis import strategies as st
from report_support import INVALID, shared_project, stored
from reportlab.graphics.shapes import PolyLine
from reportlab.platypus import Paragraph

from insrail.nav.trajectory import read_trajectory_fields
from insrail.progress import Cancelled
from insrail.project.results import TRAJECTORY_FILE, trajectory_section
from insrail.report import write_pdf
from insrail.report.charts import (
    Series,
    StripChart,
    decimate_min_max,
    line_runs,
    strip_drawing,
)
from insrail.report.content import load_report_content
from insrail.report.pdf import (
    BODY,
    CHART_MIN_HEIGHT,
    CHART_RANGE_M,
    PAGES,
    Heading,
    chart_area_height,
    chart_spans,
    chart_specs,
    _trajectory_rows,
    pages_of_charts,
    trajectory_statistics,
)

needs_poppler = pytest.mark.skipif(shutil.which("pdftotext") is None or shutil.which("pdftoppm") is None,
                                   reason="poppler-utils (pdftotext, pdftoppm) not installed; .ci/run installs them")
#: poppler reads a CJK font's text through the character maps of Debian's poppler-data
needs_cjk_maps = pytest.mark.skipif(not Path("/usr/share/poppler/cMap").is_dir(),
                                    reason="poppler-data (poppler's CJK character maps) not installed; .ci/run installs it")


@pytest.fixture(scope="module")
def project(tmp_path_factory):
    return shared_project(tmp_path_factory)


@pytest.fixture(scope="module")
def report(project, tmp_path_factory):
    return write_pdf(project, stored(project), tmp_path_factory.mktemp("pdf") / "survey.pdf")


def page_texts(path):
    text = subprocess.run(["pdftotext", "-layout", str(path), "-"], capture_output=True, text=True, check=True).stdout
    return text.split("\f")[:-1]


@needs_poppler
def test_the_report_renders_and_every_page_is_numbered(report, tmp_path):
    subprocess.run(["pdftoppm", "-r", "30", "-png", str(report), str(tmp_path / "page")], check=True, timeout=120)
    pages = sorted(tmp_path.glob("page-*.png"))
    texts = page_texts(report)
    assert len(pages) == len(texts) > 5
    assert all(p.stat().st_size > 2000 for p in pages)  # something drawn on every page
    for number, text in enumerate(texts, start=1):
        assert f"page {number} of {len(texts)}" in text


@needs_poppler
def test_pages_hold_the_summary_charts_per_chainage_range_plan_and_exceedances(project, report):
    results = stored(project)
    texts = page_texts(report)
    assert "Track geometry survey report" in texts[0] and "Synthetic line" in texts[0]
    processing = texts[1]
    for expected in ("GNSS outages", "1 longer than 3 s", "Position sigma, horizontal", "median 6.0 mm",
                     "Odometer scale error", "+1.50 per mille", "3 measurements rejected", "Track quality per 200 m"):
        assert expected in processing, expected
    # charts: one page group per chainage span (spans of equal length covering the survey), the range in the
    # page header, the axis in K-chainage
    chart_pages = [text for text in texts if "Charts DK" in text.splitlines()[0]]
    ranges = sorted({text.splitlines()[0].split("Charts ")[1].strip() for text in chart_pages})
    station = results.columns["station_m"]
    spans = chart_spans(station[0], station[-1])
    charts = chart_specs(load_report_content(project, results))
    assert len(ranges) == len(spans) and len(chart_pages) == len(spans) * len(pages_of_charts(
        len(charts), chart_area_height(PAGES[project.report.paper])))
    assert ranges[0].startswith(results.label[0])
    assert all("chainage" in text and "DK1+100" in text for text in chart_pages[:2])
    assert any("Twist 3 m (mm)" in text for text in texts)
    assert any("300 m / 150 m long wave, vertical" in text for text in texts)
    assert any("Plan view" in text.splitlines()[0] for text in texts)
    exceedance_pages = "\n".join(text for text in texts if "Exceedances" in text.splitlines()[0])
    for e in results.exceedances:
        assert f"{e.first_sleeper} - {e.last_sleeper}" in exceedance_pages
    # grouped by severity, the most severe first, channels by their display names
    headings = [line.split(":")[0].strip() for line in exceedance_pages.splitlines()
                if re.match(r"^\s*(Severe|Major|Minor): \d+\s*$", line)]
    assert headings == [h for h in ("Severe", "Major", "Minor") if h in headings] and len(headings) >= 2
    assert "30 m / 5 m short wave, left rail, lateral" in exceedance_pages and "short_wave" not in exceedance_pages


@needs_poppler
def test_an_added_section_lands_before_the_exceedances(project, tmp_path):
    path = write_pdf(project, stored(project), tmp_path / "with.pdf",
                     sections=[lambda content: [Heading("Repeatability"),
                                                Paragraph(f"Runs compared: {content.survey} only", BODY)]])
    texts = page_texts(path)
    added = next(i for i, text in enumerate(texts) if "Runs compared: run1 only" in text)
    assert "Repeatability" in texts[added].splitlines()[0]
    assert added < next(i for i, text in enumerate(texts) if "Exceedances" in text.splitlines()[0])


@needs_poppler
@needs_cjk_maps
def test_chinese_names_are_set_in_a_cjk_font(project, tmp_path):
    path = write_pdf(replace(project, name="兰新铁路第二双线", description="精调测量 SDK1+695"), stored(project), tmp_path / "cn.pdf")
    fonts = subprocess.run(["pdffonts", str(path)], capture_output=True, text=True, check=True).stdout
    # the shipped CJK font, embedded (a subset): no viewer needs a CJK system font to show it
    cjk = [line.split() for line in fonts.splitlines() if "WenQuanYiMicroHei" in line]
    assert cjk and all(fields[-5:-3] == ["yes", "yes"] for fields in cjk), fonts
    assert not [line for line in fonts.splitlines()[2:] if line.split()[-5] == "no" and "Helvetica" not in line]
    extracted = subprocess.run(["pdftotext", "-f", "1", "-l", "2", str(path), "-"], capture_output=True, text=True,
                               check=True).stdout
    assert "兰新铁路第二双线" in extracted and "高速铁路轨道工程施工质量验收标准" in extracted  # the standard's title
    subprocess.run(["pdftoppm", "-r", "20", "-png", "-f", "1", "-l", "1", str(path), str(tmp_path / "p")], check=True)


def test_writing_is_atomic_and_reports_progress(project, tmp_path):
    fractions = []
    path = write_pdf(project, stored(project), tmp_path / "r.pdf", progress=lambda f, m: fractions.append(f))
    assert path.read_bytes().startswith(b"%PDF")
    assert [p.name for p in tmp_path.iterdir()] == ["r.pdf"]
    assert fractions == sorted(fractions) and fractions[-1] == 1.0


def test_cancelling_while_the_pages_are_laid_out_leaves_the_previous_file(project, tmp_path):
    path = tmp_path / "r.pdf"
    path.write_bytes(b"previous")
    event = threading.Event()

    def progress(fraction, message):
        if "laying out" in message and fraction > 0.6:
            event.set()

    with pytest.raises(Cancelled):
        write_pdf(project, stored(project), path, progress=progress, cancel=event)
    assert event.is_set() and path.read_bytes() == b"previous"
    assert [p.name for p in tmp_path.iterdir()] == ["r.pdf"]


@settings(max_examples=60, deadline=None)
@given(n=st.integers(2, 4000), columns=st.integers(5, 400), seed=st.integers(0, 2**32 - 1))
def test_decimation_keeps_every_column_extreme(n, columns, seed):
    rng = np.random.default_rng(seed)
    x = np.cumsum(rng.uniform(0.1, 1.0, n))
    y = rng.standard_cauchy(n)
    y[rng.random(n) < 0.05] = np.nan
    kept = decimate_min_max(x, y, x[0], x[-1], columns)
    assert np.all(np.diff(kept) > 0) and np.all(np.isfinite(y[kept]))
    finite = np.flatnonzero(np.isfinite(y))
    if finite.size <= 2 * columns:
        assert kept.tolist() == finite.tolist()
        return
    assert kept.size <= 2 * columns + 2
    column = np.clip(((x - x[0]) / (x[-1] - x[0]) * columns).astype(int), 0, columns - 1)
    for c in np.unique(column[finite]):
        inside = finite[column[finite] == c]
        assert y[inside].max() in y[kept] and y[inside].min() in y[kept]


def test_lines_break_at_invalid_sleepers():
    y = np.array([1.0, 2.0, np.nan, 3.0, 4.0, 5.0, np.nan, np.nan, 6.0])
    runs = line_runs(np.flatnonzero(np.isfinite(y)), y)
    assert [r.tolist() for r in runs] == [[0, 1], [3, 4, 5]]  # a lone point draws no line


def test_a_16000_sleeper_chart_stays_light_and_keeps_its_spike():
    station = 0.625 * np.arange(16000)
    values = np.sin(station / 7.0)
    values[12345] = 9.0
    chart = StripChart("test", "mm", (Series("v", values),), (-2.0, 2.0))
    drawing = strip_drawing(chart, station, np.ones(16000, dtype=bool), 0.0, station[-1], 760.0, 95.0)
    lines = [shape for shape in drawing.contents if isinstance(shape, PolyLine)]
    points = sum(len(line.points) // 2 for line in lines)
    assert points <= 2 * 760 + 2
    top = max(max(line.points[1::2]) for line in lines)
    assert top == pytest.approx(95.0 - 14.0 - 0.05 / 1.1 * (95.0 - 14.0 - 14.0), abs=1.0)  # the spike reaches the top


def test_a_chart_writes_the_page_operators_reportlab_writes():
    """The chart's renderer writes a polyline's path at once (charts.polyline_code): the same operators."""
    from reportlab.graphics import renderPDF
    from reportlab.pdfgen.canvas import Canvas

    station = 0.625 * np.arange(4000)
    values = 3.0 * np.sin(station / 7.0) + 1e-4 * np.arange(4000)
    values[1000:1010] = np.nan  # two runs: two paths
    chart = StripChart("test", "mm", (Series("v", values), Series("w", -values)), (-2.0, 2.0))
    drawing = strip_drawing(chart, station, np.isfinite(values), 0.0, station[-1], 760.0, 95.0)
    assert sum(isinstance(shape, PolyLine) for shape in drawing.contents) == 4
    ours, reportlabs = Canvas(str(Path("unused.pdf"))), Canvas(str(Path("unused.pdf")))
    drawing.canv = ours
    drawing.draw()
    renderPDF.draw(drawing, reportlabs, 0, 0)
    assert ours._code == reportlabs._code


@pytest.mark.parametrize("method", ["drawString", "drawRightString", "drawCentredString"])
def test_the_canvas_writes_a_string_as_reportlab_does(method):
    """NumberedCanvas writes a plain string itself (no text object): the operators reportlab's Canvas writes,
    and reportlab's own way for what is not plain (another font, characters Helvetica lacks, options)."""
    from reportlab.pdfgen.canvas import Canvas

    from insrail.report.fonts import register_cjk
    from insrail.report.pdf import NumberedCanvas

    cases = [("Helvetica", 8, r"DK1+234.5 (a) \ é €"), ("Helvetica-Bold", 7.5, "k"), ("Helvetica", 8, ""),
             ("Helvetica", 8, "−3 σ"), (register_cjk(), 8, "中文 abc"), ("Times-Roman", 6.5, "x\ty")]
    options = [{}, {"mode": 0}, {"mode": None, "charSpace": 0}, {"charSpace": 1}, {"wordSpace": 2}, {"direction": "LTR"}]
    for font, size, words in cases:
        for option in options:
            reportlabs, ours = Canvas("unused.pdf"), NumberedCanvas("unused.pdf")
            for canvas in (reportlabs, ours):
                canvas.setFont(font, size, 1.2 * size)
                getattr(canvas, method)(10.123, 20.5, words, **option)
            assert ours._code == reportlabs._code, (font, words, option)


def test_invalid_stretch_is_shaded(project):
    results = stored(project)
    station = results.columns["station_m"]
    valid = results.columns["valid"] > 0
    chart = StripChart("gauge", "mm", (Series("g", results.columns["gauge_mm"]),))
    drawing = strip_drawing(chart, station, valid, station[0], station[0] + 500.0, 760.0, 95.0)
    shaded = [s for s in drawing.contents if type(s).__name__ == "Rect" and s.fillColor is not None]
    assert len(shaded) == 1
    width_m = shaded[0].width / (760.0 - 46.0 - 8.0) * 500.0
    assert width_m == pytest.approx(station[INVALID][-1] - station[INVALID][0] + 0.6, abs=0.05)


def test_chart_spans_cover_the_survey_with_full_pages():
    for first, last in ((1000.0, 1686.9), (1051.25, 2248.7), (0.0, 10_000.0), (20.0, 60.0), (1000.0, 1499.9)):
        spans = chart_spans(first, last)
        lengths = {round(b - a, 6) for a, b in spans}
        assert len(lengths) == 1 and lengths.pop() <= CHART_RANGE_M
        assert spans[0][0] <= first and spans[-1][1] >= last
        assert all(a == pytest.approx(b) for (_, a), (b, _) in itertools.pairwise(spans))
        # the last page is not a stub: the data reach well into it
        assert (last - spans[-1][0]) / (spans[-1][1] - spans[-1][0]) > 0.5 or len(spans) == 1
        fewest = int(np.ceil((last - spans[0][0]) / CHART_RANGE_M - 1e-9))
        assert len(spans) in (max(fewest, 1), fewest + 1)  # one more only where rounding to 50 m needs it
    assert len(chart_spans(0.0, 10_000.0)) == 20


def test_charts_are_shared_out_evenly_over_as_few_pages_as_keep_them_readable():
    height = 500.0
    for count in range(1, 30):
        layout = pages_of_charts(count, height)
        assert sum(layout) == count and max(layout) - min(layout) <= 1
        assert height / max(layout) >= CHART_MIN_HEIGHT  # never lower than the smallest readable chart
        assert len(layout) == int(np.ceil(count / (height // CHART_MIN_HEIGHT)))


@needs_poppler
def test_every_page_is_landscape_on_the_projects_paper(project, report, tmp_path):
    """[report] paper chooses the PDF's paper as it does the workbook's (A3 by default)."""
    from dataclasses import replace

    def page_sizes(path):
        info = subprocess.run(["pdfinfo", "-f", "1", "-l", "9999", str(path)], capture_output=True, text=True,
                              check=True).stdout
        return {tuple(round(float(v)) for v in re.search(r"size:\s+([\d.]+) x ([\d.]+)", line).groups())
                for line in info.splitlines() if re.match(r"Page\s+\d+ size:", line)}

    assert project.report.paper == "A3" and page_sizes(report) == {(1191, 842)}
    a4 = write_pdf(replace(project, report=replace(project.report, paper="A4")), stored(project), tmp_path / "a4.pdf")
    assert page_sizes(a4) == {(842, 595)}


def test_the_trajectory_figures_come_from_the_summary_or_for_older_results_from_the_file(project):
    """The processing page states the trajectory's figures from summary.toml's [trajectory]; results of older
    versions (none there) have them read from trajectory.npy: the same text, the whole arrays' numpy figures."""
    older = stored(project)
    assert "trajectory" not in older.summary
    fields = read_trajectory_fields(older.folder / TRAJECTORY_FILE, ("time_s", "sigma_pos_ned_m", "odometer_scale"))
    time, sigma, scale = fields["time_s"], fields["sigma_pos_ned_m"], fields["odometer_scale"]
    horizontal, vertical = 1e3 * np.hypot(sigma[:, 0], sigma[:, 1]), 1e3 * sigma[:, 2]
    expected = [
        ("Trajectory", f"{len(time)} epochs, {time[0]:.1f} - {time[-1]:.1f} s of week ({time[-1] - time[0]:.0f} s), "
                       "forward filter and RTS smoother"),
        ("Position sigma, horizontal", f"median {np.median(horizontal):.1f} mm, 95 % {np.percentile(horizontal, 95):.1f} "
                                       f"mm, largest {horizontal.max():.1f} mm"),
        ("Position sigma, vertical", f"median {np.median(vertical):.1f} mm, 95 % {np.percentile(vertical, 95):.1f} mm, "
                                     f"largest {vertical.max():.1f} mm"),
        ("Odometer scale error", f"{1e3 * scale[-1]:+.2f} per mille at the end")]
    assert _trajectory_rows(trajectory_statistics(older), smoother=True) == expected
    section = tomllib.loads(tomli_w.dumps({"t": trajectory_section(older.folder / TRAJECTORY_FILE)}))["t"]
    processed = replace(older, summary={**older.summary, "trajectory": section})
    assert _trajectory_rows(trajectory_statistics(processed), smoother=True) == expected
    gone = replace(older, folder=older.folder.parent / "nowhere")
    assert _trajectory_rows(trajectory_statistics(gone), smoother=True) == [("Trajectory", "not available")]


def test_a_decimated_chart_marks_every_exceedance_and_draws_its_peak():
    """16 000 sleepers on one chart (decimated to its pixel columns): every exceedance run keeps its red
    mark and its peak is still drawn (the line reaches it in the peak's pixel column)."""
    from reportlab.graphics.shapes import Rect

    from insrail.report.charts import LIMIT_COLOUR

    rng = np.random.default_rng(7)
    station = 0.625 * np.arange(16000)
    values = np.sin(station / 7.0)
    values[0], values[-1] = -1.0, 1.0  # the first and last points are kept: they fix the value scale
    exceeding = np.zeros(16000, dtype=bool)
    starts = np.sort(rng.choice(np.arange(10, 15980, 8), 60, replace=False))
    for start in starts:
        length = int(rng.integers(1, 4))
        values[start:start + length] = rng.choice([-1, 1]) * rng.uniform(2.5, 6.0, length)
        exceeding[start:start + length] = True
    chart = StripChart("test", "mm", (Series("v", values),), (-2.0, 2.0), exceeding)
    width = 760.0
    drawing = strip_drawing(chart, station, np.ones(16000, dtype=bool), 0.0, station[-1], width, 95.0)
    lines = [shape for shape in drawing.contents if isinstance(shape, PolyLine)]
    x = np.concatenate([np.asarray(line.points[0::2]) for line in lines])
    y = np.concatenate([np.asarray(line.points[1::2]) for line in lines])
    assert x.size <= 2 * (width - 46.0 - 8.0) + 2  # decimated
    scale = (y[-1] - y[0]) / 2.0  # points per mm (values -1 and 1 at the ends)
    marks = [shape for shape in drawing.contents if isinstance(shape, Rect) and shape.fillColor == LIMIT_COLOUR]
    px = 46.0 + station / station[-1] * (width - 46.0 - 8.0)
    runs = np.split(np.flatnonzero(exceeding), np.flatnonzero(np.diff(np.flatnonzero(exceeding)) > 1) + 1)
    for run in runs:
        assert any(mark.x <= px[run[0]] and px[run[-1]] <= mark.x + mark.width for mark in marks)
        peak = run[np.argmax(np.abs(values[run]))]
        column = np.abs(x - px[peak]) <= 1.0
        drawn = (y[column] - y[0]) / scale - 1.0  # back to mm
        assert (drawn.max() if values[peak] > 0 else -drawn.min()) >= abs(values[peak]) - 1e-6


def test_table_cells_written_as_strings_lay_out_as_their_paragraphs(tmp_path):
    """table() draws a cell that would be a one-line paragraph of its own text as a string: the same
    widths, row heights and (rendered) page; anything else stays a paragraph."""
    from reportlab.lib.units import mm
    from reportlab.platypus import SimpleDocTemplate, Table

    from insrail.report.pdf import TABLE_STYLE, _cell, table

    header = ["no.", "check", "peak"]
    rows = [[1, "30 m / 5 m differential versine, left", "2.51"], [2, "two  spaces", "x" * 80],
            [3, "σ 中文", "-"], [4, "", "1 & <b>"], [5, " leading", "0.25"]]
    widths = [12 * mm, 60 * mm, 30 * mm]
    fast = table(header, rows, widths)
    kinds = [[isinstance(cell, str) for cell in row] for row in fast._cellvalues]
    assert kinds == [[True, True, True], [True, True, True], [True, False, False], [True, False, True],
                     [True, False, True], [True, False, True]]
    slow = Table([[_cell(value) for value in row] for row in [header, *rows]], colWidths=widths, repeatRows=1,
                 style=TABLE_STYLE, hAlign="LEFT")
    assert fast.wrap(500, 800) == slow.wrap(500, 800) and fast._rowHeights == slow._rowHeights
    if shutil.which("pdftoppm") is None:
        return
    pages = []
    for name, flowable in (("fast", fast), ("slow", slow)):
        SimpleDocTemplate(str(tmp_path / f"{name}.pdf")).build([flowable])
        subprocess.run(["pdftoppm", "-r", "150", "-gray", str(tmp_path / f"{name}.pdf"), str(tmp_path / name)], check=True)
        pages.append(next(tmp_path.glob(f"{name}*.pgm")).read_bytes())
    assert pages[0] == pages[1]
