"""A line section of four runs batched on a Dask cluster of 1 and of 2 worker processes: the speed-up.

    python benchmarks/section_batch.py [--workdir DIR] [--workers 1 2]

The simulator's `long` preset (10.2 km) cut into four runs of about 2.6 km with 100 m overlaps over
one track (same track seed, own noise seeds), the `.npy` IMU. For each cluster size a fresh copy of
the project (no results, no cache, an empty cache of parsed tables: the runs' sleepers.csv are the same
bytes for every size, and the join would find the first size's parse) goes through `insrail batch
PROJECT --section km20-30 --scheduler ADDRESS --no-reports` on a `distributed.LocalCluster` of that
many single-threaded worker processes, started and warmed (a run processed once: insrail imported, numba's kernels loaded)
before the clock starts: a real cluster's workers outlive a batch. A task on a single-threaded worker
has a CPU budget of one (:func:`insrail.background.cpu_budget`, printed): each run is processed
serially, the one worker's batch keeps one core busy. The runs and the join's adjustment
parts run on the workers; the rest of the join here. Prints each wall time, the speed-up over one
worker, the machine's load average before and after each run (the wall speed-up needs idle cores),
and whether every joined section equals the first one byte for byte (sleepers.csv, exceedances.csv,
quality.csv).

On a loaded machine the wall times say little; so it also prints the CPU time (user + system) each
worker process and this process (the scheduler runs here too) spent on the batch, and the wall time an
idle machine would take, estimated as the busiest worker's CPU plus this process's: a lower bound, as it
counts no worker waiting for another (between the adjustment's colours). The runs' CPU side by side
against one after the other says what the cores lose to each other (shared caches and memory). Each
task's CPU time is taken on its worker (a worker plugin; one thread a worker): from them the ideal
makespan on 1 and 2 workers (:func:`ideal_makespan`), and with --tasks every task's worker, start,
wall and CPU time. Simulated surveys are kept in DIR (default /tmp/insrail-section-batch).
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


def _warm(source: str) -> str:
    """Run on each worker before timing: the first run of the project at ``source`` processed once in a
    throwaway copy (the pipeline's imports, and every numba kernel a run calls loaded - or compiled into
    the disk cache, which the first timed run otherwise paid for: run1 took 42 s of CPU against 10 s
    for the others after a change to the fusion's source), with the worker's budget of one CPU."""
    from insrail.background import cpus_limited
    from insrail.cli.main import main as cli

    folder = Path(source).with_name(f"warm-{os.getpid()}")
    shutil.rmtree(folder, ignore_errors=True)
    shutil.copytree(source, folder, ignore=shutil.ignore_patterns("results", "reports"))
    try:
        with cpus_limited(1):
            if cli(["process", str(folder), "--survey", RUNS[0][0]]) != 0:
                raise RuntimeError(f"the warm-up processing of {folder} failed")
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    return str(os.getpid())


class TaskClock:
    """A worker plugin: each task's wall and CPU time (the worker process's user + system, all its threads:
    with one thread a worker that is the task's), kept on the worker for :func:`_task_times`."""

    name = "insrail-task-clock"

    def setup(self, worker) -> None:
        self.started, self.times = {}, []

    def transition(self, key, start, finish, **kwargs) -> None:
        if finish == "executing":
            self.started[key] = (time.time(), _cpu_s())
        elif start == "executing" and key in self.started:
            wall, cpu = self.started.pop(key)
            self.times.append((str(key), wall, time.time() - wall, _cpu_s() - cpu))


def _task_times(dask_worker) -> list:
    return dask_worker.plugins[TaskClock.name].times


def _task_name(key: str) -> str:
    """``run_task-3f2a...`` -> ``run_task``."""
    return key.split("-", 1)[0]


def ideal_makespan(runs_s: list[float], parts_s: list[float], workers: int) -> float:
    """The batch's time on ``workers`` idle workers from its tasks' CPU times: the runs shared longest first
    (each to the worker free first), then the join's parts, at best their sum shared evenly and never less
    than the longest part (a window's programme is one task; the colours after it wait for it). The
    coordinator's own work (the join's table, the assessment, the files) and any wait between colours
    are left out: a lower bound of the wall time."""
    free = [0.0] * workers
    for cpu in sorted(runs_s, reverse=True):
        free[free.index(min(free))] += cpu
    return max(free) + max(sum(parts_s) / workers, max(parts_s, default=0.0))


def main() -> None:
    from distributed import Client, LocalCluster
    from distributed.diagnostics.plugin import WorkerPlugin

    from insrail.background import cpu_budget
    from insrail.cli.main import main as cli
    from insrail.project import load_project
    from insrail.project.demo import project_for_simulated_survey
    from insrail.project.model import SectionEntry, SurveyEntry, save_project

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workdir", type=Path, default=Path("/tmp/insrail-section-batch"))
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--tasks", action="store_true", help="print each task's worker, start, wall and CPU time")
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

    walls, idle, joined, runs_cpu = {}, {}, {}, {}
    for workers in args.workers:
        copy = root / f"workers{workers}"
        shutil.rmtree(copy, ignore_errors=True)
        shutil.copytree(root / "source", copy, ignore=shutil.ignore_patterns("results", "reports"))
        parsed = root / f"table-cache{workers}"  # the user's parsed tables: each cluster size starts without them
        shutil.rmtree(parsed, ignore_errors=True)
        os.environ["XDG_CACHE_HOME"] = str(parsed)
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
            with Client(cluster) as client:
                pids = client.run(_warm, str(root / "source"))
                budget = client.submit(cpu_budget, pure=False).result()
                client.register_plugin(type("Clock", (TaskClock, WorkerPlugin), {})(), name=TaskClock.name)
                before = client.run(_cpu_s)
                load = os.getloadavg()[0]
                started, here, epoch = time.perf_counter(), _cpu_s(), time.time()
                code = cli(["batch", str(copy), "--section", SECTION, "--scheduler", cluster.scheduler_address,
                            "--no-reports"])
                walls[workers], here = time.perf_counter() - started, _cpu_s() - here
                spent = {worker: cpu - before[worker] for worker, cpu in client.run(_cpu_s).items()}
                tasks = client.run(_task_times)
        if code != 0:
            raise SystemExit(f"insrail batch exited with {code} on {workers} worker(s)")
        joined[workers] = [(copy / "results" / SECTION / name).read_bytes() for name in JOINED_FILES]
        idle[workers] = max(spent.values()) + here
        every = [(number, *task) for number, (_, times) in enumerate(sorted(tasks.items())) for task in times]
        if args.tasks:
            print(f"tasks on {workers} worker(s): worker, task, start [s after the batch's start], wall, CPU [s]")
            for number, key, begun, wall, cpu in sorted(every, key=lambda t: (t[0], t[2])):
                print(f"  w{number} {_task_name(key):<20} {begun - epoch:7.1f} {wall:7.1f} {cpu:7.1f}")
        cpu_of = {name: [t[4] for t in every if _task_name(t[1]) == name] for name in ("run_task", "solve_part_in_zone")}
        runs_cpu[workers] = sum(cpu_of["run_task"])
        print(f"{workers} worker(s): task CPU s: runs {' '.join(f'{v:.1f}' for v in cpu_of['run_task'])}; the join's "
              f"{len(cpu_of['solve_part_in_zone'])} parts {sum(cpu_of['solve_part_in_zone']):.1f} in all, the longest "
              f"{max(cpu_of['solve_part_in_zone'], default=0.0):.1f}; ideal makespan from them: "
              + ", ".join(f"{k} worker(s) {ideal_makespan(cpu_of['run_task'], cpu_of['solve_part_in_zone'], k):.1f} s"
                          for k in (1, 2)))
        print(f"{workers} worker(s) ({len(set(pids.values()))} processes, a task's CPU budget {budget}): "
              f"{walls[workers]:.1f} s wall, load average "
              f"before {load:.2f}, after {os.getloadavg()[0]:.2f}; CPU s per worker "
              f"{' '.join(f'{v:.1f}' for v in sorted(spent.values(), reverse=True))}, here {here:.1f}; "
              f"idle-machine estimate {idle[workers]:.1f} s")
    first = args.workers[0]
    for workers in args.workers[1:]:
        print(f"{workers} workers: speed-up {walls[first] / walls[workers]:.2f}x over {first} (wall), "
              f"{idle[first] / idle[workers]:.2f}x (idle-machine estimate from CPU); joined section identical: "
              f"{joined[workers] == joined[first]}; the runs' CPU {runs_cpu[workers]:.1f} s side by side against "
              f"{runs_cpu[first]:.1f} s ({100 * (runs_cpu[workers] / runs_cpu[first] - 1):+.0f} %)")


if __name__ == "__main__":
    main()
