"""A line section of four runs batched on a Dask cluster of 1 and of 2 worker processes: the speed-up.

    python benchmarks/section_batch.py [--workdir DIR] [--workers 1 2]

The simulator's `long` preset (10.2 km) cut into four runs of about 2.6 km with 100 m overlaps over
one track (same track seed, own noise seeds), the `.npy` IMU. For each cluster size a fresh copy of
the project (no results, no cache) goes through `insrail batch PROJECT --section km20-30 --scheduler
ADDRESS --no-reports` on a `distributed.LocalCluster` of that many single-threaded worker processes,
started and warmed (insrail imported, numba's cache loaded) before the clock starts: a real cluster's
workers outlive a batch. The runs and the join's adjustment parts run on the workers; the rest of the
join here. Prints each wall time, the speed-up over one worker, the machine's load average before
and after each run (the wall speed-up needs idle cores), and whether every joined section equals
the first one byte for byte (sleepers.csv, exceedances.csv, quality.csv).

On a loaded machine the wall times say little; so it also prints the CPU time (user + system) each
worker process and this process spent on the batch, and the wall time an idle machine would take,
estimated as the busiest worker's CPU plus this process's: a lower bound, as it counts no worker
waiting for another (between the adjustment's colours). Simulated surveys are kept in DIR (default
/tmp/insrail-section-batch).
"""

from __future__ import annotations

import argparse
import os
import resource
import shutil
import time
from dataclasses import replace
from pathlib import Path

from section_join import simulated_run

#: (name, from, to) of each run [m]: 100 m overlaps.
RUNS = (("run1", 20050.0, 22700.0), ("run2", 22600.0, 25250.0), ("run3", 25150.0, 27800.0),
        ("run4", 27700.0, 30250.0))
SECTION = "km20-30"
JOINED_FILES = ("sleepers.csv", "exceedances.csv", "quality.csv")


def _cpu_s() -> float:
    """User + system CPU time of this process so far (all its threads)."""
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def _warm() -> str:
    """Run on each worker before timing: the pipeline's imports and numba kernels loaded."""
    import insrail.project.pipeline  # noqa: F401
    from insrail.nav import fusion  # noqa: F401

    return str(os.getpid())


def main() -> None:
    from distributed import Client, LocalCluster

    from insrail.cli.main import main as cli
    from insrail.project import load_project
    from insrail.project.demo import project_for_simulated_survey
    from insrail.project.model import SectionEntry, SurveyEntry, save_project

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workdir", type=Path, default=Path("/tmp/insrail-section-batch"))
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    args = parser.parse_args()
    root = args.workdir
    started = time.perf_counter()
    for seed, (name, start, end) in enumerate(RUNS, start=1):
        simulated_run(root / "source" / "surveys" / name, start, end, seed=seed)
    print(f"simulated in {time.perf_counter() - started:.0f} s")
    project = project_for_simulated_survey(root / "source", root / "source" / "surveys" / "run1", name="section batch")
    project = replace(project, surveys=tuple(SurveyEntry(name, f"surveys/{name}") for name, _, _ in RUNS),
                      sections=(SectionEntry(SECTION, tuple(name for name, _, _ in RUNS)),))
    save_project(project)
    load_project(root / "source")  # the project as saved is valid

    walls, idle, joined = {}, {}, {}
    for workers in args.workers:
        copy = root / f"workers{workers}"
        shutil.rmtree(copy, ignore_errors=True)
        shutil.copytree(root / "source", copy, ignore=shutil.ignore_patterns("results", "reports"))
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
            with Client(cluster) as client:
                pids = client.run(_warm)
                before = client.run(_cpu_s)
                load = os.getloadavg()[0]
                started, here = time.perf_counter(), _cpu_s()
                code = cli(["batch", str(copy), "--section", SECTION, "--scheduler", cluster.scheduler_address,
                            "--no-reports"])
                walls[workers], here = time.perf_counter() - started, _cpu_s() - here
                spent = {worker: cpu - before[worker] for worker, cpu in client.run(_cpu_s).items()}
        if code != 0:
            raise SystemExit(f"insrail batch exited with {code} on {workers} worker(s)")
        joined[workers] = [(copy / "results" / SECTION / name).read_bytes() for name in JOINED_FILES]
        idle[workers] = max(spent.values()) + here
        print(f"{workers} worker(s) ({len(set(pids.values()))} processes): {walls[workers]:.1f} s wall, load average "
              f"before {load:.2f}, after {os.getloadavg()[0]:.2f}; CPU s per worker "
              f"{' '.join(f'{v:.1f}' for v in sorted(spent.values(), reverse=True))}, here {here:.1f}; "
              f"idle-machine estimate {idle[workers]:.1f} s")
    first = args.workers[0]
    for workers in args.workers[1:]:
        print(f"{workers} workers: speed-up {walls[first] / walls[workers]:.2f}x over {first} (wall), "
              f"{idle[first] / idle[workers]:.2f}x (idle-machine estimate from CPU); joined section identical: "
              f"{joined[workers] == joined[first]}")


if __name__ == "__main__":
    main()
