"""Locate the data files in ``resources/`` (IMU profiles, tolerance profiles, icons).

Looked up, in order: ``$INSRAIL_RESOURCES``; the PyInstaller bundle
(``sys._MEIPASS/resources``); the repository's top-level ``resources/`` next to the
package (editable installs and source checkouts).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path


def resources_dir() -> Path:
    candidates = []
    if os.environ.get("INSRAIL_RESOURCES"):
        candidates.append(Path(os.environ["INSRAIL_RESOURCES"]))
    if hasattr(sys, "_MEIPASS"):
        candidates.append(Path(sys._MEIPASS) / "resources")
    candidates.append(Path(__file__).resolve().parent.parent / "resources")
    for c in candidates:
        if c.is_dir():
            return c
    raise FileNotFoundError("insrail resources folder not found; set INSRAIL_RESOURCES")


def resource(*parts: str) -> Path:
    """Path of a file under resources/, e.g. resource('imu_profiles', 'nav.toml')."""
    path = resources_dir().joinpath(*parts)
    if not path.exists():
        raise FileNotFoundError(f"resource not found: {path}")
    return path
