"""Fusion integrity on the simulator: GNSS faults, a filter started wrong, an untrustworthy survey.

    python benchmarks/integrity.py [--workdir DIR] [--only NAME ...]

On the `short` survey (nav grade, seed 1; and the same survey starting on the move) each
scenario is fused (smoothed) and compared with the truth and with the clean run:

- ``false-fix``: a constant 0.12/0.10/0.05 m (N/E/D, 16 cm horizontal) offset for 10 s while
  walking, still flagged fix (Q = 1);
- ``float``: 60 s of float solutions (Q = 2) wandering with 0.25 m RMS;
- ``outliers``: four single epochs off by 0.5 - 3 m;
- ``gnss-faults``: all three together;
- ``start-off``: the filter started 5 deg off in heading (as a wrong ``--heading``) from a first
  GNSS fix 1 m off (static start), and ``start-off-moving`` the same on a survey that starts
  on the move (track alignment), ``start-off-moving-45`` there 45 deg off;
- ``lever-mm``: the antenna lever arm given in millimetres (a survey that cannot be trusted).

Printed per scenario: RMS position error, the 1-sigma of the 5 m lag difference of the lateral
and vertical error (the 30 m/5 m irregularity error) and its ratio to the clean run's, the
fault epochs rejected and listed, the filter resets, the time from the start of motion until
the error stays within 3x the clean run's RMS, the NIS mean per source over its degrees of
freedom, and the integrity verdict (sections not valid).
"""

from __future__ import annotations

import argparse
import math
import tempfile
from dataclasses import replace
from pathlib import Path

import numpy as np

OUTLIERS = ((450.0, (2.0, 0.0, 0.0)), (700.0, (0.0, -0.5, 0.0)), (1000.0, (0.3, 0.3, -3.0)), (1250.0, (1.0, 1.0, 0.0)))
FALSE_FIX = (950.0, 10.0, (0.12, 0.10, 0.05))
FLOAT = (1100.0, 60.0, 0.25)


def survey_dir(workdir: Path, moving_start: bool) -> Path:
    from insrail.sim.scenario import preset
    from insrail.sim.simulate import simulate

    folder = workdir / ("short-moving-seed1" if moving_start else "short-seed1")
    if not (folder / "survey.toml").exists():
        config = preset("short")
        if moving_start:
            config = replace(config, motion=replace(config.motion, static_start_s=5.0))
        simulate(config, 1, folder, imu_format="npy", overwrite=True)
    return folder


def scenarios():
    """name -> (moving start, function(survey, truth) -> (survey, options overrides, fault times))."""
    from insrail.sim import gnss_faults

    def clean(survey, truth):
        return survey, {}, []

    def false_fix(survey, truth):
        t0 = survey.gnss.time_s[0] + FALSE_FIX[0]
        gnss = gnss_faults.false_fix(survey.gnss, t0, FALSE_FIX[1], FALSE_FIX[2])
        return replace(survey, gnss=gnss), {}, [(t0, t0 + FALSE_FIX[1])]

    def float_stretch(survey, truth):
        t0 = survey.gnss.time_s[0] + FLOAT[0]
        gnss = gnss_faults.float_stretch(survey.gnss, t0, FLOAT[1], FLOAT[2])
        return replace(survey, gnss=gnss), {}, [(t0, t0 + FLOAT[1])]

    def outliers(survey, truth):
        times = [survey.gnss.time_s[0] + dt for dt, _ in OUTLIERS]
        gnss = gnss_faults.outliers(survey.gnss, times, [o for _, o in OUTLIERS])
        return replace(survey, gnss=gnss), {}, [(t - 0.5, t + 0.5) for t in times]

    def all_gnss(survey, truth):
        faults = []
        for f in (false_fix, float_stretch, outliers):
            survey, _, more = f(survey, truth)
            faults += more
        return survey, {}, faults

    def start_off(survey, truth, degrees=5.0):
        # The first fix (where the start takes its position) 1 m off, the heading 5 deg off.
        first = survey.gnss.time_s[0]
        gnss = gnss_faults.outliers(survey.gnss, [first], [(0.8, 0.6, 0.0)])
        k = int(np.searchsorted(truth["time_s"], first))
        heading = float(truth["rpy_rad"][k, 2]) + math.radians(degrees)
        return replace(survey, gnss=gnss), {"initial_heading_rad": heading}, []

    def start_off_45(survey, truth):
        return start_off(survey, truth, 45.0)

    def lever_mm(survey, truth):
        trolley = survey.manifest.trolley
        wrong = replace(trolley, imu_to_antenna_m=np.asarray(trolley.imu_to_antenna_m) * 1000.0)
        return replace(survey, manifest=replace(survey.manifest, trolley=wrong)), {}, []

    return {"clean": (False, clean), "false-fix": (False, false_fix), "float": (False, float_stretch),
            "outliers": (False, outliers), "gnss-faults": (False, all_gnss), "start-off": (False, start_off),
            "clean-moving": (True, clean), "start-off-moving": (True, start_off),
            "start-off-moving-45": (True, start_off_45), "lever-mm": (False, lever_mm)}


def recovery_s(errors, clean_rms_m: float, resets) -> float:
    """Seconds from the start of motion (or from the first reset, if later) until the smoothed
    horizontal error stays within 3x the clean run's RMS; 0 when it always was."""
    moving = np.flatnonzero(errors.moving)
    start = errors.time_s[moving[0]]
    bad = np.flatnonzero(np.hypot(errors.ned_m[:, 0], errors.ned_m[:, 1]) > 3.0 * clean_rms_m)
    bad = bad[errors.time_s[bad] >= start]
    return 0.0 if bad.size == 0 else float(errors.time_s[bad[-1]] - start)


def after(errors, time_s: float):
    """The errors from ``time_s`` on."""
    keep = errors.time_s >= time_s
    return replace(errors, **{f: getattr(errors, f)[keep] for f in
                              ("time_s", "station_m", "ned_m", "lateral_m", "vertical_m", "rpy_rad", "moving")})


def main(argv: list[str] | None = None) -> None:
    from insrail.io.survey import read_survey
    from insrail.nav.earth import CGCS2000
    from insrail.nav.fusion import FusionOptions, fuse_survey
    from insrail.sim.evaluation import trajectory_errors
    from insrail.sim.truth import read_nav_truth

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workdir", type=Path, help="keep the simulated surveys here (default: a temporary folder)")
    parser.add_argument("--only", nargs="+", help="run only these scenarios (the clean runs always run)")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="insrail-integrity-bench-") as tmp:
        workdir = args.workdir or Path(tmp)
        workdir.mkdir(parents=True, exist_ok=True)
        clean = {}
        for name, (moving, make) in scenarios().items():
            if args.only and name not in args.only and not name.startswith("clean"):
                continue
            if args.only and name.startswith("clean") and not any(
                    scenarios()[o][0] == moving for o in args.only):
                continue
            folder = survey_dir(workdir, moving)
            survey = read_survey(folder)
            truth = read_nav_truth(folder / "truth" / "nav.npy")
            faulty, overrides, fault_times = make(survey, truth)
            result = fuse_survey(faulty, FusionOptions(**overrides), ellipsoid=CGCS2000, output_every=2)
            errors = trajectory_errors(result.trajectory, truth, CGCS2000)
            lat5, ver5 = errors.lag_difference_sigma_m(5.0)
            if name.startswith("clean"):
                clean[moving] = (errors.rms_horizontal_m(), lat5, ver5)
            ref = clean.get(moving, (math.nan, math.nan, math.nan))
            rejected = [r for r in result.rejections if r.measurement == "gnss_position"]
            in_fault = [r for r in rejected if any(a <= r.time_s <= b for a, b in fault_times)]
            fault_epochs = sum(int(np.sum((survey.gnss.time_s >= a) & (survey.gnss.time_s < b))) for a, b in fault_times)
            print(f"\n{name}: horizontal RMS {1e3 * errors.rms_horizontal_m():.2f} mm, vertical RMS "
                  f"{1e3 * errors.rms_vertical_m():.2f} mm; 5 m lag 1-sigma lateral {1e3 * lat5:.3f} mm "
                  f"({lat5 / ref[1]:.2f} x clean), vertical {1e3 * ver5:.3f} mm ({ver5 / ref[2]:.2f} x clean)")
            if fault_times:
                print(f"  GNSS fault epochs {fault_epochs}: {len(in_fault)} rejected and listed; "
                      f"{len(rejected) - len(in_fault)} other GNSS epochs rejected")
            recovered = recovery_s(errors, ref[0], result.resets)
            print(f"  recovered {recovered:.1f} s after the start of motion "
                  f"(error within 3x the clean RMS {1e3 * ref[0]:.1f} mm from then on)")
            if recovered > 0.0:
                rest = after(errors, errors.time_s[errors.moving][0] + recovered)
                r5 = rest.lag_difference_sigma_m(5.0)
                print(f"  the rest of the survey: horizontal RMS {1e3 * rest.rms_horizontal_m():.2f} mm, vertical RMS "
                      f"{1e3 * rest.rms_vertical_m():.2f} mm; 5 m lag 1-sigma lateral {1e3 * r5[0]:.3f} mm "
                      f"({r5[0] / ref[1]:.2f} x clean), vertical {1e3 * r5[1]:.3f} mm ({r5[1] / ref[2]:.2f} x clean)")
            for reset in result.resets:
                print(f"  {reset.message()}")
            nis = ", ".join(f"{k} {v['mean_nis_per_dof']:.2f}" for k, v in result.statistics.items())
            print(f"  NIS mean / dof: {nis}")
            integrity = getattr(result, "integrity", None)
            if integrity is not None:
                print(f"  integrity: {integrity.summary()}")


if __name__ == "__main__":
    main()
