"""One project, one writer (insrail.project.lock): a second run of a survey waits for the first or,
told not to wait, says who holds it; the lock of a killed run is taken over; surveys of one
project do not wait for each other; what killed runs left is cleaned only by a run alone."""

from __future__ import annotations

import errno
import os
import signal
import subprocess
import sys
import threading
import time

import pytest

from insrail.progress import Cancelled
from insrail.project import lock
from insrail.project.lock import LOCK_FOLDER, ProjectBusy, cache_entry, project_run, waiting_policy


def hold_in_child(project, survey: str):
    """Another process holding ``survey``'s lock (until killed); returns it once it holds it."""
    code = ("import sys, time\nfrom insrail.project.lock import project_run\n"
            "with project_run(sys.argv[1], [sys.argv[2]]):\n    print('held', flush=True)\n    time.sleep(600)\n")
    child = subprocess.Popen([sys.executable, "-c", code, str(project), survey], stdout=subprocess.PIPE, text=True)
    assert child.stdout.readline().strip() == "held"
    return child


def test_a_second_run_told_not_to_wait_names_the_holder(tmp_path):
    child = hold_in_child(tmp_path, "north")
    try:
        with waiting_policy(wait=False), pytest.raises(ProjectBusy) as caught:
            with project_run(tmp_path, ["north"]):
                pass
        assert f"by PID {child.pid}" in str(caught.value) and "survey north" in str(caught.value)
        assert caught.value.filename == str(tmp_path.resolve())
        with waiting_policy(wait=False), project_run(tmp_path, ["south"]):  # another survey: no wait
            pass
    finally:
        child.kill()
        child.wait()


def test_the_lock_of_a_killed_run_is_taken_over(tmp_path):
    child = hold_in_child(tmp_path, "north")
    os.kill(child.pid, signal.SIGKILL)
    child.wait()
    with waiting_policy(wait=False), project_run(tmp_path, ["north"]):
        assert f"by PID {os.getpid()}" in (tmp_path / LOCK_FOLDER / "survey-north.lock").read_text()


def test_a_waiting_run_says_for_whom_and_goes_on_when_the_holder_ends(tmp_path):
    child = hold_in_child(tmp_path, "north")
    messages, done = [], threading.Event()

    def second_run():
        with waiting_policy(wait=True, announce=messages.append), project_run(tmp_path, ["north"]):
            done.set()

    thread = threading.Thread(target=second_run)
    thread.start()
    try:
        time.sleep(1.0)
        assert not done.is_set()
        assert len(messages) == 1 and messages[0].startswith("waiting for the run started at ")
        assert f"by PID {child.pid}" in messages[0]
    finally:
        child.kill()
        child.wait()
    thread.join(10)
    assert done.is_set()


def test_a_waiting_run_can_be_cancelled(tmp_path):
    child = hold_in_child(tmp_path, "north")
    cancel = threading.Event()
    cancel.set()
    try:
        with pytest.raises(Cancelled), project_run(tmp_path, ["north"], progress=lambda f, m: None, cancel=cancel):
            pass
    finally:
        child.kill()
        child.wait()


def test_the_lock_is_reentrant_in_one_thread_and_cleans_only_when_alone(tmp_path):
    cleaned = []
    with project_run(tmp_path, ["north"], when_alone=lambda: cleaned.append(1)):
        with project_run(tmp_path, ["north", "south"], when_alone=lambda: cleaned.append(2)):  # no deadlock
            pass
    assert cleaned == [1]  # the inner one is not alone: the outer holds the project


def test_a_project_this_user_may_only_read_is_not_locked(tmp_path, monkeypatch):
    def read_only(path):
        raise PermissionError(errno.EACCES, "Permission denied", str(path))

    monkeypatch.setattr(lock, "_open", read_only)
    with project_run(tmp_path, ["north"]):  # as for an export from a colleague's share
        pass
    monkeypatch.setattr(lock, "_open", lambda path: (_ for _ in ()).throw(OSError(errno.EIO, "I/O error", str(path))))
    with pytest.raises(OSError, match="I/O error"), project_run(tmp_path, ["north"]):
        pass


def test_a_cache_entry_held_by_another_process_is_waited_for_and_its_lock_removed_only_by_a_run_alone(tmp_path):
    code = ("import sys, time\nfrom insrail.project.lock import cache_entry, project_run\n"
            "with project_run(sys.argv[1], []), cache_entry(sys.argv[1], 'fusion-abc'):\n"
            "    print('held', flush=True)\n    time.sleep(600)\n")
    child = subprocess.Popen([sys.executable, "-c", code, str(tmp_path)], stdout=subprocess.PIPE, text=True)
    entry_lock = tmp_path / LOCK_FOLDER / "cache-fusion-abc.lock"
    try:
        assert child.stdout.readline().strip() == "held"
        with waiting_policy(wait=False), pytest.raises(ProjectBusy, match=f"the cache entry fusion-abc is in use by "
                                                                          f"the run started at .* by PID {child.pid}"):
            with project_run(tmp_path, ["north"]), cache_entry(tmp_path, "fusion-abc"):
                pass
        assert entry_lock.exists()  # that run was not alone: the lock file stays
        messages = []
        threading.Timer(1.0, child.kill).start()
        with waiting_policy(wait=True, announce=messages.append), project_run(tmp_path, ["north"]):
            with cache_entry(tmp_path, "fusion-abc"):
                assert f"by PID {os.getpid()}" in entry_lock.read_text()
        assert len(messages) == 1 and f"by PID {child.pid}" in messages[0] and str(entry_lock) in messages[0]
    finally:
        child.kill()
        child.wait()
    with project_run(tmp_path, ["north"]):  # alone: nobody can hold or wait for an entry
        assert not entry_lock.exists()
