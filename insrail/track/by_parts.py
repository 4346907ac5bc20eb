"""Whole-run interpolations done by parts, to the bit: what the track reconstruction by parts
(:mod:`insrail.track.streamed`) and the epochs' stations on disk
(:class:`~insrail.track.sleeper_table.EpochStationsFile`) interpolate in."""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator

import numpy as np

from insrail.track.chainage import NO_STATIONS
from insrail.track.sleepers import StationTrack


def chunked_interp(x: np.ndarray, blocks: Iterable[tuple[np.ndarray, np.ndarray]]) -> np.ndarray:
    """``np.interp(x, xp, fp)`` (``fp`` (m,) or (m, k): per column) where ``xp``/``fp`` are the
    concatenation of ``blocks`` ((xp part, fp part), in order, the parts held one or two at a
    time), to the bit: each query goes to the block holding the last xp <= it, with the next
    block's first point appended, so it meets the same two neighbours as in one call."""
    x = np.asarray(x, dtype=float)
    order = np.argsort(x, kind="stable")
    xs = x[order]
    valid = int(np.count_nonzero(~np.isnan(xs)))  # NaN sort last, and interpolate to NaN
    out, done, pending = None, 0, None

    def fill(xp: np.ndarray, fp: np.ndarray, stop: int) -> None:
        nonlocal out, done
        if out is None:
            out = np.full((len(x), *fp.shape[1:]), np.nan)
        rows = order[done:stop]
        if fp.ndim == 1:
            out[rows] = np.interp(xs[done:stop], xp, fp)
        else:
            for column in range(fp.shape[1]):
                out[rows, column] = np.interp(xs[done:stop], xp, fp[:, column])
        done = stop

    points = 0
    for xp, fp in blocks:
        if not len(xp):
            continue
        points += len(xp)
        if pending is not None:
            stop = int(np.searchsorted(xs[:valid], xp[0], side="left"))
            fill(np.concatenate([pending[0], xp[:1]]), np.concatenate([pending[1], fp[:1]]), stop)
        pending = (xp, fp)
    if pending is None:
        raise ValueError("array of sample points is empty")
    fill(*pending, valid)
    if points == 1:  # np.interp on one point gives its value even at NaN
        fill(*pending, len(x))
    return out


def station_track_by_parts(parts: int, finite_part: Callable[[int], tuple[np.ndarray, np.ndarray]]) -> StationTrack:
    """The :class:`~insrail.track.sleepers.StationTrack` of
    :func:`~insrail.track.chainage.epoch_station_track` over (time, station) given in ``parts``
    parts (``finite_part(k)``: part k's epochs with a finite station), the same to the bit:
    the running maximum (minimum) is carried from part to part and the interpolations go by
    parts (:func:`chunked_interp`). Reads each part once here and again for each interpolation."""
    low, high, with_station, ends = [], [], 0, []
    for k in range(parts):
        t, s = finite_part(k)
        with_station += len(s)
        low.append(float(s.min()) if len(s) else np.nan)
        high.append(float(s.max()) if len(s) else np.nan)
        if len(s):
            ends.extend([(t[0], s[0]), (t[-1], s[-1])])
    if with_station < 2:
        raise ValueError(NO_STATIONS)
    (first_t, first_s), (last_t, last_s) = ends[0], ends[-1]
    with_data = [k for k in range(parts) if np.isfinite(low[k])]
    against = bool(last_s < first_s)
    extreme = np.minimum if against else np.maximum
    carried, running = [], np.inf if against else -np.inf
    for k in range(parts):
        carried.append(running)
        if k in with_data:
            running = float(extreme(running, low[k] if against else high[k]))
    lowest, highest = (running, first_s) if against else (first_s, running)

    def monotone(k: int) -> tuple[np.ndarray, np.ndarray]:
        t, s = finite_part(k)
        return t, extreme(extreme.accumulate(s), carried[k])

    def by_time() -> Iterator:
        for k in with_data:
            yield monotone(k)

    def by_station() -> Iterator:
        for k in (reversed(with_data) if against else with_data):
            t, s = monotone(k)
            yield (s[::-1], t[::-1]) if against else (s, t)

    return StationTrack(float(first_t), float(last_t), float(lowest), float(highest), against,
                        lambda t: chunked_interp(t, by_time()), lambda s: chunked_interp(s, by_station()))
