"""Rotations: skew matrices, Euler angles, DCMs, rotation vectors, quaternions.

Vectorised numpy over leading axes: vectors have shape (..., 3), DCMs (..., 3, 3),
quaternions (..., 4) scalar first. Euler angles are roll, pitch, heading with
``C_b^n = Rz(heading) @ Ry(pitch) @ Rx(roll)`` (z-y-x sequence, thesis 2.4.2).
"""

from __future__ import annotations

import numpy as np


def skew(v):
    """(v x) so that skew(a) @ b == cross(a, b); shape (..., 3, 3)."""
    v = np.asarray(v, dtype=float)
    if v.shape == (3,):  # the filter's per-epoch case: a literal is several times faster
        x, y, z = v.tolist()
        return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    m = np.zeros(v.shape[:-1] + (3, 3))
    m[..., 0, 1] = -v[..., 2]
    m[..., 0, 2] = v[..., 1]
    m[..., 1, 0] = v[..., 2]
    m[..., 1, 2] = -v[..., 0]
    m[..., 2, 0] = -v[..., 1]
    m[..., 2, 1] = v[..., 0]
    return m


def cross(a, b) -> np.ndarray:
    """a x b of two 3-vectors, as np.cross computes it (the same products and differences),
    without its per-call overhead, which dominates on single vectors."""
    a0, a1, a2 = np.asarray(a, dtype=float).tolist()
    b0, b1, b2 = np.asarray(b, dtype=float).tolist()
    return np.array([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0])


def euler_to_dcm(roll, pitch, heading):
    """C_b^n from roll, pitch, heading [rad]; shape (..., 3, 3)."""
    roll, pitch, heading = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (roll, pitch, heading)))
    cr, sr = np.cos(roll), np.sin(roll)
    cp, sp = np.cos(pitch), np.sin(pitch)
    ch, sh = np.cos(heading), np.sin(heading)
    c = np.empty(roll.shape + (3, 3))
    c[..., 0, 0] = cp * ch
    c[..., 0, 1] = -cr * sh + sr * sp * ch
    c[..., 0, 2] = sr * sh + cr * sp * ch
    c[..., 1, 0] = cp * sh
    c[..., 1, 1] = cr * ch + sr * sp * sh
    c[..., 1, 2] = -sr * ch + cr * sp * sh
    c[..., 2, 0] = -sp
    c[..., 2, 1] = sr * cp
    c[..., 2, 2] = cr * cp
    return c


def dcm_to_euler(c):
    """(roll, pitch, heading) [rad] from C_b^n; heading in (-pi, pi]."""
    c = np.asarray(c, dtype=float)
    roll = np.arctan2(c[..., 2, 1], c[..., 2, 2])
    pitch = np.arctan2(-c[..., 2, 0], np.hypot(c[..., 2, 1], c[..., 2, 2]))
    heading = np.arctan2(c[..., 1, 0], c[..., 0, 0])
    return roll, pitch, heading


def rotvec_to_dcm(phi):
    """DCM of the rotation vector phi (thesis 2.15), exact for any angle."""
    phi = np.asarray(phi, dtype=float)
    angle = np.linalg.norm(phi, axis=-1)
    small = angle < 1e-8
    safe = np.where(small, 1.0, angle)
    # Series below 1e-8 rad keeps full precision where the closed form cancels.
    a = np.where(small, 1.0 - angle**2 / 6.0, np.sin(safe) / safe)
    b = np.where(small, 0.5 - angle**2 / 24.0, (1.0 - np.cos(safe)) / safe**2)
    k = skew(phi)
    eye = np.broadcast_to(np.eye(3), k.shape)
    return eye + a[..., None, None] * k + b[..., None, None] * (k @ k)


def dcm_to_rotvec(c):
    """Rotation vector of a DCM (inverse of :func:`rotvec_to_dcm`), angles < pi."""
    return quat_to_rotvec(dcm_to_quat(c))


def quat_multiply(p, q):
    """Hamilton product p * q, scalar first."""
    p = np.asarray(p, dtype=float)
    q = np.asarray(q, dtype=float)
    p0, p1, p2, p3 = (p[..., i] for i in range(4))
    q0, q1, q2, q3 = (q[..., i] for i in range(4))
    out = np.empty(np.broadcast_shapes(p.shape, q.shape))
    out[..., 0] = p0 * q0 - p1 * q1 - p2 * q2 - p3 * q3
    out[..., 1] = p0 * q1 + p1 * q0 + p2 * q3 - p3 * q2
    out[..., 2] = p0 * q2 - p1 * q3 + p2 * q0 + p3 * q1
    out[..., 3] = p0 * q3 + p1 * q2 - p2 * q1 + p3 * q0
    return out


def quat_conjugate(q):
    q = np.array(q, dtype=float)
    q[..., 1:] *= -1.0
    return q


def rotvec_to_quat(phi):
    """Quaternion of a rotation vector (thesis 2.16)."""
    phi = np.asarray(phi, dtype=float)
    half = 0.5 * np.linalg.norm(phi, axis=-1)
    small = half < 1e-8
    safe = np.where(small, 1.0, half)
    s = np.where(small, 0.5 - half**2 / 12.0, 0.5 * np.sin(safe) / safe)
    out = np.empty(phi.shape[:-1] + (4,))
    out[..., 0] = np.cos(half)
    out[..., 1:] = s[..., None] * phi
    return out


def quat_to_rotvec(q):
    q = np.asarray(q, dtype=float)
    q = np.where(q[..., :1] < 0.0, -q, q)  # shortest rotation
    vnorm = np.linalg.norm(q[..., 1:], axis=-1)
    half = np.arctan2(vnorm, q[..., 0])
    small = vnorm < 1e-12
    scale = np.where(small, 2.0 / np.where(q[..., 0] == 0, 1.0, q[..., 0]), 2.0 * half / np.where(small, 1.0, vnorm))
    return scale[..., None] * q[..., 1:]


def quat_to_dcm(q):
    q = np.asarray(q, dtype=float)
    q0, q1, q2, q3 = (q[..., i] for i in range(4))
    c = np.empty(q.shape[:-1] + (3, 3))
    c[..., 0, 0] = q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3
    c[..., 0, 1] = 2.0 * (q1 * q2 - q0 * q3)
    c[..., 0, 2] = 2.0 * (q1 * q3 + q0 * q2)
    c[..., 1, 0] = 2.0 * (q1 * q2 + q0 * q3)
    c[..., 1, 1] = q0 * q0 - q1 * q1 + q2 * q2 - q3 * q3
    c[..., 1, 2] = 2.0 * (q2 * q3 - q0 * q1)
    c[..., 2, 0] = 2.0 * (q1 * q3 - q0 * q2)
    c[..., 2, 1] = 2.0 * (q2 * q3 + q0 * q1)
    c[..., 2, 2] = q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3
    return c


def dcm_to_quat(c):
    """Quaternion (scalar first, q0 >= 0) of a DCM, numerically robust (Shepperd)."""
    c = np.asarray(c, dtype=float)
    tr = c[..., 0, 0] + c[..., 1, 1] + c[..., 2, 2]
    cand = np.stack([tr, c[..., 0, 0], c[..., 1, 1], c[..., 2, 2]], axis=-1)
    k = np.argmax(cand, axis=-1)
    q = np.empty(c.shape[:-2] + (4,))
    # Four branches, each well conditioned where its pivot is the largest.
    r = np.sqrt(np.maximum(1.0 + 2.0 * np.take_along_axis(cand, k[..., None], -1)[..., 0] - tr, 1e-300))
    b0 = k == 0
    b1 = k == 1
    b2 = k == 2
    b3 = k == 3
    q[..., 0] = np.select([b0, b1, b2, b3], [0.5 * r, (c[..., 2, 1] - c[..., 1, 2]) / (2 * r), (c[..., 0, 2] - c[..., 2, 0]) / (2 * r), (c[..., 1, 0] - c[..., 0, 1]) / (2 * r)])
    q[..., 1] = np.select([b0, b1, b2, b3], [(c[..., 2, 1] - c[..., 1, 2]) / (2 * r), 0.5 * r, (c[..., 0, 1] + c[..., 1, 0]) / (2 * r), (c[..., 0, 2] + c[..., 2, 0]) / (2 * r)])
    q[..., 2] = np.select([b0, b1, b2, b3], [(c[..., 0, 2] - c[..., 2, 0]) / (2 * r), (c[..., 0, 1] + c[..., 1, 0]) / (2 * r), 0.5 * r, (c[..., 1, 2] + c[..., 2, 1]) / (2 * r)])
    q[..., 3] = np.select([b0, b1, b2, b3], [(c[..., 1, 0] - c[..., 0, 1]) / (2 * r), (c[..., 0, 2] + c[..., 2, 0]) / (2 * r), (c[..., 1, 2] + c[..., 2, 1]) / (2 * r), 0.5 * r])
    return np.where(q[..., :1] < 0.0, -q, q)


def euler_rates_to_body_rate(roll, pitch, roll_rate, pitch_rate, heading_rate):
    """omega_nb^b [rad/s] from z-y-x Euler angle rates, shape (..., 3)."""
    cr, sr = np.cos(roll), np.sin(roll)
    cp, sp = np.cos(pitch), np.sin(pitch)
    w = np.empty(np.broadcast_shapes(np.shape(roll), np.shape(heading_rate)) + (3,))
    w[..., 0] = roll_rate - heading_rate * sp
    w[..., 1] = pitch_rate * cr + heading_rate * sr * cp
    w[..., 2] = -pitch_rate * sr + heading_rate * cr * cp
    return w
