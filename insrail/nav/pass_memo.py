"""What one fusion pass works out from the IMU records alone, kept for the next pass over the same survey.

The processing fuses one survey more than once: the mounting's pass without the NHC
(``insrail.project.mounting_stage``) and the self-calibration's passes
(``insrail.nav.self_calibration``). Each pass starts by screening the IMU records, bridging their
gaps and finding the stops (``insrail.nav.fusion._prepare``): some 3.5 s of CPU a pass at 10 km,
the same every time, since it depends only on the records, the IMU profile, the odometer, the
positions the unit check rests on and the longest gap bridged, never on the filter's options. A
:class:`PassMemo` given to every pass (``fuse(..., memo=memo)``) makes it once.

A kept value is returned only for the same inputs: the records, the profile and the odometer the
same objects (held here, so their ids cannot be reused), arrays equal value for value, numbers
equal; anything else makes it again. The caller drops it (:meth:`PassMemo.clear`) when the passes
are done, so the screened records are not held through the stages after the fusion.

Passes running side by side in threads (the mounting's pass and the main fusion,
``insrail.project.mounting_stage.fused_with_mounting``) share one memo: a value is made by one
thread at a time, so the second pass to ask for it waits for the first's and takes it.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any

import numpy as np


def same_inputs(a: Any, b: Any) -> bool:
    """Whether two keys name the same inputs: tuples item by item, arrays value for value (NaN
    never equal: made again), numbers and strings by value, anything else the same object."""
    if isinstance(a, tuple) and isinstance(b, tuple):
        return len(a) == len(b) and all(same_inputs(x, y) for x, y in zip(a, b))
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        return (isinstance(a, np.ndarray) and isinstance(b, np.ndarray) and a.shape == b.shape
                and a.dtype == b.dtype and bool(np.array_equal(a, b)))
    if isinstance(a, (int, float, str)) and isinstance(b, (int, float, str)):
        return type(a) is type(b) and a == b
    return a is b


class PassMemo:
    """Values kept by name with the inputs they were made from (module docstring)."""

    def __init__(self) -> None:
        self._kept: dict[str, tuple[Any, Any]] = {}
        self._making = threading.Lock()
        self.made = 0  # values made (not taken from the memo): tests read it

    def get(self, name: str, inputs: Any, make: Callable[[], Any]) -> Any:
        """The value kept under ``name`` when it was made from the same ``inputs``, else ``make()``
        (kept for the next call). Another thread asking meanwhile waits for it."""
        with self._making:
            kept = self._kept.get(name)
            if kept is not None and same_inputs(kept[0], inputs):
                return kept[1]
            value = make()
            self.made += 1
            self._kept[name] = (inputs, value)
            return value

    def clear(self) -> None:
        with self._making:
            self._kept.clear()
