"""Join the runs of a line section into one result, its workbook and its PDF report.

A section is a [[sections]] entry of PROJECT/project.toml (name, surveys, optional from_m/to_m,
overlap = "best" or "mean"); its surveys must be processed. Writes PROJECT/results/<section>/
(sleepers.csv with continuous numbering and the source run of every row, exceedances.csv,
quality.csv, summary.toml with the overlaps' run-to-run differences) and the reports
PROJECT/reports/track_geometry_<section>.xlsx and .pdf. Export it with
`insrail export PROJECT --section NAME`. Exit code 0 when written, 1 on missing results or bad input.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from insrail.cli.progressbar import TerminalProgress


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("project", type=Path, help="project folder (with project.toml) or project .toml file")
    p.add_argument("--section", action="append", metavar="NAME", help="section to join (default: every section)")
    p.add_argument("--no-reports", action="store_true", help="join only; write no workbook and PDF")


def section_names(project, given: list[str] | None) -> list[str] | None:
    """The sections to join (``given``, default every section), or None after naming on stderr what is
    wrong (no sections, or an unknown name)."""
    names = given or [s.name for s in project.sections]
    if not names:
        print(f"insrail: {project.path}: no [[sections]] defined", file=sys.stderr)
        return None
    known = {s.name for s in project.sections}
    unknown = [n for n in names if n not in known]
    if unknown:
        print(f"insrail: {project.path}: no section named {', '.join(unknown)} (sections: "
              f"{', '.join(sorted(known)) or 'none'})", file=sys.stderr)
        return None
    return names


def show_section(result) -> None:
    """The joined section's sleepers, overlaps and own warnings (the runs' were said by their processing), on stdout."""
    print(f"section {result.name}: {result.summary['track']['sleepers']} sleepers from {', '.join(result.summary['section']['surveys'])}"
          f"; results in {result.folder.resolve()}")
    for overlap in result.overlaps:
        parts = [f"{p.removesuffix('_mm')} {v['std_mm']:.2f}" for p, v in overlap["parameters"].items()
                 if "30m_5m" in p or "short_wave" in p]
        print(f"  overlap {overlap['runs'][0]}/{overlap['runs'][1]} {overlap['from_m']:.0f}-{overlap['to_m']:.0f} m, "
              f"{overlap['sleepers']} sleepers" + (f"; 30 m/5 m difference std (mm): {', '.join(parts)}" if parts else ""))
    for notice in result.notices:
        print(f"  warning: {notice.message}")


def write_section_reports(project, name: str) -> None:
    """The joined section's workbook and PDF (PROJECT/reports/track_geometry_<name>.xlsx and .pdf)."""
    from insrail.cli.report import default_paths
    from insrail.project.lock import project_run
    from insrail.project.results import load_results
    from insrail.report.both import write_both
    from insrail.report.section_page import section_page

    xlsx, pdf = default_paths(project.folder, name)
    with project_run(project.folder, [name]):  # no run replaces the results while they are read
        results = load_results(project.folder, name)
        bar = TerminalProgress(f"{name} workbook and pdf")
        written = write_both(project, results, xlsx, pdf, progress=bar, sections=(section_page,))
        bar.done()
    for path in written:
        print(f"{name}: {path.resolve()}")


def run(args: argparse.Namespace) -> int:
    from insrail.project import load_project
    from insrail.project.section import join_section

    project = load_project(args.project)
    names = section_names(project, args.section)
    if names is None:
        return 1
    for name in names:
        bar = TerminalProgress(f"section {name}")
        try:
            result = join_section(project, name, progress=bar)
        except ValueError as err:
            bar.stopped()
            # the join's own refusals name the section already (batch prints them as they are)
            message, prefix = str(err), f"section {name}: "
            print(f"insrail: {message if message.startswith(prefix) else prefix + message}", file=sys.stderr)
            return 1
        bar.done()
        show_section(result)
        if not args.no_reports:
            write_section_reports(project, name)
    return 0
