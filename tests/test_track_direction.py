"""Surveys with or against the stationing, the trolley facing either way: everything reported
follows the stationing (rails, lateral and cant signs, sleeper numbers, chainage direction)."""

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from track_truth import truth_reconstruction

from insrail.io.track_sensors import read_sleeper_times
from insrail.sim.scenario import preset
from insrail.sim.simulate import simulate
from insrail.track.chainage import (
    epoch_station_track,
    facing_on_design,
    stations_along_path,
)
from insrail.track.errors import DesignError
from insrail.track.reversed_design import reversed_design
from insrail.track.sleeper_table import reconstruct_track
from insrail.track.sleepers import number_sleepers
from insrail.track.stationing import StationEquation, StationEquations

MM = 1e-3


@pytest.fixture(scope="module")
def reverse_survey(tmp_path_factory):
    """300 m of the `short` track through the clothoid into the curve (cant rising), run from
    the high station down to the low one, error-free IMU."""
    config = preset("short", imu_profile="perfect")
    config = replace(config, motion=replace(config.motion, start_station_m=1200.0, end_station_m=1500.0,
                                            stops=((1450.0, 10.0),), static_start_s=30.0, static_end_s=10.0,
                                            reverse=True))
    out = tmp_path_factory.mktemp("sim") / "short-reverse"
    simulate(config, seed=7, out_dir=out, imu_format="npy")
    return out


def _reconstruct(truth, folder, design=None, **options):
    return reconstruct_track(truth.trajectory, truth.trolley, truth.gauge, truth.to_engineering, design=design,
                             pulses=read_sleeper_times(folder / "sleepers.txt"), **options)


def _nearest(stations, at):
    k = np.clip(np.searchsorted(stations, at), 1, len(stations) - 1)
    return np.where(np.abs(stations[k - 1] - at) < np.abs(stations[k] - at), k - 1, k)


def test_a_run_against_the_stationing_reports_by_the_stationing(reverse_survey):
    truth = truth_reconstruction(reverse_survey)
    assert truth.nav["station_m"][-1] < truth.nav["station_m"][0] - 250.0  # it ran down the stationing
    assert facing_on_design(truth.rails, truth.design) == -1.0  # trolley frame: its x axis points down
    recon = _reconstruct(truth, reverse_survey, truth.design)
    table = recon.table
    # The trolley's reference (left) rail is the stationing's right one.
    assert recon.rails.reference_rail == "right"
    assert np.all(np.diff(table.number) == 1) and np.all(np.diff(table.station_m) > 0.5)
    assert np.all(np.diff(table.time_s) < 0)  # the sleepers of higher station were passed first
    sleepers = truth.sleepers
    rows = _nearest(sleepers["station"], table.station_m)
    assert np.abs(table.station_m - sleepers["station"][rows]).max() < 8 * MM
    assert np.array_equal(table.detected, sleepers["detected"][rows].astype(bool))
    v = table.valid
    assert v.mean() > 0.95
    true = truth.track.sections(table.station_m[v])
    assert np.abs(table.left_rail_enh_m[v] - true.left_rail_enh_m).max() < 0.05 * MM
    assert np.abs(table.right_rail_enh_m[v] - true.right_rail_enh_m).max() < 0.05 * MM
    # Cant by the stationing: + left rail higher, rising to the curve's 120 mm.
    assert np.abs(table.cant_m[v] - true.cant_m).max() < 0.05 * MM
    assert table.cant_m[v][-1] > 0.05
    # The centreline's deviation is the injected lateral irregularity, + to the right of the stationing.
    assert np.abs(table.lateral_deviation_m[v].mean(axis=1) - true.lateral_m).max() < 0.05 * MM
    assert np.abs(table.vertical_deviation_m[v].mean(axis=1) - true.vertical_m).max() < 0.05 * MM


def test_without_design_an_azimuth_names_the_stationing(reverse_survey):
    truth = truth_reconstruction(reverse_survey)
    start = float(truth.nav["station_m"][0])
    with_design = _reconstruct(truth, reverse_survey, truth.design).table
    # Stations grow towards the design's bearing (about 40 degrees there): the run goes the other way.
    recon = _reconstruct(truth, reverse_survey, start_station_m=start, stationing=40.0, fit_line=False)
    table = recon.table
    assert recon.rails.reference_rail == "right"
    assert np.all(np.diff(table.station_m) > 0) and np.all(np.diff(table.time_s) < 0)
    # Plane distance along the wavy centreline against the design station: a few tenths of a mm per 100 m.
    rows = _nearest(with_design.station_m, table.station_m)
    assert np.abs(table.station_m - with_design.station_m[rows]).max() < 10 * MM
    both = table.valid & with_design.valid[rows]
    assert np.abs(table.cant_m[both] - with_design.cant_m[rows][both]).max() < 0.05 * MM
    # "travel" (the default): stations grow as the trolley goes, its own left rail is the left one.
    default = _reconstruct(truth, reverse_survey, start_station_m=0.0, fit_line=False)
    assert default.rails.reference_rail == "left"
    assert np.all(np.diff(default.table.time_s) > 0)
    # An azimuth the run follows gives the same as "travel".
    same = stations_along_path(truth.rails, 0.0, 220.0).reference_m
    assert np.allclose(same, stations_along_path(truth.rails, 0.0).reference_m)


def test_the_design_stationed_the_other_way_gives_the_same_track(short_perfect_survey):
    truth = truth_reconstruction(short_perfect_survey)
    forward = _reconstruct(truth, short_perfect_survey, truth.design).table
    design = reversed_design(truth.design)
    backward = _reconstruct(truth, short_perfect_survey, design).table
    h = truth.design.horizontal
    mirrored = h.start_station_m + h.end_station_m - backward.station_m
    rows = _nearest(forward.station_m, mirrored)
    assert np.abs(forward.station_m[rows] - mirrored).max() < 1e-6
    assert np.array_equal(backward.number, np.arange(len(backward)) + 1)
    both = forward.valid[rows] & backward.valid
    assert both.mean() > 0.95
    f = {name: getattr(forward, name)[rows][both] for name in ("lateral_deviation_m", "vertical_deviation_m",
                                                                "cant_m", "design_cant_m", "gauge_m")}
    b = {name: getattr(backward, name)[both] for name in f}
    # The stationing's left rail is the forward's right one; lateral "+ right" turns round, cant changes sign.
    assert np.abs(b["lateral_deviation_m"] + f["lateral_deviation_m"][:, ::-1]).max() < 0.01 * MM
    assert np.abs(b["vertical_deviation_m"] - f["vertical_deviation_m"][:, ::-1]).max() < 0.01 * MM
    assert np.abs(b["cant_m"] + f["cant_m"]).max() < 0.01 * MM
    assert np.abs(b["design_cant_m"] + f["design_cant_m"]).max() < 1e-9
    assert np.abs(b["gauge_m"] - f["gauge_m"]).max() < 0.01 * MM


def test_reversed_design_is_the_same_line():
    from insrail.sim.design import design_alignment

    design = design_alignment(preset("short").design)
    other = reversed_design(design)
    h, r = design.horizontal, other.horizontal
    s = np.linspace(h.start_station_m, h.end_station_m, 501)
    m = h.start_station_m + h.end_station_m - s
    assert np.abs(np.subtract(h.point_at(s), r.point_at(m))).max() < 1e-6
    assert np.allclose(np.cos(h.azimuth_at(s) + np.pi - r.azimuth_at(m)), 1.0)
    assert np.allclose(h.curvature_at(s[1:-1]), -r.curvature_at(m[1:-1]))
    assert np.allclose(design.vertical.elevation_at(s), other.vertical.elevation_at(m))
    assert np.allclose(design.cant.cant_at(s), -other.cant.cant_at(m))
    with pytest.raises(DesignError, match="station equations"):
        reversed_design(replace(design, station_equations=StationEquations((StationEquation(1500.0, 1510.0),))))


def test_epoch_station_track_follows_either_direction():
    _, s = epoch_station_track(np.arange(5.0), np.array([5.0, 4.0, 4.0001, 3.0, 1.0]))
    assert np.array_equal(s, [5.0, 4.0, 4.0, 3.0, 1.0])
    with pytest.raises(ValueError, match="fewer than two"):
        epoch_station_track(np.arange(3.0), np.array([np.nan, 2.0, np.nan]))


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**31), missed=st.floats(0.0, 0.05), false=st.floats(0.0, 0.03))
def test_numbering_against_the_stationing_is_the_mirror_of_the_forward_one(seed, missed, false):
    rng = np.random.default_rng(seed)
    n = 300
    stations = 10.0 + 0.625 * np.arange(n) + rng.normal(0, 0.002, n)
    t = np.linspace(0.0, 400.0, 4001)
    station_fwd = 9.0 + t * (stations[-1] + 1.0 - 9.0) / t[-1]
    pass_time = np.interp(stations, station_fwd, t)
    detected = rng.uniform(size=n) >= missed
    between = rng.integers(0, n - 1, rng.binomial(n, false))
    false_t = pass_time[between] + rng.uniform(0.2, 0.8, len(between)) * (pass_time[between + 1] - pass_time[between])
    times = np.sort(np.concatenate([pass_time[detected], false_t]))
    forward = number_sleepers(times, t, station_fwd, 0.0)
    # The same sleepers passed in the opposite order: time runs backwards along the stations.
    mirrored_t = t[-1] - t[::-1]
    backward = number_sleepers(t[-1] - times, mirrored_t, station_fwd[::-1], 0.0)
    assert np.array_equal(forward.number, backward.number)
    assert np.allclose(forward.station_m, backward.station_m, atol=1e-9)
    assert np.array_equal(forward.detected, backward.detected)
    assert np.allclose(t[-1] - forward.time_s, backward.time_s, atol=1e-9)
    assert np.array_equal(forward.pulse_accepted, backward.pulse_accepted[::-1])
