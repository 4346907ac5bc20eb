"""Edit > Preferences: what the application remembers for the user, not for a project (the language)."""

from __future__ import annotations

from PySide6.QtCore import QSettings
from PySide6.QtWidgets import QComboBox, QDialog, QDialogButtonBox, QFormLayout, QLabel

from insrail.gui.translation import LANGUAGE_KEY, SYSTEM, tr
from insrail.names import LANGUAGES


class PreferencesDialog(QDialog):
    """The application's language: the system's (the default) or one chosen; it applies at the next start."""

    def __init__(self, settings: QSettings, parent=None):
        super().__init__(parent)
        self.settings = settings
        self.setWindowTitle(tr("Preferences"))
        form = QFormLayout(self)
        self.language = QComboBox()
        self.language.addItem(tr("As the system (locale)"), SYSTEM)
        for code, own_name in LANGUAGES.items():  # each language in its own words: readable whatever is shown now
            self.language.addItem(own_name, code)
        index = self.language.findData(str(settings.value(LANGUAGE_KEY, SYSTEM)))
        self.language.setCurrentIndex(max(index, 0))
        form.addRow(tr("Language"), self.language)
        form.addRow(QLabel(tr("The language changes when insrail is started again. The reports keep their "
                              "project's language (Project settings, Report).")))
        buttons = QDialogButtonBox(QDialogButtonBox.Ok | QDialogButtonBox.Cancel)
        buttons.accepted.connect(self.accept)
        buttons.rejected.connect(self.reject)
        form.addRow(buttons)

    def accept(self) -> None:
        self.settings.setValue(LANGUAGE_KEY, self.language.currentData())
        super().accept()
