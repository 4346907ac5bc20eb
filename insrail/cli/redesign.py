"""Re-design a processed ballasted survey for a tamping machine: lift and slew per sleeper.

The least total movement after which the track passes the tolerance profile's chord checks, within
project.toml's [redesign] (lift_only, min_lift_mm, max_lift_mm, max_slew_mm, margin_mm, fix_events,
[[redesign.fixed]] from_m/to_m/tolerance_mm; turnouts, level crossings and bridges of the events are
fixed by default; docs/tamping.md). Writes PROJECT/results/<survey>/redesign/: tamping.csv (station,
K-chainage, lift left/right, slew, cant, marks), design.csv and design.xml (the line fitted to the track
after the job, usable as the next survey's design), exceedances_after.csv and summary.toml. Exit code 0
when written (stretches that cannot pass are listed, not an error), 1 on missing results or bad input.
"""

from __future__ import annotations

import argparse
from pathlib import Path


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("project", type=Path, help="project folder (with project.toml) or project .toml file")
    p.add_argument("--survey", action="append", metavar="NAME", help="survey to re-design (default: every survey)")


def run(args: argparse.Namespace) -> int:
    from insrail.project import load_project
    from insrail.project.lock import project_run
    from insrail.project.redesign import run_redesign

    project = load_project(args.project)
    names = args.survey or [s.name for s in project.surveys]
    for name in names:
        project.survey(name)  # an unknown name is an error naming the surveys
        with project_run(project.folder, [name]):
            run = run_redesign(project, name)
        movement, count = run.summary["movement"], run.summary["exceedances"]
        print(f"{name} redesign: {run.folder.resolve()}")
        print(f"  largest lift {movement['largest_lift_mm']:.1f} mm at {movement['largest_lift_at_m']:.1f} m, "
              f"largest slew {movement['largest_slew_mm']:.1f} mm at {movement['largest_slew_at_m']:.1f} m, "
              f"{movement['sleepers_moved']} sleepers moved, total movement {movement['total_movement_m']:.3f} m")
        print(f"  exceedances of {run.summary['profile']}: {count['before']} before, {count['after']} after the job")
        for stretch in run.summary["active"]:
            print(f"  bound holds: {stretch['what']} {stretch['from_m']:.1f}-{stretch['to_m']:.1f} m")
        for stretch in run.summary["cannot_pass"]:
            print(f"  warning: cannot pass under the constraints: {stretch['what']} {stretch['from_m']:.1f}-"
                  f"{stretch['to_m']:.1f} m (peak {stretch['value_mm']:.2f} mm)")
        if run.summary["uncertain"]:
            print(f"  warning: {len(run.summary['uncertain'])} stretches pass after the job by less than the survey's "
                  "uncertainty of the check (three stated 1-sigma): the true track there may not pass "
                  "(summary.toml [[uncertain]])")
        for item in run.summary["not_assessed"]:
            print(f"  warning: not assessed after the job: {item['check']} {item['direction']}".rstrip()
                  + f" (stated 1-sigma {item['sigma_mm']:.2f} mm against the limit {item['limit_mm']:.1f} mm) over "
                  + ", ".join(f"{a:.0f}-{b:.0f} m" for a, b in item["stretches_m"]))
        if run.fit_problem:
            print(f"  warning: {run.fit_problem}")
    return 0
