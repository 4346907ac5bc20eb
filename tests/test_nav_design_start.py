"""The start heading from the design alignment (insrail.nav.startup, insrail.project.design_heading):
a tactical unit that cannot gyrocompass takes the design's azimuth at its start point, turned to the
way the track chord shows, with the design's 1-sigma; a design that disagrees with the track is not
used and a notice says so; in the pipeline the design file is part of the fusion's cache key."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from insrail.io.survey import read_survey
from insrail.nav.earth import CGCS2000
from insrail.nav.fusion import FusionOptions, aiding_for, fuse
from insrail.nav.imu_profile import load_imu_profile
from insrail.nav.startup import DESIGN_TRACK_SIGMA_RAD
from insrail.project.demo import project_for_simulated_survey
from insrail.project.design_heading import design_azimuth_for
from insrail.project.pipeline import fusion_key, read_design
from insrail.sim.scenario import preset
from insrail.sim.simulate import simulate
from insrail.sim.truth import read_nav_truth


@pytest.fixture(scope="module")
def tactical(tmp_path_factory):
    """150 m of the short scenario with a tactical IMU (no north from its gyros), 60 s static start,
    and a code-differential GNSS (15 cm): its chords give the heading to about 0.5 deg."""
    config = preset("short", imu_profile="tactical")
    config = replace(config, motion=replace(config.motion, start_station_m=1100.0, end_station_m=1250.0, stops=(),
                                            static_start_s=60.0, static_end_s=10.0),
                     gnss=replace(config.gnss, white_horizontal_m=0.15, white_vertical_m=0.25, gm_horizontal_m=0.05,
                                  gm_vertical_m=0.1))
    root = tmp_path_factory.mktemp("design_start")
    simulate(config, 2, root / "surveys" / "tactical", imu_format="npy")
    project = project_for_simulated_survey(root, root / "surveys" / "tactical", name="design")
    survey = read_survey(root / "surveys" / "tactical")
    truth = read_nav_truth(root / "surveys" / "tactical" / "truth" / "nav.npy")
    return project, survey, truth


TACTICAL = load_imu_profile("tactical")


def start_of(survey, design_azimuth):
    profile = load_imu_profile("tactical")
    options = FusionOptions(smoother=False)
    aiding = replace(aiding_for(survey, options, profile), design_azimuth=design_azimuth)
    result = fuse(survey.imu, aiding, profile, options, CGCS2000)
    return result


def heading_error_deg(result, truth) -> float:
    t0 = result.forward.time_s[0]
    true = float(np.interp(t0, truth["time_s"], np.unwrap(truth["rpy_rad"][:, 2])))
    return math.degrees(abs((result.info["alignment_rpy_rad"][2] - true + math.pi) % (2 * math.pi) - math.pi))


def test_a_tactical_unit_takes_its_start_heading_from_the_design(tactical):
    project, survey, truth = tactical
    design = design_azimuth_for(project, read_design(project.resolve(project.design)), TACTICAL)
    with_design, without = start_of(survey, design), start_of(survey, None)
    assert with_design.info["alignment"] == "static+design" and without.info["alignment"] == "static+track"
    said = [n.message for n in with_design.info["notices"] if "static start" in n.message]
    assert said and "the design's azimuth at station" in said[0] and "1-sigma 0.1" in said[0]
    # the design's 1-sigma holds, and it is far better than the chord's
    assert heading_error_deg(with_design, truth) < 3 * math.degrees(DESIGN_TRACK_SIGMA_RAD)
    assert heading_error_deg(with_design, truth) < heading_error_deg(without, truth)


def test_a_design_that_disagrees_with_the_track_is_not_used(tactical):
    project, survey, _ = tactical
    design = design_azimuth_for(project, read_design(project.resolve(project.design)), TACTICAL)

    def turned(lat, lon):  # another line's design, 20 deg off this track
        azimuth, *rest = design(lat, lon)
        return (azimuth + math.radians(20.0), *rest)

    result = start_of(survey, turned)
    assert result.info["alignment"] == "static+track"
    assert any("not used for the start" in n.message and "deg from the GNSS track" in n.message
               for n in result.info["notices"])


def test_off_the_design_or_with_local_control_there_is_no_design_heading(tactical):
    project, _, _ = tactical
    design = read_design(project.resolve(project.design))
    azimuth = design_azimuth_for(project, design, TACTICAL)
    plan = design.horizontal
    lat, lon = project.crs.to_geodetic(*plan.point_at(plan.start_station_m + 50.0))
    found = azimuth(float(lat), float(lon))
    assert found is not None and abs(found[3]) < 1e-6 and found[2] == pytest.approx(plan.start_station_m + 50.0)
    lat, lon = project.crs.to_geodetic(*plan.point_at(plan.start_station_m + 50.0, 30.0))
    assert azimuth(float(lat), float(lon))[3] == pytest.approx(30.0)  # found, but startup refuses it (> 5 m off)
    assert design_azimuth_for(project, None, TACTICAL) is None
    assert design_azimuth_for(replace(project, local_control=object()), design, TACTICAL) is None
    assert design_azimuth_for(project, design, load_imu_profile("nav")) is None  # it gyrocompasses


def test_the_design_is_part_of_the_fusion_key_where_it_can_change_the_start(tactical, tmp_path):
    from insrail.io.survey import read_manifest

    project, _, _ = tactical
    project = replace(project, imu_profile="tactical")
    folder = project.folder / "surveys" / "tactical"
    manifest = read_manifest(folder)
    key = fusion_key(project, manifest, folder)
    path = project.resolve(project.design)
    original = path.read_text()
    try:
        path.write_text(original.replace("\n", "\n", 1) + "\n")
        assert fusion_key(project, manifest, folder) != key
        nav = replace(project, imu_profile="nav")  # a gyrocompassing IMU: the design does not change its fusion
        assert fusion_key(nav, manifest, folder) == fusion_key(replace(nav, design=None), manifest, folder)
    finally:
        path.write_text(original)
    assert fusion_key(project, manifest, folder) == key
