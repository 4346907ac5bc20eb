"""Accuracy before a survey: the filter and smoother in covariance-only form on a planned run.

``predict`` lays out the run the way the simulator and the fusion see it (a static start
for the alignment, straight level track at constant speed, optional stops and GNSS
outages, a static end), builds every segment's Phi and Q with ``insrail.nav.error_model``,
the aiding sources with the fusion's own builder (``insrail.nav.fusion.aiding_sources``:
which aids, their sigmas) on the planned GNSS epochs, odometer record and stops, applies
them by the fusion's own schedule (``insrail.nav.measurements.schedule``: when each applies)
and hands the timeline to :func:`insrail.quality.covariance.analyse`. Prediction and fusion
share their models and their schedule, so they cannot drift apart.

Figures (``AccuracyFigures``, 1 sigma, metres): RMS over the moving part of the run of
the lateral and vertical position error, the cant error (1.5 m times the roll error),
the 5 m and 150 m lag differences of the lateral and vertical error (the quantities
behind the 30 m/5 m and 300 m/150 m checks), and inside GNSS outages the growth of the
position sigma from the outage's start to its worst point.

Straight constant-speed track is the thesis's worst case (chapter 3.2.2): curves and
speed changes make heading and the accelerometer biases more observable.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import ClassVar

import numpy as np

from insrail.io.survey import TrolleyGeometry
from insrail.io.types import GnssSolution, OdometerData
from insrail.nav import earth
from insrail.nav.error_model import (
    ErrorModelNoise,
    discretise,
    dynamics_matrix,
    noise_matrix,
    play_noise,
)
from insrail.nav.fusion import FusionOptions, aiding_sources, initial_covariance, play_drift
from insrail.nav.imu_profile import ImuProfile, load_imu_profile
from insrail.nav.measurements import NavSnapshot, schedule
from insrail.nav.relative import FRAME_HEADING_SIGMA_RAD, START_SIGMA_M
from insrail.nav.rotation import euler_to_dcm
from insrail.progress import CancelToken, ProgressFn
from insrail.quality.covariance import CovarianceProfile, PassCovariance, analyse
from insrail.quality.section_quality import LONG_LAG_M, SHORT_LAG_M

#: Cant is the roll error times the rail-centre spacing (thesis eq. 2.1, L = 1500 mm).
CANT_BASE_M = 1.5


@dataclass(frozen=True)
class GnssQuality:
    """The GNSS solution as the planner expects it: the white (epoch-to-epoch) sigma and the
    rate. The slowly varying part is the fusion's Gauss-Markov model
    (``FusionOptions.gnss_correlated_sigma_ned_m``, ``gnss_correlated_tau_s``); the file's
    sigma is the root sum of squares of both, as the simulator writes it."""

    white_horizontal_m: float = 0.010
    white_vertical_m: float = 0.020
    rate_hz: float = 1.0

    def file_sigma_ned_m(self, options: FusionOptions) -> np.ndarray:
        white = np.array([self.white_horizontal_m, self.white_horizontal_m, self.white_vertical_m])
        return np.hypot(white, options.gnss_correlated_sigma_ned_m)


@dataclass(frozen=True)
class AccuracyFigures:
    """1-sigma figures of one pass [m]; NaN where they do not apply (no outage)."""

    position_lateral_m: float
    position_vertical_m: float
    cant_m: float
    lag5_lateral_m: float
    lag5_vertical_m: float
    lag150_lateral_m: float
    lag150_vertical_m: float
    outage_growth_lateral_m: float
    outage_growth_vertical_m: float

    NAMES: ClassVar[dict[str, str]] = {
        "position_lateral_m": "position lateral",
        "position_vertical_m": "position vertical",
        "cant_m": "cant",
        "lag5_lateral_m": "5 m lag lateral (30 m/5 m)",
        "lag5_vertical_m": "5 m lag vertical (30 m/5 m)",
        "lag150_lateral_m": "150 m lag lateral (300 m/150 m)",
        "lag150_vertical_m": "150 m lag vertical (300 m/150 m)",
        "outage_growth_lateral_m": "outage growth lateral",
        "outage_growth_vertical_m": "outage growth vertical",
    }

    def as_dict(self) -> dict[str, float]:
        return {name: getattr(self, name) for name in self.NAMES}


@dataclass(frozen=True)
class Prediction:
    forward: AccuracyFigures
    smoothed: AccuracyFigures | None
    profile: CovarianceProfile
    moving: np.ndarray  # (m,) update epochs while the trolley moves
    outages_s: tuple[tuple[float, float], ...]  # GNSS outages as time intervals of the run
    inputs: dict = field(default_factory=dict)


def _rms(x) -> float:
    x = np.asarray(x)
    return float(np.sqrt(np.mean(x**2))) if x.size else math.nan


def figures(cov: PassCovariance, time_s: np.ndarray, moving: np.ndarray, outages_s) -> AccuracyFigures:
    """The summary figures of one pass over the epochs in ``moving``."""
    lags = {}
    for lag in (SHORT_LAG_M, LONG_LAG_M):
        item = cov.lag(lag)
        inside = moving[item.first_epoch] & moving[item.second_epoch]
        lags[lag] = (_rms(item.sigma_lateral_m[inside]), _rms(item.sigma_vertical_m[inside]))
    growth = [math.nan, math.nan]
    for start, end in outages_s:
        inside = (time_s >= start) & (time_s <= end)
        if inside.any():
            before = max(int(np.searchsorted(time_s, start)) - 1, 0)
            for a, sigma in enumerate((cov.sigma_lateral_m, cov.sigma_vertical_m)):
                growth[a] = np.nanmax([growth[a], sigma[inside].max() - sigma[before]])
    return AccuracyFigures(
        position_lateral_m=_rms(cov.sigma_lateral_m[moving]),
        position_vertical_m=_rms(cov.sigma_vertical_m[moving]),
        cant_m=CANT_BASE_M * _rms(cov.sigma_roll_rad[moving]),
        lag5_lateral_m=lags[SHORT_LAG_M][0], lag5_vertical_m=lags[SHORT_LAG_M][1],
        lag150_lateral_m=lags[LONG_LAG_M][0], lag150_vertical_m=lags[LONG_LAG_M][1],
        outage_growth_lateral_m=float(growth[0]), outage_growth_vertical_m=float(growth[1]),
    )


def default_trolley() -> TrolleyGeometry:
    """The simulator's trolley (lever arms of a typical A-INS trolley)."""
    from insrail.sim.scenario import default_trolley as simulated

    return simulated()


@dataclass(frozen=True)
class _Plan:
    """The run on the update grid: per segment (ending at the epoch) its mean speed and
    acceleration, and the station reached."""

    time_s: np.ndarray
    station_m: np.ndarray
    speed_mps: np.ndarray
    accel_mps2: np.ndarray


def _plan(speed_mps, length_m, stops, static_start_s, static_end_s, ramp_s, dt) -> _Plan:
    """Static start, then legs at ``speed_mps`` between the stops, each starting and ending
    with a linear speed ramp of ``ramp_s``, and a static end. The ramps matter: only while
    the speed changes does a heading error turn into a velocity error the NHC sees as
    sideways motion (before, a prediction without them claimed heading from the first
    NHC update)."""
    legs = []  # (distance, rest after it)
    position = 0.0
    for station, duration in sorted(stops):
        if not 0.0 < station < length_m:
            raise ValueError(f"stop at {station} m lies outside the run (0 - {length_m} m)")
        legs.append((station - position, duration))
        position = station
    legs.append((length_m - position, static_end_s))
    n_ramp = max(int(round(ramp_s / dt)), 1)
    up = speed_mps * (np.arange(n_ramp) + 0.5) / n_ramp
    speeds, accels = [np.zeros(int(round(static_start_s / dt)) + 1)], []
    accels.append(np.zeros_like(speeds[0]))
    for distance, rest in legs:
        cruise = max(int(round((distance - speed_mps * n_ramp * dt) / (speed_mps * dt))), 0)
        speeds += [up, np.full(cruise, speed_mps), up[::-1], np.zeros(int(round(rest / dt)))]
        a = speed_mps / (n_ramp * dt)
        accels += [np.full(n_ramp, a), np.zeros(cruise), np.full(n_ramp, -a), np.zeros(int(round(rest / dt)))]
    speed = np.concatenate(speeds)
    speed[0] = 0.0
    station = np.cumsum(speed * dt)
    return _Plan(np.arange(len(speed)) * dt, station, speed, np.concatenate(accels))


def _stops(plan: _Plan) -> list[tuple[float, float]]:
    """The plan's standstills as time intervals [start, end]: the runs of segments without
    motion (segment j ends at epoch j)."""
    still = np.concatenate([plan.speed_mps == 0.0, [False]])
    edges = np.diff(still.astype(np.int8), prepend=0)
    first, after = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    return [(float(plan.time_s[max(a - 1, 0)]), float(plan.time_s[b - 1])) for a, b in zip(first, after)]


def _snapshot(lat, h, vel_ned, accel_ned, c_bn, dt, ell, rate_span_s) -> NavSnapshot:
    """The INS state of a trolley on straight level track (``rate_span_s``: the IMU's record interval)."""
    omega_in = earth.earth_rate_ned(lat, ell) + earth.transport_rate_ned(lat, h, vel_ned, ell)
    c_nb = c_bn.T
    omega_ib_b = c_nb @ omega_in
    f_b = c_nb @ (accel_ned - np.array([0.0, 0.0, earth.normal_gravity(lat, h, ell)]))
    return NavSnapshot(time_s=0.0, lat=lat, lon=0.0, h=h, vel_ned=vel_ned, c_bn=c_bn, omega_ib_b=omega_ib_b, f_b=f_b,
                       mean_vel_ned=vel_ned, mean_omega_ib_b=omega_ib_b, segment_s=dt, odometer_scale=0.0, rate_span_s=rate_span_s,
                       ellipsoid=ell)


def predict(
    profile: ImuProfile | str = "nav",
    gnss: GnssQuality | None = GnssQuality(),
    aiding: FusionOptions = FusionOptions(),
    speed_mps: float = 1.0,
    length_m: float = 1000.0,
    outages: tuple[tuple[float, float], ...] = (),
    stops: tuple[tuple[float, float], ...] = (),
    trolley: TrolleyGeometry | None = None,
    static_start_s: float = 300.0,
    static_end_s: float = 60.0,
    ramp_s: float = 6.0,
    latitude_deg: float = 30.0,
    heading_deg: float = 0.0,
    odometer_pulse_m: float = 0.001,
    anchor_spacing_m: float = 1.0,
    ellipsoid: earth.Ellipsoid = earth.WGS84,
    progress: ProgressFn | None = None,
    cancel: CancelToken = None,
) -> Prediction:
    """Predict the 1-sigma accuracy of a planned run.

    outages : (station from the start [m], duration [s]) of GNSS outages
    stops   : (station [m], duration [s]) of stops (ZUPTs)
    aiding  : the fusion's options: which aids, their sigmas, the update rate, forward only
              (``smoother=False``) or smoothed
    gnss    : None for a relative survey (no position source: ``insrail.nav.relative``), started as the
              fusion starts one: position and heading exact, the frame's own
    """
    if isinstance(profile, str):
        profile = load_imu_profile(profile)
    if speed_mps <= 0.0 or length_m <= LONG_LAG_M:
        raise ValueError(f"need a positive speed and a run longer than {LONG_LAG_M:g} m "
                         f"(got {speed_mps} m/s, {length_m} m)")
    if gnss is not None and aiding.update_rate_hz < gnss.rate_hz:
        raise ValueError("the GNSS rate cannot exceed the filter's update rate")
    trolley = trolley or default_trolley()
    dt = 1.0 / aiding.update_rate_hz
    plan = _plan(speed_mps, length_m, stops, static_start_s, static_end_s, ramp_s, dt)
    m = len(plan.time_s)

    gnss_every = int(round(aiding.update_rate_hz / gnss.rate_hz)) if gnss is not None else 1
    has_gnss = (np.arange(m) % gnss_every == 0) & (gnss is not None)
    outages_s = []
    for station, duration in outages:
        k = int(np.searchsorted(plan.station_m, station))
        if k >= m or station < 0.0:
            raise ValueError(f"outage at {station} m lies outside the run (0 - {length_m} m)")
        outages_s.append((float(plan.time_s[k]), float(plan.time_s[k] + duration)))
        has_gnss &= ~((plan.time_s >= plan.time_s[k]) & (plan.time_s <= plan.time_s[k] + duration))

    noise = ErrorModelNoise.from_profile(profile, aiding.gnss_correlated_tau_s, aiding.gnss_correlated_sigma_ned_m)
    gqg = noise_matrix(noise)
    lat, h = math.radians(latitude_deg), 30.0
    heading = math.radians(heading_deg)
    c_vb = euler_to_dcm(*trolley.mounting_rpy_rad)
    c_bn = euler_to_dcm(0.0, 0.0, heading) @ c_vb
    file_sigma = gnss.file_sigma_ned_m(aiding) if gnss is not None else np.full(3, START_SIGMA_M)
    gnss_epochs = np.flatnonzero(has_gnss)
    k = len(gnss_epochs)
    planned_gnss = None if gnss is None else GnssSolution(plan.time_s[gnss_epochs], np.full(k, lat), np.zeros(k), np.full(k, h),
                                np.tile(file_sigma, (k, 1)), np.ones(k, dtype=int), np.zeros(k, dtype=int),
                                np.full(k, np.nan))
    planned_odometer = OdometerData(plan.time_s, plan.station_m, odometer_pulse_m)
    sources = aiding_sources(aiding, trolley, profile, planned_gnss, planned_odometer)
    timeline = schedule(plan.time_s, sources, _stops(plan))
    play = play_drift(aiding, sources)
    forward_ned = np.array([math.cos(heading), math.sin(heading), 0.0])

    # straight track: Phi, Q and every source's (H, R) depend on the speed and acceleration only
    # (a few distinct pairs); GNSS epochs lie on update epochs, so the lever's time term is zero
    cache = {}

    def segment(j):
        key = (plan.speed_mps[j], plan.accel_mps2[j])
        if key not in cache:
            vel = key[0] * forward_ned
            snap = replace(_snapshot(lat, h, vel, key[1] * forward_ned, c_bn, dt, ellipsoid, 1.0 / profile.rate_hz), time_s=plan.time_s[j])
            F = dynamics_matrix(lat, h, vel, c_bn, snap.f_b, snap.omega_ib_b, noise, ellipsoid)
            phi, q = discretise(F, gqg, dt)
            q[:3, :3] += play_noise(vel * dt, dt, play)
            cache[key] = (phi, q, snap, {})
        phi, q, snap, models = cache[key]
        updates = []
        for e in timeline.at(j):
            source = int(timeline.source[e])
            if source not in models:
                meas = timeline.measurements[source]
                models[source] = meas.model(replace(snap, time_s=meas.time_s[timeline.observation[e]]),
                                            int(timeline.observation[e]))[1:]
            updates.append(models[source])
        return phi, q, updates

    P0 = initial_covariance(profile, aiding, np.maximum(file_sigma, 0.005), 0.005, aiding.initial_sigma_level_rad,
                            aiding.initial_sigma_heading_rad if gnss is not None else FRAME_HEADING_SIGMA_RAD)
    # the evaluation counts the trolley as moving once it is 1 m from its start
    moving = plan.station_m > 1.0
    anchor_stations = np.arange(1.0, length_m, anchor_spacing_m)
    anchors = np.unique(np.searchsorted(plan.station_m, anchor_stations))
    profile_cov = analyse(P0, segment, plan.time_s, plan.station_m, np.full(m, heading), anchors,
                          (SHORT_LAG_M, LONG_LAG_M), smoother=aiding.smoother, progress=progress, cancel=cancel)
    forward = figures(profile_cov.forward, plan.time_s, moving, outages_s)
    smoothed = None if profile_cov.smoothed is None else figures(profile_cov.smoothed, plan.time_s, moving, outages_s)
    inputs = {"imu": profile.name, "gnss": gnss, "speed_mps": speed_mps, "length_m": length_m, "outages": tuple(outages),
              "stops": tuple(stops), "static_start_s": static_start_s, "static_end_s": static_end_s, "ramp_s": ramp_s}
    return Prediction(forward, smoothed, profile_cov, moving, tuple(outages_s), inputs)
