"""The desktop application in Chinese and English: every text of insrail/gui marked for translation has
its Chinese in the Qt Linguist file, the shipped .qm is the .ts compiled, the language follows the locale
unless the preferences chose one, and a Chinese window shows no English menu, tab, button or label."""

from __future__ import annotations

import re
import shutil
import string
import sys
from pathlib import Path

import pytest

pytest.importorskip("pytestqt")
from PySide6.QtCore import QSettings
from PySide6.QtWidgets import QAbstractButton, QApplication, QDockWidget, QLabel, QTabWidget

from insrail import names
from insrail.gui.translation import LANGUAGE_KEY, chosen_language, install_language, qm_file

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "installer"))
import gui_translations  # noqa: E402

TS = gui_translations.TS_FILES["zh_CN"]
#: Latin words a Chinese window may show: the program's name, formats and abbreviations written so in Chinese.
LATIN = {"insrail", "Excel", "LandXML", "project.toml", "survey.toml", "English", "Simplified", "Chinese"}
WORD = re.compile(r"[A-Za-z][A-Za-z_.]*[a-z][A-Za-z_.]*")


def english(text: str) -> set[str]:
    return {word for word in WORD.findall(text.replace("&", "")) if word not in LATIN}


def test_every_gui_text_has_its_chinese_in_the_ts_file():
    texts = gui_translations.gui_texts()
    translations = gui_translations.read_ts(TS)
    missing = {text: f"{file}:{line}" for text, (file, line) in texts.items() if not translations.get(text)}
    assert not missing, f"untranslated in {TS.name} (run python installer/gui_translations.py, translate):\n" + "\n".join(
        f"  {where}: {text!r}" for text, where in missing.items())

    def fields(text):
        return sorted(name for _, name, _, _ in string.Formatter().parse(text) if name is not None)

    assert {t: z for t, z in translations.items() if t in texts and fields(t) != fields(z)} == {}


def test_the_ts_file_has_no_unfinished_or_empty_translation():
    """Every message of the .ts is translated, not only those the code's tr() calls name (a text marked unfinished
    by Linguist or left empty is English in a Chinese window)."""
    untranslated = [source for source, translation in gui_translations.read_ts(TS).items()
                    if not (translation or "").strip()]
    assert not untranslated, f"unfinished or empty in {TS.name}:\n" + "\n".join(f"  {text!r}" for text in untranslated)


def test_the_log_panels_prefixes_and_the_cores_progress_are_in_the_windows_language(qtbot, chinese):
    from insrail.gui.logpanel import LogPanel
    from insrail.notices import Phrase
    from insrail.progress import progress_text

    panel = LogPanel()
    qtbot.addWidget(panel)
    panel.warning("x")
    panel.error("y")
    panel.progress(progress_text(Phrase("{survey}: {message}", {"survey": "K12", "message": Phrase(
        "reading the results of {survey}", {"survey": "K12"})})))
    panel.progress(progress_text("smoother"))
    lines = [line.split("  ", 1)[1] for line in panel.toPlainText().splitlines()]
    assert lines == ["警告：x", "错误：y", "K12：正在读取测量 K12 的结果", "平滑"]
    assert str(Phrase("reading the results of {survey}", {"survey": "K12"})) == "reading the results of K12"  # the CLI's


def test_the_shipped_qm_is_the_ts_compiled(tmp_path):
    if shutil.which("pyside6-lrelease", path=str(Path(sys.executable).parent)) is None:
        pytest.skip("pyside6-lrelease not beside this Python")
    gui_translations.compile_ts(TS, tmp_path / "fresh.qm")
    assert (tmp_path / "fresh.qm").read_bytes() == qm_file("zh-CN").read_bytes(), \
        "insrail_zh_CN.qm is older than its .ts: run python installer/gui_translations.py"


def test_the_language_follows_the_locale_unless_the_preferences_chose_one(tmp_path):
    settings = QSettings(str(tmp_path / "settings.ini"), QSettings.IniFormat)
    assert chosen_language(settings, "zh_CN") == "zh-CN"
    assert chosen_language(settings, "zh_TW") == "zh-CN"
    assert chosen_language(settings, "en_US") == "en"
    assert chosen_language(settings, "de_DE") == "en"
    settings.setValue(LANGUAGE_KEY, "en")
    assert chosen_language(settings, "zh_CN") == "en"
    settings.setValue(LANGUAGE_KEY, "zh-CN")
    assert chosen_language(settings, "en_US") == "zh-CN"


def shown_texts(window) -> list[str]:
    """Every text of the window's menus, toolbar, tabs, docks, buttons and labels."""
    texts = []

    def menu_texts(menu):
        for action in menu.actions():
            texts.append(action.text())
            if action.menu() is not None:
                menu_texts(action.menu())

    for action in window.menuBar().actions():
        texts.append(action.text())
        menu_texts(action.menu())
    for tabs in window.findChildren(QTabWidget):
        texts += [tabs.tabText(k) for k in range(tabs.count())]
    texts += [dock.windowTitle() for dock in window.findChildren(QDockWidget)]
    texts += [button.text() for button in window.findChildren(QAbstractButton)]
    texts += [label.text() for label in window.findChildren(QLabel)]
    return [text for text in texts if text]


@pytest.fixture
def chinese():
    app = QApplication.instance()
    install_language(app, "zh-CN")
    yield
    install_language(app, "en")


def test_a_chinese_window_has_no_english_menu_tab_or_button(qtbot, tmp_path, chinese):
    from insrail.gui.main_window import MainWindow
    from insrail.gui.preferences import PreferencesDialog

    window = MainWindow(QSettings(str(tmp_path / "settings.ini"), QSettings.IniFormat))
    qtbot.addWidget(window)
    texts = shown_texts(window)
    assert "文件(&F)" in texts and "轨道" in texts and "处理(&P)" in texts
    assert {text: english(text) for text in texts if english(text)} == {}
    preferences = PreferencesDialog(window.settings, window)
    qtbot.addWidget(preferences)
    assert {text: english(text) for text in shown_texts_of(preferences) if english(text)} == {}
    assert names.language() == "zh-CN"  # the display names of insrail.names follow


def shown_texts_of(dialog) -> list[str]:
    return [w.text() for w in dialog.findChildren(QAbstractButton) + dialog.findChildren(QLabel) if w.text()]


def test_an_english_window_is_english(qtbot, tmp_path):
    from insrail.gui.main_window import MainWindow

    window = MainWindow(QSettings(str(tmp_path / "settings.ini"), QSettings.IniFormat))
    qtbot.addWidget(window)
    texts = shown_texts(window)
    assert "&File" in texts and "Track" in texts
    assert not [text for text in texts if re.search(r"[\u4e00-\u9fff]", text)]


def test_the_event_dialog_in_chinese_names_the_kinds_fields_and_problems_in_chinese(qtbot, chinese):
    from types import SimpleNamespace

    from insrail.gui.event_dialog import EventDialog

    dialog = EventDialog(SimpleNamespace(events=None), 120.0, 100.0)
    qtbot.addWidget(dialog)
    kinds = [dialog.kind.itemText(i) for i in range(dialog.kind.count())]
    assert kinds[:3] == ["道岔", "平交道口", "桥梁"]
    dialog.start.setText("abc")
    texts = shown_texts_of(dialog) + kinds + dialog.kind.toolTip().splitlines()
    assert "应为以米计的测站里程，实为 'abc'" in texts and "类型" in texts
    names_typed = {"events.txt", "abc"}  # the event file's name and what was typed
    assert {text: english(text) - names_typed for text in texts if english(text) - names_typed} == {}


def test_the_gnss_pages_qc_in_chinese_has_chinese_keys_and_wording(qtbot, chinese):
    from types import SimpleNamespace

    from insrail.gui.views.gnss import qc_rows

    qc = {"epochs": 600, "first_s": 0.0, "last_s": 599.0, "interval_s": 1.0, "fix_rate": 0.95, "ratio_min": 3.1,
          "ratio_p05": 4.2, "ratio_median": 20.0, "epochs_by_quality": {"fix": 570, "float": 30},
          "sigma_by_quality_m": {"fix": {"horizontal_median_m": 0.008, "horizontal_p95_m": 0.012,
                                         "vertical_median_m": 0.015, "vertical_p95_m": 0.02}},
          "gaps": [{"start_s": 100.0, "end_s": 116.0, "duration_s": 16.0}]}
    report = {"qc": qc, "base": {"point": "CPII-BASE", "approximate": True, "derivation": "project control point"},
              "warnings": [], "baseline_m": 2500.0}
    groups = qc_rows(SimpleNamespace(report=report, fusion=None))
    assert [group for group, _ in groups] == ["解算", "各解类型历元数", "各解类型标准差", "中断（1）", "基准站", "警告"]
    texts = [text for _, rows in groups for row in rows for text in row]
    assert "600 个，历时 599 s（间隔 1 s）" in texts and "CPII-BASE（近似）" in texts and "至 +116 s（16 s）" in texts
    # the quality names and the base's derivation are the PPK stage's own words
    allowed = {"fix", "float", "project", "control", "point", "mm", "km"}
    assert {text: english(text) - allowed for text in texts if english(text) - allowed} == {}


def test_the_importers_headers_and_problems_in_chinese(qtbot, chinese, tmp_path):
    """The importer's own words are Chinese; a reader's error keeps its file, line and message verbatim."""
    from insrail.gui.importer import ImportWidget, preview

    widget = ImportWidget()
    qtbot.addWidget(widget)
    unknown = tmp_path / "notes.xyz"
    unknown.write_text("nothing a reader knows\n")
    widget.add_files([unknown])
    messages = [problem.message for problem in widget.check()]
    assert "没有用途为 imu 的文件" in " ".join(messages) and "请选择此文件的用途" in messages
    headers = [widget.problems.horizontalHeaderItem(i).text() for i in range(3)]
    assert headers == ["文件", "行", "问题"]
    assert {message: english(message) for message in messages if english(message) - {"imu", "gnss", "prism"}} == {}
    broken = tmp_path / "imu.npy"
    broken.write_bytes(b"not numpy")
    assert preview(broken).startswith("不是可读取的 .npy 文件：")
