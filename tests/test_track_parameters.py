"""Gauge, cross-level, twist and cant-change parameters."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from insrail.track.parameters import difference_over_base, track_parameters


def irregular_sleepers(count, seed):
    rng = np.random.default_rng(seed)
    return 200.0 + np.cumsum(0.625 + rng.uniform(-0.01, 0.01, count))


@settings(max_examples=40, deadline=None)
@given(
    gauge_slope=st.floats(-1e-3, 1e-3),
    cant_slope=st.floats(-2e-3, 2e-3),
    design_slope=st.floats(-2e-3, 2e-3),
    twist_base=st.floats(1.5, 10.0),
    seed=st.integers(0, 2**16),
)
def test_ramps_give_exact_rates_and_twists(gauge_slope, cant_slope, design_slope, twist_base, seed):
    station = irregular_sleepers(120, seed)
    along = station - station[0]
    gauge = 1.436 + gauge_slope * along
    cant = 0.05 + cant_slope * along
    design = 0.049 + design_slope * along
    result = track_parameters(station, gauge, cant, design, twist_base_m=twist_base)
    inner = np.isfinite(result.twist_m)
    assert inner.sum() > 80
    np.testing.assert_allclose(result.gauge_deviation_m, 0.001 + gauge_slope * along, atol=1e-12)
    np.testing.assert_allclose(result.gauge_change_rate[np.isfinite(result.gauge_change_rate)], gauge_slope, atol=1e-12)
    np.testing.assert_allclose(result.gauge_change_rate_sleeper[1:], gauge_slope, atol=1e-12)
    np.testing.assert_allclose(result.cross_level_m, 0.001 + (cant_slope - design_slope) * along, atol=1e-12)
    np.testing.assert_allclose(result.twist_m[inner], cant_slope * twist_base, atol=1e-12)
    np.testing.assert_allclose(result.twist_from_design_m[inner], (cant_slope - design_slope) * twist_base, atol=1e-12)
    np.testing.assert_allclose(result.cant_change_rate[1:], cant_slope, atol=1e-12)
    assert np.isnan(result.gauge_change_m[0])


def test_twist_of_a_step_and_of_a_single_sleeper():
    station = 0.625 * np.arange(40)
    cross_level = np.where(np.arange(40) >= 20, 2e-3, 0.0)
    twist = difference_over_base(station, cross_level, 3.0)
    # The step is a ramp between sleepers 19 and 20 (11.875-12.5 m). A 3 m base spans all of it
    # when it starts at sleepers 16..19 or ends at 20..23, and touches it from sleeper 15 to 24.
    assert np.flatnonzero(np.abs(twist) > 0).tolist() == list(range(15, 25))
    np.testing.assert_allclose(twist[16:24], 2e-3)
    spike = np.zeros(40)
    spike[20] = 2.5e-3
    twist = difference_over_base(station, spike, 3.0)
    assert np.abs(twist[20]) == pytest.approx(2.5e-3)  # the defect sleeper is never diluted
    assert np.isfinite(twist).all()  # near the ends one of the two bases still fits


def test_bad_inputs_are_named():
    with pytest.raises(ValueError, match="cant_m"):
        track_parameters(np.arange(5.0), np.zeros(5), np.zeros(4))
    with pytest.raises(ValueError, match="base length"):
        difference_over_base(np.arange(5.0), np.zeros(5), 0.0)
