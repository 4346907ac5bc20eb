"""Errors raised by insrail.geodesy; all are ValueErrors with a message a surveyor can act on."""

from __future__ import annotations


class GeodesyError(ValueError):
    """Base class: bad geodetic input, degenerate geometry or an implausible result."""


class SettingsError(GeodesyError):
    """Invalid settings. ``problems`` lists every problem found, each as ``"key.path: what is wrong"``."""

    def __init__(self, problems: list[str]):
        self.problems = list(problems)
        super().__init__("invalid geodesy settings:\n  " + "\n  ".join(self.problems))


class GeoidGridError(GeodesyError):
    """A geoid grid is missing, unreadable, or does not cover the points asked for."""


class FitError(GeodesyError):
    """A transformation or height-anomaly model cannot be fitted, or its result is implausible."""
