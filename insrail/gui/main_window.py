"""The main window: project explorer, central views, properties, log, progress with Cancel."""

from __future__ import annotations

import gc
import os
from pathlib import Path

import numpy as np
from PySide6.QtCore import QSettings, Qt, QTimer, QUrl
from PySide6.QtGui import QAction, QDesktopServices, QKeySequence, QUndoGroup
from PySide6.QtWidgets import (
    QDockWidget,
    QFileDialog,
    QLabel,
    QMainWindow,
    QMessageBox,
    QProgressBar,
    QPushButton,
    QTabWidget,
    QVBoxLayout,
    QWidget,
)

from insrail import __version__
from insrail.gui import export_files, plotstyle
from insrail.gui.empty import (
    EmptyState,
    ResultsOlderThanEventsBanner,
    StaleReportsBanner,
)
from insrail.gui.event_dialog import EventDialog
from insrail.gui.explorer import ProjectExplorer, PropertiesPanel
from insrail.gui.export_files import make_export_actions
from insrail.gui.importer import ImportDialog
from insrail.gui.loader import ResultsLoader
from insrail.gui.logpanel import LogPanel
from insrail.gui.plan_survey import PlanSurveyDialog
from insrail.gui.settings import recent_projects, remember_project
from insrail.gui.settings_editor import SettingsEditor
from insrail.gui.views.gnss import GnssView, input_rows
from insrail.gui.views.navigation import NavigationView
from insrail.gui.views.plan import PlanView
from insrail.gui.views.redesign import RedesignView
from insrail.gui.views.repeatability import RepeatabilityView
from insrail.gui.views.track import TrackView
from insrail.gui.viewstate import load_view_state, save_view_state
from insrail.gui.wizard import NewProjectWizard
from insrail.gui.worker import CoreWorker, ProcessingWorker, TaskWorker
from insrail.io.errors import InputError, said
from insrail.io.survey import read_manifest
from insrail.io.tomlfile import read_toml
from insrail.names import t
from insrail.notices import notices_of
from insrail.progress import ProgressMessage, progress_text
from insrail.project import (
    Project,
    ProjectError,
    StoredResults,
    load_project,
    save_project,
)
from insrail.project.event_marking import results_older_than_events
from insrail.project.gnss_stage import GnssStageResult, run_gnss_stage
from insrail.project.lock import project_run
from insrail.project.model import project_from_settings
from insrail.project.pipeline import CACHE_FOLDER
from insrail.project.plotdata import PpkView, RedesignPlot, TrackData, TrajectoryViews, redesign_plot, stored_ppk
from insrail.project.redesign import run_redesign
from insrail.project.results import RESULTS_FOLDER, SUMMARY_FILE
from insrail.report.content import ChainageAxis
from insrail.project.run_settings import settings_change_lines
from insrail.report.stale import stale_reports
from insrail.track.events import KIND_NAMES
from insrail.track.tolerance import load_tolerance_profile
from insrail.gui.preferences import PreferencesDialog
from insrail.gui.translation import tr

PROGRESS_STEPS = 1000
#: The first window's size (without saved geometry) where the screen has room for it [px].
FIRST_SIZE = (1400, 900)
#: Room kept for a window manager's frame and title bar around the first window [px].
FRAME_ALLOWANCE = (16, 48)


class MainWindow(QMainWindow):
    def __init__(self, settings: QSettings):
        super().__init__()
        plotstyle.configure()
        self.settings = settings
        self.project: Project | None = None
        self.modified = False
        self.worker: CoreWorker | None = None  # one core job at a time: processing, export or PPK
        self.job_failure_title = ""
        self.done_message = tr("Ready")  # the status bar's text when the job ends
        self.shown_survey: str | None = None
        self.results: dict[str, StoredResults] = {}
        self.wizard: NewProjectWizard | None = None
        self.plan_dialog: PlanSurveyDialog | None = None
        self.settings_editor: SettingsEditor | None = None
        self.undo_group = QUndoGroup(self)  # the Edit menu's Undo/Redo: the open settings editor's steps
        self.exported: Path | None = None
        self.request = 0  # the number of the latest results load; answers to older ones are dropped
        self.loader: ResultsLoader | None = None  # the load of the latest request while it runs
        self._loaders: set[ResultsLoader] = set()  # every load still running (kept alive until it ends)
        self._pending_view: dict | None = None  # view state to apply when its survey's track arrives

        self.plan = PlanView()
        self.navigation = NavigationView()
        self.track = TrackView()
        self.repeatability = RepeatabilityView()
        self.gnss = GnssView()
        self.gnss.surveyChosen.connect(self.show_gnss)
        self.redesign_view = RedesignView()
        self.tabs = QTabWidget()
        self.tabs.setDocumentMode(True)
        for view, title in ((self.track, tr("Track")), (self.plan, tr("Plan")), (self.navigation, tr("Navigation")),
                            (self.repeatability, tr("Repeatability")), (self.redesign_view, tr("Re-design")),
                            (self.gnss, tr("GNSS"))):
            self.tabs.addTab(view, title)
        self.tabs.setTabVisible(self.tabs.indexOf(self.gnss), False)  # for surveys with raw GNSS only
        self.empty_state = EmptyState()
        self.empty_state.processRequested.connect(lambda name: self.process([name]))
        self.stale_banner = StaleReportsBanner()
        self.stale_banner.rewriteRequested.connect(lambda: self.rewrite_reports())
        self.events_banner = ResultsOlderThanEventsBanner()
        self.events_banner.processRequested.connect(lambda name: self.process([name]))
        self.track.markEventRequested.connect(self.mark_event)
        central = QWidget()
        central_layout = QVBoxLayout(central)
        central_layout.setContentsMargins(0, 0, 0, 0)
        central_layout.setSpacing(0)
        central_layout.addWidget(self.empty_state)
        central_layout.addWidget(self.stale_banner)
        central_layout.addWidget(self.events_banner)
        central_layout.addWidget(self.tabs, 1)
        self.setCentralWidget(central)

        self.explorer = ProjectExplorer()
        self.properties = PropertiesPanel()
        self.log = LogPanel()
        self.track.exceedanceSelected.connect(self._mark_in_plan)
        self.explorer.propertiesChanged.connect(self.properties.show_rows)
        self.explorer.resultsActivated.connect(self.show_results)
        self.explorer.surveyActivated.connect(self.show_results)
        self.explorer.processRequested.connect(lambda name: self.process([name]))
        self.explorer.rewriteRequested.connect(self.rewrite_reports)
        self._dock("explorer", tr("Project"), self.explorer, Qt.LeftDockWidgetArea)
        self._dock("properties", tr("Properties"), self.properties, Qt.LeftDockWidgetArea)
        self._dock("log", tr("Log"), self.log, Qt.BottomDockWidgetArea)

        self.status = QLabel(tr("Ready"))
        self.progress = QProgressBar()
        self.progress.setRange(0, PROGRESS_STEPS)
        self.progress.setMaximumWidth(260)
        self.progress.hide()
        self.cancel_button = QPushButton(tr("Cancel"))
        self.cancel_button.clicked.connect(self.cancel_processing)
        self.cancel_button.hide()
        self.open_folder_button = QPushButton(tr("Open folder"))
        self.open_folder_button.setToolTip(tr("Open the folder of the exported report"))
        self.open_folder_button.clicked.connect(self.open_export_folder)
        self.open_folder_button.hide()
        self.statusBar().addWidget(self.status, 1)
        self.statusBar().addPermanentWidget(self.open_folder_button)
        self.statusBar().addPermanentWidget(self.progress)
        self.statusBar().addPermanentWidget(self.cancel_button)

        self._make_actions()
        self._update_title()
        geometry, state = settings.value("window/geometry"), settings.value("window/state")
        if geometry is not None:
            self.restoreGeometry(geometry)
        else:
            self._first_size()
            log_dock = self.findChild(QDockWidget, "log")
            QTimer.singleShot(0, lambda: self.resizeDocks([log_dock], [120], Qt.Vertical))  # once laid out
            self.resizeDocks([self.findChild(QDockWidget, "explorer")], [330], Qt.Horizontal)
        if state is not None:
            self.restoreState(state)

    # ------------------------------------------------------------------ building

    def _first_size(self) -> None:
        """The first window: FIRST_SIZE centred on its screen, or the whole of a smaller screen's
        available area (maximized: the window manager's frame then fits too; a 1366 x 768 laptop
        must not hide the go-to field, the log and the status bar below its edge)."""
        available = self.screen().availableGeometry()
        width, height = FIRST_SIZE
        if width + FRAME_ALLOWANCE[0] > available.width() or height + FRAME_ALLOWANCE[1] > available.height():
            self.resize(min(width, available.width()), min(height, available.height()))
            self.setWindowState(self.windowState() | Qt.WindowMaximized)
        else:
            self.resize(width, height)
            self.move(available.center() - self.rect().center())

    def _dock(self, name: str, title: str, widget, area) -> QDockWidget:
        dock = QDockWidget(title, self)
        dock.setObjectName(name)  # saveState needs names
        dock.setWidget(widget)
        self.addDockWidget(area, dock)
        return dock

    def _action(self, text: str, slot, shortcut=None, tip: str = "") -> QAction:
        action = QAction(text, self)
        if shortcut is not None:
            action.setShortcut(QKeySequence(shortcut))
        action.setStatusTip(tip)
        if tip:
            action.setToolTip(f"{tip} ({action.shortcut().toString(QKeySequence.NativeText)})"
                              if shortcut is not None else tip)
        action.triggered.connect(lambda _checked=False: slot())
        return action

    def _make_actions(self) -> None:
        self.new_action = self._action(tr("&New project…"), self.new_project, QKeySequence.New,
                                       tr("Create a project with the wizard"))
        self.open_action = self._action(tr("&Open project…"), self.open_project, QKeySequence.Open)
        self.save_action = self._action(tr("&Save project"), self.save_project, QKeySequence.Save)
        self.import_action = self._action(tr("&Import raw files…"), self.import_survey, "Ctrl+I",
                                          tr("Add a survey from raw files"))
        self.process_action = self._action(tr("&Process"), self.process, "F5", tr("Process every survey of the project"))
        self.ppk_action = self._action(tr("Post-process &GNSS"), self.post_process_gnss, "F6",
                                       tr("Run the PPK stage (RTKLIB) of the survey on the GNSS page"))
        self.redesign_action = self._action(tr("Re-design for &tamping"), self.redesign, "F7",
                                            tr("Compute the lift and slew per sleeper of the survey shown after which "
                                               "the track passes the tolerance profile (a tamping machine's job)"))
        self.cancel_action = self._action(tr("&Cancel"), self.cancel_processing, "Esc",
                                          tr("Stop the running job (processing, export, GNSS)"))
        self.export_xlsx_action = self._action(tr("&Excel workbook…"), lambda: self.export_report("xlsx"), "Ctrl+E",
                                               tr("Export the crews' Excel workbook of the survey shown"))
        self.export_xlsx_action.setIconText(tr("Export Excel"))
        self.export_pdf_action = self._action(tr("&PDF report…"), lambda: self.export_report("pdf"), "Ctrl+Shift+E",
                                              tr("Export the PDF survey report of the survey shown"))
        self.export_pdf_action.setIconText(tr("Export PDF"))
        self.export_file_actions = make_export_actions(self)  # lift/lining, DXF, LandXML, coordinates
        self.plan_survey_action = self._action(tr("&Plan survey…"), self.plan_survey, "Ctrl+Shift+P",
                                               tr("Predict the accuracy of a planned survey (IMU, GNSS, speed, aiding)"))
        self.quit_action = self._action(tr("&Quit"), self.close, QKeySequence.Quit)
        self.cancel_action.setEnabled(False)
        file_menu = self.menuBar().addMenu(tr("&File"))
        for action in (self.new_action, self.open_action):
            file_menu.addAction(action)
        self.recent_menu = file_menu.addMenu(tr("Open &recent"))
        file_menu.addAction(self.save_action)
        file_menu.addSeparator()
        file_menu.addAction(self.import_action)
        export_menu = file_menu.addMenu(tr("&Export"))
        export_menu.addAction(self.export_xlsx_action)
        export_menu.addAction(self.export_pdf_action)
        export_menu.addSeparator()
        export_menu.addActions(self.export_file_actions)
        file_menu.addSeparator()
        file_menu.addAction(self.quit_action)
        self._make_edit_menu()
        run_menu = self.menuBar().addMenu(tr("&Run"))
        run_menu.addAction(self.process_action)
        run_menu.addAction(self.ppk_action)
        run_menu.addAction(self.redesign_action)
        run_menu.addAction(self.cancel_action)
        tools_menu = self.menuBar().addMenu(tr("&Tools"))
        tools_menu.addAction(self.plan_survey_action)
        view_menu = self.menuBar().addMenu(tr("&View"))
        for dock in self.findChildren(QDockWidget):
            view_menu.addAction(dock.toggleViewAction())
        help_menu = self.menuBar().addMenu(tr("&Help"))
        self.about_action = self._action(tr("&About insrail"), self.about)
        help_menu.addAction(self.about_action)
        toolbar = self.addToolBar(tr("Main"))
        toolbar.setObjectName("main_toolbar")
        for action in (self.new_action, self.open_action, self.save_action, self.import_action, self.process_action,
                       self.cancel_action, None, self.export_xlsx_action, self.export_pdf_action, None,
                       self.plan_survey_action):
            if action is None:
                toolbar.addSeparator()
            else:
                toolbar.addAction(action)
        self.gnss.run_button.setDefaultAction(self.ppk_action)
        self._fill_recent()
        self._enable_project_actions()

    def _make_edit_menu(self) -> None:
        self.settings_action = self._action(tr("Project &settings…"), self.edit_settings, "Ctrl+,",
                                            tr("Edit the project's settings (coordinate system, trolley, processing, "
                                            "assessment)"))
        self.undo_action = self.undo_group.createUndoAction(self, tr("&Undo"))
        self.undo_action.setShortcut(QKeySequence.Undo)
        self.redo_action = self.undo_group.createRedoAction(self, tr("&Redo"))
        self.redo_action.setShortcut(QKeySequence.Redo)
        edit_menu = self.menuBar().addMenu(tr("&Edit"))
        for action in (self.undo_action, self.redo_action):
            edit_menu.addAction(action)
        edit_menu.addSeparator()
        edit_menu.addAction(self.settings_action)
        self.preferences_action = self._action(tr("&Preferences…"), self.edit_preferences, QKeySequence.Preferences,
                                               tr("The application's language"))
        edit_menu.addAction(self.preferences_action)

    def edit_preferences(self) -> PreferencesDialog:
        dialog = PreferencesDialog(self.settings, self)
        dialog.open()
        return dialog

    def edit_settings(self) -> SettingsEditor | None:
        """The settings editor of the open project (not modal; one at a time)."""
        if self.project is None:
            return None
        if self.settings_editor is None or self.settings_editor.project.path != self.project.path:
            if self.settings_editor is not None:
                self.settings_editor.close()
            self.settings_editor = SettingsEditor(self.project, self)
            self.undo_group.addStack(self.settings_editor.undo_stack)
            self.settings_editor.saved.connect(self._settings_saved)
            # Closed, its edits are out of sight: the Edit menu's Undo must not change them unseen.
            self.settings_editor.finished.connect(lambda _result: self.undo_group.setActiveStack(None))
        self.undo_group.setActiveStack(self.settings_editor.undo_stack)
        self.settings_editor.show()
        self.settings_editor.raise_()
        return self.settings_editor

    def _settings_saved(self, project: Project) -> None:
        self.log.info(tr("settings saved to {path}; {rerun}").format(path=project.path.resolve(),
                                                                     rerun=self.settings_editor.rerun.text()))
        self.set_project(project, modified=self.modified)  # the editor stays open on the saved project

    def _fill_recent(self) -> None:
        self.recent_menu.clear()
        for path in recent_projects(self.settings):
            self.recent_menu.addAction(path, lambda path=path: self.open_project(path))
        self.recent_menu.setEnabled(not self.recent_menu.isEmpty())

    def _enable_project_actions(self) -> None:
        has_project, busy = self.project is not None, self.worker is not None
        for action in (self.save_action, self.import_action, self.process_action):
            action.setEnabled(has_project and not busy)
        self.settings_action.setEnabled(has_project)
        for action in (self.export_xlsx_action, self.export_pdf_action, self.redesign_action,
                       *self.export_file_actions):
            action.setEnabled(self.shown_survey in self.results and not busy)
        self.ppk_action.setEnabled(has_project and bool(self.gnss.survey.currentText()) and not busy)
        for action in (self.new_action, self.open_action):
            action.setEnabled(not busy)
        self.cancel_action.setEnabled(busy)

    def _update_title(self) -> None:
        if self.project is None:
            self.setWindowTitle(tr("no project — insrail"))
            return
        self.setWindowTitle(f"{self.project.name}{' *' if self.modified else ''} — "
                            f"{self.project.folder.resolve()} — insrail")

    # ------------------------------------------------------------------ projects

    def maybe_save(self) -> bool:
        """True when it is fine to drop the current project (saved, discarded, or nothing to lose)."""
        if not self.modified or self.project is None:
            return True
        answer = QMessageBox.question(self, tr("Unsaved changes"), tr("Save the changes to {project}?").format(project=self.project.name),
                                      QMessageBox.Save | QMessageBox.Discard | QMessageBox.Cancel, QMessageBox.Save)
        if answer == QMessageBox.Save:
            return self.save_project()
        return answer == QMessageBox.Discard

    def new_project(self) -> NewProjectWizard | None:
        """Open the wizard (not modal: the window stays usable); the project opens when it finishes."""
        if not self.maybe_save():
            return None
        self.wizard = NewProjectWizard(self, recent_projects(self.settings))
        self.wizard.accepted.connect(lambda: self.set_project(self.wizard.project))
        self.wizard.show()
        return self.wizard

    def open_project(self, path: str | Path | None = None) -> bool:
        if not self.maybe_save():
            return False
        if path is None:
            path, _ = QFileDialog.getOpenFileName(self, tr("Open project"), filter=tr("insrail project (project.toml)"))
            if not path:
                return False
        try:
            project = load_project(path)
        except InputError as error:
            self._warn(tr("Cannot open the project"), error.said())
            return False
        self.set_project(project)
        return True

    def set_project(self, project: Project, modified: bool = False) -> None:
        self._remember_view()
        if self.settings_editor is not None and self.settings_editor.project.path != project.path:
            self.settings_editor.close()  # another project's settings must not stay open
            self.undo_group.removeStack(self.settings_editor.undo_stack)
            self.settings_editor = None
        self.project = project
        self.modified = modified
        remember_project(self.settings, project.path)
        self._fill_recent()
        self.explorer.set_project(project)
        self.log.info(tr("project {name}: {path}").format(name=project.name, path=project.path.resolve()))
        self.results.clear()
        self.shown_survey = None
        self._clear_views()
        self.empty_state.show_loading(project.name)
        self._pending_view = load_view_state(self.settings, project.path)
        self._request_views(self._pending_view.get("survey") if self._pending_view else None)
        raw_gnss = self._raw_gnss_surveys()
        self.tabs.setTabVisible(self.tabs.indexOf(self.gnss), bool(raw_gnss))
        self.gnss.set_surveys(raw_gnss)
        self._update_title()
        self._enable_project_actions()

    def save_project(self) -> bool:
        if self.project is None:
            return False
        try:
            save_project(self.project)
        except OSError as error:
            QMessageBox.warning(self, tr("Cannot save the project"), str(error))
            return False
        self.modified = False
        self._update_title()
        self.log.info(tr("saved {path}").format(path=self.project.path.resolve()))
        return True

    def import_survey(self) -> ImportDialog | None:
        """The import dialog (not modal); an imported survey joins the project (unsaved until Save)."""
        if self.project is None:
            return None
        fallback = None
        try:
            fallback = read_manifest(self.project.resolve(self.project.surveys[0].folder)).trolley
        except InputError as error:
            self.log.warning(tr("first survey's trolley geometry unavailable: {error}").format(error=error.said()))
        dialog = ImportDialog(self.project.trolley(), fallback, self)
        dialog.accepted.connect(lambda: self.add_survey(dialog.widget.name.text().strip(), dialog.folder))
        dialog.show()
        return dialog

    def add_survey(self, name: str, folder: Path) -> bool:
        project = self.project
        relative = os.path.relpath(folder.resolve(), project.folder.resolve()).replace(os.sep, "/")
        document = project.to_settings()
        document["surveys"] = [*document["surveys"], {"name": name, "folder": relative}]
        try:
            updated = project_from_settings(document, project.folder, project.path)
        except ProjectError as error:
            self.log.error(error.said())
            QMessageBox.warning(self, tr("Cannot add the survey"), "\n".join(problem.said() for problem in error.phrases))
            return False
        self.set_project(updated, modified=True)
        self.log.info(tr("survey {name} imported from {folder}").format(name=name, folder=folder.resolve()))
        return True

    # ------------------------------------------------------------------ processing

    def process(self, surveys: list[str] | None = None) -> ProcessingWorker | None:
        if self.project is None or self.worker is not None:
            return None
        if self.modified and not self.save_project():
            return None
        names = surveys or [s.name for s in self.project.surveys]
        worker = ProcessingWorker(self.project, names, self)
        worker.surveyDone.connect(self._survey_done)
        worker.cancelled.connect(self._processing_cancelled)
        return self._start(worker, tr("processing {surveys}").format(surveys=", ".join(names)), tr("Processing failed"))

    def _processing_cancelled(self) -> None:
        self.log.warning(tr("processing cancelled; previous results kept"))

    def _start(self, worker: CoreWorker, message: str, failure_title: str) -> CoreWorker:
        """Run a core job with the status bar's progress and Cancel; one job at a time."""
        self.worker = worker
        self.job_failure_title = failure_title
        self.done_message = tr("Ready")
        worker.progressed.connect(self._progressed)
        worker.failed.connect(self._failed)
        worker.finished.connect(self._worker_finished)
        self.progress.setValue(0)
        self.progress.show()
        self.cancel_button.show()
        self.cancel_button.setEnabled(True)
        self.open_folder_button.hide()
        self.log.info(message)
        worker.start()
        self._enable_project_actions()
        return worker

    def cancel_processing(self) -> None:
        if self.worker is not None:
            self.worker.cancel()
            self.cancel_button.setEnabled(False)
            self.status.setText(tr("Cancelling…"))

    def _progressed(self, fraction: float, message: ProgressMessage) -> None:
        self.progress.setValue(round(fraction * PROGRESS_STEPS))
        text = progress_text(message)  # in the window's language (the core wrote the template)
        self.status.setText(text)
        self.log.progress(text)

    def _survey_done(self, name: str) -> None:
        self.explorer.set_project(self.project)
        self.results.pop(name, None)  # processed again: the loader reads the new results
        self.show_results(name)
        if name == self.gnss.survey.currentText():
            self.show_gnss(name)
        folder = self.project.folder / RESULTS_FOLDER / name
        summary = read_toml(folder / SUMMARY_FILE)
        for notice in notices_of(summary):
            self.log.warning(f"{name}: {notice.said()}")  # in the application's language
        for path in stale_reports(self.project.folder, name):
            self.log.warning(tr("{survey}: {file} is older than these results: the banner over the views writes it "
                                "again").format(survey=name, file=path.name))
        self.log.info(tr("{survey}: {count} exceedances, results in {folder}").format(
            survey=name, count=summary["assessment"]["exceedances"], folder=folder.resolve()))

    def _failed(self, message: str) -> None:
        self._warn(self.job_failure_title, message)

    def _warn(self, title: str, message: str) -> None:
        """An error the user must see: in the log and in a dialog."""
        self.log.error(message)
        QMessageBox.warning(self, title, message)

    def _worker_finished(self) -> None:
        self.worker.deleteLater()
        self.worker = None
        self.progress.hide()
        self.cancel_button.hide()
        self.status.setText(self.done_message)
        self._enable_project_actions()
        self._show_stale_reports()  # written again, or made out of date by processing
        self.explorer.mark_reports()

    # ------------------------------------------------------------------ results

    def _clear_views(self) -> None:
        """Nothing of the previous project or survey stays on screen."""
        self.stale_banner.show_stale(None, [])
        self.track.clear_results()
        self.plan.clear_data()
        self.navigation.clear()
        self.repeatability.set_runs({})
        self.redesign_view.set_data(None)

    def _request_views(self, show: str | None) -> None:
        """Read the results (those not yet read) and the views of survey ``show`` (None: the first
        processed one) in a worker; the answers arrive in :meth:`_results_loaded`, :meth:`_track_ready`
        and :meth:`_trajectory_ready`, and are dropped if another request came meanwhile."""
        if self.loader is not None:
            self.loader.cancel()
        gc.unfreeze()  # what the previous results leave behind is collected again
        self.request += 1
        loader = ResultsLoader(self.request, self.project, [s.name for s in self.project.surveys], show,
                               self.results, self)
        loader.resultsLoaded.connect(self._results_loaded)
        loader.trackReady.connect(self._track_ready)
        loader.trajectoryReady.connect(self._trajectory_ready)
        loader.failed.connect(self._load_failed)
        loader.finished.connect(lambda loader=loader: self._loader_finished(loader))
        self.loader = loader
        self._loaders.add(loader)
        loader.start()

    def _loader_finished(self, loader: ResultsLoader) -> None:
        self._loaders.discard(loader)
        if loader is self.loader:
            self.loader = None
            # The loaded results, plots and their Qt wrappers are some 180 000 objects that live as
            # long as the project is shown: a full cyclic collection traversing them took 30-180 ms,
            # now and then in the middle of a pan frame. Frozen, the collector skips them until the
            # next load (no pause here: freezing moves them, it does not traverse them).
            gc.freeze()
        loader.deleteLater()

    def _results_loaded(self, request: int, results: dict) -> None:
        if request != self.request:
            return
        self.results = results
        self._show_runs()
        show = self.loader.show if self.loader is not None else None
        if show is None and not results:  # nothing processed yet: say so and offer Process
            surveys = self.project.surveys
            self.empty_state.show_unprocessed(surveys[0].name if surveys else None)
        self._enable_project_actions()

    def _track_ready(self, request: int, data: TrackData, chainage: ChainageAxis) -> None:
        if request != self.request:
            return
        self.shown_survey = data.survey
        self.empty_state.hide()
        self.track.set_results(data.station_m, data.number, data.label, data.columns, data.plots,
                               data.exceedances, data.bands, data.survey, data.events, chainage, data.invalid,
                               data.not_assessed)
        self.redesign_view.set_data(data.redesign)
        pending, self._pending_view = self._pending_view, None
        if pending is not None and pending.get("survey") == data.survey:
            self.track.restore_state(pending)
            if isinstance(pending.get("tab"), int) and self.tabs.isTabVisible(pending["tab"]):
                self.tabs.setCurrentIndex(pending["tab"])
        self.status.setText(tr("Showing survey {survey}").format(survey=data.survey))
        self._show_stale_reports()
        self._enable_project_actions()
        if self.loader is not None:  # the trajectory is read once the track view is painted
            QTimer.singleShot(0, self.loader.track_drawn.set)

    def _trajectory_ready(self, request: int, views: TrajectoryViews) -> None:
        if request != self.request:
            return
        for warning in views.warnings:
            self.log.warning(warning)
        self.plan.set_data(views.plan)
        self.navigation.set_series(views.time_s, views.series, views.bands, views.lines)

    def _load_failed(self, request: int, message: str) -> None:
        if request == self.request:
            self.log.error(message)

    def show_results(self, name: str) -> None:
        """Show one survey in every view (the repeatability view with all processed ones): the
        previous survey's plots go at once, the new ones come from a worker; a survey without
        results shows the empty state with Process. The same survey again (processed once more)
        keeps its chainage window, plots and tab."""
        self._pending_view = self._view_state() if name == self.shown_survey else None
        self.shown_survey = None
        self._clear_views()
        if name not in self.results and not (self.project.folder / RESULTS_FOLDER / name / SUMMARY_FILE).is_file():
            self.empty_state.show_unprocessed(name)
            self._show_runs()
            self._enable_project_actions()
            return
        for line in settings_change_lines(self.project, name):  # the views show what was processed
            self.log.warning(f"{name}: {line.said()}")  # in the application's language
        self._request_views(name)

    def _show_runs(self) -> None:
        """Every processed survey in the repeatability view, its parameters named with the project's checks."""
        try:
            checks = load_tolerance_profile(self.project.resource(self.project.tolerance_profile)).checks
        except (InputError, ValueError, OSError) as error:
            self.log.warning(tr("the check channels are shown by their columns: {error}").format(error=said(error)))
            checks = ()
        self.repeatability.set_runs({run: (s.columns["station_m"], s.columns) for run, s in self.results.items()},
                                    checks)

    def _view_state(self) -> dict | None:
        if self.shown_survey is None:
            return None
        return {"survey": self.shown_survey, "tab": self.tabs.currentIndex(), **self.track.view_state()}

    def _remember_view(self) -> None:
        """Keep the open project's view state for the next time it is opened."""
        state = self._view_state()
        if self.project is not None and state is not None:
            save_view_state(self.settings, self.project.path, state)

    def _mark_in_plan(self, first_sleeper: int, last_sleeper: int) -> None:
        number = self.results[self.shown_survey].number
        self.plan.mark_sleepers(np.flatnonzero((number >= first_sleeper) & (number <= last_sleeper)))

    # ------------------------------------------------------------------ export

    def export_report(self, kind: str, path: str | Path | None = None) -> TaskWorker | None:
        """Write the shown survey's Excel workbook (``kind`` "xlsx") or PDF report ("pdf") in a worker;
        without ``path`` a file dialog asks, starting at the default name in the project's reports folder."""
        return export_files.export_report(self, kind, path)

    def rewrite_reports(self, survey: str | None = None) -> TaskWorker | None:
        """Write the reports of ``survey`` (None: the one shown) again where they are older than its
        results (one click)."""
        return export_files.rewrite_stale_reports(self, survey)

    def _show_stale_reports(self) -> None:
        """The banner over the views and the explorer name the shown survey's out-of-date reports."""
        survey = self.shown_survey
        stale = stale_reports(self.project.folder, survey) if self.project is not None and survey else []
        self.stale_banner.show_stale(survey, [path.name for path in stale])
        older = self.project is not None and bool(survey) and results_older_than_events(self.project, survey)
        self.events_banner.show_older(survey if older else None, self.project.events if older else "")

    def mark_event(self, from_m: float, to_m: float) -> EventDialog | None:
        """The track view's measured span as a track event of the project (the dialog asks what it is)."""
        if self.project is None:
            return None
        dialog = EventDialog(self.project, from_m, to_m, self)
        dialog.accepted.connect(lambda: self._event_marked(dialog))
        dialog.open()
        return dialog

    def _event_marked(self, dialog: EventDialog) -> None:
        self.project = dialog.project
        if self.settings_editor is not None:
            self.settings_editor.adopt_saved("track.events", self.project.events)
        event = dialog.events.events[-1]
        self.log.info(tr("{kind} {start:.3f}–{end:.3f} m marked in {file}; processing again assesses with it").format(
            kind=t(KIND_NAMES[event.kind]), start=event.start, end=event.end,
            file=self.project.resolve(self.project.events).resolve()))
        self._show_stale_reports()

    def _exported(self, path: Path) -> None:
        self.exported = path
        self.log.info(tr("written {path}").format(path=path.resolve()))
        self.done_message = tr("Written {name} in {folder}").format(name=path.name, folder=path.parent.resolve())
        self.open_folder_button.show()

    def _export_cancelled(self) -> None:
        self.log.warning(tr("export cancelled; nothing written"))

    def open_export_folder(self) -> None:
        """Open the folder of the last exported report in the desktop's file manager."""
        if self.exported is not None:
            QDesktopServices.openUrl(QUrl.fromLocalFile(str(self.exported.parent.resolve())))

    # ------------------------------------------------------------------ GNSS (PPK)

    def _raw_gnss_surveys(self) -> list[str]:
        """The surveys whose survey.toml holds raw GNSS observations ([gnss_raw])."""
        names = []
        for entry in self.project.surveys:
            try:
                if self.project.manifest(entry.name).raw_gnss is not None:
                    names.append(entry.name)
            except InputError:  # the explorer shows the problem
                continue
        return names

    def show_gnss(self, name: str) -> None:
        """The GNSS page for one survey: its raw inputs and, once post-processed, the QC."""
        project = self.project
        folder = project.resolve(project.survey(name).folder)
        raw = project.manifest(name).raw_gnss
        self.gnss.set_inputs(input_rows(raw, folder, project.control_point(raw.base_point)))
        try:
            self.gnss.set_ppk(stored_ppk(project, name), " (from the processed results)")
        except InputError as error:
            self.log.error(error.said())
            self.gnss.set_ppk(None)
        self._enable_project_actions()

    def post_process_gnss(self) -> TaskWorker | None:
        """Run the PPK stage alone for the survey on the GNSS page (cached like the pipeline's)."""
        name = self.gnss.survey.currentText()
        if self.project is None or self.worker is not None or not name:
            return None
        project = self.project
        folder = project.resolve(project.survey(name).folder)
        try:
            manifest = project.manifest(name)
        except InputError as error:
            self._warn(tr("GNSS post-processing failed"), error.said())
            return None
        cache = project.folder / RESULTS_FOLDER / CACHE_FOLDER

        def task(progress, cancel) -> GnssStageResult:
            with project_run(project.folder, [name], progress, cancel):  # as processing the survey does
                return run_gnss_stage(project, folder, manifest, cache, progress, cancel)

        worker = TaskWorker(tr("survey {survey}: GNSS").format(survey=name), task, self)
        worker.succeeded.connect(self._gnss_done)
        worker.cancelled.connect(self._gnss_cancelled)
        self.tabs.setCurrentWidget(self.gnss)
        return self._start(worker, tr("post-processing the GNSS of {survey}").format(survey=name), tr("GNSS post-processing failed"))

    def _gnss_done(self, stage: GnssStageResult) -> None:
        summary = stage.summary(self.project.fusion.gnss_quality_policy)
        source = tr(" (from the cache)") if stage.from_cache else tr(" (computed now)")
        self.gnss.set_ppk(PpkView(stage.report, stage.solution, summary), source)
        self.log.info(tr("GNSS of {survey}: fix rate {rate:.1f} % of {epochs} epochs{source}").format(
            survey=self.gnss.survey.currentText(), rate=100.0 * stage.qc.fix_rate, epochs=stage.qc.epochs, source=source))
        for warning in stage.warnings():
            self.log.warning(warning.said())

    def _gnss_cancelled(self) -> None:
        self.log.warning(tr("GNSS post-processing cancelled"))

    # ------------------------------------------------------------------ tamping re-design

    def redesign(self) -> TaskWorker | None:
        """Re-design the survey shown for a tamping machine (``insrail redesign``) in a worker; the
        re-design view shows it when written."""
        name = self.shown_survey
        if self.project is None or self.worker is not None or name not in self.results:
            return None
        project, stored = self.project, self.results[name]

        def task(progress, cancel) -> tuple[dict, RedesignPlot | None]:
            with project_run(project.folder, [name], progress, cancel):
                run = run_redesign(project, name, progress, cancel)
            return run.summary, redesign_plot(stored)

        worker = TaskWorker(tr("survey {survey}: tamping re-design").format(survey=name), task, self)
        worker.succeeded.connect(self._redesign_done)
        worker.cancelled.connect(lambda: self.log.warning(tr("tamping re-design cancelled; nothing written")))
        return self._start(worker, tr("re-designing {survey} for tamping").format(survey=name), tr("Tamping re-design failed"))

    def _redesign_done(self, answer: tuple[dict, RedesignPlot | None]) -> None:
        summary, plot = answer
        self.redesign_view.set_data(plot)
        self.tabs.setCurrentWidget(self.redesign_view)
        movement, count = summary["movement"], summary["exceedances"]
        self.log.info(tr("{survey} re-designed: largest lift {lift_mm:.1f} mm, largest slew {slew_mm:.1f} mm; "
                         "exceedances of {profile}: {before} before, {after} after the job").format(
            survey=summary["survey"], lift_mm=movement["largest_lift_mm"], slew_mm=movement["largest_slew_mm"],
            profile=summary["profile"], before=count["before"], after=count["after"]))
        for stretch in summary["cannot_pass"]:
            self.log.warning(tr("{survey}: cannot pass under the constraints: {what} {from_m:.1f}-{to_m:.1f} m "
                                "(peak {value_mm:.2f} mm)").format(survey=summary["survey"], what=stretch["what"],
                                                                   from_m=stretch["from_m"], to_m=stretch["to_m"],
                                                                   value_mm=stretch["value_mm"]))
        if summary.get("uncertain"):
            self.log.warning(tr("{survey}: {count} stretches pass after the job by less than the survey's uncertainty "
                                "of the check (three stated 1-sigma): the true track there may not pass").format(
                survey=summary["survey"], count=len(summary["uncertain"])))
        for item in summary.get("not_assessed", []):
            self.log.warning(tr("{survey}: not assessed after the job: {check} {direction} (stated 1-sigma {sigma_mm:.2f} mm "
                                "against the limit {limit_mm:.1f} mm) over {where}").format(
                survey=summary["survey"], check=item["check"], direction=item["direction"], sigma_mm=item["sigma_mm"],
                limit_mm=item["limit_mm"], where=", ".join(f"{a:.0f}-{b:.0f} m" for a, b in item["stretches_m"])))
        if summary["design"]["problem"]:
            self.log.warning(f"{summary['survey']}: {summary['design']['problem']}")

    # ------------------------------------------------------------------ tools and help

    def plan_survey(self) -> PlanSurveyDialog:
        """The Plan survey dialog (not modal; one at a time)."""
        if self.plan_dialog is None:
            self.plan_dialog = PlanSurveyDialog(self)
        self.plan_dialog.show()
        self.plan_dialog.raise_()
        return self.plan_dialog

    def about(self) -> None:
        QMessageBox.about(self, tr("About insrail"), f"<b>insrail {__version__}</b><br>" + tr(
            "Inertial track-geometry trolley processing: GNSS/INS/odometer fusion, track geometry, reports."))

    # ------------------------------------------------------------------ closing

    def closeEvent(self, event) -> None:
        if self.worker is not None:
            self.worker.cancel()
            self.worker.wait()
        for loader in list(self._loaders):
            loader.cancel()
            loader.wait()
        self._remember_view()
        if self.plan_dialog is not None:
            self.plan_dialog.close()
        if self.settings_editor is not None:
            self.settings_editor.close()
        if not self.maybe_save():
            event.ignore()
            return
        self.settings.setValue("window/geometry", self.saveGeometry())
        self.settings.setValue("window/state", self.saveState())
        self.settings.sync()
        event.accept()
