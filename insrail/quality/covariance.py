"""Covariance-only filter and RTS smoother, with the cross-covariances behind lag differences.

The accuracy of track geometry measured by an aided INS is set less by the absolute
position error than by how that error changes along the track: a 30 m/5 m check sees
e(s + 5 m) - e(s), a 300 m/150 m check e(s + 150 m) - e(s). For a pair of update
epochs j < k with projection rows u_j, u_k (lateral or vertical, 1 x 3 on the position
error),

    Var[u_k e_k - u_j e_j] = u_k P_k u_k^T + u_j P_j u_j^T - 2 u_k C(k, j) u_j^T,
    C(k, j) = Cov(e_k, e_j).

This module runs the error-state Kalman filter in covariance-only form along a timeline
(the transition Phi and noise Q of every segment and the (H, R) of every measurement
applied at its end) and evaluates C(k, j) exactly for chosen pairs, without Monte Carlo.

Forward filter. The post-update error obeys e_k = (I - K_k H_k) (Phi_k e_{k-1} + w_k)
- K_k v_k; with several measurements applied one after the other at the same epoch the
factor is the product of their (I - K H). The noises after j are independent of e_j, so

    C(k, j) = M_k M_{k-1} ... M_{j+1} P_j,   M_i = (I - K_i H_i) Phi_i.

Only the columns u_j^T are needed: D_j = P_j[:, pos] u_j^T (N x 1) is pushed forward with
D_i = M_i D_{i-1} until epoch k, where u_k D_k[pos] is the cross term. All pairs alive at
an epoch are stacked as columns of one matrix, so an epoch costs one N x N by N x n_pairs
product.

RTS smoother. With A_j = P+_j Phi_{j+1}^T (P-_{j+1})^-1 the smoothed estimate is
x_j|N = x_j|j + A_j (x_j+1|N - x_j+1|j), hence the smoothed error

    e_j|N = [e_j|j - A_j e_j+1|j] + A_j e_j+1|N .

The bracket equals x_j - E[x_j | x_j+1, Y_j] (Gauss-Markov: A_j is the regression of
x_j on x_j+1 given the data up to j). It is orthogonal to x_j+1 and Y_j by construction
and to all later process and measurement noise by independence, so it is orthogonal to
every e_k|N with k > j (a linear function of x_k and Y_N). Therefore

    P_j,k|N = Cov(e_j|N, e_k|N) = A_j P_j+1,k|N = A_j A_j+1 ... A_k-1 P_k|N .

The backward pass pushes D = P_k|N[:, pos] u_k^T from epoch k back to j with D <- A_i D, the columns
of all pairs alive at once through the product A_i ... A_t-1 since a checkpoint t (``CHECKPOINT_EPOCHS``):
the same sums in another order (some 1e-13 of a lag difference's 1-sigma).
It reads Phi, P- and P+ of every epoch back from a disk record the forward pass wrote
(as the fusion's own smoother does), so the models are evaluated once per epoch.
``analyse_recorded`` runs the backward pass alone over the record the fusion itself wrote
(``insrail.nav.fusion.SmootherStore``): no replay of the models at all.
tests/test_quality_covariance.py checks both recursions against the exact covariance of
the stacked (augmented) state of a small linear system.

The covariances are the ones the real fusion computes: the closed-loop resets of
``insrail.nav.fusion`` change the estimate, not P, K or A. What this module assumes is
that the filter's model is the truth (the Monte Carlo in benchmarks/predict.py checks
that assumption against the simulator).
"""

from __future__ import annotations

import functools
import itertools
import tempfile
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from insrail import jit
from insrail.jit import cached_njit
from insrail.nav.error_model import ATT, POS
from insrail.nav import _kernels, kalman
from insrail.nav.kalman import inflate, solve_transposed
from insrail.progress import CancelToken, ProgressFn, StepProgress, check_cancel

#: One segment of the timeline: (Phi, Q, [(H, R), ...]) from the previous update epoch to this one.
Segment = tuple[np.ndarray, np.ndarray, Sequence[tuple[np.ndarray, np.ndarray]]]
#: a segment may carry a fourth element, a filter reset on it: (states, 1-sigma floor) as
#: ``insrail.nav.kalman.inflate`` applies it to P- (the replay then widens P where the filter did)


@dataclass(frozen=True)
class LagDifference:
    """1-sigma of u e(s + lag) - u e(s) for pairs of update epochs (j, k)."""

    lag_m: float
    first_epoch: np.ndarray  # j
    second_epoch: np.ndarray  # k, the first epoch at least lag_m further along the track
    station_m: np.ndarray  # station of the first point
    sigma_lateral_m: np.ndarray
    sigma_vertical_m: np.ndarray


@dataclass(frozen=True)
class PassCovariance:
    """Per update epoch 1-sigma of the lateral and vertical position and the roll error,
    and the lag differences, and the along-track position's 1-sigma, of one pass (forward filter or smoother)."""

    sigma_lateral_m: np.ndarray
    sigma_vertical_m: np.ndarray
    sigma_roll_rad: np.ndarray
    lags: tuple[LagDifference, ...]
    sigma_along_track_m: np.ndarray

    def lag(self, lag_m: float) -> LagDifference:
        for item in self.lags:
            if item.lag_m == lag_m:
                return item
        raise KeyError(f"no lag difference of {lag_m} m was computed")


@dataclass(frozen=True)
class CovarianceProfile:
    time_s: np.ndarray
    station_m: np.ndarray
    forward: PassCovariance
    smoothed: PassCovariance | None


#: Epochs of the backward pass per call of its kernel: a record's part is unpacked (Phi, P-, P+: 15 kB per
#: epoch, ~4 MB) and projected at a time (a whole record block of 2048 epochs took 30 MB more).
SMOOTH_PART_EPOCHS = 256

#: The backward pass pushes the columns of the pairs alive (some 300 on a 150 m lag) one epoch on, D <- A_i D:
#: N^2 each. It pushes instead the product of the gains since a checkpoint (N^3: some 25 columns' worth), the
#: columns seeded since one by one, and every column through the product at the checkpoint, this many epochs on.
CHECKPOINT_EPOCHS = 32

#: the figures per epoch, in this order: lateral and vertical position, roll (on the attitude error),
#: along-track position
N_PROJECTIONS = 4
_ROLL = 2


def projections(heading_rad: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Rows picking lateral (positive right), vertical (positive up) position error, roll error and
    along-track position error (positive forward) out of the NED position and attitude errors, per
    epoch: (m, 3) each (N_PROJECTIONS of them; the roll's on the attitude error)."""
    s, c = np.sin(heading_rad), np.cos(heading_rad)
    z = np.zeros_like(s)
    forward = np.column_stack([c, s, z])
    return np.column_stack([-s, c, z]), np.column_stack([z, z, z - 1.0]), forward, forward


def lag_pairs(station_m: np.ndarray, anchors: np.ndarray, lag_m: float) -> tuple[np.ndarray, np.ndarray]:
    """(j, k): k is the first epoch whose station is at least ``lag_m`` beyond epoch j's."""
    k = np.searchsorted(station_m, station_m[anchors] + lag_m - 1e-9)
    keep = k < len(station_m)
    return anchors[keep], k[keep]


class _Plan:
    """The lag pairs of an analysis and the projections that turn covariances into figures.
    Pair p of lag l is two columns of the pushed matrix D: lateral, then vertical."""

    def __init__(self, n: int, m: int, station_m, heading_rad, anchors, lags_m):
        self.n, self.m = n, m
        self.heading_rad = np.asarray(heading_rad, dtype=float)
        self.pairs = [lag_pairs(station_m, np.asarray(anchors), lag) for lag in lags_m]
        self.first = np.concatenate([j for j, _ in self.pairs]).astype(int)
        self.second = np.concatenate([k for _, k in self.pairs]).astype(int)
        self.n_pairs = len(self.first)

    # the projections of every epoch and the pairs per epoch as dicts: the replay's forward filter
    # only (the backward pass makes the projections of a block at a time and takes the pairs in CSR form)
    @functools.cached_property
    def _projections(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return projections(self.heading_rad)

    u_lat = property(lambda self: self._projections[0])
    u_ver = property(lambda self: self._projections[1])

    @functools.cached_property
    def starts_at(self) -> dict[int, np.ndarray]:
        return _group(self.first, self.m)

    @functools.cached_property
    def ends_at(self) -> dict[int, np.ndarray]:
        return _group(self.second, self.m)

    def project(self, P, i):
        """Lateral and vertical position variance, roll variance and along-track position variance at epoch i."""
        pos = P[POS : POS + 3, POS : POS + 3]
        att = P[ATT : ATT + 3, ATT : ATT + 3]
        u = self._projections
        return tuple(u[r][i] @ (att if r == _ROLL else pos) @ u[r][i] for r in range(N_PROJECTIONS))

    def seeds(self, P, i, idx):
        """Columns P[:, pos] u^T for lateral and vertical, interleaved per pair."""
        cols = np.empty((self.n, 2 * len(idx)))
        cols[:, 0::2] = (P[:, POS : POS + 3] @ self.u_lat[i])[:, None]
        cols[:, 1::2] = (P[:, POS : POS + 3] @ self.u_ver[i])[:, None]
        return cols

    def read(self, D, i, idx_cols):
        pos = D[POS : POS + 3]
        return np.column_stack([self.u_lat[i] @ pos[:, idx_cols[0::2]], self.u_ver[i] @ pos[:, idx_cols[1::2]]])


def analyse(
    P0: np.ndarray,
    segment: Callable[[int], Segment],
    time_s: np.ndarray,
    station_m: np.ndarray,
    heading_rad: np.ndarray,
    anchors: np.ndarray,
    lags_m: Sequence[float],
    smoother: bool = True,
    forward_lags: bool = True,
    progress: ProgressFn | None = None,
    cancel: CancelToken = None,
) -> CovarianceProfile:
    """Covariance-only forward filter (and RTS smoother) over update epochs 0..m-1.

    segment(j) for j = 1..m-1 gives Phi, Q of epochs j-1 -> j and the measurements applied
    at j, in the order the filter applies them; it is asked once per epoch. ``station_m``
    must not decrease; ``anchors`` are the epochs whose lag differences are wanted (e.g.
    one per metre). ``forward_lags=False`` skips the forward filter's lag differences
    (its ``lags`` are then empty) when only the smoother's are wanted.
    """
    m = len(time_s)
    n = P0.shape[0]
    plan = _Plan(n, m, station_m, heading_rad, anchors, lags_m)
    step = StepProgress(progress)
    forward_progress = step.sub(0.0, 0.7 if smoother else 1.0)

    var_f = np.empty((m, N_PROJECTIONS))
    cross_f = np.empty((plan.n_pairs, 2))
    # The backward pass needs Phi, P- and P+ of every epoch: written to disk as they come.
    record = _ReverseStore(3 * n * n) if smoother else None

    try:
        active = _ActivePairs(n)
        P = P0.copy()
        var_f[0] = plan.project(P, 0)
        if record is not None:
            record.append(np.concatenate([np.eye(n).ravel(), P0.ravel(), P0.ravel()]))
        if forward_lags:
            active.add(plan.starts_at.get(0, ()), plan.seeds(P, 0, plan.starts_at.get(0, ())))
        for j in range(1, m):
            if j % 2000 == 0:
                check_cancel(cancel)
                forward_progress(j / m, "covariance: forward filter")
            phi, q, updates, *reset = segment(j)
            P_minus = phi @ P @ phi.T + q
            if reset:
                P_minus = inflate(P_minus, *reset[0])
            P = P_minus
            M = phi if forward_lags else None
            for H, R in updates:
                HP = H @ P
                S = HP @ H.T + R
                K = np.linalg.solve(S, HP).T
                # (I - KH) P with the optimal gain equals the fusion's Joseph form
                P = P - K @ HP
                if M is not None:
                    M = M - K @ (H @ M)
            P = 0.5 * (P + P.T)
            if record is not None:
                record.append(np.concatenate([phi.ravel(), P_minus.ravel(), P.ravel()]))
            var_f[j] = plan.project(P, j)
            if M is not None:
                active.apply(M)
                done = plan.ends_at.get(j, ())
                if len(done):
                    cross_f[done] = plan.read(active.columns, j, active.take(done))
                    active.remove(done)
                new = plan.starts_at.get(j, ())
                if len(new):
                    active.add(new, plan.seeds(P, j, new))

        forward = _pass(var_f, cross_f, plan.pairs if forward_lags else [], lags_m if forward_lags else [], station_m)
        smoothed = None
        if record is not None:
            var_s, cross_s = _smooth(plan, record.reversed_blocks(n), m, step.sub(0.7, 1.0), cancel)
            smoothed = _pass(var_s, cross_s, plan.pairs, lags_m, station_m)
    finally:
        if record is not None:
            record.close()
    step(1.0, "covariance analysis done")
    return CovarianceProfile(np.asarray(time_s), np.asarray(station_m), forward, smoothed)


def analyse_recorded(
    P0: np.ndarray,
    blocks: Iterable[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]],
    time_s: np.ndarray,
    station_m: np.ndarray,
    heading_rad: np.ndarray,
    anchors: np.ndarray,
    lags_m: Sequence[float],
    progress: ProgressFn | None = None,
    cancel: CancelToken = None,
) -> CovarianceProfile:
    """The RTS smoother's figures from a forward pass recorded by the filter itself (the
    fusion's :class:`insrail.nav.fusion.SmootherStore`) instead of a replay: only the
    backward pass runs. ``blocks`` yields consecutive blocks (j, Phi_j, P-_j, P+_j) as arrays
    (k,), (k, n, n) x 3, j decreasing, from m-1 down to 1 (``SmootherStore.reversed_blocks``);
    epoch 0 has the covariance P0. The forward figures (from the recorded P+) carry no lag
    differences: those need the filter's gains, which the record does not hold."""
    m = len(time_s)
    n = P0.shape[0]
    plan = _Plan(n, m, station_m, heading_rad, anchors, lags_m)
    step = StepProgress(progress)
    var_f = np.empty((m, N_PROJECTIONS))
    last = (np.zeros(1, dtype=np.int64), np.eye(n)[None], P0[None], P0[None])
    var_s, cross_s = _smooth(plan, itertools.chain(blocks, [last]), m, step, cancel, var_f)
    step(1.0, "covariance analysis done")
    forward = _pass(var_f, np.empty((0, 2)), [], [], station_m)
    smoothed = _pass(var_s, cross_s, plan.pairs, lags_m, station_m)
    return CovarianceProfile(np.asarray(time_s), np.asarray(station_m), forward, smoothed)


def _smooth(plan: _Plan, blocks, m, progress, cancel, var_forward: np.ndarray | None = None):
    """The RTS backward pass over blocks of consecutive epochs (j, Phi_j, P-_j, P+_j) as arrays
    ((k,), (k, n, n) x 3), j decreasing from m-1 down to 0: smoothed variances and the cross terms
    of every pair; ``var_forward`` (m, N_PROJECTIONS), when given, receives the filtered variances of the
    same epochs.

    Per part of a block (:data:`SMOOTH_PART_EPOCHS`) the compiled :func:`_backward_chunk`: the gains A_j
    and the recursion itself (P_s, the pushed columns, the pairs starting and ending at each epoch), so
    no Python runs per epoch."""
    n = plan.n
    var_s = np.empty((m, N_PROJECTIONS))
    cross_s = np.empty((plan.n_pairs, 2))
    var_f = var_forward if var_forward is not None else np.empty((m, N_PROJECTIONS))
    state = _BackwardState(n, plan.n_pairs)
    starts = _csr(plan.first.astype(np.int64, copy=False), m)
    ends = _csr(plan.second.astype(np.int64, copy=False), m)
    expected = m - 1
    for block in blocks:
        js = np.asarray(block[0], dtype=np.int64)
        due = np.arange(expected, expected - len(js), -1)
        if np.any(js != due):
            i = int(np.flatnonzero(js != due)[0])
            raise ValueError(f"the covariance record gives epoch {js[i]} where epoch {due[i]} was due")
        expected -= len(js)
        check_cancel(cancel)
        progress((m - 1 - expected) / m, "covariance: smoother")
        # a block by parts of SMOOTH_PART_EPOCHS (a part's projections at a time), the block itself let go
        # before the next one is read
        for first in range(0, len(js), SMOOTH_PART_EPOCHS):
            part = slice(first, first + SMOOTH_PART_EPOCHS)
            _smooth_part(plan, js[part], block[1][part], block[2][part], block[3][part], state, starts, ends, var_s,
                         var_f, cross_s)
        del block
    if expected != -1:
        raise ValueError(f"the covariance record ends at epoch {expected + 1}, not at epoch 0")
    return var_s, cross_s


def _smooth_part(plan: _Plan, js, phi, p_minus, p_plus, state: _BackwardState, starts, ends, var_s, var_f, cross_s):
    """:func:`_backward_chunk` over consecutive epochs ``js`` (decreasing) with their Phi, P- and P+;
    ``state`` carries Phi and P- of the epoch after the first one from the part before."""
    low = int(js[-1])  # the part's projections, epochs low..js[0]
    u = np.stack(projections(plan.heading_rad[low : js[0] + 1]))  # (N_PROJECTIONS, k, 3)
    _backward_chunk(js, low, phi, p_minus, p_plus, state.phi_next, state.p_minus_next, 0 if state.started else 1, u,
                    POS, ATT, *starts, *ends, state.P_s, state.product, state.columns, state.young, state.slot_of,
                    state.pair_of_slot, state.pair_of_young, state.active, CHECKPOINT_EPOCHS, var_s, var_f, cross_s)
    state.started = True


def _csr(epochs: np.ndarray, m: int) -> tuple[np.ndarray, np.ndarray]:
    """Pairs by epoch: the pairs of epoch e are ``index[pointer[e]:pointer[e + 1]]`` (stable order)."""
    order = np.argsort(epochs, kind="stable").astype(np.int64)
    pointer = np.searchsorted(epochs[order], np.arange(m + 1)).astype(np.int64)
    return pointer, order


class _BackwardState:
    """What the backward recursion carries from one chunk to the next: the smoothed covariance,
    the pushed columns of the active pairs and Phi and P- of the last chunk's first epoch (the gain of
    the epoch before needs them); ``started`` once the survey's last epoch is smoothed.

    The columns lie in two sets (:data:`CHECKPOINT_EPOCHS`), each slot s two rows, 2 s lateral and
    2 s + 1 vertical: ``columns`` as they were at the last checkpoint, their value now ``product``
    (A_i ... A_t-1 since checkpoint t) times them, and ``young``, those seeded since, as they are now.
    ``slot_of[pair]`` is s in the first set and -1 - s in the second; ``active``: the slots in use in
    each and the epochs since the checkpoint."""

    def __init__(self, n: int, n_pairs: int):
        self.started = False
        self.phi_next, self.p_minus_next = np.zeros((n, n)), np.zeros((n, n))
        self.P_s = np.zeros((n, n))
        self.product = np.eye(n)
        self.columns, self.young = np.zeros((2 * max(n_pairs, 1), n)), np.zeros((2 * max(n_pairs, 1), n))
        self.slot_of = np.full(max(n_pairs, 1), -1, dtype=np.int64)
        self.pair_of_slot, self.pair_of_young = (np.full(max(n_pairs, 1), -1, dtype=np.int64) for _ in range(2))
        self.active = np.zeros(3, dtype=np.int64)


@cached_njit(nogil=True)  # touches no Python object: runs beside the caller's thread
def _project(out, P, u, j, low, pos, att):  # pragma: no cover - compiled
    """out[j] = lateral and vertical position variance, roll variance and along-track position
    variance of P at epoch j (projections ``u`` from epoch ``low`` on)."""
    for r in range(u.shape[0]):
        block = att if r == 2 else pos
        total = 0.0
        for p in range(3):
            for q in range(3):
                total += u[r, j - low, p] * P[block + p, block + q] * u[r, j - low, q]
        out[j, r] = total


@cached_njit(nogil=True)  # touches no Python object: runs beside the caller's thread
def _gain(phi_next, p_minus_next, p_plus):  # pragma: no cover - compiled
    """The smoother gain A = P+ Phi^T (P-)^-1 (Phi and P- of the epoch after), C-ordered: solved as
    (P-)^-1 Phi P+ and transposed (the numbers of numpy's own solve and product, to the bit)."""
    rhs = np.ascontiguousarray(phi_next) @ np.ascontiguousarray(p_plus)
    n = rhs.shape[0]
    a_t = np.empty((n, n))
    gain = np.empty((n, n))  # the solution's transpose: A
    for i in range(n):
        for j in range(n):
            a_t[i, j] = p_minus_next[j, i]
            gain[i, j] = rhs[j, i]
    solve_transposed(a_t, gain)
    return gain


@cached_njit(nogil=True)  # touches no Python object: runs beside the caller's thread
def _drop(rows, slot_of, pair_of_slot, active, which, slot, code):  # pragma: no cover - compiled
    """Slot ``slot`` of a set of pushed columns (``active[which]`` slots in use) freed: the set's last slot
    moved into it, its pair's ``slot_of`` set to ``code`` (the freed slot as ``slot_of`` tells it)."""
    last = active[which] - 1
    if slot != last:
        jit.copy_rows(rows[2 * last : 2 * last + 2], rows[2 * slot : 2 * slot + 2])
        moved = pair_of_slot[last]
        slot_of[moved] = code
        pair_of_slot[slot] = moved
    active[which] = last


@cached_njit(nogil=True)  # touches no Python object: runs beside the caller's thread
def _backward_chunk(js, low, phi, p_minus, p_plus, phi_next, p_minus_next, first, u, pos, att, starts_ptr, starts_idx,
                    ends_ptr, ends_idx, P_s, product, columns, young, slot_of, pair_of_slot, pair_of_young, active,
                    checkpoint, var_s, var_f, cross_s):  # pragma: no cover - compiled
    """The RTS recursion over one chunk of epochs (see :func:`_smooth`) with Phi, P- and P+ of each;
    ``phi_next``, ``p_minus_next``: those of the epoch after the chunk's first one (unused when ``first``
    = 1: the chunk starts with the last epoch of the survey, P_s = P+ there), left holding those of the
    chunk's last epoch for the chunk that follows. The gains are made here, one epoch at a time: no
    batch of them (20 kB per epoch with its temporaries) is held or faulted in. The columns are brought
    to the current epoch every ``checkpoint`` epochs (:class:`_BackwardState`)."""
    n = P_s.shape[0]
    for e in range(len(js)):
        j = js[e]
        if e < first:
            jit.copy_rows(p_plus[e], P_s)
        else:
            if e == 0:
                a = _gain(phi_next, p_minus_next, p_plus[e])
                before = p_minus_next
            else:
                a = _gain(phi[e - 1], p_minus[e - 1], p_plus[e])
                before = p_minus[e - 1]
            x = np.empty((n, n))
            for i in range(n):
                for c in range(n):
                    x[i, c] = P_s[i, c] - before[i, c]
            smoothed = (a @ x) @ a.T
            for i in range(n):
                for c in range(n):
                    smoothed[i, c] = p_plus[e, i, c] + smoothed[i, c]
            for i in range(n):
                for c in range(n):
                    P_s[i, c] = 0.5 * (smoothed[i, c] + smoothed[c, i])
            if active[0]:
                jit.copy_rows(a @ product, product)
            k = 2 * active[1]
            if k:
                jit.copy_rows(young[:k] @ a.T, young[:k])  # each row d^T A^T = (A d)^T
            active[2] += 1
        _project(var_s, P_s, u, j, low, pos, att)
        _project(var_f, p_plus[e], u, j, low, pos, att)
        for t in range(starts_ptr[j], starts_ptr[j + 1]):  # pairs whose first epoch is j: read and drop
            pair = starts_idx[t]
            slot = slot_of[pair]
            for r in range(2):
                total = 0.0
                for p in range(3):
                    if slot >= 0:  # (product d)[pos + p]
                        value = 0.0
                        for i in range(n):
                            value += product[pos + p, i] * columns[2 * slot + r, i]
                    else:
                        value = young[2 * (-1 - slot) + r, pos + p]
                    total += u[r, j - low, p] * value
                cross_s[pair, r] = total
            if slot >= 0:
                # np.int64: a constant argument (Literal[int]) would compile _drop once per value
                _drop(columns, slot_of, pair_of_slot, active, np.int64(0), slot, slot)
            else:
                _drop(young, slot_of, pair_of_young, active, np.int64(1), -1 - slot, slot)
        for t in range(ends_ptr[j], ends_ptr[j + 1]):  # pairs whose second epoch is j: seeded with P_s[:, pos] u^T
            pair = ends_idx[t]
            slot = active[1]
            active[1] = slot + 1
            slot_of[pair] = -1 - slot
            pair_of_young[slot] = pair
            for r in range(2):
                for i in range(n):
                    total = 0.0
                    for p in range(3):
                        total += P_s[i, pos + p] * u[r, j - low, p]
                    young[2 * slot + r, i] = total
        if active[2] >= checkpoint:  # every column brought to now, the young ones among them
            k = 2 * active[0]
            if k:
                jit.copy_rows(columns[:k] @ product.T, columns[:k])
            for slot in range(active[1]):
                to = active[0]
                active[0] = to + 1
                jit.copy_rows(young[2 * slot : 2 * slot + 2], columns[2 * to : 2 * to + 2])
                slot_of[pair_of_young[slot]] = to
                pair_of_slot[to] = pair_of_young[slot]
            active[1] = 0
            active[2] = 0
            product[:, :] = 0.0
            for i in range(n):
                product[i, i] = 1.0
    jit.copy_rows(phi[len(js) - 1], phi_next)
    jit.copy_rows(p_minus[len(js) - 1], p_minus_next)


# These kernels run compiled code of other modules (the LAPACK call of insrail.nav.kalman, the copy of
# insrail.jit): their cache entries go when those modules change (numba checks only this file).
_kernels.drop_stale_cache((_gain, _drop, _backward_chunk), (kalman.__file__, jit.__file__))


def _group(epochs: np.ndarray, m: int) -> dict[int, np.ndarray]:
    """{epoch: indices of the pairs with that epoch}."""
    order = np.argsort(epochs, kind="stable")
    keys, first = np.unique(epochs[order], return_index=True)
    return {int(k): idx for k, idx in zip(keys, np.split(order, first[1:]))}


def _pass(var, cross, pairs, lags_m, station_m) -> PassCovariance:
    var = np.maximum(var, 0.0)
    lags = []
    offset = 0
    for lag, (j, k) in zip(lags_m, pairs):
        c = cross[offset : offset + len(j)]
        offset += len(j)
        diff_lat = np.maximum(var[k, 0] + var[j, 0] - 2.0 * c[:, 0], 0.0)
        diff_ver = np.maximum(var[k, 1] + var[j, 1] - 2.0 * c[:, 1], 0.0)
        lags.append(LagDifference(float(lag), j, k, station_m[j], np.sqrt(diff_lat), np.sqrt(diff_ver)))
    return PassCovariance(np.sqrt(var[:, 0]), np.sqrt(var[:, 1]), np.sqrt(var[:, 2]), tuple(lags),
                          np.sqrt(var[:, 3]))


class _ActivePairs:
    """Columns D (N x 2 per pair) of the pairs whose first point has been passed and whose
    second has not; ``apply`` pushes all of them one epoch on."""

    def __init__(self, n: int):
        self.ids = np.empty(0, dtype=int)
        self.columns = np.empty((n, 0))

    def add(self, ids, cols):
        if len(ids):
            self.ids = np.concatenate([self.ids, np.asarray(ids, dtype=int)])
            self.columns = np.hstack([self.columns, cols])

    def apply(self, M):
        if self.ids.size:
            self.columns = M @ self.columns

    def take(self, ids) -> np.ndarray:
        """Column indices (lateral, vertical interleaved) of the given pairs, in their order."""
        where = {p: i for i, p in enumerate(self.ids)}
        slots = np.array([where[p] for p in ids], dtype=int)
        return np.column_stack([2 * slots, 2 * slots + 1]).ravel()

    def remove(self, ids):
        keep = ~np.isin(self.ids, ids)
        self.ids = self.ids[keep]
        self.columns = self.columns[:, np.repeat(keep, 2)]


class _ReverseStore:
    """Append-only, chunked, disk-backed rows read back last chunk first. Written with plain
    file writes, not a memory map: a 10 km survey's 1.4 GB of records stays in the page
    cache and never counts towards the process's memory."""

    def __init__(self, width: int, chunk: int = 1024):
        self.file = tempfile.TemporaryFile(prefix="insrail-cov-")
        self.buffer = np.empty((chunk, width))
        self.fill = 0
        self.count = 0

    def append(self, row: np.ndarray) -> None:
        self.buffer[self.fill] = row
        self.fill += 1
        self.count += 1
        if self.fill == len(self.buffer):
            self._flush()

    def _flush(self) -> None:
        self.file.write(self.buffer[: self.fill].tobytes())
        self.fill = 0

    def reversed_blocks(self, n: int):
        """Blocks (j, Phi_j, P-_j, P+_j) of rows [Phi, P-, P+] of n x n matrices, j decreasing
        (arrays (k,) and (k, n, n) x 3), the last row first."""
        nn = n * n
        for first, chunk in self.reversed_chunks():
            rows = chunk[::-1]
            yield (np.arange(first + len(chunk) - 1, first - 1, -1), rows[:, :nn].reshape(-1, n, n),
                   rows[:, nn : 2 * nn].reshape(-1, n, n), rows[:, 2 * nn :].reshape(-1, n, n))

    def reversed_chunks(self):
        """(index of the first row, rows) from the last chunk to the first."""
        self._flush()
        chunk, width = self.buffer.shape
        size = width * 8
        for first in range(((self.count - 1) // chunk) * chunk, -1, -chunk):
            rows = min(chunk, self.count - first)
            self.file.seek(first * size)
            yield first, np.frombuffer(self.file.read(rows * size), dtype=np.float64).reshape(rows, width)

    def close(self) -> None:
        self.file.close()
