"""End to end: a tunnel survey without GNSS and without a design is processed with a valid fitted
alignment (the run ends inside the curve, as the `tunnel-no-gnss` preset's does)."""

from dataclasses import replace

import numpy as np
import pytest

from insrail.cli.main import main
from insrail.io.survey import read_manifest
from insrail.project import process
from insrail.project.demo import project_for_simulated_survey
from insrail.project.model import save_project
from insrail.sim.scenario import preset
from insrail.sim.simulate import simulate
from insrail.track.alignment import Clothoid
from insrail.track.alignment_csv import read_alignment_csv

START_M, END_M = 21320.0, 21800.0
"""480 m of the `long` line: 80 m of straight, the 260 m entry clothoid and 140 m of the R 5500 m arc."""


@pytest.fixture(scope="module")
def tunnel_project(tmp_path_factory):
    config = preset("tunnel-no-gnss")
    fixes = tuple(s for s in config.prism.stations_m if START_M <= s <= END_M)
    config = replace(config, motion=replace(config.motion, start_station_m=START_M, end_station_m=END_M),
                     prism=replace(config.prism, stations_m=fixes))
    root = tmp_path_factory.mktemp("tunnel-project")
    survey = root / "surveys" / "tunnel"
    simulate(config, seed=4, out_dir=survey, imu_format="npy")
    # a survey without GNSS, as a user's: no gnss role and no empty GNSS file (which insrail refuses)
    assert "gnss" not in read_manifest(survey).files and not (survey / "gnss.pos").exists()
    project = replace(project_for_simulated_survey(root, survey, name="tunnel"), design=None, start_station_m=START_M)
    save_project(project)  # as the user's project.toml: no [track] design
    return project


def test_tunnel_without_gnss_and_design_gets_a_valid_fitted_alignment(tunnel_project, capsys):
    results = process(tunnel_project, "tunnel")
    fit = results.reconstruction.fitted
    assert fit is not None, results.summary["track"]["line_fit"]
    line_fit = results.summary["track"]["line_fit"]
    assert line_fit["fitted"] and line_fit["plan_rms_mm"] < 3.0
    assert not [n for n in results.summary["notices"] if "line-type fit" in n["message"]]
    plan = fit.alignment.horizontal
    assert isinstance(plan.elements[1], Clothoid)
    # the written design reads back (its validator accepts it) and holds the truth's transition
    written = read_alignment_csv(results.folder / "fitted_alignment.csv").horizontal
    assert [type(e) for e in written.elements] == [type(e) for e in plan.elements]
    truth = read_alignment_csv(tunnel_project.resolve("surveys/tunnel/truth/design.csv")).horizontal
    assert abs(plan.elements[1].length_m - 260.0) < 10.0
    assert abs(plan.elements[1].radius_end_m / 5500.0 - 1.0) < 0.05
    assert truth.elements[2].radius_m == 5500.0
    lateral = results.table.lateral_deviation_m[results.table.valid]
    assert np.isfinite(lateral).all()


def test_a_failing_line_fit_keeps_the_fusion_and_warns_where(tunnel_project, monkeypatch, capsys):
    """A fit that fails (here: refused outright) leaves the cached fusion and the rest of the results
    in place and says over which stations there is no fit, in summary.toml and the process output."""
    from insrail.track import sleeper_table

    def refuse(*args, **kwargs):
        raise ValueError("no alignment through these points")

    process(tunnel_project, "tunnel")  # the fusion cached
    for entry in (tunnel_project.folder / "results" / ".cache").glob("track-*"):
        entry.unlink()
    monkeypatch.setattr(sleeper_table, "fit_alignment", refuse)
    results = process(tunnel_project, "tunnel")
    assert results.fusion_from_cache and results.reconstruction.fitted is None
    (notice,) = [n for n in results.summary["notices"] if "line-type fit" in n["message"]]
    assert "no alignment through these points" in notice["message"]
    assert "over stations" in notice["message"] and notice["station_m"] == pytest.approx(START_M, abs=5.0)
    for entry in (tunnel_project.folder / "results" / ".cache").glob("track-*"):
        entry.unlink()
    main(["process", str(tunnel_project.folder)])
    assert "line-type fit" in capsys.readouterr().out
