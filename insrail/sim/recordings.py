"""Survey folders around the shared real recordings, as a user would describe them: the one place
the benchmarks (benchmarks/imu_integrity.py) and the tests (tests/test_nav_self_calibration.py)
build them from."""

from __future__ import annotations

from pathlib import Path

WALK_MANIFEST = """[survey]
name = "walk_0827"
imu_profile = "{profile}"
description = "rtklibexplorer/GNSS_IMU walk_0827: handheld u-blox + MEMS IMU, no odometer"

{imu}
[files.gnss]
path = "gnss_1730_sf.pos"
format = "rtklib-pos"

[trolley]
imu_to_antenna_m = [0.0, 0.05, 0.0]
imu_to_reference_rail_m = [0.0, 0.0, 0.0]
"""
# The source's configuration puts the IMU 5 cm to the side of the antenna ("imu_offset = [0, 0.05, 0]");
# the data decide the sign in insrail's b frame: +0.05 m fits (GNSS NIS 0.99 per degree of freedom, no
# rejection), -0.05 m does not (1.25, 18 rejected), none in between (1.06, 9 rejected).


#: the IMU record as the source converted it (GPST in Unix-style seconds, rad/s) and as the logger wrote it
#: (its power-up millisecond counter put on GPST by RTKLIB's time tag beside it, deg/s)
WALK_IMU = {
    "converted": ("""[files.imu]
path = "imu_1730_sf.csv"
format = "imu-rates-csv"
time_scale = "unix-gpst"
accel_unit = "g"
gyro_unit = "rad/s"
sensor_rpy_deg = [180.0, 0.0, -90.0]
""", ("imu_1730_sf.csv",)),
    "tag": ("""[files.imu]
path = "imu_1730.csv"
format = "imu-rates-csv"
time_scale = "rtklib-tag"
time_column = 6
accel_columns = [0, 1, 2]
gyro_columns = [3, 4, 5]
accel_unit = "g"
gyro_unit = "deg/s"
sensor_rpy_deg = [180.0, 0.0, -90.0]
""", ("imu_1730.csv", "imu_1730.csv.tag")),
}


def walk_survey(folder: Path, profile: str, real: Path, reading: str = "converted") -> Path:
    """The real walk as a survey folder: its files linked from ``real`` (the recording's folder), its
    survey.toml (WALK_MANIFEST) with ``profile`` and the IMU record's ``reading`` (WALK_IMU); ``folder``."""
    imu, files = WALK_IMU[reading]
    folder.mkdir(parents=True, exist_ok=True)
    for name in (*files, "gnss_1730_sf.pos"):
        if not (folder / name).exists():
            (folder / name).symlink_to(real / name)
    (folder / "survey.toml").write_text(WALK_MANIFEST.format(profile=profile, imu=imu))
    return folder
