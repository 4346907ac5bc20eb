"""Local control: the railway's local grid tied to the engineering CRS by common points
(``[geodesy.local]`` in project.toml; seed 004, the 4-parameter similarity onto local control).

::

    [geodesy.local]
    model = "4-parameter"        # plane similarity E, N -> local E, N (+ a height shift); or "7-parameter"
    [geodesy.local.points.CP3-101]
    east_m = 512410.123          # engineering CRS (geodesy.crs) and normal height
    north_m = 3374250.456
    height_m = 30.781
    local_east_m = 2410.118      # the same point in the local system
    local_north_m = 4250.503
    local_height_m = 30.779      # optional with the 4-parameter model (all points or none)

The transformation is fitted on the common points (:mod:`insrail.geodesy.similarity`: closed-form
least squares, residuals and leave-one-out residuals) and applied where the engineering coordinates
are formed, so the design alignment, the chainage, every coordinate in sleepers.csv and every export
are in the local system. The 4-parameter model transforms the plane; with local heights it adds their
mean difference as a height shift (heights are otherwise unchanged). The 7-parameter model is a
spatial similarity of (E, N, H) (Bursa-Wolf, coordinate frame rotation); as local grids may be turned
by any angle its rotation is not limited to datum size. Total-station prism fixes stay in the
engineering CRS. A point whose leave-one-out residual exceeds :data:`LOO_WARNING_M` is a notice.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from insrail.geodesy.errors import FitError
from insrail.geodesy.similarity import (
    Helmert7Fit,
    Similarity2DFit,
    fit_helmert_7,
    fit_similarity_2d,
)
from insrail.notices import Notice, Phrase

MODELS = ("4-parameter", "7-parameter")
ENGINEERING = ("east_m", "north_m", "height_m")
LOCAL = ("local_east_m", "local_north_m", "local_height_m")
#: A common point predicted worse than this by the others (leave-one-out) is reported: CPIII-class
#: points agree to 1-2 mm, so 5 mm is a wrong coordinate or a moved mark rather than noise.
LOO_WARNING_M = 5e-3


@dataclass(frozen=True)
class LocalPoint:
    name: str
    engineering_enh_m: tuple[float, float, float]
    local_enh_m: tuple[float, float, float]  # local height NaN when not given (4-parameter only)


@dataclass(frozen=True)
class LocalControl:
    model: str
    points: tuple[LocalPoint, ...]

    def to_settings(self) -> dict[str, Any]:
        points = {}
        for p in self.points:
            entry = dict(zip(ENGINEERING, p.engineering_enh_m)) | dict(zip(LOCAL, p.local_enh_m))
            points[p.name] = {k: v for k, v in entry.items() if not (isinstance(v, float) and math.isnan(v))}
        return {"model": self.model, "points": points}


@dataclass(frozen=True, eq=False)
class LocalFit:
    """The fitted transformation engineering (E, N, H) -> local (E, N, H)."""

    control: LocalControl
    plane: Similarity2DFit | None  # 4-parameter
    height_shift_m: float  # 4-parameter: mean local - engineering height (0 without local heights)
    height_residuals_m: np.ndarray | None
    spatial: Helmert7Fit | None  # 7-parameter

    def apply(self, east, north, height) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        east, north, height = (np.asarray(v, dtype=float) for v in (east, north, height))
        if self.spatial is not None:
            shape = east.shape
            xyz = self.spatial.apply(np.column_stack([east.ravel(), north.ravel(), np.broadcast_to(height, shape).ravel()]))
            return xyz[:, 0].reshape(shape), xyz[:, 1].reshape(shape), xyz[:, 2].reshape(shape)
        en = self.plane.apply(np.column_stack([east.ravel(), north.ravel()]))
        return en[:, 0].reshape(east.shape), en[:, 1].reshape(east.shape), height + self.height_shift_m

    def to_engineering(self, east, north, height) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The inverse: local (E, N, H) -> engineering (for what is modelled in the engineering CRS)."""
        east, north, height = (np.asarray(v, dtype=float) for v in (east, north, height))
        if self.spatial is not None:
            p = self.spatial.parameters
            m = (1.0 + p.scale_ppm * 1e-6) * p.rotation_matrix()
            local = np.column_stack([east.ravel(), north.ravel(), np.broadcast_to(height, east.shape).ravel()])
            xyz = np.linalg.solve(m, (local - [p.tx_m, p.ty_m, p.tz_m]).T).T
            return xyz[:, 0].reshape(east.shape), xyz[:, 1].reshape(east.shape), xyz[:, 2].reshape(east.shape)
        en = self.plane.parameters.inverse().apply(np.column_stack([east.ravel(), north.ravel()]))
        return en[:, 0].reshape(east.shape), en[:, 1].reshape(east.shape), height - self.height_shift_m

    def residuals_m(self) -> tuple[np.ndarray, np.ndarray]:
        """(residuals, leave-one-out residuals), each (n, 3) E, N, H [m] (observed local - transformed)."""
        if self.spatial is not None:
            return self.spatial.residuals_m, self.spatial.loo_residuals_m
        n = len(self.control.points)
        heights = self.height_residuals_m if self.height_residuals_m is not None else np.full(n, np.nan)
        # leave-one-out of a mean: the point's residual grows by n / (n - 1)
        loo_heights = heights * n / (n - 1)
        return (np.column_stack([self.plane.residuals_m, heights]),
                np.column_stack([self.plane.loo_residuals_m, loo_heights]))

    def summary(self) -> dict:
        """summary.toml's ``[local_control]``: model, parameters, RMS and per-point residuals [mm]."""
        residuals, loo = self.residuals_m()

        def mm(v: float) -> float | None:
            return round(1e3 * float(v), 3) if np.isfinite(v) else None

        def finite(entries: dict) -> dict:  # TOML has no null: a value that does not exist is left out
            return {k: v for k, v in entries.items() if v is not None}

        if self.spatial is not None:
            p = self.spatial.parameters
            parameters = {"tx_m": p.tx_m, "ty_m": p.ty_m, "tz_m": p.tz_m, "rx_arcsec": p.rx_rad / _ARCSEC,
                          "ry_arcsec": p.ry_rad / _ARCSEC, "rz_arcsec": p.rz_rad / _ARCSEC, "scale_ppm": p.scale_ppm}
            rms, loo_rms = self.spatial.rms_m, self.spatial.loo_rms_m
        else:
            p = self.plane.parameters
            parameters = {"translation_east_m": p.translation_east_m, "translation_north_m": p.translation_north_m,
                          "rotation_deg": math.degrees(p.rotation_rad), "scale_ppm": p.scale_ppm,
                          "height_shift_m": self.height_shift_m}
            rms, loo_rms = self.plane.rms_m, self.plane.loo_rms_m
        axes = ("east", "north", "height")
        return finite({"model": self.control.model, "points": len(self.control.points), "rms_mm": mm(rms),
                       "loo_rms_mm": mm(loo_rms), "parameters": {k: float(v) for k, v in parameters.items()},
                       "residuals": [finite({"name": point.name, **{f"{a}_mm": mm(v) for a, v in zip(axes, r)},
                                             **{f"loo_{a}_mm": mm(v) for a, v in zip(axes, q)}})
                                     for point, r, q in zip(self.control.points, residuals, loo)]})

    def notices(self) -> list[Notice]:
        """A notice per suspect common point. A wrong point also spoils the others' leave-one-out
        predictions, so the worst one is named, the fit repeated without it, and so on while one
        exceeds :data:`LOO_WARNING_M` (and enough points remain for a check)."""
        notices, fit = [], self
        minimum = 5 if self.control.model == "7-parameter" else 4
        while True:
            _, loo = fit.residuals_m()
            size = np.where(np.isfinite(loo), np.abs(loo), 0.0).max(axis=1)
            worst = int(np.argmax(size))
            if size[worst] <= LOO_WARNING_M:
                return notices
            point = fit.control.points[worst]
            notices.append(Notice("geodesy", "local control point {point}: the other points predict it {off_mm:.1f} mm off "
                                             "(leave-one-out; E/N/H {enh} mm): check its coordinates in "
                                             "[geodesy.local.points]",
                                  fields={"point": point.name, "off_mm": 1e3 * size[worst],
                                          "enh": ", ".join(f"{1e3 * v:.1f}" for v in loo[worst] if np.isfinite(v))}))
            if len(fit.control.points) <= minimum:
                return notices
            rest = tuple(p for p in fit.control.points if p is not point)
            try:
                fit = fit_local(LocalControl(fit.control.model, rest))
            except FitError:
                return notices


_ARCSEC = math.pi / (180.0 * 3600.0)


def fit_local(control: LocalControl) -> LocalFit:
    """Fit the transformation of ``control`` (FitError with the reason when the points cannot give one)."""
    engineering = np.array([p.engineering_enh_m for p in control.points], dtype=float).reshape(-1, 3)
    local = np.array([p.local_enh_m for p in control.points], dtype=float).reshape(-1, 3)
    if control.model == "7-parameter":
        return LocalFit(control, None, 0.0, None, fit_helmert_7(engineering, local, max_rotation_rad=math.pi))
    plane = fit_similarity_2d(engineering[:, :2], local[:, :2])
    if np.isnan(local[:, 2]).all():
        return LocalFit(control, plane, 0.0, None, None)
    differences = local[:, 2] - engineering[:, 2]
    shift = float(np.mean(differences))
    return LocalFit(control, plane, shift, differences - shift, None)


def parse_local_control(table: Any, key_path: str, problems: list[str]) -> LocalControl | None:
    """``[geodesy.local]``; problems appended as ``key.path: message``; the fit is tried too."""
    if table is None:
        return None
    if not isinstance(table, dict):
        problems.append(Phrase("{key_path}: expected a table with model and points", {"key_path": key_path}))
        return None
    unknown = sorted(set(table) - {"model", "points"})
    problems.extend(Phrase("{key_path}.{key}: unknown key (expected model, points)", {"key_path": key_path, "key": key})
                    for key in unknown)
    model = table.get("model", "4-parameter")
    if model not in MODELS:
        problems.append(Phrase("{key_path}.model: expected one of {models}, found {model!r}", {"key_path": key_path, "models": list(MODELS), "model": model}))
        return None
    raw = table.get("points")
    if not isinstance(raw, dict) or not raw:
        problems.append(Phrase("{key_path}.points: expected [{key_path}.points.<name>] tables, one per common point", {"key_path": key_path}))
        return None
    points, before = [], len(problems)
    for name, entry in raw.items():
        where = f"{key_path}.points.{name}"
        if not isinstance(entry, dict):
            problems.append(Phrase("{where}: expected a table of {keys}", {"where": where, "keys": list(ENGINEERING + LOCAL)}))
            continue
        required = ENGINEERING + LOCAL[:2] + ((LOCAL[2],) if model == "7-parameter" else ())
        missing = [k for k in required if k not in entry]
        unknown = sorted(set(entry) - set(ENGINEERING + LOCAL))
        if missing:
            problems.append(Phrase("{where}: missing {missing}", {"where": where, "missing": list(missing)}))
        problems.extend(Phrase("{where}.{key}: unknown key (expected {keys})",
                               {"where": where, "key": k, "keys": list(ENGINEERING + LOCAL)}) for k in unknown)
        values = {}
        for key in ENGINEERING + LOCAL:
            value = entry.get(key, math.nan)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or (key in entry and not math.isfinite(value)):
                problems.append(Phrase("{where}.{key}: expected a number of metres, found {value!r}", {"where": where, "key": key, "value": value}))
                value = math.nan
            values[key] = float(value)
        points.append(LocalPoint(name, tuple(values[k] for k in ENGINEERING), tuple(values[k] for k in LOCAL)))
    if len(problems) > before:
        return None
    heights = [math.isnan(p.local_enh_m[2]) for p in points]
    if any(heights) and not all(heights):
        problems.append(Phrase("{key_path}.points: local_height_m is given for some points only (all or none)", {"key_path": key_path}))
        return None
    control = LocalControl(model, tuple(points))
    try:
        fit_local(control)
    except FitError as error:
        problems.append(Phrase("{key_path}: {error}", {"key_path": key_path, "error": error}))
        return None
    return control
