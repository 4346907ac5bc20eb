"""File > Export of the files for the machines and CAD (insrail.export): lift/lining table, DXF,
LandXML lines, coordinates. One action per format; each asks for a file (the default name in the
project's reports folder) and writes it in a worker, like the reports."""

from __future__ import annotations

from pathlib import Path

from PySide6.QtGui import QAction
from PySide6.QtWidgets import QFileDialog

from insrail.export import default_export_path, export_formats, write_export

#: format -> (menu text, file filter)
MENU = {"lift-lining": ("&Lift/lining table…", "Lift/lining table (*.csv)"),
        "dxf": ("&DXF drawing…", "DXF drawing (*.dxf)"),
        "landxml": ("Measured lines as &LandXML…", "LandXML (*.xml)"),
        "csv": ("Sleeper &coordinates…", "CSV (*.csv)")}


def make_export_actions(window) -> list[QAction]:
    """The actions of File > Export for every export format (enabled like the report exports)."""
    actions = []
    for name, (text, _filter) in MENU.items():
        action = QAction(text, window)
        action.setStatusTip(f"Export the survey shown: {export_formats()[name].description}")
        action.triggered.connect(lambda _checked=False, name=name: export_file(window, name))
        actions.append(action)
    return actions


def export_file(window, format_name: str, path: str | Path | None = None):
    """Write one export of the shown survey in a worker; without ``path`` a file dialog asks."""
    from insrail.gui.worker import TaskWorker

    if window.project is None or window.shown_survey not in window.results or window.worker is not None:
        return None
    survey, stored, project = window.shown_survey, window.results[window.shown_survey], window.project
    text, file_filter = MENU[format_name]
    what = text.replace("&", "").removesuffix("…")
    if path is None:
        default = default_export_path(project.folder, survey, format_name)
        default.parent.mkdir(exist_ok=True)
        path, _ = QFileDialog.getSaveFileName(window, f"Export the {what.lower()} of {survey}", str(default), file_filter)
        if not path:
            return None
    path = Path(path)
    suffix = export_formats()[format_name].suffix.rsplit(".", 1)[1]
    if path.suffix.lower() != f".{suffix}":
        path = path.with_name(f"{path.name}.{suffix}")

    def export(progress, cancel) -> Path:
        progress(0.0, f"writing {path.name}")
        try:
            return write_export(project, stored, format_name, path)
        except OSError as error:  # the file system's words, about the file the user chose
            raise OSError(f"cannot write the file: {error.strerror or error}") from error

    worker = TaskWorker(f"{what} {path}", export, window)
    worker.succeeded.connect(window._exported)
    worker.cancelled.connect(window._export_cancelled)
    return window._start(worker, f"exporting the {what.lower()} of {survey} to {path}", "Export failed")
