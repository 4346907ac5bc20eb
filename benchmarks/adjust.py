"""Irregularity assessment speed and adjustment quality on a synthetic 10 km line.

    python benchmarks/adjust.py [--km 10] [--seed 1] [--chunk 960] [--roughness-mm 0.1]

Builds per-sleeper deviations (random-walk rails, --roughness-mm per sleeper, plus 3 bumps
of 3 mm per km),
times the full TB 10754 assessment (chords, sliding 30/5 and 300/150, parameters), then
computes the "correct to the line" and the optimised (least-movement) adjustments and prints
their total movement, the remaining differential-versine exceedances and the run times.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from insrail.track.adjustment import (
    correct_to_line,
    load_fastener_type,
    optimise_adjustment,
)
from insrail.track.exceedance import SleeperGeometry, assess
from insrail.track.tolerance import load_tolerance_profile


def synthetic_line(km: float, seed: int, roughness_m: float) -> SleeperGeometry:
    rng = np.random.default_rng(seed)
    count = int(km * 1000 / 0.625)
    station = 0.625 * np.arange(count)
    lateral = np.cumsum(rng.normal(0, roughness_m, (count, 2)), axis=0)
    vertical = np.cumsum(rng.normal(0, roughness_m, (count, 2)), axis=0)
    lateral -= np.convolve(lateral[:, 0], np.ones(801) / 801, mode="same")[:, None]  # stay near the line
    vertical -= np.convolve(vertical[:, 0], np.ones(801) / 801, mode="same")[:, None]
    for index in rng.integers(100, count - 100, size=int(km * 3)):
        lateral[index, rng.integers(0, 2)] += rng.choice([-1, 1]) * 3e-3
    design_cant = np.interp(station, [2000, 2100, 4000, 4100], [0, 0.12, 0.12, 0])
    cant = design_cant + rng.normal(0, 0.3e-3, count)
    gauge = 1.435 + rng.normal(0, 0.3e-3, count)
    return SleeperGeometry.from_arrays(station, lateral, vertical, gauge, cant, design_cant)


def differential_count(geometry, profile) -> int:
    return sum(e.kind == "differential_versine" for e in assess(geometry, profile).exceedances)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--km", type=float, default=10.0)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--chunk", type=int, default=960, help="sleepers per optimisation chunk")
    parser.add_argument("--roughness-mm", type=float, default=0.1, help="random-walk step per sleeper")
    args = parser.parse_args()
    profile = load_tolerance_profile()
    fastener = load_fastener_type()
    geometry = synthetic_line(args.km, args.seed, args.roughness_mm * 1e-3)
    print(f"{geometry.station_m.size} sleepers ({args.km:g} km), profile {profile.name}, fastener {fastener.name}")

    start = time.perf_counter()
    assessment = assess(geometry, profile)
    print(f"assessment: {time.perf_counter() - start:.2f} s, {len(assessment.exceedances)} exceedances "
          f"({differential_count(geometry, profile)} differential-versine)")

    for label, compute in (
        ("correct to line", lambda: correct_to_line(geometry, fastener)),
        ("optimised", lambda: optimise_adjustment(geometry, profile, fastener, args.chunk)),
    ):
        start = time.perf_counter()
        adjustment = compute()
        elapsed = time.perf_counter() - start
        unresolved = int(adjustment.unresolved_lateral.sum() + adjustment.unresolved_vertical.sum())
        print(f"{label:<16} total movement {adjustment.total_movement_m * 1e3:9.0f} mm, "
              f"sleeper-rails moved {int(np.count_nonzero(adjustment.lateral_m) + np.count_nonzero(adjustment.vertical_m)):6d}, "
              f"remaining 30/5+300/150 exceedances {differential_count(adjustment.apply(geometry), profile):4d}, "
              f"flagged {unresolved:4d}, {elapsed:.2f} s")


if __name__ == "__main__":
    main()
