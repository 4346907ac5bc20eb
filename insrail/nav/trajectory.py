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
