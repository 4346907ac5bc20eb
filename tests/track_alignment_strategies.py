"""Hypothesis strategies for random, valid design alignments (shared by the track tests)."""

import math

from hypothesis import strategies as st

from insrail.track.alignment import Arc, Clothoid, DesignAlignment, HorizontalAlignment, Line
from insrail.track.profile import PVI, CantTable, VerticalProfile
from insrail.track.stationing import StationEquations

lengths = st.floats(5.0, 800.0, allow_nan=False)
radii = st.floats(150.0, 12000.0, allow_nan=False)


@st.composite
def curve_groups(draw):
    """Tangent, then an arc with or without clothoid transitions."""
    turn = draw(st.sampled_from(["left", "right"]))
    radius = draw(radii)
    arc_length = draw(st.floats(5.0, min(800.0, 2.5 * radius)))
    elements = [Line(draw(lengths))]
    if draw(st.booleans()):
        elements += [Clothoid(draw(st.floats(10.0, 200.0)), math.inf, radius, turn), Arc(arc_length, radius, turn),
                     Clothoid(draw(st.floats(10.0, 200.0)), radius, math.inf, turn)]
    else:
        elements.append(Arc(arc_length, radius, turn))
    return elements


@st.composite
def design_alignments(draw):
    groups = draw(st.lists(curve_groups(), min_size=1, max_size=4))
    elements = tuple(e for group in groups for e in group) + (Line(draw(lengths)),)
    horizontal = HorizontalAlignment(
        draw(st.floats(-1e6, 1e6)), draw(st.floats(0.0, 5e6)), draw(st.floats(0.0, 2 * math.pi, exclude_max=True)),
        draw(st.floats(-1000.0, 1e5)), elements,
    )
    start, end = horizontal.start_station_m, horizontal.end_station_m
    middle = 0.5 * (start + end)
    grade_in, grade_out = draw(st.floats(-0.03, 0.03)), draw(st.floats(-0.03, 0.03))
    kind = draw(st.sampled_from(["none", "parabolic", "circular"]))
    curve = {} if kind == "none" else {"curve_radius_m": draw(st.floats(3000.0, 30000.0))}
    if kind != "none" and abs(grade_out - grade_in) * curve["curve_radius_m"] > 0.9 * (end - start):
        kind, curve = "none", {}
    z = draw(st.floats(-50.0, 3000.0))
    vertical = VerticalProfile((PVI(start, z - grade_in * (middle - start)), PVI(middle, z, kind, **curve),
                                PVI(end, z + grade_out * (end - middle))))
    cant_mm = draw(st.integers(-180, 180))
    cant = CantTable([start, middle, end], [0.0, cant_mm / 1000.0, 0.0])
    return DesignAlignment(horizontal, vertical, cant, StationEquations(prefix=draw(st.sampled_from(["K", "DK"]))),
                           draw(st.text("abcXYZ _-", min_size=1, max_size=8)).strip() or "a")
