"""Import of raw files as a survey: format detection, a preview of the first rows, reader errors shown
as file, line and what is wrong; the result is a survey folder described by ``survey.toml``.

A survey folder opened here keeps everything its ``survey.toml`` says that the form does not show: a
file's reader options and ``time_offset_s`` (a sensor's latency), the description and ``[gnss_raw]``.
Importing it unchanged leaves the file as the user wrote it (comments included); the form shows and
edits the optional ``[start]`` on the design."""

from __future__ import annotations

import dataclasses
import os
import shutil
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from PySide6.QtCore import Qt, Signal
from PySide6.QtGui import QFont
from PySide6.QtWidgets import (
    QAbstractItemView,
    QComboBox,
    QDialog,
    QDialogButtonBox,
    QFileDialog,
    QFormLayout,
    QGroupBox,
    QHBoxLayout,
    QHeaderView,
    QLabel,
    QLineEdit,
    QPlainTextEdit,
    QPushButton,
    QSpinBox,
    QSplitter,
    QTableWidget,
    QTableWidgetItem,
    QVBoxLayout,
    QWidget,
)

from insrail.gui.choices import choose, chosen, fill
from insrail.io.errors import InputError
from insrail.io.formats import FORMATS, detect_format, read_any
from insrail.io.survey import (
    MANIFEST_NAME,
    POSITION_ROLES,
    REQUIRED_ROLES,
    ROLE_TYPES,
    START_SIGMA_M,
    SurveyFile,
    SurveyManifest,
    SurveyStart,
    TrolleyGeometry,
    manifest_to_toml,
    read_manifest,
    write_manifest,
)
from insrail.gui.forms import spin_box
from insrail.resources import resources_dir
from insrail.gui.translation import tr, tr_noop

PREVIEW_LINES = 12
#: What a reader's error counts in (InputError.unit) as the status column says it; the message is the reader's
READ_UNITS = {"line": tr_noop("line"), "row": tr_noop("row")}
#: the role a file of a data type is guessed to have: the first role of that type (an odometer file is the
#: first odometer; a second one, odometer_right, is chosen by hand)
_ROLE_OF_TYPE = {data_type: role for role, data_type in reversed(ROLE_TYPES.items())}
_FILE, _ROLE, _FORMAT, _STATUS = range(4)


def shipped_names(folder: str) -> list[str]:
    return sorted(p.stem for p in (resources_dir() / folder).glob("*.toml"))


def preview(path: Path, lines: int = PREVIEW_LINES) -> str:
    """The first rows of a raw file as the user would see them in an editor (.npy: its records)."""
    if path.suffix.lower() == ".npy":
        try:
            records = np.load(path, mmap_mode="r", allow_pickle=False)
        except (ValueError, OSError) as error:
            return tr("not a readable .npy file: {error}").format(error=error)
        names = records.dtype.names or ("value",)
        rows = [" ".join(names)] + [str(records[i]) for i in range(min(lines, len(records)))]
        return tr("{count} records").format(count=len(records)) + "\n" + "\n".join(rows)
    try:
        with open(path, encoding="utf-8", errors="replace") as handle:
            return "".join(line for _, line in zip(range(lines), handle))
    except OSError as error:
        return tr("cannot read: {error}").format(error=error)


@dataclass(frozen=True)
class Problem:
    """A reader error as the surveyor wants it: which file, which line, what is wrong."""

    file: str
    line: int | None
    message: str


class ImportWidget(QWidget):
    """Pick raw files (or a survey folder), check them with the readers, write ``survey.toml``."""

    changed = Signal()

    def __init__(self, parent=None):
        super().__init__(parent)
        self.name = QLineEdit()
        self.name.setPlaceholderText(tr("letters, digits, '.', '_' or '-'"))
        self.gps_week = QSpinBox()
        self.gps_week.setRange(0, 9999)
        self.gps_week.setSpecialValueText(tr("from the files"))
        self.imu_profile = QComboBox()
        fill(self.imu_profile, "processing.imu_profile", shipped_names("imu_profiles"))
        choose(self.imu_profile, "nav")
        self.files = QTableWidget(0, 4)
        self.files.setHorizontalHeaderLabels([tr("File"), tr("Role"), tr("Format"), tr("Check")])
        self.files.setSelectionBehavior(QAbstractItemView.SelectRows)
        self.files.verticalHeader().setVisible(False)
        self.files.horizontalHeader().setSectionResizeMode(_FILE, QHeaderView.Stretch)
        self.files.horizontalHeader().setSectionResizeMode(_STATUS, QHeaderView.Stretch)
        self.preview = QPlainTextEdit(readOnly=True)
        self.preview.setFont(QFont("monospace", 8))
        self.preview.setLineWrapMode(QPlainTextEdit.NoWrap)
        self.problems = QTableWidget(0, 3)
        self.problems.setHorizontalHeaderLabels([tr("File"), tr("Line"), tr("What is wrong")])
        self.problems.verticalHeader().setVisible(False)
        self.problems.horizontalHeader().setStretchLastSection(True)
        self.problems.setEditTriggers(QAbstractItemView.NoEditTriggers)
        self.folder_trolley: TrolleyGeometry | None = None  # from a survey.toml that was opened
        # the survey.toml that was opened, with its folder: what the form does not show is kept from it
        self.opened: tuple[SurveyManifest, Path] | None = None
        self._week_from_files: int | None = None  # the GPS week check() took from the files
        self.start = QGroupBox(tr("Starts on a station of the design (before the first position fix)"))
        self.start.setCheckable(True)
        self.start.setChecked(False)
        self.start_station = spin_box(-1e7, 1e7, 3, suffix=" m")
        self.start_offset = spin_box(-10.0, 10.0, 3, suffix=" m")
        self.start_height = spin_box(-10.0, 10.0, 3, suffix=" m")
        self.start_sigma = spin_box(0.001, 10.0, 3, START_SIGMA_M, suffix=" m")
        self.start_facing = QComboBox()
        self.start_facing.addItem(tr("increasing stations"), True)
        self.start_facing.addItem(tr("decreasing stations"), False)
        start_form = QFormLayout(self.start)
        start_form.addRow(tr("Station"), self.start_station)
        start_form.addRow(tr("Offset right of the centreline"), self.start_offset)
        start_form.addRow(tr("Height above the profile"), self.start_height)
        start_form.addRow(tr("1-sigma of the start point"), self.start_sigma)
        start_form.addRow(tr("The trolley faces"), self.start_facing)

        add = QPushButton(tr("Add files…"))
        add.clicked.connect(self._browse_files)
        open_folder = QPushButton(tr("Open survey folder…"))
        open_folder.clicked.connect(self._browse_folder)
        remove = QPushButton(tr("Remove"))
        remove.clicked.connect(self._remove_selected)
        check = QPushButton(tr("Check files"))
        check.clicked.connect(self.check)
        buttons = QHBoxLayout()
        for button in (add, open_folder, remove, check):
            buttons.addWidget(button)
        buttons.addStretch(1)
        form = QFormLayout()
        form.addRow(tr("Survey name"), self.name)
        form.addRow(tr("GPS week"), self.gps_week)
        form.addRow(tr("IMU profile"), self.imu_profile)
        lower = QSplitter(Qt.Horizontal)
        preview_box = QWidget()
        preview_layout = QVBoxLayout(preview_box)
        preview_layout.setContentsMargins(0, 0, 0, 0)
        preview_layout.addWidget(QLabel(tr("First rows of the selected file")))
        preview_layout.addWidget(self.preview)
        problems_box = QWidget()
        problems_layout = QVBoxLayout(problems_box)
        problems_layout.setContentsMargins(0, 0, 0, 0)
        problems_layout.addWidget(QLabel(tr("Problems found by the readers")))
        problems_layout.addWidget(self.problems)
        lower.addWidget(preview_box)
        lower.addWidget(problems_box)
        layout = QVBoxLayout(self)
        layout.addLayout(form)
        layout.addWidget(self.start)
        layout.addLayout(buttons)
        layout.addWidget(self.files, 2)
        layout.addWidget(lower, 2)
        self.files.currentCellChanged.connect(lambda row, *_: self._show_preview(row))
        self.setAcceptDrops(True)

    # Files dropped from a file manager are added like "Add files…".
    def dragEnterEvent(self, event) -> None:
        if event.mimeData().hasUrls():
            event.acceptProposedAction()

    def dropEvent(self, event) -> None:
        paths = [url.toLocalFile() for url in event.mimeData().urls() if url.isLocalFile()]
        files = [p for p in paths if Path(p).is_file()]
        folders = [p for p in paths if (Path(p) / MANIFEST_NAME).is_file()]
        if folders:
            self.load_survey_folder(folders[0])
        elif files:
            self.add_files(files)
        event.acceptProposedAction()

    # ------------------------------------------------------------------ the file list

    def add_files(self, paths: list[str | Path], roles: dict[str, str] | None = None,
                  formats: dict[str, str] | None = None) -> None:
        """Add files; their format is detected and their role guessed from the data the format holds."""
        for path in map(Path, paths):
            name = (formats or {}).get(str(path)) or detect_format(path)
            role = (roles or {}).get(str(path)) or (_ROLE_OF_TYPE[FORMATS[name].data_type] if name else "")
            row = self.files.rowCount()
            self.files.insertRow(row)
            item = QTableWidgetItem(str(path))
            item.setFlags(item.flags() & ~Qt.ItemIsEditable)
            self.files.setItem(row, _FILE, item)
            role_box = QComboBox()
            role_box.addItems(["", *ROLE_TYPES])
            role_box.setCurrentText(role)
            format_box = QComboBox()
            format_box.addItems(["", *FORMATS])
            format_box.setCurrentText(name or "")
            for box in (role_box, format_box):
                box.currentTextChanged.connect(lambda _text: self.changed.emit())
            self.files.setCellWidget(row, _ROLE, role_box)
            self.files.setCellWidget(row, _FORMAT, format_box)
            status = QTableWidgetItem("detected" if name else "format not recognised: choose one")
            status.setFlags(status.flags() & ~Qt.ItemIsEditable)
            self.files.setItem(row, _STATUS, status)
        if self.files.rowCount():
            self.files.setCurrentCell(self.files.rowCount() - 1, _FILE)
        self.changed.emit()

    def load_survey_folder(self, folder: str | Path) -> None:
        """Take the files, name, week, IMU profile, trolley and start from an existing ``survey.toml``;
        the rest of it is kept for :meth:`write_survey`."""
        folder = Path(folder)
        manifest = read_manifest(folder)
        self.opened = (manifest, folder.resolve())
        self.files.setRowCount(0)
        paths = {role: str(folder / f.path) for role, f in manifest.files.items()}
        self.add_files(list(paths.values()), roles={p: r for r, p in paths.items()},
                       formats={paths[r]: f.format for r, f in manifest.files.items()})
        self.name.setText(folder.name)
        self.gps_week.setValue(manifest.gps_week or 0)
        choose(self.imu_profile, manifest.imu_profile)
        self.folder_trolley = manifest.trolley
        self._show_start(manifest.start)

    def _show_start(self, start: SurveyStart | None) -> None:
        self.start.setChecked(start is not None)
        if start is not None:
            self.start_station.setValue(start.station_m)
            self.start_offset.setValue(start.offset_m)
            self.start_height.setValue(start.height_m)
            self.start_sigma.setValue(start.sigma_m)
            self.start_facing.setCurrentIndex(self.start_facing.findData(start.facing_increasing))

    def survey_start(self) -> SurveyStart | None:
        """The ``[start]`` the form gives (None: the survey waits for its first position fix)."""
        if not self.start.isChecked():
            return None
        return SurveyStart(self.start_station.value(), self.start_offset.value(), self.start_height.value(),
                           self.start_sigma.value(), bool(self.start_facing.currentData()))

    def entries(self) -> list[tuple[Path, str, str]]:
        """(path, role, format) of every row."""
        return [(Path(self.files.item(row, _FILE).text()), self.files.cellWidget(row, _ROLE).currentText(),
                 self.files.cellWidget(row, _FORMAT).currentText()) for row in range(self.files.rowCount())]

    def _browse_files(self) -> None:
        paths, _ = QFileDialog.getOpenFileNames(self, tr("Raw files of one survey"))
        if paths:
            self.add_files(paths)

    def _browse_folder(self) -> None:
        folder = QFileDialog.getExistingDirectory(self, tr("Survey folder (with {file})").format(file=MANIFEST_NAME))
        if folder:
            try:
                self.load_survey_folder(folder)
            except InputError as error:
                self._show_problems([Problem(str(error.path), error.line, error.message)])

    def _remove_selected(self) -> None:
        for row in sorted({index.row() for index in self.files.selectedIndexes()}, reverse=True):
            self.files.removeRow(row)
        self.changed.emit()

    def _show_preview(self, row: int) -> None:
        if 0 <= row < self.files.rowCount():
            self.preview.setPlainText(preview(Path(self.files.item(row, _FILE).text())))

    # ------------------------------------------------------------------ checking and writing

    def check(self) -> list[Problem]:
        """Read every file with its format; every problem is listed (file, line, what is wrong)."""
        problems: list[Problem] = []
        roles = [role for _, role, _ in self.entries()]
        for role in REQUIRED_ROLES:
            if role not in roles:
                required = ", ".join(REQUIRED_ROLES)
                problems.append(Problem("", None, tr("no file has the role {role} (required: {required})").format(
                    role=role, required=required)))
        if not any(role in roles for role in POSITION_ROLES) and self._raw_gnss() is None:
            problems.append(Problem("", None, tr("no file gives the position: give a GNSS solution (gnss) or "
                                                 "total-station prism fixes (prism)")))
        weeks = set()
        for row, (path, role, name) in enumerate(self.entries()):
            status = tr("ok")
            if not role:
                problems.append(Problem(path.name, None, tr("choose the role of this file")))
                status = tr("no role")
            elif roles.count(role) > 1:
                problems.append(Problem(path.name, None, tr("more than one file has the role {role}").format(role=role)))
                status = tr("duplicate role")
            elif not name:
                problems.append(Problem(path.name, None, tr("format not recognised: choose one")))
                status = tr("no format")
            elif FORMATS[name].data_type is not ROLE_TYPES[role]:
                problems.append(Problem(path.name, None, tr("format {format} does not hold {role} data").format(format=name,
                                                                                                         role=role)))
                status = tr("format does not fit the role")
            else:
                try:
                    data = read_any(path, name)
                    weeks.add(getattr(data, "gps_week", None))
                except InputError as error:
                    message = error.said_message()  # in the window's language, its names and values verbatim
                    problems.append(Problem(error.path.name, error.line, message))
                    status = (tr("{unit} {line}: {message}").format(unit=tr(READ_UNITS.get(error.unit, error.unit)),
                                                                     line=error.line, message=message)
                              if error.line else message)
            self.files.item(row, _STATUS).setText(status)
        weeks.discard(None)
        if self.gps_week.value() == 0 and len(weeks) == 1:
            self.gps_week.setValue(weeks.pop())
            self._week_from_files = self.gps_week.value()
        self._show_problems(problems)
        return problems

    def _show_problems(self, problems: list[Problem]) -> None:
        self.problems.setRowCount(len(problems))
        for row, problem in enumerate(problems):
            for column, text in enumerate((problem.file, "" if problem.line is None else str(problem.line),
                                           problem.message)):
                self.problems.setItem(row, column, QTableWidgetItem(text))
        self.problems.resizeColumnsToContents()

    def _raw_gnss(self):
        """The opened survey's ``[gnss_raw]`` (raw GNSS observations instead of a gnss file), or None."""
        return self.opened[0].raw_gnss if self.opened is not None else None

    def _raw_gnss_paths(self) -> list[Path]:
        raw, folder = self._raw_gnss(), self.opened[1] if self.opened is not None else None
        return [] if raw is None else [(folder / name).resolve() for name in raw.input_files()]

    def survey_folder(self) -> Path:
        """The folder of the survey: the one holding all its files (the raw GNSS files included)."""
        paths = [p.resolve() for p, _, _ in self.entries()] + self._raw_gnss_paths()
        return Path(os.path.commonpath([str(p.parent) for p in paths]))

    def _kept(self, path: Path, role: str, fmt: str, relative: str) -> SurveyFile:
        """The file as survey.toml will give it: the opened survey's options and time offset kept for the
        same file read the same way (a sensor's latency must not be lost on the way into a project)."""
        if self.opened is not None:
            manifest, folder = self.opened
            before = manifest.files.get(role)
            if before is not None and before.format == fmt and (folder / before.path).resolve() == path.resolve():
                return dataclasses.replace(before, path=relative)
        return SurveyFile(relative, fmt)

    def _moved_raw_gnss(self, folder: Path):
        """``[gnss_raw]`` with its paths relative to the survey's new folder."""
        raw = self._raw_gnss()
        if raw is None:
            return None
        old = self.opened[1]

        def moved(name):
            return os.path.relpath((old / name).resolve(), folder).replace(os.sep, "/")

        changes = {key: moved(getattr(raw, key)) for key in ("base", "rover", "rover_log", "antex", "config")
                   if getattr(raw, key) is not None}
        changes.update(navigation=tuple(map(moved, raw.navigation)), precise=tuple(map(moved, raw.precise)))
        return dataclasses.replace(raw, **changes)

    def write_survey(self, trolley: TrolleyGeometry | None, into: Path | None = None) -> Path | None:
        """Check the files and write ``survey.toml`` beside them, or (``into``) copy them into that
        folder (made if missing; their layout under the survey folder kept) and write it there, the
        raw-data folder left untouched; None (problems shown) if not possible."""
        problems = self.check()
        if trolley is None:
            problems.append(Problem("", None, tr("no trolley geometry: enter it in the project")))
        name = self.name.text().strip()
        if not name:
            problems.append(Problem("", None, tr("enter a survey name")))
        if problems:
            self._show_problems(problems)
            return None
        folder = self.survey_folder()
        files = {role: self._kept(path, role, fmt, os.path.relpath(path.resolve(), folder).replace(os.sep, "/"))
                 for path, role, fmt in self.entries()}
        if into is not None:
            copies = [path.resolve() for path, _, _ in self.entries()] + self._raw_gnss_paths()
            try:
                for path in copies:
                    target = into / os.path.relpath(path, folder)
                    target.parent.mkdir(parents=True, exist_ok=True)
                    shutil.copy2(path, target)
            except OSError as error:
                self._show_problems([Problem(str(path), None, tr("cannot copy into {folder}: {error}").format(
                    folder=into, error=error.strerror or error))])
                return None
            folder = into
        raw_gnss = self._moved_raw_gnss(self.survey_folder())
        description = self.opened[0].description if self.opened is not None else ""
        gps_week = self.gps_week.value() or None
        if self.opened is not None and self.opened[0].gps_week is None and gps_week == self._week_from_files:
            gps_week = None  # the files say it; the opened survey.toml did not need to
        manifest = SurveyManifest(name=name, files=files, trolley=trolley, imu_profile=chosen(self.imu_profile),
                                  gps_week=gps_week, description=description,
                                  raw_gnss=raw_gnss, start=self.survey_start())
        if not self._unchanged(manifest, folder):
            write_manifest(folder, manifest)
        return folder

    def _unchanged(self, manifest: SurveyManifest, folder: Path) -> bool:
        """The opened survey.toml says the same in the same place: it stays as its user wrote it."""
        if self.opened is None or self.opened[1] != folder.resolve():
            return False
        return manifest_to_toml(manifest) == manifest_to_toml(self.opened[0])


class ImportDialog(QDialog):
    """The import widget in a dialog (File > Import); ``accepted`` after survey.toml was written."""

    def __init__(self, trolley: TrolleyGeometry | None, fallback: TrolleyGeometry | None = None, parent=None):
        """``trolley``: the project's geometry (it overrides every survey's); without it, the opened survey
        folder's own, else ``fallback`` (an existing survey's) is written to survey.toml."""
        super().__init__(parent)
        self.fallback = fallback
        self.setWindowTitle(tr("Import raw files as a survey"))
        self.resize(900, 640)
        self.trolley = trolley
        self.widget = ImportWidget()
        self.folder: Path | None = None
        buttons = QDialogButtonBox(QDialogButtonBox.Ok | QDialogButtonBox.Cancel)
        buttons.button(QDialogButtonBox.Ok).setText(tr("Import"))
        buttons.accepted.connect(self.accept)
        buttons.rejected.connect(self.reject)
        layout = QVBoxLayout(self)
        layout.addWidget(self.widget)
        layout.addWidget(buttons)

    def accept(self) -> None:
        self.folder = self.widget.write_survey(self.trolley or self.widget.folder_trolley or self.fallback)
        if self.folder is not None:
            super().accept()
