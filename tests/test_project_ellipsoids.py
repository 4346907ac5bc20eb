"""Every ellipsoid the project offers goes through every stage (issue 32), and the reports state the
settings the results were processed with, not today's project.toml (issue 34, "resolve once, record
once"). One simulated `short` survey, processed once on Xian80 through the CLI as a user would."""

import re
import shutil
import subprocess
import tomllib

import pytest

from insrail.cli.main import main
from insrail.geodesy.ellipsoid import ELLIPSOIDS, Ellipsoid
from insrail.io.survey import read_manifest
from insrail.project import load_project
from insrail.project.demo import project_for_simulated_survey
from insrail.project.run_settings import NOT_RECORDED, RecordedSettings, resolve_run_settings


def _edit(path, old: str, new: str) -> None:
    text = path.read_text(encoding="utf-8")
    assert re.search(old, text, flags=re.M), old
    path.write_text(re.sub(old, new, text, flags=re.M), encoding="utf-8")


def _user_project(short_nav_survey, root, crs_lines: str):
    """The simulated survey's project with [geodesy.crs] ellipsoid lines replaced as a user edits
    project.toml; the design (in the simulation's CGCS2000 grid) is dropped for a start station."""
    shutil.copytree(short_nav_survey, root / "surveys" / "short")
    project_for_simulated_survey(root, root / "surveys" / "short")
    toml = root / "project.toml"
    _edit(toml, r'^ellipsoid = "CGCS2000"$', crs_lines)
    _edit(toml, r"^design = .*$", "start_station_m = 0.0")
    return toml


def _pdf_text(path) -> str:
    return subprocess.run(["pdftotext", str(path), "-"], capture_output=True, check=True,
                          text=True).stdout


@pytest.fixture(scope="module")
def xian80(short_nav_survey, tmp_path_factory):
    root = tmp_path_factory.mktemp("xian80")
    _user_project(short_nav_survey, root, 'ellipsoid = "Xian80"')
    assert main(["process", str(root)]) == 0  # main: ValueError "unknown ellipsoid 'Xian80'" in the track stage
    return root


def test_a_survey_on_xian80_is_processed_and_reported_with_its_ellipsoid(xian80, capsys):
    summary = tomllib.loads((xian80 / "results" / "short" / "summary.toml").read_text(encoding="utf-8"))
    settings = summary["settings"]
    assert settings["ellipsoid"] == {"name": "Xian80", "a_m": 6378140.0, "inverse_flattening": 298.257}
    assert settings["crs"]["ellipsoid"] == "Xian80" and "TM Xian80 CM 114.3°" in settings["crs_text"]
    assert summary["track"]["valid_sleepers"] > 0.9 * summary["track"]["sleepers"]
    assert not [n for n in summary["notices"] if n["stage"] == "geodesy"]  # Xian80: 0.5 ppm, below the notice
    assert main(["report", str(xian80)]) == 0
    text = _pdf_text(xian80 / "reports" / "track_geometry_short.pdf")
    assert "Transverse Mercator on Xian80 (a = 6378140.000 m" in text
    assert "changed since processing" not in text


def test_the_report_states_the_crs_processed_with_after_the_project_changed(xian80, capsys):
    """Change the central meridian after processing: the report prints the CRS the results are in
    (114.3°) and says the project now states another one; the CLI warns too."""
    toml = xian80 / "project.toml"
    original = toml.read_text(encoding="utf-8")
    try:
        _edit(toml, r"^central_meridian_deg = 114.3$", "central_meridian_deg = 114.5")
        capsys.readouterr()
        assert main(["report", str(xian80)]) == 0
        err = capsys.readouterr().err
        assert "coordinate system: processed with TM Xian80 CM 114.3°" in err
        assert "the project now says TM Xian80 CM 114.5°" in err and "process again" in err
        text = " ".join(_pdf_text(xian80 / "reports" / "track_geometry_short.pdf").split())
        assert "central meridian 114.3°" in text and "central meridian 114.5°" not in text
        assert "The project has changed since processing" in text
        assert "CM 114.5°" in text  # named in the warning
        capsys.readouterr()
        out = xian80 / "lines.csv"
        assert main(["export", str(xian80), "--format", "lift-lining", "--out", str(out)]) == 0
        assert "crs = TM Xian80 CM 114.3°" in out.read_text(encoding="utf-8")
        assert "the project now says TM Xian80 CM 114.5°" in capsys.readouterr().err
    finally:
        toml.write_text(original, encoding="utf-8")


def test_results_processed_before_settings_were_recorded_say_so(xian80, tmp_path, capsys):
    copy = tmp_path / "old"
    shutil.copytree(xian80, copy, ignore=shutil.ignore_patterns(".cache", "reports"))
    summary_path = copy / "results" / "short" / "summary.toml"
    summary = summary_path.read_text(encoding="utf-8")
    summary_path.write_text(summary[:summary.index("[settings")] if "[settings" in summary else summary,
                            encoding="utf-8")
    assert "[settings" not in summary_path.read_text(encoding="utf-8")
    assert RecordedSettings.of({}).missing
    capsys.readouterr()
    assert main(["report", str(copy)]) == 0
    assert NOT_RECORDED in capsys.readouterr().err
    text = " ".join(_pdf_text(copy / "reports" / "track_geometry_short.pdf").split())
    assert "Settings not recorded" in text and "process again" in text


@pytest.mark.parametrize("crs_lines, expected", [
    ('ellipsoid = "Krassovsky"', ELLIPSOIDS["Krassovsky"]),
    ('ellipsoid = "custom"\na_m = 6378160.0\ninverse_flattening = 298.25', Ellipsoid("custom", 6378160.0, 298.25)),
])
def test_every_stage_gets_the_ellipsoid_object_of_the_crs(short_nav_survey, tmp_path, crs_lines, expected):
    """A named or custom ellipsoid in project.toml becomes the one object of the run's settings,
    which the fusion and the track stage take (no name is looked up anywhere after)."""
    _user_project(short_nav_survey, tmp_path, crs_lines)
    project = load_project(tmp_path)
    manifest = read_manifest(tmp_path / "surveys" / "short")
    run = resolve_run_settings(project, manifest)
    assert run.ellipsoid == expected
    assert run.record()["ellipsoid"] == {"name": expected.name, "a_m": expected.a,
                                         "inverse_flattening": expected.inverse_flattening}
    # GNSS baselines computed with WGS84's formulas read 16.9 ppm (3.6 ppm) long in this datum: said
    scale_mm = {"Krassovsky": "+85 mm", "custom": "+18 mm"}[expected.name]
    assert [n.stage for n in run.notices()] == ["geodesy"] and scale_mm in run.notices()[0].message
