"""What the application remembers between sessions (QSettings): window layout, recent projects."""

from __future__ import annotations

from pathlib import Path

from PySide6.QtCore import QSettings

ORGANISATION = "insrail"
APPLICATION = "insrail"
MAX_RECENT = 8


def user_settings() -> QSettings:
    return QSettings(ORGANISATION, APPLICATION)


def recent_projects(settings: QSettings) -> list[str]:
    value = settings.value("recent_projects", [])
    if isinstance(value, str):  # QSettings gives a plain string for a one-element list in INI files
        value = [value]
    return [str(v) for v in value or [] if Path(v).exists()]


def remember_project(settings: QSettings, path: Path) -> list[str]:
    path_text = str(Path(path).resolve())
    recent = [path_text] + [p for p in recent_projects(settings) if p != path_text]
    settings.setValue("recent_projects", recent[:MAX_RECENT])
    return recent[:MAX_RECENT]
