"""The PDF's fonts: Helvetica (a PDF standard font, not embedded) for what it can show, and for
everything else (Chinese, −, ‰, σ, ≥) a CJK font shipped in ``resources/fonts`` and embedded as a
subset of the glyphs used, so a viewer without CJK system fonts shows the text, not boxes
(``resources/fonts/README.md``: the font, its licence, how it is made)."""

from __future__ import annotations

import itertools

from reportlab.pdfbase import pdfmetrics
from reportlab.pdfbase.ttfonts import TTFont

from insrail.resources import resource

CJK_FONT = "InsrailCJKSans"
CJK_FONT_FILE = ("fonts", "insrail-cjk-sans.ttf")


def helvetica_can_show(text: str) -> bool:
    """Helvetica's encoding (WinAnsi, cp1252) holds every character of ``text``."""
    try:
        text.encode("cp1252")
    except UnicodeEncodeError:
        return False
    return True


def register_cjk() -> str:
    """The embedded CJK font's name, registered with reportlab on first use."""
    if CJK_FONT not in pdfmetrics.getRegisteredFontNames():
        pdfmetrics.registerFont(TTFont(CJK_FONT, str(resource(*CJK_FONT_FILE))))
    return CJK_FONT


def font_for(text: str, font: str = "Helvetica") -> str:
    """``font`` for text it can show, else the CJK font (which has Latin too: one string, one font)."""
    return font if helvetica_can_show(text) else register_cjk()


def font_runs(text: str, font: str = "Helvetica") -> list[tuple[str, str]]:
    """(run, font) of ``text``: ``font`` where it shows the characters, the CJK font for the rest (a
    bold title keeps its weight but for a "−" or a Chinese word)."""
    if helvetica_can_show(text):  # most text: one run, without a look at each character
        return [(text, font)] if text else []
    return [("".join(run), font if shown else register_cjk())
            for shown, run in itertools.groupby(text, helvetica_can_show)]
