"""The tamping re-design on the simulated ballasted survey, checked on the simulator's true track.

    python benchmarks/tamping.py [--workdir DIR] [--seed N] [--profile NAME]

Simulates and processes the ``ballasted`` demo project into ``DIR`` unless a processed one is there
(``insrail demo --preset ballasted``), re-designs it (``insrail redesign``, timed), and prints the
movements (largest lift and slew, sleepers moved, total), where the bounds hold, the stretches that
cannot pass, and the profile's exceedances before and after the job on the measured track and on
the TRUE track (the simulator's rails moved by the same amounts) outside the events the profile
does not judge (``--profile``: re-design against another tolerance profile than the project's,
e.g. the default high-speed ``cn_hsr_ballastless`` with its 300 m / 150 m check). Then processes the survey again with the re-designed line (redesign/design.xml) as
its design: the deviations from it are the corrections with the sign turned, to the fit's residual.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--workdir", type=Path, default=Path(tempfile.gettempdir()) / "insrail-tamping-benchmark")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--profile", help="tolerance profile to re-design against (default: the project's)")
    args = parser.parse_args()

    from insrail.project import load_project, process
    from insrail.project.model import save_project
    from insrail.project.redesign import run_redesign
    from insrail.project.results import load_results
    from insrail.sim.evaluation import truth_rail_deviations
    from insrail.sim.truth import read_sleeper_truth
    from insrail.track.exceedance import SleeperGeometry, assess
    from insrail.track.redesign import moved
    from insrail.track.tolerance import load_tolerance_profile

    project_dir = args.workdir
    if not (project_dir / "results" / "ballasted" / "summary.toml").is_file():
        subprocess.run([sys.executable, "-m", "insrail", "demo", "--preset", "ballasted", "--seed", str(args.seed),
                        "--out", str(project_dir)], check=True, stdout=subprocess.DEVNULL)
    project = load_project(project_dir)
    saved = project
    if args.profile:
        project = replace(project, tolerance_profile=args.profile)
    started, cpu = time.perf_counter(), time.process_time()
    run = run_redesign(project, "ballasted")
    wall, cpu = time.perf_counter() - started, time.process_time() - cpu
    summary = run.summary
    movement = summary["movement"]
    print(f"re-design of 'ballasted' ({project.tolerance_profile}), {len(run.result.station_m)} sleepers: "
          f"{wall:.1f} s wall, {cpu:.1f} s CPU (line fit included)")
    print(f"  largest lift {movement['largest_lift_mm']:.1f} mm at {movement['largest_lift_at_m']:.1f} m, largest "
          f"slew {movement['largest_slew_mm']:.1f} mm at {movement['largest_slew_at_m']:.1f} m, smallest lift "
          f"{movement['smallest_lift_mm']:.1f} mm; {movement['sleepers_moved']} sleepers moved; total "
          f"{movement['total_movement_m']:.3f} m")
    for stretch in summary["active"]:
        print(f"  bound holds: {stretch['what']} {stretch['from_m']:.1f}-{stretch['to_m']:.1f} m")
    print(f"  chord values held at their limit: {summary['binding_check_values']}")
    for stretch in summary["cannot_pass"]:
        print(f"  cannot pass: {stretch['what']} {stretch['from_m']:.1f}-{stretch['to_m']:.1f} m ({stretch['value_mm']} mm)")
    held = ", ".join(f"{h['check']} {h['direction']} {h['margin_mm']:.2f} mm".replace("  ", " ")
                     for h in summary["settings"]["held_inside_mm"])
    print(f"  held inside the limits by: {held}")
    print(f"  passes by less than its uncertainty: {len(summary['uncertain'])} stretches")
    for item in summary["not_assessed"]:
        print(f"  not assessed: {item['check']} {item['direction']} (1-sigma {item['sigma_mm']:.2f} mm against "
              f"{item['limit_mm']:.1f} mm) over {item['stretches_m']}")
    rows = run.rows
    lifts = np.array([[r.lift_left_mm, r.lift_right_mm] for r in rows])
    slews = np.array([r.slew_mm for r in rows])
    fixed = run.result.fixed
    inside = max(float(np.nanmax(np.abs(run.result.lift_m[fixed]))), float(np.nanmax(np.abs(run.result.slew_m[fixed]))))
    print(f"  tamping.csv: {len(rows)} rows, lift min {lifts.min():.1f} mm (lift only: >= 0), |slew| max "
          f"{np.abs(slews).max():.1f} mm (max {run.result.settings.max_slew_m * 1e3:.0f}); largest movement inside the "
          f"fixed stretches ({int(fixed.sum())} sleepers): {1e3 * inside:.2f} mm")

    stored = load_results(project_dir, "ballasted")
    profile = load_tolerance_profile(project.resource(project.tolerance_profile))
    truth = read_sleeper_truth(project_dir / "surveys" / "ballasted" / "truth" / "sleepers.csv")
    station = stored.columns["station_m"]
    lateral, vertical, gauge, cant, design_cant = truth_rail_deviations(truth, station)
    judged = stored.columns["valid"] > 0
    true = SleeperGeometry.from_arrays(station, lateral, vertical, gauge, cant, design_cant, valid=judged)
    before = assess(true, profile)
    after = assess(moved(true, run.result.lift_m, run.result.slew_m), profile)
    print(f"  exceedances, measured track: {summary['exceedances']['before']} before, {summary['exceedances']['after']} after "
          f"(the checks the survey assesses)")
    print(f"  exceedances, TRUE track moved by the amounts: {len(before.exceedances)} before, {len(after.exceedances)} after")
    listed = [(s.what.split(" ")[0], s.station_from_m, s.station_to_m, "cannot pass") for s in run.result.cannot_pass]
    listed += [(s.what.split(" ")[0], s.station_from_m, s.station_to_m, "uncertain") for s in run.result.uncertain]
    listed += [(item["check"], a, b, "not assessed") for item in summary["not_assessed"] for a, b in item["stretches_m"]]
    near_m = 2.5  # a knot spacing: the true track's run of a value may start a little beside the measured one's
    where = {}
    for e in after.exceedances:
        hit = next((kind for check, a, b, kind in listed
                    if check == e.check and a - near_m <= e.station_to_m and e.station_from_m <= b + near_m), None)
        where.setdefault(hit or "NOT LISTED", []).append(e)
    print("  of these, in a listed stretch of the same check: "
          + ", ".join(f"{kind} {len(found)}" for kind, found in sorted(where.items())))
    for e in where.get("NOT LISTED", []):
        print(f"    not listed: {e.check} {e.rail} {e.direction} {e.station_from_m:.1f}-{e.station_to_m:.1f} m: "
              f"{1e3 * e.peak:.2f} mm (limit {1e3 * e.limit:.1f})")

    # the re-designed line as the design of the next survey (here: the same run processed again)
    design = project_dir / "design_after_tamping.xml"
    shutil.copyfile(run.folder / "design.xml", design)
    next_project = replace(project, design=design.name)
    save_project(next_project)
    try:
        results = process(next_project, "ballasted")
    finally:
        save_project(saved)
    table = results.table
    corrections = np.interp(table.station_m, run.result.station_m, run.result.lift_m.mean(axis=1))
    residual = table.vertical_deviation_m.mean(axis=1) + corrections
    slew = np.interp(table.station_m, run.result.station_m, run.result.slew_m)
    lateral_residual = table.lateral_deviation_m.mean(axis=1) + slew
    ok = np.isfinite(residual) & np.isfinite(lateral_residual)
    print(f"  next survey on design_after_tamping.xml: {ok.sum()} sleepers; deviation + correction RMS vertical "
          f"{1e3 * np.sqrt(np.mean(residual[ok] ** 2)):.2f} mm, lateral {1e3 * np.sqrt(np.mean(lateral_residual[ok] ** 2)):.2f} mm "
          "(the line fit's residual: the design is smooth, the moved track keeps what the profile allows)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
