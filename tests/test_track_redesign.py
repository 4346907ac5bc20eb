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


@pytest.mark.parametrize("group", [1, 4])
def test_the_sliding_extreme_rows_hold_every_chord_placement(tmp_path, monkeypatch, group):
    """A long differential versine's sparse rows (sliding maximum and minimum over each pair's chord
    starts): per sleeper (group 1) they allow exactly what every chord placement written out allows,
    the same least movement as a programme with one row per pair and chord start; in groups of a
    knot spacing they ask at most a little more; the moved track passes either way."""
    from scipy.optimize import linprog

    from insrail.track import redesign as module

    monkeypatch.setattr(module, "SLIDING_STARTS", 1)  # this short chord written whole, as a 300 m one is
    monkeypatch.setattr(module, "SLIDING_GROUP", group)

    from insrail.track.adjustment_programme import RailCheck
    from insrail.track.redesign import KNOT_SPACING, UNIT_M, _knot_basis

    path = tmp_path / "long_chord.toml"
    path.write_text('name = "long chord"\n[checks.long]\nkind = "differential_versine"\nchord_m = 30.0\n'
                    'pair_m = 15.0\ndirections = ["vertical"]\nmax_abs_mm = 4.0\n', encoding="utf-8")
    profile = load_tolerance_profile(path)
    n, m, p = 300, 48, 24
    rng = np.random.default_rng(7)
    station = 1000.0 + SPACING * np.arange(n)
    vertical = np.column_stack([_wave(rng, station, 5e-3, 15, 60), _wave(rng, station, 5e-3, 15, 60)])
    vertical[[40, 41, 200], 0] = np.nan  # a gap in a rail: its chords and pairs are not held
    geometry = SleeperGeometry.from_arrays(station, np.zeros((n, 2)), vertical, np.full(n, 1.435), np.zeros(n),
                                           np.zeros(n))
    settings = RedesignSettings(margin_m=0.0)
    result = redesign(geometry, profile, settings)
    assert result.before.exceedances
    # the moved rails pass at every pair of measured sleepers (the assessment also judges the pairs
    # it interpolates across a one-sleeper gap, which the programme does not hold)
    measured = np.isfinite(vertical).all(axis=1)  # a sleeper is measured with both rails
    check = RailCheck("differential_versine", m, p, 4e-3)
    for rail in (0, 1):
        after = check.values(np.where(measured, vertical[:, rail] + result.lift_m[:, rail], np.nan))
        assert np.nanmax(np.abs(after)) <= 4e-3 + 1e-9

    # every (pair, chord start) written out, over the same knots, in the same units
    knots = _knot_basis(n, KNOT_SPACING).toarray()
    limit = 4e-3 / UNIT_M
    rows, bounds = [], []
    for rail in (0, 1):
        d = np.where(measured, vertical[:, rail], np.nan) / UNIT_M
        for k in range(n - p):
            for i in range(max(0, k - (m - p)), min(k, n - m - 1) + 1):
                if not np.isfinite(d[[k, k + p, i, i + m]]).all():
                    continue
                value = d[k] - d[k + p] + p / m * (d[i + m] - d[i])
                row = knots[k] - knots[k + p] + p / m * (knots[i + m] - knots[i])
                full = np.zeros(2 * knots.shape[1])
                full[rail * knots.shape[1]:(rail + 1) * knots.shape[1]] = row
                rows += [full, -full]
                bounds += [limit - value, limit + value]
    # a rail with a gap: the programme leaves its unmeasured sleepers unmoved
    upper = np.full(2 * knots.shape[1], 0.050 / UNIT_M)
    gap = np.flatnonzero(~np.isfinite(vertical[:, 0]))
    upper[np.flatnonzero(knots[gap].sum(axis=0) > 0)] = 0.0
    upper[knots.shape[1] + np.flatnonzero(knots[gap].sum(axis=0) > 0)] = 0.0
    weight = np.tile(knots.sum(axis=0), 2)
    written_out = linprog(weight, A_ub=np.array(rows), b_ub=np.array(bounds), bounds=list(zip(np.zeros(upper.size), upper)),
                          method="highs")
    assert written_out.status == 0
    movement = np.nansum(result.lift_m) / UNIT_M
    if group == 1:
        assert movement == pytest.approx(written_out.fun, rel=1e-6, abs=1e-3)
    else:
        assert written_out.fun - 1e-3 <= movement <= 1.15 * written_out.fun
