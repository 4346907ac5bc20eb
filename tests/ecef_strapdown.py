"""A plain reference strapdown in the ECEF frame, for testing the simulator.

Deliberately independent of insrail.nav's NED mechanisation and of the simulator's
kinematics code (different frame, no Euler angles, no transport rate, its own gravity
evaluation): if the simulator's increments are right, this integrator reproduces the
simulator's truth trajectory.

Per step (increments dtheta, dvel over dt; previous increments for the two-sample terms):
  C_k = R(-omega_ie dt) C_{k-1} R(dtheta + dtheta_prev x dtheta / 12)
  dv_f = C_{k-1} (dvel + dtheta x dvel / 2 + (dtheta_prev x dvel + dvel_prev x dtheta) / 12)
         - omega_ie x (C_{k-1} dvel) dt / 2
  v_k  = v_{k-1} + dv_f + (g(r_mid) - 2 omega_ie x v_mid) dt     (mid-step iterated)
  r_k  = r_{k-1} + (v_{k-1} + v_k) dt / 2
"""

import math

import numpy as np
from numba import njit

A = 6378137.0
OMEGA = 7.292115e-5
GAMMA_E, GAMMA_P = 9.7803253359, 9.8321849378
GM = 3.986004418e14


@njit(cache=True)
def _gravity(r, F):
    """Normal gravity vector (ECEF) at r: Somigliana plus free-air, along the ellipsoid normal
    of the ellipsoid with flattening F (WGS84 and CGCS2000 differ only there)."""
    E2 = F * (2.0 - F)
    p = math.hypot(r[0], r[1])
    lon = math.atan2(r[1], r[0])
    lat = math.atan2(r[2], p * (1.0 - E2))
    for _ in range(5):
        n = A / math.sqrt(1.0 - E2 * math.sin(lat) ** 2)
        h = p / math.cos(lat) - n
        lat = math.atan2(r[2], p * (1.0 - E2 * n / (n + h)))
    n = A / math.sqrt(1.0 - E2 * math.sin(lat) ** 2)
    h = p / math.cos(lat) - n
    s2 = math.sin(lat) ** 2
    b = A * (1.0 - F)
    k = b * GAMMA_P / (A * GAMMA_E) - 1.0
    m = OMEGA**2 * A**2 * b / GM
    g0 = GAMMA_E * (1.0 + k * s2) / math.sqrt(1.0 - E2 * s2)
    g = g0 * (1.0 - 2.0 * h / A * (1.0 + F + m - 2.0 * F * s2) + 3.0 * h * h / (A * A))
    down = np.array([-math.cos(lat) * math.cos(lon), -math.cos(lat) * math.sin(lon), -math.sin(lat)])
    return g * down


@njit(cache=True)
def _rot(phi):
    a = math.sqrt(phi[0] ** 2 + phi[1] ** 2 + phi[2] ** 2)
    k = np.array([[0.0, -phi[2], phi[1]], [phi[2], 0.0, -phi[0]], [-phi[1], phi[0], 0.0]])
    if a < 1e-8:
        s, c = 1.0 - a * a / 6.0, 0.5 - a * a / 24.0
    else:
        s, c = math.sin(a) / a, (1.0 - math.cos(a)) / (a * a)
    return np.eye(3) + s * k + c * (k @ k)


@njit(cache=True)
def integrate_ecef(time_s, dtheta, dvel, r0, v0, c_be0, dtheta_prev, dvel_prev, flattening):
    """ECEF positions (n-1, 3) at time_s[1:], from the state at time_s[0]; row k of the
    increments covers (time_s[k-1], time_s[k]]."""
    w = np.array([0.0, 0.0, OMEGA])
    r, v, c = r0.copy(), v0.copy(), c_be0.copy()
    pth, pdv = dtheta_prev.copy(), dvel_prev.copy()
    out = np.empty((len(time_s) - 1, 3))
    for k in range(1, len(time_s)):
        dt = time_s[k] - time_s[k - 1]
        dth, dv = dtheta[k], dvel[k]
        dv_b = dv + 0.5 * np.cross(dth, dv) + (np.cross(pth, dv) + np.cross(pdv, dth)) / 12.0
        dv_f = c @ dv_b - 0.5 * np.cross(w, c @ dv) * dt
        v_new = v + dv_f + (_gravity(r + 0.5 * v * dt, flattening) - 2.0 * np.cross(w, v)) * dt
        for _ in range(2):
            v_mid = 0.5 * (v + v_new)
            v_new = v + dv_f + (_gravity(r + 0.5 * v_mid * dt, flattening) - 2.0 * np.cross(w, v_mid)) * dt
        r = r + 0.5 * (v + v_new) * dt
        v = v_new
        c = _rot(-w * dt) @ c @ _rot(dth + np.cross(pth, dth) / 12.0)
        pth, pdv = dth, dv
        out[k - 1] = r
    return out
