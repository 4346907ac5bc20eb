"""What the pipeline stores for the reports: the thesis's Figure 5-7 columns beside the profile's
checks, the GNSS availability and TQI sections of summary.toml; and `insrail report`."""

import shutil
import subprocess

import numpy as np
import pytest
from openpyxl import load_workbook
from report_support import SURVEY, shared_project, stored

from insrail.cli.main import main
from insrail.project import save_project
from insrail.project.results import gnss_section, load_results
from insrail.track.parameters import guiding_rail_is_right


@pytest.fixture(scope="module")
def project(tmp_path_factory):
    return shared_project(tmp_path_factory)


def test_figure_5_7_columns_agree_with_the_profile_checks_of_the_same_base(project):
    """cn_hsr_ballastless checks the gauge change rate over 2.5 m and twist over 3 m (design ramp
    removed): the always-stored columns must be the same numbers (both written to 6 / 3 decimals)."""
    c = stored(project).columns
    np.testing.assert_array_equal(c["gauge_change_rate_2_5m_ratio"], c["check_gauge_change_rate_ratio"])
    np.testing.assert_array_equal(c["twist_3m_mm"], c["check_twist_3m_mm"])
    gauge = np.where(c["valid"] > 0, c["gauge_mm"], np.nan)
    np.testing.assert_allclose(c["gauge_change_mm"][1:], np.diff(gauge), atol=1.5e-3)
    assert np.isnan(c["gauge_change_mm"][0])


def test_the_guiding_rail_is_the_high_rail_and_left_on_straights():
    assert guiding_rail_is_right(np.array([0.0, 0.05, -0.05, -1e-6])).tolist() == [False, False, True, True]


def test_gnss_outages_are_found_at_the_start_inside_and_at_the_end():
    time = np.concatenate([np.arange(105.0, 150.0), np.arange(160.0, 190.0)])
    section = gnss_section(time, np.where(time < 120, 2, 1), 100.0, 200.0)
    assert section["outages"] == [[100.0, 105.0], [149.0, 160.0], [189.0, 200.0]]
    assert section["solutions"] == len(time) and section["fixed"] == int(np.sum(time >= 120))
    assert section["outage_total_s"] == pytest.approx(5 + 11 + 11)
    assert gnss_section(np.arange(0.0, 10.0), np.ones(10), 0.0, 9.0)["outages"] == []


def test_summary_holds_tqi_per_section(project):
    quality = stored(project).summary["track_quality"]
    station = stored(project).columns["station_m"]
    assert quality["start_m"][0] == pytest.approx(station[0], abs=1e-3)
    assert len(quality["tqi_mm"]) == int((station[-1] - station[0]) // 200) + 1
    valid = [k for k, v in enumerate(quality["tqi_mm"]) if v >= 0]
    assert valid
    for k in valid:
        assert quality["tqi_mm"][k] == pytest.approx(sum(quality[f"sd_{c}_mm"][k] for c in quality["channels"]), abs=1e-3)


def test_cli_report_writes_both_reports_into_the_project_reports_folder(project, capsys):
    (project.folder / "surveys" / SURVEY).mkdir(parents=True, exist_ok=True)
    (project.folder / "surveys" / SURVEY / "survey.toml").write_text("")
    save_project(project)
    assert main(["report", str(project.folder)]) == 0
    out = capsys.readouterr().out
    folder = project.folder / "reports"
    for suffix in (".xlsx", ".pdf"):
        path = folder / f"track_geometry_{SURVEY}{suffix}"
        assert path.stat().st_size > 10_000 and str(path.resolve()) in out
    assert main(["report", str(project.folder), "--survey", "nope"]) == 1
    assert "no survey named nope" in capsys.readouterr().err


@pytest.mark.slow
@pytest.mark.skipif(shutil.which("pdftoppm") is None, reason="poppler-utils (pdftoppm) not installed; .ci/run installs it")
def test_the_demo_writes_both_reports_and_its_pdf_renders(tmp_path, capsys):
    assert main(["demo", "--out", str(tmp_path / "demo")]) == 0
    folder = tmp_path / "demo" / "reports"
    results = load_results(tmp_path / "demo", "short")
    pdf = folder / "track_geometry_short.pdf"
    subprocess.run(["pdftoppm", "-r", "20", "-png", str(pdf), str(tmp_path / "page")], check=True, timeout=300)
    assert len(list(tmp_path.glob("page-*.png"))) > 10
    sheet = load_workbook(folder / "track_geometry_short.xlsx", read_only=True)["Sleepers"]
    rows = list(sheet.iter_rows(values_only=True))
    header = next(i for i, row in enumerate(rows) if row and row[0] == "row")
    data = rows[header + 1:]
    assert [row[1] for row in data] == results.number.tolist()
    assert [row[3] for row in data] == results.columns["station_m"].tolist()
