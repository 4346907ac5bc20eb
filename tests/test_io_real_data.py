"""Real recordings in foreign formats (rtklibexplorer/GNSS_IMU walk_0827) import correctly."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from real_data import real_path

from insrail.io import detect_format, read_any, read_imu_rates_csv, read_rtklib_pos


@pytest.fixture(scope="session")
def walk_0827() -> Path:
    """The shared walk_0827 folder; skipped locally if absent, an error in CI."""
    return real_path("walk_0827")


def test_rtklib_pos_walk(walk_0827):
    gnss = read_rtklib_pos(walk_0827 / "gnss_1730_sf.pos")
    assert len(gnss) == 536
    quality, counts = np.unique(gnss.quality, return_counts=True)
    assert dict(zip(quality.tolist(), counts.tolist())) == {1: 349, 2: 187}
    assert np.median(np.diff(gnss.time_s)) == pytest.approx(0.25, abs=1e-6)  # 4 Hz
    assert gnss.gaps == ()
    # First line: 2025/08/28 17:30:39.749 GPST = week 2381, Thursday.
    assert gnss.gps_week == 2381
    assert gnss.time_s[0] == pytest.approx(4 * 86400 + 17 * 3600 + 30 * 60 + 39.749, abs=1e-6)
    assert np.degrees(gnss.lat_rad[0]) == pytest.approx(40.0966916)
    assert np.degrees(gnss.lon_rad[0]) == pytest.approx(-105.1471665)
    assert gnss.height_m[0] == pytest.approx(1601.435)
    np.testing.assert_allclose(gnss.sigma_ned_m[0], [0.0098995, 0.0098995, 0.0100000])
    assert gnss.num_sats[0] == 25
    # vu = +0.027 m/s up in the file is -0.027 m/s down.
    np.testing.assert_allclose(gnss.vel_ned_mps[0], [0.001, -0.002, -0.027])
    np.testing.assert_allclose(gnss.sigma_vel_ned_mps[0], [0.0494975] * 3)
    assert detect_format(walk_0827 / "gnss_1730_sf.pos") == "rtklib-pos"


def test_imu_rates_csv_walk(walk_0827):
    path = walk_0827 / "imu_1730_sf.csv"
    imu = read_imu_rates_csv(path, time_scale="unix-gpst", accel_unit="g", gyro_unit="rad/s",
                             sensor_rpy_deg=(180.0, 0.0, -90.0))
    raw = np.loadtxt(path, delimiter=",")
    assert len(imu) == len(raw) - 1 == 20454
    assert imu.gps_week == 2381
    # Same time scale as the .pos: the IMU starts 1.2 s after the first GNSS epoch.
    gnss = read_rtklib_pos(walk_0827 / "gnss_1730_sf.pos")
    assert imu.time_s[0] - gnss.time_s[0] == pytest.approx(1756402240.9670007 - 1756402239.749, abs=1e-6)
    # The logger samples every 6-9 ms (median 6 ms), not at the 100 Hz its README states.
    assert imu.rate_hz == pytest.approx(1 / 0.006, rel=1e-3)
    interval = np.diff(raw[:, 0])[:, None]
    specific_force = imu.dvel_mps / interval
    # Held still at the start: gravity reaction points up, i.e. -z in the FRD body frame.
    at_rest = specific_force[:100].mean(axis=0)
    assert at_rest[2] == pytest.approx(-9.91, abs=0.05)
    assert np.hypot(at_rest[0], at_rest[1]) < 0.3
    # Sensor (x, y, z) -> body (-y, -x, -z) for roll 180, yaw -90: check one sample exactly.
    f0 = 0.5 * (raw[0, 1:4] + raw[1, 1:4]) * 9.80665
    np.testing.assert_allclose(specific_force[0], [-f0[1], -f0[0], -f0[2]], rtol=1e-9)
    w0 = 0.5 * (raw[0, 4:7] + raw[1, 4:7])
    np.testing.assert_allclose(imu.dtheta_rad[0] / interval[0], [-w0[1], -w0[0], -w0[2]], rtol=1e-9)


def test_imu_rates_csv_detected_and_read_any(walk_0827):
    path = walk_0827 / "imu_1730_sf.csv"
    assert detect_format(path) == "imu-rates-csv"
    imu = read_any(path, time_scale="unix-gpst", accel_unit="g")
    assert len(imu) == 20454


def test_rates_csv_option_errors(walk_0827):
    path = walk_0827 / "imu_1730_sf.csv"
    with pytest.raises(ValueError, match="column index 11 does not exist, the file has 11 columns"):
        read_imu_rates_csv(path, gyro_columns=(4, 5, 11))
    with pytest.raises(ValueError, match="accel_unit = 'mg'"):
        read_imu_rates_csv(path, accel_unit="mg")


def test_the_logger_record_on_its_power_up_clock_is_put_on_gpst_by_its_rtklib_time_tag(walk_0827, tmp_path):
    """imu_1730.csv counts milliseconds since the IMU's power-up; its .tag puts it on GPST. Named in a
    survey as a user writes it, its times are those of the source's converted file to a microsecond."""
    import shutil

    from insrail.io import read_manifest
    from insrail.io.survey import MANIFEST_NAME

    for name in ("imu_1730.csv", "imu_1730.csv.tag", "gnss_1730_sf.pos"):
        shutil.copy(walk_0827 / name, tmp_path / name)
    (tmp_path / MANIFEST_NAME).write_text("""
[survey]
name = "walk"

[files.imu]
path = "imu_1730.csv"
format = "imu-rates-csv"
time_scale = "rtklib-tag"
time_column = 6
accel_columns = [0, 1, 2]
gyro_columns = [3, 4, 5]
accel_unit = "g"
gyro_unit = "deg/s"
sensor_rpy_deg = [180.0, 0.0, -90.0]

[files.gnss]
path = "gnss_1730_sf.pos"
format = "rtklib-pos"

[trolley]
imu_to_antenna_m = [0.0, 0.0, 0.0]
imu_to_reference_rail_m = [0.0, 0.0, 0.0]
""")
    imu = read_manifest(tmp_path).files["imu"].read(tmp_path)
    converted = read_imu_rates_csv(walk_0827 / "imu_1730_sf.csv", time_scale="unix-gpst", accel_unit="g",
                                   sensor_rpy_deg=(180.0, 0.0, -90.0))
    assert len(imu) == len(converted) == 20454  # the partial first and last lines left out
    assert imu.gps_week == converted.gps_week == 2381
    np.testing.assert_allclose(imu.time_s, converted.time_s, rtol=0, atol=1e-6)
    # the same motion: the mean specific force over the record within 0.01 m/s^2
    span = imu.time_s[-1] - imu.time_s[0]
    np.testing.assert_allclose(imu.dvel_mps.sum(axis=0) / span, converted.dvel_mps.sum(axis=0) / span, atol=0.01)


def test_a_time_tag_that_is_not_the_records_is_refused_naming_it(walk_0827, tmp_path):
    import shutil

    from insrail.io import InputError

    shutil.copy(walk_0827 / "imu_1730.csv", tmp_path / "imu.csv")
    tag = bytearray((walk_0827 / "imu_1730.csv.tag").read_bytes())
    options = dict(time_column=6, accel_columns=(0, 1, 2), gyro_columns=(3, 4, 5), time_scale="rtklib-tag",
                   accel_unit="g", gyro_unit="deg/s")
    with pytest.raises(InputError, match=r"imu.csv.tag: file not found"):
        read_imu_rates_csv(tmp_path / "imu.csv", **options)
    (tmp_path / "imu.csv.tag").write_bytes(bytes(tag[:76 + 8 * 4000]))  # the tag of a shorter record
    with pytest.raises(InputError, match=r"imu.csv.tag: the time tag spans .* but the record imu.csv counts"):
        read_imu_rates_csv(tmp_path / "imu.csv", **options)
    (tmp_path / "imu.csv.tag").write_bytes(b"not a tag" * 20)
    with pytest.raises(InputError, match=r"imu.csv.tag: not an RTKLIB time tag"):
        read_imu_rates_csv(tmp_path / "imu.csv", **options)
