"""The linear programme behind the adjustment amounts of one direction, over both rails at once.

Amounts are in fastener steps (integers after rounding); columns of a direction's amounts are
rail-major, ``left 0..n-1, right n..2n-1``. Two kinds of constraints:

* **Rail checks** (:class:`RailCheck`): the 10 m versine and the sliding differential versines
  (30 m / 5 m, 300 m / 150 m, every chord placement) of each rail, on sleeper indices as in
  thesis eq. (2.2). Soft: an excess that no amount in range removes is penalised and later
  flagged. Each row keeps a margin for the rounding to whole steps (half a step times the
  weight of every free amount in it), so the rounded amounts pass wherever the continuous ones do.
* **Track rows** (:class:`TrackRows`): gauge and gauge change rate (lateral), cross-level and
  twist (vertical) as the profile defines them, on the sleepers' own stations with the same
  interpolation over the base as the assessment. A row is *hard* where the input lies inside its
  limits (the adjustment may never push it out), *soft* (penalised excess) where the input
  already exceeds. The rounding of the two rails' amounts can break a hard row by up to two
  steps; :func:`repair_rounding` then picks the neighbouring whole steps that hold every hard row
  (a small integer programme around the broken rows; at worst it leaves those sleepers unmoved,
  which holds them by construction).

Written out, the rows number hundreds per sleeper (every chord placement of the 300 m chord);
:func:`solve_free` adds them as the solution violates them (constraint generation, HiGHS dual
simplex restarting from its last basis), and a few per sleeper ever enter the programme.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from insrail.progress import check_cancel
from insrail.track.exceedance import SleeperGeometry
from insrail.track.irregularity import (
    DEFAULT_MAX_GAP_M,
    SLEEPER_SPACING_M,
    interpolate_valid,
)
from insrail.track.tolerance import ToleranceProfile

if TYPE_CHECKING:
    from scipy import sparse

# scipy.sparse, scipy.optimize and HiGHS (some 0.5 s of imports) are imported where a programme is
# built: insrail.track.adjustment imports this module, and the project model imports that one, so
# every command reading a project (insrail report, export) would pay for them otherwise.

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
    versine (back a, ahead b); |value| <= limit_m. ``held`` (N,) bool: the sleepers whose value
    (for a differential versine: first sleeper of the pair) the programme holds, where the survey
    can assess the check (:func:`rail_checks`); None: every one."""

    kind: str  # "differential_versine" | "versine"
    first_steps: int  # chord m | back a
    second_steps: int  # pair p | ahead b
    limit_m: float
    held: np.ndarray | None = field(default=None, repr=False, compare=False)

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

    @property
    def span_steps(self) -> tuple[int, int]:
        """How many sleepers before and after k the value at k reads."""
        if self.kind == "differential_versine":
            return self.first_steps - self.second_steps, self.first_steps
        return self.first_steps, self.second_steps

    def exceeding(self, deviation_m: np.ndarray, start: int = 0, stop: int | None = None) -> np.ndarray:
        """Sleepers of start..stop-1 whose value exceeds the limit (for a differential versine: first
        sleeper of the pair), from the deviations those values read (the same values as over the
        whole line)."""
        stop = deviation_m.size if stop is None else stop
        back, ahead = self.span_steps
        lo, hi = max(0, start - back), min(deviation_m.size, stop + ahead)
        values = self.values(deviation_m[lo:hi])[start - lo: stop - lo]
        with np.errstate(invalid="ignore"):
            found = np.flatnonzero(np.abs(values) > self.limit_m + TOLERANCE) + start
        return found if self.held is None else found[self.held[found]]


def rail_checks(profile: ToleranceProfile, direction: str, spacing_m: float = SLEEPER_SPACING_M,
                not_assessed: Mapping[tuple[str, str], np.ndarray] | None = None) -> list[RailCheck]:
    """The profile's chord checks of ``direction`` that the programme holds (chords a whole number of sleepers).
    ``not_assessed``: (check name, direction) -> the sleepers (N,) bool where the survey cannot assess
    that check (:func:`insrail.track.exceedance.assess`'s): not held there. Its values there are the
    survey's noise as much as the track's; amounts that chased them would move rails for nothing (and on
    a survey whose noise crosses the limits everywhere, one programme over the whole line, every row of
    it violated, takes minutes)."""
    checks = []
    for check in profile.checks:
        if direction not in check.directions:
            continue
        limit = min(-check.lower, check.upper)
        left_out = (not_assessed or {}).get((check.name, direction))
        held = None if left_out is None else ~np.asarray(left_out, dtype=bool)
        if check.kind == "differential_versine":
            checks.append(RailCheck(check.kind, round(check.chord_m / spacing_m), round(check.pair_m / spacing_m), limit,
                                    held))
        elif check.kind == "versine":
            back = check.chord_m / 2.0 if check.back_m is None else check.back_m
            a, b = back / spacing_m, (check.chord_m - back) / spacing_m
            if min(a, b) >= 1 and abs(a - round(a)) < 1e-6 and abs(b - round(b)) < 1e-6:
                checks.append(RailCheck(check.kind, round(a), round(b), limit, held))
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
    owner: np.ndarray  # the sleeper whose value (or base) the row checks

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
    """Rows over the 2 ``total`` amount columns, built on the sleepers ``offset``.. of a block;
    only the rows owned by sleepers own[0]..own[1]-1 are kept."""

    def __init__(self, total: int, offset: int, own: tuple[int, int], step: float):
        self.n, self.offset, self.own, self.step = total, offset, own, step
        self.rows: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []  # (row-local index, column, value)
        self.value0, self.lower, self.upper, self.box, self.owner = [], [], [], [], []
        self.count = 0

    def add(self, owner: np.ndarray, terms: list[tuple[int, np.ndarray, np.ndarray]], value0_m: np.ndarray,
            lower_m: float, upper_m: float, box: bool) -> None:
        """Rows value0 + sum(coefficient * amount[rail, sleeper]), one per block sleeper of ``owner``;
        terms hold (rail, block sleeper, coefficient) per row."""
        keep = np.flatnonzero((owner >= self.own[0] - self.offset) & (owner < self.own[1] - self.offset))
        size = keep.size
        index = np.arange(size) + self.count
        for rail, sleeper, coefficient in terms:
            coefficient = np.broadcast_to(np.asarray(coefficient, dtype=float), owner.shape)[keep]
            self.rows.append((index, rail * self.n + self.offset + sleeper[keep], coefficient))
        self.value0.append(value0_m[keep] / self.step)
        self.lower.append(np.full(size, lower_m / self.step))
        self.upper.append(np.full(size, upper_m / self.step))
        self.box.append(np.full(size, box))
        self.owner.append(self.offset + owner[keep])
        self.count += size

    def build(self) -> TrackRows:
        from scipy import sparse

        n = self.n
        if not self.count:
            empty = np.empty(0)
            return TrackRows(sparse.csr_array((0, 2 * n)), empty, empty, empty, np.empty(0, bool),
                             np.empty(0, int), np.empty(0, int), np.empty(0, int))
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
        return TrackRows(matrix, value0, lower, upper, hard, first, last, np.concatenate(self.owner))


def _base_rows(collector: _RowCollector, station: np.ndarray, series: np.ndarray, difference: np.ndarray, base_m: float,
               scale: float, lower: float, upper: float) -> None:
    """Rows of ``series`` over a base ending and starting at each sleeper, interpolated like
    :func:`insrail.track.parameters.difference_over_base`; ``difference`` (2,) the series' change
    per step of the left and right amounts; ``scale`` divides the difference (a rate: 1/base)."""
    valid = np.flatnonzero(np.isfinite(series))
    if valid.size < 2:
        return
    sv = station[valid]
    for sign in (-1.0, 1.0):  # ending: f(s) - f(s - b); starting: f(s + b) - f(s)
        query = station + sign * base_m
        far = interpolate_valid(station, series, query, DEFAULT_MAX_GAP_M)
        rows = np.flatnonzero(np.isfinite(far) & np.isfinite(series))
        if not rows.size:
            continue
        q = query[rows]
        right, left = _bracket(sv, q)
        on_right = np.isclose(sv[right], q, rtol=0.0, atol=1e-9)
        span = sv[right] - sv[left]
        weight_right = np.where(on_right | (span <= 0), 1.0, (q - sv[left]) / np.where(span > 0, span, 1.0))
        weight_left = 1.0 - weight_right
        far_left, far_right = valid[left], valid[right]
        value0 = sign * (far[rows] - series[rows]) * scale
        terms = []
        for rail in (0, 1):
            factor = difference[rail]
            terms.append((rail, rows, -sign * factor * scale * np.ones(rows.size)))
            terms.append((rail, far_left, sign * factor * scale * weight_left))
            terms.append((rail, far_right, sign * factor * scale * weight_right))
        collector.add(rows, terms, value0, lower, upper, box=False)


def _bracket(sv: np.ndarray, query: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Indices of the valid samples (stations ``sv``) each side of each query, as
    :func:`insrail.track.irregularity.interpolate_valid` takes them."""
    right = np.clip(np.searchsorted(sv, query, side="left"), 0, sv.size - 1)
    return right, np.clip(right - 1, 0, sv.size - 1)


def _based_series(geometry: SleeperGeometry, profile: ToleranceProfile, direction: str):
    """(check, series) of the direction's checks over a base: gauge change rate (lateral), twist (vertical)."""
    for check in profile.checks:
        if direction == "lateral" and check.kind == "gauge_change_rate":
            yield check, geometry.gauge_m
        elif direction == "vertical" and check.kind == "twist":
            yield check, (geometry.cant_m - geometry.design_cant_m if check.relative_to_design else geometry.cant_m)


def track_rows(geometry: SleeperGeometry, profile: ToleranceProfile, direction: str, step_m: float,
               extent: tuple[int, int] | None = None, own: tuple[int, int] | None = None) -> TrackRows:
    """The profile's gauge / gauge-change-rate (lateral) or cross-level / twist (vertical) checks
    as rows over the direction's amounts (see :class:`TrackRows`), in the order: check, then
    (over a base) ending before starting, then sleeper. With ``extent`` and ``own`` only the rows
    owned by sleepers own[0]..own[1]-1 (a sleeper owns the rows of its own value and of the bases
    ending and starting at it), built from the sleepers extent[0]..extent[1]-1 alone: the same
    rows as over the whole line when the extent holds every sleeper they read
    (:class:`TrackRowSource`)."""
    total = geometry.station_m.size
    lo, hi = extent or (0, total)
    collector = _RowCollector(total, lo, own or (0, total), step_m)
    station = geometry.station_m[lo:hi]
    gauge, cant, design_cant = geometry.gauge_m[lo:hi], geometry.cant_m[lo:hi], geometry.design_cant_m[lo:hi]
    n = station.size
    index = np.arange(n)
    # change of gauge (lateral) or cant (vertical) per step of the [left, right] amount
    difference = np.array([-1.0, 1.0]) * step_m if direction == "lateral" else np.array([1.0, -1.0]) * step_m
    cross_level = cant - design_cant
    for check in profile.checks:
        if direction == "lateral" and check.kind == "gauge_deviation":
            value0 = gauge - profile.nominal_gauge_m
            ok = index[np.isfinite(value0)]
            collector.add(ok, [(0, ok, difference[0] / step_m), (1, ok, difference[1] / step_m)], value0[ok],
                          check.lower, check.upper, box=True)
        elif direction == "lateral" and check.kind == "gauge_change_rate":
            if check.base_m is None:
                ok = np.flatnonzero(np.isfinite(gauge[1:]) & np.isfinite(gauge[:-1])) + 1
                ds = station[ok] - station[ok - 1]
                value0 = (gauge[ok] - gauge[ok - 1]) / ds
                terms = [(c, ok, difference[c] / step_m / ds) for c in (0, 1)]
                terms += [(c, ok - 1, -difference[c] / step_m / ds) for c in (0, 1)]
                collector.add(ok, terms, value0, check.lower, check.upper, box=False)
            else:
                _base_rows(collector, station, gauge, difference / step_m, check.base_m, 1.0 / check.base_m,
                           check.lower, check.upper)
        elif direction == "vertical" and check.kind == "cross_level":
            ok = index[np.isfinite(cross_level)]
            collector.add(ok, [(0, ok, difference[0] / step_m), (1, ok, difference[1] / step_m)], cross_level[ok],
                          check.lower, check.upper, box=True)
        elif direction == "vertical" and check.kind == "twist":
            series = cross_level if check.relative_to_design else cant
            _base_rows(collector, station, series, difference / step_m, check.base_m, 1.0, check.lower, check.upper)
    return collector.build()


#: Sleepers per block of track rows where a computation goes over the whole line (tests shrink it).
ROW_BLOCK = 2048


@dataclass(frozen=True)
class TrackRowSource:
    """The track rows of one direction (:func:`track_rows`), built for the sleepers a computation
    works on, so that no row set of the whole line is ever held. ``first``/``last``: per sleeper,
    the lowest and highest sleeper a row it owns may read (itself, the one before for a gauge
    change rate between neighbours, the valid samples each side of its bases' far ends)."""

    geometry: SleeperGeometry
    profile: ToleranceProfile
    direction: str
    step_m: float
    first: np.ndarray
    last: np.ndarray

    @classmethod
    def of(cls, geometry: SleeperGeometry, profile: ToleranceProfile, direction: str, step_m: float) -> TrackRowSource:
        station = geometry.station_m
        n = station.size
        first, last = np.arange(n), np.arange(n)
        for check, series in _based_series(geometry, profile, direction):
            if check.base_m is None:  # between neighbours
                first[1:] = np.minimum(first[1:], np.arange(n - 1))
                continue
            valid = np.flatnonzero(np.isfinite(series))
            if valid.size < 2:
                continue
            for sign in (-1.0, 1.0):
                right, left = _bracket(station[valid], station + sign * check.base_m)
                np.minimum(first, valid[left], out=first)
                np.maximum(last, valid[right], out=last)
        return cls(geometry, profile, direction, step_m, first, last)

    @property
    def sleepers(self) -> int:
        return self.first.size

    def owned(self, start: int, stop: int) -> TrackRows:
        """The rows owned by sleepers start..stop-1, in the whole line's order."""
        if start >= stop:
            return track_rows(self.geometry, self.profile, self.direction, self.step_m, (0, 0), (0, 0))
        extent = (int(self.first[start:stop].min()), int(self.last[start:stop].max()) + 1)
        return track_rows(self.geometry, self.profile, self.direction, self.step_m, extent, (start, stop))

    def touching(self, start: int, stop: int) -> TrackRows:
        """Every row that reads a sleeper of start..stop-1 (with the other rows of their owners),
        in the whole line's order."""
        owners = np.flatnonzero((self.first < stop) & (self.last >= start))
        if not owners.size:
            return self.owned(0, 0)
        return self.owned(int(owners[0]), int(owners[-1]) + 1)


# --------------------------------------------------------------------------- the programme

@dataclass(frozen=True)
class DirectionProblem:
    """Everything about one direction the programme needs (amounts in steps)."""

    deviation: np.ndarray  # (N, 2) steps, NaN where invalid
    valid: np.ndarray  # (N,) bool
    rows: TrackRowSource
    low: float  # fastener range [steps], whole numbers
    high: float
    step_m: float
    reference_right: np.ndarray | None  # (N,) bool: the rail that leads (guiding-rail-first practice), else None


@dataclass(frozen=True)
class _Rows:
    """Candidate rows: value = offset + sum(coefficients * amount[columns]) inside [lower, upper]
    (steps; columns rail-major over 2N). ``soft`` rows may exceed at a cost; ``rounded`` rows
    keep a margin for the rounding of their free amounts; ``key`` names the row within its family."""

    key: np.ndarray
    columns: np.ndarray  # (R, w)
    coefficients: np.ndarray  # (R, w)
    offset: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    soft: np.ndarray
    rounded: np.ndarray

    def take(self, selection: np.ndarray) -> _Rows:
        return _Rows(*(getattr(self, f)[selection] for f in
                       ("key", "columns", "coefficients", "offset", "lower", "upper", "soft", "rounded")))


class _ChordRows:
    """The rows of one chord check on one rail that the current amounts violate.

    A differential versine (chord m, pair p) has a row per point pair k and chord start i
    (i = k - (m - p) .. k, thesis eq. (2.2)): D(k) + S(i) with D(k) = x(k) - x(k+p) and
    S(i) = p/m (x(i+m) - x(i)) of x = deviation + amount. Of all chords holding a pair only the
    worst one (largest or smallest S, margin included) is proposed: the next round proposes the
    next one if the programme made it worse. A versine (back a, ahead b) has one row per sleeper.
    """

    def __init__(self, family: int, check: RailCheck, rail: int, deviation: np.ndarray, valid: np.ndarray, step: float):
        self.family, self.check, self.rail = family, check, rail
        self.n = deviation.shape[0]
        self.d = np.where(valid, deviation[:, rail], np.nan)
        self.limit = check.limit_m / step
        if check.kind == "differential_versine" and self.limit <= 1.0 + check.second_steps / check.first_steps:
            m, p = check.first_steps, check.second_steps
            raise ValueError(f"a {check.limit_m * 1e3:g} mm limit on a {m}/{p}-sleeper check leaves no room for "
                             f"{step * 1e3:g} mm fastener steps")

    @property
    def reach_steps(self) -> int:
        return self.check.reach_steps

    def violated(self, amounts: np.ndarray, half: np.ndarray, span: tuple[int, int]) -> _Rows | None:
        """Rows within sleepers span[0]..span[1]-1 whose value, widened by the rounding of their
        free amounts (``half``: 0.5 on free sleepers, 0 elsewhere), leaves the limit."""
        lo, hi = span
        d = self.d[lo:hi]
        x = d + amounts[lo:hi, self.rail]
        if self.check.kind == "differential_versine":
            rows = self._differential(d, x, half[lo:hi])
        else:
            rows = self._versine(d, x, half[lo:hi])
        if rows is None:
            return None
        k, second, offset, coefficients, high = rows
        if self.check.held is not None:  # the rows of values the survey cannot assess are not held
            keep = np.flatnonzero(self.check.held[k[0] + lo])
            if not keep.size:
                return None
            k, second, offset, high = tuple(c[keep] for c in k), second[keep], offset[keep], high[keep]
        columns = np.column_stack(k) + lo + self.rail * self.n
        key = (k[0] + lo) * self.n + second + lo
        return _Rows(2 * key + high, columns, np.broadcast_to(coefficients, columns.shape), offset,
                     np.where(high, -np.inf, -self.limit), np.where(high, self.limit, np.inf),
                     np.ones(high.size, bool), np.ones(high.size, bool))

    def _differential(self, d, x, half):
        """(columns' sleepers, chord start, offset, coefficients, upper side) of the violated rows."""
        n, m, p = x.size, self.check.first_steps, self.check.second_steps
        if n <= m:
            return None
        r = p / m
        slope, slope_margin = np.full(n, np.nan), np.zeros(n)
        slope[: n - m] = r * (x[m:] - x[: n - m])
        slope_margin[: n - m] = r * (half[m:] + half[: n - m])
        pair, pair_margin = np.full(n, np.nan), np.zeros(n)
        pair[: n - p] = x[: n - p] - x[p:]
        pair_margin[: n - p] = half[: n - p] + half[p:]
        chord_ok = np.isfinite(slope)
        width = m - p + 1
        found = []
        for high in (True, False):
            sign = 1.0 if high else -1.0
            widened = np.where(chord_ok, sign * slope + slope_margin, -np.inf)
            start = _trailing_argmax(widened, width)
            ok = (start >= 0) & np.isfinite(pair)
            ok[ok] &= chord_ok[start[ok]]
            value = np.full(n, -np.inf)
            value[ok] = sign * pair[ok] + pair_margin[ok] + widened[start[ok]]
            bad = np.flatnonzero(value > self.limit + TOLERANCE)
            found.append((bad, start[bad], np.full(bad.size, high)))
        k, i, high = (np.concatenate(parts) for parts in zip(*found))
        if not k.size:
            return None
        offset = d[k] - d[k + p] + r * (d[i + m] - d[i])
        return (k, k + p, i, i + m), i, offset, np.array([1.0, -1.0, -r, r]), high

    def _versine(self, d, x, half):
        a, b, n = self.check.first_steps, self.check.second_steps, x.size
        if self.limit <= 1.0 or n <= a + b:  # no room for the rounding: not held (as the assessment shows)
            return None
        wa, wb = a / (a + b), b / (a + b)
        k = np.arange(a, n - b)
        margin = half[k] + wb * half[k - a] + wa * half[k + b]
        with np.errstate(invalid="ignore"):
            value = x[k] - wb * x[k - a] - wa * x[k + b]
            high, low = value + margin > self.limit + TOLERANCE, value - margin < -self.limit - TOLERANCE
        bad = high | low
        if not bad.any():
            return None
        k = k[bad]
        offset = d[k] - wb * d[k - a] - wa * d[k + b]
        return (k, k - a, k + b), np.zeros(k.size, int), offset, np.array([1.0, -wb, -wa]), high[bad]


def _trailing_argmax(values: np.ndarray, width: int) -> np.ndarray:
    """Index of the largest of values[k - width + 1 .. k] for every k (-inf marks excluded entries)."""
    from insrail.track._windows import trailing_argmax  # compiled: imported when first needed

    return trailing_argmax(np.ascontiguousarray(values, dtype=float), int(width))


class _TrackRowFamily:
    """The track rows (:class:`TrackRows`) the current amounts put outside their limits; a soft
    row (already exceeding in the input) is proposed one side at a time, with its own cost."""

    def __init__(self, family: int, rows: TrackRows):
        self.family, self.rows = family, rows
        matrix = rows.matrix.tocsr()
        counts = np.diff(matrix.indptr)
        width = int(counts.max()) if counts.size else 0
        self.columns = np.zeros((matrix.shape[0], width), np.int64)
        self.coefficients = np.zeros((matrix.shape[0], width))
        row = np.repeat(np.arange(matrix.shape[0]), counts)
        position = np.arange(matrix.nnz) - np.repeat(matrix.indptr[:-1], counts)
        self.columns[row, position] = matrix.indices
        self.coefficients[row, position] = matrix.data

    reach_steps = 0  # rows are chosen by the sleepers they touch

    def violated(self, amounts: np.ndarray, half: np.ndarray, span: tuple[int, int]) -> _Rows | None:
        rows = self.rows
        if not rows.size:
            return None
        values = rows.values(amounts)
        high = values > rows.upper + 1e-7
        inside = (rows.last >= span[0]) & (rows.first < span[1])
        bad = np.flatnonzero(inside & (high | (values < rows.lower - 1e-7)))
        if not bad.size:
            return None
        soft, side = ~rows.hard[bad], high[bad]
        return _Rows(bad * 2 + (soft & side), self.columns[bad], self.coefficients[bad],
                     rows.value0[bad], np.where(soft & side, -np.inf, rows.lower[bad]),
                     np.where(soft & ~side, np.inf, rows.upper[bad]), soft, np.zeros(bad.size, bool))


#: HiGHS options of the programme: dual simplex (rows are added to a solved programme and it is
#: solved again from the last basis); no presolve, which would throw that basis away.
HIGHS_OPTIONS = {"output_flag": False, "solver": "simplex", "simplex_strategy": 1, "presolve": "off",
                 "simplex_dual_edge_weight_strategy": 0, "threads": 1}
#: HiGHS options of the integer programme of the action threshold (branch and bound; each solve
#: starts afresh, so presolve helps).
HIGHS_INTEGER_OPTIONS = {"output_flag": False, "solver": "choose", "presolve": "on", "threads": 1,
                         "mip_rel_gap": 0.02, "time_limit": 2.0}
MAX_ROUNDS = 200
#: Rounds of "solve the integer programme, add the rows it violates" before a window is given up.
MAX_INTEGER_ROUNDS = 40
#: Action-threshold windows, (before, after): the sleepers from ``before`` ahead of the first amount
#: below the threshold to ``after`` beyond it may change (each to 0 or at least the threshold); a
#: second pass centred on each amount the first one could not take out.
THRESHOLD_WINDOWS = ((6, 20), (16, 16))
#: How far [steps] beyond the threshold an amount may go from the one given (fewer choices: a fast search).
THRESHOLD_REACH = 1.0
#: The rows started with: those within this many thresholds (per free amount) of their limit.
THRESHOLD_SEED = 0.25


class _Programme:
    """The linear programme of the free sleepers of one direction in HiGHS: per free sleeper and
    rail an amount ``plus - minus`` (both >= 0, within the fastener's range, costing the
    movement), per soft row a slack (its excess, costing :data:`VIOLATION_PENALTY`), rows added
    as they are found violated."""

    def __init__(self, problem: DirectionProblem, amounts: np.ndarray, free: np.ndarray, threshold: float | None = None):
        import highspy._core as highspy_core

        # the bare solver: highspy.Highs (a wrapper of it) prints a banner on stdout when created
        self.highs = highspy_core._Highs()
        for key, value in (HIGHS_OPTIONS if threshold is None else HIGHS_INTEGER_OPTIONS).items():
            self.highs.setOptionValue(key, value)
        self.infinity = highspy_core.kHighsInf
        self.optimal = highspy_core.HighsModelStatus.kOptimal
        self.integer = threshold is not None
        self.integer_type = highspy_core.HighsVarType.kInteger
        n = free.size
        self.free_column = np.concatenate([free, free])
        columns = np.flatnonzero(self.free_column)
        self.columns, self.count = columns, columns.size
        self.variable = np.full(2 * n, -1)
        self.variable[columns] = np.arange(self.count)
        self.fixed = amounts.T.reshape(-1).copy()
        self.fixed[columns] = 0.0
        self.amounts = amounts
        self.variables = 0
        count = self.count
        if problem.reference_right is not None:
            leads = np.concatenate([~problem.reference_right, problem.reference_right])[columns]
            cost = np.where(leads, 1.0, FOLLOWER_COST)
        else:
            cost = np.ones(count)
        self._add_variables(np.concatenate([cost, cost]), np.zeros(2 * count),
                            np.concatenate([np.full(count, problem.high), np.full(count, -problem.low)]))
        if problem.reference_right is not None:  # |right - left|, the change of gauge or cross-level the follower takes
            sleepers = np.flatnonzero(free)
            size = sleepers.size
            up = self._add_variables(np.ones(size), np.zeros(size), np.full(size, np.inf))
            down = self._add_variables(np.ones(size), np.zeros(size), np.full(size, np.inf))
            left, right = self.variable[sleepers], self.variable[n + sleepers]
            index = np.column_stack([right, right + count, left, left + count, up, down])
            values = np.broadcast_to([1.0, -1.0, -1.0, 1.0, -1.0, 1.0], index.shape)
            self._add_rows(index, values, np.zeros(size), np.zeros(size))
        if threshold is not None:  # near the given amounts: the window's choices stay few
            given = amounts.T.reshape(-1)[columns]
            reach = threshold + THRESHOLD_REACH
            self._semi_integer(threshold, np.minimum(problem.high, np.maximum(given, 0.0) + reach),
                               np.minimum(-problem.low, np.maximum(-given, 0.0) + reach))

    def _semi_integer(self, threshold: float, plus_max: np.ndarray, minus_max: np.ndarray) -> None:
        """Whole steps, each amount 0 or at least ``threshold`` either way: plus and minus integer,
        each switched on by a binary (plus = 0 or threshold <= plus <= plus_max), never both on
        (else plus - minus could be a small net amount)."""
        count = self.count
        plus, minus = np.arange(count), count + np.arange(count)
        on_plus = self._add_variables(np.zeros(count), np.zeros(count), np.ones(count))
        on_minus = self._add_variables(np.zeros(count), np.zeros(count), np.ones(count))
        columns = np.concatenate([plus, minus, on_plus, on_minus]).astype(np.int32)
        self.highs.changeColsIntegrality(columns.size, columns,
                                         np.full(columns.size, self.integer_type))
        for amount, on, most in ((plus, on_plus, plus_max), (minus, on_minus, minus_max)):
            index = np.column_stack([amount, on])
            self._add_rows(index, np.broadcast_to([1.0, -threshold], index.shape), np.zeros(count),
                           np.full(count, np.inf))
            self._add_rows(index, np.column_stack([np.ones(count), -most]), np.full(count, -np.inf), np.zeros(count))
        index = np.column_stack([on_plus, on_minus])
        self._add_rows(index, np.ones(index.shape), np.full(count, -np.inf), np.ones(count))

    def _add_variables(self, cost, lower, upper) -> np.ndarray:
        size = cost.size
        index = self.variables + np.arange(size)
        if size:
            self.highs.addVars(size, np.clip(lower, -self.infinity, self.infinity),
                               np.clip(upper, -self.infinity, self.infinity))
            self.highs.changeColsCost(size, index.astype(np.int32), np.asarray(cost, float))
        self.variables += size
        return index

    def _add_rows(self, index: np.ndarray, values: np.ndarray, lower: np.ndarray, upper: np.ndarray) -> None:
        """Rows over (R, w) variable indices (-1: none); duplicates within a row are summed.

        Written row-wise as scipy's canonical CSR would be (each row's variables ascending, one
        entry per variable), from the (R, w) arrays directly: a scipy matrix per call (its checks
        and conversions) took a quarter of the adding's time."""
        count = index.shape[0]
        values = np.broadcast_to(np.asarray(values, dtype=float), index.shape)
        order = np.argsort(np.where(index >= 0, index, self.variables), axis=1, kind="stable")  # the unused last
        index, values = np.take_along_axis(index, order, axis=1), np.take_along_axis(values, order, axis=1)
        keep = index >= 0
        first = keep.copy()  # the first entry of each variable in its row
        first[:, 1:] &= index[:, 1:] != index[:, :-1]
        entry = np.cumsum(first[keep]) - 1  # the entry each kept value adds to
        data = np.bincount(entry, weights=values[keep]) if entry.size else np.zeros(0)
        starts = np.zeros(count, np.int32)
        np.cumsum(first.sum(axis=1)[:-1], out=starts[1:])
        status = self.highs.addRows(count, np.clip(lower, -self.infinity, self.infinity),
                                    np.clip(upper, -self.infinity, self.infinity), data.size, starts,
                                    index[first].astype(np.int32), data)
        if status != type(status).kOk:
            raise RuntimeError(f"adjustment optimisation: HiGHS refused rows ({status})")

    def add(self, rows: _Rows) -> None:
        coefficients = np.asarray(rows.coefficients)
        on_free = self.free_column[rows.columns] & (coefficients != 0)
        constant = rows.offset + (coefficients * self.fixed[rows.columns]).sum(axis=1)
        margin = np.where(rows.rounded, 0.5 * (np.abs(coefficients) * on_free).sum(axis=1), 0.0)
        lower, upper = rows.lower - constant + margin, rows.upper - constant - margin
        slack = np.full(rows.key.size, -1)
        soft = np.flatnonzero(rows.soft)
        slack[soft] = self._add_variables(np.full(soft.size, VIOLATION_PENALTY), np.zeros(soft.size),
                                          np.full(soft.size, np.inf))
        variable = np.where(on_free, self.variable[rows.columns], -1)
        # a soft row is one-sided: value - slack <= upper, or value + slack >= lower
        sign = np.where(np.isfinite(upper), -1.0, 1.0)
        index = np.concatenate([variable, np.where(on_free, variable + self.count, -1), slack[:, None]], axis=1)
        values = np.concatenate([coefficients, -coefficients, sign[:, None]], axis=1)
        self._add_rows(index, values, lower, upper)

    def solve(self) -> np.ndarray | None:
        """The amounts [steps] (N, 2): the programme's on free sleepers, the given ones elsewhere.
        An integer programme that has no solution (or found none in its time) gives None."""
        self.highs.run()
        status = self.highs.getModelStatus()
        if self.integer:
            if self.highs.getInfo().primal_solution_status != 2:  # no feasible solution
                return None
        elif status != self.optimal:
            raise RuntimeError(f"adjustment optimisation failed: {self.highs.modelStatusToString(status)}")
        # the amounts' columns only (a list of Python floats: the slacks' would cost as much again)
        x = np.asarray(self.highs.getSolution().col_value[: 2 * self.count])
        flat = self.amounts.T.reshape(-1).copy()
        flat[self.columns] = x[: self.count] - x[self.count: 2 * self.count]
        if self.integer:
            flat[self.columns] = np.round(flat[self.columns])
        return flat.reshape(2, -1).T


def _chord_families(problem: DirectionProblem, checks: list[RailCheck]) -> list:
    return [_ChordRows(index, check, rail, problem.deviation, problem.valid, problem.step_m)
            for index, (check, rail) in enumerate((c, r) for c in checks for r in (0, 1))]


def _with_track_rows(problem: DirectionProblem, chord: list, free: np.ndarray) -> list:
    """The chord families and the track rows that read a sleeper of the ``free`` ones' range."""
    sleepers = np.flatnonzero(free)
    return [*chord, _TrackRowFamily(len(chord), problem.rows.touching(int(sleepers[0]), int(sleepers[-1]) + 1))]


class _Generation:
    """Rows entering a programme as amounts violate them: each row holding a free amount once.

    With ``reference`` amounts (the integer programme of the action threshold) no row keeps a
    rounding margin, and a row those amounts hold is hard: the new amounts may not break it."""

    def __init__(self, programme: _Programme, families: list, free: np.ndarray, reference: np.ndarray | None = None):
        self.programme, self.families = programme, families
        sleepers = np.flatnonzero(free)
        # the rows that hold a free sleeper lie within one reach of the free ones
        self.spans = [(max(0, sleepers[0] - f.reach_steps), min(free.size, sleepers[-1] + f.reach_steps + 1))
                      for f in families]
        self.reference = None if reference is None else reference.T.reshape(-1)
        self.known: set[int] = set()  # a set: np.isin against the keys so far sorted them at every look-up

    def add(self, current: np.ndarray, half: np.ndarray) -> int:
        """Add the new rows that ``current``, widened by ``half`` a step per free amount, violates;
        how many."""
        free_column = self.programme.free_column
        added = 0
        for family, span in zip(self.families, self.spans):
            rows = family.violated(current, half, span)
            if rows is None:
                continue
            key = rows.key * len(self.families) + family.family  # unique over the families
            fresh = (free_column[rows.columns] & (np.asarray(rows.coefficients) != 0)).any(axis=1)
            fresh &= np.fromiter((k not in self.known for k in key.tolist()), bool, key.size)
            if not fresh.any():
                continue
            new = rows.take(np.flatnonzero(fresh))
            if self.reference is not None:
                value = new.offset + (np.asarray(new.coefficients) * self.reference[new.columns]).sum(axis=1)
                held = (value >= new.lower - 1e-7) & (value <= new.upper + 1e-7)
                new = replace(new, soft=new.soft & ~held, rounded=np.zeros(new.key.size, bool))
            self.known.update(key[fresh].tolist())
            self.programme.add(new)
            added += new.key.size
        return added


def solve_free(problem: DirectionProblem, amounts: np.ndarray, free: np.ndarray, checks: list[RailCheck],
               progress=None, cancel=None) -> np.ndarray:
    """Continuous amounts [steps] (N, 2): the ``free`` sleepers' least movement holding every
    chord check of both rails and every track row; the other sleepers keep ``amounts``.

    Constraint generation: the programme starts with the rows the current amounts violate and
    is solved; rows the solution violates are added and it is solved again from the last basis,
    until none is violated. Of the hundreds of thousands of rows (every chord placement of every
    check, every track row) a few per sleeper ever enter the programme. Rows of chord checks keep
    a margin of half a step per free amount they hold, so that the rounding to whole steps never
    takes them past their limit; ``cancel`` is checked between rounds."""
    free = free & problem.valid
    if not free.any():
        return amounts.copy()
    programme = _Programme(problem, amounts, free)
    generation = _Generation(programme, _with_track_rows(problem, _chord_families(problem, checks), free), free)
    half = np.where(free, 0.5, 0.0)
    current = amounts
    first = None
    for _ in range(MAX_ROUNDS):
        check_cancel(cancel)
        added = generation.add(current, half)
        if not added:
            return current
        first = first or added
        if progress is not None:
            progress(max(0.0, 1.0 - added / first), "adjustment amounts")
        current = programme.solve()
    raise RuntimeError("adjustment optimisation: the rows did not settle")


def below_threshold(amounts: np.ndarray, threshold: float) -> np.ndarray:
    """(N, 2) amounts [steps] that are not 0 but smaller than ``threshold`` steps."""
    size = np.abs(amounts)
    return (size > 0.5) & (size < threshold - 0.5)


def apply_threshold(problem: DirectionProblem, amounts: np.ndarray, checks: list[RailCheck], threshold: float,
                    cancel=None, progress=None) -> np.ndarray:
    """Whole-step amounts [steps] each 0 or at least ``threshold`` steps either way, where that
    holds every check the given ``amounts`` hold.

    Window after window from the first amount below the threshold (:data:`THRESHOLD_WINDOWS`:
    a few sleepers before it to a few after it), the window's amounts are chosen
    again by an integer programme (each plus and minus part 0 or at least the threshold, the
    least movement): every chord and track row the given amounts hold stays held, the rows
    they exceed may not get worse than their penalty allows; rows enter as the solution violates
    them (started with those within the threshold of their limit). Where no such choice exists
    or none is found in time, the window keeps its amounts, small ones included (the caller
    counts them); a second pass tries each of those again in a window centred on it."""
    if threshold <= 1.0 + TOLERANCE or not below_threshold(amounts, threshold).any():
        return amounts
    chord = _chord_families(problem, checks)
    n = amounts.shape[0]
    for second, (before, after) in enumerate(THRESHOLD_WINDOWS):
        position = 0
        while True:
            small = np.flatnonzero(below_threshold(amounts, threshold).any(axis=1))
            small = small[small >= position]
            if not small.size:
                break
            start, stop = max(0, small[0] - before), min(n, small[0] + after)
            free = np.zeros(n, bool)
            free[start:stop] = problem.valid[start:stop]
            solved = _integer_window(problem, amounts, free, _with_track_rows(problem, chord, free), threshold, cancel)
            if solved is not None:
                amounts = solved
            position = small[0] + 1 if second and solved is None else stop
            if progress is not None:
                progress((second + position / n) / len(THRESHOLD_WINDOWS), "action threshold")
    return amounts


def _integer_window(problem: DirectionProblem, amounts: np.ndarray, free: np.ndarray, families: list,
                    threshold: float, cancel) -> np.ndarray | None:
    programme = _Programme(problem, amounts, free, threshold)
    generation = _Generation(programme, families, free, reference=amounts)
    generation.add(amounts, np.where(free, THRESHOLD_SEED * threshold, 0.0))  # the rows near their limit
    nothing = np.zeros(free.size)
    for _ in range(MAX_INTEGER_ROUNDS):
        check_cancel(cancel)
        current = programme.solve()
        if current is None:
            return None
        if not generation.add(current, nothing):
            return current
    return None


def round_amounts(continuous: np.ndarray, low: float, high: float, valid: np.ndarray) -> np.ndarray:
    """Whole steps inside the range; invalid sleepers 0."""
    return np.where(valid[:, None], np.clip(np.round(continuous), low, high), 0.0)


def repair_rounding(problem: DirectionProblem, amounts: np.ndarray, continuous: np.ndarray,
                    changed: tuple[int, int]) -> np.ndarray:
    """Amounts [steps] holding every hard track row, where they held them all before sleepers
    changed[0]..changed[1]-1 changed: around each row the rounding broke, the
    sleepers' amounts are chosen again among the whole steps next to the continuous solution
    (an integer programme over a few sleepers, least distance to it). Where no such choice
    exists the sleepers stay unmoved in this direction, which holds their rows by construction;
    that is repeated (the region grows) until no hard row is broken. Only the rows reading the
    sleepers changed so far are built (the others cannot break)."""
    start, stop = changed
    rows = problem.rows.touching(start, stop)
    amounts = amounts.copy()
    total = amounts.shape[0]
    for _ in range(200):
        while True:
            broken = np.flatnonzero(rows.broken(amounts))
            if not broken.size:
                return amounts
            sleepers = np.unique(rows.matrix[broken].tocoo().col % total)
            region = np.unique(np.clip(sleepers[:, None] + np.arange(-REPAIR_PAD, REPAIR_PAD + 1), 0, total - 1))
            if start <= region[0] and region[-1] < stop:
                break
            start, stop = min(start, int(region[0])), max(stop, int(region[-1]) + 1)  # the region may change
            rows = problem.rows.touching(start, stop)
        region = region[problem.valid[region]]
        choice = _integer_choice(problem, rows, amounts, continuous, region)
        if choice is None:
            amounts[sleepers] = 0.0
        else:
            amounts[region] = choice
    amounts[:] = 0.0  # cannot happen in practice; unmoved track breaks no hard row
    return amounts


def _integer_choice(problem: DirectionProblem, rows: TrackRows, amounts: np.ndarray, continuous: np.ndarray,
                    region: np.ndarray) -> np.ndarray | None:
    from scipy import sparse
    from scipy.optimize import Bounds, LinearConstraint, milp

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
