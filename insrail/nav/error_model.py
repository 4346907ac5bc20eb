"""The INS error-state model: 22 states, their dynamics F, noise and discretisation.

State vector (0-based indices). Navigation errors (0-8) are "computed minus true";
sensor errors (9-21) are the residual errors not yet compensated ("true minus
estimate"), so the feedback subtracts the first and adds the second:

====  =======================================  ==========
0-2   position error, NED                      m (dr_D = -dh)
3-5   velocity error, NED                      m/s
6-8   attitude error phi (true n -> computed)  rad
9-11  gyro bias, b frame                       rad/s
12-14 accelerometer bias, b frame              m/s^2
15-17 gyro scale-factor error                  -
18-20 accelerometer scale-factor error         -
21    odometer scale-factor error              -
22-24 GNSS correlated position error, NED       m
====  =======================================  ==========

States 0-20 are the thesis's 21 states (eq. 2.96), F from eqs. 2.61-2.72 with the
sensor coupling of eqs. 2.24-2.26 (ins-filter digest section 5.7). State 21 augments
them with the odometer scale factor (see ``insrail.nav.measurements.OdometerNhc`` for
why it is a state here and not a pre-processing step as in thesis 5.3.1). States 22-24
model the slowly varying part of the GNSS (PPK) position error as first-order
Gauss-Markov (a few mm over minutes: multipath, residual troposphere). Treating it as
white, as the thesis does, makes the solution follow that wander at the 150 m scale
the 300 m/150 m check measures; modelled, the filter leans on the INS, odometer and NHC
there and on GNSS only for the long-term position.

Sensor errors are first-order Gauss-Markov. A bias is a turn-on constant plus an in-run
Gauss-Markov part (sigma_gm, tau): its variance stays turn-on^2 + sigma_gm^2 however long it is
not observed, and over a short time it changes only by the in-run part, 2 sigma_gm^2 / tau per
second. One state holds both as a Gauss-Markov process of that variance driven by that noise, its
correlation time tau (turn-on^2 + sigma_gm^2) / sigma_gm^2 (:func:`bias_tau_s`; a random constant
without an in-run part). With the in-run part's own tau the turn-on part was forgotten within
tau / 2 wherever nothing observed it: a MEMS accelerometer's 2 mg turn-on bias across the track,
which only the roll balances (prism fixes, no GNSS), was believed known to 0.05 mg after a few
minutes, and with it the roll to 0.3 mrad against an actual 2.4 mrad (issue 33). The
scale factors' initial sigma is their Gauss-Markov sigma. The odometer scale is a
random constant with a tiny random walk (wheel wear, temperature).

Discretisation over an interval dt (thesis 2.101, 2.105): Phi = I + F dt + (F dt)^2 / 2
and Q_k = (Phi G Q G^T Phi^T + G Q G^T) dt / 2.

The trolley's play (its frame's small yaw and pitch about the rail, ``resources/trolley_play.toml``)
makes the rail point the NHC integrates drift from the rail as a random walk in distance, q per metre
run. The NHC's white noise (sigma at the update rate f) already lets the position wander by
sigma^2 / f per second; where the NHC holds the trolley to the rail, Q_k's position block gets the
rest, :func:`play_noise`: q * run - sigma^2 / f * dt over a segment (none below the speed
sigma^2 / (f q), 0.81 m/s for the defaults), lateral and vertical to the track.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from functools import cache

import numpy as np

from insrail.nav import earth
from insrail.nav.imu_profile import ImuProfile
from insrail.nav.rotation import skew
from insrail.resources import resources_dir

N_STATES = 25
POS, VEL, ATT, BG, BA, SG, SA, ODO, GNSS = 0, 3, 6, 9, 12, 15, 18, 21, 22

#: Random walk of the odometer scale factor [1/sqrt(s)]: 1e-5 per sqrt(hour).
ODOMETER_SCALE_RANDOM_WALK = 1e-5 / 60.0


@dataclass(frozen=True)
class ErrorModelNoise:
    """Continuous noise parameters the filter uses (SI), from an IMU profile."""

    vrw: float
    arw: float
    gyro_bias_tau_s: float
    gyro_bias_psd: float
    accel_bias_tau_s: float
    accel_bias_psd: float
    gyro_scale_tau_s: float
    gyro_scale_psd: float
    accel_scale_tau_s: float
    accel_scale_psd: float
    gnss_tau_s: float = 300.0
    gnss_sigma_ned_m: tuple[float, float, float] = (0.005, 0.005, 0.010)

    @classmethod
    def from_profile(cls, p: ImuProfile, gnss_tau_s: float = 300.0,
                     gnss_sigma_ned_m: tuple[float, float, float] = (0.005, 0.005, 0.010)) -> "ErrorModelNoise":
        return cls(
            gnss_tau_s=gnss_tau_s,
            gnss_sigma_ned_m=tuple(gnss_sigma_ned_m),
            vrw=p.accel_vrw,
            arw=p.gyro_arw,
            gyro_bias_tau_s=bias_tau_s(p.gyro_bias_turn_on, p.gyro_bias_gm_sigma, p.gyro_bias_gm_tau_s),
            gyro_bias_psd=2.0 * p.gyro_bias_gm_sigma**2 / p.gyro_bias_gm_tau_s,
            accel_bias_tau_s=bias_tau_s(p.accel_bias_turn_on, p.accel_bias_gm_sigma, p.accel_bias_gm_tau_s),
            accel_bias_psd=2.0 * p.accel_bias_gm_sigma**2 / p.accel_bias_gm_tau_s,
            gyro_scale_tau_s=p.gyro_scale_factor_tau_s,
            gyro_scale_psd=2.0 * p.gyro_scale_factor**2 / p.gyro_scale_factor_tau_s,
            accel_scale_tau_s=p.accel_scale_factor_tau_s,
            accel_scale_psd=2.0 * p.accel_scale_factor**2 / p.accel_scale_factor_tau_s,
        )


def bias_tau_s(turn_on: float, gm_sigma: float, gm_tau_s: float) -> float:
    """Correlation time [s] of the one Gauss-Markov state that holds a bias's turn-on constant and its
    in-run part (module docstring): the variance turn-on^2 + gm_sigma^2, driven by the in-run part's
    2 gm_sigma^2 / gm_tau_s; infinite (a random constant) without an in-run part."""
    if gm_sigma <= 0.0:
        return math.inf
    return gm_tau_s * (turn_on**2 + gm_sigma**2) / gm_sigma**2


def initial_sensor_sigmas(p: ImuProfile) -> np.ndarray:
    """1-sigma of states 9-20 at the start: turn-on and in-run parts together."""
    gyro_bias = np.hypot(p.gyro_bias_turn_on, p.gyro_bias_gm_sigma)
    accel_bias = np.hypot(p.accel_bias_turn_on, p.accel_bias_gm_sigma)
    return np.repeat([gyro_bias, accel_bias, p.gyro_scale_factor, p.accel_scale_factor], 3)


def dynamics_matrix(lat, h, vel_ned, c_bn, f_b, omega_ib_b, noise: ErrorModelNoise, ell=earth.WGS84) -> np.ndarray:
    """F (22 x 22) at one epoch; f_b and omega_ib_b are the compensated specific force
    [m/s^2] and angular rate [rad/s] in b."""
    vn, ve, vd = vel_ned
    r_m, r_n = earth.radii(lat, ell)
    rm, rn = r_m + h, r_n + h
    w = ell.omega
    sl, cl, tl = np.sin(lat), np.cos(lat), np.tan(lat)
    sec2 = 1.0 / cl**2
    g = earth.normal_gravity(lat, h, ell)
    f_n = c_bn @ f_b

    F = np.zeros((N_STATES, N_STATES))
    # position (2.70-2.72)
    F[0, 0], F[0, 2] = -vd / rm, vn / rm
    F[1, 0], F[1, 1], F[1, 2] = ve * tl / rn, -(vd + vn * tl) / rn, ve / rn
    F[0:3, 3:6] = np.eye(3)
    # velocity (2.65-2.67)
    F[3, 0] = -(2 * ve * w * cl / rm + ve**2 * sec2 / (rm * rn))
    F[3, 2] = vn * vd / rm**2 - ve**2 * tl / rn**2
    F[4, 0] = 2 * w * (vn * cl - vd * sl) / rm + vn * ve * sec2 / (rm * rn)
    F[4, 2] = (ve * vd + vn * ve * tl) / rn**2
    F[5, 0] = 2 * w * ve * sl / rm
    F[5, 2] = -(ve**2 / rn**2 + vn**2 / rm**2 - 2 * g / (np.sqrt(r_m * r_n) + h))
    F[3, 3], F[3, 4], F[3, 5] = vd / rm, -2 * (w * sl + ve * tl / rn), vn / rm
    F[4, 3], F[4, 4], F[4, 5] = 2 * w * sl + ve * tl / rn, (vd + vn * tl) / rn, 2 * w * cl + ve / rn
    F[5, 3], F[5, 4] = -2 * vn / rm, -2 * (w * cl + ve / rn)
    F[3:6, 6:9] = skew(f_n)
    F[3:6, BA : BA + 3] = c_bn
    F[3:6, SA : SA + 3] = c_bn * f_b  # C_b^n diag(f^b)
    # attitude (2.61-2.63)
    F[6, 0], F[6, 2] = -w * sl / rm, ve / rn**2
    F[7, 2] = -vn / rm**2
    F[8, 0], F[8, 2] = -(w * cl / rm + ve * sec2 / (rn * rm)), -ve * tl / rn**2
    F[6, 4], F[7, 3], F[8, 4] = 1.0 / rn, -1.0 / rm, -tl / rn
    omega_in = np.array([w * cl + ve / rn, -vn / rm, -w * sl - ve * tl / rn])
    F[6:9, 6:9] = -skew(omega_in)
    F[6:9, BG : BG + 3] = -c_bn
    F[6:9, SG : SG + 3] = -c_bn * omega_ib_b
    # sensor errors: first-order Gauss-Markov
    F[BG : BG + 3, BG : BG + 3] = -np.eye(3) / noise.gyro_bias_tau_s
    F[BA : BA + 3, BA : BA + 3] = -np.eye(3) / noise.accel_bias_tau_s
    F[SG : SG + 3, SG : SG + 3] = -np.eye(3) / noise.gyro_scale_tau_s
    F[SA : SA + 3, SA : SA + 3] = -np.eye(3) / noise.accel_scale_tau_s
    F[GNSS : GNSS + 3, GNSS : GNSS + 3] = -np.eye(3) / noise.gnss_tau_s
    return F


def noise_matrix(noise: ErrorModelNoise) -> np.ndarray:
    """G Q G^T (22 x 22): the continuous process-noise spectral density in state space.

    The white noises are equal on the three sensor axes, so C_b^n Q C_n^b = Q: the
    matrix does not depend on the attitude.
    """
    q = np.zeros((N_STATES, N_STATES))
    q[3:6, 3:6] = noise.vrw**2 * np.eye(3)
    q[6:9, 6:9] = noise.arw**2 * np.eye(3)
    q[BG : BG + 3, BG : BG + 3] = noise.gyro_bias_psd * np.eye(3)
    q[BA : BA + 3, BA : BA + 3] = noise.accel_bias_psd * np.eye(3)
    q[SG : SG + 3, SG : SG + 3] = noise.gyro_scale_psd * np.eye(3)
    q[SA : SA + 3, SA : SA + 3] = noise.accel_scale_psd * np.eye(3)
    q[ODO, ODO] = ODOMETER_SCALE_RANDOM_WALK**2
    q[GNSS : GNSS + 3, GNSS : GNSS + 3] = np.diag(2.0 * np.square(noise.gnss_sigma_ned_m) / noise.gnss_tau_s)
    return q


@cache
def trolley_play_drift_m2_per_m() -> tuple[float, float]:
    """(lateral, vertical) drift variance of the trolley's play per metre run [m^2/m], from
    ``resources/trolley_play.toml``."""
    path = resources_dir() / "trolley_play.toml"
    with open(path, "rb") as handle:
        drift = tomllib.load(handle)["drift"]
    return drift["lateral_mm2_per_m"] * 1e-6, drift["vertical_mm2_per_m"] * 1e-6


def trolley_play_band_per_m() -> float:
    """B = 1/shortest - 1/longest wavelength [1/m] of the play's flat spectrum (``resources/trolley_play.toml``):
    at speed v its lateral (vertical) velocity has the variance 2 B v^2 x its drift per metre."""
    with open(resources_dir() / "trolley_play.toml", "rb") as handle:
        spectrum = tomllib.load(handle)["spectrum"]
    return 1.0 / spectrum["shortest_wavelength_m"] - 1.0 / spectrum["longest_wavelength_m"]


def play_noise(displacement_ned_m: np.ndarray, dt: float, play: np.ndarray) -> np.ndarray:
    """Position process noise (3 x 3, NED) of the trolley's play over a segment of ``dt`` seconds that
    moved by ``displacement_ned_m`` (module docstring): ``play`` = (lateral drift, vertical drift [m^2
    per metre run], the NHC noise's own drift sigma^2 / f [m^2/s]); lateral across the horizontal
    displacement, vertical along down (grades of a few per mille ignored). Plain scalar code: the
    compiled filter runs it as it is (``insrail.nav.fusion``)."""
    q = np.zeros((3, 3))
    dn, de = displacement_ned_m[0], displacement_ned_m[1]
    run = math.sqrt(dn * dn + de * de)
    if run > 0.0:
        lateral = max(play[0] * run - play[2] * dt, 0.0) / (run * run)  # its variance * u u^T, u = (-de, dn) / run
        q[0, 0] = lateral * de * de
        q[0, 1] = -lateral * dn * de
        q[1, 0] = q[0, 1]
        q[1, 1] = lateral * dn * dn
        q[2, 2] = max(play[1] * run - play[2] * dt, 0.0)
    return q


def discretise(F: np.ndarray, gqg: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """(Phi, Q_k) over ``dt`` (thesis 2.101 to second order, 2.105 trapezoid)."""
    fdt = F * dt
    phi = np.eye(N_STATES) + fdt + 0.5 * (fdt @ fdt)
    q = 0.5 * (phi @ gqg @ phi.T + gqg) * dt
    return phi, q
