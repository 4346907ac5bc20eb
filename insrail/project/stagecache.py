"""Stage results cached as plain ``.npz`` files, and the checksum every cache entry carries.

Nested dataclass fields are stored under ``field.subfield``; text tuples as unicode arrays; no
pickle anywhere, so a cache file is data, never code. Files are written atomically.

Integrity: every file of the cache (``.npy``, ``.npz``, ``.toml``, ``.pos``) gets a sidecar
``<file>.sha256`` written after it (:func:`seal`). A stage reuses an entry only when each of its
files matches its checksum (:func:`intact`); a truncated, empty, bit-flipped or unsealed file
(a run killed between the file and its checksum) is deleted and the stage recomputes it, with a
notice (:func:`collect_cache_notices` gathers them for the survey's summary). Results are copies,
never links into the cache, so editing a result file cannot change the cache.

Leftovers of killed runs (``.*.tmp`` files, ``.rinex-*`` staging folders, ``.track-spool-*`` spools of
the track by parts) are removed by :func:`clean_leftovers`, which the pipeline calls only when no other
run of the project holds its lock (:mod:`insrail.project.lock`): then whatever is left, a killed run
left, however young.
"""

from __future__ import annotations

import contextlib
import contextvars
import dataclasses
import hashlib
import shutil
import typing
import zipfile
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from insrail.io.atomic import atomic_write
from insrail.io.errors import InputError
from insrail.notices import Notice, Phrase

CHECKSUM_SUFFIX = ".sha256"
_notices: contextvars.ContextVar[list[Notice] | None] = contextvars.ContextVar("cache_notices", default=None)


def _sidecar(path: Path) -> Path:
    return path.with_name(path.name + CHECKSUM_SUFFIX)


def file_sha256(path: Path) -> str:
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def seal(*paths: Path) -> None:
    """Write the checksum of each (complete) cache file beside it."""
    for path in paths:
        with atomic_write(_sidecar(path), "w") as handle:
            handle.write(f"{file_sha256(path)}  {path.name}\n")


def _damage(path: Path) -> Phrase | str | None:
    """What is wrong with a cache file ('' when it is absent, None when intact)."""
    if not path.is_file():
        return ""
    try:
        recorded = _sidecar(path).read_text(encoding="ascii").split()[0]
    except (OSError, UnicodeDecodeError, IndexError):
        return Phrase("it has no checksum (a run stopped while writing it, or an older insrail wrote it)")
    if path.stat().st_size == 0:
        return Phrase("it is empty")
    if file_sha256(path) != recorded:
        return Phrase("its contents do not match its checksum (truncated or altered)")
    return None


def discard(*paths: Path) -> None:
    """Remove cache files and their checksums."""
    for path in paths:
        for item in (path, _sidecar(path)):
            item.unlink(missing_ok=True)


def note_damaged(stage: str, path: Path, reason: Phrase | str) -> None:
    """Tell the survey's summary that a cache entry was recomputed."""
    notice = Notice("cache", "the cached {stage} {file} was damaged ({reason}): recomputed", file=str(path),
                    fields={"stage": stage, "file": path.name, "reason": reason})
    collected = _notices.get()
    if collected is not None:
        collected.append(notice)


def intact(stage: str, *paths: Path) -> bool:
    """True when every file of a cache entry exists and matches its checksum.

    Absent (never computed): False, silently. Damaged: the whole entry is discarded, a notice
    recorded, and False returned so that the stage recomputes it.
    """
    damage = [(path, _damage(path)) for path in paths]
    if all(reason is None for _, reason in damage):
        return True
    if any(reason for _, reason in damage):
        path, reason = next((p, r) for p, r in damage if r)
        note_damaged(stage, path, reason)
    discard(*paths)
    return False


@contextlib.contextmanager
def collect_cache_notices() -> Iterator[list[Notice]]:
    """Gather the notices of damaged cache entries recomputed inside the block."""
    collected: list[Notice] = []
    token = _notices.set(collected)
    try:
        yield collected
    finally:
        _notices.reset(token)


def clean_leftovers(folder: Path) -> list[Path]:
    """Remove temporary files and staging folders of killed runs in ``folder`` (see the module docstring)."""
    removed = []
    if not folder.is_dir():
        return removed
    for item in folder.iterdir():
        is_leftover = ((item.name.startswith(".") and item.name.endswith(".tmp") and item.is_file())
                       or (item.name.startswith((".rinex-", ".track-spool-")) and item.is_dir()))
        try:
            if not is_leftover:
                continue
            if item.is_dir():
                shutil.rmtree(item)
            else:
                item.unlink()
        except OSError:  # gone meanwhile, or not ours to remove: left alone
            continue
        removed.append(item)
    return removed


def _flatten(value, prefix: str, out: dict[str, np.ndarray]) -> None:
    for field in dataclasses.fields(value):
        item = getattr(value, field.name)
        name = f"{prefix}{field.name}"
        if item is None:  # an optional field left empty: absent from the file, its default on reading
            continue
        if dataclasses.is_dataclass(item):
            _flatten(item, name + ".", out)
        elif isinstance(item, tuple):
            out[name] = np.array(item, dtype=str)
        else:
            out[name] = np.asarray(item)


def save_dataclass(path: Path, value) -> None:
    """Write ``value`` (a dataclass of arrays, text, numbers, tuples of text, nested dataclasses)."""
    arrays: dict[str, np.ndarray] = {}
    _flatten(value, "", arrays)
    path.parent.mkdir(parents=True, exist_ok=True)
    with atomic_write(path, "wb") as handle:
        np.savez(handle, **arrays)
    seal(path)


def _build(cls, prefix: str, arrays) -> object:
    hints = typing.get_type_hints(cls)
    values = {}
    for field in dataclasses.fields(cls):
        kind = hints[field.name]
        optional = [arg for arg in typing.get_args(kind) if arg is not type(None)]
        if len(optional) == 1 and len(typing.get_args(kind)) == 2:  # X | None, saved as an X
            kind = optional[0]
        name = f"{prefix}{field.name}"
        if name not in arrays and not any(key.startswith(name + ".") for key in arrays):
            values[field.name] = None  # saved as None (see _flatten)
            continue
        if dataclasses.is_dataclass(kind):
            values[field.name] = _build(kind, name + ".", arrays)
            continue
        array = arrays[name]
        if kind is np.ndarray:
            values[field.name] = array
        elif typing.get_origin(kind) is tuple:
            values[field.name] = tuple(str(v) for v in array)
        else:
            values[field.name] = array.item()
    return cls(**values)


def load_dataclass(path: Path, cls):
    """Read back what :func:`save_dataclass` wrote for a ``cls``."""
    try:
        with np.load(path, allow_pickle=False) as arrays:
            return _build(cls, "", {name: arrays[name] for name in arrays.files})
    except (KeyError, ValueError, TypeError, OSError, EOFError, zipfile.BadZipFile) as error:
        raise InputError(path, None, "damaged cache file ({error}): delete it to recompute", fields={"error": error}) from None


def cached_dataclass(stage: str, path: Path, cls):
    """The cached ``cls`` at ``path``, or None when absent or damaged (then discarded, with a notice)."""
    if not intact(stage, path):
        return None
    try:
        return load_dataclass(path, cls)
    except InputError as error:  # intact bytes of another layout (an older insrail)
        note_damaged(stage, path, error.message.split(": delete")[0])
        discard(path)
        return None
