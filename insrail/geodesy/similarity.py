"""Similarity transformations estimated from common points.

* 4-parameter plane similarity (``Similarity2D``)::

      [E']   [tE]       [cos θ  -sin θ] [E]
      [N'] = [tN] + s · [sin θ   cos θ] [N]

  θ is counter-clockwise in the (E, N) plane: a positive θ turns east towards north,
  so grid azimuths (clockwise from north) decrease by θ.

* 7-parameter spatial Helmert (``Helmert7``, Bursa-Wolf)::

      X' = T + (1 + m) · R(rx, ry, rz) · X,   R = R1(rx) R2(ry) R3(rz)

  in the *coordinate frame rotation* convention (EPSG method 1032, the 布尔莎 model of
  Chinese textbooks): to first order R = [[1, rz, -ry], [-rz, 1, rx], [ry, -rx, 1]].
  The exact product of the three rotations is used, so a fit and its ``apply`` agree
  exactly; for published arc-second parameters the difference from the linearised
  matrix is below 0.2 mm. Position-vector parameters (EPSG 1033) are the same with the
  rotation signs flipped.

Fits are unweighted least squares (closed form, Umeyama 1991 for the rotation). Each
fit reports residuals per point (observed target minus transformed source), RMS, the
a-posteriori σ0, parameter standard deviations (σ0-scaled), and *leave-one-out*
residuals: each point predicted by the transformation fitted without it - the honest
check of a control point, since a bad point hides in its own residual.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from insrail.geodesy._validation import Problems
from insrail.geodesy.errors import FitError

ARCSEC = math.pi / (180.0 * 3600.0)
#: Plausibility limits: beyond them the point lists almost surely do not correspond.
DEFAULT_MAX_SCALE_DEVIATION_PPM = 1000.0
DEFAULT_MAX_HELMERT_ROTATION_RAD = 1e-3  # ≈ 206″; datum rotations are a few arc-seconds
_MAX_TRANSLATION_M = 1e8


# --------------------------------------------------------------------------------------
# Parameter sets
# --------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Similarity2D:
    """4-parameter plane similarity; see the module docstring for the convention."""

    translation_east_m: float
    translation_north_m: float
    rotation_rad: float
    scale: float

    @property
    def scale_ppm(self) -> float:
        return (self.scale - 1.0) * 1e6

    def _matrix(self) -> np.ndarray:
        c, s = math.cos(self.rotation_rad), math.sin(self.rotation_rad)
        return self.scale * np.array([[c, -s], [s, c]])

    def apply(self, en) -> np.ndarray:
        """Transform points of shape (..., 2) [m]."""
        en = np.asarray(en, dtype=float)
        return en @ self._matrix().T + np.array([self.translation_east_m, self.translation_north_m])

    def inverse(self) -> Similarity2D:
        inv = np.linalg.inv(self._matrix())
        t = -inv @ np.array([self.translation_east_m, self.translation_north_m])
        return Similarity2D(float(t[0]), float(t[1]), -self.rotation_rad, 1.0 / self.scale)

    def to_settings(self) -> dict[str, float]:
        return {
            "translation_east_m": self.translation_east_m,
            "translation_north_m": self.translation_north_m,
            "rotation_arcsec": self.rotation_rad / ARCSEC,
            "scale_ppm": self.scale_ppm,
        }

    @classmethod
    def from_settings(cls, settings: Mapping[str, Any], key_path: str = "geodesy.similarity_2d") -> Similarity2D:
        problems = Problems(key_path)
        if problems.check_mapping(settings):
            problems.unknown_keys(settings, ["translation_east_m", "translation_north_m", "rotation_arcsec",
                                             "scale_ppm"])
            te = problems.number(settings, "translation_east_m", None, -_MAX_TRANSLATION_M, _MAX_TRANSLATION_M, "m")
            tn = problems.number(settings, "translation_north_m", None, -_MAX_TRANSLATION_M, _MAX_TRANSLATION_M, "m")
            rot = problems.number(settings, "rotation_arcsec", None, -648000.0, 648000.0, "arc-seconds")
            ppm = problems.number(settings, "scale_ppm", None, -DEFAULT_MAX_SCALE_DEVIATION_PPM,
                                  DEFAULT_MAX_SCALE_DEVIATION_PPM, "ppm")
        problems.raise_if_any()
        return cls(te, tn, rot * ARCSEC, 1.0 + ppm * 1e-6)


@dataclass(frozen=True)
class Helmert7:
    """7-parameter Helmert (coordinate frame rotation); see the module docstring."""

    tx_m: float
    ty_m: float
    tz_m: float
    rx_rad: float
    ry_rad: float
    rz_rad: float
    scale_ppm: float

    def rotation_matrix(self) -> np.ndarray:
        return _rotation_matrix(self.rx_rad, self.ry_rad, self.rz_rad)

    def apply(self, xyz) -> np.ndarray:
        """Transform points of shape (..., 3) [m]."""
        xyz = np.asarray(xyz, dtype=float)
        m = (1.0 + self.scale_ppm * 1e-6) * self.rotation_matrix()
        return xyz @ m.T + np.array([self.tx_m, self.ty_m, self.tz_m])

    def to_settings(self) -> dict[str, float]:
        return {
            "tx_m": self.tx_m, "ty_m": self.ty_m, "tz_m": self.tz_m,
            "rx_arcsec": self.rx_rad / ARCSEC, "ry_arcsec": self.ry_rad / ARCSEC, "rz_arcsec": self.rz_rad / ARCSEC,
            "scale_ppm": self.scale_ppm,
        }

    @classmethod
    def from_settings(cls, settings: Mapping[str, Any], key_path: str = "geodesy.helmert_7") -> Helmert7:
        problems = Problems(key_path)
        keys = ["tx_m", "ty_m", "tz_m", "rx_arcsec", "ry_arcsec", "rz_arcsec", "scale_ppm"]
        values: dict[str, float | None] = {}
        if problems.check_mapping(settings):
            problems.unknown_keys(settings, keys)
            max_arcsec = DEFAULT_MAX_HELMERT_ROTATION_RAD / ARCSEC
            for key in keys[:3]:
                values[key] = problems.number(settings, key, None, -1e5, 1e5, "m")
            for key in keys[3:6]:
                values[key] = problems.number(settings, key, None, -max_arcsec, max_arcsec, "arc-seconds")
            values["scale_ppm"] = problems.number(settings, "scale_ppm", None, -DEFAULT_MAX_SCALE_DEVIATION_PPM,
                                                  DEFAULT_MAX_SCALE_DEVIATION_PPM, "ppm")
        problems.raise_if_any()
        return cls(values["tx_m"], values["ty_m"], values["tz_m"], values["rx_arcsec"] * ARCSEC,
                   values["ry_arcsec"] * ARCSEC, values["rz_arcsec"] * ARCSEC, values["scale_ppm"])


# --------------------------------------------------------------------------------------
# Fit results
# --------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class Similarity2DFit:
    """Result of ``fit_similarity_2d``.

    ``residuals_m`` and ``loo_residuals_m`` have shape (n, 2): observed target minus
    transformed source (east, north). ``rms_m`` is the horizontal point RMS
    sqrt(mean(vE² + vN²)); ``sigma0_m`` the a-posteriori σ of one coordinate
    (redundancy 2n − 4). ``parameter_std`` holds σ of each ``Similarity2D`` field.
    """

    parameters: Similarity2D
    residuals_m: np.ndarray
    rms_m: float
    sigma0_m: float
    loo_residuals_m: np.ndarray
    loo_rms_m: float
    parameter_std: dict[str, float]

    def apply(self, en) -> np.ndarray:
        return self.parameters.apply(en)


@dataclass(frozen=True, eq=False)
class Helmert7Fit:
    """Result of ``fit_helmert_7``; residual arrays have shape (n, 3), RMS is the 3-D point RMS.

    ``loo_residuals_m`` rows are NaN where leaving the point out leaves a collinear set
    (no check possible); ``warnings`` says which.
    """

    parameters: Helmert7
    residuals_m: np.ndarray
    rms_m: float
    sigma0_m: float
    loo_residuals_m: np.ndarray
    loo_rms_m: float
    parameter_std: dict[str, float]
    warnings: tuple[str, ...] = ()

    def apply(self, xyz) -> np.ndarray:
        return self.parameters.apply(xyz)


# --------------------------------------------------------------------------------------
# Fitting
# --------------------------------------------------------------------------------------
def fit_similarity_2d(src_en, dst_en, *,
                      max_scale_deviation_ppm: float = DEFAULT_MAX_SCALE_DEVIATION_PPM) -> Similarity2DFit:
    """Fit ``dst ≈ Similarity2D.apply(src)`` from n ≥ 3 common points, arrays of shape (n, 2) [m]."""
    src, dst = _common_points(src_en, dst_en, 2, minimum=3, what="4-parameter transformation",
                              why="2 determine the 4 parameters; the 3rd is the first check")
    spread = np.sqrt(np.mean(np.sum((src - src.mean(axis=0)) ** 2, axis=1)))
    if spread < 1e-3:
        raise FitError("4-parameter transformation: the source points coincide (spread "
                       f"{spread * 1e3:.3f} mm); rotation and scale are undetermined")
    params, centred_cov_factor, jac_final = _solve_similarity_2d(src, dst)
    residuals = dst - params.apply(src)
    redundancy = 2 * len(src) - 4
    sigma0 = float(np.sqrt(np.sum(residuals**2) / redundancy))

    _refuse_mirrored_points(src, dst, residuals)  # the more specific diagnosis first
    if abs(params.scale_ppm) > max_scale_deviation_ppm:
        raise FitError(_implausible_scale_message("4-parameter", params.scale_ppm, max_scale_deviation_ppm))

    cov = jac_final @ (sigma0**2 * centred_cov_factor) @ jac_final.T
    std = dict(zip(("translation_east_m", "translation_north_m", "rotation_rad", "scale"),
                   np.sqrt(np.diag(cov)).tolist()))

    loo = np.empty_like(residuals)
    for i in range(len(src)):
        keep = np.arange(len(src)) != i
        loo[i] = dst[i] - _solve_similarity_2d(src[keep], dst[keep])[0].apply(src[i])
    return Similarity2DFit(params, residuals, _point_rms(residuals), sigma0, loo, _point_rms(loo), std)


def fit_helmert_7(src_xyz, dst_xyz, *,
                  max_scale_deviation_ppm: float = DEFAULT_MAX_SCALE_DEVIATION_PPM,
                  max_rotation_rad: float = DEFAULT_MAX_HELMERT_ROTATION_RAD) -> Helmert7Fit:
    """Fit ``dst ≈ Helmert7.apply(src)`` from n ≥ 4 non-collinear points, arrays of shape (n, 3) [m]."""
    src, dst = _common_points(src_xyz, dst_xyz, 3, minimum=4, what="7-parameter transformation",
                              why="3 determine the 7 parameters; the 4th is the first check")
    if _is_collinear(src):
        raise FitError("7-parameter transformation: the common points are (nearly) collinear, so the "
                       "rotation about their line is undetermined; add points off that line")
    params, jacobian = _solve_helmert_7(src, dst)
    residuals = dst - params.apply(src)
    redundancy = 3 * len(src) - 7
    sigma0 = float(np.sqrt(np.sum(residuals**2) / redundancy))

    if abs(params.scale_ppm) > max_scale_deviation_ppm:
        raise FitError(_implausible_scale_message("7-parameter", params.scale_ppm, max_scale_deviation_ppm))
    largest = max(abs(params.rx_rad), abs(params.ry_rad), abs(params.rz_rad))
    if largest > max_rotation_rad:
        raise FitError(f"7-parameter transformation: a fitted rotation of {largest / ARCSEC:.1f}″ exceeds "
                       f"{max_rotation_rad / ARCSEC:.1f}″; datum rotations are a few arc-seconds, so the point "
                       "lists probably do not correspond (point order, X/Y/Z columns). Pass a larger "
                       "max_rotation_rad if this is genuinely expected")

    cov = sigma0**2 * _normal_inverse(jacobian)
    std = dict(zip(("tx_m", "ty_m", "tz_m", "rx_rad", "ry_rad", "rz_rad", "scale_ppm"),
                   np.sqrt(np.diag(cov)).tolist()))

    loo = np.full_like(residuals, np.nan)
    unchecked = []
    for i in range(len(src)):
        keep = np.arange(len(src)) != i
        if _is_collinear(src[keep]):
            unchecked.append(i)
            continue
        loo[i] = dst[i] - _solve_helmert_7(src[keep], dst[keep])[0].apply(src[i])
    warnings = ()
    if unchecked:
        warnings = (f"points {unchecked} cannot be checked by leave-one-out: without each of them the "
                    "others are collinear",)
    checked = loo[np.isfinite(loo[:, 0])]
    loo_rms = _point_rms(checked) if len(checked) else float("nan")
    return Helmert7Fit(params, residuals, _point_rms(residuals), sigma0, loo, loo_rms, std, warnings)


# --------------------------------------------------------------------------------------
# Helpers
# --------------------------------------------------------------------------------------
def _common_points(src, dst, dim: int, minimum: int, what: str, why: str) -> tuple[np.ndarray, np.ndarray]:
    try:
        src = np.asarray(src, dtype=float)
        dst = np.asarray(dst, dtype=float)
    except (TypeError, ValueError):
        raise FitError(f"{what}: common points must be numeric arrays of shape (n, {dim})") from None
    for name, arr in (("source", src), ("target", dst)):
        if arr.ndim != 2 or arr.shape[1] != dim:
            raise FitError(f"{what}: {name} points must have shape (n, {dim}), got {arr.shape}")
    if src.shape != dst.shape:
        raise FitError(f"{what}: {len(src)} source points but {len(dst)} target points; "
                       "each common point needs coordinates in both systems")
    bad = ~(np.isfinite(src).all(axis=1) & np.isfinite(dst).all(axis=1))
    if bad.any():
        raise FitError(f"{what}: points {np.flatnonzero(bad).tolist()} have missing or non-finite coordinates")
    if len(src) < minimum:
        raise FitError(f"{what}: {len(src)} common point(s) given, at least {minimum} are needed ({why})")
    return src, dst


def _point_rms(residuals: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.sum(residuals**2, axis=1))))


def _implausible_scale_message(kind: str, scale_ppm: float, limit_ppm: float) -> str:
    return (f"{kind} transformation: the fitted scale differs from 1 by {scale_ppm:.1f} ppm "
            f"({scale_ppm:.1f} mm/km), beyond the plausible {limit_ppm:g} ppm; the point lists probably do "
            "not correspond (point order, swapped coordinates, mm or feet instead of metres). Pass a larger "
            "max_scale_deviation_ppm if this is genuinely expected")


def _solve_similarity_2d(src: np.ndarray, dst: np.ndarray):
    """Closed-form LS; returns the parameters, (AᵀA)⁻¹ of the centred parameters and the
    Jacobian of (tE, tN, θ, s) with respect to them."""
    src_mean, dst_mean = src.mean(axis=0), dst.mean(axis=0)
    x, y = (src - src_mean).T
    u, v = (dst - dst_mean).T
    # Centred model: u = a x - b y, v = b x + a y  (a = s cos θ, b = s sin θ).
    sxx = np.sum(x * x + y * y)
    a = np.sum(x * u + y * v) / sxx
    b = np.sum(x * v - y * u) / sxx
    scale = math.hypot(a, b)
    rotation = math.atan2(b, a)
    mx, my = src_mean
    te = dst_mean[0] - (a * mx - b * my)
    tn = dst_mean[1] - (b * mx + a * my)
    # Parameters p = (cE, cN, a, b) with cE, cN the target centroid; the design is orthogonal.
    centred_cov_factor = np.diag([1.0 / len(src), 1.0 / len(src), 1.0 / sxx, 1.0 / sxx])
    jac_final = np.array([
        [1.0, 0.0, -mx, my],
        [0.0, 1.0, -my, -mx],
        [0.0, 0.0, -b / scale**2, a / scale**2],
        [0.0, 0.0, a / scale, b / scale],
    ])
    return Similarity2D(float(te), float(tn), rotation, scale), centred_cov_factor, jac_final


def _refuse_mirrored_points(src: np.ndarray, dst: np.ndarray, residuals: np.ndarray) -> None:
    """A mirrored point set (E/N swapped in one list) fits a similarity badly but its mirror image well."""
    mirrored = src[:, ::-1]
    mirrored_params = _solve_similarity_2d(mirrored, dst)[0]
    mirrored_rms = _point_rms(dst - mirrored_params.apply(mirrored))
    rms = _point_rms(residuals)
    if rms > 0.01 and mirrored_rms < 0.1 * rms:
        raise FitError(f"4-parameter transformation: residual RMS {rms:.3f} m, but {mirrored_rms:.3f} m with "
                       "easting and northing swapped in the source points; check the column order "
                       "(surveyors' X is often north)")


def _is_collinear(points: np.ndarray) -> bool:
    centred = points - points.mean(axis=0)
    sv = np.linalg.svd(centred, compute_uv=False)
    return sv[0] == 0.0 or sv[1] / sv[0] < 1e-6


def _elementary_rotations(rx: float, ry: float, rz: float):
    """R1(rx), R2(ry), R3(rz) (coordinate frame rotations) and their derivatives."""
    cx, sx, cy, sy, cz, sz = math.cos(rx), math.sin(rx), math.cos(ry), math.sin(ry), math.cos(rz), math.sin(rz)
    r1 = np.array([[1, 0, 0], [0, cx, sx], [0, -sx, cx]])
    r2 = np.array([[cy, 0, -sy], [0, 1, 0], [sy, 0, cy]])
    r3 = np.array([[cz, sz, 0], [-sz, cz, 0], [0, 0, 1]])
    d1 = np.array([[0, 0, 0], [0, -sx, cx], [0, -cx, -sx]])
    d2 = np.array([[-sy, 0, -cy], [0, 0, 0], [cy, 0, -sy]])
    d3 = np.array([[-sz, cz, 0], [-cz, -sz, 0], [0, 0, 0]])
    return (r1, r2, r3), (d1, d2, d3)


def _rotation_matrix(rx: float, ry: float, rz: float) -> np.ndarray:
    (r1, r2, r3), _ = _elementary_rotations(rx, ry, rz)
    return r1 @ r2 @ r3


def _solve_helmert_7(src: np.ndarray, dst: np.ndarray) -> tuple[Helmert7, np.ndarray]:
    """Umeyama's closed-form LS; returns the parameters and the Jacobian of the observations
    with respect to (tx, ty, tz, rx, ry, rz, scale_ppm) at the solution."""
    src_mean, dst_mean = src.mean(axis=0), dst.mean(axis=0)
    xc, yc = src - src_mean, dst - dst_mean
    u, d, vt = np.linalg.svd(yc.T @ xc)
    reflection = np.diag([1.0, 1.0, np.sign(np.linalg.det(u @ vt))])
    rot = u @ reflection @ vt
    scale = float(np.sum(d * np.diag(reflection)) / np.sum(xc**2))
    rx = math.atan2(rot[1, 2], rot[2, 2])
    ry = -math.asin(max(-1.0, min(1.0, rot[0, 2])))
    rz = math.atan2(rot[0, 1], rot[0, 0])
    t = dst_mean - scale * rot @ src_mean

    # Jacobian in the centred form y = t' + s R (x - x̄) (well conditioned), then mapped to
    # the parameters that are reported: t = t' - s R x̄.
    (r1, r2, r3), (d1, d2, d3) = _elementary_rotations(rx, ry, rz)
    dr = (d1 @ r2 @ r3, r1 @ d2 @ r3, r1 @ r2 @ d3)
    n = len(src)
    jac_centred = np.zeros((3 * n, 7))
    jac_centred[:, :3] = np.tile(np.eye(3), (n, 1))
    for k in range(3):
        jac_centred[:, 3 + k] = (scale * xc @ dr[k].T).ravel()
    jac_centred[:, 6] = (xc @ rot.T).ravel() * 1e-6
    to_reported = np.eye(7)  # d(centred params)/d(reported params): t' = t + s R x̄
    for k in range(3):
        to_reported[:3, 3 + k] = scale * dr[k] @ src_mean
    to_reported[:3, 6] = rot @ src_mean * 1e-6
    params = Helmert7(float(t[0]), float(t[1]), float(t[2]), rx, ry, rz, (scale - 1.0) * 1e6)
    return params, jac_centred @ to_reported


def _normal_inverse(jacobian: np.ndarray) -> np.ndarray:
    """(JᵀJ)⁻¹ computed on column-equilibrated J (ECEF lever arms make JᵀJ span ~1e26)."""
    norms = np.linalg.norm(jacobian, axis=0)
    scaled = jacobian / norms
    inv = np.linalg.inv(scaled.T @ scaled)
    return inv / np.outer(norms, norms)
