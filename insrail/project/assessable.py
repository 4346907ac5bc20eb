"""Checks the survey's stated accuracy cannot resolve: not assessed where that is so, and said so.

**The one rule** (:func:`decides`, used here for every survey and by ``insrail.project.relative_survey``
for the per-section verdicts of a relative survey): a check is assessable in a section where its stated
1-sigma there lets it decide against its limit, i.e. where three of them fit within the limit
(:data:`RESOLVE_SIGMAS`). Why three, as a surveyor expects:

* the survey's noise alone must not cross the limit: at 3 sigma within it a track that is in tolerance
  is reported out of tolerance at 0.3 % of independent values (at 1 sigma: a third of them, the MEMS
  survey's 250 exceedances that meant nothing); an exceedance listed is then the track's, not the noise's;
* it is the rule the plan of the survey already uses (``insrail predict``, ``insrail.quality.tables``: a
  figure passes when its 3 sigma is within the limit) and the thesis's (5.3.1.2: a 2 mm cross-level limit
  asks for a measurement to 0.3 mm or better), so what a plan calls assessable is what processing assesses;
* a rule of 1 sigma would assess a relative survey's 300 m/150 m check with its 150 m lag at 3-5 mm against
  the 10 mm limit, and list exceedances made of the IMU's drift.

A check of the tolerance profile whose value the survey states a 1-sigma for (``quality.csv``: the
30 m/5 m differential versine by the 5 m lag, the 300 m/150 m one by the 150 m lag, a 10 m versine
by the 5 m lag (:func:`stated_figure`), the cross-level by its own) is not assessed over the 200 m
sections where the rule says so: its values there are left out of ``sleepers.csv`` and its exceedances
out of ``exceedances.csv``, and a warning names the check, the stations, the stated 1-sigma against the
limit and how many exceedances were left out (CLI, summary, PDF, GUI log).
``summary.toml [[assessment.not_assessable]]`` holds the same per check and direction. A section without
a stated figure (NaN: no lag pair has its midpoint there, within half the lag of the run's ends) holds no
value of that check either: nothing to mask.

Checks without a stated figure (gauge, twist, rates, other chords) are assessed as before: the gauge
is measured by its own sensor; the twist's error is the change of the cross-level's over a few metres,
far smaller than the cross-level's 1-sigma (mostly an accelerometer bias, constant over them).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from insrail.notices import Notice, Phrase
from insrail.quality.section_quality import LONG_LAG_M, SHORT_LAG_M, SectionQuality
from insrail.track.exceedance import Assessment
from insrail.track.tolerance import Check, ToleranceProfile

#: a check is assessable where this many of its stated 1-sigma fit within its limit (the module docstring)
RESOLVE_SIGMAS = 3.0
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


def decides(sigma_m, limit_m: float) -> np.ndarray:
    """Where a check of limit ``limit_m`` is assessable at the stated 1-sigma ``sigma_m`` (per section; NaN:
    no figure, not assessable): :data:`RESOLVE_SIGMAS` of them within the limit (the module docstring)."""
    sigma = np.asarray(sigma_m, dtype=float)
    with np.errstate(invalid="ignore"):
        return np.isfinite(sigma) & (RESOLVE_SIGMAS * sigma <= limit_m)


def check_limit_m(check: Check) -> float:
    """The limit a check's stated 1-sigma is judged against: the nearer of its bounds [m]."""
    return float(min(abs(check.lower), abs(check.upper)))


def section_sigma_m(check: Check, quality: SectionQuality, direction: str) -> np.ndarray | None:
    """The stated 1-sigma of ``check``'s values in ``direction`` per section of ``quality``, or None where
    the survey states none for it (:func:`stated_figure`)."""
    figure = stated_figure(check, direction)
    if figure is None:
        return None
    return figure[1] * np.asarray(getattr(quality, figure[0]), dtype=float)


def sleeper_sigmas(profile: ToleranceProfile, quality: SectionQuality | None,
                   station_m: np.ndarray) -> dict[tuple[str, str], np.ndarray]:
    """(check name, direction) -> the stated 1-sigma of its values at each sleeper at ``station_m`` (the
    figure of the section holding it; NaN where that section states none), for every check of ``profile``
    the survey states a figure for (:func:`stated_figure`). What a tamping re-design holds its checks
    inside their limits by (``insrail.project.redesign``)."""
    if quality is None or not len(quality.station_from_m):
        return {}
    section = _section_of(np.asarray(station_m, dtype=float), quality)
    out = {}
    for check in profile.checks:
        for direction in check.directions or ("",):
            sigma = section_sigma_m(check, quality, direction)
            if sigma is not None:
                out[(check.name, direction)] = sigma[section]
    return out


def _section_of(station: np.ndarray, quality: SectionQuality) -> np.ndarray:
    """A sleeper's section: the one its station falls in (before the first / after the last: those)."""
    return np.clip(np.searchsorted(quality.station_from_m, station, side="right") - 1, 0,
                   len(quality.station_from_m) - 1)


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
    # a line section's (insrail.project.section): per stretch, the runs whose stated 1-sigma leaves it out there
    surveys: tuple[tuple[str, ...], ...] = ()

    def where(self) -> str:
        return ", ".join(f"{a:.0f}-{b:.0f} m" + (f" ({', '.join(runs)})" if runs else "")
                         for (a, b), runs in zip(self.stretches_m, self.surveys or ((),) * len(self.stretches_m)))

    def label(self) -> str:
        return f"{self.check} {self.direction}".strip()


def not_assessable(profile: ToleranceProfile, quality: SectionQuality | None, station_m: np.ndarray) -> list[NotAssessable]:
    """Every check and direction of ``profile`` whose stated 1-sigma in some section of ``quality`` is
    beyond what its limit resolves, with the sleepers (at ``station_m``) of those sections."""
    if quality is None or not len(quality.station_from_m):
        return []
    station = np.asarray(station_m, dtype=float)
    section = _section_of(station, quality)
    out = []
    for check in profile.checks:
        limit = check_limit_m(check)
        if not np.isfinite(limit) or limit <= 0.0:
            continue
        for direction in check.directions or ("",):
            sigma = section_sigma_m(check, quality, direction)
            if sigma is None:
                continue
            beyond = np.isfinite(sigma) & ~decides(sigma, limit)  # no figure: no value of the check there
            if not beyond.any():
                continue
            # the first and last sections also hold the sleepers before and after them (``section``)
            first, last = _ends(station, quality)
            stretches = tuple((first if k == 0 else float(quality.station_from_m[k]),
                               last if k == len(beyond) - 1 else float(quality.station_to_m[k]))
                              for k in np.flatnonzero(beyond))
            out.append(NotAssessable(check.name, direction, beyond[section] & np.isfinite(station),
                                     float(np.nanmax(sigma[beyond])), limit, _joined(stretches)))
    return out


def _ends(station: np.ndarray, quality: SectionQuality) -> tuple[float, float]:
    """The first section's start and the last's end, widened to the sleepers beyond them."""
    finite = station[np.isfinite(station)]
    first, last = float(quality.station_from_m[0]), float(quality.station_to_m[-1])
    if not len(finite):
        return first, last
    return min(first, float(finite.min())), max(last, float(finite.max()))


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


#: The warning of a check not assessed somewhere (:func:`notices`; a line section knows its runs' by it).
NOTICE = ("{check}: not assessable at the stated 1-sigma {sigma_mm:.2f} mm (quality.csv) against its limit {limit_mm:.1f} "
          "mm ({sigmas:g} sigma beyond it: the survey's noise alone would cross it) over {where}: {sleepers} sleepers not "
          "assessed for it, {exceedances} exceedances there not listed; a better IMU, slower pushing or more control "
          "makes it assessable")


def notices(found: list[NotAssessable], dropped: list[int]) -> list[Notice]:
    """A warning per check and direction not assessed somewhere."""
    return [Notice("assessment", NOTICE, station_m=n.stretches_m[0][0],
                   fields={"check": Phrase("{check} {direction}", {"check": n.check, "direction": Phrase(n.direction)})
                           if n.direction else n.check,
                           "sigma_mm": 1e3 * n.sigma_m, "limit_mm": 1e3 * n.limit_m, "sigmas": RESOLVE_SIGMAS,
                           "where": n.where(),
                           "sleepers": int(n.sleepers.sum()), "exceedances": k})
            for n, k in zip(found, dropped)]


def summary_section(found: list[NotAssessable], dropped: list[int]) -> list[dict]:
    """summary.toml ``[[assessment.not_assessable]]``."""
    return [{"check": n.check, "direction": n.direction, "sigma_mm": round(1e3 * n.sigma_m, 3),
             "limit_mm": round(1e3 * n.limit_m, 3), "sleepers": int(n.sleepers.sum()), "exceedances_not_listed": k,
             "stretches_m": [[round(a, 3), round(b, 3)] for a, b in n.stretches_m],
             **({"surveys": [list(runs) for runs in n.surveys]} if n.surveys else {})}
            for n, k in zip(found, dropped)]
