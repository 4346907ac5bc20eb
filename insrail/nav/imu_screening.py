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

Every removed record is listed with its time and size. More than ``max_fraction`` of the
records out of the envelope is no longer a few corrupt records but a wrong file, unit or profile:
that is an error naming the file.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, replace

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

from insrail.io.types import GAP_FACTOR, ImuIncrements
from insrail.nav.imu_profile import ImuProfile
from insrail.notices import Notice

#: records either side whose median a record is compared with
NEIGHBOURS = 5
#: notices listing single records; the rest are summed up in one more
MAX_LISTED = 10


@dataclass(frozen=True)
class Outlier:
    """One removed IMU record: its time, what was wrong and by how much."""

    time_s: float
    index: int  # in the file's records
    quantity: str  # "specific force" or "angular rate"
    axis: str  # "x", "y", "z"
    value: float  # [m/s^2] or [rad/s]; NaN/inf when not finite
    reference: float  # the median of its neighbours, same unit
    reason: str  # "not finite", "beyond range", "spike"

    def describe(self, source: str) -> str:
        unit, scale = ("m/s^2", 1.0) if self.quantity == "specific force" else ("deg/s", 180.0 / np.pi)
        where = f"{source}: " if source else ""
        if self.reason == "not finite":
            what = f"{self.quantity} {self.axis} is {self.value}"
        else:
            what = (f"{self.quantity} {self.axis} {scale * self.value:.4g} {unit} against {scale * self.reference:.4g} "
                    f"{unit} around it ({self.reason})")
        return f"{where}IMU record {self.index + 1} at t = {self.time_s:.4f} s removed as an outlier: {what}; bridged"


def screen_imu(imu: ImuIncrements, profile: ImuProfile, max_fraction: float = 0.01
               ) -> tuple[ImuIncrements, tuple[Outlier, ...], list[Notice]]:
    """(the records inside the envelope, the removed ones, notices). The returned increments have
    holes where records were removed; :func:`insrail.nav.imu_gaps.bridge_gaps` fills them.
    Raises ValueError naming the file when more than ``max_fraction`` of the records fail."""
    n = len(imu)
    source = str(imu.source or "")
    if n < 3:
        return imu, (), []
    step = np.diff(imu.time_s)
    nominal = float(np.median(step))
    # a record after a dropout holds one nominal interval (the ImuIncrements gap contract)
    dt = np.concatenate([[nominal], np.where(step > GAP_FACTOR * nominal, nominal, step)])
    rates = {"specific force": imu.dvel_mps / dt[:, None], "angular rate": imu.dtheta_rad / dt[:, None]}
    limits = {"specific force": (profile.specific_force_range_mps2, profile.specific_force_jump_mps2),
              "angular rate": (profile.rate_range_radps, profile.rate_jump_radps)}
    bad = np.zeros(n, dtype=bool)
    found: dict[int, Outlier] = {}
    for quantity, values in rates.items():
        full_range, jump = limits[quantity]
        with np.errstate(invalid="ignore", over="ignore"):
            finite = np.isfinite(values)
            beyond = finite & (np.abs(values) > full_range)
            # spikes: only records next to a large step between neighbours are candidates
            clean = np.where(finite & ~beyond, values, np.nan)
            edge = np.abs(np.diff(clean, axis=0)) > jump
        candidates = np.flatnonzero(~finite.all(axis=1) | beyond.any(axis=1)
                                    | np.concatenate([edge.any(axis=1), [False]]) | np.concatenate([[False], edge.any(axis=1)]))
        if candidates.size > 2 * max_fraction * n + 10:
            raise ValueError(
                f"{source or 'IMU'}: {candidates.size} of {n} records ({100 * candidates.size / n:.1f} %) leave the "
                f"{profile.name} profile's envelope ({quantity} range {_show(quantity, full_range)}, change between "
                f"records {_show(quantity, jump)}): not a few corrupt records but a wrong unit, sensor axes or IMU "
                "profile; check the file's format options and survey.imu_profile")
        reference = np.full((candidates.size, 3), np.nan)
        if candidates.size:
            padded = np.pad(clean, ((NEIGHBOURS, NEIGHBOURS), (0, 0)), constant_values=np.nan)
            windows = sliding_window_view(padded, 2 * NEIGHBOURS + 1, axis=0)[candidates]  # (c, 3, w)
            windows = windows.copy()
            windows[:, :, NEIGHBOURS] = np.nan  # the record itself does not vote
            with warnings.catch_warnings():  # a record whose neighbours are all bad has no median
                warnings.simplefilter("ignore", RuntimeWarning)
                reference = np.nanmedian(windows, axis=2)
        for c, k in enumerate(candidates):
            for axis in range(3):
                value, ref = values[k, axis], reference[c, axis]
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
    if count == 0:
        return imu, (), []
    if count > max_fraction * n:
        raise ValueError(
            f"{source or 'IMU'}: {count} of {n} records ({100 * count / n:.1f} %) are outside the {profile.name} "
            "profile's envelope: not a few corrupt records but a wrong unit, sensor axes or IMU profile; check the "
            "file's format options and survey.imu_profile")
    outliers = tuple(found[k] for k in sorted(found))
    notices = [Notice("imu", o.describe(source), file=source, time_s=o.time_s) for o in outliers[:MAX_LISTED]]
    if len(outliers) > MAX_LISTED:
        rest = outliers[MAX_LISTED:]
        notices.append(Notice("imu", f"{source + ': ' if source else ''}{len(rest)} more IMU records removed as outliers "
                              f"between t = {rest[0].time_s:.4f} and {rest[-1].time_s:.4f} s and bridged (all listed "
                              "in the fusion log)", file=source, time_s=rest[0].time_s))
    keep = ~bad
    screened = replace(imu, time_s=imu.time_s[keep], dtheta_rad=imu.dtheta_rad[keep], dvel_mps=imu.dvel_mps[keep])
    return screened, outliers, notices


def _show(quantity: str, value: float) -> str:
    return f"{value / 9.80665:g} g" if quantity == "specific force" else f"{np.degrees(value):g} deg/s"
