"""The one error type readers raise for bad input."""

from __future__ import annotations

from pathlib import Path


class InputError(ValueError):
    """Bad input in a user file: names the file, the line (1-based) and what was expected.

    ``str(err)`` reads like ``imu.txt, line 1234: expected 7 numeric columns, found 6``.
    ``line`` is None when the problem is not tied to one line (e.g. an empty file).
    """

    def __init__(self, path: str | Path, line: int | None, message: str):
        self.path = Path(path)
        self.line = line
        self.message = message
        where = f"{self.path}" if line is None else f"{self.path}, line {line}"
        super().__init__(f"{where}: {message}")
