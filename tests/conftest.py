import os
import sys
from pathlib import Path

# One BLAS thread per test process, set before numpy loads (xdist's workers inherit it): `-n 2` runs as many
# processes as cores, so OpenBLAS's own threads only contended with the other worker, and their spin-waiting
# doubled the CPU of the BLAS-heavy tests (the line fit's test_the_line_fit_leaves_out_the_rows_it_is_told_to:
# 90 -> 43 s). A developer's own setting is kept.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
import pytest
from hypothesis import settings

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
# Dask's statistical profiler in the tests' in-process workers (LocalCluster(processes=False)) off, as the README
# tells users to start workers: on Python 3.11 its sys._current_frames() can deadlock the process (CPython
# gh-106883; a CI run hung in the section batch's test). Read by dask at import, inherited by spawned workers.
os.environ.setdefault("DASK_DISTRIBUTED__WORKER__PROFILE__ENABLED", "False")
# CI replays the same generated examples every run (a landing never depends on the draw); on a
# workstation hypothesis keeps exploring, and what it finds becomes a named test.
settings.register_profile("ci", derandomize=True, print_blob=True)
if os.environ.get("CI"):
    settings.load_profile("ci")
# Test helpers (reference implementations) live beside the tests.
sys.path.insert(0, str(Path(__file__).parent))

import cpu_log  # noqa: E402 (a test helper beside the tests)
import shared_build  # noqa: E402


NUMBA_WARMUP = "numba-warmup"
NUMBA_WARMUP_BESIDE = "numba-warmup-beside"


@pytest.hookimpl(trylast=True)
def pytest_configure(config):
    """The xdist controller fills insrail's numba cache once while its workers start (tests/numba_warmup.py),
    in two processes (the processing's kernels; beside them on the other core those it leaves out, then
    shared inputs); without it every worker of a clean checkout compiled the kernels itself.
    INSRAIL_TEST_CPU_LOG: each test's CPU time logged (tests/cpu_log.py)."""
    cpu_log.register(config)
    if hasattr(config, "workerinput") or not config.getoption("numprocesses", None) or config.option.collectonly:
        return
    run_folder = config._tmp_path_factory.getbasetemp()
    script = str(Path(__file__).with_name("numba_warmup.py"))
    config._numba_warmups = (
        shared_build.start_holding(run_folder, NUMBA_WARMUP,
                                   [sys.executable, script, str(run_folder / "shared" / NUMBA_WARMUP)]),
        shared_build.start_holding(run_folder, NUMBA_WARMUP_BESIDE, [sys.executable, script, "--beside", str(run_folder)]))


def pytest_unconfigure(config):
    for warmup in getattr(config, "_numba_warmups", ()):
        warmup.kill()  # a run stopped early does not wait for it
        warmup.wait()


@pytest.fixture(scope="session", autouse=True)
def _shared_run_folder(tmp_path_factory):
    """Where inputs made once per run for every xdist worker are kept (`shared_build`); the numba cache
    filled (or the controller's warm-up ended) before a worker's first test."""
    shared_build.RUN_FOLDER = shared_build.run_folder(tmp_path_factory)
    shared_build.wait_for(NUMBA_WARMUP)
    shared_build.wait_for(NUMBA_WARMUP_BESIDE)


@pytest.fixture(scope="session")
def short_perfect_survey():
    """The `short` scenario with an error-free IMU, simulated once per test run (read-only)."""
    from insrail.sim.scenario import preset
    from insrail.sim.simulate import simulate

    return shared_build.built_once("short-perfect", lambda out: simulate(preset("short", imu_profile="perfect"),
                                                                         seed=7, out_dir=out))


@pytest.fixture(scope="session")
def short_nav_survey():
    """The benchmark `short` scenario (navigation-grade IMU, seed 1), simulated once per test run (read-only)."""
    from insrail.sim.scenario import preset
    from insrail.sim.simulate import simulate

    return shared_build.built_once("short-nav", lambda out: simulate(preset("short"), seed=1, out_dir=out,
                                                                     imu_format="npy"))


@pytest.fixture(scope="session")
def tiny_nav_survey():
    """The numba warm-up's 50 m survey (tests/numba_warmup.py: navigation-grade IMU, text files), simulated once
    per test run (read-only): for tests that need a survey to run a command on, not its length."""
    from numba_warmup import tiny_scenario

    from insrail.sim.simulate import simulate

    return shared_build.built_once("tiny-nav", lambda out: simulate(tiny_scenario(), seed=1, out_dir=out,
                                                                    imu_format="text"))


@pytest.fixture
def window(qtbot, tmp_path):
    """The desktop application's main window (pytest-qt), with throwaway settings."""
    from PySide6.QtCore import QSettings

    from insrail.gui.main_window import MainWindow

    settings = QSettings(str(tmp_path / "settings.ini"), QSettings.IniFormat)  # never the user's settings
    main = MainWindow(settings)
    # pytest-qt closes its widgets before this fixture's teardown: closing must never ask (a modal question
    # would block the test run), even after a failed test left the project modified
    qtbot.addWidget(main, before_close_func=lambda widget: setattr(widget, "modified", False))
    main.resize(1400, 900)
    main.show()
    yield main
    main.modified = False  # closing must not ask (a modal question would block the tests)
    main.close()
    import gc

    gc.unfreeze()  # the shown results were frozen out of the cyclic collector: the next test starts clean
