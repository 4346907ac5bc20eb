"""Sensor error models of the simulator: IMU, GNSS, odometer, gauge, sleeper detector.

Each function takes the truth and a random generator and returns what the sensor
reports, plus the realised errors where the truth output records them.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from insrail.nav.imu_profile import ImuProfile


def gauss_markov(rng: np.random.Generator, n: int, dt: float, sigma, tau_s: float) -> np.ndarray:
    """Stationary first-order Gauss-Markov sequences, shape (n, len(sigma)).

    x_k = phi x_{k-1} + sigma sqrt(1 - phi^2) w_k with phi = exp(-dt/tau): the exact
    discretisation (its variance stays sigma^2 at every step).
    """
    # imported here: scipy.signal pulls in scipy.stats (about a second) that other commands never use
    from scipy.signal import lfilter

    sigma = np.atleast_1d(np.asarray(sigma, dtype=float))
    out = np.zeros((n, sigma.size))
    if n == 0 or not np.any(sigma > 0):
        return out
    phi = np.exp(-dt / tau_s)
    drive = np.sqrt(1.0 - phi**2)
    for j, sj in enumerate(sigma):
        if sj > 0:
            w = rng.standard_normal(n)
            x0 = rng.standard_normal() * sj
            out[:, j], _ = lfilter([sj * drive], [1.0, -phi], w, zi=[phi * x0])
    return out


@dataclass(frozen=True)
class ImuErrors:
    """The realised IMU errors of one run (SI units)."""

    gyro_bias_turn_on: np.ndarray  # (3,) rad/s
    accel_bias_turn_on: np.ndarray  # (3,) m/s^2
    gyro_scale_factor: np.ndarray  # (3,)
    accel_scale_factor: np.ndarray  # (3,)
    gyro_bias_gm: np.ndarray  # (n, 3) rad/s, in-run part
    accel_bias_gm: np.ndarray  # (n, 3) m/s^2


def draw_imu_errors(rng: np.random.Generator, profile: ImuProfile, n: int, dt: float) -> ImuErrors:
    return ImuErrors(
        gyro_bias_turn_on=rng.standard_normal(3) * profile.gyro_bias_turn_on,
        accel_bias_turn_on=rng.standard_normal(3) * profile.accel_bias_turn_on,
        gyro_scale_factor=rng.standard_normal(3) * profile.gyro_scale_factor,
        accel_scale_factor=rng.standard_normal(3) * profile.accel_scale_factor,
        gyro_bias_gm=gauss_markov(rng, n, dt, [profile.gyro_bias_gm_sigma] * 3, profile.gyro_bias_gm_tau_s),
        accel_bias_gm=gauss_markov(rng, n, dt, [profile.accel_bias_gm_sigma] * 3, profile.accel_bias_gm_tau_s),
    )


def corrupt_increments(
    rng: np.random.Generator,
    profile: ImuProfile,
    errors: ImuErrors,
    index: slice,
    dt: np.ndarray,
    dtheta: np.ndarray,
    dvel: np.ndarray,
):
    """Measured increments for the epochs ``index`` of the run (errors model of thesis 2.24-2.25):
    measured = (1 + scale) * true + bias * dt + white noise integrated over dt."""
    sqrt_dt = np.sqrt(dt)[:, None]
    gyro_bias = errors.gyro_bias_turn_on + errors.gyro_bias_gm[index]
    accel_bias = errors.accel_bias_turn_on + errors.accel_bias_gm[index]
    dtheta_m = (1.0 + errors.gyro_scale_factor) * dtheta + gyro_bias * dt[:, None]
    dvel_m = (1.0 + errors.accel_scale_factor) * dvel + accel_bias * dt[:, None]
    dtheta_m += rng.standard_normal(dtheta.shape) * profile.gyro_arw * sqrt_dt
    dvel_m += rng.standard_normal(dvel.shape) * profile.accel_vrw * sqrt_dt
    return dtheta_m, dvel_m


def in_intervals(t: np.ndarray, intervals: list[tuple[float, float]]) -> np.ndarray:
    """Mask of times inside any [start, end) interval."""
    mask = np.zeros(t.shape, dtype=bool)
    for start, end in intervals:
        mask |= (t >= start) & (t < end)
    return mask


def quantise(value: np.ndarray, step: float) -> np.ndarray:
    """Round down to whole steps, as a counter or an ADC does."""
    return np.floor(value / step) * step if step > 0 else value


def sleeper_pulse_times(
    rng: np.random.Generator,
    pass_time_s: np.ndarray,
    missed_fraction: float,
    false_fraction: float,
    jitter_s: float,
):
    """Detector pulse times from the true passing times: some missed, some false, jittered.

    Returns (pulse times sorted, detected mask over the true sleepers, false pulse times).
    """
    n = len(pass_time_s)
    detected = rng.uniform(size=n) >= missed_fraction
    n_false = rng.binomial(n, false_fraction) if n else 0
    # False pulses (ballast, cables, welds) fall between sleepers while the trolley moves.
    between = rng.integers(0, max(n - 1, 1), n_false)
    frac = rng.uniform(0.2, 0.8, n_false)
    false_times = pass_time_s[between] + frac * (pass_time_s[np.minimum(between + 1, n - 1)] - pass_time_s[between])
    times = np.concatenate([pass_time_s[detected], false_times]) + rng.normal(0.0, jitter_s, detected.sum() + n_false)
    return np.sort(times), detected, np.sort(false_times)
