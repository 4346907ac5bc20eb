"""The linear programme behind the adjustment amounts of one direction, over both rails at once.

Amounts are in fastener steps (integers after rounding); columns of a direction's amounts are
rail-major, ``left 0..n-1, right n..2n-1``. Two kinds of constraints:

* **Rail checks** (:class:`RailCheck`): the 10 m versine and the sliding differential versines
  (30 m / 5 m, 300 m / 150 m, every chord placement) of each rail, on sleeper indices as in
  thesis eq. (2.2). Soft: an excess that no amount in range removes is penalised and later
  flagged. The programme keeps a margin for the rounding to whole steps, so the rounded amounts
  pass wherever the continuous ones do.
* **Track rows** (:class:`TrackRows`): gauge and gauge change rate (lateral), cross-level and
  twist (vertical) as the profile defines them, on the sleepers' own stations with the same
  interpolation over the base as the assessment. A row is *hard* where the input lies inside its
  limits (the adjustment may never push it out), *soft* (penalised excess) where the input
  already exceeds. The rounding of the two rails' amounts can break a hard row by up to two
  steps; :func:`repair_rounding` then picks the neighbouring whole steps that hold every hard row
  (a small integer programme around the broken rows; at worst it leaves those sleepers unmoved,
  which holds them by construction).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import sparse
from scipy.optimize import Bounds, LinearConstraint, milp

from insrail.track.exceedance import SleeperGeometry
from insrail.track.irregularity import (
    DEFAULT_MAX_GAP_M,
    SLEEPER_SPACING_M,
    interpolate_valid,
)
from insrail.track.tolerance import ToleranceProfile

VIOLATION_PENALTY = 1000.0  # cost of 1 step of residual exceedance against 1 step of movement
#: In the guiding-rail-first practice the rail that follows costs this much per step of its own
#: movement (beyond the cost of changing gauge or cross-level): ties go to "follow exactly".
FOLLOWER_COST = 0.01
#: Sleepers around a broken hard row that the rounding repair may change.
REPAIR_PAD = 6
REPAIR_TIME_LIMIT_S = 5.0
TOLERANCE = 1e-9


@dataclass(frozen=True)
class RailCheck:
    """A per-rail chord check in sleeper steps: a differential versine (chord m, pair p) or a
    versine (back a, ahead b); |value| <= limit_m."""

    kind: str  # "differential_versine" | "versine"
    first_steps: int  # chord m | back a
    second_steps: int  # pair p | ahead b
    limit_m: float

    @property
    def reach_steps(self) -> int:
        return self.first_steps if self.kind == "differential_versine" else self.first_steps + self.second_steps

    def values(self, deviation_m: np.ndarray) -> np.ndarray:
        """The check's worst value per sleeper (index-based, NaN where not computable)."""
        from insrail.track.irregularity import differential_versine_grid

        if self.kind == "differential_versine":
            return differential_versine_grid(deviation_m, self.first_steps, self.second_steps)
        a, b = self.first_steps, self.second_steps
        out = np.full(deviation_m.size, np.nan)
        if deviation_m.size > a + b:
            k = np.arange(a, deviation_m.size - b)
            out[k] = deviation_m[k] - (b * deviation_m[k - a] + a * deviation_m[k + b]) / (a + b)
        return out

    def exceeding(self, deviation_m: np.ndarray) -> np.ndarray:
        """Sleepers whose value exceeds the limit (for a differential versine: first sleeper of the pair)."""
        with np.errstate(invalid="ignore"):
            return np.flatnonzero(np.abs(self.values(deviation_m)) > self.limit_m + TOLERANCE)


def rail_checks(profile: ToleranceProfile, direction: str, spacing_m: float = SLEEPER_SPACING_M) -> list[RailCheck]:
    """The profile's chord checks of ``direction`` that the programme holds (chords a whole number of sleepers)."""
    checks = []
    for check in profile.checks:
        if direction not in check.directions:
            continue
        limit = min(-check.lower, check.upper)
        if check.kind == "differential_versine":
            checks.append(RailCheck(check.kind, round(check.chord_m / spacing_m), round(check.pair_m / spacing_m), limit))
        elif check.kind == "versine":
            back = check.chord_m / 2.0 if check.back_m is None else check.back_m
            a, b = back / spacing_m, (check.chord_m - back) / spacing_m
            if min(a, b) >= 1 and abs(a - round(a)) < 1e-6 and abs(b - round(b)) < 1e-6:
                checks.append(RailCheck(check.kind, round(a), round(b), limit))
    return checks


# --------------------------------------------------------------------------- track rows

@dataclass(frozen=True)
class TrackRows:
    """Track checks of one direction as rows over the 2n amount columns (steps):
    value = value0 + matrix @ amounts, inside [lower, upper]; ``hard`` where the input is inside."""

    matrix: sparse.csr_array
    value0: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    hard: np.ndarray
    first: np.ndarray  # lowest sleeper index a row touches
    last: np.ndarray  # highest

    @property
    def size(self) -> int:
        return self.value0.size

    def values(self, amounts_steps: np.ndarray) -> np.ndarray:
        return self.value0 + self.matrix @ amounts_steps.T.reshape(-1)

    def broken(self, amounts_steps: np.ndarray) -> np.ndarray:
        """Hard rows outside their limits."""
        values = self.values(amounts_steps)
        return self.hard & ((values < self.lower - 1e-7) | (values > self.upper + 1e-7))

    def exceeding(self, amounts_steps: np.ndarray) -> np.ndarray:
        """Rows (hard or soft) outside their limits."""
        values = self.values(amounts_steps)
        return (values < self.lower - 1e-7) | (values > self.upper + 1e-7)


class _RowCollector:
    def __init__(self, n: int, step: float):
        self.n, self.step = n, step
        self.rows: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []  # (row-local index, column, value)
        self.value0, self.lower, self.upper, self.box = [], [], [], []
        self.count = 0

    def add(self, terms: list[tuple[np.ndarray, np.ndarray]], value0_m: np.ndarray, lower_m: float, upper_m: float,
            box: bool) -> None:
        """Rows value0 + sum(coefficient * amount[column]); terms hold (sleeper-rail column, coefficient per row)."""
        size = value0_m.size
        index = np.arange(size) + self.count
        for column, coefficient in terms:
            self.rows.append((index, column, np.broadcast_to(np.asarray(coefficient, dtype=float), (size,))))
        self.value0.append(value0_m / self.step)
        self.lower.append(np.full(size, lower_m / self.step))
        self.upper.append(np.full(size, upper_m / self.step))
        self.box.append(np.full(size, box))
        self.count += size

    def build(self) -> TrackRows:
        n = self.n
        if not self.count:
            empty = np.empty(0)
            return TrackRows(sparse.csr_array((0, 2 * n)), empty, empty, empty, np.empty(0, bool),
                             np.empty(0, int), np.empty(0, int))
        rows = np.concatenate([r for r, _, _ in self.rows])
        columns = np.concatenate([c for _, c, _ in self.rows])
        values = np.concatenate([v for _, _, v in self.rows])
        matrix = sparse.coo_array((values, (rows, columns)), shape=(self.count, 2 * n)).tocsr()
        matrix.sum_duplicates()
        value0, lower, upper = (np.concatenate(x) for x in (self.value0, self.lower, self.upper))
        box = np.concatenate(self.box)
        hard = (value0 >= lower - TOLERANCE) & (value0 <= upper + TOLERANCE)
        # Gauge and cross-level rows take the rails' difference, a whole number of steps: the
        # allowed change is then a whole number too, and rounding each rail can never leave it
        # (nor round a fix of an exceeding row away).
        lower = np.where(box, np.ceil(lower - value0 - TOLERANCE) + value0, lower)
        upper = np.where(box, np.floor(upper - value0 + TOLERANCE) + value0, upper)
        coo = matrix.tocoo()
        first = np.full(self.count, n, dtype=np.int64)
        last = np.full(self.count, -1, dtype=np.int64)
        np.minimum.at(first, coo.row, coo.col % n)
        np.maximum.at(last, coo.row, coo.col % n)
        return TrackRows(matrix, value0, lower, upper, hard, first, last)


def _base_rows(collector: _RowCollector, station: np.ndarray, series: np.ndarray, difference: np.ndarray, base_m: float,
               scale: float, lower: float, upper: float) -> None:
    """Rows of ``series`` over a base ending and starting at each sleeper, interpolated like
    :func:`insrail.track.parameters.difference_over_base`; ``difference`` (2,) the series' change
    per step of the left and right amounts; ``scale`` divides the difference (a rate: 1/base)."""
    valid = np.flatnonzero(np.isfinite(series))
    if valid.size < 2:
        return
    n = collector.n
    sv = station[valid]
    for sign in (-1.0, 1.0):  # ending: f(s) - f(s - b); starting: f(s + b) - f(s)
        query = station + sign * base_m
        far = interpolate_valid(station, series, query, DEFAULT_MAX_GAP_M)
        rows = np.flatnonzero(np.isfinite(far) & np.isfinite(series))
        if not rows.size:
            continue
        q = query[rows]
        right = np.clip(np.searchsorted(sv, q, side="left"), 0, sv.size - 1)
        left = np.clip(right - 1, 0, sv.size - 1)
        on_right = np.isclose(sv[right], q, rtol=0.0, atol=1e-9)
        span = sv[right] - sv[left]
        weight_right = np.where(on_right | (span <= 0), 1.0, (q - sv[left]) / np.where(span > 0, span, 1.0))
        weight_left = 1.0 - weight_right
        far_left, far_right = valid[left], valid[right]
        value0 = sign * (far[rows] - series[rows]) * scale
        terms = []
        for column, factor in ((0, difference[0]), (1, difference[1])):
            terms.append((column * n + rows, -sign * factor * scale * np.ones(rows.size)))
            terms.append((column * n + far_left, sign * factor * scale * weight_left))
            terms.append((column * n + far_right, sign * factor * scale * weight_right))
        collector.add(terms, value0, lower, upper, box=False)


def track_rows(geometry: SleeperGeometry, profile: ToleranceProfile, direction: str, step_m: float) -> TrackRows:
    """The profile's gauge / gauge-change-rate (lateral) or cross-level / twist (vertical) checks
    as rows over the direction's amounts (see :class:`TrackRows`)."""
    n = geometry.station_m.size
    collector = _RowCollector(n, step_m)
    station = geometry.station_m
    index = np.arange(n)
    # change of gauge (lateral) or cant (vertical) per step of the [left, right] amount
    difference = np.array([-1.0, 1.0]) * step_m if direction == "lateral" else np.array([1.0, -1.0]) * step_m
    cross_level = geometry.cant_m - geometry.design_cant_m
    for check in profile.checks:
        if direction == "lateral" and check.kind == "gauge_deviation":
            value0 = geometry.gauge_m - profile.nominal_gauge_m
            ok = index[np.isfinite(value0)]
            collector.add([(ok, difference[0] / step_m), (n + ok, difference[1] / step_m)], value0[ok],
                          check.lower, check.upper, box=True)
        elif direction == "lateral" and check.kind == "gauge_change_rate":
            if check.base_m is None:
                gauge = geometry.gauge_m
                ok = np.flatnonzero(np.isfinite(gauge[1:]) & np.isfinite(gauge[:-1])) + 1
                ds = station[ok] - station[ok - 1]
                value0 = (gauge[ok] - gauge[ok - 1]) / ds
                terms = [(c * n + ok, difference[c] / step_m / ds) for c in (0, 1)]
                terms += [(c * n + ok - 1, -difference[c] / step_m / ds) for c in (0, 1)]
                collector.add(terms, value0, check.lower, check.upper, box=False)
            else:
                _base_rows(collector, station, geometry.gauge_m, difference / step_m, check.base_m, 1.0 / check.base_m,
                           check.lower, check.upper)
        elif direction == "vertical" and check.kind == "cross_level":
            ok = index[np.isfinite(cross_level)]
            collector.add([(ok, difference[0] / step_m), (n + ok, difference[1] / step_m)], cross_level[ok],
                          check.lower, check.upper, box=True)
        elif direction == "vertical" and check.kind == "twist":
            series = cross_level if check.relative_to_design else geometry.cant_m
            _base_rows(collector, station, series, difference / step_m, check.base_m, 1.0, check.lower, check.upper)
    return collector.build()


# --------------------------------------------------------------------------- the window programme

class _Programme:
    """Variables and rows of one window's linear programme, assembled as sparse triplets."""

    def __init__(self):
        self.variables = 0
        self.cost: list[np.ndarray] = []
        self.var_lower: list[np.ndarray] = []
        self.var_upper: list[np.ndarray] = []
        self.rows, self.cols, self.vals, self.lower, self.upper = [], [], [], [], []
        self.count = 0

    def add_variables(self, count: int, lower, upper, cost) -> np.ndarray:
        index = self.variables + np.arange(count)
        self.variables += count
        self.var_lower.append(np.broadcast_to(np.asarray(lower, float), (count,)))
        self.var_upper.append(np.broadcast_to(np.asarray(upper, float), (count,)))
        self.cost.append(np.broadcast_to(np.asarray(cost, float), (count,)))
        return index

    def add_rows(self, terms, lower, upper) -> None:
        """Rows lower <= sum(coefficient * x[column]) <= upper; ``terms`` (columns, coefficients) per row."""
        lower = np.asarray(lower, float)
        upper = np.broadcast_to(np.asarray(upper, float), lower.shape)
        size = lower.size
        if not size:
            return
        index = self.count + np.arange(size)
        for column, coefficient in terms:
            self.rows.append(index)
            self.cols.append(np.broadcast_to(column, (size,)))
            self.vals.append(np.broadcast_to(np.asarray(coefficient, float), (size,)))
        self.lower.append(lower)
        self.upper.append(upper)
        self.count += size

    def solve(self) -> np.ndarray:
        matrix = sparse.csr_array((np.concatenate(self.vals), (np.concatenate(self.rows), np.concatenate(self.cols))),
                                  shape=(self.count, self.variables))
        result = milp(np.concatenate(self.cost), constraints=LinearConstraint(matrix, np.concatenate(self.lower),
                                                                                 np.concatenate(self.upper)),
                      bounds=Bounds(np.concatenate(self.var_lower), np.concatenate(self.var_upper)))
        if result.x is None:
            raise RuntimeError(f"adjustment optimisation failed: {result.message}")
        return result.x


def _differential_rows(lp: _Programme, amount, d: np.ndarray, valid: np.ndarray, check: RailCheck, step: float) -> None:
    """Every chord placement and point pair of one differential-versine check on one rail.

    For a chord starting at j, r(k) - r(k+p) = D(k) + S(j) with D(k) = d(k) - d(k+p) and
    S(j) = p/m (d(j+m) - d(j)); the pair's worst value over the chords holding it is reached at
    the largest or smallest S of a window of m - p + 1 starts, which running maxima/minima over
    prefixes and suffixes of blocks of that width bound with two variables each.
    """
    n = d.size
    m, p = check.first_steps, check.second_steps
    n_chords = n - m
    if n_chords <= 0:
        return
    # Rounding each amount to a whole step moves D + S by at most (1 + p/m) steps: kept as a margin.
    bound = check.limit_m / step - (1.0 + p / m)
    if bound <= 0:
        raise ValueError(f"a {check.limit_m * 1e3:g} mm limit on a {m}/{p}-sleeper check leaves no room for "
                         f"{step * 1e3:g} mm fastener steps")
    r = p / m
    pmax, qmax, pmin, qmin = (lp.add_variables(n_chords, -np.inf, np.inf, 0.0) for _ in range(4))
    ok = np.flatnonzero(valid[:n_chords] & valid[m:])
    s0 = r * (d[ok + m] - d[ok])
    chord = amount(ok + m, r) + amount(ok, -r)
    for running in (pmax, qmax):  # S_j <= running maximum
        lp.add_rows(chord + [(running[ok], -1.0)], np.full(ok.size, -np.inf), -s0)
    for running in (pmin, qmin):  # S_j >= running minimum
        lp.add_rows(chord + [(running[ok], -1.0)], -s0, np.full(ok.size, np.inf))
    block = m - p + 1
    index = np.arange(n_chords)
    previous = np.where(index % block == 0, -1, index - 1)
    following = np.where((index % block == block - 1) | (index == n_chords - 1), -1, index + 1)
    for chain, top, bottom in ((previous, pmax, pmin), (following, qmax, qmin)):
        linked = np.flatnonzero(chain >= 0)
        zeros = np.zeros(linked.size)
        lp.add_rows([(top[chain[linked]], 1.0), (top[linked], -1.0)], np.full(linked.size, -np.inf), zeros)
        lp.add_rows([(bottom[linked], 1.0), (bottom[chain[linked]], -1.0)], np.full(linked.size, -np.inf), zeros)
    k = np.arange(n - p)
    k = k[valid[k] & valid[k + p]]
    first = np.maximum(k - (m - p), 0)
    last = np.minimum(k, n_chords - 1)
    keep = first <= last
    k, first, last = k[keep], first[keep], last[keep]
    same = first // block == last // block
    d0 = d[k] - d[k + p]
    slack = lp.add_variables(k.size, 0.0, np.inf, VIOLATION_PENALTY)  # how far pair k still exceeds
    pair = amount(k, 1.0) + amount(k + p, -1.0)
    for selector, high, low in ((~same | (first % block == 0), pmax[last], pmin[last]),
                                (~same | (first % block != 0), qmax[first], qmin[first])):
        terms = [(c[selector], np.broadcast_to(v, k.shape)[selector]) for c, v in pair]
        count = int(selector.sum())
        # D(a) + max S <= bound + slack  and  D(a) + min S >= -bound - slack
        lp.add_rows(terms + [(high[selector], 1.0), (slack[selector], -1.0)], np.full(count, -np.inf),
                    bound - d0[selector])
        lp.add_rows(terms + [(low[selector], 1.0), (slack[selector], 1.0)], -bound - d0[selector],
                    np.full(count, np.inf))


def _versine_rows(lp: _Programme, amount, d: np.ndarray, valid: np.ndarray, check: RailCheck, step: float) -> None:
    """The versine at every sleeper whose chord ends are valid: d(k) - [b d(k-a) + a d(k+b)]/(a+b)."""
    a, b = check.first_steps, check.second_steps
    n = d.size
    # rounding moves the versine by at most 1/2 (1 + b/(a+b) + a/(a+b)) = 1 step
    bound = check.limit_m / step - 1.0
    if bound <= 0 or n <= a + b:
        return
    k = np.arange(a, n - b)
    k = k[valid[k] & valid[k - a] & valid[k + b]]
    wa, wb = a / (a + b), b / (a + b)
    v0 = d[k] - wb * d[k - a] - wa * d[k + b]
    slack = lp.add_variables(k.size, 0.0, np.inf, VIOLATION_PENALTY)
    terms = amount(k, 1.0) + amount(k - a, -wb) + amount(k + b, -wa)
    lp.add_rows(terms + [(slack, -1.0)], np.full(k.size, -np.inf), bound - v0)
    lp.add_rows(terms + [(slack, 1.0)], -bound - v0, np.full(k.size, np.inf))


@dataclass(frozen=True)
class DirectionProblem:
    """Everything about one direction that does not change between windows (amounts in steps)."""

    deviation: np.ndarray  # (N, 2) steps, NaN where invalid
    valid: np.ndarray  # (N,) bool
    rows: TrackRows
    low: float  # fastener range [steps], whole numbers
    high: float
    step_m: float
    reference_right: np.ndarray | None  # (N,) bool: the rail that leads (guiding-rail-first practice), else None


def solve_window(problem: DirectionProblem, amounts: np.ndarray, start: int, stop: int, checks: list[RailCheck]) -> np.ndarray:
    """Continuous amounts [steps] (stop - start, 2) of sleepers start..stop-1 of both rails. The
    sleepers one reach beyond each end keep ``amounts`` (so every chord placement and track row
    touching a free sleeper is in the programme)."""
    total = problem.deviation.shape[0]
    reach = max([c.reach_steps for c in checks] + [8])
    lo, hi = max(0, start - reach), min(total, stop + reach)
    n = hi - lo
    valid = problem.valid[lo:hi]
    free = np.zeros(n, bool)
    free[start - lo: stop - lo] = True
    free &= valid
    lp = _Programme()
    fixed = np.where(valid[:, None], amounts[lo:hi], 0.0)  # (n, 2)
    guiding = problem.reference_right is not None
    plus, minus = [], []
    for rail in (0, 1):
        if guiding:
            leads = problem.reference_right[lo:hi] == bool(rail)
            cost = np.where(leads, 1.0, FOLLOWER_COST)
        else:
            cost = 1.0
        up = np.where(free, problem.high, np.maximum(fixed[:, rail], 0.0))
        down = np.where(free, -problem.low, np.maximum(-fixed[:, rail], 0.0))
        plus.append(lp.add_variables(n, np.where(free, 0.0, up), up, cost))
        minus.append(lp.add_variables(n, np.where(free, 0.0, down), down, cost))

    def amount_of(rail: int, offset: int = 0):
        def amount(index, coefficient):
            return [(plus[rail][index + offset], coefficient), (minus[rail][index + offset], -np.asarray(coefficient, float))]
        return amount

    if guiding:  # |right - left|: the change of gauge or cross-level the following rail takes
        up = lp.add_variables(n, 0.0, np.inf, 1.0)
        down = lp.add_variables(n, 0.0, np.inf, 1.0)
        index = np.arange(n)
        lp.add_rows(amount_of(1)(index, 1.0) + amount_of(0)(index, -1.0) + [(up, -1.0), (down, 1.0)],
                    np.zeros(n), np.zeros(n))
    for check in checks:
        # each check only over the placements that can touch a free sleeper
        c_lo, c_hi = max(lo, start - check.reach_steps), min(hi, stop + check.reach_steps)
        builder = _differential_rows if check.kind == "differential_versine" else _versine_rows
        for rail in (0, 1):
            d = np.where(problem.valid[c_lo:c_hi], problem.deviation[c_lo:c_hi, rail], 0.0)
            builder(lp, amount_of(rail, c_lo - lo), d, problem.valid[c_lo:c_hi], check, problem.step_m)
    rows = problem.rows
    touching = np.flatnonzero((rows.first >= lo) & (rows.last < hi) & (rows.last >= start) & (rows.first < stop))
    if touching.size:
        sub = rows.matrix[touching].tocoo()
        rail, sleeper = sub.col // total, sub.col % total - lo
        row_plus = np.where(rail == 0, plus[0][sleeper], plus[1][sleeper])
        row_minus = np.where(rail == 0, minus[0][sleeper], minus[1][sleeper])
        v0, lower, upper = rows.value0[touching], rows.lower[touching], rows.upper[touching]
        soft = ~rows.hard[touching]
        slack = lp.add_variables(touching.size, 0.0, np.where(soft, np.inf, 0.0), VIOLATION_PENALTY)
        # value - slack <= upper and value + slack >= lower; the slack (the excess, paid) is 0 on hard rows
        for sign, row_lower, row_upper in ((-1.0, np.full(touching.size, -np.inf), upper - v0),
                                           (1.0, lower - v0, np.full(touching.size, np.inf))):
            base = lp.count
            lp.rows += [base + sub.row, base + sub.row, base + np.arange(touching.size)]
            lp.cols += [row_plus, row_minus, slack]
            lp.vals += [sub.data, -sub.data, np.full(touching.size, sign)]
            lp.lower.append(row_lower)
            lp.upper.append(row_upper)
            lp.count += touching.size
    x = lp.solve()
    solved = np.column_stack([x[plus[r]] - x[minus[r]] for r in (0, 1)])
    return solved[start - lo: stop - lo]


def round_amounts(continuous: np.ndarray, low: float, high: float, valid: np.ndarray) -> np.ndarray:
    """Whole steps inside the range; invalid sleepers 0."""
    return np.where(valid[:, None], np.clip(np.round(continuous), low, high), 0.0)


def repair_rounding(problem: DirectionProblem, amounts: np.ndarray, continuous: np.ndarray) -> np.ndarray:
    """Amounts [steps] holding every hard track row: around each row the rounding broke, the
    sleepers' amounts are chosen again among the whole steps next to the continuous solution
    (an integer programme over a few sleepers, least distance to it). Where no such choice
    exists the sleepers stay unmoved in this direction, which holds their rows by construction;
    that is repeated (the region grows) until no hard row is broken."""
    rows = problem.rows
    amounts = amounts.copy()
    total = amounts.shape[0]
    for _ in range(200):
        broken = np.flatnonzero(rows.broken(amounts))
        if not broken.size:
            return amounts
        sleepers = np.unique(rows.matrix[broken].tocoo().col % total)
        region = np.unique(np.clip(sleepers[:, None] + np.arange(-REPAIR_PAD, REPAIR_PAD + 1), 0, total - 1))
        region = region[problem.valid[region]]
        choice = _integer_choice(problem, amounts, continuous, region)
        if choice is None:
            amounts[sleepers] = 0.0
        else:
            amounts[region] = choice
    amounts[:] = 0.0  # cannot happen in practice; unmoved track breaks no hard row
    return amounts


def _integer_choice(problem: DirectionProblem, amounts: np.ndarray, continuous: np.ndarray,
                    region: np.ndarray) -> np.ndarray | None:
    rows = problem.rows
    total = amounts.shape[0]
    columns = np.concatenate([region, total + region])  # rail-major amount columns
    target = np.concatenate([continuous[region, 0], continuous[region, 1]])
    near = np.round(target)
    lower = np.clip(np.minimum(np.floor(target), near - 1), problem.low, problem.high)
    upper = np.clip(np.maximum(np.ceil(target), near + 1), problem.low, problem.high)
    matrix = rows.matrix
    in_region = np.zeros(2 * total, bool)
    in_region[columns] = True
    touched = np.flatnonzero(rows.hard & (abs(matrix[:, in_region]).sum(axis=1) > 0))
    if not touched.size:
        return amounts[region]
    flat = amounts.T.reshape(-1).copy()
    flat[columns] = 0.0
    constant = rows.value0[touched] + matrix[touched] @ flat
    local = matrix[touched][:, columns]
    count = columns.size
    # x (integer) and e >= |x - target|
    a = sparse.vstack([sparse.hstack([local, sparse.csr_array((touched.size, count))]),
                       sparse.hstack([sparse.eye_array(count), -sparse.eye_array(count)]),
                       sparse.hstack([sparse.eye_array(count), sparse.eye_array(count)])]).tocsr()
    row_lower = np.concatenate([rows.lower[touched] - constant, np.full(count, -np.inf), target])
    row_upper = np.concatenate([rows.upper[touched] - constant, target, np.full(count, np.inf)])
    cost = np.concatenate([np.zeros(count), np.ones(count)])
    result = milp(cost, constraints=LinearConstraint(a, row_lower, row_upper),
                  integrality=np.concatenate([np.ones(count), np.zeros(count)]),
                  bounds=Bounds(np.concatenate([lower, np.zeros(count)]), np.concatenate([upper, np.full(count, np.inf)])),
                  options={"time_limit": REPAIR_TIME_LIMIT_S})
    if result.x is None or result.status not in (0,):
        return None
    x = np.round(result.x[:count])
    return np.column_stack([x[: region.size], x[region.size:]])
