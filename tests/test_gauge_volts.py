"""The gauge sensor in volts with its calibration (thesis eq. 5.1, 5.3) and the curve correction of the
twin-wheel beam (eq. 5.2): read, refused naming file/line/key, and end to end through `insrail process`
against the same survey's millimetre record."""

from __future__ import annotations

import contextlib
import io
import shutil
from pathlib import Path

import numpy as np
import pytest

from insrail.cli.main import main
from insrail.io import InputError, ManifestError, read_any, read_manifest
from insrail.track.alignment_csv import read_alignment_csv
from insrail.track.rails import gauge_curve_correction_m
from survey_builder import SURVEY_NAME, Cell, built_cell_copy

K_MM_PER_V, B_MM, K_T_MM_PER_C, T_CAL_C = 2.5, 1400.0, 0.0165, 20.0
CALIBRATION = (f"k_mm_per_v = {K_MM_PER_V}\nb_mm = {B_MM}\ntemperature_coefficient_mm_per_c = {K_T_MM_PER_C}\n"
               f"calibration_temperature_c = {T_CAL_C}\n")


def _volts(time_s: np.ndarray, gauge_mm: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """What the sensor logs for ``gauge_mm``: its voltage and a temperature drifting 5 .. 35 °C."""
    temperature_c = 20.0 + 15.0 * np.sin(2 * np.pi * (time_s - time_s[0]) / 900.0)
    return (gauge_mm - B_MM - K_T_MM_PER_C * (temperature_c - T_CAL_C)) / K_MM_PER_V, temperature_c


def _write_volts(path: Path, time_s, gauge_mm, temperature: bool = True) -> None:
    volts, temperature_c = _volts(time_s, gauge_mm)
    columns = [time_s, volts, temperature_c] if temperature else [time_s, volts]
    np.savetxt(path, np.column_stack(columns), fmt=["%.3f", "%.7f", "%.3f"][:len(columns)])


def test_volts_with_temperature_read_as_the_gauge_they_were_made_from(tmp_path):
    t = 345600.0 + 0.5 * np.arange(2000)
    gauge_mm = 1435.0 + 0.3 * np.sin(t / 7.0)
    _write_volts(tmp_path / "gauge.txt", t, gauge_mm)
    read = read_any(tmp_path / "gauge.txt", "gauge-volts", k_mm_per_v=K_MM_PER_V, b_mm=B_MM,
                    temperature_coefficient_mm_per_c=K_T_MM_PER_C, calibration_temperature_c=T_CAL_C)
    assert np.max(np.abs(1e3 * read.gauge_m - gauge_mm)) < 1e-4  # mm: the file's rounding
    # without the temperature term the reading is off by K_T (T - T_cal): up to 0.25 mm here
    volts, temperature_c = _volts(t, gauge_mm)
    assert np.max(np.abs(K_MM_PER_V * volts + B_MM - gauge_mm)) > 0.2


def _manifest_folder(tmp_path: Path, gauge_options: str) -> Path:
    for name in ("imu.txt", "gnss.pos", "gauge.txt"):
        (tmp_path / name).write_text("0 0\n")
    (tmp_path / "survey.toml").write_text(
        '[survey]\nname = "r"\n\n[files.imu]\npath = "imu.txt"\nformat = "kfgins-imu"\n\n'
        '[files.gnss]\npath = "gnss.pos"\nformat = "rtklib-pos"\n\n'
        f'[files.gauge]\npath = "gauge.txt"\nformat = "gauge-volts"\n{gauge_options}\n'
        "[trolley]\nimu_to_antenna_m = [0.0, 0.0, -1.3]\n")
    return tmp_path


@pytest.mark.parametrize("options, key, says", [
    ("k_mm_per_v = 0.0\nb_mm = 1400.0\n", "files.gauge.k_mm_per_v", "is 0"),
    ("b_mm = 1400.0\n", "files.gauge.k_mm_per_v", "missing"),
    ("k_mm_per_v = 2.5\n", "files.gauge.b_mm", "missing"),
    ("k_mm_per_v = 2.5\nb_mm = 1400.0\ntemperature_coefficient_mm_per_c = 0.0165\n",
     "files.gauge.calibration_temperature_c", "missing"),
    ("k_mm_per_v = 2.5\nb_mm = 1400.0\ncalibration_temperature_c = 20.0\n",
     "files.gauge.temperature_coefficient_mm_per_c", "missing"),
    ("k_mm_per_v = 2.5\nb_mm = 1400.0\ntemperature_coefficient_mm_per_c = 0.0165\ncalibration_temperature_c = 293.15\n",
     "files.gauge.calibration_temperature_c", "degrees Celsius"),
    ('k_mm_per_v = "2.5"\nb_mm = 1400.0\n', "files.gauge.k_mm_per_v", "expected float"),
])
def test_a_calibration_that_cannot_be_is_named_by_its_key_in_survey_toml(tmp_path, options, key, says):
    with pytest.raises(ManifestError) as error:
        read_manifest(_manifest_folder(tmp_path, options))
    problem = [p for p in error.value.problems if p.startswith(key)]
    assert problem and says in problem[0], error.value.problems


def test_a_trolley_beam_spacing_in_millimetres_is_named(tmp_path):
    folder = _manifest_folder(tmp_path, CALIBRATION)
    (folder / "survey.toml").write_text((folder / "survey.toml").read_text() + "beam_wheel_spacing_m = 800.0\n")
    with pytest.raises(ManifestError, match="trolley.beam_wheel_spacing_m: expected"):
        read_manifest(folder)


def test_the_temperature_column_and_its_coefficient_go_together(tmp_path):
    t = 345600.0 + 0.05 * np.arange(50)
    gauge_mm = np.full(50, 1435.0)
    _write_volts(tmp_path / "two.txt", t, gauge_mm, temperature=False)
    with pytest.raises(InputError, match=r"two.txt, line 1: expected 3 columns \(t, volts, temperature"):
        read_any(tmp_path / "two.txt", "gauge-volts", k_mm_per_v=K_MM_PER_V, b_mm=B_MM,
                 temperature_coefficient_mm_per_c=K_T_MM_PER_C, calibration_temperature_c=T_CAL_C)
    _write_volts(tmp_path / "three.txt", t, gauge_mm)
    with pytest.raises(InputError, match="three.txt, line 1: a third column"):
        read_any(tmp_path / "three.txt", "gauge-volts", k_mm_per_v=K_MM_PER_V, b_mm=B_MM)
    lines = (tmp_path / "three.txt").read_text().splitlines()
    lines[7] = lines[7].rsplit(" ", 1)[0] + " 298.150"  # Kelvin
    (tmp_path / "kelvin.txt").write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError, match="kelvin.txt, line 8: temperature 298.15: expected degrees Celsius"):
        read_any(tmp_path / "kelvin.txt", "gauge-volts", k_mm_per_v=K_MM_PER_V, b_mm=B_MM,
                 temperature_coefficient_mm_per_c=K_T_MM_PER_C, calibration_temperature_c=T_CAL_C)
    with pytest.raises(InputError, match="three.txt: the calibration gives a median gauge of 1.43"):
        read_any(tmp_path / "three.txt", "gauge-volts", k_mm_per_v=K_MM_PER_V / 1000, b_mm=B_MM / 1000,
                 temperature_coefficient_mm_per_c=K_T_MM_PER_C, calibration_temperature_c=T_CAL_C)


def _insrail(*args: str) -> tuple[int, str]:
    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(out):
        code = main(list(args))
    return code, out.getvalue()


def _sleepers(project: Path) -> np.ndarray:
    return np.genfromtxt(project / "results" / SURVEY_NAME / "sleepers.csv", delimiter=",", names=True, dtype=None,
                         encoding="utf-8")


def test_gauge_in_volts_processes_to_the_gauge_of_the_millimetre_file_and_the_beam_corrects_curves(tmp_path):
    """The same survey twice through `insrail process`: its gauge record in mm, then in volts with a temperature
    column (the calibration in survey.toml) and the trolley's beam wheel spacing. On the straights the gauge of the
    sleepers is the millimetre run's; on the R 1500 m arc it is larger by the beam's versine, 0.083 mm for a 1 m
    beam (thesis eq. 5.2). The curvature is the measured path's over 10 m, which holds the track's lateral
    irregularities (1 mm RMS here): sleeper by sleeper the correction scatters by a few hundredths of a mm."""
    cell = Cell(imu="nav", position="rtklib-pos", ellipsoid="CGCS2000", design="csv", direction="with",
                left_out="none", trolley="minimal")
    built = built_cell_copy(cell, tmp_path / "mm", seed=7)
    code, out = _insrail("process", str(built.project))
    assert code == 0, out
    volts_project = tmp_path / "volts"
    shutil.copytree(built.project, volts_project, ignore=shutil.ignore_patterns("results"))
    survey = volts_project / "survey"
    record = np.loadtxt(survey / "gauge.txt")
    (survey / "gauge.txt").unlink()
    _write_volts(survey / "gauge_volts.txt", record[:, 0], record[:, 1])
    text = (survey / "survey.toml").read_text()
    text = text.replace('path = "gauge.txt"\nformat = "gauge-mm"\n',
                        f'path = "gauge_volts.txt"\nformat = "gauge-volts"\n{CALIBRATION}')
    text += "beam_wheel_spacing_m = 1.0\n"
    (survey / "survey.toml").write_text(text)
    code, out = _insrail("process", str(volts_project))
    assert code == 0, out

    millimetres, volts = _sleepers(built.project), _sleepers(volts_project)
    assert np.array_equal(millimetres["number"], volts["number"])
    both = np.isfinite(millimetres["gauge_mm"]) & np.isfinite(volts["gauge_mm"])
    assert both.sum() > 600
    design = read_alignment_csv(volts_project / "design.csv")
    curvature = design.horizontal.curvature_at(volts["station_m"][both])
    arc, straight = np.isclose(curvature, 1 / 1500, rtol=1e-6), curvature == 0
    assert arc.sum() > 100 and straight.sum() > 100
    difference_mm = volts["gauge_mm"][both] - millimetres["gauge_mm"][both]
    versine_mm = 1e3 * gauge_curve_correction_m(1 / 1500, 1.0, "left")  # the left (reference) rail is the outer
    assert versine_mm == pytest.approx(1e3 / 8 / 1500, rel=1e-3)
    assert np.mean(difference_mm[arc]) == pytest.approx(versine_mm, abs=0.01)
    assert np.mean(difference_mm[straight]) == pytest.approx(0.0, abs=0.01)
    expected_mm = 1e3 * gauge_curve_correction_m(curvature, 1.0, "left")
    assert np.sqrt(np.mean((difference_mm - expected_mm) ** 2)) < 0.03
