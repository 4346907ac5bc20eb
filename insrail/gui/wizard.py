"""New-project wizard: project folder, coordinate system, benchmarks, trolley geometry, IMU and
tolerance profiles, then the first survey's raw files.

Each page is checked as it is left, by the core's own validation of the whole project
(:func:`insrail.project.project_from_settings`, the same as loading project.toml): the problems of
the page's fields are shown beside each field, in the field's words. A project folder that does not
exist is created when the first page is left (and removed again if the wizard is cancelled while it
is still empty). Lever arms left at zero are named and must be confirmed. The raw files stay where
they are (survey.toml is then written beside them, and the page says so) or are copied into the
project's surveys folder, as the surveyor chooses."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
from PySide6.QtCore import Qt
from PySide6.QtWidgets import (
    QButtonGroup,
    QCheckBox,
    QComboBox,
    QDoubleSpinBox,
    QFileDialog,
    QFormLayout,
    QGridLayout,
    QHBoxLayout,
    QLabel,
    QLineEdit,
    QPushButton,
    QRadioButton,
    QVBoxLayout,
    QWidget,
    QWizard,
    QWizardPage,
)

from insrail.geodesy.crs import ELLIPSOIDS, PROJECTION_HEIGHT_CONVENTIONS
from insrail.gui.choices import choose, chosen, fill
from insrail.gui.fields import in_words, split_problem
from insrail.gui.forms import NOTE_STYLE, spin_box
from insrail.gui.importer import ImportWidget, shipped_names
from insrail.io.errors import InputError, said
from insrail.io.survey import MANIFEST_NAME, TrolleyGeometry, read_manifest
from insrail.names import joined, setting_name
from insrail.project import (
    HEIGHT_MODELS,
    Project,
    ProjectError,
    load_project,
    project_from_settings,
    save_project,
)
from insrail.project.model import PROJECT_FILE
from insrail.track.tolerance import DEFAULT_PROFILE, shipped_tolerance_profiles
from insrail.gui.translation import tr, tr_noop

LEVER_ARMS = ("imu_to_antenna_m", "imu_to_odometer_m", "imu_to_reference_rail_m", "imu_to_sleeper_detector_m",
              "imu_to_prism_m")
EACH_SURVEY = "(each survey's own)"
#: Lever arms every project uses (the prism's only in tunnels with a total station).
REQUIRED_ARMS = ("imu_to_antenna_m", "imu_to_odometer_m", "imu_to_reference_rail_m", "imu_to_sleeper_detector_m")
#: The project.toml keys each page edits (its problems are shown when it is left).
PAGE_KEYS = (("project",), ("geodesy.crs",), ("geodesy.height",), ("trolley",), ("processing", "track"), ())


def file_row(edit: QLineEdit, caption: str, pattern: str, parent: QWidget) -> QWidget:
    """A path field with a Browse button."""
    button = QPushButton(tr("Browse…"))

    def browse() -> None:
        path, _ = QFileDialog.getOpenFileName(parent, caption, filter=pattern)
        if path:
            edit.setText(path)

    button.clicked.connect(browse)
    row = QWidget()
    layout = QHBoxLayout(row)
    layout.setContentsMargins(0, 0, 0, 0)
    layout.addWidget(edit, 1)
    layout.addWidget(button)
    return row


def note_label() -> QLabel:
    note = QLabel()
    note.setStyleSheet(NOTE_STYLE)
    note.setWordWrap(True)
    note.hide()
    return note


class CheckedPage(QWizardPage):
    """A page checked by its wizard when it is left."""

    def __init__(self, wizard: NewProjectWizard, index: int):
        super().__init__()
        self._wizard, self.index = wizard, index

    def validatePage(self) -> bool:
        return self._wizard.check_page(self.index)


class NewProjectWizard(QWizard):
    """After ``accept()`` ``project`` holds the saved project. ``earlier_projects``: project files
    whose trolley geometry the trolley page offers to copy (the recently opened ones)."""

    def __init__(self, parent=None, earlier_projects=()):
        super().__init__(parent)
        self.setWindowTitle(tr("New insrail project"))
        self.setWizardStyle(QWizard.ClassicStyle)
        self.resize(900, 680)
        self.project: Project | None = None
        self.notes: dict[str, QLabel] = {}  # key path -> the note beside its field
        self.page_notes: list[QLabel] = []  # per page: problems without a field of their own
        self.created_folder: Path | None = None  # a project folder this wizard created
        self.earlier_projects = [str(p) for p in earlier_projects]
        self.rejected.connect(self._remove_created_folder)
        self.addPage(self._project_page())
        self.addPage(self._crs_page())
        self.addPage(self._height_page())
        self.addPage(self._trolley_page())
        self.addPage(self._processing_page())
        self.addPage(self._survey_page())

    # ------------------------------------------------------------------ pages

    def _new_page(self, title: str, subtitle: str) -> CheckedPage:
        page = CheckedPage(self, len(self.page_notes))
        page.setTitle(tr(title))
        page.setSubTitle(tr(subtitle))
        self.page_notes.append(note_label())
        return page

    def _page(self, title: str, subtitle: str) -> tuple[QWizardPage, QFormLayout]:
        page = self._new_page(title, subtitle)
        form = QFormLayout(page)
        return page, form

    def _row(self, form: QFormLayout, label: str, field, key: str | None = None) -> None:
        """A form row whose field has a note under it for the problems of ``key``."""
        label = tr(label)
        if key is None:
            form.addRow(label, field)
            return
        box = QWidget()
        layout = QVBoxLayout(box)
        layout.setContentsMargins(0, 0, 0, 0)
        layout.setSpacing(1)
        layout.addWidget(field) if isinstance(field, QWidget) else layout.addLayout(field)
        self.notes[key] = note_label()
        layout.addWidget(self.notes[key])
        form.addRow(label, box)

    def _end_page(self, page: QWizardPage, form: QFormLayout) -> QWizardPage:
        form.addRow(self.page_notes[page.index])
        return page

    def _project_page(self) -> QWizardPage:
        page, form = self._page(tr_noop("Project"), tr_noop("Where the project file (project.toml) and the results are kept."))
        self.name = QLineEdit(tr("New project"))
        self.folder = QLineEdit()
        browse = QPushButton(tr("Browse…"))
        browse.clicked.connect(lambda: self.folder.setText(
            QFileDialog.getExistingDirectory(self, "Project folder") or self.folder.text()))
        row = QHBoxLayout()
        row.addWidget(self.folder, 1)
        row.addWidget(browse)
        self.description = QLineEdit()
        self._row(form, tr_noop("Name"), self.name, "project.name")
        self._row(form, tr_noop("Folder"), row, "folder")
        self._row(form, tr_noop("Description"), self.description, "project.description")
        return self._end_page(page, form)

    def _crs_page(self) -> QWizardPage:
        page, form = self._page(tr_noop("Coordinate system"), tr_noop("The engineering (construction) coordinate system: a transverse "
                                "Mercator projection on the chosen ellipsoid, reduced to the projection height."))
        self.ellipsoid = QComboBox()
        self.ellipsoid.addItems(list(ELLIPSOIDS))
        self.central_meridian = spin_box(-180, 180, 6, 114.0, " °")
        self.latitude_of_origin = spin_box(-90, 90, 6, 0.0, " °")
        self.scale_factor = spin_box(0.99, 1.01, 9, 1.0)
        self.false_easting = spin_box(-1e7, 1e8, 3, 500000.0, " m")
        self.false_northing = spin_box(-2e7, 2e7, 3, 0.0, " m")
        self.projection_height = spin_box(-1000, 9000, 3, 0.0, " m")
        self.convention = QComboBox()
        fill(self.convention, "geodesy.crs.projection_height_convention", PROJECTION_HEIGHT_CONVENTIONS)
        for label, widget, key in (
                (tr_noop("Ellipsoid"), self.ellipsoid, "ellipsoid"), (tr_noop("Central meridian"), self.central_meridian,
                                                              "central_meridian_deg"),
                (tr_noop("Latitude of origin"), self.latitude_of_origin, "latitude_of_origin_deg"),
                (tr_noop("Scale factor"), self.scale_factor, "scale_factor"), (tr_noop("False easting"), self.false_easting,
                                                                      "false_easting_m"),
                (tr_noop("False northing"), self.false_northing, "false_northing_m"),
                (tr_noop("Projection height"), self.projection_height, "projection_height_m"),
                (tr_noop("Projection height applied as"), self.convention, "projection_height_convention")):
            self._row(form, label, widget, f"geodesy.crs.{key}")
        return self._end_page(page, form)

    def _height_page(self) -> QWizardPage:
        page, form = self._page(tr_noop("Benchmarks"), tr_noop("GNSS-levelling benchmarks (ellipsoidal and normal heights) fit the "
                                "height anomaly; without them heights stay ellipsoidal."))
        self.benchmarks = QLineEdit()
        self.height_model = QComboBox()
        fill(self.height_model, "geodesy.height.model", HEIGHT_MODELS)
        self._row(form, tr_noop("Benchmarks file"), file_row(self.benchmarks, "Benchmarks", "Text (*.txt *.csv);;All (*)", self),
                  "geodesy.height.benchmarks")
        self._row(form, tr_noop("Height-anomaly model"), self.height_model, "geodesy.height.model")
        return self._end_page(page, form)

    def _trolley_page(self) -> QWizardPage:
        page = self._new_page(tr_noop("Trolley geometry"), tr_noop("Lever arms from the IMU centre in the IMU body frame (forward, "
                              "right, down), metres; mounting angles of the IMU in the trolley."))
        grid = QGridLayout()
        for column, axis in enumerate((tr("forward"), tr("right"), tr("down")), start=1):
            grid.addWidget(QLabel(axis), 0, column, Qt.AlignCenter)
        self.lever_arms: dict[str, tuple[QDoubleSpinBox, ...]] = {}
        for row, key in enumerate(LEVER_ARMS, start=1):
            grid.addWidget(QLabel(setting_name(f"trolley.{key}")), row, 0)  # in the language of the moment
            self.lever_arms[key] = tuple(spin_box(-10, 10, 4, suffix=" m") for _ in range(3))
            for column, box in enumerate(self.lever_arms[key], start=1):
                grid.addWidget(box, row, column)
            self.notes[f"trolley.{key}"] = note_label()
            grid.addWidget(self.notes[f"trolley.{key}"], row, 4)
        mounting_row = len(LEVER_ARMS) + 1
        grid.addWidget(QLabel(setting_name("trolley.mounting_rpy_deg")), mounting_row, 0)
        self.mounting = tuple(spin_box(-180, 180, 4, suffix=" °") for _ in range(3))
        for column, box in enumerate(self.mounting, start=1):
            grid.addWidget(box, mounting_row, column)
        self.reference_rail = QComboBox()
        fill(self.reference_rail, "trolley.reference_rail", ("left", "right"))
        self.rail_spacing = spin_box(0.5, 3.0, 4, 1.5, " m")
        from_survey = QPushButton(tr("Copy from a survey.toml…"))
        from_survey.clicked.connect(self._browse_trolley)
        self.earlier = QComboBox()
        self.earlier.addItem(tr("Copy the trolley of an earlier project…"))
        self.earlier.addItems(self.earlier_projects)
        self.earlier.setEnabled(bool(self.earlier_projects))
        self.earlier.activated.connect(self._copy_earlier_trolley)
        self.zero_arms_ok = QCheckBox(tr("These lever arms really are zero"))
        self.zero_arms_ok.hide()
        form = QFormLayout()
        self._row(form, tr_noop("Reference rail"), self.reference_rail, "trolley.reference_rail")
        self._row(form, tr_noop("Rail centre spacing (cant base)"), self.rail_spacing, "trolley.rail_centre_spacing_m")
        copy_row = QHBoxLayout()
        copy_row.addWidget(self.earlier, 1)
        copy_row.addWidget(from_survey)
        layout = QVBoxLayout(page)
        layout.addLayout(grid)
        layout.addLayout(form)
        layout.addLayout(copy_row)
        layout.addWidget(self.page_notes[page.index])
        layout.addWidget(self.zero_arms_ok)
        layout.addStretch(1)
        return page

    def _processing_page(self) -> QWizardPage:
        page, form = self._page(tr_noop("Processing and assessment"), tr_noop("IMU error model, design alignment, tolerance "
                                "profile for the assessment and the fastener type for the adjustment."))
        self.imu_profile = QComboBox()
        fill(self.imu_profile, "processing.imu_profile", shipped_names("imu_profiles"), (tr(EACH_SURVEY), EACH_SURVEY))
        self.design = QLineEdit()
        self.start_station = spin_box(-1e7, 1e8, 3, 0.0, " m")
        self.tolerance_profile = QComboBox()
        fill(self.tolerance_profile, "track.tolerance_profile", shipped_tolerance_profiles())
        choose(self.tolerance_profile, DEFAULT_PROFILE)
        self.fastener = QComboBox()
        fill(self.fastener, "track.fastener", shipped_names("fastener_types"))
        self._row(form, tr_noop("IMU profile"), self.imu_profile, "processing.imu_profile")
        self._row(form, tr_noop("Design alignment"), file_row(self.design, "Design alignment",
                                                     "Alignment (*.csv *.xml);;All (*)", self), "track.design")
        self._row(form, tr_noop("Start station (without a design)"), self.start_station, "track.start_station_m")
        self._row(form, tr_noop("Tolerance profile"), self.tolerance_profile, "track.tolerance_profile")
        self._row(form, tr_noop("Fastener type"), self.fastener, "track.fastener")
        return self._end_page(page, form)

    def _survey_page(self) -> QWizardPage:
        page = self._new_page(tr_noop("First survey"), tr_noop("The raw files of one trolley run; formats are detected, check "
                              "them before finishing."))
        self.survey = ImportWidget()
        self.keep_raw = QRadioButton(tr("Keep the raw files where they are"))
        self.copy_raw = QRadioButton(tr("Copy the raw files into the project (surveys/<survey name>/); the raw-data "
                                     "folder is left as it is"))
        self.keep_raw.setChecked(True)
        choice = QButtonGroup(page)
        for button in (self.keep_raw, self.copy_raw):
            choice.addButton(button)
            button.toggled.connect(self._describe_raw_choice)
        self.raw_note = QLabel()
        self.raw_note.setWordWrap(True)
        self.survey.changed.connect(self._describe_raw_choice)
        self.problems = self.page_notes[page.index]
        self.problems.setTextInteractionFlags(Qt.TextSelectableByMouse)
        layout = QVBoxLayout(page)
        layout.addWidget(self.survey, 1)
        layout.addWidget(self.keep_raw)
        layout.addWidget(self.copy_raw)
        layout.addWidget(self.raw_note)
        layout.addWidget(self.problems)
        self._describe_raw_choice()
        return page

    def _describe_raw_choice(self, *_args) -> None:
        """Say where survey.toml will be written: never into a raw-data folder unannounced."""
        if not self.survey.entries():
            self.raw_note.setText("")
        elif self.copy_raw.isChecked():
            self.raw_note.setText(tr("The files and survey.toml go into {folder}.").format(folder=self.survey_target()))
        else:
            self.raw_note.setText(tr("survey.toml (the description of the survey's files) will be written into the "
                                     "raw-data folder {folder}.").format(folder=self.survey.survey_folder()))

    def survey_target(self) -> Path:
        """Where the copied raw files go: <project>/surveys/<survey name>."""
        return Path(self.folder.text().strip() or ".") / "surveys" / (self.survey.name.text().strip() or "survey")

    # ------------------------------------------------------------------ filling in

    def set_crs_settings(self, settings: dict) -> None:
        """Fill the coordinate-system page from an EngineeringCRS settings table."""
        self.ellipsoid.setCurrentText(settings.get("ellipsoid", "CGCS2000"))
        self.central_meridian.setValue(settings.get("central_meridian_deg", 0.0))
        self.latitude_of_origin.setValue(settings.get("latitude_of_origin_deg", 0.0))
        self.scale_factor.setValue(settings.get("scale_factor", 1.0))
        self.false_easting.setValue(settings.get("false_easting_m", 500000.0))
        self.false_northing.setValue(settings.get("false_northing_m", 0.0))
        self.projection_height.setValue(settings.get("projection_height_m", 0.0))
        choose(self.convention, settings.get("projection_height_convention", "scale_factor"))

    def _copy_earlier_trolley(self, index: int) -> None:
        if index <= 0:
            return
        path = Path(self.earlier.itemText(index))
        self.earlier.setCurrentIndex(0)
        try:
            project = load_project(path)
            trolley = project.trolley() or read_manifest(project.resolve(project.surveys[0].folder)).trolley
        except (InputError, IndexError) as error:
            self._show_page_note(3, [tr("the trolley of {path} cannot be read: {error}").format(path=path,
                                                                                                error=said(error))])
            return
        self.set_trolley(trolley)
        self._show_page_note(3, [])

    def set_trolley(self, trolley: TrolleyGeometry) -> None:
        for key, boxes in self.lever_arms.items():
            values = getattr(trolley, key)  # None: not given there (left at 0, to be confirmed)
            for box, value in zip(boxes, values if values is not None else np.zeros(3)):
                box.setValue(float(value))
        for box, value in zip(self.mounting, np.degrees(trolley.mounting_rpy_rad)):
            box.setValue(float(value))
        choose(self.reference_rail, trolley.reference_rail)
        self.rail_spacing.setValue(trolley.rail_centre_spacing_m)

    def _browse_trolley(self) -> None:
        path, _ = QFileDialog.getOpenFileName(self, "survey.toml with the trolley geometry", filter="survey.toml")
        if path:
            try:
                self.set_trolley(read_manifest(Path(path).parent).trolley)
            except InputError as error:
                self._show_page_note(3, [error.said()])

    # ------------------------------------------------------------------ the result

    def trolley(self) -> TrolleyGeometry:
        arms = {key: np.array([box.value() for box in boxes]) for key, boxes in self.lever_arms.items()}
        return TrolleyGeometry(**arms, reference_rail=chosen(self.reference_rail),
                               mounting_rpy_rad=np.radians([box.value() for box in self.mounting]),
                               rail_centre_spacing_m=self.rail_spacing.value())

    def settings(self, folder: Path, survey_name: str, survey_folder: Path) -> dict:
        """The project.toml document the pages describe (paths relative to ``folder``)."""
        def relative(path_text: str) -> str:
            return os.path.relpath(Path(path_text).resolve(), folder.resolve()).replace(os.sep, "/")

        height = {"model": chosen(self.height_model)}
        if self.benchmarks.text().strip():
            height["benchmarks"] = relative(self.benchmarks.text().strip())
        track = {"tolerance_profile": chosen(self.tolerance_profile), "fastener": chosen(self.fastener)}
        if self.design.text().strip():
            track["design"] = relative(self.design.text().strip())
        else:
            track["start_station_m"] = self.start_station.value()
        profile = chosen(self.imu_profile)
        processing = {} if profile == EACH_SURVEY else {"imu_profile": profile}
        return {
            "project": {"name": self.name.text().strip(), "description": self.description.text().strip()},
            "geodesy": {"crs": {
                "ellipsoid": self.ellipsoid.currentText(), "central_meridian_deg": self.central_meridian.value(),
                "latitude_of_origin_deg": self.latitude_of_origin.value(), "scale_factor": self.scale_factor.value(),
                "false_easting_m": self.false_easting.value(), "false_northing_m": self.false_northing.value(),
                "projection_height_m": self.projection_height.value(),
                "projection_height_convention": chosen(self.convention)}, "height": height},
            "trolley": {**{key: [box.value() for box in boxes] for key, boxes in self.lever_arms.items()},
                        "reference_rail": chosen(self.reference_rail),
                        "mounting_rpy_deg": [box.value() for box in self.mounting],
                        "rail_centre_spacing_m": self.rail_spacing.value()},
            "processing": processing,
            "track": track,
            "surveys": [{"name": survey_name, "folder": relative(str(survey_folder))}],
        }

    # ------------------------------------------------------------------ checking each page

    def _show_page_note(self, index: int, lines: list[str]) -> None:
        note = self.page_notes[index]
        note.setText("\n".join(lines))
        note.setVisible(bool(lines))

    def _show_problems(self, index: int, problems: list[str]) -> bool:
        """Problems of page ``index`` beside their fields (the rest under the page); True if none."""
        keys = PAGE_KEYS[index]
        mine = [p for p in problems if not keys or any(split_problem(p)[0].startswith(k) for k in keys)]
        for key, note in self.notes.items():
            if index == len(PAGE_KEYS) - 1 or any(key.startswith(k) for k in keys) or (key == "folder" and index == 0):
                note.hide()
        rest = []
        for problem in mine:
            key, message = split_problem(problem)
            note = self.notes.get(key)
            if note is not None:
                note.setText(message if not note.isVisible() else f"{note.text()}\n{message}")
                note.show()
            else:
                rest.append(in_words(problem))
        self._show_page_note(index, rest)
        return not mine

    def _problems(self, folder: Path) -> list[str]:
        """Every problem the core finds in the project the pages describe (the survey not yet written)."""
        survey = self.survey.name.text().strip() or "survey"
        survey_folder = (self.survey_target() if self.copy_raw.isChecked() or not self.survey.entries()
                         else self.survey.survey_folder())
        try:
            project_from_settings(self.settings(folder, survey, survey_folder), folder)
        except ProjectError as error:
            return [problem.said() for problem in error.phrases]  # in the window's language
        return []

    def check_page(self, index: int) -> bool:
        """Called as page ``index`` is left: its problems beside their fields; False keeps it open."""
        if index == 0:
            return self._check_folder() and self._show_problems(0, self._problems(Path(self.folder.text().strip())))
        if index == 3 and not self._check_lever_arms():
            return False
        if index == len(PAGE_KEYS) - 1:
            return self.create_project()
        return self._show_problems(index, self._problems(Path(self.folder.text().strip())))

    def _check_folder(self) -> bool:
        """The project folder: chosen, not holding a project yet; created if missing (and said so)."""
        note = self.notes["folder"]
        text = self.folder.text().strip()
        folder = Path(text)
        problem = None
        if not text:
            problem = tr("choose the folder for the project file and its results")
        elif folder.exists() and not folder.is_dir():
            problem = tr("{folder} is a file, not a folder").format(folder=folder)
        elif (folder / PROJECT_FILE).exists():
            problem = tr("a project already exists in {folder}: open it, or choose another folder").format(folder=folder)
        if problem is None and not folder.exists():
            try:
                folder.mkdir(parents=True)
            except OSError as error:
                problem = tr("cannot create the folder: {error}").format(error=error.strerror or error)
            else:
                self.created_folder = folder
                note.setStyleSheet("")
                note.setText(tr("created the folder {folder}").format(folder=folder.resolve()))
                note.show()
                return True
        note.setStyleSheet(NOTE_STYLE)
        note.setText(problem or "")
        note.setVisible(problem is not None)
        return problem is None

    def _check_lever_arms(self) -> bool:
        """Lever arms left at 0 m: named, and the page stays until the surveyor confirms them."""
        zero = [key for key in REQUIRED_ARMS if not any(box.value() for box in self.lever_arms[key])]
        for key in REQUIRED_ARMS:
            note = self.notes[f"trolley.{key}"]
            note.setText(tr("0 m: is this lever arm measured?") if key in zero else "")
            note.setVisible(key in zero)
        if not zero:
            self.zero_arms_ok.hide()
            return True
        self.zero_arms_ok.show()
        if self.zero_arms_ok.isChecked():
            return True
        self._show_page_note(3, [tr("Lever arms at 0 m: {arms}. A trolley's sensors are never all at the IMU centre: "
                                    "enter the measured lever arms, copy them from an earlier project, or confirm below "
                                    "that they really are zero.").format(
            arms=joined(setting_name(f"trolley.{k}") for k in zero))])
        return False

    def _remove_created_folder(self) -> None:
        """Cancelled: the folder this wizard created goes again if nothing was put in it."""
        if self.created_folder is not None and self.project is None:
            try:
                self.created_folder.rmdir()
            except OSError:  # not empty: something else put files there; leave it
                pass

    def create_project(self) -> bool:
        """Write the survey's survey.toml and the project file; False (problems shown) if not possible.

        The project is validated before survey.toml is written, so a rejected project leaves no file behind."""
        self.problems.clear()
        folder_text = self.folder.text().strip()
        if not folder_text:
            self.problems.setText(tr("Choose the project folder (first page)."))
            return False
        if not self.survey.entries():
            self.problems.setText(tr("Add the raw files of the first survey."))
            return False
        folder = Path(folder_text)
        copy = self.copy_raw.isChecked()
        survey_folder = self.survey_target() if copy else self.survey.survey_folder()
        document = self.settings(folder, self.survey.name.text().strip(), survey_folder)
        # the survey folder is described (or made) only once the project is known to be good
        not_yet_written = ("surveys[0].folder: not found", f"surveys[0].folder: no {MANIFEST_NAME} in") if copy else (
            f"surveys[0].folder: no {MANIFEST_NAME} in",)
        try:
            project_from_settings(document, folder)
        except ProjectError as error:
            blocking = [in_words(phrase.said()) for phrase, english in zip(error.phrases, error.problems)
                        if not english.startswith(not_yet_written)]
            if blocking:
                self.problems.setText(tr("The project has problems; go back and correct them:") + "\n" + "\n".join(blocking))
                return False
        if copy and survey_folder.exists() and any(survey_folder.iterdir()):
            self.problems.setText(tr("{folder} is not empty: choose another survey name.").format(folder=survey_folder))
            return False
        if self.survey.write_survey(self.trolley(), into=survey_folder if copy else None) is None:
            self.problems.setText(tr("The survey's files have problems (listed above)."))
            return False
        folder.mkdir(parents=True, exist_ok=True)
        self.project = project_from_settings(document, folder)
        save_project(self.project)
        return True
