"""Screenshots of the main views and tools into docs/gui_*.png (the window at 1400 x 900, offscreen).

    QT_QPA_PLATFORM=offscreen python benchmarks/gui_screenshots.py PROJECT_FOLDER [RAW_GNSS_PROJECT_FOLDER]

The docs/ pictures show the demo project with a second simulated run (seed 2) added as survey
`short2`, so that the repeatability view has two runs to overlay; the export picture writes the
PDF report into the project's results. With a second project whose survey holds raw GNSS
observations (``[gnss_raw]``), the GNSS page is post-processed and shown too.
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

from PySide6.QtCore import QSettings
from PySide6.QtWidgets import QApplication

from insrail.gui.main_window import MainWindow

DOCS = Path(__file__).resolve().parent.parent / "docs"


def settle(app, seconds: float = 0.3) -> None:
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        app.processEvents()


def wait(app, busy) -> None:
    while busy():
        app.processEvents()
        time.sleep(0.02)
    settle(app)


def save(widget, name: str) -> None:
    path = DOCS / f"gui_{name}.png"
    widget.grab().save(str(path))
    print(f"{path}: {path.stat().st_size / 1e3:.0f} kB")


def main(project: str, raw_gnss_project: str | None = None) -> None:
    app = QApplication.instance() or QApplication([])
    with tempfile.TemporaryDirectory() as settings_folder:
        window = MainWindow(QSettings(str(Path(settings_folder) / "s.ini"), QSettings.IniFormat))
        window.resize(1400, 900)
        window.show()
        window.open_project(project)
        shots = {"track": window.track, "plan": window.plan, "navigation": window.navigation,
                 "repeatability": window.repeatability}
        for name, view in shots.items():
            window.tabs.setCurrentWidget(view)
            if name == "track":
                window.track.exceedances.selectRow(4)  # the fifth along the track
            settle(app)
            save(window, name)

        window.tabs.setCurrentWidget(window.track)
        window.export_report("pdf", window.results[window.shown_survey].folder / "track_geometry_short.pdf")
        wait(app, lambda: window.worker is not None)
        save(window, "export")

        dialog = window.plan_survey()
        dialog.outage.setValue(60.0)
        dialog.run()
        wait(app, lambda: dialog.worker is not None)
        save(dialog, "plan_survey")
        dialog.sweep.setCurrentText("gyro_bias")
        dialog.run()
        wait(app, lambda: dialog.worker is not None)
        save(dialog, "plan_survey_sweep")
        dialog.close()

        if raw_gnss_project is not None:
            window.open_project(raw_gnss_project)
            window.post_process_gnss()
            wait(app, lambda: window.worker is not None)
            save(window, "gnss")
        window.modified = False
        window.close()


if __name__ == "__main__":
    main(*sys.argv[1:3])
