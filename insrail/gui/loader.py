"""Reading a survey's results for the views, off the GUI thread.

Two steps, each a signal: the sleepers (small: the track view paints from them at once), then the
trajectory (the large file: plan and navigation). Every load carries the number of the request it
answers; the window ignores answers to requests it has replaced (another project or survey was
chosen meanwhile), so a slow load can never show one project's results in another's window.
"""

from __future__ import annotations

import threading
import traceback

from PySide6.QtCore import QThread, Signal

from insrail.gui.translation import tr
from insrail.io.errors import InputError, said
from insrail.project import Project, load_results
from insrail.project.plotdata import track_data, trajectory_views
from insrail.project.results import RESULTS_FOLDER, SUMMARY_FILE
from insrail.report.content import ChainageAxis

#: The longest the trajectory waits for the track view to be drawn [s].
TRACK_DRAW_WAIT_S = 10.0


class ResultsLoader(QThread):
    """Loads the results of every processed survey of ``project`` in ``surveys`` and the views of
    ``show`` (None: the first survey that has results)."""

    resultsLoaded = Signal(int, object)  # request, {survey: StoredResults}
    trackReady = Signal(int, object, object)  # request, TrackData, its ChainageAxis
    trajectoryReady = Signal(int, object)  # request, TrajectoryViews
    failed = Signal(int, str)  # request, what went wrong (as the core words it)

    def __init__(self, request: int, project: Project, surveys, show: str | None, known=None, parent=None):
        super().__init__(parent)
        self.request, self.project, self.surveys, self.show = request, project, tuple(surveys), show
        self.known = dict(known or {})  # results already read (a survey switch reads nothing again)
        self._stop = threading.Event()
        self.track_drawn = threading.Event()  # set by the window once the track view is on screen

    def cancel(self) -> None:
        """The answer is no longer wanted: stop after the current step."""
        self._stop.set()
        self.track_drawn.set()

    def run(self) -> None:
        try:
            self._load()
        except (InputError, ValueError, OSError) as error:
            self.failed.emit(self.request, said(error))
        except Exception as error:  # noqa: BLE001 (a defect: the window must survive it and say what happened)
            traceback.print_exc()
            self.failed.emit(self.request, tr("internal error {kind}: {error} (details on the console; please report "
                                              "it)").format(kind=type(error).__name__, error=error))

    def _load(self) -> None:
        project, results = self.project, {}
        for name in self.surveys:  # in the project's order: the first processed one is shown
            if name in self.known:
                results[name] = self.known[name]
            elif (project.folder / RESULTS_FOLDER / name / SUMMARY_FILE).is_file():
                try:
                    results[name] = load_results(project.folder, name)
                except InputError as error:
                    self.failed.emit(self.request, error.said())
            if self._stop.is_set():
                return
        self.resultsLoaded.emit(self.request, results)
        show = self.show if self.show is not None else next(iter(results), None)
        if show not in results or self._stop.is_set():
            return
        data = track_data(project, results[show])
        # the chainage axis reads every sleeper's label: here, not in the GUI thread
        self.trackReady.emit(self.request, data, ChainageAxis.from_labels(data.station_m, data.label))
        # Reading the trajectory holds the interpreter for seconds: not while the track view draws.
        self.track_drawn.wait(TRACK_DRAW_WAIT_S)
        if self._stop.is_set():
            return
        self.trajectoryReady.emit(self.request, trajectory_views(project, results[show]))
