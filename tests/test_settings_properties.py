"""Property tests of the settings: survey.toml and project.toml drawn from the documented schema
(docs/formats.md, insrail/project/model.py), each optional key present or absent, values in their
documented ranges and some outside them.

What must hold: what ``insrail process`` runs before the fusion either accepts the settings or
refuses them with an InputError (ProjectError, ManifestError) naming the file and the key; never
another exception. An accepted configuration run for real through ``insrail process`` gives a
result (a handful of examples on a 150 m survey simulated once per session).
"""

from __future__ import annotations

import re
import shutil
import tomllib
from dataclasses import dataclass
from pathlib import Path

import pytest
import tomli_w
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_project_robustness import tiny_scenario  # the 150 m survey

from insrail.cli.main import main
from insrail.io.errors import InputError
from insrail.project import load_project, pipeline, process
from insrail.sim.simulate import simulate

SURVEY = "run"
#: The simulator's trolley (insrail.sim.scenario.default_trolley), as a user copies it from the sheet.
LEVER_ARMS = {"imu_to_antenna_m": [0.02, 0.18, -1.35], "imu_to_odometer_m": [0.45, -0.6, 0.31],
              "imu_to_prism_m": [0.02, 0.18, -1.52], "imu_to_sleeper_detector_m": [0.3, -0.45, 0.22],
              "imu_to_reference_rail_m": [0.1, -0.6, 0.31]}
MOUNTING_DEG = [0.05, -0.08, 0.12]
#: The role each lever arm is required with (None: by every processed survey, for the rails).
NEEDED_WITH = {"imu_to_antenna_m": "gnss", "imu_to_odometer_m": "odometer", "imu_to_prism_m": "prism",
               "imu_to_sleeper_detector_m": "sleepers", "imu_to_reference_rail_m": None}
RAW_FILES = {"imu": ("imu.npy", "imu-npy"), "gnss": ("gnss.pos", "rtklib-pos"),
             "odometer": ("odometer.txt", "odometer-distance"), "gauge": ("gauge.txt", "gauge-mm"),
             "sleepers": ("sleepers.txt", "sleeper-times")}


@pytest.fixture(scope="session")
def raw_survey(tmp_path_factory) -> Path:
    """The simulated raw files of a 150 m survey (made once per session)."""
    folder = tmp_path_factory.mktemp("settings") / SURVEY
    simulate(tiny_scenario(), 1, folder, imu_format="npy")
    (folder / "survey.toml").unlink()  # each example writes its own, as a user would
    return folder


@dataclass
class Drawn:
    """One drawn configuration and the keys whose value or absence must refuse it."""

    survey: dict
    project: dict
    refused_by: set[str]


MISSING = object()
#: The keys a drawn configuration may get wrong (one at a time, so that each refusal is seen alone).
FAULTS = ("project.name", "project.description", "survey.gps_week", "survey.imu_profile", "survey.description", "files", "files.gauge",
          *(f"trolley.{key}" for key in LEVER_ARMS), "trolley.reference_rail", "trolley.mounting_rpy_deg",
          "trolley.rail_centre_spacing_m", "geodesy.height.benchmarks", "geodesy.height.model",
          "geodesy.height.geoid_grid", "track.design", "track.start_station_m", "track.tolerance_profile",
          "track.first_sleeper_number", "track.fastener", "track.stationing_direction", "track.line_speed_kmh",
          "track.sleeper_anchor", "processing.use_nhc", "processing.update_rate_hz", "processing.imu_profile",
          "adjustment.strategy", "adjustment.threshold_mm", "report.paper")


@st.composite
def configurations(draw, valid_only=False):
    """A survey.toml and project.toml as a user writes them; unless ``valid_only``, one key (or none)
    is wrong: a value outside its documented range or type, or left out where it is needed."""
    fault = None if valid_only else draw(st.sampled_from((None, *FAULTS)))
    refused: set[str] = set()

    def put(table, key, key_path, valid, invalid=()):
        """Leave the key out or give a valid value; at the fault's key, maybe an invalid one."""
        choices = [MISSING, *valid]
        if key_path == fault and invalid:
            choices = list(invalid)
            refused.add(key_path)
        value = draw(st.sampled_from(choices))
        if value is not MISSING:
            table[key] = value

    survey: dict = {"name": SURVEY}
    put(survey, "gps_week", "survey.gps_week", [2380], [-3, "2380", 2380.5])
    put(survey, "imu_profile", "survey.imu_profile", ["nav"], ["navv", "profiles/nav.toml"])
    put(survey, "description", "survey.description", ["km 1.1 - 1.25"], [12])

    roles = {"imu", "gnss", "gauge"} | {role for role in ("odometer", "sleepers") if draw(st.booleans())}
    for role, key_path in (("gnss", "files"), ("gauge", "files.gauge")):  # no position source; no gauge
        if fault == key_path:
            roles.discard(role)
            if role == "gnss":  # with an odometer and no position source it is a relative survey
                roles.discard("odometer")
            refused.add(key_path)
    files = {role: {"path": RAW_FILES[role][0], "format": RAW_FILES[role][1]} for role in sorted(roles)}

    trolley: dict = {}
    for key, arm in LEVER_ARMS.items():
        needed = NEEDED_WITH[key] is None or NEEDED_WITH[key] in roles
        if needed and fault == f"trolley.{key}" and draw(st.booleans()):
            refused.add(fault)  # left out where it is needed
            continue
        put(trolley, key, f"trolley.{key}", [arm], [[1e3 * v for v in arm], arm[:2], "0.1 0.2 0.3"])
        if needed and key not in trolley and fault != f"trolley.{key}":
            trolley[key] = arm
        elif needed and key not in trolley:
            refused.add(fault)
    put(trolley, "reference_rail", "trolley.reference_rail", ["left"], ["middle", "LEFT"])
    put(trolley, "mounting_rpy_deg", "trolley.mounting_rpy_deg", [MOUNTING_DEG], [[0.1, 0.2], "0 0 0"])
    put(trolley, "rail_centre_spacing_m", "trolley.rail_centre_spacing_m", [1.5], [1500, -1.5, 0.5])

    crs = {"ellipsoid": "CGCS2000", "central_meridian_deg": 114.3, "projection_height_m": 30.0,
           "projection_height_convention": "scale_factor"}
    height: dict = {}
    put(height, "benchmarks", "geodesy.height.benchmarks", [f"{SURVEY}/benchmarks.txt"], ["absent.txt"])
    put(height, "model", "geodesy.height.model", ["auto", "constant", "plane"], ["spline", 3])
    put(height, "geoid_grid", "geodesy.height.geoid_grid", ["egm96"], ["absent.gtx", ""])
    track: dict = {}
    put(track, "design", "track.design", [f"{SURVEY}/truth/design.csv"], ["absent.csv"])
    put(track, "start_station_m", "track.start_station_m", [1100.0], ["1100", float("inf")])
    if "design" not in track and "start_station_m" not in track:
        if fault == "track.start_station_m":
            refused.add(fault)  # needed without a design
        else:
            track["start_station_m"] = 1100.0
    put(track, "tolerance_profile", "track.tolerance_profile", ["cn_hsr_ballastless", "cn_conventional_160"],
        ["cn-hsr"])
    put(track, "first_sleeper_number", "track.first_sleeper_number", [1, 500], [1.5])
    put(track, "fastener", "track.fastener", ["wj7", "wj8"], ["wj-7"])
    put(track, "stationing_direction", "track.stationing_direction", ["travel", 45.0], ["north"])
    put(track, "line_speed_kmh", "track.line_speed_kmh", [250, [{"from_m": 0.0, "to_m": 5000.0, "kmh": 200}]],
        [-5, "fast", [{"from_m": 10.0, "to_m": 0.0, "kmh": 100}]])
    put(track, "sleeper_anchor", "track.sleeper_anchor", [{"number": 1234, "station_m": 1150.0}],
        [{"number": 1234}, {"number": "1234", "station_m": 1150.0}])
    adjustment: dict = {}
    put(adjustment, "strategy", "adjustment.strategy", ["least_movement", "guiding_rail_first"], ["cheapest"])
    put(adjustment, "threshold_mm", "adjustment.threshold_mm", [1.0, 2.0], [50.0, -1.0])
    report: dict = {}
    put(report, "paper", "report.paper", ["A3", "A4"], ["Letter"])
    processing: dict = {}
    put(processing, "use_nhc", "processing.use_nhc", [True], ["yes"])
    put(processing, "update_rate_hz", "processing.update_rate_hz", [10.0], [-10.0, 0])
    put(processing, "imu_profile", "processing.imu_profile", ["nav"], ["navigation"])
    if survey.get("imu_profile") == "navv" and "imu_profile" in processing:
        refused.discard("survey.imu_profile")  # the project's profile replaces the survey's
    meta: dict = {}
    put(meta, "name", "project.name", ["settings"], [7])
    put(meta, "description", "project.description", ["a test"], [["a", "b"]])
    project = {"project": meta, "geodesy": {"crs": crs, "height": height},
               "track": track, "processing": processing, "adjustment": adjustment, "report": report,
               "surveys": [{"name": SURVEY, "folder": SURVEY}]}
    return Drawn({"survey": survey, "files": files, "trolley": trolley}, project, refused)


def without_empty_tables(document: dict) -> dict:
    return {key: without_empty_tables(value) if isinstance(value, dict) else value
            for key, value in document.items() if value != {}}


def write_project(root: Path, raw_survey: Path, drawn: Drawn) -> Path:
    if root.exists():
        shutil.rmtree(root)
    shutil.copytree(raw_survey, root / SURVEY)
    (root / SURVEY / "survey.toml").write_text(tomli_w.dumps(without_empty_tables(drawn.survey)))
    (root / "project.toml").write_text(tomli_w.dumps(without_empty_tables(drawn.project)))
    return root


class ReachedTheFusion(Exception):
    """Raised in place of the fusion: everything before it accepted the settings."""


def before_the_fusion(*args, **kwargs):
    raise ReachedTheFusion


def outcome_before_the_fusion(root: Path) -> InputError | None:
    """None when what ``process`` runs before the fusion accepts the project; else its InputError.
    Any other exception propagates (and fails the test)."""
    try:
        process(load_project(root), SURVEY)
    except ReachedTheFusion:
        return None
    except InputError as error:
        return error
    raise AssertionError("the fusion was expected to be reached (replaced) or the settings refused")


def assert_refusal_names_file_and_key(error: InputError, root: Path, drawn: Drawn) -> None:
    text = str(error)
    assert re.match(rf"{re.escape(str(root))}/(project\.toml|{SURVEY}/survey\.toml|{SURVEY}/benchmarks\.txt)", text), \
        text
    named = {key for key in drawn.refused_by if key in text}
    assert named, (text, drawn.refused_by)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture,
                                                                HealthCheck.too_slow])
@given(drawn=configurations())
def test_settings_are_accepted_or_refused_naming_file_and_key_before_the_fusion(drawn, raw_survey, tmp_path,
                                                                                 monkeypatch):
    monkeypatch.setattr(pipeline, "_fused_trajectory", before_the_fusion)
    root = write_project(tmp_path / "project", raw_survey, drawn)
    error = outcome_before_the_fusion(root)
    if drawn.refused_by:
        assert error is not None, f"accepted, but {sorted(drawn.refused_by)} should refuse it"
        assert_refusal_names_file_and_key(error, root, drawn)
    else:
        assert error is None, f"refused a valid configuration: {error}"


@settings(max_examples=3, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture,
                                                               HealthCheck.too_slow])
@given(drawn=configurations(valid_only=True))
def test_accepted_settings_give_a_result_through_insrail_process(drawn, raw_survey, tmp_path, capsys):
    root = write_project(tmp_path / "project", raw_survey, drawn)
    assert not drawn.refused_by
    assert main(["process", str(root)]) == 0, capsys.readouterr().err
    assert (root / "results" / SURVEY / "sleepers.csv").is_file()


def test_fuse_takes_a_survey_of_imu_and_gnss_without_any_rail_key(raw_survey, tmp_path, capsys):
    """A walk or a road test: survey.toml with the IMU, the GNSS and the antenna's lever arm only."""
    folder = tmp_path / "walk"
    folder.mkdir()
    for role in ("imu", "gnss"):
        shutil.copy(raw_survey / RAW_FILES[role][0], folder)
    (folder / "survey.toml").write_text(
        '[survey]\nname = "walk"\n\n[files.imu]\npath = "imu.npy"\nformat = "imu-npy"\n\n'
        '[files.gnss]\npath = "gnss.pos"\nformat = "rtklib-pos"\n\n'
        '[trolley]\nimu_to_antenna_m = [0.02, 0.18, -1.35]\n')
    assert main(["fuse", str(folder), "--out", str(tmp_path / "out")]) == 0, capsys.readouterr().err
    assert (tmp_path / "out" / "trajectory.npy").is_file()
    log = tomllib.loads((tmp_path / "out" / "fusion_log.toml").read_text())
    assert any("the non-holonomic constraint is applied at the IMU" in n["message"] for n in log["notices"])

    # insrail process needs the rails: refused before the fusion, naming the file, the key and why
    (tmp_path / "project.toml").write_text(
        '[geodesy.crs]\nellipsoid = "CGCS2000"\ncentral_meridian_deg = 114.3\n\n[track]\nstart_station_m = 0.0\n\n'
        '[[surveys]]\nname = "walk"\nfolder = "walk"\n')
    (folder / "gauge.txt").write_bytes((raw_survey / "gauge.txt").read_bytes())
    with (folder / "survey.toml").open("a") as manifest:
        manifest.write('\n[files.gauge]\npath = "gauge.txt"\nformat = "gauge-mm"\n')
    assert main(["process", str(tmp_path)]) == 1
    error = capsys.readouterr().err
    assert f"{folder / 'survey.toml'}: trolley.imu_to_reference_rail_m: missing; insrail process needs it" in error
    assert not (tmp_path / "results" / ".cache").exists() or not list((tmp_path / "results" / ".cache").glob("fusion-*"))


def test_a_project_trolley_needs_only_what_each_survey_uses(raw_survey, tmp_path, monkeypatch):
    """project.toml's [trolley] replaces the surveys' own, which may then be left out; without the
    sleeper detector it loads, a survey with a sleeper file is then refused before the fusion naming
    project.toml and the key, one without is accepted."""
    monkeypatch.setattr(pipeline, "_fused_trajectory", before_the_fusion)
    arms = {key: LEVER_ARMS[key] for key in ("imu_to_antenna_m", "imu_to_odometer_m", "imu_to_reference_rail_m")}
    survey = {"survey": {"name": SURVEY}, "files": {role: {"path": RAW_FILES[role][0], "format": RAW_FILES[role][1]}
                        for role in ("imu", "gnss", "odometer", "gauge", "sleepers")}}
    project = {"geodesy": {"crs": {"ellipsoid": "CGCS2000", "central_meridian_deg": 114.3}}, "trolley": arms,
               "track": {"start_station_m": 1100.0}, "surveys": [{"name": SURVEY, "folder": SURVEY}]}
    root = write_project(tmp_path / "project", raw_survey, Drawn(survey, project, set()))
    error = outcome_before_the_fusion(root)
    assert str(error).startswith(f"{root / 'project.toml'}: trolley.imu_to_sleeper_detector_m: missing; insrail "
                                 "process needs it because files.sleepers is given"), error
    del survey["files"]["sleepers"]
    root = write_project(tmp_path / "project", raw_survey, Drawn(survey, project, set()))
    assert outcome_before_the_fusion(root) is None
