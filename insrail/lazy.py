"""Package namespaces that import a submodule only when one of its names is first used (PEP 562).

A package's ``__init__`` re-exports its readers and models by name; importing them all eagerly
made ``insrail --help`` import numba, scipy and pyproj for a one-line message. A package built
with :func:`lazy_exports` keeps the same names (``from insrail.io import read_imu_kfgins`` still
works) and imports the submodule that defines a name when it is first asked for. A name must not
also be a submodule's name: the import system would set the package attribute to the module.
"""

from __future__ import annotations

import importlib
import sys
from typing import Callable


def lazy_exports(package: str, exports: dict[str, list[str]]) -> tuple[Callable, Callable]:
    """``(__getattr__, __dir__)`` for ``package`` whose submodules (keys, relative names) define
    the names listed for them."""
    where = {name: f"{package}.{module}" for module, names in exports.items() for name in names}
    clashes = sorted(set(where) & set(exports))
    if clashes:
        raise ValueError(f"{package}: names {clashes} are also submodules")

    def __getattr__(name: str):
        try:
            module = where[name]
        except KeyError:
            raise AttributeError(f"module {package!r} has no attribute {name!r}") from None
        value = getattr(importlib.import_module(module), name)
        setattr(sys.modules[package], name, value)  # the next use is a plain attribute
        return value

    def __dir__() -> list[str]:
        return sorted(set(where) | set(vars(sys.modules[package])))

    return __getattr__, __dir__
