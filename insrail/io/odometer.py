"""Odometer files: cumulative distance, or cumulative pulse counts times a pulse length.

(a) ``t distance[m]``: signed cumulative distance (driving backwards decreases it).
(b) ``t pulse_count``: signed cumulative integer count; distance = count x pulse
    length, the pulse length given to the reader or in a ``# pulse_length_m = 0.001``
    header line (the reader argument wins).
Distances keep the sensor's scale-factor error; the filter estimates it.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from insrail.io.errors import InputError
from insrail.io.textparse import (
    check_table_time,
    find_gaps,
    header_value,
    read_numeric_table,
    write_numeric_table,
)
from insrail.io.types import OdometerData


def read_odometer_distance(path: str | Path) -> OdometerData:
    """``t distance[m]`` -> OdometerData."""
    table = read_numeric_table(path, columns=(2,), column_names=("t", "distance"))
    time_s = check_table_time(table)
    return OdometerData(time_s=time_s.copy(), distance_m=table.values[:, 1].copy(),
                        gaps=find_gaps(time_s), source=table.path)


def read_odometer_pulses(path: str | Path, pulse_length_m: float | None = None) -> OdometerData:
    """``t pulse_count`` -> OdometerData with distance = count x pulse_length_m."""
    table = read_numeric_table(path, columns=(2,), column_names=("t", "pulse_count"))
    if pulse_length_m is None:
        from_header = header_value(table.comments, "pulse_length_m")
        if from_header is None:
            raise InputError(table.path, None, "pulse length unknown: give pulse_length_m (reader option "
                             "or survey.toml) or a '# pulse_length_m = 0.001' header line")
        try:
            pulse_length_m = float(from_header)
        except ValueError:
            raise InputError(table.path, None,
                             "header pulse_length_m = {from_header!r}: expected a number", fields={"from_header": from_header}) from None
    if not (np.isfinite(pulse_length_m) and pulse_length_m > 0):
        raise InputError(table.path, None, "pulse_length_m = {pulse_length_m}: expected a positive length", fields={"pulse_length_m": pulse_length_m})
    time_s = check_table_time(table)
    counts = table.values[:, 1]
    fractional = np.flatnonzero(counts != np.round(counts))
    if fractional.size:
        table.fail(fractional[0], "pulse count {counts}: expected an integer", fields={"counts": counts[fractional[0]]})
    return OdometerData(time_s=time_s.copy(), distance_m=counts * pulse_length_m,
                        pulse_length_m=float(pulse_length_m), gaps=find_gaps(time_s), source=table.path)


def write_odometer_distance(path: str | Path, odometer: OdometerData) -> None:
    """Write ``t distance[m]`` (time 1 ns, distance 1e-9 m), atomically."""
    write_numeric_table(path, [odometer.time_s, odometer.distance_m], ["%.9f", "%.9f"],
                        ["format: odometer-distance", "columns: t[s of GPS week] distance[m, cumulative, signed]"])


def write_odometer_pulses(path: str | Path, odometer: OdometerData) -> None:
    """Write ``t pulse_count`` with a ``pulse_length_m`` header line, atomically.

    Counts are distance / pulse_length_m rounded to integers; OdometerData must
    carry its pulse length.
    """
    if odometer.pulse_length_m is None:
        raise ValueError("OdometerData.pulse_length_m is None: the pulse form needs a pulse length")
    counts = np.round(odometer.distance_m / odometer.pulse_length_m)
    write_numeric_table(path, [odometer.time_s, counts], ["%.9f", "%d"],
                        ["format: odometer-pulses", f"pulse_length_m = {odometer.pulse_length_m!r}",
                         "columns: t[s of GPS week] pulse_count[cumulative, signed]"])
