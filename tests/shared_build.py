"""Costly test inputs made once per test run and shared by pytest-xdist's workers.

Each xdist worker runs its own session, so a session fixture alone is still made once per worker (twice
with ``-n 2``). These helpers make an input once in the run's temporary folder, common to the workers:
whoever asks first makes it under a file lock, the others wait for it and then read it. A failed make
leaves nothing behind, and the next one to ask tries again (and fails the same way, in its own test).
What is made here must be read-only for the tests: copy it before writing to it.
"""

from __future__ import annotations

import fcntl
import os
import pickle
import shutil
import subprocess
from collections.abc import Callable
from pathlib import Path
from typing import TypeVar

T = TypeVar("T")

RUN_FOLDER: Path | None = None  # the run's temporary folder, set by conftest's session fixture


def run_folder(tmp_path_factory) -> Path:
    """The test run's temporary folder: a worker's base folder is one level below it."""
    base = tmp_path_factory.getbasetemp()
    return base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base


def _shared(name: str) -> Path:
    if RUN_FOLDER is None:
        raise RuntimeError("shared_build.RUN_FOLDER is set by tests/conftest.py's session fixture")
    folder = RUN_FOLDER / "shared"
    folder.mkdir(exist_ok=True)
    return folder / name


def built_once(name: str, build: Callable[[Path], None]) -> Path:
    """The folder ``name``, filled by ``build(folder)`` once per test run (``folder`` does not exist yet)."""
    folder = _shared(name)
    done = folder.with_name(name + ".done")
    with open(folder.with_name(name + ".lock"), "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not done.exists():
            shutil.rmtree(folder, ignore_errors=True)
            build(folder)
            done.touch()
    return folder


def computed_once(name: str, compute: Callable[[], T]) -> T:
    """``compute()``, called once per test run; the value (pickled) is read back by every other caller."""

    def build(folder: Path) -> None:
        value = compute()
        folder.mkdir()
        (folder / "value.pickle").write_bytes(pickle.dumps(value))

    return pickle.loads((built_once(name, build) / "value.pickle").read_bytes())


#: The environment variable naming, in a process started by :func:`start_holding`, the descriptor of its lock
HELD_LOCK_FD = "SHARED_BUILD_HELD_LOCK_FD"


def start_holding(run_folder: Path, name: str, argv: list[str]) -> subprocess.Popen:
    """Starts ``argv`` in the background holding the lock of ``name`` until it ends or calls :func:`release_held`
    (the lock passes to it with its file descriptor); its output goes to ``name.log``. :func:`wait_for` waits
    for it."""
    folder = run_folder / "shared"
    folder.mkdir(exist_ok=True)
    with open(folder / (name + ".lock"), "w") as lock, open(folder / (name + ".log"), "w") as log:
        fcntl.flock(lock, fcntl.LOCK_EX)
        return subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=log, stderr=subprocess.STDOUT,
                                pass_fds=(lock.fileno(),), env={**os.environ, HELD_LOCK_FD: str(lock.fileno())})


def release_held() -> None:
    """In a process started by :func:`start_holding`: lets the lock go before the process ends."""
    os.close(int(os.environ.pop(HELD_LOCK_FD)))


def wait_for(name: str) -> None:
    """Returns once no process started by :func:`start_holding` for ``name`` runs any more (at once if none was)."""
    lock_path = _shared(name).with_name(name + ".lock")
    if lock_path.exists():
        with open(lock_path) as lock:
            fcntl.flock(lock, fcntl.LOCK_SH)
