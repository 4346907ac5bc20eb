"""Run insrail on the built-in demo survey (the simulated `short` scenario).

Simulates the 1.2 km `short` survey with a navigation-grade IMU into DIR/surveys/short
(replacing an earlier demo there), fuses it (GNSS + INS + odometer + NHC + ZUPT, RTS
smoother) into DIR/results/short, compares the result with the simulator's truth and
says what it wrote. Later processing stages join the demo as they land.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from insrail.cli.progressbar import TerminalProgress


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", type=Path, default=Path("insrail-demo"), help="demo folder (default: ./insrail-demo)")
    p.add_argument("--seed", type=int, default=1, help="random seed of the simulated survey (default: 1)")


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from insrail.io.survey import read_survey
    from insrail.nav.earth import CGCS2000
    from insrail.nav.fusion import fuse
    from insrail.nav.trajectory import save_trajectory, write_kfgins_nav
    from insrail.sim.evaluation import trajectory_errors
    from insrail.sim.scenario import preset
    from insrail.sim.simulate import simulate
    from insrail.sim.truth import read_nav_truth

    survey_dir = args.out / "surveys" / "short"
    bar = TerminalProgress("demo")
    result = simulate(preset("short"), args.seed, survey_dir, overwrite=True, progress=lambda f, m: bar(0.3 * f, m))
    print(f"insrail demo: simulated a {result.length_m:.0f} m trolley survey ({result.duration_s:.0f} s of data)")
    print(f"Survey folder: {result.folder.resolve()}")
    for role, path in result.files.items():
        print(f"  {role:16s} {str(path.relative_to(result.folder)):24s} {path.stat().st_size / 1e6:8.2f} MB")

    survey = read_survey(survey_dir)
    fusion = fuse(survey, ellipsoid=CGCS2000, progress=lambda f, m: bar(0.3 + 0.65 * f, m))
    results_dir = args.out / "results" / "short"
    results_dir.mkdir(parents=True, exist_ok=True)
    save_trajectory(results_dir / "trajectory.npy", fusion.trajectory)
    write_kfgins_nav(results_dir / "trajectory.nav", fusion.trajectory)
    elapsed = bar.done()
    errors = trajectory_errors(fusion.trajectory, read_nav_truth(survey_dir / "truth" / "nav.npy"), CGCS2000)
    lat5, ver5 = errors.lag_difference_sigma_m(5.0)
    lat150, ver150 = errors.lag_difference_sigma_m(150.0)
    rpy = np.rad2deg(errors.rms_attitude_rad())
    print(f"Fused and smoothed {len(survey.imu):,} IMU epochs; {len(fusion.rejections)} measurements rejected")
    print(f"Trajectory: {results_dir.resolve() / 'trajectory.nav'} (and trajectory.npy)")
    print("Accuracy against the simulator's truth:")
    print(f"  position RMS horizontal {1e3 * errors.rms_horizontal_m():.1f} mm, vertical {1e3 * errors.rms_vertical_m():.1f} mm")
    print(f"  attitude RMS roll {rpy[0]:.4f} deg, pitch {rpy[1]:.4f} deg, heading {rpy[2]:.4f} deg")
    print(f"  relative (1 sigma): 5 m apart lateral {1e3 * lat5:.2f} mm, vertical {1e3 * ver5:.2f} mm; "
          f"150 m apart lateral {1e3 * lat150:.2f} mm, vertical {1e3 * ver150:.2f} mm")
    print(f"Done in {elapsed:.1f} s. Raw formats: docs/formats.md; the simulator: docs/simulator.md.")
    return 0
