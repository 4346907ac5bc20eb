"""Direction independence: the demo with its design stationed the other way, and a forward and a
reverse run of one track compared.

    python benchmarks/direction.py [--workdir DIR]

1. The demo survey (`short`, nav grade, seed 1) processed twice: with its design, and with the
   same design stationed from the other end (``insrail.track.reversed_design``; the trolley then
   runs against the stationing). Prints the largest difference, sleeper by sleeper, of every
   deviation and check of sleepers.csv (left and right swapped back, lateral and cant signs turned).
   Bar (issue 22): 0.05 mm.
2. A reverse run of the same track (the trolley pushed from the far end, facing its travel; an
   independent noise seed) in the same project as the forward one, compared with
   ``insrail compare``: 1-sigma of the 30 m/5 m check differences. Bar: 0.3 mm. The checks are
   compared by magnitude (``insrail.track.repeatability``: the sign of a worst value over the chord
   placements flips between runs where two placements tie); the second forward run is the noise level.
Simulated surveys and the fusion caches are kept in DIR (default: a temporary folder).
"""

from __future__ import annotations

import argparse
import shutil
import tempfile
import tomllib
from dataclasses import replace
from pathlib import Path

import numpy as np


def _survey(folder: Path, reverse: bool, seed: int) -> Path:
    from insrail.sim.scenario import preset
    from insrail.sim.simulate import simulate

    if not (folder / "survey.toml").is_file():
        config = preset("short")
        config = replace(config, motion=replace(config.motion, reverse=reverse))
        simulate(config, seed=seed, out_dir=folder, imu_format="npy", overwrite=True, track_seed=1)
    return folder


def _read(path: Path) -> np.ndarray:
    return np.genfromtxt(path, delimiter=",", names=True, dtype=None, encoding="utf-8", missing_values="",
                         filling_values=np.nan)


#: Differential-versine checks: the value of a point pair belongs to its first point in the
#: direction of the stationing (thesis eq. 2.2), so with the stationing reversed the same pair's
#: value sits at its other point, the pair distance away, with the sign of the reversed difference.
PAIR_M = {"short_wave_30m_5m": 5.0, "long_wave_300m_150m": 150.0}


def _pairs(names) -> list[tuple[str, str, float, float]]:
    """(column in the forward run, column in the reversed-stationing run, sign, station shift [m])."""
    pairs = [("gauge_mm", "gauge_mm", 1.0, 0.0), ("cant_mm", "cant_mm", -1.0, 0.0),
             ("design_cant_mm", "design_cant_mm", -1.0, 0.0), ("twist_3m_mm", "twist_3m_mm", 1.0, 0.0),
             ("check_cross_level_mm", "check_cross_level_mm", -1.0, 0.0),
             ("check_twist_3m_mm", "check_twist_3m_mm", 1.0, 0.0), ("check_gauge_mm", "check_gauge_mm", 1.0, 0.0)]
    for name in names:
        if "left" in name and (name.startswith(("lateral_deviation", "vertical_deviation", "check_"))):
            other = name.replace("left", "right")
            sign = -1.0 if "lateral" in name else 1.0
            shift = next((pair for check, pair in PAIR_M.items() if check in name), 0.0)
            if shift:
                sign = -sign
            pairs += [(name, other, sign, shift), (other, name, sign, shift)]
    return [p for p in pairs if p[0] in names]


def reversed_stationing(work: Path) -> float:
    from insrail.project import load_project, process
    from insrail.project.demo import project_for_simulated_survey
    from insrail.project.model import SurveyEntry, save_project
    from insrail.track.alignment_csv import read_alignment_csv, write_alignment_csv
    from insrail.track.reversed_design import reversed_design

    root = work / "demo"
    survey = _survey(root / "surveys" / "short", reverse=False, seed=1)
    project = project_for_simulated_survey(root, survey)
    process(project, "short")
    design = read_alignment_csv(survey / "truth" / "design.csv")
    write_alignment_csv(root / "design_reversed.csv", reversed_design(design))
    other = root / "reversed-project"
    other.mkdir(exist_ok=True)
    (other / "results").mkdir(exist_ok=True)
    shutil.copytree(root / "results" / ".cache", other / "results" / ".cache", dirs_exist_ok=True)  # same fusion
    save_project(replace(project, folder=other, surveys=(SurveyEntry("short", "../surveys/short"),),
                         height=replace(project.height, benchmarks="../surveys/short/benchmarks.txt"),
                         design="../design_reversed.csv"))
    process(load_project(other), "short")
    forward = _read(root / "results" / "short" / "sleepers.csv")
    backward = _read(other / "results" / "short" / "sleepers.csv")
    h = design.horizontal
    mirrored = h.start_station_m + h.end_station_m - backward["station_m"]
    rows = np.searchsorted(forward["station_m"], mirrored - 1e-3)
    rows = np.clip(rows, 0, len(forward) - 1)
    same = np.abs(forward["station_m"][rows] - mirrored) < 1e-3
    print(f"1. design stationed the other way: {same.sum()} of {len(backward)} sleepers at the forward run's "
          f"stations (largest station difference {1e3 * np.abs(forward['station_m'][rows] - mirrored)[same].max():.4f} mm)")
    worst = 0.0
    for name_f, name_b, sign, shift in _pairs(forward.dtype.names):
        if shift:  # not sleeper by sleeper: the partner point falls between sleepers
            f, b = forward[name_f], backward[name_b]
            print(f"   {name_b:43s} (pair value at the pair's first point, {shift:g} m from where the forward "
                  f"stationing puts it): largest |value| {np.nanmax(np.abs(b)):.3f} mm, forward {name_f} "
                  f"{np.nanmax(np.abs(f)):.3f} mm; 1-sigma {np.nanstd(b):.3f} / {np.nanstd(f):.3f} mm")
            continue
        f, b = forward[name_f][rows][same], backward[name_b][same]
        both = np.isfinite(f) & np.isfinite(b)
        difference = float(np.abs(b[both] - sign * f[both]).max(initial=0.0))
        if np.isfinite(f).sum() != np.isfinite(b).sum():
            print(f"   {name_b}: computable at {np.isfinite(b).sum()} sleepers, forward {np.isfinite(f).sum()}")
        worst = max(worst, difference)
        print(f"   {name_b:43s} = {'-' if sign < 0 else '+'}forward {name_f}: largest difference {difference:.4f} mm")
    exceed = [tomllib.loads((p / "results" / "short" / "summary.toml").read_text())["assessment"]["exceedances"]
              for p in (root, other)]
    print(f"   largest difference sleeper by sleeper: {worst:.4f} mm (bar 0.05 mm); exceedances {exceed[0]} forward, "
          f"{exceed[1]} with the design stationed the other way")
    return worst


def forward_and_reverse(work: Path) -> float:
    from insrail.project import load_project, process
    from insrail.project.compare import compare_surveys
    from insrail.project.demo import project_for_simulated_survey
    from insrail.project.model import SurveyEntry, save_project

    root = work / "two-runs"
    forward = _survey(root / "surveys" / "forward", reverse=False, seed=2)
    _survey(root / "surveys" / "reverse", reverse=True, seed=3)
    _survey(root / "surveys" / "forward-again", reverse=False, seed=4)
    project = project_for_simulated_survey(root, forward, name="forward and reverse")
    runs = ("forward", "reverse", "forward-again")
    save_project(replace(project, surveys=tuple(SurveyEntry(name, f"surveys/{name}") for name in runs)))
    project = load_project(root)
    for name in runs:
        process(project, name)
    compare_surveys(project, list(runs))
    summary = tomllib.loads((root / "results" / "repeatability.toml").read_text())
    print("2. a reverse and a second forward run of one track against the forward run, insrail compare "
          "(1 sigma of run minus forward; the second forward run is the noise level):")
    worst = 0.0
    for name, table in summary["parameters"].items():
        reverse, again = table["reverse"], table["forward-again"]
        print(f"   {name:45s} reverse {reverse['std_mm']:.3f} mm, forward again {again['std_mm']:.3f} mm "
              f"(n = {reverse['count']}, {table['compared']})")
        if "short_wave_30m_5m" in name:
            worst = max(worst, reverse["std_mm"])
    print(f"   30 m/5 m differences reverse minus forward, largest 1 sigma: {worst:.3f} mm (bar 0.3 mm)")
    return worst


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workdir", type=Path, help="keep the simulated surveys and caches here")
    args = parser.parse_args()
    work = args.workdir or Path(tempfile.mkdtemp(prefix="insrail-direction-"))
    work.mkdir(parents=True, exist_ok=True)
    reversed_stationing(work)
    forward_and_reverse(work)


if __name__ == "__main__":
    main()
