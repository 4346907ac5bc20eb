"""insrail fuse, and process + report, beside KF-GINS, back to back on the same survey: both ratios.

    python benchmarks/kfgins.py SURVEY_DIR [SURVEY_DIR ...] --kfgins-git DIR [--scratch DIR] [--runs 2]
    python benchmarks/kfgins.py SHORT_DIR LONG_DIR --kfgins-bin PATH

KF-GINS (i2Nav-WHU/KF-GINS, GPLv3, C++/Eigen; ../shared/peers/kfgins.md) is the open loosely
coupled GNSS/INS EKF of the thesis's group: forward filter only, GNSS positions only, no
smoother, no odometer, no alignment. It is built here from a git copy of its public repository
(``--kfgins-git``: a bare git directory, e.g. the one the session's ``fetch`` leaves) into a
scratch folder outside the project tree - never vendored, never linked - or taken as a built
binary (``--kfgins-bin``).

SURVEY_DIR is a simulated survey with a text IMU file (``insrail simulate --preset long-outage
--seed 1 --out DIR``; its truth gives KF-GINS the initial state it cannot align itself). The
script writes KF-GINS's inputs (the IMU and GNSS texts without comment lines, one YAML file with
the survey's IMU profile as noise) once, then runs, ``--runs`` times in turn, the whole
``KF-GINS config.yaml`` and the whole ``insrail fuse SURVEY --out DIR`` (forward + RTS smoother,
GNSS + odometer + NHC + ZUPT, reading and writing included) under ``/usr/bin/time``, and prints
per run (insrail from bytecode compiled beforehand, as an install has it: benchmarks/bytecode.py)
wall time, CPU time (user + sys), peak RSS and IMU epochs/s, and the throughput ratio
insrail / KF-GINS (wall and CPU) of the best runs. It also prints the first-call cost of the
compiled kernels (a fresh numba cache). Both read the same 200 Hz text IMU file.

The whole pipeline is timed too: ``insrail process PROJECT`` then ``insrail report PROJECT`` of a
fresh project (``insrail.project.demo.project_for_simulated_survey`` over a hard-linked copy of the
survey; results, cache and reports removed before each run), the two commands' wall and CPU summed,
and its time as a multiple of KF-GINS's (issue 39's bar: at most 1.0x).

With several surveys (the short and the long one) each is run in turn as above (its own work folder and
project under --scratch) and a last table puts both ratios of every survey side by side, CPU and wall,
against issue 39's bars (fuse >= 3x KF-GINS's throughput, process + report <= 1.0x its time). On a loaded
machine the CPU ratios are the ones to compare; the load average before each run is printed.
"""

from __future__ import annotations

import argparse
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from bytecode import installed_env

REPO = Path(__file__).resolve().parent.parent


def build_kfgins(git_dir: Path, scratch: Path) -> Path:
    """Export the repository's HEAD (without ``dataset/``, whose demo blob a mirror may lack) and
    build it with CMake in Release mode; returns the binary."""
    binary = scratch / "kfgins" / "bin" / "KF-GINS"
    if binary.exists():
        return binary
    source = scratch / "kfgins"
    source.mkdir(parents=True, exist_ok=True)
    entries = subprocess.run(["git", f"--git-dir={git_dir}", "ls-tree", "--name-only", "HEAD"], check=True,
                             capture_output=True, text=True).stdout.split()
    archive = subprocess.run(["git", f"--git-dir={git_dir}", "archive", "HEAD", *[e for e in entries if e != "dataset"]],
                             check=True, capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", str(source)], input=archive, check=True)
    subprocess.run(["cmake", "-S", str(source), "-B", str(source / "build"), "-DCMAKE_BUILD_TYPE=Release"], check=True,
                   stdout=subprocess.DEVNULL)
    subprocess.run(["cmake", "--build", str(source / "build"), "-j2"], check=True, stdout=subprocess.DEVNULL)
    if not binary.exists():
        raise SystemExit(f"KF-GINS built, but {binary} is missing")
    return binary


def _strip_comments(src: Path, dst: Path) -> None:
    with open(src) as inp, open(dst, "w") as out:
        for line in inp:
            if line.strip() and not line.startswith(("#", "%")):
                out.write(line)


def kfgins_inputs(survey_dir: Path, work: Path) -> tuple[Path, int]:
    """KF-GINS's IMU and GNSS texts and its YAML configuration; returns (yaml, IMU epochs)."""
    from insrail.io.gnss import write_gnss_kfgins
    from insrail.io.survey import read_survey
    from insrail.nav.imu_profile import load_imu_profile
    from insrail.sim.truth import read_nav_truth

    survey = read_survey(survey_dir)
    if survey.manifest.files["imu"].format != "kfgins-imu":
        raise SystemExit(f"{survey_dir}: the IMU file must be the kfgins-imu text (simulate without --imu-format npy)")
    work.mkdir(parents=True, exist_ok=True)
    imu_txt, gnss_txt = work / "imu.txt", work / "gnss.txt"
    _strip_comments(survey_dir / survey.manifest.files["imu"].path, imu_txt)
    write_gnss_kfgins(work / "gnss_with_header.txt", survey.gnss)
    _strip_comments(work / "gnss_with_header.txt", gnss_txt)
    first_line = imu_txt.open().readline()
    start_text = first_line.split()[0]
    start = float(start_text)
    truth = read_nav_truth(survey_dir / "truth" / "nav.npy")
    k = int(np.argmin(np.abs(truth["time_s"] - start)))
    deg = math.degrees
    p = load_imu_profile(survey.manifest.imu_profile)
    lever = survey.manifest.trolley.imu_to_antenna_m

    def three(x):
        return f"[{x:.9g}, {x:.9g}, {x:.9g}]"

    yaml = f"""imupath: "{imu_txt}"
gnsspath: "{gnss_txt}"
outputpath: "{work}"
imudatalen: 7
imudatarate: {int(round(survey.imu.rate_hz))}
starttime: {start_text}
endtime: -1
initpos: [{deg(truth['lat_rad'][k]):.11f}, {deg(truth['lon_rad'][k]):.11f}, {truth['height_m'][k]:.4f}]
initvel: [{', '.join(f'{v:.6f}' for v in truth['vel_ned_mps'][k])}]
initatt: [{', '.join(f'{deg(a):.8f}' for a in truth['rpy_rad'][k])}]
initgyrbias: [0, 0, 0]
initaccbias: [0, 0, 0]
initgyrscale: [0, 0, 0]
initaccscale: [0, 0, 0]
initposstd: [0.01, 0.01, 0.02]
initvelstd: [0.005, 0.005, 0.005]
initattstd: [0.01, 0.01, 0.1]
imunoise:
  arw: {three(deg(p.gyro_arw) * 60.0)}
  vrw: {three(p.accel_vrw * 60.0)}
  gbstd: {three(deg(math.hypot(p.gyro_bias_turn_on, p.gyro_bias_gm_sigma)) * 3600.0)}
  abstd: {three(math.hypot(p.accel_bias_turn_on, p.accel_bias_gm_sigma) * 1e5)}
  gsstd: {three(p.gyro_scale_factor * 1e6)}
  asstd: {three(p.accel_scale_factor * 1e6)}
  corrtime: {p.gyro_bias_gm_tau_s / 3600.0:.6g}
antlever: [{', '.join(f'{v:.4f}' for v in lever)}]
"""
    config = work / "kf-gins.yaml"
    config.write_text(yaml)
    return config, len(survey.imu)


def timed(command: list[str], env: dict | None = None, cwd: Path | None = None) -> dict:
    """Run a whole command under /usr/bin/time -v: wall, user + sys [s], peak RSS [MB]."""
    with tempfile.NamedTemporaryFile("r", suffix=".time") as report:
        done = subprocess.run(["/usr/bin/time", "-v", "-o", report.name, *command], env=env, cwd=cwd,
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, check=False)
        text = report.read()
    if done.returncode != 0:
        raise SystemExit(f"{' '.join(command)} failed ({done.returncode}):\n{done.stdout[-3000:]}")

    def field(name):
        return re.search(rf"{re.escape(name)}: (.*)", text).group(1).strip()

    h_m_s = [float(v) for v in field("Elapsed (wall clock) time (h:mm:ss or m:ss)").split(":")]
    wall = sum(v * 60.0**i for i, v in enumerate(reversed(h_m_s)))
    return {"wall_s": wall, "cpu_s": float(field("User time (seconds)")) + float(field("System time (seconds)")),
            "rss_mb": float(field("Maximum resident set size (kbytes)")) / 1024.0, "output": done.stdout}


def insrail_command(survey_dir: Path, out: Path) -> list[str]:
    return [sys.executable, "-m", "insrail", "fuse", str(survey_dir), "--out", str(out)]


def fresh_project(survey_dir: Path, folder: Path) -> Path:
    """A project in ``folder`` over a hard-linked copy of the survey (made once)."""
    from insrail.project.demo import project_for_simulated_survey

    survey = folder / "surveys" / survey_dir.name
    if not (folder / "project.toml").is_file() or not survey.is_dir():
        shutil.rmtree(folder, ignore_errors=True)
        shutil.copytree(survey_dir, survey, copy_function=os.link)
        project_for_simulated_survey(folder, survey, name="kfgins bench")
    return folder


def process_and_report(project: Path, env: dict, cwd: Path) -> dict:
    """``insrail process`` + ``insrail report`` of the project with no results, cache or reports."""
    for produced in ("results", "reports"):
        shutil.rmtree(project / produced, ignore_errors=True)
    runs = [timed([sys.executable, "-m", "insrail", command, str(project)], env=env, cwd=cwd)
            for command in ("process", "report")]
    return {"wall_s": sum(r["wall_s"] for r in runs), "cpu_s": sum(r["cpu_s"] for r in runs),
            "rss_mb": max(r["rss_mb"] for r in runs), "output": runs[-1]["output"]}


def bench_survey(survey_dir: Path, binary: Path, scratch: Path, runs: int) -> dict:
    """Both ratios of one survey (module docstring): prints its runs and returns the best runs."""
    config, epochs = kfgins_inputs(survey_dir, scratch / "run")
    env = installed_env(dict(os.environ, PYTHONPATH=str(REPO)), scratch / "pycache")
    out = scratch / "insrail-out"
    # a project per survey: one scratch folder serves several surveys (made once each, then reused)
    project = fresh_project(survey_dir, scratch / "projects" / survey_dir.resolve().name)

    # first call with an empty numba cache: the one-off compile cost of the kernels
    cache = scratch / "numba-cache"
    shutil.rmtree(cache, ignore_errors=True)
    cold = timed(insrail_command(survey_dir, out), env=dict(env, NUMBA_CACHE_DIR=str(cache)))
    warm_env = dict(env, NUMBA_CACHE_DIR=str(cache))
    print(f"\nIMU epochs: {epochs:,} ({survey_dir})")
    print(f"{'run':<22} {'wall s':>8} {'CPU s':>8} {'peak MB':>8} {'k epochs/s wall':>16} {'k epochs/s CPU':>15}")

    def line(name, r):
        print(f"{name:<22} {r['wall_s']:8.1f} {r['cpu_s']:8.1f} {r['rss_mb']:8.0f} {epochs / r['wall_s'] / 1e3:16.1f} "
              f"{epochs / r['cpu_s'] / 1e3:15.1f}", flush=True)

    line("insrail fuse (cold)", cold)
    best = {"kfgins": None, "insrail": None, "pipeline": None}
    labels = {"kfgins": "KF-GINS", "insrail": "insrail fuse", "pipeline": "process+report"}
    for run in range(runs):
        print(f"load average before run {run + 1}: {os.getloadavg()[0]:.2f}")
        for name, command in (("kfgins", lambda: timed([str(binary), str(config)], cwd=scratch)),
                              ("insrail", lambda: timed(insrail_command(survey_dir, out), env=warm_env, cwd=scratch)),
                              # the install's own numba cache (warm after any earlier process run), as a user has it
                              ("pipeline", lambda: process_and_report(project, env, scratch))):
            r = command()
            line(f"{labels[name]} #{run + 1}", r)
            if best[name] is None or r["wall_s"] < best[name]["wall_s"]:
                best[name] = r
    k, i, p = best["kfgins"], best["insrail"], best["pipeline"]
    print(f"throughput insrail fuse / KF-GINS (best runs): wall {k['wall_s'] / i['wall_s']:.2f}x, "
          f"CPU {k['cpu_s'] / i['cpu_s']:.2f}x; peak RSS {i['rss_mb']:.0f} MB vs {k['rss_mb']:.0f} MB")
    print(f"time insrail process + report (fresh project) / KF-GINS (best runs): wall {p['wall_s'] / k['wall_s']:.2f}x, "
          f"CPU {p['cpu_s'] / k['cpu_s']:.2f}x; peak RSS {p['rss_mb']:.0f} MB")
    print(f"first call (empty numba cache) costs {cold['wall_s'] - i['wall_s']:.1f} s wall, "
          f"{cold['cpu_s'] - i['cpu_s']:.1f} s CPU more than a warm one")
    return {"epochs": epochs, **best}


def print_ratios(results: dict[Path, dict]) -> None:
    """Both ratios of every survey side by side against issue 39's bars."""
    print(f"\n{'survey':<16} {'epochs':>10} {'fuse/KF-GINS throughput CPU (wall)':>36} "
          f"{'process+report/KF-GINS time CPU (wall)':>40}")
    for survey, r in results.items():
        k, i, p = r["kfgins"], r["insrail"], r["pipeline"]
        fuse_cpu, pipe_cpu = k["cpu_s"] / i["cpu_s"], p["cpu_s"] / k["cpu_s"]
        print(f"{survey.name:<16} {r['epochs']:>10,} {fuse_cpu:>26.2f}x ({k['wall_s'] / i['wall_s']:.2f}x) "
              f"{'met' if fuse_cpu >= 3.0 else 'NOT met':>7} {pipe_cpu:>30.2f}x ({p['wall_s'] / k['wall_s']:.2f}x) "
              f"{'met' if pipe_cpu <= 1.0 else 'NOT met':>7}")
    print("bars (issue 39, CPU): insrail fuse >= 3x KF-GINS's throughput; process + report <= 1.0x KF-GINS's time")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("survey", type=Path, nargs="+",
                        help="simulated survey folder(s) with a text IMU file and truth/ (e.g. the short and the long one)")
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("--kfgins-git", type=Path, help="a git directory of i2Nav-WHU/KF-GINS (bare is fine)")
    source.add_argument("--kfgins-bin", type=Path, help="a built KF-GINS binary")
    parser.add_argument("--scratch", type=Path, default=Path(tempfile.gettempdir()) / "insrail-kfgins-bench",
                        help="build and work folder, outside the project tree")
    parser.add_argument("--runs", type=int, default=2, help="back-to-back pairs of runs (default 2)")
    args = parser.parse_args(argv)
    scratch = args.scratch.resolve()
    if REPO in scratch.parents or scratch == REPO:
        raise SystemExit(f"--scratch {scratch}: KF-GINS is built outside the project tree")
    binary = args.kfgins_bin or build_kfgins(args.kfgins_git.resolve(), scratch)
    surveys = [survey.resolve() for survey in args.survey]
    if len({survey.name for survey in surveys}) < len(surveys):
        raise SystemExit("the surveys' folders need different names (each has its own work folder under --scratch)")
    results = {survey: bench_survey(survey, binary, scratch / survey.name if len(surveys) > 1 else scratch, args.runs)
               for survey in surveys}
    print_ratios(results)
    print("insrail: forward + RTS smoother, GNSS + odometer + NHC + ZUPT, start-up alignment, trajectory.npy at 200 Hz; "
          "KF-GINS: forward only, GNSS positions only, initial state given, its text outputs at 200 Hz")


if __name__ == "__main__":
    main()
