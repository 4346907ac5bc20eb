"""The banner over the views when they have nothing to show, saying why and offering what helps."""

from __future__ import annotations

from PySide6.QtCore import Signal
from PySide6.QtWidgets import QFrame, QHBoxLayout, QLabel, QPushButton


class EmptyState(QFrame):
    """"No results for survey X yet" with a Process button, or "no project open"."""

    processRequested = Signal(str)

    def __init__(self, parent=None):
        super().__init__(parent)
        self.setObjectName("empty_state")
        self.setFrameShape(QFrame.StyledPanel)
        self.setStyleSheet("#empty_state { background: #FFF8E1; }")
        self.message = QLabel()
        self.message.setWordWrap(True)
        self.process_button = QPushButton()
        self.process_button.clicked.connect(lambda: self.processRequested.emit(self.survey))
        layout = QHBoxLayout(self)
        layout.addWidget(self.message, 1)
        layout.addWidget(self.process_button)
        self.survey = ""
        self.show_no_project()

    def show_no_project(self) -> None:
        self.survey = ""
        self.message.setText("No project open. File > New project… creates one from raw files; "
                             "File > Open project… opens a project.toml.")
        self.process_button.hide()
        self.show()

    def show_loading(self, project: str) -> None:
        self.survey = ""
        self.message.setText(f"Reading the results of {project}…")
        self.process_button.hide()
        self.show()

    def show_unprocessed(self, survey: str | None) -> None:
        """The survey shown has no results (None: the project has no survey at all)."""
        if survey is None:
            self.survey = ""
            self.message.setText("This project has no survey yet: File > Import raw files… adds one.")
            self.process_button.hide()
        else:
            self.survey = survey
            self.message.setText(f"Survey {survey} has no results yet: the track, plan and navigation views "
                                 "stay empty until it is processed.")
            self.process_button.setText(f"Process {survey}")
            self.process_button.show()
        self.show()
