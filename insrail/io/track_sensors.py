"""Track sensors on the trolley: the gauge sensor and the sleeper detector.

Gauge: ``t gauge[mm]`` (files hold millimetres; GaugeData holds metres).
Sleepers: one ``t`` per line, the time of each sleeper-detector pulse.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from insrail.io.errors import InputError
from insrail.io.textparse import check_table_time, find_gaps, read_numeric_table, write_numeric_table
from insrail.io.types import GaugeData, SleeperPulses

# Any real gauge (600 mm narrow gauge to 1676 mm broad gauge) read in mm is far above
# this; a median below it means the file was written in metres.
_MIN_PLAUSIBLE_GAUGE_MM = 100.0


def read_gauge_mm(path: str | Path) -> GaugeData:
    """``t gauge[mm]`` -> GaugeData.gauge_m."""
    table = read_numeric_table(path, columns=(2,), column_names=("t", "gauge_mm"))
    time_s = check_table_time(table)
    gauge_mm = table.values[:, 1]
    if np.median(gauge_mm) < _MIN_PLAUSIBLE_GAUGE_MM:
        raise InputError(table.path, None, f"median gauge {np.median(gauge_mm):g} mm is implausible: "
                         "expected millimetres (is the file in metres?)")
    return GaugeData(time_s=time_s.copy(), gauge_m=gauge_mm / 1000.0, gaps=find_gaps(time_s),
                     source=table.path)


def write_gauge_mm(path: str | Path, gauge: GaugeData) -> None:
    """Write ``t gauge[mm]`` (time 1 ns, gauge 1e-6 mm), atomically."""
    write_numeric_table(path, [gauge.time_s, gauge.gauge_m * 1000.0], ["%.9f", "%.6f"],
                        ["format: gauge-mm", "columns: t[s of GPS week] gauge[mm]"])


def read_sleeper_times(path: str | Path) -> SleeperPulses:
    """One time stamp per line -> SleeperPulses."""
    table = read_numeric_table(path, columns=(1,), column_names=("t",))
    return SleeperPulses(time_s=check_table_time(table).copy(), source=table.path)


def write_sleeper_times(path: str | Path, sleepers: SleeperPulses) -> None:
    """Write one pulse time per line (1 ns), atomically."""
    write_numeric_table(path, [sleepers.time_s], ["%.9f"],
                        ["format: sleeper-times", "columns: t[s of GPS week] of each sleeper pulse"])
