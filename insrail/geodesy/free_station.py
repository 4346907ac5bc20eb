"""Free-station resection of a total station on CPIII points, and the prism positions it measures.

A total station set up anywhere (a "free station") observes known CPIII points: horizontal
direction Hz (clockwise, from the circle's arbitrary zero), zenith angle V and slope distance D to
each. In the instrument's frame a target lies at

    d = D sin V,   x = d sin Hz,   y = d cos Hz,   z = D cos V + (1 - k) d^2 / (2 R)

(d horizontal distance; z the height above the trunnion axis with the curvature and refraction
term, k = 0.13, R = 6 371 km: 0.7 mm at 100 m). The station's plan position (E0, N0) and the
orientation w of its circle (the grid azimuth of Hz = 0) follow from the points by the closed-form
rigid fit E = E0 + x cos w + y sin w, N = N0 - x sin w + y cos w (no scale: the distance meter's
scale is calibrated, and a free scale would swallow the error of a wrong point); the station height
H0 is the mean of H - z. Prism positions observed from the station are then placed the same way.

The residuals check the CPIII points: each point is also predicted from the others alone
(leave-one-out), which shows a point that does not fit at its full error instead of spread over
all. The leave-one-out residual is tested against its own spread (:func:`_left_out_test`): the
pointing's precision (``ANGLE_SIGMA_RAD`` across the line of sight and in height, ``DISTANCE_SIGMA_M``
along it) propagated through the fit of the others, scaled by the variance factor of the others' residuals
(the set-up's own sigma, pooled with the instrument's, 1, counted as ``PRIOR_DOF`` redundant
observations: a set-up of three or four points still has a scale). Plan (2 degrees of freedom) and
height (1) are F-tested at ``SIGNIFICANCE`` each. A point that fails is named and, with ``reject``,
left out (one at a time, the worst first, while at least three remain). Angles in radians, distances
in metres, engineering grid E, N and normal heights H (see :mod:`insrail.geodesy`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.special import fdtri

REFRACTION_K = 0.13
EARTH_RADIUS_M = 6_371_000.0
#: The pointing's precision: 0.3 mgon (1") in direction and zenith angle, the distance meter's 0.6 mm.
ANGLE_SIGMA_RAD = 0.3e-3 * np.pi / 200.0
DISTANCE_SIGMA_M = 0.0006
#: The chance that the leave-one-out test names a good CPIII point, per point and test (plan, height).
#: Measured on 1500 random good set-ups of 8 points (4 CPIII pairs 60 m apart, 0.3 mgon, 0.5 mm): 1
#: names a good point (0.07 %; a fixed 2 mm tolerance: 6, 0.4 %), and a point 5 mm off in plan, in a
#: random direction, is named alone in 1489 (99.3 %).
SIGNIFICANCE = 1e-3
#: How many redundant observations the pointing's stated precision counts as beside a set-up's own
#: (its residuals' Satterthwaite degrees of freedom for 8 points: 4-9 in plan, 2-5 in height): 10 instead of 3
#: names no good point in those 1500 but scales too little, a set-up 3 times noisier names good points.
PRIOR_DOF = 3
MIN_POINTS = 3


@dataclass(frozen=True)
class PolarObservations:
    """Observations from one set-up (arrays of equal length): horizontal direction, zenith angle [rad],
    slope distance [m] to each target (named by ``target``)."""

    target: tuple[str, ...]
    hz_rad: np.ndarray
    zenith_rad: np.ndarray
    slope_m: np.ndarray

    def local(self) -> np.ndarray:
        """(n, 3) x, y, z of each target in the instrument's frame (see the module docstring)."""
        d = self.slope_m * np.sin(self.zenith_rad)
        z = self.slope_m * np.cos(self.zenith_rad) + (1.0 - REFRACTION_K) * d**2 / (2.0 * EARTH_RADIUS_M)
        return np.column_stack([d * np.sin(self.hz_rad), d * np.cos(self.hz_rad), z])


@dataclass(frozen=True)
class PointCheck:
    """One CPIII point of a resection: its residuals (known minus fitted, [m]) with all points and when
    left out, and whether it was used."""

    name: str
    residual_enh_m: np.ndarray  # (3,) with the solution
    left_out_residual_plan_m: float  # plan distance to its position predicted by the other points
    left_out_residual_height_m: float
    used: bool
    #: the leave-one-out test (plan or height, the larger) over its critical value: > 1 does not fit
    test_ratio: float


@dataclass(frozen=True)
class FreeStation:
    """The station: plan position, height of the trunnion axis, circle orientation; its points' checks."""

    east_m: float
    north_m: float
    height_m: float
    orientation_rad: float
    points: tuple[PointCheck, ...]
    rms_plan_m: float  # of the used points' plan residuals
    rms_height_m: float

    @property
    def rejected(self) -> tuple[str, ...]:
        """The CPIII points that do not fit (left out of the solution)."""
        return tuple(p.name for p in self.points if not p.used)

    def place(self, observations: PolarObservations) -> np.ndarray:
        """(n, 3) E, N, H of targets observed from this station (the trolley's prism)."""
        x, y, z = observations.local().T
        c, s = np.cos(self.orientation_rad), np.sin(self.orientation_rad)
        return np.column_stack([self.east_m + x * c + y * s, self.north_m - x * s + y * c, self.height_m + z])


def _fit(local: np.ndarray, known: np.ndarray) -> tuple[float, float, float, float]:
    """(E0, N0, H0, w) of the rigid plan fit and the mean height (module docstring)."""
    x, y, z = local.T
    e, n, h = known.T
    xm, ym, em, nm = x.mean(), y.mean(), e.mean(), n.mean()
    xc, yc, ec, nc = x - xm, y - ym, e - em, n - nm
    w = np.arctan2(np.sum(ec * yc - nc * xc), np.sum(ec * xc + nc * yc))
    c, s = np.cos(w), np.sin(w)
    return em - (xm * c + ym * s), nm - (ym * c - xm * s), float(np.mean(h - z)), float(w)


def _predict(parameters, local: np.ndarray) -> np.ndarray:
    e0, n0, h0, w = parameters
    x, y, z = local.T
    c, s = np.cos(w), np.sin(w)
    return np.column_stack([e0 + x * c + y * s, n0 - x * s + y * c, h0 + z])


def _pointing_variances(observations: PolarObservations) -> tuple[np.ndarray, np.ndarray]:
    """Per target the a-priori covariance of its local plan x, y ((n, 2, 2)) and variance of z (n,)."""
    d = observations.slope_m * np.sin(observations.zenith_rad)
    u = np.column_stack([np.sin(observations.hz_rad), np.cos(observations.hz_rad)])  # line of sight
    outer = u[:, :, None] * u[:, None, :]
    across = (ANGLE_SIGMA_RAD * d) ** 2
    plan = DISTANCE_SIGMA_M**2 * outer + across[:, None, None] * (np.eye(2) - outer)
    height = (ANGLE_SIGMA_RAD * observations.slope_m) ** 2 + (DISTANCE_SIGMA_M * np.cos(observations.zenith_rad)) ** 2
    return plan, height


def _left_out_test(local, known, plan_cov, height_var, used, i, significance) -> tuple[np.ndarray, float]:
    """Point i predicted from the other used points: its residual (known minus predicted, (3,)) and the
    larger of its plan and height test statistics over their critical values (module docstring)."""
    others = used.copy()
    others[i] = False
    parameters = _fit(local[others], known[others])
    residual = known - _predict(parameters, local)
    c, s = np.cos(parameters[3]), np.sin(parameters[3])
    rot = np.array([[c, s], [-s, c]])  # local plan -> grid
    grid_cov = rot @ plan_cov @ rot.T
    x, y = local[:, 0], local[:, 1]
    jac = np.zeros((len(local), 2, 3))  # d(E, N) / d(E0, N0, w)
    jac[:, 0, 0] = jac[:, 1, 1] = 1.0
    jac[:, 0, 2], jac[:, 1, 2] = y * c - x * s, -x * c - y * s
    a, cov = jac[others].reshape(-1, 3), np.zeros((2 * others.sum(),) * 2)
    for k in range(others.sum()):
        cov[2 * k:2 * k + 2, 2 * k:2 * k + 2] = grid_cov[others][k]
    inverse = np.linalg.inv(a.T @ a)
    parameter_cov = inverse @ a.T @ cov @ a @ inverse
    m = int(others.sum())
    spread = np.eye(2 * m) - a @ inverse @ a.T
    # the others' residuals weighted by their pointing's precision: at a variance factor of 1 their sum has
    # the mean trace(M) and the variance 2 trace(M^2), M = W (I - H) C (I - H)^T (the fit is unweighted):
    # a scaled chi-square of trace(M)^2 / trace(M^2) degrees of freedom (Satterthwaite)
    h_others = height_var[others]
    centre = np.eye(m) - 1.0 / m
    ratios = []
    for k, statistic, weighted, M in (
            (2, residual[i, :2] @ np.linalg.solve(grid_cov[i] + jac[i] @ parameter_cov @ jac[i].T, residual[i, :2]),
             sum(r @ np.linalg.solve(g, r) for r, g in zip(residual[others, :2], grid_cov[others])),
             np.linalg.solve(cov, spread @ cov @ spread.T)),
            (1, residual[i, 2] ** 2 / (height_var[i] + h_others.sum() / m**2),
             np.sum(residual[others, 2] ** 2 / h_others), (centre * h_others) @ centre.T / h_others[:, None])):
        expected, dof = np.trace(M), np.trace(M) ** 2 / np.trace(M @ M)
        variance_factor = (dof * weighted / expected + PRIOR_DOF) / (dof + PRIOR_DOF)
        ratios.append(statistic / (k * variance_factor) / fdtri(k, dof + PRIOR_DOF, 1.0 - significance))
    return residual[i], max(ratios)


def resect(observations: PolarObservations, known_enh_m: np.ndarray, significance: float = SIGNIFICANCE,
           reject: bool = True) -> FreeStation:
    """The free station from observations of CPIII points at ``known_enh_m`` ((n, 3), in the order of
    ``observations.target``). Raises ValueError with fewer than :data:`MIN_POINTS` points (or when
    rejecting would leave fewer)."""
    known = np.asarray(known_enh_m, dtype=float).reshape(-1, 3)
    n = len(observations.target)
    if n < MIN_POINTS or known.shape[0] != n:
        raise ValueError(f"a free station needs at least {MIN_POINTS} CPIII points with coordinates, got {n} "
                         f"observations and {known.shape[0]} known points")
    local = observations.local()
    plan_cov, height_var = _pointing_variances(observations)
    used = np.ones(n, dtype=bool)
    checks = {}
    while True:
        checks = {i: _left_out_test(local, known, plan_cov, height_var, used, i, significance)
                  for i in np.flatnonzero(used)}
        worst = max(checks, key=lambda i: checks[i][1])
        if not reject or checks[worst][1] <= 1.0 or used.sum() <= MIN_POINTS:
            break
        used[worst] = False
    if reject and checks[worst][1] > 1.0:
        names = ", ".join(observations.target[i] for i in checks if checks[i][1] > 1.0)
        residual = checks[worst][0]
        raise ValueError(f"free station: CPIII points {names} do not fit (leave-one-out residual "
                         f"{1e3 * np.hypot(*residual[:2]):.1f} mm in plan, {1e3 * abs(residual[2]):.1f} mm in height, "
                         f"{checks[worst][1]:.1f} times its test's limit) and too few points remain to tell which "
                         f"is wrong")
    # a left-out point's check is against the solution of all the used points
    all_used = used.copy()
    for i in np.flatnonzero(~used):
        all_used[i] = True
        checks[i] = _left_out_test(local, known, plan_cov, height_var, all_used, i, significance)
        all_used[i] = False
    parameters = _fit(local[used], known[used])
    residual = known - _predict(parameters, local)
    points = tuple(PointCheck(observations.target[i], residual[i], float(np.hypot(*checks[i][0][:2])),
                              float(abs(checks[i][0][2])), bool(used[i]), float(checks[i][1])) for i in range(n))
    return FreeStation(*parameters[:3], parameters[3], points,
                       float(np.sqrt(np.mean(np.sum(residual[used, :2] ** 2, axis=1)))),
                       float(np.sqrt(np.mean(residual[used, 2] ** 2))))
