"""Aiding measurements: each aiding source one small model the filter loop runs over.

Every class holds its data (times and values) and answers three questions, so the filter
(``insrail.nav.fusion``) and the accuracy prediction (``insrail.quality.prediction``) never
need to know what a measurement is:

``closing_times_s()``
    the times at which an update epoch must end because an observation was taken then
    (time-stamped sources: GNSS, total-station fixes); empty for sources that follow the
    filter's update grid (odometer/NHC, ZUPT).
``scheduled(update_time_s, stops)``
    when it applies: on the update epochs ``update_time_s`` (and with the stops, intervals
    [start, end] of standstill), the pairs (j, i) "observation i is applied at update epoch
    j", j >= 1, and the measurement bound to that grid (the odometer's mean speeds are formed
    over the grid's segments). :func:`schedule` merges them into one schedule.
``model(nav, i)``
    for its i-th observation the innovation z = predicted - measured (m,), the Jacobian H
    (m, 25) with respect to the error state of ``insrail.nav.error_model`` and the noise
    covariance R (m, m). The filter gates z with a chi-square test on its m degrees of
    freedom (``insrail.nav.kalman.gated_update``) and keeps the statistics per ``name``.

``resets``
    what a filter reset widens when this source has been rejected for too long (the filter,
    not the sensor, is then taken to be wrong): some of "position", "velocity", "attitude";
    ``position_innovation`` says the innovation's first three components are NED metres of
    position (the reset then widens the position by the size of the rejected innovations).

``compiled()``
    the same model for the compiled filter loop: a model kind, its parameters and one row of
    numbers per observation, evaluated by that kind's compiled twin of ``model`` (see
    "compiled form" below).

Lever arms are b-frame vectors from the IMU centre (thesis eqs. 2.106-2.125).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import ClassVar, Protocol

import numpy as np

from insrail.jit import cached_njit
from insrail.nav import _kernels, earth
from insrail.nav.error_model import ATT, BG, GNSS, N_STATES, ODO, POS, SG, VEL
from insrail.nav.rotation import cross, skew


@dataclass(frozen=True)
class NavSnapshot:
    """The INS solution at an update epoch (compensated sensor values).

    omega_ib_b, f_b : angular rate [rad/s] and specific force [m/s^2] of the last epoch
    rate_span_s     : the interval omega_ib_b is the mean of (the last IMU record's) [s]: its white noise
    mean_vel_ned    : mean NED velocity over the segment since the previous update [m/s]
    mean_omega_ib_b : mean compensated angular rate over that segment [rad/s]
    segment_s       : length of that segment [s]
    odometer_scale  : current estimate of the odometer scale-factor error
    gnss_error_ned_m: current estimate of the correlated GNSS position error
    """

    time_s: float
    lat: float
    lon: float
    h: float
    vel_ned: np.ndarray
    c_bn: np.ndarray
    omega_ib_b: np.ndarray
    f_b: np.ndarray
    mean_vel_ned: np.ndarray
    mean_omega_ib_b: np.ndarray
    segment_s: float
    odometer_scale: float
    rate_span_s: float
    ellipsoid: earth.Ellipsoid = earth.WGS84
    gnss_error_ned_m: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def radii_h(self):
        r_m, r_n = earth.radii(self.lat, self.ellipsoid)
        return r_m + self.h, r_n + self.h

    def omega_in_n(self) -> np.ndarray:
        return earth.earth_rate_ned(self.lat, self.ellipsoid) + earth.transport_rate_ned(
            self.lat, self.h, self.vel_ned, self.ellipsoid
        )


def _h(rows: int) -> np.ndarray:
    return np.zeros((rows, N_STATES))


def _position_rows(nav: NavSnapshot, time_s: float, lat: float, lon: float, h: float, lever: np.ndarray):
    """Innovation (NED metres) and Jacobian of a measured position of the point at ``lever``:
    z = D_R (r_ins + D_R^-1 C_b^n l - r_measured)  (thesis 2.110, 2.112), the prediction moved
    along the velocity to the observation time."""
    rm, rn = nav.radii_h()
    lever_n = nav.c_bn @ lever
    predicted_ned = lever_n + nav.vel_ned * (time_s - nav.time_s)  # relative to the IMU position
    measured_ned = np.array([(lat - nav.lat) * rm, (lon - nav.lon) * rn * np.cos(nav.lat), -(h - nav.h)])
    H = _h(3)
    H[:, POS : POS + 3] = np.eye(3)
    H[:, VEL : VEL + 3] = (time_s - nav.time_s) * np.eye(3)
    H[:, ATT : ATT + 3] = skew(lever_n)
    return predicted_ned - measured_ned, H


class Measurement(Protocol):
    """The interface every aiding source implements (see the module docstring)."""

    name: str
    time_s: np.ndarray
    resets: ClassVar[tuple[str, ...]]
    position_innovation: ClassVar[bool]

    def closing_times_s(self) -> np.ndarray: ...

    def scheduled(self, update_time_s: np.ndarray, stops: Sequence[tuple[float, float]]
                  ) -> tuple[Measurement, np.ndarray, np.ndarray]: ...

    def model(self, nav: NavSnapshot, i: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]: ...

    def compiled(self) -> CompiledModel: ...


_NO_TIMES = np.zeros(0)


def _timed_pairs(time_s: np.ndarray, update_time_s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A time-stamped observation is applied at the first update epoch at or after it;
    observations at or before the first epoch, or after the last, are not applied."""
    i = np.flatnonzero((time_s > update_time_s[0]) & (time_s <= update_time_s[-1]))
    return np.searchsorted(update_time_s, time_s[i]).astype(np.int64), i.astype(np.int64)


class _TimedSource:
    """Scheduling of sources with time-stamped observations."""

    def closing_times_s(self) -> np.ndarray:
        return self.time_s

    def scheduled(self, update_time_s, stops):
        return (self, *_timed_pairs(self.time_s, update_time_s))


@dataclass(frozen=True)
class Schedule:
    """Which observation of which source is applied at which update epoch, in the order the
    filter applies them: by epoch, then by the sources' order in ``measurements``, then by
    observation. Flat arrays, one entry per scheduled observation; the entries of epoch j
    are ``first[j]:first[j + 1]``."""

    time_s: np.ndarray  # (m,) update epochs
    measurements: tuple  # the sources bound to the update grid
    epoch: np.ndarray  # (k,) update-epoch index j
    source: np.ndarray  # (k,) index into measurements
    observation: np.ndarray  # (k,) observation index i of that source
    first: np.ndarray  # (m + 1,)

    def at(self, j: int) -> range:
        """The entries scheduled at update epoch j."""
        return range(int(self.first[j]), int(self.first[j + 1]))


def schedule(update_time_s: np.ndarray, measurements: Sequence[Measurement],
             stops: Sequence[tuple[float, float]] = ()) -> Schedule:
    """The one schedule of a list of aiding sources on an update grid: the fusion's forward
    pass and the accuracy prediction both apply exactly this."""
    bound, epochs, sources, observations = [], [], [], []
    for k, meas in enumerate(measurements):
        meas, j, i = meas.scheduled(update_time_s, stops)
        bound.append(meas)
        epochs.append(j)
        sources.append(np.full(len(j), k, dtype=np.int64))
        observations.append(i)
    epoch = np.concatenate(epochs) if epochs else np.zeros(0, dtype=np.int64)
    source = np.concatenate(sources) if sources else np.zeros(0, dtype=np.int64)
    observation = np.concatenate(observations) if observations else np.zeros(0, dtype=np.int64)
    order = np.lexsort((observation, source, epoch))
    epoch, source, observation = epoch[order], source[order], observation[order]
    first = np.searchsorted(epoch, np.arange(len(update_time_s) + 1))
    return Schedule(np.asarray(update_time_s), tuple(bound), epoch, source, observation, first)


def at_rest(stops: Sequence[tuple[float, float]], time_s: np.ndarray) -> np.ndarray:
    """Whether each time lies inside one of the stop intervals [start, end] (sorted)."""
    time_s = np.asarray(time_s, dtype=float)
    if not len(stops):
        return np.zeros(time_s.shape, dtype=bool)
    start = np.array([s[0] for s in stops])
    end = np.array([s[1] for s in stops])
    j = np.searchsorted(start, time_s) - 1
    return (j >= 0) & (time_s <= end[np.maximum(j, 0)])


@dataclass(frozen=True)
class GnssPosition(_TimedSource):
    """GNSS antenna position (thesis 2.106-2.112) with a correlated error part.

    measured = true + g + white, g the Gauss-Markov error (states 22-24, estimate
    ``nav.gnss_error_ned_m``). The file's sigma is the total; the white part's variance is
    what is left after the modelled correlated part: R = max((scale sigma)^2 - sigma_gm^2,
    floor^2). The observation time may differ from the update epoch by a fraction of an
    IMU interval; the prediction is moved along the velocity to the observation time.
    """

    time_s: np.ndarray
    lat: np.ndarray
    lon: np.ndarray
    h: np.ndarray
    sigma_ned_m: np.ndarray
    lever_arm_m: np.ndarray
    sigma_scale: float = 1.0
    sigma_floor_m: float = 0.002
    correlated_sigma_ned_m: tuple[float, float, float] = (0.0, 0.0, 0.0)
    name: str = "gnss_position"
    #: per epoch whether the solution claims its full accuracy (a fixed or flagless solution, not
    #: float or DGPS): only a run of rejected trusted epochs quickly means the filter is wrong
    trusted: np.ndarray | None = None
    resets: ClassVar[tuple[str, ...]] = ("position", "velocity", "attitude")
    position_innovation: ClassVar[bool] = True

    def model(self, nav: NavSnapshot, i: int):
        z, H = _position_rows(nav, self.time_s[i], self.lat[i], self.lon[i], self.h[i], self.lever_arm_m)
        # residual state x_g = g - g_hat: z = dr - (g - g_hat) once the estimate is removed
        z = z + nav.gnss_error_ned_m
        H[:, GNSS : GNSS + 3] = -np.eye(3)
        variance = np.square(self.sigma_scale * self.sigma_ned_m[i]) - np.square(self.correlated_sigma_ned_m)
        return z, H, np.diag(np.maximum(variance, self.sigma_floor_m**2))

    def compiled(self) -> CompiledModel:
        variance = np.square(self.sigma_scale * np.asarray(self.sigma_ned_m)) - np.square(self.correlated_sigma_ned_m)
        return _position_compiled(self, np.maximum(variance, self.sigma_floor_m**2), True)


@dataclass(frozen=True)
class GnssVelocity(_TimedSource):
    """GNSS (Doppler) velocity of the antenna (thesis 2.113-2.118)."""

    time_s: np.ndarray
    vel_ned: np.ndarray
    sigma_ned_mps: np.ndarray
    lever_arm_m: np.ndarray
    sigma_floor_mps: float = 0.002
    name: str = "gnss_velocity"
    resets: ClassVar[tuple[str, ...]] = ("velocity", "attitude")
    position_innovation: ClassVar[bool] = False

    def model(self, nav: NavSnapshot, i: int):
        # v_ant = v + C (omega_nb^b x l) = v + C (omega_ib^b x l) - (omega_in^n x) C l
        c, lever = nav.c_bn, self.lever_arm_m
        w_in = nav.omega_in_n()
        lever_n = c @ lever
        rotation_n = c @ cross(nav.omega_ib_b, lever)
        z = nav.vel_ned + rotation_n - cross(w_in, lever_n) - self.vel_ned[i]
        H = _h(3)
        H[:, VEL : VEL + 3] = np.eye(3)
        H[:, ATT : ATT + 3] = skew(rotation_n) - skew(w_in) @ skew(lever_n)
        H[:, BG : BG + 3] = -c @ skew(lever)
        H[:, SG : SG + 3] = -c @ skew(lever) * nav.omega_ib_b
        sigma = np.maximum(self.sigma_ned_mps[i], self.sigma_floor_mps)
        return z, H, np.diag(sigma**2)

    def compiled(self) -> CompiledModel:
        sigma = np.maximum(np.asarray(self.sigma_ned_mps, float), self.sigma_floor_mps)
        return _compiled(MODEL_GNSS_VELOCITY, np.asarray(self.lever_arm_m, float),
                         [self.time_s, *np.asarray(self.vel_ned, float).T, *np.square(sigma).T])


@dataclass(frozen=True)
class _VehicleFrame:
    """What the velocity of every point of the trolley in its frame v shares at one epoch:
    C_n^v and the body rate relative to n, omega_nb^b."""

    c_vb: np.ndarray
    c_nv: np.ndarray
    omega_nb_b: np.ndarray
    omega_ib_b: np.ndarray

    @classmethod
    def at(cls, nav: NavSnapshot, c_vb: np.ndarray) -> _VehicleFrame:
        c_nb = nav.c_bn.T
        return cls(c_vb, c_vb @ c_nb, nav.omega_ib_b - c_nb @ nav.omega_in_n(), nav.omega_ib_b)

    def velocity_rows(self, lever: np.ndarray, vel_ned: np.ndarray):
        """Velocity of the point at ``lever`` in v and its Jacobian (3 x 22):
        v^v = C_b^v C_n^b v^n + C_b^v (omega_nb^b x l)   (thesis 2.119, 2.123-2.125)."""
        velocity = self.c_nv @ vel_ned + self.c_vb @ cross(self.omega_nb_b, lever)
        lever_rows = -self.c_vb @ skew(lever)
        H = _h(3)
        H[:, VEL : VEL + 3] = self.c_nv
        H[:, ATT : ATT + 3] = -self.c_nv @ skew(vel_ned)
        H[:, BG : BG + 3] = lever_rows
        H[:, SG : SG + 3] = lever_rows * self.omega_ib_b
        return velocity, H


def odometer_speed_sigma(span_s, pulse_length_m: float, sigma_mps: float):
    """1-sigma of the odometer's mean speed over segments of ``span_s`` seconds: its white
    speed noise and the pulse quantisation."""
    # Each interpolated distance is off by up to one pulse (uniform), so the difference of
    # two has a standard deviation of pulse / sqrt(6).
    return np.hypot(sigma_mps, pulse_length_m / (np.sqrt(6.0) * np.asarray(span_s)))


@dataclass(frozen=True)
class OdometerNhc:
    """Odometer forward speed plus the non-holonomic constraint, in the trolley frame v.

    x row: the odometer's mean speed over the segment between two samples (distance
    increment / time), scaled by the estimated scale factor, against the INS's mean
    forward velocity of the wheel's contact point over the same segment.
    y, z rows (NHC): the trolley's reference point cannot move sideways or vertically
    relative to the rails: zero lateral and vertical velocity at every update.

    The odometer scale factor is a filter state (22nd) rather than estimated in
    pre-processing as in thesis 5.3.1: with GNSS it converges within minutes of
    motion, its uncertainty is carried into GNSS outages (where the odometer matters
    most) instead of being assumed exact, and the smoother refines it with the whole
    survey. Without GNSS it stays at its prior, exactly what pre-processing would give.
    """

    time_s: np.ndarray
    speed_mps: np.ndarray  # reported (unscaled) mean speed over the segment ending at time_s
    dcm_vehicle_from_body: np.ndarray
    odometer_lever_arm_m: np.ndarray
    nhc_lever_arm_m: np.ndarray
    sigma_speed_mps: np.ndarray
    sigma_nhc_mps: float = 0.002
    #: the gyro's white noise [rad/sqrt(s)]: the NHC point's velocity takes the last record's rate
    #: through the lever arm, so its rows carry that rate's noise, gyro_white_noise^2 / rate_span_s
    #: through the lever (a tactical unit's 0.1 deg/sqrt(h) at 200 Hz: 0.25 mm/s vertically for
    #: a rail point 0.6 m beside the IMU, more than a trolley without play shows otherwise); the
    #: odometer's row takes it through the wheel's lever arm
    gyro_white_noise: float = 0.0
    use_odometer: bool = True
    use_nhc: bool = True
    name: str = "odometer_nhc"
    resets: ClassVar[tuple[str, ...]] = ("velocity", "attitude")
    position_innovation: ClassVar[bool] = False
    #: the odometer's record (cumulative distance [m] at times [s]) the mean speeds of a grid
    #: are formed from by :meth:`scheduled`, its white speed noise and its pulse length
    odometer_time_s: np.ndarray | None = None
    odometer_distance_m: np.ndarray | None = None
    sigma_odometer_mps: float = 0.001
    pulse_length_m: float = 0.001
    #: a factor on the speeds' 1-sigma (the survey's own noise, ``insrail.nav.self_calibration``)
    sigma_speed_scale: float = 1.0
    #: (start, end) [s] of the intervals where the NHC does not hold (a rail joint's shock,
    #: ``insrail.nav.shocks``): an update whose segment meets one takes the NHC 1-sigma times
    #: ``nhc_relaxed_factor``; ``nhc_scale`` is that factor per observation once scheduled
    nhc_relaxed_s: tuple[np.ndarray, np.ndarray] = (_NO_TIMES, _NO_TIMES)
    nhc_relaxed_factor: float = 100.0
    nhc_scale: np.ndarray | None = None
    #: (start, end) [s] of the stretches whose odometer speeds are not used (the wheel slipped there,
    #: ``insrail.nav.odometer_pair``): an update whose segment meets one has no speed row (and, without
    #: the NHC, is not scheduled); ``speed_used`` says so per observation once scheduled
    odometer_left_out_s: tuple[np.ndarray, np.ndarray] = (_NO_TIMES, _NO_TIMES)
    speed_used: np.ndarray | None = None

    @classmethod
    def from_distance(cls, time_s, distance_m, dcm_vehicle_from_body, odometer_lever_arm_m, nhc_lever_arm_m,
                      sigma_odometer_mps: float, pulse_length_m: float, **kwargs) -> OdometerNhc:
        """The source before it is bound to an update grid (``scheduled`` forms the speeds)."""
        return cls(_NO_TIMES, _NO_TIMES, dcm_vehicle_from_body, odometer_lever_arm_m, nhc_lever_arm_m, _NO_TIMES,
                   odometer_time_s=np.asarray(time_s), odometer_distance_m=np.asarray(distance_m),
                   sigma_odometer_mps=sigma_odometer_mps, pulse_length_m=pulse_length_m, **kwargs)

    def closing_times_s(self) -> np.ndarray:
        return _NO_TIMES

    def scheduled(self, update_time_s, stops):
        """Applied at the end of every segment of the grid that the odometer record covers,
        with the mean speed over the segment (observation i = j - 1 for the segment ending
        at epoch j)."""
        times = np.asarray(update_time_s)
        d = np.interp(times, self.odometer_time_s, self.odometer_distance_m)
        span = np.diff(times)
        speed = np.diff(d) / span
        sigma = self.sigma_speed_scale * odometer_speed_sigma(span, self.pulse_length_m, self.sigma_odometer_mps)
        valid = (times[:-1] >= self.odometer_time_s[0]) & (times[1:] <= self.odometer_time_s[-1])
        used = ~_segments_meeting(self.odometer_left_out_s, times)
        if not self.use_nhc:  # a speed alone: nothing to apply where it is left out
            valid &= used
        i = np.flatnonzero(valid).astype(np.int64)
        scale = np.where(_segments_meeting(self.nhc_relaxed_s, times), self.nhc_relaxed_factor, 1.0)
        return (replace(self, time_s=times[1:], speed_mps=speed, sigma_speed_mps=sigma, nhc_scale=scale,
                        speed_used=used), i + 1, i)

    def model(self, nav: NavSnapshot, i: int):
        rows, z, sig = [], [], []
        frame = _VehicleFrame.at(nav, self.dcm_vehicle_from_body)
        if self.use_odometer and (self.speed_used is None or self.speed_used[i]):
            v_mean, H_odo = frame.velocity_rows(self.odometer_lever_arm_m, nav.mean_vel_ned)
            corrected = self.speed_mps[i] / (1.0 + nav.odometer_scale)
            # odometer state = residual scale error s - s_hat; the corrected speed d / (1 + s_hat)
            # changes by -d / (1 + s_hat)^2 per unit of it
            H_odo[0, ODO] = -corrected / (1.0 + nav.odometer_scale)
            rows.append(H_odo[0])
            z.append(v_mean[0] - corrected)
            # the wheel's speed takes the last record's rate through its lever arm, as the NHC's rows do
            rate = self.gyro_white_noise**2 / nav.rate_span_s * np.sum(np.square(H_odo[0, BG : BG + 3]))
            sig.append(math.sqrt(self.sigma_speed_mps[i] ** 2 + rate))
        if self.use_nhc:
            v_ref, H_nhc = frame.velocity_rows(self.nhc_lever_arm_m, nav.vel_ned)
            rows.extend(H_nhc[1:3])
            z.extend(v_ref[1:3])
            play = self.sigma_nhc_mps * (1.0 if self.nhc_scale is None else self.nhc_scale[i])
            rate = self.gyro_white_noise**2 / nav.rate_span_s * np.sum(np.square(H_nhc[1:3, BG : BG + 3]), axis=1)
            sig.extend(np.sqrt(play**2 + rate))
        return np.array(z), np.array(rows).reshape(len(z), N_STATES), np.diag(np.square(sig))

    def compiled(self) -> CompiledModel:
        return _compiled(MODEL_ODOMETER_NHC,
                         [*np.asarray(self.dcm_vehicle_from_body, float).ravel(),
                          *np.asarray(self.odometer_lever_arm_m, float), *np.asarray(self.nhc_lever_arm_m, float),
                          self.sigma_nhc_mps, float(self.use_odometer), float(self.use_nhc), self.gyro_white_noise],
                         [self.time_s, self.speed_mps, np.square(self.sigma_speed_mps),
                          np.ones(len(self.time_s)) if self.nhc_scale is None else self.nhc_scale,
                          np.ones(len(self.time_s)) if self.speed_used is None else self.speed_used])


def _segments_meeting(intervals: tuple[np.ndarray, np.ndarray], times: np.ndarray) -> np.ndarray:
    """Per segment times[k] .. times[k + 1] whether it meets one of the (start, end) intervals: it
    starts before the interval ends and ends after it starts."""
    start, end = (np.asarray(edge, dtype=float) for edge in intervals)
    if not len(start):
        return np.zeros(len(times) - 1, dtype=bool)
    order = np.argsort(start)
    start, end = start[order], np.maximum.accumulate(end[order])
    before = np.searchsorted(start, times[1:], side="left")  # intervals starting before the segment's end
    return (before > 0) & (end[np.maximum(before - 1, 0)] > times[:-1])


@dataclass(frozen=True)
class Zupt:
    """Zero velocity and zero heading rate while the trolley stands still.

    Velocity rows: the INS velocity must be zero, with the noise of the motion the platform
    shows at that stop (``stop_motion``: per stop its start, end and 1-sigma velocity from the
    accelerometers, ``insrail.nav.alignment.stop_motion_sigma``) over the floor
    ``sigma_velocity_mps`` of a platform standing still. Heading-rate row (ZARU): the mean
    compensated gyro rate about the vertical must equal the earth rate's vertical component;
    it observes the vertical gyro bias.
    """

    time_s: np.ndarray
    sigma_velocity_mps: float = 2e-6
    gyro_white_noise: float = 1e-6  # rad/sqrt(s): the ZARU sigma is this / sqrt(segment)
    stop_motion: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
    #: per observation (update epoch, once scheduled) the velocity rows' 1-sigma [m/s]
    sigma_mps: np.ndarray | None = None
    #: a factor on the velocity rows' 1-sigma (the survey's own noise, ``insrail.nav.self_calibration``)
    sigma_scale: float = 1.0
    name: str = "zupt"
    resets: ClassVar[tuple[str, ...]] = ("velocity",)
    position_innovation: ClassVar[bool] = False

    def closing_times_s(self) -> np.ndarray:
        return _NO_TIMES

    def scheduled(self, update_time_s, stops):
        """Applied at the end of every segment that starts and ends inside a stop
        (observation i = update epoch j), with that stop's motion noise."""
        update_time_s = np.asarray(update_time_s)
        rest = at_rest(stops, update_time_s)
        j = np.flatnonzero(rest[1:] & rest[:-1]).astype(np.int64) + 1
        motion = np.zeros(len(update_time_s))
        if self.stop_motion is not None and len(self.stop_motion[0]):
            start, end, sigma = self.stop_motion
            k = np.maximum(np.searchsorted(start, update_time_s, side="right") - 1, 0)
            inside = (update_time_s >= start[k]) & (update_time_s <= end[k])
            motion[inside] = sigma[k[inside]]
        sigma = self.sigma_scale * np.hypot(self.sigma_velocity_mps, motion)
        return replace(self, time_s=update_time_s, sigma_mps=sigma), j, j

    def _sigma(self) -> np.ndarray:
        return self.sigma_mps if self.sigma_mps is not None else np.full(len(self.time_s), self.sigma_velocity_mps)

    def model(self, nav: NavSnapshot, i: int):
        H = _h(4)
        H[0:3, VEL : VEL + 3] = np.eye(3)
        rate_n = nav.c_bn @ nav.mean_omega_ib_b
        earth_rate = earth.earth_rate_ned(nav.lat, nav.ellipsoid)
        z = np.concatenate([nav.vel_ned, [rate_n[2] - earth_rate[2]]])
        H[3, ATT : ATT + 3] = skew(rate_n)[2]
        H[3, BG : BG + 3] = nav.c_bn[2]
        H[3, SG : SG + 3] = nav.c_bn[2] * nav.mean_omega_ib_b
        sigma_rate = self.gyro_white_noise / np.sqrt(max(nav.segment_s, 1e-3))
        R = np.diag([self._sigma()[i] ** 2] * 3 + [sigma_rate**2])
        return z, H, R

    def compiled(self) -> CompiledModel:
        return _compiled(MODEL_ZUPT, [self.gyro_white_noise], [self.time_s, np.square(self._sigma())])


@dataclass(frozen=True)
class PositionFix(_TimedSource):
    """A known position of a point on the trolley (a total-station prism on CPIII control),
    given as geodetic coordinates after the engineering-frame observation has been
    transformed by the project's CRS and height model."""

    time_s: np.ndarray
    lat: np.ndarray
    lon: np.ndarray
    h: np.ndarray
    sigma_m: np.ndarray
    lever_arm_m: np.ndarray
    name: str = "position_fix"
    resets: ClassVar[tuple[str, ...]] = ("position", "velocity", "attitude")
    position_innovation: ClassVar[bool] = True

    @classmethod
    def from_prism(cls, prism, lever_arm_m, to_geodetic) -> PositionFix:
        """From total-station observations in the engineering frame; ``to_geodetic(east, north,
        normal_height) -> (lat, lon, h)`` is the project's CRS and height model."""
        lat, lon, h = to_geodetic(prism.east_m, prism.north_m, prism.height_m)
        return cls(prism.time_s, np.asarray(lat), np.asarray(lon), np.asarray(h), prism.sigma_m, np.asarray(lever_arm_m))

    def scheduled(self, update_time_s, stops):
        """As every time-stamped source, except a fix taken in the stop the survey starts from or ends
        in: the trolley stands still there, so the fix holds through the stop and is applied (with its
        time moved there) where the run leaves it, at the stop's last update epoch, or where the run
        arrives, at its first. A survey without GNSS starts from such a fix (the start takes its
        position with a 1-sigma of at least ``insrail.nav.startup.MIN_START_SIGMA_M``, and an
        observation at the first epoch is not applied); counting the start's wide prior as well
        overstates the information there by (1 mm / 5 mm)^2 = 4 % of the variance for a 1 mm fix."""
        t = np.asarray(update_time_s, dtype=float)
        j, i = _timed_pairs(self.time_s, t)
        if not len(stops) or len(t) < 2:
            return self, j, i
        start = np.array([s[0] for s in stops])
        end = np.array([s[1] for s in stops])
        stop = np.maximum(np.searchsorted(start, self.time_s, side="right") - 1, 0)
        inside = (self.time_s >= start[stop]) & (self.time_s <= end[stop])
        leaves = inside & (start[stop] <= t[0]) & (t[1] <= end[stop])  # the stop holding the first two epochs
        arrives = inside & ~leaves & (start[stop] <= t[-1]) & (t[-1] <= end[stop])  # the one holding the last
        moved = np.where(leaves, np.searchsorted(t, end[stop], side="right") - 1,
                         np.searchsorted(t, start[stop], side="left"))
        held = np.flatnonzero((leaves | arrives) & (moved >= 1))
        keep = ~np.isin(i, held)
        time_s = np.asarray(self.time_s, dtype=float).copy()
        time_s[held] = t[moved[held]]
        return (replace(self, time_s=time_s), np.concatenate([moved[held], j[keep]]).astype(np.int64),
                np.concatenate([held, i[keep]]).astype(np.int64))

    def model(self, nav: NavSnapshot, i: int):
        z, H = _position_rows(nav, self.time_s[i], self.lat[i], self.lon[i], self.h[i], self.lever_arm_m)
        return z, H, np.eye(3) * self.sigma_m[i] ** 2

    def compiled(self) -> CompiledModel:
        variance = np.repeat(np.square(np.asarray(self.sigma_m, float))[:, None], 3, axis=1)
        return _position_compiled(self, variance, False)


# --------------------------------------------------------------------------- compiled form
#
# The filter loop of ``insrail.nav.fusion`` is compiled (numba): it cannot call the methods
# above per update. Each model kind therefore has a compiled twin below, fed by arrays the
# Python side prepares once per survey (:meth:`compiled` of each source: a kind, a few
# parameters, one row of numbers per observation), and evaluated on the compiled form of
# the :class:`NavSnapshot`, the context vector ``ctx`` (layout CTX_*). Every twin writes
# the innovation z, the rows of H and the diagonal of R (the models' noises are independent
# per row) into preallocated arrays and returns the number of rows; :func:`evaluate`
# dispatches on the kind. The Python methods stay the definition (the covariance analysis
# uses them); tests/test_nav_measurements.py holds the twins to them.

compiled_model = cached_njit(error_model="numpy")

CTX_TIME, CTX_LAT, CTX_LON, CTX_H = 0, 1, 2, 3
CTX_VEL = 4  # (3)
CTX_C_BN = 7  # (9) row-major
CTX_OMEGA_IB = 16  # (3) last epoch's compensated rate
CTX_F_B = 19  # (3) last epoch's compensated specific force
CTX_MEAN_VEL = 22  # (3)
CTX_MEAN_OMEGA = 25  # (3)
CTX_SEGMENT = 28
CTX_ODO_SCALE = 29
CTX_GNSS_ERROR = 30  # (3)
CTX_RM_H, CTX_RN_H = 33, 34  # radii plus height
CTX_OMEGA_IN = 35  # (3) omega_in^n
CTX_EARTH_RATE = 38  # (3) omega_ie^n
CTX_RATE_SPAN = 41  # the interval CTX_OMEGA_IB is the mean of
CTX_SIZE = 42

MAX_ROWS = 6
MODEL_PARAMS = 20
MODEL_WIDTH = 8

MODEL_POSITION, MODEL_GNSS_VELOCITY, MODEL_ODOMETER_NHC, MODEL_ZUPT = 0, 1, 2, 3


@dataclass(frozen=True)
class CompiledModel:
    """A source in the compiled filter's terms: its kind (MODEL_*), parameters (MODEL_PARAMS)
    and one row (MODEL_WIDTH) per observation."""

    kind: int
    params: np.ndarray
    rows: np.ndarray


def _compiled(kind: int, params, columns) -> CompiledModel:
    p = np.zeros(MODEL_PARAMS)
    p[: len(params)] = params
    n = max((len(c) for c in columns), default=0)
    rows = np.zeros((n, MODEL_WIDTH))
    for k, c in enumerate(columns):
        rows[:, k] = c
    return CompiledModel(kind, p, rows)


def _position_compiled(self, variance: np.ndarray, correlated: bool) -> CompiledModel:
    return _compiled(MODEL_POSITION, [*np.asarray(self.lever_arm_m, float), float(correlated)],
                     [self.time_s, self.lat, self.lon, self.h, *np.asarray(variance, float).T])


@compiled_model
def fill_context(ctx, nav, sums, dt_last, odo_scale, gnss_error, time_s, earth):
    """The compiled :class:`NavSnapshot` at an update epoch, from the navigation vector and the
    segment's sums of ``insrail.nav.fusion``'s strapdown (layout there)."""
    q = nav[_kernels.NAV_Q_BN : _kernels.NAV_Q_BN + 4]
    q0, q1, q2, q3 = q[0], q[1], q[2], q[3]
    c = ctx[CTX_C_BN : CTX_C_BN + 9]
    c[0] = q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3
    c[1] = 2.0 * (q1 * q2 - q0 * q3)
    c[2] = 2.0 * (q1 * q3 + q0 * q2)
    c[3] = 2.0 * (q1 * q2 + q0 * q3)
    c[4] = q0 * q0 - q1 * q1 + q2 * q2 - q3 * q3
    c[5] = 2.0 * (q2 * q3 - q0 * q1)
    c[6] = 2.0 * (q1 * q3 - q0 * q2)
    c[7] = 2.0 * (q2 * q3 + q0 * q1)
    c[8] = q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3
    lat, lon = _kernels.lat_lon((nav[_kernels.NAV_Q_NE], nav[_kernels.NAV_Q_NE + 1], nav[_kernels.NAV_Q_NE + 2],
                               nav[_kernels.NAV_Q_NE + 3]))
    h = nav[_kernels.NAV_H]
    ctx[CTX_TIME], ctx[CTX_LAT], ctx[CTX_LON], ctx[CTX_H] = time_s, lat, lon, h
    seg = sums[9]
    for a in range(3):
        ctx[CTX_VEL + a] = nav[_kernels.NAV_VEL + a]
        ctx[CTX_OMEGA_IB + a] = sums[10 + a] / dt_last
        ctx[CTX_F_B + a] = sums[13 + a] / dt_last
        ctx[CTX_MEAN_VEL + a] = sums[a] / seg
        ctx[CTX_MEAN_OMEGA + a] = sums[3 + a] / seg
        ctx[CTX_GNSS_ERROR + a] = gnss_error[a]
    ctx[CTX_SEGMENT] = seg
    ctx[CTX_RATE_SPAN] = dt_last
    ctx[CTX_ODO_SCALE] = odo_scale
    sl, cl = math.sin(lat), math.cos(lat)
    r_m, r_n = _kernels.radii(sl, earth)
    ctx[CTX_RM_H], ctx[CTX_RN_H] = r_m + h, r_n + h
    w = earth[_kernels.EARTH_OMEGA]
    vn, ve = ctx[CTX_VEL], ctx[CTX_VEL + 1]
    ctx[CTX_EARTH_RATE], ctx[CTX_EARTH_RATE + 1], ctx[CTX_EARTH_RATE + 2] = w * cl, 0.0, -w * sl
    ctx[CTX_OMEGA_IN] = w * cl + ve / (r_n + h)
    ctx[CTX_OMEGA_IN + 1] = -vn / (r_m + h)
    ctx[CTX_OMEGA_IN + 2] = -w * sl - ve * math.tan(lat) / (r_n + h)


@compiled_model
def _mat_vec(ctx, first, v):
    """C v for the row-major 3 x 3 matrix at ctx[first:first + 9]."""
    return (ctx[first] * v[0] + ctx[first + 1] * v[1] + ctx[first + 2] * v[2],
            ctx[first + 3] * v[0] + ctx[first + 4] * v[1] + ctx[first + 5] * v[2],
            ctx[first + 6] * v[0] + ctx[first + 7] * v[1] + ctx[first + 8] * v[2])


@compiled_model
def _put_skew(H, row, col, v):
    """H[row:row + 3, col:col + 3] = skew(v)."""
    H[row, col + 1], H[row, col + 2] = -v[2], v[1]
    H[row + 1, col], H[row + 1, col + 2] = v[2], -v[0]
    H[row + 2, col], H[row + 2, col + 1] = -v[1], v[0]


@compiled_model
def _position_model(ctx, params, obs, z, H, r):
    """GnssPosition (params[3] = 1: with the correlated error states) and PositionFix."""
    lever = (params[0], params[1], params[2])
    lever_n = _mat_vec(ctx, CTX_C_BN, lever)
    dt = obs[0] - ctx[CTX_TIME]
    measured = ((obs[1] - ctx[CTX_LAT]) * ctx[CTX_RM_H], (obs[2] - ctx[CTX_LON]) * ctx[CTX_RN_H] * math.cos(ctx[CTX_LAT]),
                -(obs[3] - ctx[CTX_H]))
    correlated = params[3] != 0.0
    for a in range(3):
        z[a] = lever_n[a] + ctx[CTX_VEL + a] * dt - measured[a]
        H[a, POS + a] = 1.0
        H[a, VEL + a] = dt
        if correlated:
            z[a] += ctx[CTX_GNSS_ERROR + a]
            H[a, GNSS + a] = -1.0
        r[a] = obs[4 + a]
    _put_skew(H, 0, ATT, lever_n)
    return 3


@compiled_model
def _gnss_velocity_model(ctx, params, obs, z, H, r):
    lever = (params[0], params[1], params[2])
    w = (ctx[CTX_OMEGA_IB], ctx[CTX_OMEGA_IB + 1], ctx[CTX_OMEGA_IB + 2])
    w_in = (ctx[CTX_OMEGA_IN], ctx[CTX_OMEGA_IN + 1], ctx[CTX_OMEGA_IN + 2])
    lever_n = _mat_vec(ctx, CTX_C_BN, lever)
    rotation_n = _mat_vec(ctx, CTX_C_BN, _kernels.cross(w, lever))
    transport = _kernels.cross(w_in, lever_n)
    for a in range(3):
        z[a] = ctx[CTX_VEL + a] + rotation_n[a] - transport[a] - obs[1 + a]
        H[a, VEL + a] = 1.0
        r[a] = obs[4 + a]
    # ATT: skew(rotation_n) - skew(w_in) skew(lever_n) = skew(rotation_n) - (lever_n w_in^T - (w_in . lever_n) I)
    _put_skew(H, 0, ATT, rotation_n)
    dot = w_in[0] * lever_n[0] + w_in[1] * lever_n[1] + w_in[2] * lever_n[2]
    for a in range(3):
        for b in range(3):
            H[a, ATT + b] -= lever_n[a] * w_in[b] - (dot if a == b else 0.0)
    # BG: -C skew(l); SG: the same with column b scaled by omega_b
    for a in range(3):
        c0, c1, c2 = ctx[CTX_C_BN + 3 * a], ctx[CTX_C_BN + 3 * a + 1], ctx[CTX_C_BN + 3 * a + 2]
        # row a of -C skew(l)
        m0 = -(c1 * lever[2] - c2 * lever[1])
        m1 = -(c2 * lever[0] - c0 * lever[2])
        m2 = -(c0 * lever[1] - c1 * lever[0])
        H[a, BG], H[a, BG + 1], H[a, BG + 2] = m0, m1, m2
        H[a, SG], H[a, SG + 1], H[a, SG + 2] = m0 * w[0], m1 * w[1], m2 * w[2]
    return 3


@compiled_model
def _vehicle_velocity_row(ctx, params, c_nv, omega_nb, lever, vel, axis, H, row):
    """Row ``axis`` of _VehicleFrame.velocity_rows: the velocity component and its Jacobian into H[row]."""
    c_vb = params[0:9]
    wl = _kernels.cross(omega_nb, lever)
    v = 0.0
    for b in range(3):
        v += c_nv[3 * axis + b] * vel[b] + c_vb[3 * axis + b] * wl[b]
        H[row, VEL + b] = c_nv[3 * axis + b]
    # ATT: -(c_nv skew(vel))[axis]; row of M skew(u) is (m1 u2 - m2 u1, m2 u0 - m0 u2, m0 u1 - m1 u0)
    m0, m1, m2 = c_nv[3 * axis], c_nv[3 * axis + 1], c_nv[3 * axis + 2]
    H[row, ATT] = -(m1 * vel[2] - m2 * vel[1])
    H[row, ATT + 1] = -(m2 * vel[0] - m0 * vel[2])
    H[row, ATT + 2] = -(m0 * vel[1] - m1 * vel[0])
    m0, m1, m2 = c_vb[3 * axis], c_vb[3 * axis + 1], c_vb[3 * axis + 2]
    l0 = -(m1 * lever[2] - m2 * lever[1])
    l1 = -(m2 * lever[0] - m0 * lever[2])
    l2 = -(m0 * lever[1] - m1 * lever[0])
    H[row, BG], H[row, BG + 1], H[row, BG + 2] = l0, l1, l2
    H[row, SG] = l0 * ctx[CTX_OMEGA_IB]
    H[row, SG + 1] = l1 * ctx[CTX_OMEGA_IB + 1]
    H[row, SG + 2] = l2 * ctx[CTX_OMEGA_IB + 2]
    return v


@compiled_model
def _odometer_nhc_model(ctx, params, obs, z, H, r):
    c_vb = params[0:9]
    # C_n^v = C_b^v C_n^b = c_vb c_bn^T; omega_nb^b = omega_ib^b - C_n^b omega_in^n
    c_nv = np.empty(9)
    for a in range(3):
        for b in range(3):
            c_nv[3 * a + b] = (c_vb[3 * a] * ctx[CTX_C_BN + 3 * b] + c_vb[3 * a + 1] * ctx[CTX_C_BN + 3 * b + 1]
                               + c_vb[3 * a + 2] * ctx[CTX_C_BN + 3 * b + 2])
    omega_nb = (ctx[CTX_OMEGA_IB] - (ctx[CTX_C_BN] * ctx[CTX_OMEGA_IN] + ctx[CTX_C_BN + 3] * ctx[CTX_OMEGA_IN + 1]
                                     + ctx[CTX_C_BN + 6] * ctx[CTX_OMEGA_IN + 2]),
                ctx[CTX_OMEGA_IB + 1] - (ctx[CTX_C_BN + 1] * ctx[CTX_OMEGA_IN] + ctx[CTX_C_BN + 4] * ctx[CTX_OMEGA_IN + 1]
                                         + ctx[CTX_C_BN + 7] * ctx[CTX_OMEGA_IN + 2]),
                ctx[CTX_OMEGA_IB + 2] - (ctx[CTX_C_BN + 2] * ctx[CTX_OMEGA_IN] + ctx[CTX_C_BN + 5] * ctx[CTX_OMEGA_IN + 1]
                                         + ctx[CTX_C_BN + 8] * ctx[CTX_OMEGA_IN + 2]))
    m = 0
    if params[16] != 0.0 and obs[4] != 0.0:
        lever = (params[9], params[10], params[11])
        mean_vel = (ctx[CTX_MEAN_VEL], ctx[CTX_MEAN_VEL + 1], ctx[CTX_MEAN_VEL + 2])
        # np.int64: constant arguments (Literal[int]) would compile the row a second time, for them
        v = _vehicle_velocity_row(ctx, params, c_nv, omega_nb, lever, mean_vel, np.int64(0), H, np.int64(0))
        corrected = obs[1] / (1.0 + ctx[CTX_ODO_SCALE])
        H[0, ODO] = -corrected / (1.0 + ctx[CTX_ODO_SCALE])
        z[0] = v - corrected
        # the odometer's noise and the last record's rate noise through the wheel's lever arm
        r[0] = obs[2] + params[18] * params[18] / ctx[CTX_RATE_SPAN] * (H[0, BG] ** 2 + H[0, BG + 1] ** 2 + H[0, BG + 2] ** 2)
        m = 1
    if params[17] != 0.0:
        lever = (params[12], params[13], params[14])
        vel = (ctx[CTX_VEL], ctx[CTX_VEL + 1], ctx[CTX_VEL + 2])
        for axis in (1, 2):
            z[m] = _vehicle_velocity_row(ctx, params, c_nv, omega_nb, lever, vel, axis, H, m)
            # the play's noise and the last record's rate noise through the lever arm (OdometerNhc.gyro_white_noise)
            rate = params[18] * params[18] / ctx[CTX_RATE_SPAN] * (H[m, BG] ** 2 + H[m, BG + 1] ** 2 + H[m, BG + 2] ** 2)
            r[m] = (params[15] * obs[3]) ** 2 + rate
            m += 1
    return m


@compiled_model
def _zupt_model(ctx, params, obs, z, H, r):
    w = (ctx[CTX_MEAN_OMEGA], ctx[CTX_MEAN_OMEGA + 1], ctx[CTX_MEAN_OMEGA + 2])
    rate_n = _mat_vec(ctx, CTX_C_BN, w)
    for a in range(3):
        z[a] = ctx[CTX_VEL + a]
        H[a, VEL + a] = 1.0
        r[a] = obs[1]
    z[3] = rate_n[2] - ctx[CTX_EARTH_RATE + 2]
    H[3, ATT], H[3, ATT + 1] = -rate_n[1], rate_n[0]
    for b in range(3):
        H[3, BG + b] = ctx[CTX_C_BN + 6 + b]
        H[3, SG + b] = ctx[CTX_C_BN + 6 + b] * w[b]
    sigma_rate = params[0] / math.sqrt(max(ctx[CTX_SEGMENT], 1e-3))
    r[3] = sigma_rate * sigma_rate
    return 4


@compiled_model
def evaluate(kind, ctx, params, obs, z, H, r):
    """(z, H, diag R) of one observation ``obs`` (its row) of a source of ``kind`` into z, H
    (rows cleared first) and r; returns the number of rows."""
    H[:] = 0.0
    if kind == MODEL_POSITION:
        return _position_model(ctx, params, obs, z, H, r)
    if kind == MODEL_GNSS_VELOCITY:
        return _gnss_velocity_model(ctx, params, obs, z, H, r)
    if kind == MODEL_ODOMETER_NHC:
        return _odometer_nhc_model(ctx, params, obs, z, H, r)
    if kind == MODEL_ZUPT:
        return _zupt_model(ctx, params, obs, z, H, r)
    return -1


# The twins call the strapdown's helpers: their cache entries go when those change (see _kernels).
_kernels.drop_stale_cache((fill_context, _mat_vec, _put_skew, _position_model, _gnss_velocity_model,
                           _vehicle_velocity_row, _odometer_nhc_model, _zupt_model, evaluate), (_kernels.__file__,))
