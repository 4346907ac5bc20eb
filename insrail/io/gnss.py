"""GNSS solutions in the KF-GINS text layout (7 columns, or 13 with velocities).

``t lat[deg] lon[deg] h[m] sigN sigE sigD [m] (vN vE vD [m/s] sigvN sigvE sigvD [m/s])``,
t in GPS seconds of week, h ellipsoidal, positions of the antenna phase centre.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from insrail.io.textparse import (
    NumericTable,
    check_table_time,
    find_gaps,
    header_gps_week,
    read_numeric_table,
    write_numeric_table,
)
from insrail.io.types import GnssSolution

KFGINS_GNSS_COLUMNS = ("t", "lat", "lon", "h", "sigN", "sigE", "sigD",
                       "vN", "vE", "vD", "sigvN", "sigvE", "sigvD")


def check_geodetic(table: NumericTable, lat_deg: np.ndarray, lon_deg: np.ndarray) -> None:
    """Latitudes within +-90 deg and longitudes within -180..360 deg, else InputError."""
    bad_lat = np.flatnonzero(np.abs(lat_deg) > 90.0)
    if bad_lat.size:
        table.fail(bad_lat[0], "latitude {lat_deg} deg: expected -90 to 90 degrees", fields={"lat_deg": lat_deg[bad_lat[0]]})
    bad_lon = np.flatnonzero((lon_deg < -180.0) | (lon_deg > 360.0))
    if bad_lon.size:
        table.fail(bad_lon[0], "longitude {lon_deg} deg: expected -180 to 360 degrees", fields={"lon_deg": lon_deg[bad_lon[0]]})


def check_sigmas(table: NumericTable, sigmas: np.ndarray, what: str) -> None:
    """Standard deviations must not be negative."""
    negative = np.flatnonzero((sigmas < 0).any(axis=1))
    if negative.size:
        table.fail(negative[0], "negative {what} standard deviation {sigma}", fields={"what": what, "sigma": sigmas[negative[0]].min()})


def read_gnss_kfgins(path: str | Path) -> GnssSolution:
    """KF-GINS GNSS text (7 or 13 columns); quality, satellites and ratio are unknown (0, 0, NaN)."""
    table = read_numeric_table(path, columns=(7, 13), column_names=KFGINS_GNSS_COLUMNS)
    values = table.values
    time_s = check_table_time(table)
    check_geodetic(table, values[:, 1], values[:, 2])
    check_sigmas(table, values[:, 4:7], "position")
    with_velocity = values.shape[1] == 13
    if with_velocity:
        check_sigmas(table, values[:, 10:13], "velocity")
    n = len(values)
    return GnssSolution(
        time_s=time_s.copy(),
        lat_rad=np.radians(values[:, 1]),
        lon_rad=np.radians(values[:, 2]),
        height_m=values[:, 3].copy(),
        sigma_ned_m=values[:, 4:7].copy(),
        quality=np.zeros(n, dtype=np.int64),
        num_sats=np.zeros(n, dtype=np.int64),
        ratio=np.full(n, np.nan),
        vel_ned_mps=values[:, 7:10].copy() if with_velocity else None,
        sigma_vel_ned_mps=values[:, 10:13].copy() if with_velocity else None,
        gps_week=header_gps_week(table.path, table.comments),
        gaps=find_gaps(time_s),
        source=table.path,
    )


def write_gnss_kfgins(path: str | Path, gnss: GnssSolution) -> None:
    """Write KF-GINS GNSS text: 13 columns when velocities are present, else 7, atomically.

    Precision: time 1 ns, lat/lon 1e-12 deg, heights, sigmas and velocities 1e-6.
    """
    columns = [gnss.time_s, np.degrees(gnss.lat_rad), np.degrees(gnss.lon_rad), gnss.height_m,
               gnss.sigma_ned_m]
    formats = ["%.9f", "%.12f", "%.12f"] + ["%.6f"] * 4
    names = "t[s of GPS week] lat[deg] lon[deg] h[m, ellipsoidal] sigN sigE sigD [m]"
    if gnss.vel_ned_mps is not None:
        sigma_vel = (gnss.sigma_vel_ned_mps if gnss.sigma_vel_ned_mps is not None
                     else np.zeros_like(gnss.vel_ned_mps))
        columns += [gnss.vel_ned_mps, sigma_vel]
        formats += ["%.6f"] * 6
        names += " vN vE vD [m/s] sigvN sigvE sigvD [m/s]"
    header = ["format: kfgins-gnss"]
    if gnss.gps_week is not None:
        header.append(f"gps_week = {gnss.gps_week}")
    header += [f"columns: {names}", "antenna phase centre, WGS84/CGCS2000 geodetic, NED"]
    write_numeric_table(path, columns, formats, header)
