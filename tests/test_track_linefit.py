"""Line-type fitting: recovers the simulator's designs from noisy centrelines, exports, rejects bad input."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from insrail.sim.design import design_alignment
from insrail.sim.scenario import preset
from insrail.sim.truth import read_sleeper_truth
from insrail.track.alignment import Arc, Clothoid, HorizontalAlignment, Line
from insrail.track.alignment_csv import read_alignment_csv, write_alignment_csv
from insrail.track.landxml import read_landxml, write_landxml
from insrail.track.linefit import (
    LineFitError,
    element_table,
    fit_alignment,
    fit_horizontal,
    fit_vertical,
)
from insrail.track.profile import PVI, VerticalProfile

SLEEPER_SPACING_M = 0.625
NOISE_M = 0.5e-3


def assert_recovers(fitted, design, *, boundary_m=2.0, radius_rel=0.002, clothoid_m=1.0, vertical_rel=0.02):
    """Every design element inside the fitted range is found, to the issue's tolerances."""
    plan, truth = fitted.horizontal, design.horizontal
    inner = [
        p for p in truth.placed_elements[1:] if plan.start_station_m < p.start_station_m < plan.end_station_m
    ]
    fitted_inner = plan.placed_elements[1:]
    assert [type(p.element) for p in fitted_inner] == [type(p.element) for p in inner]
    for got, want in zip(fitted_inner, inner):
        assert abs(got.start_station_m - want.start_station_m) < boundary_m
        if isinstance(want.element, Arc):
            assert got.element.turn == want.element.turn
            assert abs(got.element.radius_m / want.element.radius_m - 1.0) < radius_rel
        if isinstance(want.element, Clothoid):
            assert abs(got.element.length_m - want.element.length_m) < clothoid_m
    got_pvis, want_pvis = fitted.vertical.pvis[1:-1], design.vertical.pvis[1:-1]
    assert len(got_pvis) == len(want_pvis)
    for got, want in zip(got_pvis, want_pvis):
        assert abs(got.station_m - want.station_m) < boundary_m
        assert abs(got.curve_radius_m / want.curve_radius_m - 1.0) < vertical_rel


def noisy(values, rng):
    return values + rng.normal(0.0, NOISE_M, np.shape(values))


def test_short_truth_with_noise_recovers_the_design(short_perfect_survey):
    truth = read_sleeper_truth(short_perfect_survey / "truth" / "sleepers.csv")
    design = read_alignment_csv(short_perfect_survey / "truth" / "design.csv")
    rng = np.random.default_rng(3)
    fit = fit_alignment(
        truth["station"], *(noisy(truth[c], rng) for c in ("centre_e", "centre_n", "centre_h"))
    )
    assert_recovers(fit.alignment, design)
    # the truth carries 1 mm RMS irregularities and 3 mm bumps: the fit leaves them in the residuals
    assert 0.6e-3 < fit.horizontal.rms_m < 2e-3
    assert 0.6e-3 < fit.vertical.rms_m < 2e-3
    labels = [k.label for k in fit.alignment.horizontal.key_points()]
    assert labels == ["POB", "TS", "SC", "CS", "ST", "POE"]


def test_long_design_from_its_points_within_tolerances():
    """(Its time is printed by benchmarks/linefit.py: a wall-clock assert fails on a loaded machine.)"""
    design = design_alignment(preset("long").design)
    rng = np.random.default_rng(8)
    stations = np.arange(20050.0, 30250.0, SLEEPER_SPACING_M)
    east, north = design.horizontal.point_at(stations)
    # a 1 mm irregularity of 40 m wavelength, which the fit must average out
    wobble = 1e-3 * np.sin(2 * np.pi * stations / 40.0)
    azimuth = design.horizontal.azimuth_at(stations)
    east, north = east + wobble * np.cos(azimuth), north - wobble * np.sin(azimuth)
    height = design.vertical.elevation_at(stations) + wobble
    fit = fit_alignment(stations, noisy(east, rng), noisy(north, rng), noisy(height, rng))
    assert_recovers(fit.alignment, design)
    turns = [row.turn for row in element_table(fit.alignment.horizontal) if row.kind == "Arc"]
    assert turns == ["right", "left"]


def test_arc_without_transitions_meets_the_straights_directly():
    truth = HorizontalAlignment(
        100.0, 200.0, 1.2, 0.0, (Line(300.0), Arc(400.0, 1500.0, "left"), Line(300.0))
    )
    stations = np.arange(0.0, 1000.0, SLEEPER_SPACING_M)
    rng = np.random.default_rng(1)
    east, north = truth.point_at(stations)
    fit = fit_horizontal(stations, noisy(east, rng), noisy(north, rng))
    assert [k.label for k in fit.alignment.key_points()] == ["POB", "PC", "PT", "POE"]
    assert np.allclose(fit.alignment.boundary_stations_m[1:3], [300.0, 700.0], atol=2.0)
    assert abs(fit.alignment.elements[1].radius_m / 1500.0 - 1.0) < 0.002


def test_straight_stays_one_line_and_profile_one_grade():
    stations = np.arange(0.0, 800.0, SLEEPER_SPACING_M)
    rng = np.random.default_rng(2)
    east = 5000.0 + 0.6 * stations
    north = 7000.0 + 0.8 * stations
    plan = fit_horizontal(stations, noisy(east, rng), noisy(north, rng))
    (line,) = plan.alignment.elements
    assert isinstance(line, Line) and math.isclose(line.length_m, stations[-1] - stations[0], abs_tol=2e-3)
    assert math.isclose(plan.alignment.start_azimuth_rad, math.atan2(0.6, 0.8), abs_tol=1e-5)
    profile = fit_vertical(stations, noisy(12.0 + 0.004 * stations, rng))
    assert len(profile.profile.pvis) == 2
    assert math.isclose(profile.profile.grades[0], 0.004, abs_tol=1e-6)


@settings(max_examples=6, deadline=None)
@given(
    radius=st.floats(1000.0, 8000.0),
    grade_change=st.floats(0.003, 0.012),
    vertical_radius=st.floats(10_000.0, 40_000.0),
    turn=st.sampled_from(["left", "right"]),
)
def test_random_curves_are_recovered(radius, grade_change, vertical_radius, turn):
    transition = 0.5 * math.sqrt(radius * 40.0) + 40.0
    horizontal = HorizontalAlignment(
        0.0, 0.0, 0.3, 0.0,
        (Line(250.0), Clothoid(transition, math.inf, radius, turn), Arc(300.0, radius, turn),
         Clothoid(transition, radius, math.inf, turn), Line(250.0)),
    )
    end = horizontal.end_station_m
    profile = VerticalProfile(
        (PVI(0.0, 10.0), PVI(0.5 * end, 10.0 + 0.001 * 0.5 * end, "circular", curve_radius_m=vertical_radius),
         PVI(end, 10.0 + 0.001 * 0.5 * end + (0.001 - grade_change) * 0.5 * end))
    )
    stations = np.arange(0.0, end, SLEEPER_SPACING_M)
    rng = np.random.default_rng(0)
    east, north = horizontal.point_at(stations)
    fit = fit_alignment(stations, noisy(east, rng), noisy(north, rng), noisy(profile.elevation_at(stations), rng))
    design = type(fit.alignment)(horizontal=horizontal, vertical=profile)
    assert_recovers(fit.alignment, design)


def test_fitted_alignment_exports_like_any_design(tmp_path):
    design = design_alignment(preset("short").design)
    stations = np.arange(1050.0, 2250.0, SLEEPER_SPACING_M)
    rng = np.random.default_rng(4)
    east, north = design.horizontal.point_at(stations)
    height = design.vertical.elevation_at(stations)
    fit = fit_alignment(stations, noisy(east, rng), noisy(north, rng), noisy(height, rng))
    write_alignment_csv(tmp_path / "fitted.csv", fit.alignment)
    write_landxml(tmp_path / "fitted.xml", fit.alignment)
    for back in (read_alignment_csv(tmp_path / "fitted.csv"), read_landxml(tmp_path / "fitted.xml")):
        assert np.allclose(back.horizontal.boundary_stations_m, fit.alignment.horizontal.boundary_stations_m, atol=1e-3)
        probe = np.linspace(1060.0, 2240.0, 50)
        assert np.allclose(np.column_stack(back.horizontal.point_at(probe)),
                           np.column_stack(fit.alignment.horizontal.point_at(probe)), atol=1e-3)
        assert np.allclose(back.vertical.elevation_at(probe), fit.alignment.vertical.elevation_at(probe), atol=1e-4)
    report = fit.report()
    assert "Clothoid" in report and "RMS" in report and report.count("\n  Arc") == 1


@pytest.mark.parametrize(
    "mutate, message",
    [
        (lambda s, e, n: (s[::-1], e, n), "does not increase"),
        (lambda s, e, n: (s, np.where(np.arange(e.size) == 7, np.nan, e), n), r"east_m\[7\]"),
        (lambda s, e, n: (s, e[:-1], n), "east_m has"),
        (lambda s, e, n: (s[:40], e[:40], n[:40]), "at least"),
    ],
)
def test_bad_input_is_named(mutate, message):
    truth = HorizontalAlignment(0.0, 0.0, 0.0, 0.0, (Line(100.0), Arc(300.0, 800.0, "right"), Line(200.0)))
    stations = np.arange(0.0, 600.0, SLEEPER_SPACING_M)
    east, north = truth.point_at(stations)
    with pytest.raises(LineFitError, match=message):
        fit_horizontal(*mutate(stations, east, north))


def test_cumulative_distance_stations_give_a_design_covering_the_data():
    """Measured data rarely carry design stations: a running distance works, and plan and profile
    cover the same range, so the fitted design evaluates everywhere along the data."""
    design = design_alignment(preset("short").design)
    rng = np.random.default_rng(6)
    truth_stations = np.arange(1050.0, 2250.0, SLEEPER_SPACING_M)
    east, north = (noisy(v, rng) for v in design.horizontal.point_at(truth_stations))
    height = noisy(design.vertical.elevation_at(truth_stations), rng)
    running = np.concatenate(([0.0], np.cumsum(np.hypot(np.diff(east), np.diff(north)))))
    fit = fit_alignment(running, east, north, height)
    plan, profile = fit.alignment.horizontal, fit.alignment.vertical
    ends = [plan.start_station_m, plan.end_station_m]
    assert np.allclose(profile.stations_m[[0, -1]], ends, atol=1e-6)
    assert np.allclose(profile.elevation_at(ends), height[[0, -1]], atol=5e-3)
    assert np.allclose(plan.boundary_stations_m[1:-1] + 1050.0, design.horizontal.boundary_stations_m[1:-1], atol=0.1)
