"""Project settings editor: the project.toml of the open project as a form.

Every committed edit is one undoable step (QUndoStack; the main window's Edit menu carries Undo
and Redo while the editor is open). A number field commits what was typed when it is left or on
Return, never at each key: an edit at each key set the field again and reformatted it under the
typing hand (``-1.45`` became -1.4000). A value is compared with the document's at the precision its
field shows, so a value of project.toml with more decimals than its field is kept as written unless
it is changed. A setting not given shows "not given", never the field's lowest number. After every edit the whole document is checked by the core exactly as loading checks it
(:func:`insrail.project.project_from_settings`) and each problem is shown beside its field in the
field's words; Save writes project.toml atomically (:func:`insrail.project.save_project`) only
when there is none. The form says which processing stages the changes will run again (the stage
cache keys of :mod:`insrail.project.pipeline` hold the same settings).
"""

from __future__ import annotations

import copy
import datetime
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from PySide6.QtCore import Qt, Signal
from PySide6.QtGui import QUndoCommand, QUndoStack
from PySide6.QtWidgets import (
    QCheckBox,
    QComboBox,
    QDialog,
    QDialogButtonBox,
    QFormLayout,
    QHBoxLayout,
    QLabel,
    QLineEdit,
    QPushButton,
    QScrollArea,
    QSpinBox,
    QTabWidget,
    QVBoxLayout,
    QWidget,
)

from insrail.geodesy.crs import CUSTOM_ELLIPSOID, ELLIPSOIDS, PROJECTION_HEIGHT_CONVENTIONS
from insrail.gui.choices import choose, chosen, fill
from insrail.gui.fields import split_problem
from insrail.gui.forms import NOTE_STYLE, spin_box
from insrail.gui.importer import shipped_names
from insrail.io.errors import InputError, said
from insrail.io.survey import read_manifest
from insrail.names import LANGUAGES, RESOURCE_SETTINGS, joined, setting_name
from insrail.project import (
    HEIGHT_MODELS,
    Project,
    ProjectError,
    project_from_settings,
    save_project,
)
from insrail.project.model import (
    FUSION_FLAGS,
    FUSION_NUMBERS,
    PAPER_SIZES,
    ReportSettings,
)
from insrail.track.tolerance import shipped_tolerance_profiles
from insrail.gui.translation import tr, tr_noop

EACH_SURVEY = tr_noop("(each survey's own)")
#: What a number field of a setting absent from project.toml shows (optional ones: "none").
NOT_GIVEN = tr_noop("not given")
#: The columns of a lever arm: the trolley's body frame b (x forward, y right, z down: FRD).
FRD_AXES = (tr_noop("forward"), tr_noop("right"), tr_noop("down"))
#: The columns of the mounting angles.
RPY_AXES = (tr_noop("roll"), tr_noop("pitch"), tr_noop("heading"))
#: The processing stages in their order; a change reruns the first stage it feeds and all after it.
STAGES = (tr_noop("fusion"), tr_noop("track reconstruction"), tr_noop("assessment"), tr_noop("adjustment"))
#: Key path prefix -> the first stage that reads it (none: only the reports change).
FIRST_STAGE = (("trolley", "fusion"), ("processing", "fusion"), ("geodesy", "track reconstruction"),
               ("track.design", "track reconstruction"), ("track.start_station_m", "track reconstruction"),
               ("track.first_sleeper_number", "track reconstruction"),
               ("track.stationing_direction", "track reconstruction"), ("track.line_speed_kmh", "assessment"),
               ("track.tolerance_profile", "assessment"), ("track.fastener", "adjustment"))


def stages_to_rerun(changed_keys) -> tuple[str, ...]:
    """The stages the changed settings make run again (the earlier ones come from the cache)."""
    first = len(STAGES)
    for key in changed_keys:
        for prefix, stage in FIRST_STAGE:
            if key == prefix or key.startswith(prefix + "."):
                first = min(first, STAGES.index(stage))
    return STAGES[first:]


@dataclass(frozen=True)
class Field:
    """One editable setting: ``key`` its project.toml key path, ``kind`` text, file, date, number,
    int, bool, choice or vector (3 numbers); ``optional`` removes the key when left empty, as does
    choosing ``default`` (the value the core takes when the key is absent)."""

    tab: str
    key: str
    kind: str
    choices: Callable[[], list[str]] | tuple[str, ...] = ()
    decimals: int = 3
    suffix: str = ""
    optional: bool = False
    default: str | None = None


_ARMS = ("imu_to_antenna_m", "imu_to_odometer_m", "imu_to_odometer_right_m", "imu_to_reference_rail_m",
         "imu_to_sleeper_detector_m", "imu_to_prism_m")
FIELDS = (
    Field(tr_noop("Project"), "project.name", "text"),
    Field(tr_noop("Project"), "project.description", "text"),
    Field(tr_noop("Coordinate system"), "geodesy.crs.ellipsoid", "choice", (*ELLIPSOIDS, CUSTOM_ELLIPSOID)),
    # only with ellipsoid = "custom" (the core refuses them beside a named ellipsoid)
    Field(tr_noop("Coordinate system"), "geodesy.crs.a_m", "number", suffix=" m", optional=True),
    Field(tr_noop("Coordinate system"), "geodesy.crs.inverse_flattening", "number", decimals=9, optional=True),
    Field(tr_noop("Coordinate system"), "geodesy.crs.central_meridian_deg", "number", decimals=6, suffix=" °"),
    Field(tr_noop("Coordinate system"), "geodesy.crs.latitude_of_origin_deg", "number", decimals=6, suffix=" °"),
    Field(tr_noop("Coordinate system"), "geodesy.crs.scale_factor", "number", decimals=9),
    Field(tr_noop("Coordinate system"), "geodesy.crs.false_easting_m", "number", suffix=" m"),
    Field(tr_noop("Coordinate system"), "geodesy.crs.false_northing_m", "number", suffix=" m"),
    Field(tr_noop("Coordinate system"), "geodesy.crs.projection_height_m", "number", suffix=" m"),
    Field(tr_noop("Coordinate system"), "geodesy.crs.projection_height_convention", "choice",
          tuple(PROJECTION_HEIGHT_CONVENTIONS)),
    Field(tr_noop("Heights"), "geodesy.height.benchmarks", "file", optional=True),
    Field(tr_noop("Heights"), "geodesy.height.model", "choice", tuple(HEIGHT_MODELS)),
    *(Field(tr_noop("Trolley"), f"trolley.{arm}", "vector", decimals=4, suffix=" m") for arm in _ARMS),
    Field(tr_noop("Trolley"), "trolley.mounting_rpy_deg", "vector", decimals=4, suffix=" °"),
    Field(tr_noop("Trolley"), "trolley.reference_rail", "choice", ("left", "right")),
    Field(tr_noop("Trolley"), "trolley.rail_centre_spacing_m", "number", decimals=4, suffix=" m"),
    Field(tr_noop("Trolley"), "trolley.beam_wheel_spacing_m", "number", decimals=4, suffix=" m", optional=True),
    Field(tr_noop("Processing"), "processing.imu_profile", "choice", lambda: shipped_names("imu_profiles"),
          optional=True),
    *(Field(tr_noop("Processing"), f"processing.{flag}", "bool") for flag in FUSION_FLAGS),
    *(Field(tr_noop("Processing"), f"processing.{number}", "number", decimals=6) for number in FUSION_NUMBERS),
    Field(tr_noop("Track"), "track.design", "file", optional=True),
    Field(tr_noop("Track"), "track.start_station_m", "number", optional=True),
    Field(tr_noop("Track"), "track.first_sleeper_number", "int"),
    Field(tr_noop("Track"), "track.tolerance_profile", "choice", shipped_tolerance_profiles),
    Field(tr_noop("Track"), "track.fastener", "choice", lambda: shipped_names("fastener_types")),
    *(Field(tr_noop("Report"), f"report.{name}", "text", optional=True)
      for name in ("client", "line_section", "track_name", "operator", "checked_by", "approved_by", "trolley")),
    Field(tr_noop("Report"), "report.trolley_calibrated", "date", optional=True),
    Field(tr_noop("Report"), "report.imu", "text", optional=True),
    Field(tr_noop("Report"), "report.imu_calibrated", "date", optional=True),
    Field(tr_noop("Report"), "report.paper", "choice", PAPER_SIZES, default=ReportSettings().paper),
    Field(tr_noop("Report"), "report.language", "choice", tuple(LANGUAGES), default=ReportSettings().language),
)
_MISSING = object()


def get_value(document: dict, key: str):
    node = document
    for part in key.split("."):
        if not isinstance(node, dict) or part not in node:
            return _MISSING
        node = node[part]
    return node


def set_value(document: dict, key: str, value) -> None:
    """Set (or with ``_MISSING`` remove) a key path of the document."""
    *parents, last = key.split(".")
    node = document
    for part in parents:
        node = node.setdefault(part, {})
    if value is _MISSING:
        node.pop(last, None)
    else:
        node[last] = value


def changed_keys(before: dict, after: dict) -> list[str]:
    return [f.key for f in FIELDS if get_value(before, f.key) != get_value(after, f.key)]


class SetSetting(QUndoCommand):
    """One committed edit of one setting (one undo step)."""

    def __init__(self, editor: SettingsEditor, key: str, before, after):
        super().__init__(f"{setting_name(key)}")
        self.editor, self.key, self.before, self.after = editor, key, before, after

    def redo(self) -> None:
        self.editor.apply(self.key, self.after)

    def undo(self) -> None:
        self.editor.apply(self.key, self.before)


class SettingsEditor(QDialog):
    """Edit the open project's settings; ``saved(Project)`` after Save wrote project.toml."""

    saved = Signal(object)

    def __init__(self, project: Project, parent=None):
        super().__init__(parent)
        self.setWindowTitle(tr("Project settings — {project}").format(project=project.name) + "[*]")  # [*]: Qt's mark of unsaved changes
        self.resize(760, 640)
        self.project = project
        self.original = project.to_settings()
        self.document = copy.deepcopy(self.original)
        self.undo_stack = QUndoStack(self)
        self.editors: dict[str, object] = {}
        self.notes: dict[str, QLabel] = {}
        self._applying = False
        self.tabs = QTabWidget()
        forms: dict[str, QFormLayout] = {}
        for spec in FIELDS:
            if spec.tab not in forms:
                page = QWidget()
                forms[spec.tab] = QFormLayout(page)
                scroll = QScrollArea()
                scroll.setWidgetResizable(True)
                scroll.setWidget(page)
                self.tabs.addTab(scroll, tr(spec.tab))
            self._add_field(forms[spec.tab], spec)
        self.no_trolley = QLabel(tr("Each survey brings its own trolley geometry (its survey.toml)."))
        self.own_trolley = QPushButton(tr("Use one trolley for the whole project (the first survey's)"))
        self.own_trolley.clicked.connect(self.use_project_trolley)
        forms["Trolley"].insertRow(0, self.no_trolley)
        forms["Trolley"].insertRow(1, self.own_trolley)
        self.general = QLabel()  # problems without a field of their own
        self.general.setStyleSheet(NOTE_STYLE)
        self.general.setWordWrap(True)
        self.rerun = QLabel()
        self.rerun.setWordWrap(True)
        self.buttons = QDialogButtonBox(QDialogButtonBox.Save | QDialogButtonBox.Close)
        self.save_button = self.buttons.button(QDialogButtonBox.Save)
        self.save_button.clicked.connect(self.save)
        self.buttons.rejected.connect(self.close)
        undo, redo = QPushButton(tr("Undo")), QPushButton(tr("Redo"))
        undo.clicked.connect(self.undo_stack.undo)
        redo.clicked.connect(self.undo_stack.redo)
        self.undo_stack.canUndoChanged.connect(undo.setEnabled)
        self.undo_stack.canRedoChanged.connect(redo.setEnabled)
        undo.setEnabled(False)
        redo.setEnabled(False)
        for button in (undo, redo, self.own_trolley, *self.buttons.buttons()):
            button.setAutoDefault(False)  # Return commits the field being typed in; it saves nothing
        row = QHBoxLayout()
        row.addWidget(undo)
        row.addWidget(redo)
        row.addStretch(1)
        row.addWidget(self.buttons)
        layout = QVBoxLayout(self)
        layout.addWidget(self.tabs, 1)
        layout.addWidget(self.general)
        layout.addWidget(self.rerun)
        layout.addLayout(row)
        for key in self.editors:
            self._show(key)
        self.problems: list[str] = []
        self.check()

    # ------------------------------------------------------------------ the form

    def _add_field(self, form: QFormLayout, spec: Field) -> None:
        kind = spec.kind
        if kind in ("text", "file", "date"):
            widget = QLineEdit()
            widget.setPlaceholderText("YYYY-MM-DD" if kind == "date" else tr("none") if spec.optional else "")
            widget.editingFinished.connect(lambda key=spec.key: self._edited(key))
        elif kind in ("number", "int"):
            if kind == "number":
                widget = spin_box(-1e9, 1e9, spec.decimals, suffix=spec.suffix)
            else:
                widget = QSpinBox()
                widget.setRange(-10**9, 10**9)
            self._commit_when_left(widget, spec.key, tr_noop("none") if spec.optional else NOT_GIVEN)
        elif kind == "bool":
            widget = QCheckBox()
            widget.toggled.connect(lambda _on, key=spec.key: self._edited(key))
        elif kind == "choice":
            widget = QComboBox()
            choices = spec.choices() if callable(spec.choices) else list(spec.choices)
            fill(widget, spec.key, choices, (tr(EACH_SURVEY), EACH_SURVEY) if spec.optional else None)
            widget.setEditable(spec.key in RESOURCE_SETTINGS)  # or a file of one's own
            widget.currentTextChanged.connect(lambda _t, key=spec.key: self._edited(key))
        else:  # a vector of three numbers
            widget = QWidget()
            row = QHBoxLayout(widget)
            row.setContentsMargins(0, 0, 0, 0)
            widget.boxes = []
            axes = RPY_AXES if spec.key == "trolley.mounting_rpy_deg" else FRD_AXES
            for axis in axes:
                box = spin_box(-1e4, 1e4, spec.decimals, suffix=spec.suffix)
                box.setToolTip(axis)
                self._commit_when_left(box, spec.key, NOT_GIVEN)
                row.addWidget(box)
                widget.boxes.append(box)
            if spec.key in (f"trolley.{_ARMS[0]}", "trolley.mounting_rpy_deg"):
                form.addRow("", self._axis_headings(axes))  # over the boxes, in the fields' column
        note = QLabel()
        note.setStyleSheet(NOTE_STYLE)
        note.setWordWrap(True)
        note.hide()
        box = QWidget()
        column = QVBoxLayout(box)
        column.setContentsMargins(0, 0, 0, 0)
        column.setSpacing(1)
        column.addWidget(widget)
        column.addWidget(note)
        label = setting_name(spec.key)
        form.addRow(label.split(": ")[-1] if ": " in label else label, box)
        self.editors[spec.key] = (spec, widget)
        self.notes[spec.key] = note

    def showEvent(self, event) -> None:
        super().showEvent(event)
        # The button box has just made Save the dialog's default button (pressed by Return): Return
        # commits the number being typed and must not write project.toml with it.
        self.save_button.setDefault(False)

    def _commit_when_left(self, box, key: str, absent_text: str) -> None:
        """A number field that commits when left or on Return (and at once on a step of its arrows);
        its lowest value stands for a setting not given and shows ``absent_text``."""
        box.setKeyboardTracking(False)
        box.setSpecialValueText(tr(absent_text))
        box.valueChanged.connect(lambda _value: self._edited(key))

    @staticmethod
    def _axis_headings(axes: tuple[str, ...]) -> QWidget:
        """Column headings over the three boxes of the vectors below."""
        headings = QWidget()
        row = QHBoxLayout(headings)
        row.setContentsMargins(0, 0, 0, 0)
        for axis in axes:
            label = QLabel(tr(axis))
            label.setAlignment(Qt.AlignCenter)
            if axes == FRD_AXES:
                label.setToolTip(tr("the trolley's body frame b: x forward, y right, z down (FRD)"))
            row.addWidget(label)
        return headings

    @staticmethod
    def _number(box, before):
        """The box's value; ``before`` (the document's) while the box shows it at its precision,
        ``_MISSING`` while it shows "not given"."""
        if box.specialValueText() and box.value() == box.minimum():
            return _MISSING
        if isinstance(before, (int, float)) and not isinstance(before, bool) and np.isfinite(before):
            decimals = box.decimals() if hasattr(box, "decimals") else 0
            if round(float(before), decimals) == round(box.value(), decimals):
                return before
        return box.value()

    def _read(self, key: str):
        """The value the field holds, as the document stores it (``_MISSING``: left empty)."""
        spec, widget = self.editors[key]
        before = get_value(self.document, key)
        if spec.kind in ("text", "file", "date"):
            text = widget.text().strip()
            if spec.optional and not text:
                return _MISSING
            if spec.kind == "date":
                try:
                    return datetime.date.fromisoformat(text)
                except ValueError:
                    return text  # the core's check says what is wrong with it, beside the field
            return text
        if spec.kind in ("number", "int"):
            return self._number(widget, before)
        if spec.kind == "bool":
            return widget.isChecked()
        if spec.kind == "choice":
            value = chosen(widget)
            absent = (spec.optional and value == EACH_SURVEY) or value in (spec.default, NOT_GIVEN)
            return _MISSING if absent else value
        if not isinstance(before, list) or len(before) != len(widget.boxes):
            before = [None] * len(widget.boxes)
        values = [self._number(box, old) for box, old in zip(widget.boxes, before)]
        if all(value is _MISSING for value in values):
            return _MISSING
        return [0.0 if value is _MISSING else value for value in values]  # a vector begun: the rest 0

    def _show(self, key: str) -> None:
        """Put the document's value into the field (signals blocked: not an edit)."""
        spec, widget = self.editors[key]
        value = get_value(self.document, key)
        present = value is not _MISSING
        widgets = widget.boxes if spec.kind == "vector" else [widget]
        for w in widgets:
            w.blockSignals(True)
        if spec.kind in ("text", "file", "date"):
            widget.setText(str(value) if present else "")
        elif spec.kind in ("number", "int"):
            widget.setValue(value if present else widget.minimum())
        elif spec.kind == "bool":
            widget.setChecked(bool(value) if present else False)
        elif spec.kind == "choice":
            choose(widget, value if present else EACH_SURVEY if spec.optional else spec.default or NOT_GIVEN)
        else:
            for box, v in zip(widget.boxes, value if present else [box.minimum() for box in widget.boxes]):
                box.setValue(float(v))
        for w in widgets:
            w.blockSignals(False)
        if key.startswith("trolley."):
            has_trolley = "trolley" in self.document
            for w in widgets:
                w.setEnabled(has_trolley)

    def _edited(self, key: str) -> None:
        if self._applying:
            return
        before, after = get_value(self.document, key), self._read(key)
        if before == after:
            return
        self.undo_stack.push(SetSetting(self, key, before, after))

    def apply(self, key: str, value) -> None:
        """Set one setting (from the undo stack: an edit, its undo or its redo)."""
        self._applying = True
        try:
            # (a copy of _MISSING would no longer be _MISSING)
            set_value(self.document, key, value if value is _MISSING else copy.deepcopy(value))
            for shown in self.editors:  # the field, or every field of a table set at once
                if shown == key or shown.startswith(key + "."):
                    self._show(shown)
        finally:
            self._applying = False
        self.check()

    def adopt_saved(self, key: str, value) -> None:
        """A setting written to project.toml outside the editor (the track view's event marking names
        the new event file): taken as saved, so that saving the editor keeps it."""
        set_value(self.original, key, copy.deepcopy(value))
        self.apply(key, value)

    def set_field(self, key: str, value) -> None:
        """Edit one field as a surveyor would (tests and scripts): the widget changes, the edit is an
        undoable step."""
        spec, widget = self.editors[key]
        if spec.kind in ("text", "file", "date"):
            widget.setText(str(value))
            widget.editingFinished.emit()
        elif spec.kind in ("number", "int"):
            widget.setValue(value)
        elif spec.kind == "bool":
            widget.setChecked(bool(value))
        elif spec.kind == "choice":
            choose(widget, value)
        else:  # the three numbers as one edit
            for box, v in zip(widget.boxes, value):
                box.blockSignals(True)
                box.setValue(float(v))
                box.blockSignals(False)
            self._edited(key)

    def use_project_trolley(self) -> None:
        """Give the project its own [trolley] table, starting from the first survey's geometry."""
        try:
            trolley = read_manifest(self.project.resolve(self.project.surveys[0].folder)).trolley
        except (InputError, IndexError) as error:
            self.general.setText(tr("The first survey's trolley geometry cannot be read: {error}").format(
                error=said(error)))
            return
        self.undo_stack.beginMacro(tr("Trolley for the whole project"))
        table = {arm: [float(v) for v in values] for arm, values in trolley.given_lever_arms().items()}
        table.update(reference_rail=trolley.reference_rail, rail_centre_spacing_m=trolley.rail_centre_spacing_m,
                     mounting_rpy_deg=[float(v) for v in np.degrees(trolley.mounting_rpy_rad)])
        if trolley.beam_wheel_spacing_m:
            table["beam_wheel_spacing_m"] = trolley.beam_wheel_spacing_m
        self.undo_stack.push(SetSetting(self, "trolley", _MISSING, table))
        self.undo_stack.endMacro()

    # ------------------------------------------------------------------ checking and saving

    def check(self) -> list[str]:
        """The core's problems with the document, shown beside their fields; what will rerun."""
        try:
            project_from_settings(self.document, self.project.folder, self.project.path)
            self.problems = []
        except ProjectError as error:
            self.problems = [problem.said() for problem in error.phrases]  # in the window's language
        for note in self.notes.values():
            note.hide()
            note.clear()
        rest = []
        for problem in self.problems:
            key, message = split_problem(problem)
            note = self.notes.get(key)
            if note is None:
                rest.append(f"{setting_name(key)}: {message}" if key else message)
                continue
            note.setText(f"{note.text()}\n{message}" if note.text() else message)
            note.show()
        self.general.setText("\n".join(rest))
        has_trolley = "trolley" in self.document
        self.no_trolley.setVisible(not has_trolley)
        self.own_trolley.setVisible(not has_trolley)
        changed = changed_keys(self.original, self.document)
        if "trolley" in self.document and "trolley" not in self.original:
            changed.append("trolley")
        stages = stages_to_rerun(changed)
        if not changed:
            self.rerun.setText("")
        elif stages:
            self.rerun.setText((tr("Changed: {settings}. Processing again will run: {stages}.") if stages[0] == STAGES[0]
                                else tr("Changed: {settings}. Processing again will run: {stages} (the earlier stages "
                                        "from the cache).")).format(
                settings=joined(sorted({setting_name(k) for k in changed})), stages=joined(tr(s) for s in stages)))
        else:
            self.rerun.setText(tr("Changed: {settings}. Nothing is processed again; the reports show the change when "
                                  "written again.").format(settings=joined(sorted({setting_name(k) for k in changed}))))
        self.save_button.setEnabled(bool(changed) and not self.problems)
        self.setWindowModified(bool(changed))
        return self.problems

    def save(self) -> bool:
        """Write project.toml (atomically) when the settings have no problem."""
        if self.check():
            return False
        project = project_from_settings(self.document, self.project.folder, self.project.path)
        try:
            save_project(project)
        except OSError as error:
            self.general.setText(tr("Cannot write {path}: {error}").format(path=self.project.path,
                                                                           error=error.strerror or error))
            return False
        self.project, self.original = project, copy.deepcopy(self.document)
        self.undo_stack.setClean()
        self.check()
        self.saved.emit(project)
        return True

