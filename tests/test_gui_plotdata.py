"""The core functions the GUI draws from (insrail.project.plotdata): no Qt needed."""

from __future__ import annotations

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from insrail.io.types import GnssSolution
from insrail.nav.earth import CGCS2000, radii
from insrail.nav.trajectory import Trajectory
from insrail.project.plotdata import (
    Envelope,
    chainage_plots,
    envelopes,
    exceedance_window,
    gap_breaks,
    gnss_residuals,
    navigation_series,
)
from insrail.track.tolerance import load_tolerance_profile

COLUMNS = ["station_m", "gauge_mm", "cant_mm", "design_cant_mm", "lateral_deviation_left_mm",
           "lateral_deviation_right_mm", "vertical_deviation_left_mm", "vertical_deviation_right_mm",
           "check_gauge_mm", "check_gauge_change_rate_ratio", "check_short_wave_30m_5m_left_lateral_mm",
           "check_short_wave_30m_5m_right_vertical_mm", "check_twist_3m_mm"]


def test_chainage_plots_follow_the_profile_and_its_limits():
    plots = {p.key: p for p in chainage_plots(COLUMNS, load_tolerance_profile("cn_hsr_ballastless"))}
    assert set(plots) == {"lateral_deviation", "vertical_deviation", "check_gauge", "check_gauge_change_rate",
                          "check_short_wave_30m_5m", "check_twist_3m", "gauge", "cant"}
    short = plots["check_short_wave_30m_5m"]
    assert short.title == "30 m / 5 m short wave"  # display names, never the profile's ids
    assert short.curves == (("left rail, lateral", "check_short_wave_30m_5m_left_lateral_mm"),
                            ("right rail, vertical", "check_short_wave_30m_5m_right_vertical_mm"))
    assert (short.lower, short.upper, short.unit) == (-2.0, 2.0, "mm")
    rate = plots["check_gauge_change_rate"]  # 'gauge' must not claim the gauge change rate's column
    assert plots["check_gauge"].curves == (("", "check_gauge_mm"),)  # a track channel: the title names it
    assert plots["check_gauge"].title == "Gauge deviation" and plots["gauge"].title == "Gauge"
    assert rate.unit == "‰" and np.isclose(rate.upper, 1000 / 1500) and rate.scale == 1e3


def test_checks_without_stored_columns_get_no_plot():
    plots = chainage_plots(COLUMNS[:8], load_tolerance_profile("cn_hsr_ballastless"))
    assert [p.key for p in plots] == ["lateral_deviation", "vertical_deviation", "gauge", "cant"]


@given(st.floats(-1e6, 1e6), st.floats(0, 500), st.floats(0, 100))
def test_exceedance_window_contains_the_exceedance(start, length, margin):
    low, high = exceedance_window(start + length, start, margin)
    assert np.isclose(low, start - margin) and np.isclose(high, start + length + margin)


def test_navigation_series_units_and_local_position():
    n = 5
    time = np.arange(n, dtype=float)
    lat = np.radians(30.0) + np.arange(n) * 1e-6  # ~6.4 m north per epoch
    zeros = np.zeros((n, 3))
    sigma = np.full((n, 3), 0.004)
    trajectory = Trajectory(time, lat, np.full(n, np.radians(114.0)), np.full(n, 20.0), zeros,
                            np.tile(np.radians([1.0, 2.0, 359.0]), (n, 1)), sigma, sigma, np.radians(sigma),
                            np.full((n, 3), np.radians(1.0) / 3600), np.full((n, 3), 1e-4), zeros, zeros, np.zeros(n))
    series = {s.key: s for s in navigation_series(trajectory, CGCS2000)}
    north = series["position"].values[:, 0]
    assert np.allclose(np.diff(north), 6.38, atol=0.05) and np.allclose(series["position"].values[:, 1:], 0.0)
    assert np.allclose(series["position_sigma"].values, 4.0)
    assert np.allclose(series["attitude"].values[0], [1.0, 2.0, 359.0])
    assert np.allclose(series["gyro_bias"].values, 1.0) and np.allclose(series["accel_bias"].values, 10.0)


def test_gnss_residuals_take_the_lever_arm_in_the_trolley_frame():
    """Heading east, antenna 0.5 m ahead and 1.5 m above the IMU: a GNSS fix exactly there has no
    residual; one 10 mm further north and 4 mm lower shows (10, 0, 4) mm. Fixes outside the
    trajectory's span are left out."""
    n = 11
    time = np.arange(n, dtype=float)
    lat, lon, h = np.radians(30.0), np.radians(114.0), 20.0
    zeros = np.zeros((n, 3))
    rpy = np.tile([0.0, 0.0, np.pi / 2], (n, 1))
    trajectory = Trajectory(time, np.full(n, lat), np.full(n, lon), np.full(n, h), zeros, rpy, zeros, zeros, zeros,
                            zeros, zeros, zeros, zeros, np.zeros(n))
    meridian, normal = radii(lat, CGCS2000)
    fix_time = np.array([-1.0, 2.5, 7.0, 12.0])
    north = np.array([0.0, 0.0, 0.010, 0.0])
    east = np.full(4, 0.5)
    up = np.array([1.5, 1.5, 1.5 - 0.004, 1.5])
    gnss = GnssSolution(fix_time, lat + north / (meridian + h), lon + east / ((normal + h) * np.cos(lat)), h + up,
                        np.full((4, 3), 0.006), np.ones(4), np.full(4, 12), np.full(4, np.nan))
    residuals = gnss_residuals(trajectory, gnss, np.array([0.5, 0.0, -1.5]), CGCS2000)
    assert residuals.time_s.tolist() == [2.5, 7.0] and residuals.unit == "mm"
    np.testing.assert_allclose(residuals.values, [[0.0, 0.0, 0.0], [10.0, 0.0, 4.0]], atol=1e-4)
    np.testing.assert_allclose(residuals.sigma, 6.0)


@given(st.integers(3, 5000), st.integers(1, 400), st.floats(0.0, 1.0), st.floats(0.0, 1.0), st.integers(0, 2**31))
def test_a_band_at_screen_resolution_covers_every_visible_sample(count, columns, a, b, seed):
    rng = np.random.default_rng(seed)
    x = np.cumsum(rng.uniform(0.1, 1.0, count))
    low = rng.normal(size=count)
    high = low + rng.uniform(0.0, 2.0, count)
    envelope = Envelope.of(x, low, high)
    x_from, x_to = sorted((x[0] + a * (x[-1] - x[0]), x[0] + b * (x[-1] - x[0])))
    bx, blow, bhigh = envelope.visible(x_from, x_to, columns)
    inside = (x >= x_from) & (x <= x_to)
    if inside.any():
        assert blow.min() <= low[inside].min() and bhigh.max() >= high[inside].max()
        # reaches both edges to within a pixel column (points sit at the middle of their bins)
        pixel = max((x_to - x_from) / columns, 1.0)
        assert bx[0] <= x[inside][0] + pixel and bx[-1] >= x[inside][-1] - pixel
    # one or two points per pixel column, unless every sample fits in 8 per column
    assert len(bx) <= max(4 * columns + 4, 8 * columns + 2)
    if inside.sum() > 64 * columns:
        assert len(bx) <= 2 * columns + 4


def test_a_band_has_no_fill_across_a_gap():
    time = np.concatenate([np.arange(0.0, 100.0), np.arange(200.0, 300.0)])
    parts = envelopes(time, -np.ones(200), np.ones(200), gap_breaks(time))
    assert [(p.x[0], p.x[-1]) for p in parts] == [(0.0, 99.0), (200.0, 299.0)]
