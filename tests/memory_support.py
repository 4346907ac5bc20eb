"""Memory growth of a computation with the survey's length, for the bounded-memory tests (issue 24).

``tracemalloc`` sees every buffer numpy allocates and is deterministic, unlike the resident set
size: a streamed stage is checked by running it on a short and a twice-as-long input (with its
chunk size shrunk, so both span many chunks) and comparing the peaks of traced memory.
"""

from __future__ import annotations

import gc
import tracemalloc
from typing import Any, Callable


def traced_peak_bytes(fn: Callable[..., Any], *args, **kwargs) -> tuple[Any, int]:
    """``fn(*args, **kwargs)`` and the peak of traced memory it allocated above what was live
    when it began (bytes)."""
    gc.collect()
    tracemalloc.start()
    try:
        tracemalloc.reset_peak()
        base, _ = tracemalloc.get_traced_memory()
        result = fn(*args, **kwargs)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    return result, peak - base


def peak_growth_bytes(run: Callable[[int], Any], length: int) -> tuple[int, int]:
    """Traced peaks of ``run(length)`` and ``run(2 * length)``: a stage bounded in memory shows
    (nearly) the same peak for both."""
    return traced_peak_bytes(run, length)[1], traced_peak_bytes(run, 2 * length)[1]
