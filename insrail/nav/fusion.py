"""GNSS/INS/odometer fusion: closed-loop error-state EKF and RTS smoother.

Forward pass
    The IMU epochs are cut into segments at update epochs: a fixed grid (``update_rate_hz``,
    10 Hz by default, where odometer/NHC and ZUPT are applied) plus the epoch that closes
    each GNSS observation. One compiled loop (numba, ``_forward_kernel``) runs per segment
    the strapdown with the increments compensated by the current sensor-error estimates
    (accumulating the mean velocity and rates over it), propagates the covariance over the
    whole segment in one step (Phi to second order, trapezoidal Q, on Phi's block structure:
    rows 0-8 dense, the sensor and GNSS Gauss-Markov rows diagonal), and applies the
    segment's measurements one after the other - each source's compiled model
    (``insrail.nav.measurements``, "compiled form"), each gated by a chi-square test on its
    innovation (``insrail.nav.kalman``). After the updates the error state is fed back into
    the navigation solution and the sensor-error estimates and reset to zero (thesis
    Fig. 5-8). Python runs only at events: a rejected observation (the rejection runs and
    the decision to reset the filter, :class:`_RejectionRuns`), the first acceptance after
    one, full output buffers and progress every 2000 segments.

Smoother
    Rauch-Tung-Striebel over the segments (thesis 2.93-2.95), compiled, chunk by chunk. With
    closed-loop resets the forward estimate of the error is zero after every update, so the
    smoothed error of the stored solution obeys e_j = A_j (e_{j+1} + dx_{j+1}) with A_j =
    P+_j Phi_{j+1}^T (P-_{j+1})^-1 and dx_{j+1} the update applied at j+1 (ins-filter digest
    6.2). The corrections are kept at the filter rate and interpolated to the IMU rate while
    the trajectory is written.

Memory stays bounded: the IMU increments reach the filter through a buffer of IMU_CHUNK
records refilled at an event (a file :func:`insrail.io.imu.read_imu_npy` mapped is never held
whole: its pages are let go behind the buffer); what the backward pass needs per segment (Phi,
P-, P+, dx packed: 916 doubles, 7.3 kB) goes to a temporary file in chunks and is read back
chunk by chunk in reverse; the forward solution at the IMU rate (12 doubles per epoch), the
forward pass's sensor estimates and sigmas and the smoother's corrections and sigmas per
update epoch go to other temporary files; the trajectory is built from them in chunks (each
reading the update epochs it lies between) and, with ``trajectory_file``, written to disk as
it is made. What still stays in memory per update epoch: the forward solution there
(``FusionResult.forward``, 32 doubles, built after the smoothed trajectory), the schedule's and the innovations' entries, the
timeline (about 0.4 kB per update epoch); per IMU epoch, the times (8 bytes).

Error-state conventions: see ``insrail.nav.error_model``. Navigation errors are computed
minus true (subtracted on feedback); sensor-error states are the residual errors not yet
compensated (added to the estimates on feedback).
"""

from __future__ import annotations

import contextlib
import itertools
import math
import os
import tempfile
import threading
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from functools import partial
from pathlib import Path
from typing import Self

import numpy as np

from insrail import jit
from insrail.io.atomic import named_write, write_at
from insrail.io.imu import release_pages
from insrail.io.survey import SurveyData, TrolleyGeometry
from insrail.io.types import GnssSolution, ImuIncrements, OdometerData
from insrail.jit import cached_njit
from insrail.nav import _kernels, chi2, earth, error_model, integrity, kalman
from insrail.nav import measurements as meas
from insrail.nav.alignment import (
    aiding_still,
    detect_stops,
    stop_motion_sigma,
    stop_thresholds,
    stop_with_moving_fixes,
)
from insrail.nav.error_model import (
    ATT,
    BA,
    BG,
    GNSS,
    N_STATES,
    ODO,
    POS,
    SA,
    SG,
    VEL,
    ErrorModelNoise,
    dynamics_matrix,
    initial_sensor_sigmas,
    noise_matrix,
    play_noise,
)
from insrail.nav.fusion_options import FusionOptions
from insrail.nav.imu_gaps import bridge_gaps, bridged_process_noise
from insrail.nav.imu_profile import ImuProfile, load_imu_profile
from insrail.nav.imu_screening import screen_imu
from insrail.nav.integrity import FusionIntegrity, InnovationRecord
from insrail.nav.measurements import (
    GnssPosition,
    GnssVelocity,
    OdometerNhc,
    PositionFix,
    Zupt,
    schedule,
)
from insrail.nav.pass_memo import PassMemo
from insrail.nav.relative import RelativeFrame, start_track
from insrail.nav.rotation import euler_to_dcm, skew
from insrail.nav.startup import KnownStart, PositionTrack, StartupError, heading_at_reset, initial_state
from insrail.nav.trajectory import (
    TRAJECTORY_DTYPE,
    Trajectory,
    TrajectoryWriter,
    load_trajectory,
    trajectory_from_records,
)
from insrail.notices import Notice, Phrase
from insrail.background import WAIT_POLL_S, BackgroundJob
from insrail.progress import CancelToken, ProgressFn, ProgressMessage, StepProgress, check_cancel


@dataclass(frozen=True)
class Rejection:
    time_s: float
    measurement: str
    test_statistic: float
    threshold: float
    innovation: tuple[float, ...]


#: what a filter reset can widen: label, first error state, number of states (FilterReset.sigma's order)
RESET_STATES = (("position", POS, 3), ("velocity", VEL, 3), ("attitude", ATT, 3), ("sensor errors", BG, 12),
                ("odometer scale", ODO, 1), ("GNSS error", GNSS, 3))


@dataclass(frozen=True)
class FilterReset:
    """The filter was reset at ``time_s``: ``source`` had been rejected without a break for
    ``rejected_s`` seconds (``rejected`` observations), with ``also_rejected`` rejected at the same
    time; the variances of ``states`` (labels of RESET_STATES) were raised to ``sigma`` (SI, in
    RESET_STATES's order); the attitude and velocity turned by ``heading_turned_rad`` about the
    vertical to the track's heading (:func:`realign_at_reset`)."""

    time_s: float
    source: str
    rejected_s: float
    rejected: int
    first_rejected_s: float  # the time of the run's first rejection: the solution is suspect from then on
    also_rejected: tuple[str, ...]
    states: tuple[str, ...]
    sigma: tuple[float, ...]
    heading_turned_rad: float = 0.0

    def message(self) -> Phrase:
        others = (Phrase(" (and {sources})", {"sources": [Phrase(source) for source in self.also_rejected]})
                  if self.also_rejected else Phrase(""))
        turned = (Phrase("; heading re-aligned to the track by {turned_deg:+.1f} deg",
                         {"turned_deg": math.degrees(self.heading_turned_rad)}) if self.heading_turned_rad else Phrase(""))
        return Phrase("filter reset at t = {time_s:.1f} s: {source}{others} rejected for {rejected_s:.1f} s ({rejected} in "
                      "a row){turned}; {states} uncertainty widened and the measurements re-admitted",
                      {"time_s": self.time_s, "source": Phrase(self.source), "others": others, "rejected_s": self.rejected_s,
                       "rejected": self.rejected, "turned": turned, "states": [Phrase(state) for state in self.states]})

    def floors(self) -> np.ndarray:
        """Per error state the 1-sigma its variance is raised to (NaN: left as it is)."""
        floor = np.full(N_STATES, np.nan)
        at = 0
        for label, first, count in RESET_STATES:
            if label in self.states:
                floor[first : first + count] = self.sigma[at : at + count]
                at += count
        return floor


#: a GNSS or prism source silent for longer than this [s] before the run of rejections that reset the
#: filter came back from a gap: the dead reckoning across it erred more than its 1-sigma said
GAP_RETURN_S = 1.0
#: forward passes that grow a gap's error before a reset after it is let stand (each doubles the growth)
MAX_GAP_PASSES = 3
#: the sources a gap return is looked for in: observations at their own times, which can fall silent
_GAP_SOURCES = (GnssPosition, GnssVelocity, PositionFix)


@dataclass(frozen=True)
class GapReturn:
    """``source`` came back from a gap (``start_s``: its last accepted observation, ``end_s``: the first
    after the gap the filter rejected) off the dead reckoning by more than its 1-sigma, so much that the
    filter was reset. Instead, the error is grown over the gap (:func:`gap_process_noise`: a white
    acceleration noise whose position and velocity 1-sigma at the gap's end are ``sigma_position_m`` and
    ``sigma_velocity_mps`` per NED axis) and the forward pass run again: its observations are then
    re-admitted through the gate, and the smoother bridges the gap instead of a reset cutting it."""

    source: str
    start_s: float
    end_s: float
    sigma_position_m: tuple[float, float, float]
    sigma_velocity_mps: tuple[float, float, float]
    distance_m: float = 0.0  # between the source's positions at the gap's ends (0: not a position source)
    accepted: bool = False  # the return passed the gate, far off (:func:`loud_returns`): no reset to avoid

    def message(self) -> Phrase:
        off = (f"{max(self.sigma_position_m):.3g} m" if max(self.sigma_position_m) > 0
               else f"{max(self.sigma_velocity_mps):.3g} m/s")
        instead = (Phrase("accepted, but beyond the 1-sigma the filter held") if self.accepted
                   else Phrase("instead of a filter reset"))
        return Phrase("{source} back after a gap of {gap_s:.1f} s at t = {time_s:.1f} s, {off} off the dead reckoning: "
                      "the uncertainty grown over the gap to that ({instead}) and the gap bridged by the smoother",
                      {"source": Phrase(self.source), "gap_s": self.end_s - self.start_s, "time_s": self.end_s,
                       "off": off, "instead": instead})


def _moved_m(source, start_s: float, end_s: float) -> float:
    """The horizontal distance [m] between a position source's observations at two of its times."""
    i, k = np.searchsorted(source.time_s, [start_s, end_s])
    k, i = min(k, len(source.time_s) - 1), min(i, len(source.time_s) - 1)
    radius = 6.371e6
    return float(radius * math.hypot(source.lat[k] - source.lat[i],
                                     (source.lon[k] - source.lon[i]) * math.cos(source.lat[i])))


def gap_returns(resets, rejections, sources, record_time_s, record_source, accepted,
                grown: tuple[GapReturn, ...] = ()) -> tuple[GapReturn, ...]:
    """The gap returns (:class:`GapReturn`) among a forward pass's ``resets``: a reset whose source, or one
    rejected with it, is a GNSS or prism source silent for more than GAP_RETURN_S (and DENSE_GAP_FACTOR of its
    usual interval) between its last accepted observation and the run's first rejection. Sparse prism fixes
    are silent between any two of them: growing the white acceleration over each such "gap" frees the dead
    reckoning's velocity (and heading) to the odometer and NHC between every two fixes, and a MEMS unit's then
    misses the next fix by metres (the configuration matrix's prism-only MEMS tunnel: its first fix after the
    start 0.9 m off without the growth, 4.2 m with it, its last 25 m off after three passes); their own gate and
    resets judge them. Its growth: the largest rejected position (velocity)
    innovation per axis from that rejection to the reset; where ``grown`` already grew the same gap, at
    least twice that. ``record_*``: every gated observation's time and source index and whether accepted
    (``integrity.InnovationRecord``'s order); ``grown`` are kept as they are."""
    found = {(g.source, round(g.start_s, 3)): g for g in grown}
    names = [m.name for m in sources]
    for reset in resets:
        for name in (reset.source, *reset.also_rejected):
            k = names.index(name)
            if not isinstance(sources[k], _GAP_SOURCES):
                continue
            mine = record_source == k
            before = mine & accepted & (record_time_s < reset.first_rejected_s)
            if not before.any():
                continue  # rejected from its start: no dead reckoning to blame
            start = float(record_time_s[before].max())
            after = mine & ~accepted & (record_time_s >= reset.first_rejected_s) & (record_time_s <= reset.time_s)
            if not after.any():
                continue
            end = float(record_time_s[after].min())
            seen = np.sort(record_time_s[mine & (record_time_s >= start) & (record_time_s <= end)])
            usual = float(np.median(np.diff(np.sort(record_time_s[mine])))) if np.count_nonzero(mine) > 2 else 0.0
            if len(seen) < 2 or np.max(np.diff(seen)) <= max(GAP_RETURN_S, DENSE_GAP_FACTOR * usual):
                continue
            peak = np.zeros(3)
            for r in rejections:
                if r.measurement == name and reset.first_rejected_s <= r.time_s <= reset.time_s:
                    peak = np.maximum(peak, np.abs(np.asarray(r.innovation[:3])))
            key = (name, round(start, 3))
            before_grown = found.get(key)
            position = sources[k].position_innovation
            pos = tuple(peak.tolist()) if position else (0.0, 0.0, 0.0)
            vel = (0.0, 0.0, 0.0) if position else tuple(peak.tolist())
            if before_grown is not None:
                pos = tuple(max(a, 2.0 * b) for a, b in zip(pos, before_grown.sigma_position_m))
                vel = tuple(max(a, 2.0 * b) for a, b in zip(vel, before_grown.sigma_velocity_mps))
            found[key] = GapReturn(name, start, end, pos, vel, _moved_m(sources[k], start, end) if position else 0.0)
    return tuple(sorted(found.values(), key=lambda g: g.start_s))


#: a source back from a gap accepted, but with a NIS beyond this share of the dead reckoning's own errors
#: (its chi-square quantile): the error across the gap was larger than the filter's model of it
LOUD_RETURN_QUANTILE = 0.95
#: a silence counts as a gap of a dense source only when it is this many times the source's usual interval
#: (sparse prism fixes return from a "gap" every time: their own gate and resets judge them)
DENSE_GAP_FACTOR = 4.0


def loud_returns(sources, record_time_s, record_source, accepted, nis, dof, innovation,
                 grown: tuple[GapReturn, ...] = ()) -> tuple[GapReturn, ...]:
    """The gap returns among a forward pass's *accepted* observations: a GNSS or prism source silent for
    more than GAP_RETURN_S (and DENSE_GAP_FACTOR of its usual interval), whose first observation after the
    silence passed the gate with a NIS beyond LOUD_RETURN_QUANTILE. The dead reckoning across the gap
    erred more than its model said; after the update the filter, believing the model's coupling of
    position and velocity errors, holds its velocity (and the smoother the gap's last seconds) to a
    1-sigma several times too small (the real walk_0827: 3.4 m back after 15 s at NIS 7.9, its velocity
    0.45 m/s off at a stated 0.06 m/s, held-out fixes 4.4 sigma off). The growth is the innovation per
    axis, as for a reset's (:func:`gap_returns`); a gap in ``grown`` is kept as it is. Arguments as
    :func:`gap_returns`'s, and per observation its ``nis``, ``dof`` and ``innovation`` rows."""
    found = {(g.source, round(g.start_s, 3)): g for g in grown}
    for k, source in enumerate(sources):
        if not isinstance(source, _GAP_SOURCES):
            continue
        mine = np.flatnonzero(record_source == k)
        if len(mine) < 3:
            continue
        times = record_time_s[mine]
        silent = np.diff(times)
        usual = float(np.median(silent))
        for i in np.flatnonzero((silent > GAP_RETURN_S) & (silent > DENSE_GAP_FACTOR * usual)):
            back = mine[i + 1]
            key = (source.name, round(float(times[i]), 3))
            if (key in found or not accepted[back]
                    or not nis[back] > chi2.upper_quantile(dof[back], 1.0 - LOUD_RETURN_QUANTILE)):
                continue
            peak = np.abs(np.nan_to_num(np.asarray(innovation[back][:3], dtype=float)))
            pos = tuple(peak.tolist()) if source.position_innovation else (0.0, 0.0, 0.0)
            vel = (0.0, 0.0, 0.0) if source.position_innovation else tuple(peak.tolist())
            moved = _moved_m(source, float(times[i]), float(times[i + 1])) if source.position_innovation else 0.0
            found[key] = GapReturn(source.name, float(times[i]), float(times[i + 1]), pos, vel, moved, accepted=True)
    return tuple(sorted(found.values(), key=lambda g: g.start_s))


#: the largest heading 1-sigma a gap's growth reaches [rad]: beyond it the error model's small angles fail
GAP_MAX_HEADING_SIGMA_RAD = 0.2


def gap_process_noise(returns: tuple[GapReturn, ...], update_time_s: np.ndarray) -> dict[int, np.ndarray]:
    """Extra process noise (N x N) per filter segment j (ending at update_time_s[j]) inside each gap of
    ``returns``, over the gap's length T, such that the dead reckoning's 1-sigma at its end reaches the
    gap's: a white acceleration per NED axis of spectral density q = max(3 sigma_p^2 / T^3,
    sigma_v^2 / T) (per segment of length d the exact [d^3/3, d^2/2; d^2/2, d] q on position and
    velocity), and, over a gap that moved ``distance_m``, a random walk of the heading of 3 sigma_h^2 /
    (distance^2 T) (sigma_h the larger horizontal sigma_p; at most GAP_MAX_HEADING_SIGMA_RAD at the end):
    with an odometer and an NHC measuring the velocity in the trolley's frame ten times a second, what
    drifts across a gap is its heading. Smooth growths: the smoother spreads the correction at the gap's
    end over the gap as a curve, and the short-wave (5 m lag) accuracy stays what the sensors give."""
    extra: dict[int, np.ndarray] = {}
    for gap in returns:
        j0 = int(np.searchsorted(update_time_s, gap.start_s, side="right"))
        j1 = int(np.searchsorted(update_time_s, gap.end_s, side="left"))
        j0, j1 = max(j0, 1), min(j1, len(update_time_s) - 1)
        if j1 < j0:
            continue
        length = max(float(update_time_s[j1] - update_time_s[j0 - 1]), 1e-3)
        q = np.maximum(3.0 * np.square(gap.sigma_position_m) / length**3,
                       np.square(gap.sigma_velocity_mps) / length)
        q_heading = 0.0
        if gap.distance_m > 0.0:
            q_heading = min(3.0 * max(gap.sigma_position_m[:2]) ** 2 / (gap.distance_m**2 * length),
                            GAP_MAX_HEADING_SIGMA_RAD**2 / length)
        for j in range(j0, j1 + 1):
            d = float(update_time_s[j] - update_time_s[j - 1])
            m = extra.setdefault(j, np.zeros((N_STATES, N_STATES)))
            for a in range(3):
                m[POS + a, POS + a] += q[a] * d**3 / 3.0
                m[POS + a, VEL + a] += q[a] * d**2 / 2.0  # the position error's rate is the velocity's
                m[VEL + a, POS + a] += q[a] * d**2 / 2.0
                m[VEL + a, VEL + a] += q[a] * d
            m[ATT + 2, ATT + 2] += q_heading * d
    return extra


def with_gap_noise(bridged_q: dict[int, np.ndarray], returns: tuple[GapReturn, ...],
                   update_time_s: np.ndarray) -> dict[int, np.ndarray]:
    """The IMU gaps' process noise ``bridged_q`` plus the gap returns' (:func:`gap_process_noise`)."""
    merged = {j: q.copy() for j, q in bridged_q.items()}
    for j, q in gap_process_noise(returns, update_time_s).items():
        merged[j] = merged[j] + q if j in merged else q
    return merged


class _RejectionRuns:
    """Per aiding source the current run of consecutive rejections (NaN start: none), and the
    decision that a run means the filter, not the sensor, is wrong. Plain arrays, one slot per source."""

    def __init__(self, sources, options: FusionOptions, initial_sigma: np.ndarray):
        k = len(sources)
        self.sources, self.options = sources, options
        self.initial_sigma = initial_sigma  # the filter's start 1-sigma: what a lost filter's sensor states go back to
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

    def pending(self, k: int) -> bool:
        """Whether the next accepted observation of source k has something to clear."""
        return bool(not np.isnan(self.start[k]) or self.resets_in_a_row[k] > 0)

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
        # attitude: widened no further (beyond some degrees the error model's small angles fail: a larger
        # heading error is turned away by realign_at_reset)
        sigma_att = np.array([o.reset_sigma_level_rad, o.reset_sigma_level_rad, o.reset_sigma_heading_rad])
        if "attitude" in names:  # a lost filter: the sensor, odometer and GNSS error states it dragged along
            names |= {"sensor errors", "odometer scale", "GNSS error"}
        values = {"position": sigma_pos, "velocity": sigma_vel, "attitude": sigma_att}
        sigma, labels = [], []
        for label, first, count in RESET_STATES:
            if label in names:
                sigma.extend(np.broadcast_to(values.get(label, self.initial_sigma[first : first + count]), count).tolist())
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
    forward: Trajectory  # at the update epochs unless fuse() was asked for it in full
    rejections: tuple[Rejection, ...]
    statistics: dict
    stops: tuple[tuple[float, float], ...]
    info: dict = field(default_factory=dict)
    timeline: UpdateTimeline | None = None
    resets: tuple[FilterReset, ...] = ()
    innovations: InnovationRecord | None = None
    integrity: FusionIntegrity | None = None


# --------------------------------------------------------------------------- kernel
#
# The forward filter is one compiled loop over the update epochs (``_forward_kernel``). Its
# state lives in a :class:`_FilterState` of plain arrays, so the loop can stop and resume
# anywhere: it returns to Python only at *events* - an observation rejected by its gate (the
# rejection-run bookkeeping and the reset decision of :class:`_RejectionRuns` stay in Python,
# the same code for every engine), the first observation accepted after such a run, a full
# output buffer, and every PROGRESS_SEGMENTS segments for progress and cancel.

N_NAV = 9  # rows of Phi that are not diagonal: position, velocity, attitude errors
RECORD_SIZE = N_NAV * N_STATES + (N_STATES - N_NAV) + N_STATES * (N_STATES + 1) + N_STATES
PROGRESS_SEGMENTS = 2000
EVENT_DONE, EVENT_REJECTED, EVENT_ACCEPTED, EVENT_FLUSH, EVENT_PROGRESS, EVENT_NEED_IMU = 0, 1, 2, 3, 4, 5
#: IMU records the forward filter holds at a time (dtheta, dvel, dt: 56 B each, 3.7 MB); tests shrink it
IMU_CHUNK = 1 << 16
_UPPER = np.triu_indices(N_STATES)

# nogil: the kernels work on arrays alone (no Python object inside), so the mounting's pass and the main
# fusion run side by side in two threads (``insrail.project.mounting_stage.fused_with_mounting``)
compiled = cached_njit(nogil=True, error_model="numpy")


@compiled
def _propagate_segment(nav, dtheta, dvel, dt, start, stop, sensor, earth_c, out, base, sums, imu_base):
    """Strapdown over epochs start..stop-1 with compensated increments.

    dtheta, dvel, dt: the IMU record from epoch imu_base on (row k - imu_base: epoch k; it must
    hold start - 1); sensor = [bg(3), ba(3), sg(3), sa(3)] (estimates); out[k - base] receives nav after epoch k;
    sums = [sum v dt (3), sum dtheta_c (3), sum dvel_c (3), total dt, last dtheta_c (3),
    last dvel_c (3)].
    """
    for i in range(16):
        sums[i] = 0.0
    th_prev = np.empty(3)
    dv_prev = np.empty(3)
    th = np.empty(3)
    dv = np.empty(3)
    for epoch in range(start, stop):
        k = epoch - imu_base
        prev = k - 1 if epoch > 0 else k
        for a in range(3):
            th_prev[a] = (dtheta[prev, a] - sensor[a] * dt[prev]) / (1.0 + sensor[6 + a])
            dv_prev[a] = (dvel[prev, a] - sensor[3 + a] * dt[prev]) / (1.0 + sensor[9 + a])
            th[a] = (dtheta[k, a] - sensor[a] * dt[k]) / (1.0 + sensor[6 + a])
            dv[a] = (dvel[k, a] - sensor[3 + a] * dt[k]) / (1.0 + sensor[9 + a])
        _kernels.strapdown_step(nav, th_prev, dv_prev, th, dv, dt[k], earth_c, nav)
        for a in range(12):
            out[epoch - base, a] = nav[a]
        for a in range(3):
            sums[a] += nav[_kernels.NAV_VEL + a] * dt[k]
            sums[3 + a] += th[a]
            sums[6 + a] += dv[a]
        sums[9] += dt[k]
    for a in range(3):
        sums[10 + a] = th[a]
        sums[13 + a] = dv[a]


@compiled
def dynamics_rows(ctx, f_b, omega_ib_b, earth_c, top):
    """Rows 0-8 (position, velocity, attitude) of ``error_model.dynamics_matrix`` at the
    compiled snapshot ``ctx`` into top (9 x N); its other rows are the diagonal of the
    Gauss-Markov sensor and GNSS states (``_FilterState.decay``)."""
    lat, h = ctx[meas.CTX_LAT], ctx[meas.CTX_H]
    vn, ve, vd = ctx[meas.CTX_VEL], ctx[meas.CTX_VEL + 1], ctx[meas.CTX_VEL + 2]
    sl, cl = math.sin(lat), math.cos(lat)
    tl = sl / cl
    r_m, r_n = _kernels.radii(sl, earth_c)
    rm, rn = r_m + h, r_n + h
    w = earth_c[_kernels.EARTH_OMEGA]
    sec2 = 1.0 / (cl * cl)
    g = _kernels.normal_gravity(sl, r_n, h, earth_c)
    c = ctx[meas.CTX_C_BN : meas.CTX_C_BN + 9]
    f_n = (c[0] * f_b[0] + c[1] * f_b[1] + c[2] * f_b[2], c[3] * f_b[0] + c[4] * f_b[1] + c[5] * f_b[2],
           c[6] * f_b[0] + c[7] * f_b[1] + c[8] * f_b[2])
    top[:] = 0.0
    top[0, 0], top[0, 2] = -vd / rm, vn / rm
    top[1, 0], top[1, 1], top[1, 2] = ve * tl / rn, -(vd + vn * tl) / rn, ve / rn
    for a in range(3):
        top[a, 3 + a] = 1.0
    top[3, 0] = -(2 * ve * w * cl / rm + ve * ve * sec2 / (rm * rn))
    top[3, 2] = vn * vd / (rm * rm) - ve * ve * tl / (rn * rn)
    top[4, 0] = 2 * w * (vn * cl - vd * sl) / rm + vn * ve * sec2 / (rm * rn)
    top[4, 2] = (ve * vd + vn * ve * tl) / (rn * rn)
    top[5, 0] = 2 * w * ve * sl / rm
    top[5, 2] = -(ve * ve / (rn * rn) + vn * vn / (rm * rm) - 2 * g / (math.sqrt(r_m * r_n) + h))
    top[3, 3], top[3, 4], top[3, 5] = vd / rm, -2 * (w * sl + ve * tl / rn), vn / rm
    top[4, 3], top[4, 4], top[4, 5] = 2 * w * sl + ve * tl / rn, (vd + vn * tl) / rn, 2 * w * cl + ve / rn
    top[5, 3], top[5, 4] = -2 * vn / rm, -2 * (w * cl + ve / rn)
    # skew(f_n)
    top[3, 7], top[3, 8] = -f_n[2], f_n[1]
    top[4, 6], top[4, 8] = f_n[2], -f_n[0]
    top[5, 6], top[5, 7] = -f_n[1], f_n[0]
    top[6, 0], top[6, 2] = -w * sl / rm, ve / (rn * rn)
    top[7, 2] = -vn / (rm * rm)
    top[8, 0], top[8, 2] = -(w * cl / rm + ve * sec2 / (rn * rm)), -ve * tl / (rn * rn)
    top[6, 4], top[7, 3], top[8, 4] = 1.0 / rn, -1.0 / rm, -tl / rn
    w_in = (w * cl + ve / rn, -vn / rm, -w * sl - ve * tl / rn)
    top[6, 7], top[6, 8] = w_in[2], -w_in[1]
    top[7, 6], top[7, 8] = -w_in[2], w_in[0]
    top[8, 6], top[8, 7] = w_in[1], -w_in[0]
    for a in range(3):
        for b in range(3):
            top[3 + a, BA + b] = c[3 * a + b]
            top[3 + a, SA + b] = c[3 * a + b] * f_b[b]
            top[6 + a, BG + b] = -c[3 * a + b]
            top[6 + a, SG + b] = -c[3 * a + b] * omega_ib_b[b]


_play_noise = compiled(play_noise)


@compiled
def _transition(top_f, decay, gqg, seg, disp, play, phi_top, phi_diag, P, P_minus):
    """Phi = I + F dt + (F dt)^2 / 2 (rows 0-8 dense in phi_top, the rest diagonal in
    phi_diag) and P- = Phi P Phi^T + (Phi G Q G^T Phi^T + G Q G^T) dt / 2 with the diagonal
    G Q G^T ``gqg`` (error_model.discretise on the block structure), plus the trolley play's
    position noise over the segment's displacement ``disp`` (NED) with ``play`` (error_model.
    play_noise; zero where no NHC holds the trolley to the rail). P- is filled from its upper
    triangle, exactly symmetric."""
    n = P.shape[0]
    for i in range(N_NAV, n):
        d = decay[i] * seg
        phi_diag[i] = 1.0 + d + 0.5 * d * d
    for i in range(N_NAV):
        for j in range(n):
            s = 0.0
            for k in range(N_NAV):
                s += top_f[i, k] * top_f[k, j]
            s *= seg * seg
            if j >= N_NAV:
                s += top_f[i, j] * seg * decay[j] * seg
            phi_top[i, j] = top_f[i, j] * seg + 0.5 * s
        phi_top[i, i] += 1.0
    # M = Phi P
    M = np.empty((n, n))
    for i in range(N_NAV):
        for c in range(n):
            M[i, c] = 0.0
        for k in range(n):
            f = phi_top[i, k]
            if f != 0.0:
                for c in range(n):
                    M[i, c] += f * P[k, c]
    for i in range(N_NAV, n):
        for c in range(n):
            M[i, c] = phi_diag[i] * P[i, c]
    for i in range(n):
        for j in range(i, n):
            if j < N_NAV:
                s = 0.0
                q = 0.0
                for k in range(n):
                    s += M[i, k] * phi_top[j, k]
                    q += phi_top[i, k] * gqg[k] * phi_top[j, k]  # i <= j < N_NAV
            else:
                s = M[i, j] * phi_diag[j]
                q = (phi_top[i, j] if i < N_NAV else (phi_diag[i] if i == j else 0.0)) * gqg[j] * phi_diag[j]
            if i == j:
                q += gqg[i]
            P_minus[i, j] = s + 0.5 * q * seg
            P_minus[j, i] = P_minus[i, j]
    q_play = _play_noise(disp, seg, play)
    for i in range(3):
        for j in range(3):
            P_minus[i, j] += q_play[i, j]


@compiled
def _feedback(nav, dx, sensor, gnss_error, odo, earth_c):
    """Apply the error estimate dx to the navigation vector, the sensor, GNSS and odometer
    error estimates (in place)."""
    lat, lon = _kernels.lat_lon((nav[0], nav[1], nav[2], nav[3]))
    h = nav[4]
    r_m, r_n = _kernels.radii(math.sin(lat), earth_c)
    lat -= dx[POS] / (r_m + h)
    lon -= dx[POS + 1] / ((r_n + h) * math.cos(lat))
    a = -0.25 * math.pi - 0.5 * lat
    ca, sa = math.cos(a), math.sin(a)
    co, so = math.cos(0.5 * lon), math.sin(0.5 * lon)
    nav[0], nav[1], nav[2], nav[3] = ca * co, -sa * so, sa * co, ca * so
    nav[4] = h + dx[POS + 2]
    for k in range(3):
        nav[5 + k] -= dx[VEL + k]
    # C_b^n <- (I + phi x) C_b^n: rotate the computed attitude back by phi in the n-frame.
    q = _kernels.quat_normalize(_kernels.quat_mul(_kernels.rotvec_quat(dx[ATT], dx[ATT + 1], dx[ATT + 2]),
                                                  (nav[8], nav[9], nav[10], nav[11])))
    nav[8], nav[9], nav[10], nav[11] = q[0], q[1], q[2], q[3]
    for k in range(12):
        sensor[k] += dx[BG + k]
    for k in range(3):
        gnss_error[k] += dx[GNSS + k]
    odo[0] += dx[ODO]


@compiled
def _pack_record(phi_top, phi_diag, P_minus, P, x, out):
    """One smoother record (RECORD_SIZE): Phi's dense rows and diagonal, P- and P+ (upper
    triangles, row by row) and the update dx."""
    n = P.shape[0]
    r = 0
    for i in range(N_NAV):
        for j in range(n):
            out[r] = phi_top[i, j]
            r += 1
    for i in range(N_NAV, n):
        out[r] = phi_diag[i]
        r += 1
    for M in (P_minus, P):
        for i in range(n):
            for j in range(i, n):
                out[r] = M[i, j]
                r += 1
    for i in range(n):
        out[r] = x[i]
        r += 1


@compiled
def _unpack_record(rec, phi, P_minus, P, dx):
    n = P.shape[0]
    r = 0
    phi[:] = 0.0
    for i in range(N_NAV):
        for j in range(n):
            phi[i, j] = rec[r]
            r += 1
    for i in range(N_NAV, n):
        phi[i, i] = rec[r]
        r += 1
    for M in (P_minus, P):
        for i in range(n):
            for j in range(i, n):
                M[i, j] = rec[r]
                M[j, i] = rec[r]
                r += 1
    for i in range(n):
        dx[i] = rec[r]
        r += 1


@compiled
def _unpack_reversed(records, phi, P_minus, P, dx):
    """:func:`_unpack_record` of each row of ``records``, the last first: record k - 1 - r into row r of the
    outputs (from a reversed view of the records both kernels would be compiled a second time, for its layout)."""
    k = records.shape[0]
    for r in range(k):
        _unpack_record(records[k - 1 - r], phi[r], P_minus[r], P[r], dx[r])


@compiled
def _first_not_below(ascending, value):
    """np.searchsorted(ascending, value) (side left) of integers, written out: numba's searchsorted is defined in
    numba.np.arraymath, which the cached kernel would then import when loaded, and with it scipy.linalg (insrail.jit)."""
    low, high = 0, ascending.shape[0]
    while low < high:
        middle = (low + high) // 2
        if ascending[middle] < value:
            low = middle + 1
        else:
            high = middle
    return low


@compiled
def _forward_kernel(pos, nav, sensor, gnss_error, odo, x, P, P_minus, phi_top, phi_diag, ctx, sums, pending,
                    dtheta, dvel, dt, imu_span, t, epochs, earth_c, decay, gqg, play, gnss_decay_tau, gap_j, gap_q,
                    first, source, observation, kinds, params, rows, row_first, gates,
                    nav_buf, nav_base, rec_buf, rec_fill, record, sensor_hist, sigma_hist, hist_base,
                    nis_out, dof_out, accepted, used, sum_sq, sum_nis, sum_dof, watched, event_nu, nu_out,
                    hph_out, r_out):
    """Run the forward filter from pos = [segment j, entry e, phase] (phase 0: segment j not
    yet propagated) until an event; returns (event, entry) and leaves pos where to resume.
    dtheta, dvel, dt: a chunk of the IMU record, IMU epochs imu_span[0] .. imu_span[1] - 1 (a
    segment that it does not hold whole, with the epoch before it, returns EVENT_NEED_IMU);
    nav_base[0]: the IMU epoch of nav_buf's first row; rec_fill[0]: records in rec_buf;
    hist_base[0]: the update epoch of the first row of sensor_hist and sigma_hist."""
    n = x.shape[0]
    m_epochs = epochs.shape[0]
    z = np.zeros(meas.MAX_ROWS)
    H = np.zeros((meas.MAX_ROWS, n))
    R = np.zeros((meas.MAX_ROWS, meas.MAX_ROWS))
    r = np.zeros(meas.MAX_ROWS)
    top_f = np.zeros((N_NAV, n))
    f_b = np.empty(3)
    w_b = np.empty(3)
    while pos[0] < m_epochs:
        j = pos[0]
        if pos[2] == 0:
            a, b = epochs[j - 1] + 1, epochs[j] + 1
            if a - 1 < imu_span[0] or b > imu_span[1]:
                return EVENT_NEED_IMU, -1
            if (b - nav_base[0] > nav_buf.shape[0] or (record and rec_fill[0] == rec_buf.shape[0])
                    or j - hist_base[0] >= sensor_hist.shape[0]):
                return EVENT_FLUSH, -1
            if j % PROGRESS_SEGMENTS == 0 and pos[1] != -2:
                pos[1] = -2  # reported; the next call goes on
                return EVENT_PROGRESS, -1
            _propagate_segment(nav, dtheta, dvel, dt, a, b, sensor, earth_c, nav_buf, nav_base[0], sums, imu_span[0])
            seg = sums[9]
            meas.fill_context(ctx, nav, sums, dt[b - 1 - imu_span[0]], odo[0], gnss_error, t[b - 1], earth_c)
            for k in range(3):
                f_b[k] = sums[6 + k] / seg
                w_b[k] = sums[3 + k] / seg
            dynamics_rows(ctx, f_b, w_b, earth_c, top_f)
            _transition(top_f, decay, gqg, seg, sums[0:3], play, phi_top, phi_diag, P, P_minus)
            # the motion an IMU gap's interpolation may have missed, the error grown over a GNSS gap
            g = _first_not_below(gap_j, j)
            if g < gap_j.shape[0] and gap_j[g] == j:
                for k in range(n):
                    for c in range(n):
                        P_minus[k, c] += gap_q[g, k, c]
            if pending[0] != 0.0:  # a reset: a burst of process noise on this segment
                kalman.inflate_in_place(P_minus, pending[1:])
                pending[0] = 0.0
            jit.copy_rows(P_minus, P)
            x[:] = 0.0
            decay_gnss = math.exp(-seg / gnss_decay_tau)  # the estimate follows its model
            for k in range(3):
                gnss_error[k] *= decay_gnss
            pos[1] = first[j]
            pos[2] = 1
        while pos[1] < first[j + 1]:
            e = pos[1]
            pos[1] = e + 1
            k = source[e]
            m = meas.evaluate(kinds[k], ctx, params[k], rows[row_first[k] + observation[e]], z, H, r)
            for a in range(m):
                for c in range(m):
                    R[a, c] = r[a] if a == c else 0.0
            # each row's innovation variance: the filter's part H P- H^T and the noise R (the noise estimates
            # of insrail.nav.self_calibration take the innovations' excess over the filter's part)
            for a in range(m):
                hph = 0.0
                for c in range(n):
                    if H[a, c] != 0.0:
                        for c2 in range(n):
                            hph += H[a, c] * P[c, c2] * H[a, c2]
                hph_out[e, a] = hph
                r_out[e, a] = r[a]
            nis, ok = kalman.update_in_place(x, P, z, H, R, m, gates[m], event_nu)
            nis_out[e] = nis
            dof_out[e] = m
            for a in range(m):
                nu_out[e, a] = event_nu[a]
            if not ok:
                return EVENT_REJECTED, e
            used[k] += 1
            for a in range(m):
                sum_sq[k, a] += event_nu[a] * event_nu[a]
            sum_nis[k] += nis
            sum_dof[k] += m
            accepted[e] = True
            if watched[k]:
                return EVENT_ACCEPTED, e
        if first[j + 1] > first[j]:
            _feedback(nav, x, sensor, gnss_error, odo, earth_c)
        for a in range(n):
            for c in range(a + 1, n):
                s = 0.5 * (P[a, c] + P[c, a])
                P[a, c] = s
                P[c, a] = s
        if record:
            _pack_record(phi_top, phi_diag, P_minus, P, x, rec_buf[rec_fill[0]])
            rec_fill[0] += 1
        row = j - hist_base[0]
        for k in range(12):
            sensor_hist[row, k] = sensor[k]
        sensor_hist[row, 12] = odo[0]
        for k in range(n):
            sigma_hist[row, k] = math.sqrt(P[k, k])
        pos[0] = j + 1
        pos[1] = 0
        pos[2] = 0
    return EVENT_DONE, -1


@compiled
def _rts_gains(records, after, gains, p0, with_start):
    """The smoother gains (``kalman.rts_gain``) of a run of consecutive smoother records into ``gains``, row
    r + 1 that of record r (its epoch): from the record's P+ and the next record's Phi and P-, the last
    record's from ``after`` (the record after the run; no row: the pass's last epoch, which has no gain).
    ``with_start`` (the run of the first records): row 0 too, epoch 0's from ``p0``."""
    n = p0.shape[0]
    phi = np.empty((n, n))
    p_minus = np.empty((n, n))
    p_plus = np.empty((n, n))
    unused = np.empty((n, n))
    dx = np.empty(n)
    k = records.shape[0]
    for r in range(k):
        if r + 1 < k:
            _unpack_record(records[r + 1], phi, p_minus, unused, dx)
        elif after.shape[0]:
            _unpack_record(after[0], phi, p_minus, unused, dx)
        else:
            continue
        _unpack_record(records[r], unused, unused, p_plus, dx)
        jit.copy_rows(kalman.rts_gain(phi, p_minus, p_plus), gains[r + 1])
    if with_start:
        _unpack_record(records[0], phi, p_minus, p_plus, dx)
        jit.copy_rows(kalman.rts_gain(phi, p_minus, p0), gains[0])


@compiled
def _rts_chunk(records, gains, state, e_next, P_s_next, p_minus_next, corrections, sigma, p0, with_start):
    """The backward RTS recursion over a run of consecutive smoother records with their gains
    (:func:`_rts_gains`; record r written to row r + 1 of corrections and sigma), last record first.
    state[0] = 1 once an epoch has been smoothed (the last epoch: smoothed = filtered); (e_next, P_s_next,
    p_minus_next) carry the successor epoch's quantities from run to run. ``with_start`` (the run of the
    first records, the last one smoothed): then epoch 0 too, before the first segment, from its covariance
    ``p0`` (row 0; its correction pair is one error, no update was applied there) - here rather than from
    Python, whose call of the compiled step would load a kernel of its own from the cache at the smoother's end."""
    n = e_next.shape[0]
    phi = np.empty((n, n))
    p_minus = np.empty((n, n))
    p_plus = np.empty((n, n))
    dx = np.empty(n)
    for r in range(records.shape[0] - 1, -1, -1):
        j = r + 1
        _unpack_record(records[r], phi, p_minus, p_plus, dx)
        if state[0] == 0.0:
            e = np.zeros(n)
            P_s = p_plus.copy()
            state[0] = 1.0
        else:
            e, P_s = kalman.rts_smoothed(gains[j], e_next, P_s_next, p_minus_next, p_plus)
        for k in range(n):
            corrections[j, 0, k] = e[k]
            corrections[j, 1, k] = e[k] + dx[k]
            sigma[j, k] = math.sqrt(max(P_s[k, k], 0.0))
            e_next[k] = e[k] + dx[k]
        jit.copy_rows(P_s, P_s_next)
        jit.copy_rows(p_minus, p_minus_next)
    if with_start:
        e, P_s = kalman.rts_smoothed(gains[0], e_next, P_s_next, p_minus_next, p0)
        for k in range(n):
            corrections[0, 0, k] = e[k]
            corrections[0, 1, k] = e[k]
            sigma[0, k] = np.sqrt(np.maximum(P_s[k, k], 0.0))


# --------------------------------------------------------------------------- storage


#: bytes of one fusion's records of its forward pass (the smoother's store and the IMU-rate navigation file) held
#: in memory, not in temporary files, when all of them fit and the fusion owns them (``insrail fuse``): the short
#: survey's ~130 MB then never go through the file system (written and read back: system time). A caller's
#: covariance store (``insrail process``) outlives the fusion into the track reconstruction, where a run peaks
#: (the 10 km survey at ~410 MB RSS against a bar of 500 MB): there both stay on disk, or a survey of 2-3 km
#: would peak above the 10 km one.
RECORDS_IN_MEMORY_BYTES = 256 * 2**20


class _Spool:
    """Bytes appended and read back by offset: in a temporary file, or in a buffer of a size given
    beforehand (:meth:`hold_in_memory`) until more than it holds is appended (then in the file: the
    bytes are the same either way, only where they lie differs)."""

    def __init__(self, prefix: str, what: str):
        self.prefix, self.what = prefix, what
        self.memory: np.ndarray | None = None
        self.file = None
        self.size = 0

    def hold_in_memory(self, capacity: int) -> None:
        """The next ``capacity`` bytes appended kept in memory (an empty spool)."""
        if self.size:
            raise ValueError(f"{self.what}: {self.size} bytes already appended")
        self.close()
        self.memory = np.empty(capacity, dtype=np.uint8)  # pages faulted in as they are written

    def append(self, data: np.ndarray) -> None:
        data = np.ascontiguousarray(data).reshape(-1).view(np.uint8)
        if self.memory is not None and self.size + len(data) > len(self.memory):
            memory, self.memory = self.memory[: self.size], None
            self.size = 0
            self.append(memory)
        if self.memory is not None:
            self.memory[self.size : self.size + len(data)] = data
        else:
            # an unnamed file: said where it lies (a full disk names the folder to clear)
            where = f"{tempfile.gettempdir()} ({self.what})"
            if self.file is None:
                self.file = named_write(where, lambda: tempfile.TemporaryFile(prefix=self.prefix))
            named_write(where, self.file.write, memoryview(data))
        self.size += len(data)

    def room(self, nbytes: int) -> np.ndarray | None:
        """Up to ``nbytes`` of the memory after the bytes appended, to be filled in place and then counted by
        :meth:`filled`; None when the bytes are not held in memory or it is full."""
        if self.memory is None or self.size == len(self.memory):
            return None
        return self.memory[self.size : self.size + nbytes]

    def filled(self, nbytes: int) -> None:
        """The first ``nbytes`` of the last :meth:`room` appended (written there in place)."""
        self.size += nbytes

    def read(self, offset: int, nbytes: int, into: np.ndarray | None = None) -> np.ndarray:
        """``nbytes`` bytes from ``offset``, read-only: a view of the memory, or read from the file into the
        start of ``into`` (uint8, a fresh array without it)."""
        if offset + nbytes > self.size:
            raise OSError(f"{tempfile.gettempdir()} ({self.what}): bytes {offset}-{offset + nbytes - 1} not written")
        if self.memory is not None:
            data = self.memory[offset : offset + nbytes]
        else:
            data = (np.empty(nbytes, dtype=np.uint8) if into is None else into)[:nbytes]
            self.file.flush()
            if os.preadv(self.file.fileno(), [data], offset) != nbytes:
                raise OSError(f"{tempfile.gettempdir()} ({self.what}): bytes {offset}-{offset + nbytes - 1} "
                              "not read back")
        data = data.view()
        data.flags.writeable = False
        return data

    def clear(self) -> None:
        """Forget every byte (the memory held stays held)."""
        if self.file is not None:
            self.file.seek(0)
            self.file.truncate()
        self.size = 0

    def close(self) -> None:
        self.memory = None
        if self.file is not None:
            self.file.close()
            self.file = None


class SmootherStore:
    """Append-only, chunked record of a forward pass for the RTS pass: per update
    epoch j = 1, 2, ... (record j - 1) Phi and Q's result P- of the segment ending at j, P+
    after the updates at j and the update dx applied there, packed (``_pack_record``: Phi's
    dense rows and diagonal, upper triangles: 916 doubles, 7.3 kB). Read back last epoch first.
    In a temporary file, or in memory when :func:`fuse` finds its records small enough
    (:data:`RECORDS_IN_MEMORY_BYTES`).

    :func:`fuse` keeps its own for the smoother and closes it. A caller that wants the
    covariances once the fusion is done (the covariance analysis of ``insrail.quality``
    reads them instead of replaying the filter) passes one it owns to ``fuse`` and closes it
    when done: ``with SmootherStore() as store: ...``.
    """

    RECORD = RECORD_SIZE

    def __init__(self, chunk: int = 2048):
        self.spool = _Spool("insrail-rts-", "the smoother's temporary file")
        self.chunk = chunk
        self.count = 0

    def __enter__(self) -> Self:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def hold_in_memory(self, count: int) -> None:
        """The next ``count`` records appended kept in memory (an empty store)."""
        self.spool.hold_in_memory(count * self.RECORD * 8)

    def append_records(self, records: np.ndarray) -> None:
        """Append packed records (k, RECORD)."""
        self.spool.append(np.asarray(records, dtype=np.float64))
        self.count += len(records)

    def room(self) -> np.ndarray | None:
        """Where up to a chunk of the next records can be written in place ((k, RECORD), then counted by
        :meth:`filled`): in the memory that holds them; None when they are not held in memory or it is full."""
        room = self.spool.room(self.chunk * self.RECORD * 8)
        return None if room is None else room.view(np.float64).reshape(-1, self.RECORD)

    def filled(self, count: int) -> None:
        """The first ``count`` records of the last :meth:`room` appended (written there in place)."""
        self.spool.filled(count * self.RECORD * 8)
        self.count += count

    def clear(self) -> None:
        """Forget every record (the forward pass is run again: :func:`fuse`'s gap returns)."""
        self.spool.clear()
        self.count = 0

    def reversed_chunks(self):
        """(index of the chunk's first record, records (k, RECORD)) from the last chunk to the first.
        From a file, the records are read into one buffer (a fresh 15 MB block per chunk is a fresh
        mapping whose pages the kernel faults in and zeroes, ``insrail.memory``): each chunk is good
        until the next one is asked for, and read-only."""
        size = self.RECORD * 8
        buffer = np.empty(min(self.chunk, max(self.count, 1)) * size, dtype=np.uint8)
        for first in range(((self.count - 1) // self.chunk) * self.chunk, -1, -self.chunk):
            n = min(self.chunk, self.count - first)
            yield first, self.spool.read(first * size, n * size, buffer).view(np.float64).reshape(n, self.RECORD)

    def reversed_blocks(self):
        """Blocks (j, Phi_j, P-_j, P+_j, dx_j) for j = count, ..., 1, unpacked (compiled) into
        arrays (k,), (k, N, N) x 3 and (k, N), a chunk at a time, j decreasing."""
        for first, chunk in self.reversed_chunks():
            k = len(chunk)
            phi, p_minus, p_plus = (np.empty((k, N_STATES, N_STATES)) for _ in range(3))
            dx = np.empty((k, N_STATES))
            _unpack_reversed(chunk, phi, p_minus, p_plus, dx)
            yield np.arange(first + k, first, -1), phi, p_minus, p_plus, dx

    def close(self):
        self.spool.close()


class _EpochFile:
    """The forward pass's navigation vectors (12 doubles) at the IMU rate, from one IMU epoch on: appended
    in chunks, read back by ranges; in a temporary file (never all in memory), or in memory when
    :func:`fuse` finds the records small enough (:data:`RECORDS_IN_MEMORY_BYTES`)."""

    WIDTH = 12

    def __init__(self, first_epoch: int, rows_in_memory: int = 0):
        self.spool = _Spool("insrail-nav-", "the fusion's temporary file")
        if rows_in_memory:
            self.spool.hold_in_memory(rows_in_memory * self.WIDTH * 8)
        self.first_epoch = first_epoch
        self.count = 0

    def append(self, rows: np.ndarray) -> None:
        self.spool.append(rows[:, : self.WIDTH])
        self.count += len(rows)

    def read(self, start_epoch: int, stop_epoch: int) -> np.ndarray:
        """Rows of IMU epochs start_epoch .. stop_epoch - 1 (read-only)."""
        size = self.WIDTH * 8
        data = self.spool.read((start_epoch - self.first_epoch) * size, (stop_epoch - start_epoch) * size)
        return data.view(np.float64).reshape(-1, self.WIDTH)

    def close(self):
        self.spool.close()


class _RowFile:
    """Rows of ``width`` doubles per update epoch in a temporary file: written at any row, read
    by ranges of rows, never all in memory (the filter-rate record: the forward pass's sensor
    estimates and sigmas, the smoother's corrections and sigmas)."""

    def __init__(self, width: int, what: str):
        self.file = tempfile.TemporaryFile(prefix="insrail-updates-")
        self.width, self.what = width, what

    def write(self, first: int, rows: np.ndarray) -> None:
        write_at(f"{tempfile.gettempdir()} ({self.what})", self.file.fileno(),
                 np.ascontiguousarray(rows, dtype=np.float64).reshape(len(rows), self.width), first * self.width * 8)

    def read(self, first: int, stop: int) -> np.ndarray:
        """Rows first .. stop - 1, (stop - first, width)."""
        size = (stop - first) * self.width * 8
        data = os.pread(self.file.fileno(), size, first * self.width * 8)
        if len(data) != size:
            raise OSError(f"{tempfile.gettempdir()} ({self.what}): rows {first}-{stop - 1} not written")
        return np.frombuffer(data, dtype=np.float64).reshape(stop - first, self.width)

    def close(self):
        self.file.close()


#: IMU epochs of the trajectory made at a time (about 45 MB while one is made); a quarter of it beside the
#: smoother (:func:`_smoothed_trajectory`), so that the chunk made after the smoother's end is short
TRAJECTORY_CHUNK = 100_000
#: update epochs of the filter-rate record held at a time while it is made
HIST_CHUNK = 4096
#: the forward pass's row per update epoch: sensor estimates and odometer scale (13), sigmas (N)
HISTORY_WIDTH = 13 + N_STATES
#: the smoother's row per update epoch: the correction pair (2 N), smoothed sigmas (N)
SMOOTHED_WIDTH = 3 * N_STATES


@dataclass
class _FilterState:
    """Everything the compiled forward loop carries from one call to the next."""

    nav: np.ndarray
    sensor: np.ndarray = field(default_factory=lambda: np.zeros(12))
    gnss_error: np.ndarray = field(default_factory=lambda: np.zeros(3))
    odo: np.ndarray = field(default_factory=lambda: np.zeros(1))
    x: np.ndarray = field(default_factory=lambda: np.zeros(N_STATES))
    P: np.ndarray = field(default_factory=lambda: np.zeros((N_STATES, N_STATES)))
    P_minus: np.ndarray = field(default_factory=lambda: np.zeros((N_STATES, N_STATES)))
    phi_top: np.ndarray = field(default_factory=lambda: np.zeros((N_NAV, N_STATES)))
    phi_diag: np.ndarray = field(default_factory=lambda: np.ones(N_STATES))
    ctx: np.ndarray = field(default_factory=lambda: np.zeros(meas.CTX_SIZE))
    sums: np.ndarray = field(default_factory=lambda: np.zeros(16))
    pending: np.ndarray = field(default_factory=lambda: np.zeros(N_STATES + 1))  # [flag, sigma floors (NaN: keep)]
    pos: np.ndarray = field(default_factory=lambda: np.array([1, 0, 0], dtype=np.int64))


# --------------------------------------------------------------------------- helpers


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
                       sigma_level_rad: float, sigma_heading_rad: float, levelled_at=None,
                       position_lever_ned_m=None) -> np.ndarray:
    """P at the first update epoch, from the alignment's sigmas, the IMU profile and the options.

    ``levelled_at`` (lat [rad], h [m], C_b^n) of a static start: the levelling took the mean specific
    force for gravity, so whatever horizontal accelerometer bias and scale-factor error the unit has went
    into the level angles, exactly so much that the velocity error does not grow at rest. The level
    errors then hold that part besides their own ``sigma_level_rad``, fully correlated with those sensor
    states (a 15 mg MEMS bias is 0.86 deg of tilt, which a 1.35 m antenna mast turns into 2 cm; a
    filter told the level is good to 0.01 deg rejects its GNSS once the trolley moves).

    ``position_lever_ned_m`` (C_b^n l of the antenna or prism whose position started the filter): the
    start position is that point's less the lever turned by the start attitude, so its error is the
    point's own (``sigma_pos_ned_m``) less skew(C_b^n l) phi, the part a fix of that point sees
    (``insrail.nav.measurements``) with the opposite sign. Taken as independent, the start position and
    the same point's fix told the filter the attitude: a MEMS unit's roll (2 mrad, a 1.5 m prism
    mast: 3 mm) came out 15 % better than anything had measured it (issue 33)."""
    sig = np.zeros(N_STATES)
    sig[POS : POS + 3] = sigma_pos_ned_m
    sig[VEL : VEL + 3] = sigma_vel_mps
    sig[ATT : ATT + 3] = [sigma_level_rad, sigma_level_rad, sigma_heading_rad]
    sig[BG : SA + 3] = initial_sensor_sigmas(profile)
    sig[ODO] = options.initial_sigma_odometer_scale
    sig[GNSS : GNSS + 3] = options.gnss_correlated_sigma_ned_m
    P = np.diag(np.maximum(sig, 1e-12) ** 2)
    if levelled_at is not None:
        lat, h, c_bn = levelled_at
        f_b = c_bn.T @ np.array([0.0, 0.0, -earth.normal_gravity(lat, h)])
        F = dynamics_matrix(lat, h, np.zeros(3), c_bn, f_b, np.zeros(3), ErrorModelNoise.from_profile(profile))
        # at rest the horizontal velocity error's rate F_va level + F_vs sensors is zero after the levelling
        sensors = np.r_[BA : BA + 3, SA : SA + 3]
        coupling = -np.linalg.solve(F[VEL : VEL + 2, ATT : ATT + 2], F[VEL : VEL + 2, sensors])
        level = slice(ATT, ATT + 2)
        p_sensors = P[np.ix_(sensors, sensors)]
        P[level, level] += coupling @ p_sensors @ coupling.T
        P[level, sensors] = coupling @ p_sensors
        P[sensors, level] = P[level, sensors].T
    if position_lever_ned_m is not None:
        lever = np.zeros((N_STATES, N_STATES))
        lever[POS : POS + 3, ATT : ATT + 3] = -skew(np.asarray(position_lever_ned_m, dtype=float))
        transform = np.eye(N_STATES) + lever
        P = transform @ P @ transform.T
    return P


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
    #: a relative survey's start frame (no GNSS, no prism fixes: insrail.nav.relative); None: positions are aided
    relative: RelativeFrame | None = None
    #: where the trolley starts without a position fix (the design at survey.toml's [start]): the filter
    #: starts there at the first IMU record (insrail.nav.startup.KnownStart); None: from the positions
    known_start: KnownStart | None = None


_ALL_TIME_S = np.array([-1e12, 1e12])
#: The NHC's 1-sigma without an odometer. Its rows at 10 Hz see the trolley's play, which is
#: correlated over seconds; with an odometer pinning the along-track velocity that does no harm,
#: without one the filter, taking them as independent, pulls its along-track velocity and
#: accelerometer bias along: on the simulator's `short` without odometer the 120 s outage drifted
#: 4.7 m along the track against a stated 0.45 m (0.45 mm/s; 1 mm/s: 4.7 x its sigma too); at 2 mm/s
#: 0.37 m against 0.24 m and 16 mm laterally instead of 127 mm, the price 0.40 / 0.34 mm instead of
#: < 0.3 mm in the 5 m lag difference where GNSS is there (5 mm/s: 0.18 m, 0.65 mm);
#: tests/test_nav_integrity.py, tests/test_nav_fusion.py.
NHC_SIGMA_WITHOUT_ODOMETER_MPS = 0.002


def nhc_point_m(trolley: TrolleyGeometry) -> np.ndarray:
    """Where the non-holonomic constraint holds (b frame [m]): the reference rail's point of a trolley;
    a survey not on rails (a walk, a road test: no ``imu_to_reference_rail_m``) at the odometer wheel's
    contact when it has one, else at the IMU."""
    for point in (trolley.imu_to_reference_rail_m, trolley.imu_to_odometer_m):
        if point is not None:
            return np.asarray(point, dtype=float)
    return np.zeros(3)


def aiding_sources(options: FusionOptions, trolley: TrolleyGeometry, profile: ImuProfile, gnss: GnssSolution | None,
                   odometer: OdometerData | None, position_fixes: PositionFix | None = None,
                   nhc_relaxed_s: tuple[np.ndarray, np.ndarray] | None = None,
                   odometer_right: OdometerData | None = None) -> tuple:
    """The aiding sources as ``options`` selects them, in the order the filter applies them at
    an update epoch: GNSS positions (and velocities), total-station fixes, odometer/NHC, ZUPT.
    The fusion and the accuracy prediction (``insrail.quality.prediction``) both build theirs here.
    ``nhc_relaxed_s``: (start, end) of the intervals where the NHC does not hold (rail joints'
    shocks, ``insrail.nav.shocks``). ``odometer_right``: a second odometer on the other rail, on the
    first one's scale (``insrail.nav.odometer_pair``), its speed a source of its own beside the first's."""
    sources: list = []
    if gnss is not None:
        sources.append(GnssPosition(gnss.time_s, gnss.lat_rad, gnss.lon_rad, gnss.height_m, gnss.sigma_ned_m,
                                    trolley.lever_arm_m("imu_to_antenna_m"), options.gnss_sigma_scale,
                                    options.gnss_sigma_floor_m, options.gnss_correlated_sigma_ned_m,
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
            odo_t, odo_d, euler_to_dcm(*trolley.mounting_rpy_rad),
            trolley.lever_arm_m("imu_to_odometer_m") if odometer is not None else np.zeros(3), nhc_point_m(trolley),
            options.odometer_sigma_mps,
            (odometer.pulse_length_m if odometer is not None else None) or 0.001,
            sigma_nhc_mps=options.nhc_sigma_mps if use_odometer else max(options.nhc_sigma_mps,
                                                                          NHC_SIGMA_WITHOUT_ODOMETER_MPS),
            gyro_white_noise=profile.gyro_arw, use_odometer=use_odometer, use_nhc=options.use_nhc, sigma_speed_scale=options.odometer_sigma_scale,
            odometer_left_out_s=left_out_s(odometer.left_out if odometer is not None else ()),
            **({} if nhc_relaxed_s is None else {"nhc_relaxed_s": nhc_relaxed_s})))
    if use_odometer and odometer_right is not None:
        sources.append(OdometerNhc.from_distance(
            odometer_right.time_s, odometer_right.distance_m, euler_to_dcm(*trolley.mounting_rpy_rad),
            trolley.lever_arm_m("imu_to_odometer_right_m"), nhc_point_m(trolley), options.odometer_sigma_mps,
            odometer_right.pulse_length_m or 0.001, use_nhc=False, name="odometer_right",
            odometer_left_out_s=left_out_s(odometer_right.left_out)))
    if options.use_zupt:
        sources.append(Zupt(np.zeros(0), options.zupt_sigma_mps, gyro_white_noise=max(profile.gyro_arw, 1e-7),
                            sigma_scale=options.zupt_sigma_scale))
    return tuple(sources)


def left_out_s(stretches) -> tuple[np.ndarray, np.ndarray]:
    """(start, end) [s] arrays of an odometer's left-out stretches (``OdometerData.left_out``)."""
    return (np.array([g.start_s for g in stretches], dtype=float), np.array([g.end_s for g in stretches], dtype=float))


def aiding_for(survey: SurveyData, options: FusionOptions, profile: ImuProfile,
               position_fixes: PositionFix | None = None,
               nhc_relaxed_s: tuple[np.ndarray, np.ndarray] | None = None) -> Aiding:
    """What a survey aids the filter with (:func:`aiding_sources`), its GNSS after the quality policy."""
    gnss, gnss_quality = (None, {}) if survey.gnss is None else gnss_by_quality(survey.gnss, options.gnss_quality_policy)
    trolley = survey.manifest.trolley
    return Aiding(aiding_sources(options, trolley, profile, gnss, survey.odometer, position_fixes, nhc_relaxed_s,
                                 survey.odometer_right), gnss, survey.odometer, trolley, gnss_quality)


def fuse_survey(survey: SurveyData, options: FusionOptions = FusionOptions(), profile: ImuProfile | None = None,
                ellipsoid: earth.Ellipsoid = earth.WGS84, position_fixes: PositionFix | None = None,
                **kwargs) -> FusionResult:
    """:func:`fuse` with the aiding sources of a survey (:func:`aiding_for`) and its IMU profile."""
    profile = profile or load_imu_profile(survey.manifest.imu_profile)
    return fuse(survey.imu, aiding_for(survey, options, profile, position_fixes), profile, options, ellipsoid, **kwargs)


def holds_to_rail(measurements) -> bool:
    """Whether an NHC among ``measurements`` holds the trolley frame's x axis along the rail."""
    return any(isinstance(m, OdometerNhc) and m.use_nhc for m in measurements)


def play_drift(options: FusionOptions, measurements) -> np.ndarray:
    """What the position process noise of the trolley's play takes (``error_model.play_noise``): its
    drift per metre run (lateral, vertical) [m^2/m] and the drift its NHC's white noise stands for
    already, sigma^2 / f [m^2/s]; where an NHC holds the trolley to the rail, else none (a hand-held
    unit's axes point anywhere). The fusion and its covariance replays use this."""
    nhc = [m for m in measurements if isinstance(m, OdometerNhc) and m.use_nhc]
    if not nhc:
        return np.zeros(3)
    return np.array([*options.play_drift_m2_per_m, nhc[0].sigma_nhc_mps**2 / options.update_rate_hz])


def update_grid(imu_time_s: np.ndarray, k0: int, every: int, measurements) -> np.ndarray:
    """The IMU epochs that end a filter segment: every ``every``-th from the start epoch
    ``k0``, the epoch that closes each time-stamped observation, and the last epoch."""
    closing = [np.zeros(0, dtype=int)]
    for source in measurements:
        times = source.closing_times_s()
        inside = times[(times > imu_time_s[k0]) & (times <= imu_time_s[-1])]
        closing.append(np.searchsorted(imu_time_s, inside))
    n = len(imu_time_s)
    return np.unique(np.concatenate([np.arange(k0, n, every), *closing, [n - 1]])).astype(int)


# --------------------------------------------------------------------------- engine


@dataclass(frozen=True)
class _Setup:
    """What the forward pass starts from (:func:`_prepare`): the screened, bridged IMU data,
    the start, the update grid, the schedule and the noise."""

    imu: ImuIncrements
    dt0: float  # the interval of the first record (the median of the first 1000)
    outliers: list
    notices: list
    stops: list
    start: object  # insrail.nav.startup's initial state
    epochs: np.ndarray
    plan: object  # insrail.nav.measurements.Schedule
    bridged_q: dict
    P0: np.ndarray
    noise: ErrorModelNoise
    gqg: np.ndarray
    play: np.ndarray  # the play's position noise (play_drift)
    gates: np.ndarray  # chi-square gate per number of rows
    #: the positions a reset's re-alignment takes the heading from: the track, when the NHC holds the
    #: trolley frame's x axis along it (not for a hand-held unit, whose axes point anywhere); else None
    heading_track: PositionTrack | None
    c_vb: np.ndarray  # C_b^v, the trolley's mounting


def _screened(imu: ImuIncrements, profile: ImuProfile, odometer: OdometerData | None, positions, max_gap_s: float,
              source_file: str) -> tuple[ImuIncrements, tuple, tuple[Notice, ...]]:
    """The records screened (:func:`screen_imu`) and their gaps bridged: (records, outliers, notices)."""
    # the unit check's rest is where the odometer or the positions let the trolley stand still
    imu, outliers, notices = screen_imu(imu, profile, aiding_still=partial(aiding_still, odometer=odometer,
                                                                           positions=positions))
    imu, warnings = bridge_gaps(imu, max_gap_s)
    removed = np.array([o.time_s for o in outliers])
    notices += [Notice("imu", w, file=source_file, time_s=gap.start_s) for gap, w in zip(imu.gaps, warnings)
                if not np.any((removed > gap.start_s) & (removed < gap.end_s))]  # a removed record says so itself
    return imu, outliers, tuple(notices)


#: groups of records summed at a time by :func:`summed_records`
SUMMED_CHUNK_GROUPS = 65536


def summed_records(imu: ImuIncrements, first: int, count: int) -> ImuIncrements:
    """The records from ``first`` on, ``count`` at a time summed into one (a coarser mechanisation):
    record 0 is record ``first`` (where the filter starts: its increments are not integrated), record i
    the sum of records first + (i - 1) count + 1 .. first + i count, stamped with the last one's time;
    the records after the last whole group are left out. Read a chunk at a time, a file-backed record's
    pages let go behind each (the main fusion reads the same record beside the mounting's pass: touched
    whole at once, its 87 MB at 10 km stayed resident)."""
    groups = (len(imu) - 1 - first) // count
    dtheta, dvel = np.empty((groups + 1, 3)), np.empty((groups + 1, 3))
    dtheta[0], dvel[0] = imu.dtheta_rad[first], imu.dvel_mps[first]
    for start in range(0, groups, SUMMED_CHUNK_GROUPS):
        end = min(start + SUMMED_CHUNK_GROUPS, groups)
        rows = slice(first + 1 + start * count, first + 1 + end * count)
        for increments, out in ((imu.dtheta_rad, dtheta), (imu.dvel_mps, dvel)):
            np.sum(increments[rows].reshape(end - start, count, 3), axis=1, out=out[1 + start : 1 + end])
        release_pages(imu.dtheta_rad, imu.dvel_mps)
    time_s = np.ascontiguousarray(imu.time_s[first : first + 1 + groups * count : count])
    return replace(imu, time_s=time_s, dtheta_rad=dtheta, dvel_mps=dvel)


def _prepare(imu: ImuIncrements, aiding: Aiding, profile: ImuProfile, options: FusionOptions,
             ellipsoid: earth.Ellipsoid, memo: PassMemo | None = None, imu_every: int = 1) -> _Setup:
    memo = memo if memo is not None else PassMemo()
    records = imu
    noise = ErrorModelNoise.from_profile(profile, options.gnss_correlated_tau_s, options.gnss_correlated_sigma_ned_m)
    gqg = noise_matrix(noise)
    trolley = aiding.trolley
    c_vb = euler_to_dcm(*trolley.mounting_rpy_rad)
    source_file = str(imu.source or "")
    gnss = aiding.gnss
    fixes = next((m for m in aiding.measurements if isinstance(m, PositionFix)), None)
    if gnss is not None:
        track = PositionTrack.from_gnss(gnss, trolley.imu_to_antenna_m)
    elif fixes is not None:
        track = PositionTrack.from_fixes(fixes)
    elif aiding.relative is not None and aiding.odometer is not None:
        track = None  # a relative survey: its start point is placed once the stops are known
    else:
        raise ValueError("the survey has neither GNSS nor total-station prism fixes, nor an odometer for a relative "
                         "survey: nothing gives its position or its distance run")
    track = track.within(imu.time_s[0], imu.time_s[-1]) if track is not None else None
    positions = None
    if aiding.odometer is None and len(track) > 1:
        positions = (track.time_s, track.local_ned(ellipsoid)[:, :2], track.horizontal_sigma_m())
    imu, outliers, notices = memo.get(
        "screening", (records, profile, aiding.odometer, positions, options.max_imu_gap_s, source_file),
        partial(_screened, records, profile, aiding.odometer, positions, options.max_imu_gap_s, source_file))
    notices = list(notices)
    n = len(imu)
    t = imu.time_s
    dt0 = float(np.median(np.diff(t[: min(n, 1000)])))

    if aiding.odometer is None:
        notices.append(Notice("fusion", "no odometer in the survey: the along-track scale comes from the {source} only",
                              severity="info",
                              fields={"source": Phrase("GNSS positions" if gnss is not None else "prism fixes")}))
    if options.use_nhc and trolley.imu_to_reference_rail_m is None:
        where = Phrase("the odometer wheel's contact" if trolley.imu_to_odometer_m is not None else "the IMU")
        notices.append(Notice("fusion", "no trolley.imu_to_reference_rail_m (a survey not on rails): the "
                              "non-holonomic constraint is applied at {where}", severity="info", fields={"where": where}))
    track = track.within(t[0], t[-1]) if track is not None else None
    if track is not None and len(track) == 0:
        where = gnss.source if gnss is not None and gnss.source else track.source
        raise ValueError(
            f"{where}: no {track.source} epoch lies within the IMU data "
            f"({t[0]:.3f} - {t[-1]:.3f} s of week); check the files and their time scales"
        )
    if aiding.odometer is None and gnss is not None and len(track) > 1:
        outage = np.flatnonzero(np.diff(track.time_s) > UNAIDED_OUTAGE_S)
        for i in outage:
            notices.append(Notice(
                "fusion", "no odometer: across the {source} outage of {outage_s:.0f} s after t = {time_s:.1f} s the "
                "along-track position rests on the IMU alone", time_s=float(track.time_s[i]),
                fields={"source": track.source, "outage_s": track.time_s[i + 1] - track.time_s[i],
                        "time_s": track.time_s[i]}))
    gyro_quiet, accel_quiet = stop_thresholds(profile.gyro_arw, profile.accel_vrw, 1.0 / dt0)
    positions = None
    if aiding.odometer is None and gnss is not None:
        positions = (track.time_s, track.local_ned(ellipsoid)[:, :2], track.horizontal_sigma_m())
    stops = list(memo.get("stops", (imu, aiding.odometer, positions, gyro_quiet, accel_quiet),
                          partial(detect_stops, imu, aiding.odometer, max_gyro_std_radps=gyro_quiet, positions=positions,
                                  max_accel_std_mps2=None if aiding.odometer is not None else accel_quiet)))
    if aiding.odometer is None and gnss is None:
        moved = stop_with_moving_fixes(stops, (track.time_s, track.local_ned(ellipsoid)[:, :2],
                                               track.horizontal_sigma_m()))
        if moved is not None:  # ZUPTs and a static alignment over a run: a wrong trajectory, not a poor one
            raise StartupError(
                f"stop detection: the {track.source} move by {moved[2]:.2f} m within {moved[0]:.1f} - {moved[1]:.1f} s, "
                f"which the IMU takes for a stop: with the {profile.name} profile's noise (quiet below "
                f"{gyro_quiet:.3g} rad/s and {accel_quiet:.3g} m/s^2 of spread) the IMU does not see the trolley move, "
                "and without an odometer or GNSS nothing else finds the stops the zero-velocity updates and the "
                "alignment rest on; add the odometer's file to the survey, or, if the unit is quieter than "
                f"'{profile.name}' says, set survey.imu_profile to the profile of its data sheet")
    if track is None:
        track, options = _relative_start(aiding.relative, imu, stops, c_vb, profile, options, ellipsoid, notices)
    start = initial_state(imu, track, stops, aiding.odometer, c_vb, profile, options, ellipsoid, aiding.design_azimuth,
                          known=aiding.known_start)
    notices.extend(start.notices)
    motion = (np.array([s[0] for s in stops]), np.array([s[1] for s in stops]),
              stop_motion_sigma(imu, stops, profile.accel_vrw))
    if imu_every > 1:  # screened, bridged and started on every record; then mechanised on their sums
        imu, start, dt0 = summed_records(imu, start.epoch, imu_every), replace(start, epoch=0), dt0 * imu_every
        t = imu.time_s
    every = max(int(round(1.0 / (options.update_rate_hz * dt0))), 1)
    epochs = update_grid(t, start.epoch, every, aiding.measurements)
    plan = schedule(t[epochs], [replace(m, stop_motion=motion) if isinstance(m, Zupt) else m
                                for m in aiding.measurements], stops)
    P0 = initial_covariance(profile, options, start.sigma_pos_ned_m, start.sigma_vel_mps, start.sigma_level_rad,
                            start.sigma_heading_rad, start.levelled_at, start.position_lever_ned_m)
    # chi-square quantile of the gate probability per degree of freedom
    gates = np.array([np.inf] + [chi2.upper_quantile(m, 1.0 - options.gate_probability) for m in range(1, meas.MAX_ROWS + 1)])
    on_rail = holds_to_rail(aiding.measurements)
    return _Setup(imu, dt0, outliers, notices, stops, start, epochs, plan, bridged_process_noise(imu, epochs), P0,
                  noise, gqg, play_drift(options, aiding.measurements), gates, track if on_rail else None, c_vb)


def _relative_start(frame: RelativeFrame, imu, stops, c_vb, profile, options: FusionOptions, ellipsoid,
                    notices: list) -> tuple[PositionTrack, FusionOptions]:
    """A relative survey's one-point start track and the options the start takes its heading from
    (``relative.start_track``; a heading the user gave stands)."""
    found = start_track(frame, imu, stops, c_vb, profile, options.min_static_s, ellipsoid)
    notices.extend(found.notices)
    heading = found.heading_rad if options.initial_heading_rad is None else options.initial_heading_rad
    return found.track, replace(options, initial_heading_rad=heading, initial_sigma_heading_rad=found.sigma_heading_rad)


def realign_at_reset(reset: FilterReset, nav: np.ndarray, setup: _Setup, options: FusionOptions,
                     ellipsoid: earth.Ellipsoid) -> FilterReset:
    """A reset that widens the attitude first turns the lost filter's heading to the track's
    (``startup.heading_at_reset``) when they differ by more than three times the track's 1-sigma:
    a lost filter can be tens of degrees off, beyond what the error model's small angles cover.
    Only where the NHC ties the trolley's x axis to the track (``setup.heading_track``).
    The attitude and velocity in ``nav`` are turned about the vertical, the heading's 1-sigma is
    then the track's (not below the level's); the reset says so."""
    found = (heading_at_reset(nav, setup.heading_track, reset.time_s, setup.c_vb, ellipsoid)
             if "attitude" in reset.states and setup.heading_track is not None else None)
    if found is None or abs(found[0]) <= 3.0 * found[1]:
        return reset
    turn, sigma = found
    q = nav[_kernels.NAV_Q_BN : _kernels.NAV_Q_BN + 4]
    nav[_kernels.NAV_Q_BN : _kernels.NAV_Q_BN + 4] = _kernels.quat_normalize(
        _kernels.quat_mul(_kernels.rotvec_quat(0.0, 0.0, turn), (q[0], q[1], q[2], q[3])))
    vn, ve = nav[_kernels.NAV_VEL], nav[_kernels.NAV_VEL + 1]
    nav[_kernels.NAV_VEL] = math.cos(turn) * vn - math.sin(turn) * ve
    nav[_kernels.NAV_VEL + 1] = math.sin(turn) * vn + math.cos(turn) * ve
    at = sum(count for label, _, count in RESET_STATES[:2] if label in reset.states) + 2  # the heading's entry
    sigma_list = list(reset.sigma)
    sigma_list[at] = max(sigma, options.reset_sigma_level_rad)
    return replace(reset, sigma=tuple(sigma_list), heading_turned_rad=turn)


@dataclass
class _ForwardPass:
    """What the forward pass leaves at the filter rate."""

    history: _RowFile  # per update epoch j: sensor estimates and odometer scale after it (13), sigmas (N)
    nis: np.ndarray  # per schedule entry
    dof: np.ndarray
    accepted: np.ndarray
    statistics: dict
    rejections: list
    resets: list
    innovation: np.ndarray  # per schedule entry, its rows (MAX_ROWS, NaN beyond its dof), float32
    filter_variance: np.ndarray  # the same rows' H P- H^T
    noise_variance: np.ndarray  # the same rows' R


def _forward(setup: _Setup, options: FusionOptions, ellipsoid: earth.Ellipsoid, store: SmootherStore | None,
             nav_file: _EpochFile, history: _RowFile, progress, cancel, nav_chunk: int = 65536) -> _ForwardPass:
    """The forward filter: the compiled loop, with Python at its events (module docstring);
    the IMU-rate solution goes to ``nav_file`` (opened at the first update epoch), the sensor
    estimates and sigmas per update epoch to ``history``."""
    plan, epochs, imu = setup.plan, setup.epochs, setup.imu
    sources = plan.measurements
    models = [s.compiled() for s in sources]
    kinds = np.array([c.kind for c in models], dtype=np.int64)
    params = np.array([c.params for c in models]).reshape(len(models), meas.MODEL_PARAMS)
    row_first = np.cumsum([0] + [len(c.rows) for c in models])[:-1].astype(np.int64)
    rows = np.concatenate([c.rows for c in models] + [np.zeros((0, meas.MODEL_WIDTH))])
    gqg = np.diag(setup.gqg).copy()
    if np.count_nonzero(setup.gqg - np.diag(gqg)):
        raise AssertionError("the compiled filter takes a diagonal G Q G^T (insrail.nav.error_model.noise_matrix)")
    decay = np.zeros(N_STATES)
    noise = setup.noise
    for first, tau in ((BG, noise.gyro_bias_tau_s), (BA, noise.accel_bias_tau_s), (SG, noise.gyro_scale_tau_s),
                       (SA, noise.accel_scale_tau_s), (GNSS, noise.gnss_tau_s)):
        decay[first : first + 3] = -1.0 / tau
    gap_j = np.array(sorted(setup.bridged_q), dtype=np.int64)
    gap_q = np.array([setup.bridged_q[j] for j in gap_j]).reshape(len(gap_j), N_STATES, N_STATES)

    m_epochs = len(epochs)
    n_entries = len(plan.epoch)
    k0 = int(epochs[0])
    state = _FilterState(nav=np.array(setup.start.nav, dtype=float))
    state.P[:] = setup.P0
    nav_buf = np.empty((nav_chunk, 12))
    nav_buf[0] = state.nav[:12]
    nav_base = np.array([k0 + 1], dtype=np.int64)
    nav_file.append(nav_buf[:1])
    writer = _RecordWriter(store) if store is not None else None
    rec_buf = writer.next_buffer() if writer is not None else np.empty((1, RECORD_SIZE))
    rec_fill = np.zeros(1, dtype=np.int64)
    hist_rows = min(HIST_CHUNK, m_epochs)
    sensor_hist = np.empty((hist_rows, 13))
    sigma_hist = np.empty((hist_rows, N_STATES))
    sensor_hist[0] = 0.0
    sigma_hist[0] = np.sqrt(np.diag(setup.P0))
    hist_base = np.zeros(1, dtype=np.int64)

    def save_history():  # the rows of the update epochs done so far
        done = int(state.pos[0]) - int(hist_base[0])
        if done > 0:
            history.write(int(hist_base[0]), np.hstack([sensor_hist[:done], sigma_hist[:done]]))
            hist_base[0] += done

    nis = np.full(n_entries, np.nan)
    nu = np.full((n_entries, meas.MAX_ROWS), np.nan, dtype=np.float32)
    hph, noise = np.full_like(nu, np.nan), np.full_like(nu, np.nan)
    dof = np.zeros(n_entries, dtype=np.int64)
    accepted = np.zeros(n_entries, dtype=bool)
    k_src = len(sources)
    used = np.zeros(k_src, dtype=np.int64)
    rejected = np.zeros(k_src, dtype=np.int64)
    sum_sq = np.zeros((k_src, meas.MAX_ROWS))
    sum_nis = np.zeros(k_src)
    sum_dof = np.zeros(k_src, dtype=np.int64)
    watched = np.zeros(k_src, dtype=bool)
    event_nu = np.zeros(meas.MAX_ROWS)
    runs = _RejectionRuns(sources, options, np.sqrt(np.diag(setup.P0)))
    rejections: list[Rejection] = []
    resets: list[FilterReset] = []
    t = imu.time_s
    # the IMU record a chunk at a time (never copied whole; a file-backed record's pages are let go)
    imu_chunk = max(min(IMU_CHUNK, len(imu)), int(np.max(np.diff(epochs))) + 1 if m_epochs > 1 else 1)
    dtheta, dvel, dt = np.empty((imu_chunk, 3)), np.empty((imu_chunk, 3)), np.empty(imu_chunk)
    imu_span = np.zeros(2, dtype=np.int64)
    gnss_tau = float(options.gnss_correlated_tau_s)
    earth_c = _kernels.earth_constants(ellipsoid)
    if m_epochs > 1 and np.max(np.diff(epochs)) > nav_chunk:
        nav_chunk = int(np.max(np.diff(epochs)))
        nav_buf = np.empty((nav_chunk, 12))
    try:
        while True:
            event, e = _forward_kernel(
                state.pos, state.nav, state.sensor, state.gnss_error, state.odo, state.x, state.P, state.P_minus,
                state.phi_top, state.phi_diag, state.ctx, state.sums, state.pending,
                dtheta, dvel, dt, imu_span, t, epochs, earth_c, decay, gqg, setup.play, gnss_tau, gap_j, gap_q,
                plan.first, plan.source, plan.observation, kinds, params, rows, row_first, setup.gates,
                nav_buf, nav_base, rec_buf, rec_fill, store is not None, sensor_hist, sigma_hist, hist_base,
                nis, dof, accepted, used, sum_sq, sum_nis, sum_dof, watched, event_nu, nu, hph, noise)
            if event == EVENT_DONE:
                break
            if event == EVENT_NEED_IMU:
                _fill_imu_chunk(imu, setup.dt0, int(epochs[state.pos[0] - 1]), dtheta, dvel, dt, imu_span)
                continue
            if event in (EVENT_FLUSH, EVENT_PROGRESS):
                if event == EVENT_PROGRESS:
                    check_cancel(cancel)
                    j = int(state.pos[0])
                    progress(j / m_epochs, Phrase("forward filter {elapsed_s:.0f} s",
                                                  {"elapsed_s": t[epochs[j]] - t[epochs[0]]}))
                upto = int(epochs[state.pos[0] - 1]) + 1 if state.pos[0] < m_epochs else int(epochs[-1]) + 1
                nav_file.append(nav_buf[: upto - nav_base[0]])
                nav_base[0] = upto
                if store is not None and rec_fill[0]:
                    writer.append(int(rec_fill[0]))
                    rec_buf = writer.next_buffer()
                    rec_fill[0] = 0
                save_history()
                continue
            k, i = int(plan.source[e]), int(plan.observation[e])
            source = sources[k]
            if event == EVENT_REJECTED:
                m = int(dof[e])
                rejected[k] += 1
                time_s = float(source.time_s[i])
                rejections.append(Rejection(time_s, source.name, float(nis[e]), float(setup.gates[m]),
                                            tuple(event_nu[:m].tolist())))
                reset = runs.rejected(k, i, time_s, event_nu[:m].copy())
                if reset is not None:
                    reset = realign_at_reset(reset, state.nav, setup, options, ellipsoid)
                    resets.append(reset)
                    state.pending[0] = 1.0
                    state.pending[1:] = reset.floors()
            else:
                runs.accepted(k)
            watched[:] = [runs.pending(s) for s in range(k_src)]
        nav_file.append(nav_buf[: int(epochs[-1]) + 1 - nav_base[0]])
        if store is not None and rec_fill[0]:
            writer.append(int(rec_fill[0]))
        if writer is not None:
            writer.wait()
    finally:
        if writer is not None:
            writer.stop()
    save_history()
    statistics = {}
    for k in dict.fromkeys(plan.source.tolist()):  # the sources in the order they first applied
        dof_k = int(dof[plan.source == k].max()) if used[k] + rejected[k] else 0
        statistics[sources[k].name] = MeasurementStats(
            int(used[k]), int(rejected[k]), sum_sq[k, :dof_k].copy() if used[k] else None, float(sum_nis[k]),
            int(sum_dof[k])).summary()
    return _ForwardPass(history, nis, dof, accepted, statistics, rejections, resets, nu, hph, noise)


class _RecordWriter:
    """The forward pass's smoother records appended to the store (7.3 kB per update epoch). Held in memory, the
    filter writes them there itself (no copy); in a file, a background job appends one of two buffers while the
    filter fills the other: the file's write beside the filter, without the GIL; one after the other with one CPU.
    The appends keep their order."""

    def __init__(self, store: SmootherStore):
        self.store = store
        self.buffers: list[np.ndarray] | None = None
        self.current = 0
        self.in_place = False  # the last buffer given is the store's memory
        self.job: BackgroundJob | None = None

    def next_buffer(self) -> np.ndarray:
        """Where the filter writes its next records (up to its length); :meth:`append` then appends them."""
        room = self.store.room() if self.job is None else None
        self.in_place = room is not None
        if self.in_place:
            return room
        if self.buffers is None:
            self.buffers = [np.empty((self.store.chunk, RECORD_SIZE)) for _ in range(2)]
        return self.buffers[self.current]

    def append(self, count: int) -> None:
        """The first ``count`` records of the last :meth:`next_buffer` appended to the store (once the last
        append is done); the other buffer is the next one then."""
        if self.in_place:
            self.store.filled(count)
            return
        self.wait()
        records = self.buffers[self.current][:count]
        self.job = BackgroundJob(lambda progress, cancel: self.store.append_records(records), None, None,
                                 name="insrail-records")
        self.current = 1 - self.current

    def wait(self) -> None:
        """The last append done; its failure (a full disk) raised."""
        job, self.job = self.job, None
        if job is not None:
            job.result()

    def stop(self) -> None:
        """The last append waited for (after a failure of the filter: its own failure is the one reported)."""
        if self.job is not None:
            self.job.stop()
            self.job = None


def _fill_imu_chunk(imu: ImuIncrements, dt0: float, start: int, dtheta, dvel, dt, span) -> None:
    """IMU records start, start + 1, ... (as many as the buffers hold) into dtheta, dvel and dt (the
    interval each integrates: dt0 for the first record), their epochs into span; a file-backed
    record's pages are then released (``insrail.io.imu.release_pages``)."""
    stop = min(start + len(dt), len(imu))
    count = stop - start
    dtheta[:count] = imu.dtheta_rad[start:stop]
    dvel[:count] = imu.dvel_mps[start:stop]
    t = imu.time_s
    if start == 0:
        dt[0] = dt0
        np.subtract(t[1:stop], t[: stop - 1], out=dt[1:count])
    else:
        np.subtract(t[start:stop], t[start - 1 : stop - 1], out=dt[:count])
    span[:] = start, stop
    release_pages(imu.dtheta_rad, imu.dvel_mps)


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
    trajectory_file: Path | None = None,
    forward_file: Path | None = None,
    full_forward: bool = False,
    memo: PassMemo | None = None,
    imu_every: int = 1,
) -> FusionResult:
    """Fuse IMU increments with a list of aiding sources into a trajectory.

    aiding         : the sources and what the start needs (:func:`aiding_for` builds it from a
                     survey; total-station fixes are a source like the others, geodetic
                     positions of the prism the caller transformed with the project's CRS)
    output_every   : the trajectory holds every n-th IMU epoch (1: the full IMU rate)
    covariance_store : an empty :class:`SmootherStore` owned by the caller: the forward pass
                     records into it (whether or not ``options.smoother``) and leaves it open, so
                     the covariances can be analysed after the fusion without replaying it
    trajectory_file : stream the trajectory into this ``trajectory.npy`` (written in chunks,
                     atomically); ``result.trajectory`` is then a read-only memory map of it.
                     Without one it is built in memory.
    forward_file, full_forward : the forward solution at every ``output_every``-th epoch, streamed
                     into ``forward_file`` or held in memory; by default ``result.forward`` holds it
                     at the update epochs only (what the covariance analysis linearises on)
    memo           : a :class:`~insrail.nav.pass_memo.PassMemo` shared by the passes over one survey:
                     the IMU screening, gap bridging and stops made once for all of them
    imu_every      : the records screened, bridged and the filter started as always, then mechanised
                     ``imu_every`` at a time, summed (:func:`summed_records`; a pass that needs less than
                     the full rate: the mounting's); ``output_every`` then counts the summed records
    """
    if covariance_store is not None and covariance_store.count:
        raise ValueError(f"the covariance store already holds {covariance_store.count} records: pass an empty one")
    step = StepProgress(progress)
    setup = _prepare(imu, aiding, profile, options, ellipsoid, memo, imu_every)
    imu, epochs, t = setup.imu, setup.epochs, setup.imu.time_s
    plan, notices = setup.plan, setup.notices
    bridged_q = setup.bridged_q
    sources = plan.measurements
    m_epochs = len(epochs)
    own_store = covariance_store is None and options.smoother
    store = SmootherStore() if own_store else covariance_store
    nav_rows = int(epochs[-1]) + 1 - int(epochs[0])
    records_bytes = nav_rows * _EpochFile.WIDTH * 8 + (0 if store is None else (m_epochs - 1) * store.RECORD * 8)
    in_memory = covariance_store is None and records_bytes <= RECORDS_IN_MEMORY_BYTES
    if store is not None and in_memory:
        store.hold_in_memory(m_epochs - 1)
    nav_file = _EpochFile(int(epochs[0]), nav_rows if in_memory else 0)
    history = _RowFile(HISTORY_WIDTH, "the fusion's temporary file")
    smoothed_rows = _RowFile(SMOOTHED_WIDTH, "the smoother's temporary file") if options.smoother else None
    obs_time = np.empty(len(plan.epoch))
    obs_trusted = np.ones(len(plan.epoch), dtype=bool)
    for k, source in enumerate(sources):
        mine = plan.source == k
        obs_time[mine] = source.time_s[plan.observation[mine]]
        if getattr(source, "trusted", None) is not None:
            obs_trusted[mine] = source.trusted[plan.observation[mine]]
    returns: tuple[GapReturn, ...] = ()
    try:
        for gap_pass in range(MAX_GAP_PASSES + 1):  # a reset after a gap: the gap's error grown, the pass run again
            forward_pass = _forward(setup, options, ellipsoid, store, nav_file, history,
                                    step.sub(0.0, 0.8 if options.smoother else 0.9), cancel)
            grown = gap_returns(forward_pass.resets, forward_pass.rejections, sources, obs_time, plan.source,
                                forward_pass.accepted, returns)
            grown = loud_returns(sources, obs_time, plan.source, forward_pass.accepted, forward_pass.nis,
                                 forward_pass.dof, forward_pass.innovation, grown)
            if grown == returns or gap_pass == MAX_GAP_PASSES:
                break
            returns = grown
            setup = replace(setup, bridged_q=with_gap_noise(bridged_q, returns, t[epochs]))
            nav_file.close()
            history.close()
            nav_file = _EpochFile(int(epochs[0]), nav_rows if in_memory else 0)
            history = _RowFile(HISTORY_WIDTH, "the fusion's temporary file")
            if store is not None:
                store.clear()
        build = partial(_trajectory, t, nav_file, epochs, history, gps_week=imu.gps_week, ell=ellipsoid, cancel=cancel)
        trajectory = None
        if options.smoother:  # first: the forward solution at the updates is then not held through it
            check_cancel(cancel)
            trajectory = _smoothed_trajectory(store, m_epochs, setup.P0, smoothed_rows,
                                              partial(build, smoothed_rows, smoothed=True, output_every=output_every,
                                                      path=trajectory_file),
                                              step.sub(0.8, 1.0), cancel)
        forward = at_updates = build(None, smoothed=False, indices=epochs)
        if forward_file is not None or full_forward:
            forward = build(None, smoothed=False, output_every=output_every, path=forward_file)
        if not options.smoother:
            trajectory = (forward if forward_file is not None and trajectory_file is None else
                          build(None, smoothed=False, output_every=output_every, path=trajectory_file,
                                progress=step.sub(0.9, 1.0)))
    finally:
        if own_store:
            store.close()
        nav_file.close()
        history.close()
        if smoothed_rows is not None:
            smoothed_rows.close()
    step(1.0, "fusion done")
    accepted = forward_pass.accepted
    applied = {}
    for k, source in enumerate(sources):
        mine = accepted & (plan.source == k)
        if mine.any():
            applied[source.name] = np.column_stack([plan.epoch[mine], plan.observation[mine]]).astype(int)
    timeline = UpdateTimeline(time_s=t[epochs], measurements={m.name: m for m in sources}, applied=applied,
                              initial_covariance=setup.P0)
    innovations = InnovationRecord(tuple(m.name for m in sources), obs_time, plan.source.copy(), forward_pass.nis,
                                   forward_pass.dof, accepted, obs_trusted, forward_pass.innovation,
                                   forward_pass.filter_variance, forward_pass.noise_variance)
    lat_e, lon_e = at_updates.lat_rad, at_updates.lon_rad
    r_m, r_n = earth.radii(lat_e[0], ellipsoid)
    station = integrity.travelled_m((lat_e - lat_e[0]) * r_m, (lon_e - lon_e[0]) * r_n * math.cos(lat_e[0]))
    resets = forward_pass.resets
    fixes = [m for m in aiding.measurements if isinstance(m, PositionFix)]
    missed = integrity.missed_fixes(trajectory, fixes, float(setup.gates[3]), ellipsoid) if fixes else ()
    verdict = integrity.assess(innovations, t[epochs], station, resets, missed=missed,
                               positions={m.name for m in sources if m.position_innovation})
    notices += [Notice("fusion", gap.message(), time_s=gap.end_s, severity="info") for gap in returns]
    notices += integrity_notices(resets, verdict)
    start = setup.start
    return FusionResult(trajectory, forward, tuple(forward_pass.rejections), forward_pass.statistics,
                        tuple(setup.stops), timeline=timeline, resets=tuple(resets), innovations=innovations,
                        integrity=verdict,
                        info={"update_epochs": m_epochs, "alignment_rpy_rad": start.rpy_rad,
                              "alignment": start.method, "warnings": [n.message for n in notices if n.severity == "warning"],
                              "notices": notices, "gnss_quality": aiding.gnss_quality,
                              "imu_outliers": setup.outliers, "imu_gaps": imu.gaps, "gap_returns": returns})


def integrity_notices(resets, verdict: FusionIntegrity) -> list[Notice]:
    """Every filter reset, every section whose solution is inconsistent with its 1-sigma and every
    stretch around a position fix the trajectory misses (their sleepers are not assessed): notices
    with their times."""
    notices = [Notice("fusion", reset.message(), time_s=reset.time_s) for reset in resets]
    notices += [Notice("fusion", why, time_s=at) for at, _, why in verdict.steps_s]
    notices += [Notice("fusion", "not valid from t = {time_from_s:.1f} s to {time_to_s:.1f} s (travelled "
                                 "{station_from_m:.0f}-{station_to_m:.0f} m): {why}; its sleepers are not assessed",
                       time_s=float(verdict.time_from_s[k]),
                       fields={"time_from_s": verdict.time_from_s[k], "time_to_s": verdict.time_to_s[k],
                               "station_from_m": verdict.station_from_m[k], "station_to_m": verdict.station_to_m[k],
                               "why": verdict.reasons[k]})
                for k in np.flatnonzero(~verdict.valid)]
    notices += [Notice("fusion", "not valid from t = {time_from_s:.1f} s to {time_to_s:.1f} s: {why}; its sleepers are not "
                                 "assessed", time_s=start, fields={"time_from_s": start, "time_to_s": end, "why": why})
                for start, end, why in (*verdict.detours_s, *verdict.missed_s)]
    return notices


#: update epochs whose smoother gains are made at a time, beside the recursion through the ones after them (:func:`_rts`)
GAIN_BLOCK = 256


def _read_only(array: np.ndarray) -> np.ndarray:
    array.flags.writeable = False
    return array


def _rts(store: SmootherStore, m: int, p0: np.ndarray, out: _RowFile, cancel: CancelToken, progress,
         made: Callable[[int], None] = lambda first: None) -> None:
    """Backward RTS pass (compiled, chunk by chunk from the store). Writes per update epoch j
    into row j of ``out`` the correction pair (left: e_j relative to the stored post-update
    solution, right: e_j + dx_j relative to the pre-update solution) and the smoothed sigmas
    (SMOOTHED_WIDTH), a chunk at a time; ``made(j)`` once the rows from j on are written. ``p0``: P
    at epoch 0, whole (its level angles' and start position's correlations with the sensor and
    attitude errors: their diagonal alone lets the smoother move epoch 0 away from the start it was given).
    The gains (:func:`_rts_gains`, half the work) need none of the smoothed results: those of the next
    GAIN_BLOCK records down are made in a background job while the recursion runs through a block."""
    state = np.zeros(1)
    e_next = np.zeros(N_STATES)
    P_s_next, p_minus_next = np.zeros((N_STATES, N_STATES)), np.zeros((N_STATES, N_STATES))
    # the first record of the chunk smoothed before (the one after it); read-only as the records' own views (the
    # spool's), so that _rts_gains has one signature: a second is a second kernel loaded from the cache, 20 ms of CPU
    after = _read_only(np.zeros((0, RECORD_SIZE)))
    # the block's gains and the next one's, made in the caller's memory (a job's thread would keep its own heap)
    gain_buffers = [np.empty((GAIN_BLOCK + 1, N_STATES, N_STATES)) for _ in range(2)]
    for first, records in store.reversed_chunks():
        check_cancel(cancel)
        progress((m - first) / m, "smoother")
        k = len(records)

        def gains_of(lower: int, into: np.ndarray, records=records, later=after, first=first) -> np.ndarray:
            upper = min(lower + GAIN_BLOCK, len(records))
            gains = into[: upper - lower + 1]  # row r: the epoch of record lower + r - 1
            _rts_gains(records[lower:upper], records[upper : upper + 1] if upper < len(records) else later, gains, p0,
                       first == 0 and lower == 0)
            return gains

        corrections, sigma = np.zeros((k + 1, 2, N_STATES)), np.zeros((k + 1, N_STATES))  # row r: epoch first + r
        lowers = range(((k - 1) // GAIN_BLOCK) * GAIN_BLOCK, -1, -GAIN_BLOCK)
        gains = gains_of(lowers[0], gain_buffers[0])
        for at, lower in enumerate(lowers):
            upcoming = (BackgroundJob(lambda progress, stopped, below=lowers[at + 1], into=gain_buffers[(at + 1) % 2]:
                                      gains_of(below, into), None, cancel, name="insrail-rts-gains")
                        if at + 1 < len(lowers) else None)
            with upcoming if upcoming is not None else contextlib.nullcontext():
                upper = min(lower + GAIN_BLOCK, k)
                _rts_chunk(records[lower:upper], gains, state, e_next, P_s_next, p_minus_next,
                           corrections[lower : upper + 1], sigma[lower : upper + 1], p0, first == 0 and lower == 0)
                if upcoming is not None:
                    gains = upcoming.result()
        after = _read_only(records[:1].copy())
        start = 0 if first == 0 else 1  # the first chunk's row 0 is epoch 0
        out.write(first + start, np.hstack([corrections[start:].reshape(k + 1 - start, 2 * N_STATES), sigma[start:]]))
        made(first + start)
    if not store.count:  # no segment: epoch 0 as the filter started it
        out.write(0, np.concatenate([np.zeros(2 * N_STATES), np.sqrt(np.maximum(np.diag(p0), 0.0))])[None])
        made(0)


class _RowsMade:
    """From which update epoch on the smoother's rows are written, told by the smoother's thread and
    waited for by the trajectory's (:func:`_smoothed_trajectory`)."""

    def __init__(self, m: int):
        self.first = m + 1  # none yet
        self.over = False  # the smoother returned or failed
        self.changed = threading.Condition()

    def made(self, first: int) -> None:
        with self.changed:
            self.first = first
            self.changed.notify_all()

    def end(self) -> None:
        with self.changed:
            self.over = True
            self.changed.notify_all()

    def wait(self, first: int, timeout_s: float) -> bool:
        """Whether the rows from ``first`` on are written (waits for them up to ``timeout_s``)."""
        with self.changed:
            return self.changed.wait_for(lambda: self.first <= first or self.over, timeout_s) and self.first <= first


def _smoothed_trajectory(store: SmootherStore, m: int, p0: np.ndarray, smoothed_rows: _RowFile, build,
                         progress: ProgressFn, cancel: CancelToken) -> Trajectory:
    """The backward pass (:func:`_rts`) and the smoothed trajectory ``build(progress=, cancel=, ready=)``
    made from its rows (:func:`_trajectory`): side by side where there are two CPUs (the pass in a
    background job, its kernel without the GIL; the trajectory's chunks last first, each as soon as
    the rows it reads are written), else one after the other. The same rows and the same file either
    way. The progress is the mean of the two's."""
    rows = _RowsMade(m)
    done = {"smoother": 0.0, "trajectory": 0.0}

    def tell(part: str, fraction: float, message: ProgressMessage) -> None:  # the caller's thread only
        done[part] = fraction
        progress(0.5 * (done["smoother"] + done["trajectory"]), message)

    def smooth(job_progress: ProgressFn, stopped: CancelToken) -> None:
        try:
            _rts(store, m, p0, smoothed_rows, stopped, job_progress, made=rows.made)
        finally:
            rows.end()

    with BackgroundJob(smooth, partial(tell, "smoother"), cancel, name="insrail-smoother") as job:
        def ready(first: int) -> None:
            while not rows.wait(first, WAIT_POLL_S):
                job.relay(partial(tell, "smoother"))
                check_cancel(cancel)
                if rows.over:
                    job.result()  # its failure
                    raise AssertionError(f"the smoother ended without the rows from update epoch {first} on")
            job.relay(partial(tell, "smoother"))

        trajectory = build(progress=partial(tell, "trajectory"), cancel=cancel, ready=ready)
        job.result(partial(tell, "smoother"))
    return trajectory


def _trajectory(t, nav_file: _EpochFile, epochs, history: _RowFile, smoothed_rows: _RowFile | None, gps_week, ell,
                smoothed, output_every: int = 1, indices: np.ndarray | None = None, path: Path | None = None,
                progress=None, cancel: CancelToken = None, ready: Callable[[int], None] | None = None) -> Trajectory:
    """Trajectory at every ``output_every``-th IMU epoch from the first update epoch on (or at
    ``indices``), the errors (``smoothed_rows``: the smoother's; None: none) interpolated
    linearly between update epochs. Built in chunks from the IMU-rate record of the forward pass
    and the filter-rate rows of the update epochs each chunk lies between; with ``path`` each
    chunk is written to that ``trajectory.npy`` as it is made and the result is a memory map of
    the file. ``ready(j)``: the chunks are made last first, each once ``ready`` returned for the
    first update epoch it reads (the smoother makes its rows from the last on)."""
    chunk = TRAJECTORY_CHUNK if ready is None else max(TRAJECTORY_CHUNK // 4, 1)
    if indices is None:  # every output_every-th epoch, made chunk by chunk (not one index per epoch held)
        first = int(epochs[0])
        n = len(range(first, int(epochs[-1]) + 1, output_every))
        # chunks of at most ``chunk`` IMU epochs of the record, whatever the output rate
        cuts = np.minimum(-(-np.arange(0, output_every * (n - 1) + chunk, chunk) // output_every), n)

        def rows_of(c0, c1):
            return first + output_every * np.arange(c0, c1)
    else:
        idx_all = np.asarray(indices)
        n = len(idx_all)
        cuts = np.searchsorted(idx_all, np.arange(idx_all[0], idx_all[-1] + chunk, chunk)) if n else np.zeros(1, int)

        def rows_of(c0, c1):
            return idx_all[c0:c1]
    writer = TrajectoryWriter(path, n) if path is not None else None
    records = None if writer is not None else np.empty(n, dtype=TRAJECTORY_DTYPE)
    blocks = [(c0, c1) for c0, c1 in itertools.pairwise(cuts) if c1 > c0]
    # every block made in one buffer (written out, or copied into the records, before the next is made): a fresh
    # 6 MB block each was a fresh mapping whose pages the kernel faults in and zeroes (insrail.memory)
    buffer = np.empty((max((c1 - c0 for c0, c1 in blocks), default=0), TRAJECTORY_DTYPE.itemsize // 8))
    made = 0
    try:
        for c0, c1 in blocks if ready is None else reversed(blocks):
            if progress is not None:
                check_cancel(cancel)
                progress(made / n, "trajectory")
            idx = rows_of(c0, c1)
            if ready is not None:
                ready(_first_update(epochs, int(idx[0])))
            rows = nav_file.read(int(idx[0]), int(idx[-1]) + 1)
            if len(rows) != len(idx):  # not every epoch (output_every): those of idx, read-only as the record itself
                rows = _read_only(rows[idx - idx[0]])
            block = _trajectory_block(t, rows, idx, epochs, history, smoothed_rows, ell, buffer[: len(idx)])
            if writer is None:
                records[c0:c1] = block
            elif ready is None:
                writer.write(block)
            else:
                writer.write_at(c0, block)
            made += c1 - c0
        if writer is not None:
            writer.commit()
    finally:
        if writer is not None:
            writer.discard()
    if writer is not None:
        return replace(load_trajectory(path, smoothed=smoothed, gps_week=gps_week, mmap=True), ellipsoid=ell)
    return trajectory_from_records(records, smoothed=smoothed, gps_week=gps_week, ellipsoid=ell)


def _segments(epochs, idx) -> np.ndarray:
    """The segment of each IMU epoch ``idx``: segment j covers epochs (epochs[j-1], epochs[j]]."""
    return np.clip(np.searchsorted(epochs, idx, side="left"), 1, max(len(epochs) - 1, 1))


def _first_update(epochs, first_idx: int) -> int:
    """The first update epoch whose rows the trajectory from IMU epoch ``first_idx`` on reads."""
    return int(_segments(epochs, np.array([first_idx]))[0]) - 1


def _trajectory_block(t, nav, idx, epochs, history: _RowFile, smoothed_rows: _RowFile | None, ell,
                      out: np.ndarray) -> np.ndarray:
    """TRAJECTORY_DTYPE records of IMU epochs ``idx`` (increasing) from their forward navigation vectors ``nav``,
    made in ``out`` (len(idx), 32): a view of it."""
    # w is the position inside the segment (:func:`_segments`)
    seg = _segments(epochs, idx)
    j0, j1 = int(seg.min()) - 1, min(int(seg.max()) + 1, len(epochs))  # the update epochs the block lies between
    rows = history.read(j0, j1)
    sensor_hist, sigma_hist = np.ascontiguousarray(rows[:, :13]), np.ascontiguousarray(rows[:, 13:])
    corrections = np.zeros((1, 2, N_STATES))
    if smoothed_rows is not None:
        rows = smoothed_rows.read(j0, j1)
        corrections = np.ascontiguousarray(rows[:, : 2 * N_STATES]).reshape(j1 - j0, 2, N_STATES)
        sigma_hist = np.ascontiguousarray(rows[:, 2 * N_STATES :])
    _trajectory_rows(t, np.ascontiguousarray(nav), idx, seg - j0, epochs[j0:j1], sensor_hist, sigma_hist,
                     corrections, smoothed_rows is not None, _kernels.earth_constants(ell), out)
    return out.view(TRAJECTORY_DTYPE).reshape(len(idx))


@compiled
def _trajectory_rows(t, nav, idx, seg, epochs, sensor_hist, sigma_hist, corrections, corrected, earth_c, out):
    """The rows of :func:`_trajectory_block` (TRAJECTORY_DTYPE's fields in order, 32 doubles): the
    forward solution at IMU epoch idx[i] (row i of nav), corrected by the smoothed error
    interpolated linearly inside its segment seg[i], with the sensor estimates used while
    propagating that segment and the interpolated sigmas."""
    n = N_STATES
    c = np.zeros(n)
    for i in range(idx.shape[0]):
        j = seg[i]
        left, right = epochs[j - 1], epochs[j]
        span = t[right] - t[left]
        w = (t[idx[i]] - t[left]) / span if span > 0.0 else 1.0
        lat, lon = _kernels.lat_lon((nav[i, 0], nav[i, 1], nav[i, 2], nav[i, 3]))
        h = nav[i, 4]
        vel = (nav[i, 5], nav[i, 6], nav[i, 7])
        q_bn = (nav[i, 8], nav[i, 9], nav[i, 10], nav[i, 11])
        if corrected:
            for k in range(n):
                c[k] = (1.0 - w) * corrections[j - 1, 0, k] + w * corrections[j, 1, k]
            r_m, r_n = _kernels.radii(math.sin(lat), earth_c)
            lat = lat - c[POS] / (r_m + h)
            lon = lon - c[POS + 1] / ((r_n + h) * math.cos(lat))
            h = h + c[POS + 2]
            vel = (vel[0] - c[VEL], vel[1] - c[VEL + 1], vel[2] - c[VEL + 2])
            q_bn = _kernels.quat_mul(_kernels.rotvec_quat(c[ATT], c[ATT + 1], c[ATT + 2]), q_bn)
        row = out[i]
        row[0], row[1], row[2], row[3] = t[idx[i]], lat, lon, h
        row[4], row[5], row[6] = vel[0], vel[1], vel[2]
        row[7], row[8], row[9] = _kernels.euler(q_bn)
        for k in range(9):  # sigma of position, velocity, attitude
            row[10 + k] = (1.0 - w) * sigma_hist[j - 1, POS + k] + w * sigma_hist[j, POS + k]
        for k in range(12):  # gyro/accel biases and scale factors
            row[19 + k] = sensor_hist[j - 1, k] + c[BG + k]
        row[31] = sensor_hist[j - 1, 12] + c[ODO]


# These kernels run compiled code of other modules (the measurement models, the Kalman update, the
# strapdown, the copy of insrail.jit): their cache entries go when those modules change (numba checks only this file).
_kernels.drop_stale_cache((_propagate_segment, dynamics_rows, _transition, _feedback, _pack_record, _unpack_record,
                           _unpack_reversed, _forward_kernel, _rts_gains, _rts_chunk, _trajectory_rows),
                          (meas.__file__, kalman.__file__, _kernels.__file__, error_model.__file__, jit.__file__))
