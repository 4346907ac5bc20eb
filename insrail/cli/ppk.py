"""Post-process rover GNSS observations against a base receiver (PPK) with RTKLIB.

Writes an RTKLIB .pos (GPST, latitude/longitude/ellipsoidal height) and prints a QC
summary: epochs by quality, fix rate, ratio and sigma statistics, gaps. Options come
from the trolley defaults (resources/gnss/ppk_default.conf) or --config, and any
RTKLIB option can be overridden with --set KEY=VALUE (e.g. --set pos1-soltype=forward).
"""

from __future__ import annotations

import argparse
import math
import sys
import warnings
from pathlib import Path

from insrail.cli.progressbar import TerminalProgress


def _option(text: str) -> tuple[str, str]:
    key, sep, value = text.partition("=")
    if not sep or not key.strip():
        raise argparse.ArgumentTypeError(f"expected KEY=VALUE, found {text!r}")
    return key.strip(), value.strip()


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("rover", type=Path, help="rover RINEX observation file")
    p.add_argument("--base", type=Path, required=True, help="base RINEX observation file")
    p.add_argument("--nav", type=Path, nargs="+", required=True, help="RINEX navigation file(s)")
    p.add_argument("--out", type=Path, required=True, help="output .pos file")
    where = p.add_mutually_exclusive_group(required=True)
    where.add_argument("--base-pos", type=float, nargs=3, metavar=("LAT", "LON", "H"),
                       help="base antenna reference point: latitude, longitude [deg], ellipsoidal height [m]")
    where.add_argument("--base-from-header", action="store_true",
                       help="use the base RINEX header's approximate position (metre level: tests only)")
    p.add_argument("--antenna-height", type=float, default=0.0, help="base antenna height above the mark [m]")
    p.add_argument("--config", type=Path, help="RTKLIB .conf instead of the trolley defaults")
    p.add_argument("--set", type=_option, action="append", default=[], metavar="KEY=VALUE",
                   help="override one RTKLIB option (repeatable)")
    p.add_argument("--precise", type=Path, nargs="+", default=[], help="SP3/CLK precise products")
    p.add_argument("--force", action="store_true", help="overwrite an existing output file")


def run(args: argparse.Namespace) -> int:
    from insrail.gnss import (ApproximateBaseWarning, BasePosition, GnssProcessingError, LongBaselineWarning,
                              OptionError, ppk)

    if args.out.exists() and not args.force:
        raise FileExistsError(f"{args.out} exists; use --force to overwrite it")
    base = None
    if args.base_pos is not None:
        lat, lon, height = args.base_pos
        if not (abs(lat) <= 90 and abs(lon) <= 360 and math.isfinite(height)):
            raise SystemExit(f"insrail ppk: --base-pos {lat} {lon} {height}: expected latitude and longitude "
                             "in degrees and a height in metres")
        base = BasePosition.from_degrees(lat, lon, height, antenna_height_m=args.antenna_height)
    bar = TerminalProgress("ppk")
    with warnings.catch_warnings():
        for category in (ApproximateBaseWarning, LongBaselineWarning):  # printed below from result.warnings
            warnings.simplefilter("ignore", category)
        try:
            result = ppk(args.rover, args.base, args.nav, args.out, base_position=base, config=args.config,
                         options_overrides=dict(args.set), precise_files=args.precise, progress=bar)
        except (OptionError, GnssProcessingError) as err:
            print(f"insrail ppk: {err}", file=sys.stderr)
            return 1
    elapsed = bar.done()
    for note in result.warnings:
        print(f"warning: {note}")
    print(f"{args.out}: {len(result.solution)} epochs in {elapsed:.1f} s")
    print(result.qc.report())
    return 0
