"""Processing in a worker thread: the core's progress callback and cancel token, marshalled with signals.

The worker only calls :func:`insrail.project.process`; signals emitted from its thread reach slots
of objects living in the GUI thread as queued calls, so the window stays responsive.
"""

from __future__ import annotations

import threading
import traceback
from collections.abc import Sequence

from PySide6.QtCore import QThread, Signal

from insrail.io.errors import InputError
from insrail.progress import Cancelled
from insrail.project import Project, process


class ProcessingWorker(QThread):
    """Processes ``surveys`` of ``project`` in order; stops at the first failure or on cancel."""

    progressed = Signal(float, str)  # overall fraction in [0, 1], the core's message
    surveyDone = Signal(str)  # a survey's results are on disk
    failed = Signal(str)  # what went wrong, as the core words it
    cancelled = Signal()

    def __init__(self, project: Project, surveys: Sequence[str], parent=None):
        super().__init__(parent)
        self.project = project
        self.surveys = tuple(surveys)
        self._stop = threading.Event()

    def cancel(self) -> None:
        """Ask the core to stop at its next check point (it leaves the previous results)."""
        self._stop.set()

    def run(self) -> None:
        count = len(self.surveys)
        for index, name in enumerate(self.surveys):
            def report(fraction: float, message: str, index=index, name=name) -> None:
                self.progressed.emit((index + fraction) / count, f"{name}: {message}")

            try:
                process(self.project, name, progress=report, cancel=self._stop)
            except Cancelled:
                self.cancelled.emit()
                return
            except (InputError, ValueError, OSError) as error:  # bad input, settings or files: the core's words
                self.failed.emit(f"survey {name}: {error}")
                return
            except Exception as error:  # noqa: BLE001 (a defect: the window must survive it and say what happened)
                traceback.print_exc()
                self.failed.emit(f"survey {name}: internal error {type(error).__name__}: {error} "
                                 "(details on the console; please report it)")
                return
            self.surveyDone.emit(name)
