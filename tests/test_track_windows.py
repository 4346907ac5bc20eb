"""The compiled trailing-window argmax of the adjustment programme against numpy's sliding windows."""

import numpy as np
import pytest
from numpy.lib.stride_tricks import sliding_window_view

from insrail.track._windows import trailing_argmax


def numpy_trailing_argmax(values: np.ndarray, width: int) -> np.ndarray:
    """The reference: the argmax of every window of the values padded with width - 1 times -inf."""
    padded = np.concatenate([np.full(width - 1, -np.inf), values])
    return np.arange(values.size) - (width - 1) + sliding_window_view(padded, width).argmax(axis=1)


@pytest.mark.parametrize("width", [1, 2, 5, 41, 241])
def test_trailing_argmax_is_numpys(width):
    rng = np.random.default_rng(width)
    for _ in range(20):
        n = int(rng.integers(1, 600))
        values = np.round(rng.normal(size=n), 1)  # rounded: many ties, the first maximum must win
        values[rng.random(n) < 0.3] = -np.inf  # excluded entries, whole windows of them too
        values[: int(rng.integers(0, n + 1)) // 4] = -np.inf
        np.testing.assert_array_equal(trailing_argmax(values, width), numpy_trailing_argmax(values, width))


def test_trailing_argmax_of_nothing_but_excluded_entries():
    values = np.full(10, -np.inf)
    np.testing.assert_array_equal(trailing_argmax(values, 4), np.arange(10) - 3)

