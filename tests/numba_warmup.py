"""Fills insrail's numba cache (``cache=True``) before pytest-xdist's workers need it.

A clean checkout has no compiled kernels: each worker compiled them itself on its first fusion, about
50 s of CPU each, at the same time. The controller starts this script as the run begins (tests/conftest.py),
holding the lock ``shared_build.numba_lock`` for it; it processes a tiny simulated survey (text files, so the
parsers compile too) while the workers collect the tests, and the workers wait for the lock before their
first test and then load what it compiled. Whatever it leaves out, a worker compiles when it needs it.

The processing compiles in one process, one core, while the workers wait: ``--beside`` runs on the other core
what the processing leaves out and a test would otherwise compile (:func:`warm_up_beside`), then makes the
costliest shared test input (:data:`PREBUILT`) in what is left of the wait.
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


def warm_up_beside() -> None:
    """The kernels' signatures the processing does not compile: the planning tool's covariance analysis
    (``insrail predict``: its arrays are not the quality stage's, some 20 s of CPU that the first test of the
    Plan survey dialog paid) and the free-inertial integration (``insrail.nav.mechanization.integrate``)."""
    import numpy as np

    from insrail.io.types import ImuIncrements
    from insrail.nav.mechanization import NavState, integrate
    from insrail.quality import predict

    predict(length_m=200.0)
    step_s = 0.01
    time_s = step_s * np.arange(1, 51)
    integrate(ImuIncrements(time_s, np.zeros((50, 3)), np.tile([0.0, 0.0, -9.8 * step_s], (50, 1))),
              NavState.from_euler(0.0, 0.5, 2.0, 30.0, np.zeros(3), 0.0, 0.0, 0.0))


#: Shared test inputs (shared_build) made beside the warm-up, each a test module's function making its input once
#: per run: the first test that needs one finds it made, or waits for it
PREBUILT = (("test_track_linefit_windows", "long_waves_once"),)


def prebuild(run_folder: Path) -> None:
    import importlib

    import shared_build

    shared_build.RUN_FOLDER = run_folder
    for module, function in PREBUILT:
        getattr(importlib.import_module(module), function)()


if __name__ == "__main__":
    if sys.argv[1] == "--beside":
        warm_up_beside()
        import shared_build

        shared_build.release_held()  # the workers start when the processing's warm-up ends too
        prebuild(Path(sys.argv[2]))
    else:
        warm_up(Path(sys.argv[1]))
