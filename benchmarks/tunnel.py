"""Tunnel: the simulator's `tunnel` preset (1.46 km without GNSS, prism fixes every 60 m) and its
`tunnel-no-gnss` preset (1.5 km with no GNSS at all), nav grade.

    python benchmarks/tunnel.py [--workdir DIR]

1. The `tunnel` survey as simulated (GNSS outside the tunnel, 1 mm prism fixes in engineering
   coordinates every 60 m inside) processed by `insrail process`: inside the tunnel, the absolute error
   of the centreline (lateral, vertical: RMS, 95 % of |error| and largest) beside the fusion's predicted
   1-sigma there (quality.csv), and the 1-sigma of the error difference 5 m and 150 m apart.
   Bars (issue 22): 30 m/5 m irregularity error 1 sigma <= 0.3 mm, absolute error <= 2 mm.
2. The same fixes as raw total-station observations: a free station beside the track every 120 m,
   8 CPIII points each (4 pairs 60 m apart: 0.3 mgon, 0.5 mm), its pointings at the prism of the fixes
   around it; written as the crew's Leica GSI-16 files `total_station.gsi` (total-station-gsi) and
   `cpiii.gsi` (cpiii-gsi) in the survey instead of prism.txt, resected and placed by `insrail process`
   (insrail.project.total_station).
   The pointings are generated from the simulated 1 mm fixes, so their errors add to those
   (conservative). Bar: within 1.5x of case 1.
3. In case 2 one CPIII point of the file is 5 mm off: `insrail process` names it (a warning per set-up
   using it) and leaves it out.
4. No GNSS at all (`tunnel-no-gnss`, the gnss role dropped from survey.toml): the fusion starts from the
   fix taken during the static start and is held by a fix every 60 m; the same figures over the run,
   for each seed of --seeds.

Beside each case with given fixes: how honest the product's predicted 1-sigma (quality.csv, per 200 m
section) is, as the RMS of error / sigma (1 when honest) and the share of sleepers within 2 sigma
(95 % when honest); and the largest |error| to expect over the run from that sigma. Between fixes
the error drifts as a random walk (the trolley's yaw and pitch play, the fusion's NHC noise), at the
fixes it is held by the fixes' noise, so the largest over a run is that of a smoothed random walk,
not of independent draws: :func:`expected_largest` simulates the 1-D smoother of a random walk with
fixes of the survey's sigma every 60 m, its drift set so that its 1-sigma equals the predicted one,
and gives the median and 90 % of the largest |error| over the run and the chance that it stays
within 2 mm. --fix-sigma-mm sets the simulated fixes' sigma per axis (default 1 mm: the simulator's
and the filter's sigma of each coordinate; 0.71 mm per axis is 1 mm plan point error).
Simulated surveys and projects are kept in DIR (default: a temporary folder).
"""

from __future__ import annotations

import argparse
import shutil
import tempfile
import tomllib
from pathlib import Path

import numpy as np

MGON = np.pi / 200_000.0


def _simulated(work: Path, name: str, seed: int, fix_sigma_m: float) -> Path:
    """The preset ``name`` simulated with prism fixes of ``fix_sigma_m`` (kept in ``work``)."""
    from dataclasses import replace

    from insrail.sim.scenario import preset
    from insrail.sim.simulate import simulate

    folder = work / f"{name}-fix{1e3 * fix_sigma_m:g}mm-seed{seed}" / name
    if not (folder / "survey.toml").is_file():
        config = preset(name)
        simulate(replace(config, prism=replace(config.prism, sigma_m=fix_sigma_m)), seed=seed, out_dir=folder,
                 imu_format="npy", overwrite=True)
    return folder


def expected_largest(fix_sigma_m: float, sigma_m: float, length_m: float, spacing_m: float = 60.0,
                     runs: int = 2000, seed: int = 0) -> tuple[float, float, float]:
    """(median, 90 % of the largest |error| over a run [m], chance it is <= 2 mm) of the RTS smoother of
    a random walk along ``length_m`` (1 m steps) with fixes of ``fix_sigma_m`` every ``spacing_m``
    (both ends included), its drift per metre chosen so that the smoother's RMS 1-sigma over the run
    is ``sigma_m`` (module docstring)."""
    stations = np.arange(0.0, length_m + 0.5)
    fixed = np.isclose(np.mod(stations + 0.5 * spacing_m, spacing_m), 0.5 * spacing_m) | (stations == stations[-1])

    def smoother(q, truth=None, noise=None):
        """Smoothed 1-sigma (and errors, given the truth and the fixes' noise) at every station."""
        n = len(stations)
        p_pred, p_filt = np.empty(n), np.empty(n)
        x_pred, x_filt = (None, None) if truth is None else (np.empty_like(truth), np.empty_like(truth))
        p, x = 1.0, (None if truth is None else np.zeros(truth.shape[0]))
        for k in range(n):
            p += q if k else 0.0
            p_pred[k] = p
            if truth is not None:
                x_pred[:, k] = x
            if fixed[k]:
                gain = p / (p + fix_sigma_m**2)
                p *= 1.0 - gain
                if truth is not None:
                    x = x + gain * (truth[:, k] + noise[:, k] - x)
            p_filt[k] = p
            if truth is not None:
                x_filt[:, k] = x
        p_s, x_s = p_filt.copy(), None if truth is None else x_filt.copy()
        for k in range(n - 2, -1, -1):
            c = p_filt[k] / p_pred[k + 1]
            p_s[k] = p_filt[k] + c * c * (p_s[k + 1] - p_pred[k + 1])
            if truth is not None:
                x_s[:, k] = x_filt[:, k] + c * (x_s[:, k + 1] - x_pred[:, k + 1])
        return np.sqrt(p_s), None if truth is None else x_s - truth

    low, high = -14.0, -2.0  # log10 of the drift variance per metre
    for _ in range(40):
        middle = 0.5 * (low + high)
        sigma = np.sqrt(np.mean(smoother(10.0**middle)[0] ** 2))
        low, high = (middle, high) if sigma < sigma_m else (low, middle)
    q = 10.0 ** (0.5 * (low + high))
    rng = np.random.default_rng(seed)
    truth = np.cumsum(rng.normal(0.0, np.sqrt(q), (runs, len(stations))), axis=1)
    _, errors = smoother(q, truth, rng.normal(0.0, fix_sigma_m, truth.shape))
    largest = np.abs(errors).max(axis=1)
    return float(np.median(largest)), float(np.percentile(largest, 90)), float(np.mean(largest <= 0.002))


def _process(root: Path, survey: Path, name: str):
    from insrail.project import process
    from insrail.project.demo import project_for_simulated_survey

    target = root / "surveys" / name
    if target.exists():  # the survey as given now (the project's cache keeps the fusion of unchanged files)
        shutil.rmtree(target)
    shutil.copytree(survey, target)
    return process(project_for_simulated_survey(root, target, name=name), name), target


def _errors(results, survey: Path, tunnel: tuple[float, float]) -> dict[str, float]:
    from insrail.sim.truth import read_sleeper_truth

    table = results.table
    truth = read_sleeper_truth(survey / "truth" / "sleepers.csv")
    order = np.argsort(truth["station"])
    stations = truth["station"][order]
    k = np.clip(np.searchsorted(stations, table.station_m), 1, len(stations) - 1)
    near = order[np.where(np.abs(stations[k - 1] - table.station_m) < np.abs(stations[k] - table.station_m), k - 1, k)]
    inside = table.valid & (table.station_m > tunnel[0]) & (table.station_m < tunnel[1])
    quality = results.quality
    in_tunnel = (quality.station_to_m > tunnel[0]) & (quality.station_from_m < tunnel[1])
    section = np.clip(np.searchsorted(quality.station_from_m, table.station_m, side="right") - 1, 0,
                      len(quality.station_from_m) - 1)
    out = {"length_m": float(np.ptp(table.station_m[inside]))}
    for name, measured, injected in (("lateral", table.lateral_deviation_m, truth["lateral"]),
                                     ("vertical", table.vertical_deviation_m, truth["vertical"])):
        error = measured.mean(axis=1) - injected[near]
        out[f"{name}_rms_mm"] = 1e3 * float(np.sqrt(np.mean(error[inside] ** 2)))
        out[f"{name}_p95_mm"] = 1e3 * float(np.percentile(np.abs(error[inside]), 95))
        out[f"{name}_max_mm"] = 1e3 * float(np.abs(error[inside]).max())
        out[f"{name}_predicted_mm"] = 1e3 * float(np.nanmedian(getattr(quality, f"sigma_{name}_m")[in_tunnel]))
        ratio = error[inside] / getattr(quality, f"sigma_{name}_m")[section[inside]]
        out[f"{name}_normalised_rms"] = float(np.sqrt(np.mean(ratio**2)))
        out[f"{name}_within_2sigma"] = float(np.mean(np.abs(ratio) <= 2.0))
        for lag in (5.0, 150.0):
            j = np.searchsorted(table.station_m, table.station_m + lag)
            ok = inside & (j < len(table))
            pair = ok & inside[np.minimum(j, len(table) - 1)]
            out[f"{name}_lag{lag:g}_mm"] = 1e3 * float(np.std(error[j[pair]] - error[pair]))
    return out


def _print(title: str, figures: dict[str, float], fix_sigma_m: float | None = None) -> None:
    """The figures of one case; with ``fix_sigma_m`` (given fixes) the largest to expect, too."""
    print(title)
    for direction in ("lateral", "vertical"):
        print(f"   {direction}: absolute RMS {figures[f'{direction}_rms_mm']:.2f} mm (predicted 1 sigma "
              f"{figures[f'{direction}_predicted_mm']:.2f} mm), 95 % {figures[f'{direction}_p95_mm']:.2f} mm, largest "
              f"{figures[f'{direction}_max_mm']:.2f} mm; error difference 1 sigma 5 m apart "
              f"{figures[f'{direction}_lag5_mm']:.3f} mm, 150 m apart {figures[f'{direction}_lag150_mm']:.3f} mm")
        print(f"      error / predicted sigma: RMS {figures[f'{direction}_normalised_rms']:.2f} (1 when honest), "
              f"{100 * figures[f'{direction}_within_2sigma']:.1f} % within 2 sigma (95 %)", end="")
        if fix_sigma_m is None:
            print()
            continue
        median, p90, chance = expected_largest(fix_sigma_m, 1e-3 * figures[f"{direction}_predicted_mm"],
                                               figures["length_m"])
        print(f"; largest to expect over {figures['length_m']:.0f} m: median {1e3 * median:.2f} mm, 90 % "
              f"{1e3 * p90:.2f} mm, P(largest <= 2 mm) = {chance:.2f}")


def _cpiii(design, stations_m: np.ndarray) -> tuple[list[str], np.ndarray]:
    """CPIII pairs at ``stations_m``: 2.2 m each side of the design centreline, 1 m above it."""
    names, points = [], []
    for s in stations_m:
        for side, offset in (("L", -2.2), ("R", 2.2)):
            e, n = design.horizontal.point_at(s, offset)
            names.append(f"CP{s:.0f}{side}")
            points.append((float(e), float(n), float(design.vertical.elevation_at(s)) + 1.0))
    return names, np.array(points)


def _observe(station: np.ndarray, orientation: float, targets: np.ndarray, rng, names):
    from insrail.geodesy.free_station import (
        EARTH_RADIUS_M,
        REFRACTION_K,
        PolarObservations,
    )

    delta = targets - station
    d = np.hypot(delta[:, 0], delta[:, 1])
    dz = delta[:, 2] - (1 - REFRACTION_K) * d**2 / (2 * EARTH_RADIUS_M)
    return PolarObservations(tuple(names), np.mod(np.arctan2(delta[:, 0], delta[:, 1]) - orientation, 2 * np.pi)
                             + rng.normal(0, 0.3 * MGON, len(d)),
                             np.arctan2(d, dz) + rng.normal(0, 0.3 * MGON, len(d)),
                             np.hypot(d, dz) + rng.normal(0, 0.0005, len(d)))


def raw_observation_survey(survey: Path, out: Path, rng) -> tuple[int, str]:
    """Write ``out`` (a copy of ``survey``) whose prism fixes are raw pointings of free stations
    (module docstring, case 2) with one CPIII point 5 mm off; returns the number of set-ups and the
    point moved."""
    from dataclasses import replace

    from insrail.io.control import read_prism_enu
    from insrail.io.survey import SurveyFile, read_manifest, write_manifest
    from insrail.io.gsi import write_cpiii_gsi, write_total_station_gsi
    from insrail.io.types import ControlPoints, TotalStationObservations
    from insrail.track.alignment_csv import read_alignment_csv

    if out.exists():
        shutil.rmtree(out)
    shutil.copytree(survey, out)
    design = read_alignment_csv(survey / "truth" / "design.csv")
    prism = read_prism_enu(survey / "prism.txt")
    fixes = np.column_stack([prism.east_m, prism.north_m, prism.height_m])
    fix_station, _ = design.horizontal.station_offset(fixes[:, 0], fixes[:, 1])
    setups = np.arange(fix_station.min() + 30.0, fix_station.max() + 60.0, 120.0)
    rows: dict[str, list] = {k: [] for k in ("setup", "target", "time_s", "hz_rad", "zenith_rad", "slope_m")}
    cpiii: dict[str, np.ndarray] = {}
    for k, s in enumerate(setups):
        e, n = design.horizontal.point_at(s, 3.0)
        station = np.array([float(e), float(n), float(design.vertical.elevation_at(s)) + 1.6])
        names, points = _cpiii(design, s + np.array([-90.0, -30.0, 30.0, 90.0]))
        cpiii.update(zip(names, points))
        orientation = rng.uniform(0, 2 * np.pi)
        near = np.abs(fix_station - s) <= 60.0 + 1e-6
        for targets, times, observed in (
                (names, np.full(len(names), prism.time_s[near].min() - 60.0), _observe(station, orientation, points, rng, names)),
                (["prism"] * int(near.sum()), prism.time_s[near],
                 _observe(station, orientation, fixes[near], rng, ["prism"] * int(near.sum())))):
            for key, values in (("setup", [f"TS{k + 1:02d}"] * len(targets)), ("target", targets), ("time_s", times),
                                ("hz_rad", observed.hz_rad), ("zenith_rad", observed.zenith_rad),
                                ("slope_m", observed.slope_m)):
                rows[key] += list(values)
    moved = sorted(cpiii)[len(cpiii) // 2]
    cpiii[moved] = cpiii[moved] + np.array([0.003, 0.004, 0.0])  # mis-surveyed by 5 mm in plan
    write_total_station_gsi(out / "total_station.gsi", TotalStationObservations(
        **{k: np.array(v) for k, v in rows.items()}, line=np.zeros(len(rows["time_s"]), dtype=int)))
    ids = sorted(cpiii)
    write_cpiii_gsi(out / "cpiii.gsi", ControlPoints(np.array(ids), *np.array([cpiii[i] for i in ids]).T))
    manifest = read_manifest(out)
    files = {role: entry for role, entry in manifest.files.items() if role != "prism"}
    files |= {"total_station": SurveyFile("total_station.gsi", "total-station-gsi"),
              "cpiii": SurveyFile("cpiii.gsi", "cpiii-gsi")}
    (out / "prism.txt").unlink()
    write_manifest(out, replace(manifest, files=files))
    return len(setups), moved


def _without_gnss(survey: Path) -> Path:
    from dataclasses import replace

    from insrail.io.survey import read_manifest, write_manifest

    manifest = read_manifest(survey)
    if "gnss" in manifest.files:
        (survey / manifest.files["gnss"].path).unlink()
        write_manifest(survey, replace(manifest, files={r: e for r, e in manifest.files.items() if r != "gnss"}))
    return survey


def main() -> None:
    from insrail.sim.scenario import preset

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workdir", type=Path, help="keep the simulated surveys and the projects here")
    parser.add_argument("--fix-sigma-mm", type=float, default=1.0,
                        help="sigma of each coordinate of the simulated prism fixes [mm] (default 1)")
    parser.add_argument("--seeds", type=int, nargs="+", default=[1], help="seeds of case 4 (default 1)")
    args = parser.parse_args()
    work = args.workdir or Path(tempfile.mkdtemp(prefix="insrail-tunnel-"))
    work.mkdir(parents=True, exist_ok=True)
    fix_sigma = 1e-3 * args.fix_sigma_mm
    survey = _simulated(work, "tunnel", 1, fix_sigma)
    outage = tomllib.loads((survey / "truth" / "errors.toml").read_text())["gnss_outages_s"][0]
    nav = np.load(survey / "truth" / "nav.npy")
    tunnel = tuple(np.interp(outage, nav["time_s"], nav["station_m"]) + np.array([60.0, -10.0]))  # after the first fix
    given, _ = _process(work / "given-fixes", survey, "tunnel")
    first = _errors(given, survey, tunnel)
    _print(f"1. prism fixes ({args.fix_sigma_mm:g} mm) every 60 m, stations {tunnel[0]:.0f} .. {tunnel[1]:.0f} m "
           f"({given.summary['fusion']['prism_fixes']} fixes):", first, fix_sigma)
    setups, moved = raw_observation_survey(survey, work / "raw-survey", np.random.default_rng(5))
    raw, _ = _process(work / "raw-fixes", work / "raw-survey", "tunnel")
    second = _errors(raw, survey, tunnel)
    _print(f"2. the fixes from raw observations on {setups} free stations, resected by insrail process "
           f"({raw.summary['fusion']['prism_fixes']} fixes):", second)
    ratio = max(second[k] / first[k] for k in first if k.endswith(("rms_mm", "lag5_mm")))
    print(f"   largest ratio to case 1 (RMS and 5 m figures): {ratio:.2f} (bar 1.5)")
    named = [n["message"] for n in raw.summary["notices"] if n["stage"] == "total station"]
    print(f"3. CPIII point {moved} 5 mm off in cpiii.gsi: {len(named)} warning(s), naming it: "
          f"{all(moved in m for m in named) and bool(named)}" + (f"; first: {named[0]}" if named else ""))
    motion = preset("tunnel-no-gnss").motion
    run = (motion.start_station_m + 1.0, motion.end_station_m - 1.0)
    largest = []
    for seed in args.seeds:
        alone = _without_gnss(_simulated(work, "tunnel-no-gnss", seed, fix_sigma))
        fourth, _ = _process(alone.parent / "project", alone, "tunnel-no-gnss")
        figures = _errors(fourth, alone, run)
        largest.append([figures["lateral_max_mm"], figures["vertical_max_mm"]])
        _print(f"4. no GNSS at all, seed {seed}: {fourth.summary['fusion']['prism_fixes']} prism fixes "
               f"({args.fix_sigma_mm:g} mm) every 60 m from the static start, stations {run[0]:.0f} .. {run[1]:.0f} m "
               f"(alignment: {fourth.summary['fusion'].get('alignment')}):", figures, fix_sigma)
    if len(args.seeds) > 1:
        largest = np.array(largest)
        print(f"   largest over the seeds {args.seeds}: lateral " + ", ".join(f"{v:.2f}" for v in largest[:, 0])
              + " mm; vertical " + ", ".join(f"{v:.2f}" for v in largest[:, 1])
              + f" mm; <= 2 mm in {int(np.sum(largest.max(axis=1) <= 2.0))} of {len(args.seeds)} runs")


if __name__ == "__main__":
    main()
