"""Screenshots of every view of the desktop application in a real X window, into docs/.

    xvfb-run -s "-screen 0 1366x768x24" python benchmarks/gui_screenshots.py PROJECT [RAW_GNSS_PROJECT]
    xvfb-run -s "-screen 0 1920x1080x24" python benchmarks/gui_screenshots.py PROJECT [RAW_GNSS_PROJECT]

The window fills the X screen; each picture is taken from the X server with ImageMagick's
``import -window root`` (what a surveyor sees, not Qt's offscreen rendering) and named after the
view and the screen size: ``docs/gui_<view>_<width>x<height>.png``. The application's language follows
the locale as when it is started (``LANG=zh_CN.UTF-8``: Chinese, the pictures named ``..._zh_CN.png``). The docs/ pictures show the
demo project with a second simulated run (seed 2) added as survey `short2`, so that the
repeatability view has two runs to overlay. With a second project whose survey holds raw GNSS
observations (``[gnss_raw]``), the GNSS page is post-processed and shown too. Without X
(``QT_QPA_PLATFORM=offscreen``) the window grabs itself instead. ``--track-only`` takes the track
view's two pictures (track, track_measure) and nothing else (the project is left as it is).
``--redesign`` runs Run > Re-design for tamping on the project's first survey (the ballasted demo,
``insrail demo --preset ballasted``) and takes the re-design view alone (``gui_redesign_...png``).
``--log`` processes every survey of the project afresh (its results' cache emptied first) and takes the
window with the log panel opened wide: the core's progress lines (``gui_log_...png``) and, scrolled to its
end, the notices and the survey's result (``gui_log_end_...png``), in the window's language.
"""

from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from PySide6.QtCore import QSettings
from PySide6.QtWidgets import QApplication

from insrail.gui.main_window import MainWindow
from insrail.gui.translation import chosen_language, install_language, tr
from insrail.project.results import report_path

DOCS = Path(__file__).resolve().parent.parent / "docs"


def settle(app, seconds: float = 0.4) -> None:
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        app.processEvents()
        time.sleep(0.01)


def wait(app, busy) -> None:
    while busy():
        app.processEvents()
        time.sleep(0.02)
    settle(app)


class Camera:
    def __init__(self, app, size: tuple[int, int], suffix: str = ""):
        self.app, self.size, self.suffix = app, size, suffix
        self.x_server = app.platformName() == "xcb" and shutil.which("import") is not None

    def save(self, widget, name: str) -> Path:
        path = DOCS / f"gui_{name}_{self.size[0]}x{self.size[1]}{self.suffix}.png"
        settle(self.app)
        if self.x_server:
            subprocess.run(["import", "-window", "root", str(path)], check=True)
        else:
            widget.grab().save(str(path))
        print(f"{path}: {path.stat().st_size / 1e3:.0f} kB")
        return path


def place(widget, size: tuple[int, int], fill: bool = True) -> None:
    """Fill the screen (there is no window manager under Xvfb to maximise it), or centre a dialog."""
    if fill:
        widget.setGeometry(0, 0, *size)
    else:
        widget.move(max((size[0] - widget.width()) // 2, 0), max((size[1] - widget.height()) // 2, 0))


def redesign_picture(app, window, camera) -> None:
    """The re-design view after Run > Re-design for tamping (the worker's progress in the status bar)."""
    window.redesign()
    wait(app, lambda: window.worker is not None)
    window.tabs.setCurrentWidget(window.redesign_view)
    camera.save(window, "redesign")


def log_picture(app, window, camera, size: tuple[int, int]) -> None:
    """The log panel after processing every survey from its raw files (the progress of each stage, the notices)."""
    from PySide6.QtCore import Qt
    from PySide6.QtWidgets import QDockWidget

    from insrail.project.pipeline import CACHE_FOLDER
    from insrail.project.results import RESULTS_FOLDER

    shutil.rmtree(window.project.folder / RESULTS_FOLDER / CACHE_FOLDER, ignore_errors=True)
    window.process()
    wait(app, lambda: window.worker is not None or window.loader is not None)
    dock = next(d for d in window.findChildren(QDockWidget) if d.widget() is window.log)
    window.resizeDocks([dock], [size[1] // 2], Qt.Vertical)
    window.log.verticalScrollBar().setValue(0)
    camera.save(window, "log")  # the progress of the stages
    window.log.verticalScrollBar().setValue(window.log.verticalScrollBar().maximum())
    camera.save(window, "log_end")  # the notices (warnings) and the survey's result


def main(project: str, raw_gnss_project: str | None = None, track_only: bool = False, redesign: bool = False,
         log: bool = False) -> None:
    app = QApplication.instance() or QApplication([])
    screen = app.primaryScreen().size()
    size = (screen.width(), screen.height())
    with tempfile.TemporaryDirectory() as settings_folder:
        settings = QSettings(str(Path(settings_folder) / "s.ini"), QSettings.IniFormat)
        language = install_language(app, chosen_language(settings))  # the locale's, as insrail gui starts
        camera = Camera(app, size, "" if language == "en" else f"_{language.replace('-', '_')}")
        window = MainWindow(settings)
        window.show()
        place(window, size)
        if not track_only and not redesign and not log:
            camera.save(window, "empty")  # no project open: what the window says
        window.open_project(project)
        wait(app, lambda: window.loader is not None)
        if log:
            log_picture(app, window, camera, size)
            window.modified = False
            window.close()
            return
        if redesign:
            redesign_picture(app, window, camera)
            window.modified = False
            window.close()
            return
        for name, view in (("track", window.track), ("plan", window.plan), ("navigation", window.navigation),
                           ("repeatability", window.repeatability)):
            if track_only and name != "track":
                continue
            window.tabs.setCurrentWidget(view)
            if name == "track":
                window.track.exceedances.selectRow(4)  # the fifth along the track
            camera.save(window, name)

        window.tabs.setCurrentWidget(window.track)
        track = window.track
        track.go_to("#300")
        track.measure_button.setChecked(True)
        track.measure("lateral_deviation", track._station[290])
        track.measure("lateral_deviation", track._station[330])
        track.show_values_at(track._station[310])
        track.plots.set_cursor(track._station[310])
        camera.save(window, "track_measure")
        track.measure_button.setChecked(False)
        if track_only:
            window.modified = False
            window.close()
            return

        editor = window.edit_settings()
        place(editor, size, fill=False)
        tabs = [editor.tabs.tabText(k) for k in range(editor.tabs.count())]
        editor.tabs.setCurrentIndex(tabs.index(tr("Track")))  # design, tolerances, fastener
        editor.set_field("track.tolerance_profile", "cn_conventional_160")
        camera.save(editor, "settings")
        editor.undo_stack.undo()
        editor.tabs.setCurrentIndex(tabs.index(tr("Report")))  # who and what the first page names, the paper
        for key, value in (("report.client", "China Railway Wuhan Group"), ("report.operator", "Li Wei"),
                           ("report.trolley", "GRP 5000 no. 117"), ("report.trolley_calibrated", "2026-03-14"),
                           ("report.imu_calibrated", "2026-13-02")):
            editor.set_field(key, value)
        camera.save(editor, "settings_report")
        while editor.undo_stack.canUndo():
            editor.undo_stack.undo()
        editor.close()

        wizard = window.new_project()
        place(wizard, size, fill=False)
        wizard.name.setText("New line section")
        wizard.folder.setText(str(Path(settings_folder) / "new project"))
        while wizard.currentPage().title() != tr("Trolley geometry"):
            wizard.next()
        wizard.next()  # every lever arm still 0 m: the page says so and waits for a confirmation
        camera.save(wizard, "wizard")
        wizard.reject()

        window.export_report("pdf", Path(settings_folder) / "report.pdf")
        wait(app, lambda: window.worker is not None)
        camera.save(window, "export")

        # Reports written, then the survey processed again: they are marked out of date, one click rewrites them.
        shown = window.shown_survey
        report_path(window.project.folder, shown, "pdf").parent.mkdir(exist_ok=True)
        for kind in ("xlsx", "pdf"):
            window.export_report(kind, report_path(window.project.folder, shown, kind))
            wait(app, lambda: window.worker is not None)
        window.process([shown])
        wait(app, lambda: window.worker is not None or window.loader is not None)
        window.tabs.setCurrentWidget(window.track)
        camera.save(window, "stale_reports")

        dialog = window.plan_survey()
        place(dialog, size, fill=False)
        dialog.outage.setValue(60.0)
        dialog.run()
        wait(app, lambda: dialog.worker is not None)
        camera.save(dialog, "plan_survey")
        dialog.close()

        if raw_gnss_project is not None:
            window.open_project(raw_gnss_project)
            wait(app, lambda: window.loader is not None)
            window.post_process_gnss()
            wait(app, lambda: window.worker is not None)
            camera.save(window, "gnss")
        window.modified = False
        window.close()


if __name__ == "__main__":
    arguments = [a for a in sys.argv[1:] if a not in ("--track-only", "--redesign", "--log")]
    main(*arguments[:2], track_only="--track-only" in sys.argv[1:], redesign="--redesign" in sys.argv[1:],
         log="--log" in sys.argv[1:])
