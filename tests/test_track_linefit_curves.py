"""Line-type fitting of compound and reverse curves built directly from alignment elements (no simulation)."""

import math

import numpy as np
import pytest

from insrail.track.alignment import Arc, Clothoid, HorizontalAlignment, Line
from insrail.track.linefit import fit_horizontal

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
