"""Raw total-station observations of free stations: the file formats, the set-ups resected on CPIII,
the prism fixes they give, a wrong CPIII point named, and the errors naming file and line."""

from dataclasses import replace

import numpy as np
import pytest

from insrail.geodesy.free_station import EARTH_RADIUS_M, REFRACTION_K
from insrail.io.errors import InputError
from insrail.io.total_station import (
    read_cpiii_enh,
    read_total_station_polar,
    write_cpiii_enh,
    write_total_station_polar,
)
from insrail.io.types import ControlPoints, TotalStationObservations
from insrail.project.total_station import prism_fixes_from_observations

MGON = np.pi / 200_000.0


def _pointings(setup, station, orientation, targets, names, times, rng, noise=True):
    delta = targets - station
    d = np.hypot(delta[:, 0], delta[:, 1])
    dz = delta[:, 2] - (1 - REFRACTION_K) * d**2 / (2 * EARTH_RADIUS_M)
    scale = 1.0 if noise else 0.0
    return {"setup": [setup] * len(d), "target": list(names), "time_s": list(times),
            "hz_rad": list(np.mod(np.arctan2(delta[:, 0], delta[:, 1]) - orientation, 2 * np.pi)
                           + scale * rng.normal(0, 0.3 * MGON, len(d))),
            "zenith_rad": list(np.arctan2(d, dz) + scale * rng.normal(0, 0.3 * MGON, len(d))),
            "slope_m": list(np.hypot(d, dz) + scale * rng.normal(0, 0.0005, len(d)))}


def simulated(rng, wrong_point=None, noise=True):
    """Two set-ups beside a straight N-bound track, each on 8 CPIII points, 3 prism pointings each."""
    names = [f"CP{k:02d}{side}" for k in range(8) for side in "LR"]
    cpiii = np.array([[500.0 + (-2.2 if side == "L" else 2.2), 1000.0 + 60.0 * k, 31.0]
                      for k in range(8) for side in "LR"])
    prism = np.array([[500.0, 1000.0 + s, 30.0 + 0.001 * s] for s in (70.0, 100.0, 130.0, 250.0, 280.0, 310.0)])
    rows = {key: [] for key in ("setup", "target", "time_s", "hz_rad", "zenith_rad", "slope_m")}
    for k, (centre, on) in enumerate(((100.0, range(4)), (280.0, range(3, 7)))):
        station = np.array([503.0, 1000.0 + centre, 31.6])
        points = [2 * j + side for j in on for side in (0, 1)]
        orientation = rng.uniform(0, 2 * np.pi)
        for part in (_pointings(f"TS{k + 1}", station, orientation, cpiii[points], [names[p] for p in points],
                                np.full(len(points), 1000.0 * k), rng, noise),
                     _pointings(f"TS{k + 1}", station, orientation, prism[3 * k:3 * k + 3], ["prism"] * 3,
                                1000.0 * k + 100.0 + 30.0 * np.arange(3), rng, noise)):
            for key in rows:
                rows[key] += part[key]
    known = cpiii.copy()
    if wrong_point is not None:
        known[names.index(wrong_point), :2] += [0.003, 0.004]  # 5 mm off in plan
    observations = TotalStationObservations(**{k: np.array(v) for k, v in rows.items()},
                                            line=np.arange(1, len(rows["time_s"]) + 1))
    return observations, ControlPoints(np.array(names), *known.T), prism


def test_observation_and_cpiii_files_round_trip(tmp_path):
    observations, points, _ = simulated(np.random.default_rng(1))
    write_total_station_polar(tmp_path / "ts.txt", observations)
    write_cpiii_enh(tmp_path / "cpiii.txt", points)
    back = read_total_station_polar(tmp_path / "ts.txt")
    np.testing.assert_array_equal(back.setup, observations.setup)
    np.testing.assert_array_equal(back.target, observations.target)
    np.testing.assert_allclose(back.hz_rad, observations.hz_rad, atol=2e-8)  # 1e-6 gon
    np.testing.assert_allclose(back.slope_m, observations.slope_m, atol=1e-5)
    assert back.line[0] == 3  # after the two comment lines: messages name the file's lines
    cpiii = read_cpiii_enh(tmp_path / "cpiii.txt")
    np.testing.assert_allclose(cpiii.north_m, points.north_m, atol=1e-5)
    degrees = tmp_path / "deg.txt"
    degrees.write_text("setup,target,t,Hz,V,D\nTS1,CP1,1.0,90.0,90.0,10.0\n")
    assert read_total_station_polar(degrees, angle_unit="deg").hz_rad[0] == pytest.approx(np.pi / 2)


@pytest.mark.parametrize("line, message", [
    ("TS1 CP1 1.0 12.0 250.0 10.0", r"line 3.*V = 250.0 gon is outside"),
    ("TS1 CP1 1.0 400.0 100.0 10.0", r"line 3.*Hz = 400.0 gon is outside"),
    ("TS1 CP1 1.0 12.0 100.0 -1.0", r"line 3.*expected a positive distance"),
    ("TS1 CP1 1.0 12.0 100.0", r"line 3.*expected 6 columns, found 5"),
    ("TS1 CP1 1.0 12.0 x 10.0", r"line 3"),
])
def test_a_bad_observation_line_is_named(tmp_path, line, message):
    path = tmp_path / "ts.txt"
    path.write_text(f"# setup target t Hz V D\nTS1 CP0 0.5 10.0 100.0 12.0\n{line}\n")
    with pytest.raises(InputError, match=message):
        read_total_station_polar(path)


def test_a_cpiii_point_given_twice_is_named(tmp_path):
    path = tmp_path / "cpiii.txt"
    path.write_text("CP1 1 2 3\nCP2 1 2 3\nCP1 4 5 6\n")
    with pytest.raises(InputError, match=r"line 3.*CP1 is given twice \(first on line 1\)"):
        read_cpiii_enh(path)


def test_set_ups_resected_on_cpiii_place_the_prism_to_a_millimetre():
    observations, points, prism = simulated(np.random.default_rng(2))
    fixes, notices = prism_fixes_from_observations(observations, points)
    assert not notices
    placed = np.column_stack([fixes.east_m, fixes.north_m, fixes.height_m])
    assert np.abs(placed - prism).max() < 1.5e-3
    assert list(fixes.point_id) == ["TS1"] * 3 + ["TS2"] * 3
    assert np.all((fixes.sigma_m >= 0.5e-3) & (fixes.sigma_m < 1.5e-3))
    exact, _ = prism_fixes_from_observations(*simulated(np.random.default_rng(2), noise=False)[:2])
    np.testing.assert_allclose(np.column_stack([exact.east_m, exact.north_m, exact.height_m]), prism, atol=1e-7)


def test_a_cpiii_point_5_mm_off_is_named_and_left_out():
    observations, points, prism = simulated(np.random.default_rng(3), wrong_point="CP02R")
    fixes, notices = prism_fixes_from_observations(observations, points)
    assert len(notices) == 1 and "set-up TS1" in notices[0].message and "CP02R does not fit" in notices[0].message
    assert notices[0].severity == "warning" and notices[0].stage == "total station"
    assert np.abs(np.column_stack([fixes.east_m, fixes.north_m, fixes.height_m]) - prism).max() < 1.5e-3


def test_an_unknown_cpiii_point_or_too_few_points_are_errors_naming_the_line():
    observations, points, _ = simulated(np.random.default_rng(4))
    keep = points.point_id != "CP05L"
    fewer = ControlPoints(points.point_id[keep], points.east_m[keep], points.north_m[keep], points.height_m[keep])
    line = int(observations.line[np.flatnonzero(observations.target == "CP05L")[0]])
    with pytest.raises(InputError, match=rf"line {line}.*set-up TS2: CPIII point CP05L is not in the CPIII file"):
        prism_fixes_from_observations(observations, fewer)
    two = np.isin(observations.target, ["CP00L", "CP00R", "prism"]) & (observations.setup == "TS1")
    few = TotalStationObservations(*(getattr(observations, k)[two] for k in (
        "setup", "target", "time_s", "hz_rad", "zenith_rad", "slope_m", "line")))
    with pytest.raises(InputError, match=r"line 1.*set-up TS1: a free station needs at least 3 CPIII points"):
        prism_fixes_from_observations(few, points)


def test_insrail_process_takes_raw_observations_and_names_a_wrong_cpiii_point(tmp_path, capsys):
    """End to end: a short simulated run with two prism stops whose fixes come as raw pointings of one
    free station (8 CPIII points, one of them 5 mm off), processed; then a pointing at a point the CPIII
    file does not hold fails `insrail process` naming the file and the line."""
    import tomllib
    from dataclasses import replace

    from insrail.cli.main import main
    from insrail.io.control import read_prism_enu
    from insrail.io.survey import SurveyFile, read_manifest, write_manifest
    from insrail.project.demo import project_for_simulated_survey
    from insrail.sim.scenario import PrismSpec, preset
    from insrail.sim.simulate import simulate
    from insrail.track.alignment_csv import read_alignment_csv

    short = preset("short")
    config = replace(short, motion=replace(short.motion, start_station_m=1100.0, end_station_m=1250.0, stops=(),
                                           static_start_s=60.0, static_end_s=10.0),
                     prism=PrismSpec(stations_m=(1150.0, 1200.0), duration_s=10.0))
    survey = tmp_path / "surveys" / "tiny"
    simulate(config, 1, survey, imu_format="npy")
    design = read_alignment_csv(survey / "truth" / "design.csv")
    prism = read_prism_enu(survey / "prism.txt")
    rng = np.random.default_rng(6)
    names, cpiii = [], []
    for s in (1100.0, 1140.0, 1210.0, 1250.0):
        for side, offset in (("L", -2.2), ("R", 2.2)):
            e, n = design.horizontal.point_at(s, offset)
            names.append(f"CP{s:.0f}{side}")
            cpiii.append((float(e), float(n), float(design.vertical.elevation_at(s)) + 1.0))
    cpiii = np.array(cpiii)
    e, n = design.horizontal.point_at(1175.0, 3.0)
    station = np.array([float(e), float(n), float(design.vertical.elevation_at(1175.0)) + 1.6])
    orientation = rng.uniform(0, 2 * np.pi)
    fixes = np.column_stack([prism.east_m, prism.north_m, prism.height_m])
    rows = [_pointings("TS1", station, orientation, cpiii, names, np.full(len(names), prism.time_s[0] - 60), rng),
            _pointings("TS1", station, orientation, fixes, ["prism"] * len(fixes), prism.time_s, rng)]
    observations = TotalStationObservations(
        **{k: np.concatenate([r[k] for r in rows]) for k in rows[0]}, line=np.arange(len(names) + len(fixes)))
    write_total_station_polar(survey / "total_station.txt", observations)
    wrong = cpiii.copy()
    wrong[names.index("CP1210R"), :2] += [0.003, 0.004]
    write_cpiii_enh(survey / "cpiii.txt", ControlPoints(np.array(names), *wrong.T))
    manifest = read_manifest(survey)
    files = {k: v for k, v in manifest.files.items() if k != "prism"}
    files |= {"total_station": SurveyFile("total_station.txt", "total-station-polar"),
              "cpiii": SurveyFile("cpiii.txt", "cpiii-enh")}
    write_manifest(survey, replace(manifest, files=files))
    project_for_simulated_survey(tmp_path, survey)

    assert main(["process", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "CP1210R does not fit" in out
    summary = tomllib.loads((tmp_path / "results" / "tiny" / "summary.toml").read_text())
    assert summary["fusion"]["prism_fixes"] == len(fixes)
    assert any(n["stage"] == "total station" and "CP1210R" in n["message"] for n in summary["notices"])

    (survey / "cpiii.txt").write_text("\n".join(line for line in (survey / "cpiii.txt").read_text().splitlines()
                                                if not line.startswith("CP1140L")) + "\n")
    assert main(["process", str(tmp_path)]) == 1
    err = capsys.readouterr().err
    assert "total_station.txt" in err and "line 5" in err and "CP1140L is not in the CPIII file" in err

    # the CPIII coordinates in millimetres; then the angles written in degrees, read as gon
    write_cpiii_enh(survey / "cpiii.txt", ControlPoints(np.array(names), *(1e3 * cpiii).T))
    assert main(["process", str(tmp_path)]) == 1
    err = capsys.readouterr().err
    assert "total_station.txt, line " in err and ": set-up TS1: the CPIII points fit the observations to" in err
    assert "coordinates in millimetres?" in err
    write_cpiii_enh(survey / "cpiii.txt", ControlPoints(np.array(names), *cpiii.T))
    write_total_station_polar(survey / "total_station.txt", replace(
        observations, hz_rad=0.9 * observations.hz_rad, zenith_rad=0.9 * observations.zenith_rad))
    assert main(["process", str(tmp_path)]) == 1
    err = capsys.readouterr().err
    assert "set-up TS1" in err and "angles in degrees read as gon?" in err


def test_raw_observations_without_cpiii_points_are_a_manifest_problem(tmp_path):
    from insrail.io.errors import ManifestError
    from insrail.io.survey import read_manifest

    for name in ("imu.npy", "ts.txt"):
        (tmp_path / name).write_text("x")
    (tmp_path / "survey.toml").write_text(
        '[survey]\nname = "t"\n[files.imu]\npath = "imu.npy"\nformat = "imu-npy"\n'
        '[files.total_station]\npath = "ts.txt"\nformat = "total-station-polar"\n'
        '[trolley]\nimu_to_reference_rail_m = [0, 0, 0.3]\n')
    with pytest.raises(ManifestError) as error:
        read_manifest(tmp_path)
    text = str(error.value)
    assert "need the CPIII points they are resected on [files.cpiii]" in text
    assert "trolley.imu_to_prism_m: missing (required with files.total_station" in text


def test_the_crews_gsi_files_place_the_same_fixes_as_the_text_files(tmp_path):
    """The set-ups written as Leica GSI-16 (pointings and CPIII coordinates), named in survey.toml by their
    formats, resect and place the prism as the text files do (GSI's 1e-5 gon and 0.01 mm: < 0.02 mm)."""
    from insrail.io.formats import read_any
    from insrail.io.gsi import write_cpiii_gsi, write_total_station_gsi

    observations, points, _ = simulated(np.random.default_rng(3), wrong_point="CP03L")
    write_total_station_gsi(tmp_path / "ts.gsi", observations)
    write_cpiii_gsi(tmp_path / "cpiii.gsi", points)
    text, text_notices = prism_fixes_from_observations(observations, points)
    gsi, gsi_notices = prism_fixes_from_observations(read_any(tmp_path / "ts.gsi"), read_any(tmp_path / "cpiii.gsi"))
    for name in ("time_s", "east_m", "north_m", "height_m"):
        np.testing.assert_allclose(getattr(gsi, name), getattr(text, name), rtol=0, atol=2e-5)
    assert [n.message.split(" (line")[0] for n in gsi_notices] == [n.message.split(" (line")[0] for n in text_notices]
    assert gsi_notices and all("CP03L does not fit" in n.message for n in gsi_notices)


def test_a_run_beyond_the_first_or_last_prism_fix_without_gnss_is_named():
    """Where a survey without GNSS runs on beyond its outermost fixes the position rests on the INS and the
    odometer alone: each such end is named with its length and time; a fix in the start or end stop
    (no distance beyond it), a survey with GNSS or without fixes has none."""
    from dataclasses import replace
    from pathlib import Path

    from insrail.io.survey import SurveyData
    from insrail.io.types import OdometerData, PrismObservations
    from insrail.project.total_station import gnss_free_run_notices

    time = np.arange(0.0, 400.0, 0.1)
    moving = np.clip(time - 100.0, 0.0, 250.0)  # still until 100 s and after 350 s, then 1 m/s
    fixes = PrismObservations(np.array([130.0, 190.0, 250.0]), np.zeros(3), np.zeros(3), np.zeros(3),
                              np.full(3, 0.001), np.array(["a", "b", "c"]))
    survey = SurveyData(None, Path("."), None, odometer=OdometerData(time, moving), prism=fixes)
    before, after = gnss_free_run_notices(survey)
    assert "goes on 30 m before its first prism fix (at 130.0 s)" in before.message and before.time_s == 130.0
    assert "goes on 100 m beyond its last prism fix (at 250.0 s)" in after.message and after.time_s == 250.0
    in_the_stops = replace(fixes, time_s=np.array([50.0, 190.0, 380.0]))
    assert gnss_free_run_notices(replace(survey, prism=in_the_stops)) == []
    assert gnss_free_run_notices(replace(survey, gnss=object())) == []
    assert gnss_free_run_notices(replace(survey, prism=None)) == []


@pytest.mark.parametrize("mistake, cause", [
    ("cpiii in mm", "coordinates in millimetres?"),
    ("degrees read as gon", "angles in degrees read as gon?"),
    ("distances in mm", "distances in millimetres?"),
])
def test_a_set_up_no_total_station_can_give_is_an_error_naming_the_set_up_and_the_cause(mistake, cause):
    observations, points, _ = simulated(np.random.default_rng(3))
    if mistake == "cpiii in mm":
        points = ControlPoints(points.point_id, 1e3 * points.east_m, 1e3 * points.north_m, 1e3 * points.height_m)
    elif mistake == "degrees read as gon":
        observations = replace(observations, hz_rad=0.9 * observations.hz_rad, zenith_rad=0.9 * observations.zenith_rad)
    else:
        observations = replace(observations, slope_m=1e3 * observations.slope_m)
    with pytest.raises(InputError) as caught:
        prism_fixes_from_observations(observations, points)
    assert caught.value.line == 1 and "set-up TS1: the CPIII points fit the observations to" in str(caught.value)
    assert "a total station gives" in str(caught.value) and cause in str(caught.value)
