"""Accuracy prediction of a planned run."""

import math

import numpy as np
import pytest

from insrail.nav.fusion import FusionOptions
from insrail.quality.prediction import GnssQuality, predict


@pytest.fixture(scope="module")
def baseline():
    # its time is printed by benchmarks/predict.py, not asserted here (a loaded machine or a cold
    # numba cache would fail a time bar)
    return predict("nav", speed_mps=1.0, length_m=1000.0)


def test_smoother_beats_the_filter_and_figures_are_plausible(baseline):
    prediction = baseline
    f, s = prediction.forward, prediction.smoothed
    for name in ("lag5_lateral_m", "lag5_vertical_m", "lag150_lateral_m", "lag150_vertical_m", "position_lateral_m"):
        assert 0.0 < getattr(s, name) < getattr(f, name), name
    # nav grade, default GNSS, 1 m/s: sub-millimetre short wave, millimetres long wave (thesis chapter 3)
    assert 0.05e-3 < s.lag5_lateral_m < 1e-3 and 0.3e-3 < f.lag5_lateral_m < 2e-3
    assert 1e-3 < f.lag150_lateral_m < 10e-3
    # cant from the roll error: hundredths of a millimetre for nav grade
    assert 0.01e-3 < f.cant_m < 0.1e-3
    assert math.isnan(f.outage_growth_lateral_m)


def test_lag_differences_are_not_the_naive_root_sum_of_squares(baseline):
    """Errors 5 m apart are strongly correlated: the lag difference is far below sqrt(2) sigma."""
    prediction = baseline
    s = prediction.smoothed
    assert s.lag5_lateral_m < 0.2 * math.sqrt(2.0) * s.position_lateral_m


def test_outage_drift_grows_with_the_outage_and_the_smoother_bridges_it():
    short = predict("tactical", length_m=400.0, outages=((150.0, 30.0),), static_start_s=60.0)
    long = predict("tactical", length_m=400.0, outages=((150.0, 120.0),), static_start_s=60.0)
    for p in (short, long):
        assert p.forward.outage_growth_lateral_m > 0.0
        assert p.smoothed.outage_growth_lateral_m < p.forward.outage_growth_lateral_m
    assert long.forward.outage_growth_lateral_m > 3.0 * short.forward.outage_growth_lateral_m
    assert long.forward.outage_growth_vertical_m > short.forward.outage_growth_vertical_m
    # the outage shows in the along-track profile: the sigma peaks inside it
    t0, t1 = long.outages_s[0]
    time_s = long.profile.time_s
    peak = time_s[np.argmax(long.profile.forward.sigma_lateral_m)]
    assert t0 < peak <= t1 + 1.0


def test_better_gnss_and_no_nhc():
    base = predict("nav", length_m=300.0, static_start_s=60.0, aiding=FusionOptions(smoother=False))
    better = predict("nav", GnssQuality(0.005, 0.010), length_m=300.0, static_start_s=60.0,
                     aiding=FusionOptions(smoother=False))
    no_nhc = predict("nav", length_m=300.0, static_start_s=60.0, aiding=FusionOptions(smoother=False, use_nhc=False))
    assert base.smoothed is None
    assert better.forward.position_vertical_m < base.forward.position_vertical_m
    assert better.forward.lag5_vertical_m < base.forward.lag5_vertical_m
    # thesis 3.3.2: without the NHC the vertical short wave is several times worse
    assert no_nhc.forward.lag5_vertical_m > 2.0 * base.forward.lag5_vertical_m


@pytest.mark.parametrize("kwargs, message", [
    ({"length_m": 100.0}, "longer than 150"),
    ({"speed_mps": 0.0}, "positive speed"),
    ({"stops": ((2000.0, 10.0),)}, "stop at 2000"),
    ({"outages": ((-5.0, 10.0),)}, "outage at -5"),
    ({"gnss": GnssQuality(rate_hz=20.0)}, "GNSS rate"),
])
def test_bad_inputs_are_explained(kwargs, message):
    with pytest.raises(ValueError, match=message):
        predict("nav", **kwargs)
