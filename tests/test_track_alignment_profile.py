"""Vertical profile, cant table and station equations."""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from insrail.track.errors import DesignError
from insrail.track.profile import PVI, CantTable, VerticalProfile
from insrail.track.stationing import StationEquation, StationEquations

G1, G2, G3 = 0.008, -0.004, 0.012
PROFILE = VerticalProfile(
    (
        PVI(0.0, 100.0),
        PVI(400.0, 100.0 + 400 * G1, "parabolic", curve_length_m=120.0),
        PVI(700.0, 100.0 + 400 * G1 + 300 * G2, "circular", curve_radius_m=20000.0),
        PVI(950.0, 100.0 + 400 * G1 + 300 * G2 + 250 * G3),
    )
)


def test_grade_lines():
    np.testing.assert_allclose(PROFILE.elevation_at([0.0, 100.0, 330.0]), [100.0, 100.8, 102.64], atol=1e-12)
    np.testing.assert_allclose(PROFILE.grade_at([10.0, 500.0, 900.0]), [G1, G2, G3], atol=1e-15)
    np.testing.assert_array_equal(PROFILE.vertical_curvature_at([10.0, 500.0, 900.0]), 0.0)


def test_parabolic_curve_closed_form():
    length, pvi_s, pvi_z = 120.0, 400.0, 103.2
    s = np.linspace(340.0, 460.0, 25)
    x = s - 340.0
    expected = pvi_z + G1 * (s - pvi_s) + (G2 - G1) * x**2 / (2 * length)
    np.testing.assert_allclose(PROFILE.elevation_at(s), expected, atol=1e-12)
    # the classic middle ordinate: Δg L / 8 below the PVI
    assert float(PROFILE.elevation_at(pvi_s)) == pytest.approx(pvi_z + (G2 - G1) * length / 8, abs=1e-12)
    np.testing.assert_allclose(PROFILE.grade_at(s), G1 + (G2 - G1) * x / length, atol=1e-15)
    g = PROFILE.grade_at(s)
    np.testing.assert_allclose(PROFILE.vertical_curvature_at(s), (G2 - G1) / length / (1 + g * g) ** 1.5)
    assert PROFILE.curve_radii_m[1] == pytest.approx(length / abs(G2 - G1))


def test_circular_curve_closed_form():
    radius, pvi_s, pvi_z = 20000.0, 700.0, 100.0 + 400 * G1 + 300 * G2
    a1, a2 = math.atan(G2), math.atan(G3)
    tangent = radius * math.tan((a2 - a1) / 2)
    begin = (pvi_s - tangent * math.cos(a1), pvi_z - tangent * math.sin(a1))
    end = (pvi_s + tangent * math.cos(a2), pvi_z + tangent * math.sin(a2))
    # sag: the centre is above, on the normal of both tangents at distance R
    centre = (begin[0] - radius * math.sin(a1), begin[1] + radius * math.cos(a1))
    assert math.hypot(end[0] - centre[0], end[1] - centre[1]) == pytest.approx(radius, abs=1e-8)
    s = np.linspace(begin[0], end[0], 21)
    expected = centre[1] - np.sqrt(radius**2 - (s - centre[0]) ** 2)
    np.testing.assert_allclose(PROFILE.elevation_at(s), expected, atol=1e-10)
    np.testing.assert_allclose(PROFILE.vertical_curvature_at(s[1:-1]), 1 / radius)
    assert PROFILE.curve_lengths_m[2] == pytest.approx(end[0] - begin[0], abs=1e-9)
    # grades continuous at both tangent points
    eps = 1e-6
    np.testing.assert_allclose(PROFILE.grade_at([begin[0] - eps, begin[0] + eps]), G2, atol=1e-9)
    np.testing.assert_allclose(PROFILE.grade_at([end[0] - eps, end[0] + eps]), G3, atol=1e-9)


def test_grade_is_continuous_everywhere():
    s = np.linspace(0.0, 950.0, 95001)
    g = PROFILE.grade_at(s)
    assert np.max(np.abs(np.diff(g))) < 0.01 * 1.1 / 1000  # |dg/ds| <= max curvature ~ 1e-4 per m


def test_crest_circle_and_radius_or_length_definitions_agree():
    crest_by_radius = VerticalProfile((PVI(0.0, 0.0), PVI(500.0, 10.0, "circular", curve_radius_m=15000.0),
                                       PVI(1000.0, 5.0)))
    length = float(crest_by_radius.curve_lengths_m[1])
    crest_by_length = VerticalProfile((PVI(0.0, 0.0), PVI(500.0, 10.0, "circular", curve_length_m=length),
                                       PVI(1000.0, 5.0)))
    s = np.linspace(0.0, 1000.0, 101)
    np.testing.assert_allclose(crest_by_length.elevation_at(s), crest_by_radius.elevation_at(s), atol=1e-9)
    np.testing.assert_allclose(crest_by_radius.vertical_curvature_at(500.0), -1 / 15000.0)
    para_by_radius = VerticalProfile((PVI(0.0, 0.0), PVI(500.0, 10.0, "parabolic", curve_radius_m=15000.0),
                                      PVI(1000.0, 5.0)))
    assert para_by_radius.curve_lengths_m[1] == pytest.approx(15000.0 * 0.03)


@pytest.mark.parametrize(
    "pvis, index, message",
    [
        ((PVI(0.0, 0.0), PVI(0.0, 1.0)), 1, "PVI 2 .* is not after PVI 1"),
        ((PVI(0.0, 0.0, "parabolic", curve_length_m=10.0), PVI(100.0, 1.0)), 0, "end of the profile"),
        ((PVI(0.0, 0.0), PVI(100.0, 2.0, "parabolic", curve_length_m=100.0),
          PVI(150.0, 0.0, "parabolic", curve_length_m=40.0), PVI(300.0, 1.0)), 2, "overlap by 20.0000 m"),
        ((PVI(0.0, 0.0), PVI(100.0, 2.0, "parabolic", curve_length_m=300.0), PVI(400.0, 1.0)), 1,
         "begins at station -50.0000 m"),
        ((PVI(0.0, 0.0), PVI(100.0, 1.0, "parabolic", curve_length_m=100.0), PVI(130.0, 0.0)), 1,
         "ends at station 150.0000 m, beyond PVI 3"),
        ((PVI(0.0, 0.0), PVI(100.0, 1.0, "circular", curve_length_m=10.0), PVI(200.0, 2.0)), 1, "grades .* equal"),
    ],
)
def test_profile_validation(pvis, index, message):
    with pytest.raises(DesignError, match=message) as err:
        VerticalProfile(pvis)
    assert err.value.index == index and err.value.part == "profile"


def test_pvi_validation_and_range():
    with pytest.raises(ValueError, match="exactly one"):
        PVI(0.0, 0.0, "parabolic", curve_length_m=10.0, curve_radius_m=1000.0)
    with pytest.raises(ValueError, match="curve must be one of"):
        PVI(0.0, 0.0, "cubic")
    with pytest.raises(ValueError, match="outside the vertical profile"):
        PROFILE.elevation_at(960.0)


def test_cant_table():
    cant = CantTable([0.0, 100.0, 160.0, 400.0, 460.0, 600.0, 650.0], [0.0, 0.0, 0.15, 0.15, 0.0, 0.0, -0.06])
    np.testing.assert_allclose(cant.cant_at([50.0, 130.0, 300.0, 445.0, 625.0]), [0.0, 0.075, 0.15, 0.0375, -0.03])
    assert cant == CantTable(list(cant.stations_m), list(cant.cant_m))
    assert cant != CantTable([0.0, 650.0], [0.0, 0.0])
    with pytest.raises(ValueError, match="outside the cant table"):
        cant.cant_at(700.0)
    with pytest.raises(DesignError, match="cant row 3 .* is not after row 2") as err:
        CantTable([0.0, 10.0, 10.0], [0.0, 0.1, 0.1])
    assert err.value.index == 2
    with pytest.raises(DesignError, match="2 stations but 3"):
        CantTable([0.0, 10.0], [0.0, 0.1, 0.2])


EQUATIONS = StationEquations(
    (StationEquation(1500.0, 1520.0), StationEquation(2000.0, 1990.0)), prefix="DK"
)  # a 20 m short chain, then a 10 m long chain


def test_station_equations_mapping_and_labels():
    np.testing.assert_array_equal(EQUATIONS.internal_stations_m, [1500.0, 1980.0])
    internal = np.array([1000.0, 1499.9, 1500.0, 1979.0, 1980.0, 2100.0])
    np.testing.assert_allclose(EQUATIONS.displayed_from_internal(internal), [1000.0, 1499.9, 1520.0, 1999.0, 1990.0,
                                                                              2110.0])
    np.testing.assert_array_equal(EQUATIONS.zone_at(internal), [0, 0, 1, 1, 2, 2])
    assert EQUATIONS.label(1695.917) == "DK1+715.917"
    assert EQUATIONS.label([0.0, 999.9996]) == ["DK0+000.000", "DK1+000.000"]
    assert StationEquations(prefix="K").label(-12.5) == "K-0+012.500"
    assert StationEquations().label(123456.7891, decimals=2) == "K123+456.79"
    assert EQUATIONS.parse_label("DK1+715.917") == pytest.approx(1695.917)


def test_station_equations_short_and_long_chains():
    with pytest.raises(ValueError, match="short chain"):
        EQUATIONS.internal_from_displayed(1510.0)
    with pytest.raises(ValueError, match="exists twice"):
        EQUATIONS.internal_from_displayed(1995.0)
    assert float(EQUATIONS.internal_from_displayed(1995.0, zone=1)) == pytest.approx(1975.0)
    assert float(EQUATIONS.internal_from_displayed(1995.0, zone=2)) == pytest.approx(1985.0)
    with pytest.raises(ValueError, match="does not exist in the zone"):
        EQUATIONS.internal_from_displayed(1000.0, zone=2)
    with pytest.raises(ValueError, match="prefix 'K'"):
        EQUATIONS.parse_label("K1+000")
    with pytest.raises(DesignError, match="does not come after"):
        StationEquations((StationEquation(100.0, 200.0), StationEquation(150.0, 160.0)))


def test_station_labels_read_at_once_as_one_by_one():
    labels = ["DK1+000.000", "DK1+715.917", "DK2+110.000", "DK1+995.5"]
    zones = [0, 1, 2, 1]
    expected = [EQUATIONS.parse_label(label, zone=zone) for label, zone in zip(labels, zones)]
    assert EQUATIONS.parse_labels(labels, zone=zones).tolist() == expected
    assert EQUATIONS.parse_labels(labels[:3]).tolist() == expected[:3]
    with pytest.raises(ValueError, match="exists twice"):
        EQUATIONS.parse_labels(labels)
    with pytest.raises(ValueError, match="prefix 'K'"):
        EQUATIONS.parse_labels(["DK1+000", "K1+000"])


@given(st.floats(0.0, 3000.0))
def test_station_equations_round_trip(internal):
    displayed = EQUATIONS.displayed_from_internal(internal)
    zone = EQUATIONS.zone_at(internal)
    assert float(EQUATIONS.internal_from_displayed(displayed, zone=zone)) == pytest.approx(internal, abs=1e-9)
    label = EQUATIONS.label(internal, decimals=6)
    assert EQUATIONS.parse_label(label, zone=int(zone)) == pytest.approx(internal, abs=1e-6)
