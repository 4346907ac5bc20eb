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
being collected, the CPU budget). It should spend its time in code that releases the GIL (numpy,
LAPACK, nogil numba kernels), or the two threads take turns instead of running side by side.

Serial fallback: with a CPU budget of one (or ``threaded=False``) the job runs to its end in
the constructor, with the progress given there; the results are the same either way.

The CPU budget (:func:`cpu_budget`) is the one answer to "how many threads may this run keep busy",
asked by every pool and every job beside the caller: the CPUs the process may run on (its affinity),
no more than the batch gave the run (:func:`cpus_limited`: a spawned batch worker its share of the
cores, a Dask worker its ``nthreads``), so that N batch workers on C cores keep C busy, not N times C.
"""

from __future__ import annotations

import contextvars
import os
import sys
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Generic, TypeVar

from insrail.progress import CancelToken, ProgressFn, ProgressMessage, is_cancelled

T = TypeVar("T")

#: How often [s] a caller waiting for the job says the job's progress.
WAIT_POLL_S = 0.1


#: The threads the batch gave the run in this context (:func:`cpus_limited`); None: no limit given.
_CPU_LIMIT: contextvars.ContextVar[int | None] = contextvars.ContextVar("insrail_cpu_limit", default=None)


def cpu_budget() -> int:
    """How many threads this run may keep busy (at least one): the CPUs this process may run on (its
    affinity; ``os.cpu_count()`` bounds it too, the count tests and embedders set to force a number),
    no more than the limit the batch gave it (:func:`cpus_limited`) nor, in a task on a Dask worker,
    than the worker's threads (a worker of one thread runs its task serially)."""
    cpus = os.cpu_count() or 1
    if hasattr(os, "sched_getaffinity"):
        cpus = min(cpus, len(os.sched_getaffinity(0)))
    for limit in (_CPU_LIMIT.get(), _dask_worker_threads()):
        if limit is not None:
            cpus = min(cpus, limit)
    return max(1, cpus)


def _dask_worker_threads() -> int | None:
    """The threads of the Dask worker running the current task (a context of its); None elsewhere.
    Dask is not imported for the question: a task on a worker finds it imported."""
    distributed = sys.modules.get("distributed")
    if distributed is None:
        return None
    try:
        return distributed.get_worker().state.nthreads
    except ValueError:  # not in a worker's task
        return None


@contextmanager
def cpus_limited(limit: int | None) -> Iterator[None]:
    """Within the block (and the threads started from it with its context, :class:`BackgroundJob`'s),
    :func:`cpu_budget` is at most ``limit`` (None: as outside). A limit only narrows the one in force."""
    if limit is None:
        yield
        return
    outer = _CPU_LIMIT.get()
    token = _CPU_LIMIT.set(max(1, limit if outer is None else min(outer, limit)))
    try:
        yield
    finally:
        _CPU_LIMIT.reset(token)


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
        if not (cpu_budget() > 1 if threaded is None else threaded):
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

    def done(self) -> bool:
        """True once the job has ended (returned or failed)."""
        return self._thread is None or not self._thread.is_alive()

    def wait(self, timeout_s: float | None = None) -> bool:
        """Wait for the job's end, at most ``timeout_s`` (None: as long as it takes); True if it has ended."""
        if self._thread is not None:
            self._thread.join(timeout_s)
        return self.done()

    def exception(self, progress: ProgressFn | None = None) -> BaseException | None:
        """What the job raised, once it has ended (its progress said meanwhile); None if it returned."""
        if self._thread is not None:
            while not self.wait(WAIT_POLL_S):
                self.relay(progress)
            self.relay(progress)
        return self._error

    def result(self, progress: ProgressFn | None = None) -> T:
        """The job's value, once it has ended (its progress said meanwhile); its exception if it failed."""
        if (error := self.exception(progress)) is not None:
            raise error
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
