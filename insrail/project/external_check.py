"""A processed survey checked against an independent reference (thesis §5.4.3): a levelling line
(heights) or another trolley's per-sleeper coordinates (plan and height).

Each reference point is met at its chainage on the survey's sleeper table: the chosen rail's
point (or the centreline, the mean of both) interpolated between the two valid sleepers around
it, no further apart than :data:`MAX_SLEEPER_GAP_M` (else the point is "not covered"). The
differences are survey − reference: vertical, and with plan coordinates lateral (+ the survey to
the right of the reference, looking towards increasing chainage; the along-track part is the
chainage's business, not the position's). Each difference has the stated 1-sigma
sqrt(σ_survey² + σ_reference²): the survey's predicted σ of its 200 m section (quality.csv) and
the reference's σ as its surveyor states it.

The verdict: a difference within 3σ is what a right σ gives 997 times in 1000; a survey agrees
with the reference when at least :data:`AGREEING_SHARE` of the points lie within 3σ (the errors
of neighbouring points are correlated, so a share, not a χ² of independent points).
"""

from __future__ import annotations

import csv
import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import tomli_w

from insrail.io.atomic import atomic_write
from insrail.io.errors import InputError
from insrail.io.external import ReferencePoints
from insrail.project.results import RESULTS_FOLDER, StoredResults

#: Two valid sleepers further apart than this do not place a point between them [m] (a gap, a
#: stretch not valid): about three sleeper spacings.
MAX_SLEEPER_GAP_M = 2.0
#: The share of points within 3σ for a survey to agree with the reference.
AGREEING_SHARE = 0.9
RAILS = ("left", "right", "centre")


@dataclass(frozen=True)
class ComponentStatistics:
    """One component's differences [m] and their agreement with the stated σ."""

    component: str  # "vertical" or "lateral"
    count: int
    mean_m: float
    rms_m: float
    max_abs_m: float
    within_2sigma: float  # share of the compared points
    within_3sigma: float

    @property
    def agrees(self) -> bool:
        return self.count > 0 and self.within_3sigma >= AGREEING_SHARE

    def to_dict(self) -> dict:
        return {"count": self.count, "mean_mm": round(1e3 * self.mean_m, 3), "rms_mm": round(1e3 * self.rms_m, 3),
                "max_abs_mm": round(1e3 * self.max_abs_m, 3), "within_2sigma": round(self.within_2sigma, 4),
                "within_3sigma": round(self.within_3sigma, 4), "agrees": self.agrees}


@dataclass(frozen=True)
class ExternalCheck:
    """The survey against one reference, per point and component (NaN where not covered)."""

    survey: str
    reference: ReferencePoints
    rail: str
    reference_sigma_m: float
    components: tuple[str, ...]
    difference_m: np.ndarray  # (n, len(components))
    sigma_m: np.ndarray  # (n, len(components)) stated 1-sigma of each difference

    def statistics(self) -> list[ComponentStatistics]:
        out = []
        for k, component in enumerate(self.components):
            d, s = self.difference_m[:, k], self.sigma_m[:, k]
            used = np.isfinite(d) & np.isfinite(s)
            d, s = d[used], s[used]
            n = int(used.sum())
            if not n:
                out.append(ComponentStatistics(component, 0, np.nan, np.nan, np.nan, np.nan, np.nan))
                continue
            out.append(ComponentStatistics(component, n, float(np.mean(d)), float(np.sqrt(np.mean(d**2))),
                                           float(np.max(np.abs(d))), float(np.mean(np.abs(d) <= 2 * s)),
                                           float(np.mean(np.abs(d) <= 3 * s))))
        return out

    @property
    def not_covered(self) -> int:
        return int(np.sum(~np.isfinite(self.difference_m[:, 0])))


def _rail_points(results: StoredResults, rail: str) -> np.ndarray:
    c = results.columns
    side = {name: np.column_stack([c[f"{name}_E_m"], c[f"{name}_N_m"], c[f"{name}_H_m"]]) for name in ("left", "right")}
    return 0.5 * (side["left"] + side["right"]) if rail == "centre" else side[rail]


def _section_sigma(results: StoredResults, chainage_m: np.ndarray, figure: str) -> np.ndarray:
    quality = results.quality
    values = getattr(quality, figure)
    index = np.searchsorted(quality.station_from_m, chainage_m, side="right") - 1
    inside = (index >= 0) & (chainage_m <= quality.station_to_m[np.clip(index, 0, None)])
    return np.where(inside, 1e-3 * values[np.clip(index, 0, None)], np.nan)


def check_against(results: StoredResults, reference: ReferencePoints, rail: str,
                  reference_sigma_m: float) -> ExternalCheck:
    """The survey's ``results`` against ``reference`` on ``rail`` ("left", "right" of the stationing or
    "centre"); ``reference_sigma_m``: the reference's stated 1-sigma per coordinate [m]."""
    if rail not in RAILS:
        raise ValueError(f"rail must be one of {', '.join(RAILS)}, not {rail!r}")
    if not reference_sigma_m > 0:
        raise ValueError(f"the reference's 1-sigma must be positive, not {reference_sigma_m!r}")
    if results.quality is None:
        raise InputError(results.folder, None, "no quality.csv (the survey's predicted 1-sigma): process it again")
    valid = (results.columns["valid"] > 0) & np.isfinite(results.columns["station_m"])
    points = _rail_points(results, rail)
    valid &= np.all(np.isfinite(points), axis=1)
    station, points = results.columns["station_m"][valid], points[valid]
    order = np.argsort(station, kind="stable")
    station, points = station[order], points[order]
    if len(station) < 2:
        raise InputError(results.folder, None, "fewer than two valid sleepers with the {rail} rail: nothing to compare", fields={"rail": rail})
    at = reference.chainage_m
    upper = np.clip(np.searchsorted(station, at, side="left"), 1, max(len(station) - 1, 1))
    lower = upper - 1
    covered = (at >= station[0]) & (at <= station[-1])
    covered &= station[upper] - station[lower] <= MAX_SLEEPER_GAP_M
    span = np.where(covered, station[upper] - station[lower], 1.0)
    weight = np.where(covered, (at - station[lower]) / np.where(span > 0, span, 1.0), np.nan)[:, None]
    surveyed = points[lower] + weight * (points[upper] - points[lower])
    vertical = surveyed[:, 2] - reference.enh_m[:, 2]
    components, difference = ["vertical"], [vertical]
    sigma = [np.hypot(_section_sigma(results, at, "sigma_vertical_mm"), reference_sigma_m)]
    if reference.has_plan:
        tangent = points[upper, :2] - points[lower, :2]
        tangent /= np.where(covered, np.linalg.norm(tangent, axis=1), 1.0)[:, None]
        right = np.column_stack([tangent[:, 1], -tangent[:, 0]])  # (E, N) of the right normal
        lateral = np.sum((surveyed[:, :2] - reference.enh_m[:, :2]) * right, axis=1)
        components.insert(0, "lateral")
        difference.insert(0, lateral)
        sigma.insert(0, np.hypot(_section_sigma(results, at, "sigma_lateral_mm"), reference_sigma_m))
    difference_m = np.where(covered[:, None], np.column_stack(difference), np.nan)
    return ExternalCheck(results.survey, reference, rail, reference_sigma_m, tuple(components), difference_m,
                         np.column_stack(sigma))


def check_files(project_folder: Path, check: ExternalCheck) -> tuple[Path, Path]:
    """``results/external_<survey>_<reference file stem>.csv`` (per point: id, chainage, per component
    the difference, its σ and difference/σ in mm) and ``.toml`` (the statistics), written atomically."""
    stem = Path(project_folder) / RESULTS_FOLDER / f"external_{check.survey}_{check.reference.source.stem}"
    text = io.StringIO()
    writer = csv.writer(text, lineterminator="\n")
    writer.writerow(["point", "chainage_m", *(f"{c}_{what}" for c in check.components
                                              for what in ("difference_mm", "sigma_mm", "normalised"))])
    for i, point in enumerate(check.reference.point_id):
        row = [point, f"{check.reference.chainage_m[i]:.4f}"]
        for k in range(len(check.components)):
            d, s = check.difference_m[i, k], check.sigma_m[i, k]
            row += ["" if not np.isfinite(v) else f"{v:.3f}" for v in (1e3 * d, 1e3 * s, d / s)]
        writer.writerow(row)
    summary = {"survey": check.survey, "reference": str(check.reference.source), "rail": check.rail,
               "reference_sigma_mm": 1e3 * check.reference_sigma_m, "points": len(check.reference),
               "not_covered": check.not_covered, "agreeing_share_3sigma": AGREEING_SHARE,
               "difference": "survey - reference; lateral + the survey right of the reference (increasing chainage)",
               **{s.component: s.to_dict() for s in check.statistics()}}
    csv_path, toml_path = stem.with_suffix(".csv"), stem.with_suffix(".toml")
    with atomic_write(csv_path) as handle:
        handle.write(text.getvalue())
    with atomic_write(toml_path, "wb") as handle:
        tomli_w.dump(summary, handle)
    return csv_path, toml_path
