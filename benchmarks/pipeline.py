"""End-to-end pipeline time and peak memory: the demo project for the `short` and `long` surveys.

    python benchmarks/pipeline.py [--workdir DIR] [--skip-long]

For each scenario, in a fresh process: simulates the survey into a demo project (not timed as
processing), then processes it (fusion, coordinates, track, assessment, adjustment) and
processes it again (fusion from the cache). Prints wall times and the process's peak memory.
Targets (issue 7): `long` <= 90 s wall and <= 2 GB.
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import resource
import tempfile
import time
from pathlib import Path


def run_scenario(name: str, workdir: str, queue) -> None:
    from insrail.project import process
    from insrail.project.demo import project_for_simulated_survey
    from insrail.sim.scenario import preset
    from insrail.sim.simulate import simulate

    root = Path(workdir) / name
    survey = root / "surveys" / name
    start = time.perf_counter()
    simulate(preset(name), seed=1, out_dir=survey, overwrite=True, imu_format="npy")
    simulated = time.perf_counter() - start
    project = project_for_simulated_survey(root, survey, name=f"benchmark {name}")
    start = time.perf_counter()
    results = process(project, name)
    first = time.perf_counter() - start
    start = time.perf_counter()
    process(project, name)
    second = time.perf_counter() - start
    peak_gb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024**2  # kB on Linux
    queue.put((name, simulated, first, second, peak_gb, len(results.table), len(results.assessment.exceedances)))


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
        context = mp.get_context("spawn")  # one clean process per scenario, so peak memory is its own
        for name in scenarios:
            queue = context.Queue()
            child = context.Process(target=run_scenario, args=(name, workdir, queue))
            child.start()
            row = queue.get()
            child.join()
            print(f"{row[0]:<9} {row[1]:>10.1f} {row[2]:>10.1f} {row[3]:>9.1f} {row[4]:>8.2f} {row[5]:>9d} {row[6]:>8d}")


if __name__ == "__main__":
    main()
