"""The project settings as the forms name them: the core reports a problem with its key path in
project.toml ("geodesy.height.benchmarks: file not found: x.txt"); a form shows it beside the
field, in the field's words ("Benchmarks file: file not found: x.txt"). The words are
:func:`insrail.names.setting_name`'s (the one table of display names)."""

from __future__ import annotations

import re

from insrail.names import setting_name

_PROBLEM = re.compile(r"^(?P<key>[A-Za-z0-9_.\[\]]+)(?:: |：)(?P<message>.*)$", re.DOTALL)  # said in English or Chinese
_INDEX = re.compile(r"\[\d+\]")


def split_problem(problem: str) -> tuple[str, str]:
    """(key path with list indices removed, message) of one of the core's problems ("" key: none)."""
    match = _PROBLEM.match(problem)
    if match is None:
        return "", problem
    return _INDEX.sub("", match.group("key")), match.group("message")


def in_words(problem: str) -> str:
    """A problem of the core with its key path replaced by the field's label."""
    key, message = split_problem(problem)
    return f"{setting_name(key)}: {message}" if key else message
