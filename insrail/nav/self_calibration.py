"""Fusion passes until the filter's stated 1-sigma is consistent with its aiding.

Two things a survey's files or its set-up may state wrongly, and which the first pass of the
filter measures (its normalised innovations, ``insrail.nav.integrity``):

* **the non-holonomic constraint** (the trolley neither slides sideways nor lifts off the rails)
  holds for a rail vehicle, not for a hand-held device or a vehicle that slides. Without an
  odometer the NHC is the only velocity aid besides GNSS, and where it does not hold the filter
  fights it: more than :data:`NHC_MAX_REJECTED` of its rows rejected. The survey is then fused
  again without it (a notice says so). With an odometer a failing NHC means a wrong lever arm or
  mounting, which the integrity verdict reports; it is not switched off.
* **the GNSS file's sigmas**: a receiver's own RTK sigmas are often optimistic by a factor of 2-3
  (a hand-held u-blox: 1 cm stated, 3 cm found). When more than :data:`GNSS_MAX_REJECTED` of the
  fixed (trusted) GNSS positions are rejected, or their mean NIS per degree of freedom exceeds
  :data:`GNSS_MAX_NIS_PER_DOF`, *and* the bulk of them disagrees too (the median NIS per degree of
  freedom over its chi-square median above :data:`GNSS_MIN_ROBUST_NIS`: not a false fix of some
  seconds, whose rejection is right), the sigmas are scaled by the factor their innovations show (the
  square root of that median ratio, between
  :data:`MIN_STEP` and :data:`MAX_STEP` per pass: a pass whose filter was lost or reset overstates
  the GNSS noise, so the iteration is damped) and the survey fused again, up to
  :data:`MAX_PASSES` passes, the scale at most :data:`MAX_GNSS_SCALE`. The notice names the factor.

* **the trolley's play** (``resources/trolley_play.toml``: its frame's yaw and pitch about the rail,
  the NHC's noise and the position process noise of ``error_model.play_noise``) differs from trolley
  to trolley: one without play has NHC innovations six times smaller than the profile's play gives.
  Once the aiding is consistent, the play is estimated from the NHC's lateral and vertical innovations
  (:func:`play_from_innovations`, a variance-component estimate under the play's own spectrum) and,
  where it differs from the one the pass ran with by more than :data:`PLAY_TOLERANCE`, the survey is
  fused again with it (the NHC's 1-sigma scaled with it: both stand for one process), up to
  :data:`MAX_PLAY_PASSES` such passes. The result is stated in the calibration
  (``play_drift_mm2_per_m`` against the profile's) and a notice; the covariance analyses run with the
  options of the pass they describe, so the stated accuracy has the same noise.

* **the odometer's, the ZUPT's and the GNSS positions' noise** (per quality class: fix, float, ...), in the
  same passes as the play (:func:`noise_from_innovations`): each row's squared innovation is the filter's own
  part H P- H^T (recorded by the forward filter) plus the noise R, so the noise's variance factor is the
  excess of the rows' squared innovations over the filter's part per unit of R (:func:`variance_component`,
  the play's estimate with the filter's part known, outliers trimmed the same way; rejected rows count: the
  gate cuts the large innovations of a noise stated too small). A factor on the 1-sigma beyond
  :data:`NOISE_TOLERANCE` is applied (only ever widening: a filter pessimistic elsewhere takes too much of
  the innovations for its own part, so a narrower estimate is stated, not applied) (``odometer_sigma_scale``, ``zupt_sigma_scale``, the GNSS
  class's factor of ``gnss_quality_policy``; at most :data:`NOISE_RANGE` x the profile's either way) and the
  survey fused again, within the play's :data:`MAX_PLAY_PASSES`. Where the filter's own uncertainty makes up
  most of the innovations (the ZUPT of a still trolley: 2 um/s against its velocity's uncertainty) the survey
  does not say what the noise is and nothing is estimated. The estimates are in the calibration
  (``fusion_log.toml``, summary.toml); an applied one also in a notice (the PDF). On the project's simulator
  the odometer's and the GNSS fixes' come out at 0.98-1.01 of the profile's: nothing changes.

A survey still inconsistent when the passes run out cannot be trusted: its integrity verdict
says why (``FusionIntegrity.inconsistent``), and ``insrail fuse``/``process``/``batch`` fail it.

A survey the first pass finds consistent is fused once: clean surveys pay nothing and their
figures do not change. A short fault (a false fix of seconds, single outliers) stays below the
thresholds and is rejected, not absorbed into the sigmas. Scaling the sigmas only ever makes the
stated 1-sigma larger, never smaller.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from insrail.nav import chi2
from insrail.notices import Notice, Phrase

NHC_SOURCE = "odometer_nhc"
GNSS_SOURCE = "gnss_position"
NHC_MAX_REJECTED = 0.2
GNSS_MAX_REJECTED = 0.05
GNSS_MAX_NIS_PER_DOF = 2.0
GNSS_MIN_ROBUST_NIS = 1.5
MAX_PASSES = 4
MAX_GNSS_SCALE = 10.0
MIN_STEP = 1.4
MAX_STEP = 2.0
#: a pass whose play is within this factor of the estimate is kept
PLAY_TOLERANCE = 1.5
#: passes for the play and the aiding noises together
MAX_PLAY_PASSES = 3
#: the estimate stays within this factor of the profile's play either way
PLAY_RANGE = 100.0
#: below this square speed [m^2/s^2] an NHC row says nothing about the play
MIN_PLAY_SPEED2 = 0.1**2
#: rows left out around a removed IMU record or a bridged gap [s]
SUSPECT_MARGIN_S = 2.0
#: a row whose square innovation exceeds PLAY_TRIM^2 x what the median row implies is an outlier
PLAY_TRIM = 10.0
#: suspect times leaving fewer than this share of the moving rows are not left out
SUSPECT_MOSTLY = 0.5
#: fewer rows than this left (5 s of travel at 10 Hz): the survey does not say what its play is
MIN_PLAY_ROWS = 50
#: the aiding noises estimated besides the play (:func:`noise_from_innovations`)
ODOMETER = "odometer"
ZUPT_SOURCE = "zupt"
#: an aiding noise estimate within this factor of the 1-sigma the pass ran with is kept
NOISE_TOLERANCE = 1.5
#: the aiding noises stay within this factor of the profile's either way
NOISE_RANGE = 10.0
#: below this share of the innovations' variance a source's noise hides under the filter's own uncertainty
MIN_NOISE_SHARE = 0.2
#: the median of chi-square with one degree of freedom
CHI2_1_MEDIAN = 0.454936423119572
#: rows per block of the play's confidence limit: 10 s at 10 Hz, longer than a filter's velocity error
#: stays correlated, so the blocks' sums are about independent
PLAY_BLOCK_ROWS = 100
#: the play's upper confidence limit where the filter's own part is most of the NHC innovations:
#: this many standard errors above the estimate (one-sided 98 %)
PLAY_CONFIDENCE_SIGMAS = 2.0


@dataclass(frozen=True)
class SourceConsistency:
    """One aiding source over a pass: trusted observations gated, the share rejected, the mean NIS
    per degree of freedom of the used ones and the robust (median-based) one of all of them."""

    observations: int
    rejected_share: float
    nis_per_dof: float
    robust_nis_per_dof: float


def consistency(result, name: str) -> SourceConsistency | None:
    """The statistics of source ``name`` in a fusion result (None when the source did not run)."""
    record = result.innovations
    if record is None or name not in record.names:
        return None
    mine = (record.source == record.names.index(name)) & np.isfinite(record.nis) & record.trusted
    if not mine.any():
        return None
    nis, dof, accepted = record.nis[mine], record.dof[mine].astype(float), record.accepted[mine]
    used = accepted.any()
    mean = float(nis[accepted].sum() / dof[accepted].sum()) if used else math.inf
    # the median NIS per dof over its chi-square median: 1 when the stated sigmas fit
    robust = float(np.median(nis / dof) / np.median(chi2.median(dof) / dof))
    return SourceConsistency(int(mine.sum()), float(1.0 - accepted.mean()), mean, robust)


def play_from_innovations(result) -> tuple[float, float] | None:
    """(lateral, vertical) play drift [m^2 per metre run] the NHC's innovations of a pass show, or None
    where it cannot tell (no NHC, a trolley hardly moving). The NHC row's innovation is the rail
    point's velocity across the track in the trolley frame, v x yaw (pitch) of the play, plus the
    filter's own uncertainty; for the play's flat spectrum over the band B
    (:func:`insrail.nav.error_model.trolley_play_band_per_m`) its mean square at speed v is
    2 B v^2 x the drift per metre, over the filter's own part H P- H^T, which the forward filter records
    (the upper bound left it in: a tactical unit's own uncertainty made it 2x the simulator's play), and
    over the rows' noise that is not the play: the gyro's white noise through the NHC point's lever arm
    (``OdometerNhc.gyro_white_noise``; a tactical unit's made a trolley without play look like 0.009
    mm^2/m vertically). Where the filter's own part is more than 1 - :data:`MIN_NOISE_SHARE` of the rows'
    mean square (a MEMS unit; a trolley without play: its innovations are then the filter's own) the
    difference is uncertain, and the estimate is its upper confidence limit (:func:`play_upper_limit`:
    the difference would put a MEMS unit's play at its floor and fail the fusion; the plain upper bound
    kept a tactical trolley without play at 0.02 mm^2/m, its stated 5 m lags 1.2x pessimistic); where the
    filter's part is not recorded, the upper bound.

    Only the innovations of a filter that tracks the trolley say what its play is: the rows at rest
    (below :data:`MIN_PLAY_SPEED2`), those rejected, inside a filter reset's suspect time (its
    reconvergence after a fault the screening could not see) or within :data:`SUSPECT_MARGIN_S` of an
    IMU record the screening removed or a gap it bridged are left out (:func:`_play_rows`), unless that
    leaves less than :data:`SUSPECT_MOSTLY` of the moving rows (a pass reset throughout: its noise is too
    small for the unit, which the estimate is to find). Of the rest, a row beyond :data:`PLAY_TRIM`
    times the 1-sigma its median implies is an outlier, not play: the estimate is the drift of the
    others (a fault of one record made the plain mean square 25-30 x the profile's play)."""
    from insrail.nav.error_model import trolley_play_band_per_m

    found = _play_rows(result)
    if found is None:
        return None
    nu2, speed2, own, other = found
    reach = 2.0 * trolley_play_band_per_m() * speed2
    drift = []
    for k in range(2):
        if own is None:
            drift.append(variance_component(nu2[:, k], reach, other[:, k]))
        elif np.sum(own[:, k]) > (1.0 - MIN_NOISE_SHARE) * np.sum(nu2[:, k]):
            # the filter's own part is most of the rows' variance (a MEMS unit, a trolley without play): the
            # survey bounds the play from above, not at the floor the difference may give (the NHC then held
            # so tight that a MEMS unit's fusion failed)
            drift.append(min(play_upper_limit(nu2[:, k], reach, own[:, k] + other[:, k]),
                             variance_component(nu2[:, k], reach, other[:, k])))
        else:
            drift.append(variance_component(nu2[:, k], reach, own[:, k] + other[:, k]))
    return tuple(drift)


def variance_component(nu2: np.ndarray, unit: np.ndarray, explained: np.ndarray | None = None) -> float:
    """The factor c of a variance component that makes squared innovations ``nu2`` (one per row) fit
    E[nu^2] = explained + c unit, robustly: ``unit`` the component's variance per row at c = 1,
    ``explained`` what the rest of the model puts into the same rows (the filter's own H P- H^T; none:
    c is an upper bound). A row beyond :data:`PLAY_TRIM` times the 1-sigma the median row implies is an
    outlier (a fault, not noise) and left out; c = sum(nu^2 - explained) / sum(unit) over the others,
    never below 0."""
    kept, explained = _trimmed(nu2, unit, explained)
    if kept is None:
        return 0.0
    return max(float(np.sum(nu2[kept] - explained[kept]) / np.sum(unit[kept])), 0.0)


def play_upper_limit(nu2: np.ndarray, unit: np.ndarray, explained: np.ndarray) -> float:
    """The upper confidence limit of :func:`variance_component`'s factor: its estimate (never below 0) plus
    :data:`PLAY_CONFIDENCE_SIGMAS` standard errors, these from the scatter of the excess nu^2 - explained
    summed over blocks of :data:`PLAY_BLOCK_ROWS` consecutive rows (the innovations of a filter are
    correlated over seconds; whole blocks about not). Fewer than two blocks: the plain upper bound."""
    kept, explained = _trimmed(nu2, unit, explained)
    if kept is None:
        return 0.0
    excess, total = nu2[kept] - explained[kept], float(np.sum(unit[kept]))
    blocks = len(excess) // PLAY_BLOCK_ROWS
    if blocks < 2:
        return variance_component(nu2, unit)
    sums = excess[: blocks * PLAY_BLOCK_ROWS].reshape(blocks, PLAY_BLOCK_ROWS).sum(axis=1)
    standard_error = math.sqrt(float(np.var(sums, ddof=1)) * len(excess) / PLAY_BLOCK_ROWS) / total
    return max(float(np.sum(excess)) / total, 0.0) + PLAY_CONFIDENCE_SIGMAS * standard_error


def _trimmed(nu2: np.ndarray, unit: np.ndarray, explained: np.ndarray | None):
    """(the rows kept: not beyond :data:`PLAY_TRIM` times the 1-sigma the median row implies, ``explained``
    as an array), or (None, ...) when the rows show nothing at all."""
    explained = np.zeros_like(unit) if explained is None else explained
    ratio = nu2 / (explained + unit)
    typical = float(np.median(ratio)) / CHI2_1_MEDIAN  # what the bulk of the rows shows
    if not typical > 0:
        return None, explained
    return ratio <= PLAY_TRIM**2 * typical, explained


def _play_rows(result) -> tuple[np.ndarray, np.ndarray, np.ndarray | None, np.ndarray] | None:
    """(squared lateral and vertical NHC innovations (n, 2), the squared speed at each (n,), the filter's
    own part of their variance (n, 2) or None where not recorded, their noise that is not the play's (n, 2):
    the rows' R less the play's NHC 1-sigma squared, zero where not recorded) of the rows
    :func:`play_from_innovations` takes, or None when too few are left."""
    record = result.innovations
    if (record is None or record.innovation is None or NHC_SOURCE not in record.names or result.forward is None
            or len(result.forward.time_s) < 2):
        return None
    take, speed2 = _usable(result, NHC_SOURCE, moving=True, min_dof=2)
    if take is None:
        return None
    dof = record.dof[take]
    rows = np.arange(record.innovation.shape[1])[None, :]
    # the NHC's lateral and vertical rows are its model's last two (an odometer row before them)
    lateral, vertical = rows == (dof - 2)[:, None], rows == (dof - 1)[:, None]

    def nhc_rows(values):
        values = np.asarray(values[take], dtype=float)
        return np.column_stack([values[lateral], values[vertical]])

    own, noise = getattr(record, "filter_variance", None), getattr(record, "noise_variance", None)
    other = np.zeros((int(take.sum()), 2))
    nhc = getattr(getattr(result, "timeline", None), "measurements", {}).get(NHC_SOURCE)
    if noise is not None and nhc is not None and len(nhc.time_s):
        # the play's part of a row's R is the NHC's 1-sigma (times a joint's relaxing factor) squared
        at = np.clip(np.searchsorted(nhc.time_s, record.time_s[take] - 1e-9), 0, len(nhc.time_s) - 1)
        scale = np.ones(len(at)) if nhc.nhc_scale is None else np.asarray(nhc.nhc_scale)[at]
        other = np.maximum(nhc_rows(noise) - np.square(nhc.sigma_nhc_mps * scale)[:, None], 0.0)
    return nhc_rows(record.innovation) ** 2, speed2[take], None if own is None else nhc_rows(own), other


def _usable(result, name: str, moving: bool, min_dof: int, trusted: bool = True, accepted: bool = True):
    """(the observations of source ``name`` whose innovations say what its noise is, the squared speed
    at every observation), (None, None) when fewer than :data:`MIN_PLAY_ROWS` are left: ``accepted`` ones
    or all gated (the gate cuts the large ones of a noise stated too small: those must count), ``trusted``
    ones or all, with at least ``min_dof`` rows, while ``moving`` (above :data:`MIN_PLAY_SPEED2`) or at
    any speed, outside a reset's suspect time and :data:`SUSPECT_MARGIN_S` about a removed IMU record or a
    bridged gap (unless that leaves less than :data:`SUSPECT_MOSTLY` of them)."""
    record = result.innovations
    mine = (record.source == record.names.index(name)) & (record.dof >= min_dof) & np.isfinite(record.nis)
    if accepted:
        mine &= record.accepted
    if trusted:
        mine &= record.trusted
    forward = result.forward
    speed2 = np.interp(record.time_s, forward.time_s, np.sum(np.square(forward.vel_ned_mps), axis=1))
    moving = mine & (speed2 >= MIN_PLAY_SPEED2) if moving else mine
    take = moving.copy()
    # a reset's suspect time, not a not-valid section: a section is not valid where the play the pass ran
    # with is too small for its innovations, which is what the estimate is for
    suspect = list(result.integrity.suspect_s) if result.integrity is not None else []
    margin = SUSPECT_MARGIN_S
    suspect += [(o.time_s - margin, o.time_s + margin) for o in result.info.get("imu_outliers", ())]
    suspect += [(g.start_s - margin, g.end_s + margin) for g in result.info.get("imu_gaps", ())]
    if suspect:
        starts, ends = np.array([[a, b] for a, b, *_ in suspect]).T
        order = np.argsort(starts)
        starts, ends = starts[order], np.maximum.accumulate(ends[order])
        before = np.searchsorted(starts, record.time_s, side="right") - 1
        take &= ~((before >= 0) & (record.time_s <= ends[np.maximum(before, 0)]))
    if take.sum() < SUSPECT_MOSTLY * moving.sum():
        # resets over most of the survey are the pass's noise too small for the unit (a MEMS unit's first pass
        # with a trolley's play), not faults: its rows are what the estimate must see
        take = moving
    if take.sum() < MIN_PLAY_ROWS:
        return None, None
    return take, speed2


@dataclass(frozen=True)
class NoiseEstimate:
    """An aiding source's noise as its innovations show it: ``factor`` on the 1-sigma the pass ran with
    (the square root of :func:`variance_component`, the filter's own H P- H^T explained), the RMS 1-sigma
    [m/s, m] that gives and the one the pass ran with, from ``rows`` innovation rows."""

    factor: float
    sigma: float
    ran_with: float
    rows: int


def noise_from_innovations(result, gnss=None) -> dict[str, NoiseEstimate]:
    """The odometer's, the ZUPT's and the GNSS positions' noise per quality class (``gnss``: the solution
    the pass was aided with, for its quality flags) the innovations of a pass show: {"odometer", "zupt",
    "gnss_fix", "gnss_float", ...: estimate}. The rows are taken as for the play (:func:`_usable`; the
    odometer's while moving: at rest it counts no pulses); a source is left out where fewer than
    :data:`MIN_PLAY_ROWS` rows are left or its noise is less than :data:`MIN_NOISE_SHARE` of their
    innovations' variance (the filter's own uncertainty hides it: the survey does not say)."""
    from insrail.nav.fusion import QUALITY_NAMES

    record = result.innovations
    out: dict[str, NoiseEstimate] = {}
    forward, timeline = getattr(result, "forward", None), getattr(result, "timeline", None)
    if (record is None or getattr(record, "filter_variance", None) is None or forward is None
            or len(forward.time_s) < 2 or timeline is None):
        return out

    def estimate(key, take, rows):
        nu2, hph, r = (np.asarray(a[take][:, rows], dtype=float).ravel()
                       for a in (np.square(record.innovation), record.filter_variance, record.noise_variance))
        fine = np.isfinite(nu2) & np.isfinite(hph) & (r > 0)
        nu2, hph, r = nu2[fine], hph[fine], r[fine]
        if len(r) < MIN_PLAY_ROWS or np.sum(r) < MIN_NOISE_SHARE * np.sum(r + hph):
            return
        c = variance_component(nu2, r, hph)
        ran_with = math.sqrt(float(np.mean(r)))
        out[key] = NoiseEstimate(math.sqrt(c), math.sqrt(c) * ran_with, ran_with, len(r))

    odometer = timeline.measurements.get(NHC_SOURCE)
    if odometer is not None and odometer.use_odometer:
        take, _ = _usable(result, NHC_SOURCE, moving=True, min_dof=1, accepted=False)
        if take is not None:
            estimate(ODOMETER, take, [0])  # the odometer's row is the first
    if ZUPT_SOURCE in record.names:
        take, _ = _usable(result, ZUPT_SOURCE, moving=False, min_dof=3, accepted=False)
        if take is not None:
            estimate(ZUPT_SOURCE, take, [0, 1, 2])  # the velocity rows (the heading rate's is the gyro's)
    if GNSS_SOURCE in record.names and gnss is not None and len(gnss.time_s):
        take, _ = _usable(result, GNSS_SOURCE, moving=False, min_dof=3, trusted=False, accepted=False)
        if take is not None:
            at = np.clip(np.searchsorted(gnss.time_s, record.time_s - 1e-9), 0, len(gnss.time_s) - 1)
            quality = np.asarray(gnss.quality)[at]
            for q in np.unique(quality[take]):
                estimate(f"gnss_{QUALITY_NAMES.get(int(q), str(int(q)))}", take & (quality == q), [0, 1, 2])
    return out


@dataclass(frozen=True)
class Calibration:
    """What the passes changed: ``passes`` run, the NHC dropped, the GNSS sigma scale used, the play
    drift (lateral, vertical) [m^2/m] and NHC 1-sigma [m/s] the result ran with and the profile's."""

    passes: int
    nhc_dropped: bool
    gnss_sigma_scale: float
    notices: tuple[Notice, ...]
    play_drift_m2_per_m: tuple[float, float] = (math.nan, math.nan)
    profile_play_drift_m2_per_m: tuple[float, float] = (math.nan, math.nan)
    nhc_sigma_mps: float = math.nan
    play_estimated: bool = False
    #: per aiding noise the last pass's innovations show (:func:`noise_from_innovations`): (its estimate,
    #: the RMS 1-sigma the first pass ran with (the profile's, the file's), the factor the result ran with)
    noise: tuple[tuple[str, NoiseEstimate, float, float], ...] = ()

    def to_dict(self) -> dict:
        noise = {}
        for key, found, profile_sigma, applied in self.noise:
            unit = "mm" if key.startswith("gnss") else "mm_per_s"
            noise[key] = {f"estimated_sigma_{unit}": float(f"{1e3 * found.sigma:.3g}"),
                          f"profile_sigma_{unit}": float(f"{1e3 * profile_sigma:.3g}"),
                          "applied_factor": round(applied, 3), "rows": found.rows}
        return {"passes": self.passes, "nhc_dropped": self.nhc_dropped,
                "gnss_sigma_scale": round(self.gnss_sigma_scale, 3),
                "play_estimated": self.play_estimated,
                "play_drift_mm2_per_m": [float(f"{1e6 * q:.3g}") for q in self.play_drift_m2_per_m],
                "profile_play_drift_mm2_per_m": [float(f"{1e6 * q:.3g}") for q in self.profile_play_drift_m2_per_m],
                "nhc_sigma_mm_per_s": float(f"{1e3 * self.nhc_sigma_mps:.3g}"), "noise": noise}


def fuse_consistent(imu, build_aiding, profile, options, ellipsoid, new_store=None, fuse=None, **kwargs):
    """:func:`insrail.nav.fusion.fuse` until consistent (see the module docstring).

    ``build_aiding(options)``: the :class:`~insrail.nav.fusion.Aiding` for the options of a pass
    (``aiding_for(survey, options, profile)``); ``new_store()``: an empty
    :class:`~insrail.nav.fusion.SmootherStore` for each pass, or None. Returns (the result, the
    options of the pass it came from, its store or None, the :class:`Calibration`); the stores of
    the passes left behind are closed, the returned one is the caller's to close. The calibration's
    notices are also appended to the result's ``info["notices"]`` (and ``info["warnings"]``)."""
    if fuse is None:
        from insrail.nav.fusion import fuse
    notices: list[Notice] = []
    nhc_dropped = False
    result = store = None
    profile_play, play_passes, estimated = options.play_drift_m2_per_m, 0, False
    profile_options, first_noise, found = options, None, {}
    for passes in range(1, MAX_PASSES + MAX_PLAY_PASSES + 1):
        if store is not None:
            store.close()
        store = new_store() if new_store is not None else None
        aiding = build_aiding(options)
        try:
            result = fuse(imu, aiding, profile, options, ellipsoid, covariance_store=store, **kwargs)
        except BaseException:
            if store is not None:
                store.close()
            raise
        said: list[Notice] = []
        found = noise_from_innovations(result, aiding.gnss) if options.estimate_noise else {}
        first_noise = found if first_noise is None else first_noise
        changed = _next_options(result, aiding, options, said)
        if changed is not None and passes - play_passes == MAX_PASSES:  # still inconsistent, no pass left to mend it
            result = replace(result, integrity=replace(result.integrity,
                                                       inconsistent=_still_inconsistent(result, passes, options, changed)))
            break
        if changed is None and play_passes < MAX_PLAY_PASSES:
            played = _play_options(result, options, profile_play) if options.estimate_play else None
            estimated |= played is not None
            changed = _noise_options(found, played or options, profile_options) or played
            play_passes += changed is not None
        notices += said
        if changed is None:
            break
        nhc_dropped |= options.use_nhc and not changed.use_nhc
        options = changed
    if estimated:
        notices.append(Notice("fusion", "trolley play estimated from the NHC innovations: {play} mm^2 per metre run "
                              "lateral/vertical (the profile resources/trolley_play.toml: {profile_play}), NHC 1-sigma "
                              "{nhc_sigma_mmps:.3g} mm/s; the stated accuracy uses them", severity="info",
                              fields={"play": _mm2(options.play_drift_m2_per_m), "profile_play": _mm2(profile_play),
                                      "nhc_sigma_mmps": 1e3 * options.nhc_sigma_mps}))
    noise = tuple((key, estimate, first_noise[key].ran_with if key in first_noise else estimate.ran_with,
                   _noise_factor(key, options, profile_options)) for key, estimate in found.items())
    for key, estimate, profile_sigma, applied in noise:
        if applied != 1.0:
            unit, given = ("mm", Phrase("the file's")) if key.startswith("gnss") else ("mm/s", Phrase("the profile's"))
            notices.append(Notice("fusion", "{source} noise estimated from its innovations: {sigma:.3g} {unit} (1-sigma, "
                                  "RMS), {given} {profile_sigma:.3g} {unit}; fused with {given} x {applied:.2f}, the stated "
                                  "accuracy uses it", severity="info",
                                  fields={"source": _noise_label(key), "sigma": 1e3 * estimate.sigma, "unit": unit,
                                          "given": given, "profile_sigma": 1e3 * profile_sigma, "applied": applied}))
    calibration = Calibration(passes, nhc_dropped, options.gnss_sigma_scale, tuple(notices),
                              tuple(options.play_drift_m2_per_m), tuple(profile_play), options.nhc_sigma_mps, estimated,
                              noise)
    result.info["notices"] = [*result.info.get("notices", []), *notices]
    result.info["warnings"] = [*result.info.get("warnings", []), *(n.message for n in notices)]
    result.info["calibration"] = calibration.to_dict()
    return result, options, store, calibration


def _mm2(drift) -> str:
    return "/".join(f"{1e6 * q:.3g}" for q in drift)


def _play_options(result, options, profile_play):
    """The options of a pass with the play the innovations of ``result`` show (clipped to PLAY_RANGE
    about the profile's ``profile_play``), or None when the pass ran with it already (PLAY_TOLERANCE).
    The NHC's 1-sigma is scaled with the square root of the play's (its drift sigma^2 / f and the play
    are one process: the speed below which the play adds nothing to the NHC's noise stays)."""
    found = play_from_innovations(result)
    if found is None or not options.use_nhc:
        return None
    wanted = tuple(float(np.clip(q, p / PLAY_RANGE, p * PLAY_RANGE)) for q, p in zip(found, profile_play))
    ratios = [w / max(q, 1e-30) for w, q in zip(wanted, options.play_drift_m2_per_m)]
    if all(1.0 / PLAY_TOLERANCE <= r <= PLAY_TOLERANCE for r in ratios):
        return None
    scale = math.sqrt(max(wanted) / max(options.play_drift_m2_per_m))
    return replace(options, play_drift_m2_per_m=wanted, nhc_sigma_mps=options.nhc_sigma_mps * scale)


_NOISE_LABELS = {ODOMETER: "odometer", ZUPT_SOURCE: "ZUPT"}


def _noise_label(key: str) -> Phrase:
    """A noise estimate's source for its notice: "odometer", "ZUPT", "GNSS fix" (a quality class verbatim)."""
    if key in _NOISE_LABELS:
        return Phrase(_NOISE_LABELS[key])
    return Phrase("GNSS {quality}", {"quality": key.removeprefix("gnss_")})


def _noise_factor(key: str, options, profile_options) -> float:
    """The factor on the profile's 1-sigma of aiding noise ``key`` that ``options`` fuse with."""
    if key == ODOMETER:
        return options.odometer_sigma_scale / profile_options.odometer_sigma_scale
    if key == ZUPT_SOURCE:
        return options.zupt_sigma_scale / profile_options.zupt_sigma_scale
    quality = _quality_flag(key)
    now, was = dict(options.gnss_quality_policy).get(quality), dict(profile_options.gnss_quality_policy).get(quality)
    return now / was if now and was else 1.0


def _quality_flag(key: str) -> int:
    from insrail.nav.fusion import QUALITY_NAMES

    name = key.removeprefix("gnss_")
    return next((q for q, n in QUALITY_NAMES.items() if n == name), -1)


def _noise_options(found: dict[str, NoiseEstimate], options, profile_options):
    """The options of a pass with the aiding noises ``found`` widened where an estimate's factor is beyond
    :data:`NOISE_TOLERANCE` (the result at most :data:`NOISE_RANGE` x the profile's), or None when
    ``options`` ran with them already (and are those of the pass). A narrower estimate is stated, not
    applied: the stated accuracy stays on the safe side."""
    changes = {}
    for key, estimate in found.items():
        # only ever widened: a filter whose own uncertainty is pessimistic elsewhere (a first pass with the
        # profile's play on a trolley without any) takes too much of the innovations for itself, and the
        # narrower noise then fails the survey (simulator, tactical grade without play: the odometer
        # estimated at 0.19-0.64 of its true noise, 257 rejections and a reset, the 5 m lag 3x worse)
        if estimate.factor <= NOISE_TOLERANCE:
            continue
        factor = float(np.clip(_noise_factor(key, options, profile_options) * estimate.factor, 1.0 / NOISE_RANGE,
                               NOISE_RANGE))
        if key == ODOMETER:
            changes["odometer_sigma_scale"] = profile_options.odometer_sigma_scale * factor
        elif key == ZUPT_SOURCE:
            changes["zupt_sigma_scale"] = profile_options.zupt_sigma_scale * factor
        else:
            quality = _quality_flag(key)
            policy = dict(changes.get("gnss_quality_policy", options.gnss_quality_policy))
            if policy.get(quality):
                policy[quality] = dict(profile_options.gnss_quality_policy)[quality] * factor
                changes["gnss_quality_policy"] = tuple(policy.items())
    changes = {k: v for k, v in changes.items() if v != getattr(options, k)}
    return replace(options, **changes) if changes else None


def _still_inconsistent(result, passes: int, options, wanted) -> str:
    """Why the last pass is not consistent (``wanted``: the options it would have needed next)."""
    if wanted.use_nhc != options.use_nhc:
        nhc = consistency(result, NHC_SOURCE)
        return f"after {passes} passes: {100 * nhc.rejected_share:.0f} % of the non-holonomic constraint's rows rejected"
    gnss = consistency(result, GNSS_SOURCE)
    return (f"after {passes} passes (GNSS sigmas x {options.gnss_sigma_scale:.2f}): {100 * gnss.rejected_share:.0f} % of "
            f"the {gnss.observations} GNSS fixes still rejected (their median NIS {gnss.robust_nis_per_dof:.2f} x its "
            "chi-square median)")


def _next_options(result, aiding, options, notices: list[Notice]):
    """The options of the next pass, or None when this one is consistent."""
    nhc = consistency(result, NHC_SOURCE)
    if aiding.odometer is None and options.use_nhc and nhc is not None and nhc.rejected_share > NHC_MAX_REJECTED:
        notices.append(Notice(
            "fusion", "the non-holonomic constraint does not hold: {share_pct:.0f} % of its {rows} rows rejected, with no "
            "odometer to blame (a hand-held device, or a vehicle that slides); fused again without it (insrail fuse "
            "--no-nhc does so from the start)", fields={"share_pct": 100 * nhc.rejected_share, "rows": nhc.observations}))
        return replace(options, use_nhc=False)
    gnss = consistency(result, GNSS_SOURCE)
    if gnss is None or (gnss.rejected_share <= GNSS_MAX_REJECTED and gnss.nis_per_dof <= GNSS_MAX_NIS_PER_DOF):
        return None
    if gnss.robust_nis_per_dof <= GNSS_MIN_ROBUST_NIS:  # a few far off (a fault), the rest as stated
        return None
    if options.gnss_sigma_scale >= MAX_GNSS_SCALE:
        return None
    step = min(max(math.sqrt(gnss.robust_nis_per_dof), MIN_STEP), MAX_STEP, MAX_GNSS_SCALE / options.gnss_sigma_scale)
    scale = options.gnss_sigma_scale * step
    notices.append(Notice(
        "fusion", "the GNSS positions disagree with their stated sigmas: {share_pct:.0f} % of {fixes} fixes rejected, "
        "NIS {nis:.2f} x its degrees of freedom (median {median_nis:.2f}); fused again with the file's sigmas x "
        "{scale:.2f} (calibrated from the innovations; --gnss-sigma-scale sets a factor from the start)",
        fields={"share_pct": 100 * gnss.rejected_share, "fixes": gnss.observations, "nis": gnss.nis_per_dof,
                "median_nis": gnss.robust_nis_per_dof, "scale": scale}))
    return replace(options, gnss_sigma_scale=scale)
