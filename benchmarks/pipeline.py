"""End-to-end pipeline time and peak memory: the demo project for the `short` and `long` surveys.

    python benchmarks/pipeline.py [--workdir DIR] [--skip-long]

For each scenario: simulates the survey into a demo project (in its own process), then, in a
fresh process, processes it (fusion, coordinates, track, assessment, adjustment) and processes
it again (fusion from the cache). Prints wall times and the processing process's peak memory.
Targets (issue 7): `long` <= 90 s wall and <= 2 GB.
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
    from insrail.project import load_project, process

    project = load_project(Path(workdir) / name)
    start = time.perf_counter()
    results = process(project, name)
    first = time.perf_counter() - start
    start = time.perf_counter()
    process(project, name)
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
        print(f"{'scenario':<9} {'simulate s':>10} {'process s':>10} {'cached s':>9} {'peak GB':>8} "
              f"{'sleepers':>9} {'exceed.':>8}")
        context = mp.get_context("spawn")
        for name in scenarios:
            simulated = in_child(context, simulate_project, name, workdir)
            first, second, peak_gb, sleepers, exceedances = in_child(context, process_project, name, workdir)
            print(f"{name:<9} {simulated:>10.1f} {first:>10.1f} {second:>9.1f} {peak_gb:>8.2f} {sleepers:>9d} "
                  f"{exceedances:>8d}")

if __name__ == "__main__":
    main()
