"""The [report] table of project.toml: what the reports' first page names and the workbook's paper;
validated like the rest of the file, round-tripped, absent from a project that does not use it."""

import datetime
import tomllib
from dataclasses import replace

import pytest
from report_support import processed_project

from insrail.project import load_project, save_project
from insrail.project.model import ProjectError, ReportSettings

REPORT = {"client": "China Railway Wuhan Group", "line_section": "Wuhan - Xianning K12 - K18", "track_name": "down line",
          "operator": "Li Wei", "checked_by": "Zhang San", "approved_by": "Wang Wu", "trolley": "GRP 5000 no. 117",
          "trolley_calibrated": datetime.date(2026, 3, 14), "imu": "iNAV-RQH no. 2231",
          "imu_calibrated": datetime.date(2025, 11, 2), "paper": "A4"}


@pytest.fixture()
def project(tmp_path):
    project = processed_project(tmp_path, n=80)
    (tmp_path / "surveys" / "run1").mkdir(parents=True, exist_ok=True)
    (tmp_path / "surveys" / "run1" / "survey.toml").write_text("")
    return project


def test_report_settings_round_trip_and_read_as_toml_dates(project):
    project = replace(project, report=ReportSettings(**REPORT))
    path = save_project(project)
    document = tomllib.loads(path.read_text())
    assert document["report"]["trolley_calibrated"] == datetime.date(2026, 3, 14)
    assert load_project(path).report == project.report
    # a date written as text is read as the date
    path.write_text(path.read_text().replace("trolley_calibrated = 2026-03-14", 'trolley_calibrated = "2026-03-14"'))
    assert load_project(path).report.trolley_calibrated == datetime.date(2026, 3, 14)


def test_a_project_without_the_table_writes_none_and_prints_on_a3(project):
    path = save_project(project)
    assert "report" not in tomllib.loads(path.read_text())
    assert load_project(path).report == ReportSettings() and ReportSettings().paper == "A3"


@pytest.mark.parametrize("entry,key,message", [
    ('paper = "letter"', "report.paper", "expected one of A3, A4"),
    ('imu_calibrated = "14.3.2026"', "report.imu_calibrated", "expected a date like 2026-03-14"),
    ("trolley_calibrated = 2026", "report.trolley_calibrated", "expected a date"),
    ("operator = 7", "report.operator", "expected text"),
    ('signed_by = "x"', "report.signed_by", "unknown key"),
])
def test_bad_report_entries_are_named_with_their_key(project, entry, key, message):
    path = save_project(project)
    path.write_text(path.read_text() + f"\n[report]\n{entry}\n")
    with pytest.raises(ProjectError) as error:
        load_project(path)
    assert any(p.startswith(f"{key}: ") and message in p for p in error.value.problems), error.value.problems
