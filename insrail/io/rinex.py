"""RINEX: GPS broadcast ephemerides in, observation files (RINEX 2.11) out.

``read_gps_ephemerides`` reads the GPS records of a RINEX 2.x or 3.x navigation file into
arrays (one row per ephemeris, the IS-GPS-200 parameters in SI units and radians; times as
(GPS week, seconds of week)). ``write_rinex2_obs`` writes an observation file with the
header lines RTKLIB relies on (APPROX POSITION XYZ, ANTENNA: DELTA H/E/N, # / TYPES OF
OBSERV, INTERVAL, TIME OF FIRST OBS). Both work in GPS time.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from insrail.io.atomic import atomic_write
from insrail.io.errors import InputError
from insrail.io.timescale import SECONDS_PER_WEEK, calendar_to_week_seconds

#: Broadcast orbit parameters in file order after the clock line (RINEX "BROADCAST ORBIT 1..6").
_ORBIT_FIELDS = ("iode", "crs_m", "delta_n_radps", "m0_rad",
                 "cuc_rad", "e", "cus_rad", "sqrt_a_sqrtm",
                 "toe_s", "cic_rad", "omega0_rad", "cis_rad",
                 "i0_rad", "crc_m", "omega_rad", "omega_dot_radps",
                 "idot_radps", "l2_codes", "week", "l2p_flag",
                 "accuracy_m", "health", "tgd_s", "iodc")


@dataclass(frozen=True)
class GpsEphemerides:
    """GPS broadcast ephemerides, one row per record (IS-GPS-200 names, SI units).

    prn; toc: clock reference time (week, seconds of week); af0_s, af1, af2_per_s;
    toe_week with toe_s; Keplerian elements and harmonic corrections; tgd_s; health.
    """

    prn: np.ndarray
    toc_week: np.ndarray
    toc_s: np.ndarray
    af0_s: np.ndarray
    af1: np.ndarray
    af2_per_s: np.ndarray
    toe_week: np.ndarray
    toe_s: np.ndarray
    sqrt_a_sqrtm: np.ndarray
    e: np.ndarray
    i0_rad: np.ndarray
    omega0_rad: np.ndarray
    omega_rad: np.ndarray
    m0_rad: np.ndarray
    delta_n_radps: np.ndarray
    omega_dot_radps: np.ndarray
    idot_radps: np.ndarray
    cuc_rad: np.ndarray
    cus_rad: np.ndarray
    crc_m: np.ndarray
    crs_m: np.ndarray
    cic_rad: np.ndarray
    cis_rad: np.ndarray
    tgd_s: np.ndarray
    health: np.ndarray
    source: Path | None = None

    def __len__(self) -> int:
        return len(self.prn)


def _numbers(path: Path, number: int, text: str, start: int, count: int) -> list[float]:
    values = []
    for k in range(count):
        field = text[start + 19 * k:start + 19 * (k + 1)].strip().replace("D", "E").replace("d", "e")
        try:
            values.append(float(field) if field else 0.0)
        except ValueError:
            raise InputError(path, number, "expected a number in columns {first}-"
                                           "{last}, found {field!r}", fields={"first": start + 19 * k + 1, "last": start + 19 * (k + 1), "field": field}) from None
    return values


def read_gps_ephemerides(path: str | Path) -> GpsEphemerides:
    """The GPS ephemerides of a RINEX 2.x (GPS) or 3.x (mixed or GPS) navigation file."""
    path = Path(path)
    if not path.is_file():
        raise InputError(path, None, "file not found")
    lines = path.read_text(encoding="ascii", errors="replace").splitlines()
    if not lines or lines[0][60:].strip() != "RINEX VERSION / TYPE":
        raise InputError(path, 1, "not a RINEX file: expected 'RINEX VERSION / TYPE' on the first line")
    try:
        version = float(lines[0][:9])
    except ValueError:
        raise InputError(path, 1, "unreadable RINEX version {version!r}", fields={"version": lines[0][:9].strip()}) from None
    file_type, system = lines[0][20:21].upper(), lines[0][40:41].upper()
    if file_type != "N" or (version >= 3 and system not in ("G", "M")):
        raise InputError(path, 1, "expected a RINEX navigation file with GPS ephemerides (type N, system G or M)")
    end = next((i for i, line in enumerate(lines) if line[60:].strip() == "END OF HEADER"), None)
    if end is None:
        raise InputError(path, None, "not a RINEX file: no 'END OF HEADER' line")
    rows: list[dict] = []
    i = end + 1
    while i < len(lines):
        line = lines[i]
        if not line.strip():
            i += 1
            continue
        if version >= 3:
            record_lines = 8 if line[0] in "GEJ" else (4 if line[0] in "RS" else 6 if line[0] == "C" else 8)
            if line[0] != "G":
                i += record_lines
                continue
            prn_text, date_text, clock_start, orbit_start = line[1:3], line[4:23].split(), 23, 4
        else:
            prn_text, date_text, clock_start, orbit_start = line[0:2], line[3:22].split(), 22, 3
        if i + 7 >= len(lines):
            raise InputError(path, i + 1, "incomplete ephemeris record: expected 8 lines")
        try:
            prn = int(prn_text)
            year, month, day, hour, minute = (int(v) for v in date_text[:5])
            second = float(date_text[5])
        except (ValueError, IndexError):
            raise InputError(path, i + 1, "expected an ephemeris record: PRN and clock epoch "
                                          "(year month day hour minute second)") from None
        if year < 100:
            year += 2000 if year < 80 else 1900
        clock = _numbers(path, i + 1, line, clock_start, 3)
        orbit = [v for k in range(1, 7) for v in _numbers(path, i + 1 + k, lines[i + k], orbit_start, 4)]
        week, toc = calendar_to_week_seconds([year], [month], [day], [hour], [minute], [second])
        row = dict(zip(_ORBIT_FIELDS, orbit))
        row.update(prn=prn, toc_week=week, toc_s=float(toc[0]), af0_s=clock[0], af1=clock[1], af2_per_s=clock[2])
        rows.append(row)
        i += 8
    if not rows:
        raise InputError(path, None, "no GPS ephemerides after the header")
    columns = {name: np.array([row[name] for row in rows]) for name in
               ("prn", "toc_week", "toc_s", "af0_s", "af1", "af2_per_s", "toe_s", "sqrt_a_sqrtm", "e", "i0_rad",
                "omega0_rad", "omega_rad", "m0_rad", "delta_n_radps", "omega_dot_radps", "idot_radps", "cuc_rad",
                "cus_rad", "crc_m", "crs_m", "cic_rad", "cis_rad", "tgd_s", "health")}
    columns["prn"] = columns["prn"].astype(int)
    columns["health"] = columns["health"].astype(int)
    # The week field is the GPS week of toe (continuous, not mod 1024).
    columns["toe_week"] = np.array([int(row["week"]) for row in rows])
    return GpsEphemerides(**columns, source=path)


# --------------------------------------------------------------------------- observation files

@dataclass(frozen=True)
class RinexObsHeader:
    """What a RINEX observation header states.

    approx_position_ecef_m : APPROX POSITION XYZ (the marker, metre level)
    antenna_delta_hen_m    : ARP above the marker (height) and east/north eccentricities
    obs_types              : RINEX 2 observation codes, e.g. ("C1", "L1", "P2", "L2")
    interval_s             : nominal epoch interval
    """

    marker_name: str
    approx_position_ecef_m: tuple[float, float, float]
    antenna_delta_hen_m: tuple[float, float, float]
    obs_types: tuple[str, ...]
    interval_s: float
    receiver_type: str = "INSRAIL SIMULATOR"
    antenna_type: str = ""
    program: str = "insrail"


def _calendar(week: int, seconds: np.ndarray) -> tuple[np.ndarray, ...]:
    """(year, month, day, hour, minute, second) in GPS time of (week, seconds of week)."""
    seconds = np.asarray(seconds, dtype=float)
    whole = np.floor(seconds + 1e-9)  # a stamp a hair below a whole second stays in that second
    fraction = np.maximum(seconds - whole, 0.0)
    stamp = (np.datetime64("1980-01-06T00:00:00", "s") + np.timedelta64(week * SECONDS_PER_WEEK, "s")
             + whole.astype(np.int64).astype("timedelta64[s]"))
    days = stamp.astype("datetime64[D]")
    months = stamp.astype("datetime64[M]")
    years = stamp.astype("datetime64[Y]")
    of_day = (stamp - days).astype(np.int64)
    return (years.astype(np.int64) + 1970, (months - years).astype(np.int64) + 1,
            (days - months).astype(np.int64) + 1, of_day // 3600, of_day % 3600 // 60, of_day % 60 + fraction)


def _header_line(content: str, label: str) -> str:
    return f"{content:<60.60}{label:<20}\n"


def write_rinex2_obs(path: str | Path, header: RinexObsHeader, gps_week: int, time_s: np.ndarray,
                     prn: np.ndarray, values: np.ndarray) -> Path:
    """Write a GPS RINEX 2.11 observation file atomically.

    time_s : (n,) epoch tags [s of ``gps_week``, receiver time]
    prn    : (n, k) satellite numbers per epoch, 0 where a slot is empty
    values : (n, k, len(header.obs_types)) observations (m for code, cycles for phase), NaN = none
    """
    time_s, prn, values = np.asarray(time_s, float), np.asarray(prn, int), np.asarray(values, float)
    n_types = len(header.obs_types)
    if values.shape != prn.shape + (n_types,) or prn.shape[0] != len(time_s):
        raise ValueError(f"write_rinex2_obs: shapes time {time_s.shape}, prn {prn.shape}, values {values.shape} "
                         f"do not fit {n_types} observation types")
    year, month, day, hour, minute, second = _calendar(gps_week, time_s)
    first = (year[0], month[0], day[0], hour[0], minute[0], second[0])
    lines = [
        _header_line("     2.11           OBSERVATION DATA    G (GPS)", "RINEX VERSION / TYPE"),
        _header_line(f"{header.program:<20}{'insrail':<20}", "PGM / RUN BY / DATE"),
        _header_line(header.marker_name, "MARKER NAME"),
        _header_line(f"{'insrail':<20}{'simulation':<40}", "OBSERVER / AGENCY"),
        _header_line(f"{'0':<20}{header.receiver_type:<20}{'1':<20}", "REC # / TYPE / VERS"),
        _header_line(f"{'0':<20}{header.antenna_type:<20}", "ANT # / TYPE"),
        _header_line("".join(f"{v:14.4f}" for v in header.approx_position_ecef_m), "APPROX POSITION XYZ"),
        _header_line("".join(f"{v:14.4f}" for v in header.antenna_delta_hen_m), "ANTENNA: DELTA H/E/N"),
        _header_line("     1     1", "WAVELENGTH FACT L1/2"),
        _header_line(f"{n_types:6d}" + "".join(f"{t:>6}" for t in header.obs_types), "# / TYPES OF OBSERV"),
        _header_line(f"{header.interval_s:10.3f}", "INTERVAL"),
        _header_line("{:6d}{:6d}{:6d}{:6d}{:6d}{:13.7f}     GPS".format(*(int(v) for v in first[:5]), first[5]),
                     "TIME OF FIRST OBS"),
        _header_line("", "END OF HEADER"),
    ]
    with atomic_write(path) as handle:
        handle.writelines(lines)
        for k in range(len(time_s)):
            present = np.flatnonzero(prn[k] > 0)
            sats = [f"G{p:02d}" for p in prn[k, present]]
            epoch = " {:02d} {:2d} {:2d} {:2d} {:2d}{:11.7f}  0{:3d}".format(
                int(year[k]) % 100, int(month[k]), int(day[k]), int(hour[k]), int(minute[k]), second[k], len(sats))
            handle.write(epoch + "".join(sats[:12]) + "\n")
            for more in range(12, len(sats), 12):
                handle.write(" " * 32 + "".join(sats[more:more + 12]) + "\n")
            for slot in present:
                fields = ["" if np.isnan(v) else f"{v:14.3f}  " for v in values[k, slot]]
                for chunk in range(0, n_types, 5):
                    handle.write("".join(f"{f:<16}" for f in fields[chunk:chunk + 5]).rstrip() + "\n")
    return Path(path)
