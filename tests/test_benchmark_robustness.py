"""benchmarks/robustness.py injects the faults it claims: each full-disk case raises its ENOSPC (a
case whose fault is never raised, or whose error is another, reports NOT-INJECTED), and insrail's
message names the path to clear."""

from __future__ import annotations

import importlib.util
import sys
from dataclasses import replace
from pathlib import Path

import pytest

from insrail.project import process
from insrail.project.demo import project_for_simulated_survey
from insrail.sim.scenario import GnssSpec, preset
from insrail.sim.simulate import simulate

BENCHMARK = Path(__file__).parents[1] / "benchmarks" / "robustness.py"


@pytest.fixture(scope="module")
def robustness():
    spec = importlib.util.spec_from_file_location("robustness_benchmark", BENCHMARK)
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclasses look their module up
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def base(tmp_path_factory, robustness):
    """A tiny project with the benchmark's survey name, processed once."""
    root = tmp_path_factory.mktemp("bench") / "base"
    short = preset("short")
    scenario = replace(short, name=robustness.SURVEY, gnss=GnssSpec(),
                       motion=replace(short.motion, start_station_m=1100.0, end_station_m=1250.0, stops=(),
                                      static_start_s=60.0, static_end_s=10.0))
    simulate(scenario, 1, root / "surveys" / robustness.SURVEY, imu_format="npy")
    process(project_for_simulated_survey(root, root / "surveys" / robustness.SURVEY, name="bench"),
            robustness.SURVEY)
    return root


def test_each_full_disk_case_raises_its_fault_and_the_message_names_a_path(robustness, base, tmp_path):
    outcomes = robustness.disk_full_cases(base, tmp_path)
    assert [o.case for o in outcomes] == ["disk full writing the results", "disk full in the smoother's temporary file",
                                          "disk full writing the fusion's trajectory into the cache"]
    for outcome in outcomes:
        assert outcome.kind == "error", outcome
        assert robustness.NO_SPACE in outcome.detail and "insrail: /" in outcome.detail


def test_a_fault_never_raised_is_reported_as_not_injected(robustness, base, tmp_path):
    result = robustness.run_cli(["process", str(base)])  # nothing patched: the run succeeds
    assert robustness.classify_injected("disk full nowhere", result, raised=False).kind == "NOT-INJECTED"
