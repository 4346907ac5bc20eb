"""IMU readers and writers: KF-GINS increment text, the binary .npy table, foreign rate CSVs.

All return :class:`~insrail.io.types.ImuIncrements`: angle and velocity increments
over the interval ending at each time stamp, body frame forward-right-down.
"""

from __future__ import annotations

import mmap
import tempfile
from collections.abc import Callable
from pathlib import Path

import numpy as np

from insrail.io.atomic import named_write, save_npy
from insrail.io.errors import InputError
from insrail.io.textparse import (
    check_table_time,
    check_time_order,
    find_gaps,
    header_gps_week,
    read_numeric_table,
    write_numeric_table,
)
from insrail.io.timescale import unix_gpst_to_week_seconds
from insrail.io.timetag import TimeTag, read_time_tag
from insrail.io.types import GAP_FACTOR, ImuIncrements

STANDARD_GRAVITY_MPS2 = 9.80665
KFGINS_IMU_COLUMNS = ("t", "dtheta_x", "dtheta_y", "dtheta_z", "dvel_x", "dvel_y", "dvel_z")
IMU_NPY_DTYPE = np.dtype([("time_s", "<f8"), ("dtheta_rad", "<f8", (3,)), ("dvel_mps", "<f8", (3,))])

# A file of rates or accelerations read as increments shows up as absurd implied rates:
# 10 g of median specific force or 20 rad/s of median turn rate is no trolley.
_MAX_MEDIAN_SPECIFIC_FORCE_MPS2 = 10 * STANDARD_GRAVITY_MPS2
_MAX_MEDIAN_TURN_RATE_RADPS = 20.0


def _norms(increments: np.ndarray) -> np.ndarray:
    """The norm of each (3,) increment, without (n, 3) temporaries."""
    return np.sqrt(np.einsum("ij,ij->i", increments, increments))


def _check_increment_magnitudes(path: Path, time_s: np.ndarray, dtheta_norm: np.ndarray,
                                dvel_norm: np.ndarray) -> None:
    """Refuse files that hold rates (rad/s, m/s^2) where increments are expected (from the
    increments' norms, :func:`_norms`)."""
    if len(time_s) < 2:
        return
    interval = float(np.median(np.diff(time_s), overwrite_input=True))
    specific_force = float(np.median(dvel_norm, overwrite_input=True)) / interval
    turn_rate = float(np.median(dtheta_norm, overwrite_input=True)) / interval
    if specific_force > _MAX_MEDIAN_SPECIFIC_FORCE_MPS2:
        raise InputError(path, None, "velocity increments imply a median specific force of "
                         "{specific_force:.0f} m/s^2 at {rate_hz:.0f} Hz: the file seems to hold "
                         "accelerations (m/s^2), expected velocity increments (m/s)", fields={"specific_force": specific_force, "rate_hz": 1 / interval})
    if turn_rate > _MAX_MEDIAN_TURN_RATE_RADPS:
        raise InputError(path, None, "angle increments imply a median turn rate of {turn_rate:.0f} "
                         "rad/s at {rate_hz:.0f} Hz: the file seems to hold angular rates, "
                         "expected angle increments (rad)", fields={"turn_rate": turn_rate, "rate_hz": 1 / interval})


def read_imu_kfgins(path: str | Path) -> ImuIncrements:
    """KF-GINS IMU text: ``t dtheta_x dtheta_y dtheta_z [rad] dvel_x dvel_y dvel_z [m/s]``.

    t is GPS seconds of week at the end of each increment interval; body FRD. A
    ``# gps_week = N`` comment line sets :attr:`ImuIncrements.gps_week`.
    """
    table = read_numeric_table(path, columns=(7,), column_names=KFGINS_IMU_COLUMNS)
    time_s = check_table_time(table)
    dtheta, dvel = table.values[:, 1:4], table.values[:, 4:7]
    _check_increment_magnitudes(table.path, time_s, _norms(dtheta), _norms(dvel))
    # the increments leave the parsed table for the copy read_imu_npy's make: a 10 km survey's
    # 100 MB table is not held beside the fusion, which reads a mapped copy in chunks
    with _IncrementsCopy(len(time_s)) as copy:
        for start in range(0, len(time_s), NPY_READ_CHUNK):
            copy.append(dtheta[start : start + NPY_READ_CHUNK], dvel[start : start + NPY_READ_CHUNK])
        increments = copy.copied()
    return ImuIncrements(time_s=np.ascontiguousarray(time_s), dtheta_rad=increments["dtheta_rad"],
                         dvel_mps=increments["dvel_mps"], gps_week=header_gps_week(table.path, table.comments),
                         gaps=find_gaps(time_s), source=table.path)


def write_imu_kfgins(path: str | Path, imu: ImuIncrements) -> None:
    """Write KF-GINS IMU text losslessly (increments %.16e; time to 1 ns), atomically."""
    header = ["format: kfgins-imu"]
    if imu.gps_week is not None:
        header.append(f"gps_week = {imu.gps_week}")
    header += ["columns: t[s of GPS week] dtheta_x dtheta_y dtheta_z [rad] dvel_x dvel_y dvel_z [m/s]",
               "increments over the interval ending at t, IMU body frame forward-right-down"]
    write_numeric_table(path, [imu.time_s, imu.dtheta_rad, imu.dvel_mps],
                        ["%.9f"] + ["%.16e"] * 6, header)


#: IMU records checked or copied at a time (a binary file's 14 MB)
NPY_READ_CHUNK = 1 << 18
#: an IMU record's increments above this size are copied to a file and mapped, not held in memory
#: (a 10 km survey's: 87 MB); below it a file costs more time than the memory it saves
MAPPED_ABOVE_BYTES = 32 << 20
#: the increments as the fusion reads them (the private copy _IncrementsCopy makes)
_INCREMENTS_DTYPE = np.dtype([("dtheta_rad", "<f8", (3,)), ("dvel_mps", "<f8", (3,))])


def release_pages(*arrays: np.ndarray) -> None:
    """Let the kernel drop the pages of a read-only file mapping behind ``arrays`` (views of the
    memory map :func:`read_imu_npy` returns): touched pages of a mapping count in the resident
    set until then. Arrays in memory are left alone."""
    mappings = {}
    for array in arrays:
        while array is not None:
            mapping = getattr(array, "_mmap", None)
            if mapping is not None:
                mappings[id(mapping)] = mapping
                break
            array = array.base
    advice = getattr(mmap, "MADV_DONTNEED", None)  # Linux and macOS; elsewhere the pages stay
    for mapping in mappings.values():
        if advice is not None:
            mapping.madvise(advice)


def _npy_header(path: Path, handle) -> tuple[tuple[int, ...], bool, np.dtype]:
    """(shape, Fortran order, dtype) of an .npy file, the handle left at its first record."""
    try:
        version = np.lib.format.read_magic(handle)
        read_header = np.lib.format.read_array_header_1_0 if version == (1, 0) else np.lib.format.read_array_header_2_0
        return read_header(handle)
    except (ValueError, OSError, EOFError) as exc:
        raise InputError(path, None, "not a readable NumPy .npy file ({exc})", fields={"exc": exc}) from None


def _imu_npy_layout(path: Path, handle) -> tuple[int, np.dtype]:
    """(records, dtype) of an IMU .npy file (see :func:`read_imu_npy`), the handle left at its first record."""
    shape, fortran, dtype = _npy_header(path, handle)
    expected = ", ".join(f"{name} {IMU_NPY_DTYPE.fields[name][0].str}" for name in IMU_NPY_DTYPE.names)
    if dtype.names is None or len(shape) != 1:
        raise InputError(path, None, "expected a 1-D structured array with fields {expected}, "
                         "found dtype {dtype} with shape {shape}", fields={"expected": expected, "dtype": dtype, "shape": str(shape)})
    for name in IMU_NPY_DTYPE.names:
        want = IMU_NPY_DTYPE.fields[name][0]
        have = dtype.fields.get(name)
        if have is None or have[0].shape != want.shape or have[0].base.kind != "f":
            raise InputError(path, None, "field {name!r}: expected {base} with shape {shape}; "
                             "the file's fields are {dtype}", fields={"name": name, "base": want.base, "shape": str(want.shape), "dtype": dtype})
    if shape[0] == 0:
        raise InputError(path, None, "empty file: no records")
    return shape[0], dtype


def scan_imu_npy(path: Path, each_block: Callable[[bytes], object]) -> None:
    """Refuse ``path`` by its header when it is not an IMU .npy, before any of its records is read;
    then hand its bytes to ``each_block`` (a cache key's hash), block by block."""
    with open(path, "rb") as handle:
        _imu_npy_layout(path, handle)
        handle.seek(0)
        for block in iter(lambda: handle.read(1 << 24), b""):
            each_block(block)


def read_imu_npy(path: str | Path) -> ImuIncrements:
    """Binary IMU increments: a .npy structured array with fields
    ``time_s`` (f8), ``dtheta_rad`` (f8, 3), ``dvel_mps`` (f8, 3), little-endian.

    Checked in chunks of NPY_READ_CHUNK records with plain reads. The times are held in memory;
    the increments (any float layout, as float64) are copied as they are checked into a private
    copy (:class:`_IncrementsCopy`: above MAPPED_ABOVE_BYTES a temporary file, already unlinked,
    mapped) and returned as read-only views of it: a large record is never held whole, and what the
    fusion reads is what was checked, even if the file is rewritten or cut while a survey is
    processed (a map of the file itself would then fault). Errors name the 0-based record index.
    """
    path = Path(path)
    if not path.exists():
        raise InputError(path, None, "file not found")
    with open(path, "rb") as handle:
        n, dtype = _imu_npy_layout(path, handle)

        def fail(index: int, message: str, fields: dict | None = None):
            raise InputError(path, index, message, unit="index", fields=fields)

        time_s = np.empty(n)
        norms = {"dtheta_rad": np.empty(n), "dvel_mps": np.empty(n)}
        with _IncrementsCopy(n) as copy:
            for start in range(0, n, NPY_READ_CHUNK):
                count = min(NPY_READ_CHUNK, n - start)
                records = np.fromfile(handle, dtype=dtype, count=count)
                if len(records) != count:
                    raise InputError(path, None, "the file ends after {read} of its {n} records", fields={"read": start + len(records), "n": n})
                checked = {}
                for name in IMU_NPY_DTYPE.names:
                    values = np.asarray(records[name], dtype=np.float64)
                    if name == "time_s":
                        time_s[start : start + count] = values
                    else:
                        norms[name][start : start + count] = _norms(values)
                        checked[name] = values
                    finite = np.isfinite(values.reshape(count, -1)).all(axis=1)
                    if not finite.all():
                        index = start + int(np.argmin(finite))
                        fail(index, "{name} is {value}: expected finite numbers", fields={"name": name, "value": values[index - start]})
                copy.append(checked["dtheta_rad"], checked["dvel_mps"])
            check_time_order(time_s, fail, unit="index", where=lambda index: index)
            _check_increment_magnitudes(path, time_s, norms["dtheta_rad"], norms["dvel_mps"])
            del norms
            increments = copy.copied()
    return ImuIncrements(time_s=time_s, dtheta_rad=increments["dtheta_rad"], dvel_mps=increments["dvel_mps"],
                         gaps=find_gaps(time_s), source=path)


class _IncrementsCopy:
    """The increments as checked, appended chunk by chunk to a private copy: for a record above
    :data:`MAPPED_ABOVE_BYTES` a temporary file (already unlinked), then mapped read-only, never held
    whole in memory; whoever reads the map in chunks lets the pages go behind the cursor
    (:func:`release_pages`; the fusion does). Either way what is read is what was checked, even if
    the survey's file is rewritten or cut meanwhile, in the same layout."""

    def __init__(self, records: int) -> None:
        self._records = records
        self._filled = 0
        self._file = None
        self._memory = None
        if records * _INCREMENTS_DTYPE.itemsize > MAPPED_ABOVE_BYTES:
            self._file = tempfile.TemporaryFile(prefix="insrail-imu-")
        else:
            self._memory = np.empty(records, dtype=_INCREMENTS_DTYPE)

    def __enter__(self) -> "_IncrementsCopy":
        return self

    def __exit__(self, *exc) -> None:
        if self._file is not None:
            self._file.close()  # the map made by copied() outlives the handle

    def append(self, dtheta_rad: np.ndarray, dvel_mps: np.ndarray) -> None:
        stop = self._filled + len(dtheta_rad)
        if self._memory is not None:
            self._memory["dtheta_rad"][self._filled : stop], self._memory["dvel_mps"][self._filled : stop] = dtheta_rad, dvel_mps
        else:
            chunk = np.empty(len(dtheta_rad), dtype=_INCREMENTS_DTYPE)
            chunk["dtheta_rad"], chunk["dvel_mps"] = dtheta_rad, dvel_mps
            # an unnamed file: said where it lies (a full disk names the folder to clear)
            named_write(f"{tempfile.gettempdir()} (the IMU record's temporary copy)", self._file.write,
                        memoryview(chunk).cast("B"))
        self._filled = stop

    def copied(self) -> np.ndarray:
        """The records appended (all ``records`` of them)."""
        assert self._filled == self._records
        if self._memory is not None:
            self._memory.flags.writeable = False  # as the map: what was checked stays so
            return self._memory
        self._file.flush()
        return np.memmap(self._file, dtype=_INCREMENTS_DTYPE, mode="r", shape=(self._records,))


def write_imu_npy(path: str | Path, imu: ImuIncrements) -> None:
    """Write the binary .npy IMU table (see :func:`read_imu_npy`), atomically."""
    records = np.empty(len(imu), dtype=IMU_NPY_DTYPE)
    records["time_s"] = imu.time_s
    records["dtheta_rad"] = imu.dtheta_rad
    records["dvel_mps"] = imu.dvel_mps
    save_npy(path, records)


TIME_SCALES = ("gps-sow", "unix-gpst", "rtklib-tag")
#: a logger's millisecond counter and the GPST span of its time tag agree far better than this
MAX_TAG_RATE_ERROR = 0.01
ACCEL_UNITS = {"m/s^2": 1.0, "g": STANDARD_GRAVITY_MPS2}
GYRO_UNITS = {"rad/s": 1.0, "deg/s": np.pi / 180.0}


def _whole_records(path: Path) -> str:
    """The file's text with a partial first and last record blanked (line numbers kept): a logger
    stream cut at the start and the end of the recording, not inside."""
    try:
        lines = path.read_text(encoding="utf-8", errors="replace").split("\n")
    except OSError as exc:
        raise InputError(path, None, "cannot be read: {reason}", fields={"reason": exc.strerror or exc}) from None
    filled = [i for i, line in enumerate(lines) if line.strip()]
    if len(filled) < 3:
        return "\n".join(lines)
    widths = [lines[i].count(",") for i in filled[1:21]]
    width = max(set(widths), key=widths.count)
    for i in (filled[0], filled[-1]):
        if lines[i].count(",") != width or lines[i].rstrip().endswith(","):
            lines[i] = ""
    return "\n".join(lines)


def on_time_tag(path: Path, tag: TimeTag, counter_ms: np.ndarray) -> tuple[int, np.ndarray]:
    """(GPS week, seconds of week) of a record stamped by its logger's millisecond counter: the
    counter stretched onto the GPST span of the time tag, its first record at the tag's start and its
    last at the tag's last write (the logger's crystal and the GNSS-disciplined host clock differ
    by a rate: 1.4e-4 on the walk_0827 record)."""
    counter_span_s = (float(counter_ms[-1]) - float(counter_ms[0])) / 1e3
    rate = tag.span_s / counter_span_s if counter_span_s > 0 else np.inf
    if not abs(rate - 1.0) <= MAX_TAG_RATE_ERROR:
        raise InputError(tag.path, None, "the time tag spans {span_s:.3f} s but the record {file} counts "
                         "{counter_span_s:.3f} s (time column in ms): not this record's tag, or the time column is not "
                         "the logger's millisecond counter", fields={"span_s": tag.span_s, "file": path.name, "counter_span_s": counter_span_s})
    week, start = unix_gpst_to_week_seconds(np.array([float(tag.start_unix_gpst_s)]))
    return week, start[0] + tag.start_fraction_s + (counter_ms - counter_ms[0]) / 1e3 * rate


def _choice(path: Path, option: str, value: str, allowed) -> None:
    if value not in allowed:
        raise InputError(path, None, "option {option} = {value!r}: expected one of {allowed}",
                         fields={"option": option, "value": value, "allowed": [repr(a) for a in allowed]})


def read_imu_rates_csv(path: str | Path, *, time_column: int = 0,
                       accel_columns: tuple[int, int, int] = (1, 2, 3),
                       gyro_columns: tuple[int, int, int] = (4, 5, 6),
                       time_scale: str = "gps-sow", accel_unit: str = "m/s^2",
                       gyro_unit: str = "rad/s",
                       sensor_rpy_deg: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> ImuIncrements:
    """Rates from a foreign logger (specific force and angular rate per sample) -> increments.

    Column indices are 0-based. time_scale "gps-sow": seconds of the GPS week;
    "unix-gpst": seconds counted like Unix time but on the GPST scale (converted to
    week + seconds of week); "rtklib-tag": the time column is the logger's millisecond counter
    (since power-up), put on GPST by the RTKLIB time tag ``<file>.tag`` beside the file
    (:func:`on_time_tag`), and a partial first or last line (the logging started or stopped
    inside a record) is left out. sensor_rpy_deg: roll, pitch, yaw [deg] of the sensor
    axes relative to the body FRD axes, ``C_s^b = Rz(yaw) Ry(pitch) Rx(roll)``, so
    ``f^b = C_s^b f^s``. Each output increment is the trapezoidal integral of the
    rates over the interval between consecutive samples, stamped at its end; the
    output has one sample fewer than the file. Across a dropout (an interval longer than
    1.5 x the median) the record after it holds the median interval at its own rates, so that
    the gap is bridged once, by the fusion (:mod:`insrail.nav.imu_gaps`).
    """
    path = Path(path)
    _choice(path, "time_scale", time_scale, TIME_SCALES)
    _choice(path, "accel_unit", accel_unit, ACCEL_UNITS)
    _choice(path, "gyro_unit", gyro_unit, GYRO_UNITS)
    wanted = {"time_column": [time_column], "accel_columns": list(accel_columns),
              "gyro_columns": list(gyro_columns)}
    for option, indices in wanted.items():
        if option != "time_column" and len(indices) != 3:
            raise InputError(path, None, "option {option}: expected 3 column indices, found {count}", fields={"option": option, "count": len(indices)})
    if len(sensor_rpy_deg) != 3:
        raise InputError(path, None, "option sensor_rpy_deg: expected 3 angles (roll, pitch, yaw)")

    tag = read_time_tag(path.with_name(path.name + ".tag")) if time_scale == "rtklib-tag" else None
    table = read_numeric_table(path, text=_whole_records(path) if tag is not None else None)
    width = table.values.shape[1]
    for option, indices in wanted.items():
        for index in indices:
            if not 0 <= int(index) < width:
                raise InputError(path, None, "option {option}: column index {index} does not exist, "
                                 "the file has {width} columns (indices 0 to {last})", fields={"option": option, "index": index, "width": width, "last": width - 1})
    stamps = check_table_time(table, time_column)
    if len(stamps) < 2:
        raise InputError(path, None, "need at least 2 samples to integrate rates into increments")
    if time_scale == "unix-gpst":
        gps_week, time_s = unix_gpst_to_week_seconds(stamps)
    elif tag is not None:
        gps_week, time_s = on_time_tag(path, tag, stamps)
    else:
        gps_week, time_s = None, stamps

    from scipy.spatial.transform import Rotation  # scipy.spatial (and scipy.sparse): only for rates files

    sensor_to_body = Rotation.from_euler("ZYX", np.asarray(sensor_rpy_deg, dtype=float)[::-1],
                                         degrees=True).as_matrix()
    specific_force = table.values[:, list(accel_columns)] * ACCEL_UNITS[accel_unit] @ sensor_to_body.T
    angular_rate = table.values[:, list(gyro_columns)] * GYRO_UNITS[gyro_unit] @ sensor_to_body.T
    interval = np.diff(time_s)
    dtheta = 0.5 * (angular_rate[1:] + angular_rate[:-1]) * interval[:, None]
    dvel = 0.5 * (specific_force[1:] + specific_force[:-1]) * interval[:, None]
    # Across a dropout the rates are not integrated: the record after it holds one nominal
    # interval at its own rates, as every IMU reader's gap contract says, and the fusion's
    # bridge_gaps fills the gap once (integrating here too would count the motion twice).
    nominal = float(np.median(interval))
    dropout = interval > GAP_FACTOR * nominal
    dtheta[dropout] = angular_rate[1:][dropout] * nominal
    dvel[dropout] = specific_force[1:][dropout] * nominal
    return ImuIncrements(
        time_s=time_s[1:].copy(),
        dtheta_rad=dtheta,
        dvel_mps=dvel,
        gps_week=gps_week,
        gaps=find_gaps(time_s),
        source=path,
    )
