"""Reports older than their results: `insrail report --check`, the warning of `insrail report` and of
`insrail process`, the core function the GUI asks; `insrail report --help` says where reports go."""

import os

import pytest
from report_support import SURVEY, processed_project

import insrail.cli.process as process_cli
import insrail.project
from insrail.cli.main import main
from insrail.project import save_project
from insrail.project.results import load_results, report_path
from insrail.report import report_is_stale, stale_reports


@pytest.fixture()
def project(tmp_path):
    project = processed_project(tmp_path, n=120)
    (tmp_path / "surveys" / SURVEY).mkdir(parents=True, exist_ok=True)
    (tmp_path / "surveys" / SURVEY / "survey.toml").write_text("")
    save_project(project)
    return project


def reprocessed(project, earlier_s: float = 60.0) -> None:
    """The survey processed again after the reports were written: the reports are dated before its results
    (rather than the results in the future, so that a report written now is newer)."""
    written = (project.folder / "results" / SURVEY / "summary.toml").stat().st_mtime
    for suffix in ("xlsx", "pdf"):
        path = report_path(project.folder, SURVEY, suffix)
        if path.exists():
            os.utime(path, (written - earlier_s, written - earlier_s))


def test_a_report_older_than_its_results_is_found_and_check_says_so(project, capsys):
    xlsx, pdf = (report_path(project.folder, SURVEY, suffix) for suffix in ("xlsx", "pdf"))
    assert not report_is_stale(pdf, project.folder, SURVEY)  # not written yet: nothing out of date
    assert main(["report", str(project.folder), "--check"]) == 0
    assert "reports/track_geometry_run1.pdf: not written" in capsys.readouterr().out
    assert main(["report", str(project.folder)]) == 0
    capsys.readouterr()
    assert stale_reports(project.folder, SURVEY) == [] and not report_is_stale(xlsx, project.folder, SURVEY)
    assert main(["report", str(project.folder), "--check"]) == 0
    assert capsys.readouterr().out.count("up to date") == 2

    reprocessed(project)
    assert report_is_stale(xlsx, project.folder, SURVEY) and report_is_stale(pdf, project.folder, SURVEY)
    assert stale_reports(project.folder, SURVEY) == [xlsx, pdf]
    assert main(["report", str(project.folder), "--check"]) == 1
    out = capsys.readouterr().out
    assert "reports/track_geometry_run1.xlsx: OLDER than the results" in out and out.count("OLDER") == 2

    # writing only the workbook elsewhere leaves the default reports stale, and says so
    assert main(["report", str(project.folder), "--pdf", str(project.folder / "elsewhere.pdf")]) == 0
    err = capsys.readouterr().err
    assert "reports/track_geometry_run1.xlsx, reports/track_geometry_run1.pdf are older than these results" in err
    # writing them again brings them up to date
    assert main(["report", str(project.folder)]) == 0
    assert "older than" not in capsys.readouterr().err
    assert main(["report", str(project.folder), "--check"]) == 0


def test_insrail_process_says_the_reports_are_now_out_of_date(project, capsys, monkeypatch):
    assert main(["report", str(project.folder)]) == 0
    capsys.readouterr()

    def process_again(project_, name, progress=None):  # what the pipeline leaves: results newer than the reports
        reprocessed(project_, earlier_s=5.0)
        return load_results(project_.folder, name)

    monkeypatch.setattr(insrail.project, "process", process_again)
    monkeypatch.setattr(process_cli, "describe", lambda results, checks=(): [f"Survey {results.survey}"])
    assert main(["process", str(project.folder)]) == 0
    out = capsys.readouterr().out
    assert "warning: reports/track_geometry_run1.xlsx, reports/track_geometry_run1.pdf are older than these results" \
        in out and "run `insrail report`" in out


def test_report_help_says_where_the_reports_go(capsys):
    with pytest.raises(SystemExit):
        main(["report", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "PROJECT/reports/" in text and "--check" in text
    assert "into that results folder" not in text
