"""Chord versines, sliding differential versines, wavelength bands and section statistics."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from insrail.track.irregularity import (
    UniformGrid,
    band_pass,
    differential_versine,
    differential_versine_grid,
    interpolate_valid,
    section_statistics,
    versine,
    versine_xy,
)

SPACING = 0.625


def sleepers(count, start=1000.0):
    return start + SPACING * np.arange(count)


def irregular_sleepers(count, seed, jitter=0.01):
    rng = np.random.default_rng(seed)
    return 500.0 + np.cumsum(SPACING + rng.uniform(-jitter, jitter, count))


def brute_force_differential(d, m, p):
    """Every chord start, every pair inside it, worst signed value at the pair's first point."""
    n = d.size
    worst = np.full(n, np.nan)
    for i in range(n - m):
        if not (np.isfinite(d[i]) and np.isfinite(d[i + m])):
            continue
        j = np.arange(i, i + m + 1)
        residual = d[j] - (d[i] + (j - i) / m * (d[i + m] - d[i]))
        for k in range(i, i + m - p + 1):
            value = residual[k - i] - residual[k - i + p]
            if np.isfinite(value) and not abs(worst[k]) >= abs(value):
                worst[k] = value
    return worst


def continuous_worst_gain(wavelength, chord, pair):
    """max |r(x0+u) - r(x0+u+p)| of a unit sine over chord starts x0 and pair offsets u (dense)."""
    k = 2 * np.pi / wavelength
    x0 = np.linspace(0.0, wavelength, 721)[:, None]
    u = np.linspace(0.0, chord - pair, 801)[None, :]
    value = np.sin(k * (x0 + u)) - np.sin(k * (x0 + u + pair)) + pair / chord * (np.sin(k * (x0 + chord)) - np.sin(k * x0))
    return np.abs(value).max()


@pytest.mark.parametrize("m,p", [(8, 2), (48, 8), (20, 10)])
def test_differential_versine_matches_brute_force_with_gaps(m, p):
    rng = np.random.default_rng(m * 100 + p)
    d = np.cumsum(rng.normal(0, 1e-3, 150))
    d[[17, 60, 61, 62, 120]] = np.nan
    fast = differential_versine_grid(d, m, p)
    slow = brute_force_differential(d, m, p)
    np.testing.assert_array_equal(np.isnan(fast), np.isnan(slow))
    np.testing.assert_allclose(fast[np.isfinite(fast)], slow[np.isfinite(slow)], atol=1e-15)


@pytest.mark.parametrize(
    "chord,pair,wavelength,digest_gain",
    [(30, 5, 10, 2.0), (30, 5, 20, 1.75), (30, 5, 30, 1.0), (30, 5, 60, 0.54), (30, 5, 150, 0.11),
     (300, 150, 70, 1.65), (300, 150, 100, 2.0), (300, 150, 200, 2.41), (300, 150, 400, 1.7)],
)
def test_differential_versine_of_sine_gives_worst_case_gain(chord, pair, wavelength, digest_gain):
    station = sleepers(4000)
    amplitude = 1e-3
    value = differential_versine(station, amplitude * np.sin(2 * np.pi * station / wavelength + 0.3), chord, pair)
    gain = np.nanmax(np.abs(value)) / amplitude
    independent = continuous_worst_gain(wavelength, chord, pair)
    assert gain == pytest.approx(independent, rel=0.01)
    assert gain == pytest.approx(digest_gain, abs=0.01 + 0.01 * digest_gain)


@pytest.mark.parametrize("chord,pair,wavelength", [(30, 5, 5.0), (30, 5, 2.5), (300, 150, 50.0), (300, 150, 150.0)])
def test_differential_versine_comb_zeros(chord, pair, wavelength):
    station = sleepers(2000)
    value = differential_versine(station, 1e-3 * np.sin(2 * np.pi * station / wavelength), chord, pair)
    assert np.nanmax(np.abs(value)) < 1e-12
    assert np.isfinite(value).sum() > 500


def test_single_bump_is_seen_by_every_pair_touching_it():
    station = sleepers(200)
    d = np.zeros(200)
    d[100] = 3e-3
    value = differential_versine(station, d, 30, 5)
    assert np.flatnonzero(np.abs(value) > 2e-3).tolist() == [92, 100]  # pairs (92, 100) and (100, 108)
    assert value[100] == pytest.approx(3e-3) and value[92] == pytest.approx(-3e-3)


@settings(max_examples=40, deadline=None)
@given(
    offset=st.floats(-0.05, 0.05),
    slope=st.floats(-0.01, 0.01),
    seed=st.integers(0, 2**16),
)
def test_straight_deviation_has_no_irregularity(offset, slope, seed):
    station = irregular_sleepers(600, seed)
    d = offset + slope * (station - station[0])
    for chord, pair in [(30, 5), (300, 150)]:
        value = differential_versine(station, d, chord, pair)
        assert np.nanmax(np.abs(value)) < 1e-12
    assert np.nanmax(np.abs(versine(station, d, 10.0))) < 1e-12
    assert np.nanmax(np.abs(versine(station, d, 10.0, back_m=2.5))) < 1e-12


@pytest.mark.parametrize("wavelength", [12.0, 20.0, 40.0, 100.0])
def test_ten_metre_chord_gain_of_sine(wavelength):
    station = irregular_sleepers(3000, 1, jitter=0.002)
    value = versine(station, 1e-3 * np.sin(2 * np.pi * station / wavelength), 10.0)
    # Interpolated chord ends on irregular sleepers: the peak sits within 0.5 % of the analytic gain.
    assert np.nanmax(np.abs(value)) / 1e-3 == pytest.approx(1 - np.cos(np.pi * 10.0 / wavelength), rel=0.005)


@pytest.mark.parametrize("back", [5.0, 2.5, 7.5])
def test_versine_of_circle(back):
    radius = 7000.0
    station = sleepers(200)  # chord ends on sleepers: linear interpolation would bend the parabola
    d = (station - station[100]) ** 2 / (2 * radius)  # offset of a circle from its tangent (parabolic)
    value = versine(station, d, 10.0, back_m=back)
    assert np.nanmedian(value) == pytest.approx(-back * (10 - back) / (2 * radius), rel=1e-9)
    assert np.isnan(value[0]) and np.isnan(value[-1])


def test_versine_xy_of_circle():
    radius = 7000.0
    station = sleepers(400)
    angle = station / radius  # a right-hand curve: clockwise from north
    east, north = radius - radius * np.cos(angle), radius * np.sin(angle)
    value = versine_xy(station, east, north, 10.0)
    exact = radius - np.sqrt(radius**2 - 25.0)  # sagitta of a 10 m chord (arc length ~ chord here)
    assert np.nanmean(value) == pytest.approx(-exact, rel=1e-6)
    assert exact * 1e3 == pytest.approx(1.786, abs=1e-3)  # the digest's example


def test_uniform_grid_round_trip_keeps_gaps_and_exact_nodes():
    station = sleepers(20)
    values = np.arange(20, dtype=float)
    values[[5, 11, 12]] = np.nan
    grid = UniformGrid.resample(station, values)
    assert np.isnan(grid.values[[11, 12]]).all()
    assert grid.values[5] == pytest.approx(5.0)  # one missing sleeper is bridged
    back = grid.at(station, grid.values)
    assert back[10] == 10.0 and back[13] == 13.0  # exact nodes survive NaN neighbours
    with pytest.raises(ValueError, match="multiple of the grid spacing"):
        grid.steps(30.1, "chord length")


def test_interpolation_refuses_bad_stations():
    with pytest.raises(ValueError, match="must increase"):
        interpolate_valid(np.array([0.0, 1.0, 1.0]), np.zeros(3), np.array([0.5]))
    with pytest.raises(ValueError, match="one value per station"):
        versine(np.arange(5.0), np.zeros(4))


def test_band_pass_keeps_its_band_and_drops_the_rest():
    station = sleepers(3200)
    inside = 2e-3 * np.sin(2 * np.pi * station / 10.0)
    outside = 5e-3 * np.sin(2 * np.pi * station / 120.0)
    d1 = band_pass(station, inside + outside, "D1")
    core = slice(600, -600)
    assert np.abs(d1[core] - inside[core]).max() < 0.05 * 2e-3
    d3 = band_pass(station, inside + outside, "D3_level")
    assert np.abs(d3[core] - outside[core]).max() < 0.1 * 5e-3


def test_band_pass_leaves_short_stretches_empty():
    station = sleepers(400)
    d = np.sin(station)
    d[30] = d[31] = np.nan
    out = band_pass(station, d, "D2")  # 70 m needs 112 sleepers: the first 30 are too few
    assert np.isnan(out[:32]).all() and np.isfinite(out[40:]).all()


def test_section_statistics_and_tqi():
    station = sleepers(1280, start=0.0)  # 800 m: four 200 m sections
    sine = 2e-3 * np.sin(2 * np.pi * station / 10.0)
    noise = np.random.default_rng(3).normal(0, 1e-3, station.size)
    noise[:300] = np.nan  # the first section is mostly invalid
    stats = section_statistics(station, {"level": sine, "gauge": noise})
    assert stats.start_m.tolist() == [0.0, 200.0, 400.0, 600.0]
    np.testing.assert_allclose(stats.standard_deviation_m[:, 0], 2e-3 / np.sqrt(2), rtol=2e-3)
    assert np.isnan(stats.standard_deviation_m[0, 1])
    np.testing.assert_allclose(stats.standard_deviation_m[1:, 1], 1e-3, rtol=0.1)
    np.testing.assert_allclose(stats.track_quality_index_m[1:], stats.standard_deviation_m[1:].sum(axis=1))
