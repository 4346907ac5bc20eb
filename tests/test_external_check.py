"""`insrail compare --levelling/--points`: a processed survey checked against a levelling line and another
trolley's per-sleeper coordinates (thesis §5.4.3), both made from the simulator's truth plus their stated noise."""

from __future__ import annotations

import contextlib
import io
import tomllib
from pathlib import Path

import numpy as np
import pytest

from insrail.cli.main import main
from insrail.io import InputError
from insrail.io.external import read_levelling_line, read_trolley_points
from insrail.sim.truth import read_sleeper_truth
from survey_builder import SURVEY_NAME, Cell, build_cell

LEVELLING_SIGMA_MM, POINTS_SIGMA_MM = 0.3, 1.0


def _insrail(*args: str) -> tuple[int, str]:
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
        code = main([str(a) for a in args])
    return code, out.getvalue()


def _references(truth: Path, folder: Path, up_mm: float = 0.0, right_mm: float = 0.0) -> tuple[Path, Path]:
    """A levelling line of the left rail every 5 m and the right rail's coordinates every 4th sleeper, as a
    surveyor writes them, from the truth plus noise of their stated sigma; ``up_mm`` and ``right_mm`` move every
    reference point (a reference that is off)."""
    folder.mkdir()
    t = read_sleeper_truth(truth / "sleepers.csv")
    rng = np.random.default_rng(5)
    station = t["station"]
    levelled = np.arange(0, len(station), 8)  # every 5 m
    heights = t["left_h"][levelled] + 1e-3 * (up_mm + LEVELLING_SIGMA_MM * rng.standard_normal(len(levelled)))
    levelling = folder / "levelling.csv"
    levelling.write_text("point,chainage,H\n" + "".join(
        f"L{k},{station[i]:.3f},{h:.5f}\n" for k, (i, h) in enumerate(zip(levelled, heights))))
    rows = np.arange(0, len(station), 4)
    east, north, height = (t[f"right_{axis}"] for axis in "enh")
    azimuth = np.arctan2(np.gradient(east), np.gradient(north))
    right = np.column_stack([np.cos(azimuth), -np.sin(azimuth)])  # (E, N) of the right normal
    noise = 1e-3 * POINTS_SIGMA_MM * rng.standard_normal((len(rows), 3))
    e = east[rows] + 1e-3 * right_mm * right[rows, 0] + noise[:, 0]
    n = north[rows] + 1e-3 * right_mm * right[rows, 1] + noise[:, 1]
    h = height[rows] + 1e-3 * up_mm + noise[:, 2]
    points = folder / "trolley_b.csv"
    points.write_text("# sleeper coordinates of trolley B, right rail\n" + "".join(
        f"{int(t['index'][i])} {station[i]:.4f} {e[k]:.4f} {n[k]:.4f} {h[k]:.4f}\n" for k, i in enumerate(rows)))
    return levelling, points


def _compare(project: Path, levelling: Path, points: Path) -> tuple[int, str]:
    return _insrail("compare", project, "--surveys", SURVEY_NAME, "--levelling", levelling, "--levelling-sigma-mm",
                    LEVELLING_SIGMA_MM, "--levelling-rail", "left", "--points", points, "--points-sigma-mm",
                    POINTS_SIGMA_MM, "--points-rail", "right")


@pytest.fixture(scope="module")
def processed(tmp_path_factory):
    folder = tmp_path_factory.mktemp("external")
    cell = Cell(imu="nav", position="gnss+prism", ellipsoid="CGCS2000", design="csv", direction="with",
                left_out="none", trolley="minimal")
    built = build_cell(cell, folder, seed=11)
    code, out = _insrail("process", built.project)
    assert code == 0, out
    return built, folder


def _summary(project: Path, reference: Path) -> dict:
    return tomllib.loads((project / "results" / f"external_{SURVEY_NAME}_{reference.stem}.toml").read_text())


def test_a_survey_agrees_with_a_levelling_line_and_another_trolley_within_their_sigma(processed):
    built, folder = processed
    levelling, points = _references(built.truth, folder / "good")
    code, out = _compare(built.project, levelling, points)
    assert code == 0, out
    level, trolley = _summary(built.project, levelling), _summary(built.project, points)
    assert level["points"] > 70 and level["not_covered"] <= 2 and "lateral" not in level
    assert level["vertical"]["agrees"] and level["vertical"]["within_3sigma"] >= 0.95
    assert abs(level["vertical"]["mean_mm"]) < 1.5 and level["vertical"]["rms_mm"] < 2.0
    for component in ("lateral", "vertical"):
        assert trolley[component]["agrees"] and abs(trolley[component]["mean_mm"]) < 1.5, trolley
        # the reference's own noise (1 mm) is in the differences: their RMS cannot be far below it
        assert 0.7 < trolley[component]["rms_mm"] < 3.0, trolley
    table = np.genfromtxt(built.project / "results" / f"external_{SURVEY_NAME}_{levelling.stem}.csv", delimiter=",",
                          names=True, dtype=None, encoding="utf-8")
    assert np.all(table["vertical_sigma_mm"][np.isfinite(table["vertical_sigma_mm"])] > LEVELLING_SIGMA_MM)


def test_a_reference_off_by_5_mm_is_reported_with_its_sign_and_fails(processed):
    """Every reference point 5 mm higher and 5 mm to the right: survey - reference is -5 mm in both, beyond 3 sigma."""
    built, folder = processed
    levelling, points = _references(built.truth, folder / "off", up_mm=5.0, right_mm=5.0)
    code, out = _compare(built.project, levelling, points)
    assert code == 3 and "DOES NOT AGREE" in out, out
    level, trolley = _summary(built.project, levelling), _summary(built.project, points)
    assert level["vertical"]["mean_mm"] == pytest.approx(-5.0, abs=1.5) and not level["vertical"]["agrees"]
    for component in ("lateral", "vertical"):
        assert trolley[component]["mean_mm"] == pytest.approx(-5.0, abs=1.5), trolley
        assert not trolley[component]["agrees"]


def test_reference_files_are_read_strictly(tmp_path):
    (tmp_path / "l.csv").write_text("point,chainage,H\nA,100.0,12.3\nA,105.0,12.4\n")
    with pytest.raises(InputError, match=r"l.csv, line 3: point 'A' appears twice \(also on line 2\)"):
        read_levelling_line(tmp_path / "l.csv")
    (tmp_path / "p.csv").write_text("1 100.0 500.0 3000.0\n")
    with pytest.raises(InputError, match="p.csv, line 1: expected 5 columns, found 4"):
        read_trolley_points(tmp_path / "p.csv")
    (tmp_path / "h.csv").write_text("A,100.0,12,3\n")
    with pytest.raises(InputError, match="h.csv, line 1: expected 3 columns, found 4"):
        read_levelling_line(tmp_path / "h.csv")
