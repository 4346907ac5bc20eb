"""Initial alignment and stop detection.

Static coarse alignment (thesis 5.3.1.1): levelling from the mean specific force, then
gyrocompassing from the mean angular rate. With a navigation-grade gyro (0.01 deg/h) and
a few minutes at rest the heading comes out to about 0.05 deg; the filter refines it.

Stops are found where the IMU is quiet (thresholds from the IMU profile's noise, never below
what a pushed trolley shows) and the odometer, or without one the positions, do not move; the
ZUPT measurement and the static alignment use them. Which start-up a survey gets (static,
track, given heading): :mod:`insrail.nav.startup`.
"""

from __future__ import annotations

import numpy as np

from insrail.io.imu import release_pages
from insrail.io.types import ImuIncrements, OdometerData
from insrail.nav import earth


#: standard gravity [m/s^2]; normal gravity on the earth's surface lies within it -0.03/+0.03 (9.78 at
#: the equator to 9.83 at the poles, less 3e-6 per metre of height)
GRAVITY_MPS2 = 9.80665
GRAVITY_SPREAD_MPS2 = 0.03
#: the accelerometer bias is allowed this many of its 1-sigma along gravity
GRAVITY_BIAS_SIGMAS = 3.0
#: whatever the profile, a mean specific force at rest within this of standard gravity is gravity
#: (the window insrail always accepted, 9.7-9.9 m/s^2)
GRAVITY_FLOOR_MPS2 = 0.1


def gravity_tolerance_mps2(profile) -> float:
    """How far [m/s^2] the mean specific force at rest may lie from standard gravity with the IMU
    ``profile``'s accelerometers (:class:`insrail.nav.imu_profile.ImuProfile`): the spread of normal
    gravity plus GRAVITY_BIAS_SIGMAS x the bias's 1-sigma (turn-on and in-run together), never less
    than GRAVITY_FLOOR_MPS2. A MEMS unit 14 mg off is within what its profile says; an accelerometer
    read in g (1.0) or ft/s^2 (32.2) is far outside any."""
    bias = float(np.hypot(profile.accel_bias_turn_on, profile.accel_bias_gm_sigma))
    return max(GRAVITY_FLOOR_MPS2, GRAVITY_SPREAD_MPS2 + GRAVITY_BIAS_SIGMAS * bias)


def static_levelling(imu: ImuIncrements, start: int, stop: int, tolerance_mps2: float = GRAVITY_FLOOR_MPS2):
    """(roll, pitch [rad], mean specific force f^b [m/s^2], mean angular rate w^b [rad/s]) of
    the IMU samples ``start:stop`` at rest. Raises ValueError when the samples do not look
    static (the mean specific force is not gravity within ``tolerance_mps2``:
    :func:`gravity_tolerance_mps2` of the IMU's profile)."""
    if stop - start < 10:
        raise ValueError("static alignment needs at least 10 IMU samples at rest")
    span = imu.time_s[stop - 1] - imu.time_s[start] + (imu.time_s[start] - imu.time_s[start - 1] if start > 0 else 0.0)
    f = imu.dvel_mps[start:stop].sum(axis=0) / span
    w = imu.dtheta_rad[start:stop].sum(axis=0) / span
    g = np.linalg.norm(f)
    if not abs(g - GRAVITY_MPS2) < tolerance_mps2:
        raise ValueError(f"static alignment: mean specific force {g:.4f} m/s^2 over "
                         f"{imu.time_s[start]:.3f}-{imu.time_s[stop - 1]:.3f} s is not gravity "
                         f"({GRAVITY_MPS2 - tolerance_mps2:.3f}-{GRAVITY_MPS2 + tolerance_mps2:.3f} m/s^2 with the IMU "
                         "profile's accelerometer bias); is the trolley at rest, are the accelerometers in another "
                         "unit, or is the IMU profile's bias too small for this unit?")
    roll = np.arctan2(-f[1], -f[2])
    pitch = np.arctan2(f[0], np.hypot(f[1], f[2]))
    return float(roll), float(pitch), f, w


def gyrocompass(roll: float, pitch: float, w: np.ndarray, lat: float, ell: earth.Ellipsoid = earth.WGS84) -> float:
    """Heading [rad] of b from the mean angular rate ``w`` at rest, levelled by roll and pitch.

    The level frame l is b rotated back by roll and pitch (C_b^l = Ry(pitch) Rx(roll)); in
    it the earth rate is (w cos(lat) cos(heading), -w cos(lat) sin(heading), -w sin(lat)).
    Raises ValueError when the horizontal earth rate is implausible (the gyros cannot
    resolve it, or the trolley moved).
    """
    cr, sr, cp, sp = np.cos(roll), np.sin(roll), np.cos(pitch), np.sin(pitch)
    w_level = np.array(
        [cp * w[0] + sp * sr * w[1] + sp * cr * w[2], cr * w[1] - sr * w[2], -sp * w[0] + cp * sr * w[1] + cp * cr * w[2]]
    )
    horizontal = np.hypot(w_level[0], w_level[1])
    expected = ell.omega * np.cos(lat)
    if not 0.5 * expected < horizontal < 1.5 * expected:
        raise ValueError(
            f"static alignment: horizontal earth rate {horizontal:.3e} rad/s, expected {expected:.3e}; "
            "the gyros cannot find north (tactical-grade or MEMS IMU, or motion)"
        )
    return float(np.arctan2(-w_level[1], w_level[0]))


def gyrocompass_sigma_rad(gyro_bias_radps: float, gyro_arw: float, duration_s: float, lat: float,
                          ell: earth.Ellipsoid = earth.WGS84) -> float:
    """1-sigma of a gyrocompass heading over ``duration_s`` at rest: the gyro bias and the angle
    random walk averaged over the stop, against the horizontal earth rate (pi when the error
    reaches the earth rate itself: no north at all)."""
    error = np.hypot(gyro_bias_radps, gyro_arw / np.sqrt(max(duration_s, 1e-3)))
    ratio = error / (ell.omega * np.cos(lat))
    return float(np.arctan(ratio)) if ratio < 0.5 else float(np.pi)


#: a pushed trolley rocks by far more than this [rad/s, m/s^2] (the floor of the stop thresholds)
STOP_GYRO_STD_FLOOR_RADPS = 2e-4
STOP_ACCEL_STD_FLOOR_MPS2 = 2e-3
#: the stop thresholds in units of the IMU's own noise per sample (a stop must not be missed
#: because a MEMS unit is noisier than the floor)
STOP_NOISE_FACTOR = 5.0


#: the specific force is averaged over blocks of this length [s] before its spread is taken
ACCEL_BLOCK_S = 0.05


def stop_thresholds(gyro_arw: float, accel_vrw: float, rate_hz: float) -> tuple[float, float]:
    """(gyro [rad/s], accelerometer [m/s^2]) standard deviation over the detection window below
    which the IMU counts as quiet: the larger of the trolley's floor and
    ``STOP_NOISE_FACTOR`` x the profile's white noise (ARW x sqrt(rate) per gyro sample, VRW /
    sqrt(ACCEL_BLOCK_S) per accelerometer block)."""
    return (max(STOP_GYRO_STD_FLOOR_RADPS, STOP_NOISE_FACTOR * gyro_arw * np.sqrt(rate_hz)),
            max(STOP_ACCEL_STD_FLOOR_MPS2, STOP_NOISE_FACTOR * accel_vrw / np.sqrt(ACCEL_BLOCK_S)))


#: The slowest rocking of a standing platform [Hz] the ZUPT's noise allows for: motion of acceleration
#: std a gives velocities of a / (2 pi f) at frequency f (an operator leaning on the handle, a hand's
#: sway); faster vibration moves the platform less for the same acceleration.
STOP_ROCKING_HZ = 0.5
STOP_MOTION_CHUNK_S = 5.0


def stop_motion_sigma(imu: ImuIncrements, stops, accel_vrw: float) -> np.ndarray:
    """Per stop [start, end] the 1-sigma velocity [m/s] of the motion the accelerometers show there
    beyond their white noise (``accel_vrw`` [m/s/sqrt(s)]): the noise of the zero-velocity update.

    The specific force is formed over blocks of ACCEL_BLOCK_S (a logger's jittering time stamps
    would otherwise pass for motion); per axis its variance over the stop, less the noise's
    variance over a block and less three times that variance's sampling spread (a perfectly still
    platform then shows none in 99.9 % of its axes), is the motion's; its acceleration std over
    2 pi STOP_ROCKING_HZ is the velocity. The variance is taken about the mean of each
    STOP_MOTION_CHUNK_S, so the in-run bias drifting over a long stop does not pass for motion.
    """
    step = np.diff(imu.time_s)
    nominal = float(np.median(step)) if len(step) else 1.0
    m = max(int(round(ACCEL_BLOCK_S / nominal)), 1)
    sigma = np.zeros(len(stops))
    for k, (t0, t1) in enumerate(stops):
        a, b = np.searchsorted(imu.time_s, [t0, t1])
        b = min(b, len(imu.time_s) - 1)
        blocks = (b - a) // m
        dv = imu.dvel_mps[a + 1 : a + 1 + blocks * m].reshape(blocks, m, 3).sum(axis=1)
        span = (imu.time_s[a + m : a + 1 + blocks * m : m] - imu.time_s[a : a + blocks * m : m])[:, None]
        f = dv / span
        chunk = np.arange(blocks) // max(int(round(STOP_MOTION_CHUNK_S / ACCEL_BLOCK_S)), 1)
        counts = np.bincount(chunk)
        f -= np.stack([np.bincount(chunk, f[:, a]) for a in range(3)], axis=1)[chunk] / counts[chunk, None]
        dof = blocks - len(counts)
        if dof < 2:
            continue
        noise = accel_vrw**2 / float(np.median(span))
        excess = np.sum(f**2, axis=0) / dof - noise * (1.0 + 3.0 * np.sqrt(2.0 / dof))
        sigma[k] = np.sqrt(np.sum(np.maximum(excess, 0.0))) / (2.0 * np.pi * STOP_ROCKING_HZ)
    return sigma


def _moving_std(values: np.ndarray, n_win: int) -> np.ndarray:
    kernel = np.ones(n_win) / n_win
    mean = np.convolve(values, kernel, mode="same")
    return np.sqrt(np.maximum(np.convolve(values**2, kernel, mode="same") - mean**2, 0.0))


def _still(imu: ImuIncrements, odometer, nominal, lo: int, first: int, stop: int, hi: int, window_s, max_speed_mps,
           max_gyro_std_radps, max_accel_std_mps2, positions) -> np.ndarray:
    """:func:`detect_stops`'s still flags of records first .. stop - 1, from records lo .. hi - 1."""
    time_s = imu.time_s[lo:hi]
    step = np.diff(imu.time_s[max(lo - 1, 0) : hi])
    dt = step if lo > 0 else np.concatenate([[nominal], step])  # a logger's jitter must not pass for motion
    n_win = max(int(round(window_s / nominal)), 2)
    rate = np.linalg.norm(imu.dtheta_rad[lo:hi], axis=1) / dt
    still = _moving_std(rate, n_win) < max_gyro_std_radps
    if max_accel_std_mps2 is not None:
        # Per axis (a gentle start changes the direction of f, not |f|), over blocks of
        # ACCEL_BLOCK_S: a logger's time stamps rounded to the millisecond make single-sample
        # rates jump by 10 % of gravity.
        m = max(int(round(ACCEL_BLOCK_S / nominal)), 1)
        kernel = np.ones(m)
        span = np.convolve(dt, kernel, mode="same")
        spread = np.sqrt(sum(_moving_std(np.convolve(imu.dvel_mps[lo:hi, a], kernel, mode="same") / span, n_win) ** 2
                             for a in range(3)))
        still &= spread < max_accel_std_mps2

    still &= aiding_still(time_s, window_s, odometer, positions, max_speed_mps)
    release_pages(imu.dtheta_rad, imu.dvel_mps)  # a mapped file's pages behind the chunk
    return still[first - lo : stop - lo]


def aiding_still(time_s: np.ndarray, window_s: float, odometer: OdometerData | None,
                 positions: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
                 max_speed_mps: float = 0.002) -> np.ndarray:
    """Per time [s] whether the aiding lets the platform stand still over ``window_s`` around it:
    with an odometer, it moved less than ``max_speed_mps * window_s`` (not still where the odometer
    does not cover the window); without one, the ``positions`` (time [s], horizontal local positions
    (n, 2) [m], their 1-sigma (n,) [m]) moved by no more than three times their noise plus that
    (still where they do not cover the window: the IMU decides alone there); all still without either."""
    half = 0.5 * window_s
    if odometer is not None:
        d_ahead = np.interp(time_s + half, odometer.time_s, odometer.distance_m)
        d_behind = np.interp(time_s - half, odometer.time_s, odometer.distance_m)
        return ((np.abs(d_ahead - d_behind) < max_speed_mps * window_s)
                & (time_s - half >= odometer.time_s[0]) & (time_s + half <= odometer.time_s[-1]))
    if positions is not None and len(positions[0]) > 1:
        t_pos, ne, sigma = positions
        ahead = np.column_stack([np.interp(time_s + half, t_pos, ne[:, a]) for a in range(2)])
        behind = np.column_stack([np.interp(time_s - half, t_pos, ne[:, a]) for a in range(2)])
        noise = np.interp(time_s, t_pos, sigma)
        covered = (time_s - half >= t_pos[0]) & (time_s + half <= t_pos[-1])
        return ~covered | (np.hypot(*(ahead - behind).T) < 3.0 * np.sqrt(2.0) * noise + max_speed_mps * window_s)
    return np.ones(len(time_s), dtype=bool)


def stop_with_moving_fixes(stops, positions: tuple[np.ndarray, np.ndarray, np.ndarray]
                           ) -> tuple[float, float, float] | None:
    """The first stop (start [s], end [s], the fixes' largest move within it [m]) within which the
    ``positions`` (time [s], horizontal local positions (n, 2) [m], their 1-sigma (n,) [m]) move by
    more than three times their noise: the trolley moved during what the IMU took for a stop. None
    if there is none. Sparse fixes (a total station's, taken at the trolley's stops) cannot say when
    it moved between them, so they do not veto in :func:`detect_stops`; they do show that an IMU too
    noisy to see a pushed trolley's motion has taken a run for a stop."""
    t_pos, ne, sigma = positions
    for t0, t1 in stops:
        inside = np.flatnonzero((t_pos >= t0) & (t_pos <= t1))
        if inside.size < 2:
            continue
        move = np.hypot(*(ne[inside] - ne[inside[0]]).T)
        noise = 3.0 * np.hypot(sigma[inside], sigma[inside[0]])
        if np.any(move > noise):
            return float(t0), float(t1), float(np.max(move))
    return None


def detect_stops(
    imu: ImuIncrements,
    odometer: OdometerData | None,
    window_s: float = 1.0,
    max_speed_mps: float = 0.002,
    max_gyro_std_radps: float = STOP_GYRO_STD_FLOOR_RADPS,
    min_duration_s: float = 2.0,
    max_accel_std_mps2: float | None = None,
    positions: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None,
    chunk: int = 1 << 18,
) -> list[tuple[float, float]]:
    """Intervals [start, end] [s] where the trolley stands still.

    Still = the IMU is quiet (the gyro rate's standard deviation over the window around a
    sample below ``max_gyro_std_radps``: a pushed trolley rocks by far more; with
    ``max_accel_std_mps2`` also the specific force vector's, whose direction changes as soon as
    the trolley accelerates) AND, with an odometer, it moved less than
    ``max_speed_mps * window_s`` within the window. Without an odometer ``positions`` (time [s],
    horizontal local positions (n, 2) [m], their 1-sigma (n,) [m]), when given, must not move
    by more than three times their noise over the window either; the IMU decides alone where
    there are none. Intervals shorter than ``min_duration_s`` are dropped; the ends are pulled in
    by half a window so no moving sample is declared still. The thresholds of an IMU class:
    :func:`stop_thresholds`. ``chunk`` records are judged at a time (memory bounded for any
    length; the result does not depend on it).
    """
    nominal = np.median(np.diff(imu.time_s), overwrite_input=True)
    n = len(imu.time_s)
    # a chunk of records at a time, each with the records its windows reach on either side
    margin = 2 * max(int(round(window_s / nominal)), 2) + 2 * max(int(round(ACCEL_BLOCK_S / nominal)), 1)
    still = np.concatenate([_still(imu, odometer, nominal, max(first - margin, 0), first, min(first + chunk, n),
                                   min(first + chunk + margin, n), window_s, max_speed_mps, max_gyro_std_radps,
                                   max_accel_std_mps2, positions)
                            for first in range(0, n, chunk)])
    half = 0.5 * window_s

    edges = np.diff(still.astype(np.int8), prepend=0, append=0)
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1
    intervals = []
    for a, b in zip(starts, ends):
        t0, t1 = imu.time_s[a] + half, imu.time_s[b] - half
        if t1 - t0 >= min_duration_s:
            intervals.append((float(t0), float(t1)))
    return intervals
