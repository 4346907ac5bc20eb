"""A project whose survey holds raw GNSS observations (simulated RINEX) instead of a solution:
`insrail process` runs PPK as a cached stage, writes gnss.pos and gnss_qc.toml, and the fused
trajectory agrees with the simulator's truth; the base point comes from the project; bad input
is refused naming the file or key."""

import shutil
import threading
import tomllib
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from real_data import REAL
from track_truth import expected_deviations

from insrail.cli.main import main
from insrail.cli.process import describe
from insrail.gnss import gnss_qc
from insrail.io.errors import InputError, ManifestError
from insrail.io.rinex import RinexObsHeader, write_rinex2_obs
from insrail.io.survey import read_manifest, read_survey, write_manifest
from insrail.io.survey_gnss import RawGnss
from insrail.io.types import GnssSolution
from insrail.nav.fusion import FusionOptions
from insrail.progress import Cancelled
from insrail.project import (
    ProjectError,
    load_project,
    load_results,
    process,
    project_from_settings,
    save_project,
)
from insrail.project.control_points import ControlPoint, resolve_control_point
from insrail.project.demo import project_for_simulated_survey
from insrail.project.gnss_stage import GnssStageResult, run_gnss_stage
from insrail.project.pipeline import fit_heights
from insrail.sim.evaluation import trajectory_errors
from insrail.sim.gnss_obs import convert_survey_to_raw_gnss
from insrail.sim.scenario import preset
from insrail.sim.simulate import simulate
from insrail.sim.truth import read_nav_truth, read_sleeper_truth

NAV = REAL / "rinex_0759_3040" / "07590920.05n"


def scenario():
    """`short` cut to 200 m with a 60 s static start, on 2005-04-02 11:00 GPST (the navigation
    file's day), with a 20 s GNSS outage: about 4.5 minutes."""
    config = preset("short", gps_week=1316, start_time_s=558000.0025)
    motion = replace(config.motion, end_station_m=1250.0, static_start_s=60.0, static_end_s=30.0, stops=())
    return replace(config, motion=motion, gnss=replace(config.gnss, outages=((1150.0, 20.0),)))


@pytest.fixture(scope="module")
def raw_survey(tmp_path_factory):
    """A simulated survey with rover/base RINEX instead of gnss.pos, and its project (not processed)."""
    root = tmp_path_factory.mktemp("raw_gnss")
    folder = root / "surveys" / "short"
    config = scenario()
    simulate(config, seed=3, out_dir=folder)
    raw = convert_survey_to_raw_gnss(folder, config, NAV, seed=4)
    project = project_for_simulated_survey(root, folder)
    project = replace(project, control_points=(ControlPoint(raw.base_point, engineering=raw.base_enh_m),))
    save_project(project)
    return root, raw


@pytest.fixture(scope="module")
def processed(raw_survey):
    root, raw = raw_survey
    assert main(["process", str(root)]) == 0
    project = load_project(root)
    return root, raw, project


def test_survey_manifest_holds_raw_gnss(raw_survey):
    root, raw = raw_survey
    manifest = read_manifest(root / "surveys" / "short")
    assert "gnss" not in manifest.files and not (root / "surveys" / "short" / "gnss.pos").exists()
    assert manifest.raw_gnss.rover == "rover.obs" and manifest.raw_gnss.base == "base.obs"
    assert manifest.raw_gnss.navigation == (NAV.name,) and manifest.raw_gnss.base_point == raw.base_point
    assert manifest.raw_gnss.base_antenna_height_m == 1.55
    with pytest.raises(InputError, match="gnss_raw: the survey holds raw GNSS observations"):
        read_survey(root / "surveys" / "short")


def test_process_runs_ppk_and_matches_the_truth(processed):
    root, raw, project = processed
    folder = root / "results" / "short"
    assert {"gnss.pos", "gnss_qc.toml", "trajectory.npy", "summary.toml"} <= {p.name for p in folder.iterdir()}
    summary = tomllib.loads((folder / "summary.toml").read_text())
    gnss = summary["ppk"]
    assert gnss["source"] == "ppk" and not gnss["from_cache"] and gnss["fix_rate"] >= 0.95
    assert gnss["epochs"] == sum(gnss["epochs_by_quality"].values()) == raw.observations.epochs
    assert gnss["fusion_excluded_epochs"] == gnss["epochs_by_quality"].get("single", 0)
    assert gnss["base"]["point"] == raw.base_point and not gnss["base"]["approximate"]
    assert "h = H + zeta" in gnss["base"]["derivation"]
    assert summary["files"]["gnss"] == "gnss.pos"
    lines = describe(load_results(root, "short"))  # what `insrail process` printed
    assert lines[1].startswith("  GNSS (PPK, computed): fix rate") and "base CPII-BASE" in lines[1]
    assert "gnss.pos, gnss_qc.toml" in lines[-1]
    qc = tomllib.loads((folder / "gnss_qc.toml").read_text())
    assert qc["qc"]["fix_rate"] == gnss["fix_rate"] and qc["qc"]["gaps"][0]["duration_s"] == pytest.approx(21.0)
    # The base mark through the CRS and the fitted height anomaly lands on the truth within the fit's
    # error; the mark stands off the line, outside the benchmarks' hull, and the surveyor is told so.
    truth = tomllib.loads((root / "surveys" / "short" / "truth" / "base_point.toml").read_text())
    loo_m = 1e-3 * summary["heights"]["loo_rms_mm"]
    assert gnss["base"]["ellipsoidal_height_m"] == pytest.approx(truth["ellipsoidal_height_m"], abs=3 * loo_m)
    assert gnss["warnings"][0].startswith("control point CPII-BASE: height anomaly extrapolated")
    assert any(line.startswith("  warning: gnss: control point CPII-BASE") for line in lines)
    assert gnss["base"]["lat_deg"] == pytest.approx(truth["lat_deg"], abs=1e-9)
    # The fused trajectory agrees with the truth as in the demo (GNSS-limited, millimetres).
    trajectory = load_results(root, "short").trajectory()
    errors = trajectory_errors(trajectory, read_nav_truth(root / "surveys" / "short" / "truth" / "nav.npy"),
                               project.crs.reference_ellipsoid)
    assert len(trajectory) > 50_000
    assert errors.rms_horizontal_m() < 0.005 and errors.rms_vertical_m() < 0.008
    assert np.abs(errors.ned_m[errors.moving]).max() < 0.015


def test_rerun_reuses_both_caches_and_a_changed_base_refuses(processed, tmp_path):
    root, raw, project = processed
    again = process(project, "short")
    assert again.summary["ppk"]["from_cache"] and again.fusion_from_cache
    before_m = again.trajectory.height_m  # read now: the result folder is replaced by the next run
    # The base antenna measured 3 cm higher: PPK and fusion run again, heights drop by 3 cm.
    folder = root / "surveys" / "short"
    manifest = read_manifest(folder)
    write_manifest(folder, replace(manifest, raw_gnss=replace(manifest.raw_gnss, base_antenna_height_m=1.58)))
    try:
        changed = process(project, "short")
    finally:
        write_manifest(folder, manifest)
    assert not changed.summary["ppk"]["from_cache"] and not changed.fusion_from_cache
    assert np.median(changed.trajectory.height_m - before_m) == pytest.approx(0.03, abs=0.003)


def test_base_from_the_rinex_header_is_approximate_and_warned(raw_survey, tmp_path):
    root, _ = raw_survey
    folder = root / "surveys" / "short"
    manifest = read_manifest(folder)
    header_manifest = replace(manifest, raw_gnss=replace(manifest.raw_gnss, base_point="rinex-header",
                                                         base_antenna_height_m=None))
    project = load_project(root)
    stage = run_gnss_stage(project, folder, header_manifest, tmp_path / "cache")
    assert stage.report["base"]["approximate"] and "approximate" in stage.warnings()[0]
    # the QC report keeps the warnings as phrases (insrail.notices), summary.toml in English
    assert stage.report["warnings"][0]["template"].startswith("base position from the RINEX header of {file}")
    assert stage.summary(project.fusion.gnss_quality_policy)["warnings"] == [str(w) for w in stage.warnings()]
    assert stage.qc.fix_rate >= 0.95


def test_cancel_in_the_gnss_stage_leaves_no_cache_entry(raw_survey, tmp_path):
    root, _ = raw_survey
    folder = root / "surveys" / "short"
    token = threading.Event()

    def cancel_when_rtklib_runs(fraction, message):
        if "RTKLIB" in message:
            token.set()

    with pytest.raises(Cancelled):
        run_gnss_stage(load_project(root), folder, read_manifest(folder), tmp_path / "cache",
                       progress=cancel_when_rtklib_runs, cancel=token)
    assert list((tmp_path / "cache").iterdir()) == []  # neither a result nor a temporary file


def _copy_project(root: Path, target: Path) -> Path:
    shutil.copytree(root / "surveys", target / "surveys")
    shutil.copy(root / "project.toml", target / "project.toml")
    return target


def test_unknown_base_point_names_the_key(raw_survey, tmp_path):
    root, raw = raw_survey
    project = replace(load_project(root), control_points=(ControlPoint("CP-OTHER", geodetic=(30.5, 114.4, 12.0)),))
    with pytest.raises(InputError, match=f"survey.toml: gnss_raw.base_point: unknown control point "
                                         f"'{raw.base_point}'.*known: CP-OTHER"):
        process(project, "short")


def test_missing_rinex_and_bad_keys_are_listed_with_key_paths(raw_survey, tmp_path):
    root, _ = raw_survey
    copy = _copy_project(root, tmp_path)
    folder = copy / "surveys" / "short"
    (folder / "base.obs").unlink()
    text = (folder / "survey.toml").read_text()
    (folder / "survey.toml").write_text(text.replace("base_antenna_height_m = 1.55", "base_antenna_height_m = \"1.55\""))
    with pytest.raises(ManifestError) as error:
        process(load_project(copy), "short")
    assert "gnss_raw.base: file not found: base.obs" in error.value.problems
    assert any(p.startswith("gnss_raw.base_antenna_height_m: expected a height") for p in error.value.problems)


def test_base_not_overlapping_the_rover_names_the_base_file(raw_survey, tmp_path):
    root, _ = raw_survey
    copy = _copy_project(root, tmp_path)
    folder = copy / "surveys" / "short"
    header = RinexObsHeader("BASE", (-2274855.0, 5008560.0, 3217209.0), (1.55, 0.0, 0.0), ("C1", "L1", "P2", "L2"),
                            1.0)
    late = 600000.0 + np.arange(10.0)  # an hour after the survey
    write_rinex2_obs(folder / "base.obs", header, 1316, late, np.full((10, 1), 5), np.full((10, 1, 4), 2.2e7))
    with pytest.raises(InputError, match="base.obs: base and rover do not overlap in time"):
        process(load_project(copy), "short")


def test_control_points_in_project_toml_are_validated_with_key_paths(raw_survey):
    root, _ = raw_survey
    document = tomllib.loads((root / "project.toml").read_text())
    document["geodesy"]["control_points"] = {
        "A": {"lat_deg": 30.5, "lon_deg": 114.4},
        "B": {"east_m": 1.0, "north_m": 2.0, "normal_height_m": 3.0, "lat_deg": 30.0},
        "C": {"east_m": 1.0, "north_m": "x", "normal_height_m": 3.0},
        "D": {"lat_deg": 91.0, "lon_deg": 114.4, "ellipsoidal_height_m": 3.0, "height": 1},
    }
    with pytest.raises(ProjectError) as error:
        project_from_settings(document, root)
    problems = error.value.problems
    assert "geodesy.control_points.A.ellipsoidal_height_m: missing" in problems
    assert any(p.startswith("geodesy.control_points.B: give either lat_deg") for p in problems)
    assert "geodesy.control_points.C.north_m: expected a number, found 'x'" in problems
    assert any(p.startswith("geodesy.control_points.D.height: unknown key") for p in problems)
    assert any(p.startswith("geodesy.control_points.D: latitude 91.0") for p in problems)
    document["geodesy"]["control_points"] = {"CP1": {"east_m": 512000.0, "north_m": 3374000.0, "normal_height_m": 30.0}}
    project = project_from_settings(document, root)
    assert project.control_point("CP1") == ControlPoint("CP1", engineering=(512000.0, 3374000.0, 30.0))
    assert project_from_settings(project.to_settings(), root) == project


def test_receiver_log_is_converted_once_and_its_navigation_used(raw_survey, tmp_path):
    root, _ = raw_survey
    log = tmp_path / "rover.dat"
    log.write_bytes((REAL / "walk_0827" / "gnss_1730.ubx").read_bytes()[:200_000])
    shutil.copy(root / "surveys" / "short" / "base.obs", tmp_path / "base.obs")
    manifest = read_manifest(root / "surveys" / "short")
    raw = RawGnss(base="base.obs", navigation=(), base_point="rinex-header", rover_log="rover.dat",
                  rover_log_format="ubx")
    cache = tmp_path / "cache"
    # The walk (2021) and the simulated base (2005) do not overlap: PPK refuses after the conversion.
    stamps = []
    for _ in range(2):
        with pytest.raises(InputError, match="base.obs: base and rover do not overlap in time"):
            run_gnss_stage(load_project(root), tmp_path, replace(manifest, raw_gnss=raw), cache)
        converted = list(cache.glob("rinex-*"))
        assert len(converted) == 1 and sorted(p.name for p in converted[0].glob("*.???")) == ["rover.nav", "rover.obs"]
        stamps.append((converted[0] / "rover.obs").stat().st_mtime_ns)
    assert stamps[0] == stamps[1]  # the second run took the converted files from the cache


def test_control_points_resolve_in_the_crs_datum(raw_survey):
    root, raw = raw_survey
    project = load_project(root)
    fit = fit_heights(project)
    geodetic = resolve_control_point(ControlPoint("G", geodetic=(30.5, 114.4, 12.0)), project.crs, fit)
    assert (np.degrees(geodetic.lat_rad), np.degrees(geodetic.lon_rad), geodetic.height_m) == pytest.approx(
        (30.5, 114.4, 12.0), abs=1e-12)
    east, north, normal_height = raw.base_enh_m
    engineering = resolve_control_point(ControlPoint("E", engineering=raw.base_enh_m), project.crs, fit)
    back = project.crs.to_plane(engineering.lat_rad, engineering.lon_rad)
    assert np.allclose(back, (east, north), atol=1e-6)
    zeta = float(fit.zeta_m(np.array([east]), np.array([north]))[0])
    assert engineering.height_m == pytest.approx(normal_height + zeta, abs=1e-9) and -13.0 < zeta < -11.5
    without_benchmarks = resolve_control_point(ControlPoint("E", engineering=raw.base_enh_m), project.crs, None)
    assert without_benchmarks.height_m == normal_height and "H taken as ellipsoidal" in without_benchmarks.derivation


def test_summary_counts_the_epochs_the_fusion_inflates_or_excludes(tmp_path):
    quality = np.array([1, 1, 2, 2, 2, 5])
    n = len(quality)
    solution = GnssSolution(time_s=np.arange(n, dtype=float), lat_rad=np.full(n, 0.5), lon_rad=np.full(n, 2.0),
                            height_m=np.zeros(n), sigma_ned_m=np.full((n, 3), 0.01), quality=quality,
                            num_sats=np.full(n, 8), ratio=np.full(n, 5.0))
    stage = GnssStageResult(solution, gnss_qc(solution), tmp_path / "p.pos", tmp_path / "q.toml", "0" * 64, False,
                            {"base": {"point": "CP1"}, "warnings": []})
    summary = stage.summary(FusionOptions().gnss_quality_policy)
    assert summary["epochs_by_quality"] == {"fix": 2, "float": 3, "single": 1}
    assert summary["fix_rate"] == pytest.approx(2 / 6)
    assert summary["fusion_inflated_epochs"] == 3 and summary["fusion_excluded_epochs"] == 1
    assert summary["fusion_by_quality"]["float"] == {"epochs": 3, "use": "sigma x 3"}
    assert summary["fusion_by_quality"]["single"] == {"epochs": 1, "use": "excluded"}
    custom = stage.summary(((1, 1.0), (2, None), (5, 10.0)))
    assert custom["fusion_inflated_epochs"] == 1 and custom["fusion_excluded_epochs"] == 3


def test_antex_and_base_antenna_reach_rtklib(raw_survey, tmp_path, monkeypatch):
    root, raw = raw_survey
    folder = root / "surveys" / "short"
    (folder / "igs.atx").write_text("ANTEX placeholder: the options are checked, RTKLIB does not run\n")
    manifest = read_manifest(folder)
    manifest = replace(manifest, raw_gnss=replace(manifest.raw_gnss, antex="igs.atx",
                                                  base_antenna_type="TRM55971.00     NONE"))
    seen = {}

    def record(*args, **kwargs):
        seen.update(kwargs)
        raise Cancelled("recorded")

    monkeypatch.setattr("insrail.project.gnss_stage.ppk", record)
    with pytest.raises(Cancelled):
        run_gnss_stage(load_project(root), folder, manifest, tmp_path / "cache")
    assert seen["options_overrides"] == {"file-rcvantfile": str(folder / "igs.atx"), "ant1-anttype": "*",
                                         "ant2-anttype": "*"}
    base = seen["base_position"]
    assert base.antenna_type == "TRM55971.00     NONE" and base.antenna_height_m == 1.55
    assert base.rtklib_options()["ant2-anttype"] == "TRM55971.00     NONE"  # applied after the overrides
    assert np.allclose(base.ecef(), raw.base_mark_ecef_m, atol=0.01)  # the mark, within the height fit's error


@pytest.mark.slow
def test_whole_short_survey_from_rinex_matches_the_truth(tmp_path, capsys):
    """The full `short` benchmark (1.2 km, two stops, a 120 s outage on the curve) from RINEX."""
    config = preset("short", gps_week=1316, start_time_s=558000.0025)
    folder = tmp_path / "surveys" / "short"
    simulate(config, seed=1, out_dir=folder, imu_format="npy")
    raw = convert_survey_to_raw_gnss(folder, config, NAV, seed=2)
    project = project_for_simulated_survey(tmp_path, folder)
    save_project(replace(project, control_points=(ControlPoint(raw.base_point, engineering=raw.base_enh_m),)))
    assert main(["process", str(tmp_path)]) == 0
    print(capsys.readouterr().out)
    stored = load_results(tmp_path, "short")
    assert stored.summary["ppk"]["fix_rate"] >= 0.95
    errors = trajectory_errors(stored.trajectory(), read_nav_truth(folder / "truth" / "nav.npy"),
                               load_project(tmp_path).crs.reference_ellipsoid)
    print(f"RINEX short: trajectory RMS horizontal {1e3 * errors.rms_horizontal_m():.2f} mm, vertical "
          f"{1e3 * errors.rms_vertical_m():.2f} mm; fix rate {100 * stored.summary['ppk']['fix_rate']:.1f} %")
    assert errors.rms_horizontal_m() < 0.005 and errors.rms_vertical_m() < 0.008
    truth = read_sleeper_truth(folder / "truth" / "sleepers.csv")
    lateral, vertical = expected_deviations(truth)
    station = stored.columns["station_m"]
    right = np.clip(np.searchsorted(truth["station"], station), 1, len(truth) - 1)
    rows = np.where(np.abs(truth["station"][right - 1] - station) < np.abs(truth["station"][right] - station),
                    right - 1, right)
    close = np.abs(truth["station"][rows] - station) < 0.05
    assert close.mean() > 0.95
    for side, rail in enumerate(("left", "right")):
        measured = stored.columns[f"lateral_deviation_{rail}_mm"][close]
        assert np.nanmax(np.abs(measured - 1e3 * lateral[rows[close], side])) < 10
        measured = stored.columns[f"vertical_deviation_{rail}_mm"][close]
        assert np.nanmax(np.abs(measured - 1e3 * vertical[rows[close], side])) < 10


HOSTILE = 'r";touch PWNED;".gz'


def test_hostile_rinex_name_in_a_handed_over_project_runs_nothing(raw_survey, tmp_path, monkeypatch):
    """A project someone hands over names its rover `r";touch PWNED;".gz` (a plain RINEX file):
    `insrail process` and `insrail batch` post-process it and run no command."""
    root, _ = raw_survey
    copy = _copy_project(root, tmp_path / "handed_over")
    folder = copy / "surveys" / "short"
    (folder / "rover.obs").rename(folder / HOSTILE)
    manifest = (folder / "survey.toml").read_text()
    assert 'rover = "rover.obs"' in manifest
    (folder / "survey.toml").write_text(manifest.replace('rover = "rover.obs"', "rover = 'r\";touch PWNED;\".gz'"))
    monkeypatch.chdir(tmp_path)
    assert main(["process", str(copy)]) == 0
    assert not list(tmp_path.rglob("PWNED"))
    for entry in (copy / "results" / ".cache").glob("ppk-*"):  # batch runs RTKLIB again, in its worker
        entry.unlink()
    assert main(["batch", str(copy), "--workers", "1"]) == 0
    assert not list(tmp_path.rglob("PWNED"))
    assert len(load_results(copy, "short").trajectory().time_s) > 0
