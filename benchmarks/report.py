"""Report speed on a 10 km survey: the crews' workbook and the PDF report of 16 000 sleepers.

    python benchmarks/report.py [--project DIR] [--survey NAME] [--sleepers 16000] [--keep]

Takes the results of a processed survey (by default runs `insrail demo` into a temporary folder
first, about 30 s, not timed), tiles its sleeper table end to end until it holds --sleepers rows
(stations, sleeper numbers, times, coordinates and exceedances shifted per copy, labels
recomputed, the TQI sections and GNSS outages repeated), then times write_workbook and write_pdf.
The budget for both together is 20 s.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import tempfile
import time
import tomllib
from pathlib import Path

import numpy as np

from insrail.project import load_project
from insrail.project.results import (
    EXCEEDANCE_HEADER,
    EXCEEDANCES_FILE,
    SLEEPERS_FILE,
    SUMMARY_FILE,
    TRAJECTORY_FILE,
    load_results,
    summary_toml,
    write_results,
)
from insrail.report import write_pdf, write_workbook
from insrail.track.stationing import StationEquations

BUDGET_S = 20.0


def tiled_results(project_folder: Path, survey: str, sleepers: int, name: str) -> None:
    """Write ``results/<name>/`` holding ``survey``'s results repeated to ``sleepers`` rows."""
    source = load_results(project_folder, survey)
    n = len(source)
    copies = -(-sleepers // n)
    c = source.columns
    spacing = float(np.median(np.diff(c["station_m"])))
    length = c["station_m"][-1] - c["station_m"][0] + spacing
    duration = c["time_s"][-1] - c["time_s"][0] + 1.0
    shift = {"station_m": length, "time_s": duration}
    for rail in ("left", "right"):  # the next copy starts where the previous one ended
        for axis in "EN":
            key = f"{rail}_{axis}_m"
            step = c[key][-1] - c[key][0]
            shift[key] = step + step / max(n - 1, 1)
    columns = {key: np.concatenate([values + k * shift.get(key, 0.0) for k in range(copies)])[:sleepers]
               for key, values in c.items()}
    number = np.concatenate([source.number + k * n for k in range(copies)])[:sleepers]
    prefix = source.label[0].split("+")[0].rstrip("0123456789-") if source.label else "K"
    label = StationEquations(prefix=prefix).label(columns["station_m"])
    header = ",".join(["number", "label", *columns]) + "\n"
    block = np.column_stack(list(columns.values()))
    lines = [",".join([str(num), lab, *("" if np.isnan(v) else f"{v:.6f}" for v in row)])
             for num, lab, row in zip(number.tolist(), label, block.tolist())]
    sleepers_csv = header + "\n".join(lines) + "\n"

    rows = [",".join(EXCEEDANCE_HEADER)]
    for k in range(copies):
        for e in source.exceedances:
            first, last = e.first_sleeper + k * n, e.last_sleeper + k * n
            if last <= number[-1]:
                rows.append(",".join([e.check, e.kind, e.rail, e.direction, e.unit, f"{e.station_from_m + k * length:.3f}",
                                      f"{e.station_to_m + k * length:.3f}", f"{e.peak:.6f}", f"{e.limit:.6f}",
                                      str(first), str(last)]))
    summary = tomllib.loads((source.folder / SUMMARY_FILE).read_text(encoding="utf-8"))
    summary["track"].update(sleepers=sleepers, valid_sleepers=int(columns["valid"].sum()),
                            station_to_m=float(columns["station_m"][-1]))
    summary["assessment"]["exceedances"] = len(rows) - 1
    quality = summary.get("track_quality", {})
    if quality.get("start_m"):
        sections = len(quality["start_m"])
        for key, values in quality.items():
            if isinstance(values, list) and len(values) == sections:
                quality[key] = [v + k * length if key == "start_m" else v for k in range(copies) for v in values]
    gnss = summary.get("gnss", {})
    if gnss.get("outages"):
        gnss["outages"] = [[a + k * duration, b + k * duration] for k in range(copies) for a, b in gnss["outages"]]
    write_results(project_folder / "results", name, {
        TRAJECTORY_FILE: source.folder / TRAJECTORY_FILE, SLEEPERS_FILE: sleepers_csv,
        EXCEEDANCES_FILE: "\n".join(rows) + "\n", SUMMARY_FILE: summary_toml(summary)})


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--project", type=Path, help="a processed project (default: run `insrail demo` first)")
    parser.add_argument("--survey", default="short")
    parser.add_argument("--sleepers", type=int, default=16000)
    parser.add_argument("--keep", action="store_true", help="keep the reports (printed paths)")
    args = parser.parse_args()
    scratch = Path(tempfile.mkdtemp(prefix="insrail-report-bench-"))
    try:
        folder = args.project
        if folder is None:
            folder = scratch / "demo"
            print("running insrail demo for the source results ...", flush=True)
            subprocess.run([sys.executable, "-m", "insrail", "demo", "--out", str(folder)], check=True,
                           stdout=subprocess.DEVNULL)
        name = f"{args.survey}-x{args.sleepers}"
        tiled_results(folder, args.survey, args.sleepers, name)
        project = load_project(folder)
        results = load_results(folder, name)
        print(f"{len(results)} sleepers, {results.columns['station_m'][-1] - results.columns['station_m'][0]:.0f} m, "
              f"{len(results.exceedances)} exceedances")
        out = (folder / "results" / name) if args.keep else scratch
        started = time.perf_counter()
        xlsx = write_workbook(project, results, out / "report.xlsx")
        workbook_s = time.perf_counter() - started
        started = time.perf_counter()
        pdf = write_pdf(project, results, out / "report.pdf")
        pdf_s = time.perf_counter() - started
        total = workbook_s + pdf_s
        print(f"workbook {workbook_s:.1f} s ({xlsx.stat().st_size / 1e6:.1f} MB), pdf {pdf_s:.1f} s "
              f"({pdf.stat().st_size / 1e6:.1f} MB), together {total:.1f} s: "
              f"{'within' if total <= BUDGET_S else 'OVER'} the {BUDGET_S:.0f} s budget")
        if args.keep:
            print(f"reports: {xlsx}\n         {pdf}")
        return 0 if total <= BUDGET_S else 1
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
        if args.project is not None and not args.keep:
            shutil.rmtree(args.project / "results" / f"{args.survey}-x{args.sleepers}", ignore_errors=True)


if __name__ == "__main__":
    sys.exit(main())
