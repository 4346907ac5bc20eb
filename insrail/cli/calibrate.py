"""Estimate the IMU's mounting on the trolley from a survey and print it for its survey.toml.

Pitch and yaw of the IMU in the trolley frame come from a pass of the fusion without the
non-holonomic constraint: the reference rail point's velocity, which runs along the rail, seen in
the IMU's axes (the survey needs GNSS). The roll needs the cant against a design's (thesis 5.3.1.2):
where the survey belongs to a project with a design (``--project``, else the project.toml in a folder
above the survey that lists it), the survey is processed in it (``insrail.project.pipeline.process``,
its fusion and track cached as for ``insrail process``; its results are written) and the three axes are
those it estimates (summary.toml [fusion.mounting]); elsewhere the survey's own roll is kept and said.
Prints each estimate with its 1-sigma and the line ``mounting_rpy_deg = [...]`` for the [trolley]
table it came from (survey.toml, or project.toml when the project gives the trolley); exit 1 where
nothing can be estimated.
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
    p.add_argument("--project", type=Path,
                   help="the survey's project (default: the project.toml in a folder above the survey listing it); "
                        "with a design the roll is estimated too")
    p.add_argument("--imu-profile", help="IMU error profile name or .toml (default: the survey's; without a project)")
    p.add_argument("--ellipsoid", choices=tuple(ELLIPSOIDS), default="CGCS2000",
                   help="navigation ellipsoid (default CGCS2000; without a project)")


def project_of(survey: Path, given: Path | None):
    """(project, survey name) the survey folder belongs to, or None: ``given`` (a project folder or its
    project.toml; an error when it does not list the survey), else the first project.toml above the
    survey that lists it."""
    from insrail.project.model import load_project

    folder = survey.resolve()
    candidates = [given] if given is not None else [p / "project.toml" for p in folder.parents
                                                     if (p / "project.toml").is_file()]
    for path in candidates:
        project = load_project(path)
        for entry in project.surveys:
            if project.resolve(entry.folder).resolve() == folder:
                return project, entry.name
        if given is not None:
            raise ValueError(f"{project.path}: lists no survey in {survey}")
    return None


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from insrail.io.survey import read_survey
    from insrail.nav.fusion import FusionOptions, aiding_for, fuse
    from insrail.nav.imu_profile import load_imu_profile
    from insrail.nav.mounting import MountingEstimate
    from insrail.project.mounting_stage import yaw_pitch_pass

    bar = TerminalProgress("calibrate")
    target = "survey.toml"
    try:
        found = project_of(args.survey, args.project)
        if found is not None and found[0].design is not None:
            from insrail.project.pipeline import process

            project, name = found
            results = process(project, name, progress=bar)
            trolley = project.trolley()
            given = trolley.mounting_rpy_rad if trolley is not None else project.manifest(name).trolley.mounting_rpy_rad
            estimate = MountingEstimate.from_dict(results.summary["fusion"]["mounting"], given)
            target = "project.toml" if trolley is not None else target
            where = f"survey {name} processed in {project.path} (results in {results.folder})"
        else:
            survey = read_survey(args.survey, progress=lambda f, m: bar(0.05 * f, m))
            # one odometer serves the pass; a second is used once compared with the first (insrail process, fuse)
            survey = replace(survey, odometer_right=None)
            profile = load_imu_profile(args.imu_profile or survey.manifest.imu_profile)
            estimate = yaw_pitch_pass(survey, lambda o: aiding_for(survey, o, profile), profile, FusionOptions(),
                                      ELLIPSOIDS[args.ellipsoid], fuse, progress=lambda f, m: bar(0.05 + 0.95 * f, m))
            where = ("not in a project with a design: the roll needs the design's cant (--project)" if found is None
                     else f"{found[0].path} has no design: the roll needs the design's cant")
    except ValueError as err:
        bar.stopped()
        print(f"insrail calibrate: {args.survey}: {err}", file=sys.stderr)
        return 1
    bar.done()
    print(where)
    print(estimate.text())
    if not np.isfinite(estimate.sigma_rad).any():
        print(f"insrail calibrate: {args.survey}: nothing estimated", file=sys.stderr)
        return 1
    found_rpy = np.where(np.isfinite(estimate.sigma_rad), estimate.rpy_rad, estimate.given_rpy_rad)
    kept = ", ".join(axis for axis, ok in zip(("roll", "pitch", "yaw"), np.isfinite(estimate.sigma_rad)) if not ok)
    sigmas = ", ".join(f"{math.degrees(s):.4f}" if np.isfinite(s) else "-" for s in estimate.sigma_rad)
    print(f"for {target if target == 'project.toml' else args.survey / 'survey.toml'} [trolley]:")
    print(f"mounting_rpy_deg = [{', '.join(f'{v:.4f}' for v in np.degrees(found_rpy))}]  "
          f"# 1-sigma [{sigmas}] deg" + (f"; {kept} as given" if kept else ""))
    return 0
