"""Sliding-window resampling in station."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from insrail.track.resample import interpolate_in_station, sliding_window_fit, window_pairs


@settings(max_examples=50, deadline=None)
@given(seed=st.integers(0, 2**31), a=st.floats(-1e3, 1e3), b=st.floats(-1, 1), c=st.floats(-0.01, 0.01),
       offset=st.floats(0, 5e4))
def test_quadratics_are_reproduced_from_irregular_points_with_stops(seed, a, b, c, offset):
    rng = np.random.default_rng(seed)
    stations = offset + np.sort(rng.uniform(0, 20, 3000))
    stations = np.concatenate([stations, np.full(500, stations[1000])])  # a stop: many points at one station
    values = a + b * (stations - offset) + c * (stations - offset) ** 2
    at = offset + np.linspace(1, 19, 30)
    fitted = sliding_window_fit(stations, np.column_stack([values, -values]), at)
    expected = a + b * (at - offset) + c * (at - offset) ** 2
    assert np.allclose(fitted[:, 0], expected, rtol=0, atol=1e-9 * (1 + abs(a)))
    assert np.allclose(fitted[:, 1], -expected, rtol=0, atol=1e-9 * (1 + abs(a)))


def test_short_waves_are_barely_smoothed_and_noise_is_averaged():
    stations = np.arange(0.0, 60.0, 0.006)  # 1.2 m/s at 200 Hz
    rng = np.random.default_rng(1)
    wave = 1e-3 * np.sin(2 * np.pi * stations / 3.0)
    at = np.arange(5.0, 55.0, 0.625)
    clean = sliding_window_fit(stations, wave, at)
    assert np.abs(clean - 1e-3 * np.sin(2 * np.pi * at / 3.0)).max() < 1e-6
    noisy = sliding_window_fit(stations, wave + rng.normal(0, 1e-4, len(stations)), at)
    # ~100 points per window, 3 parameters: the centre value's noise drops about 6-fold.
    assert np.std(noisy - clean) < 3e-5


def test_windows_without_support_on_both_sides_are_nan():
    stations = np.arange(0.0, 10.0, 0.01)
    values = stations.copy()
    values[500:520] = np.nan  # a hole of 0.2 m is bridged; the ends are not extrapolated
    fitted = sliding_window_fit(stations, values, np.array([-0.2, 0.0, 5.1, 9.99, 10.2, 50.0]))
    assert np.isnan(fitted[[0, 4, 5]]).all()
    assert fitted[2] == pytest.approx(5.1)
    assert np.isnan(fitted[1]) and np.isnan(fitted[3])  # at the very ends only one half is covered
    with pytest.raises(ValueError, match="window must be positive"):
        sliding_window_fit(stations, values, np.array([1.0]), window_m=0.0)
    with pytest.raises(ValueError, match="3 values for 1000 stations"):
        sliding_window_fit(stations, values[:3], np.array([1.0]))


def test_window_pairs_enumerate_every_point_in_reach():
    stations = np.array([0.0, 0.1, 0.2, 0.5, 0.9])
    window, point, counts = window_pairs(stations, np.array([0.1, 0.8]), 0.15)
    assert counts.tolist() == [3, 1]
    assert list(zip(window.tolist(), point.tolist())) == [(0, 0), (0, 1), (0, 2), (1, 4)]


def test_interpolation_in_station_averages_a_standing_trolley():
    stations = np.array([0.0, 1.0, 1.0, 1.0, 2.0, np.nan])
    values = np.array([1.0, 2.0, 4.0, 3.0, 5.0, 100.0])
    out = interpolate_in_station(stations, values, np.array([-1.0, 0.5, 1.0, 1.5, 3.0]))
    assert np.isnan(out[[0, 4]]).all()
    assert out[1:4].tolist() == [2.0, 3.0, 4.0]


def test_the_fit_in_chunks_of_stations_is_the_fit_in_one_pass(monkeypatch):
    """Memory is bounded by fitting a chunk of output stations at a time: each window's sums are
    formed as in one pass, so the results are the same to the bit."""
    from insrail.track import resample

    rng = np.random.default_rng(4)
    station = np.sort(rng.uniform(0.0, 400.0, 60_000))
    station[::97] = np.nan
    values = np.column_stack([np.sin(station / 7.0), np.cos(station / 3.0)]) + 1e-4 * rng.standard_normal((60_000, 2))
    values[::131, 1] = np.nan
    at = np.arange(-1.0, 401.0, 0.625)
    monkeypatch.setattr(resample, "FIT_CHUNK_STATIONS", 10 * len(at))
    whole = resample.sliding_window_fit(station, values, at)
    monkeypatch.setattr(resample, "FIT_CHUNK_STATIONS", 37)
    chunked = resample.sliding_window_fit(station, values, at)
    assert np.isnan(whole).any() and np.isfinite(whole).sum() > 1000
    np.testing.assert_array_equal(chunked, whole)
