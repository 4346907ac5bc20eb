"""The error types readers raise for bad input."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

from insrail.notices import Phrase


#: ``str(err)``'s place, per unit (InputError.unit), as a template said in the language in use
_PLACES = {"line": "{file}, line {line}: {message}", "row": "{file}, row {line}: {message}",
           "index": "{file}, index {line}: {message}"}


class InputError(ValueError):
    """Bad input in a user file: names the file, the line (1-based) and what was expected.

    ``str(err)`` reads like ``imu.txt, line 1234: expected 7 numeric columns, found 6``.
    ``line`` is None when the problem is not tied to one line (e.g. an empty file).
    ``unit`` names what ``line`` counts: "line" for text files, "row" for binary
    tables (a .npy record array), so the message points where the user must look.

    Languages, as a notice's (insrail/notices.py): ``message`` is a string literal with ``{fields}``, never an
    f-string, and ``fields`` holds the values (file and key names verbatim, numbers, a :class:`Phrase` for a
    part of the sentence in words), or ``message`` is a Phrase. ``str(err)`` and :attr:`message` are the English
    (the CLI, tests); :meth:`said` is the text in the language in use (the desktop application's). Every template
    has its Chinese in ``insrail/names_zh.py`` (``tests/test_languages.py`` fails otherwise).
    """

    def __init__(self, path: str | Path, line: int | None, message: str | Phrase, *, unit: str = "line",
                 fields: Mapping[str, object] | None = None):
        self.path = Path(path)
        self.line = line
        self.phrase = message if isinstance(message, Phrase) else Phrase(message, fields or {})
        self.message = str(self.phrase)
        self.unit = unit
        where = f"{self.path}" if line is None else f"{self.path}, {unit} {line}"
        super().__init__(f"{where}: {self.message}")

    def said_message(self) -> str:
        """:attr:`message` in the language in use."""
        return self.phrase.said()

    def said(self) -> str:
        """``str(err)`` in the language in use: the file name verbatim, the unit and the message translated."""
        from insrail.names import t

        where = "{file}: {message}" if self.line is None else _PLACES.get(self.unit, "{file}, line {line}: {message}")
        return t(where).format(file=self.path, line=self.line, message=self.said_message())


class ProblemsError(InputError):
    """A settings file (or the files it names) has problems; ``problems`` lists all of them (English),
    ``phrases`` the same to be said in another language. Each problem starts with the key path it concerns,
    e.g. ``files.gnss.path: file not found: gnss.pos``."""

    def __init__(self, path: str | Path, problems: Sequence[str | Phrase]):
        self.phrases = tuple(p if isinstance(p, Phrase) else Phrase(str(p)) for p in problems)
        self.problems = tuple(str(p) for p in self.phrases)
        english = self._heading() + "\n  " + "\n  ".join(self.problems)  # said by said_message
        super().__init__(path, None, english)

    def _heading(self) -> str:
        return "1 problem:" if len(self.problems) == 1 else f"{len(self.problems)} problems:"

    def said_message(self) -> str:
        from insrail.names import t

        heading = t("1 problem:") if len(self.problems) == 1 else t("{count} problems:").format(count=len(self.problems))
        return heading + "".join("\n  " + phrase.said() for phrase in self.phrases)


class ManifestError(ProblemsError):
    """``survey.toml`` (or the files it names) has problems; ``problems`` lists all of them."""


def reason_of(error: BaseException) -> str | Phrase:
    """What a core error (a ValueError) says, as a reader's InputError takes it: its Phrase where it carries one
    (``error.phrase``, as a DesignError does, or a Phrase as its argument), else its English text."""
    phrase = getattr(error, "phrase", None)
    if isinstance(phrase, Phrase):
        return phrase
    if error.args and isinstance(error.args[0], Phrase):
        return error.args[0]
    return str(error)


def said(error: BaseException) -> str:
    """An error as the user reads it in the language in use: an :class:`InputError` said (:meth:`InputError.said`),
    any other in its own words."""
    if isinstance(error, InputError):
        return error.said()
    reason = reason_of(error)
    return reason.said() if isinstance(reason, Phrase) else reason
