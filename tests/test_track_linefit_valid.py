"""The line-type fit returns an alignment its own validator accepts and that follows the data, or
refuses the stretch with a LineFitError naming it -- never a valid alignment that does not follow.

Random plausible alignments (straights, clothoids, arcs, compound curves; the data starting or
ending anywhere, inside curves too), sub-millimetre to millimetre noise and stretches without
points (sleepers left out of the fit), and the degenerate solution a drifting tunnel centreline
gave: a curve collapsed to a lone clothoid after a straight.
"""

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from insrail.track.alignment import Arc, Clothoid, HorizontalAlignment, Line
from insrail.track.linefit import (ARC, CLOTHOID, LINE, LineFitError, _Chain, _check_local_follow, _simplified,
                                   fit_alignment, fit_horizontal)

SPACING_M = 0.625
FOLLOW_RMS_FACTOR = 1.5
"""The plan residual RMS stays within this factor of the noise (+ 0.2 mm)."""
FOLLOW_MAX_M = 6e-3
"""... and no point lies farther than this from the fitted plan (noise up to 1 mm: 6 sigma)."""


@st.composite
def alignments(draw):
    """Line, then 1-3 curves (clothoid, arc, clothoid; sometimes no transitions, sometimes a
    compound arc pair), each followed by a straight (sometimes very short: a reverse curve)."""
    elements = [Line(draw(st.floats(80.0, 400.0)))]
    for _ in range(draw(st.integers(1, 3))):
        turn = draw(st.sampled_from(["left", "right"]))
        radii = [draw(st.floats(600.0, 12_000.0))]
        if draw(st.booleans()):
            radii.append(radii[0] * draw(st.sampled_from([0.6, 1.5])))
        transitions = draw(st.booleans()) or len(radii) > 1
        transition = draw(st.floats(40.0, 200.0))
        if transitions:
            elements.append(Clothoid(transition, math.inf, radii[0], turn))
        for i, radius in enumerate(radii):
            elements.append(Arc(draw(st.floats(60.0, 500.0)), radius, turn))
            if i + 1 < len(radii):
                elements.append(Clothoid(transition, radius, radii[i + 1], turn))
        if transitions:
            elements.append(Clothoid(transition, radii[-1], math.inf, turn))
        elements.append(Line(draw(st.floats(80.0, 400.0))))
    return HorizontalAlignment(500_000.0, 3_300_000.0, draw(st.floats(0.0, 2 * math.pi)), 0.0, tuple(elements))


@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    truth=alignments(),
    cut=st.tuples(st.floats(0.0, 0.4), st.floats(0.0, 0.4)),
    noise_m=st.floats(0.1e-3, 1e-3),
    gap=st.tuples(st.floats(0.1, 0.9), st.floats(0.0, 60.0)),
    seed=st.integers(0, 2**16),
)
def test_fitted_alignment_passes_the_validator_and_follows_the_data(truth, cut, noise_m, gap, seed):
    length = truth.end_station_m
    first, last = cut[0] * length, length - cut[1] * length
    stations = np.arange(first, last, SPACING_M)
    if stations.size < 2 or stations[-1] - stations[0] < 200.0:
        stations = np.arange(0.0, length, SPACING_M)
    # a stretch without points, as where invalid sleepers are left out
    middle = stations[0] + gap[0] * (stations[-1] - stations[0])
    stations = stations[(stations < middle) | (stations > middle + gap[1])]
    rng = np.random.default_rng(seed)
    east, north = (v + rng.normal(0.0, noise_m, stations.size) for v in truth.point_at(stations))
    height = 30.0 + 0.002 * stations + rng.normal(0.0, noise_m, stations.size)

    try:
        fit = fit_alignment(stations, east, north, height)
    except LineFitError as error:  # refused: it must say where
        assert f"{stations[0]:.1f} and {stations[-1]:.1f} m" in str(error)
        return

    plan = fit.alignment.horizontal
    # the validator, again, on the elements as a user's file would give them
    HorizontalAlignment(plan.start_east_m, plan.start_north_m, plan.start_azimuth_rad, plan.start_station_m,
                        plan.elements)
    for before, after in zip(plan.elements[:-1], plan.elements[1:]):
        if isinstance(before, Clothoid) or isinstance(after, Clothoid):
            assert math.isclose(before.curvature_end, after.curvature_start, rel_tol=1e-6, abs_tol=1e-12)
    assert fit.horizontal.rms_m < FOLLOW_RMS_FACTOR * noise_m + 0.2e-3
    assert np.abs(fit.horizontal.offset_m).max() < FOLLOW_MAX_M
    assert fit.vertical.rms_m < FOLLOW_RMS_FACTOR * noise_m + 0.2e-3


def test_a_fit_that_does_not_follow_the_data_is_refused_naming_the_stretch():
    """The case hypothesis found: data 2.5 m into the entry transition to 18 m into the exit
    transition of an R 1050 m curve; the chain the seed led to was valid but 267 mm off the
    points. Either the fit follows the data or it says where it failed."""
    inf = math.inf
    truth = HorizontalAlignment(500000.0, 3300000.0, 1.192092896e-07, 0.0, (
        Line(81.00986797905698), Clothoid(200.0, inf, 1050.0, "left"), Arc(301.9847954055469, 1050.0, "left"),
        Clothoid(200.0, 1050.0, inf, "left"), Line(80.0)))
    length = truth.end_station_m
    stations = np.arange(0.09678359464058464 * length, length - 0.30312555776199085 * length, SPACING_M)
    rng = np.random.default_rng(0)
    noise_m = 0.0008214587190658006
    east, north = (v + rng.normal(0.0, noise_m, stations.size) for v in truth.point_at(stations))
    try:
        fit = fit_horizontal(stations, east, north)
    except LineFitError as error:
        assert f"{stations[0]:.1f} and {stations[-1]:.1f} m" in str(error)
        assert "does not follow" in str(error)
    else:
        assert fit.rms_m < FOLLOW_RMS_FACTOR * noise_m + 0.2e-3


def test_a_plan_that_leaves_its_data_at_an_end_is_refused_naming_where():
    """The case hypothesis found next: data ending 19.6 m into an arc without transitions (R 600 m)
    were fitted valid, RMS 1.4 mm, but with a clothoid for the arc: 8.5 mm off at the data's end.
    Either the fit follows the data there or it says between which stations it does not."""
    truth = HorizontalAlignment(500000.0, 3300000.0, 0.0, 0.0, (Line(181.0), Arc(60.0, 600.0, "left"), Line(80.0)))
    stations = np.arange(0.0, 0.625 * truth.end_station_m, SPACING_M)
    rng = np.random.default_rng(0)
    east, north = (v + rng.normal(0.0, 0.1e-3, stations.size) for v in truth.point_at(stations))
    try:
        fit = fit_horizontal(stations, east, north)
    except LineFitError as error:
        assert f"{stations[0]:.1f} and {stations[-1]:.1f} m does not follow the centreline between" in str(error)
        assert "max residual" in str(error) and "against a noise of" in str(error)
    else:
        assert np.abs(fit.offset_m).max() < FOLLOW_MAX_M


def test_a_local_defect_inside_the_data_is_no_misfit_but_a_plan_leaving_them_is():
    """A lateral defect of a few sleepers inside the data is what the deviations must show; the same
    offset held over a window's length, or a point far off at an end, is a plan that does not follow."""
    stations = np.arange(0.0, 300.0, SPACING_M)
    noise = np.random.default_rng(1).normal(0.0, 0.5e-3, stations.size)
    defect = noise + np.where(np.abs(stations - 150.0) < 2.0, 10e-3, 0.0)
    _check_local_follow(stations, defect)  # no refusal
    for offsets, where in ((noise + np.where(np.abs(stations - 150.0) < 20.0, 3e-3, 0.0), "between 1"),
                           (noise + np.where(stations > 297.0, 10e-3, 0.0), "and 299.4 m: max residual")):
        with pytest.raises(LineFitError, match=where):
            _check_local_follow(stations, offsets)


def test_a_curve_collapsed_to_a_lone_clothoid_merges_into_the_straight():
    """The solution the tunnel survey gave: the entry clothoid and the arc of a flat curve shrunk
    to nothing, leaving "Clothoid 26 m, R 15 km -> inf" right after a straight, which the
    validator refuses. The chain is simplified to one straight."""
    chain = _Chain(0.0, 300.0, 0.0, 0.0, (LINE, CLOTHOID, ARC, CLOTHOID, LINE))
    x = np.array([0.0, 0.3, 80.0, 0.0, 0.0, 26.27, 1.0 / 15031.8])
    try:
        chain.alignment(x)
    except ValueError as error:
        assert "does not continue the curvature" in str(error)
    else:
        raise AssertionError("the collapsed chain should be refused by the validator")
    simpler, x_simpler = _simplified(chain, x, 1e-3, 50_000.0)
    assert simpler.kinds == (LINE,)
    (line,) = simpler.alignment(x_simpler).elements
    assert isinstance(line, Line) and math.isclose(line.length_m, 300.0)


def test_a_spiral_spiral_curve_keeps_its_peak():
    """An arc shrunk to nothing between two transitions is a spiral-spiral curve: kept."""
    chain = _Chain(0.0, 600.0, 0.0, 0.0, (LINE, CLOTHOID, ARC, CLOTHOID, LINE))
    x = np.array([0.0, 0.3, 200.0, 100.0, 0.0, 100.0, 1.0 / 1500.0])
    result = _simplified(chain, x, 1e-3, 50_000.0)
    assert result is None
    kinds = [type(e).__name__ for e in chain.alignment(x).elements]
    assert kinds == ["Line", "Clothoid", "Clothoid", "Line"]


def test_a_chain_solved_past_its_data_is_refused_naming_the_stretch(monkeypatch):
    """Hypothesis found a chain whose simplification left its last element cut to nothing: the
    refusal said "the fitted elements are longer than the data" without saying where. Any refusal
    while the chain is solved now names the stretch."""
    import insrail.track.linefit as linefit

    def cut_to_nothing(chain, x, station, east, north):
        raise LineFitError("line fitting: the fitted elements are longer than the data")

    monkeypatch.setattr(linefit, "_solve_chain", cut_to_nothing)
    stations = np.arange(100.0, 900.0, SPACING_M)
    with pytest.raises(LineFitError) as refused:
        linefit.fit_horizontal(stations, 500_000.0 + stations, np.full(stations.size, 3_300_000.0))
    assert "between 100.0 and 899.4 m" in str(refused.value)
    assert "the fitted elements are longer than the data" in str(refused.value)
