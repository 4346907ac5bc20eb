"""Fuse a survey's IMU, GNSS and odometer into a trajectory (EKF + RTS smoother).

Reads the survey folder (survey.toml and its raw files), runs the GNSS/INS/odometer
filter with NHC and ZUPT and the smoother, and writes into OUT: trajectory.npy (every
field, SI; streamed to disk as it is made) and fusion_log.toml (measurement statistics,
every rejected measurement with its time and size, stops, alignment, options); with
--forward also forward_trajectory.npy, with --text the KF-GINS text files trajectory.nav,
trajectory_std.txt and imu_errors.txt (of every written trajectory).

Total-station prism fixes ([files.prism], or raw observations [files.total_station] resected on
[files.cpiii]) are in engineering coordinates: with --project PROJECT they are placed by that
project's CRS and height model (and its trolley and ellipsoid apply), as ``insrail process`` does.
Without it they cannot be placed: a survey with GNSS is fused on its GNSS alone and says so, a
survey without GNSS is refused.
"""

from __future__ import annotations

import argparse
import math
import sys
from dataclasses import asdict, replace
from functools import partial
from pathlib import Path

from insrail.cli.progressbar import TerminalProgress
from insrail.geodesy.ellipsoid import ELLIPSOIDS


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("survey", type=Path, help="survey folder (with survey.toml)")
    p.add_argument("--out", type=Path, required=True, help="folder for the results")
    p.add_argument("--no-smoother", action="store_true", help="forward filter only")
    p.add_argument("--no-nhc", action="store_true", help="do not use the non-holonomic constraint")
    p.add_argument("--gnss-only", action="store_true", help="GNSS positions only: no odometer, NHC or ZUPT")
    p.add_argument("--imu-profile", help="IMU error profile name or .toml (default: the survey's)")
    p.add_argument("--rate", type=float, default=0.0, help="output rate [Hz] (default: the IMU rate)")
    p.add_argument("--project", type=Path,
                   help="project (folder or project.toml) whose CRS and height model place the survey's total-station "
                        "prism fixes in the fusion (its trolley and ellipsoid then apply too)")
    p.add_argument("--ellipsoid", choices=tuple(ELLIPSOIDS),
                   help="navigation ellipsoid (default: the project's with --project, else CGCS2000)")
    p.add_argument("--heading", type=float,
                   help="initial heading of the IMU [deg]: skips the gyrocompass and sets the start velocity's direction")
    p.add_argument("--heading-sigma", type=float, default=0.1,
                   help="1-sigma of the --heading [deg] (default 0.1)")
    p.add_argument("--gnss-sigma-scale", type=float, default=1.0, help="factor on the GNSS file's sigmas (default 1)")
    p.add_argument("--gnss-sigma-floor", type=float, default=2.0, help="smallest GNSS sigma used [mm] (default 2)")
    p.add_argument("--forward", action="store_true",
                   help="also write the forward filter's solution (forward_trajectory.npy) beside the smoothed one")
    p.add_argument("--text", action="store_true",
                   help="also write the KF-GINS text files (trajectory.nav, trajectory_std.txt, imu_errors.txt)")


def run(args: argparse.Namespace) -> int:
    from insrail.background import BackgroundJob
    from insrail.io.survey import read_survey
    from insrail.memory import collector_paused

    bar = TerminalProgress("fuse")
    # a project's [trolley] replaces the survey's own, which may then be left out
    project_trolley = args.project is not None and _project_trolley_given(args.project)
    reading_progress = partial(_reading_progress, bar)
    # the survey's files read (their text parsed by compiled code, without the GIL) while the filter's modules are
    # imported: some 0.2 s of a short survey's 2 s; the start-up without the garbage collector's passes
    with collector_paused(), BackgroundJob(lambda progress, cancel: read_survey(args.survey, progress=progress,
                                                                                trolley_from_project=project_trolley),
                                           reading_progress, None, name="insrail-reading") as reading:
        import tomli_w

        from insrail.io.atomic import atomic_write
        from insrail.io.errors import InputError
        from insrail.nav.fusion import QUALITY_NAMES, FusionOptions, aiding_for
        from insrail.nav.imu_profile import load_imu_profile
        from insrail.nav.pass_memo import PassMemo
        from insrail.nav.relative import RelativeFrame
        from insrail.nav.self_calibration import fuse_consistent
        from insrail.nav.trajectory import write_kfgins_imu_errors, write_kfgins_nav, write_kfgins_std

        survey = reading.result(reading_progress)
    options = FusionOptions(
        smoother=not args.no_smoother,
        use_nhc=not (args.no_nhc or args.gnss_only),
        use_odometer=not args.gnss_only,
        use_zupt=not args.gnss_only,
        initial_heading_rad=None if args.heading is None else math.radians(args.heading),
        initial_sigma_heading_rad=math.radians(args.heading_sigma),
        gnss_sigma_scale=args.gnss_sigma_scale,
        gnss_sigma_floor_m=args.gnss_sigma_floor / 1000.0,
    )
    try:
        survey, fixes, project_ellipsoid, placed = _prism_fixes(survey, args.project)
        if survey.odometer_right is not None:  # the second odometer on the first's scale, its slips left out
            from insrail.project.odometer_pair_stage import with_odometer_pair
            from insrail.project.plausibility import file_labels
            survey, pair_notices, _ = with_odometer_pair(survey, file_labels(survey))
            placed = [*placed, *pair_notices]
    except ValueError as err:
        if isinstance(err, InputError):
            raise
        bar.stopped()
        print(f"insrail fuse: survey {survey.manifest.name} ({args.survey}): {err}", file=sys.stderr)
        return 1
    if args.ellipsoid is not None and project_ellipsoid is not None and args.ellipsoid != project_ellipsoid.name:
        bar.stopped()
        print(f"insrail fuse: --ellipsoid {args.ellipsoid} conflicts with the project's CRS on {project_ellipsoid.name}: "
              "leave it out with --project", file=sys.stderr)
        return 2
    if survey.manifest.start is not None:  # the design is the project's: fuse reads none
        print(f"insrail fuse: survey {survey.manifest.name}: survey.toml [start] (station "
              f"{survey.manifest.start.station_m:g} m) is not used: the start on the design needs the project's design "
              "(insrail process); the fusion starts from the positions", file=sys.stderr)
    every = max(int(round(survey.imu.rate_hz / args.rate)), 1) if args.rate > 0 else 1
    ellipsoid = project_ellipsoid or ELLIPSOIDS[args.ellipsoid or "CGCS2000"]
    args.out.mkdir(parents=True, exist_ok=True)
    # Streamed under staging names; an untrustworthy solution is not put where a user would take it.
    staged = {"trajectory.npy": args.out / ".trajectory.fusing.npy"}
    if args.forward and options.smoother:
        staged["forward_trajectory.npy"] = args.out / ".forward_trajectory.fusing.npy"
    try:
        profile = load_imu_profile(args.imu_profile or survey.manifest.imu_profile)
        # fused again where the first pass shows the NHC or the GNSS sigmas do not hold (self_calibration)
        # a relative survey (no position source) runs in a local frame: no project, no design here
        frame = RelativeFrame.local() if survey.manifest.relative else None
        result, options, _, _ = fuse_consistent(survey.imu, lambda o: replace(aiding_for(survey, o, profile, fixes),
                                                                              relative=frame), profile, options,
                                                ellipsoid, output_every=every,
                                                progress=lambda f, m: bar(0.05 + 0.85 * f, m),
                                                trajectory_file=staged["trajectory.npy"],
                                                forward_file=staged.get("forward_trajectory.npy"),
                                                memo=PassMemo())  # each pass's IMU screening made once
    except BaseException as err:
        for path in staged.values():
            path.unlink(missing_ok=True)
        if isinstance(err, InputError) or not isinstance(err, ValueError):
            raise
        # profile, start-up, screening, filter: the message says what to do
        bar.stopped()
        print(f"insrail fuse: survey {survey.manifest.name} ({args.survey}): {err}", file=sys.stderr)
        return 1
    bar(0.9, "writing")
    traj = result.trajectory
    verdict = result.integrity
    for name, path in staged.items():
        if verdict.trusted:
            path.replace(args.out / name)
        else:
            path.unlink(missing_ok=True)
    if verdict.trusted and args.text:
        write_kfgins_nav(args.out / "trajectory.nav", traj)
        write_kfgins_std(args.out / "trajectory_std.txt", traj)
        write_kfgins_imu_errors(args.out / "imu_errors.txt", traj)
        if "forward_trajectory.npy" in staged:
            write_kfgins_nav(args.out / "forward_trajectory.nav", result.forward)
    log = {
        "survey": str(args.survey.resolve()),
        "imu_profile": profile.name,
        "options": {k: v for k, v in asdict(options).items() if v is not None and k != "gnss_quality_policy"},
        "gnss_quality_policy": {QUALITY_NAMES[q]: ("excluded" if f is None else f) for q, f in options.gnss_quality_policy},
        "alignment_rpy_deg": [float(a) * 57.29577951308232 for a in result.info["alignment_rpy_rad"]],
        "odometer_scale_ppm": float(traj.odometer_scale[-1] * 1e6),
        "stops_s": [list(s) for s in result.stops],
        "warnings": result.info["warnings"],
        "prism_fixes": 0 if fixes is None else len(fixes.time_s),
        "notices": [n.to_dict() for n in (*placed, *result.info["notices"])],
        "alignment": result.info["alignment"],
        "imu_outliers_removed": [
            {"time_s": o.time_s, "record": o.index + 1, "quantity": o.quantity, "axis": o.axis, "reason": o.reason,
             "value": o.value if math.isfinite(o.value) else str(o.value), "neighbours_median": o.reference}
            for o in result.info["imu_outliers"] if math.isfinite(o.reference)
        ] + [{"time_s": o.time_s, "record": o.index + 1, "quantity": o.quantity, "axis": o.axis, "reason": o.reason,
              "value": str(o.value)} for o in result.info["imu_outliers"] if not math.isfinite(o.reference)],
        "imu_gaps_bridged_s": [[g.start_s, g.end_s] for g in result.info["imu_gaps"]],
        "along_track_scale": "odometer" if survey.odometer is not None else "GNSS positions only (no odometer)",
        "gnss_quality": {k: {kk: vv for kk, vv in v.items() if vv is not None} for k, v in result.info["gnss_quality"].items()},
        "measurements": result.statistics,
        "resets": [{"time_s": r.time_s, "source": r.source, "rejected_s": r.rejected_s, "rejected": r.rejected,
                    "also_rejected": list(r.also_rejected), "states": list(r.states), "sigma": list(r.sigma)}
                   for r in result.resets],
        "integrity": verdict.to_dict(),
        "calibration": result.info["calibration"],
        "rejected": [
            {"time_s": r.time_s, "measurement": r.measurement, "test_statistic": r.test_statistic,
             "threshold": r.threshold, "innovation": list(r.innovation)}
            for r in result.rejections
        ],
    }
    with atomic_write(args.out / "fusion_log.toml") as stream:
        stream.write(tomli_w.dumps(log))
    elapsed = bar.done()
    for notice in (*placed, *result.info["notices"]):
        print(f"{'warning' if notice.severity == 'warning' else 'note'}: {notice.text()}")
    kind = "smoothed" if options.smoother else "forward"
    print(f"Fused {len(survey.imu):,} IMU epochs in {elapsed:.1f} s ({kind}); {len(result.rejections)} measurements rejected")
    for quality, c in result.info["gnss_quality"].items():
        how = f"used, sigma x {c['sigma_factor']:g}" if c["used"] else "excluded"
        print(f"  GNSS {quality:8s} {c['epochs']:7d} epochs ({how})")
    for name, st in result.statistics.items():
        print(f"  {name:14s} used {st['used']:7d}  rejected {st['rejected']:4d}  mean NIS {st['mean_nis']:.2f} "
              f"({st['mean_nis_per_dof']:.2f} x its degrees of freedom)")
    print(f"  integrity: {verdict.summary()}")
    if not verdict.trusted:
        print(f"insrail: survey {args.survey}: {verdict.failure()}; only fusion_log.toml was written",
              file=sys.stderr)
        return 1
    print(f"  odometer scale {traj.odometer_scale[-1] * 1e6:+.0f} ppm; final 1-sigma N/E/D "
          + "/".join(f"{1e3 * s:.1f}" for s in traj.sigma_pos_ned_m[-1]) + " mm")
    print(f"Results: {args.out.resolve()}")
    return 0


def _reading_progress(bar: TerminalProgress, fraction: float, message) -> None:
    bar(0.05 * fraction, message)


def _prism_fixes(survey, project_path: Path | None):
    """(survey with its raw total-station observations placed, the prism fixes as position fixes or
    None, the project's ellipsoid or None, the notices of placing them): module docstring. Raises
    ValueError for a survey whose only position source is fixes that cannot be placed."""
    from dataclasses import replace

    count = sum(len(getattr(survey, role)) for role in ("prism", "total_station") if getattr(survey, role) is not None)
    if project_path is None:
        if count and survey.gnss is None:
            raise ValueError(f"its {count} total-station observation(s) are its only position source and are in "
                             "engineering coordinates: give --project PROJECT, whose CRS and height model place them")
        if count:
            print(f"note: the survey's {count} total-station observation(s) are not used: their engineering "
                  "coordinates need a project's CRS and height model (--project PROJECT); fused on GNSS alone")
        return survey, None, None, []
    from insrail.notices import Notice  # the project's pipeline (and its tracks) only for --project
    from insrail.project.model import load_project
    from insrail.project.pipeline import fit_heights, prism_fixes
    from insrail.project.total_station import with_total_station_fixes

    project = load_project(project_path)
    trolley = project.trolley(set(survey.manifest.files))
    if trolley is not None:
        survey = replace(survey, manifest=replace(survey.manifest, trolley=trolley))
    if not count:
        return survey, None, project.crs.reference_ellipsoid, []
    survey, placed = with_total_station_fixes(survey)
    fixes = prism_fixes(project, survey.prism, survey.manifest.trolley, fit_heights(project))
    placed = [*placed, Notice("fuse", "{count} total-station prism fix(es) placed by project {project} ({crs})",
                              severity="info", fields={"count": len(fixes.time_s), "project": project.name,
                                                       "crs": project.crs.describe()})]
    return survey, fixes, project.crs.reference_ellipsoid, placed


def _project_trolley_given(project: Path) -> bool:
    """Whether the project gives the [trolley] (the project model, and the track code it imports, are
    loaded only for --project)."""
    from insrail.project.model import load_project

    return load_project(project).trolley_settings is not None
