"""The Plan survey dialog and the GNSS page, driven through the real main window (pytest-qt, offscreen).

Predictions stay short (200 to 300 m); the raw-GNSS survey is the simulated `short` cut to a few
minutes with a 15 s outage, so RTKLIB runs in a couple of seconds.
"""

from __future__ import annotations

import inspect
import shutil
from dataclasses import replace

import numpy as np
import pytest

pytest.importorskip("pytestqt")

from gui_wait import wait_for_worker
from real_data import REAL

from insrail.gui.choices import choose
from insrail.io.survey import read_manifest
from insrail.nav.fusion import FusionOptions
from insrail.project import load_project, save_project
from insrail.project.control_points import ControlPoint
from insrail.project.demo import project_for_simulated_survey
from insrail.project.gnss_stage import GNSS_POS_FILE, GNSS_QC_FILE, run_gnss_stage
from insrail.quality import GnssQuality, predict
from insrail.quality.sweep import sweep
from insrail.quality.tables import accuracy_rows
from insrail.sim.gnss_obs import convert_survey_to_raw_gnss
from insrail.sim.scenario import preset
from insrail.sim.simulate import simulate

NAV = REAL / "rinex_0759_3040" / "07590920.05n"


def table_rows(table) -> list[list[str]]:
    return [[table.item(r, c).text() for c in range(table.columnCount())] for r in range(table.rowCount())]


def recording(monkeypatch, name: str) -> list:
    """The dialog's calls of ``insrail.gui.plan_survey.<name>`` (predict or sweep): each call's arguments bound
    to the function's parameters (without its progress and cancel) and its result. The test compares them with
    the call it expects instead of computing the prediction a second time (deterministic: the same figures)."""
    from insrail.gui import plan_survey

    function = getattr(plan_survey, name)
    calls = []

    def recorded(*args, **kwargs):
        bound = inspect.signature(function).bind(*args, **kwargs)
        result = function(*args, **kwargs)
        calls.append((_inputs(bound), result))
        return result

    monkeypatch.setattr(plan_survey, name, recorded)
    return calls


def _inputs(bound: inspect.BoundArguments) -> dict:
    bound.apply_defaults()
    return {key: value for key, value in bound.arguments.items() if key not in ("progress", "cancel")}


def inputs_of(function, *args, **kwargs) -> dict:
    """What a call ``function(*args, **kwargs)`` passes, as :func:`recording` holds it."""
    return _inputs(inspect.signature(function).bind(*args, **kwargs))


def test_plan_survey_shows_the_figures_of_predict(window, qtbot, monkeypatch):
    calls = recording(monkeypatch, "predict")
    dialog = window.plan_survey()
    assert dialog.isVisible() and window.plan_survey() is dialog  # one dialog, raised again
    choose(dialog.imu, "tactical")
    dialog.gnss_horizontal.setValue(15.0)
    dialog.gnss_vertical.setValue(30.0)
    dialog.speed.setValue(2.0)
    dialog.length.setValue(300.0)
    dialog.outage.setValue(20.0)
    dialog.nhc.setChecked(False)
    dialog.run_button.click()
    assert not dialog.run_button.isEnabled() and dialog.cancel_button.isEnabled()
    wait_for_worker(qtbot, dialog)  # as long as it reports progress: under load it took over 30 s

    ((inputs, expected),) = calls
    assert inputs == inputs_of(predict, "tactical", GnssQuality(0.015, 0.030), FusionOptions(use_nhc=False),
                               speed_mps=2.0, length_m=300.0, outages=((150.0, 20.0),))
    rows = accuracy_rows(expected.smoothed, with_outage=True)
    shown = table_rows(dialog.table)
    assert [r[0] for r in shown] == [row.label for row in rows]
    assert [r[1] for r in shown] == [f"{row.sigma_mm:.3f}" for row in rows]
    assert [r[2] for r in shown] == [f"{row.three_sigma_mm:.3f}" for row in rows]
    assert [r[4] for r in shown] == [row.verdict for row in rows]
    assert {"ok", "exceeds the limit at 3 sigma"} >= {r[4] for r in shown if r[3]}
    assert dialog.heading.text() == ("Predicted accuracy, smoothed solution: IMU tactical, GNSS 15/30 mm, "
                                     "2 m/s, 300 m, 20 s outage at 150 m")
    assert dialog.plot.isHidden() and dialog.message.text() == "done"


def test_plan_survey_sweep_table_and_plot(window, qtbot, monkeypatch):
    calls = recording(monkeypatch, "sweep")
    dialog = window.plan_survey()
    dialog.length.setValue(200.0)
    dialog.smoothed.setCurrentIndex(1)  # forward filter
    dialog.sweep.setCurrentIndex(dialog.sweep.findData("speed"))
    assert dialog.sweep.currentText() == "Pushing speed"  # the parameter in words (insrail.names)
    assert dialog.sweep_values.placeholderText().startswith("0.25 0.5 1 2 5")
    dialog.sweep_values.setText("1 x")
    assert dialog.run() is None and "sweep values" in dialog.message.text()
    dialog.sweep_values.setText("1, 3")
    dialog.run()
    wait_for_worker(qtbot, dialog)

    ((inputs, expected),) = calls
    assert inputs == inputs_of(sweep, "speed", (1.0, 3.0), "nav", GnssQuality(), speed_mps=1.0,
                               aiding=FusionOptions(smoother=False), length_m=200.0, outages=())
    shown = table_rows(dialog.table)
    assert [dialog.table.horizontalHeaderItem(c).text() for c in (2, 3)] == ["1 m/s", "3 m/s"]
    assert shown[4][0] == "30 m/5 m vertical (5 m lag)" and shown[4][1] == "2.0"
    assert [shown[4][2], shown[4][3]] == [f"{1e3 * f.lag5_vertical_m:.3f}" for f in expected.forward]
    assert dialog.plot.isVisible()
    curves = dialog.plot.getPlotItem().listDataItems()
    assert len(curves) == 5
    x, y = curves[0].getOriginalDataset()  # 3 sigma of the 5 m lag, lateral
    assert list(x) == [1.0, 3.0] and np.allclose(y, [3e3 * f.lag5_lateral_m for f in expected.forward])


def test_plan_survey_cancel(window, qtbot):
    dialog = window.plan_survey()
    dialog.length.setValue(30_000.0)  # about a minute of computing
    dialog.run()
    wait_for_worker(qtbot, dialog, until=lambda: dialog.progress.value() > 0)
    assert dialog.worker is not None, "the minute of computing ended before it could be cancelled"
    dialog.cancel_button.click()
    wait_for_worker(qtbot, dialog)
    assert dialog.message.text() == "cancelled" and dialog.result is None and dialog.run_button.isEnabled()


# --------------------------------------------------------------------------- GNSS page

@pytest.fixture(scope="module")
def raw_gnss_project(tmp_path_factory):
    """A project whose survey holds rover/base RINEX: `short` cut to 1100 m after a 60 s static
    start, on the navigation file's day, with a 15 s GNSS outage (about 3 minutes)."""
    root = tmp_path_factory.mktemp("gui-raw-gnss")
    folder = root / "surveys" / "short"
    config = preset("short", gps_week=1316, start_time_s=558000.0025)
    motion = replace(config.motion, end_station_m=1100.0, static_start_s=60.0, static_end_s=20.0, stops=())
    config = replace(config, motion=motion, gnss=replace(config.gnss, outages=((1060.0, 15.0),)))
    simulate(config, seed=5, out_dir=folder)
    raw = convert_survey_to_raw_gnss(folder, config, NAV, seed=6)
    project = project_for_simulated_survey(root, folder)
    save_project(replace(project, control_points=(ControlPoint(raw.base_point, engineering=raw.base_enh_m),)))
    return root


def test_gnss_page_runs_ppk_and_shows_the_stage_qc(window, qtbot, raw_gnss_project, tmp_path):
    root = tmp_path / "project"
    shutil.copytree(raw_gnss_project, root)
    assert window.open_project(root)
    page = window.gnss
    assert window.tabs.isTabVisible(window.tabs.indexOf(page)) and page.survey.currentText() == "short"
    assert page.inputs.value("Files", "rover (RINEX)") == "rover.obs"
    assert page.inputs.value("Files", "navigation") == NAV.name
    assert page.inputs.value("Base", "base point") == "CPII-BASE"
    assert page.inputs.value("Base", "antenna height (ARP)") == "1.5500 m"
    assert page.headline.text().startswith("Not post-processed yet") and window.ppk_action.isEnabled()
    assert not window.export_pdf_action.isEnabled()  # nothing processed

    window.ppk_action.trigger()  # cancelled at once: RTKLIB's child process is stopped
    window.cancel_button.click()
    qtbot.waitUntil(lambda: window.worker is None, timeout=30_000)
    assert "GNSS post-processing cancelled" in window.log.toPlainText()
    assert page.shown is None and not list((root / "results" / ".cache").glob("ppk-*"))

    window.ppk_action.trigger()
    assert window.tabs.currentWidget() is page and not window.ppk_action.isEnabled()
    qtbot.waitUntil(lambda: window.worker is None, timeout=60_000)
    project = load_project(root)
    stage = run_gnss_stage(project, root / "surveys" / "short", read_manifest(root / "surveys" / "short"),
                           root / "results" / ".cache")
    assert stage.from_cache  # the page's run filled the pipeline's cache
    fix_rate = f"{100.0 * stage.qc.fix_rate:.1f} %"
    assert page.qc.value("Solution", "fix rate") == fix_rate and f"Fix rate {fix_rate}" in page.headline.text()
    assert page.shown.report["qc"]["fix_rate"] == stage.qc.fix_rate
    assert page.qc.value("Epochs by quality", "fix").startswith(f"{stage.qc.epochs_by_quality['fix']} (")
    assert "fusion: sigma x 1" in page.qc.value("Epochs by quality", "fix")
    assert page.qc.value("Gaps", "+" + f"{stage.qc.gaps[0].start_s - stage.qc.first_s:.0f} s").endswith("(16 s)")
    assert page.qc.value("Base", "baseline") == f"{stage.report['baseline_m'] / 1e3:.3f} km"
    assert page.qc.value("Warnings", "") == "none"
    plotted = sum(len(item.getOriginalDataset()[0]) for item in page.quality_plot.listDataItems())
    assert plotted == stage.qc.epochs
    assert f"fix rate {fix_rate} of {stage.qc.epochs} epochs (computed now)" in window.log.toPlainText()

    # After processing, the page reads the survey's results (here put there as the pipeline does).
    results = root / "results" / "short"
    results.mkdir()
    shutil.copy(stage.pos_file, results / GNSS_POS_FILE)
    shutil.copy(stage.qc_file, results / GNSS_QC_FILE)
    window.show_gnss("short")
    assert page.headline.text().endswith("(from the processed results)")
    assert page.qc.value("Solution", "fix rate") == fix_rate
