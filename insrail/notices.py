"""Notices: what a stage must tell the user about its input or its result, without failing.

A stage that repairs or doubts something (an IMU gap bridged, a record removed as an outlier,
a filter reset, a height anomaly extrapolated, a plausibility check that is borderline) returns
:class:`Notice` objects beside its result; it never prints. The pipeline gathers them, in the
order they happened, into ``summary.toml`` as ``[[notices]]`` tables; from there ``insrail
process`` prints them (``  warning: ...``), the PDF's processing page lists them and the GUI
log shows them, so a notice reaches every place the user looks.

An error (the result would be wrong) is an exception, not a notice: ``InputError`` for a file,
``ValueError`` with the survey and what to do otherwise.

``stage`` is a short word for where it happened (``imu``, ``fusion``, ``gnss``, ``heights``,
``track``, ``assessment``, ``adjustment``, ...); ``message`` is a whole sentence that names the
file and the unit where they matter; ``file``, ``time_s`` (the survey's time scale, GPS seconds
of week) and ``station_m`` (chainage) locate it when known.

Languages: a notice is written once, in English, and read in the report's language.

* Its second argument, ``template``, is a string literal with ``{fields}``, never an f-string; the
  values go in ``fields``::

      Notice("imu", "{file}: IMU gap of {gap_s:.3f} s after t = {time_s:.4f} s", file=name,
             fields={"file": name, "gap_s": gap, "time_s": start})

  The template (and the stage word) has its Chinese in ``insrail/names_zh.py``, like every report
  text; ``tests/test_languages.py`` walks every ``Notice(...)`` and ``Phrase(...)`` of the package and
  fails on a message written as an f-string or a concatenation, and on a template without its entry.
  Chinese keeps the template's fields (``{gap_s:.3f}``), in the order its sentence needs.
* A field's value is a number (formatted by the template), a string shown **verbatim** (a file name,
  a survey's or a point's name, a key of survey.toml: never English words of insrail's own), a
  :class:`Phrase` (a part of the sentence in words: a template and its fields, translated too; a
  helper that words a reason returns one) or a list of those (joined as the language lists them).
  A template without fields is shown as it is (braces in it are text).
* :attr:`Notice.message` and :meth:`Notice.text` are the English (the CLI, the GUI's log, tests,
  summary.toml's ``message``); :meth:`Notice.said` is the text in the language in use
  (:func:`insrail.names.t`; a report's inside :func:`insrail.names.in_language`). summary.toml keeps
  ``template`` and ``fields`` beside the English ``message``, so a report written later says it in
  its language; a notice written without them stays English.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

SEVERITIES = ("warning", "info")


@dataclass(frozen=True)
class Phrase:
    """A part of a sentence in words: an English ``template`` (a literal with an entry in names_zh.py) and its
    ``fields`` (module docstring). ``str()`` gives the English, so a Phrase reads as before in an error or a log."""

    template: str
    fields: Mapping[str, object] = field(default_factory=dict)

    def __post_init__(self):
        object.__setattr__(self, "fields", dict(self.fields))
        str(self)  # a template whose fields do not fit fails here, where it is made, not in a report

    def _rendered(self, translated: bool) -> str:
        template = self.template
        if translated:
            from insrail.names import t  # lazy: the nav core makes notices without the display names loaded

            template = t(template)
        if not self.fields:  # a text without fields is not a template: braces in it are text
            return template
        return template.format(**{key: _rendered(value, translated) for key, value in self.fields.items()})

    def said(self) -> str:
        """In the language in use (:func:`insrail.names.t`)."""
        return self._rendered(True)

    def __str__(self) -> str:
        return self._rendered(False)

    def __contains__(self, text: str) -> bool:
        """``"gap" in phrase``: in its English, as in the string it replaces."""
        return text in str(self)

    def to_dict(self) -> dict:
        return {"template": self.template, **({"fields": _stored(self.fields)} if self.fields else {})}

    @classmethod
    def from_dict(cls, table: Mapping) -> Phrase:
        return cls(str(table["template"]), _restored(table.get("fields", {})))


def _rendered(value, translated: bool):
    if isinstance(value, Phrase):
        return value._rendered(translated)
    if isinstance(value, (list, tuple)):
        parts = [str(_rendered(item, translated)) for item in value]
        if translated:
            from insrail.names import joined

            return joined(parts)
        return ", ".join(parts)
    return value


def _stored(fields: Mapping) -> dict:
    """Fields as TOML holds them: a Phrase as a table, a list as an array."""
    def stored(value):
        if isinstance(value, Phrase):
            return value.to_dict()
        if isinstance(value, (list, tuple)):
            return [stored(item) for item in value]
        return value.item() if hasattr(value, "item") else value  # numpy scalars as Python's

    return {key: stored(value) for key, value in fields.items()}


def _restored(fields: Mapping) -> dict:
    def restored(value):
        if isinstance(value, Mapping):
            return Phrase.from_dict(value)
        if isinstance(value, list):
            return [restored(item) for item in value]
        return value

    return {key: restored(value) for key, value in fields.items()}


@dataclass(frozen=True)
class Notice:
    stage: str
    template: str | Phrase  # the English template (module docstring); a Phrase brings its fields
    file: str = ""
    time_s: float | None = None
    station_m: float | None = None
    severity: str = "warning"
    fields: Mapping[str, object] = field(default_factory=dict)

    def __post_init__(self):
        if self.severity not in SEVERITIES:
            raise ValueError(f"notice severity {self.severity!r}: expected one of {', '.join(SEVERITIES)}")
        if isinstance(self.template, Phrase):
            object.__setattr__(self, "fields", {**self.template.fields, **self.fields})
            object.__setattr__(self, "template", self.template.template)
        object.__setattr__(self, "fields", dict(self.fields))
        self.phrase()  # a template whose fields do not fit fails where the notice is made

    def phrase(self) -> Phrase:
        return Phrase(self.template, self.fields)

    @property
    def message(self) -> str:
        """The message in English (its template filled in)."""
        return str(self.phrase())

    def text(self) -> str:
        """One line for a log or the CLI, in English: ``stage: message``."""
        return f"{self.stage}: {self.message}"

    def said(self) -> str:
        """:meth:`text` in the language in use (a report's: :func:`insrail.names.in_language`)."""
        from insrail.names import t

        return t("{stage}: {message}").format(stage=t(self.stage), message=self.phrase().said())

    def to_dict(self) -> dict:
        """The ``[[notices]]`` table (TOML has no null: unknown places are left out): ``message`` in English,
        and the template and its fields for a report in another language."""
        table = {"stage": self.stage, "severity": self.severity, "message": self.message}
        if self.fields:
            table |= {"template": self.template, "fields": _stored(self.fields)}
        if self.file:
            table["file"] = self.file
        if self.time_s is not None and math.isfinite(self.time_s):
            table["time_s"] = float(self.time_s)
        if self.station_m is not None and math.isfinite(self.station_m):
            table["station_m"] = float(self.station_m)
        return table

    @classmethod
    def from_dict(cls, table: dict) -> Notice:
        """A notice of summary.toml; one written before notices had templates is its English ``message``."""
        if "template" in table:
            template, fields = str(table["template"]), _restored(table.get("fields", {}))
        else:  # written without fields (or by an insrail before the templates): the English
            template, fields = str(table.get("message", "")), {}
        return cls(stage=str(table.get("stage", "")), template=template, fields=fields,
                   file=str(table.get("file", "")), time_s=table.get("time_s"), station_m=table.get("station_m"),
                   severity=str(table.get("severity", "warning")))


def notices_of(summary: dict) -> list[Notice]:
    """The notices recorded in a survey's summary (``[[notices]]``), in order."""
    return [Notice.from_dict(table) for table in summary.get("notices", [])]


#: How problems follow one another: on one line ("a; b") or one a line (an indented list).
IN_A_LINE, ONE_A_LINE = "{before}; {then}", "{before}\n  {then}"


def one_after_another(parts: list[str | Phrase], joint: str = IN_A_LINE) -> Phrase:
    """Problems said one after another (``joint``: :data:`IN_A_LINE` or :data:`ONE_A_LINE`), each in the
    language in use."""
    if not parts:
        raise ValueError("one_after_another: no parts")
    said = phrase_of(parts[0])
    for part in parts[1:]:
        said = Phrase(joint, {"before": said, "then": phrase_of(part)})
    return said


def phrase_of(stored: str | Mapping | Phrase) -> Phrase:
    """A text as a file keeps it (:meth:`Phrase.to_dict`'s table), or as an older insrail wrote it (English), or
    as a caller gives it (a Phrase, or a literal template without fields)."""
    if isinstance(stored, Phrase):
        return stored
    return Phrase.from_dict(stored) if isinstance(stored, Mapping) else Phrase(str(stored))
