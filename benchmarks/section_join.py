"""A line section of two runs: the simulator's `long` preset (10.2 km) cut into two runs with a
500 m overlap over one track (same track seed, independent noise seeds), processed and joined.

    python benchmarks/section_join.py [--workdir DIR] [--overlap mean]

Prints the joined table's sleepers, whether it equals each run's outside the overlap, whether the
numbering is continuous, the overlap's run-to-run differences (1-sigma of the 30 m/5 m checks:
issue 23's bar 0.3 mm; compared by magnitude and not within 30 m of the overlap's ends, see
insrail.track.repeatability) against their predicted sigma, and where the workbook and PDF went.
Simulated surveys and the fusion caches are kept in DIR (default /tmp/insrail-section-join).
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

CUT_M = (20050.0, 25400.0, 24900.0, 30250.0)  # run 1 from, to; run 2 from, to: 500 m overlap


def simulated_run(folder: Path, start: float, end: float, seed: int) -> Path:
    from insrail.sim.scenario import preset
    from insrail.sim.simulate import simulate

    if not (folder / "survey.toml").is_file():
        config = preset("long")
        stops = tuple(s for s in config.motion.stops if start + 100 < s[0] < end - 100)
        config = replace(config, motion=replace(config.motion, start_station_m=start, end_station_m=end, stops=stops))
        simulate(config, seed=seed, out_dir=folder, imu_format="npy", overwrite=True, track_seed=7)
    return folder


def main() -> None:
    from insrail.cli.main import main as cli
    from insrail.project import load_project, process
    from insrail.project.demo import project_for_simulated_survey
    from insrail.project.model import SectionEntry, SurveyEntry, save_project
    from insrail.project.results import load_results

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workdir", type=Path, default=Path("/tmp/insrail-section-join"))
    parser.add_argument("--overlap", choices=("best", "mean"), default="best")
    args = parser.parse_args()
    root = args.workdir
    started = time.perf_counter()
    first = simulated_run(root / "surveys" / "run1", CUT_M[0], CUT_M[1], seed=1)
    simulated_run(root / "surveys" / "run2", CUT_M[2], CUT_M[3], seed=2)
    print(f"simulated in {time.perf_counter() - started:.0f} s")
    project = project_for_simulated_survey(root, first, name="long section")
    project = replace(project, surveys=(SurveyEntry("run1", "surveys/run1"), SurveyEntry("run2", "surveys/run2")),
                      sections=(SectionEntry("km20-30", ("run1", "run2"), overlap=args.overlap),))
    save_project(project)
    project = load_project(root)
    for name in ("run1", "run2"):
        started = time.perf_counter()
        process(project, name)
        print(f"processed {name} in {time.perf_counter() - started:.0f} s")
    started = time.perf_counter()
    assert cli(["section", str(root)]) == 0
    print(f"joined and reported in {time.perf_counter() - started:.0f} s")
    joined = load_results(root, "km20-30")
    runs = [load_results(root, name) for name in ("run1", "run2")]
    c = joined.columns
    print(f"joined: {len(joined)} sleepers, {int((c['valid'] > 0).sum())} valid, stations "
          f"{c['station_m'][0]:.1f}-{c['station_m'][-1]:.1f} m")
    print(f"numbering continuous: {bool(np.all(np.diff(joined.number) == 1))} ({joined.number[0]}..{joined.number[-1]})")
    for run in runs:
        source = c[f"source_{run.survey}"] == 1.0
        only = ~np.isin(np.round(c["station_m"], 2), np.round(np.concatenate(
            [r.columns["station_m"] for r in runs if r is not run]), 2))
        rows = source & only
        mine = np.isin(np.round(run.columns["station_m"], 4), np.round(c["station_m"][rows], 4))
        same = all(np.array_equal(c[k][rows], run.columns[k][mine], equal_nan=True)
                   for k in ("lateral_deviation_left_mm", "vertical_deviation_right_mm", "gauge_mm", "cant_mm", "left_E_m"))
        print(f"{run.survey}: {int(rows.sum())} rows from it alone, equal to its own: {same}")
    for overlap in joined.summary["section"]["overlaps"]:
        print(f"overlap {overlap['runs']} {overlap['from_m']:.1f}-{overlap['to_m']:.1f} m, {overlap['sleepers']} sleepers:")
        for name, values in overlap["parameters"].items():
            predicted = values.get("predicted_sigma_mm")
            print(f"  {name:48s} {values['compared']:9s} std {values['std_mm']:7.3f} mm  RMS {values['rms_mm']:7.3f} mm"
                  + (f"  predicted {predicted:6.3f} mm{'  EXCEEDS 3 sigma' if values.get('exceeds') else ''}"
                     if predicted is not None else ""))
    print(f"notices: {[n['message'] for n in joined.summary['notices'] if n['stage'] == 'section']}")
    print(f"workbook and PDF: {root / 'reports'}")


if __name__ == "__main__":
    main()
