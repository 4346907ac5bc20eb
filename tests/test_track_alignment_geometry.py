"""Horizontal alignment geometry: chain, clothoids, projection (station/offset)."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad
from scipy.special import fresnel

from insrail.track.alignment import Arc, Clothoid, HorizontalAlignment, Line
from insrail.track.errors import DesignError

START_AZIMUTH = 0.7
R = 2800.0
LS = 120.0
LC = 400.0


def brief_alignment() -> HorizontalAlignment:
    """300 m line, 120 m clothoid, R 2800 m arc of 400 m, 120 m clothoid, 300 m line."""
    return HorizontalAlignment(
        start_east_m=512345.678,
        start_north_m=3380512.345,
        start_azimuth_rad=START_AZIMUTH,
        start_station_m=1000.0,
        elements=(
            Line(300.0),
            Clothoid(LS, math.inf, R, "right"),
            Arc(LC, R, "right"),
            Clothoid(LS, R, math.inf, "right"),
            Line(300.0),
        ),
    )


ALIGNMENT = brief_alignment()


def to_local(alignment, east, north, origin_station):
    """Coordinates in the frame of the tangent at origin_station: x along, y to the right."""
    e0, n0 = alignment.point_at(origin_station)
    az = float(alignment.azimuth_at(origin_station))
    de, dn = east - e0, north - n0
    return de * math.sin(az) + dn * math.cos(az), de * math.cos(az) - dn * math.sin(az)


def test_layout_and_key_points():
    assert ALIGNMENT.length_m == pytest.approx(1240.0)
    assert ALIGNMENT.end_station_m == pytest.approx(2240.0)
    labels = [(k.label, k.station_m) for k in ALIGNMENT.key_points()]
    assert labels == [("POB", 1000.0), ("TS", 1300.0), ("SC", 1420.0), ("CS", 1820.0), ("ST", 1940.0),
                      ("POE", 2240.0)]
    np.testing.assert_array_equal(ALIGNMENT.boundary_stations_m, [1000, 1300, 1420, 1820, 1940, 2240])
    assert ALIGNMENT.element_at(1419.999).index == 1
    assert ALIGNMENT.element_at(1420.0).index == 2  # a joint belongs to the next element
    assert isinstance(ALIGNMENT.element_at(1500.0).element, Arc)
    np.testing.assert_array_equal(ALIGNMENT.element_index_at([1000.0, 1350.0, 2240.0]), [0, 1, 4])


def test_end_azimuth_equals_total_deflection():
    deflection = 2 * LS / (2 * R) + LC / R
    assert float(ALIGNMENT.azimuth_at(ALIGNMENT.end_station_m)) == pytest.approx(START_AZIMUTH + deflection, abs=1e-13)


def test_curvature_diagram():
    k = ALIGNMENT.curvature_at([1100.0, 1360.0, 1600.0, 1880.0, 2000.0])
    np.testing.assert_allclose(k, [0.0, 0.5 / R, 1 / R, 0.5 / R, 0.0], atol=1e-15)
    left = HorizontalAlignment(0.0, 0.0, 0.0, 0.0, (Line(10.0), Clothoid(50.0, math.inf, 500.0, "left"),
                                                    Arc(10.0, 500.0, "left")))
    assert float(left.curvature_at(65.0)) == pytest.approx(-1 / 500)
    assert float(left.azimuth_at(70.0)) == pytest.approx(2 * math.pi - 50.0 / 1000 - 10.0 / 500)


def test_arc_radius_recovered_from_three_points():
    e, n = ALIGNMENT.point_at(np.array([1430.0, 1600.0, 1810.0]))
    a = np.hypot(e[1] - e[0], n[1] - n[0])
    b = np.hypot(e[2] - e[1], n[2] - n[1])
    c = np.hypot(e[2] - e[0], n[2] - n[0])
    area2 = abs((e[1] - e[0]) * (n[2] - n[0]) - (e[2] - e[0]) * (n[1] - n[0]))
    assert a * b * c / (2 * area2) == pytest.approx(R, abs=1e-6)


def test_tangent_and_position_continuity_at_joints():
    joints = ALIGNMENT.boundary_stations_m[1:-1]
    eps = 1e-6
    az_before, az_after = ALIGNMENT.azimuth_at(joints - eps), ALIGNMENT.azimuth_at(joints + eps)
    assert np.max(np.abs(az_after - az_before)) < 2 * eps / R + 1e-12
    e0, n0 = ALIGNMENT.point_at(joints - eps)
    e1, n1 = ALIGNMENT.point_at(joints + eps)
    assert np.max(np.abs(np.hypot(e1 - e0, n1 - n0) - 2 * eps)) < 1e-8
    for before, after in zip(ALIGNMENT.placed_elements[:-1], ALIGNMENT.placed_elements[1:]):
        assert (before.end_east_m, before.end_north_m) == (after.start_east_m, after.start_north_m)
        assert before.end_azimuth_rad == pytest.approx(after.start_azimuth_rad, abs=1e-15)


def test_entry_clothoid_matches_fresnel_integrals():
    # x = A sqrt(pi) C(l / (A sqrt(pi))), y = A sqrt(pi) S(...), A^2 = R L
    l = np.linspace(0.0, LS, 61)
    stations = 1300.0 + l
    x, y = to_local(ALIGNMENT, *ALIGNMENT.point_at(stations), 1300.0)
    scale = math.sqrt(R * LS * math.pi)
    s_fresnel, c_fresnel = fresnel(l / scale)
    np.testing.assert_allclose(x, scale * c_fresnel, atol=1e-9)
    np.testing.assert_allclose(y, scale * s_fresnel, atol=1e-9)


def test_compound_clothoid_matches_numerical_integration():
    length, r1, r2 = 180.0, 400.0, 1500.0
    alignment = HorizontalAlignment(0.0, 0.0, 1.0, 0.0, (Arc(10.0, r1, "left"), Clothoid(length, r1, r2, "left")))
    k0, k1 = -1 / r1, -1 / r2
    heading = lambda u: k0 * u + 0.5 * (k1 - k0) / length * u * u  # noqa: E731
    for u in (0.0, 7.3, 55.0, 123.4, length):
        x_ref = quad(lambda t: math.cos(heading(t)), 0.0, u, epsabs=1e-12, epsrel=1e-12)[0]
        y_ref = quad(lambda t: math.sin(heading(t)), 0.0, u, epsabs=1e-12, epsrel=1e-12)[0]
        x, y = to_local(alignment, *alignment.point_at(10.0 + u), 10.0)
        assert float(x) == pytest.approx(x_ref, abs=1e-9)
        assert float(y) == pytest.approx(y_ref, abs=1e-9)  # y to the right: negative for a left turn


@settings(max_examples=60, deadline=None)
@given(
    stations=st.lists(st.floats(1000.0, 2240.0), min_size=1, max_size=40),
    offsets=st.lists(st.floats(-20.0, 20.0), min_size=40, max_size=40),
)
def test_point_at_station_offset_round_trip(stations, offsets):
    s = np.array(stations)
    o = np.array(offsets[: len(stations)])
    east, north = ALIGNMENT.point_at(s, o)
    station, offset = ALIGNMENT.station_offset(east, north)
    np.testing.assert_allclose(station, s, atol=1e-6)
    np.testing.assert_allclose(offset, o, atol=1e-6)


def test_offset_sign_right_positive():
    north_line = HorizontalAlignment(100.0, 200.0, 0.0, 0.0, (Line(50.0),))
    station, offset = north_line.station_offset([103.0, 96.0], [210.0, 220.0])
    np.testing.assert_allclose(station, [10.0, 20.0])
    np.testing.assert_allclose(offset, [3.0, -4.0])
    east, north = north_line.point_at(5.0, 2.0)
    assert (float(east), float(north)) == pytest.approx((102.0, 205.0))


def test_points_beyond_the_ends_are_reported_as_nan():
    e0, n0 = ALIGNMENT.point_at(1000.0)
    az0 = START_AZIMUTH
    behind = (e0 - 5.0 * math.sin(az0), n0 - 5.0 * math.cos(az0))
    e1, n1 = ALIGNMENT.point_at(2240.0)
    az1 = float(ALIGNMENT.azimuth_at(2240.0))
    ahead = (e1 + 5.0 * math.sin(az1) + 1.0, n1 + 5.0 * math.cos(az1))
    station, offset = ALIGNMENT.station_offset([behind[0], ahead[0], np.nan, e0], [behind[1], ahead[1], 0.0, n0])
    assert np.isnan(station[:3]).all() and np.isnan(offset[:3]).all()
    assert station[3] == pytest.approx(1000.0, abs=1e-9) and offset[3] == pytest.approx(0.0, abs=1e-9)


def test_station_offset_of_20000_points():
    rng = np.random.default_rng(7)
    alignment = brief_alignment()  # fresh: the search index is built inside the timed call
    s = rng.uniform(1000.0, 2240.0, 20_000)
    o = rng.uniform(-20.0, 20.0, 20_000)
    east, north = alignment.point_at(s, o)
    station, offset = alignment.station_offset(east, north)
    assert np.max(np.abs(station - s)) < 1e-6 and np.max(np.abs(offset - o)) < 1e-6


def test_compiled_state_is_the_alignments_own():
    """The projection's compiled state (insrail.track._projection) is _state's, point by point."""
    from insrail.track._projection import knot_state
    from insrail.track.alignment import _GL_FRACTIONS, _GL_WEIGHTS

    knots = ALIGNMENT._knots
    stations = np.linspace(990.0, 2250.0, 2001)  # the end elements extrapolated too
    expected = np.column_stack(ALIGNMENT._state(stations))
    got = np.array([knot_state(knots.station_m, knots.east_m, knots.north_m, knots.azimuth_rad, knots.curvature,
                               knots.curvature_rate, _GL_FRACTIONS, _GL_WEIGHTS, s) for s in stations])
    np.testing.assert_allclose(got, expected, rtol=0.0, atol=1e-9)


def test_points_along_the_track_project_as_scattered_ones():
    """A survey's points, in order and 1 cm apart, start from their neighbour's station (warm
    start); across a gap of NaN, a jump and the ends they start afresh: the same stations as
    the same points in random order, each started from the nearest sample."""
    rng = np.random.default_rng(3)
    s = np.concatenate([np.arange(995.0, 1600.0, 0.01), np.arange(1900.0, 2245.0, 0.01)])  # a 300 m jump
    o = 0.7 + 0.003 * rng.standard_normal(len(s))
    east, north = ALIGNMENT.point_at(np.clip(s, 1000.0, 2240.0), o)
    east = east + np.where(s < 1000.0, s - 1000.0, 0.0) * math.sin(START_AZIMUTH)  # behind the start: no foot
    north = north + np.where(s < 1000.0, s - 1000.0, 0.0) * math.cos(START_AZIMUTH)
    east[20_000:20_500] = np.nan  # a gap
    station, offset = ALIGNMENT.station_offset(east, north)
    order = rng.permutation(len(s))
    scattered = np.full_like(station, np.nan), np.full_like(offset, np.nan)
    scattered[0][order], scattered[1][order] = ALIGNMENT.station_offset(east[order], north[order])
    np.testing.assert_array_equal(np.isnan(station), np.isnan(scattered[0]))
    assert np.isnan(station[s < 1000.0 - 1e-3]).all() and np.isnan(station[20_000:20_500]).all()
    inside = (s >= 1000.0) & (s <= 2240.0) & np.isfinite(east)
    assert np.isfinite(station[inside]).all()
    np.testing.assert_allclose(station[inside], s[inside], atol=1e-6)
    np.testing.assert_allclose(station, scattered[0], atol=1e-9)
    np.testing.assert_allclose(offset, scattered[1], atol=1e-9)


def test_evaluation_outside_the_alignment_raises():
    with pytest.raises(ValueError, match="outside the horizontal alignment"):
        ALIGNMENT.point_at([1500.0, 2250.0])
    with pytest.raises(ValueError, match="outside"):
        ALIGNMENT.azimuth_at(999.0)


def test_clothoid_must_continue_the_curvature():
    with pytest.raises(DesignError, match="element 3") as err:
        HorizontalAlignment(0.0, 0.0, 0.0, 0.0, (Line(10.0), Clothoid(50.0, math.inf, 2800.0, "right"),
                                                 Arc(100.0, 3000.0, "right")))
    assert (err.value.part, err.value.index) == ("horizontal", 2)
    with pytest.raises(DesignError, match="turn"):
        HorizontalAlignment(0.0, 0.0, 0.0, 0.0, (Clothoid(50.0, math.inf, 800.0, "right"), Arc(10.0, 800.0, "left")))
    # lines and arcs may meet without a transition (old lines)
    HorizontalAlignment(0.0, 0.0, 0.0, 0.0, (Line(10.0), Arc(10.0, 300.0, "left"), Line(5.0)))


@pytest.mark.parametrize(
    "make, message",
    [
        (lambda: Line(-1.0), "length"),
        (lambda: Arc(10.0, 0.0, "right"), "radius"),
        (lambda: Arc(10.0, 100.0, "up"), "turn"),
        (lambda: Clothoid(10.0, math.inf, math.inf, "right"), "Line"),
        (lambda: Clothoid(10.0, 300.0, 300.0, "right"), "Arc"),
        (lambda: HorizontalAlignment(0.0, 0.0, 0.0, 0.0, ()), "at least one element"),
    ],
)
def test_bad_elements_are_rejected(make, message):
    with pytest.raises(ValueError, match=message):
        make()
