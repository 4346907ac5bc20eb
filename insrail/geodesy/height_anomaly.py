"""Height anomaly ζ = h − H fitted on GNSS-levelling benchmarks.

GNSS gives ellipsoidal heights h, the railway needs normal heights H from levelling; the
height anomaly ζ = h − H is smooth and is interpolated from benchmarks where both are
known. Candidate models (plane coordinates are centred on the benchmarks and in km, so
coefficients are in m, m/km, m/km²):

* ``constant``   ζ = a0                                              (1 parameter)
* ``plane``      ζ = a0 + a1 x + a2 y                                (3)
* ``quadratic``  ζ = a0 + a1 x + a2 y + a3 x² + a4 xy + a5 y²        (6)
* ``spline``     cubic spline (not-a-knot ends) through the benchmarks in chainage, continued
  linearly beyond the end benchmarks (for long corridors, where a surface is poorly
  determined across the line). It interpolates, so its internal RMS is 0 by
  construction; judge it by leave-one-out.

Every model needs at least one benchmark more than it has parameters (4 for the spline),
so there is always a check. Optionally a global geoid is removed first and restored
afterwards (remove-restore): the model is fitted to ζ − N_geoid, which is smoother.

Model choice (``model="auto"``) is by leave-one-out RMS: each benchmark predicted by the
model fitted without it. Among the models within max(10 %, 0.5 mm) of the best
leave-one-out RMS the one with the fewest parameters is chosen, since extra parameters
that do not predict better only add extrapolation risk.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Protocol

import numpy as np

from insrail.geodesy._validation import Problems
from insrail.geodesy.crs import EngineeringCRS
from insrail.geodesy.errors import FitError, GeodesyError
from insrail.geodesy.geoid import GeoidGrid, PlaneGeoid
from insrail.notices import Phrase

if TYPE_CHECKING:  # scipy.interpolate and scipy.spatial are imported when a model is fitted, not by
    from scipy.interpolate import CubicSpline  # the project model and the reports that only name them

MODELS = ("constant", "plane", "quadratic", "spline")
_SURFACE_PARAMETERS = {"constant": 1, "plane": 3, "quadratic": 6}
_SPLINE_MINIMUM_POINTS = 4
_PLAUSIBLE_ZETA_M = 150.0  # the geoid stays within about -107 m ... +86 m
_DEGENERATE_RATIO = 1e-6  # singular-value ratio below which the geometry cannot fix a model
_SELECTION_RELATIVE_TOLERANCE = 0.10
_SELECTION_ABSOLUTE_TOLERANCE_M = 0.0005
_HULL_TOLERANCE_M = 1.0  # benchmarks are rarely closer than this to the track; don't warn for less


class HeightAnomalyModel(Protocol):
    """What the rest of insrail calls: ζ [m] at plane coordinates (and chainage for spline models)."""

    name: str

    def zeta_m(self, east_m, north_m, chainage_m=None) -> np.ndarray: ...


@dataclass(frozen=True, eq=False)
class SurfaceModel:
    """Polynomial surface ζ(E, N) (``constant``, ``plane`` or ``quadratic``), plus the geoid if any."""

    name: str
    centre_east_m: float
    centre_north_m: float
    coefficients: np.ndarray  # m, m/km, m/km² in the order of the module docstring
    geoid: PlaneGeoid | None = None

    def zeta_m(self, east_m, north_m, chainage_m=None) -> np.ndarray:
        east, north = np.broadcast_arrays(np.asarray(east_m, dtype=float), np.asarray(north_m, dtype=float))
        basis = _surface_basis(self.name, (east - self.centre_east_m) / 1000.0,
                               (north - self.centre_north_m) / 1000.0)
        zeta = basis @ self.coefficients
        return zeta + self.geoid.undulation_m(east, north) if self.geoid is not None else zeta


@dataclass(frozen=True, eq=False)
class ChainageSplineModel:
    """Cubic spline ζ(chainage) (not-a-knot ends), linear beyond the end benchmarks, plus the geoid if any."""

    chainage_m: np.ndarray  # benchmark chainages, increasing
    values_m: np.ndarray  # fitted quantity at them (ζ, or ζ − N with a geoid)
    geoid: PlaneGeoid | None = None
    name: str = "spline"
    _spline: CubicSpline = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        from scipy.interpolate import CubicSpline

        object.__setattr__(self, "_spline", CubicSpline(self.chainage_m, self.values_m, bc_type="not-a-knot"))

    def zeta_m(self, east_m, north_m, chainage_m=None) -> np.ndarray:
        if chainage_m is None:
            raise GeodesyError("the height-anomaly model is a spline in chainage: give chainage_m")
        s = np.asarray(chainage_m, dtype=float)
        lo, hi = self.chainage_m[0], self.chainage_m[-1]
        clipped = np.clip(s, lo, hi)
        zeta = self._spline(clipped) + self._spline(clipped, 1) * (s - clipped)
        if self.geoid is not None:
            zeta = zeta + self.geoid.undulation_m(east_m, north_m)
        return zeta


@dataclass(frozen=True, eq=False)
class CandidateFit:
    """One model fitted to the benchmarks: residuals (observed − model) and leave-one-out residuals [m].

    A leave-one-out residual is NaN where the remaining benchmarks cannot determine the model.
    """

    name: str
    n_parameters: int
    residuals_m: np.ndarray
    internal_rms_m: float
    loo_residuals_m: np.ndarray
    loo_rms_m: float


@dataclass(frozen=True, eq=False)
class HeightAnomalyFit:
    """Result of ``fit_height_anomaly``: the chosen model and how every candidate did."""

    model: HeightAnomalyModel
    candidates: tuple[CandidateFit, ...]
    not_fitted: dict[str, str]  # model name -> why it could not be fitted
    benchmarks_en: np.ndarray
    benchmark_chainage_m: np.ndarray | None
    geoid: PlaneGeoid | None

    @property
    def model_name(self) -> str:
        return self.model.name

    @property
    def chosen(self) -> CandidateFit:
        return next(c for c in self.candidates if c.name == self.model.name)

    @property
    def internal_rms_m(self) -> float:
        return self.chosen.internal_rms_m

    @property
    def loo_rms_m(self) -> float:
        return self.chosen.loo_rms_m

    def zeta_m(self, east_m, north_m, chainage_m=None) -> np.ndarray:
        return self.model.zeta_m(east_m, north_m, chainage_m)

    def extrapolation_mask(self, east_m, north_m, chainage_m=None) -> np.ndarray:
        """True where the chosen model extrapolates: outside the benchmarks' chainage span for the
        spline, outside their convex hull (beyond 1 m) for the surfaces."""
        if isinstance(self.model, ChainageSplineModel):
            if chainage_m is None:
                raise GeodesyError("the height-anomaly model is a spline in chainage: give chainage_m")
            s = np.asarray(chainage_m, dtype=float)
            return (s < self.benchmark_chainage_m.min()) | (s > self.benchmark_chainage_m.max())
        return _hull_excess_m(self.benchmarks_en, east_m, north_m) > _HULL_TOLERANCE_M

    def warnings_for(self, east_m, north_m, chainage_m=None) -> list[Phrase]:
        """Warnings for the points where ζ is extrapolated (empty when all are covered)."""
        outside = self.extrapolation_mask(east_m, north_m, chainage_m)
        if not outside.any():
            return []
        count, total = int(outside.sum()), outside.size
        if isinstance(self.model, ChainageSplineModel):
            s = np.asarray(chainage_m, dtype=float)[outside]
            lo, hi = self.benchmark_chainage_m.min(), self.benchmark_chainage_m.max()
            beyond = max(lo - s.min(), s.max() - hi)
            return [Phrase("height anomaly extrapolated at {count} of {total} points: chainage {from_m:.1f} to {to_m:.1f} m "
                           "is outside the benchmarks' span {lo_m:.1f} to {hi_m:.1f} m (up to {beyond_m:.1f} m beyond)",
                           {"count": count, "total": total, "from_m": s.min(), "to_m": s.max(), "lo_m": lo, "hi_m": hi,
                            "beyond_m": beyond})]
        excess = _hull_excess_m(self.benchmarks_en, east_m, north_m)[outside]
        if np.isinf(excess).all():
            return [Phrase("height anomaly extrapolated at {count} of {total} points: the benchmarks have no 2-D hull "
                           "(collinear), so every point off their line is extrapolated", {"count": count, "total": total})]
        return [Phrase("height anomaly extrapolated at {count} of {total} points: they lie outside the benchmarks' convex "
                       "hull, up to {beyond_m:.1f} m beyond it", {"count": count, "total": total, "beyond_m": excess.max()})]

    def report(self) -> str:
        """Plain-text summary for the processing log and reports."""
        geoid = f", remove-restore with {self.geoid.describe()}" if self.geoid is not None else ""
        lines = [f"Height anomaly ζ = h − H from {len(self.benchmarks_en)} benchmarks{geoid}",
                 f"{'model':<10} {'params':>6} {'internal RMS':>13} {'leave-one-out RMS':>18}"]
        for c in self.candidates:
            internal = "interpolates" if c.name == "spline" else f"{c.internal_rms_m * 1e3:.1f} mm"
            mark = "  <- chosen" if c.name == self.model_name else ""
            lines.append(f"{c.name:<10} {c.n_parameters:>6} {internal:>13} {c.loo_rms_m * 1e3:>15.1f} mm{mark}")
        lines += [f"{name:<10} not fitted: {reason}" for name, reason in self.not_fitted.items()]
        return "\n".join(lines)


def fit_height_anomaly(benchmarks_en, zeta_m, model: str = "auto", chainage_m=None,
                       geoid: PlaneGeoid | None = None) -> HeightAnomalyFit:
    """Fit ζ on benchmarks (``benchmarks_en`` shape (n, 2) [m], ``zeta_m`` shape (n,) = h − H [m]).

    ``model`` is one of ``MODELS`` or ``"auto"`` (all that can be fitted, best by leave-one-out
    RMS; ``spline`` only when ``chainage_m`` is given). Raises ``FitError`` when an explicitly
    requested model cannot be fitted, or when no model can.
    """
    en, zeta, chainage = _validated_benchmarks(benchmarks_en, zeta_m, chainage_m, model)
    observed = zeta - geoid.undulation_m(en[:, 0], en[:, 1]) if geoid is not None else zeta
    if model == "auto":
        names = [m for m in MODELS if m != "spline" or chainage is not None]
    else:
        names = [model]

    candidates, models, not_fitted = [], {}, {}
    for name in names:
        try:
            fitted = _fit_model(name, en, observed, chainage)
        except FitError as err:
            if model != "auto":
                raise
            not_fitted[name] = str(err)
            continue
        residuals = observed - fitted.zeta_m(en[:, 0], en[:, 1], chainage)
        loo = _leave_one_out(name, en, observed, chainage)
        finite = loo[np.isfinite(loo)]
        candidates.append(CandidateFit(name, _n_parameters(name, len(en)), residuals,
                                       float(np.sqrt(np.mean(residuals**2))), loo,
                                       float(np.sqrt(np.mean(finite**2))) if finite.size else float("nan")))
        models[name] = replace(fitted, geoid=geoid)
    if not candidates:
        raise FitError("no height-anomaly model can be fitted:\n  " + "\n  ".join(
            f"{n}: {r}" for n, r in not_fitted.items()))
    chosen = _select(candidates)
    return HeightAnomalyFit(models[chosen.name], tuple(candidates), not_fitted, en, chainage, geoid)


# --------------------------------------------------------------------------------------
def _validated_benchmarks(benchmarks_en, zeta_m, chainage_m, model):
    if model != "auto" and model not in MODELS:
        raise GeodesyError(f"unknown height-anomaly model {model!r}; expected 'auto' or one of {', '.join(MODELS)}")
    if model == "spline" and chainage_m is None:
        raise FitError("the spline model is a function of chainage: give chainage_m for the benchmarks")
    en = np.asarray(benchmarks_en, dtype=float)
    zeta = np.asarray(zeta_m, dtype=float)
    if en.ndim != 2 or en.shape[1] != 2:
        raise GeodesyError(f"benchmark coordinates must have shape (n, 2) (east, north), got {en.shape}")
    if zeta.shape != (len(en),):
        raise GeodesyError(f"{len(en)} benchmarks but height anomalies of shape {zeta.shape}")
    chainage = None
    if chainage_m is not None:
        chainage = np.asarray(chainage_m, dtype=float)
        if chainage.shape != (len(en),):
            raise GeodesyError(f"{len(en)} benchmarks but chainages of shape {chainage.shape}")
    bad = ~(np.isfinite(en).all(axis=1) & np.isfinite(zeta)
            & (np.isfinite(chainage) if chainage is not None else True))
    if bad.any():
        raise GeodesyError(f"benchmarks {np.flatnonzero(bad).tolist()} have missing or non-finite values")
    absurd = np.abs(zeta) > _PLAUSIBLE_ZETA_M
    if absurd.any():
        i = int(np.flatnonzero(absurd)[0])
        raise FitError(f"benchmark {i}: height anomaly ζ = h − H = {zeta[i]:.3f} m is impossible on Earth "
                       f"(|ζ| < {_PLAUSIBLE_ZETA_M:g} m); check that h is ellipsoidal and H is a normal "
                       "height, both in metres")
    return en, zeta, chainage


def _n_parameters(name: str, n_points: int) -> int:
    return n_points if name == "spline" else _SURFACE_PARAMETERS[name]


def _surface_basis(name: str, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    columns = [np.ones_like(x)]
    if name in ("plane", "quadratic"):
        columns += [x, y]
    if name == "quadratic":
        columns += [x * x, x * y, y * y]
    return np.stack(columns, axis=-1)


_GEOMETRY_HINT = {
    "plane": "the benchmarks are (nearly) collinear, so the slope across their line is undetermined; "
             "use 'spline' (in chainage) or 'constant', or add benchmarks off the line",
    "quadratic": "the benchmarks lie (nearly) on one line or conic (e.g. all on the centreline of a straight "
                 "or circular section), so a quadratic surface is undetermined; use 'spline' or 'plane', or "
                 "add benchmarks off the line",
}


def _fit_model(name, en, observed, chainage):
    """The model fitted to ``observed`` (ζ, or ζ − N with a geoid), without the geoid attached."""
    n = len(en)
    if name == "spline":
        if n < _SPLINE_MINIMUM_POINTS:
            raise FitError(f"the spline needs at least {_SPLINE_MINIMUM_POINTS} benchmarks, {n} given")
        order = np.argsort(chainage)
        s = chainage[order]
        if np.any(np.diff(s) <= 0.0):
            i = int(np.flatnonzero(np.diff(s) <= 0.0)[0])
            raise FitError(f"two benchmarks share chainage {s[i]:.3f} m; a spline in chainage needs distinct "
                           "chainages (merge them or drop one)")
        return ChainageSplineModel(s, observed[order])
    p = _SURFACE_PARAMETERS[name]
    if n < p + 1:
        raise FitError(f"the {name} model needs at least {p + 1} benchmarks ({p} parameters and one check), "
                       f"{n} given")
    centre = en.mean(axis=0)
    basis = _surface_basis(name, (en[:, 0] - centre[0]) / 1000.0, (en[:, 1] - centre[1]) / 1000.0)
    norms = np.linalg.norm(basis, axis=0)
    sv = np.linalg.svd(basis / np.where(norms > 0, norms, 1.0), compute_uv=False)
    if name != "constant" and sv[-1] < _DEGENERATE_RATIO * sv[0]:
        raise FitError(_GEOMETRY_HINT[name])
    coefficients = np.linalg.lstsq(basis, observed, rcond=None)[0]
    return SurfaceModel(name, float(centre[0]), float(centre[1]), coefficients)


def _leave_one_out(name, en, observed, chainage) -> np.ndarray:
    loo = np.full(len(en), np.nan)
    for i in range(len(en)):
        keep = np.arange(len(en)) != i
        try:
            fitted = _fit_model(name, en[keep], observed[keep], None if chainage is None else chainage[keep])
        except FitError:
            continue
        loo[i] = observed[i] - fitted.zeta_m(en[i:i + 1, 0], en[i:i + 1, 1],
                                             None if chainage is None else chainage[i:i + 1])[0]
    return loo


def _select(candidates: list[CandidateFit]) -> CandidateFit:
    scored = [c for c in candidates if np.isfinite(c.loo_rms_m)]
    if not scored:
        return min(candidates, key=lambda c: c.n_parameters)
    best = min(c.loo_rms_m for c in scored)
    tolerance = max(_SELECTION_RELATIVE_TOLERANCE * best, _SELECTION_ABSOLUTE_TOLERANCE_M)
    return min((c for c in scored if c.loo_rms_m <= best + tolerance), key=lambda c: c.n_parameters)


def _hull_excess_m(benchmarks_en: np.ndarray, east_m, north_m) -> np.ndarray:
    """Distance [m] by which each point lies outside the benchmarks' convex hull (≤ 0 inside);
    +inf everywhere when the benchmarks have no 2-D hull (collinear or fewer than 3)."""
    from scipy.spatial import ConvexHull, QhullError

    east, north = np.broadcast_arrays(np.asarray(east_m, dtype=float), np.asarray(north_m, dtype=float))
    try:
        hull = ConvexHull(benchmarks_en)
    except (QhullError, ValueError):
        return np.full(east.shape, np.inf)
    # Each facet row is (unit normal, offset) with normal·p + offset <= 0 inside; the largest
    # value is the distance outside (exact near edges, a lower bound near vertices).
    points = np.stack([east, north], axis=-1)
    return np.max(points @ hull.equations[:, :2].T + hull.equations[:, 2], axis=-1)


@dataclass(frozen=True)
class HeightAnomalySettings:
    """The ``[geodesy.height_anomaly]`` table: model choice and optional geoid grid for remove-restore.

    ``geoid_grid`` is a file path, ``"egm96"`` for the EGM96 grid shipped with insrail,
    or None for no remove-restore.
    """

    model: str = "auto"
    geoid_grid: str | None = None

    def to_settings(self) -> dict[str, str]:
        out = {"model": self.model}
        if self.geoid_grid is not None:
            out["geoid_grid"] = self.geoid_grid
        return out

    @classmethod
    def from_settings(cls, settings, key_path: str = "geodesy.height_anomaly") -> HeightAnomalySettings:
        problems = Problems(key_path)
        model, grid = "auto", None
        if problems.check_mapping(settings):
            problems.unknown_keys(settings, ["model", "geoid_grid"])
            model = problems.choice(settings, "model", "auto", ("auto", *MODELS))
            grid = settings.get("geoid_grid")
            if grid is not None and (not isinstance(grid, str) or not grid.strip()):
                problems.add("geoid_grid", f"expected a grid file path or 'egm96', got {grid!r}")
        problems.raise_if_any()
        return cls(model, grid)

    def plane_geoid(self, crs: EngineeringCRS) -> PlaneGeoid | None:
        """Open the configured grid (raises ``GeoidGridError`` if it is missing)."""
        if self.geoid_grid is None:
            return None
        grid = GeoidGrid.egm96() if self.geoid_grid == "egm96" else GeoidGrid(Path(self.geoid_grid))
        return PlaneGeoid(grid, crs)
