"""End-to-end pipeline time and peak memory: the demo project for the `short` and `long` surveys.

    python benchmarks/pipeline.py [--workdir DIR] [--skip-long]

For each scenario: simulates the survey into a demo project (in its own process), then, in a
fresh process, processes it (fusion, coordinates, track, assessment, adjustment) and processes
it again after the surveyor edited the tolerance profile (a copy of the default with a band-passed
D1 check added: fusion, track and adjustment from the cache, a new assessment and result files). Prints both wall times, their ratio and the processing process's peak memory.
Targets (issue 7): `long` <= 90 s wall and <= 2 GB; the rerun >= 10x faster.
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import resource
import tempfile
import time
from pathlib import Path


def simulate_project(name: str, workdir: str, queue) -> None:
    from insrail.project.demo import project_for_simulated_survey
    from insrail.sim.scenario import preset
    from insrail.sim.simulate import simulate

    root = Path(workdir) / name
    survey = root / "surveys" / name
    start = time.perf_counter()
    simulate(preset(name), seed=1, out_dir=survey, overwrite=True, imu_format="npy")
    project_for_simulated_survey(root, survey, name=f"benchmark {name}")
    queue.put(time.perf_counter() - start)


def process_project(name: str, workdir: str, queue) -> None:
    from dataclasses import replace

    from insrail.project import load_project, process
    from insrail.resources import resources_dir

    project = load_project(Path(workdir) / name)
    default = (resources_dir() / "tolerance_profiles" / f"{project.tolerance_profile}.toml").read_text(encoding="utf-8")
    # a check the adjustment does not hold (a changed chord or gauge limit re-optimises the amounts)
    edited = default + '\n[checks.d1_peak]\nkind = "band_peak"\nband = "D1"\nmax_abs_mm = 0.5\n'
    (project.folder / "edited-tolerances.toml").write_text(edited, encoding="utf-8")
    start = time.perf_counter()
    results = process(project, name)
    first = time.perf_counter() - start
    start = time.perf_counter()
    process(replace(project, tolerance_profile="edited-tolerances.toml"), name)
    second = time.perf_counter() - start
    peak_gb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024**2  # kB on Linux
    queue.put((first, second, peak_gb, len(results.table), len(results.assessment.exceedances)))


def in_child(context, target, *args):
    """Run ``target`` in a fresh process (its peak memory is its own) and return what it reports."""
    queue = context.Queue()
    child = context.Process(target=target, args=(*args, queue))
    child.start()
    value = queue.get()
    child.join()
    return value


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workdir", type=Path, help="where to put the projects (default: a temporary folder)")
    parser.add_argument("--skip-long", action="store_true", help="only the short survey")
    args = parser.parse_args()
    scenarios = ["short"] if args.skip_long else ["short", "long"]
    with tempfile.TemporaryDirectory() as tmp:
        workdir = str(args.workdir or tmp)
        print(f"{'scenario':<9} {'simulate s':>10} {'process s':>10} {'rerun s':>8} {'ratio':>6} {'peak GB':>8} "
              f"{'sleepers':>9} {'exceed.':>8}")
        context = mp.get_context("spawn")
        for name in scenarios:
            simulated = in_child(context, simulate_project, name, workdir)
            first, second, peak_gb, sleepers, exceedances = in_child(context, process_project, name, workdir)
            print(f"{name:<9} {simulated:>10.1f} {first:>10.1f} {second:>8.2f} {first / second:>6.0f} {peak_gb:>8.2f} "
                  f"{sleepers:>9d} {exceedances:>8d}")

if __name__ == "__main__":
    main()
