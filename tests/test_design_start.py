"""The start from the design (issue 37, seed 002 §5.3.1.1): survey.toml's ``[start]`` puts the trolley on a
station of the design, and the fusion starts there from the design's position, azimuth, grade and cant
without waiting for a position fix. Written as a user writes it (survey_builder: minimal survey.toml, the
``[start]`` table typed in), processed through the command line and compared with the simulator's truth."""

from __future__ import annotations

import contextlib
import io
import math
import tomllib
import zlib

import numpy as np
import pytest

from insrail.cli.main import main
from insrail.io.survey import ManifestError, read_manifest, write_manifest
from survey_builder import FIRST_STATION_M, SURVEY_NAME, Cell, build_cell, truth_errors

#: a navigation-grade unit (it gyrocompasses; the position is the design's until GNSS arrives), GNSS as
#: KF-GINS text (its first column the time)
CELL = Cell("nav", "kfgins-gnss", "CGCS2000", "csv", "with", "none", "minimal")
#: GNSS arrives this long after the IMU's first record: 60 s static start, then about 100 m of run
GNSS_LATE_S = 150.0
START = f"\n[start]\nstation_m = {FIRST_STATION_M}\n"


def insrail(*args: str) -> tuple[int, str]:
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
        code = main(list(args))
    return code, out.getvalue()


@pytest.fixture(scope="module")
def late_gnss(tmp_path_factory):
    """One simulated run whose GNSS begins GNSS_LATE_S after the IMU, its survey.toml with [start], processed.
    (Without [start] the fusion waits for the first GNSS epoch: its sleepers began at 1120.6 m, the first
    100 m and 159 sleepers lost.)"""
    cell = build_cell(CELL, tmp_path_factory.mktemp("late"), seed=zlib.crc32(CELL.cell_id.encode()))
    survey = cell.project / "survey"
    imu_t0 = float(np.loadtxt(survey / "imu.txt", max_rows=1)[0])
    gnss = np.loadtxt(survey / "gnss.txt")
    np.savetxt(survey / "gnss.txt", gnss[gnss[:, 0] >= imu_t0 + GNSS_LATE_S], fmt="%.9f %.11f %.11f %.4f %.4f %.4f %.4f")
    toml = survey / "survey.toml"
    toml.write_text(toml.read_text() + START)
    code, out = insrail("process", str(cell.project))
    assert code == 0, out
    results = cell.project / "results" / SURVEY_NAME
    return cell, (truth_errors(results / "sleepers.csv", cell, normal_heights=False),
                  tomllib.loads((results / "summary.toml").read_text()), out,
                  np.genfromtxt(results / "quality.csv", delimiter=",", names=True))


def _first_station(comparison) -> float:
    return min(float(np.nanmin(rail.station_m)) for rail in comparison.rails.values())


def test_a_survey_starting_before_gnss_is_measured_from_its_start_station(late_gnss):
    """The sleepers begin at the start station and, before GNSS arrives (about 100 m), agree with the truth
    within their stated 1-sigma (quality.csv), as they do after it."""
    cell, (comparison, summary, out, quality) = late_gnss
    assert _first_station(comparison) < FIRST_STATION_M + 2.0
    assert summary["fusion"]["alignment"] == "static+known"
    assert ("static start on the design at station 1020.000 m: position from the design (1-sigma 0.020 m "
            "horizontal, 100 m in height)") in out
    imu_t0 = float(np.loadtxt(cell.project / "survey" / "imu.txt", max_rows=1)[0])
    truth = np.loadtxt(cell.truth / "sleepers.csv", delimiter=",", skiprows=1, usecols=(1, 2))  # station, pass time
    gnss_from_m = float(np.interp(imu_t0 + GNSS_LATE_S, truth[:, 1], truth[:, 0]))
    assert gnss_from_m > FIRST_STATION_M + 80.0
    for side, rail in comparison.rails.items():
        early = rail.station_m < gnss_from_m
        assert early.sum() > 100
        for axis, errors in (("lateral", rail.lateral_m), ("vertical", rail.vertical_m)):
            stated = 1e-3 * np.interp(rail.station_m[early], quality["station_from_m"], quality[f"sigma_{axis}_mm"])
            ratio = np.abs(errors[early]) / stated
            assert np.percentile(ratio, 95) < 3.0, f"{side} {axis}: {np.percentile(ratio, 95):.2f} sigma"
        late = ~early
        assert np.sqrt(np.mean(rail.lateral_m[late] ** 2)) < 0.02


def test_start_is_read_from_survey_toml_and_refused_when_wrong(tmp_path):
    (tmp_path / "imu.txt").write_text("0 0 0 0 0 0 0\n")
    (tmp_path / "odo.txt").write_text("0 0\n")
    base = ('[survey]\nname = "s"\n[files.imu]\npath = "imu.txt"\nformat = "kfgins-imu"\n'
            '[files.odometer]\npath = "odo.txt"\nformat = "odometer-distance"\n'
            '[trolley]\nimu_to_odometer_m = [0, 0, 0]\n')
    (tmp_path / "survey.toml").write_text(base + "[start]\nstation_m = 1020.5\noffset_m = 0.01\nfacing = \"decreasing\"\n")
    start = read_manifest(tmp_path).start
    assert (start.station_m, start.offset_m, start.height_m, start.facing_increasing) == (1020.5, 0.01, 0.0, False)
    assert math.isclose(start.sigma_m, 0.02)
    write_manifest(tmp_path, read_manifest(tmp_path))  # written back as read (the GUI's and the simulator's writer)
    assert read_manifest(tmp_path).start == start
    (tmp_path / "survey.toml").write_text(base + "[start]\nstaton_m = 1020.5\nfacing = \"up\"\n")
    with pytest.raises(ManifestError) as error:
        read_manifest(tmp_path)
    text = str(error.value)
    assert "start.staton_m: unknown key" in text and "start.station_m: expected" in text and "start.facing" in text


def test_a_moving_start_takes_the_designs_attitude_and_the_odometers_speed(late_gnss):
    """The same run cut to start 40 m into the motion (no stop to level on): position, roll, pitch and
    heading from the design at the truth's station there, the velocity the odometer's along it; each within
    3 of its stated 1-sigma of the truth."""
    from insrail.io.survey import SurveyStart, read_survey
    from insrail.io.types import ImuIncrements
    from insrail.nav.earth import CGCS2000, radii
    from insrail.nav.fusion import FusionOptions
    from insrail.nav.imu_profile import load_imu_profile
    from insrail.nav.mechanization import lat_lon_from_q_ne
    from insrail.nav.rotation import euler_to_dcm
    from insrail.nav.startup import initial_state
    from insrail.project.design_start import known_start
    from insrail.project.model import load_project
    from insrail.project.pipeline import read_design
    from insrail.sim.truth import read_nav_truth

    cell, _ = late_gnss
    survey = read_survey(cell.project / "survey")
    project = load_project(cell.project)
    truth = read_nav_truth(cell.truth / "nav.npy")
    t_start = float(truth["time_s"][0]) + 100.0
    j = int(np.searchsorted(truth["time_s"], t_start))
    k = int(np.searchsorted(survey.imu.time_s, truth["time_s"][j]))
    imu = ImuIncrements(survey.imu.time_s[k:], survey.imu.dtheta_rad[k:], survey.imu.dvel_mps[k:])
    known = known_start(project, read_design(project.resolve(project.design)), project.crs,
                        SurveyStart(float(truth["station_m"][j])), survey.manifest.trolley)
    trolley = survey.manifest.trolley
    start = initial_state(imu, None, [], survey.odometer, euler_to_dcm(*trolley.mounting_rpy_rad),
                          load_imu_profile("nav"), FusionOptions(), CGCS2000, known=known)
    assert start.method == "known" and start.epoch == 0
    apart = np.asarray(start.rpy_rad) - truth["rpy_rad"][j]
    apart[2] = (apart[2] + np.pi) % (2 * np.pi) - np.pi
    assert np.all(np.abs(apart) < 3.0 * np.array([start.sigma_level_rad, start.sigma_level_rad,
                                                  start.sigma_heading_rad])), np.degrees(apart)
    lat, lon = lat_lon_from_q_ne(start.nav[0:4])
    r_m, r_n = radii(truth["lat_rad"][j], CGCS2000)
    north = (lat - truth["lat_rad"][j]) * r_m
    east = (lon - truth["lon_rad"][j]) * r_n * np.cos(truth["lat_rad"][j])
    assert math.hypot(north, east) < 3.0 * start.sigma_pos_ned_m[0], (north, east)
    assert np.linalg.norm(start.nav[5:8] - truth["vel_ned_mps"][j]) < 3.0 * start.sigma_vel_mps
