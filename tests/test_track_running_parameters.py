"""Cant change rate, alignment and height change rates, cant deficiency and its rate (thesis §5.6):
hand-computed cases and the textbook formula, and their checks in a tolerance profile."""

import numpy as np
import pytest

from insrail.project.model import project_from_settings
from insrail.track.exceedance import SleeperGeometry, assess
from insrail.track.parameters import (
    LineSpeed,
    cant_deficiency_m,
    cant_deficiency_rate_mps,
    line_speed_mps,
    rate_over_base,
)
from insrail.track.tolerance import load_tolerance_profile

SPACING = 0.625


def test_cant_change_rate_by_hand():
    # cant 0 up to 5 m, then rising 2 mm per metre; base 3 m
    station = np.arange(0, 20.001, SPACING)
    cant = np.where(station > 5.0, 2e-3 * (station - 5.0), 0.0)
    rate = rate_over_base(station, cant, 3.0)
    at = {s: r for s, r in zip(station, rate)}
    assert at[5.0] == pytest.approx(6e-3 / 3.0)  # base 5..8 m: 6 mm over 3 m
    assert at[3.75] == pytest.approx(3.5e-3 / 3.0)  # base 3.75..6.75 m: 3.5 mm
    assert at[1.25] == pytest.approx(0.0)  # base 1.25..4.25 m: level
    assert at[12.5] == pytest.approx(2e-3)  # on the ramp: 2 per mille either way


def test_alignment_change_rate_of_a_kink_by_hand():
    # lateral deviation of the left rail: a 1.5 mm step at 10 m (between two sleepers), base 2.5 m
    station = np.arange(0, 20.001, SPACING)
    lateral = np.zeros((station.size, 2))
    lateral[station > 10.0, 0] = 1.5e-3
    geometry = SleeperGeometry.from_arrays(station, lateral, np.zeros_like(lateral), np.full(station.size, 1.435),
                                           np.zeros(station.size))
    profile = _profile("""
[checks.alignment_rate]
kind = "deviation_change_rate"
base_m = 2.5
directions = ["lateral"]
max_abs_ratio = "1/2000"
""")
    result = assess(geometry, profile)
    left = result.channel("alignment_rate", "left", "lateral").values
    right = result.channel("alignment_rate", "right", "lateral").values
    np.testing.assert_allclose(right, 0.0)
    # the step lies between the sleepers at 10 and 10.625 m; every sleeper with a 2.5 m base reaching
    # over it (8.125 .. 12.5 m) sees 1.5 mm / 2.5 m = 0.6 per mille
    spans = (station > 7.5) & (station <= 12.5)
    np.testing.assert_allclose(left[spans], 1.5e-3 / 2.5)
    np.testing.assert_allclose(left[~spans & np.isfinite(left)], 0.0)
    (run,) = [e for e in result.exceedances if e.check == "alignment_rate"]
    assert (run.station_from_m, run.station_to_m) == (8.125, 12.5) and run.rail == "left"


def _profile(checks: str, tmp=None):
    import tempfile
    from pathlib import Path

    path = Path(tempfile.mkdtemp()) / "profile.toml"
    path.write_text('name = "test"\n' + checks)
    return load_tolerance_profile(path)


@pytest.mark.parametrize("radius, cant_mm, speed_kmh", [(2000.0, 120.0, 160.0), (5500.0, 150.0, 300.0),
                                                        (800.0, 60.0, 120.0)])
def test_cant_deficiency_is_the_textbook_value_on_an_arc(radius, cant_mm, speed_kmh):
    station = np.arange(1000.0, 1200.0, SPACING)
    for hand, sign in (("right", 1.0), ("left", -1.0)):
        curvature = np.full(station.size, sign / radius)
        cant = np.full(station.size, sign * cant_mm * 1e-3)  # the outer rail higher
        geometry = SleeperGeometry.from_arrays(station, np.zeros((station.size, 2)), np.zeros((station.size, 2)),
                                               np.full(station.size, 1.435), cant, cant, curvature_1pm=curvature,
                                               line_speed_mps=np.full(station.size, speed_kmh / 3.6))
        textbook_mm = 11.8 * speed_kmh**2 / radius - cant_mm
        # 11.8 is 1500 / (3.6^2 * 9.81) = 11.7985 rounded: equal to 0.02 %
        np.testing.assert_allclose(1e3 * geometry.cant_deficiency_m(), textbook_mm, rtol=0,
                                   atol=2e-4 * 11.8 * speed_kmh**2 / radius, err_msg=hand)


def test_cant_deficiency_check_and_its_rate_on_a_transition():
    # a clothoid from straight to R 2000 m over 100 m with the cant ramped 0 -> 120 mm, 160 km/h
    station = np.arange(0.0, 300.001, SPACING)
    along = np.clip((station - 100.0) / 100.0, 0.0, 1.0)
    curvature, cant = along / 2000.0, 0.12 * along
    speed = line_speed_mps((LineSpeed(0.0, 1e9, 160.0),), station)
    geometry = SleeperGeometry.from_arrays(station, np.zeros((station.size, 2)), np.zeros((station.size, 2)),
                                           np.full(station.size, 1.435), cant, cant, curvature_1pm=curvature,
                                           line_speed_mps=speed)
    deficiency = geometry.cant_deficiency_m()
    full = 1.5 * (160 / 3.6) ** 2 / (9.81 * 2000.0) - 0.12
    np.testing.assert_allclose(deficiency[station >= 200.0], full, atol=1e-12)
    np.testing.assert_allclose(deficiency[station <= 100.0], 0.0, atol=1e-12)
    # the rate: (full deficiency / 100 m) at 44.4 m/s on the transition, away from its ends
    rate = cant_deficiency_rate_mps(station, deficiency, speed, 3.0)
    middle = (station > 105.0) & (station < 195.0)
    np.testing.assert_allclose(rate[middle], full / 100.0 * 160 / 3.6, rtol=1e-9)
    profile = _profile("""
[checks.deficiency]
kind = "cant_deficiency"
max_abs_mm = 25.0

[checks.deficiency_rate]
kind = "cant_deficiency_rate"
base_m = 3.0
max_abs_mm_per_s = 10.0
""")
    result = assess(geometry, profile)
    assert full * 1e3 > 25.0 and full / 100 * 160 / 3.6 * 1e3 > 10.0  # both limits crossed
    checks = {e.check for e in result.exceedances}
    assert checks == {"deficiency", "deficiency_rate"}
    # without a line speed the channels are empty (NaN), not zero
    silent = assess(SleeperGeometry.from_arrays(station, np.zeros((station.size, 2)), np.zeros((station.size, 2)),
                                                np.full(station.size, 1.435), cant, cant), profile)
    assert not silent.exceedances and np.isnan(silent.channel("deficiency").values).all()


def test_cant_excess_on_straight_track_is_negative():
    assert cant_deficiency_m(np.array([0.0]), np.array([40.0]), np.array([-0.02]))[0] == pytest.approx(-0.02)


def test_line_speed_settings(tmp_path):
    (tmp_path / "s").mkdir()
    (tmp_path / "s" / "survey.toml").write_text("")
    base = {"geodesy": {"crs": {"central_meridian_deg": 117.0}}, "surveys": [{"name": "s", "folder": "s"}]}
    one = project_from_settings(base | {"track": {"start_station_m": 0.0, "line_speed_kmh": 250}}, tmp_path)
    assert line_speed_mps(one.line_speeds, np.array([-1e6, 0.0, 1e6])) == pytest.approx(250 / 3.6)
    ranges = [{"from_m": 0.0, "to_m": 4200.0, "kmh": 250}, {"from_m": 4200.0, "to_m": 9000.0, "kmh": 160}]
    two = project_from_settings(base | {"track": {"start_station_m": 0.0, "line_speed_kmh": ranges}}, tmp_path)
    np.testing.assert_allclose(3.6 * line_speed_mps(two.line_speeds, np.array([-1.0, 0.0, 4199.0, 4200.0, 9000.0])),
                               [np.nan, 250, 250, 160, np.nan])
    assert project_from_settings(two.to_settings(), tmp_path).line_speeds == two.line_speeds
    assert project_from_settings(one.to_settings(), tmp_path).line_speeds == one.line_speeds
    from insrail.project.model import ProjectError

    with pytest.raises(ProjectError) as error:
        project_from_settings(base | {"track": {"start_station_m": 0.0, "line_speed_kmh": [
            {"from_m": 10.0, "to_m": 5.0, "kmh": 100}, {"from_m": 0.0, "kmh": 100}, "fast"]}}, tmp_path)
    text = str(error.value)
    assert "line_speed_kmh[0]: from_m (10.0) must be below to_m (5.0)" in text
    assert "line_speed_kmh[1]: expected a table" in text and "line_speed_kmh[2]" in text
