"""The Kalman filter's three operations, free of anything about sensors or navigation.

``gated_update`` applies one measurement (innovation z = predicted - measured, Jacobian H,
noise R) to the error state x and its covariance P after a chi-square test of the
normalised innovation squared (NIS) against ``gate``; ``inflate`` is the filter reset that
widens chosen variances when the filter has lost its way; ``rts_step`` is one step of the
Rauch-Tung-Striebel smoother for the closed-loop filter of ``insrail.nav.fusion``.

The work is done by compiled (numba) functions on plain float64 arrays, in place, so the
compiled filter loop of ``insrail.nav.fusion`` calls them per update without any Python;
``gated_update`` and ``inflate`` are their array-in, array-out forms for Python callers.
"""

from __future__ import annotations

import math

import numpy as np
from numba import _helperlib, types

from insrail.jit import cached_njit

compiled = cached_njit(error_model="numpy")

# LAPACK's dgesv called as numba's np.linalg.solve calls it: through numba's C helper numba_xgesv, which finds
# dgesv in scipy.linalg.cython_lapack. The same routine on the same numbers gives solve's result to the bit;
# solve itself copies its right-hand side in by a slice assignment, which compiles numba's message of a shape
# mismatch (shapes formatted into a string: seconds of a first run's compiling, insrail.jit).
_LAPACK_INT = np.int64 if getattr(_helperlib, "LAPACK_BUILD_ILP64", False) else np.int32  # numba's F_INT
_XGESV = types.ExternalFunction("numba_xgesv", types.intc(
    types.char, types.intp, types.intp, types.CPointer(types.float64), types.intp,
    types.CPointer(types.int64 if _LAPACK_INT is np.int64 else types.int32), types.CPointer(types.float64), types.intp))
_DOUBLE = ord("d")


@compiled
def update_in_place(x, P, z, H, R, m, gate, nu):
    """One gated update of (x, P) in place with the first ``m`` rows of z, H and R; the
    innovation nu = z - H x goes to ``nu``. Returns (nis, accepted).

    nis = nu^T S^-1 nu with S = H P H^T + R (Cholesky; a non-positive S gives NaN). A
    measurement with nis > gate (or NaN) is rejected: x and P stay unchanged. Otherwise the
    gain K = P H^T S^-1 updates x and P in Joseph form, (I - K H) P (I - K H)^T + K R K^T,
    evaluated as two rank-m corrections (symmetric and positive for any gain, which matters
    with gains as large as a 1 mm GNSS fix gives). H's zeros are skipped."""
    n = x.shape[0]
    HP = np.zeros((m, n))
    for a in range(m):
        s = z[a]
        for k in range(n):
            h = H[a, k]
            if h != 0.0:
                s -= h * x[k]
                for c in range(n):
                    HP[a, c] += h * P[k, c]
        nu[a] = s
    # S and its Cholesky factor L (lower)
    L = np.zeros((m, m))
    for a in range(m):
        for b in range(a + 1):
            s = R[a, b]
            for k in range(n):
                h = H[b, k]
                if h != 0.0:
                    s += HP[a, k] * h
            for c in range(b):
                s -= L[a, c] * L[b, c]
            if a == b:
                if not s > 0.0:
                    return math.nan, False
                L[a, a] = math.sqrt(s)
            else:
                L[a, b] = s / L[b, b]
    # y = L^-1 nu: nis = |y|^2
    y = np.empty(m)
    nis = 0.0
    for a in range(m):
        s = nu[a]
        for c in range(a):
            s -= L[a, c] * y[c]
        y[a] = s / L[a, a]
        nis += y[a] * y[a]
    if not nis <= gate:
        return nis, False
    # K^T = S^-1 H P (m x n): forward and back substitution on every column
    Kt = HP.copy()
    for col in range(n):
        for a in range(m):
            s = Kt[a, col]
            for c in range(a):
                s -= L[a, c] * Kt[c, col]
            Kt[a, col] = s / L[a, a]
        for a in range(m - 1, -1, -1):
            s = Kt[a, col]
            for c in range(a + 1, m):
                s -= L[c, a] * Kt[c, col]
            Kt[a, col] = s / L[a, a]
    for a in range(m):
        for k in range(n):
            x[k] += Kt[a, k] * nu[a]
    # P1 = (I - K H) P = P - K (H P)
    for i in range(n):
        for j in range(n):
            s = P[i, j]
            for a in range(m):
                s -= Kt[a, i] * HP[a, j]
            P[i, j] = s
    # P1 H^T, then P1 (I - K H)^T = P1 - (P1 H^T) K^T, plus K R K^T
    P1Ht = np.zeros((n, m))
    for a in range(m):
        for k in range(n):
            h = H[a, k]
            if h != 0.0:
                for i in range(n):
                    P1Ht[i, a] += P[i, k] * h
    KR = np.zeros((n, m))
    for i in range(n):
        for b in range(m):
            s = 0.0
            for a in range(m):
                s += Kt[a, i] * R[a, b]
            KR[i, b] = s
    for i in range(n):
        for j in range(n):
            s = P[i, j]
            for a in range(m):
                s += (KR[i, a] - P1Ht[i, a]) * Kt[a, j]
            P[i, j] = s
    return nis, True


@compiled
def inflate_in_place(P, sigma_floor):
    """The filter reset: every variance whose ``sigma_floor`` is not NaN raised to at least
    sigma_floor**2 by adding to the diagonal (a burst of process noise: the correlations
    shrink, P stays positive and the RTS smoother stays consistent across the reset)."""
    for k in range(P.shape[0]):
        s = sigma_floor[k]
        if not math.isnan(s):
            P[k, k] += max(s * s - P[k, k], 0.0)


def gated_update(x: np.ndarray, P: np.ndarray, z: np.ndarray, H: np.ndarray, R: np.ndarray, gate: float):
    """:func:`update_in_place` on copies: (x, P, nu, nis, accepted); rejected, x and P come
    back as they were given."""
    x_new, P_new = np.array(x, dtype=float), np.array(P, dtype=float)
    z, H, R = (np.ascontiguousarray(a, dtype=float) for a in (z, H, R))
    nu = np.empty(len(z))
    nis, ok = update_in_place(x_new, P_new, z, H, R, len(z), float(gate), nu)
    return (x_new, P_new, nu, float(nis), True) if ok else (x, P, nu, float(nis), False)


def inflate(P: np.ndarray, states: np.ndarray, sigma_floor: np.ndarray) -> np.ndarray:
    """:func:`inflate_in_place` of ``states`` on a copy of P."""
    P = np.array(P, dtype=float)
    floor = np.full(len(P), np.nan)
    floor[np.asarray(states)] = sigma_floor
    inflate_in_place(P, floor)
    return P


@compiled
def rts_step(e_next, P_s_next, phi_next, p_minus_next, p_plus):
    """One backward step of the RTS smoother: (e_j, P_s_j) from epoch j+1's smoothed error
    e_next (relative to j+1's pre-update solution) and covariance P_s_next, the transition
    phi_next and predicted covariance p_minus_next of the segment j -> j+1, and P+_j:
    :func:`rts_smoothed` with the gain :func:`rts_gain` (thesis 2.93-2.95)."""
    return rts_smoothed(rts_gain(phi_next, p_minus_next, p_plus), e_next, P_s_next, p_minus_next, p_plus)


@compiled
def solve_transposed(a_t, b_t):
    """np.linalg.solve(a, b) for a = a_t^T (n x n) and b = b_t^T (n x k), in place and to the bit: C-ordered,
    a_t and b_t are a and b in Fortran's order, as LAPACK takes them (the copies solve makes); b_t becomes
    the solution's transpose, a_t a's LU factors. Errors as solve's: LinAlgError for an infinite or NaN
    entry and for a singular a."""
    n, k = b_t.shape[1], b_t.shape[0]
    for i in range(n):
        for j in range(n):
            if not math.isfinite(a_t[i, j]):
                raise np.linalg.LinAlgError("Array must not contain infs or NaNs.")
        for c in range(k):
            if not math.isfinite(b_t[c, i]):
                raise np.linalg.LinAlgError("Array must not contain infs or NaNs.")
    pivots = np.empty(n, dtype=_LAPACK_INT)
    if _XGESV(_DOUBLE, n, k, a_t.ctypes, n, pivots.ctypes, b_t.ctypes, n) != 0:
        raise np.linalg.LinAlgError("Matrix is singular to machine precision.")


@compiled
def rts_gain(phi_next, p_minus_next, p_plus):
    """The smoother gain A_j = P+_j Phi^T (P-_{j+1})^-1 of :func:`rts_step`, C-ordered. It needs the
    forward pass's quantities only, none of the smoothed ones: the gains can be made ahead of the
    backward recursion (``insrail.nav.fusion._rts``). A^T solves P-^T A^T = (P+ Phi^T)^T."""
    gain = p_plus @ phi_next.T  # (P+ Phi^T)^T in Fortran's order
    solve_transposed(p_minus_next.copy(), gain)
    return gain


@compiled
def rts_smoothed(A, e_next, P_s_next, p_minus_next, p_plus):
    """(e_j, P_s_j) of :func:`rts_step` from its gain ``A`` (:func:`rts_gain`). The sums element by
    element: numba compiles an array expression as a loop of its own, and that for each of them."""
    n = A.shape[0]
    difference = np.empty((n, n))
    a_t = np.empty((n, n))
    for i in range(n):
        for j in range(n):
            difference[i, j] = P_s_next[i, j] - p_minus_next[i, j]
            a_t[i, j] = A[j, i]
    smoothed = A @ difference @ a_t
    for i in range(n):
        for j in range(n):
            smoothed[i, j] = p_plus[i, j] + smoothed[i, j]
    return A @ e_next, smoothed
