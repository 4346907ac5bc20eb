"""Make the CJK font the PDF report embeds: a subset of WenQuanYi Micro Hei (Apache-2.0).

    python installer/cjk_font_subset.py [SOURCE.ttc]

SOURCE defaults to Debian's ``fonts-wqy-microhei`` file (``apt-get install fonts-wqy-microhei``, at
development time only: nothing is downloaded when insrail runs). Writes
``resources/fonts/insrail-cjk-sans.ttf`` with the characters the reports need: Latin, Greek and the
symbols Helvetica lacks (− ‰ σ ≥ ≤ →), CJK punctuation and full-width forms, every hanzi of GB 2312
(the 6763 common simplified characters: the railway terms 轨距 水平 超高 轨向 高低 扭曲 三角坑 弦 检测
调整量 里程 and the standards' titles) and any other character of the shipped resources' texts.
TrueType outlines (reportlab embeds only TrueType), hinting dropped to keep the file small; reportlab
subsets it again to the glyphs a PDF uses.
"""

from __future__ import annotations

import sys
from pathlib import Path

from fontTools import subset
from fontTools.ttLib import TTFont

ROOT = Path(__file__).resolve().parent.parent
SOURCE = Path("/usr/share/fonts/truetype/wqy/wqy-microhei.ttc")
TARGET = ROOT / "resources" / "fonts" / "insrail-cjk-sans.ttf"
#: Unicode blocks kept whole: Latin, Latin-1, Greek, general punctuation, letterlike symbols, arrows,
#: mathematical operators, CJK symbols and punctuation, full-width forms.
BLOCKS = ((0x20, 0x7E), (0xA0, 0x17F), (0x370, 0x3FF), (0x2000, 0x206F), (0x2100, 0x214F), (0x2190, 0x21FF),
          (0x2200, 0x22FF), (0x3000, 0x303F), (0xFF00, 0xFFEF))


def gb2312_hanzi() -> set[int]:
    """The 6763 hanzi of GB 2312 (rows 16 to 87 of the EUC-CN table)."""
    characters = set()
    for row in range(0xB0, 0xF8):
        for cell in range(0xA1, 0xFF):
            try:
                characters.add(ord(bytes([row, cell]).decode("gb2312")))
            except UnicodeDecodeError:
                pass
    return characters


def resource_characters() -> set[int]:
    """Every non-ASCII character of the shipped resources' text files (profiles, fastener types)."""
    found = set()
    for path in (ROOT / "resources").rglob("*.toml"):
        found |= {ord(c) for c in path.read_text(encoding="utf-8") if ord(c) > 0x7F}
    return found


def main(argv: list[str]) -> int:
    source = Path(argv[0]) if argv else SOURCE
    font = TTFont(source, fontNumber=0) if source.suffix == ".ttc" else TTFont(source)
    wanted = gb2312_hanzi() | resource_characters()
    for first, last in BLOCKS:
        wanted |= set(range(first, last + 1))
    available = set(font.getBestCmap())
    missing = sorted(c for c in resource_characters() if c not in available)
    if missing:
        print("not in the source font:", "".join(chr(c) for c in missing))
    options = subset.Options()
    options.hinting = False
    options.layout_features = []
    options.name_IDs = ["*"]  # keep the copyright and licence records
    options.notdef_outline = True
    subsetter = subset.Subsetter(options)
    subsetter.populate(unicodes=sorted(wanted & available))
    subsetter.subset(font)
    TARGET.parent.mkdir(parents=True, exist_ok=True)
    font.save(TARGET)
    print(f"{TARGET}: {len(font.getBestCmap())} characters, {TARGET.stat().st_size / 1e6:.1f} MB")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
