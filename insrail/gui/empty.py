"""The banner over the views when they have nothing to show, saying why and offering what helps."""

from __future__ import annotations

from PySide6.QtCore import Signal
from PySide6.QtWidgets import QFrame, QHBoxLayout, QLabel, QPushButton
from insrail.gui.translation import tr


class Banner(QFrame):
    """A coloured strip over the views: a message and the button that helps."""

    def __init__(self, name: str, background: str, parent=None):
        super().__init__(parent)
        self.setObjectName(name)
        self.setFrameShape(QFrame.StyledPanel)
        self.setStyleSheet(f"#{name} {{ background: {background}; }}")
        self.message = QLabel()
        self.message.setWordWrap(True)
        self.button = QPushButton()
        layout = QHBoxLayout(self)
        layout.addWidget(self.message, 1)
        layout.addWidget(self.button)


class EmptyState(Banner):
    """"No results for survey X yet" with a Process button, or "no project open"."""

    processRequested = Signal(str)

    def __init__(self, parent=None):
        super().__init__("empty_state", "#FFF8E1", parent)
        self.process_button = self.button
        self.process_button.clicked.connect(lambda: self.processRequested.emit(self.survey))
        self.survey = ""
        self.show_no_project()

    def show_no_project(self) -> None:
        self.survey = ""
        self.message.setText(tr("No project open. File > New project… creates one from raw files; "
                             "File > Open project… opens a project.toml."))
        self.process_button.hide()
        self.show()

    def show_loading(self, project: str) -> None:
        self.survey = ""
        self.message.setText(tr("Reading the results of {project}…").format(project=project))
        self.process_button.hide()
        self.show()

    def show_unprocessed(self, survey: str | None) -> None:
        """The survey shown has no results (None: the project has no survey at all)."""
        if survey is None:
            self.survey = ""
            self.message.setText(tr("This project has no survey yet: File > Import raw files… adds one."))
            self.process_button.hide()
        else:
            self.survey = survey
            self.message.setText(tr("Survey {survey} has no results yet: the track, plan and navigation views stay "
                                    "empty until it is processed.").format(survey=survey))
            self.process_button.setText(tr("Process {survey}").format(survey=survey))
            self.process_button.show()
        self.show()


class StaleReportsBanner(Banner):
    """"The reports of survey X are older than its results" with a button writing them again
    (:mod:`insrail.report.stale` decides what is stale); hidden while every report is current."""

    rewriteRequested = Signal()

    def __init__(self, parent=None):
        super().__init__("stale_reports", "#FDE7E7", parent)
        self.rewrite_button = self.button
        self.rewrite_button.setToolTip(tr("Write the out-of-date reports again, at their places, from the current "
                                       "results"))
        self.rewrite_button.clicked.connect(self.rewriteRequested)
        self.stale: list[str] = []
        self.hide()

    def show_stale(self, survey: str | None, names: list[str]) -> None:
        """The out-of-date report files of the survey shown ([]: the banner goes)."""
        self.stale = list(names)
        if not names:
            self.hide()
            return
        one = len(names) == 1
        self.message.setText("⚠ " + (tr("The report {names} of survey {survey} was written before the survey was "
                                        "processed again: it describes results that no longer exist.") if one else
                                     tr("The reports {names} of survey {survey} were written before the survey was "
                                        "processed again: they describe results that no longer exist.")).format(
            names=tr(" and ").join(names), survey=survey))
        self.rewrite_button.setText(tr("Write it again") if one else tr("Write them again"))
        self.show()


class ResultsOlderThanEventsBanner(Banner):
    """"Survey X was processed before the event file changed" with Process
    (:func:`insrail.project.event_marking.results_older_than_events` decides); hidden otherwise."""

    processRequested = Signal(str)

    def __init__(self, parent=None):
        super().__init__("results_older_than_events", "#FFF8E1", parent)
        self.process_button = self.button
        self.process_button.clicked.connect(lambda: self.processRequested.emit(self.survey))
        self.survey = ""
        self.hide()

    def show_older(self, survey: str | None, events_file: str = "") -> None:
        """The survey shown, when its results are older than ``events_file`` (None: the banner goes)."""
        self.survey = survey or ""
        if not survey:
            self.hide()
            return
        self.message.setText("⚠ " + tr("Survey {survey} was processed before its events ({events}) changed: its "
                                       "results, plots and exceedances do not show them yet. Process it again.").format(
            survey=survey, events=events_file))
        self.process_button.setText(tr("Process {survey}").format(survey=survey))
        self.show()
