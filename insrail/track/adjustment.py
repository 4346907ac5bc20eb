"""Fastener adjustment amounts per sleeper and rail for the adjustment crews.

An adjustment ``a`` is the movement of one rail at one sleeper, in the deviation's sign
convention (lateral + right, vertical + up, metres): after the adjustment the deviation is
``d + a``, the gauge changes by ``a_right - a_left`` (lateral) and the cant by
``a_left - a_right`` (vertical). Amounts are whole fastener steps (1 mm for WJ-8) inside the
fastener's range, which is taken relative to the as-built state.

Two ways to compute them:

* :func:`correct_to_line`: each sleeper is moved back to the design (or fitted) line, rounded
  to the step and clipped to the range (what the thesis's InsRail prints).
* :func:`optimise_adjustment`: per direction, both rails together (a linear programme, HiGHS;
  :mod:`insrail.track.adjustment_programme`): the least movement that brings every chord check
  of each rail (10 m versine, 30 m / 5 m and 300 m / 150 m differential versines, every chord
  placement; not where the survey cannot assess a check: ``not_assessed``) inside its limit, never
  pushes gauge, gauge change rate, cross-level or twist out of the profile's limits where they were
  inside (and brings them in where it can), keeps every amount in the fastener's range, in whole
  steps. ``strategy="guiding_rail_first"`` is the
  crews' practice: the guiding rail (outer rail of a curve, left on straights) is lined and the
  low rail (inner rail, left on straights) levelled, the other rail follows through gauge and
  cross-level.

:func:`reassess` applies the amounts, assesses the result against every check of the profile
and flags each sleeper that still fails, with the reason (:data:`REASONS`).

The chord checks work on sleeper indices (a 30 m chord is 48 sleeper spacings, thesis eq.
(2.2)), so the sleepers are assumed evenly spaced there; the re-assessment checks on stations.
"""

from __future__ import annotations

import tomllib
from concurrent.futures import FIRST_COMPLETED, Executor, ThreadPoolExecutor, wait
from collections.abc import Mapping
from contextlib import nullcontext
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from insrail.background import cpu_budget
from insrail.progress import CancelToken, ProgressFn, check_cancel
from insrail.resources import resources_dir
from insrail.track.adjustment_programme import (
    DirectionProblem,
    ROW_BLOCK,
    RailCheck,
    TrackRowSource,
    apply_threshold,
    below_threshold,
    rail_checks,
    repair_rounding,
    round_amounts,
    solve_free,
)
from insrail.track.adjustment_parts import PartTable, read_part_table
from insrail.track.exceedance import RAILS, Assessment, SleeperGeometry, assess
from insrail.track.irregularity import BANDS_M, SLEEPER_SPACING_M
from insrail.track.parameters import guiding_rail_is_right
from insrail.track.tolerance import SettingsFileError, ToleranceProfile, read_number

DIRECTIONS = ("lateral", "vertical")
DEFAULT_FASTENER = "wj8"
#: How the optimisation shares the movement between the rails (project setting ``[adjustment] strategy``).
STRATEGIES = {
    "least_movement": "least total movement of both rails",
    "guiding_rail_first": "move the guiding rail for line and the low rail for level; the other rail follows "
                          "(only the gauge / cross-level change it needs counts)",
}
DEFAULT_STRATEGY = "least_movement"
#: Bumped when the programme's amounts for the same input change (joins the pipeline's cache key).
PROGRAMME_VERSION = 4  # 4: the windows of a round solved colour after colour (adjustment.colours), not left to right
#: Track-level checks the programme holds (:func:`insrail.track.adjustment_programme.track_rows`).
TRACK_KINDS = ("gauge_deviation", "gauge_change_rate", "cross_level", "twist")
#: Why a sleeper still fails a check after the adjustment (bits of Adjustment.reason_*).
RANGE_EXHAUSTED = 1
CONFLICTING_CHECKS = 2
NOT_OPTIMISED = 4
REASONS = {RANGE_EXHAUSTED: "fastener range exhausted", CONFLICTING_CHECKS: "conflicting checks",
           NOT_OPTIMISED: "check not held by the optimisation"}
#: Rounds of "solve the windows, check the whole line again" (a round with no new exceedance ends it).
MAX_SWEEPS = 4
#: Free sleepers around an exceeding value, in reaches of its check.
WINDOW_PAD = 2
#: How often [s] the progress of the channels (solved in parallel threads) is reported.
PROGRESS_INTERVAL_S = 0.2
#: Sleepers beyond its windows that solving a part may read (track rows' bases) or change (the
#: rounding repair): parts of a round lie further apart than the longest chord and twice this.
PART_MARGIN = 64


@dataclass(frozen=True)
class FastenerType:
    """Adjustment range per rail [m] relative to the as-built state, and the step [m]."""

    name: str
    description: str
    step_m: float
    lateral_range_m: tuple[float, float]
    vertical_range_m: tuple[float, float]
    #: direction -> the parts per amount (:mod:`insrail.track.adjustment_parts`); none where the file has none
    parts: dict[str, PartTable] = field(default_factory=dict, repr=False, compare=False)

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
    parts = {direction: read_part_table(path, f"{direction}_parts", data[f"{direction}_parts"],
                                        1e3 * values[f"{direction}_min_mm"], 1e3 * values[f"{direction}_max_mm"])
             for direction in DIRECTIONS if f"{direction}_parts" in data}
    return FastenerType(
        name=str(data.get("name", path.stem)),
        description=str(data.get("description", "")),
        step_m=values["step_mm"],
        lateral_range_m=(values["lateral_min_mm"], values["lateral_max_mm"]),
        vertical_range_m=(values["vertical_min_mm"], values["vertical_max_mm"]),
        parts=parts,
    )


@dataclass(frozen=True)
class Adjustment:
    """Amounts [m] per sleeper (n, 2) [left, right]; ``unresolved_*`` flags the sleeper-rails
    that still fail a check after the adjustment, ``reason_*`` says why (bits of
    :data:`REASONS`: the fastener range is used up there, or the checks conflict)."""

    lateral_m: np.ndarray
    vertical_m: np.ndarray
    unresolved_lateral: np.ndarray  # (n, 2) bool
    unresolved_vertical: np.ndarray  # (n, 2) bool
    fastener: str
    reason_lateral: np.ndarray  # (n, 2) uint8, bits of REASONS
    reason_vertical: np.ndarray

    def reasons(self) -> list[str]:
        """Per sleeper, why a check still fails there ("" where none), e.g. "lateral left: fastener
        range exhausted"."""
        texts = [[] for _ in range(self.lateral_m.shape[0])]
        for direction, codes in (("lateral", self.reason_lateral), ("vertical", self.reason_vertical)):
            for column, rail in enumerate(RAILS):
                for index in np.flatnonzero(codes[:, column]):
                    why = " + ".join(text for bit, text in REASONS.items() if codes[index, column] & bit)
                    texts[index].append(f"{direction} {rail}: {why}")
        return ["; ".join(t) for t in texts]

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
    return Adjustment(amounts["lateral"], amounts["vertical"], unresolved["lateral"], unresolved["vertical"], fastener.name,
                      unresolved["lateral"].astype(np.uint8) * RANGE_EXHAUSTED,
                      unresolved["vertical"].astype(np.uint8) * RANGE_EXHAUSTED)


def reference_rail_is_right(design_cant_m: np.ndarray, direction: str) -> np.ndarray:
    """The rail that leads the adjustment per sleeper, True where it is the right rail: for line
    the guiding rail (the outer, higher rail of a curve; left on straights), for level the low
    rail (the inner rail of a curve; left on straights). [U] the crews' handbook rule, as for
    :func:`insrail.track.parameters.guiding_rail_is_right`."""
    if direction == "lateral":
        return guiding_rail_is_right(design_cant_m)
    return np.asarray(design_cant_m, dtype=float) > 0.0  # left rail higher: the right one is low


def _trouble_windows(n: int, trouble: np.ndarray, pad: np.ndarray, merge: int) -> list[tuple[int, int]]:
    """Sleeper ranges [start, stop) worth moving: around each sleeper of ``trouble`` (an exceeding
    value) ``pad`` sleepers on either side (the reach of its check: every amount that changes the
    value), merged where they come closer than ``merge``."""
    if not trouble.size:
        return []
    starts, stops = np.clip(trouble - WINDOW_PAD * pad, 0, n), np.clip(trouble + WINDOW_PAD * pad + 1, 0, n)
    order = np.argsort(starts)
    windows: list[list[int]] = []
    for start, stop in zip(starts[order], stops[order]):
        if windows and start <= windows[-1][1] + merge:
            windows[-1][1] = max(windows[-1][1], stop)
        else:
            windows.append([int(start), int(stop)])
    return [(a, b) for a, b in windows]


@dataclass(frozen=True)
class _State:
    """Where the current amounts leave one direction: the sleepers of exceeding chord-check values
    and of exceeding track rows."""

    trouble: np.ndarray  # sleepers of exceeding values (any check)
    pad: np.ndarray  # reach of the check of each trouble sleeper


def _state(problem: DirectionProblem, amounts: np.ndarray, checks: list[RailCheck]) -> _State:
    """Checked block by block (:data:`ROW_BLOCK` sleepers): nothing of the whole line's size but
    the amounts and deviations."""
    n = amounts.shape[0]
    blocks = [(start, min(n, start + ROW_BLOCK)) for start in range(0, n, ROW_BLOCK)]
    current = problem.step_m * (problem.deviation + amounts)
    trouble, pad = [], []
    for check in checks:
        for rail in (0, 1):
            sleepers = np.concatenate([np.zeros(0, int), *(check.exceeding(current[:, rail], *block) for block in blocks)])
            trouble.append(sleepers)
            pad.append(np.full(sleepers.size, check.reach_steps))
    ends = [np.zeros(0, int)]
    for block in blocks:
        rows = problem.rows.owned(*block)
        bad = np.flatnonzero(rows.exceeding(amounts))
        ends += [rows.first[bad], rows.last[bad]]
    sleepers = np.unique(np.concatenate(ends))
    trouble.append(sleepers)
    pad.append(np.full(sleepers.size, 8))
    return _State(np.concatenate([np.zeros(0, int), *trouble]), np.concatenate([np.zeros(0, int), *pad]))


def _sweep_progress(progress, sweep: int):
    """The first round takes most of the work (0..0.9), the rounds after it share the rest."""
    if progress is None:
        return None
    if sweep == 0:
        return lambda fraction, message: progress(0.9 * fraction, message)
    return lambda fraction, message: progress(0.9 + 0.1 * (sweep - 1 + fraction) / (MAX_SWEEPS - 1), message)


def _share(progress, done: int, size: int, total: int):
    """Progress of one window of ``size`` sleepers after ``done`` of ``total``."""
    if progress is None:
        return None
    return lambda fraction, message: progress((done + fraction * size) / total, message)


@dataclass(frozen=True)
class Part:
    """Windows [start, stop) of one round, in order, solved one after the other; ``zone``: the sleepers
    that solving them may read or change (the windows widened by :data:`PART_MARGIN`)."""

    windows: tuple[tuple[int, int], ...]
    zone: tuple[int, int]

    @property
    def size(self) -> int:
        return sum(stop - start for start, stop in self.windows)


def _part_gap(checks: list[RailCheck]) -> int:
    """Sleepers between windows that do not see each other: the longest chord and twice :data:`PART_MARGIN`."""
    return max((check.reach_steps for check in checks), default=0) + 2 * PART_MARGIN


def independent_parts(problem: DirectionProblem, checks: list[RailCheck], windows: list[tuple[int, int]]) -> list[Part]:
    """The round's windows (in order) grouped into parts that do not see each other: windows closer
    than the longest chord plus twice :data:`PART_MARGIN` are one part. A window's programme reads
    the amounts within a chord of its sleepers (and its track rows' bases), and its rounding repair
    changes a few sleepers beyond it: parts further apart neither read nor change each other's
    sleepers, so solving them side by side gives the amounts of solving every window in order."""
    n = problem.deviation.shape[0]
    gap = _part_gap(checks)
    groups: list[list[tuple[int, int]]] = []
    for window in windows:
        if groups and window[0] - groups[-1][-1][1] < gap:
            groups[-1].append(window)
        else:
            groups.append([window])
    return [Part(tuple(group), (max(0, group[0][0] - PART_MARGIN), min(n, group[-1][1] + PART_MARGIN)))
            for group in groups]


def solve_part(problem: DirectionProblem, amounts: np.ndarray, checks: list[RailCheck], part: Part, progress=None,
               cancel=None) -> np.ndarray:
    """Amounts [steps] (n, 2) with the part's windows solved one after the other, each by a linear
    programme (:func:`insrail.track.adjustment_programme.solve_free`) rounded to whole steps and
    repaired where the rounding broke a hard track row; the other sleepers keep ``amounts``."""
    n = amounts.shape[0]
    done = 0
    for start, stop in part.windows:
        free = np.zeros(n, bool)
        free[start:stop] = problem.valid[start:stop]
        continuous = solve_free(problem, amounts, free, checks, _share(progress, done, stop - start, part.size), cancel)
        amounts = np.where(free[:, None], round_amounts(continuous, problem.low, problem.high, problem.valid), amounts)
        amounts = repair_rounding(problem, amounts, continuous, (start, stop))
        done += stop - start
    return amounts


def solve_part_in_zone(problem: DirectionProblem, amounts: np.ndarray, checks: list[RailCheck], part: Part,
                       progress=None, cancel=None) -> tuple[np.ndarray, bool]:
    """A task of a round (run where the executor runs it, a Dask worker or a thread): the amounts of
    the part's zone after :func:`solve_part`, and whether it changed a sleeper outside its zone (it
    then did not stay independent: the caller solves the round in order)."""
    solved = solve_part(problem, amounts, checks, part, progress, cancel)
    start, stop = part.zone
    outside = bool(np.any(solved[:start] != amounts[:start]) or np.any(solved[stop:] != amounts[stop:]))
    return solved[start:stop], outside


def _reads_within_zone(problem: DirectionProblem, part: Part) -> bool:
    """Whether the track rows touching the part's windows read only sleepers of its zone (bases across
    a long stretch of invalid sleepers may reach further)."""
    first, last = problem.rows.first, problem.rows.last
    start, stop = part.windows[0][0], part.windows[-1][1]
    owners = np.flatnonzero((first < stop) & (last >= start))
    return not owners.size or (first[owners].min() >= part.zone[0] and last[owners].max() < part.zone[1])


def _solve_parts(problem: DirectionProblem, amounts: np.ndarray, checks: list[RailCheck], parts: list[Part],
                 executor: Executor | None, progress, cancel, tasks_see_cancel: bool) -> np.ndarray:
    """The round's amounts: the parts solved side by side as tasks of ``executor`` (the largest first;
    ``tasks_see_cancel``: the tasks run in this process and may be given the cancel token and the
    progress), each task's zone taken into the amounts; in order, here, without an executor or when
    the parts are not independent after all (:func:`solve_part_in_zone`): the same amounts."""
    total = sum(part.size for part in parts)
    if executor is None or not all(_reads_within_zone(problem, part) for part in parts):
        done = 0
        for part in parts:
            amounts = solve_part(problem, amounts, checks, part, _share(progress, done, part.size, total), cancel)
            done += part.size
        return amounts
    futures = {}
    for part in sorted(parts, key=lambda p: p.size, reverse=True):
        hooks = (_share(progress, 0, part.size, total), cancel) if tasks_see_cancel else ()
        futures[executor.submit(solve_part_in_zone, problem, amounts, checks, part, *hooks)] = part
    try:
        waiting = set(futures)
        while waiting:
            check_cancel(cancel)
            finished, waiting = wait(waiting, timeout=PROGRESS_INTERVAL_S, return_when=FIRST_COMPLETED)
            if progress is not None and finished:
                progress(sum(futures[f].size for f in futures if f.done()) / total, "adjustment amounts")
    except BaseException:
        for future in futures:
            future.cancel()
        raise
    result = amounts.copy()
    for future, part in futures.items():
        zone, outside = future.result()
        if outside:
            return _solve_parts(problem, amounts, checks, parts, None, progress, cancel, tasks_see_cancel)
        result[part.zone[0]:part.zone[1]] = zone  # the zones lie apart (a chord at least)
    return result


def colours(windows: list[tuple[int, int]], checks: list[RailCheck]) -> list[list[tuple[int, int]]]:
    """The round's windows in colours, solved colour after colour (the amounts of the colours before
    held): each window takes the first colour whose last window lies a part's gap before it
    (:func:`independent_parts`), so that the windows of one colour are independent parts, solved
    side by side. The colours follow from the windows alone: the amounts do not depend on how many
    workers solve them."""
    gap = _part_gap(checks)
    classes: list[list[tuple[int, int]]] = []
    for window in windows:
        for members in classes:
            if window[0] - members[-1][1] >= gap:
                members.append(window)
                break
        else:
            classes.append([window])
    return classes


def _colour_progress(progress, colour: int, count: int):
    if progress is None:
        return None
    return lambda fraction, message: progress((colour + fraction) / count, message)


def _optimise_direction(problem: DirectionProblem, checks: list[RailCheck], progress=None, cancel=None,
                        threshold: float = 1.0, executor: Executor | None = None,
                        tasks_see_cancel: bool = True, unadjusted: _State | None = None) -> np.ndarray:
    """Amounts [steps] (n, 2) of one direction.

    Only the sleepers near exceedances are moved (two reaches of the check around each
    exceeding value), window after window, each by a linear programme
    (:func:`insrail.track.adjustment_programme.solve_free`: every chord check of both rails and
    every track row held, the rows entering as they are found violated; the windows solved
    before are held where their rows reach into the next one). The windows go colour after
    colour (:func:`colours`: the windows of a colour lie a chord apart, so they do not see each
    other): the independent parts of a colour (:func:`independent_parts`) are solved side by side
    on ``executor`` (one after the other without one), the same amounts either way. Each
    solution is rounded to whole steps and the rounding repaired where it broke a hard track row.
    The line is then checked again: windows around exceedances that the previous round did not
    already try are solved again, until there are none. Last, amounts below the action ``threshold``
    [steps] are taken out where the checks allow (:func:`insrail.track.adjustment_programme.apply_threshold`).
    ``unadjusted``: the line's state without amounts, when the caller has it (the first round's).
    """
    n = problem.deviation.shape[0]
    amounts = np.zeros((n, 2))
    tried = np.zeros(n, bool)  # exceeding sleepers a round already worked on
    for sweep in range(MAX_SWEEPS):
        state = unadjusted if sweep == 0 and unadjusted is not None else _state(problem, amounts, checks)
        fresh = ~tried[state.trouble]
        windows = _trouble_windows(n, state.trouble[fresh], state.pad[fresh], merge=16)
        if not windows:
            break
        tried[state.trouble] = True
        sweep_progress = _sweep_progress(progress, sweep)
        classes = colours(windows, checks)
        for colour, members in enumerate(classes):
            amounts = _solve_parts(problem, amounts, checks, independent_parts(problem, checks, members), executor,
                                   _colour_progress(sweep_progress, colour, len(classes)), cancel, tasks_see_cancel)
    # the threshold's integer programmes report in the last tenth (monotonic with the rounds after the first)
    threshold_progress = (None if progress is None
                          else lambda fraction, message: progress(0.9 + 0.1 * fraction, message))
    return apply_threshold(problem, amounts, checks, threshold, cancel, threshold_progress)


def direction_problem(geometry: SleeperGeometry, profile: ToleranceProfile, fastener: FastenerType, direction: str,
                      strategy: str = DEFAULT_STRATEGY) -> DirectionProblem:
    deviation = geometry.lateral_deviation_m if direction == "lateral" else geometry.vertical_deviation_m
    valid = np.all(np.isfinite(deviation), axis=1)
    if direction == "lateral":
        valid &= np.isfinite(geometry.gauge_m)
    else:
        valid &= np.isfinite(geometry.cant_m)
    low, high = fastener.range_m(direction)
    step = fastener.step_m
    if strategy not in STRATEGIES:
        raise ValueError(f"adjustment strategy {strategy!r}: expected one of {', '.join(STRATEGIES)}")
    reference = reference_rail_is_right(geometry.design_cant_m, direction) if strategy == "guiding_rail_first" else None
    return DirectionProblem(np.where(valid[:, None], deviation, np.nan) / step, valid,
                            TrackRowSource.of(geometry, profile, direction, step),
                            float(np.ceil(low / step - 1e-9)), float(np.floor(high / step + 1e-9)), step, reference)


def threshold_steps(fastener: FastenerType, threshold_m: float | None) -> float:
    """The action threshold in whole fastener steps (at least one: None is one step)."""
    if threshold_m is None:
        return 1.0
    return max(1.0, float(np.ceil(threshold_m / fastener.step_m - 1e-9)))


def optimise_amounts(
    geometry: SleeperGeometry, profile: ToleranceProfile, fastener: FastenerType, strategy: str = DEFAULT_STRATEGY,
    progress: ProgressFn | None = None, cancel: CancelToken = None, threshold_m: float | None = None,
    executor: Executor | None = None, not_assessed: Mapping[tuple[str, str], np.ndarray] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """(lateral, vertical) amounts [m] (n, 2) of :func:`optimise_adjustment`, not yet re-assessed.
    Each amount is 0 or at least the action threshold ``threshold_m`` (rounded up to whole steps;
    None: one step) where the checks allow it (:func:`below_threshold_count` counts the others).
    ``not_assessed`` (as :func:`insrail.track.exceedance.assess` takes it): the chord checks are not
    held where the survey cannot assess them (:func:`insrail.track.adjustment_programme.rail_checks`).

    The two directions are independent: one thread each, the heavier submitted first. The
    independent parts of each round (:func:`independent_parts`) are solved as tasks of
    ``executor`` (e.g. a Dask client's ``get_executor()``: the parts run on the cluster's workers),
    by default by threads here (HiGHS releases the GIL while it solves); the amounts are the same
    either way. ``progress`` is called from the calling thread, ``cancel`` is checked before every
    programme is solved here and while the executor's tasks run (see :mod:`insrail.progress`)."""
    problems = {d: direction_problem(geometry, profile, fastener, d, strategy) for d in DIRECTIONS}
    checks = {d: rail_checks(profile, d, not_assessed=not_assessed) for d in DIRECTIONS}
    done = {d: 0.0 for d in DIRECTIONS}

    def solve(direction: str) -> np.ndarray:
        def direction_progress(fraction: float, message: str) -> None:
            done[direction] = max(done[direction], fraction)  # a second round starts again from 0

        return _optimise_direction(problems[direction], checks[direction], direction_progress, cancel,
                                   threshold_steps(fastener, threshold_m), parts_executor, local, unadjusted[direction])

    # the first round's state, its sleepers' reach: the work expected of a direction (the heavier starts first)
    unadjusted = {d: _state(problems[d], np.zeros(problems[d].deviation.shape), checks[d]) for d in DIRECTIONS}
    order = sorted(DIRECTIONS, key=lambda d: int(unadjusted[d].pad.sum()), reverse=True)
    local = executor is None
    with ThreadPoolExecutor(min(len(order), cpu_budget())) as pool, \
            ThreadPoolExecutor(cpu_budget()) if local else nullcontext(executor) as parts_executor:
        futures = {direction: pool.submit(solve, direction) for direction in order}
        while not wait(futures.values(), timeout=PROGRESS_INTERVAL_S).done.issuperset(futures.values()):
            if progress is not None:
                progress(float(np.mean(list(done.values()))), "adjustment amounts")
        steps = {direction: futures[direction].result() for direction in DIRECTIONS}
    if progress is not None:
        progress(1.0, "adjustment amounts")
    return steps["lateral"] * fastener.step_m, steps["vertical"] * fastener.step_m


def below_threshold_count(adjustment: Adjustment, fastener: FastenerType, threshold_m: float | None) -> int:
    """Sleepers with an amount below the action threshold that the checks needed (kept)."""
    threshold = threshold_steps(fastener, threshold_m)
    small = [below_threshold(a / fastener.step_m, threshold).any(axis=1)
             for a in (adjustment.lateral_m, adjustment.vertical_m)]
    return int(np.count_nonzero(small[0] | small[1]))


def optimise_adjustment(
    geometry: SleeperGeometry, profile: ToleranceProfile, fastener: FastenerType, progress: ProgressFn | None = None,
    cancel: CancelToken = None, strategy: str = DEFAULT_STRATEGY, threshold_m: float | None = None,
) -> Adjustment:
    """The optimised amounts (:func:`optimise_amounts`) with the sleepers that still fail a check
    flagged by :func:`reassess`."""
    lateral, vertical = optimise_amounts(geometry, profile, fastener, strategy, progress, cancel, threshold_m)
    return reassess(geometry, lateral, vertical, profile, fastener)[1]


def _reach_steps(check, spacing_m: float = SLEEPER_SPACING_M) -> int:
    """How far [sleepers] from a failing value an amount changes it."""
    if check.kind in ("versine", "differential_versine"):
        return int(np.ceil(check.chord_m / spacing_m))
    if check.kind in ("twist", "gauge_change_rate"):
        return int(np.ceil((check.base_m or spacing_m) / spacing_m)) + 1
    if check.kind == "band_peak":
        return int(np.ceil(BANDS_M[check.band][1] / spacing_m / 2)) if isinstance(check.band, str) else 0
    return 0


def reassess(geometry: SleeperGeometry, lateral_m: np.ndarray, vertical_m: np.ndarray, profile: ToleranceProfile,
             fastener: FastenerType, not_assessed: Mapping[tuple[str, str], np.ndarray] | None = None,
             ) -> tuple[Assessment, Adjustment]:
    """The assessment of the adjusted geometry (every check of ``profile``, none where ``not_assessed``
    says the survey cannot assess it: :func:`insrail.track.exceedance.assess`) and the adjustment
    with every sleeper-rail of a remaining exceedance run flagged. The reason is "fastener range
    exhausted" where an amount within the check's reach sits at the end of the range, "check not
    held by the optimisation" for a check the programme does not model (band-passed peaks, chords
    of a fraction of a sleeper), otherwise "conflicting checks" (holding this check would break
    another one, or the rounding to whole steps)."""
    n = geometry.station_m.size
    unresolved = {d: np.zeros((n, 2), bool) for d in DIRECTIONS}
    reasons = {d: np.zeros((n, 2), np.uint8) for d in DIRECTIONS}
    amounts = {"lateral": lateral_m, "vertical": vertical_m}
    at_end = {}
    for direction in DIRECTIONS:
        low, high = fastener.range_m(direction)
        step = fastener.step_m
        low, high = np.ceil(low / step - 1e-9) * step, np.floor(high / step + 1e-9) * step
        at_end[direction] = (amounts[direction] <= low + 1e-9) | (amounts[direction] >= high - 1e-9)
    provisional = Adjustment(lateral_m, vertical_m, unresolved["lateral"], unresolved["vertical"], fastener.name,
                             reasons["lateral"], reasons["vertical"])
    after = assess(provisional.apply(geometry), profile, not_assessed=not_assessed)
    checks = {c.name: c for c in profile.checks}
    held = {d: rail_checks(profile, d) for d in DIRECTIONS}
    for e in after.exceedances:
        check = checks[e.check]
        if check.kind in ("gauge_deviation", "gauge_change_rate"):
            targets = [("lateral", 0), ("lateral", 1)]
        elif e.rail in RAILS and e.direction in DIRECTIONS:
            targets = [(e.direction, RAILS.index(e.rail))]
        else:  # cross-level, twist, cant change rate and deficiency: the level of both rails
            targets = [("vertical", 0), ("vertical", 1)]
        reach = _reach_steps(check)
        near = slice(max(0, e.first_index - reach), e.last_index + reach + 1)
        if check.kind in ("versine", "differential_versine"):
            modelled = any(h.limit_m == min(-check.lower, check.upper) and h.reach_steps == reach
                           for h in held[targets[0][0]])
        else:
            modelled = check.kind in TRACK_KINDS
        for direction, column in targets:
            run = slice(e.first_index, e.last_index + 1)
            unresolved[direction][run, column] = True
            if not modelled:
                code = NOT_OPTIMISED
            elif at_end[direction][near, column].any() or (len(targets) == 2 and at_end[direction][near].any()):
                code = RANGE_EXHAUSTED
            else:
                code = CONFLICTING_CHECKS
            reasons[direction][run, column] |= code
    adjustment = Adjustment(lateral_m, vertical_m, unresolved["lateral"], unresolved["vertical"], fastener.name,
                            reasons["lateral"], reasons["vertical"])
    return after, adjustment


def programme_settings(profile: ToleranceProfile) -> dict:
    """What the optimised amounts depend on in a profile (for a cache key): the checks the
    programme holds, with their limits."""
    kinds = ("differential_versine", "versine", *TRACK_KINDS)
    return {"version": PROGRAMME_VERSION, "nominal_gauge_m": profile.nominal_gauge_m,
            "checks": [repr(c) for c in profile.checks if c.kind in kinds]}
