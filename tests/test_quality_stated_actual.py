"""The stated accuracy against the actual error on the project's simulator (issue 33's Done-when): with the
trolley's play and without it, navigation and tactical grade, actual/stated RMS within [0.8, 1.25] for the
5 m lag (lateral, vertical), the lateral and along-track position and the cross-level.

The figures are errors of which a survey holds one or a few draws (its error slope, the GNSS's correlated
error, the accelerometer bias behind the cross-level), so only many surveys judge them: the slow test runs
``benchmarks/stated_actual.py``'s surveys over 32 seeds (128 surveys of 200 m). The fast one holds the
measure the band is about: the RMS of a lag difference keeps the survey's error slope."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pytest

from insrail.sim.evaluation import TrajectoryErrors

BENCHMARK = Path(__file__).parents[1] / "benchmarks" / "stated_actual.py"
BAND = (0.8, 1.25)
DONE_WHEN = ("lateral", "along_track", "cross_level", "lag5_lateral", "lag5_vertical")
SEEDS = range(9, 41)


@pytest.fixture(scope="module")
def bench():
    spec = importlib.util.spec_from_file_location("stated_actual_benchmark", BENCHMARK)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


@pytest.mark.slow
@pytest.mark.parametrize(("grade", "play"), [("nav", True), ("nav", False), ("tactical", True), ("tactical", False)])
def test_the_stated_accuracy_fits_the_simulators_surveys(bench, tmp_path, grade, play):
    runs = [bench.one_survey(tmp_path, grade, play, seed, 200.0) for seed in SEEDS]
    ratios = {figure: float(np.sqrt(np.nanmean([r[figure][1] for r in runs]) / np.nanmean([r[figure][0] for r in runs])))
              for figure in DONE_WHEN}
    outside = {figure: round(ratio, 2) for figure, ratio in ratios.items() if not BAND[0] <= ratio <= BAND[1]}
    assert not outside, f"actual/stated outside {BAND}: {outside}"


def test_a_lag_differences_rms_keeps_the_surveys_error_slope():
    """A lateral error growing 0.1 mm per metre (a heading error's slope) under 0.01 mm of scatter: its 5 m lag
    difference is 0.5 mm, which the RMS states and the standard deviation about the mean misses."""
    station = np.arange(0.0, 200.0, 0.1)
    scatter = np.random.default_rng(1).normal(0.0, 1e-5, station.size)
    errors = TrajectoryErrors(time_s=station, station_m=station, ned_m=np.zeros((station.size, 3)),
                              lateral_m=1e-4 * station + scatter, vertical_m=scatter, rpy_rad=np.zeros((station.size, 3)),
                              moving=station > 1.0)
    lateral, vertical = errors.lag_difference_rms_m(5.0)
    assert lateral == pytest.approx(5e-4, rel=0.01) and vertical == pytest.approx(np.sqrt(2) * 1e-5, rel=0.1)
    assert errors.lag_difference_sigma_m(5.0)[0] < 0.05 * lateral
