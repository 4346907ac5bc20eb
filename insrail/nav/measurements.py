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

The data are plain arrays and ``model`` is array-in, array-out, so that a compiled filter
loop can evaluate the same models later.

Lever arms are b-frame vectors from the IMU centre (thesis eqs. 2.106-2.125).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import ClassVar, Protocol

import numpy as np

from insrail.nav import earth
from insrail.nav.error_model import ATT, BG, GNSS, N_STATES, ODO, POS, SG, VEL
from insrail.nav.rotation import cross, skew


@dataclass(frozen=True)
class NavSnapshot:
    """The INS solution at an update epoch (compensated sensor values).

    omega_ib_b, f_b : angular rate [rad/s] and specific force [m/s^2] of the last epoch
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
        sigma = odometer_speed_sigma(span, self.pulse_length_m, self.sigma_odometer_mps)
        valid = (times[:-1] >= self.odometer_time_s[0]) & (times[1:] <= self.odometer_time_s[-1])
        i = np.flatnonzero(valid).astype(np.int64)
        return replace(self, time_s=times[1:], speed_mps=speed, sigma_speed_mps=sigma), i + 1, i

    def model(self, nav: NavSnapshot, i: int):
        rows, z, sig = [], [], []
        frame = _VehicleFrame.at(nav, self.dcm_vehicle_from_body)
        if self.use_odometer:
            v_mean, H_odo = frame.velocity_rows(self.odometer_lever_arm_m, nav.mean_vel_ned)
            corrected = self.speed_mps[i] / (1.0 + nav.odometer_scale)
            # odometer state = residual scale error s - s_hat: z = dv_x - v (s - s_hat)
            H_odo[0, ODO] = -corrected
            rows.append(H_odo[0])
            z.append(v_mean[0] - corrected)
            sig.append(self.sigma_speed_mps[i])
        if self.use_nhc:
            v_ref, H_nhc = frame.velocity_rows(self.nhc_lever_arm_m, nav.vel_ned)
            rows.extend(H_nhc[1:3])
            z.extend(v_ref[1:3])
            sig.extend([self.sigma_nhc_mps] * 2)
        return np.array(z), np.array(rows).reshape(len(z), N_STATES), np.diag(np.square(sig))


@dataclass(frozen=True)
class Zupt:
    """Zero velocity and zero heading rate while the trolley stands still.

    Velocity rows: the INS velocity must be zero. Heading-rate row (ZARU): the mean
    compensated gyro rate about the vertical must equal the earth rate's vertical
    component; it observes the vertical gyro bias.
    """

    time_s: np.ndarray
    sigma_velocity_mps: float = 0.001
    gyro_white_noise: float = 1e-6  # rad/sqrt(s): the ZARU sigma is this / sqrt(segment)
    name: str = "zupt"
    resets: ClassVar[tuple[str, ...]] = ("velocity",)
    position_innovation: ClassVar[bool] = False

    def closing_times_s(self) -> np.ndarray:
        return _NO_TIMES

    def scheduled(self, update_time_s, stops):
        """Applied at the end of every segment that starts and ends inside a stop
        (observation i = update epoch j)."""
        rest = at_rest(stops, update_time_s)
        j = np.flatnonzero(rest[1:] & rest[:-1]).astype(np.int64) + 1
        return replace(self, time_s=np.asarray(update_time_s)), j, j

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
        R = np.diag([self.sigma_velocity_mps**2] * 3 + [sigma_rate**2])
        return z, H, R


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

    def model(self, nav: NavSnapshot, i: int):
        z, H = _position_rows(nav, self.time_s[i], self.lat[i], self.lon[i], self.h[i], self.lever_arm_m)
        return z, H, np.eye(3) * self.sigma_m[i] ** 2
