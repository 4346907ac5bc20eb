"""Fastener adjustment amounts per sleeper and rail for the adjustment crews.

An adjustment ``a`` is the movement of one rail at one sleeper, in the deviation's sign
convention (lateral + right, vertical + up, metres): after the adjustment the deviation is
``d + a``. Amounts are whole fastener steps (1 mm for WJ-8) inside the fastener's range, which
is taken relative to the as-built state.

Two strategies:

* :func:`correct_to_line`: each sleeper is moved back to the design (or fitted) line, rounded
  to the step and clipped to the range (what the thesis's InsRail prints).
* :func:`optimise_adjustment`: the least total movement (sum of |a|) that keeps every
  differential-versine check (30 m / 5 m, 300 m / 150 m, every chord placement) inside its
  limit and every amount inside the fastener range; a linear programme (HiGHS) per rail and
  direction, rounded to whole steps. Sleepers whose checks are still not met are flagged.

Both work on sleeper indices: a chord of 30 m is 48 sleeper spacings, as in thesis eq. (2.2),
so the sleepers are assumed evenly spaced (the assessment re-checks the result on stations).
"""

from __future__ import annotations

import os
import tomllib
from concurrent.futures import ThreadPoolExecutor, wait
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy import sparse
from scipy.optimize import Bounds, LinearConstraint, milp

from insrail.progress import CancelToken, ProgressFn, check_cancel
from insrail.resources import resources_dir
from insrail.track.exceedance import RAILS, SleeperGeometry
from insrail.track.irregularity import SLEEPER_SPACING_M, differential_versine_grid
from insrail.track.tolerance import SettingsFileError, ToleranceProfile, read_number

DIRECTIONS = ("lateral", "vertical")
DEFAULT_FASTENER = "wj8"
VIOLATION_PENALTY = 1000.0  # cost of 1 step of residual exceedance against 1 step of movement
#: Rounds of "solve the windows, check the whole line again" (a round that changes nothing ends it).
MAX_SWEEPS = 4
#: How often [s] the progress of the channels (solved in parallel threads) is reported.
PROGRESS_INTERVAL_S = 0.2


@dataclass(frozen=True)
class FastenerType:
    """Adjustment range per rail [m] relative to the as-built state, and the step [m]."""

    name: str
    description: str
    step_m: float
    lateral_range_m: tuple[float, float]
    vertical_range_m: tuple[float, float]

    def range_m(self, direction: str) -> tuple[float, float]:
        return self.lateral_range_m if direction == "lateral" else self.vertical_range_m


def load_fastener_type(name_or_path: str | Path = DEFAULT_FASTENER) -> FastenerType:
    """A fastener type by shipped name (resources/fastener_types) or TOML path."""
    path = Path(name_or_path)
    if path.suffix != ".toml":
        path = resources_dir() / "fastener_types" / f"{name_or_path}.toml"
    if not path.is_file():
        raise SettingsFileError(path, "", "no such fastener type file")
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as err:
        raise SettingsFileError(path, "", f"not valid TOML: {err}") from None
    values = {}
    for key in ("step_mm", "lateral_min_mm", "lateral_max_mm", "vertical_min_mm", "vertical_max_mm"):
        if key not in data:
            raise SettingsFileError(path, key, "missing (a fastener type needs step_mm and the lateral/vertical min and max)")
        values[key] = read_number(path, key, data[key], positive=key == "step_mm") * 1e-3
    for direction in DIRECTIONS:
        low, high = values[f"{direction}_min_mm"], values[f"{direction}_max_mm"]
        if not low <= 0.0 <= high:
            raise SettingsFileError(path, f"{direction}_min_mm", "the range must contain 0 (min <= 0 <= max)")
    return FastenerType(
        name=str(data.get("name", path.stem)),
        description=str(data.get("description", "")),
        step_m=values["step_mm"],
        lateral_range_m=(values["lateral_min_mm"], values["lateral_max_mm"]),
        vertical_range_m=(values["vertical_min_mm"], values["vertical_max_mm"]),
    )


@dataclass(frozen=True)
class Adjustment:
    """Amounts [m] per sleeper (n, 2) [left, right]; ``unresolved_*`` flags sleepers where the
    target (the line, or the checks) cannot be reached within the fastener range."""

    lateral_m: np.ndarray
    vertical_m: np.ndarray
    unresolved_lateral: np.ndarray  # (n, 2) bool
    unresolved_vertical: np.ndarray  # (n, 2) bool
    fastener: str

    @property
    def total_movement_m(self) -> float:
        return float(np.abs(self.lateral_m).sum() + np.abs(self.vertical_m).sum())

    def apply(self, geometry: SleeperGeometry) -> SleeperGeometry:
        """The geometry as if the adjustment were made: deviations moved, gauge and cant follow
        (a left rail moved right narrows the gauge; a left rail raised adds cant)."""
        return SleeperGeometry(
            station_m=geometry.station_m,
            lateral_deviation_m=geometry.lateral_deviation_m + self.lateral_m,
            vertical_deviation_m=geometry.vertical_deviation_m + self.vertical_m,
            gauge_m=geometry.gauge_m + self.lateral_m[:, 1] - self.lateral_m[:, 0],
            cant_m=geometry.cant_m + self.vertical_m[:, 0] - self.vertical_m[:, 1],
            design_cant_m=geometry.design_cant_m,
            sleeper_number=geometry.sleeper_number,
            curvature_1pm=geometry.curvature_1pm,
            line_speed_mps=geometry.line_speed_mps,
        )


def _round_to_step(values: np.ndarray, step: float, low: float, high: float) -> np.ndarray:
    return np.clip(np.round(values / step) * step, np.ceil(low / step - 1e-9) * step, np.floor(high / step + 1e-9) * step)


def correct_to_line(geometry: SleeperGeometry, fastener: FastenerType) -> Adjustment:
    """Move every rail back to the line: a = -d in whole steps, clipped to the range; flagged
    where the clipped amount leaves more than half a step. Invalid sleepers are not moved."""
    amounts, unresolved = {}, {}
    for direction, deviation in (("lateral", geometry.lateral_deviation_m), ("vertical", geometry.vertical_deviation_m)):
        low, high = fastener.range_m(direction)
        wanted = np.where(np.isfinite(deviation), -deviation, 0.0)
        amounts[direction] = _round_to_step(wanted, fastener.step_m, low, high)
        unresolved[direction] = np.abs(wanted - amounts[direction]) > 0.5 * fastener.step_m + 1e-12
    return Adjustment(amounts["lateral"], amounts["vertical"], unresolved["lateral"], unresolved["vertical"], fastener.name)


@dataclass(frozen=True)
class ChordLimit:
    """A differential-versine check in sleeper steps: chord m, pair p, |value| <= limit_m."""

    chord_steps: int
    pair_steps: int
    limit_m: float


def chord_limits(profile: ToleranceProfile, direction: str, spacing_m: float = SLEEPER_SPACING_M) -> list[ChordLimit]:
    """The profile's differential-versine checks that apply to ``direction``, in sleeper steps."""
    limits = []
    for check in profile.checks:
        if check.kind == "differential_versine" and direction in check.directions:
            limits.append(
                ChordLimit(round(check.chord_m / spacing_m), round(check.pair_m / spacing_m), min(-check.lower, check.upper))
            )
    return limits


def _window_rows(n_chords: int, block: int):
    """Prefix/suffix running-extreme structure over blocks of ``block`` chord starts.

    Returns (previous index for the prefix chain, next index for the suffix chain), -1 at
    block boundaries. A window of ``block`` consecutive starts is the suffix of one block
    plus the prefix of the next, so its maximum is bounded by two running variables.
    """
    index = np.arange(n_chords)
    previous = np.where(index % block == 0, -1, index - 1)
    following = np.where((index % block == block - 1) | (index == n_chords - 1), -1, index + 1)
    return previous, following


def _chord_terms(start: np.ndarray, m: int, r: float, n: int, sign: float) -> list:
    """sign * (S(a) - S0) = sign * r (a[j+m] - a[j]) as (column, coefficient) pairs, a = a+ - a-
    with a+ in columns 0..n-1 and a- in n..2n-1."""
    return [(start + m, sign * r), (start + m + n, -sign * r), (start, -sign * r), (start + n, sign * r)]


def _channel_programme(
    deviation: np.ndarray, limits: list[ChordLimit], low: float, high: float, step: float, fixed_steps: np.ndarray
):
    """min sum |a| s.t. every sliding check of deviation + a within its limit (up to a penalised
    slack), low <= a <= high, a = ``fixed_steps`` where that is finite. Linear programme.

    Variables (in steps): a+ (n), a- (n), and per check the running maxima/minima of the chord
    term S over prefixes (P) and suffixes (Q) of blocks: Pmax, Qmax, Pmin, Qmin (n - m each).
    """
    n = deviation.size
    valid = np.isfinite(deviation)
    d = np.where(valid, deviation, 0.0) / step  # work in steps: integer amounts
    rows, cols, vals, upper = [], [], [], []
    row = 0

    def add(entries, bound):
        nonlocal row
        for column, coefficient in entries:
            rows.append(np.broadcast_to(row + np.arange(bound.size), bound.shape))
            cols.append(column)
            vals.append(np.broadcast_to(coefficient, bound.shape))
        upper.append(bound)
        row += bound.size

    variables = 2 * n
    slack_columns = []
    for limit in limits:
        m, p = limit.chord_steps, limit.pair_steps
        # Rounding each amount to a whole step moves a check value D + S by at most
        # (1 + p/m) steps, so the programme keeps that margin and the rounded amounts still pass.
        bound = limit.limit_m / step - (1.0 + p / m)
        if bound <= 0:
            raise ValueError(
                f"a {limit.limit_m * 1e3:g} mm limit on a {m}/{p}-sleeper check leaves no room for "
                f"{step * 1e3:g} mm fastener steps"
            )
        n_chords = n - m
        if n_chords <= 0:
            continue
        r = p / m
        pmax, qmax, pmin, qmin = (variables + k * n_chords + np.arange(n_chords) for k in range(4))
        variables += 4 * n_chords
        ok = np.flatnonzero(valid[:n_chords] & valid[m:])
        s0 = r * (d[ok + m] - d[ok])
        for running in (pmax, qmax):  # S_j <= running maximum
            add(_chord_terms(ok, m, r, n, 1.0) + [(running[ok], -1.0)], -s0)
        for running in (pmin, qmin):  # S_j >= running minimum
            add(_chord_terms(ok, m, r, n, -1.0) + [(running[ok], 1.0)], s0)
        previous, following = _window_rows(n_chords, m - p + 1)
        chained = np.flatnonzero(previous >= 0)
        add([(pmax[previous[chained]], 1.0), (pmax[chained], -1.0)], np.zeros(chained.size))
        add([(pmin[chained], 1.0), (pmin[previous[chained]], -1.0)], np.zeros(chained.size))
        chained = np.flatnonzero(following >= 0)
        add([(qmax[following[chained]], 1.0), (qmax[chained], -1.0)], np.zeros(chained.size))
        add([(qmin[chained], 1.0), (qmin[following[chained]], -1.0)], np.zeros(chained.size))
        # Every pair (k, k + p) against the chords starting at max(0, k-w) .. min(k, n_chords-1).
        k = np.arange(n - p)
        k = k[valid[k] & valid[k + p]]
        first = np.maximum(k - (m - p), 0)
        last = np.minimum(k, n_chords - 1)
        keep = first <= last
        k, first, last = k[keep], first[keep], last[keep]
        block = m - p + 1
        same = first // block == last // block
        d0 = d[k] - d[k + p]
        slack = variables + np.arange(k.size)  # how far pair k still exceeds: penalised, flagged
        variables += k.size
        slack_columns.append(slack)
        pair = [(k, 1.0), (k + n, -1.0), (k + p, -1.0), (k + p + n, 1.0)]
        for selector, hi_column, lo_column in (
            (~same | (first % block == 0), pmax[last], pmin[last]),
            (~same | (first % block != 0), qmax[first], qmin[first]),
        ):
            # D(a) + max S <= limit + slack  and  -(D(a) + min S) <= limit + slack
            add([(c[selector], v) for c, v in pair] + [(hi_column[selector], 1.0), (slack[selector], -1.0)], bound - d0[selector])
            add([(c[selector], -v) for c, v in pair] + [(lo_column[selector], -1.0), (slack[selector], -1.0)], bound + d0[selector])
    a_low, a_high = np.ceil(low / step - 1e-9), np.floor(high / step + 1e-9)
    lower = np.full(variables, -np.inf)
    upper_bounds = np.full(variables, np.inf)
    lower[: 2 * n] = 0.0
    upper_bounds[:n] = np.where(valid, a_high, 0.0)
    upper_bounds[n : 2 * n] = np.where(valid, -a_low, 0.0)
    fixed = np.flatnonzero(np.isfinite(fixed_steps))
    lower[fixed] = upper_bounds[fixed] = np.maximum(fixed_steps[fixed], 0.0)
    lower[fixed + n] = upper_bounds[fixed + n] = np.maximum(-fixed_steps[fixed], 0.0)
    cost = np.zeros(variables)
    cost[: 2 * n] = 1.0
    for slack in slack_columns:
        lower[slack] = 0.0
        cost[slack] = VIOLATION_PENALTY
    matrix = sparse.csr_array((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(row, variables))
    return cost, matrix, np.concatenate(upper), Bounds(lower, upper_bounds)


def _trouble_windows(deviation: np.ndarray, limits: list[ChordLimit]) -> list[tuple[int, int]]:
    """Sleeper ranges [start, stop) worth moving: around every exceeding pair, the sleepers of
    every chord placement holding it plus half a chord of room, merged where their LP ranges
    (one chord beyond each end) would overlap."""
    n = deviation.size
    starts, stops = [], []
    for limit, pairs in zip(limits, _exceeding_pairs(deviation, limits)):
        m, p = limit.chord_steps, limit.pair_steps
        starts.append(pairs - (m - p) - 2 * m)
        stops.append(pairs + m + 2 * m + 1)
    if not starts:
        return []
    starts, stops = np.clip(np.concatenate(starts), 0, n), np.clip(np.concatenate(stops), 0, n)
    order = np.argsort(starts)
    reach = max(limit.chord_steps for limit in limits)
    windows: list[list[int]] = []
    for start, stop in zip(starts[order], stops[order]):
        if windows and start <= windows[-1][1] + 2 * reach:
            windows[-1][1] = max(windows[-1][1], stop)
        else:
            windows.append([start, stop])
    return [(int(a), int(b)) for a, b in windows]


def _solve_window(deviation, amounts, start, stop, limits, low, high, step) -> np.ndarray:
    """Amounts [steps] of sleepers start..stop-1 by the LP; the sleepers one chord beyond each
    end keep ``amounts``, so every chord placement touching a free sleeper is in the programme."""
    reach = max(limit.chord_steps for limit in limits)
    lo, hi = max(0, start - reach), min(deviation.size, stop + reach)
    fixed = amounts[lo:hi].copy()
    fixed[start - lo : stop - lo] = np.nan
    cost, matrix, upper, bounds = _channel_programme(deviation[lo:hi], limits, low, high, step, fixed)
    result = milp(cost, constraints=LinearConstraint(matrix, -np.inf, upper), bounds=bounds)
    if result.x is None:
        raise RuntimeError(f"adjustment optimisation failed: {result.message}")
    piece = hi - lo
    return np.round(result.x[start - lo : stop - lo] - result.x[piece + start - lo : piece + stop - lo])


def _optimise_channel(deviation, limits, low, high, step, chunk_sleepers, progress=None, cancel=None):
    """(amounts [m], unresolved flags) for one rail and direction.

    Only the sleepers near exceedances are moved (:func:`_trouble_windows`), by a linear
    programme over the window plus one chord of fixed sleepers on either side, holding only the
    checks that are exceeded (the others, typically the long 300 m / 150 m chord, would triple
    the programme's size for constraints that are inactive). A window longer than
    ``chunk_sleepers`` is solved in consecutive chunks, each starting from the amounts of the
    one before (the greedy hand-over costs some optimality; the cost grows linearly with the
    length of line). The continuous solution is rounded to whole steps. The line is then
    checked again against every limit; a check the moves broke joins the programme and the
    windows are solved again, until nothing changes. Sleepers of every pair that still
    exceeds its limit are flagged.
    """
    n = deviation.size
    amounts = np.zeros(n)
    active: list[ChordLimit] = []
    for _ in range(MAX_SWEEPS):
        current = deviation + step * amounts
        exceeded = [limit for limit, pairs in zip(limits, _exceeding_pairs(current, limits)) if pairs.size]
        active += [limit for limit in exceeded if limit not in active]
        windows = _trouble_windows(current, exceeded)
        pieces = [(a, min(a + chunk_sleepers, stop)) for start, stop in windows
                  for a in range(start, stop, chunk_sleepers)]
        changed = False
        for index, (start, stop) in enumerate(pieces):
            check_cancel(cancel)
            if progress is not None:
                progress(index / len(pieces), "adjustment amounts")
            solved = _solve_window(deviation, amounts, start, stop, active, low, high, step)
            changed |= not np.array_equal(solved, amounts[start:stop])
            amounts[start:stop] = solved
        if not changed:
            break
    amounts = amounts * step
    unresolved = np.zeros(n, bool)
    for limit, exceeding in zip(limits, _exceeding_pairs(deviation + amounts, limits)):
        unresolved[exceeding] = True
        unresolved[exceeding + limit.pair_steps] = True
    return amounts, unresolved


def _expected_work(deviation: np.ndarray, limits: list[ChordLimit]) -> int:
    """Rough cost of optimising one channel, for scheduling: the sleepers of its first round's
    windows times the checks they are solved for (each check adds its chord terms)."""
    exceeded = [limit for limit, pairs in zip(limits, _exceeding_pairs(deviation, limits)) if pairs.size]
    return len(exceeded) * sum(stop - start for start, stop in _trouble_windows(deviation, exceeded))


def _exceeding_pairs(deviation: np.ndarray, limits: list[ChordLimit]) -> list[np.ndarray]:
    """First sleepers of the pairs exceeding each limit (any chord placement)."""
    return [
        np.flatnonzero(np.abs(differential_versine_grid(deviation, limit.chord_steps, limit.pair_steps)) > limit.limit_m + 1e-9)
        for limit in limits
    ]


def _passes(deviation: np.ndarray, limits: list[ChordLimit]) -> bool:
    return not any(pairs.size for pairs in _exceeding_pairs(deviation, limits))


def optimise_adjustment(
    geometry: SleeperGeometry, profile: ToleranceProfile, fastener: FastenerType, chunk_sleepers: int = 960,
    progress: ProgressFn | None = None, cancel: CancelToken = None,
) -> Adjustment:
    """Least total movement that satisfies every differential-versine check of ``profile``
    (every chord placement and point pair) within the fastener range, per rail and direction.

    Where no amount within range satisfies a check, the excess is minimised (penalised
    VIOLATION_PENALTY times a unit of movement). Sleepers of pairs that still exceed after
    rounding to whole steps are flagged unresolved. Invalid sleepers are not moved and their
    pairs are not checked. Gauge and cross-level are not constraints here (the rails are
    optimised independently); re-assess the adjusted geometry to see them. The four channels
    (rail x direction) are solved in parallel threads; ``progress`` is called from the calling
    thread, ``cancel`` is checked before every programme is solved (see :mod:`insrail.progress`).
    """
    amounts = {direction: np.zeros((geometry.station_m.size, 2)) for direction in DIRECTIONS}
    flags = {direction: np.zeros((geometry.station_m.size, 2), bool) for direction in DIRECTIONS}
    deviations = {"lateral": geometry.lateral_deviation_m, "vertical": geometry.vertical_deviation_m}
    channels = [(direction, column) for direction in DIRECTIONS for column in range(len(RAILS))]
    done = np.zeros(len(channels))  # per channel, written by its thread, reported by this one

    def solve(index: int):
        def channel_progress(fraction: float, message: str) -> None:
            done[index] = max(done[index], fraction)  # a second round starts again from 0

        direction, column = channels[index]
        low, high = fastener.range_m(direction)
        return _optimise_channel(deviations[direction][:, column], chord_limits(profile, direction), low, high,
                                 fastener.step_m, chunk_sleepers, channel_progress, cancel)

    # The channels are independent and HiGHS releases the GIL while it solves: one thread each,
    # the heaviest submitted first, so that with fewer cores than channels it does not start last.
    def expected_work(index: int) -> int:
        direction, column = channels[index]
        return _expected_work(deviations[direction][:, column], chord_limits(profile, direction))

    order = sorted(range(len(channels)), key=expected_work, reverse=True)
    with ThreadPoolExecutor(min(len(channels), os.cpu_count() or 1)) as pool:
        futures = {index: pool.submit(solve, index) for index in order}
        while not wait(futures.values(), timeout=PROGRESS_INTERVAL_S).done.issuperset(futures.values()):
            if progress is not None:
                progress(float(done.mean()), "adjustment amounts")
        for index, (direction, column) in enumerate(channels):
            amounts[direction][:, column], flags[direction][:, column] = futures[index].result()
    if progress is not None:
        progress(1.0, "adjustment amounts")
    return Adjustment(amounts["lateral"], amounts["vertical"], flags["lateral"], flags["vertical"], fastener.name)
