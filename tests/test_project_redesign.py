"""insrail redesign end to end on the simulator's ballasted survey: every row of tamping.csv meets the
constraints, the TRUE track moved by the amounts passes the profile wherever they allow, and the
re-designed line is the next survey's design (processed with it)."""

import shutil
import subprocess
import sys
from dataclasses import replace

import numpy as np
import pytest

from insrail.export.tamping import read_tamping
from insrail.project import load_project, process
from insrail.project.model import save_project
from insrail.project.pipeline import read_design
from insrail.project.redesign import run_redesign
from insrail.project.results import load_results
from insrail.sim.evaluation import truth_rail_deviations
from insrail.sim.truth import read_sleeper_truth
from insrail.track.exceedance import SleeperGeometry, assess
from insrail.track.redesign import moved
from insrail.track.tolerance import load_tolerance_profile


@pytest.mark.slow
def test_ballasted_survey_redesign_passes_on_the_truth_and_its_design_processes_the_next_survey(tmp_path):
    subprocess.run([sys.executable, "-m", "insrail", "demo", "--preset", "ballasted", "--out", str(tmp_path)],
                   check=True, stdout=subprocess.DEVNULL)
    (tmp_path / "project.toml").write_text((tmp_path / "project.toml").read_text()
                                           + "\n[redesign]\nmax_slew_mm = 8\n")
    project = load_project(tmp_path)
    run = run_redesign(project, "ballasted")

    table = read_tamping(run.folder / "tamping.csv")
    lifts = np.column_stack([table.values["lift_left"], table.values["lift_right"]])
    assert lifts.min() >= 0.0 and lifts.max() <= 50.0
    assert np.abs(table.values["slew"]).max() <= 8.0
    fixed = [(1500.0, 1540.0), (1800.0, 1808.0)]  # the preset's bridge and level crossing
    for start, end in fixed:
        inside = (table.station_m >= start) & (table.station_m <= end)
        assert inside.sum() > 10 and np.all(lifts[inside] == 0.0) and np.all(table.values["slew"][inside] == 0.0)
    assert {"TS", "SC", "CS", "ST", "PVI"} <= set(table.mark)
    assert any(m.startswith("fixed start (bridge") for m in table.mark)
    assert table.label[0].startswith("K1+")

    stored = load_results(tmp_path, "ballasted")
    truth = read_sleeper_truth(tmp_path / "surveys" / "ballasted" / "truth" / "sleepers.csv")
    station = stored.columns["station_m"]
    lateral, vertical, gauge, cant, design_cant = truth_rail_deviations(truth, station)
    true = SleeperGeometry.from_arrays(station, lateral, vertical, gauge, cant, design_cant,
                                       valid=stored.columns["valid"] > 0)
    profile = load_tolerance_profile(project.resource(project.tolerance_profile))
    assert len(assess(true, profile).exceedances) > 20
    after = assess(moved(true, run.result.lift_m, run.result.slew_m), profile)
    listed = [(s.station_from_m, s.station_to_m) for s in run.result.cannot_pass]
    for e in after.exceedances:  # only where the constraints do not allow the track to pass
        assert any(a - 10.0 <= e.station_from_m <= b + 10.0 for a, b in listed), e

    design = read_design(run.folder / "design.xml")  # the project's own alignment reader
    assert design.horizontal.start_station_m <= station[5] and design.vertical is not None
    shutil.copyfile(run.folder / "design.xml", tmp_path / "after_tamping.xml")
    save_project(replace(project, design="after_tamping.xml"))
    results = process(load_project(tmp_path), "ballasted")
    ok = np.isfinite(results.table.vertical_deviation_m[:, 0])
    assert ok.sum() > 1800
    # the deviations from the re-designed line are minus the corrections to the line fit's residual
    lift = np.interp(results.table.station_m[ok], run.result.station_m, run.result.lift_m[:, 0])
    residual = results.table.vertical_deviation_m[ok, 0] + lift
    assert np.sqrt(np.mean(residual**2)) < 0.015
