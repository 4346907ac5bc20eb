"""project.toml: round trip, every problem reported with its key path, atomic save."""

import os
import subprocess
import sys
import textwrap
import tomllib
from dataclasses import replace

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from insrail.geodesy.crs import EngineeringCRS
from insrail.io.errors import InputError
from insrail.nav.fusion import FusionOptions
from insrail.project import (
    HeightSettings,
    Project,
    ProjectError,
    SurveyEntry,
    load_project,
    save_project,
)
from insrail.project.model import FUSION_NUMBERS

CRS = {"ellipsoid": "CGCS2000", "central_meridian_deg": 114.3, "false_easting_m": 500000.0,
       "projection_height_m": 30.0}


def make_folder(root):
    """A project folder with two survey folders (only their survey.toml is looked at here),
    a benchmarks file and a design file name."""
    for name in ("a", "b"):
        (root / "surveys" / name).mkdir(parents=True, exist_ok=True)
        (root / "surveys" / name / "survey.toml").write_text("")
    (root / "benchmarks.txt").write_text("BM1 30.4 114.4 14.0 26.5\n")
    return root


def sample_project(root, **changes):
    project = Project(folder=root, name="line 7", description="two runs", crs=EngineeringCRS.from_settings(CRS),
                      height=HeightSettings(benchmarks="benchmarks.txt"),
                      surveys=(SurveyEntry("a", "surveys/a"), SurveyEntry("b", "surveys/b")),
                      start_station_m=1000.0, first_sleeper_number=5, tolerance_profile="fra_class_3")
    return replace(project, **changes)


def test_round_trip(tmp_path):
    trolley = {"imu_to_antenna_m": [0.02, 0.18, -1.35], "imu_to_odometer_m": [0.45, -0.6, 0.31],
               "imu_to_sleeper_detector_m": [0.3, -0.45, 0.22], "imu_to_reference_rail_m": [0.1, -0.6, 0.31],
               "reference_rail": "right", "mounting_rpy_deg": [0.05, -0.08, 0.12]}
    project = sample_project(make_folder(tmp_path), imu_profile="tactical", trolley_settings=trolley,
                             fusion=FusionOptions(use_nhc=False, update_rate_hz=5.0, gnss_sigma_scale=1.5))
    path = save_project(project)
    loaded = load_project(tmp_path)
    assert loaded == project
    assert load_project(path) == project
    # A plain TOML file a surveyor can read and edit.
    document = tomllib.loads(path.read_text())
    assert document["surveys"][1] == {"name": "b", "folder": "surveys/b"}
    assert document["processing"]["use_nhc"] is False
    assert loaded.trolley().reference_rail == "right"
    assert loaded.trolley().mounting_rpy_rad[2] == pytest.approx(0.12 * 3.141592653589793 / 180)
    assert sample_project(tmp_path).trolley() is None  # each survey brings its own


@settings(max_examples=25, deadline=None)
@given(numbers=st.dictionaries(st.sampled_from(FUSION_NUMBERS), st.floats(1e-4, 1e4)),
       flags=st.fixed_dictionaries({"use_zupt": st.booleans(), "smoother": st.booleans()}),
       start=st.floats(-1e6, 1e6), number=st.integers(-10**6, 10**6))
def test_round_trip_of_processing_options(tmp_path_factory, numbers, flags, start, number):
    root = make_folder(tmp_path_factory.mktemp("p"))
    project = sample_project(root, fusion=FusionOptions(**numbers, **flags), start_station_m=start,
                             first_sleeper_number=number)
    save_project(project)
    assert load_project(root) == project


def test_every_problem_is_listed_with_its_key_path(tmp_path):
    make_folder(tmp_path)
    (tmp_path / "project.toml").write_text(textwrap.dedent("""
        colour = "blue"
        [geodesy.crs]
        ellipsoid = "CGCS2000"
        scale_factor = 2.0
        [geodesy.height]
        benchmarks = "missing.txt"
        model = "spline"
        [processing]
        use_nhc = "yes"
        update_rate_hz = -1
        imu_profile = "no-such-imu"
        [track]
        design = "design.csv"
        tolerance_profile = "no_such_profile"
        fastener = 3
        [trolley]
        reference_rail = "middle"
        [[surveys]]
        name = "a"
        folder = "surveys/a"
        [[surveys]]
        name = "a"
        folder = "surveys/b"
        [[surveys]]
        name = "c"
        folder = "surveys/c"
    """))
    with pytest.raises(ProjectError) as caught:
        load_project(tmp_path)
    keys = {problem.split(":")[0] for problem in caught.value.problems}
    assert {"colour", "geodesy.crs.central_meridian_deg", "geodesy.crs.scale_factor", "geodesy.height.benchmarks",
            "geodesy.height.model", "processing.use_nhc", "processing.update_rate_hz", "processing.imu_profile",
            "track.design", "track.tolerance_profile", "track.fastener", "surveys[1].name", "trolley.reference_rail",
            "surveys[2].folder"} <= keys
    assert "surveys[2].folder: not found: surveys/c" in caught.value.problems
    assert str(tmp_path / "project.toml") in str(caught.value)


def test_missing_tables_and_bad_toml(tmp_path):
    (tmp_path / "project.toml").write_text("[project]\nname = 'x'\n")
    with pytest.raises(ProjectError) as caught:
        load_project(tmp_path)
    keys = {p.split(":")[0] for p in caught.value.problems}
    assert keys == {"geodesy.crs", "track.start_station_m", "surveys"}
    (tmp_path / "project.toml").write_text("[project\n")
    with pytest.raises(InputError) as bad:
        load_project(tmp_path)
    assert bad.value.line == 1


def test_killed_save_leaves_the_previous_project_intact(tmp_path):
    project = sample_project(make_folder(tmp_path))
    path = save_project(project)
    before = path.read_bytes()
    # A child process starts saving a changed project and is killed half way through writing.
    script = textwrap.dedent(f"""
        import os, signal
        from dataclasses import replace
        from insrail.project import load_project, save_project
        def die(fd):  # the new file written, not yet in place
            os.kill(os.getpid(), signal.SIGKILL)
        os.fsync = die
        save_project(replace(load_project({str(tmp_path)!r}), name="changed"))
    """)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(p) for p in sys.path if p])}
    child = subprocess.run([sys.executable, "-c", script], check=False, env=env)
    assert child.returncode == -9
    assert path.read_bytes() == before
    assert load_project(tmp_path) == project


def test_saving_keeps_the_comments_and_layout_of_the_users_file(tmp_path):
    project = sample_project(make_folder(tmp_path))
    path = save_project(project)
    text = path.read_text()
    assert "[project]\n" in text and "[track]\n" in text
    written = ("# Line 7, north section: settings agreed with the client on 3 May\n"
               + text.replace("[project]\n", "[project]\n# the contract's name\n", 1)
                     .replace("[track]\n", "[track]   # from the design office\n", 1))
    path.write_text(written)
    save_project(replace(load_project(tmp_path), name="renamed"))
    saved = path.read_text()
    assert saved.startswith("# Line 7, north section: settings agreed with the client on 3 May\n")
    assert "[project]\n# the contract's name\n" in saved and "[track]   # from the design office\n" in saved
    assert load_project(tmp_path) == replace(project, name="renamed")
    assert len(saved.splitlines()) == len(written.splitlines())  # nothing else rewritten


def test_stationing_direction_without_a_design(tmp_path):
    project = sample_project(make_folder(tmp_path), stationing_direction=212.5)
    save_project(project)
    assert load_project(tmp_path).stationing_direction == 212.5
    assert tomllib.loads(project.path.read_text())["track"]["stationing_direction"] == 212.5
    save_project(sample_project(tmp_path))
    assert load_project(tmp_path).stationing_direction == "travel"
    text = project.path.read_text().replace("[track]\n", '[track]\nstationing_direction = "uphill"\n')
    project.path.write_text(text)
    with pytest.raises(ProjectError, match=r"track.stationing_direction: expected a number, found 'uphill' or \"travel\""):
        load_project(tmp_path)


def test_sleeper_anchor(tmp_path):
    from insrail.track.sleepers import SleeperAnchor

    project = sample_project(make_folder(tmp_path), sleeper_anchor=SleeperAnchor(1234, station_m=1500.0))
    save_project(project)
    assert load_project(tmp_path).sleeper_anchor == SleeperAnchor(1234, station_m=1500.0)
    text = project.path.read_text()
    assert "[track.sleeper_anchor]" in text or "sleeper_anchor = {" in text
    for bad, message in (('{ number = 1.5, station_m = 1.0 }', "track.sleeper_anchor.number: expected a whole number"),
                         ('{ number = 3 }', "give exactly one of station_m"),
                         ('{ number = 3, station_m = 1.0, time_s = 2.0 }', "give exactly one of station_m")):
        save_project(sample_project(tmp_path))
        project.path.write_text(project.path.read_text().replace("[track]\n", f"[track]\nsleeper_anchor = {bad}\n"))
        with pytest.raises(ProjectError, match=message):
            load_project(tmp_path)


def test_adjustment_strategy(tmp_path):
    from insrail.project.model import AdjustmentSettings

    make_folder(tmp_path)
    path = save_project(sample_project(tmp_path))
    assert "adjustment" not in tomllib.loads(path.read_text())  # an untouched project writes no table
    assert load_project(tmp_path).adjustment.strategy == "least_movement"
    guided = sample_project(tmp_path, adjustment=AdjustmentSettings("guiding_rail_first"))
    save_project(guided)
    assert tomllib.loads(path.read_text())["adjustment"] == {"strategy": "guiding_rail_first"}
    assert load_project(tmp_path) == guided
    text = path.read_text().replace('strategy = "guiding_rail_first"', 'strategy = "lowest_rail"\nthreshold = 2')
    path.write_text(text)
    with pytest.raises(ProjectError) as info:
        load_project(tmp_path)
    message = str(info.value)
    assert "adjustment.strategy: expected 'least_movement' or 'guiding_rail_first', found 'lowest_rail'" in message
    assert "adjustment.threshold: unknown key" in message


def test_adjustment_action_threshold(tmp_path):
    from insrail.project.model import AdjustmentSettings

    make_folder(tmp_path)
    path = save_project(sample_project(tmp_path))
    assert load_project(tmp_path).adjustment.threshold_mm is None  # one fastener step: every amount is listed
    chosen = sample_project(tmp_path, adjustment=AdjustmentSettings(threshold_mm=2.0))
    save_project(chosen)
    assert tomllib.loads(path.read_text())["adjustment"] == {"threshold_mm": 2.0}
    assert load_project(tmp_path) == chosen and load_project(tmp_path).adjustment.threshold_m == pytest.approx(2e-3)
    for bad, message in (("-1", "adjustment.threshold_mm: expected a positive number, found -1"),
                         ('"2 mm"', "adjustment.threshold_mm: expected a number, found '2 mm'"),
                         ("12", "adjustment.threshold_mm: expected at most 10 mm, found 12")):
        path.write_text(path.read_text().replace("threshold_mm = 2.0", f"threshold_mm = {bad}"))
        with pytest.raises(ProjectError, match=message):
            load_project(tmp_path)
        save_project(chosen)


def _with_redesign(tmp_path, table: str):
    make_folder(tmp_path)
    (tmp_path / "project.toml").write_text(textwrap.dedent("""
        [geodesy.crs]
        ellipsoid = "CGCS2000"
        central_meridian_deg = 114.3
        [track]
        start_station_m = 1000.0
        [[surveys]]
        name = "a"
        folder = "surveys/a"
    """) + textwrap.dedent(table))


def test_redesign_table_as_a_user_writes_it_and_its_round_trip(tmp_path):
    _with_redesign(tmp_path, """
        [redesign]
        max_slew_mm = 15
        [[redesign.fixed]]
        from_m = 1640.0
        to_m = 1660.0
        [[redesign.fixed]]
        from_m = 1700.0
        to_m = 1710.0
        tolerance_mm = 2
    """)
    project = load_project(tmp_path)
    assert project.redesign.max_slew_mm == 15.0 and project.redesign.lift_only and project.redesign.fix_events
    assert [(f.from_m, f.to_m, f.tolerance_mm) for f in project.redesign.fixed] == [(1640.0, 1660.0, 0.0),
                                                                                    (1700.0, 1710.0, 2.0)]
    save_project(project)
    assert load_project(tmp_path).redesign == project.redesign
    from insrail.project.redesign import resolve_settings

    events = [{"kind": "bridge", "station_from_m": 1500.0, "station_to_m": 1540.0, "text": "Xiaohe"},
              {"kind": "joint", "station_from_m": 1600.0, "station_to_m": 1600.0, "text": ""}]
    settings = resolve_settings(project.redesign, events)
    assert settings.max_slew_m == pytest.approx(0.015)
    assert [(f.from_m, f.source) for f in settings.fixed] == [(1640.0, "redesign.fixed[0]"), (1700.0, "redesign.fixed[1]"),
                                                              (1500.0, "bridge Xiaohe")]
    assert settings.fixed[1].tolerance_m == pytest.approx(0.002)


def test_redesign_table_problems_name_their_keys(tmp_path):
    _with_redesign(tmp_path, """
        [redesign]
        lift_only = "yes"
        max_lift_mm = -5
        min_lift_mm = 80
        speed = 3
        [[redesign.fixed]]
        from_m = 1660.0
        to_m = 1640.0
        [[redesign.fixed]]
        from_m = 1700.0
    """)
    with pytest.raises(ProjectError) as caught:
        load_project(tmp_path)
    keys = {problem.split(":")[0] for problem in caught.value.problems}
    assert {"redesign.lift_only", "redesign.max_lift_mm", "redesign.min_lift_mm", "redesign.speed",
            "redesign.fixed[0]", "redesign.fixed[1]"} <= keys
