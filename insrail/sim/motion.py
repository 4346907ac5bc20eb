"""Station as a function of time: the trolley's speed profile.

The speed is piecewise: constant pieces and smooth transitions between two speeds
with the "smootherstep" S(x) = 6x^5 - 15x^4 + 10x^3, whose first and second
derivatives vanish at both ends, so speed, acceleration and jerk are continuous.
Station, speed and acceleration are evaluated in closed form.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class SpeedProfile:
    """Pieces of the speed profile; piece i starts at ``start_time_s[i]`` at station
    ``start_station_m[i]`` and lasts ``duration_s[i]``, moving speed from
    ``speed_from_mps[i]`` to ``speed_to_mps[i]`` (equal for a constant piece)."""

    start_time_s: np.ndarray
    duration_s: np.ndarray
    start_station_m: np.ndarray
    speed_from_mps: np.ndarray
    speed_to_mps: np.ndarray

    @property
    def end_time_s(self) -> float:
        return float(self.start_time_s[-1] + self.duration_s[-1])

    @property
    def end_station_m(self) -> float:
        return float(self.start_station_m[-1] + self.duration_s[-1] * 0.5 * (self.speed_from_mps[-1] + self.speed_to_mps[-1]))

    def evaluate(self, t):
        """(station [m], speed [m/s], acceleration [m/s^2]) at times ``t`` [s]."""
        t = np.asarray(t, dtype=float)
        i = np.clip(np.searchsorted(self.start_time_s, t, side="right") - 1, 0, len(self.start_time_s) - 1)
        duration = self.duration_s[i]
        x = np.clip((t - self.start_time_s[i]) / duration, 0.0, 1.0)
        v0 = self.speed_from_mps[i]
        dv = self.speed_to_mps[i] - v0
        smooth = x**3 * (10.0 + x * (-15.0 + 6.0 * x))
        smooth_integral = x**4 * (2.5 + x * (-3.0 + x))
        smooth_rate = 30.0 * x**2 * (1.0 - x) ** 2
        station = self.start_station_m[i] + duration * (v0 * x + dv * smooth_integral)
        speed = v0 + dv * smooth
        accel = dv * smooth_rate / duration
        return station, speed, accel


class _ProfileBuilder:
    def __init__(self, start_time_s: float, start_station_m: float):
        self.pieces: list[tuple[float, float, float, float, float]] = []
        self.t = start_time_s
        self.s = start_station_m
        self.v = 0.0

    def hold(self, duration_s: float) -> None:
        if duration_s > 0:
            self.pieces.append((self.t, duration_s, self.s, self.v, self.v))
            self.t += duration_s
            self.s += duration_s * self.v

    def change(self, speed_mps: float, duration_s: float) -> None:
        self.pieces.append((self.t, duration_s, self.s, self.v, speed_mps))
        self.t += duration_s
        self.s += duration_s * 0.5 * (self.v + speed_mps)
        self.v = speed_mps

    def build(self) -> SpeedProfile:
        arr = np.array(self.pieces, dtype=float)
        return SpeedProfile(arr[:, 0], arr[:, 1], arr[:, 2], arr[:, 3], arr[:, 4])


def walking_profile(
    rng: np.random.Generator,
    start_time_s: float,
    start_station_m: float,
    end_station_m: float,
    cruise_speed_mps: float,
    speed_variation: float,
    speed_change_interval_s: float,
    ramp_s: float,
    static_start_s: float,
    static_end_s: float,
    stops: tuple[tuple[float, float], ...] = (),
) -> SpeedProfile:
    """A trolley pushed from ``start_station_m`` to ``end_station_m``.

    Static for ``static_start_s`` (initial alignment), then walking at
    ``cruise_speed_mps`` varied by +-``speed_variation`` (a fraction) every
    ``speed_change_interval_s``, stopping for each ``(station, duration)`` in
    ``stops``, and static again for ``static_end_s`` at the end. Speed changes
    take ``ramp_s`` seconds.
    """
    if not start_station_m < end_station_m:
        raise ValueError("the survey must end beyond its start station")
    b = _ProfileBuilder(start_time_s, start_station_m)
    b.hold(static_start_s)
    targets = sorted(stops) + [(end_station_m, static_end_s)]
    for stop_station, stop_duration in targets:
        if not b.s < stop_station <= end_station_m:
            raise ValueError(f"stop at station {stop_station} m lies outside the survey or behind another stop")
        while True:
            speed = cruise_speed_mps * (1.0 + speed_variation * rng.uniform(-1.0, 1.0))
            # Distance needed to change to this speed and then brake to rest.
            brake = ramp_s * 0.5 * speed
            change = ramp_s * 0.5 * (b.v + speed)
            remaining = stop_station - b.s
            if remaining <= change + brake + speed * 1.0:
                # Not enough room for another change: cruise at the current speed (or a
                # gentle one from rest) and brake exactly onto the stop station.
                if b.v == 0.0:
                    speed = min(cruise_speed_mps, remaining / ramp_s)
                    b.change(speed, ramp_s)
                    remaining = stop_station - b.s
                cruise = (remaining - ramp_s * 0.5 * b.v) / b.v
                b.hold(max(cruise, 0.0))
                b.change(0.0, ramp_s)
                break
            b.change(speed, ramp_s)
            hold = min(speed_change_interval_s * rng.uniform(0.6, 1.4), (stop_station - b.s - brake) / speed - ramp_s)
            b.hold(max(hold, 0.0))
        b.s = stop_station  # remove floating-point drift so stops land on their stations
        b.hold(stop_duration)
    return b.build()
