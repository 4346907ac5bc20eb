"""A text progress bar for the terminal, fed by the core's ``progress(fraction, message)``."""

from __future__ import annotations

import sys
import time

from insrail.progress import ProgressMessage


class TerminalProgress:
    """Callable progress sink drawing ``[#####.....]  42 %  message`` on stderr.

    On a non-terminal stream (CI logs, pipes) it prints one line per 10 % instead
    of redrawing, so logs stay readable.
    """

    def __init__(self, label: str, stream=None, width: int = 30):
        self.label = label
        self.stream = stream or sys.stderr
        self.width = width
        self.tty = hasattr(self.stream, "isatty") and self.stream.isatty()
        self._last_decile = -1
        self._last_draw = 0.0
        self._drawn = False
        self._start = time.monotonic()

    def __call__(self, fraction: float, message: ProgressMessage = "") -> None:
        fraction = min(max(fraction, 0.0), 1.0)
        message = str(message)  # the CLI's output is English (a Phrase's template filled in)
        if self.tty:
            now = time.monotonic()
            if now - self._last_draw < 0.1 and fraction < 1.0:
                return
            self._last_draw = now
            self._drawn = fraction < 1.0
            filled = int(round(self.width * fraction))
            bar = "#" * filled + "." * (self.width - filled)
            self.stream.write(f"\r{self.label} [{bar}] {100 * fraction:5.1f} %  {message[:40]:<40}")
            if fraction >= 1.0:
                self.stream.write("\n")
            self.stream.flush()
        else:
            decile = int(fraction * 10)
            if decile > self._last_decile:
                self._last_decile = decile
                self.stream.write(f"{self.label}: {100 * fraction:3.0f} %  {message}\n")
                self.stream.flush()

    def done(self) -> float:
        """Finish the bar; returns the elapsed wall time [s]."""
        self(1.0, "done")
        return time.monotonic() - self._start

    def stopped(self) -> None:
        """End the bar of a step that failed: no "100 % done" above its error (on a terminal, the line ends)."""
        if self.tty and self._drawn:
            self.stream.write("\n")
            self.stream.flush()
