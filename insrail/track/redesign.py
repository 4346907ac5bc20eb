"""Constrained re-design of a ballasted track for a tamping machine: the lift of each rail and the
slew of the track per sleeper, the least total movement after which the track passes the tolerance
profile's chord checks, within what the machine and the line allow.

Conventions (those of :mod:`insrail.track`): lift + up, per rail [left, right]; slew + to the right
looking towards increasing station, the same for both rails (a tamping machine moves the track
panel: the gauge does not change); cant + when the left rail is higher, so a lift of the left rail
adds cant. Metres inside.

The formulation (``docs/tamping.md`` says why it is the right one): the design is the measured
track plus the corrections, ``design = measured + correction``, one correction per sleeper (the
lift of each rail, the slew). Every chord check of the profile -- the 10 m versine, the 30 m / 5 m
and 300 m / 150 m differential versines at every chord placement (thesis eq. 2.2) -- is linear in
the rail positions, so in the corrections: ``|check(deviation + correction)| <= limit - margin``.
Cross-level and twist (vertical) are linear in the lifts' difference. With the bounds -- lift >= 0
(``lift_only``; at least ``min_lift`` where the machine needs one), lift <= ``max_lift``,
|slew| <= ``max_slew``, no movement (within a tolerance) inside fixed stretches -- the least total
movement (the L1 norm of the corrections) is a linear programme, solved with HiGHS (dual simplex,
restarting from its last basis as rows are added, as the fastener programme of
:mod:`insrail.track.adjustment_programme`; sparse rows). The corrections are linear between knots
every :data:`KNOT_SPACING` sleepers (a machine's lift and slew are smooth). Every check row has a slack variable costing
:data:`EXCESS_PENALTY` per unit against 1 per unit of movement: where the bounds leave no way to
pass (a dip beside a bridge deeper than the chord allows), the programme still has a solution,
the excess stays where it cannot go, and the stretch is listed (:attr:`Redesign.cannot_pass`).

What the survey can tell of the track after the job: its moved values carry the survey's error, so
a check held at its limit may fail on the true track. The caller states per check the survey's
``uncertainty`` of its values (``insrail.project.redesign``: three of quality.csv's 1-sigma, the
one assessable rule of ``insrail.project.assessable``) and where a check is ``not_assessed`` at all.
Each check is held that far inside its limit (at least ``margin_m``); a value after the job within
it of the limit is "passes by less than its uncertainty" (:attr:`Redesign.uncertain`), and a check
not assessed is neither passed nor failed (left out of :attr:`Redesign.after`, as the processing's
assessment leaves it out).

The rows of every chord placement number hundreds per sleeper; they enter as the current solution
violates them (constraint generation, the rows of
:class:`insrail.track.adjustment_programme` -- the same rows the fastener optimisation holds), a
few per sleeper in the end.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from insrail.progress import CancelToken, ProgressFn, StepProgress, check_cancel
from insrail.track import adjustment_programme
from insrail.track.adjustment_programme import _ChordRows as ChordRows
from insrail.track.adjustment_programme import _TrackRowFamily as TrackRowFamily
from insrail.track.adjustment_programme import RailCheck, rail_checks, track_rows
from insrail.track.exceedance import Assessment, SleeperGeometry, assess
from insrail.track.tolerance import ToleranceProfile

if TYPE_CHECKING:
    from scipy import sparse

# scipy.sparse and HiGHS are imported where a programme is built: start-up of commands that only read a
# project (insrail.track.adjustment_programme).

#: Unit of the programme's variables [m]: 0.1 mm, fine enough for a machine's millimetre values
#: and leaving the chord rows' limits many units wide.
UNIT_M = 1.0e-4
#: Cost of one unit of a check's excess against one unit of movement: an excess stays only where no
#: movement within the bounds removes it.
EXCESS_PENALTY = 1000.0
MAX_ROUNDS = 100
#: A solve of the programme taking longer than this [s] is stopped and said so (RedesignError).
SOLVE_TIME_LIMIT_S = 300.0
#: The re-design's HiGHS options over the fastener programme's: steepest-edge pricing (its
#: programme, with the long chords' rows, is ten times the fastener programme's size).
REDESIGN_OPTIONS = {"simplex_dual_edge_weight_strategy": 2}
#: The corrections are linear between knots every this many sleepers (2.5 m at 0.625 m): a tamping
#: machine's lift and slew are smooth along the track, and a quarter of the variables keeps the
#: 300 m chord's rows, which couple sleepers 480 apart, solvable in seconds.
KNOT_SPACING = 4
#: Bounds of the sliding extremes of :class:`_SlidingChord` [units]: 10 m, never reached; bounded,
#: they sit at a bound when out of the basis, which the dual simplex handles far better than free ones.
EXTREME_BOUND = 1.0e5
#: A differential versine with at least this many chord starts per pair (the 300 m / 150 m
#: check's 241) is written whole in the sparse form of :class:`_SlidingChord`; a shorter one (the
#: 30 m / 5 m check's 41) enters row by row as the solution violates it.
SLIDING_STARTS = 100
#: ... in groups of this many chord starts and pairs (one knot spacing).
SLIDING_GROUP = KNOT_SPACING


class RedesignError(ValueError):
    """The re-design cannot be computed as asked (the message says why and what to change)."""


@dataclass(frozen=True)
class FixedStretch:
    """A stretch of station where the track must not move (a bridge, a level crossing, a turnout, a
    platform edge), except within ``tolerance_m``; ``source`` names where it came from."""

    from_m: float
    to_m: float
    tolerance_m: float = 0.0
    source: str = ""


@dataclass(frozen=True)
class RedesignSettings:
    """What the machine and the line allow (``[redesign]`` of project.toml, resolved with the
    event stretches by :mod:`insrail.project.redesign`)."""

    lift_only: bool = True
    min_lift_m: float = 0.0
    max_lift_m: float = 0.050
    max_slew_m: float = 0.030
    #: each chord check is held this far inside its limit: the survey's own error (a few tenths of a
    #: mm over a chord) must not take the track moved by the amounts back out
    margin_m: float = 0.0005
    fixed: tuple[FixedStretch, ...] = ()

    def fixed_mask(self, station_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(fixed, tolerance [m]) per sleeper: inside a fixed stretch, and the smallest tolerance there."""
        fixed = np.zeros(station_m.size, bool)
        tolerance = np.full(station_m.size, np.inf)
        for stretch in self.fixed:
            inside = (station_m >= stretch.from_m) & (station_m <= stretch.to_m)
            fixed |= inside
            tolerance[inside] = np.minimum(tolerance[inside], stretch.tolerance_m)
        return fixed, np.where(fixed, tolerance, 0.0)


@dataclass(frozen=True)
class Stretch:
    """A run of sleepers [first, last] (indices) with what holds there."""

    first: int
    last: int
    station_from_m: float
    station_to_m: float
    what: str
    value_m: float = float("nan")  # the largest value there (an excess, a movement)


@dataclass(frozen=True)
class Redesign:
    """The corrections per sleeper and what bound them.

    ``lift_m`` (n, 2) [left, right] + up, ``slew_m`` (n,) + right: NaN at a sleeper without a
    measurement. ``before``/``after``: the profile's assessment of the measured track and of the
    measured track moved by the corrections, without the checks the survey cannot assess there;
    ``cannot_pass``: the stretches where a check still fails after the job (the bounds do not let
    it pass); ``uncertain``: where one passes by less than its uncertainty; ``margin_m``: per check
    name and direction, how far inside its limit the programme held it; ``active``: where a bound holds the
    corrections (lift at its largest or smallest, slew at its largest, a fixed stretch's edge)."""

    station_m: np.ndarray
    lift_m: np.ndarray
    slew_m: np.ndarray
    fixed: np.ndarray
    settings: RedesignSettings
    before: Assessment
    after: Assessment
    cannot_pass: tuple[Stretch, ...]
    #: where a check passes after the job by less than its stated uncertainty (the true track may not)
    uncertain: tuple[Stretch, ...]
    active: tuple[Stretch, ...]
    binding_rows: dict[str, int]  # per check name, the rows the solution holds at their limit
    rounds: int
    margin_m: dict[tuple[str, str], float]

    @property
    def total_movement_m(self) -> float:
        """Sum over the sleepers of |lift left| + |lift right| + |slew|."""
        return float(np.nansum(np.abs(self.lift_m)) + np.nansum(np.abs(self.slew_m)))

    def cant_change_m(self) -> np.ndarray:
        """The change of cant the lifts make (left minus right)."""
        return self.lift_m[:, 0] - self.lift_m[:, 1]


def moved(geometry: SleeperGeometry, lift_m: np.ndarray, slew_m: np.ndarray) -> SleeperGeometry:
    """The track as it will be after the job: every rail moved by the corrections (NaN: not moved),
    the gauge as it was, the cant changed by the lifts' difference."""
    lift = np.nan_to_num(lift_m)
    slew = np.nan_to_num(slew_m)
    return replace(geometry, lateral_deviation_m=geometry.lateral_deviation_m + slew[:, None],
                   vertical_deviation_m=geometry.vertical_deviation_m + lift,
                   cant_m=geometry.cant_m + lift[:, 0] - lift[:, 1])


class _Programme(adjustment_programme._Programme):
    """One direction's linear programme in HiGHS (the fastener programme's solver set-up and row
    writing; dual simplex restarting from its last basis as rows are added): per column (a rail at a
    sleeper, or a sleeper) a correction ``plus - minus`` (both >= 0) costing its movement, per added
    row side a slack costing :data:`EXCESS_PENALTY`."""

    def __init__(self, basis: sparse.csr_array, lower: np.ndarray, upper: np.ndarray):
        import highspy._core as highspy_core

        self.highs = highspy_core._Highs()
        for key, value in {**adjustment_programme.HIGHS_OPTIONS, **REDESIGN_OPTIONS}.items():
            self.highs.setOptionValue(key, value)
        self.infinity = highspy_core.kHighsInf
        self.optimal = highspy_core.HighsModelStatus.kOptimal
        self.out_of_time = highspy_core.HighsModelStatus.kTimeLimit
        self.variables = 0
        self.basis, self.size = basis, basis.shape[1]
        # a positive lower bound (a minimum lift) is carried by plus alone; each knot costs the
        # movement of the sleepers it moves
        weight = np.asarray(basis.sum(axis=0)).ravel()
        self._add_variables(weight, np.maximum(lower, 0.0), np.maximum(upper, 0.0))
        self._add_variables(weight, np.zeros(self.size), np.maximum(-lower, 0.0))
        self.keys: set[tuple[int, int]] = set()

    def add(self, family: int, key: np.ndarray, columns: np.ndarray, coefficients: np.ndarray,
            offset: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> int:
        """Rows ``offset + coefficients . correction[columns]`` (columns of sleeper and rail) within
        [lower, upper], each finite side as ``sign * (...) - slack <= sign * bound``; returns how
        many rows were new."""
        from scipy import sparse

        fresh = np.array([(family, int(k)) not in self.keys for k in key], bool)
        if not fresh.any():
            return 0
        self.keys.update((family, int(k)) for k in key[fresh])
        columns, coefficients = columns[fresh], np.broadcast_to(coefficients, columns.shape)[fresh]
        offset, lower, upper = offset[fresh], lower[fresh], upper[fresh]
        count = columns.shape[0]
        rows = np.repeat(np.arange(count), columns.shape[1])
        on_sleepers = sparse.csr_array((coefficients.ravel(), (rows, columns.ravel())),
                                       shape=(count, self.basis.shape[0]))
        on_knots = (on_sleepers @ self.basis).tocsr()
        on_knots.sum_duplicates()
        lengths = np.diff(on_knots.indptr)
        width = int(lengths.max())
        index = np.full((count, width), -1)
        value = np.zeros((count, width))
        row = np.repeat(np.arange(count), lengths)
        position = np.arange(on_knots.nnz) - np.repeat(on_knots.indptr[:-1], lengths)
        index[row, position] = on_knots.indices
        value[row, position] = on_knots.data
        for sign, bound in ((1.0, upper), (-1.0, lower)):
            side = np.flatnonzero(np.isfinite(bound))
            if not side.size:
                continue
            slack = self._add_variables(np.full(side.size, EXCESS_PENALTY), np.zeros(side.size),
                                        np.full(side.size, np.inf))
            plus = index[side]
            minus = np.where(plus >= 0, plus + self.size, -1)
            side_value = sign * value[side]
            self._add_rows(np.concatenate([plus, minus, slack[:, None]], axis=1),
                           np.concatenate([side_value, -side_value, -np.ones((side.size, 1))], axis=1),
                           np.full(side.size, -np.inf), sign * (bound[side] - offset[side]))
        return int(fresh.sum())

    def add_free(self, count: int) -> np.ndarray:
        """``count`` free variables costing nothing (the sliding extremes of :class:`_SlidingChord`)."""
        return self._add_variables(np.zeros(count), np.full(count, -EXTREME_BOUND), np.full(count, EXTREME_BOUND))

    def add_slack(self, count: int) -> np.ndarray:
        """``count`` excess variables (>= 0) costing :data:`EXCESS_PENALTY` each."""
        return self._add_variables(np.full(count, EXCESS_PENALTY), np.zeros(count), np.full(count, np.inf))

    def add_rows(self, on_sleepers: sparse.csr_array, others: np.ndarray, other_values: np.ndarray,
                 upper: np.ndarray) -> None:
        """Rows ``on_sleepers @ correction + other_values . variables[others] <= upper`` (the
        corrections per sleeper column, through the knots)."""
        from scipy import sparse

        count = others.shape[0]
        if not count:
            return
        on_knots = (on_sleepers @ self.basis).tocoo()
        row = np.concatenate([on_knots.row, on_knots.row, np.repeat(np.arange(count), others.shape[1])])
        column = np.concatenate([on_knots.col, on_knots.col + self.size, others.ravel()])
        value = np.concatenate([on_knots.data, -on_knots.data, np.broadcast_to(other_values, others.shape).ravel()])
        matrix = sparse.csr_array((value, (row, column)), shape=(count, self.variables))
        matrix.sum_duplicates()
        status = self.highs.addRows(count, np.full(count, -self.infinity), np.clip(upper, -self.infinity, self.infinity),
                                    matrix.nnz, matrix.indptr[:-1].astype(np.int32), matrix.indices.astype(np.int32),
                                    matrix.data)
        if status != type(status).kOk:
            raise RuntimeError(f"tamping re-design: HiGHS refused rows ({status})")

    def solve(self) -> np.ndarray:
        """The corrections [units] per sleeper column."""
        # the limit is on each solve (HiGHS counts the run time of the object)
        self.highs.setOptionValue("time_limit", self.highs.getRunTime() + SOLVE_TIME_LIMIT_S)
        self.highs.run()
        status = self.highs.getModelStatus()
        if status == self.out_of_time:
            raise RedesignError(f"the tamping re-design's linear programme found no solution in {SOLVE_TIME_LIMIT_S:g} s "
                                f"({self.variables} variables); re-design a shorter stretch (docs/tamping.md)")
        if status != self.optimal:
            raise RuntimeError(f"tamping re-design: the linear programme failed ({self.highs.modelStatusToString(status)})")
        x = np.asarray(self.highs.getSolution().col_value)
        return self.basis @ (x[: self.size] - x[self.size: 2 * self.size])


class _SlidingChord:
    """Every row of one long differential versine (chord m, pair p) on one rail, sparse: the sliding
    maximum (and minimum) of the chord term over each pair's chord starts.

    A pair k passes when ``|D(k) + S(i)| <= limit`` for every chord start i of its window
    ``k - (m - p) .. k`` (thesis eq. 2.2; :func:`insrail.track.irregularity.differential_versine_grid`),
    that is ``D(k) + max S <= limit`` and ``-D(k) - min S <= limit``. The chord starts and the pairs
    are taken in groups of ``group`` sleepers: U(g) >= S(i) for every start i of group g, V(h) >=
    D(k) for every pair k of group h (exact rows, one per sleeper). Cut the groups of starts into
    blocks as long as a window: a window is a suffix of one block and a prefix of the next. Per
    block, P(g) >= U(j) for j from the block's start to g (rows ``P(g) >= U(g)``, ``P(g) >= P(g-1)``)
    and Q(g) >= U(j) for j from g to the block's end, so ``V(h) + Q(a) <= limit`` and ``V(h) + P(e)
    <= limit`` (a, e the ends of the groups holding the windows of group h's pairs) hold every chord
    start of every pair of the group. With ``group`` 1 that is exactly the check; with a larger group
    a pair is also held against the chord starts of its window's end groups beyond the window (at
    most ``group - 1`` sleepers each way: a 300 m chord moved by less than 2.5 m), which only asks
    more. Per pair and side a few rows of a few entries instead of m - p + 1 rows."""

    def __init__(self, check: RailCheck, rail: int, deviation: np.ndarray, n: int, group: int):
        self.check, self.rail, self.n, self.group = check, rail, n, group
        self.d = deviation

    def rows(self, programme: _Programme, limit: float) -> None:
        from scipy import sparse

        m, p, n, size = self.check.first_steps, self.check.second_steps, self.n, self.group
        if n <= m:
            return
        r = p / m
        d, column, width = self.d, self.rail * n, programme.basis.shape[0]
        starts = n - m
        chord = np.flatnonzero(np.isfinite(d[m:]) & np.isfinite(d[:starts]))
        pair = np.flatnonzero(np.isfinite(d[: n - p]) & np.isfinite(d[p:]))
        first = np.maximum(pair - (m - p), 0)
        last = np.minimum(pair, starts - 1)
        counted = np.concatenate([[0], np.cumsum(np.isin(np.arange(starts), chord))])
        pair, first, last = (a[counted[last + 1] > counted[first]] for a in (pair, first, last))  # a chord holds them
        if not pair.size:
            return
        groups = (starts - 1) // size + 1
        pair_group = pair // size
        owners = np.unique(pair_group)
        slot = np.searchsorted(owners, pair_group)
        window_first = np.full(owners.size, groups)
        window_last = np.full(owners.size, -1)
        np.minimum.at(window_first, slot, first // size)
        np.maximum.at(window_last, slot, last // size)
        block = int(np.max(window_last - window_first)) + 1
        g = np.arange(groups)
        block_start = g // block * block
        block_end = np.minimum(block_start + block, groups) - 1
        inner = np.flatnonzero(g > block_start)
        none = sparse.csr_array((inner.size, width))
        chord_terms = sparse.csr_array((np.tile([r, -r], chord.size), (np.repeat(np.arange(chord.size), 2),
                                        np.column_stack([chord + m, chord]).ravel() + column)), shape=(chord.size, width))
        pair_terms = sparse.csr_array((np.tile([1.0, -1.0], pair.size), (np.repeat(np.arange(pair.size), 2),
                                       np.column_stack([pair, pair + p]).ravel() + column)), shape=(pair.size, width))
        for sign in (1.0, -1.0):
            extreme, prefix, suffix = (programme.add_free(groups) for _ in range(3))
            pairs = programme.add_free(owners.size)
            # U(g) >= sign * S(i), V(h) >= sign * D(k): sign * terms - U <= -sign * measured
            programme.add_rows(sign * chord_terms, extreme[chord // size][:, None], np.array([-1.0]),
                               -sign * r * (d[chord + m] - d[chord]))
            programme.add_rows(sign * pair_terms, pairs[slot][:, None], np.array([-1.0]),
                               -sign * (d[pair] - d[pair + p]))
            nothing = sparse.csr_array((groups, width))
            for aux in (prefix, suffix):  # P(g), Q(g) >= U(g)
                programme.add_rows(nothing, np.column_stack([extreme, aux]), np.array([1.0, -1.0]), np.zeros(groups))
            # P(g) >= P(g-1) and Q(g-1) >= Q(g) within a block
            programme.add_rows(none, np.column_stack([prefix[inner - 1], prefix[inner]]), np.array([1.0, -1.0]),
                               np.zeros(inner.size))
            programme.add_rows(none, np.column_stack([suffix[inner], suffix[inner - 1]]), np.array([1.0, -1.0]),
                               np.zeros(inner.size))
            # V(h) with the window's extreme: across two blocks Q(a) and P(e); within one block
            # Q(a) where the window reaches the block's end, else P(e) (from the block's start: more)
            split = block_start[window_first] != block_start[window_last]
            use_suffix = split | (block_end[window_last] == window_last)
            use_prefix = split | ~use_suffix
            slack = programme.add_slack(owners.size)
            for use, aux in ((use_suffix, suffix[window_first]), (use_prefix, prefix[window_last])):
                count = int(use.sum())
                programme.add_rows(sparse.csr_array((count, width)),
                                   np.column_stack([pairs[use], aux[use], slack[use]]), np.array([1.0, 1.0, -1.0]),
                                   np.full(count, limit))


def _knot_basis(n: int, spacing: int) -> sparse.csr_array:
    """(n, knots): the corrections of n sleepers, linear between knots every ``spacing`` sleepers
    (the last sleeper a knot too)."""
    from scipy import sparse

    knots = np.unique(np.append(np.arange(0, n, spacing), n - 1))
    j = np.arange(n)
    right = np.clip(np.searchsorted(knots, j, side="right"), 1, knots.size - 1)
    left = right - 1
    span = knots[right] - knots[left]
    w = (j - knots[left]) / np.where(span > 0, span, 1)
    matrix = sparse.coo_array((np.concatenate([1.0 - w, w]), (np.concatenate([j, j]), np.concatenate([left, right]))),
                              shape=(n, knots.size)).tocsr()
    matrix.eliminate_zeros()
    return matrix


def _knot_bounds(basis: sparse.csr_array, lower: np.ndarray, upper: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Knot bounds that hold every sleeper's: the tightest of the sleepers each knot moves. Where
    they conflict (a knot moving a fixed sleeper and one that needs a minimum lift) the upper bound
    wins: the fixed track stays, the minimum lift ramps down to it over one knot spacing."""
    coo = basis.tocoo()
    knot_lower = np.full(basis.shape[1], -np.inf)
    knot_upper = np.full(basis.shape[1], np.inf)
    np.maximum.at(knot_lower, coo.col, lower[coo.row])
    np.minimum.at(knot_upper, coo.col, upper[coo.row])
    return np.minimum(knot_lower, knot_upper), knot_upper


def _families(deviation_m: np.ndarray, valid: np.ndarray, checks: list[RailCheck], track=None) -> tuple[list, list]:
    """The row families of one direction: (the versines, the short differential versines and the
    track rows, entering as the solution violates them; each long differential versine on each rail,
    written whole in :class:`_SlidingChord`'s sparse form).""" 
    deviation = np.where(valid[:, None], deviation_m, np.nan) / UNIT_M
    long = [c for c in checks if c.kind == "differential_versine" and c.first_steps - c.second_steps >= SLIDING_STARTS]
    generated = [ChordRows(index, check, rail, deviation, valid, UNIT_M)
                 for index, (check, rail) in enumerate((c, r) for c in checks if c not in long for r in (0, 1))]
    if track is not None and track.size:
        generated.append(TrackRowFamily(len(generated), track))
    sliding = [_SlidingChord(check, rail, deviation[:, rail], deviation.shape[0], SLIDING_GROUP)
               for check in long for rail in (0, 1)]
    return generated, sliding


def _solve_direction(families: tuple[list, list], n: int, lower_m: np.ndarray, upper_m: np.ndarray,
                     per_rail: bool, cancel: CancelToken = None) -> tuple[np.ndarray, int]:
    """Corrections [m] (n, 2) of one direction (``per_rail`` False: one per sleeper for both rails)
    and the rounds of constraint generation it took."""
    from scipy import sparse

    generated, sliding = families
    knots = _knot_basis(n, KNOT_SPACING)
    if per_rail:
        basis = sparse.block_diag([knots, knots], format="csr")
    else:  # one slew for both rails' columns
        basis = sparse.vstack([knots, knots], format="csr")
    bounds = (lower_m, upper_m) if per_rail else (np.tile(lower_m, 2), np.tile(upper_m, 2))
    programme = _Programme(basis, *_knot_bounds(basis, bounds[0] / UNIT_M, bounds[1] / UNIT_M))
    for family in sliding:
        family.rows(programme, family.check.limit_m / UNIT_M)
    start = np.clip(0.0, *bounds) / UNIT_M  # the movement the bounds force on their own
    amounts = np.column_stack([start[:n], start[n:]])
    if sliding:
        x = programme.solve()
        amounts = np.column_stack([x[:n], x[n:]])
    half = np.zeros(n)  # no rounding to steps: no margin for it
    for rounds in range(1, MAX_ROUNDS + 1):
        check_cancel(cancel)
        added = 0
        for family in generated:
            rows = family.violated(amounts, half, (0, n))
            if rows is not None:
                added += programme.add(family.family, rows.key, rows.columns, np.asarray(rows.coefficients),
                                       rows.offset, rows.lower, rows.upper)
        if not added:
            return amounts * UNIT_M, rounds
        x = programme.solve()
        amounts = np.column_stack([x[:n], x[n:]])
    raise RuntimeError("tamping re-design: the rows did not settle")


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    edges = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    return list(zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1) - 1))


def _bounds(settings: RedesignSettings, fixed: np.ndarray, tolerance: np.ndarray, measured: np.ndarray):
    """(lift lower, lift upper, slew limit) [m] per sleeper."""
    if settings.lift_only:
        lift_low = np.where(fixed, 0.0, settings.min_lift_m)
    else:
        lift_low = np.where(fixed, -tolerance, -settings.max_lift_m)
    lift_high = np.where(fixed, np.minimum(tolerance, settings.max_lift_m), settings.max_lift_m)
    slew = np.where(fixed, np.minimum(tolerance, settings.max_slew_m), settings.max_slew_m)
    # a sleeper without a measurement is not moved (nothing says where it is)
    return (np.where(measured, lift_low, 0.0), np.where(measured, lift_high, 0.0), np.where(measured, slew, 0.0))


def redesign(geometry: SleeperGeometry, profile: ToleranceProfile, settings: RedesignSettings,
             assessed: np.ndarray | None = None, progress: ProgressFn | None = None,
             cancel: CancelToken = None, uncertainty: Mapping[tuple[str, str], np.ndarray] | None = None,
             not_assessed: Mapping[tuple[str, str], np.ndarray] | None = None) -> Redesign:
    """The corrections (module docstring) for ``geometry`` (deviations of every measured sleeper,
    those inside events too: the chords reach across them) under ``settings``; ``assessed``: the
    sleepers the profile judges (event stretches are not), by default every measured one.
    ``uncertainty``: (check name, direction) -> per sleeper how far inside its limit a value must be
    for the true track to pass ([m]; NaN or absent: none stated); ``not_assessed``: (check name,
    direction) -> the sleepers where the survey cannot assess that check (``direction`` "" for a
    check of the whole track, as :func:`insrail.track.exceedance.assess` takes them)."""
    progress = StepProgress(progress)
    uncertainty, not_assessed = dict(uncertainty or {}), dict(not_assessed or {})
    n = geometry.station_m.size
    vertical_measured = np.all(np.isfinite(geometry.vertical_deviation_m), axis=1) & np.isfinite(geometry.cant_m)
    lateral_measured = np.all(np.isfinite(geometry.lateral_deviation_m), axis=1)
    fixed, tolerance = settings.fixed_mask(geometry.station_m)
    lift_low, lift_high, _ = _bounds(settings, fixed, tolerance, vertical_measured)
    _, _, slew_limit = _bounds(settings, fixed, tolerance, lateral_measured)
    judged = (vertical_measured & lateral_measured) if assessed is None else np.asarray(assessed, bool)
    margins = _margins(profile, settings.margin_m, uncertainty, not_assessed, judged)
    held = {direction: [replace(c, limit_m=c.limit_m - margins[(check.name, direction)])
                        for check in profile.checks if direction in check.directions
                        for c in rail_checks(replace(profile, checks=(check,)), direction)]
            for direction in ("lateral", "vertical")}
    vertical_deviation = np.where(vertical_measured[:, None], geometry.vertical_deviation_m, np.nan)
    lateral_deviation = np.where(lateral_measured[:, None], geometry.lateral_deviation_m, np.nan)
    vertical = _families(vertical_deviation, vertical_measured, held["vertical"],
                         track_rows(geometry, _held_track_checks(profile, margins), "vertical", UNIT_M))
    progress(0.0, "tamping re-design: the lifts")
    lift, rounds_v = _solve_direction(vertical, n, np.concatenate([lift_low, lift_low]),
                                      np.concatenate([lift_high, lift_high]), per_rail=True, cancel=cancel)
    progress(0.5, "tamping re-design: the slews")
    lateral = _families(lateral_deviation, lateral_measured, held["lateral"])
    slew2, rounds_l = _solve_direction(lateral, n, -slew_limit, slew_limit, per_rail=False, cancel=cancel)
    progress(1.0, "tamping re-design: the track after the job")
    lift = np.where(vertical_measured[:, None], lift, np.nan)
    slew = np.where(lateral_measured, slew2[:, 0], np.nan)
    # round-off of the solver (1e-9 of a unit) must not read as a lowering or a slew past the limit
    lift = np.where(np.abs(lift) < 1e-9, 0.0, lift)
    slew = np.where(np.abs(slew) < 1e-9, 0.0, slew)

    before = assess(judged_only(geometry, judged), profile, not_assessed=not_assessed)
    after = assess(judged_only(moved(geometry, lift, slew), judged), profile, not_assessed=not_assessed)
    cannot = tuple(Stretch(e.first_index, e.last_index, e.station_from_m, e.station_to_m,
                           f"{e.check} {e.rail} {e.direction}".strip(), e.peak) for e in after.exceedances)
    active = _active(geometry.station_m, lift, slew, fixed, settings)
    binding = _binding(moved(geometry, lift, slew), held)
    return Redesign(geometry.station_m, lift, slew, fixed, settings, before, after, cannot,
                    _uncertain(after, geometry.station_m, uncertainty), active, binding, max(rounds_v, rounds_l),
                    margins)


#: A value after the job within this of the limit it was held at is at it [m] (the solver's and the floats' rounding).
AT_HELD_LIMIT_M = 1e-6
#: The whole-track checks of the lifts' programme (``track_rows``) held inside their limits by the margin.
_TRACK_KINDS = ("cross_level", "twist")
#: Every kind of check the programme holds (the chord checks of ``rail_checks`` and the track rows).
_HELD_KINDS = ("versine", "differential_versine", *_TRACK_KINDS)


def _margins(profile: ToleranceProfile, margin_m: float, uncertainty: dict, not_assessed: dict,
             judged: np.ndarray) -> dict[tuple[str, str], float]:
    """Per check the programme holds, by name and direction, how far inside its limit: the largest
    uncertainty stated for it over the sleepers where it is assessed, at least ``margin_m`` (the
    survey's unstated error), at most the limit (held at zero: as close as the survey tells)."""
    margins = {}
    for check in profile.checks:
        if check.kind not in _HELD_KINDS:
            continue
        limit = min(-check.lower, check.upper)
        for direction in check.directions or ("",):
            stated = uncertainty.get((check.name, direction))
            margin = margin_m
            if stated is not None:
                where = judged & ~np.asarray(not_assessed.get((check.name, direction), False), bool)
                values = np.asarray(stated, float)[where]
                if np.isfinite(values).any():
                    margin = max(margin, float(np.nanmax(values)))
            margins[(check.name, direction)] = min(margin, limit) if np.isfinite(limit) else margin
    return margins


def _held_track_checks(profile: ToleranceProfile, margins: dict[tuple[str, str], float]) -> ToleranceProfile:
    """``profile`` with its cross-level and twist limits drawn in by their margins (the lifts' track rows)."""
    def held(check):
        if check.kind not in _TRACK_KINDS:
            return check
        margin = margins[(check.name, "")]
        return replace(check, lower=min(check.lower + margin, 0.0), upper=max(check.upper - margin, 0.0))

    return replace(profile, checks=tuple(held(check) for check in profile.checks))


def _uncertain(after: Assessment, station: np.ndarray, uncertainty: dict) -> tuple[Stretch, ...]:
    """Runs of sleepers where a check's value after the job is within its limit but not by its
    uncertainty: the true track there may fail it."""
    found = []
    for channel in after.channels:
        stated = uncertainty.get((channel.check, channel.direction))
        if stated is None:
            continue
        values = channel.values
        within = np.nan_to_num(np.asarray(stated, float)) - AT_HELD_LIMIT_M
        with np.errstate(invalid="ignore"):
            close = ((values <= channel.upper) & (values > channel.upper - within)) | (
                (values >= channel.lower) & (values < channel.lower + within))
        for first, last in _runs(close):
            peak = first + int(np.nanargmax(np.abs(values[first:last + 1])))
            found.append(Stretch(int(first), int(last), float(station[first]), float(station[last]),
                                 f"{channel.check} {channel.rail} {channel.direction}".strip(), float(values[peak])))
    return tuple(sorted(found, key=lambda s: (s.station_from_m, s.what)))


def judged_only(geometry: SleeperGeometry, judged: np.ndarray) -> SleeperGeometry:
    """The geometry with the sleepers the profile does not judge left out (NaN)."""
    blank = lambda a: np.where(judged.reshape(-1, *([1] * (a.ndim - 1))), a, np.nan)  # noqa: E731
    return replace(geometry, lateral_deviation_m=blank(geometry.lateral_deviation_m),
                   vertical_deviation_m=blank(geometry.vertical_deviation_m), gauge_m=blank(geometry.gauge_m),
                   cant_m=blank(geometry.cant_m))


def _active(station: np.ndarray, lift: np.ndarray, slew: np.ndarray, fixed: np.ndarray,
            settings: RedesignSettings) -> tuple[Stretch, ...]:
    """Runs of sleepers where a bound holds the corrections."""
    eps = 1e-6
    found = []
    tests = [("lift at max_lift", np.nanmax(np.abs(lift), axis=1) >= settings.max_lift_m - eps, np.nanmax(np.abs(lift), axis=1)),
             ("slew at max_slew", np.abs(np.nan_to_num(slew)) >= settings.max_slew_m - eps, np.abs(slew))]
    if settings.lift_only and settings.min_lift_m > 0:
        low = np.nanmin(lift, axis=1) <= settings.min_lift_m + eps
        tests.append(("lift at min_lift", low & ~fixed, np.nanmin(lift, axis=1)))
    for what, mask, value in tests:
        for first, last in _runs(mask & ~fixed):
            found.append(Stretch(int(first), int(last), float(station[first]), float(station[last]), what,
                                 float(np.nanmax(value[first:last + 1]))))
    for first, last in _runs(fixed):
        found.append(Stretch(int(first), int(last), float(station[first]), float(station[last]), "fixed stretch", 0.0))
    return tuple(sorted(found, key=lambda s: s.station_from_m))


def _binding(after: SleeperGeometry, held: dict[str, list[RailCheck]]) -> dict[str, int]:
    """Per chord check, the sleeper-rails whose value after the job sits at the held limit (within
    0.05 mm): where the check, not the bounds, decided the corrections."""
    counts: dict[str, int] = {}
    for direction, deviation in (("lateral", after.lateral_deviation_m), ("vertical", after.vertical_deviation_m)):
        for check in held[direction]:
            name = f"{direction} {check.kind} {check.first_steps}/{check.second_steps}"
            total = 0
            for rail in (0, 1):
                values = np.abs(check.values(deviation[:, rail]))
                with np.errstate(invalid="ignore"):
                    total += int(np.sum(values >= check.limit_m - 5e-5))
            counts[name] = counts.get(name, 0) + total
    return counts
