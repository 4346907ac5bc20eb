"""Collecting settings problems so the user sees all of them at once.

A ``Problems`` object is filled while a settings dict is read; ``raise_if_any()``
turns the collected list into one ``SettingsError``. Messages start with the key
path in the project file (``geodesy.crs.scale_factor: ...``).
"""

from __future__ import annotations

import difflib
import math
from collections.abc import Iterable, Mapping
from typing import Any

from insrail.geodesy.errors import SettingsError


class Problems:
    def __init__(self, prefix: str = ""):
        self.prefix = prefix
        self.items: list[str] = []

    def path(self, key: str) -> str:
        return f"{self.prefix}.{key}" if self.prefix else key

    def add(self, key: str, message: str) -> None:
        self.items.append(f"{self.path(key)}: {message}")

    def raise_if_any(self) -> None:
        if self.items:
            raise SettingsError(self.items)

    def check_mapping(self, settings: Any) -> bool:
        if not isinstance(settings, Mapping):
            where = self.prefix or "settings"
            self.items.append(f"{where}: expected a table of key = value pairs, got {type(settings).__name__}")
            return False
        return True

    def unknown_keys(self, settings: Mapping, allowed: Iterable[str]) -> None:
        allowed = list(allowed)
        for key in settings:
            if key not in allowed:
                close = difflib.get_close_matches(str(key), allowed, n=1)
                hint = f" (did you mean '{close[0]}'?)" if close else f" (allowed: {', '.join(allowed)})"
                self.add(str(key), f"unknown key{hint}")

    def number(self, settings: Mapping, key: str, default: float | None, low: float, high: float,
               unit: str) -> float | None:
        """Read a finite number in [low, high]; record a problem and return None otherwise."""
        if key not in settings:
            if default is None:
                self.add(key, f"missing; expected a number in {unit}")
            return default
        return self.check_range(key, settings[key], low, high, unit)

    def check_range(self, key: str, value: Any, low: float, high: float, unit: str) -> float | None:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            self.add(key, f"expected a number{' in ' + unit if unit else ''}, got {value!r}")
            return None
        value = float(value)
        if not math.isfinite(value) or not low <= value <= high:
            unit_suffix = f" {unit}" if unit else ""
            self.add(key, f"{value:g}{unit_suffix} is outside the plausible range {low:g} to {high:g}{unit_suffix}")
            return None
        return value

    def choice(self, settings: Mapping, key: str, default: str, choices: Iterable[str]) -> str | None:
        choices = list(choices)
        value = settings.get(key, default)
        if value not in choices:
            self.add(key, f"expected one of {', '.join(repr(c) for c in choices)}, got {value!r}")
            return None
        return value
