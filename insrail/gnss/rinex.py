"""What insrail checks in RINEX files before handing them to RTKLIB.

Only headers and epoch time tags are read (RINEX 2.x and 3.x): the file type, the
approximate antenna position, the antenna height, and the first and last epoch, so
that missing navigation data or base and rover that do not overlap give a clear
error instead of an empty RTKLIB output. Times are GPS seconds since 1980-01-06.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from insrail.io.errors import InputError
from insrail.io.timescale import calendar_to_week_seconds

SECONDS_PER_WEEK = 604800.0
# Epoch lines: RINEX 3 "> 2005 04 02 00 00 30.0000000  0 12", RINEX 2 " 05  4  2  0  0 30.0000000  0  7G..".
_EPOCH_RINEX3 = re.compile(r"^> (\d{4}) ([ \d]\d) ([ \d]\d) ([ \d]\d) ([ \d]\d) ([ \d]\d\.\d+) +[0-6]", re.MULTILINE)
_EPOCH_RINEX2 = re.compile(r"^ ([ \d]\d) ([ \d]\d) ([ \d]\d) ([ \d]\d) ([ \d]\d) ([ \d]\d\.\d{7})  [0-6]", re.MULTILINE)


@dataclass(frozen=True)
class RinexObsInfo:
    """Header facts of a RINEX observation file.

    approx_position_ecef_m : APPROX POSITION XYZ (None when absent or zero)
    antenna_delta_hen_m    : ANTENNA: DELTA H/E/N
    first_s, last_s        : first and last epoch [GPS s since 1980-01-06]
    epochs                 : number of epoch records
    """

    path: Path
    version: float
    approx_position_ecef_m: tuple[float, float, float] | None
    antenna_delta_hen_m: tuple[float, float, float]
    first_s: float
    last_s: float
    epochs: int


def _header(path: Path) -> tuple[list[str], str]:
    if not path.is_file():
        raise InputError(path, None, "file not found")
    text = path.read_text(encoding="ascii", errors="replace")
    lines = text.splitlines()
    for number, line in enumerate(lines):
        if line[60:].strip() == "END OF HEADER":
            return lines[:number + 1], "\n".join(lines[number + 1:])
    raise InputError(path, None, "not a RINEX file: no 'END OF HEADER' line")


def _version_and_type(path: Path, header: list[str]) -> tuple[float, str]:
    first = header[0]
    if first[60:].strip() != "RINEX VERSION / TYPE":
        raise InputError(path, 1, "not a RINEX file: expected 'RINEX VERSION / TYPE' on the first line")
    try:
        version = float(first[:9])
    except ValueError:
        raise InputError(path, 1, "unreadable RINEX version {version!r}", fields={"version": first[:9].strip()}) from None
    return version, first[20:21].upper()


def _to_gps_seconds(fields: np.ndarray, two_digit_year: bool) -> np.ndarray:
    year = fields[:, 0]
    if two_digit_year:
        year = np.where(year < 80, year + 2000, year + 1900)
    week, seconds = calendar_to_week_seconds(year, fields[:, 1], fields[:, 2], fields[:, 3], fields[:, 4],
                                             fields[:, 5])
    return week * SECONDS_PER_WEEK + seconds


def read_obs_info(path: str | Path) -> RinexObsInfo:
    """Header facts and epoch span of a RINEX observation file; InputError if it is not one."""
    path = Path(path)
    header, body = _header(path)
    version, file_type = _version_and_type(path, header)
    if file_type != "O":
        raise InputError(path, 1, "expected a RINEX observation file (type O), found type {file_type!r}", fields={"file_type": file_type})
    approx = None
    delta = (0.0, 0.0, 0.0)
    for number, line in enumerate(header, 1):
        label = line[60:].strip()
        try:
            xyz = (0.0, 0.0, 0.0)
            if label == "APPROX POSITION XYZ":
                xyz = tuple(float(line[i:i + 14]) for i in (0, 14, 28))
                approx = xyz if any(xyz) else None
            elif label == "ANTENNA: DELTA H/E/N":
                xyz = delta = tuple(float(line[i:i + 14]) for i in (0, 14, 28))
        except ValueError:
            raise InputError(path, number, "unreadable {label}: expected three F14.4 numbers", fields={"label": label}) from None
        if not all(map(math.isfinite, xyz)):
            raise InputError(path, number, "{label}: non-finite value {text!r}: expected three "
                             "F14.4 numbers in metres", fields={"label": label, "text": line[:42].strip()})
    pattern = _EPOCH_RINEX3 if version >= 3 else _EPOCH_RINEX2
    tags = pattern.findall(body)
    if not tags:
        raise InputError(path, None, "no observation epochs after the header")
    times = _to_gps_seconds(np.array(tags, dtype=float), two_digit_year=version < 3)
    return RinexObsInfo(path, version, approx, delta, float(times.min()), float(times.max()), len(tags))


def check_navigation(path: str | Path) -> None:
    """InputError unless ``path`` is a RINEX navigation file with at least one record."""
    path = Path(path)
    header, body = _header(path)
    _version, file_type = _version_and_type(path, header)
    if file_type not in ("N", "G", "H", "L", "C", "J", "I", "E", "B"):
        raise InputError(path, 1, "expected a RINEX navigation file (type N, G, ...), found type {file_type!r}", fields={"file_type": file_type})
    if not body.strip():
        raise InputError(path, None, "no navigation data: the file holds a header and no ephemerides")
