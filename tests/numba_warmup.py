"""Fills insrail's numba cache (``cache=True``) before pytest-xdist's workers need it.

A clean checkout has no compiled kernels: each worker compiled them itself on its first fusion, about
50 s of CPU each, at the same time. The controller starts this script as the run begins (tests/conftest.py),
holding the lock ``shared_build.numba_lock`` for it; it processes a tiny simulated survey (text files, so the
parsers compile too) while the workers collect the tests, and the workers wait for the lock before their
first test and then load what it compiled. Whatever it leaves out, a worker compiles when it needs it.
"""

from __future__ import annotations

import sys
from dataclasses import replace
from pathlib import Path


def tiny_scenario():
    """The `short` scenario cut to 50 m after a 30 s static start (navigation-grade IMU, GNSS throughout)."""
    from insrail.sim.scenario import GnssSpec, preset

    short = preset("short")
    return replace(short, name="warmup", gnss=GnssSpec(),
                   motion=replace(short.motion, start_station_m=1100.0, end_station_m=1150.0, stops=(),
                                  static_start_s=30.0, static_end_s=5.0))


def warm_up(folder: Path) -> None:
    from insrail.project import process
    from insrail.project.demo import project_for_simulated_survey
    from insrail.sim.simulate import simulate

    simulate(tiny_scenario(), 1, folder / "surveys" / "warmup", imu_format="text")
    process(project_for_simulated_survey(folder, folder / "surveys" / "warmup", name="warmup"), "warmup")


if __name__ == "__main__":
    warm_up(Path(sys.argv[1]))
