"""Accuracy after a survey: the covariance analysis along its actual measurement timeline.

``survey_quality`` replays what the forward filter of ``insrail.nav.fusion`` did (its
``FusionResult.timeline``: the update epochs and every measurement it applied, rejected
ones left out; the GNSS gaps, stops with their ZUPTs, odometer and NHC; its filter resets,
which widen P where the filter widened it) in covariance-only form: Phi and Q of every segment from ``insrail.nav.error_model`` linearised on the forward
trajectory, H and R from the fusion's own measurement objects. It then summarises the
forward or smoothed covariances per section of track (200 m by default): the 1-sigma
lateral and vertical position error and the 1-sigma of the 5 m and 150 m lag differences,
the quantities behind the 30 m/5 m and 300 m/150 m checks, the 1-sigma of the cross-level
(cant): the roll error over the rails' spacing, 1.5 m, and of the along-track position.

Stations are the odometer distance from the first update epoch (plus ``station_offset_m``);
a lag pair is assigned to the section holding its midpoint. Section figures are RMS values
over the moving update epochs (position) or pairs (lags) in the section.

The processing pipeline splits the work: ``epoch_quality`` (the expensive covariance pass,
cached with the fusion; for the smoothed pass only the backward recursion over the fusion's
own record of Phi, P- and P+ when given its ``SmootherStore``) keeps one pass's figures per
update epoch and per lag pair;
``sections_along`` then forms the sections on any station measure given per epoch, e.g. the
project's chainage, which is known only after the track reconstruction.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from insrail.io.survey import SurveyData
from insrail.nav import earth
from insrail.nav.error_model import (
    N_STATES,
    ErrorModelNoise,
    discretise,
    dynamics_matrix,
    noise_matrix,
    play_noise,
)
from insrail.nav.fusion import FusionOptions, FusionResult, SmootherStore, _unpack_reversed, play_drift
from insrail.nav.imu_profile import ImuProfile, load_imu_profile
from insrail.nav.measurements import NavSnapshot
from insrail.nav.rotation import euler_to_dcm
from insrail.progress import CancelToken, ProgressFn
from insrail.quality.covariance import (
    SMOOTH_PART_EPOCHS,
    CovarianceProfile,
    PassCovariance,
    analyse,
    analyse_recorded,
)
from insrail.quality.prediction import CANT_BASE_M, LONG_LAG_M, SHORT_LAG_M
from insrail.quality.section_quality import SectionQuality, weakness

#: Below this speed [m/s] the direction of travel is carried over from the last motion.
_MOVING_SPEED_MPS = 0.05

def survey_quality(
    survey: SurveyData,
    result: FusionResult,
    options: FusionOptions = FusionOptions(),
    profile: ImuProfile | None = None,
    ellipsoid: earth.Ellipsoid = earth.WGS84,
    section_m: float = 200.0,
    smoothed: bool | None = None,
    station_offset_m: float = 0.0,
    anchor_spacing_m: float = 1.0,
    progress: ProgressFn | None = None,
    cancel: CancelToken = None,
) -> SectionQuality:
    """Per-section accuracy of a fused survey. ``options``, ``profile`` and ``ellipsoid``
    must be those the fusion used; ``smoothed`` defaults to what the fusion delivered."""
    if section_m <= 0.0:
        raise ValueError(f"section length must be positive, got {section_m} m")
    smoothed = result.trajectory.smoothed if smoothed is None else smoothed
    cov = _covariance(survey, result, options, profile, ellipsoid, smoothed, True, station_offset_m,
                      anchor_spacing_m, None, progress, cancel)
    return sections(cov, smoothed, section_m)


def _covariance(survey, result, options, profile, ellipsoid, smoothed, forward_lags, station_offset_m,
                anchor_spacing_m, store: SmootherStore | None, progress, cancel) -> CovarianceProfile:
    """The covariance analysis along the fusion's timeline (stations: odometer distance):
    with the fusion's ``store`` the smoother's backward pass over its record, else a replay."""
    epochs = UpdateEpochs.of(survey.odometer, result, station_offset_m)
    if store is not None and smoothed and not forward_lags:
        return _recorded(epochs, store, anchor_spacing_m, progress, cancel)
    t, station, heading = epochs.time_s, epochs.station_m, epochs.heading_rad
    timeline = result.timeline
    nav = result.forward
    k = _forward_index(nav, t)
    anchors = _anchors(station, anchor_spacing_m)
    lags_m = (SHORT_LAG_M, LONG_LAG_M)
    profile = profile or load_imu_profile(survey.manifest.imu_profile)
    noise = ErrorModelNoise.from_profile(profile, options.gnss_correlated_tau_s, options.gnss_correlated_sigma_ned_m)
    gqg = noise_matrix(noise)
    m = len(t)
    lat, lon, h, vel = nav.lat_rad[k], nav.lon_rad[k], nav.height_m[k], nav.vel_ned_mps[k]
    c_bn = euler_to_dcm(nav.rpy_rad[k, 0], nav.rpy_rad[k, 1], nav.rpy_rad[k, 2])
    odometer_scale = nav.odometer_scale[k]
    # Mean compensated-enough rates over each segment from the raw increments (biases of a
    # few deg/h do not change F).
    imu = survey.imu
    i_end = np.searchsorted(imu.time_s, t - 1e-6)
    cum_theta = np.vstack([np.zeros(3), np.cumsum(imu.dtheta_rad, axis=0)])
    cum_vel = np.vstack([np.zeros(3), np.cumsum(imu.dvel_mps, axis=0)])
    seg = np.diff(t, prepend=t[0])
    seg[0] = seg[1] if m > 1 else 0.1
    span = np.maximum(seg, 1e-6)[:, None]
    i_start = np.searchsorted(imu.time_s, t - seg - 1e-6)
    omega_b = (cum_theta[i_end + 1] - cum_theta[i_start + 1]) / span
    f_b = (cum_vel[i_end + 1] - cum_vel[i_start + 1]) / span
    # the fusion's models take the rate of the record ending at the epoch (its noise is the NHC rows')
    rate_span = np.diff(imu.time_s, prepend=imu.time_s[0] - (imu.time_s[1] - imu.time_s[0]))[i_end]

    applied_at: dict[int, list] = {}
    for name, pairs in timeline.applied.items():
        meas = timeline.measurements[name]
        for j, i in pairs:
            applied_at.setdefault(int(j), []).append((meas, int(i)))

    def snapshot(j):
        return NavSnapshot(time_s=float(t[j]), lat=float(lat[j]), lon=float(lon[j]), h=float(h[j]), vel_ned=vel[j],
                           c_bn=c_bn[j], omega_ib_b=omega_b[j], f_b=f_b[j], mean_vel_ned=vel[j],
                           mean_omega_ib_b=omega_b[j], segment_s=float(seg[j]), odometer_scale=float(odometer_scale[j]),
                           rate_span_s=float(rate_span[j]),
                           ellipsoid=ellipsoid)

    resets = reset_segments(result)
    play = play_drift(options, timeline.measurements.values())

    def segment(j):
        F = dynamics_matrix(lat[j], h[j], vel[j], c_bn[j], f_b[j], omega_b[j], noise, ellipsoid)
        phi, q = discretise(F, gqg, seg[j])
        q[:3, :3] += play_noise(vel[j] * seg[j], seg[j], play)
        snap = snapshot(j)
        updates = (meas.model(snap, i)[1:] for meas, i in applied_at.get(j, ()))
        return (phi, q, updates, resets[j]) if j in resets else (phi, q, updates)

    return analyse(timeline.initial_covariance, segment, t, station, heading, anchors, lags_m,
                   smoother=smoothed, forward_lags=forward_lags, progress=progress, cancel=cancel)


@dataclass(frozen=True)
class UpdateEpochs:
    """What the analysis of the fusion's record reads of the fusion, per update epoch: its time,
    station (odometer distance from the first epoch, plus an offset) and direction of travel,
    and the covariance at the first one. Taken out of the :class:`FusionResult` so that the
    caller can let the result (the forward solution at the update epochs, the innovations:
    ~0.3 kB per update epoch) go before the analysis runs."""

    time_s: np.ndarray
    station_m: np.ndarray
    heading_rad: np.ndarray
    initial_covariance: np.ndarray

    @classmethod
    def of(cls, odometer, result: FusionResult, station_offset_m: float = 0.0) -> UpdateEpochs:
        timeline = result.timeline
        if timeline is None:
            raise ValueError("the fusion result carries no measurement timeline; fuse the survey again")
        t = timeline.time_s
        nav = result.forward  # the navigation state the filter linearised on, at the update epochs
        k = _forward_index(nav, t)
        distance = _travelled_m(odometer, t, nav, k)
        station = distance - distance[0] + station_offset_m
        heading = _travel_direction(nav.vel_ned_mps[k], nav.rpy_rad[k, 2])
        return cls(t, station, heading, timeline.initial_covariance)


def recorded_quality(epochs: UpdateEpochs, store: SmootherStore, anchor_spacing_m: float = 1.0,
                     progress: ProgressFn | None = None, cancel: CancelToken = None) -> EpochQuality:
    """:func:`epoch_quality` of a smoothed fusion from its ``store``, given only the fusion's
    :class:`UpdateEpochs` (the same figures to the bit)."""
    return EpochQuality.from_profile(_recorded(epochs, store, anchor_spacing_m, progress, cancel), True)


def _recorded(epochs: UpdateEpochs, store: SmootherStore, anchor_spacing_m, progress, cancel) -> CovarianceProfile:
    """The smoother's backward pass over the fusion's record of Phi, P- and P+."""
    t = epochs.time_s
    if store.count != len(t) - 1:
        raise ValueError(f"the covariance store holds {store.count} segments, the fusion's timeline "
                         f"{len(t) - 1}: it is not this fusion's record")
    return analyse_recorded(epochs.initial_covariance, _reversed_parts(store), t, epochs.station_m, epochs.heading_rad,
                            _anchors(epochs.station_m, anchor_spacing_m), (SHORT_LAG_M, LONG_LAG_M),
                            progress=progress, cancel=cancel)


def _reversed_parts(store: SmootherStore):
    """The store's records as blocks (j, Phi_j, P-_j, P+_j) of :data:`SMOOTH_PART_EPOCHS`, j decreasing
    (``SmootherStore.reversed_blocks`` without the updates dx): the store's read buffer is unpacked a
    part at a time, so that no more than a part's matrices (4 MB) are held beside the analysis. Every
    part is unpacked into the same arrays (fresh ones per part were fresh mappings whose pages the
    kernel faults in and zeroes, ``insrail.memory``): a part is good until the next one is asked for."""
    size = max(min(SMOOTH_PART_EPOCHS, store.chunk, store.count), 1)  # a part lies inside a chunk
    phi, p_minus, p_plus = (np.empty((size, N_STATES, N_STATES)) for _ in range(3))
    dx = np.empty((size, N_STATES))
    for first, chunk in store.reversed_chunks():
        top = first + len(chunk)
        for start in range(0, len(chunk), SMOOTH_PART_EPOCHS):
            part = chunk[max(len(chunk) - start - SMOOTH_PART_EPOCHS, 0) : len(chunk) - start]  # unpacked last first
            k = len(part)
            _unpack_reversed(part, phi[:k], p_minus[:k], p_plus[:k], dx[:k])
            yield np.arange(top - start, top - start - k, -1), phi[:k], p_minus[:k], p_plus[:k]


def _forward_index(nav, t: np.ndarray) -> np.ndarray:
    """Index of each update epoch ``t`` in the forward solution ``nav``."""
    return np.clip(np.searchsorted(nav.time_s, t - 1e-6), 0, len(nav.time_s) - 1)


def _anchors(station: np.ndarray, spacing_m: float) -> np.ndarray:
    """The epochs whose lag differences are wanted: the first at or past every ``spacing_m``."""
    return np.unique(np.searchsorted(station, np.arange(station[0], station[-1], spacing_m)))


def reset_segments(result: FusionResult) -> dict[int, tuple[np.ndarray, np.ndarray]]:
    """Per update epoch j, the filter reset the fusion applied to the P- of segment j (states, 1-sigma
    floor): the one decided at the update epoch of the rejected observation that ended the run, applied
    to the next segment (``insrail.nav.fusion``)."""
    t = result.timeline.time_s
    out = {}
    for reset in result.resets:
        j = int(np.searchsorted(t, reset.time_s - 1e-6)) + 1
        if 0 < j < len(t):
            floors = reset.floors()
            states = np.flatnonzero(~np.isnan(floors))
            out[j] = (states, floors[states])
    return out


def _travelled_m(odometer, t: np.ndarray, nav, k: np.ndarray) -> np.ndarray:
    """Distance travelled at the update epochs ``t``: the odometer's, or without one the fused
    horizontal speed integrated (never decreasing)."""
    if odometer is not None:
        return np.maximum.accumulate(np.interp(t, odometer.time_s, odometer.distance_m))
    speed = np.hypot(nav.vel_ned_mps[k, 0], nav.vel_ned_mps[k, 1])
    return np.concatenate([[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(t))])


def _travel_direction(vel_ned: np.ndarray, heading_rad: np.ndarray) -> np.ndarray:
    """Direction of the velocity where the trolley moves, carried over through stops (the
    IMU heading before the first motion)."""
    speed = np.hypot(vel_ned[:, 0], vel_ned[:, 1])
    moving = speed > _MOVING_SPEED_MPS
    direction = np.where(moving, np.arctan2(vel_ned[:, 1], vel_ned[:, 0]), heading_rad)
    last = np.maximum.accumulate(np.where(moving, np.arange(len(speed)), -1))
    return np.where(last >= 0, direction[np.maximum(last, 0)], heading_rad)


def sections(profile: CovarianceProfile, smoothed: bool, section_m: float = 200.0) -> SectionQuality:
    """Section figures of one pass of a covariance profile. The last section takes the
    remainder of the track, so it is between 1/4 and 5/4 of ``section_m`` long."""
    epochs = EpochQuality.from_profile(profile, smoothed)
    station = profile.station_m
    n = max(int(math.floor((station[-1] - station[0]) / section_m + 0.75)), 1)
    edges = station[0] + section_m * np.arange(n + 1)
    edges[-1] = station[-1]

    def section_of(where):
        return np.clip(np.searchsorted(edges, where, side="right") - 1, 0, n - 1)

    return _binned(epochs, station, section_of, edges[:-1], edges[1:], profile)


@dataclass(frozen=True)
class EpochQuality:
    """One pass of a survey's covariance analysis, per update epoch and per lag pair [m]:
    what section figures are made of, on whatever station measure (see ``sections_along``).
    Lag pair p joins epochs ``lag5_first_epoch[p]`` and ``lag5_second_epoch[p]``."""

    smoothed: bool
    time_s: np.ndarray  # update epochs [s of week]
    moving: np.ndarray  # the trolley advanced over the segment ending at the epoch
    sigma_lateral_m: np.ndarray
    sigma_vertical_m: np.ndarray
    lag5_first_epoch: np.ndarray
    lag5_second_epoch: np.ndarray
    lag5_sigma_lateral_m: np.ndarray
    lag5_sigma_vertical_m: np.ndarray
    lag150_first_epoch: np.ndarray
    lag150_second_epoch: np.ndarray
    lag150_sigma_lateral_m: np.ndarray
    lag150_sigma_vertical_m: np.ndarray
    sigma_cross_level_m: np.ndarray  # CANT_BASE_M x the roll's 1-sigma
    sigma_along_track_m: np.ndarray

    LAGS: ClassVar[dict[str, float]] = {"lag5": SHORT_LAG_M, "lag150": LONG_LAG_M}

    @classmethod
    def from_profile(cls, profile: CovarianceProfile, smoothed: bool) -> EpochQuality:
        cov: PassCovariance = profile.smoothed if smoothed else profile.forward
        if cov is None:
            raise ValueError("the covariance profile has no smoothed pass")
        lags = {}
        for prefix, lag_m in cls.LAGS.items():
            item = cov.lag(lag_m)
            lags |= {f"{prefix}_first_epoch": item.first_epoch, f"{prefix}_second_epoch": item.second_epoch,
                     f"{prefix}_sigma_lateral_m": item.sigma_lateral_m,
                     f"{prefix}_sigma_vertical_m": item.sigma_vertical_m}
        station = profile.station_m
        return cls(smoothed=bool(smoothed), time_s=profile.time_s, moving=np.diff(station, prepend=station[0]) > 0.0,
                   sigma_lateral_m=cov.sigma_lateral_m, sigma_vertical_m=cov.sigma_vertical_m,
                   sigma_cross_level_m=CANT_BASE_M * cov.sigma_roll_rad, sigma_along_track_m=cov.sigma_along_track_m,
                   **lags)


def epoch_quality(
    survey: SurveyData,
    result: FusionResult,
    options: FusionOptions = FusionOptions(),
    profile: ImuProfile | None = None,
    ellipsoid: earth.Ellipsoid = earth.WGS84,
    smoothed: bool | None = None,
    anchor_spacing_m: float = 1.0,
    covariance_store: SmootherStore | None = None,
    progress: ProgressFn | None = None,
    cancel: CancelToken = None,
) -> EpochQuality:
    """The covariance analysis of a fused survey for the pass it delivered (or ``smoothed``),
    kept per epoch. Only that pass's lag differences are computed.

    ``covariance_store``: the :class:`SmootherStore` the fusion recorded into (``fuse(...,
    covariance_store=...)``). The smoothed analysis then runs only the backward pass over the
    filter's own Phi, P- and P+ (a fraction of the replay's cost; the same figures to the
    replay's linearisation differences, well under 1 %). The forward analysis, whose lag
    differences need the gains, always replays."""
    smoothed = result.trajectory.smoothed if smoothed is None else smoothed
    cov = _covariance(survey, result, options, profile, ellipsoid, smoothed, not smoothed, 0.0, anchor_spacing_m,
                      covariance_store, progress, cancel)
    return EpochQuality.from_profile(cov, smoothed)


def sections_along(epochs: EpochQuality, station_m: np.ndarray, start_m: float,
                   section_m: float = 200.0) -> SectionQuality:
    """Section figures on a station measure given per update epoch (e.g. the chainage of the
    reconstructed centreline at the epochs' times): sections [start_m + k section_m,
    start_m + (k + 1) section_m), k = 0, 1, ..., as many as the moving epochs cover, the last
    one cut at the last covered station. Stations before ``start_m`` (e.g. the metre before
    the first sleeper) count in the first section."""
    if section_m <= 0.0:
        raise ValueError(f"section length must be positive, got {section_m} m")
    station = np.asarray(station_m, dtype=float)
    if station.shape != epochs.time_s.shape:
        raise ValueError(f"need one station per update epoch ({len(epochs.time_s)}), got {station.shape}")
    covered = station[epochs.moving & np.isfinite(station)]
    if covered.size == 0 or covered.max() <= start_m:
        raise ValueError(f"no moving epoch lies beyond station {start_m} m: nothing to divide into sections")
    high = float(covered.max())
    n = max(int(math.ceil((high - start_m) / section_m)), 1)
    edges = start_m + section_m * np.arange(n + 1)
    edges[-1] = min(edges[-1], high)

    def section_of(where):
        return np.clip(np.floor((where - start_m) / section_m).astype(int), 0, n - 1)

    return _binned(epochs, station, section_of, edges[:-1], edges[1:])


def _binned(epochs: EpochQuality, station: np.ndarray, section_of, station_from, station_to,
            profile: CovarianceProfile | None = None) -> SectionQuality:
    """RMS per section of the position sigmas (moving epochs) and the lag sigmas (pairs, by the
    station of their midpoint); NaN where a section has none."""
    n = len(station_from)

    def rms_per_section(where, values):
        keep = np.isfinite(where)
        idx = section_of(where[keep])
        sums = np.bincount(idx, values[keep] ** 2, minlength=n)
        counts = np.bincount(idx, minlength=n)
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(counts > 0, np.sqrt(sums / np.maximum(counts, 1)), np.nan)

    moving = epochs.moving
    figures = {"sigma_lateral_m": rms_per_section(station[moving], epochs.sigma_lateral_m[moving]),
               "sigma_vertical_m": rms_per_section(station[moving], epochs.sigma_vertical_m[moving]),
               "sigma_cross_level_m": rms_per_section(station[moving], epochs.sigma_cross_level_m[moving]),
               "sigma_along_track_m": rms_per_section(station[moving], epochs.sigma_along_track_m[moving])}
    for prefix in EpochQuality.LAGS:
        first, second = getattr(epochs, f"{prefix}_first_epoch"), getattr(epochs, f"{prefix}_second_epoch")
        middle = 0.5 * (station[first] + station[second])
        for axis in ("lateral", "vertical"):
            figures[f"sigma_{prefix}_{axis}_m"] = rms_per_section(middle, getattr(epochs, f"{prefix}_sigma_{axis}_m"))
    return SectionQuality(station_from_m=np.asarray(station_from, dtype=float),
                          station_to_m=np.asarray(station_to, dtype=float), smoothed=epochs.smoothed, profile=profile,
                          **figures)
