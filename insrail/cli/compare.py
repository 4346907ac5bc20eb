"""Compare repeated surveys of the same track (repeatability, as in the thesis's section 5.4.2).

Reads the processed results of the named surveys (default: every survey of the project; the
first is the reference), aligns them by chainage and writes PROJECT/results/repeatability.csv
(per sleeper, each run minus the reference, per parameter) and repeatability.toml (mean, std,
RMS, 95th percentile and maximum of the differences). Process the surveys first. Exit code 0,
1 on bad input (missing results, unknown survey), 2 on bad usage.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("project", type=Path, help="project folder (with project.toml) or project .toml file")
    p.add_argument("--surveys", nargs="+", metavar="NAME", help="surveys to compare (the first is the reference)")


def run(args: argparse.Namespace) -> int:
    from insrail.project import load_project
    from insrail.project.compare import compare_surveys

    project = load_project(args.project)
    names = args.surveys or [s.name for s in project.surveys]
    unknown = [n for n in names if n not in {s.name for s in project.surveys}]
    if unknown:
        print(f"insrail: {project.path}: no survey named {', '.join(unknown)}", file=sys.stderr)
        return 1
    if len(names) < 2:
        print("insrail compare: needs at least two surveys", file=sys.stderr)
        return 2
    result, path = compare_surveys(project, names)
    print(f"Repeatability against {result.reference} ({result.station_m.size} sleepers): {path.resolve()}")
    print(f"  {'parameter':<44} {'run':<16} {'mean mm':>8} {'std mm':>7} {'95% mm':>7} {'max mm':>7}")
    for parameter in result.parameters:
        for k, run_name in enumerate(result.compared):
            print(f"  {parameter.name.removesuffix('_mm'):<44} {run_name:<16} {1e3 * parameter.mean[k]:8.3f} "
                  f"{1e3 * parameter.std[k]:7.3f} {1e3 * parameter.p95_abs[k]:7.3f} {1e3 * parameter.max_abs[k]:7.3f}")
    return 0
