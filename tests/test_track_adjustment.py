"""Fastener types, correct-to-line and optimised adjustment amounts."""

import numpy as np
import pytest

from insrail.track.adjustment import (
    correct_to_line,
    load_fastener_type,
    optimise_adjustment,
)
from insrail.track.exceedance import SleeperGeometry, assess
from insrail.track.tolerance import SettingsFileError, load_tolerance_profile


def random_walk_track(count, seed, sigma=0.3e-3):
    rng = np.random.default_rng(seed)
    station = 2000.0 + 0.625 * np.arange(count)
    lateral = np.cumsum(rng.normal(0, sigma, (count, 2)), axis=0)
    vertical = np.cumsum(rng.normal(0, sigma, (count, 2)), axis=0)
    lateral -= lateral.mean(axis=0)
    vertical -= vertical.mean(axis=0)
    return SleeperGeometry.from_arrays(station, lateral, vertical, np.full(count, 1.435), np.zeros(count))


def differential_exceedances(geometry, profile):
    return [e for e in assess(geometry, profile).exceedances if e.kind == "differential_versine"]


def test_wj8_and_bad_fastener_files(tmp_path):
    wj8 = load_fastener_type()
    assert wj8.step_m == pytest.approx(1e-3)
    assert wj8.lateral_range_m == pytest.approx((-5e-3, 5e-3)) and wj8.vertical_range_m == pytest.approx((-4e-3, 26e-3))
    path = tmp_path / "f.toml"
    path.write_text("step_mm = 1\nlateral_min_mm = 1\nlateral_max_mm = 5\nvertical_min_mm = -4\nvertical_max_mm = 26\n")
    with pytest.raises(SettingsFileError, match="must contain 0") as info:
        load_fastener_type(path)
    assert info.value.key == "lateral_min_mm"
    path.write_text("step_mm = 1\n")
    with pytest.raises(SettingsFileError, match="missing"):
        load_fastener_type(path)


def test_correct_to_line_rounds_clips_flags_and_moves_gauge_and_cant():
    station = 0.625 * np.arange(4)
    lateral = np.array([[1.4e-3, -0.4e-3], [-7e-3, 0.0], [0.0, 2.6e-3], [np.nan, 0.0]])
    vertical = np.array([[-30e-3, 0.0], [5e-3, 0.0], [0.0, 0.6e-3], [0.0, 0.0]])
    geometry = SleeperGeometry.from_arrays(station, lateral, vertical, np.full(4, 1.435), np.zeros(4))
    adjustment = correct_to_line(geometry, load_fastener_type())
    np.testing.assert_allclose(adjustment.lateral_m * 1e3, [[-1, 0], [5, 0], [0, -3], [0, 0]])
    np.testing.assert_allclose(adjustment.vertical_m * 1e3, [[26, 0], [-4, 0], [0, -1], [0, 0]])
    assert adjustment.unresolved_lateral.tolist() == [[False, False], [True, False], [False, False], [False, False]]
    assert adjustment.unresolved_vertical[:, 0].tolist() == [True, True, False, False]
    moved = adjustment.apply(geometry)
    # Right rail moved 3 mm left at sleeper 2: gauge 3 mm narrower; left rail raised 26 mm: +26 mm cant.
    assert moved.gauge_m[2] == pytest.approx(1.435 - 3e-3)
    assert moved.cant_m[0] == pytest.approx(26e-3) and moved.cant_m[2] == pytest.approx(1e-3)
    assert moved.lateral_deviation_m[0, 0] == pytest.approx(0.4e-3)


def test_optimised_adjustment_passes_every_check_with_less_movement():
    profile = load_tolerance_profile()
    fastener = load_fastener_type()
    geometry = random_walk_track(700, seed=4)
    assert len(differential_exceedances(geometry, profile)) > 10
    optimised = optimise_adjustment(geometry, profile, fastener, chunk_sleepers=960)
    to_line = correct_to_line(geometry, fastener)
    assert differential_exceedances(optimised.apply(geometry), profile) == []
    assert not optimised.unresolved_lateral.any() and not optimised.unresolved_vertical.any()
    assert optimised.total_movement_m < 0.2 * to_line.total_movement_m
    for amounts, (low, high) in ((optimised.lateral_m, fastener.lateral_range_m), (optimised.vertical_m, fastener.vertical_range_m)):
        np.testing.assert_allclose(amounts * 1e3, np.round(amounts * 1e3), atol=1e-9)
        assert amounts.min() >= low - 1e-12 and amounts.max() <= high + 1e-12


def test_a_kink_beyond_the_fastener_range_is_flagged_and_only_there():
    profile = load_tolerance_profile()
    geometry = random_walk_track(600, seed=8, sigma=0.05e-3)
    lateral = geometry.lateral_deviation_m.copy()
    lateral[300:, 0] += 30e-3  # a 30 mm lateral step in the left rail: far beyond 2 x 5 mm of range
    kinked = SleeperGeometry.from_arrays(geometry.station_m, lateral, geometry.vertical_deviation_m, geometry.gauge_m, geometry.cant_m)
    adjustment = optimise_adjustment(kinked, profile, load_fastener_type(), chunk_sleepers=960)
    flagged = np.flatnonzero(adjustment.unresolved_lateral[:, 0])
    assert flagged.size > 0 and np.abs(flagged - 300).max() <= 48
    assert not adjustment.unresolved_lateral[:, 1].any()
    remaining = differential_exceedances(adjustment.apply(kinked), profile)
    assert remaining and all(e.rail == "left" and e.direction == "lateral" for e in remaining)
    for e in remaining:
        assert adjustment.unresolved_lateral[e.first_index : e.last_index + 1, 0].any()


def test_invalid_sleepers_are_not_moved_and_the_rest_still_passes():
    profile = load_tolerance_profile()
    base = random_walk_track(700, seed=11)
    valid = np.ones(700, bool)
    valid[200:215] = False  # a level crossing
    geometry = SleeperGeometry.from_arrays(
        base.station_m, base.lateral_deviation_m, base.vertical_deviation_m, base.gauge_m, base.cant_m, valid=valid
    )
    adjustment = optimise_adjustment(geometry, profile, load_fastener_type())
    assert not adjustment.lateral_m[200:215].any() and not adjustment.vertical_m[200:215].any()
    assert np.count_nonzero(adjustment.lateral_m) > 0
    assert differential_exceedances(adjustment.apply(geometry), profile) == []


def test_optimised_adjustment_reports_progress_and_can_be_cancelled():
    from insrail.progress import Cancelled

    profile = load_tolerance_profile()
    geometry = random_walk_track(700, seed=4)
    fractions = []
    optimise_adjustment(geometry, profile, load_fastener_type(), progress=lambda f, m: fractions.append(f))
    assert fractions[-1] == 1.0 and fractions == sorted(fractions)
    with pytest.raises(Cancelled):
        optimise_adjustment(geometry, profile, load_fastener_type(), cancel=lambda: True)


def test_the_heaviest_channel_is_solved_first_and_the_order_changes_nothing(monkeypatch):
    """With fewer threads than channels the channel with the most trouble starts first; the
    amounts do not depend on the order the channels are solved in."""
    from insrail.track import adjustment

    profile = load_tolerance_profile()
    quiet = random_walk_track(700, seed=8, sigma=0.05e-3)
    rough = random_walk_track(700, seed=4)
    vertical = quiet.vertical_deviation_m.copy()
    vertical[:, 1] = rough.vertical_deviation_m[:, 1]  # only the right rail's vertical needs work
    geometry = SleeperGeometry.from_arrays(quiet.station_m, quiet.lateral_deviation_m, vertical, quiet.gauge_m,
                                           quiet.cant_m)
    assert {(e.direction, e.rail) for e in differential_exceedances(geometry, profile)} == {("vertical", "right")}
    parallel = optimise_adjustment(geometry, profile, load_fastener_type())
    solved = []
    channel = adjustment._optimise_channel

    def recording(deviation, *args, **kwargs):
        solved.append(deviation)
        return channel(deviation, *args, **kwargs)

    monkeypatch.setattr(adjustment, "_optimise_channel", recording)
    monkeypatch.setattr(adjustment.os, "cpu_count", lambda: 1)  # one thread: channels run in submission order
    serial = optimise_adjustment(geometry, profile, load_fastener_type())
    assert len(solved) == 4 and np.array_equal(solved[0], vertical[:, 1])
    for name in ("lateral_m", "vertical_m", "unresolved_lateral", "unresolved_vertical"):
        np.testing.assert_array_equal(getattr(serial, name), getattr(parallel, name))
