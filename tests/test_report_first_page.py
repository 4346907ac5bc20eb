"""The PDF's first page, the one a client signs off: read back with pdftotext for what it must state
(coordinate system with its parameters, height datum, instruments with calibration, the conclusion
with exceedances per severity and channel, the predicted accuracy against the limits, the adjustment,
the sign-off block) and checked against the result files, not against the report's own arithmetic."""

import datetime
import shutil
import subprocess
from collections import Counter
from dataclasses import replace

import pytest
from report_support import processed_project, stored

from insrail.project.model import ReportSettings
from insrail.project.results import QUALITY_FILE, QUALITY_HEADER, load_results
from insrail.report import write_pdf
from insrail.report.pdf import PAGES

pytestmark = pytest.mark.skipif(shutil.which("pdftotext") is None,
                                reason="poppler-utils (pdftotext) not installed; .ci/run installs it")

REPORT = ReportSettings(client="China Railway Wuhan Group", line_section="Wuhan - Xianning K12 - K18",
                        track_name="down line", operator="Li Wei", checked_by="Zhang San", approved_by="Wang Wu",
                        trolley="GRP 5000 no. 117", trolley_calibrated=datetime.date(2026, 3, 14),
                        imu="iNAV-RQH no. 2231", imu_calibrated=datetime.date(2025, 11, 2))


def first_page(path, crop: tuple[int, int, int, int] | None = None) -> str:
    """The text of page 1, or of the rectangle (x, y, width, height in points) of it."""
    area = [option for flag, value in zip(("-x", "-y", "-W", "-H"), crop) for option in (flag, str(value))] if crop else []
    return subprocess.run(["pdftotext", "-f", "1", "-l", "1", *area, str(path), "-"], capture_output=True, text=True,
                          check=True).stdout


def conclusion_area(paper: str) -> tuple[int, int, int, int]:
    """The right part of the landscape first page: the conclusion (the survey block is on the left;
    the right column starts near x = 425 pt on A4, the page is the A4 one enlarged on A3)."""
    width, height = PAGES[paper]
    left = round(420 * width / PAGES["A4"][0])
    return left, 0, int(width) - left, int(height)


def one_line(text: str) -> str:
    return " ".join(text.split())


@pytest.fixture(scope="module")
def project(tmp_path_factory):
    root = tmp_path_factory.mktemp("first-page")
    project = processed_project(root)
    # a predicted accuracy whose third section is too weak for the 30 m / 5 m check laterally (3 x 0.8 > 2 mm)
    lag5_lateral = [0.2, 0.25, 0.8, 0.3]
    rows = [",".join(map(str, [1000 + 200 * k, 1200 + 200 * k, 3.0, 6.0, lag5_lateral[k], 0.3, 1.5, 2.0, 0.4, 5.0]))
            for k in range(4)]
    (root / "results" / "run1" / QUALITY_FILE).write_text("\n".join([",".join(QUALITY_HEADER), *rows]) + "\n")
    return replace(project, report=REPORT)


@pytest.fixture(scope="module")
def report(project, tmp_path_factory):
    return write_pdf(project, stored(project), tmp_path_factory.mktemp("pdf") / "r.pdf")


@pytest.fixture(scope="module")
def page(report):
    return one_line(first_page(report))


@pytest.fixture(scope="module")
def conclusion(report, project):
    return one_line(first_page(report, conclusion_area(project.report.paper)))


def test_the_first_page_states_the_coordinate_system_and_heights(page):
    for expected in ("Transverse Mercator on CGCS2000", "a = 6378137.000 m", "1/f = 298.257222",
                     "central meridian 114.3°", "scale factor 1", "false easting 500000.000 m",
                     "projection height 30.000 m", "ellipsoidal heights on CGCS2000"):
        assert expected in page, expected


def test_the_first_page_names_the_instruments_with_calibration_and_the_people(page):
    for expected in ("GRP 5000 no. 117; calibrated 2026-03-14", "iNAV-RQH no. 2231; calibrated 2025-11-02",
                     "China Railway Wuhan Group", "Wuhan - Xianning K12 - K18", "down line", "Li Wei", "Zhang San",
                     "Wang Wu", "Checked by", "Approved by", "signature", "High-speed ballastless track",
                     "towards increasing chainage (DK1+000.000 to DK1+686.875)"):
        assert expected in page, expected


def test_the_conclusion_counts_the_exceedances_per_severity_and_channel(project, conclusion):
    page = conclusion
    results = load_results(project.folder, "run1")
    shares = [abs(e.peak - e.limit) / abs(e.limit) for e in results.exceedances]
    severity = Counter("severe" if s > 1.0 else "major" if s > 0.25 else "minor" for s in shares)
    assert len(severity) >= 2  # the synthetic defects reach more than one severity
    summary = ", ".join(f"{severity[name]} {name}" for name in ("severe", "major", "minor") if severity[name])
    assert f"{len(results.exceedances)} exceedances (runs of sleepers beyond a limit)" in page
    assert f"{summary}." in page
    channels = Counter((e.check, e.rail, e.direction) for e in results.exceedances)
    (check, rail, direction), most = channels.most_common(1)[0]
    assert check == "short_wave_30m_5m"
    by_severity = Counter("severe" if s > 1.0 else "major" if s > 0.25 else "minor"
                          for e, s in zip(results.exceedances, shares) if (e.check, e.rail, e.direction) == (
                              check, rail, direction))
    cells = " ".join(str(by_severity[name]) for name in ("severe", "major", "minor") if by_severity[name])
    assert f"30 m / 5 m short wave, {rail} rail, {direction} {cells} {most} " in page
    assert "short_wave" not in page and "_" not in page.replace("cn_hsr_ballastless", "")


def test_the_conclusion_judges_the_predicted_accuracy_against_the_limits(conclusion):
    page = conclusion
    # 3 sigma of the weakest section against the limit: lateral 2.40 > 2 mm, vertical 0.90 mm within
    assert "30 m / 5 m short wave, lateral ±2.0 0.28 2.40 NOT within the limit" in page
    assert "30 m / 5 m short wave, vertical ±2.0 0.30 0.90 within the limit" in page
    assert "300 m / 150 m long wave, vertical ±10.0 2.00 6.00 within the limit" in page


def test_the_conclusion_summarises_the_adjustment(project, conclusion):
    page = conclusion
    results = load_results(project.folder, "run1")
    moving = sum(1 for row in zip(*(results.columns[f"adjust_{d}_{r}_mm"] for d in ("lateral", "vertical")
                                    for r in ("left", "right"))) if any(v != 0 for v in row))
    assert f"{moving} sleepers to adjust" in page
    unresolved = results.summary["adjustment"]["unresolved_sleepers"]  # the re-assessment's honest count
    assert ("every check met after adjustment" if unresolved == 0 else
            f"{unresolved} sleepers where the checks still fail after adjustment") in page
    after = results.summary["adjustment"]["after"]  # the re-assessment per channel, in one sentence
    assert f"After adjustment: {after['exceedances']} exceedances (before " in page
    assert f"{after['new_exceedances']} where the track passed before" in page


def test_without_report_settings_the_blanks_say_so_and_the_imu_model_is_named(project, tmp_path):
    bare = replace(project, report=ReportSettings(), imu_profile="tactical")
    page = one_line(first_page(write_pdf(bare, stored(project), tmp_path / "bare.pdf")))
    assert "Client not stated" in page and "calibration date not stated" in page
    assert "error model tactical" in page
