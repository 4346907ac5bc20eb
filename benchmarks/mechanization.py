"""Throughput of the compiled strapdown loop on a 1.7 M-epoch recording (the `long` scenario size).

    PYTHONPATH=. python benchmarks/mechanization.py [--epochs N]

Runs two fresh interpreters sharing an empty numba cache directory: the first compiles the
kernels, the second loads them from the disk cache. Each reports its start-up cost (first
call on 10 epochs) and then epochs/s of

* the bare compiled loop (``_kernels.integrate_span``, no output kept),
* ``integrate`` keeping every epoch, and every 200th (1 Hz) epoch,

on synthetic navigation-grade increments (trolley at rest with white noise).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time

import numpy as np


def synthetic_imu(n: int):
    from insrail.io.types import ImuIncrements
    from insrail.nav import earth, rotation

    dt = 0.005
    lat, h = np.deg2rad(31.0), 20.0
    c_nb = rotation.euler_to_dcm(0.01, -0.005, 1.2).T
    rng = np.random.default_rng(7)
    dtheta = c_nb @ earth.earth_rate_ned(lat) * dt + rng.normal(0.0, 1e-7, (n, 3))
    dvel = c_nb @ np.array([0.0, 0.0, -earth.normal_gravity(lat, h)]) * dt + rng.normal(0.0, 1e-5, (n, 3))
    imu = ImuIncrements(1000.0 + dt * np.arange(1, n + 1), dtheta, dvel)
    return imu, (lat, 2.0, h)


def run_once(n: int) -> None:
    t_import = time.perf_counter()
    from insrail.nav import _kernels
    from insrail.nav.earth import WGS84
    from insrail.nav.mechanization import NavState, integrate, nav_vector

    small, (lat, lon, h) = synthetic_imu(10)
    state = NavState.from_euler(small.time_s[0], lat, lon, h, np.zeros(3), 0.01, -0.005, 1.2)
    integrate(small, state)
    print(f"  start-up (import + first call): {time.perf_counter() - t_import:6.2f} s")

    imu, _ = synthetic_imu(n)
    dt = np.full(n, 0.005)
    sink = (np.empty((1, 4)), np.empty(1), np.empty((1, 3)), np.empty((1, 4)))  # nothing is stored
    earth = _kernels.earth_constants(WGS84)
    t = time.perf_counter()
    _kernels.integrate_span(nav_vector(state), imu.dtheta_rad, imu.dvel_mps, dt, earth, 1, n, n, 0, *sink)
    elapsed = time.perf_counter() - t
    print(f"  compiled loop only:             {n / elapsed / 1e6:6.2f} M epochs/s ({elapsed:.3f} s)")
    for every in (1, 200):
        t = time.perf_counter()
        sol = integrate(imu, state, output_every=every)
        elapsed = time.perf_counter() - t
        rate = n / elapsed / 1e6
        print(f"  integrate(output_every={every:3d}):    {rate:6.2f} M epochs/s ({elapsed:.3f} s, {len(sol)} rows)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--epochs", type=int, default=1_700_000)
    parser.add_argument("--once", action="store_true", help="one measurement in this process (internal)")
    args = parser.parse_args()
    if args.once:
        run_once(args.epochs)
        return
    with tempfile.TemporaryDirectory(prefix="insrail-numba-") as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        for label in ("cold: compiles the kernels", "warm: loads them from the disk cache"):
            print(f"{label} ({args.epochs} epochs)")
            subprocess.run([sys.executable, __file__, "--once", "--epochs", str(args.epochs)], env=env, check=True)


if __name__ == "__main__":
    main()
