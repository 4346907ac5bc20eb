"""RTKLIB processing options as text: ``key = value`` pairs with RTKLIB's own option names.

insrail does not re-describe RTKLIB's options. A configuration is an ordered mapping
``{key: value-text}`` read from an RTKLIB ``.conf`` file (``# comments`` allowed) and
checked against RTKLIB's option table (``pyrtklib.sysopts``): unknown keys and
values RTKLIB refuses are errors naming the file and line (or the override key).
Enumerations take the name (``kinematic``) or the number (``2``), as in rtkpost.

The trolley defaults live in ``resources/gnss/ppk_default.conf``.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path

from insrail.io.errors import InputError
from insrail.notices import Phrase
from insrail.resources import resource

DEFAULT_CONFIG = ("gnss", "ppk_default.conf")


class OptionError(ValueError):
    """An RTKLIB option key or value that RTKLIB does not accept."""


def rtklib_option_table() -> dict[str, tuple[int, str]]:
    """RTKLIB's option table: key -> (format, comment). Format 0 int, 1 float, 2 text, 3 enum."""
    import pyrtklib

    table: dict[str, tuple[int, str]] = {}
    index = 0
    while True:
        entry = pyrtklib.sysopts[index]
        # Arr1Dchar[0] is the whole NUL-terminated C string.
        name = entry.name[0]
        if not name:
            return table
        table[name] = (entry.format, entry.comment[0])
        index += 1


def _enum_choices(comment: str) -> dict[str, str]:
    """'0:off,1:on' -> {'off': '0', 'on': '1', '0': '0', '1': '1'}."""
    choices: dict[str, str] = {}
    for item in comment.split(","):
        number, _, name = item.partition(":")
        if number.strip().isdigit() and name:
            choices[name.strip()] = number.strip()
            choices[number.strip()] = number.strip()
    return choices


def same_value(key: str, a: str, b: str, table: Mapping[str, tuple[int, str]]) -> bool:
    """True if two values of option ``key`` mean the same (an enumeration's name and number do)."""
    fmt, comment = table[key]
    if fmt == 3:
        choices = _enum_choices(comment)
        return choices.get(a) == choices.get(b)
    return a == b


def check_option(key: str, value: str, table: Mapping[str, tuple[int, str]]) -> Phrase | None:
    """None if RTKLIB accepts ``key = value``, else what is wrong."""
    if key not in table:
        return Phrase("unknown RTKLIB option {key!r}", {"key": key})
    fmt, comment = table[key]
    if fmt == 0:
        try:
            int(value, 0)
        except ValueError:
            return Phrase("{key} = {value!r}: expected an integer", {"key": key, "value": value})
    elif fmt == 1:
        try:
            float(value)
        except ValueError:
            return Phrase("{key} = {value!r}: expected a number", {"key": key, "value": value})
    elif fmt == 3:
        choices = _enum_choices(comment)
        if value not in choices:
            return Phrase("{key} = {value!r}: expected one of {choices}", {"key": key, "value": value, "choices": comment})
    return None


def parse_config(path: str | Path) -> dict[str, str]:
    """Read an RTKLIB .conf file into {key: value}, checking every key and value."""
    path = Path(path)
    if not path.is_file():
        raise InputError(path, None, "RTKLIB configuration file not found")
    table = rtklib_option_table()
    options: dict[str, str] = {}
    for number, raw in enumerate(path.read_text(encoding="utf-8", errors="replace").splitlines(), 1):
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        key, sep, value = line.partition("=")
        if not sep:
            raise InputError(path, number, "expected 'key = value', found {line!r}", fields={"line": line})
        key, value = key.strip(), value.strip()
        problem = check_option(key, value, table)
        if problem:
            raise InputError(path, number, problem)
        options[key] = value
    return options


def load_options(config: str | Path | None = None,
                 overrides: Mapping[str, object] | None = None) -> dict[str, str]:
    """The trolley defaults (or ``config``) with ``overrides`` applied; all checked."""
    options = parse_config(config if config is not None else resource(*DEFAULT_CONFIG))
    table = rtklib_option_table()
    for key, value in (overrides or {}).items():
        text = str(value).strip()
        problem = check_option(key, text, table)
        if problem:
            raise OptionError(Phrase("options_overrides[{key!r}]: {problem}", {"key": key, "problem": problem}))
        options[key] = text
    return options


def apply_options(options: Mapping[str, str]):
    """RTKLIB's (prcopt_t, solopt_t, filopt_t) from ``options`` over RTKLIB's own defaults.

    Goes through RTKLIB's option buffer (str2opt + getsysopts) so RTKLIB's unit
    conversions (deg -> rad, base position types) apply exactly as in rtkpost.
    Not thread-safe (RTKLIB keeps the buffer in static memory): call it in the
    process that runs postpos.
    """
    import pyrtklib

    index = {name: i for i, name in enumerate(rtklib_option_table())}
    pyrtklib.resetsysopts()
    for key, value in options.items():
        # Index the table directly: pyrtklib's searchopt() frees RTKLIB's static entry.
        if pyrtklib.str2opt(pyrtklib.sysopts[index[key]], value) != 1:
            raise OptionError(Phrase("RTKLIB refused {key} = {value!r}", {"key": key, "value": value}))
    prcopt, solopt, filopt = pyrtklib.prcopt_t(), pyrtklib.solopt_t(), pyrtklib.filopt_t()
    pyrtklib.getsysopts(prcopt, solopt, filopt)
    return prcopt, solopt, filopt
