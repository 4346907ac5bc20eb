"""Parsed sleeper tables kept in binary, per user: opening a survey does not parse its text again.

sleepers.csv of a 10 km survey is 5 MB of text; parsing it costs about a second of CPU, half of the
desktop application's budget for showing a project. The table parsed once is kept here as an
``.npz`` (numpy arrays only, no pickles) named by the BLAKE2 hash of the file's bytes, so what comes
back is always what the file says now: a file processed again, edited or replaced has another hash
and is parsed again. sleepers.csv stays the record; this is only a copy of its parse.

The entries live in the user's cache folder (``$XDG_CACHE_HOME`` or ``~/.cache``, then
``insrail/tables``; ``$LOCALAPPDATA`` on Windows); the newest :data:`MAX_ENTRIES` are kept. A cache
that cannot be read or written (no home folder, a read-only or full disk, a damaged entry) is never
an error: the table is parsed as without it.
"""

from __future__ import annotations

import hashlib
import os
import sys
import zipfile
from pathlib import Path

import numpy as np

from insrail.io.atomic import atomic_write

#: How many tables are kept (the oldest go first); a 10 km survey's entry is about 7 MB.
MAX_ENTRIES = 24
#: Bumped when the parsed form changes: entries of another version are never read.
VERSION = 1

#: number, labels, {column: values}, not_assessed texts, adjustment notes (as results._read_sleepers returns)
SleeperTableParse = tuple[np.ndarray, tuple[str, ...], dict[str, np.ndarray], tuple[str, ...], tuple[str, ...]]


def cache_folder() -> Path | None:
    """The folder of the entries; None where the user has no cache folder."""
    base = os.environ.get("XDG_CACHE_HOME") or (os.environ.get("LOCALAPPDATA") if sys.platform == "win32" else None)
    if not base:
        home = os.environ.get("HOME") or os.environ.get("USERPROFILE")
        if not home:
            return None
        base = str(Path(home) / ".cache")
    return Path(base) / "insrail" / "tables"


def _entry(data: bytes) -> Path | None:
    folder = cache_folder()
    if folder is None:
        return None
    return folder / f"sleepers-v{VERSION}-{hashlib.blake2b(data, digest_size=20).hexdigest()}.npz"


def load(data: bytes) -> SleeperTableParse | None:
    """The parse of the sleepers.csv whose bytes are ``data``, if it is kept; else None."""
    entry = _entry(data)
    if entry is None or not entry.is_file():
        return None
    try:
        with np.load(entry, allow_pickle=False) as stored:
            names = [str(name) for name in stored["names"]]
            values = stored["values"]
            table = (stored["number"], tuple(stored["label"].tolist()),
                     {name: values[:, k] for k, name in enumerate(names)},
                     tuple(stored["not_assessed"].tolist()), tuple(stored["notes"].tolist()))
    except (OSError, ValueError, KeyError, zipfile.BadZipFile):  # damaged or foreign: parse the file instead
        return None
    try:
        os.utime(entry)  # recently used: kept longest
    except OSError:
        pass
    return table


def store(data: bytes, table: SleeperTableParse) -> None:
    """Keep the parse ``table`` of the sleepers.csv bytes ``data`` (quietly nothing where the cache
    cannot be written)."""
    entry = _entry(data)
    if entry is None:
        return
    number, label, columns, not_assessed, notes = table
    names = list(columns)
    values = np.column_stack([columns[name] for name in names]) if names else np.zeros((len(number), 0))
    try:
        entry.parent.mkdir(parents=True, exist_ok=True)
        with atomic_write(entry, "wb") as handle:
            np.savez(handle, number=np.asarray(number), label=np.array(label, dtype=str),
                     names=np.array(names, dtype=str), values=values,
                     not_assessed=np.array(not_assessed, dtype=str), notes=np.array(notes, dtype=str))
        _prune(entry.parent)
    except OSError:
        return


def _prune(folder: Path) -> None:
    entries = sorted(folder.glob("sleepers-*.npz"), key=lambda path: path.stat().st_mtime, reverse=True)
    for old in entries[MAX_ENTRIES:]:
        old.unlink(missing_ok=True)
