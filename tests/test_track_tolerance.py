"""Tolerance profiles (shipped files, validation messages, copying) and exceedance assessment."""

import math

import numpy as np
import pytest

from insrail.sim.irregularity import random_irregularity
from insrail.sim.scenario import preset
from insrail.track.exceedance import SleeperGeometry, assess, exceedance_runs
from insrail.track.tolerance import (
    DEFAULT_PROFILE,
    SettingsFileError,
    copy_tolerance_profile,
    load_tolerance_profile,
    shipped_tolerance_profiles,
)

VALID = """
name = "mine"
nominal_gauge_mm = 1435.0
[checks.gauge]
kind = "gauge_deviation"
max_abs_mm = 1.0
[checks.short]
kind = "differential_versine"
chord_m = 30.0
pair_m = 5.0
max_abs_mm = 2.0
"""


def test_shipped_profiles_load_and_the_default_holds_tb10754_values():
    names = shipped_tolerance_profiles()
    assert {"cn_hsr_ballastless", "cn_conventional_160", "en13848_5_template"} <= set(names)
    assert {f"fra_class_{c}" for c in range(1, 6)} <= set(names)
    for name in names:
        assert load_tolerance_profile(name).checks
    default = {c.name: c for c in load_tolerance_profile().checks}
    assert load_tolerance_profile().name == DEFAULT_PROFILE
    assert default["gauge"].upper == pytest.approx(1e-3) and default["gauge"].lower == pytest.approx(-1e-3)
    assert default["gauge_change_rate"].upper == pytest.approx(1 / 1500)
    assert default["long_wave_300m_150m"].upper == pytest.approx(10e-3)
    assert (default["short_wave_30m_5m"].chord_m, default["short_wave_30m_5m"].pair_m) == (30.0, 5.0)
    assert default["twist_3m"].base_m == 3.0 and default["cross_level"].upper == pytest.approx(1e-3)
    fra5 = {c.name: c for c in load_tolerance_profile("fra_class_5").checks}
    assert fra5["alignment_62ft"].upper == pytest.approx(0.75 * 0.0254)
    assert fra5["gauge"].lower == pytest.approx(-0.5 * 0.0254) and fra5["gauge"].upper == pytest.approx(0.0254)


@pytest.mark.parametrize(
    "change,key,message",
    [
        (('max_abs_mm = 1.0\n[checks.short]', 'max_abs_mm = 1.0\nbase_m = 3\n[checks.short]'), "checks.gauge.base_m", "not a setting"),
        (('kind = "gauge_deviation"', 'kind = "gauge"'), "checks.gauge.kind", "expected one of"),
        (("pair_m = 5.0", "pair_m = 35.0"), "checks.short.pair_m", "shorter than the chord"),
        (("chord_m = 30.0\n", ""), "checks.short.chord_m", "needs chord_m"),
        (("max_abs_mm = 2.0", ""), "checks.short", "no limit"),
        (("max_abs_mm = 2.0", 'max_abs_mm = "two"'), "checks.short.max_abs_mm", "expected a number"),
        (("max_abs_mm = 2.0", "lower_mm = 2.0\nupper_mm = 1.0"), "checks.short", "must be below"),
        (("max_abs_mm = 2.0", "max_abs_mm = -2.0"), "checks.short.max_abs_mm", "positive limit"),
        (("max_abs_mm = 2.0", 'directions = ["sideways"]\nmax_abs_mm = 2.0'), "checks.short.directions", "lateral"),
        (('name = "mine"', 'name = "mine"\nspeed = 3'), "speed", "unknown key"),
        (("nominal_gauge_mm = 1435.0", "nominal_gauge_mm = 0"), "nominal_gauge_mm", "positive"),
    ],
)
def test_profile_errors_name_file_key_and_expectation(tmp_path, change, key, message):
    old, new = change
    assert old in VALID
    path = tmp_path / "mine.toml"
    path.write_text(VALID.replace(old, new, 1), encoding="utf-8")
    with pytest.raises(SettingsFileError, match=message) as info:
        load_tolerance_profile(path)
    assert info.value.key == key and info.value.path == path and str(path) in str(info.value)


def test_ratio_strings_and_broken_files(tmp_path):
    path = tmp_path / "rate.toml"
    path.write_text('[checks.rate]\nkind = "gauge_change_rate"\nbase_m = "sleeper"\nmax_abs_ratio = "1/1000"\n')
    (check,) = load_tolerance_profile(path).checks
    assert check.base_m is None and check.upper == pytest.approx(1e-3) and check.lower == pytest.approx(-1e-3)
    path.write_text('[checks.rate]\nkind = "gauge_change_rate"\nbase_m = 2.5\nmax_abs_ratio = "1/x"\n')
    with pytest.raises(SettingsFileError, match="ratio like"):
        load_tolerance_profile(path)
    path.write_text("[checks\n")
    with pytest.raises(SettingsFileError, match="not valid TOML"):
        load_tolerance_profile(path)
    with pytest.raises(SettingsFileError, match="shipped: .*cn_hsr_ballastless"):
        load_tolerance_profile("no_such_profile")


def test_copy_profile_for_editing(tmp_path):
    copy = copy_tolerance_profile(DEFAULT_PROFILE, tmp_path / "site.toml")
    assert load_tolerance_profile(copy).checks == load_tolerance_profile().checks
    with pytest.raises(FileExistsError):
        copy_tolerance_profile(DEFAULT_PROFILE, copy)


def test_exceedance_runs_merge_consecutive_sleepers_and_pick_the_peak():
    values = np.array([0, 3, 4, np.nan, -5, -2, 0, 2.5, 0], dtype=float)
    assert exceedance_runs(values, -2.0, 2.0) == [(1, 2, 2), (4, 4, 4), (7, 7, 7)]
    assert exceedance_runs(values, -math.inf, 4.5) == []


def synthetic_track(count=2400, seed=5):
    """Smooth deviations well inside the limits (long waves only, 0.2 mm noise)."""
    rng = np.random.default_rng(seed)
    station = 10000.0 + 0.625 * np.arange(count)
    wave = 1.5e-3 * np.sin(2 * np.pi * station / 400.0)
    lateral = np.column_stack([wave, wave]) + rng.normal(0, 0.1e-3, (count, 2))
    vertical = np.column_stack([-wave, -wave]) + rng.normal(0, 0.1e-3, (count, 2))
    gauge = 1.435 + rng.normal(0, 0.1e-3, count)
    design_cant = np.interp(station, [10300, 10400, 11000, 11100], [0, 0.1, 0.1, 0])
    cant = design_cant + rng.normal(0, 0.1e-3, count)
    return station, lateral, vertical, gauge, cant, design_cant


def test_clean_track_passes_and_injected_defects_are_found_where_they_are():
    station, lateral, vertical, gauge, cant, design_cant = synthetic_track()
    profile = load_tolerance_profile()
    clean = assess(SleeperGeometry.from_arrays(station, lateral, vertical, gauge, cant, design_cant), profile)
    assert clean.exceedances == ()  # the designed cant ramp (1 mm per metre) is not a twist defect
    lateral[400, 0] += 3e-3  # left rail pushed 3 mm right at one sleeper
    vertical[1500, 1] -= 2.5e-3  # right rail dipped
    gauge[900:903] += 1.6e-3  # a 3-sleeper wide spot
    cant[2000] += 2.5e-3
    valid = np.ones(station.size, bool)
    valid[1200:1210] = False  # an invalid stretch (level crossing) with a gross value inside
    lateral[1205, 1] += 0.05
    result = assess(
        SleeperGeometry.from_arrays(station, lateral, vertical, gauge, cant, design_cant, valid, np.arange(station.size) + 7001),
        profile,
    )
    found = {(e.check, e.rail, e.direction) for e in result.exceedances}
    assert ("short_wave_30m_5m", "left", "lateral") in found and ("versine_10m", "left", "lateral") in found
    assert ("short_wave_30m_5m", "right", "vertical") in found
    assert ("gauge", "track", "") in found and ("cross_level", "track", "") in found and ("twist_3m", "track", "") in found
    assert not any(e.rail == "right" and e.direction == "lateral" for e in result.exceedances)

    def covers(check, rail, direction, index):
        return any(
            e.first_index - 1 <= index <= e.last_index + 1
            for e in result.exceedances
            if (e.check, e.rail, e.direction) == (check, rail, direction)
        )

    assert covers("short_wave_30m_5m", "left", "lateral", 400)
    assert covers("versine_10m", "left", "lateral", 400)
    assert covers("short_wave_30m_5m", "right", "vertical", 1500)
    gauge_run = next(e for e in result.exceedances if e.check == "gauge")
    assert (gauge_run.first_index, gauge_run.last_index) == (900, 902)
    assert (gauge_run.first_sleeper, gauge_run.last_sleeper) == (7901, 7903)
    assert gauge_run.station_from_m == pytest.approx(station[900]) and gauge_run.limit == pytest.approx(1e-3)
    short = [e for e in result.exceedances if e.check == "short_wave_30m_5m" and e.rail == "left"]
    assert max(abs(e.peak) for e in short) == pytest.approx(3e-3, abs=0.3e-3)
    assert np.isnan(result.channel("versine_10m", "right", "lateral").values[1200:1210]).all()


def test_geometry_shapes_are_checked():
    station = np.arange(10.0)
    with pytest.raises(ValueError, match=r"lateral_deviation_m: expected shape \(10, 2\)"):
        SleeperGeometry.from_arrays(station, np.zeros(10), np.zeros((10, 2)), np.zeros(10), np.zeros(10))


def test_simulator_bumps_above_the_limit_are_all_reported_at_their_chainage():
    spec = preset("long").irregularities
    station = 20100.0 + 0.625 * np.arange(16160)  # 10 km of sleepers
    rng = np.random.default_rng(3)
    offsets = {}
    for direction, bumps in (("lateral", spec.lateral_bumps), ("vertical", spec.vertical_bumps)):
        injected = random_irregularity(rng, 0.1e-3, bumps=bumps)
        offsets[direction] = np.repeat(injected.evaluate(station)[:, None], 2, axis=1)  # the centreline moves both rails
    geometry = SleeperGeometry.from_arrays(station, offsets["lateral"], offsets["vertical"], np.full(station.size, 1.435), np.zeros(station.size))
    result = assess(geometry, load_tolerance_profile())
    limit = 2e-3
    checked = 0
    for direction, bumps in (("lateral", spec.lateral_bumps), ("vertical", spec.vertical_bumps)):
        for bump in bumps:
            if abs(bump.amplitude_m) <= limit * 1.05:  # clear of the limit, so noise cannot decide
                continue
            peak = int(np.argmin(np.abs(station - (bump.start_station_m + bump.length_m / 2))))
            for rail in ("left", "right"):
                assert any(
                    e.first_index - 1 <= peak <= e.last_index + 1
                    for e in result.exceedances
                    if (e.check, e.rail, e.direction) == ("short_wave_30m_5m", rail, direction)
                ), (direction, rail, bump)
            checked += 1
    assert checked >= 8


def test_every_check_kind_has_a_signal_and_en_template_finds_a_d1_dip():
    from insrail.track.exceedance import SIGNALS
    from insrail.track.tolerance import KINDS

    assert set(SIGNALS) == set(KINDS)
    station = 0.625 * np.arange(1600)
    vertical = np.zeros((1600, 2))
    x = (station - 500.0) / 8.0
    dip = np.where((x > 0) & (x < 1), -25e-3 * np.sin(np.pi * x) ** 4, 0.0)
    vertical += dip[:, None]
    geometry = SleeperGeometry.from_arrays(station, np.zeros((1600, 2)), vertical, np.full(1600, 1.435), np.zeros(1600))
    result = assess(geometry, load_tolerance_profile("en13848_5_template"))
    runs = [e for e in result.exceedances if e.check == "level_d1"]
    assert {e.rail for e in runs} == {"left", "right"}
    assert all(e.peak < -16e-3 and 500.0 <= e.station_from_m <= e.station_to_m <= 508.0 for e in runs)
    assert not [e for e in result.exceedances if e.check != "level_d1"]


def test_track_quality_index_sums_the_seven_channels():
    from insrail.track.exceedance import track_quality

    station = 0.625 * np.arange(1920)  # 1200 m: six 200 m sections
    vertical = np.zeros((1920, 2))
    vertical[:, 0] = 2e-3 * np.sin(2 * np.pi * station / 10.0)  # inside D1
    vertical[:, 1] = 3e-3 * np.sin(2 * np.pi * station / 100.0)  # outside D1: no contribution
    gauge = 1.435 + 0.5e-3 * np.sin(2 * np.pi * station / 8.0)
    geometry = SleeperGeometry.from_arrays(station, np.zeros((1920, 2)), vertical, gauge, np.zeros(1920))
    quality = track_quality(geometry)
    assert quality.channels == ("left_level", "right_level", "left_alignment", "right_alignment", "gauge", "cross_level", "twist")
    inner = slice(1, 5)  # the filter settles within a section of the ends
    np.testing.assert_allclose(quality.standard_deviation_m[inner, 0], 2e-3 / np.sqrt(2), rtol=0.03)
    assert (quality.standard_deviation_m[inner, 1] < 0.05e-3).all()
    np.testing.assert_allclose(quality.standard_deviation_m[inner, 4], 0.5e-3 / np.sqrt(2), rtol=0.02)
    np.testing.assert_allclose(quality.track_quality_index_m[inner], 2e-3 / np.sqrt(2) + 0.5e-3 / np.sqrt(2), rtol=0.05)
