"""Raw total-station observations of free stations, and the CPIII coordinates they resect on.

``total-station-polar``: one pointing per line, ``setup target t Hz V D``:

* setup  : the set-up's name (every line of one set-up carries it; a set-up is one instrument
           position and one circle orientation, so its lines belong together wherever they stand)
* target : a CPIII point id (a backsight the station is resected on) or ``prism`` (the trolley's
           prism: a fix of the trolley at time t)
* t      : time of the pointing [s of GPS week]; needed for the prism, informative for CPIII points
* Hz     : horizontal direction, clockwise from the circle's zero [gon, or deg with the reader
           option ``angle_unit = "deg"``]
* V      : zenith angle (0 up, 100 gon horizontal) [gon or deg]
* D      : slope distance, reduced for prism constant and atmosphere [m]

``cpiii-enh``: ``id E N H``, the CPIII points in the engineering frame (easting, northing [m],
normal height [m]), each id once.

Both are small text tables (comma or whitespace separated, ``#`` comments); errors name the file,
the line and what was expected. The resection and the prism positions it gives are
:mod:`insrail.geodesy.free_station` (driven by :mod:`insrail.project.total_station`).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from insrail.io.atomic import atomic_write
from insrail.io.control import _check_ids
from insrail.io.textparse import read_token_table
from insrail.io.types import ControlPoints, TotalStationObservations

POLAR_COLUMNS = ("setup", "target", "t", "Hz", "V", "D")
CPIII_COLUMNS = ("id", "E", "N", "H")
PRISM_TARGET = "prism"
_ANGLE_UNITS = {"gon": np.pi / 200.0, "deg": np.pi / 180.0}


def read_total_station_polar(path: str | Path, angle_unit: str = "gon") -> TotalStationObservations:
    """``setup target t Hz V D`` -> TotalStationObservations (angles in radians)."""
    if angle_unit not in _ANGLE_UNITS:
        raise ValueError(f"angle_unit: expected one of {', '.join(_ANGLE_UNITS)}, found {angle_unit!r}")
    table = read_token_table(path, min_columns=6, max_columns=6, column_names=POLAR_COLUMNS)
    unit = _ANGLE_UNITS[angle_unit]
    time_s, hz, zenith, slope = (table.numbers(k) for k in (2, 3, 4, 5))
    full_circle = 2 * np.pi / unit
    for name, values, low, high in (("Hz", hz, 0.0, full_circle), ("V", zenith, 0.0, full_circle / 2)):
        bad = np.flatnonzero((values < low) | (values >= high) if name == "Hz" else (values <= low) | (values >= high))
        if bad.size:
            table.fail(bad[0], "{name} = {value} {angle_unit} is outside {low:g}..{high:g} {angle_unit}", fields={"name": name, "value": values[bad[0]], "angle_unit": angle_unit, "low": low, "high": high})
    bad = np.flatnonzero(~(slope > 0))
    if bad.size:
        table.fail(bad[0], "slope distance D = {slope} m: expected a positive distance", fields={"slope": slope[bad[0]]})
    setup, target = table.texts(0), table.texts(1)
    prism = np.flatnonzero(target == PRISM_TARGET)
    if prism.size and np.any(np.diff(time_s[prism]) <= 0):
        row = prism[1:][np.diff(time_s[prism]) <= 0][0]
        table.fail(row, "prism time {time_s} s is not after the previous prism pointing's: times must increase", fields={"time_s": time_s[row]})
    return TotalStationObservations(setup=setup, target=target, time_s=time_s, hz_rad=hz * unit,
                                    zenith_rad=zenith * unit, slope_m=slope,
                                    line=np.array([table.line_of_row(k) for k in range(len(setup))]),
                                    source=table.path)


def write_total_station_polar(path: str | Path, observations: TotalStationObservations) -> None:
    """Write ``setup target t Hz V D`` (angles 1e-6 gon, distances 0.01 mm), atomically."""
    _check_ids(list(observations.setup) + list(observations.target), allow_empty=False)
    gon = 200.0 / np.pi
    with atomic_write(path) as handle:
        handle.write("# format: total-station-polar\n# columns: setup target t[s of GPS week] Hz[gon] V[gon, zenith] "
                     "D[m, slope]; target 'prism' is the trolley's prism\n")
        for row in zip(observations.setup, observations.target, observations.time_s, gon * observations.hz_rad,
                       gon * observations.zenith_rad, observations.slope_m):
            handle.write("{} {} {:.6f} {:.7f} {:.7f} {:.5f}\n".format(*row))


def read_cpiii_enh(path: str | Path) -> ControlPoints:
    """``id E N H`` -> ControlPoints; the same id twice is an error."""
    table = read_token_table(path, min_columns=4, max_columns=4, column_names=CPIII_COLUMNS)
    ids = table.texts(0)
    seen: dict[str, int] = {}
    for row, point in enumerate(ids):
        if point in seen:
            table.fail(row, "point {point} is given twice (first on line {line_of_row})", fields={"point": point, "line_of_row": table.line_of_row(seen[point])})
        seen[point] = row
    return ControlPoints(point_id=ids, east_m=table.numbers(1), north_m=table.numbers(2), height_m=table.numbers(3),
                         source=table.path)


def write_cpiii_enh(path: str | Path, points: ControlPoints) -> None:
    """Write ``id E N H`` (1e-5 m), atomically."""
    _check_ids(points.point_id, allow_empty=False)
    with atomic_write(path) as handle:
        handle.write("# format: cpiii-enh\n# columns: id E[m] N[m] H[m, normal height], engineering frame\n")
        for point, e, n, h in zip(points.point_id, points.east_m, points.north_m, points.height_m):
            handle.write(f"{point} {e:.5f} {n:.5f} {h:.5f}\n")
