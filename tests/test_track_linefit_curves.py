"""Line-type fitting of compound and reverse curves built directly from alignment elements (no simulation)."""

import math

import numpy as np
import pytest

from insrail.track.alignment import Arc, Clothoid, HorizontalAlignment, Line
from insrail.track.linefit import LineFitError, fit_horizontal

SLEEPER_SPACING_M = 0.625
NOISE_M = 0.5e-3
INF = math.inf

CURVES = {
    "compound through a clothoid": (
        Line(300.0), Clothoid(80.0, INF, 1200.0, "right"), Arc(250.0, 1200.0, "right"),
        Clothoid(60.0, 1200.0, 2500.0, "right"), Arc(300.0, 2500.0, "right"),
        Clothoid(90.0, 2500.0, INF, "right"), Line(300.0),
    ),
    "compound arcs meeting directly": (
        Line(300.0), Clothoid(80.0, INF, 1200.0, "left"), Arc(250.0, 1200.0, "left"),
        Arc(300.0, 2500.0, "left"), Clothoid(90.0, 2500.0, INF, "left"), Line(300.0),
    ),
    "S-curve through an inflection": (
        Line(300.0), Clothoid(80.0, INF, 1500.0, "right"), Arc(250.0, 1500.0, "right"),
        Clothoid(70.0, 1500.0, INF, "right"), Clothoid(90.0, INF, 1800.0, "left"), Arc(300.0, 1800.0, "left"),
        Clothoid(90.0, 1800.0, INF, "left"), Line(300.0),
    ),
    "reverse curves with a 40 m straight": (
        Line(300.0), Clothoid(80.0, INF, 1500.0, "right"), Arc(250.0, 1500.0, "right"),
        Clothoid(70.0, 1500.0, INF, "right"), Line(40.0), Clothoid(90.0, INF, 1800.0, "left"),
        Arc(300.0, 1800.0, "left"), Clothoid(90.0, 1800.0, INF, "left"), Line(300.0),
    ),
}


@pytest.mark.parametrize("name", CURVES)
def test_compound_and_reverse_curves_are_segmented_and_fitted(name):
    truth = HorizontalAlignment(1000.0, 2000.0, 0.4, 0.0, CURVES[name])
    stations = np.arange(0.0, truth.end_station_m, SLEEPER_SPACING_M)
    rng = np.random.default_rng(5)
    east, north = truth.point_at(stations)
    # a 1 mm irregularity of 40 m wavelength across the track, which the fit must average out
    wobble = 1e-3 * np.sin(2 * np.pi * stations / 40.0)
    azimuth = truth.azimuth_at(stations)
    east = east + wobble * np.cos(azimuth) + rng.normal(0.0, NOISE_M, stations.size)
    north = north - wobble * np.sin(azimuth) + rng.normal(0.0, NOISE_M, stations.size)
    fit = fit_horizontal(stations, east, north).alignment
    assert [type(e) for e in fit.elements] == [type(e) for e in truth.elements], [e.describe() for e in fit.elements]
    assert np.allclose(fit.boundary_stations_m[1:-1], truth.boundary_stations_m[1:-1], atol=0.5)
    for got, want in zip(fit.elements, truth.elements):
        assert got.curvature_start == pytest.approx(want.curvature_start, rel=0.002, abs=1e-9)
        assert got.curvature_end == pytest.approx(want.curvature_end, rel=0.002, abs=1e-9)
        if isinstance(want, Clothoid):
            assert abs(got.length_m - want.length_m) < 0.5


def noisy_points(truth, stations, seed):
    rng = np.random.default_rng(seed)
    east, north = truth.point_at(stations)
    return east + rng.normal(0.0, NOISE_M, stations.size), north + rng.normal(0.0, NOISE_M, stations.size)


def assert_fits(fit, truth, first, last):
    """The elements the data cover, found as a surveyor expects: the same kinds, arcs' radii within
    0.2 %, joints within 2 m (one in a stretch without points too: the elements around it place it)."""
    want = [p for p in truth.placed_elements if p.end_station_m > first + 0.5 and p.start_station_m < last - 0.5]
    got = fit.placed_elements
    assert [type(p.element) for p in got] == [type(p.element) for p in want], [p.element.describe() for p in got]
    for g, w in zip(got, want):
        if g is not got[0]:
            assert abs(g.start_station_m - w.start_station_m) < 2.0
        if isinstance(w.element, Arc):
            assert g.element.turn == w.element.turn
            assert g.element.radius_m == pytest.approx(w.element.radius_m, rel=0.002)


@pytest.mark.parametrize("gap", [(480.0, 50.0), (615.0, 50.0), (800.0, 60.0)],
                         ids=["in the first arc", "over the clothoid between the arcs", "in the second arc"])
def test_a_stretch_without_points_inside_a_compound_curve_is_fitted_as_its_elements(gap):
    """Sleepers left out over 50-60 m inside a compound curve: chords ending in the gap once bent the
    curvature diagram (a chord end interpolated across the gap lies on its chord, 26 cm inside an
    R 1200 m arc), the seed got arcs of alternating radius and the fit returned one arc as four of
    the same radius after hundreds of solver evaluations. The curve is found as laid."""
    truth = HorizontalAlignment(1000.0, 2000.0, 0.7, 0.0, CURVES["compound through a clothoid"])
    stations = np.arange(0.0, truth.end_station_m, 0.6)
    stations = stations[(stations < gap[0]) | (stations > gap[0] + gap[1])]
    fit = fit_horizontal(stations, *noisy_points(truth, stations, 5))
    assert_fits(fit.alignment, truth, stations[0], stations[-1])


def test_data_without_two_chords_clear_of_their_gaps_are_refused_naming_the_stretch():
    """Two clusters of points 60 m apart: every heading chord ends in the gap, where it would be
    interpolated, so the curvature diagram has nothing to stand on."""
    stations = np.concatenate((np.arange(0.0, 5.0, 0.6), np.arange(65.0, 75.0, 0.6)))
    with pytest.raises(LineFitError, match=r"between 0\.0 and 74\.6 m .*no two chords of 20 m have both ends on the "
                                           r"data, points more than 5\.0 m apart being a gap"):
        fit_horizontal(stations, 1000.0 + stations, np.full(stations.size, 2000.0))


@pytest.mark.parametrize("transition_m", [40.0, 80.0])
@pytest.mark.parametrize("before_m", [3.0, 6.0, 10.0])
@pytest.mark.parametrize("at_start", [True, False], ids=["start", "end"])
def test_data_beginning_a_few_metres_before_a_curve_fit_the_straight_and_the_transition(at_start, before_m,
                                                                                        transition_m):
    """Data beginning (ending) a few metres on the straight before (after) a transition, closer than
    the curvature diagram's blind end: they were refused (the transition fitted as a piece running
    from the data's edge, which then went, leaving the arc to run there: 100 mm off). Now the
    straight and the whole transition are found."""
    truth = HorizontalAlignment(1000.0, 2000.0, 0.7, 0.0, (
        Line(200.0), Clothoid(transition_m, INF, 1000.0, "right"), Arc(300.0, 1000.0, "right"),
        Clothoid(transition_m, 1000.0, INF, "right"), Line(200.0)))
    if at_start:
        stations = np.arange(200.0 - before_m, truth.end_station_m, 0.6)
    else:
        stations = np.arange(0.0, truth.end_station_m - 200.0 + before_m, 0.6)
    fit = fit_horizontal(stations, *noisy_points(truth, stations, 7))
    assert_fits(fit.alignment, truth, stations[0], stations[-1])
