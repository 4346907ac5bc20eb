"""The log panel: the core's progress messages, warnings and errors, time-stamped."""

from __future__ import annotations

import re
import time

from PySide6.QtCore import QSize
from PySide6.QtWidgets import QPlainTextEdit

from insrail.gui.translation import tr


class LogPanel(QPlainTextEdit):
    def __init__(self, parent=None):
        super().__init__(parent)
        self.setReadOnly(True)
        self.setMaximumBlockCount(5000)
        self._last_kind = ""

    def sizeHint(self) -> QSize:
        """A few lines: the views get the height."""
        return QSize(600, 110)

    def info(self, message: str) -> None:
        self._append("", message)

    def warning(self, message: str) -> None:
        self._append(tr("warning: "), message)

    def error(self, message: str) -> None:
        self._append(tr("error: "), message)

    def progress(self, message: str) -> None:
        """Log a progress message once per stage: counters ("epoch 1200/28000") do not make new lines."""
        kind = re.sub(r"[\d.]+", "#", message)
        if kind != self._last_kind:
            self._append("", message)
        self._last_kind = kind

    def _append(self, prefix: str, message: str) -> None:
        self.appendPlainText(f"{time.strftime('%H:%M:%S')}  {prefix}{message}")
