"""Run > Re-design for tamping in the desktop application: the core's re-design in a worker with
progress, then the re-design view (measured and re-designed track, lift and slew) from its files."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("pytestqt")

from insrail.export.tamping import read_tamping
from tests.test_gui_app import demo_project, processed_copy, wait_views  # noqa: F401 (demo_project: a fixture)


def test_redesign_runs_in_a_worker_and_the_view_draws_the_files(window, qtbot, demo_project, tmp_path):  # noqa: F811
    root = processed_copy(demo_project, tmp_path / "copy")
    assert not window.redesign_action.isEnabled()  # nothing shown yet
    assert window.open_project(root)
    wait_views(window, qtbot)
    view = window.redesign_view
    assert view.data is None and view.note.text().startswith("No re-design of this survey")
    assert window.redesign_action.isEnabled()

    window.redesign_action.trigger()
    assert window.progress.isVisible() and not window.redesign_action.isEnabled()  # one job at a time
    qtbot.waitUntil(lambda: window.worker is None, timeout=300_000)
    assert window.tabs.currentWidget() is view
    data = view.data
    assert data is not None and data.survey == "short"
    assert "re-designed: largest lift" in window.log.toPlainText()

    # the view draws tamping.csv's amounts at the sleepers, and the measured track moved by them
    table = read_tamping(root / "results" / "short" / "redesign" / "tamping.csv")
    sleeper = np.array([m == "" for m in table.mark])
    assert np.nanmax(data.lift_left_mm) == pytest.approx(table.values["lift_left"][sleeper].max())
    assert np.nanmax(np.abs(data.slew_mm)) == pytest.approx(np.abs(table.values["slew"][sleeper]).max())
    lift = 0.5 * (data.lift_left_mm + data.lift_right_mm)
    assert np.allclose(data.after_mm["vertical"] - data.measured_mm["vertical"], lift, equal_nan=True)
    assert np.nanmin(data.lift_left_mm) >= 0.0  # lift only
    assert [len(item.listDataItems()) for item in view.items] == [2, 2, 3]
    assert str(data.exceedances_before) in view.note.text()

    # opened again, the survey shows its stored re-design
    window.modified = False
    assert window.open_project(root)
    wait_views(window, qtbot)
    assert window.redesign_view.data is not None
    assert np.allclose(window.redesign_view.data.slew_mm, data.slew_mm, equal_nan=True)
