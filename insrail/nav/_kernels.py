"""Compiled (numba) strapdown kernels: the per-epoch NED mechanization and its helpers.

Everything here is compiled by numba (cached on disk) and allocation-free: small vectors
travel as tuples of floats (kept in registers), so the functions can be called from other
compiled loops, the aided-INS filter in particular, once per 200 Hz epoch.

Navigation vector ``nav`` (float64[NAV_SIZE]), the state one epoch hands to the next:

====================  =====================================================================
``nav[0:4]``          q_n^e, position quaternion (scalar first, thesis 2.5)
``nav[4]``            ellipsoidal height h [m]
``nav[5:8]``          ground velocity v^n, NED [m/s]
``nav[8:12]``         q_b^n, attitude quaternion (scalar first)
``nav[12:15]``        v_{k-1} - v_{k-2} [m/s], the last velocity change, for the mid-epoch
                      extrapolation of the gravity/Coriolis term (Savage 2000)
====================  =====================================================================

Why q_n^e + h rather than latitude/longitude: the thesis updates position as a quaternion
product (2.37) that is exact for the rotations it composes and free of the longitude
singularity, and its mid-epoch position interpolation (2.47)-(2.48) is defined on q_n^e.
The kernel never needs latitude itself, only sin/cos of it, which are read off the third
column of C_n^e (the ellipsoid normal), so no inverse trigonometry runs per epoch and a
residual wander angle (rotation of n about its own down axis) cannot bias them.

Earth vector ``earth`` (float64[EARTH_SIZE]), from :func:`earth_constants`, so one compiled
kernel serves WGS84, CGCS2000 or a test ellipsoid: a, e^2, f, omega_ie, gamma_e (normal
gravity at the equator), Somigliana's k and m = omega^2 a^2 b / GM.
"""

from __future__ import annotations

import math

import numpy as np

from insrail.jit import cached_njit
from insrail.nav.earth import Ellipsoid

NAV_Q_NE = 0
NAV_H = 4
NAV_VEL = 5
NAV_Q_BN = 8
NAV_DVEL_LAST = 12
NAV_SIZE = 15

EARTH_A = 0
EARTH_E2 = 1
EARTH_F = 2
EARTH_OMEGA = 3
EARTH_GAMMA_E = 4
EARTH_K = 5
EARTH_M = 6
EARTH_SIZE = 7

# Cached on disk so a new process starts in well under a second. IEEE semantics for
# division (error_model="numpy") drop numba's per-division zero checks (~8 % faster); the
# only divisor that can vanish, cos(lat), is kept away from zero by NavState's pole check.
compiled = cached_njit(error_model="numpy")

# Below |0.5 phi| = 1e-3 rad the Taylor series of cos and sin(x)/x, cut after x^4, are
# exact in double precision (next term < 1e-18) and cheaper than the library calls.
_SERIES_HALF_ANGLE2 = 1e-6


def earth_constants(ell: Ellipsoid) -> np.ndarray:
    """Pack an :class:`~insrail.nav.earth.Ellipsoid` into the kernels' ``earth`` vector."""
    out = np.empty(EARTH_SIZE)
    out[EARTH_A] = ell.a
    out[EARTH_E2] = ell.e2
    out[EARTH_F] = ell.f
    out[EARTH_OMEGA] = ell.omega
    out[EARTH_GAMMA_E] = ell.gamma_e
    out[EARTH_K] = ell.k_somigliana
    out[EARTH_M] = ell.m
    return out


@compiled
def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@compiled
def quat_mul(p, q):
    """Hamilton product p * q of scalar-first quaternions (tuples)."""
    return (
        p[0] * q[0] - p[1] * q[1] - p[2] * q[2] - p[3] * q[3],
        p[0] * q[1] + p[1] * q[0] + p[2] * q[3] - p[3] * q[2],
        p[0] * q[2] - p[1] * q[3] + p[2] * q[0] + p[3] * q[1],
        p[0] * q[3] + p[1] * q[2] - p[2] * q[1] + p[3] * q[0],
    )


@compiled
def quat_normalize(q):
    """Thesis (2.49)."""
    s = 1.0 / math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    return (q[0] * s, q[1] * s, q[2] * s, q[3] * s)


@compiled
def rotvec_quat(x, y, z):
    """Quaternion of the rotation vector (x, y, z) (thesis 2.16, 2.38, 2.43)."""
    half2 = 0.25 * (x * x + y * y + z * z)
    if half2 < _SERIES_HALF_ANGLE2:
        c = 1.0 - half2 * (0.5 - half2 / 24.0)
        s = 0.5 * (1.0 - half2 * (1.0 / 6.0 - half2 / 120.0))
    else:
        half = math.sqrt(half2)
        c = math.cos(half)
        s = 0.5 * math.sin(half) / half
    return (c, s * x, s * y, s * z)


@compiled
def quat_rotate(q, v):
    """C(q) v for a unit quaternion q: v + 2 q0 (u x v) + 2 u x (u x v), u = vector part."""
    u = (q[1], q[2], q[3])
    t = cross(u, v)
    t2 = cross(u, t)
    return (
        v[0] + 2.0 * (q[0] * t[0] + t2[0]),
        v[1] + 2.0 * (q[0] * t[1] + t2[1]),
        v[2] + 2.0 * (q[0] * t[2] + t2[2]),
    )


@compiled
def _down_axis_ecef(q_ne):
    """Third column of C_n^e, the down axis in e: -(cos lat cos lon, cos lat sin lon, sin lat)
    (thesis 2.4). A rotation of n about its own down axis (wander) leaves it unchanged."""
    return (
        2.0 * (q_ne[1] * q_ne[3] + q_ne[0] * q_ne[2]),
        2.0 * (q_ne[2] * q_ne[3] - q_ne[0] * q_ne[1]),
        q_ne[0] * q_ne[0] - q_ne[1] * q_ne[1] - q_ne[2] * q_ne[2] + q_ne[3] * q_ne[3],
    )


@compiled
def lat_sincos(q_ne):
    """(sin, cos) of geodetic latitude from q_n^e, without inverse trigonometry."""
    c02, c12, c22 = _down_axis_ecef(q_ne)
    return -c22, math.sqrt(c02 * c02 + c12 * c12)


@compiled
def lat_lon(q_ne):
    """Geodetic latitude and longitude [rad] from q_n^e, a tuple (as the strapdown's: each layout or
    writability of an array passed instead would compile it and :func:`_down_axis_ecef` once more)."""
    c02, c12, c22 = _down_axis_ecef(q_ne)
    return math.atan2(-c22, math.sqrt(c02 * c02 + c12 * c12)), math.atan2(-c12, -c02)


@compiled
def euler(q_bn):
    """z-y-x Euler angles (roll, pitch, heading) [rad] of b relative to n from q_b^n."""
    q0, q1, q2, q3 = q_bn[0], q_bn[1], q_bn[2], q_bn[3]
    c00 = q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3
    c10 = 2.0 * (q1 * q2 + q0 * q3)
    c20 = 2.0 * (q1 * q3 - q0 * q2)
    c21 = 2.0 * (q2 * q3 + q0 * q1)
    c22 = q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3
    return math.atan2(c21, c22), math.atan2(-c20, math.sqrt(c21 * c21 + c22 * c22)), math.atan2(c10, c00)


@compiled
def lat_lon_rows(q_ne, lat, lon):
    """:func:`lat_lon` for every row of q_ne (m, 4) into lat, lon (m,)."""
    for i in range(q_ne.shape[0]):
        lat[i], lon[i] = lat_lon((q_ne[i, 0], q_ne[i, 1], q_ne[i, 2], q_ne[i, 3]))


@compiled
def euler_rows(q_bn, roll, pitch, heading):
    """:func:`euler` for every row of q_bn (m, 4)."""
    for i in range(q_bn.shape[0]):
        roll[i], pitch[i], heading[i] = euler(q_bn[i])


@compiled
def radii(sin_lat, earth):
    """Meridian and prime-vertical radii R_M, R_N [m] (thesis 2.8, 2.9)."""
    w2 = 1.0 - earth[EARTH_E2] * sin_lat * sin_lat
    r_n = earth[EARTH_A] / math.sqrt(w2)
    return r_n * (1.0 - earth[EARTH_E2]) / w2, r_n


@compiled
def normal_gravity(sin_lat, r_n, h, earth):
    """Somigliana normal gravity with the free-air height terms, as earth.normal_gravity.

    ``r_n`` is the prime-vertical radius at the same latitude: a / r_n = sqrt(1 - e^2 sin^2).
    """
    s2 = sin_lat * sin_lat
    a = earth[EARTH_A]
    f = earth[EARTH_F]
    g0 = earth[EARTH_GAMMA_E] * (1.0 + earth[EARTH_K] * s2) * r_n / a
    return g0 * (1.0 - 2.0 * h / a * (1.0 + f + earth[EARTH_M] - 2.0 * f * s2) + 3.0 * h * h / (a * a))


@compiled
def earth_rate(sin_lat, cos_lat, earth):
    """omega_ie^n (thesis 2.6)."""
    return (earth[EARTH_OMEGA] * cos_lat, 0.0, -earth[EARTH_OMEGA] * sin_lat)


@compiled
def transport_rate(sin_lat, cos_lat, r_m, r_n, h, vel):
    """omega_en^n (thesis 2.7)."""
    east = vel[1] / (r_n + h)
    return (east, -vel[0] / (r_m + h), -east * sin_lat / cos_lat)


@compiled
def _frame_rotation(w_ie, w_en, dt):
    """zeta = (omega_ie^n + omega_en^n) dt, rotation of n w.r.t. inertial space (2.36)."""
    return ((w_ie[0] + w_en[0]) * dt, (w_ie[1] + w_en[1]) * dt, (w_ie[2] + w_en[2]) * dt)


@compiled
def strapdown_step(nav, dtheta_prev, dvel_prev, dtheta, dvel, dt, earth, out):
    """Advance the navigation vector over one IMU interval (thesis 2.32-2.49, order of 4.5).

    nav, out      : float64[NAV_SIZE] at t_{k-1} and t_k (``out`` may be ``nav`` itself)
    dtheta_prev,
    dvel_prev     : compensated increments of the interval ending at t_{k-1} [rad, m/s]
    dtheta, dvel  : compensated increments of the interval (t_{k-1}, t_k]
    dt            : t_k - t_{k-1} [s]
    earth         : float64[EARTH_SIZE] from :func:`earth_constants`
    """
    q_ne = (nav[0], nav[1], nav[2], nav[3])
    h = nav[NAV_H]
    vel = (nav[5], nav[6], nav[7])
    q_bn = (nav[8], nav[9], nav[10], nav[11])
    th = (dtheta[0], dtheta[1], dtheta[2])
    dv = (dvel[0], dvel[1], dvel[2])
    th_prev = (dtheta_prev[0], dtheta_prev[1], dtheta_prev[2])
    dv_prev = (dvel_prev[0], dvel_prev[1], dvel_prev[2])

    # Mid-epoch t_{k-1/2} by extrapolation: velocity from its last change, position with
    # the velocity at t_{k-1} (half an epoch moves it < 3 cm: first order suffices).
    vel_mid = (
        vel[0] + 0.5 * nav[NAV_DVEL_LAST],
        vel[1] + 0.5 * nav[NAV_DVEL_LAST + 1],
        vel[2] + 0.5 * nav[NAV_DVEL_LAST + 2],
    )
    sin0, cos0 = lat_sincos(q_ne)
    r_m0, _ = radii(sin0, earth)
    dlat = 0.5 * dt * vel[0] / (r_m0 + h)
    sin_mid = sin0 + cos0 * dlat
    cos_mid = cos0 - sin0 * dlat
    h_mid = h - 0.5 * dt * vel[2]
    r_m, r_n = radii(sin_mid, earth)
    gravity = normal_gravity(sin_mid, r_n, h_mid, earth)
    w_ie = earth_rate(sin_mid, cos_mid, earth)
    w_en = transport_rate(sin_mid, cos_mid, r_m, r_n, h_mid, vel_mid)
    zeta = _frame_rotation(w_ie, w_en, dt)

    # Velocity: rotation and sculling terms (2.35), n-frame rotation (2.34),
    # gravity/Coriolis at mid-epoch (2.33), sum (2.32). (2.35) is extended by the next term
    # of the rotation series, 1/6 dtheta x (dtheta x dvel) (Savage 2000's exact-form
    # rotation compensation, expanded): without it angular vibration of rate w rectifies
    # into a vertical error g |w|^2 dt^2 / 6 (1.6e-7 m/s^2, 3 cm in 10 min for a 0.02 rad
    # roll oscillation at 0.7 Hz; see the curved-motion test).
    rot = cross(th, dv)
    rot2 = cross(th, rot)
    scul_a = cross(th_prev, dv)
    scul_b = cross(dv_prev, th)
    dv_b = (
        dv[0] + 0.5 * rot[0] + rot2[0] / 6.0 + (scul_a[0] + scul_b[0]) / 12.0,
        dv[1] + 0.5 * rot[1] + rot2[1] / 6.0 + (scul_a[1] + scul_b[1]) / 12.0,
        dv[2] + 0.5 * rot[2] + rot2[2] / 6.0 + (scul_a[2] + scul_b[2]) / 12.0,
    )
    dv_n = quat_rotate(q_bn, dv_b)
    zeta_dv = cross(zeta, dv_n)
    coriolis = cross((2.0 * w_ie[0] + w_en[0], 2.0 * w_ie[1] + w_en[1], 2.0 * w_ie[2] + w_en[2]), vel_mid)
    vel_new = (
        vel[0] + dv_n[0] - 0.5 * zeta_dv[0] - coriolis[0] * dt,
        vel[1] + dv_n[1] - 0.5 * zeta_dv[1] - coriolis[1] * dt,
        vel[2] + dv_n[2] - 0.5 * zeta_dv[2] + (gravity - coriolis[2]) * dt,
    )

    # Position: zeta with the interpolated mid velocity (2.36), q_n^e product (2.37)-(2.39)
    # with the earth rotation xi entering as -0.5 xi (the thesis prints +; see ins-filter.md),
    # height with the mid vertical velocity (2.40).
    # (2.37) is evaluated as q_n^e(k-1) [q(-xi^n) q(zeta)], xi^n = C_e^n xi, an identity
    # (q(-xi) q = q q(-C_e^n xi)) that cancels the two ~omega_ie dt rotations before they
    # touch q_n^e; normalising their product first makes it exactly [1, 0, 0, 0] at rest, so
    # q_n^e does not collect the same rounding error every epoch (0.07 mm in 10 min with
    # the literal order).
    vel_avg = (0.5 * (vel[0] + vel_new[0]), 0.5 * (vel[1] + vel_new[1]), 0.5 * (vel[2] + vel_new[2]))
    w_en = transport_rate(sin_mid, cos_mid, r_m, r_n, h_mid, vel_avg)
    zeta = _frame_rotation(w_ie, w_en, dt)
    xi_scale = -earth[EARTH_OMEGA] * dt  # -xi^n = -omega dt * (third row of C_n^e)
    q_earth = rotvec_quat(
        xi_scale * 2.0 * (q_ne[1] * q_ne[3] - q_ne[0] * q_ne[2]),
        xi_scale * 2.0 * (q_ne[2] * q_ne[3] + q_ne[0] * q_ne[1]),
        -xi_scale * sin0,
    )
    q_step = quat_normalize(quat_mul(q_earth, rotvec_quat(zeta[0], zeta[1], zeta[2])))
    q_ne_new = quat_normalize(quat_mul(q_ne, q_step))
    h_new = h - vel_avg[2] * dt

    # Attitude: mid position by halving the n-relative-to-e rotation (2.47)-(2.48), whose
    # half-angle quaternion is (1 + q)/|1 + q|; zeta recomputed there; coning (2.45);
    # body (2.43, 2.41) and n-frame (2.46, 2.42) updates; normalisation (2.49).
    q_rel = quat_mul((q_ne[0], -q_ne[1], -q_ne[2], -q_ne[3]), q_ne_new)
    if q_rel[0] < 0.0:
        q_rel = (-q_rel[0], -q_rel[1], -q_rel[2], -q_rel[3])
    q_half = quat_normalize((1.0 + q_rel[0], q_rel[1], q_rel[2], q_rel[3]))
    sin_m, cos_m = lat_sincos(quat_mul(q_ne, q_half))
    h_m = 0.5 * (h + h_new)
    r_m, r_n = radii(sin_m, earth)
    w_ie = earth_rate(sin_m, cos_m, earth)
    w_en = transport_rate(sin_m, cos_m, r_m, r_n, h_m, vel_avg)
    zeta = _frame_rotation(w_ie, w_en, dt)
    coning = cross(th_prev, th)
    q_body = rotvec_quat(th[0] + coning[0] / 12.0, th[1] + coning[1] / 12.0, th[2] + coning[2] / 12.0)
    q_nav = rotvec_quat(-zeta[0], -zeta[1], -zeta[2])
    q_bn_new = quat_normalize(quat_mul(q_nav, quat_mul(q_bn, q_body)))

    for i in range(4):
        out[NAV_Q_NE + i] = q_ne_new[i]
        out[NAV_Q_BN + i] = q_bn_new[i]
    out[NAV_H] = h_new
    for i in range(3):
        out[NAV_VEL + i] = vel_new[i]
        out[NAV_DVEL_LAST + i] = vel_new[i] - vel[i]


@compiled
def integrate_span(nav, dtheta, dvel, dt, earth, start, stop, output_every, done, q_ne, h, vel, q_bn):
    """Run :func:`strapdown_step` for epochs ``start <= k < stop``, updating ``nav`` in place.

    dtheta, dvel : (n, 3) compensated increments; epoch k uses row k-1 as the previous
                   interval (row 0 for k = 0, which makes the first update one-sample)
    dt           : (n,) interval lengths [s]
    done         : epochs processed before ``start`` (for the output decimation)
    q_ne, h, vel, q_bn : outputs (m, 4), (m,), (m, 3), (m, 4); after the j-th processed
                   epoch (counting from 1) with j % output_every == 0 the state goes to
                   row j // output_every
    """
    for k in range(start, stop):
        prev = k - 1 if k > 0 else 0
        strapdown_step(nav, dtheta[prev], dvel[prev], dtheta[k], dvel[k], dt[k], earth, nav)
        j = done + k - start + 1
        if j % output_every == 0:
            row = j // output_every
            for i in range(4):
                q_ne[row, i] = nav[NAV_Q_NE + i]
                q_bn[row, i] = nav[NAV_Q_BN + i]
            h[row] = nav[NAV_H]
            for i in range(3):
                vel[row, i] = nav[NAV_VEL + i]


def drop_stale_cache(dispatchers, dependencies) -> None:
    """Numba checks a cached kernel only against its own source file: a kernel that calls compiled
    functions of other modules (the filter loop calls the measurement models, the Kalman update and
    the strapdown) would keep running their old code after they changed. Called once at import by
    such a module, this removes the module's cache entries that are older than any of
    ``dependencies`` (module files), so they are compiled again."""
    import os
    from pathlib import Path

    try:
        newest = max(os.stat(path).st_mtime for path in dependencies)
    except OSError:  # no source files (a frozen bundle): nothing changes there
        return
    for dispatcher in dispatchers:
        cache = getattr(dispatcher, "_cache", None)
        index = getattr(getattr(cache, "_cache_file", None), "_index_path", None)
        if index is None:
            continue
        index = Path(index)
        try:
            stale = index.stat().st_mtime < newest
        except OSError:  # not cached yet
            continue
        if stale:
            for entry in index.parent.glob(index.name.removesuffix(".nbi") + ".*"):
                entry.unlink(missing_ok=True)
