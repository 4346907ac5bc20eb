"""The sensors' clocks against the IMU's: each file's time offset estimated, reported and refused.

The fusion runs on the IMU's clock; a file whose time stamps run late or early puts its
measurements at the wrong place along the track (an odometer 1 s late at 1.2 m/s: 1.2 m), which
the filter can only half absorb, mostly silently. Every offset here is *how late a file's time
stamps run against the IMU's clock* [s] (negative: early), the quantity ``time_offset_s`` of
``[files.<role>]`` in survey.toml takes off the stamps as the file is read:

* odometer: its acceleration (the second difference of its distance over :data:`SMOOTHING_S`)
  against the IMU's forward specific force, integrated twice and differenced the same way, both
  high-passed over :data:`HIGHPASS_S` (gravity along a grade); the lag searched within
  ±:data:`SEARCH_S` by cross-correlation, then refined by least squares. The starts, stops and
  speed changes carry it; a survey always has a start from rest;
* GNSS: its speed cross-correlated with the odometer's (:func:`estimate_gnss_odometer_offset`),
  put on the IMU's clock through the odometer's offset;
* sleeper detector: the pulses' distances along the odometer lie one sleeper spacing apart only at
  the right time shift while the speed changes (a shift δ moves a step between pulses by δ times
  the speed change over it); put on the IMU's clock through the odometer's offset. A file that fits
  no shift (another survey, another run) is refused by :func:`check_sleeper_match`;
* gauge: not estimated. Its readings are a function of the distance alone, and only the stops tell a
  time shift from the track's own gauge changes: a trolley's smooth start moves it 4 mm in the first
  0.3 s and 50 mm in the first second (the simulated 150 m survey), over which the gauge changes by
  0.01-0.02 mm against the sensor's 0.1 mm noise. A late gauge places its values v x offset along the
  track (1.2 m at 1.2 m/s and 1 s); a known latency is given as ``time_offset_s`` of ``[files.gauge]``.

An offset of :data:`NOTICE_OFFSET_S` or more is a notice, one of :data:`MAX_OFFSET_S` or more an
error naming the file and the offset (give it as ``time_offset_s`` when it is a known latency);
an offset that cannot be told to :data:`MAX_SIGMA_S` (a survey without speed changes) is not
judged. When the odometer and the GNSS both run the same offset against the IMU, the IMU's own
time stamps are the ones named.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from insrail.background import BackgroundJob
from insrail.io.errors import InputError, ManifestError
from insrail.io.survey import MANIFEST_NAME, SurveyData
from insrail.io.types import GnssSolution, ImuIncrements, OdometerData, SleeperPulses
from insrail.nav.rotation import euler_to_dcm
from insrail.notices import Notice, Phrase
from insrail.progress import Cancelled
from insrail.project.plausibility import GPS_MINUS_UTC_S, distance_at, gnss_track, read_as, running_sum_at

NOTICE_OFFSET_S = 0.2
MAX_OFFSET_S = 0.5
MAX_SIGMA_S = 0.05
#: what an offset is stated to at best: the odometer's against the IMU lies within ±0.04 s of the
#: truth on the simulated surveys (the trolley's play and the grade leak into the IMU's acceleration)
ESTIMATE_FLOOR_S = 0.05
GRID_STEP_S = 0.1
SMOOTHING_S = 0.5
HIGHPASS_S = 30.0
SEARCH_S = 60.0
MIN_ACCELERATION_RMS_MPS2 = 0.005
MIN_CORRELATION = 0.8
MOVING_MPS = 0.05
MIN_SLEEPER_MATCH = 0.8
#: sleepers are laid to about ±10 mm (0.6 m: 1.7 %); the simulated detector scatters 0.5 %
MAX_SLEEPER_SCATTER = 0.02
SLEEPER_SEARCH_S = 300.0


@dataclass(frozen=True)
class ClockOffset:
    """How late one file's time stamps run against the IMU's clock, and how that was found."""

    role: str
    offset_s: float
    sigma_s: float
    method: Phrase


# --------------------------------------------------------------------------- odometer against the IMU

def _highpass(values: np.ndarray, samples: int) -> np.ndarray:
    """``values`` less their running mean over ``samples`` (the mean of what lies inside at the ends)."""
    kernel = np.ones(samples)
    mean = np.convolve(values, kernel, mode="same") / np.convolve(np.ones(len(values)), kernel, mode="same")
    return values - mean


def _second_difference(values: np.ndarray, step: int) -> np.ndarray:
    """(x[i+step] - 2 x[i] + x[i-step]) / (step * GRID_STEP_S)^2 for the samples ``step`` from either end."""
    return (values[2 * step:] - 2.0 * values[step:-step] + values[:-2 * step]) / (step * GRID_STEP_S) ** 2


def _imu_forward_velocity(imu: ImuIncrements, mounting_rpy_rad: np.ndarray, times: np.ndarray) -> np.ndarray:
    """The running sum of the IMU's velocity increments along the trolley's forward axis at ``times``
    (gravity and biases left in: the second difference and the high-pass take them out)."""
    forward = euler_to_dcm(*mounting_rpy_rad)[0]  # the trolley's x axis in the b frame: C_b^v row 0
    after = np.clip(np.searchsorted(imu.time_s, times), 1, len(imu.time_s) - 1)
    records = sorted(set(after.tolist()) | set((after - 1).tolist()))
    sums = np.zeros(len(records))
    for axis in range(3):
        if forward[axis] != 0.0:
            sums += forward[axis] * np.asarray(running_sum_at(imu.dvel_mps, axis, records)[1])
    at = dict(zip(records, sums))
    t0, t1 = imu.time_s[after - 1], imu.time_s[after]
    v0, v1 = np.array([at[i] for i in (after - 1).tolist()]), np.array([at[i] for i in after.tolist()])
    return v0 + (v1 - v0) * np.clip((times - t0) / (t1 - t0), 0.0, 1.0)


def _correlate_full(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """scipy.signal.correlate(a, b, mode="full", method="fft") of two real series, bit for bit (its
    FFT product, done here: scipy.signal imports scipy.stats, about a second of every processing)."""
    from scipy import fft

    size = a.size + b.size - 1
    shape = [fft.next_fast_len(size, True)]
    product = fft.rfftn(a, shape, axes=[0]) * fft.rfftn(b[::-1].conj(), shape, axes=[0])
    return fft.irfftn(product, shape, axes=[0])[:size].copy()


def estimate_odometer_offset(imu: ImuIncrements, odometer: OdometerData,
                             mounting_rpy_rad: np.ndarray) -> ClockOffset | None:
    """The odometer's time offset against the IMU from their accelerations; None when the survey's
    accelerations are too weak or too unlike to tell."""
    step = int(round(SMOOTHING_S / GRID_STEP_S))
    start = max(float(imu.time_s[0]), float(odometer.time_s[0])) + SMOOTHING_S
    end = min(float(imu.time_s[-1]), float(odometer.time_s[-1])) - SMOOTHING_S
    if end - start < 4 * HIGHPASS_S:
        return None
    grid = np.arange(start, end, GRID_STEP_S)
    velocity = _imu_forward_velocity(imu, mounting_rpy_rad, grid)
    travelled = np.concatenate([[0.0], np.cumsum(0.5 * (velocity[1:] + velocity[:-1]) * GRID_STEP_S)])
    samples = int(round(HIGHPASS_S / GRID_STEP_S))
    imu_acceleration = _highpass(_second_difference(travelled, step), samples)
    inner = grid[step:-step]

    def odometer_acceleration(offset_s: float) -> np.ndarray:
        # the odometer read at the IMU's times plus the offset: its stamps run offset_s late
        distance = np.interp(grid + offset_s, odometer.time_s, odometer.distance_m)
        return _highpass(_second_difference(distance, step), samples)

    unshifted = odometer_acceleration(0.0)
    if min(np.std(unshifted), np.std(imu_acceleration)) < MIN_ACCELERATION_RMS_MPS2:
        return None
    lags = int(round(SEARCH_S / GRID_STEP_S))
    # full[k] = sum_n odometer[n + k - (N - 1)] * imu[n]: the odometer lagging by k - (N - 1) samples
    full = _correlate_full(unshifted, imu_acceleration)
    centre = len(inner) - 1
    window = full[centre - lags:centre + lags + 1]
    coarse = (int(np.argmax(np.abs(window))) - lags) * GRID_STEP_S
    fine = coarse + np.arange(-GRID_STEP_S, GRID_STEP_S + 1e-9, 0.01)

    def fit(offset_s: float) -> tuple[float, float, np.ndarray]:
        acceleration = odometer_acceleration(offset_s)
        usable = np.abs(inner + offset_s - np.clip(inner + offset_s, odometer.time_s[0], odometer.time_s[-1])) == 0
        a, b = acceleration[usable], imu_acceleration[usable]
        gain = float(a @ b / (a @ a))
        return float(np.mean((b - gain * a) ** 2)), gain, usable

    costs = [fit(offset)[0] for offset in fine]
    best = int(np.argmin(costs))
    offset = float(fine[best])
    if 0 < best < len(fine) - 1:  # the parabola's vertex through the three costs around the least
        left, middle, right = costs[best - 1:best + 2]
        curvature = left - 2 * middle + right
        if curvature > 0:
            offset += 0.01 * 0.5 * (left - right) / curvature
    cost, gain, usable = fit(offset)
    slope = (odometer_acceleration(offset + 0.01) - odometer_acceleration(offset - 0.01))[usable] / 0.02
    correlation = np.corrcoef(odometer_acceleration(offset)[usable], imu_acceleration[usable])[0, 1]
    if abs(correlation) < MIN_CORRELATION or not slope.any():
        return None
    sigma = float(np.sqrt(cost / (gain**2 * (slope @ slope))))
    return ClockOffset("odometer", offset, sigma, Phrase("its acceleration against the IMU's, r = {r:.3f}",
                                                         {"r": abs(correlation)}))


# --------------------------------------------------------------------------- GNSS against the odometer

def estimate_gnss_odometer_offset(odometer: OdometerData, gnss: GnssSolution) -> tuple[float, float, float] | None:
    """(offset [s], its sigma [s], correlation there): the odometer's speed at t + offset best
    matches the GNSS speed at t (the odometer's stamps run ``offset`` later than the GNSS's).
    None when the speed profile has too little variation to tell."""
    time_s, xyz = gnss_track(gnss)
    if len(time_s) < 30 or len(odometer.time_s) < 30:
        return None
    dt = np.diff(time_s)
    regular = dt <= 1.5 * np.median(dt)
    gnss_speed = np.linalg.norm(np.diff(xyz, axis=0), axis=1)[regular] / dt[regular]
    t0, t1 = time_s[:-1][regular], time_s[1:][regular]
    if len(gnss_speed) < 30 or np.std(gnss_speed) < 0.05:
        return None

    def odometer_speed(offset: float) -> np.ndarray:
        return np.abs(distance_at(odometer, t1 + offset) - distance_at(odometer, t0 + offset)) / (t1 - t0)

    def correlation(offsets: np.ndarray) -> np.ndarray:
        out = np.full(len(offsets), -1.0)
        for i, offset in enumerate(offsets):
            speed = odometer_speed(offset)
            both = np.isfinite(speed)
            if both.sum() >= 0.5 * len(speed) and np.std(speed[both]) > 0:
                out[i] = np.corrcoef(speed[both], gnss_speed[both])[0, 1]
        return out

    coarse = np.arange(-SEARCH_S, SEARCH_S + 0.5, 0.5)
    best = float(coarse[int(np.argmax(correlation(coarse)))])
    fine = np.arange(best - 0.6, best + 0.61, 0.05)
    fine_values = correlation(fine)
    offset = float(fine[int(np.argmax(fine_values))])
    # least squares about the peak: the speed difference against the speed's change with the offset
    speed = odometer_speed(offset)
    slope = (odometer_speed(offset + 0.05) - odometer_speed(offset - 0.05)) / 0.1
    both = np.isfinite(speed) & np.isfinite(slope)
    gain = float(speed[both] @ gnss_speed[both] / (speed[both] @ speed[both]))
    residual = gnss_speed[both] - gain * speed[both]
    step = float(residual @ slope[both] / (gain * slope[both] @ slope[both]))
    if abs(step) < 0.05:
        offset += step
    sigma = float(np.sqrt(np.mean(residual**2) / (gain**2 * (slope[both] @ slope[both])))) if slope[both].any() else np.inf
    return offset, sigma, float(fine_values.max())


# --------------------------------------------------------------------------- sleeper pulses against the odometer

def _sleeper_match(pulses: np.ndarray, odometer: OdometerData, offset: float) -> tuple[float, float]:
    """(share of consecutive pulses one spacing apart along the odometer, that spacing [m])."""
    steps = np.diff(distance_at(odometer, pulses + offset))
    steps = np.abs(steps[np.isfinite(steps)])
    if len(steps) < 10:
        return 0.0, float("nan")
    spacing = float(np.median(steps))
    if spacing <= 0:
        return 0.0, spacing
    return float(np.mean(np.abs(steps - spacing) < 0.25 * spacing)), spacing


def check_sleeper_match(pulses: SleeperPulses | None, odometer: OdometerData, sleepers_label: str,
                        odometer_label: str) -> None:
    """InputError when the sleeper pulses lie one spacing apart along the odometer distance at no
    time shift (a file of another survey or run), or clearly better at one far away."""
    if pulses is None or len(pulses.time_s) < 20:
        return
    match, spacing = _sleeper_match(pulses.time_s, odometer, 0.0)
    offsets = np.arange(-SLEEPER_SEARCH_S, SLEEPER_SEARCH_S + 0.5, 0.5)
    scores = [_sleeper_match(pulses.time_s, odometer, o)[0] for o in offsets]
    best = int(np.argmax(scores))
    clearly_shifted = abs(offsets[best]) > 1.0 and scores[best] - match > 0.1
    if match >= MIN_SLEEPER_MATCH and not clearly_shifted:
        return
    hint = (Phrase("; shifted by {shift_s:+.1f} s they would match ({score_pct:.0f} %): a file on another time scale",
                   {"shift_s": offsets[best], "score_pct": 100 * scores[best]}) if scores[best] >= MIN_SLEEPER_MATCH else
            Phrase(": a file of another survey or run, or a detector that misses or doubles pulses"))
    path = pulses.source or Path(sleepers_label)
    raise InputError(path, None, "{read_as}only {match_pct:.0f} % of consecutive sleeper pulses lie one "
                     "sleeper spacing ({spacing:.3f} m, the median) apart along the odometer distance "
                     "({odometer_label}); expected at least {min_match_pct:.0f} % and no better match "
                     "at another time{hint}", fields={"read_as": read_as(sleepers_label), "match_pct": 100 * match, "spacing": spacing, "odometer_label": odometer_label, "min_match_pct": 100 * MIN_SLEEPER_MATCH, "hint": hint})


def estimate_sleeper_odometer_offset(pulses: SleeperPulses, odometer: OdometerData
                                     ) -> tuple[float, float, float] | None:
    """(offset [s], its sigma [s], the steps' RMS scatter about whole spacings as a share of the
    spacing): the pulses lie one spacing apart along the odometer read at the
    pulse times plus ``offset`` (the odometer's stamps run ``offset`` later than the pulses').
    Least squares over the steps between consecutive pulses (a missed sleeper: two spacings; a
    false pulse is left out): a shift δ changes a step by δ times the speed change over it."""
    times = np.asarray(pulses.time_s, dtype=float)
    offset, sigma, scatter = 0.0, np.inf, np.inf
    for _ in range(4):
        at = times + offset
        distance = distance_at(odometer, at)
        speed = (distance_at(odometer, at + 0.1) - distance_at(odometer, at - 0.1)) / 0.2
        steps, change = np.diff(distance), np.diff(speed)
        moving = (np.abs(speed[:-1]) > MOVING_MPS) & (np.abs(speed[1:]) > MOVING_MPS) & np.isfinite(steps + change)
        if moving.sum() < 20:
            return None
        spacing = float(np.median(np.abs(steps[moving])))
        count = np.round(np.abs(steps) / spacing)
        residual = np.abs(steps) - count * spacing
        usable = moving & (count >= 1) & (count <= 2) & (np.abs(residual) < 0.15 * spacing)
        signed_change = np.sign(steps) * change
        weight = float(signed_change[usable] @ signed_change[usable])
        if usable.sum() < 20 or weight <= 0:
            return None
        step = -float(residual[usable] @ signed_change[usable]) / weight
        offset += step
        spread = float(np.sqrt(np.mean((residual[usable] + step * signed_change[usable]) ** 2)))
        sigma, scatter = spread / np.sqrt(weight), spread / spacing
        if abs(step) < 1e-3:
            break
    return offset, sigma, scatter


# --------------------------------------------------------------------------- all clocks of a survey

def clock_offsets(survey: SurveyData) -> tuple[list[ClockOffset], float]:
    """The offsets that can be told (sigma within :data:`MAX_SIGMA_S`) against the IMU's clock, and
    the sleeper pulses' scatter about whole spacings along the odometer (a share of the spacing;
    NaN without them)."""
    scatter = float("nan")
    if survey.odometer is None:
        return [], scatter
    found = []
    odometer = estimate_odometer_offset(survey.imu, survey.odometer, survey.manifest.trolley.mounting_rpy_rad)
    base = 0.0 if odometer is None else odometer.offset_s
    if odometer is not None:
        found.append(odometer)
    if survey.gnss is not None and (gnss := estimate_gnss_odometer_offset(survey.odometer, survey.gnss)):
        offset, sigma, correlation = gnss
        if correlation >= MIN_CORRELATION:
            method = Phrase("its speed against the odometer's, r = {r:.3f}{added}",
                            {"r": correlation, "added": Phrase(", the odometer's offset against the IMU added"
                                                               if odometer is not None else "")})
            found.append(ClockOffset("gnss", base - offset, float(np.hypot(sigma, odometer.sigma_s if odometer else 0.0)),
                                     method))
    if survey.sleepers is not None and (sleepers := estimate_sleeper_odometer_offset(survey.sleepers, survey.odometer)):
        offset, sigma, scatter = sleepers
        found.append(ClockOffset("sleepers", base - offset, float(np.hypot(sigma, odometer.sigma_s if odometer else 0.0)),
                                 Phrase("the spacing of its pulses along the odometer{added}",
                                        {"added": Phrase(", the odometer's offset against the IMU added"
                                                         if odometer is not None else "")})))
    return [offset for offset in found if offset.sigma_s <= MAX_SIGMA_S], scatter


def _cause(offset_s: float, role: str) -> Phrase:
    seconds = abs(offset_s)
    if role == "gnss" and round(seconds) in GPS_MINUS_UTC_S and abs(seconds - round(seconds)) < 0.3:
        return Phrase("{leap_s} s is GPS - UTC (leap seconds): GNSS times in UTC read as GPST (an RTKLIB .pos "
                      "written in UTC, or without its header)", {"leap_s": round(seconds)})
    return Phrase("the loggers' clocks are not synchronised, or a file of another survey")


def check_clocks(survey: SurveyData, labels: dict[str, str]) -> list[Notice]:
    """Notices for the offsets from :data:`NOTICE_OFFSET_S`; an InputError naming the file (a
    ManifestError naming each, for several) for those from :data:`MAX_OFFSET_S`. ``labels``: the
    files as :func:`~insrail.project.plausibility.describe` names them, by role."""
    if survey.odometer is not None:
        check_sleeper_match(survey.sleepers, survey.odometer, labels["sleepers"], labels["odometer"])
    found, scatter = clock_offsets(survey)
    notices = []
    if scatter > MAX_SLEEPER_SCATTER:
        path = survey.sleepers.source or Path(labels["sleepers"])
        notices.append(Notice("time", "{sleepers}: the sleeper pulses lie {scatter_pct:.1f} % (RMS) off whole sleeper "
                              "spacings along the odometer ({odometer}), more than sleepers are laid to: a file of "
                              "another run, or a detector that misses, doubles or delays pulses", file=str(path),
                              fields={"sleepers": labels["sleepers"], "scatter_pct": 100 * scatter,
                                      "odometer": labels["odometer"]}))
    offsets = {offset.role: offset for offset in found}
    odometer, gnss = offsets.get("odometer"), offsets.get("gnss")
    if (odometer is not None and gnss is not None and abs(odometer.offset_s) >= NOTICE_OFFSET_S
            and abs(odometer.offset_s - gnss.offset_s) < NOTICE_OFFSET_S):
        # the odometer and the GNSS agree with each other: the IMU's stamps are the odd ones
        sleepers = offsets.get("sleepers")
        offsets = {"imu": ClockOffset("imu", -0.5 * (odometer.offset_s + gnss.offset_s), max(odometer.sigma_s, gnss.sigma_s),
                                      Phrase("the odometer's and the GNSS's accelerations and speeds, which agree"))}
        if sleepers is not None:
            offsets["sleepers"] = ClockOffset("sleepers", sleepers.offset_s - odometer.offset_s, sleepers.sigma_s,
                                              sleepers.method)
    problems = []
    for role, offset in offsets.items():
        seconds = offset.offset_s
        if abs(seconds) < NOTICE_OFFSET_S:
            continue
        entry = survey.manifest.files.get(role)
        data = getattr(survey, role, None)
        path = getattr(data, "source", None) or (survey.folder / entry.path if entry else Path(role))
        label = labels.get(role, path.name)
        given = entry.time_offset_s if entry is not None else 0.0
        text = Phrase("its time stamps run {seconds:.2f} s late against the IMU's clock (±{sigma_s:.2f} s, from "
                      "{method}{given})" if seconds > 0 else
                      "its time stamps run {seconds:.2f} s early against the IMU's clock (±{sigma_s:.2f} s, from "
                      "{method}{given})",
                      {"seconds": abs(seconds), "sigma_s": max(offset.sigma_s, ESTIMATE_FLOOR_S), "method": offset.method,
                       "given": Phrase("; after the time_offset_s = {given_s:g} s given", {"given_s": given}) if given
                       else Phrase("")})
        if abs(seconds) < MAX_OFFSET_S:
            notices.append(Notice("time", "{label}: {text}: check the time synchronisation, or give the offset as "
                                  "time_offset_s = {offset_s:.2f} in [files.{role}] of survey.toml if it is the "
                                  "sensor's latency", file=str(path),
                                  fields={"label": label, "text": text, "offset_s": given + seconds, "role": role}))
            continue
        remedy = (Phrase("if it is the sensor's known latency, give time_offset_s = {offset_s:.2f} in [files.{role}] "
                         "of survey.toml", {"offset_s": given + seconds, "role": role}) if role != "imu"
                  else Phrase("the IMU's clock is the reference the others are put on"))
        problems.append(InputError(path, None, "{read_as}{text}; an offset of {max_offset_s:g} s or more "
                                   "is refused: likely {cause}; {remedy}", fields={"read_as": read_as(label), "text": text, "max_offset_s": MAX_OFFSET_S, "cause": _cause(seconds, role), "remedy": remedy}))
    if len(problems) == 1:
        raise problems[0]
    if problems:
        raise ManifestError(survey.folder / MANIFEST_NAME, [Phrase("{file}: {message}", {"file": str(problem.path),
                                                                                        "message": problem.phrase})
                                                            for problem in problems])
    return notices


class ClockCheck:
    """:func:`check_clocks` beside the work after it (the other checks, the fusion's IMU screening; 1.7 s of
    CPU at 10 km), a :class:`~insrail.background.BackgroundJob` (at once in the caller's thread on a CPU
    budget of one). Its verdict still comes first: :meth:`failed` tells the work beside it to stop,
    :meth:`first` raises its error in place of the work's, :meth:`notices` waits for them (raising its error)."""

    def __init__(self, survey: SurveyData, labels: dict[str, str]):
        self._job = BackgroundJob(lambda progress, cancel: check_clocks(survey, labels), None, None, "insrail-clocks")

    def failed(self) -> bool:
        return self._job.done() and self._job.exception() is not None

    def notices(self) -> list[Notice]:
        return self._job.result()

    def first(self, error: BaseException) -> None:
        """Raise the clocks' error, if any, where the work beside them failed with ``error`` (a cancel by the
        user is not held up for the verdict)."""
        if isinstance(error, Cancelled) and not self._job.done():
            return
        if (verdict := self._job.exception()) is not None:
            raise verdict from None
