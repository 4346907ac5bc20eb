"""Line sections: two overlapping runs of one track joined into one result on the stationing
(continuous numbering, each row's source, the overlap's differences), its workbook and PDF."""

import subprocess
import tomllib
from dataclasses import replace

import numpy as np
import pytest
from report_support import synthetic_table

from insrail.cli.main import main
from insrail.project.model import (
    ProjectError,
    SectionEntry,
    SurveyEntry,
    project_from_settings,
    save_project,
)
from insrail.project.results import (
    EXCEEDANCES_FILE,
    QUALITY_HEADER,
    RESULTS_FOLDER,
    SLEEPERS_FILE,
    SUMMARY_FILE,
    exceedances_csv,
    load_results,
    sleepers_csv,
    summary_toml,
    write_results,
)
from insrail.track.adjustment import load_fastener_type, reassess
from insrail.track.exceedance import SleeperGeometry, assess
from insrail.track.tolerance import load_tolerance_profile

NOISE_M = 0.05e-3  # run-to-run noise of the deviations
SIGMA_LAG5_MM = {"run1": 0.10, "run2": 0.20}  # run1 predicted better


def write_run(root, name, table, rows, rng, lag5_mm):
    sub = replace(table, **{k: getattr(table, k)[rows] for k in (
        "number", "station_m", "time_s", "detected", "centre_enh_m", "left_rail_enh_m", "right_rail_enh_m",
        "gauge_m", "cant_m", "design_cant_m", "lateral_deviation_m", "vertical_deviation_m", "sigma_pos_ned_m",
        "sigma_roll_rad", "valid")}, label=tuple(np.array(table.label, dtype=object)[rows]))
    sub = replace(sub, number=np.arange(1, len(sub.station_m) + 1),  # each run numbers from 1
                  lateral_deviation_m=sub.lateral_deviation_m + rng.normal(0, NOISE_M, sub.lateral_deviation_m.shape),
                  vertical_deviation_m=sub.vertical_deviation_m + rng.normal(0, NOISE_M, sub.vertical_deviation_m.shape))
    profile = load_tolerance_profile("cn_hsr_ballastless")
    geometry = SleeperGeometry.from_arrays(sub.station_m, sub.lateral_deviation_m, sub.vertical_deviation_m, sub.gauge_m,
                                           sub.cant_m, sub.design_cant_m, valid=sub.valid, sleeper_number=sub.number)
    assessment = assess(geometry, profile)
    # the runs' own amounts are not used by the join (it adjusts the joined table again): zero amounts,
    # which spare the fixture two optimisations
    zero = np.zeros_like(sub.lateral_deviation_m)
    adjustment = reassess(geometry, zero, zero, profile, load_fastener_type("wj8"))[1]
    summary = {"survey": {"name": name, "folder": f"surveys/{name}", "imu_epochs": 1000, "gps_week": 2380},
               "heights": {"model": "none (ellipsoidal heights)"},
               "track": {"design": "", "sleepers": len(sub.station_m)},
               "assessment": {"tolerance_profile": profile.name, "exceedances": len(assessment.exceedances),
                              "by_check": {}},
               "quality": {"pass": "smoothed"}, "notices": [{"stage": "imu", "message": f"{name}: a notice"}]}
    start = np.arange(sub.station_m[0], sub.station_m[-1], 200.0)
    # every check resolved by the figures (three 1-sigma within its limit: the 1 mm cross-level's 0.3 mm), as the
    # runs' own assessment above has it; test_a_check_a_run_cannot_assess_is_not_assessed_in_the_section: one not
    quality = "\n".join([",".join(QUALITY_HEADER)] + [
        f"{s:.3f},{s + 200:.3f},3.000,3.000,{lag5_mm:.3f},{lag5_mm:.3f},1.000,1.000,0.300,5.000" for s in start]) + "\n"
    write_results(root / RESULTS_FOLDER, name, {
        SLEEPERS_FILE: sleepers_csv(sub, assessment, adjustment), EXCEEDANCES_FILE: exceedances_csv(assessment),
        "quality.csv": quality, SUMMARY_FILE: summary_toml(summary)})
    (root / "surveys" / name).mkdir(parents=True, exist_ok=True)
    (root / "surveys" / name / "survey.toml").touch()


@pytest.fixture(scope="module")
def project(tmp_path_factory):
    from report_support import CRS

    from insrail.geodesy.crs import EngineeringCRS
    from insrail.project.model import HeightSettings, Project

    root = tmp_path_factory.mktemp("section")
    table = synthetic_table(1100)
    rng = np.random.default_rng(8)
    write_run(root, "run2", table, slice(500, 1100), rng, SIGMA_LAG5_MM["run2"])  # 312 m of overlap: rows 500-799
    write_run(root, "run1", table, slice(0, 800), rng, SIGMA_LAG5_MM["run1"])
    project = Project(folder=root, name="Line", crs=EngineeringCRS.from_settings(CRS, "geodesy.crs"),
                      height=HeightSettings(), surveys=(SurveyEntry("run1", "surveys/run1"),
                                                        SurveyEntry("run2", "surveys/run2")),
                      start_station_m=1000.0, sections=(SectionEntry("km1", ("run2", "run1")),))
    save_project(project)
    return project, table


@pytest.fixture
def amounts_not_optimised(monkeypatch):
    """A join's adjustment amounts all zero, for a test that reads the joined table and its checks (computed before
    the adjustment), not its amounts: each optimisation of the joined 1100 sleepers is some 15 s of CPU, and
    test_the_joined_table_is_each_runs_outside_the_overlap_and_numbered_continuously checks the join's adjustment."""
    from insrail.project import section

    def zero_amounts(geometry, *args, **kwargs):
        return np.zeros_like(geometry.lateral_deviation_m), np.zeros_like(geometry.vertical_deviation_m)

    monkeypatch.setattr(section, "optimise_amounts", zero_amounts)


def test_the_joined_table_is_each_runs_outside_the_overlap_and_numbered_continuously(project, capsys):
    project, table = project
    assert main(["section", str(project.folder)]) == 0
    out = capsys.readouterr().out
    assert "section km1: 1100 sleepers from run1, run2" in out and "overlap run1/run2" in out
    joined = load_results(project.folder, "km1")
    run1, run2 = load_results(project.folder, "run1"), load_results(project.folder, "run2")
    c = joined.columns
    np.testing.assert_array_equal(joined.number, np.arange(1, 1101))
    np.testing.assert_allclose(c["station_m"], table.station_m, atol=5e-5)
    # outside the overlap the rows are the runs' own; in it run1 (better predicted) is taken, except where the track
    # is (coordinates, deviations): those go over from run1 to run2 along a half cosine, without a step, across
    # the overlap and, it being shorter, across 4 x the profile's longest chord (300 m) centred on it, each run's
    # rows there moved by their share of the runs' difference held at its end values
    for name in ("gauge_mm", "cant_mm"):
        np.testing.assert_array_equal(c[name][:500], run1.columns[name][:500], err_msg=name)
        np.testing.assert_array_equal(c[name][800:], run2.columns[name][300:], err_msg=name)
    np.testing.assert_array_equal(c["gauge_mm"][500:800], run1.columns["gauge_mm"][500:])
    station = c["station_m"]
    both = (run1.columns["valid"][500:] > 0) & (run2.columns["valid"][:300] > 0)
    centre = 0.5 * (station[500:800][both][0] + station[500:800][both][-1])
    along = np.clip((station - (centre - 600.0)) / 1200.0, 0.0, 1.0)
    share = 0.5 * (1 - np.cos(np.pi * along))  # a half cosine: no kink where the taper begins or ends
    assert 0.0 < share[0] and share[-1] < 1.0  # the section (687 m) lies inside the taper
    for name in ("lateral_deviation_left_mm", "vertical_deviation_right_mm", "left_E_m"):
        difference = np.interp(station, station[500:800][both],
                               run2.columns[name][:300][both] - run1.columns[name][500:][both])
        first = np.r_[run1.columns[name], run2.columns[name][300:]]
        expected = np.where(np.arange(1100) < 800, first + share * difference, first - (1 - share) * difference)
        expected[500:800] = np.where(both | (run1.columns["valid"][500:] > 0), expected[500:800],
                                     run2.columns[name][:300] - (1 - share[500:800]) * difference[500:800])
        np.testing.assert_allclose(c[name], expected, rtol=0, atol=1e-3 if name.endswith("_mm") else 1e-6,
                                   err_msg=name)
        assert np.nanmax(np.abs(np.diff(c[name]))) < np.nanmax(np.abs(np.diff(first))) + 1e-9  # no step at the seam
    np.testing.assert_array_equal(c["source_run1"], np.r_[np.ones(800), np.zeros(300)])
    np.testing.assert_array_equal(c["source_run2"], np.r_[np.zeros(800), np.ones(300)])
    summary = tomllib.loads((joined.folder / "summary.toml").read_text())
    (overlap,) = summary["section"]["overlaps"]
    assert overlap["runs"] == ["run1", "run2"] and overlap["sleepers"] > 250
    deviation = overlap["parameters"]["lateral_deviation_left_mm"]
    assert deviation["std_mm"] == pytest.approx(np.sqrt(2) * NOISE_M * 1e3, rel=0.25)  # the noise of two runs
    assert deviation["predicted_sigma_mm"] == pytest.approx(np.hypot(3.0, 3.0), abs=1e-4) and not deviation["exceeds"]
    short_wave = overlap["parameters"]["check_short_wave_30m_5m_left_lateral_mm"]
    assert short_wave["std_mm"] < 0.3 and not short_wave["exceeds"]
    # the worst-over-placements checks by magnitude, not within a chord of the overlap's ends (where one
    # run's value is the worst of fewer placements); the 312 m overlap is too short for the 300 m chord
    assert short_wave["compared"] == "magnitude" and overlap["parameters"]["gauge_mm"]["compared"] == "signed"
    assert short_wave["count"] == pytest.approx(overlap["sleepers"] - 2 * 30 / 0.625, abs=2)
    assert "check_long_wave_300m_150m_left_lateral_mm" not in overlap["parameters"]
    assert not [n for n in summary["notices"] if n["stage"] == "section"]
    assert {"run1: a notice", "run2: a notice"} <= {n["message"] for n in summary["notices"]}
    # the joined table's adjustment re-assessed as a survey's is
    adjustment = summary["adjustment"]
    assert adjustment["strategy"] == "least_movement" and adjustment["sleepers_to_work_on"] > 0
    assert adjustment["after"]["by_check_before"] == summary["assessment"]["by_check"]
    assert 0 < adjustment["after"]["exceedances"] < sum(summary["assessment"]["by_check"].values())
    assert adjustment["unresolved_sleepers"] > 0  # what still fails is flagged with its reason
    assert sum(adjustment["unresolved_reasons"].values()) >= adjustment["unresolved_sleepers"]
    # one workbook and one PDF, the PDF with the section page
    pdf = project.folder / "reports" / "track_geometry_km1.pdf"
    assert pdf.is_file() and (project.folder / "reports" / "track_geometry_km1.xlsx").is_file()
    text = subprocess.run(["pdftotext", str(pdf), "-"], capture_output=True, text=True, check=True).stdout
    assert "Line section: joined runs" in text and "Overlap run2 - run1" in text
    assert "After adjustment: " in " ".join(text.split())
    # the exports take the section like a survey
    assert main(["export", str(project.folder), "--section", "km1", "--format", "lift-lining",
                 "--out", str(project.folder / "km1.csv")]) == 0
    assert len((project.folder / "km1.csv").read_text().splitlines()) == 9 + 1100  # the layout-2 header lines


def test_weighted_mean_in_the_overlap(project, capsys, amounts_not_optimised):
    project, _ = project
    mean = replace(project, sections=(SectionEntry("km1m", ("run1", "run2"), overlap="mean"),))
    save_project(mean)
    try:
        assert main(["section", str(project.folder), "--no-reports"]) == 0
        capsys.readouterr()
        c = load_results(project.folder, "km1m").columns
        run1, run2 = load_results(project.folder, "run1").columns, load_results(project.folder, "run2").columns
        share = 0.1**-2 / (0.1**-2 + 0.2**-2)  # weights 1/sigma^2 of the 5 m lag figures
        both = slice(500, 800)
        np.testing.assert_allclose(c["source_run1"][both], share)
        expected = share * run1["gauge_mm"][both] + (1 - share) * run2["gauge_mm"][:300]
        np.testing.assert_allclose(c["gauge_mm"][both], expected, atol=1e-3)
        np.testing.assert_array_equal(c["source_run1"][:500], 1.0)
    finally:
        save_project(project)


def test_two_runs_a_few_millimetres_apart_join_without_a_step(project, tmp_path, capsys, amounts_not_optimised):
    """Runs of one track differ by their absolute error (a few mm, within their stated accuracy): the joined
    track goes from one to the other across the overlap, so no chord check reads the difference as a step of
    the track (row by row it was one: false 10 m and 30 m / 5 m exceedances at the seam)."""
    import shutil

    project, _ = project
    joins = {}
    for apart_mm in (8.0, 0.0):  # run2 8 mm to the side of run1 (its GNSS's error), and the same runs not apart
        apart = tmp_path / f"apart{apart_mm:g}"
        shutil.copytree(project.folder, apart)
        for run, offset_mm, invalid in (("run2", apart_mm, range(100, 106)), ("run1", 0.0, range(650, 656))):
            path = apart / "results" / run / "sleepers.csv"
            lines = path.read_text().splitlines()
            header = lines[0].split(",")
            shifted = [header.index(k) for k in ("lateral_deviation_left_mm", "lateral_deviation_right_mm")]
            rows = []
            for row, line in enumerate(lines[1:]):
                cells = line.split(",")
                for k in shifted if offset_mm and cells[shifted[0]] else ():
                    cells[k] = f"{float(cells[k]) + offset_mm:.3f}"
                if row in invalid:  # a few sleepers of each run not valid inside the overlap
                    cells[header.index("valid")] = "0"
                rows.append(",".join(cells))
            path.write_text("\n".join([lines[0], *rows]) + "\n")
        assert main(["section", str(apart), "--no-reports"]) == 0
        capsys.readouterr()
        joins[apart_mm] = load_results(apart, "km1").columns
    joined, original = joins[8.0], joins[0.0]
    moved = joined["lateral_deviation_left_mm"] - original["lateral_deviation_left_mm"]
    # the 8 mm go over along a half cosine 1200 m long (4 x the 300 m chord) centred on the overlap (rows 500-799)
    station = original["station_m"]
    along = np.clip((station - 0.5 * (station[500] + station[799]) + 600.0) / 1200.0, 0.0, 1.0)
    known = np.isfinite(moved)  # the deviation is not known at every sleeper of the synthetic runs
    assert known.mean() > 0.9
    np.testing.assert_allclose(moved[known], 8.0 * 0.5 * (1 - np.cos(np.pi * along[known])), atol=0.25)
    # at most 0.02 mm from one sleeper to the next, never a step (not where one run's sleepers are not valid
    # either; there the other run's noise, 0.07 mm, is in the comparison)
    assert np.nanmax(np.abs(np.diff(moved))) < 0.25
    for check, most_mm in (("check_versine_10m_left_lateral_mm", 0.1), ("check_short_wave_30m_5m_left_lateral_mm", 0.8),
                           ("check_long_wave_300m_150m_left_lateral_mm", 1.0)):
        # the 300 m / 150 m check by magnitude: its value is the largest over 480 placements of its chord, so its
        # sign may go over to another placement's when two magnitudes are close
        change = (np.abs(joined[check]) - np.abs(original[check]) if "long_wave" in check
                  else joined[check] - original[check])
        difference = np.nanmax(np.abs(change))
        # the checks see the track, not the runs' difference (row by row, 8 mm at the seam; spread over the
        # overlap alone, 187 m, the 300 m / 150 m check read several millimetres of it)
        assert difference < most_mm, (check, difference)


def test_runs_that_disagree_are_a_notice(project, tmp_path, capsys, amounts_not_optimised):
    project, _ = project
    shifted = tmp_path / "p"
    import shutil

    shutil.copytree(project.folder, shifted)
    # both runs claim 0.01 mm accuracy of position: their 0.07 mm difference is then beyond belief
    for run in ("run1", "run2"):
        path = shifted / "results" / run / "quality.csv"
        lines = path.read_text().splitlines()
        path.write_text("\n".join([lines[0]] + [",".join(line.split(",")[:2] + ["0.010", "0.010"] + line.split(",")[4:])
                                                for line in lines[1:]]) + "\n")
    assert main(["section", str(shifted), "--no-reports"]) == 0
    out = capsys.readouterr().out
    assert "warning: runs run1 and run2 differ by" in out and "lateral_deviation_left_mm" in out
    summary = load_results(shifted, "km1").summary
    assert any(n["stage"] == "section" and "more than 3 x the predicted 0.01 mm" in n["message"]
               for n in summary["notices"])


def test_a_check_a_run_cannot_assess_is_not_assessed_in_the_section(project, tmp_path, capsys, monkeypatch):
    """A run whose stated accuracy cannot resolve a check (a noisy survey) leaves it out (insrail.project.assessable):
    the section joining it leaves it out too, wherever a row holds that run's values, and its adjustment does not
    hold it there (the section assessed it anyway: exceedances and amounts from a survey's noise). The section's
    warning names the run and stands for the run's own: each said once, the run's other warnings kept."""
    import shutil

    from insrail.notices import Notice, Phrase
    from insrail.project import assessable, relative_survey, section
    from insrail.project.redesign import section_quality

    project, _ = project
    noisy = tmp_path / "p"
    shutil.copytree(project.folder, noisy)
    # run2's first 200 m (1312.5-1512.5 m, its overlap with run1 and 12.5 m beyond it): a 1 mm 5 m lag figure across
    # the track, where the 2 mm 30 m / 5 m and 10 m versine checks ask for 0.67 mm (three 1-sigma within the limit)
    path = noisy / "results" / "run2" / "quality.csv"
    header, first, *rest = path.read_text().splitlines()
    cells = first.split(",")
    cells[header.split(",").index("sigma_lag5_lateral_mm")] = "1.000"
    path.write_text("\n".join([header, ",".join(cells), *rest]) + "\n")
    run2 = load_results(noisy, "run2")  # its own warnings, as processing with that quality.csv writes them
    found = assessable.not_assessable(load_tolerance_profile("cn_hsr_ballastless"), section_quality(run2.quality),
                                      run2.columns["station_m"])
    # and the warning a relative survey gives for its own sections (insrail.project.relative_survey), as one would
    relative = Notice("track", relative_survey.NOTICE, station_m=1312.5, fields={
        "check": "short_wave_30m_5m", "count": 1, "sections": 4, "sigmas": 3, "limit_mm": 2.0,
        "where": [Phrase("{from_m:.0f}-{to_m:.0f} m ({sigma_mm:.2f} mm)", {"from_m": 1312.5, "to_m": 1512.5,
                                                                           "sigma_mm": 1.0})]})
    (noisy / "results" / "run2" / "summary.toml").write_bytes(summary_toml(run2.summary | {"notices": [
        *run2.summary["notices"], *(n.to_dict() for n in assessable.notices(found, [0] * len(found))),
        relative.to_dict()]}))
    assert sum("not assessable" in n["message"] for n in load_results(noisy, "run2").summary["notices"]) == 2
    assert sum("cannot be assessed" in n["message"] for n in load_results(noisy, "run2").summary["notices"]) == 1
    save_project(replace(project, folder=noisy, sections=(SectionEntry("km1", ("run2", "run1")),
                                                          SectionEntry("km1m", ("run1", "run2"), overlap="mean"))))
    held = {}

    def no_amounts(geometry, *args, not_assessed=None, **kwargs):  # what the adjustment was told not to hold
        held[len(held)] = not_assessed
        return np.zeros_like(geometry.lateral_deviation_m), np.zeros_like(geometry.vertical_deviation_m)

    monkeypatch.setattr(section, "optimise_amounts", no_amounts)
    assert main(["section", str(noisy), "--no-reports"]) == 0
    out = capsys.readouterr().out
    assert "short_wave_30m_5m lateral: not assessable at the stated 1-sigma 1.00 mm" in out
    for name, not_assessed in zip(("km1", "km1m"), held.values()):
        joined = load_results(noisy, name)
        c, station = joined.columns, joined.columns["station_m"]
        # the rows holding run2's values there: its own, and the overlap's, whichever run the rule takes (with "best"
        # run1's, but the rails' positions go over to run2's there row by row; in a mean both runs')
        left_out = (station > 1312.4) & (station < 1512.4)
        np.testing.assert_array_equal(np.flatnonzero(left_out), np.arange(500, 820))
        if name == "km1":
            assert (c["source_run1"][500:800] == 1.0).all()
        flagged = {(n["check"], n["direction"]): n for n in joined.summary["assessment"]["not_assessable"]}
        assert set(flagged) == {("versine_10m", "lateral"), ("short_wave_30m_5m", "lateral")}, name
        short_wave = flagged[("short_wave_30m_5m", "lateral")]
        assert short_wave["sleepers"] == 320 and short_wave["sigma_mm"] == 1.0 and short_wave["limit_mm"] == 2.0
        assert short_wave["stretches_m"] == [[1312.5, 1511.875]]
        assert short_wave["exceedances_not_listed"] > 0  # the alignment defect at 1312.5 m: the noisy run cannot tell
        for rail in ("left", "right"):
            values = c[f"check_short_wave_30m_5m_{rail}_lateral_mm"]
            assert np.isnan(values[left_out]).all() and np.isfinite(values[~left_out]).sum() > 600
            assert np.isfinite(c[f"check_short_wave_30m_5m_{rail}_vertical_mm"][left_out]).any()  # resolved: assessed
        assert np.isfinite(c["check_gauge_mm"][left_out]).all()  # no stated figure: the gauge is assessed as before
        assert not any(e.check == "short_wave_30m_5m" and e.direction == "lateral"
                       and 1312.4 < e.station_from_m < 1512.4 for e in joined.exceedances)
        np.testing.assert_array_equal(not_assessed[("short_wave_30m_5m", "lateral")], left_out)  # not held there
        said = [n["message"] for n in joined.summary["notices"]]
        warned = [m for m in said if "not assessable" in m]
        assert len(warned) == 2 and sum(m.startswith("short_wave_30m_5m lateral: not assessable") for m in warned) == 1
        assert all(" over 1312-1512 m (run2): 320 sleepers not assessed" in m for m in warned), warned
        assert {"run1: a notice", "run2: a notice"} <= set(said)  # the runs' other warnings: kept
        assert not any("cannot be assessed" in m for m in said)  # the section's own warning says it for its rows
        assert short_wave["surveys"] == [["run2"]]
        # the sleepers' own reasons are the runs' (a check left out is an empty value of it, as in a run's file)
        assert set(joined.not_assessed) == set(load_results(noisy, "run1").not_assessed)


def test_a_run_without_a_valid_sleeper_is_refused_naming_the_section_once(project, tmp_path, capsys):
    project, _ = project
    spoilt = tmp_path / "p"
    import shutil

    shutil.copytree(project.folder, spoilt)
    path = spoilt / "results" / "run2" / "sleepers.csv"
    header, *rows = path.read_text().splitlines()
    valid = header.split(",").index("valid")
    path.write_text("\n".join([header] + [",".join(v if i != valid else "0" for i, v in enumerate(row.split(",")))
                                          for row in rows]) + "\n")
    assert main(["section", str(spoilt), "--no-reports"]) == 1
    err = capsys.readouterr().err
    refusal = [line for line in err.splitlines() if line.startswith("insrail:")]
    assert refusal == ["insrail: section km1: survey run2 has no valid sleeper"], err
    assert "done" not in err  # the progress of a join that failed does not end in "100 %  done"


def test_section_settings_are_checked(tmp_path):
    for name in ("a", "b"):
        (tmp_path / name).mkdir()
        (tmp_path / name / "survey.toml").touch()
    base = {"geodesy": {"crs": {"central_meridian_deg": 117.0}}, "track": {"start_station_m": 0.0},
            "surveys": [{"name": "a", "folder": "a"}, {"name": "b", "folder": "b"}]}
    ok = project_from_settings(base | {"sections": [{"name": "s", "surveys": ["a", "b"], "from_m": 0.0, "to_m": 9.0}]},
                               tmp_path)
    assert ok.sections == (SectionEntry("s", ("a", "b"), 0.0, 9.0, "best"),)
    assert project_from_settings(ok.to_settings(), tmp_path).sections == ok.sections
    with pytest.raises(ProjectError) as error:
        project_from_settings(base | {"sections": [{"name": "a", "surveys": ["a"]},
                                                   {"name": "t", "surveys": ["a", "c"], "overlap": "avg"},
                                                   {"name": "u", "surveys": ["a"], "from_m": 5.0, "to_m": 1.0}]}, tmp_path)
    text = str(error.value)
    assert "sections[0].name: 'a' is already the name of a survey" in text
    assert "sections[1].surveys: no survey named 'c'" in text and "sections[1].overlap: expected one of best, mean" in text
    assert "sections[2]: from_m (5.0) must be below to_m (1.0)" in text


def test_a_section_of_unprocessed_surveys_fails_clearly(project, tmp_path, capsys):
    project, _ = project
    bare = tmp_path / "bare"
    for name in ("run1", "run2"):
        (bare / "surveys" / name).mkdir(parents=True)
        (bare / "surveys" / name / "survey.toml").touch()
    save_project(replace(project, folder=bare))
    assert main(["section", str(bare)]) == 1
    err = capsys.readouterr().err
    assert "no results for survey" in err and "Traceback" not in err
    assert main(["section", str(bare), "--section", "nope"]) == 1
    assert "no section named nope" in capsys.readouterr().err


@pytest.mark.slow
def test_two_simulated_runs_of_one_track_joined(tmp_path, capsys):
    """End to end on the simulator: the `short` preset cut into two runs with 200 m of overlap over one
    track (same track seed, own noise seeds), processed and joined (benchmarks/section_join.py does the
    `long` preset with 500 m)."""
    from insrail.project import load_project, process
    from insrail.project.demo import project_for_simulated_survey
    from insrail.sim.scenario import preset
    from insrail.sim.simulate import simulate

    for name, start, end, seed in (("run1", 1050.0, 1750.0, 1), ("run2", 1550.0, 2250.0, 2)):
        config = preset("short")
        stops = tuple(s for s in config.motion.stops if start + 50 < s[0] < end - 50)
        config = replace(config, motion=replace(config.motion, start_station_m=start, end_station_m=end, stops=stops),
                         gnss=replace(config.gnss, outages=()))  # the preset's outage would fall in one run's overlap
        simulate(config, seed=seed, out_dir=tmp_path / "surveys" / name, imu_format="npy", track_seed=5)
    project = project_for_simulated_survey(tmp_path, tmp_path / "surveys" / "run1")
    project = replace(project, surveys=(SurveyEntry("run1", "surveys/run1"), SurveyEntry("run2", "surveys/run2")),
                      sections=(SectionEntry("line", ("run1", "run2")),))
    save_project(project)
    project = load_project(tmp_path)
    for name in ("run1", "run2"):
        process(project, name)
    assert main(["section", str(tmp_path)]) == 0
    capsys.readouterr()
    joined = load_results(tmp_path, "line")
    np.testing.assert_array_equal(np.diff(joined.number), 1)
    (overlap,) = joined.summary["section"]["overlaps"]
    assert overlap["to_m"] - overlap["from_m"] > 150
    for name, values in overlap["parameters"].items():
        if "30m_5m" in name:
            assert values["std_mm"] <= 0.3, name
    run1 = load_results(tmp_path, "run1")
    alone = joined.columns["station_m"] < overlap["from_m"] - 1.0
    np.testing.assert_array_equal(joined.columns["gauge_mm"][alone], run1.columns["gauge_mm"][:alone.sum()])
