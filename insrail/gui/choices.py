"""Lists of choices that show words and hold ids: each item's text is its display name
(:mod:`insrail.names`), its data the value project.toml stores. A list that takes a file of
one's own (an editable one) gives back what was typed where it names no item."""

from __future__ import annotations

from collections.abc import Iterable
from functools import cache

from PySide6.QtCore import Qt
from PySide6.QtWidgets import QComboBox

from insrail.gui.translation import tr
from insrail.io.errors import InputError
from insrail.names import CHOICE_NAMES, RESOURCE_SETTINGS, choice_name, resource_name
from insrail.nav.imu_profile import load_imu_profile
from insrail.track.adjustment import load_fastener_type
from insrail.track.tolerance import load_tolerance_profile

_LOADERS = {"tolerance_profiles": load_tolerance_profile, "fastener_types": load_fastener_type,
            "imu_profiles": load_imu_profile}


@cache
def _description(folder: str, name: str) -> str:
    try:
        return _LOADERS[folder](name).description
    except (InputError, ValueError, OSError):  # a file of one's own that does not load: its path
        return ""


def value_text(key: str, value) -> str:
    """The words for a setting's value on screen: a listed value's name, a shipped resource's
    description, anything else as written."""
    if isinstance(value, bool):  # a switch: "True" / "False" as the file writes it, in the application's language
        return tr("True") if value else tr("False")
    text = str(value)
    if key in CHOICE_NAMES and text in CHOICE_NAMES[key]:
        return choice_name(key, text)
    if key in RESOURCE_SETTINGS:
        description = _description(RESOURCE_SETTINGS[key], text)
        return resource_name(text, description) if description else text
    return text


def fill(combo: QComboBox, key: str, values: Iterable[str], first: tuple[str, object] | None = None) -> None:
    """The list of ``values`` of setting ``key`` in words (``first``: a (text, data) item before them)."""
    if first is not None:
        combo.addItem(*first)
    for value in values:
        combo.addItem(value_text(key, value), value)
        combo.setItemData(combo.count() - 1, str(value), Qt.ToolTipRole)  # the id, for the curious


def choose(combo: QComboBox, value) -> None:
    """Select the item holding ``value`` (added, as written, if the list lacks it)."""
    index = combo.findData(value)
    if index < 0:
        combo.addItem(str(value), value)
        index = combo.count() - 1
    combo.setCurrentIndex(index)


def chosen(combo: QComboBox):
    """The value of the item shown, or the text typed into an editable list that names no item."""
    index = combo.currentIndex()
    if index >= 0 and combo.itemText(index) == combo.currentText():
        return combo.itemData(index)
    return combo.currentText()
