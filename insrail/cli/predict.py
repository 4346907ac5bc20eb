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

from insrail.cli.progressbar import TerminalProgress

#: figure -> (label, tolerance [mm] of the check it stands for, or None)
ROWS = {
    "position_lateral_m": ("absolute position, lateral", None),
    "position_vertical_m": ("absolute position, vertical", None),
    "cant_m": ("cant (1500 mm x roll)", 2.0),
    "lag5_lateral_m": ("30 m/5 m alignment (5 m lag)", 2.0),
    "lag5_vertical_m": ("30 m/5 m vertical (5 m lag)", 2.0),
    "lag150_lateral_m": ("300 m/150 m alignment (150 m lag)", 10.0),
    "lag150_vertical_m": ("300 m/150 m vertical (150 m lag)", 10.0),
    "outage_growth_lateral_m": ("outage: lateral sigma growth", None),
    "outage_growth_vertical_m": ("outage: vertical sigma growth", None),
}
SWEEP_DEFAULTS = {
    "gyro_bias": (0.005, 0.01, 0.1, 1.0),
    "accel_bias": (10.0, 25.0, 100.0, 300.0),
    "arw": (0.0022, 0.01, 0.05, 0.1),
    "vrw": (0.00075, 0.003, 0.01, 0.03),
    "gnss_sigma": (0.005, 0.01, 0.02, 0.05),
    "speed": (0.25, 0.5, 1.0, 2.0, 5.0),
}


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--imu", default="nav", help="IMU profile name or .toml (default: nav)")
    p.add_argument("--gnss-sigma", type=float, nargs=2, metavar=("H", "V"), default=(0.010, 0.020),
                   help="white GNSS sigma horizontal and vertical [m] (default 0.010 0.020)")
    p.add_argument("--speed", type=float, default=1.0, help="trolley speed [m/s] (default 1)")
    p.add_argument("--length", type=float, default=1000.0, help="track length [m] (default 1000)")
    p.add_argument("--outage", type=float, default=0.0, help="a GNSS outage of this many seconds mid-run")
    p.add_argument("--no-nhc", action="store_true", help="without the non-holonomic constraint")
    p.add_argument("--sweep", choices=sorted(SWEEP_DEFAULTS), help="vary one parameter from the baseline")
    p.add_argument("--values", type=float, nargs="+", help="values of the swept parameter (default: a typical range)")
    group = p.add_mutually_exclusive_group()
    group.add_argument("--smoothed", dest="smoothed", action="store_true", default=True,
                       help="figures of the RTS-smoothed solution (default)")
    group.add_argument("--forward", dest="smoothed", action="store_false", help="figures of the forward filter")


def _mm(value_m: float) -> str:
    return f"{'-':>8}" if math.isnan(value_m) else f"{1e3 * value_m:8.3f}"


def run(args: argparse.Namespace) -> int:
    from insrail.nav.fusion import FusionOptions
    from insrail.quality.prediction import GnssQuality, predict
    from insrail.quality.sweep import sweep

    gnss = GnssQuality(*args.gnss_sigma)
    aiding = FusionOptions(smoother=args.smoothed, use_nhc=not args.no_nhc)
    outages = ((0.5 * args.length, args.outage),) if args.outage > 0 else ()
    pass_name = "smoothed" if args.smoothed else "forward"
    bar = TerminalProgress("predict")
    if args.sweep:
        values = args.values or SWEEP_DEFAULTS[args.sweep]
        table = sweep(args.sweep, values, args.imu, gnss, speed_mps=args.speed, aiding=aiding, length_m=args.length,
                      outages=outages, progress=bar)
        bar.done()
        figures = table.smoothed if args.smoothed else table.forward
        names = [n for n in ROWS if not n.startswith("outage") or outages]
        print(f"{pass_name} solution, 1 sigma [mm], {args.sweep} in {table.unit}")
        print(f"{args.sweep:>12} " + " ".join(f"{n.replace('_m', ''):>20}" for n in names))
        for value, fig in zip(table.values, figures):
            d = fig.as_dict()
            print(f"{value:12g} " + " ".join(f"{1e3 * d[n]:20.3f}" for n in names))
        return 0
    prediction = predict(args.imu, gnss, aiding, speed_mps=args.speed, length_m=args.length, outages=outages,
                         progress=bar)
    elapsed = bar.done()
    figures = (prediction.smoothed if args.smoothed else prediction.forward).as_dict()
    print(f"Predicted accuracy, {pass_name} solution: IMU {args.imu}, GNSS {1e3 * gnss.white_horizontal_m:g}/"
          f"{1e3 * gnss.white_vertical_m:g} mm, {args.speed:g} m/s, {args.length:g} m"
          + (f", {args.outage:g} s outage at {0.5 * args.length:g} m" if outages else "") + f" ({elapsed:.1f} s)")
    print(f"{'figure':<36} {'1 sigma':>8} {'3 sigma':>8} {'limit':>8}  [mm]")
    for name, (label, limit) in ROWS.items():
        value = figures[name]
        if name.startswith("outage") and not outages:
            continue
        verdict = ""
        if limit is not None:
            verdict = "  ok" if 3e3 * value <= limit else "  exceeds the limit at 3 sigma"
        print(f"{label:<36} {_mm(value)} {_mm(3.0 * value)} {(f'{limit:8.1f}' if limit else ' ' * 8)}{verdict}")
    return 0
