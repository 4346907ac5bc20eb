"""Predicted accuracy (covariance analysis) against a Monte Carlo of the real fusion.

    python benchmarks/predict.py [--runs 20] [--workdir DIR] [--imu nav] [--speed 1.0]

Predicts the 1-sigma figures of a 1 km straight run at constant speed with
``insrail.quality.predict`` (forward filter and RTS smoother), then simulates the
``straight`` scenario with ``--runs`` seeds, fuses each survey with the default options
(``insrail.nav.fusion.fuse``; its ``forward`` trajectory is what ``smoother=False``
returns, so one fusion gives both passes) and compares the errors against the truth
(``insrail.sim.evaluation``). Monte Carlo figures are pooled over the runs as root mean
squares (the errors have zero mean): position over the moving epochs, lag differences
over point pairs at sleeper spacing. Per-seed errors are cached in the work folder, so a
rerun with more seeds only simulates the new ones.
"""

from __future__ import annotations

import argparse
import math
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

LENGTH_M = 1000.0
FIGURES = ("position_lateral_m", "position_vertical_m", "cant_m", "lag5_lateral_m", "lag5_vertical_m",
           "lag150_lateral_m", "lag150_vertical_m")


def run_errors(workdir: Path, seed: int, imu: str, speed: float, options) -> Path:
    """Simulate and fuse one seed; cache the errors of both passes."""
    from insrail.io.survey import read_survey
    from insrail.nav.earth import CGCS2000
    from insrail.nav.fusion import fuse_survey
    from insrail.sim.evaluation import trajectory_errors
    from insrail.sim.scenario import preset
    from insrail.sim.simulate import simulate
    from insrail.sim.truth import read_nav_truth

    config = preset("straight", imu_profile=imu)
    play = config.play
    tag = f"{imu}-{speed:g}-nhc{1e3 * options.nhc_sigma_mps:g}-play{1e3 * play.pitch_rms_rad:g}-{1e3 * play.yaw_rms_rad:g}"
    cache = workdir / f"errors-{tag}-seed{seed}.npz"
    if cache.exists():
        return cache
    config = replace(config, motion=replace(config.motion, cruise_speed_mps=speed))
    folder = workdir / f"straight-{tag}-seed{seed}"
    simulate(config, seed, folder, imu_format="npy", overwrite=True)
    survey = read_survey(folder)
    result = fuse_survey(survey, options, ellipsoid=CGCS2000, output_every=4, full_forward=True)
    truth = read_nav_truth(folder / "truth" / "nav.npy")
    arrays = {}
    for name, trajectory in (("forward", result.forward), ("smoothed", result.trajectory)):
        e = trajectory_errors(trajectory, truth, CGCS2000)
        arrays.update({f"{name}_station": e.station_m, f"{name}_lateral": e.lateral_m, f"{name}_vertical": e.vertical_m,
                       f"{name}_roll": e.rpy_rad[:, 0], f"{name}_moving": e.moving})
    np.savez(cache, **arrays)
    for path in sorted(folder.rglob("*"), reverse=True):  # the survey itself is not needed again
        path.unlink() if path.is_file() else path.rmdir()
    folder.rmdir()
    return cache


def _sums(arrays, name: str) -> dict[str, tuple[float, int]]:
    """Sums of squares and counts of one run's errors, per figure."""
    from insrail.sim.evaluation import SLEEPER_SPACING_M

    s, moving = arrays[f"{name}_station"], arrays[f"{name}_moving"]
    lat, ver, roll = arrays[f"{name}_lateral"], arrays[f"{name}_vertical"], arrays[f"{name}_roll"]
    out = {"position_lateral_m": (np.sum(lat[moving] ** 2), moving.sum()),
           "position_vertical_m": (np.sum(ver[moving] ** 2), moving.sum()),
           "cant_m": (np.sum((1.5 * roll[moving]) ** 2), moving.sum())}
    grid = np.arange(s[moving][0] + 1.0, s[-1] - 1.0, SLEEPER_SPACING_M)  # as TrajectoryErrors.lag_difference_sigma_m
    k = np.searchsorted(s, grid)
    for lag in (5, 150):
        n = int(round(lag / SLEEPER_SPACING_M))
        for axis, e in (("lateral", lat[k]), ("vertical", ver[k])):
            d = e[n:] - e[:-n]
            out[f"lag{lag}_{axis}_m"] = (np.sum(d**2), d.size)
    return out


def monte_carlo(caches: list[Path]) -> dict[str, dict[str, float]]:
    result = {}
    for name in ("forward", "smoothed"):
        totals = {f: [0.0, 0] for f in FIGURES}
        for cache in caches:
            with np.load(cache) as arrays:
                for f, (ss, n) in _sums(arrays, name).items():
                    totals[f][0] += ss
                    totals[f][1] += n
        result[name] = {f: math.sqrt(ss / n) for f, (ss, n) in totals.items()}
    return result


def main(argv: list[str] | None = None) -> None:
    from insrail.nav.fusion import FusionOptions
    from insrail.quality.prediction import predict

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=20)
    parser.add_argument("--first-seed", type=int, default=1)
    parser.add_argument("--imu", default="nav")
    parser.add_argument("--speed", type=float, default=1.0)
    parser.add_argument("--nhc-sigma", type=float, help="NHC sigma of the fusion and the prediction [mm/s] "
                        "(default: FusionOptions's)")
    parser.add_argument("--workdir", type=Path, help="keep per-seed errors here (default: a temporary folder)")
    parser.add_argument("--sweeps", type=Path, metavar="DIR",
                        help="instead: write the chapter-3 sweep table and plot (accuracy_sweeps.md/.svg) into DIR")
    args = parser.parse_args(argv)
    if args.sweeps:
        sweeps(args.sweeps)
        return

    options = FusionOptions() if args.nhc_sigma is None else FusionOptions(nhc_sigma_mps=args.nhc_sigma / 1e3)
    start = time.perf_counter()
    prediction = predict(args.imu, aiding=options, speed_mps=args.speed, length_m=LENGTH_M)
    elapsed = time.perf_counter() - start
    print(f"prediction: {args.imu}, default GNSS, NHC {1e3 * options.nhc_sigma_mps:g} mm/s, {args.speed:g} m/s, "
          f"{LENGTH_M:g} m straight, "
          f"forward and smoothed in {elapsed:.1f} s")
    with tempfile.TemporaryDirectory(prefix="insrail-predict-bench-") as tmp:
        workdir = args.workdir or Path(tmp)
        workdir.mkdir(parents=True, exist_ok=True)
        caches = []
        for seed in range(args.first_seed, args.first_seed + args.runs):
            t0 = time.perf_counter()
            caches.append(run_errors(workdir, seed, args.imu, args.speed, options))
            print(f"  Monte Carlo run {seed}: {time.perf_counter() - t0:.0f} s", flush=True)
        mc = monte_carlo(caches)
    print(f"\n1-sigma [mm]; Monte Carlo: {args.runs} runs of the real fusion")
    print(f"{'figure':<34} {'pass':<9} {'predicted':>10} {'MC':>8} {'pred/MC':>8}")
    from insrail.quality.prediction import AccuracyFigures

    for name in ("forward", "smoothed"):
        predicted = getattr(prediction, name).as_dict()
        for f in FIGURES:
            p, m = 1e3 * predicted[f], 1e3 * mc[name][f]
            print(f"{AccuracyFigures.NAMES[f]:<34} {name:<9} {p:10.3f} {m:8.3f} {p / m:8.2f}")


SWEEPS = {
    "gyro_bias": (0.005, 0.01, 0.1, 1.0),
    "accel_bias": (25.0, 100.0, 300.0),
    "arw": (0.0022, 0.01, 0.05),
    "vrw": (0.00075, 0.01, 0.03),
    "gnss_sigma": (0.005, 0.01, 0.02),
    "speed": (0.25, 0.5, 1.0, 2.0, 5.0),
}
SWEEP_FIGURES = ("position_lateral_m", "position_vertical_m", "cant_m", "lag5_lateral_m", "lag5_vertical_m",
                 "lag150_lateral_m", "lag150_vertical_m")


def sweeps(out: Path) -> None:
    """Thesis chapter-3 style sweeps: a markdown table (forward / smoothed) and an SVG plot."""
    from insrail.nav.fusion import FusionOptions
    from insrail.quality.sweep import sweep

    lines = ["| parameter | value | " + " | ".join(f.replace("_m", "") for f in SWEEP_FIGURES) + " |",
             "|---|---|" + "---|" * len(SWEEP_FIGURES)]
    tables = {}
    for parameter, values in SWEEPS.items():
        table = sweep(parameter, values, aiding=FusionOptions())
        tables[parameter] = table
        for value, f, s in zip(table.values, table.forward, table.smoothed):
            fd, sd = f.as_dict(), s.as_dict()
            cells = [f"{1e3 * fd[n]:.2f} / {1e3 * sd[n]:.2f}" if n != "cant_m" else f"{1e3 * fd[n]:.3f} / {1e3 * sd[n]:.3f}"
                     for n in SWEEP_FIGURES]
            lines.append(f"| {parameter} [{table.unit}] | {value:g} | " + " | ".join(cells) + " |")
        print(f"sweep {parameter} done", flush=True)
    out.mkdir(parents=True, exist_ok=True)
    (out / "accuracy_sweeps.md").write_text("\n".join(lines) + "\n")
    (out / "accuracy_sweeps.svg").write_text(_svg(tables))


def _svg(tables) -> str:
    """Small multiples, log-log: 3-sigma of the 5 m and 150 m lateral lag differences (forward
    filter solid, smoother dashed) against each swept parameter."""
    w, h, cols = 260, 200, 3
    rows = math.ceil(len(tables) / cols)
    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{cols * w}" height="{rows * h + 30}" '
             'font-family="sans-serif" font-size="10">',
             '<text x="10" y="18" font-size="12">3-sigma lateral lag difference [mm]: 5 m (blue), 150 m (red); '
             'forward solid, smoothed dashed; dotted: 2 mm / 10 mm limits</text>']
    for i, (name, table) in enumerate(tables.items()):
        x0, y0 = (i % cols) * w + 45, (i // cols) * h + 45
        pw, ph = w - 65, h - 60
        xs = np.log10(table.values)
        xlo, xhi = xs.min(), xs.max()
        ylo, yhi = -2.0, 1.5  # 0.01 .. 30 mm

        def px(x, y):
            return x0 + pw * (x - xlo) / (xhi - xlo), y0 + ph * (1 - (np.clip(y, ylo, yhi) - ylo) / (yhi - ylo))

        parts.append(f'<rect x="{x0}" y="{y0}" width="{pw}" height="{ph}" fill="none" stroke="#888"/>')
        parts.append(f'<text x="{x0}" y="{y0 + ph + 28}">{name} [{table.unit}]</text>')
        for v, x in zip(table.values, xs):
            tx, _ = px(x, ylo)
            parts.append(f'<text x="{tx - 8:.0f}" y="{y0 + ph + 12}">{v:g}</text>')
        for tick in (0.01, 0.1, 1.0, 10.0):
            _, ty = px(xlo, math.log10(tick))
            parts.append(f'<text x="{x0 - 32}" y="{ty + 3:.0f}">{tick:g}</text>')
        for limit in (2.0, 10.0):
            _, ty = px(xlo, math.log10(limit))
            parts.append(f'<line x1="{x0}" y1="{ty:.1f}" x2="{x0 + pw}" y2="{ty:.1f}" stroke="#aaa" stroke-dasharray="1,3"/>')
        for figs, dash in ((table.forward, ""), (table.smoothed, ' stroke-dasharray="5,3"')):
            for key, colour in (("lag5_lateral_m", "#1f5fbf"), ("lag150_lateral_m", "#c0392b")):
                pts = " ".join("%.1f,%.1f" % px(x, math.log10(3e3 * getattr(f, key))) for x, f in zip(xs, figs))
                parts.append(f'<polyline points="{pts}" fill="none" stroke="{colour}" stroke-width="1.5"{dash}/>')
    parts.append("</svg>")
    return "\n".join(parts) + "\n"


if __name__ == "__main__":
    main()
