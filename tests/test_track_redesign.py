"""The tamping re-design (insrail.track.redesign): the corrections meet the bounds, the moved track
passes the chord checks wherever the bounds allow, and where they do not the stretch is listed."""

import numpy as np
import pytest

from insrail.track.exceedance import SleeperGeometry
from insrail.track.redesign import FixedStretch, RedesignSettings, moved, redesign
from insrail.track.tolerance import load_tolerance_profile

SPACING = 0.625


def _wave(rng, station, rms, shortest, longest, count=40):
    wavelength = np.exp(rng.uniform(np.log(shortest), np.log(longest), count))
    amplitude = wavelength / np.sqrt(0.5 * np.sum(wavelength**2)) * rms
    return np.cos(np.outer(station, 2 * np.pi / wavelength) + rng.uniform(0, 2 * np.pi, count)) @ amplitude


def _dip(station, at, depth, length):
    return -depth * np.where(np.abs(station - at) < length / 2, np.cos((station - at) / length * np.pi) ** 2, 0.0)


def _ballasted(seed=1, n=1280):
    """A ballasted track as measured: long waves (8 mm vertical, 5 mm lateral RMS), short waves, dips."""
    rng = np.random.default_rng(seed)
    station = 1000.0 + SPACING * np.arange(n)
    vertical = _wave(rng, station, 8e-3, 40, 200) + _wave(rng, station, 1e-3, 3, 70)
    vertical += _dip(station, 1150.0, 15e-3, 10.0) + _dip(station, 1420.0, 12e-3, 8.0)
    lateral = _wave(rng, station, 5e-3, 40, 200) + _wave(rng, station, 1e-3, 3, 70) + _dip(station, 1300.0, -8e-3, 9.0)
    cross = rng.normal(0.0, 1e-4, n)
    return SleeperGeometry.from_arrays(station, np.column_stack([lateral, lateral]),
                                       np.column_stack([vertical + cross / 2, vertical - cross / 2]),
                                       np.full(n, 1.435), cross, np.zeros(n))


def test_corrections_meet_the_bounds_and_the_moved_track_passes():
    geometry = _ballasted()
    profile = load_tolerance_profile("cn_conventional_160")
    settings = RedesignSettings(max_lift_m=0.040, max_slew_m=0.010, fixed=(FixedStretch(1200.0, 1230.0, 0.0, "bridge"),))
    result = redesign(geometry, profile, settings)
    assert len(result.before.exceedances) > 5
    assert np.all(result.lift_m >= 0.0) and np.all(result.lift_m <= 0.040 + 1e-9)
    assert np.all(np.abs(result.slew_m) <= 0.010 + 1e-9)
    inside = (geometry.station_m >= 1200.0) & (geometry.station_m <= 1230.0)
    assert np.all(result.lift_m[inside] == 0.0) and np.all(result.slew_m[inside] == 0.0)
    assert result.fixed[inside].all()
    assert result.after.exceedances == () and result.cannot_pass == ()
    assert np.nanmax(result.lift_m) > 0.005  # the dips were lifted


def test_lift_only_never_lowers_and_a_minimum_lift_holds_outside_fixed_stretches():
    geometry = _ballasted(seed=3)
    profile = load_tolerance_profile("cn_conventional_160")
    settings = RedesignSettings(min_lift_m=0.010, fixed=(FixedStretch(1300.0, 1320.0, 0.002, "level crossing"),))
    result = redesign(geometry, profile, settings)
    inside = (geometry.station_m >= 1300.0) & (geometry.station_m <= 1320.0)
    # the minimum lift ramps down to the fixed stretch within one knot spacing (4 sleepers) of it
    beside = (geometry.station_m >= 1300.0 - 4 * SPACING) & (geometry.station_m <= 1320.0 + 4 * SPACING)
    assert np.all(result.lift_m[~beside] >= 0.010 - 1e-9)
    assert np.all((result.lift_m[inside] >= 0.0) & (result.lift_m[inside] <= 0.002 + 1e-9))
    # a 10 mm minimum lift cannot meet a crossing held within 2 mm without a 10 m versine beyond its
    # limit at the crossing's ends: listed there, and nowhere else
    assert result.cannot_pass
    for stretch in result.cannot_pass:
        assert min(abs(stretch.station_from_m - edge) for edge in (1300.0, 1320.0)) < 10.0, stretch


def test_a_dip_beside_a_fixed_stretch_that_cannot_pass_is_listed():
    n = 640
    station = 1000.0 + SPACING * np.arange(n)
    # a 20 mm dip half on a bridge (the track there may not be lifted) and half beyond its end
    # (where it may not be lowered): the 10 m versine there cannot pass
    vertical = _dip(station, 1100.0, 20e-3, 10.0)
    geometry = SleeperGeometry.from_arrays(station, np.zeros((n, 2)), np.column_stack([vertical, vertical]),
                                           np.full(n, 1.435), np.zeros(n), np.zeros(n))
    profile = load_tolerance_profile("cn_conventional_160")
    settings = RedesignSettings(fixed=(FixedStretch(1060.0, 1100.0, 0.0, "bridge"),))
    result = redesign(geometry, profile, settings)
    assert result.cannot_pass, "the versine across the bridge's end cannot pass and must be listed"
    assert all(1090.0 <= s.station_from_m <= 1115.0 for s in result.cannot_pass)
    assert all("versine" in s.what and "vertical" in s.what for s in result.cannot_pass)
    # without the bridge the same dip is lifted out
    free = redesign(geometry, profile, RedesignSettings())
    assert free.cannot_pass == () and free.after.exceedances == ()


def test_moved_changes_cant_by_the_lifts_difference_and_keeps_the_gauge():
    geometry = _ballasted(n=200)
    lift = np.column_stack([np.full(200, 0.004), np.full(200, 0.001)])
    after = moved(geometry, lift, np.full(200, 0.002))
    assert np.allclose(after.cant_m - geometry.cant_m, 0.003)
    assert np.allclose(after.gauge_m, geometry.gauge_m)
    assert np.allclose(after.lateral_deviation_m - geometry.lateral_deviation_m, 0.002)


@pytest.mark.parametrize("limit", [0.030, 0.005])
def test_slew_limit_binds_and_is_reported(limit):
    geometry = _ballasted(seed=5)
    profile = load_tolerance_profile("cn_conventional_160")
    result = redesign(geometry, profile, RedesignSettings(max_slew_m=limit))
    assert np.nanmax(np.abs(result.slew_m)) <= limit + 1e-9
    at_limit = [s for s in result.active if s.what == "slew at max_slew"]
    assert bool(at_limit) == (limit == 0.005)
