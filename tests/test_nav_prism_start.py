"""The start heading of a unit that cannot gyrocompass in a tunnel (insrail.nav.startup): its prism fixes are
all taken at rest, at the stops, so no fix is "in motion"; the chord from the static start's fix to the next
one gives the heading (it was refused: "the trolley never moves far enough", with --heading the only way out,
which `insrail process` does not have)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from insrail.geodesy import EngineeringCRS
from insrail.io.survey import read_survey
from insrail.nav.earth import CGCS2000
from insrail.nav.fusion import FusionOptions, aiding_for, fuse
from insrail.nav.imu_profile import load_imu_profile
from insrail.nav.measurements import PositionFix
from insrail.sim.scenario import GnssSpec, MotionSpec, PrismSpec, preset
from insrail.sim.simulate import height_anomaly, simulate
from insrail.sim.truth import read_nav_truth


def test_a_mems_unit_with_prism_fixes_at_stops_takes_its_start_heading_from_them(tmp_path):
    config = preset("short", imu_profile="mems")
    fixes = (1100.0, 1130.0, 1160.0, 1190.0)
    config = replace(config, motion=MotionSpec(start_station_m=1100.0, end_station_m=1190.0, static_start_s=40.0,
                                               static_end_s=10.0),
                     gnss=GnssSpec(), prism=PrismSpec(stations_m=fixes, duration_s=10.0))
    simulate(config, 5, tmp_path / "run", imu_format="npy")
    survey = replace(read_survey(tmp_path / "run"), gnss=None)  # in a tunnel: the prism fixes alone
    crs = EngineeringCRS.from_settings(config.geodetic.crs)

    def to_geodetic(east, north, normal_height):
        lat, lon = crs.to_geodetic(east, north)
        return lat, lon, normal_height + height_anomaly(config, east, north)

    fixes = PositionFix.from_prism(survey.prism, survey.manifest.trolley.imu_to_prism_m, to_geodetic)
    profile = load_imu_profile("mems")
    options = FusionOptions(smoother=False)
    result = fuse(survey.imu, aiding_for(survey, options, profile, fixes), profile, options, CGCS2000)
    truth = read_nav_truth(tmp_path / "run" / "truth" / "nav.npy")
    t0 = result.forward.time_s[0]
    true = float(np.interp(t0, truth["time_s"], np.unwrap(truth["rpy_rad"][:, 2])))
    error = (result.info["alignment_rpy_rad"][2] - true + math.pi) % (2 * math.pi) - math.pi
    assert result.info["alignment"] == "static+track"
    assert abs(math.degrees(error)) < 0.1  # 1 mm fixes 30 m apart on a straight
