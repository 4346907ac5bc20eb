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
    listed = [(s.station_from_m, s.station_to_m) for s in (*run.result.cannot_pass, *run.result.uncertain)]
    listed += [tuple(stretch) for item in run.summary["not_assessed"] for stretch in item["stretches_m"]]
    for e in after.exceedances:  # only where the constraints (or the survey's accuracy) do not let it pass
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


def _quality(edges_m, lag5_lateral_mm, lag5_vertical_mm, cross_level_mm=0.05):
    """quality.csv as read back: the stated 1-sigma per section (the 5 m lags' per section, the rest small)."""
    from insrail.project.results import StoredQuality

    k = len(edges_m) - 1
    small = np.full(k, 0.05)
    return StoredQuality(True, np.asarray(edges_m[:-1], float), np.asarray(edges_m[1:], float), small, small,
                         np.asarray(lag5_lateral_mm, float), np.asarray(lag5_vertical_mm, float), small, small,
                         np.full(k, cross_level_mm), small)


def test_after_the_job_a_check_the_survey_cannot_resolve_is_not_called_passing_and_one_it_can_passes_on_the_truth():
    """The re-assessment after the job takes the one assessable rule (3 sigma within the limit): over
    the section whose stated 5 m lag sigma is too large for the 10 m versine's 3 mm, that check is
    not assessed after the job (no value, no exceedance, listed), not "passes"; where it is assessed
    the check is held three sigma inside its limit, so the TRUE track (the measured one less the
    survey's error) moved by the amounts passes wherever nothing is listed. With only the fixed
    0.5 mm margin (no stated accuracy) it does not: the test can fail."""
    from insrail.project.redesign import survey_uncertainty
    from insrail.track.redesign import RedesignSettings, redesign
    from insrail.track.adjustment_programme import RailCheck
    from tests.test_track_redesign import _ballasted, _wave

    true = _ballasted(seed=7)  # 1280 sleepers, 1000-1800 m
    # the survey's error of the rails' height: waves of 6-30 m, 0.5 mm RMS (its 10 m versine 0.54 mm RMS)
    error = _wave(np.random.default_rng(11), true.station_m, 0.5e-3, 6, 30)
    measured = replace(true, vertical_deviation_m=true.vertical_deviation_m + error[:, None])
    assert np.nanstd(RailCheck("versine", 8, 8, 0.0).values(error)) < 1.0e-3 * np.sqrt(0.5)  # within the stated
    profile = load_tolerance_profile("cn_conventional_160")
    # vertical: 1000-1400 m 5 m lag 1 mm (10 m versine 0.71 mm: 3 sigma 2.1 mm, within 3 mm), 1400-1800 m
    # 10 mm (3 sigma 21 mm: not assessable); lateral 0.6 mm throughout
    quality = _quality([1000.0, 1200.0, 1400.0, 1600.0, 1800.0], [0.6] * 4, [1.0, 1.0, 10.0, 10.0])
    uncertainty = survey_uncertainty(profile, quality, measured.station_m)
    assert [(n.check, n.direction, n.stretches_m) for n in uncertainty.not_assessable] == [
        ("versine_10m", "vertical", ((1400.0, 1800.0),))]
    result = redesign(measured, profile, RedesignSettings(), uncertainty=uncertainty.within_m,
                      not_assessed=uncertainty.masks())

    beyond = measured.station_m >= 1400.0
    vertical = [c for c in result.after.channels if c.check == "versine_10m" and c.direction == "vertical"]
    assert len(vertical) == 2 and all(np.all(np.isnan(c.values[beyond])) for c in vertical)
    assert not any(e.check == "versine_10m" and e.direction == "vertical" and e.station_to_m >= 1400.0
                   for e in result.after.exceedances)
    assert not any(s.what.startswith("versine_10m") and s.what.endswith("vertical") and s.station_to_m >= 1400.0
                   for s in (*result.cannot_pass, *result.uncertain))
    assert result.margin_m[("versine_10m", "vertical")] == pytest.approx(3 * 1.0e-3 * np.sqrt(0.5))
    assert result.margin_m[("versine_10m", "lateral")] == pytest.approx(3 * 0.6e-3 * np.sqrt(0.5))

    def unlisted_on_the_truth(outcome):
        after = assess(moved(true, outcome.lift_m, outcome.slew_m), profile, not_assessed=uncertainty.masks())
        listed = [(s.station_from_m, s.station_to_m) for s in (*outcome.cannot_pass, *outcome.uncertain)]
        return [e for e in after.exceedances if not any(a - 5.0 <= e.station_from_m <= b + 5.0 for a, b in listed)]

    assert len(result.before.exceedances) > 5
    assert unlisted_on_the_truth(result) == []
    # the fixed margin alone (what the re-design held before it took the survey's accuracy)
    unaware = redesign(measured, profile, RedesignSettings(), not_assessed=uncertainty.masks())
    assert unlisted_on_the_truth(unaware)
