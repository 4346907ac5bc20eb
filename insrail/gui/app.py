"""Start the desktop application."""

from __future__ import annotations

import sys
import time
from pathlib import Path


def run(project: str | Path | None = None, argv: list[str] | None = None, screenshot: str | Path | None = None) -> int:
    """Show the main window (opening ``project`` if given) and run the event loop; the exit code.

    With ``screenshot`` the window is drawn once with the project's results, saved as that PNG
    and closed (a check that the application starts, e.g. from an installed bundle)."""
    from PySide6.QtWidgets import QApplication

    from insrail.memory import tune_allocator
    from insrail.gui.main_window import MainWindow
    from insrail.gui.settings import APPLICATION, ORGANISATION, user_settings
    from insrail.gui.translation import chosen_language, install_language

    tune_allocator()
    app = QApplication.instance() or QApplication(argv if argv is not None else sys.argv[:1])
    app.setOrganizationName(ORGANISATION)
    app.setApplicationName(APPLICATION)
    settings = user_settings()
    install_language(app, chosen_language(settings))  # before any window: its texts are translated when made
    window = MainWindow(settings)
    window.show()
    if project is not None and not window.open_project(project):
        return 1
    if screenshot is not None:
        while window.loader is not None:  # the results are read in a worker
            app.processEvents()
            time.sleep(0.01)
        app.processEvents()
        window.resize(1400, 900)
        app.processEvents()
        saved = window.grab().save(str(screenshot))
        window.setWindowModified(False)
        window.close()
        return 0 if saved else 1
    return app.exec()


def main() -> int:
    """The ``insrail-gui`` entry point: ``insrail-gui [PROJECT]``."""
    return run(sys.argv[1] if len(sys.argv) > 1 else None)
