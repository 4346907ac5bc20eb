"""The format registry: every raw-data format by name, format detection, ``read_any``.

A format is one reader (and usually one writer) plus the data type it yields; the
survey folder (``survey.toml``) and the GUI import dialog refer to formats by the
registry key. Adding a format is one entry in :data:`FORMATS`.
"""

from __future__ import annotations

import inspect
import typing
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

import numpy as np

from insrail.io import control, events, gnss, gsi, imu, odometer, rtklib, total_station, track_sensors
from insrail.io.errors import InputError
from insrail.io.textparse import (
    COMMENT_MARKERS,
    bounded_lines,
    check_text_file,
    header_value,
    is_number,
    split_fields,
    strip_comment,
)
from insrail.io.types import (
    Benchmarks,
    ControlPoints,
    GaugeData,
    GnssSolution,
    ImuIncrements,
    OdometerData,
    PrismObservations,
    SleeperPulses,
    TotalStationObservations,
)


def _scan_text(path: Path, each_block: Callable[[bytes], object]) -> None:
    check_text_file(path, each_block=each_block)


@dataclass(frozen=True)
class FileFormat:
    """One raw-data format: its registry name, reader, writer and the type the reader returns.

    ``scan(path, each_block)`` reads the file once in blocks, refusing it (InputError) at the first
    block that shows it is not of this kind, and hands each block to ``each_block``: the cache key
    hashes a raw file this way, so a disk image named as an IMU file is refused in a moment instead
    of after hashing all of it. Every format is text (:func:`check_text_file`) but the binary ones.
    """

    name: str
    read: Callable[..., Any]
    write: Callable[..., None] | None
    data_type: type
    description: str
    #: (option, why) for options that are each of the right type but together no valid setting
    #: (a calibration slope of 0, a key another needs): survey.toml names them by key before reading
    check_options: Callable[[dict], list[tuple[str, str]]] | None = None
    scan: Callable[[Path, Callable[[bytes], object]], None] = _scan_text

    def options(self) -> dict[str, inspect.Parameter]:
        """The reader's keyword options (everything after the path)."""
        parameters = list(inspect.signature(self.read).parameters.values())[1:]
        return {p.name: p for p in parameters}

    def option_hints(self) -> dict[str, Any]:
        hints = typing.get_type_hints(self.read)
        return {name: hints[name] for name in self.options()}


FORMATS: dict[str, FileFormat] = {f.name: f for f in (
    FileFormat("kfgins-imu", imu.read_imu_kfgins, imu.write_imu_kfgins, ImuIncrements,
               "IMU increments, KF-GINS 7-column text"),
    FileFormat("imu-npy", imu.read_imu_npy, imu.write_imu_npy, ImuIncrements,
               "IMU increments, NumPy .npy structured array", scan=imu.scan_imu_npy),
    FileFormat("imu-rates-csv", imu.read_imu_rates_csv, None, ImuIncrements,
               "IMU rates (specific force, angular rate) from a foreign logger, CSV/text"),
    FileFormat("kfgins-gnss", gnss.read_gnss_kfgins, gnss.write_gnss_kfgins, GnssSolution,
               "GNSS positions (and velocities), KF-GINS 7- or 13-column text"),
    FileFormat("rtklib-pos", rtklib.read_rtklib_pos, rtklib.write_rtklib_pos, GnssSolution,
               "GNSS solution, RTKLIB .pos (latitude/longitude/height)"),
    FileFormat("odometer-distance", odometer.read_odometer_distance, odometer.write_odometer_distance,
               OdometerData, "odometer cumulative distance [m]"),
    FileFormat("odometer-pulses", odometer.read_odometer_pulses, odometer.write_odometer_pulses,
               OdometerData, "odometer cumulative pulse counts"),
    FileFormat("gauge-mm", track_sensors.read_gauge_mm, track_sensors.write_gauge_mm, GaugeData,
               "gauge sensor [mm]"),
    FileFormat("gauge-volts", track_sensors.read_gauge_volts, None, GaugeData,
               "gauge sensor voltage [V] (and temperature [°C]) with its calibration",
               track_sensors.gauge_volts_option_problems),
    FileFormat("sleeper-times", track_sensors.read_sleeper_times, track_sensors.write_sleeper_times,
               SleeperPulses, "sleeper detector pulse times"),
    FileFormat("prism-enu", control.read_prism_enu, control.write_prism_enu, PrismObservations,
               "total-station prism positions on CPIII, engineering frame"),
    FileFormat("total-station-polar", total_station.read_total_station_polar, total_station.write_total_station_polar,
               TotalStationObservations, "raw total-station pointings (Hz, V, slope distance) of free stations"),
    FileFormat("total-station-gsi", gsi.read_total_station_gsi, gsi.write_total_station_gsi,
               TotalStationObservations, "raw total-station pointings of free stations, Leica GSI-16 (or GSI-8)"),
    FileFormat("cpiii-enh", total_station.read_cpiii_enh, total_station.write_cpiii_enh, ControlPoints,
               "CPIII point coordinates, engineering frame"),
    FileFormat("cpiii-gsi", gsi.read_cpiii_gsi, gsi.write_cpiii_gsi, ControlPoints,
               "CPIII point coordinates, engineering frame, Leica GSI-16 (or GSI-8)"),
    FileFormat("benchmarks", control.read_benchmarks, control.write_benchmarks, Benchmarks,
               "GNSS-levelling benchmarks (h and H)"),
    FileFormat("events", events.read_events, events.write_events, events.EventList,
               "track events: turnouts, level crossings, bridges, joints, stretches not to assess"),
)}


def get_format(name: str) -> FileFormat:
    try:
        return FORMATS[name]
    except KeyError:
        raise ValueError(f"unknown format {name!r}: expected one of {', '.join(FORMATS)}") from None


def unknown_options(file_format: FileFormat, options: dict) -> list[str]:
    return [key for key in options if key not in file_format.options()]


def read_any(path: str | Path, format: str | None = None, **options) -> Any:
    """Read ``path`` with the named format, or the detected one when ``format`` is None."""
    path = Path(path)
    name = format if format is not None else detect_format(path)
    if name is None:
        if not path.exists():
            raise InputError(path, None, "file not found")
        raise InputError(path, None, "format not recognised: name it explicitly (one of {formats})",
                         fields={"formats": list(FORMATS)})
    file_format = get_format(name)
    unknown = unknown_options(file_format, options)
    if unknown:
        raise InputError(path, None, "unknown option {unknown!r} for format {name} "
                         "(known: {known})", fields={"unknown": unknown[0], "name": name, "known": ', '.join(file_format.options()) or 'none'})
    return file_format.read(path, **options)


# --- detection ------------------------------------------------------------------------------

_DETECT_LINES = 20


def _head(path: Path) -> tuple[list[str], list[list[str]]]:
    """Comment lines and the fields of up to _DETECT_LINES data lines (header row dropped)."""
    comments: list[str] = []
    rows: list[list[str]] = []
    with open(path, encoding="utf-8", errors="replace") as handle:
        for _, raw in bounded_lines(handle, path):
            line = raw.strip().lstrip("\ufeff")
            if line[:1] in COMMENT_MARKERS:
                comments.append(line[1:].strip())
                continue
            content = strip_comment(line)
            if not content:
                continue
            fields = split_fields(content, "," if "," in content else None)
            if not rows and not any(is_number(f) for f in fields):
                continue  # header row of column names
            rows.append(fields)
            if len(rows) >= _DETECT_LINES:
                break
    return comments, rows


def _is_imu_npy(path: Path) -> bool:
    try:
        records = np.load(path, mmap_mode="r", allow_pickle=False)
    except (ValueError, OSError, EOFError):
        return False
    return records.dtype.names is not None and set(imu.IMU_NPY_DTYPE.names) <= set(records.dtype.names)


def _detect_from_columns(path: Path, comments: list[str], rows: list[list[str]]) -> str | None:
    width = len(rows[0])
    if any(len(r) != width for r in rows):
        return None
    if not is_number(rows[0][0]):
        return "benchmarks" if width == 5 else None
    if width in (5, 6) and all(is_number(f) for r in rows for f in r[:5]):
        return "prism-enu"
    if not all(is_number(f) for r in rows for f in r):
        return None
    values = np.array(rows, dtype=float)
    if width == 1:
        return "sleeper-times"
    if width == 2:
        second = values[:, 1]
        if header_value(comments, "pulse_length_m") is not None:
            return "odometer-pulses"
        if 500.0 <= second.min() and second.max() <= 2000.0 and np.ptp(second) < 100.0:
            return "gauge-mm"
        return "odometer-pulses" if np.all(second == np.round(second)) else "odometer-distance"
    if width == 7 and np.all(np.abs(values[:, 1:4]) < 0.5):
        return "kfgins-imu"
    if width in (7, 13) and np.all(np.abs(values[:, 1]) <= 90) and np.all(np.abs(values[:, 2]) <= 360):
        return "kfgins-gnss"
    if width in (15, 24) and np.all(values[:, 0] == np.round(values[:, 0])):
        return "rtklib-pos"  # 'week tow' form without a header
    if width >= 7 and path.suffix.lower() in (".csv", ".txt"):
        return "imu-rates-csv"
    return None


def detect_format(path: str | Path) -> str | None:
    """Registry name of the format of ``path`` from its extension and first lines, or None.

    Files written by insrail name their format in a ``# format: ...`` line; other
    files are recognised by their header and the shape and range of their columns.
    """
    path = Path(path)
    if not path.is_file():
        return None
    if path.suffix.lower() == ".npy":
        return "imu-npy" if _is_imu_npy(path) else None
    gsi_format = gsi.detect(path)
    if gsi_format is not None:
        return gsi_format
    try:
        comments, rows = _head(path)
    except OSError:
        return None
    declared = header_value(comments, "format")
    if declared in FORMATS:
        return declared
    if any(c.split()[:1] in (["GPST"], ["UTC"], ["JST"]) and "latitude" in c for c in comments):
        return "rtklib-pos"
    if not rows:
        return None
    if "/" in rows[0][0]:
        return "rtklib-pos"  # calendar time form
    return _detect_from_columns(path, comments, rows)
