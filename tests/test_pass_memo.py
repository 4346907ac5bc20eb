"""The IMU screening, gap bridging and stops made once for the passes over one survey (insrail.nav.pass_memo):
the passes give what they give without the memo, and new inputs are screened anew."""

import threading
from dataclasses import replace

import numpy as np
import pytest

from insrail.io.survey import read_survey
from insrail.nav.earth import CGCS2000
from insrail.nav.fusion import FusionOptions, aiding_for, fuse
from insrail.nav.imu_profile import load_imu_profile
from insrail.nav.pass_memo import PassMemo, same_inputs

SECONDS = 420.0  # the static start and the first metres of the push


@pytest.fixture(scope="module")
def survey(short_nav_survey):
    """The first seconds of the survey with one gyro record spiked (removed by the screening, said in a notice)."""
    survey = read_survey(short_nav_survey)
    imu = survey.imu
    keep = imu.time_s < imu.time_s[0] + SECONDS
    dtheta = imu.dtheta_rad[keep].copy()
    dtheta[len(dtheta) // 2, 0] += 0.01
    return replace(survey, imu=replace(imu, time_s=imu.time_s[keep], dtheta_rad=dtheta, dvel_mps=imu.dvel_mps[keep]))


def _passes(survey, memo):
    """The mounting's pass (no NHC) and the main pass, as the processing runs them."""
    profile = load_imu_profile(survey.manifest.imu_profile)
    main = FusionOptions()
    results = []
    for options in (replace(main, use_nhc=False, estimate_play=False), main):
        results.append(fuse(survey.imu, aiding_for(survey, options, profile), profile, options, CGCS2000,
                            output_every=20, memo=memo))
    return results


def test_passes_with_the_memo_give_what_they_give_without(survey):
    memo = PassMemo()
    with_memo = _passes(survey, memo)
    assert memo.made == 2  # the screening (with the bridging) and the stops, once for both passes
    without = _passes(survey, None)
    for a, b in zip(with_memo, without):
        for name in ("time_s", "lat_rad", "lon_rad", "height_m", "rpy_rad", "sigma_pos_ned_m"):
            assert np.array_equal(getattr(a.trajectory, name), getattr(b.trajectory, name))
        assert a.stops == b.stops
        assert [o.index for o in a.info["imu_outliers"]] == [o.index for o in b.info["imu_outliers"]] != []
        assert [n.message for n in a.info["notices"]] == [n.message for n in b.info["notices"]]
    # each pass says the removed record once (a kept list extended by one pass would say it twice in the next)
    for result in with_memo:
        assert sum("spike" in n.message and n.stage == "imu" for n in result.info["notices"]) == 1


def test_other_records_or_odometer_are_screened_anew(survey):
    memo = PassMemo()
    profile = load_imu_profile(survey.manifest.imu_profile)
    options = FusionOptions(smoother=False)
    fuse(survey.imu, aiding_for(survey, options, profile), profile, options, CGCS2000, output_every=20, memo=memo)
    made = memo.made
    shorter = replace(survey.imu, time_s=survey.imu.time_s[:-200], dtheta_rad=survey.imu.dtheta_rad[:-200],
                      dvel_mps=survey.imu.dvel_mps[:-200])
    fuse(shorter, aiding_for(survey, options, profile), profile, options, CGCS2000, output_every=20, memo=memo)
    assert memo.made == made + 2
    no_odometer = replace(survey, imu=shorter, odometer=None)
    fuse(shorter, aiding_for(no_odometer, options, profile), profile, options, CGCS2000, output_every=20, memo=memo)
    assert memo.made == made + 4


def test_same_inputs_compares_arrays_by_value_and_objects_by_identity():
    a, b = np.arange(3.0), np.arange(3.0)
    thing = object()
    assert same_inputs((thing, a, 5.0, None), (thing, b, 5.0, None))
    assert not same_inputs((thing, a), (object(), a))
    assert not same_inputs(a, b + 1e-12)
    assert not same_inputs(np.array([np.nan]), np.array([np.nan]))  # made again, never taken for the same
    assert not same_inputs(5.0, 5) and not same_inputs(None, (a,)) and not same_inputs((a,), (a, a))


def test_passes_in_two_threads_make_a_value_once():
    """The mounting's pass and the main fusion side by side: the second to ask waits for the first's value."""
    memo = PassMemo()
    inputs = (np.arange(5.0), 3.0)
    started, values = threading.Event(), []

    def make():
        started.set()
        threading.Event().wait(0.2)  # the other thread asks meanwhile
        return object()

    def ask():
        values.append(memo.get("screening", inputs, make))

    threads = [threading.Thread(target=ask)]
    threads[0].start()
    started.wait()
    threads.append(threading.Thread(target=ask))
    threads[1].start()
    for thread in threads:
        thread.join()
    assert memo.made == 1 and values[0] is values[1]
