"""The CPU budget (insrail.background.cpu_budget): the process's CPUs, narrowed by the batch (a local worker's
share of the cores, a Dask worker's threads), seen by the threads of its jobs, and kept to by every pool."""

from __future__ import annotations

import os
import threading
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from types import SimpleNamespace

import pytest

from insrail.background import BackgroundJob, cpu_budget, cpus_limited
from insrail.project import batch
from insrail.project.batch import BatchTask, run_task, worker_cpus


def cores(monkeypatch, count: int) -> None:
    """This process may run on ``count`` CPUs."""
    monkeypatch.setattr(os, "cpu_count", lambda: count)
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: set(range(count)), raising=False)


def test_the_budget_is_the_affinity_narrowed_by_a_limit_that_only_narrows(monkeypatch):
    cores(monkeypatch, 8)
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: {0, 1, 2}, raising=False)  # taskset: 3 of the 8
    assert cpu_budget() == 3
    with cpus_limited(2):
        assert cpu_budget() == 2
        with cpus_limited(5):  # a wider limit inside a narrower one does not widen it
            assert cpu_budget() == 2
        with cpus_limited(None):
            assert cpu_budget() == 2
    with cpus_limited(16):
        assert cpu_budget() == 3
    with cpus_limited(0):
        assert cpu_budget() == 1
    assert cpu_budget() == 3


def test_a_jobs_thread_keeps_the_callers_budget_and_one_thread_runs_it_in_the_caller(monkeypatch):
    cores(monkeypatch, 4)
    with cpus_limited(2):
        job = BackgroundJob(lambda progress, cancel: (cpu_budget(), threading.current_thread()), None, None, "budget")
        budget, thread = job.result()
    assert budget == 2 and thread is not threading.current_thread()
    with cpus_limited(1):
        budget, thread = BackgroundJob(lambda progress, cancel: (cpu_budget(), threading.current_thread()), None,
                                       None, "budget").result()
    assert budget == 1 and thread is threading.current_thread()


def test_local_batch_workers_share_the_cores(monkeypatch):
    cores(monkeypatch, 4)
    assert [worker_cpus(n) for n in (1, 2, 3, 4, 8)] == [4, 2, 1, 1, 1]


def test_a_batch_task_runs_its_survey_within_the_cpus_it_was_given(monkeypatch):
    cores(monkeypatch, 4)
    seen = []

    def process(project, survey):
        seen.append(cpu_budget())
        return SimpleNamespace(folder=Path("results") / survey)

    monkeypatch.setattr(batch, "load_project", lambda path: "project")
    monkeypatch.setattr("insrail.project.pipeline.process", process)
    for cpus in (1, 2, None):
        assert run_task(BatchTask(Path("project.toml"), "run1"), cpus).ok
    assert seen == [1, 2, 4]
    assert cpu_budget() == 4  # the limit ends with the task


@pytest.mark.parametrize("threads", [1, 2])
def test_a_task_on_a_dask_worker_gets_the_workers_threads(threads, monkeypatch):
    distributed = pytest.importorskip("distributed")
    cores(monkeypatch, 4)

    def budgets():  # the task's own, and a job's beside it (its thread started from the task)
        with BackgroundJob(lambda progress, cancel: cpu_budget(), None, None, "beside", threaded=True) as job:
            return cpu_budget(), job.result()

    with distributed.LocalCluster(n_workers=1, threads_per_worker=threads, processes=False,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as client:
        assert client.submit(budgets, pure=False).result() == (threads, threads)
    assert cpu_budget() == 4  # outside the worker's tasks, in the same process: the process's


def test_the_adjustment_keeps_to_the_budget(monkeypatch):
    """The adjustment sizes its pools by the budget: a batch worker of one CPU solves the directions and
    parts one at a time (the same amounts)."""
    from test_track_adjustment_parts import kinked_track

    from insrail.track import adjustment
    from insrail.track.adjustment import load_fastener_type, optimise_amounts
    from insrail.track.tolerance import load_tolerance_profile

    cores(monkeypatch, 4)
    pools = []

    class Recorded(ThreadPoolExecutor):
        def __init__(self, max_workers=None, *args, **kwargs):
            pools.append(max_workers)
            super().__init__(max_workers, *args, **kwargs)

    monkeypatch.setattr(adjustment, "ThreadPoolExecutor", Recorded)
    geometry = kinked_track([400, 1900], 2400)
    amounts = {}
    for cpus in (1, 4):
        pools.clear()
        with cpus_limited(cpus):
            amounts[cpus] = optimise_amounts(geometry, load_tolerance_profile(), load_fastener_type())
        assert pools == [min(2, cpus), cpus]  # the directions' pool, the parts'
    for one, four in zip(amounts[1], amounts[4]):
        assert one.tobytes() == four.tobytes()


def test_the_rails_of_a_one_cpu_run_are_made_in_its_own_thread(monkeypatch):
    from insrail.track import streamed

    cores(monkeypatch, 4)
    pools = []
    monkeypatch.setattr(streamed, "ThreadPoolExecutor", lambda threads, **kwargs: pools.append(threads))
    track = SimpleNamespace(parts=[(0, 5), (5, 5)], check=lambda: None,
                            _part_rails=lambda start, count: (start, threading.current_thread()))
    with cpus_limited(1):
        made = list(streamed._Streamed._rails_in_order(track))
    assert made == [(0, threading.current_thread()), (5, threading.current_thread())] and pools == []


def test_a_run_of_one_cpu_writes_its_reports_in_one_process(monkeypatch):
    from insrail.report import both

    cores(monkeypatch, 4)
    monkeypatch.setattr(both, "running_tasks", lambda: 1.0)
    assert both.side_by_side(both.SIDE_BY_SIDE_MIN_SLEEPERS)
    with cpus_limited(1):
        assert not both.side_by_side(both.SIDE_BY_SIDE_MIN_SLEEPERS)
