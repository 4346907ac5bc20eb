"""The IMU mounting estimated from the survey (issue 37, thesis 5.3.1.2): a survey.toml whose mounting is
0.3 deg wrong on each axis is processed with the estimate, says so, and measures as with the right one."""

from __future__ import annotations

import contextlib
import io
import math
import re
import shutil
import subprocess
import tomllib
import zlib

import numpy as np
import pytest

from insrail.cli.main import main
from insrail.nav.mounting import CROSS_LEVEL_REFERENCE_M, roll_from_cant
from survey_builder import SURVEY_NAME, Cell, built_cell_copy, truth_errors

WRONG_DEG = 0.3
CELL = Cell("nav", "rtklib-pos", "CGCS2000", "csv", "with", "none", "calibrated")


def insrail(*args: str) -> tuple[int, str]:
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
        code = main(list(args))
    return code, out.getvalue()


def _chord_errors(built) -> np.ndarray:
    comparison = truth_errors(built.project / "results" / SURVEY_NAME / "sleepers.csv", built, normal_heights=False)
    return np.array([np.std(check) for rail in comparison.rails.values() for check in rail.check_30m_5m_m()])


@pytest.fixture(scope="module")
def surveys(tmp_path_factory):
    """The same simulated run processed with the right mounting and with each axis 0.3 deg wrong."""
    built = {}
    for name, offset in (("right", 0.0), ("wrong", WRONG_DEG)):
        cell = built_cell_copy(CELL, tmp_path_factory.mktemp(name), seed=zlib.crc32(CELL.cell_id.encode()))
        toml = cell.project / "survey" / "survey.toml"
        given = np.degrees(cell.config.trolley.mounting_rpy_rad) + offset
        text, count = re.subn(r"mounting_rpy_deg = .*", f"mounting_rpy_deg = [{', '.join(f'{v:.4f}' for v in given)}]",
                              toml.read_text())
        assert count == 1
        toml.write_text(text)
        code, out = insrail("process", str(cell.project))
        assert code == 0, out
        built[name] = (cell, out)
    return built


def test_a_mounting_given_wrong_is_estimated_applied_and_said(surveys):
    cell, out = surveys["wrong"]
    truth = np.degrees(cell.config.trolley.mounting_rpy_rad)
    summary = tomllib.loads((cell.project / "results" / SURVEY_NAME / "summary.toml").read_text())
    mounting = summary["fusion"]["mounting"]
    for i, axis in enumerate(("roll", "pitch", "yaw")):
        entry = mounting[axis]
        assert abs(entry["estimate_deg"] - truth[i]) < 0.03, (axis, entry, truth[i])
        assert entry["applied"] and abs(mounting["applied_rpy_deg"][i] - truth[i]) < 0.03
    assert "differs from survey.toml's trolley.mounting_rpy_deg by more than 3 sigma (pitch by 0.300 deg" in out
    assert "(roll by 0.29" in out and "give trolley.mounting_rpy_deg = [" in out
    # the right mounting: estimated as well, nothing applied, no warning
    right, out = surveys["right"]
    summary = tomllib.loads((right.project / "results" / SURVEY_NAME / "summary.toml").read_text())
    assert not any(summary["fusion"]["mounting"][axis]["applied"] for axis in ("roll", "pitch", "yaw"))
    assert "mounting_rpy_deg by more than" not in out


@pytest.mark.parametrize("name", ["right", "wrong"])
def test_the_pass_beside_the_main_fusion_gives_the_results_of_one_after_the_other(surveys, name, tmp_path):
    """The fixture's processing ran the mounting's pass and the main fusion side by side (the right mounting: the
    main fusion's guess kept; the wrong one: discarded, fused again); on one CPU they run one after the other,
    as before: the results are the same to the byte."""
    from insrail.background import cpus_limited

    cell, _ = surveys[name]
    serial = tmp_path / "project"
    shutil.copytree(cell.project, serial, ignore=shutil.ignore_patterns("results", "reports"))
    with cpus_limited(1):
        code, out = insrail("process", str(serial))
    assert code == 0, out
    ran, again = (folder / "results" / SURVEY_NAME for folder in (cell.project, serial))
    for file in ("trajectory.npy", "sleepers.csv", "quality.csv", "exceedances.csv"):
        assert (ran / file).read_bytes() == (again / file).read_bytes(), file

    def summary(folder):
        return re.sub(r"processing_time_s = .*", "", (folder / "summary.toml").read_text())

    assert summary(ran) == summary(again)


def test_with_the_estimate_the_30m_5m_error_is_as_with_the_right_mounting(surveys):
    right, wrong = _chord_errors(surveys["right"][0]), _chord_errors(surveys["wrong"][0])
    assert np.all(wrong <= 1.1 * right), (wrong, right)


def test_the_report_names_the_estimate(surveys):
    cell, _ = surveys["wrong"]
    assert insrail("report", str(cell.project))[0] == 0
    if shutil.which("pdftotext") is None:
        pytest.skip("pdftotext (poppler) not installed: the PDF's text is not read")
    text = subprocess.run(["pdftotext", "-raw", str(cell.project / "reports" / f"track_geometry_{SURVEY_NAME}.pdf"), "-"],
                          capture_output=True, check=True, text=True).stdout
    assert "IMU mounting" in text and "estimated from the survey: roll +0.05" in text


def test_calibrate_prints_the_mounting_for_the_survey_toml(surveys, tmp_path):
    """In its project (with a design) all three axes within 0.03 deg of the truth, roll included; the survey
    alone (copied out of the project) gives pitch and yaw and keeps its roll, saying why."""
    cell, _ = surveys["wrong"]
    truth = np.degrees(cell.config.trolley.mounting_rpy_rad)

    def printed(out):
        line = next(line for line in out.splitlines() if line.startswith("mounting_rpy_deg = ["))
        return [float(v) for v in line.split("[")[1].split("]")[0].split(",")], line

    code, out = insrail("calibrate", str(cell.project / "survey"))
    assert code == 0, out
    values, line = printed(out)
    assert all(abs(values[i] - truth[i]) < 0.03 for i in range(3)), (values, truth)
    assert "as given" not in line and "processed in" in out
    alone = tmp_path / "alone"
    shutil.copytree(cell.project / "survey", alone)
    code, out = insrail("calibrate", str(alone))
    assert code == 0, out
    values, line = printed(out)
    assert abs(values[1] - truth[1]) < 0.03 and abs(values[2] - truth[2]) < 0.03
    assert values[0] == pytest.approx(truth[0] + WRONG_DEG, abs=1e-4) and "roll as given" in line
    assert "the roll needs the design's cant" in out


def test_the_roll_is_the_mean_cant_against_the_designs():
    """A roll eps too large tilts the trolley's y axis by -eps: the cant reads 1.5 m x eps low everywhere."""
    rng = np.random.default_rng(1)
    design = np.r_[np.zeros(300), np.linspace(0.0, 0.1, 100), np.full(300, 0.1)]
    eps = math.radians(0.3)
    cant = design - 1.5 * eps + rng.normal(0.0, 0.3e-3, design.size)
    found = roll_from_cant(np.array([0.3 + eps, 0.0, 0.0]), cant, design, 1.5, np.ones(design.size, bool))
    assert found.rpy_rad[0] == pytest.approx(0.3, abs=3 * found.sigma_rad[0])
    assert found.sigma_rad[0] >= CROSS_LEVEL_REFERENCE_M / 1.5 and found.significant[0]
    assert np.isnan(found.sigma_rad[1:]).all() and not found.significant[1:].any()
