"""The mounting's yaw/pitch pass and the main fusion side by side (insrail.project.mounting_stage.fused_with_mounting):
the main fusion's guess with survey.toml's mounting kept where the pass applies no axis, discarded and fused again
where it applies one; failures, cancel and progress as one after the other; serial on one CPU.
(The processing's results to the byte both ways: tests/test_mounting_calibration.py.)"""

from __future__ import annotations

import threading
from dataclasses import dataclass

import numpy as np
import pytest

from insrail.background import cpus_limited
from insrail.nav.mounting import MountingEstimate, not_estimated
from insrail.notices import Phrase
from insrail.progress import Cancelled, check_cancel
from insrail.project.mounting_stage import fused_with_mounting

GIVEN = np.radians([0.1, -0.2, 0.3])


@dataclass(frozen=True)
class Trolley:
    mounting_rpy_rad: object


@dataclass(frozen=True)
class Manifest:
    trolley: Trolley


@dataclass(frozen=True)
class Survey:
    manifest: Manifest
    gnss: object = "gnss"


def confirmed(survey):
    return not_estimated(survey.manifest.trolley.mounting_rpy_rad, Phrase("the NHC is off"))


def applying_yaw(survey):
    given = np.asarray(survey.manifest.trolley.mounting_rpy_rad, dtype=float)
    return MountingEstimate(given, given + [0.0, 0.0, 0.01], np.array([np.nan, np.nan, 1e-4]))


class Fusions:
    """A pass and a main fusion that run ``steps`` steps, checking the cancel, reporting progress and recording
    what they ran with, in which thread and what was discarded."""

    def __init__(self, estimate=confirmed, pass_error=None, fuse_error=None, steps=20, pass_steps=None):
        self.estimate, self.pass_error, self.fuse_error = estimate, pass_error, fuse_error
        self.steps, self.pass_steps = steps, pass_steps if pass_steps is not None else steps
        self.fused, self.discarded, self.threads = [], [], set()
        self.lock = threading.Lock()

    def _run(self, steps, progress, cancel, error):
        self.threads.add(threading.get_ident())
        for i in range(steps):
            check_cancel(cancel)
            threading.Event().wait(0.005)
            progress((i + 1) / steps, "step")
        if error is not None:
            raise error

    def pass_(self, survey, progress, cancel):
        self._run(self.pass_steps, progress, cancel, self.pass_error)
        return self.estimate(survey)

    def fuse(self, survey, progress, cancel):
        mounting = np.asarray(survey.manifest.trolley.mounting_rpy_rad).copy()
        with self.lock:
            self.fused.append(mounting)
        self._run(self.steps, progress, cancel, self.fuse_error if len(self.fused) == 1 else None)
        return ("result", mounting)

    def discard(self, result):
        self.discarded.append(result)

    def __call__(self, progress=None, cancel=None, survey=None):
        survey = survey or Survey(Manifest(Trolley(tuple(GIVEN))))
        return fused_with_mounting(survey, self.pass_, self.fuse, self.discard, progress, cancel)


def test_a_confirmed_mounting_keeps_the_main_fusion_run_beside_the_pass():
    runs = Fusions(steps=150)
    seen = []
    mounting, survey, result = runs(progress=lambda f, m: seen.append(f))
    assert len(runs.fused) == 1 and runs.discarded == [] and len(runs.threads) == 2
    assert result[1].tobytes() == GIVEN.tobytes() == np.asarray(survey.manifest.trolley.mounting_rpy_rad).tobytes()
    assert seen == sorted(seen) and seen[-1] == 1.0 and len(seen) > 2  # moving, never back, to 100 %


def test_an_applied_axis_discards_the_guess_and_fuses_again_with_the_estimate():
    runs = Fusions(estimate=applying_yaw, steps=400, pass_steps=5)
    seen = []
    mounting, survey, result = runs(progress=lambda f, m: seen.append(f))
    assert mounting.significant.tolist() == [False, False, True]
    assert runs.discarded == [None]  # stopped by the pass's verdict: it failed (cancelled), left nothing
    assert [m.tobytes() for m in runs.fused] == [GIVEN.tobytes(), mounting.applied_rpy_rad().tobytes()]
    assert result[1].tobytes() == mounting.applied_rpy_rad().tobytes()
    assert seen == sorted(seen) and seen[-1] == 1.0


def test_a_guess_that_finished_first_is_discarded_with_what_it_left():
    runs = Fusions(estimate=applying_yaw, steps=2, pass_steps=30)
    mounting, _, result = runs()
    assert len(runs.discarded) == 1 and runs.discarded[0][1].tobytes() == GIVEN.tobytes()
    assert result[1].tobytes() == mounting.applied_rpy_rad().tobytes()


def test_the_pass_failing_stops_the_main_fusion_and_is_raised():
    runs = Fusions(pass_error=RuntimeError("the pass broke"), steps=2000, pass_steps=3)
    with pytest.raises(RuntimeError, match="the pass broke"):
        runs()
    assert runs.discarded == [None] and len(runs.fused) == 1


def test_the_main_fusion_failing_is_raised_where_the_pass_confirms_the_mounting():
    runs = Fusions(fuse_error=ValueError("gnss.pos: no epoch within the IMU data"), steps=2)
    with pytest.raises(ValueError, match="no epoch within the IMU data"):
        runs()
    assert runs.discarded == []
    # where the pass applies an axis the failure belonged to the guess: fused again, as one after the other
    runs = Fusions(estimate=applying_yaw, fuse_error=ValueError("no epoch"), steps=2)
    mounting, _, result = runs()
    assert runs.discarded == [None] and result[1].tobytes() == mounting.applied_rpy_rad().tobytes()


def test_cancel_stops_both_threads():
    runs = Fusions(steps=100000)
    asked = threading.Event()
    threading.Timer(0.1, asked.set).start()
    with pytest.raises(Cancelled):
        runs(cancel=asked)
    assert runs.discarded == [None]


def test_one_cpu_or_no_gnss_runs_them_one_after_the_other_in_the_callers_thread():
    for survey, cpus in ((None, 1), (Survey(Manifest(Trolley(tuple(GIVEN))), gnss=None), 2)):
        for estimate in (confirmed, applying_yaw):
            runs = Fusions(estimate=estimate, steps=3)
            with cpus_limited(cpus):
                mounting, _, result = runs(survey=survey)
            assert runs.threads == {threading.get_ident()} and runs.discarded == []
            assert [m.tobytes() for m in runs.fused] == [mounting.applied_rpy_rad().tobytes()]
