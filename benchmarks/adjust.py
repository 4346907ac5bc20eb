"""Adjustment amounts on the `short` and `long` demo projects: exceedances before and after, movement, time.

    python benchmarks/adjust.py [--workdir DIR] [--skip-long] [--strategy least_movement|guiding_rail_first]
                                [--threshold-mm 2]

For each scenario the demo project is simulated and processed into ``DIR/<scenario>`` unless a
processed one is there already (the `long` one takes many minutes: keep the folder and pass it
again). The sleeper geometry is read back from the results' sleepers.csv (as any later process
sees it), the amounts are optimised again (timed) and the adjusted geometry is re-assessed
against every check of the project's tolerance profile. Prints per check channel the
exceedance runs before and after (and how many of the after runs are new), the total movement,
the sleepers to work on (any amount of at least one step), the sleepers still failing with
their reasons, and the optimisation's wall and CPU time (on a loaded machine the wall time says
little). Target (issue 19): `long` <= 20 s. Each scenario runs twice: with the default action
threshold (one fastener step: every amount) and with ``--threshold-mm`` (each amount 0 or at least
that; the sleepers left with a smaller amount the checks need are counted).
"""

from __future__ import annotations

import argparse
import tempfile
import time
from collections import Counter
from pathlib import Path

import numpy as np


def ensure_processed(name: str, workdir: Path) -> Path:
    from insrail.project import load_project, process
    from insrail.project.demo import project_for_simulated_survey
    from insrail.sim.scenario import preset
    from insrail.sim.simulate import simulate

    root = workdir / name
    if (root / "results" / name / "sleepers.csv").is_file():
        return root
    survey = root / "surveys" / name
    print(f"simulating and processing {name} into {root} (minutes)", flush=True)
    simulate(preset(name), seed=1, out_dir=survey, overwrite=True, imu_format="npy")
    project_for_simulated_survey(root, survey, name=f"benchmark {name}")
    process(load_project(root), name)
    return root


def stored_geometry(root: Path, name: str):
    from insrail.project.results import load_results
    from insrail.track.exceedance import SleeperGeometry

    results = load_results(root, name)
    c = results.columns
    lateral = np.column_stack([c["lateral_deviation_left_mm"], c["lateral_deviation_right_mm"]]) * 1e-3
    vertical = np.column_stack([c["vertical_deviation_left_mm"], c["vertical_deviation_right_mm"]]) * 1e-3
    return SleeperGeometry.from_arrays(c["station_m"], lateral, vertical, c["gauge_mm"] * 1e-3, c["cant_mm"] * 1e-3,
                                       c["design_cant_mm"] * 1e-3, valid=c["valid"] > 0, sleeper_number=results.number)


def channel(e) -> str:
    return "/".join(p for p in (e.check, e.rail if e.rail != "track" else "", e.direction) if p)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workdir", type=Path, help="where the demo projects are (default: a temporary folder)")
    parser.add_argument("--skip-long", action="store_true", help="only the short survey")
    parser.add_argument("--strategy", default="least_movement")
    parser.add_argument("--threshold-mm", type=float, default=2.0,
                        help="the action threshold of the second run (0: only the default)")
    args = parser.parse_args()

    from insrail.project import load_project
    from insrail.track.adjustment import load_fastener_type
    from insrail.track.tolerance import load_tolerance_profile

    with tempfile.TemporaryDirectory() as tmp:
        workdir = args.workdir or Path(tmp)
        for name in ["short"] if args.skip_long else ["short", "long"]:
            root = ensure_processed(name, workdir)
            project = load_project(root)
            profile = load_tolerance_profile(project.resource(project.tolerance_profile))
            fastener = load_fastener_type(project.resource(project.fastener))
            geometry = stored_geometry(root, name)
            for threshold_mm in [None] + ([args.threshold_mm] if args.threshold_mm else []):
                run(name, geometry, profile, fastener, args.strategy, threshold_mm)


def run(name, geometry, profile, fastener, strategy, threshold_mm) -> None:
    from insrail.track.adjustment import REASONS, below_threshold_count, optimise_amounts, reassess, threshold_steps
    from insrail.track.exceedance import assess

    threshold_m = None if threshold_mm is None else 1e-3 * threshold_mm
    before = assess(geometry, profile)
    start, start_cpu = time.perf_counter(), time.process_time()
    lateral, vertical = optimise_amounts(geometry, profile, fastener, strategy=strategy, threshold_m=threshold_m)
    elapsed, cpu = time.perf_counter() - start, time.process_time() - start_cpu
    after, adjustment = reassess(geometry, lateral, vertical, profile, fastener)
    counts_before = Counter(channel(e) for e in before.exceedances)
    counts_after = Counter(channel(e) for e in after.exceedances)
    failing_before = {channel(e): np.zeros(geometry.station_m.size, bool) for e in before.exceedances}
    for e in before.exceedances:
        failing_before[channel(e)][e.first_index:e.last_index + 1] = True
    new = Counter(channel(e) for e in after.exceedances
                  if not failing_before.get(channel(e), np.zeros(1, bool))[e.first_index:e.last_index + 1].any())
    threshold = 1e3 * fastener.step_m * threshold_steps(fastener, threshold_m)
    print(f"\n{name}: {geometry.station_m.size} sleepers, profile {profile.name}, fastener {fastener.name}, "
          f"strategy {strategy}, action threshold {threshold:g} mm")
    print(f"  {'channel':<38} {'before':>7} {'after':>7} {'new':>5}")
    for key in sorted(set(counts_before) | set(counts_after)):
        print(f"  {key:<38} {counts_before[key]:7d} {counts_after[key]:7d} {new[key]:5d}")
    print(f"  {'all channels':<38} {sum(counts_before.values()):7d} {sum(counts_after.values()):7d} "
          f"{sum(new.values()):5d}")
    moved = np.any(np.abs(lateral) > 1e-9, axis=1) | np.any(np.abs(vertical) > 1e-9, axis=1)
    reasons = Counter()
    for codes in (adjustment.reason_lateral, adjustment.reason_vertical):
        for bit, text in REASONS.items():
            reasons[text] += int(np.any(codes & bit, axis=1).sum())
    failing = int(np.any(adjustment.unresolved_lateral | adjustment.unresolved_vertical, axis=1).sum())
    print(f"  total movement {1e3 * adjustment.total_movement_m:.0f} mm, sleepers to work on {int(moved.sum())} "
          f"({below_threshold_count(adjustment, fastener, threshold_m)} with an amount below the threshold), "
          f"still failing {failing} ({', '.join(f'{k}: {v}' for k, v in reasons.items() if v) or 'none'}), "
          f"optimisation {elapsed:.1f} s wall, {cpu:.1f} s CPU (both directions in parallel threads)", flush=True)


if __name__ == "__main__":
    main()
