"""survey.toml's [gnss_raw] table (validation with key paths, round trip) and the RINEX 2.11
observation writer (read back by the header checks insrail runs before RTKLIB)."""

import re

import numpy as np
import pytest
import tomli_w
from hypothesis import given, settings
from hypothesis import strategies as st

from insrail.gnss.rinex import read_obs_info
from insrail.io.errors import ManifestError
from insrail.io.rinex import RinexObsHeader, write_rinex2_obs
from insrail.io.survey import read_manifest, write_manifest
from insrail.io.timescale import calendar_to_week_seconds

TROLLEY = {"imu_to_antenna_m": [0.0, 0.0, -1.3], "imu_to_odometer_m": [0.3, 0.7, 0.25],
           "imu_to_reference_rail_m": [0.0, -0.72, 0.35]}


def _survey(folder, gnss_raw, with_solution=False):
    for name in ("imu.txt", "odo.txt", "rover.obs", "base.obs", "brdc.nav", "gnss.pos", "rover.ubx"):
        (folder / name).write_text("x")
    files = {"imu": {"path": "imu.txt", "format": "kfgins-imu"},
             "odometer": {"path": "odo.txt", "format": "odometer-distance"}}
    if with_solution:
        files["gnss"] = {"path": "gnss.pos", "format": "rtklib-pos"}
    document = {"survey": {"name": "s"}, "files": files, "trolley": TROLLEY, "gnss_raw": gnss_raw}
    (folder / "survey.toml").write_text(tomli_w.dumps(document))


def test_raw_gnss_round_trips(tmp_path):
    raw = {"rover": "rover.obs", "base": "base.obs", "navigation": ["brdc.nav"], "base_point": "CP1",
           "base_antenna_height_m": 1.532, "base_antenna_type": "TRM55971.00     NONE"}
    _survey(tmp_path, raw)
    manifest = read_manifest(tmp_path)
    assert "gnss" not in manifest.files
    assert manifest.raw_gnss.navigation == ("brdc.nav",) and manifest.raw_gnss.base_antenna_height_m == 1.532
    assert not manifest.raw_gnss.base_from_header
    write_manifest(tmp_path, manifest)
    again = read_manifest(tmp_path)
    assert again.raw_gnss == manifest.raw_gnss and again.files == manifest.files


def test_every_problem_with_its_key_path(tmp_path):
    _survey(tmp_path, {"rover": "rover.obs", "rover_log": "rover.ubx", "base": "missing.obs",
                       "navigation": ["brdc.nav", "other.nav"], "base_point": "rinex-header",
                       "base_antenna_height_m": 1.5, "base_antenna_type": 7, "sp3": "x"}, with_solution=True)
    with pytest.raises(ManifestError) as error:
        read_manifest(tmp_path)
    assert set(error.value.problems) == {
        "gnss_raw.sp3: unknown key (expected rover, rover_log, rover_log_format, base, navigation, precise, antex, "
        "config, base_point, base_antenna_height_m, base_antenna_type)",
        "gnss_raw.rover: give either rover (RINEX observations) or rover_log (a receiver log)",
        "gnss_raw.base: file not found: missing.obs",
        "gnss_raw.navigation[1]: file not found: other.nav",
        "gnss_raw.base_antenna_height_m: not used with base_point = \"rinex-header\" (the header's ANTENNA: "
        "DELTA H applies); remove it or name a control point",
        "gnss_raw.base_antenna_type: expected an ANTEX antenna name (up to 20 characters), found 7",
        "files.gnss: give either a GNSS solution [files.gnss] or raw observations [gnss_raw], not both",
    }


def test_control_point_needs_the_antenna_height_and_navigation_is_required(tmp_path):
    _survey(tmp_path, {"rover": "rover.obs", "base": "base.obs", "base_point": "CP1"})
    with pytest.raises(ManifestError) as error:
        read_manifest(tmp_path)
    assert set(error.value.problems) == {
        "gnss_raw.navigation: expected a list of file names relative to the survey folder (at least one)",
        "gnss_raw.base_antenna_height_m: missing (the base antenna's reference point above control point CP1, "
        "metres)",
    }


def test_a_survey_without_gnss_names_both_ways(tmp_path):
    """Without any position source and without an odometer (with one it is a relative survey)."""
    _survey(tmp_path, {})
    text = (tmp_path / "survey.toml").read_text().replace("[gnss_raw]\n", "")
    text = re.sub(r"\[files.odometer\]\n(\w+ = .*\n)+", "", text)
    (tmp_path / "survey.toml").write_text(text)
    with pytest.raises(ManifestError, match=r"files: no position source: give a GNSS solution \[files.gnss\], raw "
                                            r"GNSS observations \[gnss_raw\], total-station prism fixes \[files.prism\] or raw "
                                            r"total-station observations \[files.total_station\]; or, for a relative survey"):
        read_manifest(tmp_path)


@settings(max_examples=25, deadline=None)
@given(year=st.integers(1999, 2035), day_of_year=st.integers(0, 364), second_of_day=st.integers(0, 86399),
       fraction=st.sampled_from([0.0, 0.5, 0.25]), epochs=st.integers(1, 30), satellites=st.integers(1, 15))
def test_rinex2_writer_round_trips_time_tags_and_header(tmp_path_factory, year, day_of_year, second_of_day,
                                                       fraction, epochs, satellites):
    week, start = calendar_to_week_seconds([year], [1], [1], [0], [0], [0.0])
    t0 = float(start[0]) + 86400.0 * day_of_year + second_of_day + fraction
    tags = t0 + np.arange(epochs)
    prn = np.tile(np.arange(1, satellites + 1), (epochs, 1))
    values = np.full((epochs, satellites, 4), 2.2e7)
    values[:, :, 1] = 1.2e8
    header = RinexObsHeader("TEST", (-2274855.123, 5008559.9, 3217209.4), (1.55, 0.0, 0.0), ("C1", "L1", "P2", "L2"),
                            1.0)
    path = write_rinex2_obs(tmp_path_factory.mktemp("rinex") / "t.obs", header, week, tags, prn, values)
    info = read_obs_info(path)
    assert info.epochs == epochs and info.version == 2.11
    assert info.first_s == pytest.approx(week * 604800.0 + tags[0], abs=1e-6)
    assert info.last_s == pytest.approx(week * 604800.0 + tags[-1], abs=1e-6)
    assert info.approx_position_ecef_m == (-2274855.123, 5008559.9, 3217209.4)
    assert info.antenna_delta_hen_m == (1.55, 0.0, 0.0)
    lines = path.read_text().splitlines()
    body = lines[next(i for i, line in enumerate(lines) if "END OF HEADER" in line) + 1:]
    continuation = 1 if satellites > 12 else 0
    assert len(body) == epochs * (1 + continuation + satellites)
    assert body[1 + continuation].split() == ["22000000.000", "120000000.000", "22000000.000", "22000000.000"]
