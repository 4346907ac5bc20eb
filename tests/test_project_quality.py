"""Predicted accuracy per section in the processing pipeline: quality.csv on the chainage, the
[quality] summary, StoredResults.quality, the fusion cache and the PDF, on a survey with a GNSS
outage."""

import shutil
import subprocess
import threading
import time
import tomllib
from dataclasses import replace

import numpy as np
import pytest

from insrail import background
from insrail.progress import Cancelled, is_cancelled
from insrail.project import pipeline, process
from insrail.project.demo import project_for_simulated_survey
from insrail.project.results import QUALITY_FILE, QUALITY_HEADER, _read_quality, load_results
from insrail.report import write_pdf
from insrail.sim.scenario import preset
from insrail.sim.simulate import simulate

SURVEY = "outage"


@pytest.fixture(scope="module")
def processed(tmp_path_factory):
    """600 m of the `short` line with a tactical-grade IMU and a 120 s GNSS outage from station
    1460 m (to about 1600 m), no stops: three 200 m sections, the outage inside the middle one."""
    config = preset("short", imu_profile="tactical")
    config = replace(config,
                     motion=replace(config.motion, start_station_m=1250.0, end_station_m=1850.0, stops=(),
                                    static_start_s=60.0, static_end_s=20.0),
                     gnss=replace(config.gnss, outages=((1460.0, 120.0),)))
    root = tmp_path_factory.mktemp("quality-project")
    simulate(config, 3, root / "surveys" / SURVEY, imu_format="npy")
    project = project_for_simulated_survey(root, root / "surveys" / SURVEY)
    return project, process(project, SURVEY)


def outage_chainage(project, stored) -> tuple[float, float]:
    """Chainage of the outage's start and end: its GPS times mapped through the sleeper table."""
    errors = tomllib.loads((project.folder / "surveys" / SURVEY / "truth" / "errors.toml").read_text())
    (start, end), = errors["gnss_outages_s"]
    time, station = stored.columns["time_s"], stored.columns["station_m"]
    return tuple(float(np.interp(t, time, station)) for t in (start, end))


def test_quality_csv_is_on_the_chainage_of_the_tqi_sections(processed):
    project, results = processed
    folder = results.folder
    lines = (folder / QUALITY_FILE).read_text().splitlines()
    assert lines[0].split(",") == QUALITY_HEADER
    stored = load_results(project.folder, SURVEY)
    quality = stored.quality
    assert quality is not None and quality.smoothed and len(quality) == len(lines) - 1 == 3
    # sections of the project's chainage, aligned with the [track_quality] sections (from the first sleeper)
    starts = stored.summary["track_quality"]["start_m"]
    assert len(starts) == 3
    np.testing.assert_allclose(quality.station_from_m, starts, atol=1e-3)
    np.testing.assert_allclose(quality.station_to_m[:-1], quality.station_from_m[1:])
    assert quality.station_to_m[-1] == pytest.approx(stored.columns["station_m"][-1], abs=2.0)
    assert np.all(np.isfinite(quality.sigma_lag5_lateral_mm)) and np.all(quality.sigma_lag5_lateral_mm > 0.0)
    assert np.all(quality.sigma_lag150_vertical_mm > quality.sigma_lag5_vertical_mm)
    # the cross-level (cant): 1.5 m x the roll's 1-sigma, a few hundredths of a millimetre with a navigation grade IMU
    assert np.all(quality.sigma_cross_level_mm > 0.0) and np.all(quality.sigma_cross_level_mm < 1.0)
    assert stored.summary["quality"]["median"]["sigma_cross_level_mm"] > 0.0
    # a quality.csv written before the cross-level column reads with that column empty
    old = folder.parent / "before-cross-level.csv"
    old.write_text("\n".join(",".join(line.split(",")[:8]) for line in lines) + "\n")
    before = _read_quality(old, True)
    np.testing.assert_allclose(before.sigma_lag5_lateral_mm, quality.sigma_lag5_lateral_mm)
    assert np.all(np.isnan(before.sigma_cross_level_mm)) and np.all(np.isnan(before.sigma_along_track_mm))
    # the along-track position: GNSS-held, a few millimetres
    assert np.all(quality.sigma_along_track_mm > 1.0) and np.all(quality.sigma_along_track_mm < 50.0)
    # the in-memory table is the file's
    np.testing.assert_allclose(1e3 * results.quality.sigma_lag150_lateral_m, quality.sigma_lag150_lateral_mm,
                               atol=1e-3)


def test_the_outage_section_is_the_weakest(processed):
    project, _ = processed
    stored = load_results(project.folder, SURVEY)
    quality = stored.quality
    first, last = outage_chainage(project, stored)
    assert 1455.0 < first < 1465.0 and last - first > 100.0
    outage = int(np.searchsorted(quality.station_from_m, 0.5 * (first + last)) - 1)
    assert outage == 1 and quality.station_from_m[1] < first and last < quality.station_to_m[1]
    assert quality.weakest_sections(3)[0] == outage
    for figure in ("sigma_lateral_mm", "sigma_lag5_lateral_mm", "sigma_lag150_lateral_mm"):
        assert quality.weakest(figure) == outage, figure
    others = [k for k in range(len(quality)) if k != outage]
    assert quality.sigma_lag5_lateral_mm[outage] > 1.1 * quality.sigma_lag5_lateral_mm[others].max()
    summary = stored.summary["quality"]
    assert summary["pass"] == "smoothed" and summary["sections"] == 3
    assert summary["weakest"]["station_from_m"] == pytest.approx(quality.station_from_m[outage], abs=1e-3)
    assert summary["weakest"]["sigma_lag5_lateral_mm"] == pytest.approx(quality.sigma_lag5_lateral_mm[outage], abs=1e-3)
    assert summary["median"]["sigma_lag5_lateral_mm"] == pytest.approx(np.median(quality.sigma_lag5_lateral_mm),
                                                                       abs=1e-3)


def test_a_cached_rerun_reuses_the_covariance_analysis(processed, monkeypatch):
    project, results = processed
    before = (results.folder / QUALITY_FILE).read_text()
    assert pipeline.quality_cache_file(results.folder.parent / ".cache" / "x.npy").name == "x.quality.npz"
    assert list((results.folder.parent / ".cache").glob("fusion-*.quality.npz"))

    def refuse(*args, **kwargs):
        raise AssertionError("the covariance analysis ran again")

    monkeypatch.setattr(pipeline, "epoch_quality", refuse)
    monkeypatch.setattr(pipeline, "recorded_quality", refuse)
    again = process(project, SURVEY)
    assert again.fusion_from_cache
    assert (again.folder / QUALITY_FILE).read_text() == before


def test_cancelling_the_covariance_analysis_caches_nothing(processed, tmp_path):
    project, _ = processed
    root = tmp_path / "project"
    shutil.copytree(project.folder / "surveys" / SURVEY, root / "surveys" / SURVEY)
    fresh = project_for_simulated_survey(root, root / "surveys" / SURVEY)
    messages = []

    def progress(fraction, message):
        messages.append((fraction, str(message)))  # a Phrase's English (insrail.progress)

    with pytest.raises(Cancelled):
        process(fresh, SURVEY, progress=progress, cancel=lambda: bool(messages) and messages[-1][1].startswith("covariance: smoother"))
    analysis = [f for f, m in messages if m.startswith("covariance")]
    assert analysis and analysis == sorted(analysis)
    assert not list((root / "results" / ".cache").glob("fusion-*"))  # neither the fusion nor its analysis
    assert not (root / "results" / SURVEY).exists()


def test_results_without_quality_file_load_with_none(processed, tmp_path):
    project, _ = processed
    copy = tmp_path / "project"
    shutil.copytree(project.folder / "results" / SURVEY, copy / "results" / SURVEY)
    (copy / "results" / SURVEY / QUALITY_FILE).unlink()
    assert load_results(copy, SURVEY).quality is None


@pytest.mark.skipif(shutil.which("pdftotext") is None, reason="poppler-utils (pdftotext) not installed")
def test_the_pdf_shows_the_predicted_accuracy_with_the_outage_section_weakest(processed, tmp_path):
    project, _ = processed
    stored = load_results(project.folder, SURVEY)
    path = write_pdf(project, stored, tmp_path / "report.pdf")
    text = subprocess.run(["pdftotext", "-layout", str(path), "-"], capture_output=True, text=True,
                          check=True).stdout
    assert "Predicted accuracy per section" in text
    station, labels = stored.columns["station_m"], stored.label
    inside = np.flatnonzero((station >= stored.quality.station_from_m[1]) & (station < stored.quality.station_to_m[1]))
    weakest = next(line for line in text.splitlines() if "weakest 1" in line)
    assert labels[inside[0]] in weakest
    assert f"{stored.quality.sigma_lag5_lateral_mm[1]:.2f}" in weakest


def test_the_gui_track_view_shades_the_predicted_accuracy_widest_at_the_outage(processed, window, qtbot):
    """The band behind the track plots: +-3 sigma per section, the outage section the widest."""
    import pyqtgraph as pg

    from insrail.project.plotdata import BAND_SIGMAS

    project, _ = processed
    assert window.open_project(project.folder)
    qtbot.waitUntil(lambda: window.loader is None, timeout=60_000)  # results are read in a worker
    stored = window.results[SURVEY]
    quality = stored.quality
    outage = quality.weakest("sigma_lag5_lateral_mm")
    plots = window.track.plots.plots
    expected = {"lateral_deviation": quality.sigma_lateral_mm,
                "check_short_wave_30m_5m": np.maximum(quality.sigma_lag5_lateral_mm, quality.sigma_lag5_vertical_mm),
                "check_long_wave_300m_150m": np.maximum(quality.sigma_lag150_lateral_mm,
                                                        quality.sigma_lag150_vertical_mm)}
    for key, sigma_mm in expected.items():
        fills = [item for item in plots[key].items if isinstance(item, pg.FillBetweenItem)]
        assert len(fills) == 1, key
        upper = fills[0].curves[0]
        x, y = upper.getData()
        np.testing.assert_allclose(x[::2], quality.station_from_m)
        np.testing.assert_allclose(y[::2], BAND_SIGMAS * sigma_mm, rtol=1e-9)
        assert "predicted" in plots[key].titleLabel.text
    half_width = next(item for item in plots["check_short_wave_30m_5m"].items
                      if isinstance(item, pg.FillBetweenItem)).curves[0].getData()[1][::2]
    assert int(np.argmax(half_width)) == outage
    assert not any(isinstance(item, pg.FillBetweenItem) for item in plots["gauge"].items)


def test_insrail_process_prints_the_predicted_accuracy(processed):
    from insrail.cli.process import describe

    project, _ = processed
    stored = load_results(project.folder, SURVEY)
    line = next(line for line in describe(stored) if line.startswith("  predicted accuracy (smoothed"))
    weakest = stored.quality.weakest_sections(1)[0]
    assert f"weakest {stored.quality.station_from_m[weakest]:.0f}.." in line
    assert f"5 m lag {stored.quality.sigma_lag5_lateral_mm[weakest]:.2f}/" in line.split("weakest")[1]


def test_the_workbook_summary_gives_the_predicted_accuracy_per_section(processed, tmp_path):
    from openpyxl import load_workbook

    from insrail.report import write_workbook

    project, _ = processed
    stored = load_results(project.folder, SURVEY)
    rows = [list(row) for row in load_workbook(write_workbook(project, stored, tmp_path / "q.xlsx"),
                                               read_only=True)["Summary"].iter_rows(values_only=True)]
    header = next(i for i, row in enumerate(rows) if "Predicted 1σ, 5 m lag difference, lateral (mm)" in row)
    column = rows[header].index("Predicted 1σ, 5 m lag difference, lateral (mm)")
    shown = [row[column] for row in rows[header + 1:header + 1 + len(stored.quality)]]
    np.testing.assert_allclose(shown, stored.quality.sigma_lag5_lateral_mm, atol=1e-9)
    assert rows[header].index("Predicted 1σ, 150 m lag difference, vertical (mm)") == column + 3


def fresh_copy(project, tmp_path, name: str):
    """A project of the same survey with nothing computed yet."""
    root = tmp_path / name
    shutil.copytree(project.folder / "surveys" / SURVEY, root / "surveys" / SURVEY)
    return root, project_for_simulated_survey(root, root / "surveys" / SURVEY)


RESULT_FILES = ("sleepers.csv", "quality.csv", "exceedances.csv", "trajectory.npy")


def test_the_analysis_beside_the_track_says_its_progress_forward_and_matches_the_serial_run(processed, tmp_path,
                                                                                          monkeypatch):
    """With two CPUs the covariance analysis runs in a thread beside the track reconstruction: every
    progress call comes from the calling thread, the fractions never go back, the analysis's progress
    is said within the track's step; with one CPU it runs before the track, and the results are the
    same to the byte."""
    project, _ = processed
    runs = {}
    for cpus in (2, 1):
        monkeypatch.setattr(background.os, "cpu_count", lambda: cpus)
        root, fresh = fresh_copy(project, tmp_path, f"cpus-{cpus}")
        said = []
        caller = threading.current_thread()
        process(fresh, SURVEY, progress=lambda f, m: said.append((f, str(m), threading.current_thread() is caller)))
        assert all(in_caller for _, _, in_caller in said)
        track = next(i for i, (_, m, _) in enumerate(said) if m == "rails, chainage and sleepers")
        analysis = [i for i, (_, m, _) in enumerate(said) if m.startswith("covariance")]
        assert analysis and (min(analysis) > track if cpus > 1 else max(analysis) < track)
        fractions = [f for f, _, _ in said[min(analysis[0], track):]]  # (the fusion's second pass starts again)
        assert fractions == sorted(fractions)
        assert not any(thread.name == "covariance analysis" for thread in threading.enumerate())
        runs[cpus] = root / "results" / SURVEY
    for name in RESULT_FILES:
        assert (runs[2] / name).read_bytes() == (runs[1] / name).read_bytes(), name
    assert list((runs[2].parent / ".cache").glob("fusion-*.quality.npz.sha256"))  # sealed


def test_cancelling_while_the_analysis_runs_beside_the_track_stops_both_and_caches_no_fusion(processed, tmp_path,
                                                                                          monkeypatch):
    project, _ = processed
    monkeypatch.setattr(background.os, "cpu_count", lambda: 2)
    root, fresh = fresh_copy(project, tmp_path, "cancelled")
    real = pipeline.recorded_quality
    running = threading.Event()

    def held(*args, cancel, **kwargs):  # still running when the track starts, until the cancel reaches it
        running.set()
        while not is_cancelled(cancel):
            time.sleep(0.01)
        return real(*args, cancel=cancel, **kwargs)

    monkeypatch.setattr(pipeline, "recorded_quality", held)
    messages = []
    with pytest.raises(Cancelled):
        process(fresh, SURVEY, progress=lambda f, m: messages.append(str(m)),
                cancel=lambda: "rails, chainage and sleepers" in messages)
    assert running.is_set()
    assert not any(thread.name == "covariance analysis" for thread in threading.enumerate())
    assert not list((root / "results" / ".cache").glob("fusion-*"))  # neither the trajectory nor its analysis
    assert not (root / "results" / SURVEY).exists()


def test_a_failure_of_the_analysis_beside_the_track_propagates_and_caches_no_fusion(processed, tmp_path,
                                                                                   monkeypatch):
    project, _ = processed
    monkeypatch.setattr(background.os, "cpu_count", lambda: 2)
    root, fresh = fresh_copy(project, tmp_path, "failed")

    def broken(*args, **kwargs):
        raise ValueError("the covariance store holds 3 segments, the fusion's timeline 5: it is not this fusion's record")

    monkeypatch.setattr(pipeline, "recorded_quality", broken)
    with pytest.raises(ValueError, match="the covariance store holds 3 segments"):
        process(fresh, SURVEY)
    assert not list((root / "results" / ".cache").glob("fusion-*"))
    assert not (root / "results" / SURVEY).exists()
