"""Waiting for a GUI worker (insrail.gui.worker.CoreWorker) without a fixed deadline.

A fixed timeout either fails a slow but working run on a loaded machine (the Plan survey test
timed out at 30 s under a load average of 10) or, made long, waits minutes for a hung one. The
worker says that it works: its ``progressed`` signal. :func:`wait_for_worker` waits as long as
the worker keeps reporting, and fails once it has been silent for ``silent_s`` (a hang, or a
loop that no longer reports), naming the last thing it said.
"""

from __future__ import annotations

import time

#: How long a worker may go without reporting progress before the wait calls it hung: the
#: predictions and the pipeline report several times a second when they run alone.
SILENT_S = 120.0


def wait_for_worker(qtbot, holder, silent_s: float = SILENT_S, until=None) -> None:
    """Returns once ``holder.worker`` is None (the worker finished and the holder let it go), or
    ``until()`` is true; processes the GUI's events meanwhile. Fails when the worker reported no
    progress for ``silent_s``."""
    worker = holder.worker
    assert worker is not None, "no worker is running"
    heard = {"at": time.monotonic(), "what": "nothing yet"}

    def progressed(fraction, message) -> None:  # called in the worker's thread or the GUI's: two stores
        heard["what"] = f"{100.0 * fraction:.0f} %: {message}"
        heard["at"] = time.monotonic()

    worker.progressed.connect(progressed)
    try:
        while holder.worker is not None and not (until is not None and until()):
            silent = time.monotonic() - heard["at"]
            assert silent < silent_s, (f"the worker reported no progress for {silent:.0f} s (hung?); "
                                       f"last heard: {heard['what']}")
            qtbot.wait(20)
    finally:
        if holder.worker is worker:
            worker.progressed.disconnect(progressed)
