"""File > Export: the reports (Excel workbook, PDF) and the files for the machines and CAD
(insrail.export: lift/lining table, DXF, LandXML lines, coordinates), and writing a survey's
reports again when they are older than its results. Each export asks for a file (the default
name in the project's reports folder) and writes it in a worker, with the window's progress and
Cancel; the window is the :class:`insrail.gui.main_window.MainWindow`."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from PySide6.QtGui import QAction
from PySide6.QtWidgets import QFileDialog

from insrail.export import default_export_path, export_formats, write_export
from insrail.notices import Phrase
from insrail.progress import CancelToken, ProgressFn, StepProgress
from insrail.project.lock import project_run
from insrail.project.results import report_path
from insrail.report import write_pdf, write_workbook
from insrail.report.stale import stale_reports
from insrail.gui.translation import tr, tr_noop

#: report kind (its suffix) -> (what it is, writer, file dialog filter)
REPORTS = {"xlsx": (tr_noop("Excel workbook"), write_workbook, tr_noop("Excel workbook (*.xlsx)")),
           "pdf": (tr_noop("PDF report"), write_pdf, tr_noop("PDF report (*.pdf)"))}
#: export format -> (menu text, file filter)
MENU = {"lift-lining": (tr_noop("&Lift/lining table…"), tr_noop("Lift/lining table (*.csv)")),
        "dxf": (tr_noop("&DXF drawing…"), tr_noop("DXF drawing (*.dxf)")),
        "landxml": (tr_noop("Measured lines as &LandXML…"), tr_noop("LandXML (*.xml)")),
        "csv": (tr_noop("Sleeper &coordinates…"), tr_noop("CSV (*.csv)"))}


def make_export_actions(window) -> list[QAction]:
    """The actions of File > Export for every export format (enabled like the report exports)."""
    actions = []
    for name, (text, _filter) in MENU.items():
        action = QAction(tr(text), window)
        action.setStatusTip(tr("Export the survey shown: {what}").format(what=export_formats()[name].description))
        action.triggered.connect(lambda _checked=False, name=name: export_file(window, name))
        actions.append(action)
    return actions


def _ready(window) -> bool:
    return window.project is not None and window.shown_survey in window.results and window.worker is None


def _chosen_path(window, what: str, default: Path, file_filter: str, suffix: str, path) -> Path | None:
    """``path``, or the file the user picks (the dialog starts at ``default``), ending in ``.suffix``."""
    if path is None:
        default.parent.mkdir(exist_ok=True)  # the dialog opens in the project's reports folder
        path, _ = QFileDialog.getSaveFileName(window, tr("Export the {what} of {survey}").format(
                                                  what=what.lower(), survey=window.shown_survey),
                                              str(default), file_filter)
        if not path:
            return None
    path = Path(path)
    return path if path.suffix.lower() == f".{suffix}" else path.with_name(f"{path.name}.{suffix}")


def _start_writing(window, survey: str, subject: str, message: str, write: Callable[[ProgressFn, CancelToken], Path]):
    """Run ``write`` in a worker holding ``survey``'s lock, as the command line's report and export
    do (a run of the survey started elsewhere is waited for in the worker, with its message in the
    status bar, and can be cancelled); a file system error is worded about the file the user chose."""
    from insrail.gui.worker import TaskWorker

    folder = window.project.folder

    def task(progress, cancel) -> Path:
        with project_run(folder, [survey], progress, cancel):
            try:
                return write(progress, cancel)
            except OSError as error:
                raise OSError(f"cannot write the file: {error.strerror or error}") from error

    worker = TaskWorker(subject, task, window)
    worker.succeeded.connect(window._exported)
    worker.cancelled.connect(window._export_cancelled)
    return window._start(worker, message, tr("Export failed"))


def export_report(window, kind: str, path: str | Path | None = None):
    """Write the shown survey's Excel workbook (``kind`` "xlsx") or PDF report ("pdf")."""
    if not _ready(window):
        return None
    survey, stored, project = window.shown_survey, window.results[window.shown_survey], window.project
    what, writer, file_filter = REPORTS[kind]
    what, file_filter = tr(what), tr(file_filter)
    path = _chosen_path(window, what, report_path(project.folder, survey, kind), file_filter, kind, path)
    if path is None:
        return None
    return _start_writing(window, survey, f"{what} {path}", tr("exporting the {what} of {survey} to {path}").format(what=what.lower(), survey=survey, path=path),
                          lambda progress, cancel: writer(project, stored, path, progress, cancel))


def export_file(window, format_name: str, path: str | Path | None = None):
    """Write one export (lift/lining, DXF, LandXML, coordinates) of the shown survey."""
    if not _ready(window):
        return None
    survey, stored, project = window.shown_survey, window.results[window.shown_survey], window.project
    text, file_filter = MENU[format_name]
    what = text.replace("&", "").removesuffix("…")
    suffix = export_formats()[format_name].suffix.rsplit(".", 1)[1]
    path = _chosen_path(window, what, default_export_path(project.folder, survey, format_name), file_filter, suffix,
                        path)
    if path is None:
        return None

    def write(progress, _cancel) -> Path:
        progress(0.0, Phrase("writing {file}", {"file": path.name}))
        return write_export(project, stored, format_name, path)

    return _start_writing(window, survey, f"{what} {path}", tr("exporting the {what} of {survey} to {path}").format(what=what.lower(), survey=survey, path=path),
                          write)


def rewrite_stale_reports(window, survey: str | None = None):
    """Write again, at their places, the reports of ``survey`` (None: the one shown) that are older
    than its results."""
    survey = survey or window.shown_survey
    if window.project is None or survey not in window.results or window.worker is not None:
        return None
    stored, project = window.results[survey], window.project
    stale = stale_reports(project.folder, survey)
    if not stale:
        return None

    def write(progress, cancel) -> Path:
        step = StepProgress(progress)
        for k, path in enumerate(stale):
            REPORTS[path.suffix.lstrip(".").lower()][1](project, stored, path, step.sub(k / len(stale),
                                                                                        (k + 1) / len(stale)), cancel)
        return stale[-1]

    names = ", ".join(path.name for path in stale)
    return _start_writing(window, survey, tr("reports of {survey}").format(survey=survey),
                          tr("writing {files} again from the results of {survey}").format(files=names, survey=survey), write)
