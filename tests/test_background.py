"""BackgroundJob: a job beside the calling thread, its progress said by the caller (forward only),
its exception raised where its result is asked for, stopped with the caller, serial on one CPU."""

import threading
import time

import pytest

from insrail import background
from insrail.background import BackgroundJob
from insrail.progress import Cancelled, check_cancel


def stepping(steps: int, pause_s: float = 0.0, fail_at: int | None = None, release: threading.Event | None = None):
    """A job saying steps/steps of progress, checking the cancel at each step."""
    def job(progress, cancel):
        if release is not None:
            release.wait(5.0)
        for k in range(steps):
            check_cancel(cancel)
            if k == fail_at:
                raise ValueError(f"step {k}: the covariance record ends early")
            progress((k + 1) / steps, "covariance: smoother")
            time.sleep(pause_s)
        return threading.current_thread().name
    return job


def test_the_job_runs_in_its_own_thread_and_its_progress_is_said_by_the_caller_forward_only():
    said = []

    def progress(fraction, message):
        said.append((fraction, message, threading.current_thread() is threading.main_thread()))

    job = BackgroundJob(stepping(20, 0.002), None, None, "analysis", threaded=True)
    for _ in range(50):
        job.relay(progress)
        time.sleep(0.001)
    assert job.result(progress) == "analysis"
    fractions = [f for f, _, _ in said]
    assert said and all(in_caller for _, _, in_caller in said)
    assert fractions == sorted(set(fractions)) and fractions[-1] == 1.0
    assert {m for _, m, _ in said} == {"covariance: smoother"}


def test_the_jobs_exception_is_raised_by_result_with_its_message():
    job = BackgroundJob(stepping(10, fail_at=3), None, None, "analysis", threaded=True)
    with pytest.raises(ValueError, match="step 3: the covariance record ends early") as raised:
        job.result()
    assert any(frame.name == "job" for frame in __import__("traceback").extract_tb(raised.value.__traceback__))


def test_the_callers_cancel_stops_the_job():
    cancel = threading.Event()
    job = BackgroundJob(stepping(10_000, 0.001), None, cancel, "analysis", threaded=True)
    cancel.set()
    with pytest.raises(Cancelled):
        job.result()


def test_stop_ends_the_job_and_waits_for_it():
    release = threading.Event()
    job = BackgroundJob(stepping(10_000, 0.001, release=release), None, None, "analysis", threaded=True)
    release.set()
    job.stop()
    assert not any(thread.name == "analysis" for thread in threading.enumerate())


def test_on_one_cpu_the_job_runs_at_once_in_the_caller_with_the_progress_given(monkeypatch):
    monkeypatch.setattr(background.os, "cpu_count", lambda: 1)
    said = []
    job = BackgroundJob(stepping(4), lambda f, m: said.append(f), None, "analysis")
    assert said == [0.25, 0.5, 0.75, 1.0]  # said before the constructor returned
    assert job.result() == threading.current_thread().name
    job.relay(lambda f, m: said.append(f))  # nothing more to say
    assert said == [0.25, 0.5, 0.75, 1.0]
    with pytest.raises(ValueError, match="step 1"):
        BackgroundJob(stepping(4, fail_at=1), None, None, "analysis")


def test_as_a_context_manager_a_failure_in_the_block_stops_the_job_and_leaves_no_thread():
    with pytest.raises(KeyError, match="the caller's own failure"):
        with BackgroundJob(stepping(10_000, 0.001), None, None, "figures", threaded=True) as job:
            raise KeyError("the caller's own failure")
    assert not any(thread.name == "figures" for thread in threading.enumerate())
    with BackgroundJob(stepping(3), None, None, "figures", threaded=True) as job:
        assert job.result() == "figures"
