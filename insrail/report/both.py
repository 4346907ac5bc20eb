"""The workbook and the PDF of one survey written side by side: the workbook in a spawned process while
this one writes the PDF.

Both writers are pure Python (the GIL): threads would take turns, a second process runs them at once.
Where this process runs a single thread (the ``insrail report`` command: :func:`start_method`) the
child is forked: it starts at once with the modules, the results and the report content made here, and
imports openpyxl while this process imports reportlab. Elsewhere it is spawned, never forked (the GUI and
the batch have threads; a fork copies their locks held), and pays its own start-up (about 1 s of
imports, overlapping the PDF). The child is used only for a survey long enough to pay for its start
and where a second CPU is free to take it (:func:`side_by_side`), else the two are written one after
the other in this process.
A spawned child gets the project and the results read here (pickled), so both reports are of the same
results; its progress comes back over a pipe and is shown with the PDF's as one (the mean of the two
fractions). A failure in either reaches the caller with its own message and type (a ValueError stays a
ValueError); cancel (or a failure of the PDF) is passed to the child, which stops at its next check
point; each writer writes atomically, so nothing half-written is left.
"""

from __future__ import annotations

import multiprocessing
import os
import pickle
import threading
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from insrail.background import cpu_budget
from insrail.progress import Cancelled, CancelToken, ProgressFn, ProgressMessage, is_cancelled
from insrail.project.model import Project
from insrail.project.results import StoredResults

if TYPE_CHECKING:
    from insrail.report.content import ReportContent


#: Below this many sleepers the workbook takes less time than a spawned process's start-up (some 1.1 s of
#: imports against 0.13 ms of CPU per sleeper, 2026-12): both are written here, one after the other.
SIDE_BY_SIDE_MIN_SLEEPERS = 10_000
#: The same for a forked process, which starts in milliseconds: below this many sleepers the workbook
#: (openpyxl's import, some 0.1 s, and its rows) takes little more than the fork's copies of the pages
#: this process then writes (some 0.05 s of CPU with a short survey's results, 2026-12).
FORKED_MIN_SLEEPERS = 500


def start_method() -> str:
    """How the workbook's process starts: forked where this process runs a single thread (no other
    thread can hold a lock the child would copy held; the kernel's count, ``/proc/self/task``, sees
    the threads Python did not start too), else spawned."""
    try:
        alone = len(os.listdir("/proc/self/task")) == 1
    except OSError:  # no /proc: the thread count is not known
        return "spawn"
    return "fork" if alone and "fork" in multiprocessing.get_all_start_methods() else "spawn"


def side_by_side(sleepers: int, method: str = "spawn") -> bool:
    """The workbook of ``sleepers`` rows in a process of its own started by ``method``
    (:func:`start_method`): long enough to pay for its start, and a second CPU free for it: this
    process may use more than one, they are not all busy now (the tasks running, this process
    included, leave one idle: :func:`running_tasks`), and it is no daemon (a pool's worker, which may
    have no children). On a busy machine a second process only adds its start to the CPU time the
    two reports take."""
    cpus = cpu_budget()
    least = FORKED_MIN_SLEEPERS if method == "fork" else SIDE_BY_SIDE_MIN_SLEEPERS
    return (sleepers >= least and cpus > 1 and running_tasks() <= cpus - 1
            and not multiprocessing.current_process().daemon)


def running_tasks() -> float:
    """The tasks running or ready to run now, this process included: the kernel's count (``/proc/loadavg``'s
    fourth field). The load average lags by a minute: right after ``insrail process`` used both CPUs it
    still says they are busy. Elsewhere: the last minute's load average plus this process."""
    try:
        return float(Path("/proc/loadavg").read_text(encoding="ascii").split()[3].split("/")[0])
    except (OSError, IndexError, ValueError):
        return (os.getloadavg()[0] if hasattr(os, "getloadavg") else 0.0) + 1.0


def write_both(project: Project, results: StoredResults, xlsx: Path, pdf: Path, progress: ProgressFn | None = None,
               cancel: CancelToken = None, sections: Sequence = (), concurrent: bool | None = None) -> list[Path]:
    """Write the workbook to ``xlsx`` and the PDF (with ``sections``) to ``pdf``; returns both paths.
    ``concurrent``: None decides by :func:`side_by_side`; False writes one after the other here."""
    from insrail.report.content import report_content

    shown = _Shared(progress)
    method = start_method()
    if not (side_by_side(len(results), method) if concurrent is None else concurrent):
        from insrail.report import write_pdf, write_workbook  # here only: openpyxl's imports are the child's otherwise

        content = report_content(project, results)  # made once for both
        write_workbook(project, results, xlsx, progress=shown.part(0), cancel=cancel, content=content)
        return [xlsx, write_pdf(project, results, pdf, progress=shown.part(1), cancel=cancel, sections=sections,
                                content=content)]
    # a forked child takes the content made here (a spawned one makes its own: pickling it costs as much)
    content = report_content(project, results) if method == "fork" else None
    context = multiprocessing.get_context(method)
    stop = context.Event()
    receiver, sender = context.Pipe(duplex=False)
    child = context.Process(target=_write_workbook_here, args=(sender, stop, project, results, xlsx, content),
                            name="insrail workbook", daemon=True)
    child.start()
    sender.close()  # the child holds the only sending end: its end of the pipe is seen
    from insrail.report import write_pdf  # reportlab's imports beside the child's start
    outcome: list = []
    failed = threading.Event()  # the workbook failed: the PDF stops at its next check point
    listener = threading.Thread(target=_listen, args=(receiver, shown.part(0), outcome, failed), daemon=True)
    listener.start()
    try:
        write_pdf(project, results, pdf, progress=shown.part(1),
                  cancel=lambda: is_cancelled(cancel) or failed.is_set(), sections=sections, content=content)
    except Cancelled:
        if not failed.is_set() or is_cancelled(cancel):
            stop.set()
            raise
    except BaseException:
        stop.set()  # the PDF failed or was interrupted: the workbook stops too
        raise
    finally:
        listener.join()
        child.join()
        receiver.close()
    if not outcome:
        raise RuntimeError(f"the workbook's process ended without a word (exit code {child.exitcode})")
    if isinstance(outcome[0], BaseException):
        raise outcome[0]  # the workbook's failure (the PDF, stopped by it, is not written)
    return [xlsx, pdf]


class _Shared:
    """One progress of two writers: the mean of their fractions, the message of the latest."""

    def __init__(self, progress: ProgressFn | None):
        self.progress = progress
        self.fractions = [0.0, 0.0]
        self.lock = threading.Lock()

    def part(self, index: int) -> ProgressFn:
        def report(fraction: float, message: ProgressMessage = "") -> None:
            if self.progress is None:
                return
            with self.lock:
                self.fractions[index] = fraction
                self.progress(sum(self.fractions) / 2, message)

        return report


def _listen(receiver, progress: ProgressFn, outcome: list, failed: threading.Event) -> None:
    """The child's messages: progress until its outcome (its path, or the error it raised: ``failed`` set)."""
    while True:
        try:
            kind, *payload = receiver.recv()
        except EOFError:  # the child ended without an outcome (killed): write_both says so
            failed.set()
            return
        except Exception as error:  # noqa: BLE001 - an outcome that cannot be read back here
            payload = [RuntimeError(f"the workbook failed: {error}")]
            kind = "outcome"
        if kind == "progress":
            progress(*payload)
            continue
        outcome.append(payload[0])
        if isinstance(payload[0], BaseException):
            failed.set()
        return


def _write_workbook_here(sender, stop, project: Project, results: StoredResults, path: Path,
                         content: ReportContent | None = None) -> None:
    """The child: the workbook (of ``content`` where the parent made it), its progress and its outcome
    (its path, or the error it raised) sent back."""
    from insrail.memory import tune_allocator
    from insrail.report import write_workbook

    tune_allocator()  # as the `insrail` command does first (a forked child has it already)

    def progress(fraction: float, message: ProgressMessage = "") -> None:
        sender.send(("progress", fraction, message))

    try:
        outcome = write_workbook(project, results, path, progress=progress, cancel=stop, content=content)
    except BaseException as error:  # noqa: BLE001 - every failure goes back to the parent, which raises it
        outcome = _portable(error)
    sender.send(("outcome", outcome))
    sender.close()


def _portable(error: BaseException) -> BaseException:
    """``error`` where it pickles both ways, else its nearest kind the caller handles with the same
    message (an InputError or a NotARegularFile takes other arguments than it pickles)."""
    try:
        pickle.loads(pickle.dumps(error))
        return error
    except Exception:  # noqa: BLE001 - any failure to pickle or to rebuild it
        pass
    if isinstance(error, OSError):
        return OSError(error.errno, error.strerror, error.filename)
    for kind in (ValueError, Cancelled, KeyboardInterrupt):
        if isinstance(error, kind):
            return kind(str(error))
    return RuntimeError(f"the workbook failed: {type(error).__name__}: {error}")
