"""Reading the TOML files users edit (survey.toml, project.toml) with errors that name the line."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

from insrail.io.errors import InputError


#: A survey.toml or project.toml is a few kilobytes; a larger file is no settings file (and is not read).
MAX_TOML_BYTES = 16 << 20


def read_toml(path: str | Path) -> dict:
    """The document in ``path``; syntax errors become InputError at tomllib's line."""
    path = Path(path)
    try:
        if path.stat().st_size > MAX_TOML_BYTES:
            raise InputError(path, None, "larger than the limit of {limit_mib} MiB for a settings file", fields={"limit_mib": MAX_TOML_BYTES >> 20})
        return tomllib.loads(path.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as exc:
        # tomllib says "... (at line 7, column 3)"; lift the line into the error's place.
        match = re.search(r"\(at line (\d+), column \d+\)", str(exc))
        raise InputError(path, int(match.group(1)) if match else None, "not valid TOML: {exc}", fields={"exc": exc}) from None
    except UnicodeDecodeError as exc:
        raise InputError(path, None, "not UTF-8 text: {exc}", fields={"exc": exc}) from None
