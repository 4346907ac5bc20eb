"""Strapdown INS mechanization in the local-level NED frame (thesis 2.4.4).

Free-inertial integration of IMU increments on the project's ellipsoid with normal
gravity: two-sample velocity update with rotation and sculling compensation and mid-epoch
gravity/Coriolis (2.32-2.36), position as the quaternion q_n^e plus height (2.37-2.40),
two-sample (coning-compensated) attitude quaternion update (2.41-2.49). The per-epoch
update lives in :mod:`insrail.nav._kernels` (numba, cached on disk) so the aided-INS
filter can call it from its own compiled loop; :func:`integrate` runs it over a whole
recording.

The increments given here are taken as already compensated for sensor errors (thesis 3.3);
the filter compensates them with its current estimates before each step.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from insrail.io.types import ImuIncrements
from insrail.nav import _kernels
from insrail.nav.earth import WGS84, Ellipsoid
from insrail.nav.rotation import dcm_to_quat, euler_to_dcm
from insrail.notices import Phrase
from insrail.progress import CancelToken, ProgressFn, check_cancel

#: Epochs per call of the compiled loop; progress and cancel are served between calls.
CHUNK_EPOCHS = 200_000

#: The n-frame is singular at the poles (tan(lat) in the transport rate).
MAX_ABS_LAT_RAD = np.deg2rad(89.9)


def q_ne_from_lat_lon(lat, lon):
    """Position quaternion q_n^e (..., 4) from geodetic latitude and longitude [rad] (2.5)."""
    lat, lon = np.broadcast_arrays(np.asarray(lat, dtype=float), np.asarray(lon, dtype=float))
    a = -0.25 * np.pi - 0.5 * lat
    ca, sa = np.cos(a), np.sin(a)
    co, so = np.cos(0.5 * lon), np.sin(0.5 * lon)
    return np.stack([ca * co, -sa * so, sa * co, ca * so], axis=-1)


def _rows_of(q) -> np.ndarray:
    q = np.asarray(q, dtype=float)
    if q.shape[-1:] != (4,):
        raise ValueError(f"expected quaternions of shape (..., 4), got {q.shape}")
    return np.ascontiguousarray(q.reshape(-1, 4))


def lat_lon_from_q_ne(q_ne):
    """Geodetic latitude and longitude [rad] from q_n^e (..., 4), via the n-frame down axis
    in e (wander-free); arrays of shape (...)."""
    rows = _rows_of(q_ne)
    lat, lon = np.empty(len(rows)), np.empty(len(rows))
    _kernels.lat_lon_rows(rows, lat, lon)
    shape = np.shape(q_ne)[:-1]
    return lat.reshape(shape), lon.reshape(shape)


def euler_from_q_bn(q_bn):
    """(roll, pitch, heading) [rad] of b relative to n from q_b^n (..., 4); heading in (-pi, pi]."""
    rows = _rows_of(q_bn)
    angles = np.empty((3, len(rows)))
    _kernels.euler_rows(rows, angles[0], angles[1], angles[2])
    shape = np.shape(q_bn)[:-1]
    return tuple(a.reshape(shape) for a in angles)


@dataclass(frozen=True)
class NavState:
    """Navigation state at one instant: the initial condition of :func:`integrate`.

    time_s      : GPS seconds of week
    lat_rad, lon_rad, height_m : geodetic position of the IMU centre (ellipsoidal height)
    vel_ned_mps : (3,) ground velocity north, east, down
    q_bn        : (4,) attitude quaternion q_b^n, scalar first; normalised on construction.
                  Use :meth:`from_euler` to give roll, pitch, heading instead.
    """

    time_s: float
    lat_rad: float
    lon_rad: float
    height_m: float
    vel_ned_mps: np.ndarray
    q_bn: np.ndarray

    def __post_init__(self):
        for name in ("time_s", "lat_rad", "lon_rad", "height_m"):
            value = getattr(self, name)
            if not np.isfinite(value):
                raise ValueError(f"NavState.{name}: expected a finite number, got {value!r}")
            object.__setattr__(self, name, float(value))
        if abs(self.lat_rad) > MAX_ABS_LAT_RAD:
            raise ValueError(
                f"NavState.lat_rad: |latitude| must stay below {np.rad2deg(MAX_ABS_LAT_RAD):.1f} deg "
                f"(the NED frame is singular at the poles), got {np.rad2deg(self.lat_rad):.6f} deg"
            )
        vel = np.array(self.vel_ned_mps, dtype=float)
        if vel.shape != (3,) or not np.all(np.isfinite(vel)):
            raise ValueError(f"NavState.vel_ned_mps: expected 3 finite numbers (N, E, D), got {self.vel_ned_mps!r}")
        q = np.array(self.q_bn, dtype=float)
        if q.shape != (4,) or not np.all(np.isfinite(q)):
            raise ValueError(f"NavState.q_bn: expected 4 finite numbers (scalar first), got {self.q_bn!r}")
        norm = np.linalg.norm(q)
        if abs(norm - 1.0) > 1e-6:
            raise ValueError(f"NavState.q_bn: expected a unit quaternion, its norm is {norm:.9g}")
        vel.flags.writeable = False
        q = q / norm
        q.flags.writeable = False
        object.__setattr__(self, "vel_ned_mps", vel)
        object.__setattr__(self, "q_bn", q)

    @classmethod
    def from_euler(cls, time_s, lat_rad, lon_rad, height_m, vel_ned_mps, roll_rad, pitch_rad, heading_rad):
        """State with the attitude given as z-y-x Euler angles of b relative to n [rad]."""
        q = dcm_to_quat(euler_to_dcm(roll_rad, pitch_rad, heading_rad))
        return cls(time_s, lat_rad, lon_rad, height_m, vel_ned_mps, q)

    @property
    def euler_rad(self) -> tuple[float, float, float]:
        """(roll, pitch, heading) [rad]."""
        return tuple(float(a) for a in euler_from_q_bn(self.q_bn))


@dataclass(frozen=True)
class NavSolution:
    """Free-inertial solution, one row per output epoch (row 0 = the initial state).

    time_s        : (m,) GPS seconds of week
    lat_rad, lon_rad, height_m : (m,) geodetic position of the IMU centre
    vel_ned_mps   : (m, 3) ground velocity north, east, down
    roll_rad, pitch_rad, heading_rad : (m,) z-y-x Euler angles of b relative to n;
                    heading in (-pi, pi]
    q_bn          : (m, 4) attitude quaternion q_b^n, scalar first
    q_ne          : (m, 4) position quaternion q_n^e (thesis 2.5), the exact form of the
                    position that lat/lon are computed from
    """

    time_s: np.ndarray
    lat_rad: np.ndarray
    lon_rad: np.ndarray
    height_m: np.ndarray
    vel_ned_mps: np.ndarray
    roll_rad: np.ndarray
    pitch_rad: np.ndarray
    heading_rad: np.ndarray
    q_bn: np.ndarray
    q_ne: np.ndarray

    def __len__(self) -> int:
        return len(self.time_s)

    def state(self, index: int) -> NavState:
        """The solution at one row as a :class:`NavState`, e.g. to continue integrating."""
        return NavState(
            self.time_s[index], self.lat_rad[index], self.lon_rad[index], self.height_m[index],
            self.vel_ned_mps[index], self.q_bn[index],
        )


def nav_vector(state: NavState) -> np.ndarray:
    """The compiled kernels' navigation vector (layout in :mod:`insrail.nav._kernels`) at ``state``.

    The last-velocity-change slot starts at zero: the first gravity/Coriolis evaluation
    then uses the initial velocity for the mid-epoch one.
    """
    nav = np.zeros(_kernels.NAV_SIZE)
    nav[_kernels.NAV_Q_NE : _kernels.NAV_Q_NE + 4] = q_ne_from_lat_lon(state.lat_rad, state.lon_rad)
    nav[_kernels.NAV_H] = state.height_m
    nav[_kernels.NAV_VEL : _kernels.NAV_VEL + 3] = state.vel_ned_mps
    nav[_kernels.NAV_Q_BN : _kernels.NAV_Q_BN + 4] = state.q_bn
    return nav


def _where(imu: ImuIncrements, index: int) -> str:
    source = f"{imu.source}: " if imu.source is not None else ""
    return f"{source}IMU sample {index} (t = {imu.time_s[index]:.6f} s)"


def _validated_arrays(imu: ImuIncrements):
    """The increments as contiguous float64 arrays (copied only if needed), checked."""
    time = np.ascontiguousarray(imu.time_s, dtype=float)
    dtheta = np.ascontiguousarray(imu.dtheta_rad, dtype=float)
    dvel = np.ascontiguousarray(imu.dvel_mps, dtype=float)
    n = len(time)
    if time.ndim != 1 or dtheta.shape != (n, 3) or dvel.shape != (n, 3):
        raise ValueError(
            f"ImuIncrements: expected time_s (n,), dtheta_rad (n, 3), dvel_mps (n, 3); "
            f"got {time.shape}, {dtheta.shape}, {dvel.shape}"
        )
    if n < 2:
        raise ValueError(f"ImuIncrements: expected at least 2 samples, got {n}")
    finite = np.isfinite(time) & np.isfinite(dtheta).all(axis=1) & np.isfinite(dvel).all(axis=1)
    if not finite.all():
        bad = int(np.argmin(finite))
        raise ValueError(f"{_where(imu, bad)}: expected finite time and increments, found NaN or inf")
    steps = np.diff(time)
    if not (steps > 0.0).all():
        bad = int(np.argmin(steps > 0.0)) + 1
        raise ValueError(f"{_where(imu, bad)}: expected time to increase, previous sample is at {time[bad - 1]:.6f} s")
    return time, dtheta, dvel


def integrate(
    imu: ImuIncrements,
    initial: NavState,
    ellipsoid: Ellipsoid = WGS84,
    progress: ProgressFn | None = None,
    cancel: CancelToken = None,
    output_every: int = 1,
) -> NavSolution:
    """Free-inertial navigation from ``initial`` over all later IMU samples.

    ``initial.time_s`` must be an IMU time stamp (integration starts with the next
    interval, whose predecessor feeds the two-sample terms) or the start of the first
    interval, one nominal sample interval before ``time_s[0]`` (the first update is then
    one-sample). Each increment covers the interval since the previous time stamp (the
    :class:`~insrail.io.types.ImuIncrements` contract), so the one after a gap is integrated
    over the whole gap; a reader whose device drops increments must say so in ``gaps``
    and the caller decide how to bridge them.

    output_every : keep every n-th epoch (row 0 is always the initial state)
    Raises ValueError for malformed increments or an initial time that is not on the grid,
    :class:`insrail.progress.Cancelled` when ``cancel`` is set between chunks.
    """
    if int(output_every) != output_every or output_every < 1:
        raise ValueError(f"output_every: expected a positive integer, got {output_every!r}")
    output_every = int(output_every)
    time, dtheta, dvel = _validated_arrays(imu)
    nominal = float(np.median(np.diff(time)))
    tolerance = 1e-3 * nominal
    index = int(np.searchsorted(time, initial.time_s - tolerance))
    if index < len(time) and abs(time[index] - initial.time_s) <= tolerance:
        start = index + 1
    elif abs(time[0] - nominal - initial.time_s) <= tolerance:
        start = 0
    else:
        raise ValueError(
            f"NavState.time_s = {initial.time_s:.6f} s: expected an IMU time stamp within "
            f"{tolerance:.2e} s, or the start of the first interval ({time[0] - nominal:.6f} s); "
            f"the IMU data span {time[0]:.6f} to {time[-1]:.6f} s"
        )
    dt = np.empty_like(time)
    dt[0] = nominal
    dt[1:] = np.diff(time)

    n_epochs = len(time) - start
    rows = 1 + n_epochs // output_every
    q_ne, height, vel, q_bn = np.empty((rows, 4)), np.empty(rows), np.empty((rows, 3)), np.empty((rows, 4))
    nav = nav_vector(initial)
    q_ne[0] = nav[_kernels.NAV_Q_NE : _kernels.NAV_Q_NE + 4]
    height[0], vel[0], q_bn[0] = initial.height_m, initial.vel_ned_mps, initial.q_bn
    earth = _kernels.earth_constants(ellipsoid)
    for chunk_start in range(start, len(time), CHUNK_EPOCHS):
        check_cancel(cancel)
        chunk_stop = min(chunk_start + CHUNK_EPOCHS, len(time))
        _kernels.integrate_span(
            nav, dtheta, dvel, dt, earth, chunk_start, chunk_stop, output_every, chunk_start - start,
            q_ne, height, vel, q_bn,
        )
        if progress is not None:
            done = chunk_stop - start
            progress(done / max(n_epochs, 1), Phrase("strapdown: {done} of {epochs} IMU epochs", {"done": done, "epochs": n_epochs}))

    times = np.empty(rows)
    times[0] = initial.time_s
    times[1:] = time[start - 1 + output_every * np.arange(1, rows)]
    lat, lon = lat_lon_from_q_ne(q_ne)
    roll, pitch, heading = euler_from_q_bn(q_bn)
    return NavSolution(times, lat, lon, height, vel, roll, pitch, heading, q_bn, q_ne)
