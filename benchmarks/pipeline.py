"""End-to-end pipeline time and memory per stage: the demo projects of the `short`, `long` (and 20 km) surveys.

    python benchmarks/pipeline.py [--workdir DIR] [--skip-long] [--twenty] [--only long long20] [--reuse]

For each scenario: simulates the survey into a demo project (its own process; with --reuse an
existing project in --workdir is taken as it is, its results removed), then runs, each in a fresh
process as the commands would:

1. ``process``: `insrail process` on the fresh project (fusion, coordinates, track, assessment,
   adjustment, result files);
2. ``report``:  `insrail report` (the workbook and the PDF: side by side, the workbook in a spawned process,
   where a second CPU is free, as insrail.report.both decides; the step's CPU includes that process's);
3. ``rerun``:   `insrail process` again after the surveyor edited the tolerance profile (a copy of
   the default with a band-passed D1 check added: fusion, track and adjustment from the cache, a
   new assessment and result files).

Per stage (the pipeline's progress steps; "start-up" is the interpreter and the imports, insrail's
from bytecode compiled beforehand as an install has it: benchmarks/bytecode.py) it prints
the wall time, the CPU time (user + system) and the stage's own peak resident memory (the
kernel's high-water mark is reset at each stage: /proc/self/clear_refs). Per step it prints the
whole process's wall, CPU and peak RSS (getrusage of the child), i.e. what `/usr/bin/time -v`
says of the command. Beside a stage's peak, "anon MB" and "file MB" split the resident memory
into anonymous (heap, numpy buffers) and file-backed (memory-mapped files, the libraries) pages,
as /proc/self/status's RssAnon and RssFile give them at the stage's largest sampled VmRSS (sampled
every 20 ms and at the stage's end, so a shorter spike than that may be missed by these two
columns, never by the peak). On a loaded machine the CPU time is the figure to compare. The "numba s"
column is the wall time spent compiling numba kernels in the stage (numba's "numba:compile"
events: a kernel whose on-disk cache is missing or stale, e.g. the first run after an install or
after a change to the engine; once per install, not per survey): the first `long` run after such
a change pays some 30 s there, which is not the pipeline's own cost. With more than one CPU the
covariance analysis of a fresh fusion runs in a thread beside the track reconstruction: the
"track reconstruction" row then holds both (and there is no "covariance analysis" row).

Bars (issue 24): `long` process + report <= 60 s wall and <= 1.5 GB peak RSS; the rerun <= 5 s; with
--twenty (or --only long long20) the 20 km survey `long20` (the `long` design twice end to end, same
trolley and sensors; simulated once, some 4 min) as well, and its process + report peak RSS within 10 %
of `long`'s.
With --keep-outputs DIR the sleepers.csv and quality.csv of every step are copied there (to compare two
versions of insrail on the same project).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

from bytecode import installed_env

#: The pipeline's progress messages that begin a stage, and the stage's name in the table.
STAGES = {
    "height model": "height model",
    "fusion reused from the cache": "fusion",
    "rails, chainage and sleepers": "track reconstruction",
    "irregularities and exceedances": "assessment",
    "adjustment amounts": "adjustment",
    "writing results": "result files",
    "done": None,
}
EDITED_PROFILE = "edited-tolerances.toml"


class CompileTimer:
    """Wall time of numba's top-level "numba:compile" events (cache misses only: a kernel loaded
    from its on-disk cache raises none). Registered once numba is imported (by the code under
    test, never by the benchmark itself)."""

    def __init__(self):
        self.total_s = 0.0
        self.depth = 0
        self.registered = False
        self.began = 0.0

    def register_if_loaded(self) -> None:
        if self.registered or "numba" not in sys.modules:
            return
        from numba.core import event

        timer = self

        class Listener(event.Listener):
            def on_start(self, _event):
                if timer.depth == 0:
                    timer.began = time.perf_counter()
                timer.depth += 1

            def on_end(self, _event):
                timer.depth -= 1
                if timer.depth == 0:
                    timer.total_s += time.perf_counter() - timer.began

        event.register("numba:compile", Listener())
        self.registered = True


class RssSampler:
    """RssAnon and RssFile at the largest VmRSS seen since :meth:`take` (a thread samples
    /proc/self/status every ``interval_s``)."""

    def __init__(self, interval_s: float = 0.02):
        self.lock = threading.Lock()
        self.best = (0.0, float("nan"), float("nan"))
        self.stopped = threading.Event()
        self.thread = threading.Thread(target=self._run, args=(interval_s,), daemon=True)
        self.thread.start()

    @staticmethod
    def _status() -> tuple[float, float, float]:
        """VmRSS, RssAnon and RssFile (MB)."""
        values = {}
        with open("/proc/self/status", encoding="ascii") as status:
            for line in status:
                key, _, rest = line.partition(":")
                if key in ("VmRSS", "RssAnon", "RssFile"):
                    values[key] = int(rest.split()[0]) / 1024
        return values.get("VmRSS", 0.0), values.get("RssAnon", float("nan")), values.get("RssFile", float("nan"))

    def sample(self) -> None:
        now = self._status()
        with self.lock:
            if now[0] >= self.best[0]:
                self.best = now

    def _run(self, interval_s: float) -> None:
        while not self.stopped.wait(interval_s):
            self.sample()

    def take(self) -> tuple[float, float]:
        """(RssAnon, RssFile) at the largest VmRSS since the last take; the next period starts."""
        self.sample()
        with self.lock:
            _, anon, file = self.best
            self.best = (0.0, float("nan"), float("nan"))
        return anon, file


class StageClock:
    """Wall, CPU, peak RSS (with its anonymous and file-backed parts) and numba compile time per
    stage, switched by :meth:`enter`."""

    def __init__(self, started_wall: float):
        self.rows: list[dict] = []
        self.stage: str | None = None
        self.wall = started_wall
        self.cpu = 0.0  # the process's CPU time so far is charged to the first stage
        self.compiles = CompileTimer()
        self.compiled_s = 0.0
        self.rss = RssSampler()
        self.enter("start-up")

    @staticmethod
    def _cpu() -> float:
        usage = resource.getrusage(resource.RUSAGE_SELF)
        return usage.ru_utime + usage.ru_stime

    @staticmethod
    def _peak_mb() -> float:
        with open("/proc/self/status", encoding="ascii") as status:
            for line in status:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024
        return float("nan")

    @staticmethod
    def _reset_peak() -> None:
        try:
            with open("/proc/self/clear_refs", "w", encoding="ascii") as handle:
                handle.write("5")  # resets VmHWM to the current RSS
        except OSError:
            pass

    def enter(self, stage: str | None) -> None:
        if stage == self.stage:
            return
        now, cpu = time.time(), self._cpu()
        self.compiles.register_if_loaded()
        anon, file = self.rss.take()
        if self.stage is not None:
            self.rows.append({"stage": self.stage, "wall_s": now - self.wall, "cpu_s": cpu - self.cpu,
                              "peak_mb": self._peak_mb(), "anon_mb": anon, "file_mb": file,
                              "numba_s": self.compiles.total_s - self.compiled_s})
        self._reset_peak()
        self.stage, self.wall, self.cpu, self.compiled_s = stage, now, cpu, self.compiles.total_s

    def progress(self, fraction: float, message) -> None:
        message = getattr(message, "template", message)  # a Phrase: its English template
        if message in STAGES:
            self.enter(STAGES[message])
        elif message.startswith("covariance"):
            if self.stage != "track reconstruction":  # said beside the track (a thread): the track's row holds both
                self.enter("covariance analysis")
        elif self.stage in ("height model", "start-up"):
            self.enter("fusion")

    def merged(self) -> list[dict]:
        """Rows of the same stage added up (a stage may be entered twice), in first-seen order."""
        out: dict[str, dict] = {}
        for row in self.rows:
            item = out.setdefault(row["stage"], {"stage": row["stage"], "wall_s": 0.0, "cpu_s": 0.0, "peak_mb": 0.0,
                                                 "numba_s": 0.0})
            for key in ("wall_s", "cpu_s", "numba_s"):
                item[key] += row[key]
            if row["peak_mb"] >= item["peak_mb"]:
                item.update(peak_mb=row["peak_mb"], anon_mb=row["anon_mb"], file_mb=row["file_mb"])
        return list(out.values())


# --------------------------------------------------------------------------- the child steps

def long20_scenario():
    """The `long` survey twice over: its design repeated end to end (about 20.6 km, the second
    copy's profile raised to join the first's end), the same trolley, sensors and speeds, a stop
    every kilometre."""
    from dataclasses import replace

    from insrail.sim.irregularity import Bump
    from insrail.sim.scenario import long_scenario

    long = long_scenario()
    design, motion = long.design, long.motion
    length = design.pvis[-1][0] - design.pvis[0][0]
    rise = design.pvis[-1][1] - design.pvis[0][1]
    pvis = (*design.pvis[:-1], (design.pvis[-1][0], design.pvis[-1][1], 25000.0),
            *((station + length, height + rise, radius) for station, height, radius in design.pvis[1:]))
    cant = (*design.cant, *((station + length, value) for station, value in design.cant[1:]))
    twice = replace(design, horizontal=design.horizontal * 2, pvis=pvis, cant=cant)

    def doubled(bumps):
        return (*bumps, *(Bump(bump.start_station_m + length, bump.length_m, bump.amplitude_m) for bump in bumps))

    first, last = motion.stops[0][0], motion.stops[-1][0]
    stops = tuple((float(station), 20.0) for station in range(int(first), int(last + length) + 1, 1000))
    return replace(long, name="long20", design=twice,
                   motion=replace(motion, end_station_m=motion.end_station_m + length, stops=stops),
                   irregularities=replace(long.irregularities,
                                          lateral_bumps=doubled(long.irregularities.lateral_bumps),
                                          vertical_bumps=doubled(long.irregularities.vertical_bumps)))


def step_simulate(name: str, root: Path) -> dict:
    from insrail.project.demo import project_for_simulated_survey
    from insrail.sim.scenario import preset
    from insrail.sim.simulate import simulate

    survey = root / "surveys" / name
    scenario = long20_scenario() if name == "long20" else preset(name)
    simulate(scenario, seed=1, out_dir=survey, overwrite=True, imu_format="npy")
    project_for_simulated_survey(root, survey, name=f"benchmark {name}")
    return {}


def step_process(name: str, root: Path, clock: StageClock, edited: bool) -> dict:
    from dataclasses import replace

    from insrail.project import load_project, process

    project = load_project(root)
    if edited:
        project = replace(project, tolerance_profile=EDITED_PROFILE)
    results = process(project, name, progress=clock.progress)
    clock.enter(None)
    return {"sleepers": len(results.table), "exceedances": len(results.assessment.exceedances),
            "fusion_from_cache": results.fusion_from_cache}


def step_report(name: str, root: Path, clock: StageClock) -> dict:
    from insrail.project import load_project
    from insrail.project.results import load_results
    from insrail.report import write_pdf, write_workbook
    from insrail.report.both import side_by_side, write_both

    project = load_project(root)
    out = root / "reports"
    out.mkdir(exist_ok=True)
    clock.enter("read results")
    results = load_results(project.folder, name)
    xlsx, pdf = out / f"track_geometry_{name}.xlsx", out / f"track_geometry_{name}.pdf"
    together = side_by_side(len(results))
    if together:  # as `insrail report` writes them: the workbook in a process of its own
        clock.enter("workbook + pdf")
        write_both(project, results, xlsx, pdf, concurrent=True)
    else:
        clock.enter("workbook")
        write_workbook(project, results, xlsx)
        clock.enter("pdf")
        write_pdf(project, results, pdf)
    clock.enter(None)
    return {"side_by_side": together}


def child_main(argv: list[str]) -> None:
    from insrail.memory import tune_allocator

    tune_allocator()  # as the `insrail` command does first
    step, name, root, started = argv[0], argv[1], Path(argv[2]), float(argv[3])
    clock = StageClock(started)
    if step == "simulate":
        info = step_simulate(name, root)
        clock.enter(None)
    elif step in ("process", "rerun"):
        info = step_process(name, root, clock, edited=step == "rerun")
    else:
        info = step_report(name, root, clock)
    print("BENCHMARK " + json.dumps({"stages": clock.merged(), **info}), flush=True)


def run_child(step: str, name: str, root: Path, env: dict[str, str]) -> dict:
    """One step in a fresh interpreter; its stages and its own wall, CPU and peak RSS."""
    started = time.time()
    child = subprocess.Popen([sys.executable, __file__, "--child", step, name, str(root), repr(started)],
                             stdout=subprocess.PIPE, text=True, env=env)
    out = child.stdout.read()
    _, status, usage = os.wait4(child.pid, 0)
    wall = time.time() - started
    child.returncode = os.waitstatus_to_exitcode(status)
    if child.returncode != 0:
        raise SystemExit(f"{step} of {name} failed (exit code {child.returncode})")
    line = next(item for item in out.splitlines() if item.startswith("BENCHMARK "))
    report = json.loads(line[len("BENCHMARK "):])
    # the stages reset the kernel's high-water mark, which is also what getrusage reports: the
    # process's peak is the largest of its stages' peaks
    peak_mb = max([usage.ru_maxrss / 1024, *(row["peak_mb"] for row in report["stages"])])
    report.update(wall_s=wall, cpu_s=usage.ru_utime + usage.ru_stime, peak_mb=peak_mb)
    return report


def edit_tolerances(root: Path) -> None:
    """The surveyor's edit: the default profile with a check the adjustment does not hold (a
    changed chord or gauge limit would re-optimise the amounts)."""
    from insrail.project import load_project
    from insrail.resources import resources_dir

    project = load_project(root)
    default = (resources_dir() / "tolerance_profiles" / f"{project.tolerance_profile}.toml").read_text(encoding="utf-8")
    edited = default + '\n[checks.d1_peak]\nkind = "band_peak"\nband = "D1"\nmax_abs_mm = 0.5\n'
    (root / EDITED_PROFILE).write_text(edited, encoding="utf-8")


def print_step(name: str, step: str, report: dict) -> None:
    print(f"\n{name} {step}: {report['wall_s']:.1f} s wall, {report['cpu_s']:.1f} s CPU, "
          f"peak RSS {report['peak_mb']:.0f} MB" + (f", {report['sleepers']} sleepers, {report['exceedances']} exceedances"
                                                    if "sleepers" in report else ""))
    print(f"  {'stage':<22} {'wall s':>8} {'CPU s':>8} {'peak MB':>8} {'anon MB':>8} {'file MB':>8} {'numba s':>8}")
    for row in report["stages"]:
        print(f"  {row['stage']:<22} {row['wall_s']:>8.2f} {row['cpu_s']:>8.2f} {row['peak_mb']:>8.0f} "
              f"{row['anon_mb']:>8.0f} {row['file_mb']:>8.0f} {row['numba_s']:>8.2f}")


def main() -> int:
    if len(sys.argv) > 1 and sys.argv[1] == "--child":
        child_main(sys.argv[2:])
        return 0
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workdir", type=Path, help="where the projects are (default: a temporary folder)")
    parser.add_argument("--skip-long", action="store_true", help="only the short survey")
    parser.add_argument("--only", nargs="+", choices=("short", "long", "long20"), help="these scenarios only")
    parser.add_argument("--twenty", action="store_true",
                        help="also the 20 km survey (long20) and the 20 km / 10 km peak RSS side by side")
    parser.add_argument("--reuse", action="store_true",
                        help="take a project already simulated in --workdir (its results and cache removed)")
    parser.add_argument("--keep-outputs", type=Path, metavar="DIR", help="copy each step's sleepers.csv to DIR")
    args = parser.parse_args()
    scenarios = args.only or (["short"] if args.skip_long else ["short", "long"]) + (["long20"] if args.twenty else [])
    peaks: dict[str, dict[str, float]] = {}
    failed = False
    with tempfile.TemporaryDirectory() as tmp:
        workdir = args.workdir or Path(tmp)
        env = installed_env(dict(os.environ), workdir / "pycache")
        for name in scenarios:
            root = workdir / name
            if not (args.reuse and (root / "project.toml").is_file()):
                simulated = run_child("simulate", name, root, env)
                print(f"{name}: simulated in {simulated['wall_s']:.1f} s")
            shutil.rmtree(root / "results", ignore_errors=True)
            shutil.rmtree(root / "reports", ignore_errors=True)
            edit_tolerances(root)
            totals = {}
            for step in ("process", "report", "rerun"):
                report = run_child(step, name, root, env)
                totals[step] = report
                print_step(name, step, report)
                if args.keep_outputs and step != "report":
                    args.keep_outputs.mkdir(parents=True, exist_ok=True)
                    for kept in ("sleepers.csv", "quality.csv"):
                        shutil.copy(root / "results" / name / kept, args.keep_outputs / f"{name}-{step}-{kept}")
            wall = totals["process"]["wall_s"] + totals["report"]["wall_s"]
            cpu = totals["process"]["cpu_s"] + totals["report"]["cpu_s"]
            peak = max(totals["process"]["peak_mb"], totals["report"]["peak_mb"])
            rerun = totals["rerun"]
            print(f"\n{name}: process + report {wall:.1f} s wall, {cpu:.1f} s CPU, peak RSS {peak:.0f} MB; "
                  f"rerun after a tolerance edit {rerun['wall_s']:.1f} s wall, {rerun['cpu_s']:.1f} s CPU")
            peaks[name] = {step: totals[step]["peak_mb"] for step in ("process", "report")}
            if name == "long":
                bars = [("process + report wall <= 60 s", wall <= 60.0), ("peak RSS <= 1.5 GB", peak <= 1500.0),
                        ("rerun wall <= 5 s", rerun["wall_s"] <= 5.0)]
                print("  " + "; ".join(f"{what}: {'met' if ok else 'NOT met'}" for what, ok in bars))
                failed |= not all(ok for _, ok in bars)
    if "long" in peaks and "long20" in peaks:
        failed |= not print_length_ratio(peaks["long"], peaks["long20"])
    return 1 if failed else 0


def print_length_ratio(ten: dict[str, float], twenty: dict[str, float]) -> bool:
    """Peak RSS of process and report at 10 and 20 km side by side; True when the 20 km peak is
    within 10 % of the 10 km one (issue 24: memory bounded for any length)."""
    print(f"\n  {'peak RSS MB':<12} {'10 km':>8} {'20 km':>8} {'ratio':>7}")
    for step in ("process", "report"):
        print(f"  {step:<12} {ten[step]:>8.0f} {twenty[step]:>8.0f} {twenty[step] / ten[step]:>7.3f}")
    ratio = max(twenty.values()) / max(ten.values())
    met = ratio <= 1.10
    print(f"  process + report {max(ten.values()):.0f} -> {max(twenty.values()):.0f} MB, ratio {ratio:.3f}: "
          f"20 km peak within 10 % of 10 km's: {'met' if met else 'NOT met'}")
    return met


if __name__ == "__main__":
    sys.exit(main())
