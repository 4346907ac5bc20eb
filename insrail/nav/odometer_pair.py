"""Two odometers, one on each rail (thesis 5.2.2.3): their cross-check, slip detection and bridging.

Frames: the trolley frame v (x along the track, y to the right, z down), the lever arms in the IMU's
b frame as in survey.toml, C_b^v from the mounting angles.

The contact points of the two wheels move with the trolley; their speeds along x differ by the
trolley's rotation:  v_R - v_L = omega_y dz - omega_z dy  (dy, dz: the right wheel's contact point
from the left one's, in v; omega: the trolley's rate, which the gyros measure to far better than the
wheels can). The difference of the two distance records, less the gyros' angle times the spacing,
is therefore flat while both wheels roll:

    r(t) = (d_R - d_L) - (theta_y dz - theta_z dy)      theta = integral of C_b^v omega_ib^b

apart from the wheels' scale difference (a slope k per metre travelled, estimated here: the right
record is put on the left one's scale, so the filter's one odometer scale state serves both) and the
earth's rate (7e-5 rad/s x 1.5 m = 0.1 mm/s, 0.01 % of 1 m/s: left in). A wheel that slips counts
less than it rolls: r's rate per metre leaves 0 over the stretch (left slipping: +s, right: -s).

Which wheel slips the difference cannot say; the IMU can. A slip starts and ends as a step of
s x speed in that wheel's speed which the trolley's along-track acceleration, the x specific force
(plus gravity's slowly varying part along the grade), does not show. So each wheel's speed less the
integrated x specific force is fitted around the stretch's ends with a line and a step; the wheel
whose steps are the slip's, the other's near 0, is the slipping one. Its speeds are left out over
the stretch (the other wheel carries the along-track speed there); where the steps do not single
out one wheel, both are left out and the INS with the NHC bridges the stretch. Either way a notice
names the file, the times, the distance travelled and the slip.

Heading rate from the difference, (v_R - v_L) / dy, is not used as a measurement: at 10 Hz the 1 mm
pulses alone make it a few mrad/s noisy, and over 100 m a 1e-4 difference of the wheels' scales is
a 7 mrad heading error, where a navigation-grade gyro drifts by microradians (measured in
tests/test_odometer_pair.py). The gyros are the reference here, and the difference detects slip.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from insrail.io.types import Gap, ImuIncrements, OdometerData

#: the grid the two records are compared on [s]
GRID_S = 0.1
#: the window over which the rate of the difference is formed [s]
WINDOW_S = 1.0
#: below this speed [m/s] a window is not judged (a start, a stop: the ratio means nothing)
MIN_SPEED_MPS = 0.3
#: a wheel counting this share less (or more) than the other, after the curve's part, is slipping;
#: at least ``PULSE_SIGMAS`` times what the pulses' quantisation alone gives at the window's speed
SLIP_THRESHOLD = 0.01
PULSE_SIGMAS = 5.0
#: a shorter run of slipping windows [s] is a jolt, not a stretch
MIN_STRETCH_S = 1.0
#: runs of slipping windows closer than this [s] are one stretch
MERGE_GAP_S = 1.0
#: the step test: the lines fitted this long [s] before and after a stretch's end, leaving out
#: ``STEP_GUARD_S`` either side (where in the first window the slip began)
STEP_SPAN_S = 4.0
STEP_GUARD_S = 1.2
#: the slipping wheel's steps must be this many times the other's, and at least half the slip's
STEP_RATIO = 3.0


@dataclass(frozen=True)
class Slip:
    """A stretch where one wheel (or, unresolved, one of the two) did not count what it rolled.

    wheel          : "left" or "right" (the role odometer / odometer_right); "either": the IMU could
                     not tell which, and both are left out
    start_s, end_s : the stretch left out [s, the survey's time scale]
    from_m, to_m   : the distance the other (good) wheel had travelled from its first record there
    slip           : the share of the distance the slipping wheel did not count (0.05: 5 % short;
                     negative: it counted more than it rolled)
    """

    wheel: str
    start_s: float
    end_s: float
    from_m: float
    to_m: float
    slip: float


@dataclass(frozen=True)
class OdometerPair:
    """The two odometers compared.

    relative_scale : the right wheel's distance per metre of the left one's, less 1 (its record is
                     divided by 1 + this before the filter: both then share one scale state)
    spacing_m      : the lateral (y) spacing of the two contact points in the trolley frame [m]
    slips          : the stretches found, in time order
    left, right    : the two records for the filter: the right one on the left one's scale, each
                     with its slipping stretches in ``left_out``
    """

    relative_scale: float
    spacing_m: float
    slips: tuple[Slip, ...]
    left: OdometerData
    right: OdometerData

    def to_dict(self) -> dict:
        """The ``[fusion.odometer_pair]`` table of summary.toml."""
        return {"relative_scale": self.relative_scale, "spacing_m": self.spacing_m,
                "slips": [{"wheel": s.wheel, "start_s": s.start_s, "end_s": s.end_s, "from_m": s.from_m,
                           "to_m": s.to_m, "slip_percent": 100.0 * s.slip} for s in self.slips]}


def _cumulative_at(imu: ImuIncrements, increments_v: np.ndarray, times: np.ndarray) -> np.ndarray:
    """The running sum of v-frame increments (n, 3), read at ``times`` (each increment ends at its time)."""
    total = np.cumsum(increments_v, axis=0)
    return np.column_stack([np.interp(times, imu.time_s, total[:, a]) for a in range(3)])


def _runs(flag: np.ndarray) -> list[tuple[int, int]]:
    """(first, last) index of each run of True."""
    edges = np.diff(np.concatenate([[0], flag.astype(np.int8), [0]]))
    return list(zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1))


def _step(t: np.ndarray, u: np.ndarray, at_s: float) -> float:
    """The step at ``at_s`` of a line-plus-step fitted to u(t) within STEP_SPAN_S of it (outside the
    guard); NaN when one side has no samples."""
    near = np.abs(t - at_s)
    use = (near <= STEP_SPAN_S) & (near >= STEP_GUARD_S)
    after = t[use] > at_s
    if after.sum() < 5 or (~after).sum() < 5:
        return float("nan")
    design = np.column_stack([np.ones(use.sum()), t[use] - at_s, after.astype(float)])
    return float(np.linalg.lstsq(design, u[use], rcond=None)[0][2])


def compare_odometers(imu: ImuIncrements, left: OdometerData, right: OdometerData, lever_left_m: np.ndarray,
                      lever_right_m: np.ndarray, c_vb: np.ndarray) -> OdometerPair:
    """The two wheels compared through the gyros (module docstring): their relative scale, the
    stretches where one slipped, and the two records for the filter."""
    start = max(left.time_s[0], right.time_s[0], imu.time_s[0])
    end = min(left.time_s[-1], right.time_s[-1], imu.time_s[-1])
    offset = np.asarray(c_vb @ (np.asarray(lever_right_m, float) - np.asarray(lever_left_m, float)))
    spacing_m = float(offset[1])
    if end - start < 2 * WINDOW_S:
        return OdometerPair(0.0, spacing_m, (), left, right)
    t = np.arange(start, end, GRID_S)
    d_left = np.interp(t, left.time_s, left.distance_m)
    d_right = np.interp(t, right.time_s, right.distance_m)
    theta = _cumulative_at(imu, imu.dtheta_rad @ c_vb.T, t)
    r = (d_right - d_left) - (theta[:, 1] * offset[2] - theta[:, 2] * offset[1])
    w = int(round(WINDOW_S / GRID_S))
    rate = (r[w:] - r[:-w]) / WINDOW_S
    speed = 0.5 * ((d_left[w:] - d_left[:-w]) + (d_right[w:] - d_right[:-w])) / WINDOW_S
    moving = np.abs(speed) > MIN_SPEED_MPS
    if not moving.any():
        return OdometerPair(0.0, spacing_m, (), left, right)
    share = np.where(moving, rate / np.where(moving, speed, 1.0), 0.0)
    # four read distances in a window's difference, each off by up to a pulse (uniform)
    pulse_m = max(left.pulse_length_m or 0.001, right.pulse_length_m or 0.001)
    threshold = np.maximum(SLIP_THRESHOLD, PULSE_SIGMAS * pulse_m / np.sqrt(3.0) / WINDOW_S
                           / np.maximum(np.abs(speed), MIN_SPEED_MPS))
    # the scale difference from the median, then from all the distance where neither wheel slips
    relative_scale = float(np.median(share[moving]))
    for _ in range(2):
        flagged = moving & (np.abs(share - relative_scale) > threshold)
        rolling = moving & ~flagged
        if rolling.any():
            relative_scale = float(np.sum(rate[rolling]) / np.sum(speed[rolling]))
    flagged = moving & (np.abs(share - relative_scale) > threshold)
    # runs closer than MERGE_GAP_S are one stretch
    runs = _runs(flagged)
    merged: list[list[int]] = []
    for first, last in runs:
        if merged and (first - merged[-1][1]) * GRID_S <= MERGE_GAP_S:
            merged[-1][1] = last
        else:
            merged.append([first, last])
    if not merged:
        return _pair(relative_scale, spacing_m, (), left, right)
    # each wheel's speed less the integrated x specific force: smooth but for a slip's steps
    speed_t = t[:-w] + 0.5 * WINDOW_S
    along = _cumulative_at(imu, imu.dvel_mps @ c_vb.T, speed_t)[:, 0]
    residual_left = (d_left[w:] - d_left[:-w]) / WINDOW_S - along
    residual_right = (d_right[w:] - d_right[:-w]) / WINDOW_S - along
    slips = []
    for first, last in merged:
        if (last - first) * GRID_S < MIN_STRETCH_S:
            continue
        # window k spans t[k] .. t[k] + WINDOW_S and is flagged once a fifth of it slips: the slip
        # began about 0.8 windows after the first one's start and ended 0.2 after the last one's
        start_s, end_s = float(t[first]), float(t[last] + WINDOW_S)  # the slip with a window's margin
        onset, finish = float(t[first] + 0.8 * WINDOW_S), float(t[last] + 0.2 * WINDOW_S)
        inside = slice(first + w, last - w + 1) if last - w + 1 > first + w else slice(first, last + 1)
        slip_share = float(np.sum(rate[inside] - relative_scale * speed[inside]) / np.sum(speed[inside]))
        steps = {}
        for wheel, residual in (("left", residual_left), ("right", residual_right)):
            steps[wheel] = np.nansum([abs(_step(speed_t, residual, onset)), abs(_step(speed_t, residual, finish))])
        expected = abs(slip_share) * float(np.mean(np.abs(speed[first:last + 1])))
        big, small = ("left", "right") if steps["left"] > steps["right"] else ("right", "left")
        resolved = steps[big] > STEP_RATIO * steps[small] and steps[big] > 0.5 * expected
        wheel = big if resolved else "either"
        # left counting less raises r (slip > 0); right counting less lowers it
        slip = slip_share if wheel == "left" else -slip_share if wheel == "right" else abs(slip_share)
        good = d_right if wheel == "left" else d_left
        travelled = np.interp([start_s, end_s], t, good) - good[0]
        slips.append(Slip(wheel, start_s, end_s, float(travelled[0]), float(travelled[1]), slip))
    return _pair(relative_scale, spacing_m, tuple(slips), left, right)


def _pair(relative_scale: float, spacing_m: float, slips: tuple[Slip, ...], left: OdometerData,
          right: OdometerData) -> OdometerPair:
    def left_out(wheel: str) -> tuple[Gap, ...]:
        return tuple(Gap(s.start_s, s.end_s) for s in slips if s.wheel in (wheel, "either"))

    return OdometerPair(relative_scale, spacing_m, slips, replace(left, left_out=left_out("left")),
                        replace(right, distance_m=right.distance_m / (1.0 + relative_scale),
                                left_out=left_out("right")))
