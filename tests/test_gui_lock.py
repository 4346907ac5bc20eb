"""The GUI's Process while another process holds the survey's lock (insrail.project.lock): the window
says whom it waits for, goes on when the holder ends, and Cancel ends the run cleanly.

The project is written the way a user writes one (tests/survey_builder.py); the holder is a real
separate process. Every modal dialog is replaced by a recorder: offscreen, a dialog would block the
test forever, and none may appear here anyway.
"""

from __future__ import annotations

import pytest
from survey_builder import SURVEY_NAME, Cell, built_cell_copy
from test_project_lock import hold_in_child

pytest.importorskip("pytestqt")
from PySide6.QtWidgets import QDialog, QMessageBox

from insrail.project.lock import ProjectBusy, project_run, waiting_policy

WAIT_S = 60
#: The survey (simulated once per test run; test_gauge_volts processes the same one)
CELL = Cell("nav", "rtklib-pos", "CGCS2000", "csv", "with", "none", "minimal")


@pytest.fixture
def no_dialogs(monkeypatch):
    """Every dialog the window could open is recorded and answered at once (never shown)."""
    shown = []

    def record(*args, **kwargs):
        shown.append(args[1:3])
        return QMessageBox.Cancel

    for name in ("critical", "warning", "question", "information", "about"):
        monkeypatch.setattr(QMessageBox, name, record)
    monkeypatch.setattr(QMessageBox, "exec", lambda self: shown.append(("exec", self.text())) or QMessageBox.Cancel)
    monkeypatch.setattr(QDialog, "exec", lambda self: shown.append(("exec", type(self).__name__)) or 0)
    return shown


def test_process_waits_for_a_run_of_another_process_says_for_whom_and_goes_on(window, qtbot, no_dialogs, tmp_path):
    built = built_cell_copy(CELL, tmp_path, seed=7)
    assert window.open_project(built.project / "project.toml")
    qtbot.waitUntil(lambda: window.loader is None, timeout=WAIT_S * 1000)

    holder = hold_in_child(built.project, SURVEY_NAME)  # as a CLI `insrail process` of the survey would
    try:
        assert window.process() is not None
        qtbot.waitUntil(lambda: "waiting for the run started at" in window.status.text(), timeout=WAIT_S * 1000)
        status = window.status.text()
        assert status.startswith(f"{SURVEY_NAME}: waiting for the run started at ")
        assert f"by PID {holder.pid}" in status
        assert status in window.log.toPlainText()  # the log keeps it after the status bar moves on
        qtbot.wait(1000)  # the run still waits, the window answers meanwhile
        assert window.worker is not None and window.worker.isRunning()
        assert window.cancel_button.isVisible() and window.cancel_button.isEnabled()
        assert window.status.text() == status
    finally:
        holder.kill()
        holder.wait()

    # the holder gone, the run takes the lock and goes on to its stages
    qtbot.waitUntil(lambda: "height model" in window.log.toPlainText(), timeout=WAIT_S * 1000)
    window.cancel_button.click()
    qtbot.waitUntil(lambda: window.worker is None, timeout=WAIT_S * 1000)
    assert "processing cancelled; previous results kept" in window.log.toPlainText()
    assert not (built.project / "results" / SURVEY_NAME / "summary.toml").exists()
    assert no_dialogs == []
    with waiting_policy(wait=False), project_run(built.project, [SURVEY_NAME]):  # the GUI let go of the lock
        pass


def test_process_cancelled_while_waiting_for_the_lock_ends_cleanly(window, qtbot, no_dialogs, tmp_path):
    built = built_cell_copy(CELL, tmp_path, seed=7)
    assert window.open_project(built.project / "project.toml")
    qtbot.waitUntil(lambda: window.loader is None, timeout=WAIT_S * 1000)
    holder = hold_in_child(built.project, SURVEY_NAME)
    try:
        window.process()
        qtbot.waitUntil(lambda: f"by PID {holder.pid}" in window.status.text(), timeout=WAIT_S * 1000)
        window.cancel_button.click()
        qtbot.waitUntil(lambda: window.worker is None, timeout=WAIT_S * 1000)  # Cancel is looked at while waiting
        assert "processing cancelled; previous results kept" in window.log.toPlainText()
        assert "height model" not in window.log.toPlainText()  # it never went past the lock
        assert no_dialogs == []
        with pytest.raises(ProjectBusy), waiting_policy(wait=False), project_run(built.project, [SURVEY_NAME]):
            pass  # the holder still has it: the GUI took nothing from it
    finally:
        holder.kill()
        holder.wait()
