"""Reader speed on a 3-hour, 200 Hz IMU recording (2.2 million lines), and simulator speed.

    python benchmarks/io_speed.py [--lines N] [--no-simulator]

The simulator measurement runs the `long` scenario (about 10 km, 1.8 M IMU epochs) with
the navigation-grade IMU and writes it as a KF-GINS text survey.

Generates the files in a temporary folder (about 340 MB of text), times each
measurement and prints the figures. One function per measurement; main() runs them.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

from insrail.io import read_imu_kfgins, read_imu_npy, write_imu_kfgins, write_imu_npy
from insrail.io.types import ImuIncrements

RATE_HZ = 200.0
DEFAULT_LINES = 2_200_000


def realistic_imu(lines: int, seed: int = 7) -> ImuIncrements:
    """A trolley at walking pace: gravity, earth rate, small vibration, navigation-grade noise."""
    rng = np.random.default_rng(seed)
    dt = 1.0 / RATE_HZ
    time_s = 456_300.0 + dt * np.arange(1, lines + 1)
    dtheta = rng.normal(0.0, 2e-7, (lines, 3)) + np.array([5.3e-5, 0.0, -6.1e-5]) * dt
    dvel = rng.normal(0.0, 5e-5, (lines, 3)) + np.array([0.02, 0.0, -9.79]) * dt
    return ImuIncrements(time_s=time_s, dtheta_rad=dtheta, dvel_mps=dvel, gps_week=2380)


def timed(label: str, action) -> object:
    start = time.perf_counter()
    result = action()
    print(f"{label:<34s} {time.perf_counter() - start:7.2f} s")
    return result


def measure_kfgins_text(folder: Path, imu: ImuIncrements) -> None:
    path = folder / "imu.txt"
    timed(f"write_imu_kfgins ({len(imu):,} lines)", lambda: write_imu_kfgins(path, imu))
    print(f"{'  file size':<34s} {path.stat().st_size / 1e6:7.1f} MB")
    back = timed("read_imu_kfgins", lambda: read_imu_kfgins(path))
    assert np.array_equal(back.dvel_mps, imu.dvel_mps), "text round trip lost precision"
    # the yardstick: numpy's C parser, which read_numeric_table falls back to for what the
    # compiled reader leaves (see insrail.io.fastparse)
    timed("  np.loadtxt of the same file", lambda: np.loadtxt(path, ndmin=2))


def measure_npy(folder: Path, imu: ImuIncrements) -> None:
    path = folder / "imu.npy"
    timed("write_imu_npy", lambda: write_imu_npy(path, imu))
    timed("read_imu_npy", lambda: read_imu_npy(path))


def measure_simulator(folder: Path) -> None:
    from insrail.sim.scenario import preset
    from insrail.sim.simulate import simulate

    result = timed("simulate long (nav grade, text)", lambda: simulate(preset("long"), 1, folder / "long"))
    print(f"{'  survey':<34s} {result.length_m:7.0f} m, {result.duration_s:.0f} s, "
          f"{result.imu_epochs:,} IMU epochs, {result.sleepers:,} sleepers")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--lines", type=int, default=DEFAULT_LINES)
    parser.add_argument("--no-simulator", action="store_true", help="skip the simulator measurement")
    args = parser.parse_args(argv)
    imu = realistic_imu(args.lines)
    with tempfile.TemporaryDirectory(prefix="insrail-io-speed-") as tmp:
        folder = Path(tmp)
        measure_kfgins_text(folder, imu)
        measure_npy(folder, imu)
        if not args.no_simulator:
            measure_simulator(folder)


if __name__ == "__main__":
    main()
