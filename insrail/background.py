"""One job in a thread of its own while the calling thread goes on (with one CPU: at once, in the caller).

:class:`BackgroundJob` runs ``job(progress, cancel)`` beside its caller, e.g. the covariance
analysis of a fusion while the track is reconstructed from the fused trajectory. The rules of
:mod:`insrail.progress` hold across the two threads:

* progress: the job's calls are recorded; the *calling* thread says them, through the progress
  of its own current step (:meth:`BackgroundJob.relay`, and while it waits in
  :meth:`BackgroundJob.result`), and only forward. So a progress callback is only ever called
  from the thread that called the pipeline (the CLI's bar, the GUI's worker, a benchmark's clock
  need not be thread-safe), and the fractions it sees never go back;
* cancel: the job sees the caller's token, and a stop of its own (:meth:`BackgroundJob.stop`,
  when the caller fails or is cancelled: the job raises :class:`~insrail.progress.Cancelled` at
  its next check point and is waited for, so nothing of it goes on behind the caller's back);
* failures: the job's exception is raised by :meth:`BackgroundJob.result` as it was raised (its
  message and traceback). As a context manager the job is stopped and waited for when the block
  ends, so a failure between the start and the result leaves no thread behind.

The job runs in a copy of the caller's context (:mod:`contextvars`: the language, the notices
being collected). It should spend its time in code that releases the GIL (numpy, LAPACK, nogil
numba kernels), or the two threads take turns instead of running side by side.

Serial fallback: with ``os.cpu_count() == 1`` (or ``threaded=False``) the job runs to its end in
the constructor, with the progress given there; the results are the same either way.
"""

from __future__ import annotations

import contextvars
import os
import threading
from collections.abc import Callable
from typing import Generic, TypeVar

from insrail.progress import CancelToken, ProgressFn, ProgressMessage, is_cancelled

T = TypeVar("T")

#: How often [s] a caller waiting for the job says the job's progress.
WAIT_POLL_S = 0.1


def threads_worth_it() -> bool:
    """True when a second thread can run beside the caller (more than one CPU)."""
    return (os.cpu_count() or 1) > 1


class BackgroundJob(Generic[T]):
    """``job(progress, cancel) -> T`` beside the calling thread (see the module docstring).

    ``progress`` is where the job's progress goes when it runs serially (in the constructor);
    threaded, it is said through the progress the caller passes to :meth:`relay` and
    :meth:`result`. ``name`` names the thread (in a traceback, a profiler)."""

    def __init__(self, job: Callable[[ProgressFn, CancelToken], T], progress: ProgressFn | None,
                 cancel: CancelToken, name: str, threaded: bool | None = None):
        self._value: T | None = None
        self._error: BaseException | None = None
        self._thread: threading.Thread | None = None
        if not (threads_worth_it() if threaded is None else threaded):
            self._value = job(progress or (lambda fraction, message: None), cancel)
            return
        self._guard = threading.Lock()
        self._latest: tuple[float, ProgressMessage] | None = None
        self._said = -1.0
        self._stopped = threading.Event()

        def record(fraction: float, message: ProgressMessage = "") -> None:
            with self._guard:
                self._latest = (fraction, message)

        def stop_asked() -> bool:
            return self._stopped.is_set() or is_cancelled(cancel)

        def run() -> None:
            try:
                self._value = job(record, stop_asked)
            except BaseException as error:  # noqa: BLE001 - handed to the caller by result()
                self._error = error

        context = contextvars.copy_context()
        self._thread = threading.Thread(target=context.run, args=(run,), name=name, daemon=True)
        self._thread.start()

    def relay(self, progress: ProgressFn | None) -> None:
        """Say the job's latest progress through ``progress`` when it moved on (the calling thread only)."""
        if self._thread is None or progress is None:
            return
        with self._guard:
            latest = self._latest
        if latest is not None and latest[0] > self._said:
            self._said = latest[0]
            progress(*latest)

    def result(self, progress: ProgressFn | None = None) -> T:
        """The job's value, once it has ended (its progress said meanwhile); its exception if it failed."""
        if self._thread is not None:
            while self._thread.is_alive():
                self._thread.join(WAIT_POLL_S)
                self.relay(progress)
            self.relay(progress)
        if self._error is not None:
            raise self._error
        return self._value

    def __enter__(self) -> BackgroundJob[T]:
        return self

    def __exit__(self, kind, error, traceback) -> bool:
        """The job stopped and waited for when the block ends (at once when it failed: see :meth:`stop`)."""
        self.stop()
        return False

    def stop(self) -> None:
        """Ask the job to stop and wait until it has (what it raised then is dropped: the caller's
        own failure is the one to report)."""
        if self._thread is not None:
            self._stopped.set()
            self._thread.join()
