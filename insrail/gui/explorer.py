"""Project explorer (surveys, their raw files, results) and the properties panel of the selected item."""

from __future__ import annotations

from PySide6.QtCore import Qt, Signal
from PySide6.QtWidgets import QMenu, QTreeWidget, QTreeWidgetItem

from insrail.gui.choices import value_text
from insrail.gui.fields import split_problem
from insrail.io.errors import InputError
from insrail.io.survey import MANIFEST_NAME
from insrail.io.tomlfile import read_toml
from insrail.names import setting_name
from insrail.project import Project
from insrail.project.results import RESULTS_FOLDER, SUMMARY_FILE, report_path
from insrail.report.stale import REPORT_SUFFIXES, report_is_stale
from insrail.gui.translation import tr

ROLE = Qt.UserRole


def flatten(settings: dict, prefix: str = "") -> list[tuple[str, str | bool]]:
    """Key paths and values of a nested settings table, as the TOML files name them (a switch stays a bool:
    :func:`insrail.gui.choices.value_text` words it in the application's language)."""
    rows = []
    for key, value in settings.items():
        path = f"{prefix}{key}"
        if isinstance(value, dict):
            rows += flatten(value, path + ".")
        elif isinstance(value, list) and value and isinstance(value[0], dict):
            for i, entry in enumerate(value):
                rows += flatten(entry, f"{path}[{i}].")
        else:
            rows.append((path, ", ".join(map(str, value)) if isinstance(value, list)
                         else value if isinstance(value, bool) else str(value)))
    return rows


class ProjectExplorer(QTreeWidget):
    """Items carry (kind, payload): ("project", None), ("survey", name), ("file", (survey, role)),
    ("gnss_raw", survey), ("results", name), ("report", (survey, path)); a report older than its
    survey's results is marked ⚠."""

    propertiesChanged = Signal(list)  # [(key, value)] of the selected item
    resultsActivated = Signal(str)  # a survey whose results should be shown
    surveyActivated = Signal(str)  # a survey double-clicked: show it (its results, or that it has none)
    processRequested = Signal(str)  # a survey to process
    rewriteRequested = Signal(str)  # a survey whose out-of-date reports should be written again

    def __init__(self, parent=None):
        super().__init__(parent)
        self.setHeaderLabels([tr("Project")])
        self.project: Project | None = None
        self.currentItemChanged.connect(lambda item, _old: self._describe(item))
        self.itemDoubleClicked.connect(self._activated)
        self.setContextMenuPolicy(Qt.CustomContextMenu)
        self.customContextMenuRequested.connect(self._context_menu)

    def set_project(self, project: Project | None) -> None:
        self.project = project
        self.clear()
        if project is None:
            return
        root = self._item(self, project.name, ("project", None))
        surveys = self._item(root, tr("Surveys"), ("group", None))
        results = self._item(root, tr("Results"), ("group", None))
        for entry in project.surveys:
            survey = self._item(surveys, entry.name, ("survey", entry.name))
            try:
                manifest = project.manifest(entry.name)
            except InputError as error:
                self._item(survey, f"⚠ {error.said_message().splitlines()[0]}", ("error", error.said()))
                continue
            for role, file in manifest.files.items():
                self._item(survey, f"{role}: {file.path}", ("file", (entry.name, role)))
            raw = manifest.raw_gnss
            if raw is not None:
                for name in (raw.rover or raw.rover_log, raw.base, *raw.navigation, *raw.precise, raw.antex, raw.config):
                    if name is not None:
                        self._item(survey, f"gnss_raw: {name}", ("gnss_raw", entry.name))
            if (project.folder / RESULTS_FOLDER / entry.name / SUMMARY_FILE).is_file():
                self._add_reports(self._item(results, entry.name, ("results", entry.name)))
        self.expandAll()
        self.setCurrentItem(root)

    def _add_reports(self, results: QTreeWidgetItem) -> None:
        """The survey's reports at their default places under its results item, the stale ones marked."""
        survey = results.data(0, ROLE)[1]
        for suffix in REPORT_SUFFIXES:
            path = report_path(self.project.folder, survey, suffix)
            if not path.is_file():
                continue
            stale = report_is_stale(path, self.project.folder, survey)
            item = self._item(results, tr("⚠ {name} (older than the results)").format(name=path.name) if stale
                              else path.name, ("report", (survey, path)))
            item.setToolTip(0, tr("written before the survey was processed again: it describes results that no longer "
                                  "exist") if stale else
                            tr("written from the current results: {path}").format(path=path.resolve()))

    def mark_reports(self) -> None:
        """List and mark the reports again (written, or made out of date by processing)."""
        if self.project is None:
            return
        group = next((self.topLevelItem(0).child(k) for k in range(self.topLevelItem(0).childCount())
                      if self.topLevelItem(0).child(k).text(0) == "Results"), None)
        if group is None:
            return
        known = {group.child(k).data(0, ROLE)[1] for k in range(group.childCount())}
        for entry in self.project.surveys:  # results of a survey processed since the tree was made
            if entry.name not in known and (self.project.folder / RESULTS_FOLDER / entry.name / SUMMARY_FILE).is_file():
                self._item(group, entry.name, ("results", entry.name))
        for k in range(group.childCount()):
            results = group.child(k)
            for child in [results.child(j) for j in range(results.childCount())]:
                results.removeChild(child)
            self._add_reports(results)
            results.setExpanded(True)

    def _item(self, parent, text: str, data) -> QTreeWidgetItem:
        item = QTreeWidgetItem(parent, [text])
        item.setData(0, ROLE, data)
        return item

    def context_actions(self, item: QTreeWidgetItem) -> list[tuple[str, object]]:
        """(text, slot) of what can be done with an item."""
        kind, payload = item.data(0, ROLE)
        if kind == "survey":
            return [(tr("Process {survey}").format(survey=payload), lambda: self.processRequested.emit(payload))]
        if kind == "results":
            actions = [(tr("Show results of {survey}").format(survey=payload), lambda: self.resultsActivated.emit(payload)),
                       (tr("Process {survey} again").format(survey=payload),
                        lambda: self.processRequested.emit(payload))]
            stale = [item.child(k) for k in range(item.childCount()) if item.child(k).text(0).startswith("⚠")]
            if stale:
                actions.append((tr("Write the out-of-date reports of {survey} again").format(survey=payload),
                                lambda: self.rewriteRequested.emit(payload)))
            return actions
        if kind == "report" and item.text(0).startswith("⚠"):
            return [(tr("Write the out-of-date reports again"), lambda: self.rewriteRequested.emit(payload[0]))]
        return []

    def _context_menu(self, position) -> None:
        item = self.itemAt(position)
        actions = self.context_actions(item) if item is not None else []
        if actions:
            menu = QMenu(self)
            for text, slot in actions:
                menu.addAction(text, slot)
            menu.popup(self.viewport().mapToGlobal(position))

    def _activated(self, item: QTreeWidgetItem) -> None:
        kind, payload = item.data(0, ROLE)
        if kind == "results":
            self.resultsActivated.emit(payload)
        elif kind == "survey":
            self.surveyActivated.emit(payload)

    def _describe(self, item: QTreeWidgetItem | None) -> None:
        if item is None or self.project is None:
            self.propertiesChanged.emit([])
            return
        kind, payload = item.data(0, ROLE)
        project = self.project
        if kind == "project":
            rows = [(tr("folder"), str(project.folder.resolve())), (tr("coordinate system"), project.crs.describe())]
            rows += rows_in_words(flatten(project.to_settings()))
        elif kind == "survey":
            folder = project.resolve(project.survey(payload).folder)
            rows = [(tr("folder"), str(folder.resolve()))]
            try:
                rows += rows_in_words(flatten(read_toml(folder / MANIFEST_NAME)))
            except (OSError, ValueError) as error:
                rows.append((tr("problem"), str(error)))
        elif kind == "file":
            survey, role = payload
            folder = project.resolve(project.survey(survey).folder)
            file = project.manifest(survey).files[role]
            path = folder / file.path
            rows = [(tr("role"), role), (tr("path"), str(path.resolve())), (tr("format"), file.format),
                    (tr("size"), f"{path.stat().st_size / 1e6:.2f} MB" if path.is_file() else tr("missing"))]
            rows += [(tr("option {name}").format(name=k), str(v)) for k, v in file.options.items()]
        elif kind == "gnss_raw":
            raw = project.manifest(payload).raw_gnss
            rows = rows_in_words(flatten({"gnss_raw": raw.to_settings()}))
        elif kind == "results":
            summary = project.folder / RESULTS_FOLDER / payload / SUMMARY_FILE
            rows = [(tr("folder"), str(summary.parent.resolve()))] + rows_in_words(flatten(read_toml(summary)))
        elif kind == "report":
            survey, path = payload
            stale = report_is_stale(path, project.folder, survey)
            rows = [(tr("file"), str(path.resolve())),
                    (tr("state"), tr("older than the results: written before the survey was processed again") if stale
                     else tr("written from the current results"))]
        elif kind == "error":
            rows = [(tr("problem"), payload)]
        else:
            rows = []
        self.propertiesChanged.emit(rows)


def rows_in_words(rows: list[tuple[str, str]]) -> list[tuple[str, str]]:
    """Key paths and values as the screen shows them: names (:func:`insrail.names.setting_name`, in
    words where the table has none), a listed value or a shipped resource by its name."""
    words = []
    for key, value in rows:
        bare = split_problem(f"{key}: ")[0]
        words.append((setting_name(bare), value_text(bare, value)))
    return words


class PropertiesPanel(QTreeWidget):
    def __init__(self, parent=None):
        super().__init__(parent)
        self.setHeaderLabels([tr("Property"), tr("Value")])
        self.setRootIsDecorated(False)
        self.setColumnWidth(0, 170)
        self.setWordWrap(True)

    def show_rows(self, rows: list[tuple[str, str]]) -> None:
        self.clear()
        for key, value in rows:
            item = QTreeWidgetItem(self, [key, value])
            item.setToolTip(1, value)

    def rows(self) -> list[tuple[str, str]]:
        return [(self.topLevelItem(i).text(0), self.topLevelItem(i).text(1)) for i in range(self.topLevelItemCount())]
