"""Compare repeated surveys of the same track (repeatability, as in the thesis's section 5.4.2).

Reads the processed results of the named surveys (default: every survey of the project; the
first is the reference), aligns them by chainage and writes PROJECT/results/repeatability.csv
(per sleeper, each run minus the reference, per parameter) and repeatability.toml (mean, std,
RMS, 95th percentile and maximum of the differences). Process the surveys first. Exit code 0,
1 on bad input (missing results, unknown survey), 2 on bad usage.

With ``--levelling`` and/or ``--points`` one survey is checked against an independent reference
instead (thesis §5.4.3, :mod:`insrail.project.external_check`): a levelling line and another
trolley's per-sleeper coordinates, the differences against the stated σ into
PROJECT/results/external_<survey>_<file>.csv and .toml. Exit code 0 when the survey agrees with
every reference, 3 when it does not (the figures say where), 1 on bad input.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("project", type=Path, help="project folder (with project.toml) or project .toml file")
    p.add_argument("--surveys", nargs="+", metavar="NAME", help="surveys to compare (the first is the reference)")
    p.add_argument("--levelling", type=Path, metavar="FILE",
                   help="a levelling line (point, chainage, H) to check the one survey named by --surveys against")
    p.add_argument("--levelling-sigma-mm", type=float, metavar="S", help="the levelling's stated 1-sigma per point [mm]")
    p.add_argument("--levelling-rail", choices=("left", "right", "centre"), help="what was levelled")
    p.add_argument("--points", type=Path, metavar="FILE",
                   help="another trolley's per-sleeper coordinates (point, chainage, E, N, H) to check against")
    p.add_argument("--points-sigma-mm", type=float, metavar="S", help="their stated 1-sigma per coordinate [mm]")
    p.add_argument("--points-rail", choices=("left", "right", "centre"), help="which rail (or the centreline) they are")


def _external(args: argparse.Namespace, project, names: list[str]) -> int:
    """The one survey ``names`` against the levelling line and/or the other trolley's points."""
    from insrail.io.external import read_levelling_line, read_trolley_points
    from insrail.project.external_check import check_against, check_files
    from insrail.project.results import load_results

    if len(names) != 1:
        print("insrail compare: --levelling and --points check one survey: name it with --surveys NAME", file=sys.stderr)
        return 2
    references = []
    for option, reader in (("levelling", read_levelling_line), ("points", read_trolley_points)):
        path = getattr(args, option)
        if path is None:
            continue
        sigma, rail = getattr(args, f"{option}_sigma_mm"), getattr(args, f"{option}_rail")
        if sigma is None or rail is None or not sigma > 0:
            print(f"insrail compare: --{option} needs --{option}-sigma-mm (the reference's stated 1-sigma, > 0) and "
                  f"--{option}-rail (left, right or centre)", file=sys.stderr)
            return 2
        references.append((reader(path), rail, 1e-3 * sigma))
    results = load_results(project.folder, names[0])
    agrees = True
    for reference, rail, sigma in references:
        check = check_against(results, reference, rail, sigma)
        csv_path, _ = check_files(project.folder, check)
        print(f"{names[0]} against {reference.source} ({rail}, reference 1-sigma {1e3 * sigma:.2f} mm): "
              f"{len(reference) - check.not_covered} of {len(reference)} points compared: {csv_path.resolve()}")
        print(f"  {'component':<10} {'mean mm':>8} {'RMS mm':>7} {'max mm':>7} {'<=2σ':>6} {'<=3σ':>6}")
        for s in check.statistics():
            verdict = "agrees with the stated sigma" if s.agrees else "DOES NOT AGREE with the stated sigma"
            agrees &= s.agrees
            print(f"  {s.component:<10} {1e3 * s.mean_m:8.3f} {1e3 * s.rms_m:7.3f} {1e3 * s.max_abs_m:7.3f} "
                  f"{100 * s.within_2sigma:5.1f}% {100 * s.within_3sigma:5.1f}%  {verdict}")
    return 0 if agrees else 3


def run(args: argparse.Namespace) -> int:
    from insrail.project import load_project
    from insrail.project.compare import compare_surveys

    project = load_project(args.project)
    names = args.surveys or [s.name for s in project.surveys]
    unknown = [n for n in names if n not in {s.name for s in project.surveys}]
    if unknown:
        print(f"insrail: {project.path}: no survey named {', '.join(unknown)}", file=sys.stderr)
        return 1
    if args.levelling is not None or args.points is not None:
        return _external(args, project, names)
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
