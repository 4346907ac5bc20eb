"""Build the scenario's design alignment from its plain-data description."""

from __future__ import annotations

import math

from insrail.sim.scenario import DesignSpec
from insrail.track.alignment import Arc, Clothoid, DesignAlignment, HorizontalAlignment, Line
from insrail.track.profile import PVI, CantTable, VerticalProfile


def design_alignment(spec: DesignSpec) -> DesignAlignment:
    elements = []
    for item in spec.horizontal:
        kind, length = item[0], float(item[1])
        if kind == "line":
            elements.append(Line(length))
        elif kind == "clothoid":
            elements.append(Clothoid(length, float(item[2]), float(item[3]), item[4]))
        elif kind == "arc":
            elements.append(Arc(length, float(item[2]), item[3]))
        else:
            raise ValueError(f"unknown horizontal element {kind!r} in the scenario design")
    horizontal = HorizontalAlignment(
        start_east_m=spec.start_east_m,
        start_north_m=spec.start_north_m,
        start_azimuth_rad=math.radians(spec.start_azimuth_deg),
        start_station_m=spec.start_station_m,
        elements=tuple(elements),
    )
    pvis = tuple(
        PVI(station, elevation, curve="circular", curve_radius_m=radius) if radius > 0 else PVI(station, elevation)
        for station, elevation, radius in spec.pvis
    )
    stations, cant = zip(*spec.cant)
    return DesignAlignment(
        horizontal=horizontal,
        vertical=VerticalProfile(pvis),
        cant=CantTable(stations, cant),
        name=spec.name,
    )
