"""The reconstruction on a fused trajectory (navigation-grade IMU, GNSS with a 120 s outage,
noisy gauge, 1 % missed and 0.5 % false sleeper pulses): the benchmark `short` survey."""

import tomllib

import numpy as np
import pytest

from insrail.io.survey import read_survey
from insrail.nav.earth import CGCS2000
from insrail.nav.fusion import fuse_survey
from insrail.track.alignment_csv import read_alignment_csv
from insrail.track.sleeper_table import reconstruct_track
from test_track_deviations import expected_deviations
from track_truth import truth_reconstruction

MM = 1e-3
#: Sleepers in the moving mean removed to isolate the short waves (30 m at 0.625 m).
SHORT_WAVE_SLEEPERS = 48


@pytest.fixture(scope="module")
def reconstructed(short_nav_survey):
    survey = read_survey(short_nav_survey)
    trajectory = fuse_survey(survey, ellipsoid=CGCS2000).trajectory
    recon = truth_reconstruction(short_nav_survey)
    result = reconstruct_track(trajectory, survey.manifest.trolley, survey.gauge, recon.to_engineering,
                               design=read_alignment_csv(short_nav_survey / "truth" / "design.csv"),
                               pulses=survey.sleepers, first_number=0)
    truth = recon.sleepers
    first = int(truth["index"][np.argmin(np.abs(truth["station"] - result.table.station_m[0]))])
    return short_nav_survey, result, truth, result.table.number + first


def short_waves(error):
    kernel = np.ones(SHORT_WAVE_SLEEPERS) / SHORT_WAVE_SLEEPERS
    return (error - np.convolve(error, kernel, mode="same"))[SHORT_WAVE_SLEEPERS:-SHORT_WAVE_SLEEPERS]


def test_sleepers_numbered_exactly_on_the_fused_trajectory(reconstructed):
    folder, result, truth, rows = reconstructed
    sleepers = result.sleepers
    assert np.array_equal(truth["index"][rows].astype(int), rows)
    assert np.array_equal(sleepers.detected, truth["detected"][rows].astype(bool))
    false_times = tomllib.loads((folder / "truth" / "errors.toml").read_text())["false_sleeper_pulse_times_s"]
    assert len(sleepers.false_pulse_times_s) == len(false_times)
    # Chainage location: the thesis asks for 5 cm; the smoothed solution gives about 1 cm.
    assert np.abs(sleepers.station_m - truth["station"][rows]).max() < 0.05


def test_gauge_cant_and_deviations_on_the_fused_trajectory(reconstructed):
    _, result, truth, rows = reconstructed
    tab = result.table
    assert tab.valid.all()
    assert np.sqrt(np.mean((tab.gauge_m - truth["gauge"][rows]) ** 2)) < 0.15 * MM  # sensor: 0.1 mm noise
    assert np.abs(tab.cant_m - truth["cant"][rows]).max() < 0.3 * MM
    lateral, vertical = expected_deviations(truth)
    lateral_error = tab.lateral_deviation_m - lateral[rows]
    vertical_error = tab.vertical_deviation_m - vertical[rows]
    # Absolute: the GNSS's correlated centimetre errors, much reduced by the smoother.
    assert np.abs(lateral_error).max() < 10 * MM and np.abs(vertical_error).max() < 10 * MM
    # Short waves (what the 30 m chord sees) are sub-millimetre.
    for side in (0, 1):
        assert np.sqrt(np.mean(short_waves(lateral_error[:, side]) ** 2)) < 0.3 * MM
        assert np.sqrt(np.mean(short_waves(vertical_error[:, side]) ** 2)) < 0.3 * MM
