"""Per-section quality of a fused survey with a GNSS outage."""

from dataclasses import replace

import numpy as np
import pytest

from insrail.io.survey import read_survey
from insrail.nav.earth import CGCS2000
from insrail.nav.fusion import FusionOptions, SmootherStore, fuse_survey
from insrail.quality import covariance
from insrail.quality import survey as quality_survey
from insrail.quality.survey import EpochQuality, epoch_quality, sections, survey_quality
from insrail.sim.scenario import preset
from insrail.sim.simulate import simulate

SECTION_M = 100.0


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    """400 m of the short scenario with a tactical IMU and a 120 s GNSS outage from 150 m
    into the run (about 150-294 m at 1.2 m/s), fused with the filter's covariance record kept."""
    config = preset("short", imu_profile="tactical")
    config = replace(
        config,
        motion=replace(config.motion, start_station_m=1450.0, end_station_m=1850.0, stops=(), static_start_s=60.0,
                       static_end_s=20.0),
        gnss=replace(config.gnss, outages=((1600.0, 120.0),)),
    )
    folder = tmp_path_factory.mktemp("quality") / "survey"
    simulate(config, 3, folder, imu_format="npy")
    survey = read_survey(folder)
    with SmootherStore() as store:
        yield survey, fuse_survey(survey, FusionOptions(), ellipsoid=CGCS2000, covariance_store=store), store


@pytest.fixture(scope="module")
def fused(recorded):
    """The survey, its fusion and the replay's per-section quality."""
    survey, result, _ = recorded
    return survey, result, survey_quality(survey, result, ellipsoid=CGCS2000, section_m=SECTION_M)


def test_replay_reproduces_the_fusion_covariance(fused):
    """Same timeline, same models: the replayed sigmas are the fusion's own."""
    _, result, quality = fused
    t = result.timeline.time_s
    for trajectory, cov in ((result.forward, quality.profile.forward), (result.trajectory, quality.profile.smoothed)):
        k = np.searchsorted(trajectory.time_s, t[:-1] - 1e-6)
        np.testing.assert_allclose(cov.sigma_vertical_m[:-1], trajectory.sigma_pos_ned_m[k, 2], rtol=2e-3)
        # straight north-east bound start: compare the horizontal variance, which does not depend on heading
        horizontal = np.hypot(trajectory.sigma_pos_ned_m[k, 0], trajectory.sigma_pos_ned_m[k, 1])
        assert np.all(cov.sigma_lateral_m[:-1] <= horizontal * (1 + 2e-3))


def test_the_fusions_record_gives_the_replays_figures(recorded, fused):
    """Backward pass over the filter's own Phi, P-, P+ against the replay's: the same pairs, the
    same figures up to the replay's linearisation (end-of-segment state, raw increments)."""
    survey, result, store = recorded
    replayed = EpochQuality.from_profile(fused[2].profile, smoothed=True)
    messages = []
    from_record = epoch_quality(survey, result, ellipsoid=CGCS2000, covariance_store=store,
                                progress=lambda f, m: messages.append((f, str(m))))
    assert from_record.smoothed
    for name in ("time_s", "moving", "lag5_first_epoch", "lag5_second_epoch", "lag150_first_epoch",
                 "lag150_second_epoch"):
        np.testing.assert_array_equal(getattr(from_record, name), getattr(replayed, name), err_msg=name)
    for name in ("sigma_lateral_m", "sigma_vertical_m", "lag5_sigma_lateral_m", "lag5_sigma_vertical_m",
                 "lag150_sigma_lateral_m", "lag150_sigma_vertical_m"):
        np.testing.assert_allclose(getattr(from_record, name), getattr(replayed, name), rtol=1e-3, err_msg=name)
    fractions = [f for f, _ in messages]
    assert any(m.startswith("covariance: smoother") for _, m in messages)
    assert fractions == sorted(fractions) and fractions[-1] == 1.0


def test_the_record_is_analysed_without_the_imu_data(recorded):
    """The pipeline drops the 200 Hz IMU record before the analysis of the fusion's record: the
    figures are the same to the bit without it."""
    survey, result, store = recorded
    with_imu = epoch_quality(survey, result, ellipsoid=CGCS2000, covariance_store=store)
    without = epoch_quality(replace(survey, imu=None), result, ellipsoid=CGCS2000, covariance_store=store)
    for name, value in vars(with_imu).items():
        np.testing.assert_array_equal(getattr(without, name), value, err_msg=name)


def test_the_record_is_analysed_alike_by_parts_of_any_size(recorded, monkeypatch):
    """The record is unpacked and analysed by parts (memory), each part carrying Phi and P- of its first
    epoch to the gain of the part after: the figures are the same to the bit with parts of a few epochs or
    of the whole record."""
    survey, result, store = recorded
    figures = []
    for part in (7, 1 << 30):
        monkeypatch.setattr(covariance, "SMOOTH_PART_EPOCHS", part)
        monkeypatch.setattr(quality_survey, "SMOOTH_PART_EPOCHS", part)
        figures.append(epoch_quality(survey, result, ellipsoid=CGCS2000, covariance_store=store))
    for name, value in vars(figures[0]).items():
        np.testing.assert_array_equal(getattr(figures[1], name), value, err_msg=name)


def test_a_record_of_another_fusion_is_refused(recorded):
    survey, result, store = recorded
    with SmootherStore() as other, pytest.raises(ValueError, match="not this fusion's record"):
        epoch_quality(survey, result, ellipsoid=CGCS2000, covariance_store=other)
    with pytest.raises(ValueError, match="already holds"):
        fuse_survey(survey, covariance_store=store)


def test_outage_section_is_the_weakest(fused):
    _, _, quality = fused
    assert quality.smoothed
    station = quality.profile.station_m
    assert 380.0 < station[-1] < 420.0
    assert len(quality.station_from_m) == 4
    np.testing.assert_allclose(quality.station_to_m[:-1], quality.station_from_m[1:])
    outage_section = 2  # 200-300 m: the end of the outage, where the sigma has grown most
    assert quality.weakest("sigma_lateral_m") == outage_section
    forward = sections(quality.profile, smoothed=False, section_m=SECTION_M)
    assert forward.weakest("sigma_lateral_m") == outage_section
    assert forward.weakest("sigma_lag5_lateral_m") == outage_section
    # the smoother bridges the outage: better than the forward filter everywhere
    assert np.all(quality.sigma_lateral_m <= forward.sigma_lateral_m)
    assert forward.sigma_lateral_m[outage_section] > 2.0 * forward.sigma_lateral_m[0]


def test_rows_for_csv(fused):
    _, _, quality = fused
    rows = quality.to_rows()
    assert len(rows) == len(quality.station_from_m)
    assert set(rows[0]) == {"station_from_m", "station_to_m", "sigma_lateral_mm", "sigma_vertical_mm",
                            "sigma_lag5_lateral_mm", "sigma_lag5_vertical_mm", "sigma_lag150_lateral_mm",
                            "sigma_lag150_vertical_mm", "sigma_cross_level_mm", "sigma_along_track_mm"}
    # the cross-level: the roll's 1-sigma over the rails' 1.5 m, RMS over the section's moving epochs
    roll = quality.profile.smoothed.sigma_roll_rad
    assert 0.0 < rows[1]["sigma_cross_level_mm"] <= 1e3 * 1.5 * roll.max() + 1e-3
    assert rows[1]["sigma_lag5_lateral_mm"] == pytest.approx(1e3 * quality.sigma_lag5_lateral_m[1], abs=1e-3)
    with pytest.raises(ValueError, match="unknown figure"):
        quality.weakest("sigma_lateral_mm")


def test_result_without_timeline_is_refused(fused):
    survey, result, _ = fused
    with pytest.raises(ValueError, match="no measurement timeline"):
        survey_quality(survey, replace(result, timeline=None))


def test_the_replay_widens_p_where_the_filter_was_reset(recorded):
    """A 1 m false fix for 40 s while moving resets the filter (its position, velocity and attitude
    variances raised); the forward replay knows the reset: its sigmas are the filter's own after it."""
    from insrail.sim import gnss_faults

    survey, _, _ = recorded
    gnss = gnss_faults.false_fix(survey.gnss, survey.gnss.time_s[0] + 100.0, 40.0, (1.0, 0.0, 0.0))
    faulty = replace(survey, gnss=gnss)
    result = fuse_survey(faulty, FusionOptions(smoother=False), ellipsoid=CGCS2000)
    assert result.resets
    quality = survey_quality(faulty, result, FusionOptions(smoother=False), ellipsoid=CGCS2000,
                             section_m=SECTION_M, smoothed=False)
    t = result.timeline.time_s
    k = np.searchsorted(result.forward.time_s, t[:-1] - 1e-6)
    after = t[:-1] >= result.resets[0].time_s
    np.testing.assert_allclose(quality.profile.forward.sigma_vertical_m[:-1][after],
                               result.forward.sigma_pos_ned_m[k, 2][after], rtol=2e-3)
