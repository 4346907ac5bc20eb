"""The simulator's truth files, written beside each simulated survey and read by tests
and benchmarks.

``truth/nav.npy``       structured array at the IMU rate (NAV_TRUTH_DTYPE): IMU position,
                        NED velocity, attitude of b relative to NED, and station of the
                        trolley's reference point
``truth/antenna.npy``   the GNSS antenna's phase centre (ANTENNA_TRUTH_DTYPE: time, ECEF) at the
                        GNSS rate on the whole run, outages included (the RINEX simulator's rover)
``truth/sleepers.csv``  one row per sleeper: design station, passing time of the detector,
                        whether the detector saw it, centreline and rails (E, N, H), gauge,
                        cant, design cant and the injected irregularities
``truth/errors.toml``   realised sensor errors (turn-on biases, scale factors, odometer
                        scale, GNSS outages, false sleeper pulses); ``truth/imu_bias_gm.npy``
                        the in-run bias parts at 1 s
``truth/scenario.toml`` every scenario parameter, the seed and the engineering CRS
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

NAV_TRUTH_DTYPE = np.dtype(
    [
        ("time_s", "f8"),
        ("lat_rad", "f8"),
        ("lon_rad", "f8"),
        ("height_m", "f8"),
        ("vel_ned_mps", "f8", (3,)),
        ("rpy_rad", "f8", (3,)),
        ("station_m", "f8"),
    ]
)

ANTENNA_TRUTH_DTYPE = np.dtype([("time_s", "f8"), ("ecef_m", "f8", (3,))])

#: Columns of truth/sleepers.csv: (name, unit). Lengths in metres; the CSV header row
#: carries "name [unit]".
SLEEPER_COLUMNS = (
    ("index", "-"),
    ("station", "m"),
    ("pass_time", "s"),
    ("detected", "-"),
    ("centre_e", "m"), ("centre_n", "m"), ("centre_h", "m"),
    ("left_e", "m"), ("left_n", "m"), ("left_h", "m"),
    ("right_e", "m"), ("right_n", "m"), ("right_h", "m"),
    ("design_e", "m"), ("design_n", "m"), ("design_h", "m"),
    ("gauge", "m"),
    ("cant", "m"),
    ("design_cant", "m"),
    ("lateral", "m"),
    ("vertical", "m"),
    ("gauge_deviation", "m"),
    ("cross_level", "m"),
)


def write_sleeper_truth(path: Path, sections, index, pass_time_s, detected) -> Path:
    cols = [
        index, sections.station_m, pass_time_s, detected.astype(float),
        *sections.centre_enh_m.T, *sections.left_rail_enh_m.T, *sections.right_rail_enh_m.T,
        *sections.design_centre_enh_m.T, sections.gauge_m, sections.cant_m, sections.design_cant_m,
        sections.lateral_m, sections.vertical_m, sections.gauge_deviation_m, sections.cross_level_m,
    ]
    header = ",".join(f"{name} [{unit}]" for name, unit in SLEEPER_COLUMNS)
    fmt = ["%d", "%.6f", "%.6f", "%d"] + ["%.6f"] * 12 + ["%.9f"] * 7
    np.savetxt(path, np.column_stack(cols), delimiter=",", header=header, comments="", fmt=fmt)
    return path


@dataclass(frozen=True)
class SleeperTruth:
    """truth/sleepers.csv as arrays keyed by column name (see SLEEPER_COLUMNS)."""

    columns: dict[str, np.ndarray]

    def __getitem__(self, name: str) -> np.ndarray:
        return self.columns[name]

    def __len__(self) -> int:
        return len(self.columns["station"])


def read_sleeper_truth(path: str | Path) -> SleeperTruth:
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return SleeperTruth({name: data[:, i] for i, (name, _) in enumerate(SLEEPER_COLUMNS)})


def read_nav_truth(path: str | Path) -> np.ndarray:
    """truth/nav.npy (memory-mapped: a 10 km run holds 1.7 M rows)."""
    arr = np.load(path, mmap_mode="r")
    if arr.dtype != NAV_TRUTH_DTYPE:
        raise ValueError(f"{path}: not an insrail navigation truth file (dtype {arr.dtype})")
    return arr


def read_antenna_truth(path: str | Path) -> np.ndarray:
    """truth/antenna.npy: the antenna phase centre (time [s of week], ECEF [m])."""
    arr = np.load(path)
    if arr.dtype != ANTENNA_TRUTH_DTYPE:
        raise ValueError(f"{path}: not an insrail antenna truth file (dtype {arr.dtype})")
    return arr
