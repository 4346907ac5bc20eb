"""Compare a fused trajectory with the simulator's navigation truth.

The figures the benchmarks and tests quote: position error (north, east, down and its
lateral/vertical parts across the track), attitude error, the error inside GNSS outages,
and the relative accuracy track geometry needs: the standard deviation of the difference
of the lateral (vertical) error between points a given distance apart along the track
(5 m for the 30 m/5 m check, 150 m for 300 m/150 m; thesis eqs. 3.8-3.11).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from insrail.nav import earth
from insrail.nav.trajectory import Trajectory

SLEEPER_SPACING_M = 0.625


@dataclass(frozen=True)
class TrajectoryErrors:
    """Errors (solution minus truth) at the trajectory's epochs."""

    time_s: np.ndarray
    station_m: np.ndarray
    ned_m: np.ndarray  # (n, 3)
    lateral_m: np.ndarray  # positive to the right of the direction of travel
    vertical_m: np.ndarray  # positive up
    rpy_rad: np.ndarray  # (n, 3), wrapped to (-pi, pi]
    moving: np.ndarray  # the trolley has left its start

    def rms_horizontal_m(self) -> float:
        return float(np.sqrt(np.mean(np.sum(self.ned_m[self.moving, :2] ** 2, axis=1))))

    def rms_vertical_m(self) -> float:
        return float(np.sqrt(np.mean(self.ned_m[self.moving, 2] ** 2)))

    def rms_attitude_rad(self) -> np.ndarray:
        return np.sqrt(np.mean(self.rpy_rad[self.moving] ** 2, axis=0))

    def max_in(self, intervals) -> tuple[float, float]:
        """Largest horizontal and vertical error inside the time intervals (NaN if none)."""
        mask = np.zeros(len(self.time_s), dtype=bool)
        for start, end in intervals:
            mask |= (self.time_s >= start) & (self.time_s <= end)
        if not mask.any():
            return float("nan"), float("nan")
        return float(np.max(np.hypot(self.ned_m[mask, 0], self.ned_m[mask, 1]))), float(np.max(np.abs(self.ned_m[mask, 2])))

    def lag_difference_sigma_m(self, lag_m: float) -> tuple[float, float]:
        """1-sigma of e(s + lag) - e(s) for the lateral and the vertical error, sampled at
        sleeper spacing along the travelled stations (with or against the stationing), about
        its mean over the survey (the part a survey's constant slope of its error leaves)."""
        differences = self._lag_differences(lag_m)
        return (float("nan"), float("nan")) if differences is None else tuple(float(np.std(d)) for d in differences)

    def lag_difference_rms_m(self, lag_m: float) -> tuple[float, float]:
        """RMS of e(s + lag) - e(s) for the lateral and the vertical error (sampled as in
        :meth:`lag_difference_sigma_m`), its mean over the survey included: what a stated
        1-sigma of the lag difference (``insrail.quality``) describes. A survey's error slope
        (a heading error, the GNSS's correlated error drifting) is one draw per survey, so
        only many surveys judge it."""
        differences = self._lag_differences(lag_m)
        return ((float("nan"), float("nan")) if differences is None
                else tuple(float(np.sqrt(np.mean(np.square(d)))) for d in differences))

    def _lag_differences(self, lag_m: float) -> tuple[np.ndarray, np.ndarray] | None:
        s = self.station_m if self.station_m[-1] >= self.station_m[0] else -self.station_m
        grid = np.arange(s[self.moving][0] + 1.0, s[-1] - 1.0, SLEEPER_SPACING_M)
        k = np.searchsorted(s, grid)  # first epoch reaching each station (travelled stations never decrease)
        lag = int(round(lag_m / SLEEPER_SPACING_M))
        if len(k) <= lag:
            return None
        lat, ver = self.lateral_m[k], self.vertical_m[k]
        return lat[lag:] - lat[:-lag], ver[lag:] - ver[:-lag]


def trajectory_errors(trajectory: Trajectory, truth: np.ndarray, ell: earth.Ellipsoid = earth.WGS84) -> TrajectoryErrors:
    """Errors of ``trajectory`` against truth/nav.npy rows at the same IMU epochs."""
    k = np.searchsorted(truth["time_s"], trajectory.time_s - 1e-6)
    if np.any(k >= len(truth)) or np.abs(truth["time_s"][np.minimum(k, len(truth) - 1)] - trajectory.time_s).max() > 1e-6:
        raise ValueError("the trajectory's epochs are not epochs of the truth file")
    tt = truth[k]
    r_m, r_n = earth.radii(tt["lat_rad"], ell)
    north = (trajectory.lat_rad - tt["lat_rad"]) * (r_m + tt["height_m"])
    east = (trajectory.lon_rad - tt["lon_rad"]) * (r_n + tt["height_m"]) * np.cos(tt["lat_rad"])
    down = -(trajectory.height_m - tt["height_m"])
    heading = tt["rpy_rad"][:, 2]
    lateral = -north * np.sin(heading) + east * np.cos(heading)
    rpy = np.angle(np.exp(1j * (trajectory.rpy_rad - tt["rpy_rad"])))
    station = tt["station_m"]
    return TrajectoryErrors(
        time_s=trajectory.time_s,
        station_m=station,
        ned_m=np.column_stack([north, east, down]),
        lateral_m=lateral,
        vertical_m=-down,
        rpy_rad=rpy,
        moving=np.abs(station - station[0]) > 1.0,
    )


def truth_rail_deviations(truth, station_m: np.ndarray) -> tuple[np.ndarray, ...]:
    """The true track's rails against the design at the sleepers nearest ``station_m`` (the simulator's
    ``truth/sleepers.csv``, :class:`insrail.sim.truth.SleeperTruth`): (lateral (n, 2), vertical (n, 2),
    gauge, cant, design cant) [m], rails [left, right] with the signs of ``insrail.track``. A rail's
    deviation is the centreline's irregularity with half the gauge (lateral: a wider gauge moves the
    left rail left) or half the cross-level (vertical: a positive one raises the left rail) on it."""
    stations = truth["station"]
    nearest = np.clip(np.searchsorted(stations, station_m), 1, stations.size - 1)
    nearest -= (station_m - stations[nearest - 1]) < (stations[nearest] - station_m)
    lateral, vertical = truth["lateral"][nearest], truth["vertical"][nearest]
    half_gauge, half_cross = 0.5 * truth["gauge_deviation"][nearest], 0.5 * truth["cross_level"][nearest]
    return (np.column_stack([lateral - half_gauge, lateral + half_gauge]),
            np.column_stack([vertical + half_cross, vertical - half_cross]),
            truth["gauge"][nearest], truth["cant"][nearest], truth["design_cant"][nearest])
