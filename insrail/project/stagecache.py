"""Stage results cached as plain ``.npz`` files: a (nested) dataclass of numpy arrays, text and numbers.

Nested dataclass fields are stored under ``field.subfield``; text tuples as unicode arrays; no
pickle anywhere, so a cache file is data, never code. Files are written atomically; one that
cannot be read back raises InputError naming it.
"""

from __future__ import annotations

import dataclasses
import typing
import zipfile
from pathlib import Path

import numpy as np

from insrail.io.atomic import atomic_write
from insrail.io.errors import InputError


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


def _build(cls, prefix: str, arrays) -> object:
    hints = typing.get_type_hints(cls)
    values = {}
    for field in dataclasses.fields(cls):
        kind = hints[field.name]
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
    except (KeyError, ValueError, OSError, zipfile.BadZipFile) as error:
        raise InputError(path, None, f"damaged cache file ({error}): delete it to recompute") from None
