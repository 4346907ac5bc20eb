"""Progress reporting and cancellation for long-running core steps.

Every long step in the core takes two optional arguments:

* ``progress(fraction, message)``: called with ``fraction`` in [0, 1] as the step
  advances. The CLI draws a progress bar from it, the GUI a QProgressBar and its log.
  ``message`` is said in the user's language like a notice (:mod:`insrail.notices`): a string
  literal without fields (``"smoother"``) or a :class:`~insrail.notices.Phrase` with them
  (``Phrase("reading the results of {survey}", {"survey": name})``), never an f-string; each
  template has its Chinese in ``insrail/names_zh.py`` (``tests/test_languages.py`` walks the calls).
  ``str(message)`` is the English (the CLI's bar); :func:`progress_text` the language in use (the
  GUI's, in its own thread: a report's language never leaks into the window).
* ``cancel``: anything with an ``is_set()`` method (e.g. ``threading.Event``) or a
  zero-argument callable returning True when the user asked to stop. The step
  then raises :class:`Cancelled` at its next check point and writes nothing
  half-finished.
"""

from __future__ import annotations

from typing import Callable, Protocol, Union

from insrail.notices import Phrase, phrase_of


class Cancelled(Exception):
    """Raised inside a core step when the user cancelled it."""


class _Flag(Protocol):
    def is_set(self) -> bool: ...


#: a progress message: a literal template without fields or a Phrase (module docstring)
ProgressMessage = Union[str, Phrase]
ProgressFn = Callable[[float, ProgressMessage], None]
CancelToken = Union[_Flag, Callable[[], bool], None]


def progress_text(message: ProgressMessage) -> str:
    """A progress message in the language in use (:func:`insrail.names.t`): the same template as the CLI's English."""
    return phrase_of(message).said()


def is_cancelled(cancel: CancelToken) -> bool:
    if cancel is None:
        return False
    if hasattr(cancel, "is_set"):
        return bool(cancel.is_set())
    return bool(cancel())


def check_cancel(cancel: CancelToken) -> None:
    """Raise :class:`Cancelled` if the user asked to stop."""
    if is_cancelled(cancel):
        raise Cancelled("cancelled by the user")


class StepProgress:
    """Maps the progress of one sub-step onto a slice of the parent's [0, 1] range.

    >>> sub = StepProgress(progress, 0.2, 0.5)   # this sub-step covers 20 %..50 %
    >>> sub(0.5, "half way")                      # parent sees 0.35
    """

    def __init__(self, progress: ProgressFn | None, start: float = 0.0, stop: float = 1.0):
        self._progress = progress
        self._start = start
        self._span = stop - start

    def __call__(self, fraction: float, message: ProgressMessage = "") -> None:
        if self._progress is not None:
            f = min(max(fraction, 0.0), 1.0)
            self._progress(self._start + self._span * f, message)

    def sub(self, start: float, stop: float) -> "StepProgress":
        return StepProgress(self, start, stop)
