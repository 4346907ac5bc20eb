"""GNSS/INS/odometer fusion: closed-loop error-state EKF and RTS smoother.

Forward pass
    The IMU epochs are cut into segments at update epochs: a fixed grid (``update_rate_hz``,
    10 Hz by default, where odometer/NHC and ZUPT are applied) plus the epoch that closes
    each GNSS observation. A compiled kernel (numba) runs the strapdown over a segment with
    the increments compensated by the current sensor-error estimates and accumulates the
    mean velocity and rates over it; Python then propagates the covariance over the whole
    segment in one step (Phi to second order, trapezoidal Q) and applies the segment's
    measurements one after the other, each gated by a chi-square test on its innovation.
    After the updates the error state is fed back into the navigation solution and the
    sensor-error estimates and reset to zero (thesis Fig. 5-8). No Python code runs per
    200 Hz epoch.

Smoother
    Rauch-Tung-Striebel over the segments (thesis 2.93-2.95). With closed-loop resets the
    forward estimate of the error is zero after every update, so the smoothed error of the
    stored solution obeys e_j = A_j (e_{j+1} + dx_{j+1}) with A_j = P+_j Phi_{j+1}^T
    (P-_{j+1})^-1 and dx_{j+1} the update applied at j+1 (ins-filter digest 6.2).

Memory stays bounded: what the backward pass needs per segment (Phi, P-, P+, dx: 1474
doubles, 12 kB) goes to a temporary file in chunks and is read back chunk by chunk in
reverse, so a 10 km survey (90 000 segments, about 1 GB) never holds more than one chunk
of covariances in RAM. The navigation solution itself (12 doubles per IMU epoch) stays
in memory.

Error-state conventions: see ``insrail.nav.error_model``. Navigation errors are computed
minus true (subtracted on feedback); sensor-error states are the residual errors not yet
compensated (added to the estimates on feedback).
"""

from __future__ import annotations

import math
import tempfile
from dataclasses import dataclass, field, replace
from typing import Self

import numpy as np
from numba import njit
from scipy.stats import chi2

from insrail.io.survey import SurveyData, TrolleyGeometry
from insrail.io.types import GnssSolution, ImuIncrements, OdometerData
from insrail.nav import _kernels, earth, integrity, kalman
from insrail.nav.alignment import detect_stops, stop_thresholds
from insrail.nav.error_model import (
    ATT,
    BG,
    GNSS,
    N_STATES,
    ODO,
    POS,
    SA,
    VEL,
    ErrorModelNoise,
    discretise,
    dynamics_matrix,
    initial_sensor_sigmas,
    noise_matrix,
)
from insrail.nav.imu_gaps import bridge_gaps, bridged_process_noise
from insrail.nav.imu_profile import ImuProfile, load_imu_profile
from insrail.nav.imu_screening import screen_imu
from insrail.nav.integrity import FusionIntegrity, InnovationRecord
from insrail.nav.measurements import (
    GnssPosition,
    GnssVelocity,
    NavSnapshot,
    OdometerNhc,
    PositionFix,
    Zupt,
    schedule,
)
from insrail.nav.mechanization import (
    euler_from_q_bn,
    lat_lon_from_q_ne,
    q_ne_from_lat_lon,
)
from insrail.nav.rotation import (
    euler_to_dcm,
    quat_multiply,
    quat_to_dcm,
    rotvec_to_quat,
)
from insrail.nav.startup import PositionTrack, initial_state
from insrail.nav.trajectory import Trajectory
from insrail.notices import Notice
from insrail.progress import CancelToken, ProgressFn, StepProgress, check_cancel


@dataclass(frozen=True)
class FusionOptions:
    """What the filter uses and how much it trusts it."""

    use_gnss_velocity: bool = True  # when the GNSS file has velocities
    use_odometer: bool = True
    use_nhc: bool = True
    use_zupt: bool = True
    smoother: bool = True
    update_rate_hz: float = 10.0
    gnss_sigma_scale: float = 1.0
    #: (RTKLIB quality flag, factor on its sigmas or None to exclude): 0 unknown, 1 fix, 2 float,
    #: 3 SBAS, 4 DGPS, 5 single, 6 PPP. Float solutions are kept with inflated sigmas, single ones left out.
    gnss_quality_policy: tuple[tuple[int, float | None], ...] = (
        (0, 1.0), (1, 1.0), (2, 3.0), (3, 5.0), (4, 5.0), (5, None), (6, 2.0),
    )
    gnss_sigma_floor_m: float = 0.002
    #: correlated part of the GNSS position error (Gauss-Markov): short-baseline PPK
    gnss_correlated_sigma_ned_m: tuple[float, float, float] = (0.005, 0.005, 0.010)
    gnss_correlated_tau_s: float = 300.0
    # Calibrated so that the mean NIS per degree of freedom of odometer/NHC is within 0.5-2 on the
    # simulator (0.57-0.60; benchmarks/fusion.py) with the clean accuracy unchanged (within 2 %):
    # the NHC innovations are 0.33 mm/s RMS (the trolley's play), the thesis's Table 3-2 says
    # 0.1 mm/s/sqrt(Hz), i.e. 0.3 mm/s at 10 Hz; tighter than 0.45 mm/s the solution follows the play.
    odometer_sigma_mps: float = 0.0005  # plus the pulse quantisation over the segment
    nhc_sigma_mps: float = 0.00045
    # A standing trolley: kept at 1 mm/s for real ones (an operator's touch), so on the simulator,
    # whose trolley stands perfectly still, the ZUPT's mean NIS per dof is 0.25 (its velocity rows
    # see 0.02-0.08 mm/s); tightening it does not change that much (0.4 at 0.01 mm/s).
    zupt_sigma_mps: float = 0.001
    gate_probability: float = 0.9999
    initial_heading_rad: float | None = None  # None: gyrocompassing in the static start
    initial_sigma_heading_rad: float = math.radians(0.1)
    initial_sigma_level_rad: float = math.radians(0.01)
    initial_sigma_odometer_scale: float = 0.01
    min_static_s: float = 30.0
    max_imu_gap_s: float = 5.0  # longer IMU gaps are refused, shorter ones bridged with a warning
    #: Gating that cannot lock out: an aiding source rejected without a break for this long means
    #: the filter is wrong, not the sensor: the filter is reset (``FilterReset``). Longer than a
    #: GNSS false fix lasts (a wrong ambiguity fix of 10-20 cm for some seconds) so that one is
    #: rejected, not followed; the shorter limit applies while another source is rejected too
    #: (every sensor disagreeing with the filter: an IMU fault, a lost filter).
    reset_after_s: float = 20.0
    reset_after_s_all_rejected: float = 2.0
    #: the limit for observations that doubt themselves (GNSS float, DGPS): a float stretch is
    #: rejected for as long as it disagrees, the filter reset only after this long
    reset_after_s_doubtful: float = 120.0
    #: what the reset widens at least to: position (or twice the largest rejected position
    #: innovation), velocity (or that position over the time rejected), level and heading
    reset_sigma_position_m: float = 0.5
    reset_sigma_velocity_mps: float = 0.1
    reset_sigma_level_rad: float = math.radians(0.2)
    reset_sigma_heading_rad: float = math.radians(10.0)


@dataclass(frozen=True)
class Rejection:
    time_s: float
    measurement: str
    test_statistic: float
    threshold: float
    innovation: tuple[float, ...]


@dataclass(frozen=True)
class FilterReset:
    """The filter was reset at ``time_s``: ``source`` had been rejected without a break for
    ``rejected_s`` seconds (``rejected`` observations), with ``also_rejected`` rejected at the same
    time; the variances of ``states`` were raised to ``sigma`` (SI, same order)."""

    time_s: float
    source: str
    rejected_s: float
    rejected: int
    first_rejected_s: float  # the time of the run's first rejection: the solution is suspect from then on
    also_rejected: tuple[str, ...]
    states: tuple[str, ...]
    sigma: tuple[float, ...]

    def message(self) -> str:
        others = f" (and {', '.join(self.also_rejected)})" if self.also_rejected else ""
        return (f"filter reset at t = {self.time_s:.1f} s: {self.source}{others} rejected for {self.rejected_s:.1f} s "
                f"({self.rejected} in a row); {', '.join(self.states)} uncertainty widened and the measurements re-admitted")


class _RejectionRuns:
    """Per aiding source the current run of consecutive rejections (NaN start: none), and the
    decision that a run means the filter, not the sensor, is wrong. Plain arrays, one slot per source."""

    def __init__(self, sources, options: FusionOptions):
        k = len(sources)
        self.sources, self.options = sources, options
        self.start = np.full(k, np.nan)
        self.first_trusted = np.full(k, np.nan)  # the run's first rejection of a trusted observation
        self.last = np.full(k, np.nan)
        self.count = np.zeros(k, dtype=np.int64)
        self.peak = np.zeros((k, 3))  # largest |position innovation| per NED axis in the run
        self.resets_in_a_row = np.zeros(k, dtype=np.int64)  # resets that did not bring the source back

    def accepted(self, k: int) -> None:
        self.start[k] = np.nan
        self.first_trusted[k] = np.nan
        self.count[k] = 0
        self.peak[k] = 0.0
        self.resets_in_a_row[k] = 0

    def rejected(self, k: int, i: int, time_s: float, nu: np.ndarray) -> FilterReset | None:
        """Record the rejection of observation i of source k; a reset when the run has lasted too long."""
        if np.isnan(self.start[k]):
            self.start[k] = time_s
        trusted = getattr(self.sources[k], "trusted", None)
        if np.isnan(self.first_trusted[k]) and (trusted is None or trusted[i]):
            self.first_trusted[k] = time_s
        self.last[k] = time_s
        self.count[k] += 1
        if self.sources[k].position_innovation:
            self.peak[k] = np.maximum(self.peak[k], np.abs(nu[:3]))
        others = [o for o in range(len(self.sources))
                  if o != k and not np.isnan(self.start[o]) and time_s - self.last[o] <= 1.0]
        o = self.options
        trusted_for = time_s - self.first_trusted[k]  # NaN: no trusted observation rejected
        if not (trusted_for >= (o.reset_after_s_all_rejected if others else o.reset_after_s)
                or time_s - self.start[k] >= o.reset_after_s_doubtful):
            return None
        return self._reset(k, time_s, others)

    def _reset(self, k: int, time_s: float, others: list[int]) -> FilterReset:
        o = self.options
        involved = [k, *others]
        widen = 10.0 ** min(self.resets_in_a_row[k], 3)  # a reset that did not help is followed by a wider one
        names = {name for i in involved for name in self.sources[i].resets}
        peak = np.max(self.peak[involved], axis=0)
        duration = max(time_s - np.nanmin(self.start[involved]), 1.0)
        sigma_pos = np.maximum(2.0 * peak, o.reset_sigma_position_m)
        sigma_vel = widen * np.maximum(sigma_pos / duration if "position" in names else 0.0, o.reset_sigma_velocity_mps)
        sigma_pos = widen * sigma_pos
        # attitude: widened no further (beyond some degrees the error model's small angles fail)
        sigma_att = np.array([o.reset_sigma_level_rad, o.reset_sigma_level_rad, o.reset_sigma_heading_rad])
        states, sigma, labels = [], [], []
        for label, first, values in (("position", POS, sigma_pos), ("velocity", VEL, sigma_vel), ("attitude", ATT, sigma_att)):
            if label in names:
                states.extend(range(first, first + 3))
                sigma.extend(np.broadcast_to(values, 3).tolist())
                labels.append(label)
        reset = FilterReset(float(time_s), self.sources[k].name, float(time_s - self.start[k]), int(self.count[k]),
                            float(np.nanmin(self.start[involved])),
                            tuple(self.sources[i].name for i in others), tuple(labels), tuple(sigma))
        for i in involved:
            resets = self.resets_in_a_row[i]
            self.accepted(i)
            self.resets_in_a_row[i] = resets + 1
        return reset


@dataclass
class MeasurementStats:
    used: int = 0
    rejected: int = 0
    sum_sq: np.ndarray | None = None  # per innovation component
    sum_nis: float = 0.0
    sum_dof: int = 0

    def add(self, z, nis):
        self.used += 1
        self.sum_sq = z**2 if self.sum_sq is None else self.sum_sq + z**2
        self.sum_nis += nis
        self.sum_dof += len(z)

    def summary(self) -> dict:
        """Counts, innovation RMS per component, the mean NIS of the used observations and that
        mean over their degrees of freedom (1 when the stated 1-sigma fits the innovations)."""
        rms = (np.sqrt(self.sum_sq / self.used).tolist() if self.used else [])
        return {"used": self.used, "rejected": self.rejected, "innovation_rms": rms,
                "mean_nis": self.sum_nis / self.used if self.used else float("nan"),
                "mean_nis_per_dof": self.sum_nis / self.sum_dof if self.sum_dof else float("nan")}


@dataclass(frozen=True)
class UpdateTimeline:
    """What the forward filter did when, for covariance analyses along the survey
    (``insrail.quality.survey_quality``): the update epochs, the measurement models, and per
    measurement the (update-epoch index, observation index) pairs it applied; rejected
    observations are not listed. The record costs two integers per applied observation."""

    time_s: np.ndarray  # (m,) update epochs [s of week]
    measurements: dict  # name -> measurement model (insrail.nav.measurements)
    applied: dict  # name -> (k, 2) int array
    initial_covariance: np.ndarray  # (N, N) at the first update epoch


@dataclass(frozen=True)
class FusionResult:
    trajectory: Trajectory  # smoothed when options.smoother, else the forward solution
    forward: Trajectory
    rejections: tuple[Rejection, ...]
    statistics: dict
    stops: tuple[tuple[float, float], ...]
    info: dict = field(default_factory=dict)
    timeline: UpdateTimeline | None = None
    resets: tuple[FilterReset, ...] = ()
    innovations: InnovationRecord | None = None
    integrity: FusionIntegrity | None = None


# --------------------------------------------------------------------------- kernel


@njit(cache=True)
def _propagate_segment(nav, dtheta, dvel, dt, start, stop, sensor, earth_c, out, sums):
    """Strapdown over epochs start..stop-1 with compensated increments.

    sensor = [bg(3), ba(3), sg(3), sa(3)] (estimates); out[k] receives nav after epoch k;
    sums = [sum v dt (3), sum dtheta_c (3), sum dvel_c (3), total dt, last dtheta_c (3),
    last dvel_c (3)].
    """
    for i in range(16):
        sums[i] = 0.0
    th_prev = np.empty(3)
    dv_prev = np.empty(3)
    th = np.empty(3)
    dv = np.empty(3)
    for k in range(start, stop):
        prev = k - 1 if k > 0 else 0
        for a in range(3):
            th_prev[a] = (dtheta[prev, a] - sensor[a] * dt[prev]) / (1.0 + sensor[6 + a])
            dv_prev[a] = (dvel[prev, a] - sensor[3 + a] * dt[prev]) / (1.0 + sensor[9 + a])
            th[a] = (dtheta[k, a] - sensor[a] * dt[k]) / (1.0 + sensor[6 + a])
            dv[a] = (dvel[k, a] - sensor[3 + a] * dt[k]) / (1.0 + sensor[9 + a])
        _kernels.strapdown_step(nav, th_prev, dv_prev, th, dv, dt[k], earth_c, nav)
        for a in range(12):
            out[k, a] = nav[a]
        for a in range(3):
            sums[a] += nav[_kernels.NAV_VEL + a] * dt[k]
            sums[3 + a] += th[a]
            sums[6 + a] += dv[a]
        sums[9] += dt[k]
    for a in range(3):
        sums[10 + a] = th[a]
        sums[13 + a] = dv[a]


# --------------------------------------------------------------------------- storage


class SmootherStore:
    """Append-only, chunked, disk-backed record of a forward pass for the RTS pass: per update
    epoch j = 1, 2, ... (record j - 1) Phi and Q's result P- of the segment ending at j, P+
    after the updates at j and the update dx applied there. Read back last epoch first.

    :func:`fuse` keeps its own for the smoother and closes it. A caller that wants the
    covariances once the fusion is done (the covariance analysis of ``insrail.quality``
    reads them instead of replaying the filter) passes one it owns to ``fuse`` and closes it
    when done: ``with SmootherStore() as store: ...``.
    """

    RECORD = 3 * N_STATES * N_STATES + N_STATES  # Phi, P-, P+, dx

    def __init__(self, chunk: int = 2048):
        self.file = tempfile.TemporaryFile(prefix="insrail-rts-")
        self.chunk = chunk
        self.buffer = np.empty((chunk, self.RECORD))
        self.fill = 0
        self.count = 0

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def append(self, phi, p_minus, p_plus, dx):
        n = N_STATES * N_STATES
        row = self.buffer[self.fill]
        row[:n] = phi.ravel()
        row[n : 2 * n] = p_minus.ravel()
        row[2 * n : 3 * n] = p_plus.ravel()
        row[3 * n :] = dx
        self.fill += 1
        self.count += 1
        if self.fill == self.chunk:
            self.flush()

    def flush(self):
        if self.fill:
            try:
                self.file.write(self.buffer[: self.fill].tobytes())
            except OSError as err:  # an unnamed file: say where it lies (a full disk names the folder to clear)
                raise OSError(err.errno, err.strerror,
                              f"{tempfile.gettempdir()} (the smoother's temporary file)") from None
            self.fill = 0

    def reversed_records(self):
        """(j, Phi_j, P-_j, P+_j, dx_j) for j = count, ..., 1: views into one chunk read from disk."""
        self.flush()
        size = self.RECORD * 8
        nn = N_STATES * N_STATES
        for first in range(((self.count - 1) // self.chunk) * self.chunk, -1, -self.chunk):
            n = min(self.chunk, self.count - first)
            self.file.seek(first * size)
            chunk = np.frombuffer(self.file.read(n * size), dtype=np.float64).reshape(n, self.RECORD)
            for r in range(n - 1, -1, -1):
                rec = chunk[r]
                yield (first + r + 1, rec[:nn].reshape(N_STATES, N_STATES), rec[nn : 2 * nn].reshape(N_STATES, N_STATES),
                       rec[2 * nn : 3 * nn].reshape(N_STATES, N_STATES), rec[3 * nn :])

    def close(self):
        self.file.close()


# --------------------------------------------------------------------------- helpers


def _feedback(nav: np.ndarray, dx: np.ndarray, sensor: np.ndarray, gnss_error: np.ndarray, odo_scale: float, ell) -> float:
    """Apply the error estimate dx to the navigation vector, the sensor and GNSS error
    estimates (in place); returns the new odometer scale estimate."""
    lat, lon = lat_lon_from_q_ne(nav[0:4])
    h = nav[4]
    r_m, r_n = earth.radii(lat, ell)
    lat -= dx[POS] / (r_m + h)
    lon -= dx[POS + 1] / ((r_n + h) * np.cos(lat))
    nav[0:4] = q_ne_from_lat_lon(lat, lon)
    nav[4] = h + dx[POS + 2]
    nav[5:8] -= dx[VEL : VEL + 3]
    # C_b^n <- (I + phi x) C_b^n: rotate the computed attitude back by phi in the n-frame.
    q = quat_multiply(rotvec_to_quat(dx[ATT : ATT + 3]), nav[8:12])
    nav[8:12] = q / np.linalg.norm(q)
    sensor += dx[BG : SA + 3]
    gnss_error += dx[GNSS : GNSS + 3]
    return odo_scale + dx[ODO]


#: without an odometer, a gap of the positions longer than this [s] leaves the along-track position unaided
UNAIDED_OUTAGE_S = 10.0

QUALITY_NAMES = {0: "unknown", 1: "fix", 2: "float", 3: "sbas", 4: "dgps", 5: "single", 6: "ppp"}
#: GNSS solutions that claim their full accuracy (unknown: a format without flags)
TRUSTED_QUALITY = (0, 1, 6)


def gnss_by_quality(gnss: GnssSolution, policy) -> tuple[GnssSolution, dict[str, dict]]:
    """Apply the surveyor's choice per GNSS quality flag: keep with sigmas x factor, or exclude.

    Returns the solution to use and, per quality present, {"epochs", "factor", "used"}.
    """
    factors = dict(policy)
    keep = np.zeros(len(gnss), dtype=bool)
    scale = np.ones(len(gnss))
    counts = {}
    for q in np.unique(gnss.quality):
        mask = gnss.quality == q
        factor = factors.get(int(q))
        counts[QUALITY_NAMES.get(int(q), str(int(q)))] = {
            "epochs": int(mask.sum()), "sigma_factor": factor, "used": factor is not None,
        }
        if factor is not None:
            keep |= mask
            scale[mask] = factor
    sig_vel = None if gnss.sigma_vel_ned_mps is None else gnss.sigma_vel_ned_mps[keep] * scale[keep, None]
    kept = replace(
        gnss,
        time_s=gnss.time_s[keep], lat_rad=gnss.lat_rad[keep], lon_rad=gnss.lon_rad[keep], height_m=gnss.height_m[keep],
        sigma_ned_m=gnss.sigma_ned_m[keep] * scale[keep, None], quality=gnss.quality[keep], num_sats=gnss.num_sats[keep],
        ratio=gnss.ratio[keep], vel_ned_mps=None if gnss.vel_ned_mps is None else gnss.vel_ned_mps[keep],
        sigma_vel_ned_mps=sig_vel,
    )
    return kept, counts


def initial_covariance(profile: ImuProfile, options: FusionOptions, sigma_pos_ned_m, sigma_vel_mps: float,
                       sigma_level_rad: float, sigma_heading_rad: float) -> np.ndarray:
    """P at the first update epoch, from the alignment's sigmas, the IMU profile and the options."""
    sig = np.zeros(N_STATES)
    sig[POS : POS + 3] = sigma_pos_ned_m
    sig[VEL : VEL + 3] = sigma_vel_mps
    sig[ATT : ATT + 3] = [sigma_level_rad, sigma_level_rad, sigma_heading_rad]
    sig[BG : SA + 3] = initial_sensor_sigmas(profile)
    sig[ODO] = options.initial_sigma_odometer_scale
    sig[GNSS : GNSS + 3] = options.gnss_correlated_sigma_ned_m
    return np.diag(np.maximum(sig, 1e-12) ** 2)


@dataclass(frozen=True)
class Aiding:
    """What the filter is aided with: the aiding sources (``insrail.nav.measurements``), applied
    at an update epoch in this order, and what the start of the filter needs besides them (the
    GNSS solution for the initial position and the track heading, the odometer for stop
    detection and the initial speed, the trolley's mounting and lever arms)."""

    measurements: tuple
    gnss: GnssSolution | None  # after the quality policy (``gnss_by_quality``); None: no GNSS (prism fixes)
    odometer: OdometerData | None  # None: no odometer (NHC alone, stops from the IMU and the positions)
    trolley: TrolleyGeometry
    gnss_quality: dict = field(default_factory=dict)  # per quality flag: epochs, sigma factor, used
    design_azimuth: object = None  # the design's azimuth at a position, for the start (insrail.nav.startup)


_ALL_TIME_S = np.array([-1e12, 1e12])


def aiding_sources(options: FusionOptions, trolley: TrolleyGeometry, profile: ImuProfile, gnss: GnssSolution | None,
                   odometer: OdometerData | None, position_fixes: PositionFix | None = None) -> tuple:
    """The aiding sources as ``options`` selects them, in the order the filter applies them at
    an update epoch: GNSS positions (and velocities), total-station fixes, odometer/NHC, ZUPT.
    The fusion and the accuracy prediction (``insrail.quality.prediction``) both build theirs here."""
    sources: list = []
    if gnss is not None:
        sources.append(GnssPosition(gnss.time_s, gnss.lat_rad, gnss.lon_rad, gnss.height_m, gnss.sigma_ned_m,
                                    trolley.imu_to_antenna_m, options.gnss_sigma_scale, options.gnss_sigma_floor_m,
                                    options.gnss_correlated_sigma_ned_m,
                                    trusted=np.isin(gnss.quality, TRUSTED_QUALITY)))
    if gnss is not None and options.use_gnss_velocity and gnss.vel_ned_mps is not None:
        sources.append(GnssVelocity(gnss.time_s, gnss.vel_ned_mps, gnss.sigma_vel_ned_mps, trolley.imu_to_antenna_m))
    if position_fixes is not None:
        sources.append(position_fixes)
    use_odometer = options.use_odometer and odometer is not None
    if use_odometer or options.use_nhc:
        # without an odometer the NHC rows alone, on a record that covers all time (its speeds unused)
        odo_t, odo_d = (odometer.time_s, odometer.distance_m) if odometer is not None else (_ALL_TIME_S, np.zeros(2))
        sources.append(OdometerNhc.from_distance(
            odo_t, odo_d, euler_to_dcm(*trolley.mounting_rpy_rad), trolley.imu_to_odometer_m,
            trolley.imu_to_reference_rail_m, options.odometer_sigma_mps,
            (odometer.pulse_length_m if odometer is not None else None) or 0.001,
            sigma_nhc_mps=options.nhc_sigma_mps, use_odometer=use_odometer, use_nhc=options.use_nhc))
    if options.use_zupt:
        sources.append(Zupt(np.zeros(0), options.zupt_sigma_mps, gyro_white_noise=max(profile.gyro_arw, 1e-7)))
    return tuple(sources)


def aiding_for(survey: SurveyData, options: FusionOptions, profile: ImuProfile,
               position_fixes: PositionFix | None = None) -> Aiding:
    """What a survey aids the filter with (:func:`aiding_sources`), its GNSS after the quality policy."""
    gnss, gnss_quality = (None, {}) if survey.gnss is None else gnss_by_quality(survey.gnss, options.gnss_quality_policy)
    trolley = survey.manifest.trolley
    return Aiding(aiding_sources(options, trolley, profile, gnss, survey.odometer, position_fixes), gnss,
                  survey.odometer, trolley, gnss_quality)


def fuse_survey(survey: SurveyData, options: FusionOptions = FusionOptions(), profile: ImuProfile | None = None,
                ellipsoid: earth.Ellipsoid = earth.WGS84, position_fixes: PositionFix | None = None,
                **kwargs) -> FusionResult:
    """:func:`fuse` with the aiding sources of a survey (:func:`aiding_for`) and its IMU profile."""
    profile = profile or load_imu_profile(survey.manifest.imu_profile)
    return fuse(survey.imu, aiding_for(survey, options, profile, position_fixes), profile, options, ellipsoid, **kwargs)


def update_grid(imu_time_s: np.ndarray, k0: int, every: int, measurements) -> np.ndarray:
    """The IMU epochs that end a filter segment: every ``every``-th from the start epoch
    ``k0``, the epoch that closes each time-stamped observation, and the last epoch."""
    closing = [np.zeros(0, dtype=int)]
    for meas in measurements:
        times = meas.closing_times_s()
        inside = times[(times > imu_time_s[k0]) & (times <= imu_time_s[-1])]
        closing.append(np.searchsorted(imu_time_s, inside))
    n = len(imu_time_s)
    return np.unique(np.concatenate([np.arange(k0, n, every), *closing, [n - 1]])).astype(int)


# --------------------------------------------------------------------------- engine


def fuse(
    imu: ImuIncrements,
    aiding: Aiding,
    profile: ImuProfile,
    options: FusionOptions = FusionOptions(),
    ellipsoid: earth.Ellipsoid = earth.WGS84,
    output_every: int = 1,
    covariance_store: SmootherStore | None = None,
    progress: ProgressFn | None = None,
    cancel: CancelToken = None,
) -> FusionResult:
    """Fuse IMU increments with a list of aiding sources into a trajectory.

    aiding         : the sources and what the start needs (:func:`aiding_for` builds it from a
                     survey; total-station fixes are a source like the others, geodetic
                     positions of the prism the caller transformed with the project's CRS)
    output_every   : the trajectories hold every n-th IMU epoch (1: the full IMU rate)
    covariance_store : an empty :class:`SmootherStore` owned by the caller: the forward pass
                     records into it (whether or not ``options.smoother``) and leaves it open, so
                     the covariances can be analysed after the fusion without replaying it
    """
    if covariance_store is not None and covariance_store.count:
        raise ValueError(f"the covariance store already holds {covariance_store.count} records: pass an empty one")
    step = StepProgress(progress)
    noise = ErrorModelNoise.from_profile(profile, options.gnss_correlated_tau_s, options.gnss_correlated_sigma_ned_m)
    gqg = noise_matrix(noise)
    trolley = aiding.trolley
    c_vb = euler_to_dcm(*trolley.mounting_rpy_rad)
    source_file = str(imu.source or "")
    imu, outliers, notices = screen_imu(imu, profile)
    imu, warnings = bridge_gaps(imu, options.max_imu_gap_s)
    removed = np.array([o.time_s for o in outliers])
    notices += [Notice("imu", w, file=source_file, time_s=gap.start_s) for gap, w in zip(imu.gaps, warnings)
                if not np.any((removed > gap.start_s) & (removed < gap.end_s))]  # a removed record says so itself
    n = len(imu)
    t = imu.time_s
    dt = np.empty(n)
    dt[1:] = np.diff(t)
    dt[0] = np.median(dt[1 : min(n, 1000)])

    gnss = aiding.gnss
    fixes = next((m for m in aiding.measurements if isinstance(m, PositionFix)), None)
    if aiding.odometer is None:
        notices.append(Notice("fusion", "no odometer in the survey: the along-track scale comes from the "
                              f"{'GNSS positions' if gnss is not None else 'prism fixes'} only", severity="info"))
    if gnss is not None:
        track = PositionTrack.from_gnss(gnss, trolley.imu_to_antenna_m).within(t[0], t[-1])
    elif fixes is not None:
        track = PositionTrack.from_fixes(fixes).within(t[0], t[-1])
    else:
        raise ValueError("the survey has neither GNSS nor total-station prism fixes: nothing gives its position")
    if len(track) == 0:
        where = gnss.source if gnss is not None and gnss.source else track.source
        raise ValueError(
            f"{where}: no {track.source} epoch lies within the IMU data "
            f"({t[0]:.3f} - {t[-1]:.3f} s of week); check the files and their time scales"
        )
    if aiding.odometer is None and gnss is not None and len(track) > 1:
        outage = np.flatnonzero(np.diff(track.time_s) > UNAIDED_OUTAGE_S)
        for i in outage:
            notices.append(Notice(
                "fusion", f"no odometer: across the {track.source} outage of {track.time_s[i + 1] - track.time_s[i]:.0f} s "
                f"after t = {track.time_s[i]:.1f} s the along-track position rests on the IMU alone",
                time_s=float(track.time_s[i])))
    gyro_quiet, accel_quiet = stop_thresholds(profile.gyro_arw, profile.accel_vrw, 1.0 / dt[0])
    positions = None
    if aiding.odometer is None and gnss is not None:
        positions = (track.time_s, track.local_ned(ellipsoid)[:, :2], track.horizontal_sigma_m())
    stops = detect_stops(imu, aiding.odometer, max_gyro_std_radps=gyro_quiet, positions=positions,
                         max_accel_std_mps2=None if aiding.odometer is not None else accel_quiet)
    start = initial_state(imu, track, stops, aiding.odometer, c_vb, profile, options, ellipsoid, aiding.design_azimuth)
    notices.extend(start.notices)
    k0, nav = start.epoch, start.nav
    nav_store = np.empty((n, 12))
    nav_store[: k0 + 1] = nav[:12]

    every = max(int(round(1.0 / (options.update_rate_hz * dt[0]))), 1)
    epochs = update_grid(t, k0, every, aiding.measurements)
    plan = schedule(t[epochs], aiding.measurements, stops)
    bridged_q = bridged_process_noise(imu, epochs)
    sources = plan.measurements

    # --- forward pass ---------------------------------------------------------------------
    P = initial_covariance(profile, options, start.sigma_pos_ned_m, start.sigma_vel_mps, start.sigma_level_rad,
                           start.sigma_heading_rad)
    P_initial = P.copy()
    accepted = np.zeros(len(plan.epoch), dtype=bool)
    innovation_nis = np.full(len(plan.epoch), np.nan)
    innovation_dof = np.zeros(len(plan.epoch), dtype=np.int64)
    runs = _RejectionRuns(sources, options)
    resets: list[FilterReset] = []
    pending_reset = None
    sensor = np.zeros(12)
    gnss_error = np.zeros(3)
    odo_scale = 0.0
    sensor_hist = np.empty((len(epochs), 13))
    sigma_hist = np.empty((len(epochs), N_STATES))
    sensor_hist[0, :12], sensor_hist[0, 12] = sensor, odo_scale
    sigma_hist[0] = np.sqrt(np.diag(P))
    own_store = covariance_store is None and options.smoother
    store = SmootherStore() if own_store else covariance_store
    earth_c = _kernels.earth_constants(ellipsoid)
    sums = np.zeros(16)
    gates = {m: chi2.ppf(options.gate_probability, m) for m in range(1, 7)}
    stats: dict[str, MeasurementStats] = {}
    rejections: list[Rejection] = []
    forward_step = step.sub(0.0, 0.8 if options.smoother else 0.95)
    m_epochs = len(epochs)

    try:
        for j in range(1, m_epochs):
            if j % 2000 == 0:
                check_cancel(cancel)
                forward_step(j / m_epochs, f"forward filter {t[epochs[j]] - t[epochs[0]]:.0f} s")
            a, b = epochs[j - 1] + 1, epochs[j] + 1
            _propagate_segment(nav, imu.dtheta_rad, imu.dvel_mps, dt, a, b, sensor, earth_c, nav_store, sums)
            seg = sums[9]
            lat, lon = lat_lon_from_q_ne(nav[0:4])
            snap = NavSnapshot(
                time_s=t[b - 1], lat=float(lat), lon=float(lon), h=float(nav[4]), vel_ned=nav[5:8].copy(),
                c_bn=quat_to_dcm(nav[8:12]), omega_ib_b=sums[10:13] / dt[b - 1], f_b=sums[13:16] / dt[b - 1],
                mean_vel_ned=sums[0:3] / seg, mean_omega_ib_b=sums[3:6] / seg, segment_s=seg,
                odometer_scale=odo_scale, ellipsoid=ellipsoid, gnss_error_ned_m=gnss_error.copy(),
            )
            F = dynamics_matrix(snap.lat, snap.h, snap.vel_ned, snap.c_bn, sums[6:9] / seg, sums[3:6] / seg, noise, ellipsoid)
            phi, q = discretise(F, gqg, seg)
            q = q + bridged_q.get(j, 0.0)  # the motion an IMU gap's interpolation may have missed
            P_minus = phi @ P @ phi.T + q
            if pending_reset is not None:  # a burst of process noise on this segment
                P_minus = kalman.inflate(P_minus, np.array(pending_reset[0]), np.array(pending_reset[1]))
                pending_reset = None
            P = P_minus.copy()
            x = np.zeros(N_STATES)
            gnss_error *= math.exp(-seg / options.gnss_correlated_tau_s)  # the estimate follows its model

            entries = plan.at(j)
            for e in entries:
                meas, i = sources[plan.source[e]], int(plan.observation[e])
                z, H, R = meas.model(snap, i)
                x, P, nu, nis, ok = kalman.gated_update(x, P, z, H, R, gates[len(z)])
                st = stats.setdefault(meas.name, MeasurementStats())
                innovation_nis[e], innovation_dof[e] = nis, len(z)
                if not ok:
                    st.rejected += 1
                    rejections.append(Rejection(float(meas.time_s[i]), meas.name, nis, gates[len(z)], tuple(nu)))
                    reset = runs.rejected(int(plan.source[e]), i, float(meas.time_s[i]), nu)
                    if reset is not None:
                        resets.append(reset)
                        pending_reset = ([s for label, first in (("position", POS), ("velocity", VEL), ("attitude", ATT))
                                          if label in reset.states for s in range(first, first + 3)], reset.sigma)
                    continue
                st.add(nu, nis)
                runs.accepted(int(plan.source[e]))
                accepted[e] = True
            if len(entries):
                odo_scale = _feedback(nav, x, sensor, gnss_error, odo_scale, ellipsoid)
            P = 0.5 * (P + P.T)
            if store is not None:
                store.append(phi, P_minus, P, x)
            sensor_hist[j, :12], sensor_hist[j, 12] = sensor, odo_scale
            sigma_hist[j] = np.sqrt(np.diag(P))

        forward = _trajectory(t, nav_store, epochs, sensor_hist, sigma_hist, None, imu.gps_week, ellipsoid, False,
                              output_every)
        trajectory = forward
        if options.smoother:
            smooth_step = step.sub(0.8, 0.95)
            corrections, sigma_smooth = _rts(store, m_epochs, sigma_hist[0], cancel, smooth_step)
            trajectory = _trajectory(t, nav_store, epochs, sensor_hist, sigma_smooth, corrections, imu.gps_week,
                                     ellipsoid, True, output_every)
    finally:
        if own_store:
            store.close()
    step(1.0, "fusion done")
    statistics = {name: s.summary() for name, s in stats.items()}
    applied = {}
    for k, meas in enumerate(sources):
        mine = accepted & (plan.source == k)
        if mine.any():
            applied[meas.name] = np.column_stack([plan.epoch[mine], plan.observation[mine]]).astype(int)
    timeline = UpdateTimeline(time_s=t[epochs], measurements={m.name: m for m in sources}, applied=applied,
                              initial_covariance=P_initial)
    obs_time = np.empty(len(plan.epoch))
    obs_trusted = np.ones(len(plan.epoch), dtype=bool)
    for k, meas in enumerate(sources):
        mine = plan.source == k
        obs_time[mine] = meas.time_s[plan.observation[mine]]
        if getattr(meas, "trusted", None) is not None:
            obs_trusted[mine] = meas.trusted[plan.observation[mine]]
    innovations = InnovationRecord(tuple(m.name for m in sources), obs_time, plan.source.copy(), innovation_nis,
                                   innovation_dof, accepted, obs_trusted)
    lat_e, lon_e = lat_lon_from_q_ne(nav_store[epochs, 0:4])
    r_m, r_n = earth.radii(lat_e[0], ellipsoid)
    station = integrity.travelled_m((lat_e - lat_e[0]) * r_m, (lon_e - lon_e[0]) * r_n * math.cos(lat_e[0]))
    verdict = integrity.assess(innovations, t[epochs], station, resets)
    notices += integrity_notices(resets, verdict)
    return FusionResult(trajectory, forward, tuple(rejections), statistics, tuple(stops), timeline=timeline,
                        resets=tuple(resets), innovations=innovations, integrity=verdict,
                        info={"update_epochs": m_epochs, "alignment_rpy_rad": start.rpy_rad,
                              "alignment": start.method, "warnings": [n.message for n in notices if n.severity == "warning"],
                              "notices": notices, "gnss_quality": aiding.gnss_quality,
                              "imu_outliers": outliers, "imu_gaps": imu.gaps})


def integrity_notices(resets, verdict: FusionIntegrity) -> list[Notice]:
    """Every filter reset and every section whose solution is inconsistent with its 1-sigma (its
    sleepers are not assessed): notices with their times."""
    notices = [Notice("fusion", reset.message(), time_s=reset.time_s) for reset in resets]
    notices += [Notice("fusion", f"not valid from t = {verdict.time_from_s[k]:.1f} s to {verdict.time_to_s[k]:.1f} s "
                                 f"(travelled {verdict.station_from_m[k]:.0f}-{verdict.station_to_m[k]:.0f} m): "
                                 f"{verdict.reasons[k]}; its sleepers are not assessed",
                       time_s=float(verdict.time_from_s[k]))
                for k in np.flatnonzero(~verdict.valid)]
    return notices


def _rts(store: SmootherStore, m: int, sigma0: np.ndarray, cancel: CancelToken, progress):
    """Backward RTS pass. Returns per update epoch j the correction pair
    (left: e_j relative to the stored post-update solution, right: e_j + dx_j relative
    to the pre-update solution) as an (m, 2, N) array, and the smoothed sigmas (m, N)."""
    corrections = np.zeros((m, 2, N_STATES))
    sigma = np.zeros((m, N_STATES))
    e_next = np.zeros(N_STATES)
    P_s_next = None
    phi_next = p_minus_next = None
    for j, phi, p_minus, p_plus, dx in store.reversed_records():
        if j % 2048 == 0:
            check_cancel(cancel)
            progress((m - j) / m, "smoother")
        if P_s_next is None:  # last epoch: smoothed = filtered
            e, P_s = np.zeros(N_STATES), p_plus
        else:
            e, P_s = kalman.rts_step(e_next, P_s_next, phi_next, p_minus_next, p_plus)
        corrections[j, 0] = e
        corrections[j, 1] = e + dx
        sigma[j] = np.sqrt(np.maximum(np.diag(P_s), 0.0))
        # Prepare epoch j-1: its successor's quantities.
        e_next = e + dx
        P_s_next, phi_next, p_minus_next = P_s, phi, p_minus
    # epoch 0: before the first segment
    e, P_s = kalman.rts_step(e_next, P_s_next, phi_next, p_minus_next, np.diag(sigma0**2))
    corrections[0, 0] = corrections[0, 1] = e
    sigma[0] = np.sqrt(np.maximum(np.diag(P_s), 0.0))
    return corrections, sigma


def _trajectory(t, nav_store, epochs, sensor_hist, sigma_hist, corrections, gps_week, ell, smoothed, output_every,
                chunk: int = 100_000):
    """Trajectory at every ``output_every``-th IMU epoch from the first update epoch on, the
    errors interpolated linearly between update epochs. Built in chunks so the temporaries
    of a 10 km survey stay small."""
    idx_all = np.arange(epochs[0], epochs[-1] + 1, output_every)
    n = len(idx_all)
    out = {name: np.empty((n, 3)) for name in ("vel", "rpy", "sp", "sv", "sa", "bg", "ba", "sg", "sa_")}
    lat_out, lon_out, h_out, odo_out = np.empty(n), np.empty(n), np.empty(n), np.empty(n)
    for c0 in range(0, n, chunk):
        idx = idx_all[c0 : c0 + chunk]
        sl = slice(c0, c0 + len(idx))
        # Segment j covers epochs (epochs[j-1], epochs[j]]; w is the position inside it.
        seg = np.clip(np.searchsorted(epochs, idx, side="left"), 1, len(epochs) - 1)
        left, right = epochs[seg - 1], epochs[seg]
        w = ((t[idx] - t[left]) / (t[right] - t[left]))[:, None]
        nav = nav_store[idx]
        lat, lon = lat_lon_from_q_ne(nav[:, 0:4])
        h, vel, q_bn = nav[:, 4], nav[:, 5:8], nav[:, 8:12]
        sensors = sensor_hist[seg - 1].copy()  # the estimates used while propagating the segment
        if corrections is not None:
            c = (1.0 - w) * corrections[seg - 1, 0] + w * corrections[seg, 1]
            r_m, r_n = earth.radii(lat, ell)
            lat = lat - c[:, POS] / (r_m + h)
            lon = lon - c[:, POS + 1] / ((r_n + h) * np.cos(lat))
            h = h + c[:, POS + 2]
            vel = vel - c[:, VEL : VEL + 3]
            q_bn = quat_multiply(rotvec_to_quat(c[:, ATT : ATT + 3]), q_bn)
            sensors[:, :12] += c[:, BG : SA + 3]
            sensors[:, 12] += c[:, ODO]
        sig = (1.0 - w) * sigma_hist[seg - 1] + w * sigma_hist[seg]
        lat_out[sl], lon_out[sl], h_out[sl] = lat, lon, h
        out["vel"][sl] = vel
        out["rpy"][sl] = np.column_stack(euler_from_q_bn(q_bn))
        out["sp"][sl], out["sv"][sl], out["sa"][sl] = sig[:, POS : POS + 3], sig[:, VEL : VEL + 3], sig[:, ATT : ATT + 3]
        out["bg"][sl], out["ba"][sl], out["sg"][sl], out["sa_"][sl] = (sensors[:, 0:3], sensors[:, 3:6], sensors[:, 6:9], sensors[:, 9:12])
        odo_out[sl] = sensors[:, 12]
    return Trajectory(
        time_s=t[idx_all], lat_rad=lat_out, lon_rad=lon_out, height_m=h_out, vel_ned_mps=out["vel"], rpy_rad=out["rpy"],
        sigma_pos_ned_m=out["sp"], sigma_vel_ned_mps=out["sv"], sigma_rpy_rad=out["sa"],
        gyro_bias_radps=out["bg"], accel_bias_mps2=out["ba"], gyro_scale=out["sg"], accel_scale=out["sa_"],
        odometer_scale=odo_out, smoothed=smoothed, gps_week=gps_week, ellipsoid_name=ell.name,
    )
