"""Simulate a trolley survey with a known truth (the benchmark scenarios).

Writes a survey folder in the documented raw formats (imu, gnss.pos, odometer, gauge,
sleepers, benchmarks, survey.toml) plus truth/ with the navigation truth at the IMU
rate, the per-sleeper truth of centreline and rails, the design alignment and the
realised sensor errors.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from insrail.cli.progressbar import TerminalProgress


def _positive(text: str) -> float:
    value = float(text)
    if not value > 0.0:
        raise argparse.ArgumentTypeError(f"expected a speed above 0 m/s, got {text}")
    return value


def add_arguments(p: argparse.ArgumentParser) -> None:
    from insrail.sim.scenario import PRESETS

    p.add_argument("--preset", choices=sorted(PRESETS), default="short", help="scenario (default: short, about 1.2 km)")
    p.add_argument("--grade", default="nav", help="IMU error preset: a profile of resources/imu_profiles (nav, tactical, tactical_fog, mems, mems_handheld, perfect) or a profile .toml (default: nav)")
    p.add_argument("--seed", type=int, default=1, help="random seed (default: 1)")
    p.add_argument("--speed", type=_positive, metavar="M/S",
                   help="cruise speed of the push [m/s] (default: the preset's, 1.2 in most)")
    p.add_argument("--accel-bias-mg", type=float, metavar="MG",
                   help="the accelerometers' turn-on bias on each axis [mg] (default: drawn from the grade's profile)")
    p.add_argument("--no-play", action="store_true",
                   help="a trolley without play: its frame follows the rails exactly")
    p.add_argument("--out", type=Path, required=True, help="survey folder to write")
    p.add_argument("--imu-format", choices=("text", "npy"), default="text", help="IMU file: KF-GINS text or binary .npy")
    p.add_argument("--gnss-velocity", action="store_true", help="add velocity columns to the GNSS solution")
    p.add_argument("--force", action="store_true", help="replace DIR if it exists")


def run(args: argparse.Namespace) -> int:
    from dataclasses import replace

    from insrail.nav.alignment import GRAVITY_MPS2 as STANDARD_GRAVITY_MPS2
    from insrail.sim.scenario import preset
    from insrail.sim.simulate import simulate

    config = preset(args.preset, imu_profile=args.grade)
    if args.speed is not None:
        config = replace(config, motion=replace(config.motion, cruise_speed_mps=args.speed))
    if args.accel_bias_mg is not None:
        config = replace(config, accel_bias_turn_on_mps2=(args.accel_bias_mg * 1e-3 * STANDARD_GRAVITY_MPS2,) * 3)
    if args.no_play:
        config = replace(config, play=replace(config.play, pitch_rms_rad=0.0, yaw_rms_rad=0.0))
    if args.gnss_velocity:
        config = replace(config, gnss=replace(config.gnss, with_velocity=True))
    bar = TerminalProgress(f"simulate {args.preset}")
    result = simulate(config, args.seed, args.out, imu_format=args.imu_format, overwrite=args.force, progress=bar)
    elapsed = bar.done()
    print(f"Simulated '{config.name}' ({result.length_m:.0f} m, {result.duration_s:.0f} s, IMU grade {args.grade}, seed {args.seed}) in {elapsed:.1f} s")
    print(f"  IMU epochs {result.imu_epochs}, GNSS epochs {result.gnss_epochs}, sleepers {result.sleepers}")
    print(f"Survey folder: {result.folder.resolve()}")
    for role, path in result.files.items():
        print(f"  {role:16s} {path.relative_to(result.folder)}")
    return 0
