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
all. A point whose leave-one-out plan or height residual exceeds the tolerance is named and, with
``reject``, left out (one at a time, the worst first, while at least three remain). Angles in
radians, distances in metres, engineering grid E, N and normal heights H (see
:mod:`insrail.geodesy`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

REFRACTION_K = 0.13
EARTH_RADIUS_M = 6_371_000.0
#: Largest leave-one-out residual of a CPIII point that still fits [m] (plan and height apart): well
#: above the sub-millimetre residuals of a good set-up, well below a mis-surveyed point's 5 mm.
DEFAULT_TOLERANCE_M = 0.002
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


def _left_out(local: np.ndarray, known: np.ndarray, used: np.ndarray, i: int) -> np.ndarray:
    others = used.copy()
    others[i] = False
    return known[i] - _predict(_fit(local[others], known[others]), local[i:i + 1])[0]


def resect(observations: PolarObservations, known_enh_m: np.ndarray, tolerance_m: float = DEFAULT_TOLERANCE_M,
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
    used = np.ones(n, dtype=bool)
    while True:
        left_out = np.array([_left_out(local, known, used, i) if used[i] else np.full(3, np.nan) for i in range(n)])
        plan = np.hypot(left_out[:, 0], left_out[:, 1])
        height = np.abs(left_out[:, 2])
        badness = np.where(used, np.maximum(plan, height), -np.inf)
        worst = int(np.argmax(badness))
        if not reject or badness[worst] <= tolerance_m or used.sum() <= MIN_POINTS:
            break
        used[worst] = False
    if reject and badness[worst] > tolerance_m:
        names = ", ".join(observations.target[i] for i in np.flatnonzero(badness > tolerance_m))
        raise ValueError(f"free station: CPIII points {names} do not fit (leave-one-out residual "
                         f"{1e3 * badness[worst]:.1f} mm > {1e3 * tolerance_m:.1f} mm) and too few points remain "
                         f"to tell which is wrong")
    parameters = _fit(local[used], known[used])
    residual = known - _predict(parameters, local)
    # a left-out point's check is its residual against the solution of the others
    left_out = np.array([_left_out(local, known, used, i) if used[i] else residual[i] for i in range(n)])
    points = tuple(PointCheck(observations.target[i], residual[i], float(np.hypot(*left_out[i, :2])),
                              float(abs(left_out[i, 2])), bool(used[i])) for i in range(n))
    return FreeStation(*parameters[:3], parameters[3], points,
                       float(np.sqrt(np.mean(np.sum(residual[used, :2] ** 2, axis=1)))),
                       float(np.sqrt(np.mean(residual[used, 2] ** 2))))
