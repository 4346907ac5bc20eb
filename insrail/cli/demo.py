"""Run insrail on the built-in demo survey (the simulated `short` scenario).

Simulates the 1.2 km `short` survey with a navigation-grade IMU into DIR/surveys/short
(replacing an earlier demo there) and says what it wrote. The processing stages are added
to the demo as they land.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from insrail.cli.progressbar import TerminalProgress


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", type=Path, default=Path("insrail-demo"), help="demo folder (default: ./insrail-demo)")
    p.add_argument("--seed", type=int, default=1, help="random seed of the simulated survey (default: 1)")


def run(args: argparse.Namespace) -> int:
    from insrail.sim.scenario import preset
    from insrail.sim.simulate import simulate

    survey_dir = args.out / "surveys" / "short"
    bar = TerminalProgress("demo: simulating the short survey")
    result = simulate(preset("short"), args.seed, survey_dir, overwrite=True, progress=bar)
    elapsed = bar.done()
    print(f"insrail demo: simulated a {result.length_m:.0f} m trolley survey ({result.duration_s:.0f} s of data) in {elapsed:.1f} s")
    print(f"Survey folder: {result.folder.resolve()}")
    for role, path in result.files.items():
        size = path.stat().st_size
        print(f"  {role:16s} {str(path.relative_to(result.folder)):24s} {size / 1e6:8.2f} MB")
    print("Raw formats are described in docs/formats.md; truth/ holds the simulator's truth.")
    return 0
