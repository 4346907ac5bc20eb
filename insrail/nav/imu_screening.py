"""Sensor-level screening of the IMU records before the filter.

A logger's bit flip or a corrupt record shows up as one increment far outside anything the
trolley can do: one 5 ms velocity increment 1 m/s too large is 20 g of specific force for one
record, which sends the strapdown (and then the filter, whose gates lock out the aiding)
hundreds of metres off. Such records are removed before the filter, and the hole they leave is
bridged like a logger dropout (:func:`insrail.nav.imu_gaps.bridge_gaps`).

A record is an outlier when, in the IMU profile's envelope (``[range]`` of the profile,
:class:`insrail.nav.imu_profile.ImuProfile`):

* a value is not a finite number;
* its specific force or angular rate (increment / interval) exceeds the measurement range on
  an axis; or
* it departs from the median of its neighbours (``NEIGHBOURS`` records either side) by more
  than the largest change between neighbouring records a trolley gives. Real motion at
  100-200 Hz changes the rates smoothly; a step (a stop, a curve entry) keeps the median on
  either side, so only short spikes are removed.

Inside the envelope a single faulty record is still far outside the sensor's noise: a 3 mrad jump
in one 5 ms angle increment (0.6 rad/s, below the 50 deg/s envelope) leaves a permanent 3 mrad
roll error, 4.5 mm of cross-level, that the aiding takes seconds to notice and the filter only
resets after the first sleepers behind it were measured with it. So a record is also an outlier
("spike below the envelope") when it departs from the median of its neighbours by more than
``QUIET_SPIKE_SIGMAS`` times their own spread about it (1.4826 x their median absolute
departure: the motion and vibration of the moment) and times the profile's noise per record (angle
or velocity random walk over one interval). Smooth motion, a ramp or a step keeps the centre
record near its neighbours' median; vibration widens the neighbours' spread with it. When more
than ``max_fraction`` of the records fail only this test, the motion is too rough for it: nothing
is removed by it and a notice says single-record faults below the envelope cannot be found there.

Every removed record is listed with its time and size. More than ``max_fraction`` of the
records out of the envelope is no longer a few corrupt records but a wrong file, unit or profile:
that is an error naming the file.

Before that, the units are checked with the physics (:func:`check_units`): the median specific
force (of 50 ms means) is about gravity (a trolley's or a walker's accelerations average out), and at
rest (seconds where the accelerometers are as quiet as the profile's noise allows) the angular
rate is the earth rate plus at most the profile's gyro bias. A file off by a unit's factor is an
error naming the file and the likely unit ("delta-theta looks like degrees, not radians": 57.3 x;
velocity increments in g, in mm/s or ft/s; specific force or rates instead of increments; running
sums instead of increments), not a fusion that ends "inconsistent over 100 % of the survey".
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from insrail.background import BackgroundJob
from insrail.io.imu import release_pages
from insrail.io.types import GAP_FACTOR, ImuIncrements
from insrail.nav.alignment import GRAVITY_MPS2, gravity_tolerance_mps2, stop_thresholds
from insrail.nav.imu_profile import ImuProfile
from insrail.notices import Notice, Phrase

#: ``(times [s], window [s]) -> still flags``: whether the aiding lets the platform rest there
StillnessTest = Callable[[np.ndarray, float], np.ndarray]

#: records either side whose median a record is compared with
NEIGHBOURS = 5
#: a record this many times its neighbours' spread (and the profile's noise per record) off their median
QUIET_SPIKE_SIGMAS = 100.0
#: records the below-envelope test reads at a time at most (rates, medians and spreads: 9 values per record)
QUIET_CHUNK = 1 << 16
#: notices listing single records; the rest are summed up in one more
MAX_LISTED = 10


#: why a record is removed (an outlier's ``reason``)
OUTLIER_REASONS = ("not finite", "beyond range", "spike", "spike below the envelope")


@dataclass(frozen=True)
class Outlier:
    """One removed IMU record: its time, what was wrong and by how much."""

    time_s: float
    index: int  # in the file's records
    quantity: str  # "specific force" or "angular rate"
    axis: str  # "x", "y", "z"
    value: float  # [m/s^2] or [rad/s]; NaN/inf when not finite
    reference: float  # the median of its neighbours, same unit
    reason: str  # one of OUTLIER_REASONS

    def describe(self, source: str) -> Phrase:
        unit, scale = ("m/s^2", 1.0) if self.quantity == "specific force" else ("deg/s", 180.0 / np.pi)
        quantity = Phrase("specific force" if self.quantity == "specific force" else "angular rate")
        if self.reason == "not finite":
            what = Phrase("{quantity} {axis} is {value}", {"quantity": quantity, "axis": self.axis, "value": str(self.value)})
        else:
            what = Phrase("{quantity} {axis} {value:.4g} {unit} against {reference:.4g} {unit} around it ({reason})",
                          {"quantity": quantity, "axis": self.axis, "value": scale * self.value, "unit": unit,
                           "reference": scale * self.reference, "reason": Phrase(self.reason)})
        return Phrase("{where}IMU record {record} at t = {time_s:.4f} s removed as an outlier: {what}; bridged",
                      {"where": f"{source}: " if source else "", "record": self.index + 1, "time_s": self.time_s,
                       "what": what})


def _intervals(time_s: np.ndarray, index: np.ndarray, nominal: float) -> np.ndarray:
    """The interval each record ``index`` integrates over: the time since the record before, one
    nominal interval for the first record and after a dropout (the ImuIncrements gap contract)."""
    step = time_s[index] - time_s[np.maximum(index - 1, 0)]
    return np.where((index == 0) | (step > GAP_FACTOR * nominal), nominal, step)


def _candidates(time_s: np.ndarray, increments: np.ndarray, nominal: float, full_range: float, jump: float,
                first: int, stop: int) -> np.ndarray:
    """Indices in [first, stop) of the records that may be outliers: not finite, beyond the range,
    or next to a step between neighbouring records larger than ``jump``; the records either side
    of the chunk are read for its steps."""
    from insrail.nav._screening_kernels import candidate_rows  # numba: only when screening

    n = len(time_s)
    stop = min(stop, n)
    lo, hi = max(first - 1, 0), min(stop + 1, n)
    found = candidate_rows(np.asarray(time_s), np.asarray(increments), nominal, GAP_FACTOR * nominal, full_range, jump, lo, hi)
    release_pages(increments)  # a mapped file's pages behind the chunk
    return found[(found >= first) & (found < stop)]


def screen_imu(imu: ImuIncrements, profile: ImuProfile, max_fraction: float = 0.01, chunk: int = 1 << 18,
               aiding_still: StillnessTest | None = None) -> tuple[ImuIncrements, tuple[Outlier, ...], list[Notice]]:
    """(the records inside the envelope, the removed ones, notices). The returned increments have
    holes where records were removed; :func:`insrail.nav.imu_gaps.bridge_gaps` fills them.
    ``aiding_still``: what the odometer or the positions say about rest (:func:`check_units`).
    Raises ValueError naming the file when more than ``max_fraction`` of the records fail.
    The records are screened ``chunk`` at a time (memory bounded for any length)."""
    n = len(imu)
    source = str(imu.source or "")
    if n < 3:
        return imu, (), []
    check_units(imu, profile, aiding_still)
    nominal = float(np.median(np.diff(imu.time_s), overwrite_input=True))
    increments = {"specific force": imu.dvel_mps, "angular rate": imu.dtheta_rad}
    limits = {"specific force": (profile.specific_force_range_mps2, profile.specific_force_jump_mps2),
              "angular rate": (profile.rate_range_radps, profile.rate_jump_radps)}
    bad = np.zeros(n, dtype=bool)
    found: dict[int, Outlier] = {}
    for quantity, values in increments.items():
        full_range, jump = limits[quantity]
        candidates = np.concatenate([_candidates(imu.time_s, values, nominal, full_range, jump, first, first + chunk)
                                     for first in range(0, n, chunk)])
        if candidates.size > 2 * max_fraction * n + 10:
            raise ValueError(
                f"{source or 'IMU'}: {candidates.size} of {n} records ({100 * candidates.size / n:.1f} %) leave the "
                f"{profile.name} profile's envelope ({quantity} range {_show(quantity, full_range)}, change between "
                f"records {_show(quantity, jump)}): not a few corrupt records but a wrong unit, sensor axes or IMU "
                "profile; check the file's format options and survey.imu_profile")
        # each candidate against the median of its neighbours (NaN beyond the file's ends and where not clean)
        near = candidates[:, None] + np.arange(-NEIGHBOURS, NEIGHBOURS + 1)
        inside = (near >= 0) & (near < n)
        near = np.clip(near, 0, n - 1)
        with np.errstate(invalid="ignore", over="ignore"):
            rates = values[near] / _intervals(imu.time_s, near, nominal)[..., None]  # (c, w, 3)
            clean = np.where(inside[..., None] & np.isfinite(rates) & (np.abs(rates) <= full_range), rates, np.nan)
        clean[:, NEIGHBOURS] = np.nan  # the record itself does not vote
        reference = np.full((candidates.size, 3), np.nan)
        if candidates.size:
            with warnings.catch_warnings():  # a record whose neighbours are all bad has no median
                warnings.simplefilter("ignore", RuntimeWarning)
                reference = np.nanmedian(clean, axis=1)
        for c, k in enumerate(candidates):
            for axis in range(3):
                value, ref = rates[c, NEIGHBOURS, axis], reference[c, axis]
                if not np.isfinite(value):
                    reason = "not finite"
                elif abs(value) > full_range:
                    reason = "beyond range"
                elif np.isfinite(ref) and abs(value - ref) > jump:
                    reason = "spike"
                else:
                    continue
                bad[k] = True
                if k not in found:
                    found[k] = Outlier(float(imu.time_s[k]), int(k), quantity, "xyz"[axis], float(value),
                                       float(ref), reason)
                break
    count = int(bad.sum())
    if count > max_fraction * n:
        raise ValueError(
            f"{source or 'IMU'}: {count} of {n} records ({100 * count / n:.1f} %) are outside the {profile.name} "
            "profile's envelope: not a few corrupt records but a wrong unit, sensor axes or IMU profile; check the "
            "file's format options and survey.imu_profile")
    notices: list[Notice] = []
    noise = {"specific force": profile.accel_vrw / math.sqrt(nominal), "angular rate": profile.gyro_arw / math.sqrt(nominal)}
    quiet: dict[int, Outlier] = {}

    def spikes(quantity: str) -> list[tuple[int, int, float, float]]:
        return _spikes_below_envelope(imu.time_s, increments[quantity], nominal, noise[quantity], bad,
                                      min(chunk, QUIET_CHUNK))

    # the angular rates' in a thread beside the specific force's (their medians compiled without the GIL)
    with BackgroundJob(lambda progress, cancel: spikes("angular rate"), None, None, name="insrail-screening") as rates:
        found_in = {"specific force": spikes("specific force"), "angular rate": rates.result()}
    for quantity, spiked in found_in.items():
        for k, axis, value, ref in spiked:
            if k not in quiet:
                quiet[k] = Outlier(float(imu.time_s[k]), k, quantity, "xyz"[axis], value, ref, "spike below the envelope")
    if len(quiet) > max_fraction * n:
        notices.append(Notice("imu", "{where}{count} of {records} IMU records depart from their neighbours by more than "
                              "{sigmas:g} x their spread: the motion is too rough to tell a single faulty record inside "
                              "the envelope from it; none removed by that test, and such a fault would be seen only by "
                              "the aiding", file=source,
                              fields={"where": source + ": " if source else "", "count": len(quiet), "records": n,
                                      "sigmas": QUIET_SPIKE_SIGMAS}))
    else:
        found.update(quiet)
        bad[list(quiet)] = True
    if not found:
        return imu, (), notices
    outliers = tuple(found[k] for k in sorted(found))
    notices += [Notice("imu", o.describe(source), file=source, time_s=o.time_s) for o in outliers[:MAX_LISTED]]
    if len(outliers) > MAX_LISTED:
        rest = outliers[MAX_LISTED:]
        notices.append(Notice("imu", "{where}{count} more IMU records removed as outliers between t = {first_s:.4f} and "
                              "{last_s:.4f} s and bridged (all listed in the fusion log)", file=source,
                              time_s=rest[0].time_s,
                              fields={"where": source + ": " if source else "", "count": len(rest),
                                      "first_s": rest[0].time_s, "last_s": rest[-1].time_s}))
    keep = ~bad
    screened = replace(imu, time_s=imu.time_s[keep], dtheta_rad=imu.dtheta_rad[keep], dvel_mps=imu.dvel_mps[keep])
    return screened, outliers, notices


def _spikes_below_envelope(time_s: np.ndarray, increments: np.ndarray, nominal: float, noise: float,
                           removed: np.ndarray, chunk: int) -> list[tuple[int, int, float, float]]:
    """(index, axis, rate, neighbours' median) of the records more than QUIET_SPIKE_SIGMAS x
    max(their neighbours' spread, ``noise``) off the neighbours' median (module docstring); records
    already ``removed`` neither vote nor are tested again (a median next to them is not formed);
    ``chunk`` records at a time."""
    from insrail.nav._screening_kernels import neighbour_median_and_spread  # numba: only when screening

    n = len(time_s)
    width = 2 * NEIGHBOURS + 1
    out = []
    for first in range(0, n, chunk):
        lo, hi = max(first - NEIGHBOURS, 0), min(first + chunk + NEIGHBOURS, n)
        if hi - lo < width:
            continue
        with np.errstate(invalid="ignore", over="ignore"):
            rates = increments[lo:hi] / _intervals(time_s, np.arange(lo, hi), nominal)[:, None]
            rates[removed[lo:hi] | ~np.isfinite(rates).all(axis=1)] = np.nan
            reference, spread = neighbour_median_and_spread(rates, NEIGHBOURS)  # (m, 3) each
            centre = rates[NEIGHBOURS:hi - lo - NEIGHBOURS]
            spike = np.abs(centre - reference) > QUIET_SPIKE_SIGMAS * np.maximum(spread, noise)
        release_pages(increments)
        index = np.arange(lo + NEIGHBOURS, hi - NEIGHBOURS)
        inside = (index >= first) & (index < first + chunk)
        for row, axis in zip(*np.nonzero(spike & inside[:, None])):
            out.append((int(index[row]), int(axis), float(centre[row, axis]), float(reference[row, axis])))
    return out


def _show(quantity: str, value: float) -> str:
    return f"{value / 9.80665:g} g" if quantity == "specific force" else f"{np.degrees(value):g} deg/s"


# --------------------------------------------------------------------------- units

#: a second's mean specific force of a trolley or a walker within this share of gravity
GRAVITY_TOLERANCE = 0.1
#: at rest, |mean rate| may exceed the earth rate by this many 1-sigma of the gyro bias and noise
REST_RATE_SIGMAS = 5.0
#: seconds at rest needed before the gyro's unit is judged there
MIN_REST_S = 5.0
_EARTH_RATE_RADPS = 7.292115e-5
_BLOCK_S = 1.0
_SUB_BLOCK_S = 0.05


class ImuUnitError(ValueError):
    """An IMU file whose increments are off by a unit's factor (the message names the file and the unit)."""


def _unit_guesses(quantity: str, rate_hz: float) -> list[tuple[str, float | None]]:
    """(what the file would hold, factor the file's values are too large by; None: running sums)."""
    if quantity == "specific force":
        return [("running sums of the velocity increments, not the increments", None),
                ("velocity increments in g*s (the accelerometers in g), not m/s", 1.0 / GRAVITY_MPS2),
                ("velocity increments in mm/s, not m/s", 1000.0),
                ("velocity increments in ft/s, not m/s", 1.0 / 0.3048),
                (f"specific force in m/s^2 (rates), not velocity increments in m/s over each {1e3 / rate_hz:g} ms record",
                 rate_hz),
                (f"specific force in g (rates), not velocity increments in m/s over each {1e3 / rate_hz:g} ms record",
                 rate_hz / GRAVITY_MPS2)]
    degrees = 180.0 / np.pi
    return [("running sums of the angle increments (angles), not the increments", None),
            ("degrees, not radians", degrees),
            (f"angular rates in rad/s, not angle increments over each {1e3 / rate_hz:g} ms record", rate_hz),
            (f"angular rates in deg/s, not angle increments in rad over each {1e3 / rate_hz:g} ms record",
             rate_hz * degrees)]


#: records the unit check reads at a time (whole blocks of them); its temporary arrays of a record's interval
#: (8 bytes each) stay under the C allocator's 2 MiB threshold (insrail.memory), reused from its heap: at 1 << 18
#: each was a fresh mapping, its 512 pages faulted in and zeroed
UNITS_CHUNK = 1 << 17


def _block_means(values: np.ndarray, time_s: np.ndarray, nominal: float, per_block: int) -> np.ndarray:
    """(blocks, 3) mean rate over consecutive blocks of ``per_block`` records (each record over
    its :func:`_intervals`), read UNITS_CHUNK records at a time (a mapped file's pages let go behind)."""
    m = (len(time_s) // per_block) * per_block
    step = max(UNITS_CHUNK // per_block, 1) * per_block
    means = [np.zeros((0, 3))]
    for lo in range(0, m, step):
        hi = min(lo + step, m)
        dt = _intervals(time_s, np.arange(lo, hi), nominal)
        means.append(values[lo:hi].reshape(-1, per_block, 3).sum(axis=1) / dt.reshape(-1, per_block).sum(axis=1)[:, None])
        release_pages(values)
    return np.concatenate(means)


def _released(value, *arrays):
    """``value``, once the pages of ``arrays`` (a mapped file's) are let go."""
    release_pages(*arrays)
    return value


def _finite_records(imu: ImuIncrements) -> int:
    """How many records have finite increments, UNITS_CHUNK at a time."""
    count = 0
    for lo in range(0, len(imu), UNITS_CHUNK):
        hi = lo + UNITS_CHUNK
        count += int(np.count_nonzero(np.isfinite(imu.dvel_mps[lo:hi]).all(axis=1)
                                      & np.isfinite(imu.dtheta_rad[lo:hi]).all(axis=1)))
        release_pages(imu.dvel_mps, imu.dtheta_rad)
    return count


def check_units(imu: ImuIncrements, profile: ImuProfile, aiding_still: StillnessTest | None = None) -> None:
    """Raise :class:`ImuUnitError` naming the file when the increments are off by a unit's factor
    (see the module docstring); say nothing on a plausible file, or where it cannot be judged
    (less than two seconds of data; no rest for the gyro). ``aiding_still(times [s], window [s])``
    says per time whether the odometer or the positions let the platform stand still over the window
    around it (:func:`insrail.nav.alignment.aiding_still`): a trolley pushed smoothly along a curve
    has accelerometers as quiet as at rest, and turns at v / R (3e-4 rad/s at 0.5 m/s on R = 1500 m),
    far more than the earth rate the gyro sees at rest; only seconds the aiding lets be still are rest."""
    n = len(imu)
    step = np.diff(imu.time_s)
    nominal = float(np.median(step, overwrite_input=True)) if n > 1 else 0.0
    if not nominal > 0.0 or n * nominal < 2.0 * _BLOCK_S:
        return
    rate_hz = 1.0 / nominal
    del step
    t = imu.time_s
    per_block = max(round(_BLOCK_S / nominal), 2)
    sub = max(round(_SUB_BLOCK_S / nominal), 1)
    source = str(imu.source or "the IMU file")

    def judged(quantity: str, increments: np.ndarray, plausible, measured: str, expected: str,
               sums_possible=lambda increments: True) -> None:
        if plausible(increments):
            return
        for meaning, factor in _unit_guesses(quantity, rate_hz):
            if factor is None:
                if not sums_possible(increments):
                    continue
                candidate = np.diff(increments, axis=0, prepend=increments[:1] * 0.0)
            else:
                candidate = increments / factor
            if plausible(candidate):
                raise ImuUnitError(
                    f"{source}: the {'velocity' if quantity == 'specific force' else 'angle'} increments look like "
                    f"{meaning} ({expected}; the file gives {measured}); check the file's units (survey.toml "
                    "[files.imu]: format, accel_unit, gyro_unit) or the logger's export")
        raise ImuUnitError(f"{source}: {expected}; the file gives {measured}: not an IMU record in the units "
                           "insrail reads (m/s and rad per record); check the file's format and units in survey.toml")

    with np.errstate(invalid="ignore", over="ignore"):
        finite_records = _finite_records(imu)
        if finite_records < 0.99 * n:
            return  # a record's screening says what is wrong with it
        dvel, dtheta = imu.dvel_mps, imu.dtheta_rad
        if finite_records < n:  # copies only then
            finite = np.isfinite(imu.dvel_mps).all(axis=1) & np.isfinite(imu.dtheta_rad).all(axis=1)
            dvel, dtheta = np.where(finite[:, None], dvel, 0.0), np.where(finite[:, None], dtheta, 0.0)

        # the specific force's 50 ms means: its gravity (tested, then said in a message) and the rest below, made once
        f_sub = _block_means(dvel, t, nominal, sub)

        def gravity_of(increments):  # over 50 ms: a few corrupt records move the median by nothing
            means = f_sub if increments is dvel else _block_means(increments, t, nominal, sub)
            return float(np.median(np.linalg.norm(means, axis=1)))

        def gravity_plausible(increments):
            return abs(gravity_of(increments) / GRAVITY_MPS2 - 1.0) <= GRAVITY_TOLERANCE

        judged("specific force", dvel, gravity_plausible, f"{gravity_of(dvel):.4g} m/s^2",
               f"the specific force averaged over 50 ms should be about gravity, {GRAVITY_MPS2:.2f} m/s^2")

        # seconds at rest: the accelerometers' spread (of 50 ms means, as the stop detection) at their noise
        _, accel_quiet = stop_thresholds(profile.gyro_arw, profile.accel_vrw, rate_hz)
        subs = max(per_block // sub, 2)
        per_block_rest = sub * subs
        m = (len(f_sub) // subs) * subs
        spread = np.linalg.norm(f_sub[:m].reshape(-1, subs, 3).std(axis=1), axis=1)
        f_mean = f_sub[:m].reshape(-1, subs, 3).mean(axis=1)
        rest = (spread < accel_quiet) & (np.abs(np.linalg.norm(f_mean, axis=1) - GRAVITY_MPS2)
                                         < gravity_tolerance_mps2(profile))
        if aiding_still is not None and rest.any():
            centres = t[per_block_rest // 2 : len(rest) * per_block_rest : per_block_rest]
            rest &= aiding_still(centres, per_block_rest * nominal)
        if rest.any():  # and the gyro as quiet as in the quietest of them, whatever its unit (slow sways pass the
            # accelerometers' test)
            g_blocks = dtheta[: len(rest) * sub * subs].reshape(len(rest), sub * subs, 3)
            g_spread = np.concatenate([_released(np.linalg.norm(g_blocks[first : first + 1024].std(axis=1), axis=1),
                                                 dtheta)
                                       for first in range(0, len(rest), 1024)])  # a chunk of blocks at a time
            rest &= g_spread <= 4.0 * np.min(g_spread[rest])
        if rest.sum() * per_block_rest * nominal < MIN_REST_S:
            return
        bias = math.hypot(profile.gyro_bias_turn_on, profile.gyro_bias_gm_sigma)
        noise = profile.gyro_arw / math.sqrt(per_block_rest * nominal)
        limit = _EARTH_RATE_RADPS + REST_RATE_SIGMAS * math.sqrt(3.0) * math.hypot(bias, noise)

        def rest_rate(increments):
            return float(np.median(np.linalg.norm(_block_means(increments, t, nominal, per_block_rest)[rest], axis=1)))

        gyro_rest_rate = rest_rate(dtheta)  # tested, then said in a message: made once

        def wanders_at_rest(increments):
            """Running sums at rest wander far more within a second than they change from record to
            record; increments at rest (in any unit) are a constant plus white noise: the record-to-
            record change is sqrt(2) x their spread about the block's mean."""
            blocks = increments[: len(rest) * per_block_rest].reshape(len(rest), per_block_rest, 3)[rest]
            spread = np.std(blocks - blocks.mean(axis=1, keepdims=True))
            return bool(np.std(np.diff(blocks, axis=1)) < 0.5 * spread)

        # the telescoping sum of differences is small over any second: only wandering values can be sums
        judged("angular rate", dtheta,
               lambda increments: (gyro_rest_rate if increments is dtheta else rest_rate(increments)) <= limit,
               f"{gyro_rest_rate:.4g} rad/s",
               f"at rest ({rest.sum() * per_block_rest * nominal:.0f} s where the accelerometers are quiet) the angular "
               f"rate should be the earth rate plus the {profile.name} profile's gyro bias, at most {limit:.3g} rad/s",
               sums_possible=wanders_at_rest)
