"""Relative surveys: no GNSS, no prism fixes; the IMU, the odometer, the non-holonomic constraint
and zero-velocity updates at the stops (seed 000: a stop about every 60 m) carry the trajectory.

Nothing observes where the trolley is, nor (beyond the gyrocompass) which way it points: the
trajectory's position and azimuth are those of its start, held within the IMU's drift. Its shape
over tens to hundreds of metres - gauge, cant, twist, versines, the 30 m/5 m check - is what the
survey measures; its coordinates are a frame of its own, not the line's.

The frame's start (:class:`RelativeFrame`) is given by the caller (``insrail.project``): the design's
point and azimuth at the start station where the project has a design, else a local frame. The
filter starts on it as on a single position fix at rest (:func:`start_track`): the static
levelling gives the tilt, the heading comes from the gyrocompass where the unit finds north, else
from the design's azimuth (the trolley taken to run towards increasing stationing unless the coarse
gyrocompass says otherwise). A local frame's latitude, which the earth rate and gravity need, comes
from the earth rate itself (its elevation in the levelled frame: :func:`latitude_from_earth_rate`).

Frames: n = NED, b = IMU body FRD, v = trolley frame; angles in radians.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from insrail.io.types import ImuIncrements
from insrail.nav import earth
from insrail.nav.alignment import gravity_tolerance_mps2, gyrocompass, gyrocompass_sigma_rad, static_levelling
from insrail.nav.rotation import euler_to_dcm
from insrail.nav.startup import PositionTrack, StartupError, finds_north
from insrail.notices import Notice, Phrase

#: 1-sigma [m] of the start point and [rad] of the start heading the filter is given: the start defines
#: the frame, so its errors are those of the frame (a shift and a turn of the whole survey, which no
#: chord check sees), not of the survey. The true heading error (gyrocompass or design: 0.05-0.1 deg)
#: also misdirects the earth rate taken off the gyros, by omega cos(lat) sin(error) (0.01-0.03 deg/h),
#: which the gyro bias states take up; the stated accuracy is then that of the shape, relative to the
#: start, and the notice gives the frame's own heading 1-sigma.
START_SIGMA_M = 0.005
FRAME_HEADING_SIGMA_RAD = 1e-5


@dataclass(frozen=True)
class RelativeFrame:
    """Where a relative survey's frame starts: a geodetic point and, from a design, the line's true
    azimuth there (towards increasing stationing) with its 1-sigma. ``lat_rad`` None: a local
    frame, its latitude from the earth rate (:func:`latitude_from_earth_rate`)."""

    lat_rad: float | None
    lon_rad: float
    height_m: float
    azimuth_rad: float | None
    sigma_azimuth_rad: float
    source: Phrase  # for messages: "the design at station 1020.000 m" or "a local frame"
    #: from the IMU to the frame's point on the trolley, b frame [m] (the track centre of a start on the design,
    #: survey.toml [start]); zero: the IMU is the point
    lever_arm_m: np.ndarray = field(default_factory=lambda: np.zeros(3))
    #: the 1-sigma [m] of the frame's point against the line (survey.toml [start] sigma_m); 0: not on the line
    sigma_m: float = 0.0

    @classmethod
    def local(cls, lon_rad: float = 0.0, on_meridian: bool = False) -> RelativeFrame:
        """A local frame at longitude ``lon_rad`` (it only names the frame: ``on_meridian``, the CRS's central
        meridian), its latitude from the earth rate."""
        return cls(None, lon_rad, 0.0, None, math.pi,
                   Phrase("a local frame on the central meridian" if on_meridian else "a local frame"))


def latitude_from_earth_rate(f_b: np.ndarray, w_b: np.ndarray, profile, ell: earth.Ellipsoid) -> tuple[float, float]:
    """(latitude [rad], 1-sigma) from the mean specific force and angular rate at rest: the earth rate's
    component along the down axis is -omega sin(lat)."""
    down = -np.asarray(f_b, float) / float(np.linalg.norm(f_b))
    ratio = float(-np.dot(w_b, down) / ell.omega)
    bias = math.hypot(profile.gyro_bias_turn_on, profile.gyro_bias_gm_sigma)
    return math.asin(max(-1.0, min(1.0, ratio))), min(bias / ell.omega, math.pi / 2)


@dataclass(frozen=True)
class RelativeStart:
    """What the filter starts from in a relative survey: a one-point position track at the static
    start, the heading of b to start with (its 1-sigma for the filter: :data:`FRAME_HEADING_SIGMA_RAD`)
    and what to tell the user."""

    track: PositionTrack
    heading_rad: float
    sigma_heading_rad: float
    notices: tuple[Notice, ...]


def start_track(frame: RelativeFrame, imu: ImuIncrements, stops, c_vb: np.ndarray, profile, min_static_s: float,
                ell: earth.Ellipsoid) -> RelativeStart:
    """The start of a relative survey on ``frame`` (see the module docstring). Raises
    :class:`StartupError` when the survey does not begin at rest (nothing then gives the tilt) or
    when neither the gyrocompass nor a design gives the heading."""
    t = imu.time_s
    static = stops[0] if stops and stops[0][0] <= t[0] + 5.0 else None
    if static is None or static[1] - static[0] < min_static_s:
        raise StartupError(
            f"relative survey (no GNSS, no prism fixes): the survey must begin with the trolley at rest for at least "
            f"{min_static_s:g} s (the static alignment is the only attitude it gets); the odometer and the IMU show "
            + ("no stop at its start" if static is None else f"a stop of {static[1] - static[0]:.1f} s"))
    k1 = int(np.searchsorted(t, static[1]))
    roll, pitch, f_b, w_b = static_levelling(imu, 1, k1, gravity_tolerance_mps2(profile))
    notices = []
    lat = frame.lat_rad
    if lat is None:
        lat, sigma_lat = latitude_from_earth_rate(f_b, w_b, profile, ell)
        if sigma_lat > math.radians(10.0) and frame.azimuth_rad is None:
            raise StartupError(
                "relative survey in a local frame (no design): the latitude and north come from the earth rate, which "
                f"a {profile.name} gyro does not resolve; give the project a design alignment (its start point and "
                "azimuth start the frame)")
        notices.append(Notice("fusion", "relative survey in a local frame: latitude {lat_deg:.2f} deg from the earth "
                              "rate at the static start (1-sigma {sigma_deg:.2f} deg)", severity="info",
                              fields={"lat_deg": math.degrees(lat), "sigma_deg": math.degrees(sigma_lat)}))
    duration = static[1] - static[0]
    sigma_compass = gyrocompass_sigma_rad(math.hypot(profile.gyro_bias_turn_on, profile.gyro_bias_gm_sigma),
                                          profile.gyro_arw, duration, lat, ell)
    if finds_north(profile, duration):
        try:
            heading = gyrocompass(roll, pitch, w_b, lat, ell)
        except ValueError as error:
            raise StartupError(f"relative survey: {error}") from None
        sigma = sigma_compass
        notices.append(Notice("fusion", "relative survey: heading {heading_deg:.2f} deg by gyrocompassing (1-sigma "
                              "{sigma_deg:.3f} deg: the frame's azimuth)", severity="info",
                              fields={"heading_deg": math.degrees(heading) % 360, "sigma_deg": math.degrees(sigma)}))
    else:
        if frame.azimuth_rad is None:
            raise StartupError(
                f"relative survey in a local frame (no design): a {profile.name} gyro does not find north over the "
                f"{duration:.0f} s static start, and nothing else gives the heading the earth rate is taken off with; "
                "give the project a design alignment (its start point and azimuth start the frame)")
        heading_v = frame.azimuth_rad
        direction = Phrase("towards increasing stationing (taken: the gyros do not tell)")
        if sigma_compass < math.radians(30.0):  # the coarse compass tells which way along the line
            try:
                compass = gyrocompass(roll, pitch, w_b, lat, ell)
            except ValueError:
                compass = None
            if compass is not None:
                c_bn = euler_to_dcm(roll, pitch, compass)
                forward = c_bn @ c_vb.T[:, 0]  # the trolley's x axis in n
                along = math.cos(math.atan2(forward[1], forward[0]) - heading_v)
                if along < 0.0:
                    heading_v += math.pi
                direction = Phrase("against increasing stationing (coarse gyrocompass)" if along < 0.0 else
                                   "towards increasing stationing (coarse gyrocompass)")
        c_bn = euler_to_dcm(0.0, 0.0, heading_v) @ c_vb  # b turned from v about (nearly) the vertical
        heading = float(math.atan2(c_bn[1, 0], c_bn[0, 0]))
        sigma = frame.sigma_azimuth_rad
        notices.append(Notice("fusion", "relative survey: heading {heading_deg:.2f} deg from {frame} (1-sigma "
                              "{sigma_deg:.2f} deg: the frame's azimuth), the trolley running {direction}", severity="info",
                              fields={"heading_deg": math.degrees(heading) % 360, "frame": frame.source,
                                      "sigma_deg": math.degrees(sigma), "direction": direction}))
    t0 = float(t[0]) + 0.5 * (static[1] - float(t[0]))
    track = PositionTrack(np.array([t0]), np.array([lat]), np.array([frame.lon_rad]), np.array([frame.height_m]),
                          np.full((1, 3), START_SIGMA_M), np.asarray(frame.lever_arm_m, float), Phrase("relative start"))
    notices.append(Notice("fusion", "relative survey (no GNSS, no prism fixes): the trajectory starts on {frame}; "
                          "gauge, cant, twist and the chord checks are measured, coordinates and deviations from the "
                          "design are not", severity="info", fields={"frame": frame.source}))
    return RelativeStart(track, float(heading), FRAME_HEADING_SIGMA_RAD, tuple(notices))
