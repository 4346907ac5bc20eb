"""The same design stationed the other way: what a railway's drawings of the opposite track
direction, or of the line chained from its other end, give for one piece of track.

Station s of the design becomes s' = start + end - s (the same station range, run from the
other end): elements in reverse order with their turns flipped (a clothoid's radii swapped),
the start at the old end with the azimuth turned by 180 degrees, PVIs mirrored, cant negated
(the stationing's left rail is the old right one). Station equations are refused: the displayed
chainage of the opposite direction is a railway's own table, not something to derive.
"""

from __future__ import annotations

import math

import numpy as np

from insrail.track.alignment import (
    Arc,
    Clothoid,
    DesignAlignment,
    HorizontalAlignment,
    Line,
)
from insrail.track.errors import DesignError
from insrail.track.profile import PVI, CantTable, VerticalProfile

_OTHER_TURN = {"left": "right", "right": "left"}


def _reversed_element(element):
    if isinstance(element, Line):
        return element
    if isinstance(element, Arc):
        return Arc(element.length_m, element.radius_m, _OTHER_TURN[element.turn])
    return Clothoid(element.length_m, element.radius_end_m, element.radius_start_m, _OTHER_TURN[element.turn])


def reversed_design(design: DesignAlignment, name: str | None = None) -> DesignAlignment:
    """``design`` stationed from its other end (see the module docstring)."""
    if design.station_equations.equations:
        raise DesignError("station_equations", None,
                          "a design with station equations cannot be reversed: the other direction's chainage "
                          "(its own station equations) must come from the railway's drawings")
    h = design.horizontal
    first, last = h.start_station_m, h.end_station_m

    def mirrored(station):
        return first + last - np.asarray(station, dtype=float)

    east, north = h.point_at(last)
    horizontal = HorizontalAlignment(
        start_east_m=float(east), start_north_m=float(north),
        start_azimuth_rad=float((h.azimuth_at(last) + math.pi) % (2 * math.pi)),
        start_station_m=first, elements=tuple(_reversed_element(e) for e in reversed(h.elements)))
    vertical = None
    if design.vertical is not None:
        vertical = VerticalProfile(tuple(
            PVI(float(mirrored(p.station_m)), p.elevation_m, p.curve, p.curve_length_m, p.curve_radius_m)
            for p in reversed(design.vertical.pvis)))
    cant = None
    if design.cant is not None:
        cant = CantTable(mirrored(design.cant.stations_m)[::-1], -design.cant.cant_m[::-1])
    return DesignAlignment(horizontal, vertical, cant, design.station_equations,
                           name or f"{design.name} (reversed)")
