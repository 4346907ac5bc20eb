"""Rail joints (thesis §5.3.1.2): the simulator's shocks at joints every 25 m are found in the IMU record by
`insrail process`, listed as `joint` events and in summary.toml's [joints], and the NHC is relaxed over them."""

from __future__ import annotations

import contextlib
import io
import tomllib
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from insrail.cli.main import main
from insrail.io.types import ImuIncrements
from insrail.nav.measurements import OdometerNhc
from insrail.nav.shocks import NHC_RELAXED_S, detect_shocks
from insrail.sim.scenario import JointSpec
from survey_builder import SURVEY_NAME, Cell, build_cell, scenario

JOINTS = JointSpec(spacing_m=25.0, first_station_m=1012.5)


def test_a_shock_is_found_at_its_time_and_walking_is_not_one():
    dt = 0.005
    t = 345600.0 + dt * np.arange(20000)
    rng = np.random.default_rng(3)
    # a push: 0.3 m/s^2 changing over seconds, sensor noise 0.02 m/s^2, gravity on z
    f = np.column_stack([0.3 * np.sin(t / 3.0), 0.1 * np.sin(t / 5.0), -9.8 + 0.2 * np.sin(t / 2.0)])
    f += 0.02 * rng.standard_normal(f.shape)
    joint_times = np.array([345612.3, 345650.0, 345671.77])
    dvel = f * dt
    for passing in joint_times:
        near = np.abs(t - passing) < 0.2
        dvel[near] += JOINTS.shock_mps2(t[near] - 0.5 * dt - passing) * dt
    shocks = detect_shocks(ImuIncrements(t, np.zeros((len(t), 3)), dvel))
    assert len(shocks) == 3
    assert np.max(np.abs(shocks.time_s - joint_times)) < 2 * dt
    assert not len(detect_shocks(ImuIncrements(t, np.zeros((len(t), 3)), f * dt)))
    # a fault of one record (0.07 m/s in one increment) does not ring: no shock, the NHC keeps watching it
    faulty = dvel.copy()
    faulty[t.searchsorted(345630.0), 2] += 0.07
    found = detect_shocks(ImuIncrements(t, np.zeros((len(t), 3)), faulty))
    assert len(found) == 3 and np.max(np.abs(found.time_s - joint_times)) < 2 * dt


def test_an_update_whose_segment_meets_a_shock_takes_the_relaxed_nhc():
    source = OdometerNhc.from_distance(np.array([0.0, 100.0]), np.array([0.0, 120.0]), np.eye(3), np.zeros(3),
                                       np.zeros(3), 0.001, 0.001, sigma_nhc_mps=0.0005,
                                       nhc_relaxed_s=(np.array([10.32, 30.0]), np.array([10.82, 30.5])))
    scheduled, _, _ = source.scheduled(np.arange(0.0, 50.0, 0.1), None)
    relaxed = scheduled.time_s[scheduled.nhc_scale > 1]
    assert np.allclose(relaxed, [10.4, 10.5, 10.6, 10.7, 10.8, 10.9, 30.1, 30.2, 30.3, 30.4, 30.5])
    assert set(np.unique(scheduled.nhc_scale)) == {1.0, source.nhc_relaxed_factor}


def _insrail(*args) -> tuple[int, str]:
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
        code = main([str(a) for a in args])
    return code, out.getvalue()


def test_joints_of_a_simulated_survey_are_detected_and_listed(tmp_path):
    cell = Cell(imu="nav", position="rtklib-pos", ellipsoid="CGCS2000", design="csv", direction="with",
                left_out="none", trolley="minimal")
    built = build_cell(cell, tmp_path, seed=4, config=replace(scenario(cell), joints=JOINTS))
    truth = tomllib.loads((built.truth / "errors.toml").read_text())
    true_stations = np.array(truth["joint_stations_m"])
    assert len(true_stations) == 17  # 1020 .. 1440 m
    code, out = _insrail("process", built.project)
    assert code == 0, out
    assert "rail joints: 17 detected from IMU shocks" in out and "median spacing 25.0" in out, out
    summary = tomllib.loads((built.project / "results" / SURVEY_NAME / "summary.toml").read_text())
    assert summary["joints"]["detected"] == 17 and summary["joints"]["nhc_relaxed_s"] == NHC_RELAXED_S
    joints = [e for e in summary["events"] if e["kind"] == "joint"]
    stations = np.array([e["station_from_m"] for e in joints])
    assert len(stations) == 17 and np.max(np.abs(stations - true_stations)) < 0.1, stations - true_stations
    assert all(not e["not_assessed"] and e["source"] == "IMU shock" for e in joints)
