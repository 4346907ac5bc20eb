"""Fusion integrity against faulty input: corrupt IMU records, IMU gaps, a survey without odometer.

    python benchmarks/imu_integrity.py [--seed 1] [--workdir DIR] [--skip-sim] [--skip-walk]

Simulator `short`, navigation grade (the survey of benchmarks/fusion.py): the clean run, then
one corrupt record (+1 m/s added to one 5 ms velocity increment while the trolley walks), a
0.5 s and a 2 s IMU gap while moving. For each: horizontal/vertical position RMS against the
truth and its ratio to the clean run, the 1-sigma of the 5 m lag difference of the lateral and
vertical error (outside +-5 m of the fault, and inside), and what the fusion said (records
removed, gaps bridged). Then the rates-CSV dropout (sum of the vertical velocity increments at
rest with a 1 s dropout, against the clean file) and the real handheld MEMS walk
(../shared/data/real/walk_0827, GNSS only, no odometer) through `insrail fuse` with the shipped
`mems_handheld` profile and then the data sheet's `mems`: the share of GNSS epochs used and the
smoothed position against the fixes per axis in units of the file's and of the used 1-sigma.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import tempfile
import tomllib
from dataclasses import replace
from pathlib import Path

import numpy as np

FAULT_OFFSET_S = 900.0  # after the start of the survey: the trolley walks
LAG_M = 5.0


def survey_dir(workdir: Path, seed: int) -> Path:
    from insrail.sim.scenario import preset
    from insrail.sim.simulate import simulate

    folder = workdir / f"short-seed{seed}"
    if not (folder / "survey.toml").exists():
        simulate(preset("short"), seed, folder, imu_format="npy", overwrite=True)
    return folder


def lag_sigma_mm(errors, lag_m: float, exclude: tuple[float, float] | None, inside: bool = False):
    """1-sigma [mm] of e(s + lag) - e(s) (lateral, vertical) over pairs at sleeper spacing; pairs
    touching the station interval ``exclude`` left out (or, with ``inside``, only those)."""
    from insrail.sim.evaluation import SLEEPER_SPACING_M

    s = errors.station_m
    grid = np.arange(s[errors.moving][0] + 1.0, s[-1] - 1.0 - lag_m, SLEEPER_SPACING_M)
    a, b = np.searchsorted(s, grid), np.searchsorted(s, grid + lag_m)
    keep = np.ones(len(grid), dtype=bool)
    if exclude is not None:
        touches = (grid + lag_m >= exclude[0]) & (grid <= exclude[1])
        keep = touches if inside else ~touches
    if not keep.any():
        return float("nan"), float("nan")
    lat = errors.lateral_m[b[keep]] - errors.lateral_m[a[keep]]
    ver = errors.vertical_m[b[keep]] - errors.vertical_m[a[keep]]
    return 1e3 * float(np.std(lat)), 1e3 * float(np.std(ver))


def simulator_cases(folder: Path) -> None:
    from insrail.io.survey import read_survey
    from insrail.nav.earth import CGCS2000
    from insrail.nav.fusion import fuse_survey
    from insrail.sim.evaluation import trajectory_errors
    from insrail.sim.truth import read_nav_truth

    survey = read_survey(folder)
    truth = read_nav_truth(folder / "truth" / "nav.npy")
    imu = survey.imu
    t_fault = imu.time_s[0] + FAULT_OFFSET_S
    k = int(np.searchsorted(imu.time_s, t_fault))
    fault_station = float(np.interp(t_fault, truth["time_s"], truth["station_m"]))

    def corrupt():
        dvel = imu.dvel_mps.copy()
        dvel[k, 0] += 1.0
        return replace(imu, dvel_mps=dvel), (fault_station - LAG_M, fault_station + LAG_M)

    def gap(seconds):
        def make():
            keep = (imu.time_s <= t_fault) | (imu.time_s > t_fault + seconds)
            end = float(np.interp(t_fault + seconds, truth["time_s"], truth["station_m"]))
            return (replace(imu, time_s=imu.time_s[keep], dtheta_rad=imu.dtheta_rad[keep], dvel_mps=imu.dvel_mps[keep]),
                    (fault_station - LAG_M, end + LAG_M))
        return make

    cases = {"clean": lambda: (imu, None), "corrupt Δv +1 m/s": corrupt, "gap 0.5 s moving": gap(0.5),
             "gap 2 s moving": gap(2.0)}
    print(f"simulator `short`, nav grade, {folder.name}; fault at t0 + {FAULT_OFFSET_S:.0f} s, station "
          f"{fault_station:.1f} m (moving)")
    print(f"{'case':<20} {'horiz':>7} {'vert':>7} {'x clean':>7} {'lat5':>6} {'ver5':>6} {'lat5 in':>7} "
          f"{'ver5 in':>7}  {'removed / bridged (what the fusion said)'}")
    print(f"{'':<20} {'mm':>7} {'mm':>7} {'':>7} {'mm':>6} {'mm':>6} {'mm':>7} {'mm':>7}")
    clean_rms = None
    for name, make in cases.items():
        data, zone = make()
        result = fuse_survey(replace(survey, imu=data), ellipsoid=CGCS2000, output_every=2)
        errors = trajectory_errors(result.trajectory, truth, CGCS2000)
        rms = float(np.hypot(errors.rms_horizontal_m(), errors.rms_vertical_m()))
        clean_rms = clean_rms or rms
        out5 = lag_sigma_mm(errors, LAG_M, zone)
        in5 = lag_sigma_mm(errors, LAG_M, zone, inside=True) if zone else (float("nan"),) * 2
        said = [n.message.split(": ", 1)[-1][:70] for n in result.info["notices"] if n.stage == "imu"]
        print(f"{name:<20} {1e3 * errors.rms_horizontal_m():7.2f} {1e3 * errors.rms_vertical_m():7.2f} "
              f"{rms / clean_rms:7.2f} {out5[0]:6.3f} {out5[1]:6.3f} {in5[0]:7.3f} {in5[1]:7.3f}  "
              f"{len(result.info['imu_outliers'])} removed, {len(result.info['imu_gaps'])} bridged; "
              f"{'; '.join(said) or '-'}")
        if name.startswith("corrupt"):
            listed = [o for o in result.info["imu_outliers"] if abs(o.time_s - imu.time_s[k]) < 1e-6]
            print(f"{'':<20} record at t = {imu.time_s[k]:.4f} s listed as removed: {'yes' if listed else 'NO'}")


def rates_dropout() -> None:
    """Sum of the vertical velocity increments of a rates CSV at rest, clean and with a 1 s dropout."""
    from insrail.io.imu import read_imu_rates_csv
    from insrail.nav.imu_gaps import bridge_gaps

    rate, seconds = 200.0, 10.0
    t = 230400.0 + np.arange(int(rate * seconds) + 1) / rate
    rows = np.column_stack([t, np.zeros_like(t), np.zeros_like(t), np.full_like(t, -9.79), np.zeros((len(t), 3))])
    with tempfile.TemporaryDirectory() as tmp:
        clean_path, holed_path = Path(tmp) / "clean.csv", Path(tmp) / "holed.csv"
        np.savetxt(clean_path, rows, delimiter=",", fmt="%.6f")
        keep = (t < t[0] + 4.0) | (t >= t[0] + 5.0)
        np.savetxt(holed_path, rows[keep], delimiter=",", fmt="%.6f")
        clean, _ = bridge_gaps(read_imu_rates_csv(clean_path))
        holed, warnings = bridge_gaps(read_imu_rates_csv(holed_path))
    print(f"\nrates CSV at rest, {seconds:.0f} s at {rate:.0f} Hz: sum of dv_z clean {clean.dvel_mps[:, 2].sum():.3f} m/s, "
          f"with a 1 s dropout bridged {holed.dvel_mps[:, 2].sum():.3f} m/s ({len(warnings)} gap bridged; "
          f"{len(clean)} / {len(holed)} records)")


def walk(workdir: Path, profile: str, options: list[str]) -> None:
    """The real walk through `insrail fuse` as a user runs it; the share of fixes used and the smoothed
    antenna position against the fixes per axis, in units of the file's sigmas and of those the fusion
    used (the file's x the quality policy's factor x the calibrated scale)."""
    from insrail.cli.main import main
    from insrail.io import read_rtklib_pos
    from insrail.nav.earth import WGS84, radii
    from insrail.nav.fusion import FusionOptions
    from insrail.nav.rotation import euler_to_dcm
    from insrail.nav.trajectory import load_trajectory
    from insrail.sim.recordings import walk_survey

    real = Path(__file__).resolve().parents[2] / "shared" / "data" / "real" / "walk_0827"
    if not real.is_dir():
        real = Path("/work/shared/data/real/walk_0827")
    folder, out = walk_survey(workdir / "walk_0827", profile, real), workdir / f"walk_0827_fused_{profile}"
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed), contextlib.redirect_stderr(printed):
        code = main(["fuse", str(folder), "--out", str(out), "--ellipsoid", "WGS84", *options])
    print(f"\nwalk_0827 (handheld MEMS, no odometer), imu_profile {profile}: insrail fuse {' '.join(options)} "
          f"-> exit {code}")
    for line in printed.getvalue().splitlines():
        if not line.startswith("fuse:"):
            print("   ", line)
    if code != 0:
        return
    log = tomllib.loads((out / "fusion_log.toml").read_text())
    gnss = read_rtklib_pos(folder / "gnss_1730_sf.pos")
    traj = load_trajectory(out / "trajectory.npy")
    inside = (gnss.time_s >= traj.time_s[0]) & (gnss.time_s <= traj.time_s[-1])
    used = log["measurements"].get("gnss_position", {}).get("used", 0)
    t = gnss.time_s[inside]
    k = np.clip(np.searchsorted(traj.time_s, t), 0, len(traj) - 1)
    antenna = np.einsum("nij,j->ni", euler_to_dcm(*traj.rpy_rad[k].T), np.array([0.0, 0.05, 0.0]))
    r_m, r_n = radii(gnss.lat_rad[inside], WGS84)
    d = np.column_stack([(np.interp(t, traj.time_s, traj.lat_rad) - gnss.lat_rad[inside]) * r_m + antenna[:, 0],
                         (np.interp(t, traj.time_s, traj.lon_rad) - gnss.lon_rad[inside]) * r_n
                         * np.cos(gnss.lat_rad[inside]) + antenna[:, 1],
                         -(np.interp(t, traj.time_s, traj.height_m) - gnss.height_m[inside]) + antenna[:, 2]])
    policy = dict(FusionOptions().gnss_quality_policy)
    factor = np.array([policy.get(int(q)) or np.nan for q in gnss.quality[inside]])
    scale = log["calibration"]["gnss_sigma_scale"]
    sigma_used = np.maximum(gnss.sigma_ned_m[inside] * (factor * scale)[:, None], log["options"]["gnss_sigma_floor_m"])
    print(f"    GNSS epochs within the IMU span {int(inside.sum())}, position updates used {used} "
          f"({100 * used / max(int(inside.sum()), 1):.1f} %), rejected {log['measurements'].get('gnss_position', {}).get('rejected', 0)}; "
          f"passes {log['calibration']['passes']}, NHC dropped {log['calibration']['nhc_dropped']}, "
          f"GNSS sigma scale {scale:g}")
    print(f"    smoothed antenna - fixes RMS N/E/D {' / '.join(f'{1e3 * v:.1f}' for v in np.sqrt(np.mean(d**2, axis=0)))} mm")
    for label, sigma in (("the file's sigmas", gnss.sigma_ned_m[inside]), ("the sigmas used", sigma_used)):
        within = np.abs(d) / sigma < 3.0
        print(f"    within 3 x {label:17s}: N {100 * within[:, 0].mean():5.1f} %  E {100 * within[:, 1].mean():5.1f} %  "
              f"D {100 * within[:, 2].mean():5.1f} %  all axes {100 * within.all(axis=1).mean():5.1f} %")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--workdir", type=Path, default=Path(tempfile.gettempdir()) / "insrail-bench")
    parser.add_argument("--skip-sim", action="store_true")
    parser.add_argument("--skip-walk", action="store_true")
    args = parser.parse_args()
    args.workdir.mkdir(parents=True, exist_ok=True)
    if not args.skip_sim:
        simulator_cases(survey_dir(args.workdir, args.seed))
    rates_dropout()
    if not args.skip_walk:
        # as a user runs it: the hand-held profile, nothing else (the fusion finds that the NHC does not
        # hold and calibrates the receiver's optimistic sigmas); then the data sheet's MEMS profile
        walk(args.workdir, "mems_handheld", [])
        walk(args.workdir, "mems", [])


if __name__ == "__main__":
    main()
