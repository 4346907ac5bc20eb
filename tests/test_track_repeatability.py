"""Repeatability of the worst-over-placements checks: compared by magnitude, not by their sign."""

import numpy as np
import pytest

from insrail.track.irregularity import differential_versine
from insrail.track.repeatability import complete_over, repeatability


def _track(stations):
    """A rough rail: waves of 6-40 m, about 1 mm."""
    rng = np.random.default_rng(11)
    wavelength = rng.uniform(6.0, 40.0, 40)
    phase = rng.uniform(0.0, 2 * np.pi, 40)
    return 0.3e-3 * np.cos(np.outer(stations, 2 * np.pi / wavelength) + phase).sum(axis=1) / np.sqrt(20)


def test_the_30m_5m_check_is_compared_by_magnitude_where_its_sign_flips_between_runs():
    stations = np.arange(0.0, 1500.0, 0.625)
    track = _track(stations)
    noise = 2e-6  # each run within 2 micrometres of the track
    rng = np.random.default_rng(5)
    measured = {name: track + rng.uniform(-noise, noise, stations.size) for name in ("a", "b")}
    runs = {name: (stations, {"check": differential_versine(stations, d)}) for name, d in measured.items()}
    signed = repeatability(runs).parameter("check")
    magnitude = repeatability(runs, placements_m={"check": 30.0}).parameter("check")
    assert magnitude.by_magnitude and not signed.by_magnitude
    # Where two chord placements of opposite sign nearly tie, micrometres decide the sign of the
    # worst value: the signed difference is then twice the check's value there ...
    assert signed.max_abs[0] > 0.2e-3
    assert np.sum(np.abs(signed.difference[0]) > 0.1e-3) >= 2
    # ... while its magnitude moves no more than the pair and chord terms of the runs' difference do
    # (2 + 2 * 5 / 30 times its largest value; the worst over placements is 1-Lipschitz).
    apart = np.abs(measured["a"] - measured["b"]).max()
    assert magnitude.max_abs[0] <= (2 + 2 * 5 / 30) * apart + 1e-12
    assert magnitude.count[0] == complete_over(stations, 30.0).sum() > 2000  # not within a chord of the ends


def test_worst_over_placements_compared_by_magnitude_and_only_where_both_runs_are_complete():
    stations = np.arange(0.0, 100.0, 0.625)
    value = np.full(stations.size, 1e-3)
    late = stations >= 20.0  # run b starts 20 m later: its checks there see fewer placements
    runs = {"a": (stations, {"check": value, "cant": value}),
            "b": (stations[late], {"check": -value[late], "cant": -value[late]})}
    result = repeatability(runs, placements_m={"check": 10.0})
    check = result.parameter("check")
    assert check.by_magnitude and check.max_abs[0] == 0.0
    compared = result.station_m[np.isfinite(check.difference[0])]
    assert compared.min() == pytest.approx(30.0) and compared.max() == pytest.approx(stations[-1] - 10.0)
    assert result.parameter("cant").mean[0] == pytest.approx(-2e-3)  # a sign error of a plain value shows
    assert not result.parameter("cant").by_magnitude
    assert result.parameter("cant").count[0] == late.sum()


def test_complete_over_stops_a_reach_short_of_ends_and_gaps():
    stations = np.concatenate([np.arange(0.0, 20.0, 0.5), np.arange(25.0, 40.0, 0.5)])
    complete = complete_over(stations, 5.0, max_gap_m=2.0)
    assert stations[complete].min() == 5.0 and stations[complete].max() == 34.5
    assert not complete[(stations > 14.5) & (stations < 30.0)].any()
    assert complete[(stations >= 5.0) & (stations <= 14.5)].all()
