"""Start-up of the fusion filter: where the trolley is, how it is oriented and how well that is known.

One start for every IMU class (thesis 5.3.1.1 for the static case):

* **static start** (the survey begins with a stop of at least ``FusionOptions.min_static_s``):
  levelling from the mean specific force; the heading by gyrocompassing when the profile's gyro
  resolves the horizontal earth rate better than the track does (navigation grade: about
  0.05 deg), otherwise from the position track of the first motion after the stop (tactical and
  MEMS units; the stop's ZUPT/ZARU hold the heading until then);
* **moving start**: the attitude of the track over its first metres, the velocity along it;
* a heading given by the user (``FusionOptions.initial_heading_rad``) replaces both and skips
  the gyrocompass; at a moving start it also sets the direction of the initial velocity;
* with a **design alignment** (``design``: the track's azimuth at a position, from the project's
  design and CRS) the track's local azimuth at the start point is a heading candidate for a unit
  that cannot gyrocompass (:func:`finds_north`; the caller passes no design for one that can): the design says the line, the track chord which way along it
  the trolley faces (the candidate is used only when it agrees with the chord within three times
  their combined 1-sigma, else a notice says why not). Its 1-sigma: the trolley's yaw on the rails
  and the track's departure from its design (:data:`DESIGN_TRACK_SIGMA_RAD`), and the design's
  curvature times the start position's along-track 1-sigma.

The position track is the GNSS antenna's solution or, without GNSS (a tunnel), the total-station
prism fixes. Its heading at the start point is the direction of a chord from there, corrected
for the curvature the next chord of the same length shows (exact on a circle); its 1-sigma
combines the positions' noise over the chord with half the curvature correction (the part a
change of curvature can leave), and the chord length with the smallest 1-sigma is used: short
chords on tight curves, long ones on straights. The trolley's heading from it adds the trolley's
yaw against the chord (:data:`TROLLEY_YAW_SIGMA_RAD`).

A **known start** (:class:`KnownStart`: the design's point, azimuth, grade and cant at the station the
survey starts on, thesis 5.3.1.1) starts the filter at the first IMU record without any position: at
a static start the tilt is levelled and the heading gyrocompassed where the unit finds north, else
the design's azimuth is taken; at a moving start the whole attitude is the design's and the
velocity the odometer's along it. GNSS or prism fixes arriving later aid it from their first epoch.

A trolley pushed with its IMU x axis against the direction of travel is recognised at a static
start by the sign of the IMU's forward velocity change when it sets off.

Frames: n = NED, b = IMU body FRD, v = trolley frame (x forward, ``C_b^v`` from the mounting
angles); angles in radians.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from insrail.io.types import GnssSolution, ImuIncrements, OdometerData
from insrail.nav import _kernels, earth
from insrail.nav.alignment import gravity_tolerance_mps2, gyrocompass, gyrocompass_sigma_rad, static_levelling
from insrail.nav.mechanization import q_ne_from_lat_lon
from insrail.nav.rotation import (
    dcm_to_euler,
    dcm_to_quat,
    euler_to_dcm,
    quat_multiply,
    quat_to_dcm,
    rotvec_to_quat,
)
from insrail.notices import Notice, Phrase

#: chord lengths [m] tried for the track heading
CHORDS_M = (0.5, 1.0, 2.0, 3.0, 5.0, 10.0, 20.0, 40.0)
#: 1-sigma of the heading of a chord of length L from positions of horizontal 1-sigma s, after
#: the curvature correction 1.5 psi1 - 0.5 psi2 (three points with independent noise)
_CHORD_NOISE_FACTOR = 2.6
#: speed [m/s] above which the trolley counts as moving at the start
MIN_START_SPEED_MPS = 0.2
#: a gyrocompass heading is used when its 1-sigma is below this, or below the track's
MAX_GYROCOMPASS_SIGMA_RAD = math.radians(0.5)
#: the tightest curve [m] assumed where the track shows only one chord (sparse prism fixes)
MIN_RADIUS_M = 150.0
#: the smallest 1-sigma [m] of the start position
MIN_START_SIGMA_M = 0.005


#: 1-sigma [rad] of a trolley's heading against the direction of a chord of its track: its yaw between
#: the rails (a few mm of play over its length) and the track's own bends under the chord (mm over tens
#: of metres); the chord's noise (:func:`track_heading`) says nothing of either. A tactical unit
#: started 0.07 deg off a 60 m prism chord told good to 0.01 deg rejects the next fix 60 m on.
TROLLEY_YAW_SIGMA_RAD = math.radians(0.1)
#: 1-sigma [rad] of a trolley's heading against its design's local azimuth: its yaw between the
#: rails (a few mm of play over its length) and the track's departure from the design (mm per m)
DESIGN_TRACK_SIGMA_RAD = math.radians(0.1)
#: farther [m] from the design than this, the trolley is not on that line
DESIGN_MAX_OFFSET_M = 5.0


@dataclass(frozen=True)
class DesignAzimuth:
    """The design's local azimuth at the start: ``heading_rad`` (true north, towards increasing
    stationing), its ``sigma_rad``, the station and offset of the start point."""

    heading_rad: float
    sigma_rad: float
    station_m: float
    offset_m: float


def finds_north(profile, static_s: float) -> bool:
    """Whether the profile's gyros gyrocompass to :data:`MAX_GYROCOMPASS_SIGMA_RAD` over a stop of
    ``static_s`` (at the equator, where it is easiest): such a unit never needs the design's azimuth."""
    bias = math.hypot(profile.gyro_bias_turn_on, profile.gyro_bias_gm_sigma)
    return gyrocompass_sigma_rad(bias, profile.gyro_arw, static_s, 0.0) <= MAX_GYROCOMPASS_SIGMA_RAD


def design_heading(design, lat_rad: float, lon_rad: float, sigma_along_m: float) -> DesignAzimuth | None:
    """The design candidate at a position (None without a design, or off it). ``design(lat, lon)``
    returns (true azimuth [rad] towards increasing stationing, curvature [1/m], station [m], offset
    [m]) or None where the position has no foot on the design."""
    if design is None:
        return None
    found = design(float(lat_rad), float(lon_rad))
    if found is None:
        return None
    azimuth, curvature, station, offset = (float(v) for v in found)
    if not (math.isfinite(azimuth) and abs(offset) <= DESIGN_MAX_OFFSET_M):
        return None
    return DesignAzimuth(azimuth, math.hypot(DESIGN_TRACK_SIGMA_RAD, curvature * sigma_along_m), station, offset)


def _on_design(candidate: DesignAzimuth, heading_rad: float, sigma_rad: float, what: Phrase, notices: list,
               time_s: float) -> tuple[float, float] | None:
    """(heading, 1-sigma) of the design candidate turned to the direction of ``heading_rad`` (the
    track chord's, of 1-sigma ``sigma_rad``), when it agrees with it and is the better; None otherwise
    (a notice when it disagrees)."""
    turned = candidate.heading_rad + (math.pi if abs(_wrap(heading_rad - candidate.heading_rad)) > math.pi / 2 else 0.0)
    apart = abs(float(_wrap(heading_rad - turned)))
    limit = 3.0 * math.hypot(sigma_rad, candidate.sigma_rad)
    if apart > limit:
        notices.append(Notice("fusion", "the design's azimuth at the start (station {station_m:.1f} m, {offset_m:+.2f} m "
                              "off it) is {apart_deg:.2f} deg from the {what}, more than 3 x their 1-sigma ({limit_deg:.2f} "
                              "deg): not used for the start", time_s=time_s,
                              fields={"station_m": candidate.station_m, "offset_m": candidate.offset_m,
                                      "apart_deg": math.degrees(apart), "what": what, "limit_deg": math.degrees(limit)}))
        return None
    if candidate.sigma_rad >= sigma_rad:
        return None
    return float(_wrap(turned)), candidate.sigma_rad


@dataclass(frozen=True)
class KnownStart:
    """The trolley's place and attitude at the start without a position fix: a point on the trolley
    (``lever_arm_m`` from the IMU, b frame) at ``lat_rad, lon_rad, height_m`` with 1-sigma
    ``sigma_ned_m``; the trolley frame v's roll, pitch and heading [rad] there with their 1-sigma;
    ``source`` for messages ("the design at station 1020.000 m")."""

    lat_rad: float
    lon_rad: float
    height_m: float
    lever_arm_m: np.ndarray
    sigma_ned_m: np.ndarray
    rpy_v_rad: tuple[float, float, float]
    sigma_level_rad: float
    sigma_heading_rad: float
    source: Phrase


@dataclass(frozen=True)
class PositionTrack:
    """Known positions of one point on the trolley over time: the GNSS antenna's solution or the
    total-station prism fixes. ``lever_arm_m``: from the IMU to that point, b frame [m]."""

    time_s: np.ndarray
    lat_rad: np.ndarray
    lon_rad: np.ndarray
    height_m: np.ndarray
    sigma_ned_m: np.ndarray  # (n, 3)
    lever_arm_m: np.ndarray
    source: Phrase  # "GNSS" or "prism fixes", for messages

    @classmethod
    def from_gnss(cls, gnss: GnssSolution, lever_arm_m: np.ndarray) -> PositionTrack:
        return cls(gnss.time_s, gnss.lat_rad, gnss.lon_rad, gnss.height_m, gnss.sigma_ned_m,
                   np.asarray(lever_arm_m, dtype=float), Phrase("GNSS"))

    @classmethod
    def from_fixes(cls, fixes) -> PositionTrack:
        """From :class:`insrail.nav.measurements.PositionFix` (isotropic 1-sigma per fix)."""
        sigma = np.repeat(np.asarray(fixes.sigma_m, dtype=float)[:, None], 3, axis=1)
        return cls(np.asarray(fixes.time_s), np.asarray(fixes.lat), np.asarray(fixes.lon), np.asarray(fixes.h), sigma,
                   np.asarray(fixes.lever_arm_m, dtype=float), Phrase("prism fixes"))

    def __len__(self) -> int:
        return len(self.time_s)

    def within(self, t0: float, t1: float) -> PositionTrack:
        keep = (self.time_s > t0) & (self.time_s <= t1)
        return PositionTrack(self.time_s[keep], self.lat_rad[keep], self.lon_rad[keep], self.height_m[keep],
                             self.sigma_ned_m[keep], self.lever_arm_m, self.source)

    def local_ned(self, ell: earth.Ellipsoid) -> np.ndarray:
        """(n, 3) NED metres relative to the first position (flat: a start-up needs metres)."""
        lat0, lon0, h0 = self.lat_rad[0], self.lon_rad[0], self.height_m[0]
        r_m, r_n = earth.radii(lat0, ell)
        return np.column_stack([(self.lat_rad - lat0) * (r_m + h0), (self.lon_rad - lon0) * (r_n + h0) * np.cos(lat0),
                                -(self.height_m - h0)])

    def horizontal_sigma_m(self) -> np.ndarray:
        return np.hypot(self.sigma_ned_m[:, 0], self.sigma_ned_m[:, 1]) / math.sqrt(2.0)


@dataclass(frozen=True)
class TrackHeading:
    """Direction of the track at one of its epochs: heading and pitch of the travel direction."""

    index: int  # epoch of the track the direction holds at
    heading_rad: float
    pitch_rad: float
    sigma_heading_rad: float
    chord_m: float


def _wrap(angle):
    return (angle + np.pi) % (2.0 * np.pi) - np.pi


def track_heading(ned: np.ndarray, sigma_h_m: np.ndarray, i0: int) -> TrackHeading | None:
    """The travel direction at track epoch ``i0`` from the positions after it (see the module
    docstring); None when the track never gets two chords of the shortest length away."""
    p = ned[i0:]
    best = None
    for chord in CHORDS_M:
        d1 = np.hypot(*(p[:, :2] - p[0, :2]).T)
        far1 = np.flatnonzero(d1 >= chord)
        if far1.size == 0:
            break
        j1 = int(far1[0])
        psi1 = math.atan2(p[j1, 1] - p[0, 1], p[j1, 0] - p[0, 0])
        d2 = np.hypot(*(p[j1:, :2] - p[j1, :2]).T)
        far2 = np.flatnonzero(d2 >= chord)
        if far2.size:
            j2 = j1 + int(far2[0])
            psi2 = math.atan2(p[j2, 1] - p[j1, 1], p[j2, 0] - p[j1, 0])
            bend = float(_wrap(psi2 - psi1))
            noise = _CHORD_NOISE_FACTOR * float(np.max(sigma_h_m[[i0, i0 + j1, i0 + j2]])) / d1[j1]
            sigma = math.hypot(noise, 0.25 * abs(bend))
        elif best is None:  # one chord only (sparse prism fixes): the curvature is not seen, assume the tightest
            bend = 0.0
            noise = math.sqrt(2.0) * float(np.max(sigma_h_m[[i0, i0 + j1]])) / d1[j1]
            sigma = math.hypot(noise, d1[j1] / (2.0 * MIN_RADIUS_M))
        else:
            break
        if best is None or sigma < best.sigma_heading_rad:
            pitch = math.atan2(-(p[j1, 2] - p[0, 2]), d1[j1])
            best = TrackHeading(i0, float(_wrap(psi1 - 0.5 * bend)), pitch, sigma, chord)
    return best


#: window [s] of the in-motion (velocity-matching) alignment
MATCHING_WINDOW_S = 10.0
#: the residuals of the velocity matching are correlated in time (integrated noise): their
#: formal 1-sigma is inflated by this factor
_MATCHING_SIGMA_FACTOR = 3.0


@dataclass(frozen=True)
class MatchedAttitude:
    """Attitude of b at the start of a window in motion, from velocity matching."""

    rpy_rad: tuple[float, float, float]
    sigma_heading_rad: float
    window_s: float


def velocity_matching(imu: ImuIncrements, track: PositionTrack, ned: np.ndarray, i0: int, ell: earth.Ellipsoid,
                      window_s: float = MATCHING_WINDOW_S) -> MatchedAttitude | None:
    """The attitude of b at track epoch ``i0`` that best carries the IMU's velocity increments
    onto the track's velocity changes over the next ``window_s`` (in-motion alignment, Wahba's
    problem solved by SVD): with the gyros integrated from b0, ``v(t) - v(t0) - g (t - t0) =
    C_b0^n sum C_bk^b0 dv_k``. Gravity fixes the tilt, the trolley's (or walker's) horizontal
    accelerations and turns fix the heading, whichever way the IMU points; on a straight at
    constant speed they are weak and the 1-sigma says so. Earth rate and Coriolis (below
    1e-4 m/s^2 at walking speed) are left out. None when the window holds too few epochs."""
    t0 = float(track.time_s[i0])
    t1 = min(t0 + window_s, float(track.time_s[-1]) - 0.5)
    epochs = np.flatnonzero((track.time_s > t0 + 0.5) & (track.time_s <= t1))
    if epochs.size < 8:
        return None
    k0, k1 = np.searchsorted(imu.time_s, [t0, t1 + 0.01])
    theta, dvel = imu.dtheta_rad[k0:k1], imu.dvel_mps[k0:k1]
    # C_bk^b0 by quaternion integration (startup only: one Python loop over a few thousand records)
    q = np.array([1.0, 0.0, 0.0, 0.0])
    step_q = rotvec_to_quat(theta)
    dv_b0 = np.empty_like(dvel)
    for k in range(len(theta)):
        rotated = quat_multiply(q, step_q[k])  # C_bk^b0 after the record's rotation
        # the velocity increment over the record in b0, at the mid-rotation (first order)
        dv_b0[k] = 0.5 * (quat_to_dcm(q) + quat_to_dcm(rotated)) @ dvel[k]
        q = rotated / np.linalg.norm(rotated)
    cumulative = np.cumsum(dv_b0, axis=0)
    stamps = imu.time_s[k0:k1]
    v0 = _track_velocity(track, ned, t0)
    gravity = np.array([0.0, 0.0, float(earth.normal_gravity(track.lat_rad[i0], track.height_m[i0], ell))])
    alpha, beta = [], []
    for j in epochs:
        tj = float(track.time_s[j])
        m = int(np.searchsorted(stamps, tj))
        if m == 0 or m > len(stamps):
            continue
        alpha.append(cumulative[m - 1])
        beta.append(_track_velocity(track, ned, tj) - v0 - gravity * (stamps[m - 1] - stamps[0] + (stamps[0] - t0)))
    if len(alpha) < 8:
        return None
    alpha, beta = np.array(alpha), np.array(beta)
    u, _, vt = np.linalg.svd(beta.T @ alpha)
    c_bn = u @ np.diag([1.0, 1.0, np.linalg.det(u) * np.linalg.det(vt)]) @ vt
    roll, pitch, heading = (float(a) for a in dcm_to_euler(c_bn))
    # heading 1-sigma: horizontal residuals across the rotated increments' horizontal spread
    rotated = alpha @ c_bn.T
    residual = beta - rotated
    lever = np.hypot(rotated[:, 0], rotated[:, 1])
    spread = float(np.sum(lever**2))
    if spread <= 0.0:
        return None
    sigma_r = float(np.sqrt(np.sum(residual[:, :2] ** 2) / max(2 * len(alpha) - 3, 1)))
    sigma = min(_MATCHING_SIGMA_FACTOR * sigma_r / math.sqrt(spread), math.pi)
    return MatchedAttitude((roll, pitch, heading), sigma, t1 - t0)


def first_motion(track: PositionTrack, ned: np.ndarray, after_s: float, odometer: OdometerData | None) -> int | None:
    """Index of the first track epoch after ``after_s`` from which the trolley moves faster than
    :data:`MIN_START_SPEED_MPS`: by the odometer over one second, or without one by the track
    over the next second beyond three times its noise. None if it never does."""
    t = track.time_s
    if odometer is not None:
        d_ahead = np.interp(t + 0.5, odometer.time_s, odometer.distance_m)
        d_behind = np.interp(t - 0.5, odometer.time_s, odometer.distance_m)
        moving = np.abs(d_ahead - d_behind) > MIN_START_SPEED_MPS
    else:
        ahead = np.column_stack([np.interp(t + 1.0, t, ned[:, a]) for a in range(2)])
        step = np.hypot(*(ahead - ned[:, :2]).T)
        noise = 3.0 * math.sqrt(2.0) * track.horizontal_sigma_m()
        moving = (step > np.maximum(MIN_START_SPEED_MPS, noise)) & (t + 1.0 <= t[-1])
    found = np.flatnonzero(moving & (t >= after_s))
    return int(found[0]) if found.size else None


def _speed_at(track: PositionTrack, ned: np.ndarray, i: int, odometer: OdometerData | None) -> float:
    """Speed [m/s] at track epoch i: odometer over +-0.5 s, else the track over the next second."""
    t = track.time_s[i]
    if odometer is not None:
        return float(abs(np.diff(np.interp([t - 0.5, t + 0.5], odometer.time_s, odometer.distance_m))[0]))
    ahead = np.array([np.interp(t + 1.0, track.time_s, ned[:, a]) for a in range(3)])
    return float(np.linalg.norm(ahead - ned[i]))


@dataclass(frozen=True)
class Start:
    """Initial state of the filter: IMU epoch, navigation vector and its 1-sigma."""

    epoch: int
    nav: np.ndarray
    method: str  # "static" (levelling + gyrocompass), "static+track", "static+design", "static+given", "track",
    # "design", "matched", "given"
    rpy_rad: tuple[float, float, float]
    sigma_pos_ned_m: np.ndarray
    sigma_vel_mps: float
    sigma_level_rad: float
    sigma_heading_rad: float
    notices: tuple[Notice, ...] = ()
    #: a static start's (lat [rad], h [m], C_b^n): its level angles hold the horizontal accelerometer
    #: errors (insrail.nav.fusion.initial_covariance); None at a moving start
    levelled_at: tuple[float, float, np.ndarray] | None = None
    #: C_b^n l of the point whose position started the filter (the antenna, the prism): the IMU's start
    #: position is that position less the lever turned by the start attitude, so its error holds the
    #: attitude's through the lever (insrail.nav.fusion.initial_covariance); None: no lever
    position_lever_ned_m: np.ndarray | None = None


class StartupError(ValueError):
    """The filter cannot be started: the message says why and what to give instead."""


def initial_state(imu: ImuIncrements, track: PositionTrack, stops, odometer: OdometerData | None, c_vb: np.ndarray,
                  profile, options, ell: earth.Ellipsoid, design=None, known: KnownStart | None = None) -> Start:
    """The filter's start (see the module docstring). ``track``: the positions inside the IMU
    span; ``options``: :class:`insrail.nav.fusion.FusionOptions`; ``design``: see
    :func:`design_heading`; ``known``: a :class:`KnownStart`, which then gives the start (the track
    aids the filter only). Raises :class:`StartupError`."""
    if known is not None:
        return _known_start(imu, known, stops, odometer, c_vb, profile, options, ell)
    t = imu.time_s
    ned = track.local_ned(ell)
    sigma_h = track.horizontal_sigma_m()
    given = options.initial_heading_rad
    notices: list[Notice] = []
    static = stops[0] if stops and stops[0][0] <= t[0] + 5.0 else None
    if static is not None and static[1] - static[0] >= options.min_static_s and track.time_s[0] <= static[1]:
        i0 = 0
        roll, pitch, _, w = static_levelling(imu, 1, int(np.searchsorted(t, static[1])), gravity_tolerance_mps2(profile))
        mounting = np.eye(3)  # the static alignment gives the attitude of b itself
        vel, sigma_vel, sigma_level = np.zeros(3), 0.005, options.initial_sigma_level_rad
        if given is not None:
            method, heading, sigma_heading = "static+given", given, options.initial_sigma_heading_rad
        else:
            method, heading, sigma_heading = _static_heading(imu, track, ned, sigma_h, static, roll, pitch, w,
                                                             odometer, c_vb, profile, options, ell, notices, design)
    else:
        i0 = first_motion(track, ned, -math.inf, odometer)
        if i0 is None:
            raise StartupError(
                f"the survey neither starts with a stop of {options.min_static_s:g} s (for a static alignment) nor "
                f"moves faster than {MIN_START_SPEED_MPS} m/s by the {'odometer' if odometer is not None else track.source}; "
                "nothing to align on - check the files, or give the initial heading (--heading)")
        direction = track_heading(ned, sigma_h, i0)
        matched = velocity_matching(imu, track, ned, i0, ell) if given is None else None
        if direction is None and matched is None and given is None:
            raise StartupError(
                f"track alignment: the {track.source} track never leaves a {2 * CHORDS_M[0]:g} m circle after "
                f"t = {track.time_s[i0]:.3f} s; give the initial heading (--heading)")
        mounting = c_vb  # the track gives the attitude of the trolley frame v
        if given is not None:
            method, heading, sigma_heading = "given", given, options.initial_sigma_heading_rad
            roll, pitch = _moving_levelling(imu, track, ned, i0, heading, c_vb)
        elif matched is not None and (direction is None or matched.sigma_heading_rad < direction.sigma_heading_rad):
            method, sigma_heading = "matched", matched.sigma_heading_rad
            roll, pitch, heading = matched.rpy_rad
            mounting = np.eye(3)  # velocity matching gives the attitude of b itself
            notices.append(Notice("fusion", "moving start: initial attitude by matching the IMU to the {source} velocities "
                                  "over {window_s:.0f} s, heading {heading_deg:.2f} deg (1-sigma {sigma_deg:.2f} deg)",
                                  time_s=float(track.time_s[i0]), severity="info",
                                  fields={"source": track.source, "window_s": matched.window_s,
                                          "heading_deg": math.degrees(heading) % 360,
                                          "sigma_deg": math.degrees(sigma_heading)}))
        else:
            method, heading = "track", direction.heading_rad
            sigma_heading = math.hypot(direction.sigma_heading_rad, TROLLEY_YAW_SIGMA_RAD)
            candidate = design_heading(design, track.lat_rad[i0], track.lon_rad[i0], float(sigma_h[i0]))
            on_design = None if candidate is None else _on_design(
                candidate, heading, sigma_heading, Phrase("{source} track's chord", {"source": track.source}), notices,
                float(track.time_s[i0]))
            if on_design is not None:
                method, (heading, sigma_heading) = "design", on_design
            roll, pitch = _moving_levelling(imu, track, ned, i0, heading, c_vb)
            where = (Phrase("the design's azimuth at station {station_m:.1f} m, the direction from the {source} track",
                            {"station_m": candidate.station_m, "source": track.source}) if on_design is not None else
                     Phrase("the {source} track over {chord_m:g} m chords",
                            {"source": track.source, "chord_m": direction.chord_m}))
            notices.append(Notice("fusion", "moving start: initial heading {heading_deg:.2f} deg from {where} (1-sigma "
                                  "{sigma_deg:.2f} deg)", time_s=float(track.time_s[i0]), severity="info",
                                  fields={"heading_deg": math.degrees(heading) % 360, "where": where,
                                          "sigma_deg": math.degrees(sigma_heading)}))
        t_start = float(track.time_s[i0])
        if odometer is not None:  # a trolley on rails: the odometer's speed along the travel direction
            speed = _speed_at(track, ned, i0, odometer)
            travel = heading if mounting is c_vb else math.atan2(*_track_velocity(track, ned, t_start)[1::-1])
            vel = speed * np.array([np.cos(travel) * np.cos(pitch), np.sin(travel) * np.cos(pitch), -np.sin(pitch)])
            sigma_vel = 0.05
        else:  # the track's own velocity; its change over a second (acceleration) counts as uncertainty
            vel = _track_velocity(track, ned, t_start)
            change = _track_velocity(track, ned, t_start + 0.5) - _track_velocity(track, ned, t_start - 0.5)
            noise = 2.0 * float(sigma_h[i0])  # a difference of two positions one second apart
            sigma_vel = max(0.05, 0.5 * float(np.linalg.norm(change)), noise)
        sigma_level = math.radians(0.5)
    c_bn = euler_to_dcm(roll, pitch, heading) @ mounting
    lat0, lon0, h0 = track.lat_rad[i0], track.lon_rad[i0], track.height_m[i0]
    d_lat, d_lon, d_h = earth.ned_to_geodetic_delta(c_bn @ track.lever_arm_m, lat0, h0, ell)
    nav = np.zeros(_kernels.NAV_SIZE)
    nav[0:4] = q_ne_from_lat_lon(lat0 - d_lat, lon0 - d_lon)
    nav[4] = h0 - d_h
    nav[5:8] = vel
    nav[8:12] = dcm_to_quat(c_bn)
    return Start(epoch=int(np.searchsorted(t, track.time_s[i0])), nav=nav, method=method,
                 rpy_rad=(float(roll), float(pitch), float(heading)),
                 sigma_pos_ned_m=np.maximum(track.sigma_ned_m[i0], MIN_START_SIGMA_M), sigma_vel_mps=sigma_vel,
                 sigma_level_rad=sigma_level, sigma_heading_rad=float(sigma_heading), notices=tuple(notices),
                 levelled_at=(float(lat0 - d_lat), float(h0 - d_h), c_bn) if method.startswith("static") else None,
                 position_lever_ned_m=c_bn @ np.asarray(track.lever_arm_m, dtype=float))


def _sigmas(known: KnownStart) -> Phrase:
    """The known start's position 1-sigma, for its notice."""
    horizontal, vertical = float(known.sigma_ned_m[0]), float(known.sigma_ned_m[2])
    return (Phrase("1-sigma {sigma_m:.3f} m", {"sigma_m": horizontal}) if vertical == horizontal else
            Phrase("1-sigma {sigma_m:.3f} m horizontal, {vertical_m:g} m in height",
                   {"sigma_m": horizontal, "vertical_m": vertical}))


def _known_start(imu: ImuIncrements, known: KnownStart, stops, odometer: OdometerData | None, c_vb: np.ndarray,
                 profile, options, ell: earth.Ellipsoid) -> Start:
    """The start on a :class:`KnownStart` at the first IMU record (see the module docstring)."""
    t = imu.time_s
    roll_v, pitch_v, heading_v = known.rpy_v_rad
    static = stops[0] if stops and stops[0][0] <= t[0] + 5.0 else None
    notices = []
    if static is not None and static[1] - static[0] >= options.min_static_s:
        roll, pitch, _, w = static_levelling(imu, 1, int(np.searchsorted(t, static[1])), gravity_tolerance_mps2(profile))
        sigma_compass = gyrocompass_sigma_rad(math.hypot(profile.gyro_bias_turn_on, profile.gyro_bias_gm_sigma),
                                              profile.gyro_arw, static[1] - static[0], known.lat_rad, ell)
        compass = None
        if options.initial_heading_rad is None and sigma_compass < min(known.sigma_heading_rad, MAX_GYROCOMPASS_SIGMA_RAD):
            try:
                compass = gyrocompass(roll, pitch, w, known.lat_rad, ell)
            except ValueError:
                compass = None
        if options.initial_heading_rad is not None:
            method, heading, sigma_heading, how = ("static+given", options.initial_heading_rad,
                                                   options.initial_sigma_heading_rad, Phrase("as given"))
        elif compass is not None:
            method, heading, sigma_heading, how = "static+known", compass, sigma_compass, Phrase("by gyrocompassing")
        else:  # the heading of b whose trolley x axis has the design's azimuth (b turned from v about the vertical)
            c_bn = euler_to_dcm(0.0, 0.0, heading_v) @ c_vb
            method, heading, sigma_heading = "static+known", float(np.arctan2(c_bn[1, 0], c_bn[0, 0])), known.sigma_heading_rad
            how = Phrase("from {source}", {"source": known.source})
        c_bn = euler_to_dcm(roll, pitch, heading)
        vel, sigma_vel, sigma_level = np.zeros(3), 0.005, options.initial_sigma_level_rad
        notices.append(Notice("fusion", "static start on {source}: position from the design ({sigmas}), heading "
                              "{heading_deg:.2f} deg {how} (1-sigma {sigma_deg:.2f} deg)", time_s=float(t[0]), severity="info",
                              fields={"source": known.source, "sigmas": _sigmas(known),
                                      "heading_deg": math.degrees(heading) % 360, "how": how,
                                      "sigma_deg": math.degrees(sigma_heading)}))
    else:
        if odometer is None:
            raise StartupError(f"a moving start on {known.source} needs the odometer's speed (survey.toml "
                               "[files.odometer]) or a static start")
        roll, pitch, heading = roll_v, pitch_v, heading_v
        c_bn = euler_to_dcm(roll_v, pitch_v, heading_v) @ c_vb
        # along the trolley's x axis, signed as the odometer counts (backwards decreases)
        speed = float(np.interp(t[0] + 1.0, odometer.time_s, odometer.distance_m)
                      - np.interp(t[0], odometer.time_s, odometer.distance_m))
        vel = speed * euler_to_dcm(roll_v, pitch_v, heading_v)[:, 0]
        method, sigma_heading, sigma_vel, sigma_level = "known", known.sigma_heading_rad, 0.05, known.sigma_level_rad
        notices.append(Notice("fusion", "moving start on {source}: position and attitude from the design ({sigmas}, "
                              "{level_deg:.2f} deg level, {heading_deg:.2f} deg heading), speed {speed_mps:+.2f} m/s from "
                              "the odometer", time_s=float(t[0]), severity="info",
                              fields={"source": known.source, "sigmas": _sigmas(known),
                                      "level_deg": math.degrees(sigma_level), "heading_deg": math.degrees(sigma_heading),
                                      "speed_mps": speed}))
    d_lat, d_lon, d_h = earth.ned_to_geodetic_delta(c_bn @ np.asarray(known.lever_arm_m, float), known.lat_rad,
                                                    known.height_m, ell)
    nav = np.zeros(_kernels.NAV_SIZE)
    lat0, h0 = known.lat_rad - d_lat, known.height_m - d_h
    nav[0:4] = q_ne_from_lat_lon(lat0, known.lon_rad - d_lon)
    nav[4] = h0
    nav[5:8] = vel
    nav[8:12] = dcm_to_quat(c_bn)
    rpy = dcm_to_euler(c_bn)
    return Start(epoch=0, nav=nav, method=method, rpy_rad=(float(rpy[0]), float(rpy[1]), float(rpy[2])),
                 sigma_pos_ned_m=np.maximum(np.asarray(known.sigma_ned_m, float), MIN_START_SIGMA_M),
                 sigma_vel_mps=sigma_vel, sigma_level_rad=sigma_level, sigma_heading_rad=float(sigma_heading),
                 notices=tuple(notices), levelled_at=(float(lat0), float(h0), c_bn) if method.startswith("static") else None)


#: the window [s] over which the attitude of a moving start is levelled
LEVELLING_WINDOW_S = 2.0


def _track_velocity(track: PositionTrack, ned: np.ndarray, time_s: float) -> np.ndarray:
    """NED velocity [m/s] of the track around ``time_s`` (central difference over one second)."""
    a, b = time_s - 0.5, time_s + 0.5
    return np.array([np.interp(b, track.time_s, ned[:, k]) - np.interp(a, track.time_s, ned[:, k]) for k in range(3)])


def _moving_levelling(imu, track, ned, i0, heading_v, c_vb) -> tuple[float, float]:
    """Roll and pitch of the trolley frame v at a moving start: the mean specific force over the
    first :data:`LEVELLING_WINDOW_S` less the acceleration the track shows over the same window
    (a chord's pitch from noisy heights would be worse, a specific force with the trolley's
    acceleration in it tilted by a / g)."""
    t0 = float(track.time_s[i0])
    t1 = min(t0 + LEVELLING_WINDOW_S, float(track.time_s[-1]))
    k0, k1 = np.searchsorted(imu.time_s, [t0, t1])
    k1 = max(k1, k0 + 10)
    span = float(imu.time_s[min(k1, len(imu) - 1)] - imu.time_s[k0]) or 1.0
    f_v = c_vb @ (imu.dvel_mps[k0:k1].sum(axis=0) / span)
    accel_ned = (_track_velocity(track, ned, t1) - _track_velocity(track, ned, t0)) / max(t1 - t0, 1e-3)
    accel_level = euler_to_dcm(0.0, 0.0, heading_v).T @ accel_ned
    gravity_part = f_v - accel_level  # f = a - g: what is left is the reaction to gravity, tilted
    roll = float(np.arctan2(-gravity_part[1], -gravity_part[2]))
    pitch = float(np.arctan2(gravity_part[0], np.hypot(gravity_part[1], gravity_part[2])))
    return roll, pitch


def _static_heading(imu, track, ned, sigma_h, static, roll, pitch, w, odometer, c_vb, profile, options, ell, notices,
                    design=None):
    """(method, heading of b, 1-sigma) at a static start: gyrocompass or the track of the first motion."""
    lat = float(track.lat_rad[0])
    gyro_bias = math.hypot(profile.gyro_bias_turn_on, profile.gyro_bias_gm_sigma)
    sigma_compass = gyrocompass_sigma_rad(gyro_bias, profile.gyro_arw, static[1] - static[0], lat, ell)
    compass, why = None, ""
    if sigma_compass < math.pi:
        try:
            compass = gyrocompass(roll, pitch, w, lat, ell)
        except ValueError as err:
            why = str(err)
    else:
        why = Phrase("a {profile} gyro does not resolve the earth rate", {"profile": profile.name})
    if compass is not None and sigma_compass <= MAX_GYROCOMPASS_SIGMA_RAD:
        return "static", compass, max(options.initial_sigma_heading_rad, sigma_compass)
    moving = first_motion(track, ned, static[1], odometer)
    if moving is None and track.time_s[-1] > static[1]:
        # every fix taken at rest (prism fixes at stops): the chord from the last one of the static start
        moving = max(int(np.searchsorted(track.time_s, static[1], side="right")), 1)
    direction = None
    if moving is not None:
        direction = track_heading(ned, sigma_h, max(moving - 1, 0))
    if direction is None or (compass is not None and sigma_compass <= direction.sigma_heading_rad):
        if compass is not None:
            return "static", compass, max(options.initial_sigma_heading_rad, sigma_compass)
        raise StartupError(
            f"static alignment: {why}, and the {track.source} track after the stop does not give a heading "
            "(the trolley never moves far enough); give the initial heading (--heading)")
    # The track's direction is that of the trolley frame v, forward or backward.
    backward = _sets_off_backwards(imu, track, ned, moving, roll, pitch, c_vb, ell)
    heading_v, source = direction.heading_rad + (math.pi if backward else 0.0), None
    sigma_v = math.hypot(direction.sigma_heading_rad, TROLLEY_YAW_SIGMA_RAD)
    candidate = design_heading(design, track.lat_rad[0], track.lon_rad[0], float(sigma_h[0]))
    on_design = None if candidate is None else _on_design(
        candidate, heading_v, sigma_v, Phrase("{source} track of the first motion", {"source": track.source}), notices,
        float(track.time_s[moving]))
    if on_design is not None and not (compass is not None and sigma_compass <= on_design[1]):
        (heading_v, sigma_v), source = on_design, candidate
    # heading of b: the mounting rotates b against v about (nearly) the vertical
    c_bn = euler_to_dcm(0.0, 0.0, heading_v) @ c_vb
    heading_b = float(np.arctan2(c_bn[1, 0], c_bn[0, 0]))
    reason = why or Phrase("gyrocompass 1-sigma {sigma_deg:.1f} deg with the {profile} profile",
                           {"sigma_deg": math.degrees(sigma_compass), "profile": profile.name})
    where = (Phrase("the design's azimuth at station {station_m:.1f} m, the direction from the {source} track of the "
                    "first motion", {"station_m": source.station_m, "source": track.source}) if source else
             Phrase("the {source} track of the first motion over {chord_m:g} m chords",
                    {"source": track.source, "chord_m": direction.chord_m}))
    notices.append(Notice(
        "fusion", "static start: heading {heading_deg:.2f} deg from {where} (1-sigma {sigma_deg:.2f} deg), not by "
        "gyrocompassing ({reason}){backwards}", time_s=float(track.time_s[moving]), severity="info",
        fields={"heading_deg": math.degrees(heading_b) % 360, "where": where, "sigma_deg": math.degrees(sigma_v),
                "reason": reason, "backwards": Phrase("; the trolley set off backwards" if backward else "")}))
    return ("static+design" if source else "static+track"), heading_b, sigma_v


def _sets_off_backwards(imu, track, ned, moving, roll, pitch, c_vb, ell) -> bool:
    """Whether the IMU's forward (v-frame x) velocity change over the first two seconds of motion
    opposes the track's: the trolley is pushed with its x axis against the travel direction."""
    t0 = track.time_s[max(moving - 1, 0)]
    k0, k1 = np.searchsorted(imu.time_s, [t0, t0 + 2.0])
    if k1 - k0 < 10:
        return False
    c_bl = euler_to_dcm(roll, pitch, 0.0)  # b to the level frame at the start heading
    span = imu.time_s[k1 - 1] - imu.time_s[k0]
    gravity = earth.normal_gravity(track.lat_rad[0], track.height_m[0], ell)
    dv_level = c_bl @ imu.dvel_mps[k0:k1].sum(axis=0) + np.array([0.0, 0.0, gravity * span])
    dv_forward = float((c_bl @ c_vb.T @ np.array([1.0, 0.0, 0.0])) @ dv_level)
    ahead = np.array([np.interp(t0 + 2.0, track.time_s, ned[:, a]) for a in range(2)])
    speed = float(np.hypot(*(ahead - ned[max(moving - 1, 0), :2]))) / 2.0
    return dv_forward < -0.5 * speed


def heading_at_reset(nav: np.ndarray, track: PositionTrack, time_s: float, c_vb: np.ndarray,
                     ell: earth.Ellipsoid) -> tuple[float, float] | None:
    """For a filter reset at ``time_s``: the yaw [rad] to turn the lost filter's attitude by (about
    the n frame's down axis) so its trolley heading is the track's travel direction there (the
    chord of :func:`track_heading`, as the moving start takes it; forwards or backwards, whichever
    is nearer the filter's), and that heading's 1-sigma. ``nav`` is the strapdown's navigation
    vector (attitude quaternion q_bn at NAV_Q_BN). None when the track gives no chord from there."""
    i0 = int(np.searchsorted(track.time_s, time_s))
    if i0 >= len(track) - 1:
        return None
    found = track_heading(track.local_ned(ell), track.horizontal_sigma_m(), i0)
    if found is None:
        return None
    q = nav[_kernels.NAV_Q_BN : _kernels.NAV_Q_BN + 4]
    forward_n = quat_to_dcm(q) @ c_vb.T[:, 0]
    filter_heading = math.atan2(forward_n[1], forward_n[0])
    turn = float(_wrap(found.heading_rad - filter_heading))
    if abs(turn) > 0.5 * math.pi:  # the trolley runs backwards along the track
        turn = float(_wrap(turn + math.pi))
    return turn, found.sigma_heading_rad
