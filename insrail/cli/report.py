"""Write the crews' Excel workbook and the PDF survey report of processed surveys.

Reads PROJECT/project.toml and the results of `insrail process` in PROJECT/results/<survey>/.
Without --xlsx or --pdf both reports go into PROJECT/reports/ (track_geometry_<survey>.xlsx and
.pdf; processing the survey again leaves them there, and they are then older than the results:
`insrail report` and `insrail process` say so); with one or both options only the named files are
written (then --survey must name one survey if the project has several). --check writes nothing
and lists the reports in PROJECT/reports/ older than their results.
Exit code 0 when every report was written (with --check: none is out of date), 1 on missing
results, bad input or (with --check) an out-of-date report, 130 when cancelled.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from insrail.cli.progressbar import TerminalProgress
from insrail.io.atomic import NotARegularFile, check_output_path


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("project", type=Path, help="project folder (with project.toml) or project .toml file")
    p.add_argument("--survey", action="append", metavar="NAME",
                   help="survey to report (repeatable; default: every survey of the project)")
    p.add_argument("--xlsx", type=Path, metavar="FILE", help="write the Excel workbook to FILE")
    p.add_argument("--pdf", type=Path, metavar="FILE", help="write the PDF report to FILE")
    p.add_argument("--check", action="store_true",
                   help="write nothing; list the reports in PROJECT/reports/ older than their survey's results")


def default_paths(project_folder: Path, survey: str) -> tuple[Path, Path]:
    """Where the reports go without --xlsx/--pdf: ``<project>/reports/track_geometry_<survey>.*``."""
    from insrail.project.results import report_path

    xlsx, pdf = report_path(project_folder, survey, "xlsx"), report_path(project_folder, survey, "pdf")
    xlsx.parent.mkdir(exist_ok=True)
    return xlsx, pdf


def write_reports(project, survey: str, xlsx: Path | None, pdf: Path | None) -> list[Path]:
    """Write the requested reports of one processed survey with a progress bar; returns the files."""
    from insrail.project.lock import project_run
    from insrail.project.results import load_results
    from insrail.report.both import write_both

    written = []
    with project_run(project.folder, [survey]):  # no run replaces the results while they are read
        results = load_results(project.folder, survey)
        if xlsx is not None and pdf is not None:  # side by side where a second CPU is free
            bar = TerminalProgress(f"{survey} workbook and pdf")
            written = write_both(project, results, xlsx, pdf, progress=bar)
            bar.done()
            return written
        import insrail.report as reports  # a writer's module (openpyxl, reportlab) imported when it is used

        for path, writer, what in ((xlsx, "write_workbook", "workbook"), (pdf, "write_pdf", "pdf")):
            if path is not None:
                bar = TerminalProgress(f"{survey} {what}")
                written.append(getattr(reports, writer)(project, results, path, progress=bar))
                bar.done()
    return written


def _unwritable(path: Path | None) -> str | None:
    """Why a report cannot be written at ``path`` (None when it can, or when no path is given)."""
    if path is None:
        return None
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        return f"the folder {folder} does not exist"
    if path.is_dir():
        return "is a folder: give a file name"
    try:
        check_output_path(path)
    except NotARegularFile as error:  # a device or FIFO: refused now, not after building the report
        return error.strerror
    if not os.access(folder, os.W_OK | os.X_OK):
        return f"no permission to write in {folder}"
    return None


def run(args: argparse.Namespace) -> int:
    from insrail.cli.process import chosen_surveys
    from insrail.project import load_project
    from insrail.project.run_settings import settings_change_lines
    from insrail.report.stale import stale_report_lines

    project = load_project(args.project)
    names = chosen_surveys(project, args.survey)
    if names is None:
        return 1
    if args.check:
        return _check(project, names)
    explicit = args.xlsx is not None or args.pdf is not None
    for option, path in (("--xlsx", args.xlsx), ("--pdf", args.pdf)):
        problem = _unwritable(path)
        if problem:  # said before building anything
            print(f"insrail: {option} {path}: {problem}", file=sys.stderr)
            return 1
    if explicit and len(names) > 1:
        print(f"insrail: --xlsx/--pdf name one file: choose the survey with --survey ({', '.join(names)})", file=sys.stderr)
        return 1
    for name in names:
        xlsx, pdf = (args.xlsx, args.pdf) if explicit else default_paths(project.folder, name)
        try:
            written = write_reports(project, name, xlsx, pdf)
        except ValueError as err:  # tolerance profile changed since processing, unreadable settings file
            print(f"insrail: survey {name}: {err}", file=sys.stderr)
            return 1
        for path in written:
            print(f"{name}: {path.resolve()}")
        for line in settings_change_lines(project, name):  # the reports state the settings processed with
            print(f"{name}: warning: {line}", file=sys.stderr)
        for line in stale_report_lines(project.folder, name, indent=f"{name}: "):  # a default report not rewritten
            print(line, file=sys.stderr)
    return 0


def _check(project, names: list[str]) -> int:
    from insrail.project.results import report_path
    from insrail.report.stale import REPORT_SUFFIXES, report_is_stale, results_written_s

    out_of_date = 0
    for name in names:
        for suffix in REPORT_SUFFIXES:
            path = report_path(project.folder, name, suffix)
            if not path.exists():
                state = "not written"
            elif results_written_s(project.folder, name) is None:
                state = "no results (process the survey)"
            elif report_is_stale(path, project.folder, name):
                state, out_of_date = "OLDER than the results: run insrail report", out_of_date + 1
            else:
                state = "up to date"
            print(f"{name}: {path.relative_to(project.folder)}: {state}")
    return 1 if out_of_date else 0
