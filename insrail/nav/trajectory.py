"""The fused trajectory: what ``insrail.nav`` hands to ``insrail.track``.

Position, velocity and attitude of the IMU centre with their 1-sigma, at the IMU rate
or decimated, plus the estimated sensor errors and the odometer scale. Attitude is of
the IMU body frame b relative to NED; the trolley frame follows with the mounting
angles of the survey's trolley geometry.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field

import numpy as np

from insrail.geodesy.ellipsoid import WGS84, Ellipsoid
from insrail.io.atomic import named_write, write_at


@dataclass(frozen=True)
class Trajectory:
    """Arrays of length n unless noted; sigma arrays have the same shape as their value."""

    time_s: np.ndarray
    lat_rad: np.ndarray
    lon_rad: np.ndarray
    height_m: np.ndarray
    vel_ned_mps: np.ndarray  # (n, 3)
    rpy_rad: np.ndarray  # (n, 3) roll, pitch, heading
    sigma_pos_ned_m: np.ndarray  # (n, 3)
    sigma_vel_ned_mps: np.ndarray  # (n, 3)
    sigma_rpy_rad: np.ndarray  # (n, 3)
    gyro_bias_radps: np.ndarray  # (n, 3) estimated sensor errors
    accel_bias_mps2: np.ndarray  # (n, 3)
    gyro_scale: np.ndarray  # (n, 3)
    accel_scale: np.ndarray  # (n, 3)
    odometer_scale: np.ndarray  # (n,) estimated scale-factor error of the odometer
    smoothed: bool = False
    gps_week: int | None = None
    ellipsoid: Ellipsoid = WGS84  #: the latitude, longitude and height are on it (a file does not say: its reader's)
    info: dict = field(default_factory=dict)

    def __len__(self) -> int:
        return len(self.time_s)


#: Binary layout of trajectory.npy: one structured record per epoch, SI units.
TRAJECTORY_DTYPE = np.dtype(
    [
        ("time_s", "f8"), ("lat_rad", "f8"), ("lon_rad", "f8"), ("height_m", "f8"),
        ("vel_ned_mps", "f8", (3,)), ("rpy_rad", "f8", (3,)),
        ("sigma_pos_ned_m", "f8", (3,)), ("sigma_vel_ned_mps", "f8", (3,)), ("sigma_rpy_rad", "f8", (3,)),
        ("gyro_bias_radps", "f8", (3,)), ("accel_bias_mps2", "f8", (3,)),
        ("gyro_scale", "f8", (3,)), ("accel_scale", "f8", (3,)), ("odometer_scale", "f8"),
    ]
)


#: records per block when a trajectory is written or converted to text
CHUNK_RECORDS = 100_000


def trajectory_from_records(records: np.ndarray, **kwargs) -> Trajectory:
    """A :class:`Trajectory` whose arrays are views of TRAJECTORY_DTYPE ``records`` (no copy)."""
    return Trajectory(**{name: records[name] for name in TRAJECTORY_DTYPE.names}, **kwargs)


class TrajectoryWriter:
    """Writes ``trajectory.npy`` (``n`` TRAJECTORY_DTYPE records) block by block as they are made,
    under a temporary name: :meth:`commit` puts it in place, :meth:`discard` (after a failure, or
    after commit: then a no-op) removes what was written. The file reads like any ``np.save``d one.
    The blocks are written one after the other, or each at its place (:meth:`write_at`: blocks made
    last first), not both."""

    def __init__(self, path, n: int):
        from pathlib import Path

        self.path = Path(path)
        self.tmp = self.path.with_name(f".{self.path.name}.partial")
        self.n, self.written = n, 0
        self.handle = open(self.tmp, "wb")
        named_write(self.path, np.lib.format.write_array_header_1_0, self.handle, {
            "descr": np.lib.format.dtype_to_descr(TRAJECTORY_DTYPE), "fortran_order": False, "shape": (n,)})
        named_write(self.path, self.handle.flush)
        self.header_bytes = self.handle.tell()

    def write(self, block: np.ndarray) -> None:
        if block.dtype != TRAJECTORY_DTYPE or self.written + len(block) > self.n:
            raise ValueError(f"{self.path}: expected at most {self.n - self.written} more trajectory records")
        named_write(self.path, self.handle.write, memoryview(np.ascontiguousarray(block)).cast("B"))
        self.written += len(block)

    def write_at(self, first: int, block: np.ndarray) -> None:
        """Records ``first`` .. ``first + len(block) - 1``; every record written once."""
        if block.dtype != TRAJECTORY_DTYPE or first < 0 or first + len(block) > self.n:
            raise ValueError(f"{self.path}: records {first}-{first + len(block) - 1} are not among its {self.n}")
        write_at(self.path, self.handle.fileno(), np.ascontiguousarray(block),
                 self.header_bytes + first * TRAJECTORY_DTYPE.itemsize)
        self.written += len(block)

    def commit(self) -> None:
        import os

        if self.written != self.n:
            raise ValueError(f"{self.path}: {self.written} of {self.n} trajectory records written")
        named_write(self.path, self.handle.flush)
        named_write(self.path, os.fsync, self.handle.fileno())
        named_write(self.path, self.handle.close)
        os.replace(self.tmp, self.path)

    def discard(self) -> None:
        if not self.handle.closed:
            self.handle.close()
        self.tmp.unlink(missing_ok=True)


def save_trajectory(path, trajectory: Trajectory) -> None:
    """Write ``trajectory.npy`` (TRAJECTORY_DTYPE records), atomically, in blocks."""
    writer = TrajectoryWriter(path, len(trajectory))
    try:
        for first in range(0, len(trajectory), CHUNK_RECORDS):
            part = slice(first, first + CHUNK_RECORDS)
            block = np.empty(len(trajectory.time_s[part]), dtype=TRAJECTORY_DTYPE)
            for name in TRAJECTORY_DTYPE.names:
                block[name] = getattr(trajectory, name)[part]
            writer.write(block)
        writer.commit()
    finally:
        writer.discard()


def load_trajectory(path, smoothed: bool = True, gps_week: int | None = None, mmap: bool = False,
                    only: tuple[str, ...] | None = None, start: int = 0, count: int | None = None) -> Trajectory:
    """Read a ``trajectory.npy`` written by :func:`save_trajectory`; ``mmap``: its arrays are
    read-only views of the file mapped into memory (read as they are used), not copies.
    ``only``: read just these fields (a consumer of a few of them, e.g. the track
    reconstruction's ``insrail.track.rails.POSE_FIELDS``: 13 of the 32 doubles per epoch); every
    other field is NaN, read-only and takes no memory. ``start``, ``count``: just these records
    (:func:`read_trajectory_fields`; not with ``mmap``)."""
    if mmap:
        records = np.load(path, allow_pickle=False, mmap_mode="r")
        if records.dtype != TRAJECTORY_DTYPE:
            raise ValueError(f"{path}: not an insrail trajectory file (record layout {records.dtype})")
        return trajectory_from_records(records, smoothed=smoothed, gps_week=gps_week)
    fields = read_trajectory_fields(path, TRAJECTORY_DTYPE.names if only is None else only, start=start, count=count)
    n = len(next(iter(fields.values())))
    absent = {name: np.broadcast_to(np.nan, (n, *TRAJECTORY_DTYPE[name].shape))
              for name in TRAJECTORY_DTYPE.names if name not in fields}
    return Trajectory(**fields, **absent, smoothed=smoothed, gps_week=gps_week)


def trajectory_records(path) -> int:
    """The number of records of a ``trajectory.npy`` (its header only is read)."""
    with open(path, "rb") as handle:
        return _trajectory_header(path, handle)


#: numpy parses a ``.npy`` header with ast.literal_eval, and CPython 3.11's parser is not safe in two threads at
#: once ("SystemError: AST constructor recursion depth mismatch": the track's threads read the trajectory by parts)
NPY_HEADER_LOCK = threading.Lock()


def _trajectory_header(path, handle) -> int:
    """Reads the ``.npy`` header of an open trajectory file; its record count."""
    version = np.lib.format.read_magic(handle)
    read_header = np.lib.format.read_array_header_1_0 if version == (1, 0) else np.lib.format.read_array_header_2_0
    with NPY_HEADER_LOCK:
        shape, fortran, dtype = read_header(handle)
    if dtype != TRAJECTORY_DTYPE or fortran or len(shape) != 1:
        raise ValueError(f"{path}: not an insrail trajectory file (record layout {dtype})")
    return shape[0]


def read_trajectory_fields(path, names, chunk: int = CHUNK_RECORDS, start: int = 0,
                           count: int | None = None) -> dict[str, np.ndarray]:
    """The named fields of a ``trajectory.npy`` (e.g. ``sigma_pos_ned_m``) as contiguous arrays,
    read a chunk of records at a time with plain reads: neither the whole file (0.26 kB per
    epoch, 0.55 GB for 10 km) nor a memory map of it ever counts towards the process's memory.
    ``start``, ``count``: only the records ``start`` .. ``start + count - 1`` (to the end when
    ``count`` is None)."""
    unknown = set(names) - set(TRAJECTORY_DTYPE.names)
    if unknown or not names:
        raise ValueError(f"not trajectory fields: {', '.join(sorted(unknown)) or 'none asked for'}")
    with open(path, "rb") as handle:
        records_in_file = _trajectory_header(path, handle)
        if not 0 <= start <= records_in_file:
            raise ValueError(f"{path}: record {start} asked for, the file has {records_in_file}")
        total = records_in_file - start if count is None else min(count, records_in_file - start)
        handle.seek(start * TRAJECTORY_DTYPE.itemsize, 1)
        out = {name: np.empty((total, *TRAJECTORY_DTYPE[name].shape)) for name in names}
        for first in range(0, total, chunk):
            records = np.fromfile(handle, dtype=TRAJECTORY_DTYPE, count=min(chunk, total - first))
            if len(records) != min(chunk, total - first):
                raise ValueError(f"{path}: the file ends after {start + first + len(records)} of its "
                                 f"{records_in_file} records")
            for name in names:
                out[name][first : first + len(records)] = records[name]
    return out


def _write_text_table(path, trajectory: Trajectory, columns, formats: list[str], header: list[str]) -> None:
    """A whitespace-separated table with '#' header lines, atomically, CHUNK_RECORDS rows at a
    time: ``columns(part)`` gives the columns of the rows of slice ``part`` of the trajectory,
    so a long survey's text never sits in memory whole."""
    from insrail.io.atomic import atomic_write

    row_format = " ".join(formats) + "\n"
    with atomic_write(path) as handle:
        for line in header:
            handle.write(f"# {line}\n")
        for first in range(0, len(trajectory), CHUNK_RECORDS):
            part = slice(first, first + CHUNK_RECORDS)
            block = np.column_stack([np.asarray(c, dtype=np.float64) for c in columns(part)])
            handle.write((row_format * len(block)) % tuple(block.ravel().tolist()))


def write_kfgins_nav(path, trajectory: Trajectory) -> None:
    """KF-GINS navigation result (11 columns: week, sow, lat, lon [deg], h [m], vN vE vD [m/s],
    roll pitch yaw [deg]); yaw in [0, 360)."""
    deg = np.rad2deg
    week = float(trajectory.gps_week or 0)
    t = trajectory

    def columns(part):
        rpy = np.asarray(t.rpy_rad[part])
        return [np.full(len(rpy), week), t.time_s[part], deg(t.lat_rad[part]), deg(t.lon_rad[part]), t.height_m[part],
                *np.asarray(t.vel_ned_mps[part]).T, deg(rpy[:, 0]), deg(rpy[:, 1]), np.mod(deg(rpy[:, 2]), 360.0)]

    _write_text_table(
        path, trajectory, columns,
        ["%.0f", "%.6f", "%.11f", "%.11f", "%.5f", "%.6f", "%.6f", "%.6f", "%.7f", "%.7f", "%.7f"],
        ["format: kfgins-nav (insrail trajectory of the IMU centre)",
         "columns: week sow[s] lat[deg] lon[deg] h[m, ellipsoidal] vN vE vD[m/s] roll pitch yaw[deg]"],
    )


def write_kfgins_std(path, trajectory: Trajectory) -> None:
    """1-sigma of the trajectory, KF-GINS STD layout restricted to position, velocity, attitude:
    sow, sigma N E D [m], sigma vN vE vD [m/s], sigma roll pitch yaw [deg]."""
    t = trajectory
    _write_text_table(
        path, trajectory,
        lambda part: [t.time_s[part], *np.asarray(t.sigma_pos_ned_m[part]).T, *np.asarray(t.sigma_vel_ned_mps[part]).T,
                      *np.rad2deg(t.sigma_rpy_rad[part]).T],
        ["%.6f"] + ["%.6f"] * 6 + ["%.7f"] * 3,
        ["format: kfgins-std (1-sigma)", "columns: sow[s] sN sE sD[m] svN svE svD[m/s] sroll spitch syaw[deg]"],
    )


def write_kfgins_imu_errors(path, trajectory: Trajectory) -> None:
    """Estimated sensor errors, KF-GINS IMU_ERR layout plus the odometer scale: sow, gyro bias
    [deg/h] x3, accel bias [mGal] x3, gyro scale [ppm] x3, accel scale [ppm] x3, odometer scale [ppm]."""
    t = trajectory
    _write_text_table(
        path, trajectory,
        lambda part: [t.time_s[part], *(np.rad2deg(t.gyro_bias_radps[part]) * 3600.0).T,
                      *(np.asarray(t.accel_bias_mps2[part]) * 1e5).T, *(np.asarray(t.gyro_scale[part]) * 1e6).T,
                      *(np.asarray(t.accel_scale[part]) * 1e6).T, np.asarray(t.odometer_scale[part]) * 1e6],
        ["%.6f"] + ["%.5f"] * 13,
        ["format: kfgins-imu-err (estimated sensor errors)",
         "columns: sow[s] bgx bgy bgz[deg/h] bax bay baz[mGal] sgx sgy sgz[ppm] sax say saz[ppm] odometer_scale[ppm]"],
    )
