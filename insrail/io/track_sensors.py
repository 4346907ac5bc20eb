"""Track sensors on the trolley: the gauge sensor and the sleeper detector.

Gauge: ``t gauge[mm]`` (files hold millimetres; GaugeData holds metres), or the sensor's raw
``t volts [temperature_C]`` with its calibration (thesis eq. 5.1, 5.3): gauge [mm] =
k·v + b + K_T·(T − T_cal), k and b fitted on gauge blocks at the temperature T_cal.
Sleepers: one ``t`` per line, the time of each sleeper-detector pulse.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from insrail.io.errors import InputError
from insrail.io.textparse import check_table_time, find_gaps, read_numeric_table, write_numeric_table
from insrail.io.types import GaugeData, SleeperPulses
from insrail.notices import Phrase, one_after_another

# Any real gauge (600 mm narrow gauge to 1676 mm broad gauge) read in mm is far above
# this; a median below it means the file was written in metres.
_MIN_PLAUSIBLE_GAUGE_MM = 100.0
#: A gauge sensor's temperature sensor inside the trolley: beyond these a column is not a
#: temperature in degrees Celsius (Kelvin, Fahrenheit, or another quantity) [°C].
TEMPERATURE_RANGE_C = (-50.0, 85.0)


def read_gauge_mm(path: str | Path) -> GaugeData:
    """``t gauge[mm]`` -> GaugeData.gauge_m."""
    table = read_numeric_table(path, columns=(2,), column_names=("t", "gauge_mm"))
    time_s = check_table_time(table)
    gauge_mm = table.values[:, 1]
    if np.median(gauge_mm) < _MIN_PLAUSIBLE_GAUGE_MM:
        raise InputError(table.path, None, "median gauge {median:g} mm is implausible: "
                         "expected millimetres (is the file in metres?)", fields={"median": np.median(gauge_mm)})
    return GaugeData(time_s=time_s.copy(), gauge_m=gauge_mm / 1000.0, gaps=find_gaps(time_s),
                     source=table.path)


def gauge_volts_option_problems(options: dict) -> list[tuple[str, Phrase]]:
    """(option, why) for each calibration option of ``gauge-volts`` that is missing or cannot be a
    calibration; ``options`` as survey.toml gives them (absent keys left out)."""
    problems = []
    for key, what in (("k_mm_per_v", Phrase("the sensor's slope k [mm/V] (thesis eq. 5.3)")),
                      ("b_mm", Phrase("the sensor's offset b [mm] (thesis eq. 5.3)"))):
        if options.get(key) is None:
            problems.append((key, Phrase("missing: the gauge-volts format needs {what}", {"what": what})))
    k = options.get("k_mm_per_v")
    if k is not None and k == 0:
        problems.append(("k_mm_per_v", Phrase("is 0: a slope of 0 mm/V makes every reading the same gauge; expected "
                                              "the calibration's slope (typically a few mm/V)")))
    given = [options.get(key) is not None for key in ("temperature_coefficient_mm_per_c", "calibration_temperature_c")]
    if given[0] and not given[1]:
        problems.append(("calibration_temperature_c", Phrase("missing: with temperature_coefficient_mm_per_c give the "
                                                             "temperature [°C] at which k and b were calibrated")))
    if given[1] and not given[0]:
        problems.append(("temperature_coefficient_mm_per_c", Phrase("missing: calibration_temperature_c is given but "
                                                                    "no temperature coefficient K_T [mm/°C]")))
    low, high = TEMPERATURE_RANGE_C
    t_cal = options.get("calibration_temperature_c")
    if t_cal is not None and not low <= t_cal <= high:
        problems.append(("calibration_temperature_c", Phrase("{value:g}: expected degrees Celsius, {low:g} .. {high:g}",
                                                             {"value": t_cal, "low": low, "high": high})))
    return problems


def read_gauge_volts(path: str | Path, k_mm_per_v: float | None = None, b_mm: float | None = None,
                     temperature_coefficient_mm_per_c: float | None = None,
                     calibration_temperature_c: float | None = None) -> GaugeData:
    """``t volts`` or ``t volts temperature[°C]`` and the calibration -> GaugeData.gauge_m (see the
    module docstring). A temperature column needs K_T and K_T needs one: neither is ignored."""
    options = {"k_mm_per_v": k_mm_per_v, "b_mm": b_mm, "calibration_temperature_c": calibration_temperature_c,
               "temperature_coefficient_mm_per_c": temperature_coefficient_mm_per_c}
    problems = gauge_volts_option_problems(options)
    if problems:
        raise InputError(path, None, one_after_another([Phrase("option {key}: {why}", {"key": key, "why": why})
                                                        for key, why in problems]))
    table = read_numeric_table(path, columns=(2, 3), column_names=("t", "volts", "temperature_c"))
    time_s = check_table_time(table)
    with_temperature = table.values.shape[1] == 3
    if temperature_coefficient_mm_per_c is not None and not with_temperature:
        table.fail(0, "expected 3 columns (t, volts, temperature [°C]) because the calibration gives a temperature "
                   "coefficient (temperature_coefficient_mm_per_c), found 2")
    if with_temperature and temperature_coefficient_mm_per_c is None:
        table.fail(0, "a third column (temperature) but the calibration gives no temperature coefficient: give "
                   "temperature_coefficient_mm_per_c and calibration_temperature_c (K_T = 0 for a sensor that "
                   "needs none)")
    gauge_mm = k_mm_per_v * table.values[:, 1] + b_mm
    if with_temperature:
        temperature_c = table.values[:, 2]
        low, high = TEMPERATURE_RANGE_C
        outside = np.flatnonzero((temperature_c < low) | (temperature_c > high))
        if len(outside):
            table.fail(int(outside[0]), "temperature {temperature_c:g}: expected degrees Celsius, "
                       "{low:g} .. {high:g}", fields={"temperature_c": temperature_c[outside[0]], "low": low, "high": high})
        gauge_mm = gauge_mm + temperature_coefficient_mm_per_c * (temperature_c - calibration_temperature_c)
    if np.median(gauge_mm) < _MIN_PLAUSIBLE_GAUGE_MM:
        raise InputError(table.path, None, "the calibration gives a median gauge of {median:g} mm: "
                         "expected millimetres (k_mm_per_v in mm/V and b_mm in mm)", fields={"median": np.median(gauge_mm)})
    return GaugeData(time_s=time_s.copy(), gauge_m=gauge_mm / 1000.0, gaps=find_gaps(time_s), source=table.path)


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
