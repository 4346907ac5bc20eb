"""Every survey of many projects processed in parallel: on this machine's cores or on a Dask cluster.

Each (project, survey) is one task running :func:`insrail.project.process` in a worker, exactly
as ``insrail process`` would: same cache, same result files, so a batch gives the same results
as single runs. A task that fails is reported (its outcome holds the error) and the others go
on. Locally the tasks run in a ``ProcessPoolExecutor`` (spawned processes: one survey per
process at a time, so peak memory is ``workers`` times one survey's, about 2 GB for a 10 km
survey). With a Dask scheduler address the tasks are submitted to that cluster
(``pip install insrail[cluster]``); its workers must see the project folders under the same
paths (a shared file system).

A task's own threads (the fusion's pass beside it, the track's, the adjustment's) keep to the task's
CPU budget (:func:`insrail.background.cpu_budget`): in a local worker process its share of the cores
(``max(1, cores // workers)``, given with the task), on a Dask worker the worker's threads. So the
batch keeps as many CPUs busy as it has workers' threads, not that many times each run's threads.

Security: a Dask scheduler runs whatever its clients submit, and its workers unpickle what they
receive. Anyone who can reach a plain ``tcp://`` scheduler can run code on every worker, with
access to every project folder they see. Run the scheduler on a trusted network only, or with
TLS: a ``tls://`` address and Dask's security settings (``distributed.comm.tls.*``, with
``distributed.comm.require-encryption: true``) from a Dask configuration file given as
``security`` (:func:`dask_security`), as ``distributed.security.Security`` reads them.

A line section (:mod:`insrail.project.section`) is batched with :func:`run_section_batch`: its runs
are the tasks (on the cores or the cluster, as above), and once every run is processed the section
is joined here, in the coordinating process, from the result files the workers wrote; each run's files
are read here as it finishes, while the others are processed, so that the join finds their parse in the
user's cache (:mod:`insrail.project.table_cache`). On a cluster the join's adjustment (most of the join's
work) goes back to the workers, through the batch's one client, its independent parts as tasks
(:func:`insrail.track.adjustment.optimise_amounts`). The joined section is the one ``insrail
process`` of each run and ``insrail section`` give.

Cancelling (the ``cancel`` token, or Ctrl-C in the CLI) stops scheduling: tasks not started are
dropped, running ones are left to finish (or are interrupted by the same Ctrl-C, which leaves
their previous results in place), and :class:`insrail.progress.Cancelled` is raised.
"""

from __future__ import annotations

import sys
import time
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from dataclasses import dataclass
from multiprocessing import get_context
from pathlib import Path
from typing import TYPE_CHECKING, Callable

from insrail.background import cpu_budget, cpus_limited
from insrail.io.errors import InputError
from insrail.notices import Phrase
from insrail.progress import Cancelled, CancelToken, ProgressFn, is_cancelled
from insrail.project.model import PROJECT_FILE, Project, load_project

if TYPE_CHECKING:
    from insrail.project.section import SectionResult

#: How often [s] the coordinator looks at the cancel token while tasks run.
POLL_S = 0.2


@dataclass(frozen=True)
class BatchTask:
    """One survey to process; ``size_bytes``: its folder's files (the order tasks start in, :func:`longest_first`)."""

    project_file: Path
    survey: str
    size_bytes: int = 0


@dataclass(frozen=True)
class BatchOutcome:
    """What became of one task: ``detail`` is the results folder, or the error when not ``ok``."""

    project_file: Path
    survey: str
    ok: bool
    detail: str
    elapsed_s: float

    @property
    def label(self) -> str:
        """``<project folder>/<survey>``; a project that did not load shows its path and ``*``."""
        project = self.project_file.parent.name if self.project_file.name == PROJECT_FILE else str(self.project_file)
        return f"{project}/{self.survey}"


def batch_tasks(projects: list[str | Path]) -> tuple[list[BatchTask], list[BatchOutcome]]:
    """One task per survey of every project; a project that cannot be loaded is a failed outcome."""
    tasks, failed = [], []
    for given in projects:
        path = Path(given)
        path = path / PROJECT_FILE if path.is_dir() else path
        try:
            project = load_project(path)
        except InputError as error:
            failed.append(BatchOutcome(path, "*", False, str(error), 0.0))
            continue
        tasks += [BatchTask(project.path, survey.name, survey_bytes(project, survey.name)) for survey in project.surveys]
    return tasks, failed


def survey_bytes(project: Project, survey: str) -> int:
    """The size of the files in a survey's folder (its records; 0 for a folder that cannot be read: the
    processing says why)."""
    try:
        return sum(entry.stat().st_size for entry in project.resolve(project.survey(survey).folder).iterdir()
                   if entry.is_file())
    except OSError:
        return 0


def longest_first(tasks: list[BatchTask]) -> list[BatchTask]:
    """The tasks in the order they are started: the largest survey first (its processing time follows its
    records, the IMU's above all), so that the last task to start on fewer workers than tasks is a short one
    and no worker is left with a long one after the others are done; equal sizes keep their order."""
    return sorted(tasks, key=lambda task: -task.size_bytes)


def section_tasks(project: Project, sections: list[str]) -> list[BatchTask]:
    """One task per run of the named sections (a run shared by two sections once, in section order).
    KeyError for a section the project does not define."""
    surveys = dict.fromkeys(survey for name in sections for survey in project.section(name).surveys)
    return [BatchTask(project.path, survey, survey_bytes(project, survey)) for survey in surveys]


def run_task(task: BatchTask, cpus: int | None = None) -> BatchOutcome:
    """Process one survey (in a worker) with at most ``cpus`` threads busy (None: the worker's own
    budget, a Dask worker's threads). Any error becomes a failed outcome: one bad survey must not take
    the batch down."""
    from insrail.memory import tune_allocator
    from insrail.project.pipeline import process

    tune_allocator()  # a worker is a process of its own (spawned, or a Dask worker)
    started = time.monotonic()
    try:
        with cpus_limited(cpus):
            results = process(load_project(task.project_file), task.survey)
    except Exception as error:  # noqa: BLE001 - reported per survey, with its type
        detail = str(error) if isinstance(error, InputError) else f"{type(error).__name__}: {error}"
        return BatchOutcome(task.project_file, task.survey, False, detail, time.monotonic() - started)
    return BatchOutcome(task.project_file, task.survey, True, str(results.folder), time.monotonic() - started)


def dask_security(config_file: str | Path):
    """``distributed.security.Security`` from a Dask YAML configuration file (the format of
    ``~/.config/dask/distributed.yaml``): its ``distributed.comm.tls`` keys (``ca-file``,
    ``client.cert``, ``client.key``; a path or the PEM text) and ``distributed.comm.require-encryption``.
    InputError naming the file for a file that cannot be read or names a missing certificate."""
    import dask.config
    import yaml
    from distributed.security import Security

    path = Path(config_file)
    try:
        document = yaml.safe_load(path.read_text(encoding="utf-8"))
    except OSError as err:
        raise InputError(path, None, "cannot read the Dask security settings: {strerror}", fields={"strerror": err.strerror}) from None
    except yaml.YAMLError as err:
        raise InputError(path, None, "not a Dask YAML configuration file: {err}", fields={"err": err}) from None
    if not isinstance(document, dict) or not isinstance(document.get("distributed", {}).get("comm"), dict):
        raise InputError(path, None, "expected Dask settings under distributed.comm (tls: ca-file, client: cert, "
                         "key; require-encryption)")
    tls = document["distributed"]["comm"].get("tls", {}) or {}
    for key, value in (("ca-file", tls.get("ca-file")), ("client.cert", (tls.get("client") or {}).get("cert")),
                       ("client.key", (tls.get("client") or {}).get("key"))):
        if isinstance(value, str) and "-----BEGIN" not in value and not Path(value).expanduser().is_file():
            raise InputError(path, None, "distributed.comm.tls.{key}: file not found: {file}", fields={"key": key, "file": value})
    with dask.config.set(_dotted(document)):  # key by key: Dask's other defaults stay
        return Security()


def _dotted(document: dict, prefix: str = "") -> dict:
    """``{"a": {"b": 1}}`` -> ``{"a.b": 1}``."""
    flat = {}
    for key, value in document.items():
        name = f"{prefix}{key}"
        flat.update(_dotted(value, name + ".") if isinstance(value, dict) else {name: value})
    return flat


def run_batch(projects: list[str | Path], workers: int | None = None, scheduler: str | None = None,
              progress: ProgressFn | None = None, cancel: CancelToken = None,
              security=None) -> list[BatchOutcome]:
    """Process every survey of ``projects`` (folders or project.toml files) with ``workers``
    local processes (default: one per core), or on the Dask cluster at ``scheduler`` (its
    workers decide the parallelism; ``security``: a ``distributed.security.Security``, see
    :func:`dask_security`); outcomes in task order, projects that failed to load first. ``progress`` gets one call per finished task
    with the fraction done and ``"<project>/<survey>: done in 12.3 s"`` or ``"...: FAILED: why"``."""
    tasks, failed = batch_tasks(projects)
    return _run_tasks(tasks, failed, workers, scheduler, progress, cancel, security)


def _run_tasks(tasks: list[BatchTask], failed: list[BatchOutcome], workers, scheduler,
               progress: ProgressFn | None, cancel: CancelToken, security, client=None,
               finished: Callable[[BatchOutcome], None] | None = None) -> list[BatchOutcome]:
    """Run ``tasks`` after reporting ``failed`` (projects that did not load); outcomes in task order,
    ``failed`` first. ``client``: a Dask client of the cluster at ``scheduler`` to submit to (default: one
    for this batch); ``finished`` is called with each task's outcome as it comes, before its progress."""
    outcomes: list[BatchOutcome] = []
    total = len(tasks) + len(failed)

    def report(outcome: BatchOutcome) -> None:
        outcomes.append(outcome)
        if finished is not None:
            finished(outcome)
        if progress is not None:
            progress(len(outcomes) / total,
                     Phrase("{survey}: done in {elapsed_s:.1f} s", {"survey": outcome.label, "elapsed_s": outcome.elapsed_s})
                     if outcome.ok else Phrase("{survey}: FAILED: {error}", {"survey": outcome.label, "error": outcome.detail}))

    for outcome in failed:
        report(outcome)
    if tasks and client is not None:
        _run_on_dask(tasks, client, report, cancel)
    elif tasks and scheduler is not None:
        with _dask_client(scheduler, security) as client:
            _run_on_dask(tasks, client, report, cancel)
    elif tasks:
        _run_locally(tasks, workers, report, cancel)
    order = {(t.project_file, t.survey): i for i, t in enumerate(tasks)}
    return sorted(outcomes, key=lambda o: order.get((o.project_file, o.survey), -1))


def run_section_batch(project: Project, sections: list[str], workers: int | None = None,
                      scheduler: str | None = None, progress: ProgressFn | None = None,
                      cancel: CancelToken = None, security=None) -> tuple[list[BatchOutcome], list[SectionResult]]:
    """Process the runs of the project's ``sections`` as :func:`run_batch` does (locally or on the Dask
    cluster at ``scheduler``), then join each section here (:func:`insrail.project.section.join_section`).
    When a run failed no section is joined (its outcome says why): the section results are then empty."""
    from insrail.project.section import join_section

    tasks = section_tasks(project, sections)
    if scheduler is None:
        outcomes = _run_tasks(tasks, [], workers, None, progress, cancel, security, finished=_read_ahead(project))
        if not all(o.ok for o in outcomes):
            return outcomes, []
        return outcomes, [join_section(project, name, cancel=cancel) for name in sections]
    with _dask_client(scheduler, security) as client:  # the runs, then the join's adjustment, on the cluster's workers
        outcomes = _run_tasks(tasks, [], None, scheduler, progress, cancel, security, client, _read_ahead(project))
        if not all(o.ok for o in outcomes):
            return outcomes, []
        executor = client.get_executor(pure=False)
        return outcomes, [join_section(project, name, cancel=cancel, executor=executor) for name in sections]


def _read_ahead(project: Project) -> Callable[[BatchOutcome], None]:
    """What to do with each processed run while the others are still processed: read its results once, so
    that the user's cache of parsed sleeper tables (:mod:`insrail.project.table_cache`) holds them when the
    section is joined (the join reads the files again under its lock: the cache answers only for the very
    bytes it parsed). Nothing without such a cache; a run that cannot be read here is left to the join to report."""
    from insrail.project import table_cache
    from insrail.project.results import load_results

    def read(outcome: BatchOutcome) -> None:
        if outcome.ok and table_cache.cache_folder() is not None:
            try:
                load_results(project.folder, outcome.survey)
            except Exception:  # noqa: BLE001 - the join reads the run again and says what is wrong with it
                pass

    return read


def _outcome(future, task: BatchTask) -> BatchOutcome:
    """The task's outcome, or a failed one when its worker died (killed, out of memory)."""
    try:
        return future.result()
    except Exception as error:  # noqa: BLE001 - the worker, not the survey, failed
        return BatchOutcome(task.project_file, task.survey, False, f"worker lost: {type(error).__name__}: {error}", 0.0)


def worker_cpus(workers: int) -> int:
    """The CPU budget of each of ``workers`` local worker processes: their share of this one's."""
    return max(1, cpu_budget() // workers)


def _run_locally(tasks, workers, report, cancel) -> None:
    workers = max(1, min(workers or cpu_budget(), len(tasks)))
    cpus = worker_cpus(workers)
    waiting = longest_first(tasks)
    pending = {}
    with ProcessPoolExecutor(workers, mp_context=get_context("spawn")) as pool:

        def start_more() -> None:  # no more tasks in flight than workers: the rest stay cancellable
            while waiting and len(pending) < workers:
                task = waiting.pop(0)
                pending[pool.submit(run_task, task, cpus)] = task

        try:
            start_more()
            while pending:
                done, _ = wait(pending, timeout=POLL_S, return_when=FIRST_COMPLETED)
                for future in done:
                    report(_outcome(future, pending.pop(future)))
                if is_cancelled(cancel):
                    raise Cancelled("batch cancelled by the user")
                start_more()
        except BaseException:
            for future in pending:
                future.cancel()
            raise


def _dask_client(scheduler: str, security=None):
    try:
        from distributed import Client
    except ImportError:
        raise RuntimeError("a Dask scheduler needs the 'distributed' package: pip install insrail[cluster]") from None
    client = Client(scheduler, timeout="10s", security=security)
    if sys.version_info < (3, 12):
        client.run(_stop_statistical_profiler)
    return client


def _stop_statistical_profiler(dask_worker) -> None:
    """Stop a Dask worker's statistical profiler (the dashboard's profile: ``sys._current_frames()`` every 10 ms).

    Why: on Python 3.11 ``sys._current_frames()`` can deadlock the whole worker process (CPython gh-106883,
    dask/distributed#8616: it holds the runtime's lock while allocating, a garbage collection then frees a
    thread-local object that takes the same lock). A batch that hangs for ever is worse than a dashboard
    without its profile. Workers joining after the client connected keep theirs: start them with
    ``DASK_DISTRIBUTED__WORKER__PROFILE__ENABLED=False`` (README, "A line section on a Dask cluster")."""
    for name in ("profile", "profile-cycle"):
        callback = dask_worker.periodic_callbacks.pop(name, None)
        if callback is not None:
            callback.stop()


def _run_on_dask(tasks, client, report, cancel) -> None:
    from distributed import wait as dask_wait

    ordered = longest_first(tasks)  # the scheduler starts the higher priority first
    pending = {client.submit(run_task, task, pure=False, priority=len(ordered) - rank): task
               for rank, task in enumerate(ordered)}
    try:
        while pending:
            try:
                dask_wait(list(pending), timeout=POLL_S, return_when="FIRST_COMPLETED")
            except TimeoutError:
                pass
            for future in [f for f in pending if f.done()]:
                report(_outcome(future, pending.pop(future)))
            if is_cancelled(cancel):
                raise Cancelled("batch cancelled by the user")
    except BaseException:
        client.cancel(list(pending))
        raise
