"""The desktop application's language: every text a user reads goes through :func:`tr`, translated by
Qt from the Linguist file ``insrail/gui/i18n/insrail_<language>.qm`` (made from the ``.ts`` beside it by
``python installer/gui_translations.py``; ``tests/test_gui_translation.py`` fails on a text without its
translation and on a ``.qm`` older than its ``.ts``).

The language follows the system locale (a Chinese locale: Simplified Chinese, any other: English) unless
Edit > Preferences chose one (QSettings ``language``: "system", "en" or "zh-CN"; it takes effect at the next
start). The display names of :mod:`insrail.names` (columns, checks, settings) follow the same language
(:func:`insrail.names.set_language`); the reports keep their project's own (``[report] language``).
"""

from __future__ import annotations

from pathlib import Path

from PySide6.QtCore import QCoreApplication, QLibraryInfo, QLocale, QSettings, QTranslator

from insrail.names import DEFAULT_LANGUAGE, LANGUAGES, language_of_locale, set_language

CONTEXT = "insrail"
FOLDER = Path(__file__).parent / "i18n"
#: QSettings key of the language chosen in the preferences.
LANGUAGE_KEY = "language"
SYSTEM = "system"
#: Qt's own texts (standard buttons, file dialogs) per language: its translation file's name.
QT_TRANSLATIONS = {"zh-CN": "qtbase_zh_CN"}
_installed: list[QTranslator] = []  # kept alive as long as the application


def tr(text: str) -> str:
    """``text`` (English, as written in the code) in the application's language."""
    return QCoreApplication.translate(CONTEXT, text)


def qm_file(code: str) -> Path:
    return FOLDER / f"insrail_{code.replace('-', '_')}.qm"


def chosen_language(settings: QSettings, system_locale: str | None = None) -> str:
    """The language of the preferences, or for "system" (the default) the system locale's."""
    chosen = str(settings.value(LANGUAGE_KEY, SYSTEM))
    if chosen in LANGUAGES:
        return chosen
    return language_of_locale(system_locale if system_locale is not None else QLocale.system().name())


def install_language(app: QCoreApplication, code: str) -> str:
    """Translate the application (its own texts, Qt's and insrail.names') into ``code``; the language in use."""
    for translator in _installed:
        app.removeTranslator(translator)
    _installed.clear()
    set_language(code)
    if code == DEFAULT_LANGUAGE:
        return code
    for path in (qm_file(code), Path(QLibraryInfo.path(QLibraryInfo.TranslationsPath)) / f"{QT_TRANSLATIONS[code]}.qm"):
        translator = QTranslator(app)
        if translator.load(str(path)):
            app.installTranslator(translator)
            _installed.append(translator)
    QLocale.setDefault(QLocale(QLocale.Chinese, QLocale.China) if code == "zh-CN" else QLocale(QLocale.English))
    return code


def tr_noop(text: str) -> str:
    """Marks a text of a table for translation where it is shown (:func:`tr` of the value); returns it as is."""
    return text
