"""New-project wizard: project folder, coordinate system, benchmarks, trolley geometry, IMU and
tolerance profiles, then the first survey's raw files. The project is validated by the core
(:func:`insrail.project.project_from_settings`); its problems are listed with their key paths."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
from PySide6.QtCore import Qt
from PySide6.QtWidgets import (
    QComboBox,
    QDoubleSpinBox,
    QFileDialog,
    QFormLayout,
    QGridLayout,
    QHBoxLayout,
    QLabel,
    QLineEdit,
    QPushButton,
    QVBoxLayout,
    QWidget,
    QWizard,
    QWizardPage,
)

from insrail.geodesy.crs import ELLIPSOIDS, PROJECTION_HEIGHT_CONVENTIONS
from insrail.gui.importer import ImportWidget, shipped_names
from insrail.io.errors import InputError
from insrail.io.survey import MANIFEST_NAME, TrolleyGeometry, read_manifest
from insrail.project import (
    HEIGHT_MODELS,
    Project,
    ProjectError,
    project_from_settings,
    save_project,
)
from insrail.track.tolerance import DEFAULT_PROFILE, shipped_tolerance_profiles

LEVER_ARMS = (("imu_to_antenna_m", "IMU → GNSS antenna"), ("imu_to_odometer_m", "IMU → odometer wheel contact"),
              ("imu_to_reference_rail_m", "IMU → reference rail gauge point"),
              ("imu_to_sleeper_detector_m", "IMU → sleeper detector"), ("imu_to_prism_m", "IMU → prism"))
EACH_SURVEY = "(each survey's own)"


def spin(low: float, high: float, decimals: int, value: float = 0.0, suffix: str = "") -> QDoubleSpinBox:
    box = QDoubleSpinBox()
    box.setRange(low, high)
    box.setDecimals(decimals)
    box.setValue(value)
    box.setSuffix(suffix)
    return box


def file_row(edit: QLineEdit, caption: str, pattern: str, parent: QWidget) -> QWidget:
    """A path field with a Browse button."""
    button = QPushButton("Browse…")

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


class NewProjectWizard(QWizard):
    """After ``accept()`` ``project`` holds the saved project."""

    def __init__(self, parent=None):
        super().__init__(parent)
        self.setWindowTitle("New insrail project")
        self.setWizardStyle(QWizard.ClassicStyle)
        self.resize(860, 640)
        self.project: Project | None = None
        self.addPage(self._project_page())
        self.addPage(self._crs_page())
        self.addPage(self._height_page())
        self.addPage(self._trolley_page())
        self.addPage(self._processing_page())
        self.addPage(self._survey_page())

    # ------------------------------------------------------------------ pages

    def _page(self, title: str, subtitle: str) -> tuple[QWizardPage, QFormLayout]:
        page = QWizardPage()
        page.setTitle(title)
        page.setSubTitle(subtitle)
        form = QFormLayout(page)
        return page, form

    def _project_page(self) -> QWizardPage:
        page, form = self._page("Project", "Where the project file (project.toml) and the results are kept.")
        self.name = QLineEdit("New project")
        self.folder = QLineEdit()
        browse = QPushButton("Browse…")
        browse.clicked.connect(lambda: self.folder.setText(
            QFileDialog.getExistingDirectory(self, "Project folder") or self.folder.text()))
        row = QHBoxLayout()
        row.addWidget(self.folder, 1)
        row.addWidget(browse)
        self.description = QLineEdit()
        form.addRow("Name", self.name)
        form.addRow("Folder", row)
        form.addRow("Description", self.description)
        return page

    def _crs_page(self) -> QWizardPage:
        page, form = self._page("Coordinate system", "The engineering (construction) coordinate system: a transverse "
                                "Mercator projection on the chosen ellipsoid, reduced to the projection height.")
        self.ellipsoid = QComboBox()
        self.ellipsoid.addItems(list(ELLIPSOIDS))
        self.central_meridian = spin(-180, 180, 6, 114.0, " °")
        self.latitude_of_origin = spin(-90, 90, 6, 0.0, " °")
        self.scale_factor = spin(0.99, 1.01, 9, 1.0)
        self.false_easting = spin(-1e7, 1e8, 3, 500000.0, " m")
        self.false_northing = spin(-2e7, 2e7, 3, 0.0, " m")
        self.projection_height = spin(-1000, 9000, 3, 0.0, " m")
        self.convention = QComboBox()
        self.convention.addItems(list(PROJECTION_HEIGHT_CONVENTIONS))
        for label, widget in (("Ellipsoid", self.ellipsoid), ("Central meridian", self.central_meridian),
                              ("Latitude of origin", self.latitude_of_origin), ("Scale factor", self.scale_factor),
                              ("False easting", self.false_easting), ("False northing", self.false_northing),
                              ("Projection height", self.projection_height),
                              ("Projection height applied as", self.convention)):
            form.addRow(label, widget)
        return page

    def _height_page(self) -> QWizardPage:
        page, form = self._page("Benchmarks", "GNSS-levelling benchmarks (ellipsoidal and normal heights) fit the "
                                "height anomaly; without them heights stay ellipsoidal.")
        self.benchmarks = QLineEdit()
        self.height_model = QComboBox()
        self.height_model.addItems(list(HEIGHT_MODELS))
        form.addRow("Benchmarks file", file_row(self.benchmarks, "Benchmarks", "Text (*.txt *.csv);;All (*)", self))
        form.addRow("Height-anomaly model", self.height_model)
        return page

    def _trolley_page(self) -> QWizardPage:
        page = QWizardPage()
        page.setTitle("Trolley geometry")
        page.setSubTitle("Lever arms from the IMU centre in the IMU body frame (forward, right, down), metres; "
                         "mounting angles of the IMU in the trolley.")
        grid = QGridLayout()
        for column, axis in enumerate(("forward", "right", "down"), start=1):
            grid.addWidget(QLabel(axis), 0, column, Qt.AlignCenter)
        self.lever_arms: dict[str, tuple[QDoubleSpinBox, ...]] = {}
        for row, (key, label) in enumerate(LEVER_ARMS, start=1):
            grid.addWidget(QLabel(label), row, 0)
            self.lever_arms[key] = tuple(spin(-10, 10, 4, suffix=" m") for _ in range(3))
            for column, box in enumerate(self.lever_arms[key], start=1):
                grid.addWidget(box, row, column)
        mounting_row = len(LEVER_ARMS) + 1
        grid.addWidget(QLabel("Mounting roll, pitch, heading"), mounting_row, 0)
        self.mounting = tuple(spin(-180, 180, 4, suffix=" °") for _ in range(3))
        for column, box in enumerate(self.mounting, start=1):
            grid.addWidget(box, mounting_row, column)
        self.reference_rail = QComboBox()
        self.reference_rail.addItems(["left", "right"])
        self.rail_spacing = spin(0.5, 3.0, 4, 1.5, " m")
        from_survey = QPushButton("Copy from a survey.toml…")
        from_survey.clicked.connect(self._browse_trolley)
        form = QFormLayout()
        form.addRow("Reference rail", self.reference_rail)
        form.addRow("Rail centre spacing (cant base)", self.rail_spacing)
        layout = QVBoxLayout(page)
        layout.addLayout(grid)
        layout.addLayout(form)
        layout.addWidget(from_survey, 0, Qt.AlignLeft)
        layout.addStretch(1)
        return page

    def _processing_page(self) -> QWizardPage:
        page, form = self._page("Processing and assessment", "IMU error model, design alignment, tolerance "
                                "profile for the assessment and the fastener type for the adjustment.")
        self.imu_profile = QComboBox()
        self.imu_profile.addItems([EACH_SURVEY, *shipped_names("imu_profiles")])
        self.design = QLineEdit()
        self.start_station = spin(-1e7, 1e8, 3, 0.0, " m")
        self.tolerance_profile = QComboBox()
        self.tolerance_profile.addItems(shipped_tolerance_profiles())
        self.tolerance_profile.setCurrentText(DEFAULT_PROFILE)
        self.fastener = QComboBox()
        self.fastener.addItems(shipped_names("fastener_types"))
        form.addRow("IMU profile", self.imu_profile)
        form.addRow("Design alignment", file_row(self.design, "Design alignment", "Alignment (*.csv *.xml);;All (*)",
                                                 self))
        form.addRow("Start station (without a design)", self.start_station)
        form.addRow("Tolerance profile", self.tolerance_profile)
        form.addRow("Fastener type", self.fastener)
        return page

    def _survey_page(self) -> QWizardPage:
        page = SurveyPage(self)
        page.setTitle("First survey")
        page.setSubTitle("The raw files of one trolley run; formats are detected, check them before finishing.")
        self.survey = ImportWidget()
        self.problems = QLabel()
        self.problems.setWordWrap(True)
        self.problems.setStyleSheet("color: #C00000")
        self.problems.setTextInteractionFlags(Qt.TextSelectableByMouse)
        layout = QVBoxLayout(page)
        layout.addWidget(self.survey, 1)
        layout.addWidget(self.problems)
        return page

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
        self.convention.setCurrentText(settings.get("projection_height_convention", "scale_factor"))

    def set_trolley(self, trolley: TrolleyGeometry) -> None:
        for key, boxes in self.lever_arms.items():
            values = getattr(trolley, key)
            for box, value in zip(boxes, values):
                box.setValue(float(value) if np.isfinite(value) else 0.0)
        for box, value in zip(self.mounting, np.degrees(trolley.mounting_rpy_rad)):
            box.setValue(float(value))
        self.reference_rail.setCurrentText(trolley.reference_rail)
        self.rail_spacing.setValue(trolley.rail_centre_spacing_m)

    def _browse_trolley(self) -> None:
        path, _ = QFileDialog.getOpenFileName(self, "survey.toml with the trolley geometry", filter="survey.toml")
        if path:
            try:
                self.set_trolley(read_manifest(Path(path).parent).trolley)
            except InputError as error:
                self.problems.setText(str(error))

    # ------------------------------------------------------------------ the result

    def trolley(self) -> TrolleyGeometry:
        arms = {key: np.array([box.value() for box in boxes]) for key, boxes in self.lever_arms.items()}
        return TrolleyGeometry(**arms, reference_rail=self.reference_rail.currentText(),
                               mounting_rpy_rad=np.radians([box.value() for box in self.mounting]),
                               rail_centre_spacing_m=self.rail_spacing.value())

    def settings(self, folder: Path, survey_name: str, survey_folder: Path) -> dict:
        """The project.toml document the pages describe (paths relative to ``folder``)."""
        def relative(path_text: str) -> str:
            return os.path.relpath(Path(path_text).resolve(), folder.resolve()).replace(os.sep, "/")

        height = {"model": self.height_model.currentText()}
        if self.benchmarks.text().strip():
            height["benchmarks"] = relative(self.benchmarks.text().strip())
        track = {"tolerance_profile": self.tolerance_profile.currentText(), "fastener": self.fastener.currentText()}
        if self.design.text().strip():
            track["design"] = relative(self.design.text().strip())
        else:
            track["start_station_m"] = self.start_station.value()
        profile = self.imu_profile.currentText()
        processing = {} if profile == EACH_SURVEY else {"imu_profile": profile}
        return {
            "project": {"name": self.name.text().strip(), "description": self.description.text().strip()},
            "geodesy": {"crs": {
                "ellipsoid": self.ellipsoid.currentText(), "central_meridian_deg": self.central_meridian.value(),
                "latitude_of_origin_deg": self.latitude_of_origin.value(), "scale_factor": self.scale_factor.value(),
                "false_easting_m": self.false_easting.value(), "false_northing_m": self.false_northing.value(),
                "projection_height_m": self.projection_height.value(),
                "projection_height_convention": self.convention.currentText()}, "height": height},
            "trolley": {**{key: [box.value() for box in boxes] for key, boxes in self.lever_arms.items()},
                        "reference_rail": self.reference_rail.currentText(),
                        "mounting_rpy_deg": [box.value() for box in self.mounting],
                        "rail_centre_spacing_m": self.rail_spacing.value()},
            "processing": processing,
            "track": track,
            "surveys": [{"name": survey_name, "folder": relative(str(survey_folder))}],
        }

    def create_project(self) -> bool:
        """Write the survey's survey.toml and the project file; False (problems shown) if not possible.

        The project is validated before survey.toml is written, so a rejected project leaves no file behind."""
        self.problems.clear()
        folder_text = self.folder.text().strip()
        if not folder_text:
            self.problems.setText("Choose the project folder (first page).")
            return False
        if not self.survey.entries():
            self.problems.setText("Add the raw files of the first survey.")
            return False
        folder = Path(folder_text)
        survey_folder = self.survey.survey_folder()
        document = self.settings(folder, self.survey.name.text().strip(), survey_folder)
        not_yet_written = f"surveys[0].folder: no {MANIFEST_NAME} in"
        try:
            project_from_settings(document, folder)
        except ProjectError as error:
            blocking = [p for p in error.problems if not p.startswith(not_yet_written)]
            if blocking:
                self.problems.setText("The project has problems; go back and correct them:\n" + "\n".join(blocking))
                return False
        if self.survey.write_survey(self.trolley()) is None:
            self.problems.setText("The survey's files have problems (listed above).")
            return False
        folder.mkdir(parents=True, exist_ok=True)
        self.project = project_from_settings(document, folder)
        save_project(self.project)
        return True


class SurveyPage(QWizardPage):
    """The last page: Finish creates the project, or stays with the problems listed."""

    def __init__(self, wizard: NewProjectWizard):
        super().__init__()
        self._wizard = wizard

    def validatePage(self) -> bool:
        return self._wizard.create_project()
