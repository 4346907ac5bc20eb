"""Predict the accuracy of a planned survey (covariance analysis of the fusion).

Straight track at constant speed after a 300 s static alignment: the 1-sigma and 3-sigma
of the absolute position, the cant and the 5 m and 150 m lag differences behind the
30 m/5 m (2 mm) and 300 m/150 m (10 mm) checks, for the RTS-smoothed solution (default)
or the forward filter. --sweep PARAM repeats the prediction for several values of one
parameter (gyro_bias deg/h, accel_bias mGal, arw deg/sqrt(h), vrw m/s/sqrt(h),
gnss_sigma m, speed m/s).
"""

from __future__ import annotations

import argparse
import math
import sys

from insrail.cli.progressbar import TerminalProgress


def _number(low: float, high: float, low_included: bool = False):
    """An argparse type: a finite number in (low, high] (or [low, high])."""
    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a number, found {text!r}") from None
        above = value >= low if low_included else value > low
        if not (math.isfinite(value) and above and value <= high):
            bound = "at least" if low_included else "more than"
            raise argparse.ArgumentTypeError(f"{text}: expected {bound} {low:g} and at most {high:g}")
        return value
    return parse


def _imu_profile(text: str) -> str:
    """An argparse type: a shipped IMU profile's name or an existing .toml file."""
    from insrail.nav.imu_profile import load_imu_profile

    try:
        load_imu_profile(text)
    except ValueError as err:
        raise argparse.ArgumentTypeError(str(err)) from None
    return text


def add_arguments(p: argparse.ArgumentParser) -> None:
    from insrail.quality.tables import SWEEP_VALUES  # imports the quality package (numba): only for predict

    p.add_argument("--imu", default="nav", type=_imu_profile, help="IMU profile name or .toml (default: nav)")
    p.add_argument("--gnss-sigma", type=_number(0.0, 100.0), nargs=2, metavar=("H", "V"), default=(0.010, 0.020),
                   help="white GNSS sigma horizontal and vertical [m] (default 0.010 0.020)")
    p.add_argument("--speed", type=_number(0.0, 100.0), default=1.0, help="trolley speed [m/s] (default 1)")
    p.add_argument("--length", type=_number(0.0, 1e6), default=1000.0, help="track length [m] (default 1000)")
    p.add_argument("--outage", type=_number(0.0, 1e6, low_included=True), default=0.0,
                   help="a GNSS outage of this many seconds mid-run")
    p.add_argument("--no-nhc", action="store_true", help="without the non-holonomic constraint")
    p.add_argument("--relative", action="store_true",
                   help="a relative survey: no GNSS, no prism; odometer, NHC and stops (see --stop-every)")
    p.add_argument("--stop-every", type=_number(0.0, 1e6), default=60.0, metavar="M",
                   help="with --relative: a stop every M metres (default 60, seed 000)")
    p.add_argument("--stop-s", type=_number(0.0, 3600.0), default=10.0, metavar="S",
                   help="with --relative: each stop's duration [s] (default 10)")
    p.add_argument("--sweep", choices=sorted(SWEEP_VALUES), help="vary one parameter from the baseline")
    p.add_argument("--values", type=float, nargs="+", help="values of the swept parameter (default: a typical range)")
    group = p.add_mutually_exclusive_group()
    group.add_argument("--smoothed", dest="smoothed", action="store_true", default=True,
                       help="figures of the RTS-smoothed solution (default)")
    group.add_argument("--forward", dest="smoothed", action="store_false", help="figures of the forward filter")


def run(args: argparse.Namespace) -> int:
    from insrail.nav.fusion_options import FusionOptions
    from insrail.quality.prediction import GnssQuality, predict
    from insrail.quality.sweep import sweep
    from insrail.quality.tables import (
        SWEEP_VALUES,
        accuracy_rows,
        accuracy_table,
        prediction_heading,
        sweep_table,
    )

    gnss = None if args.relative else GnssQuality(*args.gnss_sigma)
    aiding = FusionOptions(smoother=args.smoothed, use_nhc=not args.no_nhc)
    outages = ((0.5 * args.length, args.outage),) if args.outage > 0 else ()
    if args.relative and (args.sweep or outages):
        print("insrail predict: --relative has no GNSS: no --outage, and no --sweep", file=sys.stderr)
        return 2
    import numpy as np  # only when predicting: `insrail --help` imports no numerical library

    stops = (tuple((float(s), args.stop_s) for s in np.arange(args.stop_every, args.length - 1.0, args.stop_every))
             if args.relative else ())
    bar = TerminalProgress("predict")
    if args.sweep:
        values = args.values or SWEEP_VALUES[args.sweep]
        table = sweep(args.sweep, values, args.imu, gnss, speed_mps=args.speed, aiding=aiding, length_m=args.length,
                      outages=outages, progress=bar)
        bar.done()
        print("\n".join(sweep_table(table, args.smoothed, bool(outages))))
        return 0
    prediction = predict(args.imu, gnss, aiding, speed_mps=args.speed, length_m=args.length, outages=outages,
                         stops=stops, progress=bar)
    elapsed = bar.done()
    figures = prediction.smoothed if args.smoothed else prediction.forward
    print(f"{prediction_heading(prediction, args.smoothed)} ({elapsed:.1f} s)")
    print("\n".join(accuracy_table(accuracy_rows(figures, bool(outages), relative=args.relative))))
    return 0
