"""The fused trajectory: what ``insrail.nav`` hands to ``insrail.track``.

Position, velocity and attitude of the IMU centre with their 1-sigma, at the IMU rate
or decimated, plus the estimated sensor errors and the odometer scale. Attitude is of
the IMU body frame b relative to NED; the trolley frame follows with the mounting
angles of the survey's trolley geometry.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


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
    ellipsoid_name: str = "WGS84"
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


def save_trajectory(path, trajectory: Trajectory) -> None:
    """Write ``trajectory.npy`` (TRAJECTORY_DTYPE records), atomically."""
    from insrail.io.atomic import atomic_write

    records = np.empty(len(trajectory), dtype=TRAJECTORY_DTYPE)
    for name in TRAJECTORY_DTYPE.names:
        records[name] = getattr(trajectory, name)
    with atomic_write(path, "wb") as handle:
        np.save(handle, records, allow_pickle=False)


def load_trajectory(path, smoothed: bool = True, gps_week: int | None = None) -> Trajectory:
    """Read a ``trajectory.npy`` written by :func:`save_trajectory`."""
    records = np.load(path, allow_pickle=False)
    if records.dtype != TRAJECTORY_DTYPE:
        raise ValueError(f"{path}: not an insrail trajectory file (record layout {records.dtype})")
    return Trajectory(**{name: np.ascontiguousarray(records[name]) for name in TRAJECTORY_DTYPE.names},
                      smoothed=smoothed, gps_week=gps_week)


def write_kfgins_nav(path, trajectory: Trajectory) -> None:
    """KF-GINS navigation result (11 columns: week, sow, lat, lon [deg], h [m], vN vE vD [m/s],
    roll pitch yaw [deg]); yaw in [0, 360)."""
    from insrail.io.textparse import write_numeric_table

    deg = np.rad2deg
    week = np.full(len(trajectory), trajectory.gps_week or 0, dtype=float)
    yaw = np.mod(deg(trajectory.rpy_rad[:, 2]), 360.0)
    write_numeric_table(
        path,
        [week, trajectory.time_s, deg(trajectory.lat_rad), deg(trajectory.lon_rad), trajectory.height_m,
         *trajectory.vel_ned_mps.T, deg(trajectory.rpy_rad[:, 0]), deg(trajectory.rpy_rad[:, 1]), yaw],
        ["%.0f", "%.6f", "%.11f", "%.11f", "%.5f", "%.6f", "%.6f", "%.6f", "%.7f", "%.7f", "%.7f"],
        ["format: kfgins-nav (insrail trajectory of the IMU centre)",
         "columns: week sow[s] lat[deg] lon[deg] h[m, ellipsoidal] vN vE vD[m/s] roll pitch yaw[deg]"],
    )


def write_kfgins_std(path, trajectory: Trajectory) -> None:
    """1-sigma of the trajectory, KF-GINS STD layout restricted to position, velocity, attitude:
    sow, sigma N E D [m], sigma vN vE vD [m/s], sigma roll pitch yaw [deg]."""
    from insrail.io.textparse import write_numeric_table

    write_numeric_table(
        path,
        [trajectory.time_s, *trajectory.sigma_pos_ned_m.T, *trajectory.sigma_vel_ned_mps.T, *np.rad2deg(trajectory.sigma_rpy_rad).T],
        ["%.6f"] + ["%.6f"] * 6 + ["%.7f"] * 3,
        ["format: kfgins-std (1-sigma)", "columns: sow[s] sN sE sD[m] svN svE svD[m/s] sroll spitch syaw[deg]"],
    )


def write_kfgins_imu_errors(path, trajectory: Trajectory) -> None:
    """Estimated sensor errors, KF-GINS IMU_ERR layout plus the odometer scale: sow, gyro bias
    [deg/h] x3, accel bias [mGal] x3, gyro scale [ppm] x3, accel scale [ppm] x3, odometer scale [ppm]."""
    from insrail.io.textparse import write_numeric_table

    write_numeric_table(
        path,
        [trajectory.time_s, *(np.rad2deg(trajectory.gyro_bias_radps) * 3600.0).T, *(trajectory.accel_bias_mps2 * 1e5).T,
         *(trajectory.gyro_scale * 1e6).T, *(trajectory.accel_scale * 1e6).T, trajectory.odometer_scale * 1e6],
        ["%.6f"] + ["%.5f"] * 13,
        ["format: kfgins-imu-err (estimated sensor errors)",
         "columns: sow[s] bgx bgy bgz[deg/h] bax bay baz[mGal] sgx sgy sgz[ppm] sax say saz[ppm] odometer_scale[ppm]"],
    )
