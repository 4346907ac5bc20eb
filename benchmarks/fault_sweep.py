"""GNSS faults swept over duration and size: are the sleepers left valid as good as they say?

    python benchmarks/fault_sweep.py [--workdir DIR] [--grade nav|tactical|mems|...] [--only TEXT ...]

A 300 m cut of the `short` survey (seed 3, 60 s static start; with the nav grade the survey of
tests/test_nav_integrity.py; ``--grade`` another IMU profile) is simulated once; each case puts one GNSS fault into its solution file
(``insrail.sim.gnss_faults``), makes a demo project of it and runs ``insrail process`` as a user would.
Per case it prints the exit code (an untrusted survey is refused: rc 1 and why), the valid sleepers,
the largest error of a valid sleeper's rail deviations from the design against the simulator's truth
(``truth/sleepers.csv``), how many valid sleepers are off by more than 20 mm (a gross error: the
survey's absolute 1-sigma is a few mm), and the fusion's warnings that name the fault (a reset, a
detour between two resets, a step that stayed).

Target: no valid sleeper off by more than 20 mm, except where a warning says the absolute position
on one side of a step is off by its size (``step`` in the warnings: the filter cannot tell which side
of a GNSS jump that stays is right).

Measured (session 19): before the detour check, a 1 m false fix of 40 s left 18 sleepers between the two
resets valid, 537 mm off (exit 0); now none of the 36 cases leaves a valid sleeper off by more than 11 mm
but the 0.5 m step that stays (263 valid sleepers up to 278 mm off, the step said at the reset); two
false fixes on the 300 m survey make it untrusted (refused, rc 1).
"""

from __future__ import annotations

import argparse
import contextlib
import csv
import io
import shutil
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

GROSS_MM = 20.0


def base_survey(workdir: Path, grade: str) -> Path:
    from insrail.sim.scenario import preset
    from insrail.sim.simulate import simulate

    folder = workdir / f"simulated-{grade}"
    if not (folder / "survey.toml").exists():
        base = preset("short", imu_profile=grade)
        config = replace(base, motion=replace(base.motion, end_station_m=1350.0, static_start_s=60.0,
                                              static_end_s=20.0, stops=()), gnss=replace(base.gnss, outages=()))
        simulate(config, seed=3, out_dir=folder, imu_format="npy")
    return folder


def cases(start_s: float, end_s: float) -> dict:
    from insrail.sim import gnss_faults

    out = {}
    for duration in (5, 15, 25, 40, 60, 90):
        for offset in ((0.05, 0, 0), (0.2, 0, 0), (1.0, 0, 0), (0, 0, 0.3), (3.0, 2.0, 0)):
            name = f"false-fix-{duration}s-{'/'.join(f'{o:g}' for o in offset)}m"
            out[name] = lambda g, d=duration, o=offset: gnss_faults.false_fix(g, start_s + 150.0, d, o)
    out["step-0.5m-stays"] = lambda g: gnss_faults.false_fix(g, start_s + 150.0, 1e6, (0.5, 0, 0))
    out["two-false-fixes-40s"] = lambda g: gnss_faults.false_fix(
        gnss_faults.false_fix(g, start_s + 120.0, 40, (1, 0, 0)), start_s + 200.0, 40, (0, 1, 0))
    out["false-fix-at-end-40s"] = lambda g: gnss_faults.false_fix(g, end_s - 30.0, 40, (1, 0, 0))
    out["false-fix-as-motion-starts"] = lambda g: gnss_faults.false_fix(g, start_s + 55.0, 40, (1, 0, 0))
    out["float-60s-0.25m"] = lambda g: gnss_faults.float_stretch(g, start_s + 150.0, 60, 0.25)
    out["float-60s-1m"] = lambda g: gnss_faults.float_stretch(g, start_s + 150.0, 60, 1.0)
    return out


def run_case(base: Path, workdir: Path, name: str, fault, gnss, truth) -> str:
    from insrail.cli.main import main
    from insrail.io.rtklib import write_rtklib_pos
    from insrail.io.survey import read_manifest
    from insrail.project.demo import project_for_simulated_survey
    from insrail.sim.evaluation import truth_rail_deviations

    root = workdir / f"{base.name}-cases" / name.replace("/", "_")  # beside the base survey, never inside it
    shutil.rmtree(root, ignore_errors=True)
    folder = root / "surveys" / "faulty"
    shutil.copytree(base, folder)
    write_rtklib_pos(folder / read_manifest(folder).files["gnss"].path, fault(gnss))
    project_for_simulated_survey(root, folder, name="faulty")
    said = io.StringIO()
    with contextlib.redirect_stderr(said), contextlib.redirect_stdout(said):
        code = main(["process", str(root)])
    text = said.getvalue()
    if code != 0:
        return f"rc {code}: {text.strip().splitlines()[-1][:110] if text.strip() else ''}"
    with open(root / "results" / "faulty" / "sleepers.csv", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    station = np.array([float(r["station_m"]) for r in rows])
    valid = np.array([r["valid"] == "1" for r in rows])
    measured = [np.array([[float(r[f"{d}_deviation_{rail}_mm"] or "nan") for rail in ("left", "right")] for r in rows])
                for d in ("lateral", "vertical")]
    lateral, vertical, *_ = truth_rail_deviations(truth, station)
    error = np.fmax(np.abs(measured[0] - 1e3 * lateral).max(axis=1), np.abs(measured[1] - 1e3 * vertical).max(axis=1))
    worst = float(np.nanmax(error[valid])) if valid.any() else float("nan")
    said_kinds = ",".join(k for k, word in (("reset", "filter reset at"), ("detour", "off and back"),
                                            ("step", "solution follows"), ("not valid", "not valid from")) if word in text)
    return (f"rc 0: valid {valid.sum():4d}/{len(rows)}  worst valid {worst:7.2f} mm  "
            f"gross {int(np.sum(valid & (error > GROSS_MM))):3d}  said: {said_kinds or '-'}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workdir", type=Path)
    parser.add_argument("--grade", default="nav", help="the IMU profile (resources/imu_profiles; default: nav)")
    parser.add_argument("--only", nargs="*", default=[])
    args = parser.parse_args()
    from insrail.io.survey import read_survey
    from insrail.sim.truth import read_sleeper_truth

    with tempfile.TemporaryDirectory() as scratch:
        workdir = args.workdir or Path(scratch)
        workdir.mkdir(parents=True, exist_ok=True)
        base = base_survey(workdir, args.grade)
        gnss = read_survey(base).gnss
        truth = read_sleeper_truth(base / "truth" / "sleepers.csv")
        for name, fault in cases(float(gnss.time_s[0]), float(gnss.time_s[-1])).items():
            if args.only and not any(text in name for text in args.only):
                continue
            started = time.perf_counter()
            print(f"{name:32s} {run_case(base, workdir, name, fault, gnss, truth)}  {time.perf_counter() - started:5.1f} s",
                  flush=True)


if __name__ == "__main__":
    main()
