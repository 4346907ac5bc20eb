"""Integrity of a fused solution: is it as good as its stated 1-sigma, and where is it not?

The forward filter tests every observation of every aiding source against its predicted
innovation covariance (the normalised innovation squared, NIS, chi-square with the
observation's degrees of freedom when the filter's 1-sigma is right). This module turns
that record into a verdict per section of track and for the whole survey:

- per aiding source and per section (200 m of travelled distance by default) the number of
  observations, the share rejected by the gate and the mean NIS per degree of freedom of the
  used ones (1 when the stated 1-sigma fits; 4 means the residuals are twice their 1-sigma);
- a section is **not valid** when, for any source with at least ``MIN_OBSERVATIONS`` there,
  more than ``MAX_REJECTED_SHARE`` of its trusted observations were rejected (a GNSS float
  stretch rejected is the receiver's fault, not the solution's) or the mean NIS per degree of
  freedom of the used ones exceeds ``MAX_NIS_PER_DOF``;
- each filter reset (``insrail.nav.fusion.FilterReset``) makes the time from the last accepted
  observation of the source it was reset for before the run's first rejection to
  ``RESET_SETTLE_S`` after the reset suspect: the solution was wrong there, or converging again.
  The fault that started the run lies after that last agreement, not at the first rejection: a
  single bad IMU record 35 ms before a sleeper pulse spoils that sleeper's pose before the next
  odometer update is rejected;
- two resets of one source whose jumps undo each other (:data:`DETOUR_SHARE`: the median innovations of
  the runs of rejections they ended add up to little of either) bracket a **detour**: the source went
  off and came back (a false fix of a few tens of seconds), the first reset moved the solution onto it
  and the second one back. The solution between them followed the source off the track, agreeing with
  it and so with its own 1-sigma: the whole time from the first reset's suspect start to the second
  one's end is suspect (a 1 m false fix of 40 s left 18 sleepers between the two resets' intervals
  valid, 537 mm off the design);
- a reset of a position source that no later one undoes is a **step**: the source said one thing before it
  and another after it, and the solution follows it; which side is right cannot be told, and the absolute
  position on one side is off by about the jump (a GNSS fix that stayed 0.5 m off left the deviations from the
  design 0.28-0.5 m off after it). Said as a warning at the reset (:func:`steps`); the chord checks either
  side are not affected;
- every position fix (a prism on CPIII control), accepted or rejected by the forward filter, is
  compared with the final trajectory (:func:`missed_fixes`): a trajectory that misses a fix by
  more than the filter's gate, against the fix's and its own 1-sigma, is not valid from the
  fix before it to the fix after it (what ties it there is that fix). The filter's record alone
  cannot see this: after a reset it may converge on a wrong heading whose later fixes, rejected
  or re-admitted with a wide covariance, all look consistent with its 1-sigma;
- a survey whose not-valid sections, or whose stretches between missed fixes, cover more than
  ``MOSTLY`` of its travelled length cannot be trusted: :class:`UntrustedSolution` says which
  sources and sections, and why.

Sleepers passed inside a not-valid section or a suspect interval are flagged and not assessed
(``insrail.project.pipeline``). Sections are cut on the forward solution's travelled distance,
so the verdict does not depend on the odometer.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from insrail.nav import earth
from insrail.nav.rotation import euler_to_dcm
from insrail.notices import Phrase, phrase_of

MIN_OBSERVATIONS = 5
MAX_REJECTED_SHARE = 0.2
MAX_NIS_PER_DOF = 4.0
RESET_SETTLE_S = 10.0
#: two resets of one source make a detour where their jumps add up to at most this share of the larger
DETOUR_SHARE = 0.5
MOSTLY = 0.5
SECTION_M = 200.0


class UntrustedSolution(ValueError):
    """The fused solution is inconsistent with its own 1-sigma over most of the survey."""


@dataclass(frozen=True)
class InnovationRecord:
    """Every observation the forward filter gated, in the order it did: the observation's time,
    its source (index into ``names``), NIS, degrees of freedom, whether it was used and whether it
    claimed its full accuracy (a GNSS float solution does not: its rejection is its own fault)."""

    names: tuple[str, ...]
    time_s: np.ndarray
    source: np.ndarray
    nis: np.ndarray
    dof: np.ndarray
    accepted: np.ndarray
    trusted: np.ndarray
    #: (n, rows) the innovation of each observation's rows in its model's units (NaN beyond its
    #: degrees of freedom; float32: what the variance estimates of ``insrail.nav.self_calibration`` need)
    innovation: np.ndarray | None = None
    #: (n, rows) each row's innovation variance as the filter modelled it: its own part H P- H^T and the
    #: measurement noise R (float32; the noise estimates of ``insrail.nav.self_calibration``)
    filter_variance: np.ndarray | None = None
    noise_variance: np.ndarray | None = None


@dataclass(frozen=True)
class FusionIntegrity:
    """The verdict per section and for the survey. Per section k and source s: ``count[k, s]``
    trusted observations, ``rejected_share[k, s]`` of them rejected, ``nis_per_dof[k, s]`` the mean NIS
    per degree of freedom of the used ones (NaN without any). ``suspect_s``: (start, end, why) of
    the filter resets."""

    names: tuple[str, ...]
    station_from_m: np.ndarray
    station_to_m: np.ndarray
    time_from_s: np.ndarray
    time_to_s: np.ndarray
    count: np.ndarray
    rejected_share: np.ndarray
    nis_per_dof: np.ndarray
    valid: np.ndarray
    reasons: tuple[Phrase, ...]
    suspect_s: tuple[tuple[float, float, Phrase], ...]
    invalid_share: float  # of the travelled length
    #: why the whole survey is inconsistent though its sections are not (``insrail.nav.self_calibration``:
    #: the GNSS positions still disagreeing with the solution when its passes ran out); "" when not
    inconsistent: str = ""
    #: (start, end, why) in seconds of week around each position fix the trajectory misses
    #: (:func:`missed_fixes`) and their share of the travelled length
    missed_s: tuple[tuple[float, float, Phrase], ...] = ()
    missed_share: float = 0.0
    #: (start, end, why) in seconds of week of each detour between two resets (:func:`detours`)
    detours_s: tuple[tuple[float, float, Phrase], ...] = ()
    #: (time, jump [m], why) of each reset of a position source that stayed (:func:`steps`)
    steps_s: tuple[tuple[float, float, Phrase], ...] = ()

    @property
    def trusted(self) -> bool:
        return not (self.invalid_share > MOSTLY or self.missed_share > MOSTLY or self.inconsistent)

    def not_valid_intervals(self) -> list[tuple[float, float, str]]:
        """(start, end, why) in seconds of week: the not-valid sections and the suspect intervals."""
        out = [(float(self.time_from_s[k]), float(self.time_to_s[k]),
                (f"fusion inconsistent in section {self.station_from_m[k]:.0f}-{self.station_to_m[k]:.0f} m: "
                 f"{self.reasons[k]}")) for k in np.flatnonzero(~self.valid)]
        return out + list(self.suspect_s) + list(self.detours_s) + list(self.missed_s)

    def summary(self) -> Phrase:
        bad = int(np.sum(~self.valid))
        return Phrase(
            "{consistent} of {sections} sections of {section_m:.0f} m consistent with their 1-sigma{bad}{resets}{detours}"
            "{steps}{missed}{inconsistent}",
            {"consistent": len(self.valid) - bad, "sections": len(self.valid), "section_m": SECTION_M,
             "bad": Phrase("; not valid: {share_pct:.0f} % of the length", {"share_pct": 100 * self.invalid_share})
             if bad else Phrase(""),
             "resets": Phrase("; {count} filter reset(s)", {"count": len(self.suspect_s)}) if self.suspect_s else Phrase(""),
             "detours": Phrase("; {count} detour(s) of a source between two resets", {"count": len(self.detours_s)})
             if self.detours_s else Phrase(""),
             "steps": Phrase("; {count} step(s) of a position source that stayed", {"count": len(self.steps_s)})
             if self.steps_s else Phrase(""),
             "missed": Phrase("; {count} position fix(es) missed by the trajectory beyond their 1-sigma ({share_pct:.0f} % "
                              "of the length)", {"count": len(self.missed_s), "share_pct": 100 * self.missed_share})
             if self.missed_s else Phrase(""),
             "inconsistent": f"; inconsistent: {self.inconsistent}" if self.inconsistent else ""})

    def failure(self) -> str:
        """Why the survey cannot be trusted (for :class:`UntrustedSolution`)."""
        worst = []
        for s, name in enumerate(self.names):
            counted = self.count[:, s] > 0
            if not counted.any():
                continue
            rejected = np.nansum(self.rejected_share[counted, s] * self.count[counted, s]) / self.count[counted, s].sum()
            with np.errstate(invalid="ignore"):
                nis = np.nanmedian(self.nis_per_dof[counted, s]) if np.isfinite(self.nis_per_dof[counted, s]).any() \
                    else math.nan
            worst.append(f"{name} {100 * rejected:.0f} % rejected, NIS {nis:.1f} x its degrees of freedom")
        if self.invalid_share > MOSTLY:
            where = (f"over {100 * self.invalid_share:.0f} % of the survey ({int(np.sum(~self.valid))} of "
                     f"{len(self.valid)} sections)")
        elif self.missed_share > MOSTLY:
            where = (f"over {100 * self.missed_share:.0f} % of the survey, where it misses {len(self.missed_s)} "
                     f"position fixes ({self.missed_s[0][2]})")
        else:
            where = self.inconsistent
        return (f"the fused solution is inconsistent with its own 1-sigma {where}: " + "; ".join(worst)
                + ". Check the lever arms and mounting angles in survey.toml, the IMU profile (a MEMS unit carried "
                  "by hand or shaken: mems_handheld) and the GNSS solution's time scale and sigmas")

    def to_dict(self) -> dict:
        """For fusion_log.toml and summary.toml (no NaN: TOML readers choke on it); ``summary`` a phrase's table
        (:mod:`insrail.notices`: the report says it in its language)."""
        def clean(x):
            return [round(float(v), 3) if np.isfinite(v) else -1.0 for v in x]

        return {"trusted": self.trusted, "invalid_share": round(self.invalid_share, 4), "summary": self.summary().to_dict(),
                "sources": list(self.names),
                "not_valid": [{"station_from_m": round(float(self.station_from_m[k]), 1),
                               "station_to_m": round(float(self.station_to_m[k]), 1),
                               "time_from_s": round(float(self.time_from_s[k]), 3),
                               "time_to_s": round(float(self.time_to_s[k]), 3), "reason": str(self.reasons[k]),
                               "why": phrase_of(self.reasons[k]).to_dict(),
                               "nis_per_dof": clean(self.nis_per_dof[k]),
                               "rejected_share": clean(self.rejected_share[k])}
                              for k in np.flatnonzero(~self.valid)],
                "suspect": [{"time_from_s": round(a, 3), "time_to_s": round(b, 3), "reason": str(why),
                             "why": phrase_of(why).to_dict()} for a, b, why in self.suspect_s],
                "detours": [{"time_from_s": round(a, 3), "time_to_s": round(b, 3), "reason": str(why),
                             "why": phrase_of(why).to_dict()} for a, b, why in self.detours_s],
                "steps": [{"time_s": round(at, 3), "jump_m": round(off, 3), "reason": str(why),
                           "why": phrase_of(why).to_dict()} for at, off, why in self.steps_s],
                "missed_fixes": [{"time_from_s": round(a, 3), "time_to_s": round(b, 3), "reason": str(why),
                                  "why": phrase_of(why).to_dict()} for a, b, why in self.missed_s],
                "missed_share": round(self.missed_share, 4)}


def travelled_m(north_m: np.ndarray, east_m: np.ndarray) -> np.ndarray:
    """Cumulative horizontal distance along a sequence of positions [m]."""
    return np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(north_m), np.diff(east_m)))])


def last_agreement_s(record: InnovationRecord, source: str, first_rejected_s: float) -> float:
    """The time of the last observation of ``source`` accepted before ``first_rejected_s`` (that
    time itself when there is none: the run began with the source)."""
    if source not in record.names:
        return first_rejected_s
    agreed = record.accepted & (record.source == record.names.index(source)) & (record.time_s < first_rejected_s)
    return float(record.time_s[agreed].max()) if agreed.any() else first_rejected_s


def reset_jump(record: InnovationRecord, reset) -> np.ndarray | None:
    """Where a filter reset of a position source moved the solution: the median innovation (NED m) of the run
    of rejected observations it ended; None without the record's innovations."""
    if record.innovation is None or reset.source not in record.names:
        return None
    run = ((record.source == record.names.index(reset.source)) & ~record.accepted
           & (record.time_s >= reset.first_rejected_s) & (record.time_s <= reset.time_s))
    rows = np.asarray(record.innovation[run][:, :3], dtype=float)
    if not len(rows) or not np.isfinite(rows).all(axis=0).any():
        return None
    return np.nanmedian(rows, axis=0)


def detours(resets, jumps, suspect) -> tuple[tuple[tuple[float, float, Phrase], ...], set[int]]:
    """(start, end, why) of every detour (module docstring), and the indices of the resets that make them: two
    resets in a row of one source whose ``jumps`` (per reset, :func:`reset_jump`; None: not a position source)
    add up to at most :data:`DETOUR_SHARE` of the larger, from the first one's suspect start to the second
    one's suspect end (``suspect``: the resets' intervals, in their order)."""
    out, paired = [], set()
    for source in {reset.source for reset in resets}:  # a reset of another source between them does not part them
        order = sorted((i for i, reset in enumerate(resets) if reset.source == source), key=lambda i: resets[i].time_s)
        for a, b in zip(order, order[1:]):
            there, back = jumps[a], jumps[b]
            if there is None or back is None or a in paired:
                continue
            off = float(np.linalg.norm(np.nan_to_num(there)))
            if float(np.linalg.norm(np.nan_to_num(there + back))) > DETOUR_SHARE * max(off, float(np.linalg.norm(np.nan_to_num(back)))):
                continue
            paired |= {a, b}
            out.append((suspect[a][0], suspect[b][1],
                        Phrase("between the filter resets at t = {first_s:.1f} s and {second_s:.1f} s the solution followed "
                               "{source} {off_m:.3f} m off and back: the source was wrong there (a false fix), or before and "
                               "after", {"first_s": resets[a].time_s, "second_s": resets[b].time_s,
                                         "source": Phrase(source), "off_m": off})))
    return tuple(sorted(out, key=lambda interval: interval[0])), paired


def steps(resets, jumps, paired: set[int]) -> tuple[tuple[float, float, Phrase], ...]:
    """(reset time, jump [m], why) of every reset of a position source that no later one undid (not in
    ``paired``, :func:`detours`): the solution stays on the source's side of the jump, and the source said
    one thing before it and another after. Which side is right the filter cannot tell; the chord checks on
    either side are not affected (the sleepers in the reset's suspect interval are not assessed), but the
    absolute position on one side is off by about the jump: said where it happened."""
    out = []
    for index, (reset, jump) in enumerate(zip(resets, jumps)):
        if jump is None or index in paired:
            continue
        off = float(np.linalg.norm(np.nan_to_num(jump)))
        out.append((reset.time_s, off,
                    Phrase("after the filter reset at t = {time_s:.1f} s the solution follows {source} {off_m:.3f} m from "
                           "where it was: the absolute position (the deviations from the design) before or after it is off "
                           "by about that much, a wrong fix that stayed or one before it; check against a control point",
                           {"time_s": reset.time_s, "source": Phrase(reset.source), "off_m": off})))
    return tuple(out)


def missed_fixes(trajectory, fixes, gate: float, ellipsoid) -> tuple[tuple[float, float, Phrase], ...]:
    """(start, end, why) around every fix of the ``PositionFix`` sources ``fixes`` that ``trajectory``
    misses: the point at the fix's lever arm, interpolated to its time, off the fix by a normalised
    squared residual beyond ``gate`` (the filter's 3-row chi-square gate) against the fix's variance
    plus the trajectory's position variance (their sum: the fix is in the trajectory when it was used,
    so this overstates the residual's variance and does not flag a fix the trajectory holds). The
    interval runs from the fix before to the fix after it (the trajectory's start or end without one)."""
    t = np.asarray(trajectory.time_s, dtype=float)
    out = []
    for fix in fixes:
        time_s = np.asarray(fix.time_s, dtype=float)
        inside = np.flatnonzero((time_s >= t[0]) & (time_s <= t[-1]))
        if not len(inside):
            continue
        ts = time_s[inside]
        lat, lon, h = (np.interp(ts, t, np.asarray(x, dtype=float))
                       for x in (trajectory.lat_rad, trajectory.lon_rad, trajectory.height_m))
        rpy = np.column_stack([np.interp(ts, t, np.unwrap(np.asarray(trajectory.rpy_rad[:, k], dtype=float)))
                               for k in range(3)])
        sigma_traj = np.column_stack([np.interp(ts, t, np.asarray(trajectory.sigma_pos_ned_m[:, k], dtype=float))
                                      for k in range(3)])
        lever_ned = euler_to_dcm(rpy[:, 0], rpy[:, 1], rpy[:, 2]) @ np.asarray(fix.lever_arm_m, dtype=float)
        r_m, r_n = earth.radii(lat, ellipsoid)
        residual = lever_ned - np.column_stack([(fix.lat[inside] - lat) * (r_m + h),
                                                (fix.lon[inside] - lon) * (r_n + h) * np.cos(lat),
                                                -(fix.h[inside] - h)])
        variance = np.square(np.asarray(fix.sigma_m, dtype=float)[inside])[:, None] + np.square(sigma_traj)
        nis = np.sum(residual**2 / variance, axis=1)
        order = np.sort(time_s)
        for k in np.flatnonzero(nis > gate):
            before, after = order[order < ts[k]], order[order > ts[k]]
            off = float(np.linalg.norm(residual[k]))
            out.append((float(before[-1]) if len(before) else float(t[0]),
                        float(after[0]) if len(after) else float(t[-1]),
                        Phrase("the trajectory misses the {source} at t = {time_s:.1f} s by {off_m:.3f} m, {ratio:.0f} x "
                               "its 1-sigma", {"source": Phrase(fix.name), "time_s": ts[k], "off_m": off,
                                                "ratio": math.sqrt(nis[k])})))
    return tuple(sorted(out))


def _share(intervals, time_s: np.ndarray, station_m: np.ndarray) -> float:
    """The share of the travelled length inside the union of the (start, end, ...) intervals."""
    length = float(station_m[-1] - station_m[0])
    if not intervals or length <= 0:
        return 0.0
    covered = np.zeros(len(time_s), dtype=bool)
    for start, end, *_ in intervals:
        covered |= (time_s >= start) & (time_s <= end)
    return float(np.sum(np.diff(station_m)[covered[1:] & covered[:-1]]) / length)


def assess(record: InnovationRecord, time_s: np.ndarray, station_m: np.ndarray, resets=(),
           section_m: float = SECTION_M, missed=(), positions=frozenset()) -> FusionIntegrity:
    """The integrity of a forward pass whose update epochs ``time_s`` lie at ``station_m``
    (non-decreasing travelled distance) with the observations in ``record``; ``missed``: the
    intervals around the position fixes the final trajectory misses (:func:`missed_fixes`);
    ``positions``: the sources whose innovations are positions (:func:`detours`)."""
    length = float(station_m[-1] - station_m[0])
    n = max(int(math.floor(length / section_m + 0.75)), 1)  # the last section takes the remainder
    edges = station_m[0] + section_m * np.arange(n + 1)
    edges[-1] = station_m[-1]
    epoch_section = np.clip(np.searchsorted(edges, station_m, side="right") - 1, 0, n - 1)
    obs_station = np.interp(record.time_s, time_s, station_m)
    obs_section = np.clip(np.searchsorted(edges, obs_station, side="right") - 1, 0, n - 1)
    n_src = len(record.names)
    count = np.zeros((n, n_src))
    rejected = np.zeros((n, n_src))
    nis_sum = np.zeros((n, n_src))
    dof_sum = np.zeros((n, n_src))
    gated = np.isfinite(record.nis) & record.trusted
    np.add.at(count, (obs_section[gated], record.source[gated]), 1.0)
    bad = gated & ~record.accepted
    np.add.at(rejected, (obs_section[bad], record.source[bad]), 1.0)
    good = np.isfinite(record.nis) & record.accepted
    np.add.at(nis_sum, (obs_section[good], record.source[good]), record.nis[good])
    np.add.at(dof_sum, (obs_section[good], record.source[good]), record.dof[good])
    with np.errstate(invalid="ignore", divide="ignore"):
        share = np.where(count > 0, rejected / np.maximum(count, 1.0), np.nan)
        nis_per_dof = np.where(dof_sum > 0, nis_sum / np.maximum(dof_sum, 1.0), np.nan)
    enough = count >= MIN_OBSERVATIONS
    too_many_rejected = enough & (share > MAX_REJECTED_SHARE)
    too_large = enough & (nis_per_dof > MAX_NIS_PER_DOF)
    reasons = []
    for k in range(n):
        why = [Phrase("{source} {share_pct:.0f} % rejected", {"source": Phrase(record.names[s]), "share_pct": 100 * share[k, s]})
               for s in np.flatnonzero(too_many_rejected[k])]
        why += [Phrase("{source} residuals {ratio:.1f} x their 1-sigma",
                       {"source": Phrase(record.names[s]), "ratio": math.sqrt(nis_per_dof[k, s])})
                for s in np.flatnonzero(too_large[k] & ~too_many_rejected[k])]
        reasons.append(Phrase("{reasons}", {"reasons": why}))
    valid = ~(too_many_rejected | too_large).any(axis=1)
    time_from = np.array([time_s[epoch_section == k].min() if np.any(epoch_section == k) else np.nan for k in range(n)])
    time_to = np.array([time_s[epoch_section == k].max() if np.any(epoch_section == k) else np.nan for k in range(n)])
    widths = np.diff(edges)
    invalid_share = float(widths[~valid].sum() / widths.sum()) if widths.sum() > 0 else float(np.mean(~valid))
    suspect = tuple((last_agreement_s(record, reset.source, reset.first_rejected_s), reset.time_s + RESET_SETTLE_S,
                     reset.message()) for reset in resets)
    jumps = [reset_jump(record, reset) if reset.source in positions else None for reset in resets]
    found, paired = detours(resets, jumps, suspect)
    return FusionIntegrity(record.names, edges[:-1].copy(), edges[1:].copy(), time_from, time_to, count, share,
                           nis_per_dof, valid, tuple(reasons), suspect, invalid_share, missed_s=tuple(missed),
                           missed_share=_share(missed, np.asarray(time_s), np.asarray(station_m)),
                           detours_s=found, steps_s=steps(resets, jumps, paired))
