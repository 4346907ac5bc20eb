"""The IMU's mounting on the trolley (C_b^v: roll, pitch, yaw of b in the trolley frame v), from the survey.

The non-holonomic constraint holds the trolley frame's x axis along the rail; with a mounting
0.3 deg wrong it holds the IMU's axes 0.3 deg off the track and pulls the attitude against the
other sources (thesis 5.3.1.2; measured: the 30 m/5 m error 0.116 -> 0.362 mm with the yaw 0.3 deg
wrong, nothing said). So the mounting is estimated from the survey itself:

* **yaw and pitch** - a pass of the fusion without the NHC (which would impose the given mounting),
  smoothed, at the update rate: the velocity of the reference rail's point (the IMU's velocity plus
  the turn rate times the lever arm) runs along the rail, so seen in b it is the v frame's x axis:
  ``x_v^b = (cos psi cos theta, -sin psi, cos psi sin theta)`` for small roll, psi and theta the
  mounting's yaw and pitch. Averaged over the moving epochs. Its 1-sigma: the spread of the means
  of :data:`BLOCK_S` blocks (the errors are correlated in time) and, not averaged away, the pass's
  own heading and pitch 1-sigma of b (the estimate is as good as the IMU's attitude);
* **roll** - the thesis's field method: the measured cant against the design's (a straight level
  stretch's is zero). A roll error eps of the mounting tilts the trolley's y axis by -eps, so the
  measured cant is ``spacing * eps`` lower everywhere: eps = -mean(cant - design cant) / spacing. It
  assumes the track's mean cross-level is the design's (the survey's own mean cant offset is
  calibrated away; the notice says so). Its 1-sigma: block means again, over
  :data:`ROLL_BLOCK_SLEEPERS` sleepers, and that assumption's (:data:`CROSS_LEVEL_REFERENCE_M`).

A mounting estimate more than :data:`SIGNIFICANT_SIGMAS` times its 1-sigma from the given one is
applied (the caller fuses again / places the rails again with it) and said in a warning.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from insrail.nav.rotation import euler_to_dcm
from insrail.notices import Phrase, phrase_of

#: moving epochs: the rail point's speed above this [m/s]
MIN_SPEED_MPS = 0.3
#: the yaw/pitch series is averaged in blocks of this length [s] for its 1-sigma
BLOCK_S = 30.0
ROLL_BLOCK_SLEEPERS = 48
#: 1-sigma [m] of the track's mean cross-level against its design's over a survey (what the roll takes for
#: zero: the rails' laying and the gauge's reading): 0.3 mm is 0.011 deg over 1.5 m
CROSS_LEVEL_REFERENCE_M = 0.3e-3
#: an estimate this many 1-sigma from the given mounting is applied (and warned of)
SIGNIFICANT_SIGMAS = 3.0
AXES = ("roll", "pitch", "yaw")


@dataclass(frozen=True)
class MountingEstimate:
    """The mounting the survey shows: (roll, pitch, yaw) [rad] and 1-sigma (NaN: not estimated,
    ``why`` says why), against the given one."""

    given_rpy_rad: np.ndarray
    rpy_rad: np.ndarray
    sigma_rad: np.ndarray
    why: dict = field(default_factory=dict)  # axis -> why it is not estimated (a Phrase: said in the report's language)

    @property
    def significant(self) -> np.ndarray:
        """Per axis: the estimate lies more than SIGNIFICANT_SIGMAS x its 1-sigma from the given one."""
        apart = np.abs(self.rpy_rad - self.given_rpy_rad)
        return np.isfinite(self.sigma_rad) & (apart > SIGNIFICANT_SIGMAS * np.nan_to_num(self.sigma_rad, nan=np.inf))

    def applied_rpy_rad(self) -> np.ndarray:
        """The mounting to use: the estimate where it is significant, the given one elsewhere."""
        return np.where(self.significant, self.rpy_rad, self.given_rpy_rad)

    def combined(self, other: MountingEstimate) -> MountingEstimate:
        """This estimate with the axes ``other`` estimated taken from it."""
        take = np.isfinite(other.sigma_rad)
        why = {axis: text for axis, text in {**self.why, **other.why}.items() if not take[AXES.index(axis)]}
        return MountingEstimate(self.given_rpy_rad, np.where(take, other.rpy_rad, self.rpy_rad),
                                np.where(take, other.sigma_rad, self.sigma_rad), why)

    @classmethod
    def from_dict(cls, table: dict | None, given_rpy_rad) -> MountingEstimate:
        """From :meth:`to_dict`'s table (None: a fusion cached before the calibration: not estimated)."""
        if table is None:
            return not_estimated(given_rpy_rad, Phrase("fused before the mounting calibration"))
        given = np.radians(np.asarray(table["given_rpy_deg"], dtype=float))
        rpy, sigma, why = given.copy(), np.full(3, np.nan), {}
        for i, axis in enumerate(AXES):
            entry = table[axis]
            if "estimate_deg" in entry:
                rpy[i], sigma[i] = math.radians(entry["estimate_deg"]), math.radians(entry["sigma_deg"])
            else:
                why[axis] = why_of(entry)
        return cls(given, rpy, sigma, why)

    def to_dict(self) -> dict:
        """summary.toml's ``[fusion.mounting]`` [deg]."""
        out = {"given_rpy_deg": [round(float(v), 5) for v in np.degrees(self.given_rpy_rad)],
               "applied_rpy_deg": [round(float(v), 5) for v in np.degrees(self.applied_rpy_rad())]}
        for i, axis in enumerate(AXES):
            if np.isfinite(self.sigma_rad[i]):
                out[axis] = {"estimate_deg": round(math.degrees(self.rpy_rad[i]), 5),
                             "sigma_deg": round(math.degrees(self.sigma_rad[i]), 5),
                             "applied": bool(self.significant[i])}
            else:
                why = phrase_of(self.why.get(axis, ""))
                out[axis] = {"not_estimated": str(why), **why.to_dict()}  # the English, and its template for a report
        return out

    def text(self) -> Phrase:
        """One line: each axis's estimate and 1-sigma, or why not (a why is one of the texts of names_zh.py)."""
        parts = []
        for i, axis in enumerate(AXES):
            if np.isfinite(self.sigma_rad[i]):
                parts.append(Phrase("{axis} {estimate_deg:+.3f} deg (1-sigma {sigma_deg:.4f}, given {given_deg:+.3f})",
                                    {"axis": Phrase(axis), "estimate_deg": math.degrees(self.rpy_rad[i]),
                                     "sigma_deg": math.degrees(self.sigma_rad[i]),
                                     "given_deg": math.degrees(self.given_rpy_rad[i])}))
            else:
                parts.append(Phrase("{axis} not estimated ({reason})",
                                    {"axis": Phrase(axis), "reason": phrase_of(self.why.get(axis, ""))}))
        return Phrase("IMU mounting from the survey: {axes}", {"axes": parts})


def why_of(entry: dict) -> Phrase:
    """Why an axis is not estimated, from :meth:`MountingEstimate.to_dict`'s table (English alone: an older summary)."""
    return Phrase.from_dict(entry) if "template" in entry else Phrase(str(entry["not_estimated"]))


def not_estimated(given_rpy_rad, why: Phrase) -> MountingEstimate:
    given = np.asarray(given_rpy_rad, dtype=float)
    return MountingEstimate(given, given.copy(), np.full(3, np.nan), {axis: why for axis in AXES})


def _block_sigma(time_s: np.ndarray, values: np.ndarray, block: float) -> float:
    """1-sigma of the mean of ``values`` from the spread of its block means (at least two blocks)."""
    index = np.floor((time_s - time_s[0]) / block).astype(int)
    # time runs forward: each block is one contiguous stretch (its mean over the same values in order)
    means = np.array([part.mean() for part in np.split(values, np.flatnonzero(np.diff(index)) + 1)])
    if len(means) < 2:
        return math.inf
    return float(np.std(means, ddof=1) / math.sqrt(len(means)))


def yaw_pitch_from_velocity(trajectory, given_rpy_rad, rail_point_m: np.ndarray) -> MountingEstimate:
    """Yaw and pitch of the mounting from a trajectory fused without the NHC (see the module docstring);
    ``rail_point_m``: the reference rail's point in b [m]."""
    given = np.asarray(given_rpy_rad, dtype=float)
    t = np.asarray(trajectory.time_s, dtype=float)
    rpy = np.asarray(trajectory.rpy_rad, dtype=float)
    heading = np.unwrap(rpy[:, 2])
    turn = np.gradient(heading, t) if len(t) > 2 else np.zeros(len(t))
    c_bn = euler_to_dcm(rpy[:, 0], rpy[:, 1], rpy[:, 2])
    arm_n = c_bn @ np.asarray(rail_point_m, dtype=float)
    # the turn rate about the vertical (down) times the lever arm: what the rail point moves besides the IMU
    vel = np.asarray(trajectory.vel_ned_mps, dtype=float) + np.column_stack(
        [-turn * arm_n[:, 1], turn * arm_n[:, 0], np.zeros(len(t))])
    v_b = np.einsum("kji,kj->ki", c_bn, vel)  # C_n^b v
    speed = np.linalg.norm(v_b, axis=1)
    moving = speed > MIN_SPEED_MPS
    if moving.sum() < 100:
        return not_estimated(given, Phrase("the trolley hardly moves"))
    v = v_b[moving] * np.sign(v_b[moving, :1])  # a trolley pushed backwards runs along -x_v
    yaw = -np.arctan2(v[:, 1], np.hypot(v[:, 0], v[:, 2]))
    pitch = np.arctan2(v[:, 2], v[:, 0])
    sigma_att = np.asarray(trajectory.sigma_rpy_rad, dtype=float)[moving]
    estimate = given.copy()
    sigma = np.full(3, np.nan)
    for i, series, attitude in ((1, pitch, sigma_att[:, 1]), (2, yaw, sigma_att[:, 2])):
        estimate[i] = float(np.mean(series))
        sigma[i] = math.hypot(_block_sigma(t[moving], series, BLOCK_S), float(np.median(attitude)))
    return MountingEstimate(given, estimate, sigma, {"roll": Phrase("it needs the cant against a design's: insrail process")})


def roll_from_cant(given_rpy_rad, cant_m: np.ndarray, design_cant_m: np.ndarray, spacing_m: float,
                   valid: np.ndarray) -> MountingEstimate:
    """Roll of the mounting from the measured cant against the design's (see the module docstring)."""
    given = np.asarray(given_rpy_rad, dtype=float)
    difference = (np.asarray(cant_m, float) - np.asarray(design_cant_m, float))
    use = np.asarray(valid, bool) & np.isfinite(difference)
    if use.sum() < 2 * ROLL_BLOCK_SLEEPERS:
        return not_estimated(given, Phrase("fewer than {count} valid sleepers with a design cant",
                                           {"count": 2 * ROLL_BLOCK_SLEEPERS}))
    tilt = difference[use] / spacing_m
    estimate, sigma = given.copy(), np.full(3, np.nan)
    estimate[0] = given[0] + float(np.mean(tilt))
    sigma[0] = math.hypot(_block_sigma(np.arange(use.sum(), dtype=float), tilt, float(ROLL_BLOCK_SLEEPERS)),
                          CROSS_LEVEL_REFERENCE_M / spacing_m)
    return MountingEstimate(given, estimate, sigma, {"pitch": Phrase("from the velocity"), "yaw": Phrase("from the velocity")})
