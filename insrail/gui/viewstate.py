"""What a surveyor set up in the views of a project (tab, chainage window, plots shown), kept in
QSettings per project so that it is there again when the project is opened next time."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

from PySide6.QtCore import QSettings


def _key(project_path: Path) -> str:
    # QSettings reads "/" as groups and some characters not at all: a digest of the path is safe
    return "views/" + hashlib.sha1(str(Path(project_path).resolve()).encode()).hexdigest()


def save_view_state(settings: QSettings, project_path: Path, state: dict) -> None:
    settings.setValue(_key(project_path), json.dumps(state))


def load_view_state(settings: QSettings, project_path: Path) -> dict | None:
    """The state saved for the project, or None (never saved, or unreadable: start afresh)."""
    text = settings.value(_key(project_path))
    try:
        state = json.loads(text) if text else None
    except (TypeError, ValueError):
        return None
    return state if isinstance(state, dict) else None
