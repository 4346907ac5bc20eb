"""Line-type fitting on the simulator's `short` and `long` truth centrelines plus white noise.

    python benchmarks/linefit.py [--scenario short long] [--seed 1] [--noise-mm 0.5]
                                 [--long-wave-mm 5] [--work DIR]

Simulates each scenario with a perfect IMU (the centreline truth does not depend on the
IMU; `long` takes about 30 s, reused when DIR already holds it), adds --noise-mm of white
noise to the truth centreline (which already carries the injected 1 mm irregularities and
3 mm bumps), fits plan and profile, and prints every element boundary, arc radius,
clothoid length and vertical-curve radius against the design with the issue's bars
(boundaries 2 m, radii 0.2 %, clothoid lengths 1 m, vertical radii 2 %, <= 10 s per 10 km).

Then adds a GNSS-like long-wave error (--long-wave-mm at 2 km wavelength plus a drift of the
same size, across and up) and prints how well the global fit and the windowed reference
(500 m windows, 150 m overlap, eq. 5.24) recover the injected irregularities, with run times.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

# insrail before numpy, as every insrail command imports them: insrail sets OPENBLAS_NUM_THREADS=1 for the
# numpy it precedes; numpy first starts OpenBLAS with a thread per core, which on a loaded machine slowed the
# solver's SVDs four times and timed a fit no `insrail process` runs
import insrail  # noqa: F401, I001
import numpy as np

from insrail.sim.scenario import preset
from insrail.sim.simulate import simulate
from insrail.sim.truth import read_sleeper_truth
from insrail.track.alignment import Arc, Clothoid
from insrail.track.alignment_csv import read_alignment_csv
from insrail.track.linefit import fit_alignment
from insrail.track.linefit_windows import fit_windows

BOUNDARY_BAR_M = 2.0
RADIUS_BAR = 0.002
CLOTHOID_BAR_M = 1.0
VERTICAL_RADIUS_BAR = 0.02
SECONDS_PER_10_KM_BAR = 10.0


def survey(name: str, seed: int, work: Path) -> Path:
    folder = work / f"{name}-seed{seed}"
    if not (folder / "truth" / "sleepers.csv").exists():
        simulate(preset(name, imu_profile="perfect"), seed, folder, overwrite=True)
    return folder


def verdict(ok: bool) -> str:
    return "ok" if ok else "FAIL"


def compare(fitted, design) -> bool:
    """Print the fitted elements against the design; True when every figure is inside its bar."""
    plan = fitted.horizontal
    truth = [
        p for p in design.horizontal.placed_elements[1:]
        if plan.start_station_m < p.start_station_m < plan.end_station_m
    ]
    got = plan.placed_elements[1:]
    if [type(p.element) for p in got] != [type(p.element) for p in truth]:
        print("  element sequence differs:", [p.element.describe() for p in got])
        return False
    all_ok = True
    print("  joint  design [m]  error [m]   element                          error")
    for label, g, t in zip((k.label for k in plan.key_points()[1:-1]), got, truth):
        boundary_error = g.start_station_m - t.start_station_m
        ok = abs(boundary_error) < BOUNDARY_BAR_M
        figure = ""
        if isinstance(t.element, Arc):
            error = g.element.radius_m / t.element.radius_m - 1.0
            ok &= abs(error) < RADIUS_BAR and g.element.turn == t.element.turn
            figure = f"arc R {t.element.radius_m:.0f} m {t.element.turn:<5}  {100 * error:+.4f} %"
        elif isinstance(t.element, Clothoid):
            error = g.element.length_m - t.element.length_m
            ok &= abs(error) < CLOTHOID_BAR_M
            figure = f"clothoid L {t.element.length_m:.0f} m      {error:+.3f} m"
        else:
            figure = f"line L {t.element.length_m:.0f} m"
        print(f"  {label:<5}{t.start_station_m:>11.3f}{boundary_error:>+11.3f}   {figure:<33}{verdict(ok)}")
        all_ok &= ok
    got_pvis, truth_pvis = fitted.vertical.pvis[1:-1], design.vertical.pvis[1:-1]
    if len(got_pvis) != len(truth_pvis):
        print(f"  {len(got_pvis)} PVIs found, design has {len(truth_pvis)}")
        return False
    print("  PVI    design [m]  error [m]   vertical curve               error")
    for i, (g, t) in enumerate(zip(got_pvis, truth_pvis), start=2):
        station_error = g.station_m - t.station_m
        error = g.curve_radius_m / t.curve_radius_m - 1.0
        ok = abs(station_error) < BOUNDARY_BAR_M and abs(error) < VERTICAL_RADIUS_BAR
        print(
            f"  {i:<5}{t.station_m:>11.3f}{station_error:>+11.3f}   R {t.curve_radius_m:.0f} m"
            f"{'':<15}{100 * error:+.3f} %   {verdict(ok)}"
        )
        all_ok &= ok
    return all_ok


def long_wave_recovery(amplitude_mm, design, truth, east, north, height, noise) -> None:
    """Print the global and windowed deviations' errors on a centreline carrying a long-wave error."""
    station = truth["station"]
    relative = (station - station[0]) / (station[-1] - station[0])
    long_wave = 1e-3 * amplitude_mm * (np.sin(2 * np.pi * station / 2000.0) + relative**2)
    azimuth = design.horizontal.azimuth_at(station)
    east_lw, north_lw = east + long_wave * np.cos(azimuth), north - long_wave * np.sin(azimuth)
    height_lw = height + long_wave
    started, started_cpu = time.perf_counter(), time.process_time()
    fit = fit_alignment(station, east_lw, north_lw, height_lw)
    global_s, global_cpu_s = time.perf_counter() - started, time.process_time() - started_cpu
    reference = fit_windows(fit, station, east_lw, north_lw, height_lw)
    windowed_s = time.perf_counter() - started - global_s
    windowed_cpu_s = time.process_time() - started_cpu - global_cpu_s
    # what the deviations should show: the injected irregularities and the white noise, nothing longer
    truth_lateral = truth["lateral"] + noise[0] * np.cos(azimuth) - noise[1] * np.sin(azimuth)
    truth_vertical = truth["vertical"] + noise[2]
    print(f"  with a {amplitude_mm} mm long wave (2 km) and drift: global fit {global_s:.2f} s "
          f"(CPU {global_cpu_s:.2f} s), windows {windowed_s:.2f} s (CPU {windowed_cpu_s:.2f} s, "
          f"{len(reference.windows)} windows)")
    print("  deviation error [mm]        RMS lateral  max lateral  RMS vertical  max vertical")
    for label, lateral, vertical in (("global fit", fit.horizontal.offset_m, fit.vertical.residual_m),
                                     ("windowed (eq. 5.24)", reference.lateral_m, reference.vertical_m)):
        el, ev = 1e3 * (lateral - truth_lateral), 1e3 * (vertical - truth_vertical)
        print(f"  {label:<26}{np.sqrt(np.mean(el**2)):>12.3f}{np.abs(el).max():>13.3f}"
              f"{np.sqrt(np.mean(ev**2)):>14.3f}{np.abs(ev).max():>14.3f}")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--scenario", nargs="+", default=["short", "long"])
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--noise-mm", type=float, default=0.5)
    parser.add_argument("--long-wave-mm", type=float, default=5.0)
    parser.add_argument("--work", type=Path, default=Path(tempfile.gettempdir()) / "insrail-linefit-bench")
    args = parser.parse_args()
    all_ok = True
    for name in args.scenario:
        folder = survey(name, args.seed, args.work)
        truth = read_sleeper_truth(folder / "truth" / "sleepers.csv")
        design = read_alignment_csv(folder / "truth" / "design.csv")
        rng = np.random.default_rng(args.seed)
        station = truth["station"]
        noise = rng.normal(0.0, 1e-3 * args.noise_mm, (3, len(truth)))
        east, north, height = (truth[c] + noise[i] for i, c in enumerate(("centre_e", "centre_n", "centre_h")))
        started, started_cpu = time.perf_counter(), time.process_time()
        fit = fit_alignment(station, east, north, height, name=f"fitted {name}")
        elapsed, elapsed_cpu = time.perf_counter() - started, time.process_time() - started_cpu
        length_km = (station[-1] - station[0]) / 1000.0
        time_ok = elapsed <= SECONDS_PER_10_KM_BAR * max(length_km, 1.0) / 10.0
        print(f"\n{name}: {len(truth)} points over {length_km:.2f} km, noise {args.noise_mm} mm")
        print(
            f"  fit time {elapsed:.2f} s ({verdict(time_ok)}; CPU {elapsed_cpu:.2f} s); residual RMS plan "
            f"{1e3 * fit.horizontal.rms_m:.2f} mm, profile {1e3 * fit.vertical.rms_m:.2f} mm"
        )
        all_ok &= compare(fit.alignment, design) and time_ok
        long_wave_recovery(args.long_wave_mm, design, truth, east, north, height, noise)
    print("\nall figures inside the bars" if all_ok else "\nSOME FIGURES OUTSIDE THE BARS")
    return 0 if all_ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
