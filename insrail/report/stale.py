"""Whether a report still describes the results it was written from.

A report is a copy of a survey's results at the time it was written. Processing the survey again
(new data, a changed setting, a new tolerance profile) replaces ``results/<survey>/`` whole
(:func:`insrail.project.results.write_results`), and the reports in ``reports/`` then describe
results that no longer exist. A report is *stale* when it was written before the current results'
``summary.toml`` (the last file of a result folder, written once per processing). ``insrail report``,
``insrail process`` and the GUI ask here; nothing else decides it.
"""

from __future__ import annotations

from pathlib import Path

from insrail.project.results import RESULTS_FOLDER, SUMMARY_FILE, report_path

#: The report kinds written by default (``insrail report``, the GUI's export).
REPORT_SUFFIXES = ("xlsx", "pdf")


def results_written_s(project_folder: Path | str, survey: str) -> float | None:
    """When the survey's current results were written (modification time, s), None without results."""
    summary = Path(project_folder) / RESULTS_FOLDER / survey / SUMMARY_FILE
    try:
        return summary.stat().st_mtime
    except FileNotFoundError:
        return None


def report_is_stale(report: Path | str, project_folder: Path | str, survey: str) -> bool:
    """True when ``report`` exists and was written before the survey's current results (processed
    again since). A missing report or missing results are not stale: there is nothing out of date."""
    written = results_written_s(project_folder, survey)
    try:
        return written is not None and Path(report).stat().st_mtime < written
    except FileNotFoundError:
        return False


def stale_reports(project_folder: Path | str, survey: str) -> list[Path]:
    """The survey's reports at their default places (``reports/track_geometry_<survey>.*``) that are stale."""
    return [path for path in (report_path(Path(project_folder), survey, suffix) for suffix in REPORT_SUFFIXES)
            if report_is_stale(path, project_folder, survey)]


def stale_report_lines(project_folder: Path | str, survey: str, indent: str = "  ") -> list[str]:
    """What a command says about the survey's stale reports ([] when none)."""
    stale = stale_reports(project_folder, survey)
    if not stale:
        return []
    names = ", ".join(str(path.relative_to(Path(project_folder))) for path in stale)
    one = len(stale) == 1
    return [(f"{indent}warning: {names} {'is' if one else 'are'} older than these results (written before the survey "
             f"was processed again): run `insrail report` to bring {'it' if one else 'them'} up to date")]
