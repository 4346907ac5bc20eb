"""The "Mark as track event" dialog: kind, chainage range and a note for a span of the track view,
checked as typed (the problems beside their fields) and appended to the project's event file by
:func:`insrail.project.event_marking.mark_event` (the core writes; this only asks)."""

from __future__ import annotations

import math

from PySide6.QtCore import Qt
from PySide6.QtWidgets import (
    QComboBox,
    QDialog,
    QDialogButtonBox,
    QFormLayout,
    QLabel,
    QLineEdit,
    QVBoxLayout,
)

from insrail.io.errors import InputError, said
from insrail.io.events import EVENT_KINDS, Event, EventList, event_problems
from insrail.project.event_marking import DEFAULT_EVENTS_FILE, mark_event
from insrail.project.model import Project
from insrail.names import t
from insrail.track.events import KIND_NAMES
from insrail.gui.translation import tr

PROBLEM_STYLE = "color: #B00020;"


class EventDialog(QDialog):
    """Mark ``from_m``–``to_m`` (stations, as the measuring tool selected them) as an event of ``project``.
    After ``accept``: ``project`` names its event file and ``events`` holds the file as read back."""

    def __init__(self, project: Project, from_m: float, to_m: float, parent=None):
        super().__init__(parent)
        self.setWindowTitle(tr("Mark as track event"))
        self.project = project
        self.events: EventList | None = None
        self.kind = QComboBox()
        for kind in EVENT_KINDS:
            self.kind.addItem(t(KIND_NAMES[kind]).capitalize(), kind)
        self.kind.setToolTip("\n".join(f"{t(KIND_NAMES[k]).capitalize()}: {t(what)}" for k, what in EVENT_KINDS.items()))
        low, high = sorted((from_m, to_m))
        self.start = QLineEdit(f"{low:.3f}")
        self.end = QLineEdit(f"{high:.3f}")
        self.end.setPlaceholderText(tr("empty: a point (a joint, a note)"))
        self.text = QLineEdit()
        self.text.setPlaceholderText(tr("optional: W12 No. 18 right-hand, LC 3, …"))
        self.problems = {name: QLabel() for name in ("kind", "from", "to", "text")}
        form = QFormLayout()
        for label, field, name in ((tr("Kind"), self.kind, "kind"), (tr("From station [m]"), self.start, "from"),
                                   (tr("To station [m]"), self.end, "to"), (tr("Note"), self.text, "text")):
            form.addRow(label, field)
            problem = self.problems[name]
            problem.setStyleSheet(PROBLEM_STYLE)
            problem.setWordWrap(True)
            problem.hide()
            form.addRow("", problem)
        target = project.events or tr("{file} (new; the project will name it)").format(file=DEFAULT_EVENTS_FILE)
        self.where = QLabel(tr("Appended to the project's event file {file}; the surveys need processing again to "
                               "assess with it.").format(file=target))
        self.where.setWordWrap(True)
        self.general = QLabel()
        self.general.setStyleSheet(PROBLEM_STYLE)
        self.general.setWordWrap(True)
        self.general.setTextInteractionFlags(Qt.TextSelectableByMouse)
        self.general.hide()
        self.buttons = QDialogButtonBox(QDialogButtonBox.Ok | QDialogButtonBox.Cancel)
        self.buttons.button(QDialogButtonBox.Ok).setText(tr("Mark"))
        self.buttons.accepted.connect(self.accept)
        self.buttons.rejected.connect(self.reject)
        layout = QVBoxLayout(self)
        layout.addLayout(form)
        layout.addWidget(self.where)
        layout.addWidget(self.general)
        layout.addWidget(self.buttons)
        for field in (self.start, self.end, self.text):
            field.textChanged.connect(self.check)
        self.kind.currentIndexChanged.connect(self.check)
        self.check()

    def set_kind(self, kind: str) -> None:
        self.kind.setCurrentIndex(self.kind.findData(kind))

    def typed_event(self) -> Event | None:
        """The event as typed, None while a chainage is not a number (:meth:`check` says which)."""
        try:
            start = float(self.start.text())
            end = start if not self.end.text().strip() else float(self.end.text())
        except ValueError:
            return None
        return Event(self.kind.currentData(), start, end, "station_m", text=self.text.text().strip())

    def check(self) -> dict[str, str]:
        """The problems of the fields as typed, shown beside them; Mark is enabled without any."""
        problems: dict[str, str] = {}
        for name, field, may_be_empty in (("from", self.start, False), ("to", self.end, True)):
            text = field.text().strip()
            if not text and may_be_empty:
                continue
            try:
                value = float(text)
            except ValueError:
                problems[name] = (tr("expected a station in metres, found {text}").format(text=repr(text)) if text
                                  else tr("a station is needed"))
                continue
            if not math.isfinite(value):
                problems[name] = tr("expected a finite station, found {text}").format(text=repr(text))
        event = self.typed_event()
        if not problems and event is not None:
            problems = event_problems(event)
        for name, label in self.problems.items():
            label.setText(problems.get(name, ""))
            label.setVisible(name in problems)
        self.buttons.button(QDialogButtonBox.Ok).setEnabled(not problems)
        return problems

    def accept(self) -> None:
        if self.check():
            return
        try:
            self.project, self.events = mark_event(self.project, self.typed_event())
        except (InputError, OSError, ValueError) as error:
            self.general.setText(tr("Not marked: {error}").format(error=said(error)))
            self.general.show()
            return
        super().accept()
