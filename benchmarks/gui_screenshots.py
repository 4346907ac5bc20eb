"""Screenshots of the main views into docs/gui_*.png (the window at 1400 x 900, offscreen).

    QT_QPA_PLATFORM=offscreen python benchmarks/gui_screenshots.py PROJECT_FOLDER

The docs/ pictures show the demo project with a second simulated run (seed 2) added as survey
`short2`, so that the repeatability view has two runs to overlay.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

from PySide6.QtCore import QSettings
from PySide6.QtWidgets import QApplication

from insrail.gui.main_window import MainWindow

DOCS = Path(__file__).resolve().parent.parent / "docs"


def main(project: str) -> None:
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
            for _ in range(5):
                app.processEvents()
            path = DOCS / f"gui_{name}.png"
            window.grab().save(str(path))
            print(f"{path}: {path.stat().st_size / 1e3:.0f} kB")
        window.modified = False
        window.close()


if __name__ == "__main__":
    main(sys.argv[1])
