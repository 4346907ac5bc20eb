"""Estimate the IMU's mounting on the trolley from a survey and print it for its survey.toml.

Pitch and yaw of the IMU in the trolley frame come from a pass of the fusion without the
non-holonomic constraint: the reference rail point's velocity, which runs along the rail, seen in
the IMU's axes (the survey needs GNSS). The roll needs the cant against a design's (thesis 5.3.1.2):
``insrail process`` estimates it for a project with a design (summary.toml [fusion.mounting]); here
the survey's own roll is kept. Prints each estimate with its 1-sigma and the line
``mounting_rpy_deg = [...]`` for the survey.toml's [trolley] table; exit 1 where nothing can be estimated.
"""

from __future__ import annotations

import argparse
import math
import sys
from dataclasses import replace
from pathlib import Path

from insrail.cli.progressbar import TerminalProgress
from insrail.geodesy.ellipsoid import ELLIPSOIDS


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("survey", type=Path, help="survey folder (with survey.toml)")
    p.add_argument("--imu-profile", help="IMU error profile name or .toml (default: the survey's)")
    p.add_argument("--ellipsoid", choices=tuple(ELLIPSOIDS), default="CGCS2000",
                   help="navigation ellipsoid (default CGCS2000)")


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from insrail.io.survey import read_survey
    from insrail.nav.fusion import FusionOptions, aiding_for, fuse
    from insrail.nav.imu_profile import load_imu_profile
    from insrail.project.mounting_stage import yaw_pitch_pass

    bar = TerminalProgress("calibrate")
    survey = read_survey(args.survey, progress=lambda f, m: bar(0.05 * f, m))
    # one odometer serves the pass; a second is used once compared with the first (insrail process, fuse)
    survey = replace(survey, odometer_right=None)
    try:
        profile = load_imu_profile(args.imu_profile or survey.manifest.imu_profile)
        estimate = yaw_pitch_pass(survey, lambda o: aiding_for(survey, o, profile), profile, FusionOptions(),
                                  ELLIPSOIDS[args.ellipsoid], fuse, progress=lambda f, m: bar(0.05 + 0.95 * f, m))
    except ValueError as err:
        bar.done()
        print(f"insrail calibrate: survey {survey.manifest.name} ({args.survey}): {err}", file=sys.stderr)
        return 1
    bar.done()
    print(estimate.text())
    if not np.isfinite(estimate.sigma_rad).any():
        print(f"insrail calibrate: survey {survey.manifest.name} ({args.survey}): nothing estimated", file=sys.stderr)
        return 1
    found = np.where(np.isfinite(estimate.sigma_rad), estimate.rpy_rad, estimate.given_rpy_rad)
    kept = ", ".join(axis for axis, ok in zip(("roll", "pitch", "yaw"), np.isfinite(estimate.sigma_rad)) if not ok)
    sigmas = ", ".join(f"{math.degrees(s):.4f}" if np.isfinite(s) else "-" for s in estimate.sigma_rad)
    print(f"for {args.survey / 'survey.toml'} [trolley]:")
    print(f"mounting_rpy_deg = [{', '.join(f'{v:.4f}' for v in np.degrees(found))}]  "
          f"# 1-sigma [{sigmas}] deg" + (f"; {kept} as given" if kept else ""))
    return 0
