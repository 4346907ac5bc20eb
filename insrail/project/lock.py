"""One project, one writer: the locks that keep two runs of one project from writing the same files.

Two kinds of lock, both ``flock`` locks on files in ``PROJECT/results/.locks/`` (the kernel releases
them when their process dies, so the lock of a run that was killed is never in the way):

* the project lock (``project.lock``), held *shared* by every run for its whole length. A run that
  finds no other run (it gets the lock *exclusively* without waiting) first removes what killed runs
  left behind (staging folders, temporary files: ``when_alone``), then holds it shared like the
  others. So no run ever removes a folder another run is writing.
* one lock per survey's results (``survey-<name>.lock``), held *exclusively* by whatever writes or
  reads that survey's results (``process``, ``report``, ``section``, ``export``, the GUI's workers
  through :func:`insrail.project.process`): two surveys of one project (a batch) still run in
  parallel, two runs of one survey one after the other. The holder writes its PID, start time and
  command into the file, which is what a second run shows while it waits ("waiting for the run
  started at ... by PID ..."); with :func:`waiting_policy` (``--no-wait``) it raises
  :class:`ProjectBusy` instead.
* one lock per cache entry (``cache-<entry>.lock``, :func:`cache_entry`), held *exclusively* while a
  run looks the entry up and, when absent, computes and writes it: two surveys with identical data
  (one survey copied under two names, a batch) share cache keys, and the second waits and reuses
  the entry instead of writing the same files at the same time. Taken inside the project lock and
  after the survey locks (a run never waits for a survey while holding an entry: no deadlock). A run
  may hold two entries, always in the pipeline's order: the fusion's stays held (not sealed while its
  covariance analysis runs beside) while the track's is taken, never the other way round.
  These files are removed by a run that finds no other run of the project (nobody can hold or
  wait for one then); a lock file is never removed otherwise, since a run that opened it before
  its removal and one that opens it after would each get a lock of their own.

A thread that already holds a survey's lock may take it again (the CLI's ``report`` of a survey
being processed in the same call); another thread of the same process waits like another process.
Where ``flock`` is missing (Windows) runs are not locked.
"""

from __future__ import annotations

import contextlib
import contextvars
import errno
import os
import sys
import threading
import time
from collections.abc import Callable, Iterable, Iterator
from pathlib import Path
from urllib.parse import quote

from insrail.notices import Phrase
from insrail.progress import CancelToken, ProgressFn, check_cancel

try:
    import fcntl
except ImportError:  # Windows
    fcntl = None

LOCK_FOLDER = Path("results") / ".locks"
CACHE_LOCK_PREFIX = "cache-"
#: How often [s] a waiting run tries the lock again (and looks at its cancel token).
POLL_S = 0.25

_wait = contextvars.ContextVar("lock_wait", default=True)
_announce: contextvars.ContextVar[Callable[[str], None] | None] = contextvars.ContextVar("lock_announce", default=None)
_held: dict[tuple[Path, int], int] = {}  # (lock file, thread) -> depth, for the re-entrant survey lock
_held_guard = threading.Lock()


class ProjectBusy(OSError):
    """Another run holds the lock and this one was told not to wait (names the lock's holder)."""

    def __init__(self, path: Path, holder: str):
        super().__init__(errno.EBUSY, f"{holder}; not waiting (--no-wait): run again when it has finished", str(path))


@contextlib.contextmanager
def waiting_policy(wait: bool, announce: Callable[[str], None] | None = None) -> Iterator[None]:
    """Inside the block a busy lock is waited for, ``announce`` told why (the CLI prints it; without
    it the message goes to the run's progress), or with ``wait`` False raises :class:`ProjectBusy`."""
    tokens = (_wait.set(wait), _announce.set(announce))
    try:
        yield
    finally:
        _announce.reset(tokens[1])
        _wait.reset(tokens[0])


def _open(path: Path) -> int:
    path.parent.mkdir(parents=True, exist_ok=True)
    return os.open(path, os.O_RDWR | os.O_CREAT | getattr(os, "O_CLOEXEC", 0), 0o644)


def _try(fd: int, how: int) -> bool:
    try:
        fcntl.flock(fd, how | fcntl.LOCK_NB)
        return True
    except BlockingIOError:
        return False


def _holder(fd: int) -> str:
    """Who holds the lock, as its holder wrote it ('another run' while it has not yet)."""
    try:
        text = os.pread(fd, 512, 0).decode("utf-8", "replace").strip()
    except OSError:
        text = ""
    return text or "another run of this project"


def _acquire(fd: int, path: Path, what: str, project_folder: Path, progress: ProgressFn | None,
             cancel: CancelToken) -> None:
    """Take ``what``'s lock (a survey's, a cache entry's) exclusively, waiting (with a message) or
    raising :class:`ProjectBusy` as the caller chose; then name this run as its holder."""
    how = fcntl.LOCK_EX
    if _try(fd, how):
        _name_holder(fd)
        return
    holder = _holder(fd)
    if not _wait.get():
        raise ProjectBusy(project_folder, f"{what} is in use by {holder}")
    message = Phrase("waiting for {holder} to finish ({file})", {"holder": holder, "file": str(path)})
    announce = _announce.get()
    if announce is not None:
        announce(str(message))
    elif progress is not None:
        progress(0.0, message)
    while not _try(fd, how):
        check_cancel(cancel)
        time.sleep(POLL_S)
    _name_holder(fd)


def _name_holder(fd: int) -> None:
    """What a run waiting for this lock is shown: this run's start, PID and command line."""
    started = time.strftime("%Y-%m-%d %H:%M:%S", time.localtime())
    os.ftruncate(fd, 0)
    os.pwrite(fd, f"the run started at {started} by PID {os.getpid()} ({command_line()})".encode(), 0)


def _survey_lock_file(project_folder: Path, survey: str) -> Path:
    return project_folder / LOCK_FOLDER / f"survey-{quote(survey, safe='')}.lock"


@contextlib.contextmanager
def project_run(project_folder: Path, surveys: Iterable[str], progress: ProgressFn | None = None,
                cancel: CancelToken = None, when_alone: Callable[[], None] | None = None) -> Iterator[None]:
    """Hold the project's lock (shared) and the locks of ``surveys`` (exclusive) for the block.

    Whoever waits is shown this process's command line; ``when_alone`` runs first when no other run
    of the project is going on (see the module docstring)."""
    if fcntl is None:
        yield
        return
    project_folder = Path(project_folder).resolve()
    thread = threading.get_ident()
    try:
        project_fd = _open(project_folder / LOCK_FOLDER / "project.lock")
    except OSError as err:
        if err.errno not in (errno.EACCES, errno.EPERM, errno.EROFS):
            raise
        project_fd = None
    if project_fd is None:  # a project this user may only read: there is nothing of it this run can write either
        yield
        return
    with contextlib.ExitStack() as stack:
        stack.callback(os.close, project_fd)
        if _try(project_fd, fcntl.LOCK_EX):  # no other run of the project: nobody holds or waits for an entry
            for entry_lock in (project_folder / LOCK_FOLDER).glob(f"{CACHE_LOCK_PREFIX}*.lock"):
                entry_lock.unlink(missing_ok=True)
            if when_alone is not None:
                when_alone()
        fcntl.flock(project_fd, fcntl.LOCK_SH)  # from exclusive: converted; else waits for a cleaning run (short)
        for survey in sorted(set(surveys)):  # always in one order: two runs of several surveys cannot deadlock
            path = _survey_lock_file(project_folder, survey)
            key = (path, thread)
            with _held_guard:
                if key in _held:
                    _held[key] += 1
                    stack.callback(_release, key, None)
                    continue
            fd = _open(path)
            stack.callback(os.close, fd)
            _acquire(fd, path, f"survey {survey}", project_folder, progress, cancel)
            with _held_guard:
                _held[key] = 1
            stack.callback(_release, key, fd)
        yield


@contextlib.contextmanager
def cache_entry(project_folder: Path, entry: str, progress: ProgressFn | None = None,
                cancel: CancelToken = None) -> Iterator[None]:
    """Hold the lock of the cache entry ``entry`` (its file name without suffix, ``fusion-<key>``)
    for the block, in which the caller looks it up and, when absent, computes and writes it (see
    the module docstring). Call it inside :func:`project_run`."""
    if fcntl is None:
        yield
        return
    project_folder = Path(project_folder).resolve()
    path = project_folder / LOCK_FOLDER / f"{CACHE_LOCK_PREFIX}{quote(entry, safe='')}.lock"
    try:
        fd = _open(path)
    except OSError as err:
        if err.errno not in (errno.EACCES, errno.EPERM, errno.EROFS):
            raise
        yield  # a project this user may only read: no entry can be written either
        return
    try:
        _acquire(fd, path, f"the cache entry {entry}", project_folder, progress, cancel)
        try:
            yield
        finally:
            os.ftruncate(fd, 0)
    finally:
        os.close(fd)


def _release(key: tuple[Path, int], fd: int | None) -> None:
    with _held_guard:
        _held[key] -= 1
        if _held[key]:
            return
        del _held[key]
    if fd is not None:
        os.ftruncate(fd, 0)  # before the lock goes with the descriptor: no holder left named


def command_line() -> str:
    """How this process was started, for the lock's holder text ("insrail process PROJECT", "insrail gui")."""
    return " ".join([Path(sys.argv[0]).name, *sys.argv[1:]])[:200] if sys.argv and sys.argv[0] else "insrail"
