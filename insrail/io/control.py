"""Control data: total-station prism fixes on CPIII points, and GNSS-levelling benchmarks.

Prism: ``t E N H sigma [id]``: time [s of GPS week], prism position in the
engineering frame (easting, northing, normal height) [m], standard deviation of
each coordinate [m], optional CPIII point id (text) as a last column.
Benchmarks: ``id lat[deg] lon[deg] h[m] H[m]``: ellipsoidal height h and normal
height H at the same point.
These files are small (tens to thousands of lines), so they are parsed field by field.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Iterable

import numpy as np

from insrail.io.atomic import atomic_write
from insrail.io.textparse import check_time_order, read_token_table
from insrail.io.types import Benchmarks, PrismObservations

PRISM_COLUMNS = ("t", "E", "N", "H", "sigma", "id")
BENCHMARK_COLUMNS = ("id", "lat", "lon", "h", "H")
_SAFE_ID = re.compile(r"^[^\s,#%]+$")


def read_prism_enu(path: str | Path) -> PrismObservations:
    """``t E N H sigma [id]`` -> PrismObservations (point_id "" where a line has none)."""
    table = read_token_table(path, min_columns=5, max_columns=6, column_names=PRISM_COLUMNS)
    time_s = table.numbers(0)
    check_time_order(time_s, table.fail, where=table.line_of_row)
    sigma = table.numbers(4)
    negative = np.flatnonzero(sigma < 0)
    if negative.size:
        table.fail(negative[0], "negative standard deviation {sigma}", fields={"sigma": sigma[negative[0]]})
    return PrismObservations(time_s=time_s, east_m=table.numbers(1), north_m=table.numbers(2),
                             height_m=table.numbers(3), sigma_m=sigma, point_id=table.texts(5),
                             source=table.path)


def read_benchmarks(path: str | Path) -> Benchmarks:
    """``id lat[deg] lon[deg] h[m] H[m]`` (comma or whitespace separated) -> Benchmarks."""
    table = read_token_table(path, min_columns=5, max_columns=5, column_names=BENCHMARK_COLUMNS)
    ids = table.unique_ids("benchmark")
    lat_deg, lon_deg = table.numbers(1), table.numbers(2)
    for values, limit, name in ((lat_deg, 90.0, "latitude"), (lon_deg, 360.0, "longitude")):
        bad = np.flatnonzero(np.abs(values) > limit)
        if bad.size:
            table.fail(bad[0], "{name} {value} deg out of range", fields={"name": name, "value": values[bad[0]]})
    return Benchmarks(point_id=ids, lat_rad=np.radians(lat_deg), lon_rad=np.radians(lon_deg),
                      h_m=table.numbers(3), normal_height_m=table.numbers(4), source=table.path)


def _check_ids(ids: Iterable[str], allow_empty: bool) -> None:
    for point in ids:
        if not (allow_empty and point == "") and not _SAFE_ID.match(point):
            raise ValueError(f"point id {point!r} cannot be written: ids must be non-empty and hold no "
                             "whitespace, commas, '#' or '%'")


def write_prism_enu(path: str | Path, prism: PrismObservations) -> None:
    """Write ``t E N H sigma [id]`` (time 1 ns, coordinates 1e-6 m), atomically."""
    ids = list(prism.point_id) if len(prism.point_id) else [""] * len(prism)
    _check_ids(ids, allow_empty=True)
    with atomic_write(path) as handle:
        handle.write("# format: prism-enu\n# columns: t[s of GPS week] E[m] N[m] H[m, normal height] "
                     "sigma[m] point_id, engineering frame\n")
        for t, e, n, h, s, point in zip(prism.time_s, prism.east_m, prism.north_m, prism.height_m,
                                        prism.sigma_m, ids):
            handle.write(f"{t:.9f} {e:.6f} {n:.6f} {h:.6f} {s:.6f} {point}".rstrip() + "\n")


def write_benchmarks(path: str | Path, benchmarks: Benchmarks) -> None:
    """Write ``id lat lon h H`` (lat/lon 1e-11 deg, heights 1e-6 m), atomically."""
    _check_ids(benchmarks.point_id, allow_empty=False)
    with atomic_write(path) as handle:
        handle.write("# format: benchmarks\n# columns: id lat[deg] lon[deg] h[m, ellipsoidal] "
                     "H[m, normal height]\n")
        for point, lat, lon, h, big_h in zip(benchmarks.point_id, np.degrees(benchmarks.lat_rad),
                                             np.degrees(benchmarks.lon_rad), benchmarks.h_m,
                                             benchmarks.normal_height_m):
            handle.write(f"{point} {lat:.11f} {lon:.11f} {h:.6f} {big_h:.6f}\n")
