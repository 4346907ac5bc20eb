"""Compiled (numba) sliding-window reductions of the adjustment programme's chord checks.

:func:`trailing_argmax` is the index of the largest value in each trailing window, what
``sliding_window_view(padded, width).argmax(axis=1)`` gives, in one pass over the values (a
queue of the window's candidates) instead of ``width`` comparisons per value: the 300 m / 150 m
differential versine's windows are 241 sleepers wide, and every round of every adjustment window
takes them again.
"""

from __future__ import annotations

import numpy as np

from insrail.jit import cached_njit


@cached_njit(nogil=True)
def trailing_argmax(values: np.ndarray, width: int) -> np.ndarray:
    """For every k the index of the largest of ``values[k - width + 1 .. k]``, the first one where
    several are as large; where all of them are -inf (or the window begins before the values), the
    window's first index ``k - width + 1`` (which may be negative), as numpy's ``argmax`` of the
    window padded with -inf says. ``values`` must hold no NaN."""
    n = values.shape[0]
    out = np.empty(n, np.int64)
    # the window's candidates: indices in increasing order, their values decreasing (an equal value
    # stays behind the earlier one, which is the first maximum)
    queue = np.empty(n, np.int64)
    head, tail = 0, 0
    for k in range(n):
        value = values[k]
        while tail > head and values[queue[tail - 1]] < value:
            tail -= 1
        queue[tail] = k
        tail += 1
        if queue[head] <= k - width:  # left the window (one index a step)
            head += 1
        best = queue[head]
        out[k] = best if values[best] > -np.inf else k - width + 1
    return out
