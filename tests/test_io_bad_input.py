"""Bad input: every text format names the file and the exact line of the problem."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np
import pytest

from insrail.io import (
    InputError,
    read_gauge_mm,
    read_gnss_kfgins,
    read_imu_kfgins,
    read_imu_npy,
    read_odometer_distance,
    read_odometer_pulses,
    read_prism_enu,
    read_rtklib_pos,
    read_sleeper_times,
)
from insrail.io.imu import IMU_NPY_DTYPE


@dataclass(frozen=True)
class Case:
    name: str
    read: Callable
    header: tuple[str, ...]
    fields: Callable[[float], list[str]]
    time_index: int = 0
    value_index: int = 1  # a numeric field to corrupt


CASES = [
    Case("kfgins-imu", read_imu_kfgins, ("# t dtheta dvel",),
         lambda t: [f"{t:.3f}", "1e-5", "2e-5", "3e-5", "1e-4", "2e-4", "-0.049"]),
    Case("kfgins-gnss", read_gnss_kfgins, (),
         lambda t: [f"{t:.3f}", "30.5", "114.3", "20.0", "0.01", "0.01", "0.02"]),
    Case("rtklib-pos", read_rtklib_pos, ("% program : test", "%  GPST latitude(deg) longitude(deg) height(m)"),
         lambda t: ["2381", f"{t:.3f}", "40.1", "-105.1", "1601.4", "1", "25", "0.01", "0.01", "0.02",
                    "0", "0", "0", "0.0", "3.2"], time_index=1, value_index=2),
    Case("odometer-distance", read_odometer_distance, ("t,distance",),
         lambda t: [f"{t:.3f}", f"{t * 1.5:.3f}"]),
    Case("odometer-pulses", read_odometer_pulses, ("# pulse_length_m = 0.001",),
         lambda t: [f"{t:.3f}", f"{int(t * 10)}"]),
    Case("gauge-mm", read_gauge_mm, (), lambda t: [f"{t:.3f}", "1435.2"]),
    Case("sleeper-times", read_sleeper_times, ("# sleepers",), lambda t: [f"{t:.3f}"], value_index=0),
    Case("prism-enu", read_prism_enu, ("t E N H sigma id",),
         lambda t: [f"{t:.3f}", "500.1", "3000.2", "12.3", "0.001", "CP1"]),
]
ROWS = 6
BAD_ROW = 3  # 0-based data row that gets corrupted


def write_case(path: Path, case: Case, corrupt: Callable[[list[list[str]]], None] | None = None) -> int:
    """Write a valid file (optionally corrupted); return the file line of BAD_ROW."""
    rows = [case.fields(100.0 + 0.25 * i) for i in range(ROWS)]
    if corrupt is not None:
        corrupt(rows)
    sep = "," if case.header and "," in case.header[0] else " "
    lines = list(case.header) + [sep.join(r) for r in rows]
    path.write_text("\n".join(lines) + "\n")
    return len(case.header) + BAD_ROW + 1


def expect_error(case: Case, path: Path, line: int | None, fragment: str) -> InputError:
    with pytest.raises(InputError) as info:
        case.read(path)
    err = info.value
    assert err.path == path
    assert err.line == line, str(err)
    assert fragment in err.message, str(err)
    assert str(err).startswith(f"{path}, line {line}:" if line else f"{path}:")
    return err


@pytest.fixture(params=CASES, ids=lambda c: c.name)
def case(request):
    return request.param


def test_valid_file_reads(case, tmp_path):
    path = tmp_path / "ok.txt"
    write_case(path, case)
    assert len(case.read(path)) == ROWS


def test_wrong_column_count(case, tmp_path):
    path = tmp_path / "bad.txt"
    line = write_case(path, case, lambda rows: rows[BAD_ROW].append("1.5"))
    expect_error(case, path, line, "columns, found")


def test_missing_column(tmp_path):
    case = CASES[0]
    path = tmp_path / "bad.txt"
    line = write_case(path, case, lambda rows: rows[BAD_ROW].pop())
    expect_error(case, path, line, "expected 7 columns, found 6")


def test_non_numeric_field(case, tmp_path):
    path = tmp_path / "bad.txt"

    def corrupt(rows):
        rows[BAD_ROW][case.value_index] = "12.3abc"

    line = write_case(path, case, corrupt)
    err = expect_error(case, path, line, "expected a number, found '12.3abc'")
    assert f"column {case.value_index + 1}" in err.message


def test_nan_value(case, tmp_path):
    path = tmp_path / "bad.txt"

    def corrupt(rows):
        rows[BAD_ROW][case.value_index] = "nan"

    line = write_case(path, case, corrupt)
    expect_error(case, path, line, "expected a finite number")


def test_duplicate_time(case, tmp_path):
    path = tmp_path / "bad.txt"

    def corrupt(rows):
        rows[BAD_ROW][case.time_index] = rows[BAD_ROW - 1][case.time_index]

    line = write_case(path, case, corrupt)
    err = expect_error(case, path, line, "duplicate time stamp")
    assert f"line {line - 1}" in err.message


def test_decreasing_time(case, tmp_path):
    path = tmp_path / "bad.txt"

    def corrupt(rows):
        rows[BAD_ROW][case.time_index] = "99.000"

    line = write_case(path, case, corrupt)
    expect_error(case, path, line, "is earlier than")


def test_empty_file(case, tmp_path):
    path = tmp_path / "empty.txt"
    path.write_text("\n".join(case.header) + "\n\n")
    expect_error(case, path, None, "empty file")
    if case.read is read_rtklib_pos:  # a GNSS logger in a tunnel: what to do instead
        expect_error(case, path, None, "leaves [files.gnss] out of its survey.toml")


def test_missing_file(case, tmp_path):
    expect_error(case, tmp_path / "nowhere.txt", None, "file not found")


def test_line_numbers_count_comments_and_blank_lines(tmp_path):
    path = tmp_path / "imu.txt"
    good = "100.000 1e-5 2e-5 3e-5 1e-4 2e-4 -0.049"
    path.write_text(f"# a\n\n% b\n{good}\n\n# c\n100.005 1e-5 2e-5\n")
    with pytest.raises(InputError) as info:
        read_imu_kfgins(path)
    assert info.value.line == 7
    assert "expected 7 columns, found 3" in info.value.message


def test_imu_file_holding_accelerations_is_refused(tmp_path):
    path = tmp_path / "rates.txt"
    rows = [f"{100 + 0.005 * i:.3f} 0.001 0.002 0.003 0.1 0.2 -9.8" for i in range(10)]
    path.write_text("\n".join(rows) + "\n")
    with pytest.raises(InputError, match="accelerations"):
        read_imu_kfgins(path)


def test_pulses_without_pulse_length(tmp_path):
    path = tmp_path / "odo.txt"
    path.write_text("1.0 10\n2.0 20\n")
    with pytest.raises(InputError, match="pulse length unknown"):
        read_odometer_pulses(path)
    assert read_odometer_pulses(path, pulse_length_m=0.002).distance_m[-1] == pytest.approx(0.04)


def test_fractional_pulse_count(tmp_path):
    path = tmp_path / "odo.txt"
    path.write_text("# pulse_length_m = 0.001\n1.0 10\n2.0 20.5\n")
    with pytest.raises(InputError) as info:
        read_odometer_pulses(path)
    assert info.value.line == 3 and "expected an integer" in info.value.message


def test_gauge_in_metres_is_refused(tmp_path):
    path = tmp_path / "gauge.txt"
    path.write_text("1.0 1.435\n2.0 1.436\n")
    with pytest.raises(InputError, match="metres"):
        read_gauge_mm(path)


def test_latitude_out_of_range(tmp_path):
    path = tmp_path / "gnss.txt"
    path.write_text("1.0 30.5 114.3 20 0.01 0.01 0.02\n2.0 95.0 114.3 20 0.01 0.01 0.02\n")
    with pytest.raises(InputError) as info:
        read_gnss_kfgins(path)
    assert info.value.line == 2 and "latitude" in info.value.message


def test_pos_in_ecef_form_is_refused(tmp_path):
    path = tmp_path / "x.pos"
    path.write_text("%  GPST x-ecef(m) y-ecef(m) z-ecef(m) Q ns\n2381 100.0 1 2 3 1 5\n")
    with pytest.raises(InputError, match="not supported"):
        read_rtklib_pos(path)


def _write_npy(path: Path, time_s, dtheta=None) -> None:
    records = np.zeros(len(time_s), dtype=IMU_NPY_DTYPE)
    records["time_s"] = time_s
    if dtheta is not None:
        records["dtheta_rad"] = dtheta
    np.save(path, records)


def test_npy_errors_name_the_record_index(tmp_path):
    path = tmp_path / "imu.npy"
    _write_npy(path, [1.0, 2.0, 2.0, 3.0])
    with pytest.raises(InputError) as info:
        read_imu_npy(path)
    assert info.value.line == 2 and info.value.unit == "index"
    assert str(info.value).startswith(f"{path}, index 2: duplicate time stamp")

    dtheta = np.zeros((4, 3))
    dtheta[3, 1] = np.inf
    _write_npy(path, [1.0, 2.0, 3.0, 4.0], dtheta)
    with pytest.raises(InputError) as info:
        read_imu_npy(path)
    assert info.value.line == 3 and "dtheta_rad" in info.value.message


def test_npy_increments_are_those_checked_even_if_the_file_is_rewritten_or_cut(tmp_path):
    """The increments read_imu_npy returns (mapped, not held in memory) are a private copy of what it
    checked: rewriting the file in place, or cutting it, while a survey is processed changes nothing
    (a map of the file itself would show the new bytes, or fault on the cut pages)."""
    path = tmp_path / "imu.npy"
    time_s = 100.0 + 0.005 * np.arange(5000)
    dtheta = np.random.default_rng(1).normal(0.0, 1e-5, (len(time_s), 3))
    _write_npy(path, time_s, dtheta)
    imu = read_imu_npy(path)
    with open(path, "r+b") as handle:  # in place: the same inode, as a copy over the file does
        handle.seek(-len(time_s) * IMU_NPY_DTYPE.itemsize, 2)
        handle.write(np.ones(len(time_s), dtype=IMU_NPY_DTYPE).tobytes())
    assert np.array_equal(imu.dtheta_rad, dtheta) and not imu.dtheta_rad.flags.writeable
    with open(path, "r+b") as handle:
        handle.truncate(128)
    assert np.array_equal(imu.dtheta_rad[-10:], dtheta[-10:]) and np.all(imu.dvel_mps == 0.0)


def test_npy_with_wrong_fields(tmp_path):
    path = tmp_path / "imu.npy"
    np.save(path, np.zeros((4, 7)))
    with pytest.raises(InputError, match="structured array"):
        read_imu_npy(path)
    path.write_bytes(b"not numpy at all")
    with pytest.raises(InputError, match="not a readable NumPy"):
        read_imu_npy(path)


def test_both_comment_markers_anywhere(tmp_path):
    path = tmp_path / "imu.txt"
    good = "{:.3f} 1e-5 2e-5 3e-5 1e-4 2e-4 -0.049"
    path.write_text("# header\n" + good.format(100) + "\n% logger paused\n"
                    + good.format(100.005) + " # trailing note\n" + good.format(100.010) + " % another\n")
    imu = read_imu_kfgins(path)
    np.testing.assert_allclose(imu.time_s, [100.0, 100.005, 100.010])
