"""Checks the survey's stated accuracy cannot resolve: not assessed where that is so, and said so.

A check of the tolerance profile whose value the survey states a 1-sigma for (``quality.csv``: the
30 m/5 m differential versine by the 5 m lag, the 300 m/150 m one by the 150 m lag, a 10 m versine
by the 5 m lag (:func:`stated_figure`), the cross-level by its own) cannot tell a track outside its
limit from the survey's noise where that 1-sigma is above the limit (x :data:`RESOLVE_SIGMAS`): the noise
alone then crosses the limit at a third of independent values or more (a MEMS survey's 3.4 mm against the
2 mm of the 30 m/5 m check listed 250 exceedances that meant nothing). There the check is not
assessed over the 200 m sections concerned: its values there are left out of ``sleepers.csv`` and
its exceedances out of ``exceedances.csv``, and a warning names the check, the stations, the stated
1-sigma against the limit and how many exceedances were left out (CLI, summary, PDF, GUI log).
``summary.toml [[assessment.not_assessable]]`` holds the same per check and direction.

Checks without a stated figure (gauge, twist, rates, other chords) are assessed as before: the gauge
is measured by its own sensor; the twist's error is the change of the cross-level's over a few metres,
far smaller than the cross-level's 1-sigma (mostly an accelerometer bias, constant over them).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from insrail.notices import Notice, Phrase
from insrail.quality.prediction import LONG_LAG_M, SHORT_LAG_M
from insrail.quality.survey import SectionQuality
from insrail.track.exceedance import Assessment
from insrail.track.tolerance import Check, ToleranceProfile

#: a check is assessable where its stated 1-sigma is within its limit / RESOLVE_SIGMAS. Not 2 or 3 (the
#: plan's 3 sigma rule, insrail.quality.tables): a weak section's real exceedance well beyond the limit
#: is still found and listed (tests/test_project_pipeline.py's injected bumps)
RESOLVE_SIGMAS = 1.0
#: a differential versine whose pair length is within this of a stated lag [m] has that lag's figure
_PAIR_TOLERANCE_M = 0.5


def stated_figure(check: Check, direction: str) -> tuple[str, float] | None:
    """(the ``SectionQuality`` attribute, its factor) giving the stated 1-sigma of ``check``'s values in
    ``direction`` ("" for a check of the whole track), or None where the survey states none for it.
    A symmetric versine over a chord of twice a stated lag is half the difference of two such lag
    differences: 1/sqrt(2) of the lag's 1-sigma where they are independent (the play's random walk)."""
    if check.kind == "cross_level":
        return "sigma_cross_level_m", 1.0
    for lag_m, name in ((SHORT_LAG_M, "lag5"), (LONG_LAG_M, "lag150")):
        if check.kind == "differential_versine" and abs(check.pair_m - lag_m) <= _PAIR_TOLERANCE_M:
            return f"sigma_{name}_{direction}_m", 1.0
        if (check.kind == "versine" and check.back_m is None
                and abs(check.chord_m - 2.0 * lag_m) <= 2.0 * _PAIR_TOLERANCE_M):
            return f"sigma_{name}_{direction}_m", math.sqrt(0.5)
    return None


@dataclass(frozen=True)
class NotAssessable:
    """One check in one direction not assessed over some sections: ``sleepers`` (n,) the sleepers
    there, the largest stated 1-sigma there and the check's limit [m], and the sections' stations."""

    check: str
    direction: str
    sleepers: np.ndarray
    sigma_m: float
    limit_m: float
    stretches_m: tuple[tuple[float, float], ...]

    def where(self) -> str:
        return ", ".join(f"{a:.0f}-{b:.0f} m" for a, b in self.stretches_m)

    def label(self) -> str:
        return f"{self.check} {self.direction}".strip()


def not_assessable(profile: ToleranceProfile, quality: SectionQuality | None, station_m: np.ndarray) -> list[NotAssessable]:
    """Every check and direction of ``profile`` whose stated 1-sigma in some section of ``quality`` is
    beyond what its limit resolves, with the sleepers (at ``station_m``) of those sections."""
    if quality is None or not len(quality.station_from_m):
        return []
    station = np.asarray(station_m, dtype=float)
    # a sleeper's section: the one its station falls in (before the first / after the last: those)
    section = np.clip(np.searchsorted(quality.station_from_m, station, side="right") - 1, 0,
                      len(quality.station_from_m) - 1)
    out = []
    for check in profile.checks:
        limit = min(abs(check.lower), abs(check.upper))
        if not np.isfinite(limit) or limit <= 0.0:
            continue
        for direction in check.directions or ("",):
            figure = stated_figure(check, direction)
            if figure is None:
                continue
            sigma = figure[1] * np.asarray(getattr(quality, figure[0]), dtype=float)
            with np.errstate(invalid="ignore"):
                beyond = sigma > limit / RESOLVE_SIGMAS
            if not beyond.any():
                continue
            stretches = tuple((float(quality.station_from_m[k]), float(quality.station_to_m[k]))
                              for k in np.flatnonzero(beyond))
            out.append(NotAssessable(check.name, direction, beyond[section] & np.isfinite(station),
                                     float(np.nanmax(sigma[beyond])), limit, _joined(stretches)))
    return out


def _joined(stretches: tuple[tuple[float, float], ...]) -> tuple[tuple[float, float], ...]:
    """Adjacent sections as one stretch."""
    joined: list[tuple[float, float]] = []
    for a, b in stretches:
        if joined and abs(joined[-1][1] - a) < 1e-6:
            joined[-1] = (joined[-1][0], b)
        else:
            joined.append((a, b))
    return tuple(joined)


def masks(found: list[NotAssessable]) -> dict[tuple[str, str], np.ndarray]:
    """(check, direction) -> the sleepers whose values of that check are not assessed
    (:func:`insrail.track.exceedance.assess`'s ``not_assessed``)."""
    return {(n.check, n.direction): n.sleepers for n in found}


def left_out(found: list[NotAssessable], everything: Assessment, assessed: Assessment) -> list[int]:
    """Per entry of ``found``: how many exceedances the full assessment lists that ``assessed`` leaves out."""
    def count(assessment, n):
        return sum(1 for e in assessment.exceedances if e.check == n.check and e.direction == n.direction)

    return [count(everything, n) - count(assessed, n) for n in found]


def notices(found: list[NotAssessable], dropped: list[int]) -> list[Notice]:
    """A warning per check and direction not assessed somewhere."""
    return [Notice("assessment", "{check}: not assessable at the stated 1-sigma {sigma_mm:.2f} mm (quality.csv) "
                                 "against its limit {limit_mm:.1f} mm (the survey's noise alone would cross it) over "
                                 "{where}: {sleepers} sleepers not assessed for it, {exceedances} exceedances there not "
                                 "listed; a better IMU, slower pushing or more control makes it assessable",
                   station_m=n.stretches_m[0][0],
                   fields={"check": Phrase("{check} {direction}", {"check": n.check, "direction": Phrase(n.direction)})
                           if n.direction else n.check,
                           "sigma_mm": 1e3 * n.sigma_m, "limit_mm": 1e3 * n.limit_m, "where": n.where(),
                           "sleepers": int(n.sleepers.sum()), "exceedances": k})
            for n, k in zip(found, dropped)]


def summary_section(found: list[NotAssessable], dropped: list[int]) -> list[dict]:
    """summary.toml ``[[assessment.not_assessable]]``."""
    return [{"check": n.check, "direction": n.direction, "sigma_mm": round(1e3 * n.sigma_m, 3),
             "limit_mm": round(1e3 * n.limit_m, 3), "sleepers": int(n.sleepers.sum()), "exceedances_not_listed": k,
             "stretches_m": [[round(a, 3), round(b, 3)] for a, b in n.stretches_m]}
            for n, k in zip(found, dropped)]
