"""Aiding measurements: each turns the INS state at an update epoch into (innovation, H, R).

Every class holds its data (times and values), and ``model(nav, i)`` returns, for its
i-th observation, the innovation z = predicted - measured (m,), the Jacobian H (m, 22)
with respect to the error state of ``insrail.nav.error_model`` and the noise
covariance R (m, m). The filter never needs to know what a measurement is.

Lever arms are b-frame vectors from the IMU centre (thesis eqs. 2.106-2.125).
"""

from __future__ import annotations

from dataclasses import dataclass, field

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


@dataclass(frozen=True)
class GnssPosition:
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

    def model(self, nav: NavSnapshot, i: int):
        z, H = _position_rows(nav, self.time_s[i], self.lat[i], self.lon[i], self.h[i], self.lever_arm_m)
        # residual state x_g = g - g_hat: z = dr - (g - g_hat) once the estimate is removed
        z = z + nav.gnss_error_ned_m
        H[:, GNSS : GNSS + 3] = -np.eye(3)
        variance = np.square(self.sigma_scale * self.sigma_ned_m[i]) - np.square(self.correlated_sigma_ned_m)
        return z, H, np.diag(np.maximum(variance, self.sigma_floor_m**2))


@dataclass(frozen=True)
class GnssVelocity:
    """GNSS (Doppler) velocity of the antenna (thesis 2.113-2.118)."""

    time_s: np.ndarray
    vel_ned: np.ndarray
    sigma_ned_mps: np.ndarray
    lever_arm_m: np.ndarray
    sigma_floor_mps: float = 0.002
    name: str = "gnss_velocity"

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
class PositionFix:
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

    @classmethod
    def from_prism(cls, prism, lever_arm_m, to_geodetic) -> PositionFix:
        """From total-station observations in the engineering frame; ``to_geodetic(east, north,
        normal_height) -> (lat, lon, h)`` is the project's CRS and height model."""
        lat, lon, h = to_geodetic(prism.east_m, prism.north_m, prism.height_m)
        return cls(prism.time_s, np.asarray(lat), np.asarray(lon), np.asarray(h), prism.sigma_m, np.asarray(lever_arm_m))

    def model(self, nav: NavSnapshot, i: int):
        z, H = _position_rows(nav, self.time_s[i], self.lat[i], self.lon[i], self.h[i], self.lever_arm_m)
        return z, H, np.eye(3) * self.sigma_m[i] ** 2
