"""Initial alignment and stop detection.

Static coarse alignment (thesis 5.3.1.1): levelling from the mean specific force, then
gyrocompassing from the mean angular rate. With a navigation-grade gyro (0.01 deg/h) and
a few minutes at rest the heading comes out to about 0.05 deg; the filter refines it.

Stops are found where the odometer does not move and the IMU is quiet; the ZUPT
measurement and the static alignment use them.
"""

from __future__ import annotations

import numpy as np

from insrail.io.types import ImuIncrements, OdometerData
from insrail.nav import earth


def coarse_alignment(imu: ImuIncrements, start: int, stop: int, lat: float, ell: earth.Ellipsoid = earth.WGS84):
    """(roll, pitch, heading) [rad] of b from the IMU samples ``start:stop`` at rest.

    The level frame l is b rotated back by roll and pitch (C_b^l = Ry(pitch) Rx(roll)); in
    it the earth rate is (w cos(lat) cos(heading), -w cos(lat) sin(heading), -w sin(lat)).
    Raises ValueError when the samples do not look static (gravity missing or the mean
    horizontal earth rate implausible), e.g. an alignment window that includes motion.
    """
    if stop - start < 10:
        raise ValueError("static alignment needs at least 10 IMU samples at rest")
    span = imu.time_s[stop - 1] - imu.time_s[start] + (imu.time_s[start] - imu.time_s[start - 1] if start > 0 else 0.0)
    f = imu.dvel_mps[start:stop].sum(axis=0) / span
    w = imu.dtheta_rad[start:stop].sum(axis=0) / span
    g = np.linalg.norm(f)
    if not 9.7 < g < 9.9:
        raise ValueError(f"static alignment: mean specific force {g:.4f} m/s^2 is not gravity; is the trolley at rest?")
    roll = np.arctan2(-f[1], -f[2])
    pitch = np.arctan2(f[0], np.hypot(f[1], f[2]))
    cr, sr, cp, sp = np.cos(roll), np.sin(roll), np.cos(pitch), np.sin(pitch)
    w_level = np.array(
        [cp * w[0] + sp * sr * w[1] + sp * cr * w[2], cr * w[1] - sr * w[2], -sp * w[0] + cp * sr * w[1] + cp * cr * w[2]]
    )
    horizontal = np.hypot(w_level[0], w_level[1])
    expected = ell.omega * np.cos(lat)
    if not 0.5 * expected < horizontal < 1.5 * expected:
        raise ValueError(
            f"static alignment: horizontal earth rate {horizontal:.3e} rad/s, expected {expected:.3e}; "
            "the gyros cannot find north (tactical-grade IMU or motion) - give the initial heading instead"
        )
    heading = np.arctan2(-w_level[1], w_level[0])
    return float(roll), float(pitch), float(heading)


def detect_stops(
    imu: ImuIncrements,
    odometer: OdometerData,
    window_s: float = 1.0,
    max_speed_mps: float = 0.002,
    max_gyro_std_radps: float = 2e-4,
    min_duration_s: float = 2.0,
) -> list[tuple[float, float]]:
    """Intervals [start, end] [s] where the trolley stands still.

    Still = the odometer moved less than ``max_speed_mps * window_s`` within the window
    around a sample AND the gyro rate's standard deviation over the window is below
    ``max_gyro_std_radps`` (a pushed trolley rocks by far more). Intervals shorter than
    ``min_duration_s`` are dropped; the ends are pulled in by half a window so no moving
    sample is declared still.
    """
    dt = np.median(np.diff(imu.time_s))
    n_win = max(int(round(window_s / dt)), 2)
    rate = np.linalg.norm(imu.dtheta_rad, axis=1) / dt
    kernel = np.ones(n_win) / n_win
    mean = np.convolve(rate, kernel, mode="same")
    var = np.maximum(np.convolve(rate**2, kernel, mode="same") - mean**2, 0.0)
    quiet = np.sqrt(var) < max_gyro_std_radps

    half = 0.5 * window_s
    d_ahead = np.interp(imu.time_s + half, odometer.time_s, odometer.distance_m)
    d_behind = np.interp(imu.time_s - half, odometer.time_s, odometer.distance_m)
    not_moving = np.abs(d_ahead - d_behind) < max_speed_mps * window_s
    inside = (imu.time_s - half >= odometer.time_s[0]) & (imu.time_s + half <= odometer.time_s[-1])
    still = quiet & not_moving & inside

    edges = np.diff(still.astype(np.int8), prepend=0, append=0)
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1
    intervals = []
    for a, b in zip(starts, ends):
        t0, t1 = imu.time_s[a] + half, imu.time_s[b] - half
        if t1 - t0 >= min_duration_s:
            intervals.append((float(t0), float(t1)))
    return intervals


def track_alignment(
    imu: ImuIncrements,
    gnss_time_s: np.ndarray,
    gnss_ned_m: np.ndarray,
    odometer: OdometerData,
    min_speed_mps: float = 0.2,
    min_distance_m: float = 10.0,
):
    """Initial attitude for a survey that starts moving: (GNSS epoch index, roll, pitch,
    heading) of the trolley frame.

    Heading and pitch are the direction of the GNSS track over the first
    ``min_distance_m`` of motion (10 m with 1 cm GNSS noise: about 0.1 deg); roll comes
    from the mean specific force over the same stretch (a walking trolley accelerates by
    a few cm/s^2: a few hundredths of a degree). ``gnss_ned_m`` are GNSS positions as
    local NED metres. Raises ValueError when the survey never moves far enough.
    """
    d_ahead = np.interp(gnss_time_s + 0.5, odometer.time_s, odometer.distance_m)
    d_behind = np.interp(gnss_time_s - 0.5, odometer.time_s, odometer.distance_m)
    moving = np.flatnonzero(np.abs(d_ahead - d_behind) > min_speed_mps)
    if moving.size == 0:
        raise ValueError("track alignment: the trolley never moves faster than "
                         f"{min_speed_mps} m/s (by the odometer)")
    i0 = int(moving[0])
    travelled = np.hypot(*(gnss_ned_m[i0:, :2] - gnss_ned_m[i0, :2]).T)
    far = np.flatnonzero(travelled >= min_distance_m)
    if far.size == 0:
        raise ValueError(f"track alignment: the GNSS track never leaves a {min_distance_m:.0f} m circle")
    i1 = i0 + int(far[0])
    d = gnss_ned_m[i1] - gnss_ned_m[i0]
    heading = np.arctan2(d[1], d[0])
    pitch = np.arctan2(-d[2], np.hypot(d[0], d[1]))
    k0, k1 = np.searchsorted(imu.time_s, gnss_time_s[[i0, i1]])
    f = imu.dvel_mps[k0:k1].sum(axis=0)
    roll = np.arctan2(-f[1], -f[2])
    return i0, float(roll), float(pitch), float(heading)
