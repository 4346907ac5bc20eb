"""The error types readers raise for bad input."""

from __future__ import annotations

from pathlib import Path


class InputError(ValueError):
    """Bad input in a user file: names the file, the line (1-based) and what was expected.

    ``str(err)`` reads like ``imu.txt, line 1234: expected 7 numeric columns, found 6``.
    ``line`` is None when the problem is not tied to one line (e.g. an empty file).
    ``unit`` names what ``line`` counts: "line" for text files, "row" for binary
    tables (a .npy record array), so the message points where the user must look.
    """

    def __init__(self, path: str | Path, line: int | None, message: str, *, unit: str = "line"):
        self.path = Path(path)
        self.line = line
        self.message = message
        self.unit = unit
        where = f"{self.path}" if line is None else f"{self.path}, {unit} {line}"
        super().__init__(f"{where}: {message}")


class ManifestError(InputError):
    """``survey.toml`` (or the files it names) has problems; ``problems`` lists all of them.

    Each problem starts with the key path it concerns, e.g.
    ``files.gnss.path: file not found: gnss.pos``.
    """

    def __init__(self, path: str | Path, problems: list[str] | tuple[str, ...]):
        self.problems = tuple(problems)
        count = len(self.problems)
        summary = f"{count} problem{'s' if count != 1 else ''}:\n  " + "\n  ".join(self.problems)
        super().__init__(path, None, summary)
