"""RTKLIB solution files (.pos), latitude/longitude/height form.

Columns (RTKLIB ``outsolheads``)::

    time  lat lon height  Q ns  sdn sde sdu sdne sdeu sdun  age ratio
          [vn ve vu  sdvn sdve sdvu sdvne sdveu sdvun]

* time is ``yyyy/mm/dd hh:mm:ss.sss`` or ``week tow``, on the scale the ``%``
  column header names: GPST, UTC or JST (UTC and JST are converted to GPST with the
  leap-second table).
* lat/lon in degrees, or ``d m s`` triples when the header says ``latitude(d'")``.
* velocities are north-east-UP; GnssSolution is NED, so vD = -vu. The up sigma
  sdu is kept as the down sigma. Cross terms (sdne...) and age are not kept.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from insrail import __version__
from insrail.io.errors import InputError
from insrail.io.gnss import check_geodetic, check_sigmas
from insrail.io.textparse import (
    COMMENT_MARKERS,
    check_text_file,
    check_time_order,
    find_gaps,
    read_numeric_table,
    strip_comment,
    write_numeric_table,
)
from insrail.io.timescale import (
    SECONDS_PER_WEEK,
    calendar_to_week_seconds,
    normalise_week,
    seconds_to_week_tow,
    utc_to_gpst,
    week_tow_to_week_seconds,
)
from insrail.io.types import GnssSolution

JST_MINUS_UTC_S = 9 * 3600
_SOLUTION_COLUMNS = ("Q", "ns", "sdn", "sde", "sdu", "sdne", "sdeu", "sdun", "age", "ratio")
_VELOCITY_COLUMNS = ("vn", "ve", "vu", "sdvn", "sdve", "sdvu", "sdvne", "sdveu", "sdvun")
_CALENDAR_COLUMNS = ("year", "month", "day", "hour", "minute", "second")
_WEEK_COLUMNS = ("week", "tow")
_MAX_QUALITY = 6

POS_HEADER_NOTE = ("(lat/lon/height=WGS84/ellipsoidal,Q=1:fix,2:float,3:sbas,4:dgps,5:single,6:ppp,"
                   "ns=# of satellites)")
POS_COLUMN_HEADER = ("  GPST                      latitude(deg)   longitude(deg)  height(m)   Q  ns"
                     "   sdn(m)   sde(m)   sdu(m)  sdne(m)  sdeu(m)  sdun(m) age(s)  ratio")
POS_VELOCITY_HEADER = ("    vn(m/s)    ve(m/s)    vu(m/s)     sdvn     sdve     sdvu    sdvne"
                       "    sdveu    sdvun")


def _column_header(path: Path, text: str) -> tuple[str, bool]:
    """(time system, DMS?) from the ``%`` column header line; (GPST, False) without one."""
    for raw in text.splitlines():
        line = raw.strip()
        if line[:1] not in COMMENT_MARKERS:
            if strip_comment(line):
                break
            continue
        fields = line[1:].split()
        if fields and fields[0] in ("GPST", "UTC", "JST"):
            if "latitude(deg)" in fields or "latitude(d'\")" in fields:
                return fields[0], "latitude(d'\")" in fields
            raise InputError(path, None, "solution form {form!r} is not supported: "
                             "expected latitude/longitude/height (RTKLIB out-solformat=llh)", fields={"form": ' '.join(fields[1:4])})
    return "GPST", False


def _first_data_fields(path: Path, text: str) -> list[str]:
    for raw in text.splitlines():
        content = strip_comment(raw)
        if content:
            return content.split()
    raise InputError(path, None, "empty file: no solution epochs (a survey without any GNSS, in a tunnel, leaves "
                     "[files.gnss] out of its survey.toml)")


def _dms_to_degrees(fields: np.ndarray) -> np.ndarray:
    """(n, 3) degrees, minutes, seconds -> degrees; the sign sits on the degrees (also "-0")."""
    sign = np.where(np.signbit(fields[:, 0]), -1.0, 1.0)
    return sign * (np.abs(fields[:, 0]) + fields[:, 1] / 60.0 + fields[:, 2] / 3600.0)


def read_rtklib_pos(path: str | Path) -> GnssSolution:
    """RTKLIB .pos (LLH) with or without velocity columns; see the module docstring."""
    path = Path(path)
    if not path.exists():
        raise InputError(path, None, "file not found")
    if path.is_dir():
        raise InputError(path, None, "is a folder, expected a file")
    check_text_file(path)
    text = path.read_text(encoding="utf-8", errors="replace")
    time_system, dms = _column_header(path, text)
    calendar = "/" in _first_data_fields(path, text)[0]
    time_names = _CALENDAR_COLUMNS if calendar else _WEEK_COLUMNS
    position_names = (("lat_d", "lat_m", "lat_s", "lon_d", "lon_m", "lon_s", "height") if dms
                      else ("lat", "lon", "height"))
    names = time_names + position_names + _SOLUTION_COLUMNS + _VELOCITY_COLUMNS
    base_count = len(time_names) + len(position_names) + len(_SOLUTION_COLUMNS)
    # Dates and clock times become plain numbers; every line keeps its place.
    numeric_text = text.translate(str.maketrans("/:", "  "))
    table = read_numeric_table(path, columns=(base_count, base_count + len(_VELOCITY_COLUMNS)),
                               column_names=names, text=numeric_text)
    values = table.values

    t_cols = len(time_names)
    if calendar:
        year, month, day, hour, minute, second = values[:, :6].T
        in_range = ((month >= 1) & (month <= 12) & (day >= 1) & (day <= 31) & (hour >= 0) & (hour < 24)
                    & (minute >= 0) & (minute < 60) & (second >= 0) & (second < 61)
                    & (values[:, :5] == np.round(values[:, :5])).all(axis=1))
        if not in_range.all():
            table.fail(int(np.argmin(in_range)), "invalid calendar date or time: expected yyyy/mm/dd hh:mm:ss.sss")
        gps_week, time_s = calendar_to_week_seconds(year, month, day, hour, minute, second)
    else:
        week, tow = values[:, 0], values[:, 1]
        in_range = (week >= 0) & (week == np.round(week)) & (tow >= 0) & (tow < SECONDS_PER_WEEK + 1)
        if not in_range.all():
            table.fail(int(np.argmin(in_range)), "invalid GPS week or time of week: expected 'week tow'")
        gps_week, time_s = week_tow_to_week_seconds(week, tow)
    if time_system == "JST":
        gps_week, time_s = normalise_week(gps_week, time_s - JST_MINUS_UTC_S)
    if time_system in ("UTC", "JST"):
        gps_week, time_s = utc_to_gpst(gps_week, time_s)
    check_time_order(time_s, table.fail, where=table.line_of_row)

    p = t_cols
    if dms:
        lat_deg, lon_deg = _dms_to_degrees(values[:, p:p + 3]), _dms_to_degrees(values[:, p + 3:p + 6])
        p += 6
    else:
        lat_deg, lon_deg = values[:, p], values[:, p + 1]
        p += 2
    height = values[:, p]
    solution = values[:, p + 1:p + 1 + len(_SOLUTION_COLUMNS)]
    check_geodetic(table, lat_deg, lon_deg)
    quality, num_sats = solution[:, 0], solution[:, 1]
    bad_q = np.flatnonzero((quality != np.round(quality)) | (quality < 0) | (quality > _MAX_QUALITY))
    if bad_q.size:
        table.fail(bad_q[0], "Q = {quality}: expected an integer 0 to {max_quality}", fields={"quality": quality[bad_q[0]], "max_quality": _MAX_QUALITY})
    check_sigmas(table, solution[:, 2:5], "position")

    vel_ned = sigma_vel = None
    if values.shape[1] == base_count + len(_VELOCITY_COLUMNS):
        velocity = values[:, base_count:]
        vel_ned = velocity[:, 0:3] * np.array([1.0, 1.0, -1.0])
        sigma_vel = velocity[:, 3:6].copy()
        check_sigmas(table, sigma_vel, "velocity")
    return GnssSolution(
        time_s=time_s,
        lat_rad=np.radians(lat_deg),
        lon_rad=np.radians(lon_deg),
        height_m=height.copy(),
        sigma_ned_m=solution[:, 2:5].copy(),
        quality=quality.astype(np.int64),
        num_sats=num_sats.astype(np.int64),
        ratio=solution[:, 9].copy(),
        vel_ned_mps=vel_ned,
        sigma_vel_ned_mps=sigma_vel,
        gps_week=gps_week,
        gaps=find_gaps(time_s),
        source=path,
    )


def write_rtklib_pos(path: str | Path, gnss: GnssSolution, gps_week: int | None = None) -> None:
    """Write an RTKLIB .pos in the ``week tow`` GPST form with RTKLIB's header, atomically.

    rtkplot reads it. The week is ``gps_week`` or else ``gnss.gps_week``; one of them
    must be known. Unknown ratios (NaN) are written as 0, age and cross terms as 0.
    Precision: tow 1 us, lat/lon 1e-11 deg, heights and sigmas 1e-6 m.
    """
    week0 = gps_week if gps_week is not None else gnss.gps_week
    if week0 is None:
        raise ValueError("the .pos week/tow form needs the GPS week: GnssSolution.gps_week is unknown, "
                         "pass gps_week=")
    week, tow = seconds_to_week_tow(week0, gnss.time_s)
    n = len(gnss)
    zeros = np.zeros(n)
    columns = [week, tow, np.degrees(gnss.lat_rad), np.degrees(gnss.lon_rad), gnss.height_m,
               gnss.quality, gnss.num_sats, gnss.sigma_ned_m, zeros, zeros, zeros, zeros,
               np.nan_to_num(gnss.ratio, nan=0.0)]
    formats = ["%4d", "%.6f", "%.11f", "%.11f", "%.6f", "%3d", "%3d"] + ["%.6f"] * 6 + ["%.2f", "%.1f"]
    column_header = POS_COLUMN_HEADER
    if gnss.vel_ned_mps is not None:
        sigma_vel = (gnss.sigma_vel_ned_mps if gnss.sigma_vel_ned_mps is not None
                     else np.zeros_like(gnss.vel_ned_mps))
        columns += [gnss.vel_ned_mps * np.array([1.0, 1.0, -1.0]), sigma_vel, zeros, zeros, zeros]
        formats += ["%.6f"] * 9
        column_header += POS_VELOCITY_HEADER
    # write_numeric_table prefixes "# "; RTKLIB headers start with "%", so build them here.
    header = [f"program   : insrail {__version__}", POS_HEADER_NOTE, column_header]
    write_numeric_table(path, columns, formats, header, marker="%")
