"""Core calls in a worker thread: the core's progress callback and cancel token, marshalled with signals.

The workers only call the core (:func:`insrail.project.process`, the report writers, the PPK
stage, the prediction); signals emitted from their thread reach slots of objects living in the
GUI thread as queued calls, so the window stays responsive.
"""

from __future__ import annotations

import threading
import traceback
from collections.abc import Callable, Sequence

from PySide6.QtCore import QThread, Signal

from insrail.gnss.ppk import GnssProcessingError
from insrail.gui.translation import tr
from insrail.io.errors import InputError, said
from insrail.notices import Phrase, phrase_of
from insrail.progress import Cancelled, CancelToken, ProgressFn, ProgressMessage
from insrail.project import Project, process

#: Failures the core words for the user (bad input, settings, files, RTKLIB refusing the data);
#: anything else is a defect.
EXPECTED_ERRORS = (InputError, ValueError, OSError, GnssProcessingError)


class CoreWorker(QThread):
    """Runs :meth:`work` in its thread; failures and cancellation become signals."""

    #: fraction in [0, 1], the core's message (a literal or a Phrase: said in the window's language, in its thread)
    progressed = Signal(float, object)
    failed = Signal(str)  # what went wrong, as the core words it, after the subject
    cancelled = Signal()

    def __init__(self, parent=None):
        super().__init__(parent)
        self._stop = threading.Event()
        self.subject = ""  # what the work is about, for the failure message ("survey short")

    def cancel(self) -> None:
        """Ask the core to stop at its next check point (it leaves the previous results)."""
        self._stop.set()

    def work(self) -> None:
        raise NotImplementedError

    def run(self) -> None:
        try:
            self.work()
        except Cancelled:
            self.cancelled.emit()
        except EXPECTED_ERRORS as error:
            self.failed.emit(f"{self.subject}: {said(error)}")  # a reader's error in the window's language
        except Exception as error:  # noqa: BLE001 (a defect: the window must survive it and say what happened)
            traceback.print_exc()
            self.failed.emit(tr("{subject}: internal error {kind}: {error} (details on the console; please report "
                                "it)").format(subject=self.subject, kind=type(error).__name__, error=error))


class ProcessingWorker(CoreWorker):
    """Processes ``surveys`` of ``project`` in order; stops at the first failure or on cancel."""

    surveyDone = Signal(str)  # a survey's results are on disk

    def __init__(self, project: Project, surveys: Sequence[str], parent=None):
        super().__init__(parent)
        self.project = project
        self.surveys = tuple(surveys)

    def work(self) -> None:
        count = len(self.surveys)
        for index, name in enumerate(self.surveys):
            def report(fraction: float, message: ProgressMessage, index=index, name=name) -> None:
                self.progressed.emit((index + fraction) / count,
                                     Phrase("{survey}: {message}", {"survey": name, "message": phrase_of(message)}))

            self.subject = tr("survey {survey}").format(survey=name)
            process(self.project, name, progress=report, cancel=self._stop)
            self.surveyDone.emit(name)


class TaskWorker(CoreWorker):
    """One core call ``task(progress, cancel)``; its return value arrives with ``succeeded``."""

    succeeded = Signal(object)

    def __init__(self, subject: str, task: Callable[[ProgressFn, CancelToken], object], parent=None):
        super().__init__(parent)
        self.subject = subject
        self.task = task

    def work(self) -> None:
        self.succeeded.emit(self.task(self.progressed.emit, self._stop))
