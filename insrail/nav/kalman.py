"""The Kalman filter's three operations, free of anything about sensors or navigation.

``gated_update`` applies one measurement (innovation z = predicted - measured, Jacobian H,
noise R) to the error state x and its covariance P after a chi-square test of the
normalised innovation squared (NIS) against ``gate``; ``inflate`` is the filter reset that
widens chosen variances when the filter has lost its way; ``rts_step`` is one step of the
Rauch-Tung-Striebel smoother for the closed-loop filter of ``insrail.nav.fusion``.

Every function takes and returns plain float64 arrays (no objects), so that a later
compiled filter loop can call compiled versions of them unchanged.
"""

from __future__ import annotations

import numpy as np


def gated_update(x: np.ndarray, P: np.ndarray, z: np.ndarray, H: np.ndarray, R: np.ndarray, gate: float):
    """One gated measurement update: (x, P, nu, nis, accepted).

    nu = z - H x is the innovation against the current estimate and nis = nu^T S^-1 nu with
    S = H P H^T + R. A measurement with nis > gate is rejected: x and P come back unchanged.
    Otherwise the gain K = P H^T S^-1 updates x and P in Joseph form (symmetric and positive
    for any gain, which matters with gains as large as a 1 mm GNSS fix gives)."""
    nu = z - H @ x
    S = H @ P @ H.T + R
    nis = float(nu @ np.linalg.solve(S, nu))
    if not nis <= gate:  # NaN is rejected too
        return x, P, nu, nis, False
    K = np.linalg.solve(S, H @ P).T
    x = x + K @ nu
    I_KH = np.eye(P.shape[0]) - K @ H
    P = I_KH @ P @ I_KH.T + K @ R @ K.T
    return x, P, nu, nis, True


def inflate(P: np.ndarray, states: np.ndarray, sigma_floor: np.ndarray) -> np.ndarray:
    """The filter reset: the variances of ``states`` raised to at least ``sigma_floor``**2 by
    adding to the diagonal (a burst of process noise: the correlations shrink, P stays
    positive and the RTS smoother stays consistent across the reset). Returns a new P."""
    P = P.copy()
    P[states, states] += np.maximum(np.square(sigma_floor) - P[states, states], 0.0)
    return P


def rts_step(e_next: np.ndarray, P_s_next: np.ndarray, phi_next: np.ndarray, p_minus_next: np.ndarray,
             p_plus: np.ndarray):
    """One backward step of the RTS smoother: (e_j, P_s_j) from epoch j+1's smoothed error
    e_next (relative to j+1's pre-update solution) and covariance P_s_next, the transition
    phi_next and predicted covariance p_minus_next of the segment j -> j+1, and P+_j.
    A_j = P+_j Phi^T (P-_{j+1})^-1 (thesis 2.93-2.95)."""
    A = np.linalg.solve(p_minus_next.T, (p_plus @ phi_next.T).T).T
    return A @ e_next, p_plus + A @ (P_s_next - p_minus_next) @ A.T
