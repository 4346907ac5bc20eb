"""Bring the desktop application's Qt Linguist files up to date with its code, and compile them.

    python installer/gui_translations.py

Every text of ``insrail/gui`` passed to ``tr("...")`` or ``tr_noop("...")`` (:mod:`insrail.gui.translation`)
is a message of ``insrail/gui/i18n/insrail_zh_CN.ts`` (context "insrail"): a new text is added unfinished
(translate it in Qt Linguist, ``pyside6-linguist``, or in the file), a text no longer in the code is dropped,
the translations of the others are kept. Then ``pyside6-lrelease`` compiles the ``.qm`` the application
loads (shipped beside it; ``tests/test_gui_translation.py`` checks both are up to date).
"""

from __future__ import annotations

import ast
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
GUI = ROOT / "insrail" / "gui"
TS_FILES = {"zh_CN": GUI / "i18n" / "insrail_zh_CN.ts"}
CONTEXT = "insrail"
MARKERS = ("tr", "tr_noop")


def gui_texts(folder: Path = GUI) -> dict[str, tuple[str, int]]:
    """Every text marked for translation under ``folder``: text -> (file relative to the repository, line)."""
    found: dict[str, tuple[str, int]] = {}
    for path in sorted(folder.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in MARKERS
                    and node.args and isinstance(node.args[0], ast.Constant) and isinstance(node.args[0].value, str)):
                found.setdefault(node.args[0].value, (path.relative_to(ROOT).as_posix(), node.lineno))
    return found


def read_ts(path: Path) -> dict[str, str | None]:
    """source -> translation (None: unfinished) of a .ts file's context."""
    if not path.exists():
        return {}
    messages = {}
    for message in ET.parse(path).getroot().iter("message"):
        translation = message.find("translation")
        finished = translation is not None and translation.get("type") not in ("unfinished", "vanished", "obsolete")
        messages[message.findtext("source")] = translation.text if finished and translation.text else None
    return messages


def write_ts(path: Path, language: str, texts: dict[str, tuple[str, int]], translations: dict[str, str | None]) -> int:
    """Write the .ts of ``texts`` with the known ``translations``; the number left unfinished."""
    root = ET.Element("TS", version="2.1", language=language)
    context = ET.SubElement(root, "context")
    ET.SubElement(context, "name").text = CONTEXT
    unfinished = 0
    for text, (file, line) in texts.items():
        message = ET.SubElement(context, "message")
        ET.SubElement(message, "location", filename=f"../../../{file}", line=str(line))
        ET.SubElement(message, "source").text = text
        translation = ET.SubElement(message, "translation")
        if translations.get(text):
            translation.text = translations[text]
        else:
            translation.set("type", "unfinished")
            unfinished += 1
    ET.indent(root)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text('<?xml version="1.0" encoding="utf-8"?>\n<!DOCTYPE TS>\n'
                    + ET.tostring(root, encoding="unicode") + "\n", encoding="utf-8")
    return unfinished


def lrelease() -> str:
    """The pyside6-lrelease beside this Python (PySide6 ships it)."""
    found = shutil.which("pyside6-lrelease", path=str(Path(sys.executable).parent)) or shutil.which("pyside6-lrelease")
    if found is None:
        raise SystemExit("pyside6-lrelease not found: install PySide6 (pip install -e '.[test]')")
    return found


def compile_ts(ts: Path, qm: Path) -> None:
    subprocess.run([lrelease(), "-silent", str(ts), "-qm", str(qm)], check=True)


def main() -> int:
    texts = gui_texts()
    for language, ts in TS_FILES.items():
        unfinished = write_ts(ts, language, texts, read_ts(ts))
        compile_ts(ts, ts.with_suffix(".qm"))
        print(f"{ts.relative_to(ROOT)}: {len(texts)} texts, {unfinished} unfinished")
    return 0


if __name__ == "__main__":
    sys.exit(main())
