"""Leica GSI (Geo Serial Interface) files of a total station: the raw pointings of free stations
(``total-station-gsi``, for ``[files.total_station]``) and CPIII coordinates (``cpiii-gsi``, for
``[files.cpiii]``).

A GSI file holds one block per line, a block is words separated by blanks. GSI-16 blocks start
with ``*`` and carry 16 data characters per word, GSI-8 blocks 8; both are read, GSI-16 is written.
A word is

    positions 1-2   word index (WI)
              3-6   additional information: for WI 11 the block number; for a measured value
                    position 5 the input mode and position 6 the unit (below)
              7     sign, + or -
              8-    the data, right-justified and zero-filled

Words read (every other word, e.g. 51 ppm/mm, 58 prism constant, 87 reflector height, 19
date/time, and every other block, e.g. code blocks 41-49, is skipped):

    11          point id; its leading zeros are padding and dropped
    21, 22      horizontal direction Hz and vertical (zenith) angle V. Unit 2: gon, 3: degrees, both
                with five decimals; 4: sexagesimal DDDMMSSs (the last digit 0.1"); mil (5) is refused.
                A face-II pointing (V beyond half a circle) is reduced to face I.
    31          slope distance, reduced by the instrument for prism constant and atmosphere. Unit 0:
                metres with a 1 mm last digit, 6: 0.1 mm, 8: 0.01 mm; feet (1, 7) are refused
    71          remark 1: the time of the pointing [s of GPS week]. GSI has no word for a time to
                the second (WI 19 holds minutes), so the trolley's control software or the crew
                records it here; a prism pointing needs it
    81, 82, 83  easting, northing, height of the target, unit as 31: the CPIII points of a
                ``cpiii-gsi`` file. In a pointing's block they are the instrument's own computation
                and not used: the set-ups are resected on the CPIII points here
    84-86, 88   station easting, northing, height, instrument height: a block with any of them and
                no 21, 22 or 31 is a station block, which starts a set-up named by its WI 11 (its
                coordinates are not used: a free station is resected on its CPIII points)

In ``total-station-gsi`` a pointing (a block with 21, 22 and 31) follows a station block; its
WI 11 names a CPIII point, or the trolley's prism when it starts with ``prism_prefix`` (any case).
Errors name the file, the line and the word. The resection is :mod:`insrail.geodesy.free_station`.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import NoReturn

import numpy as np

from insrail.io.atomic import atomic_write
from insrail.io.errors import InputError
from insrail.io.textparse import bounded_lines, check_text_file, quoted
from insrail.io.total_station import PRISM_TARGET
from insrail.io.types import ControlPoints, TotalStationObservations

POINT_ID, HZ, V, SLOPE, TIME = "11", "21", "22", "31", "71"
TARGET_ENH = ("81", "82", "83")
STATION = ("84", "85", "86", "88")
#: Unit digit (position 6) of an angle word -> radians per last digit.
ANGLE_UNITS = {"2": math.pi / 200.0 * 1e-5, "3": math.pi / 180.0 * 1e-5}
SEXAGESIMAL = "4"
#: Unit digit of a distance or coordinate word -> metres per last digit.
LENGTH_UNITS = {"0": 1e-3, "6": 1e-4, "8": 1e-5}
_REFUSED = {"1": "feet", "7": "feet", "5": "mil"}
_WORD = re.compile(r"^(\d\d)(.{4})([+-])(\S+)$")
_DATA_WIDTH = 16
_WORD_GAP = " "


@dataclass(frozen=True)
class _Word:
    index: str  # WI
    info: str
    negative: bool
    data: str
    position: int  # 1-based within the block
    text: str


class _Block:
    """One line's words by word index; :meth:`fail` names file, line and word."""

    def __init__(self, path: Path, line: int, content: str):
        self.path, self.line = path, line
        self.words: dict[str, _Word] = {}
        for position, text in enumerate(content.lstrip("*").split(), start=1):
            match = _WORD.match(text)
            if match is None:
                self.fail("word {position} ({quoted}): expected a GSI word: a two-digit word index, four "
                          "characters of information, a sign and the data", fields={"position": position, "quoted": quoted(text)})
            word = _Word(match[1], match[2], match[3] == "-", match[4], position, text)
            if word.index in self.words:
                self.fail("word {position} ({text}): word index {index} appears twice in the block", fields={"position": position, "text": text, "index": word.index})
            self.words[word.index] = word

    def fail(self, message: str, fields: dict | None = None) -> NoReturn:
        raise InputError(self.path, self.line, message, fields=fields)

    def has(self, *indices: str) -> list[str]:
        return [i for i in indices if i in self.words]

    def text(self, index: str) -> str:
        """A text word (point id): the data without its zero padding."""
        data = self.words[index].data.lstrip("0")
        return data or "0"

    def _unit(self, word: _Word, units: dict[str, float], what: str) -> float:
        unit = word.info[-1]
        if unit in units:
            return units[unit]
        known = ", ".join(sorted(units))
        self.fail("word {position} ({text}): {what} in "
                  "{get} is not read: expected unit digit (position 6) "
                  "{known}{value}", fields={"position": word.position, "text": word.text, "what": what, "get": _REFUSED.get(unit, 'unit ' + repr(unit)), "known": known, "value": ' or ' + SEXAGESIMAL if what == 'an angle' else ''})

    def _digits(self, word: _Word) -> int:
        if not word.data.isdigit():
            self.fail("word {position} ({text}): expected digits after the sign, found {quoted}", fields={"position": word.position, "text": word.text, "quoted": quoted(word.data)})
        return -int(word.data) if word.negative else int(word.data)

    def length(self, index: str) -> float:
        """A distance or coordinate [m]."""
        word = self.words[index]
        return self._digits(word) * self._unit(word, LENGTH_UNITS, "a distance")

    def angle(self, index: str) -> float:
        """An angle [rad]."""
        word = self.words[index]
        if word.info[-1] == SEXAGESIMAL:
            value = self._digits(word)
            sign, value = (-1 if value < 0 else 1), abs(value)
            seconds = value % 1000 / 10.0
            minutes = value // 1000 % 100
            if minutes >= 60 or seconds >= 60:
                self.fail("word {position} ({text}): expected DDDMMSSs with minutes and seconds "
                          "below 60", fields={"position": word.position, "text": word.text})
            return sign * math.radians(value // 100_000 + minutes / 60.0 + seconds / 3600.0)
        return self._digits(word) * self._unit(word, ANGLE_UNITS, "an angle")

    def number(self, index: str) -> float:
        """A decimal number written as text (remark 71)."""
        word = self.words[index]
        try:
            value = float(word.data)
        except ValueError:
            value = math.nan
        if not math.isfinite(value):
            self.fail("word {position} ({text}): expected a number, found {quoted}", fields={"position": word.position, "text": word.text, "quoted": quoted(word.data)})
        return -value if word.negative else value


_BOM = "\ufeff".encode().decode("latin-1")  # a UTF-8 byte-order mark read as latin-1


def _lines(handle, path: Path):
    """(line number, content) of the non-empty lines, a byte-order mark dropped (bounded: a binary
    file or an endless line is refused, :func:`insrail.io.textparse.bounded_lines`)."""
    for line, raw in bounded_lines(handle, path):
        content = raw.strip().removeprefix(_BOM) if line == 1 else raw.strip()
        if content:
            yield line, content


def _blocks(path: Path):
    check_text_file(path)
    with open(path, encoding="latin-1") as handle:
        for line, content in _lines(handle, path):
            yield _Block(path, line, content)


def read_total_station_gsi(path: str | Path, prism_prefix: str = PRISM_TARGET) -> TotalStationObservations:
    """Leica GSI-16 (or GSI-8) pointings of free stations -> TotalStationObservations (module
    docstring). A CPIII pointing without a time (WI 71) gets the time of the set-up's first timed
    pointing, or NaN when none has one."""
    path = Path(path)
    full = 2.0 * math.pi
    rows: dict[str, list] = {k: [] for k in ("setup", "target", "time_s", "hz_rad", "zenith_rad", "slope_m", "line")}
    setup = None
    for block in _blocks(path):
        measured = block.has(HZ, V, SLOPE)
        if not measured:
            if block.has(*STATION):
                if POINT_ID not in block.words:
                    block.fail("a station block (words {has}) needs the set-up's "
                               "name in word {point_id}", fields={"has": list(block.has(*STATION)), "point_id": POINT_ID})
                setup = block.text(POINT_ID)
            continue
        missing = [w for w in (POINT_ID, HZ, V, SLOPE) if w not in block.words]
        if missing:
            block.fail("a pointing needs words 11 (point id), 21 (Hz), 22 (V) and 31 (slope distance): "
                       "word {missing} missing", fields={"missing": list(missing)})
        if setup is None:
            block.fail("a pointing before any station block: expected a block with the set-up's name (word 11) "
                       "and its station words 84-86 or 88 first")
        hz, zenith, slope = block.angle(HZ), block.angle(V), block.length(SLOPE)
        if not 0.0 <= hz < full:
            block.fail("word {position} ({text}): Hz outside the full circle", fields={"position": block.words[HZ].position, "text": block.words[HZ].text})
        if not 0.0 < zenith < full or zenith == math.pi:
            block.fail("word {position} ({text}): V = {degrees:.5f} deg "
                       "is not a zenith angle of face I or II", fields={"position": block.words[V].position, "text": block.words[V].text, "degrees": math.degrees(zenith)})
        if zenith > math.pi:  # face II: the telescope transited, the circle read half a turn on
            zenith, hz = full - zenith, (hz + math.pi) % full
        if not slope > 0.0:
            block.fail("word {position} ({text}): expected a positive "
                       "slope distance", fields={"position": block.words[SLOPE].position, "text": block.words[SLOPE].text})
        target = block.text(POINT_ID)
        is_prism = target.lower().startswith(prism_prefix.lower())
        if is_prism and TIME not in block.words:
            block.fail("prism pointing {target}: expected its time [s of GPS week] in word {time} (remark 1)", fields={"target": target, "time": TIME})
        for key, value in (("setup", setup), ("target", PRISM_TARGET if is_prism else target),
                           ("time_s", block.number(TIME) if TIME in block.words else math.nan), ("hz_rad", hz),
                           ("zenith_rad", zenith), ("slope_m", slope), ("line", block.line)):
            rows[key].append(value)
    if not rows["line"]:
        raise InputError(path, None, "no pointing: expected blocks with words 11, 21, 22 and 31")
    table = {k: np.array(v) for k, v in rows.items()}
    prism = np.flatnonzero(table["target"] == PRISM_TARGET)
    late = prism[1:][np.diff(table["time_s"][prism]) <= 0]
    if late.size:
        raise InputError(path, int(table["line"][late[0]]), "word {time}: prism time {time_s} s is "
                         "not after the previous prism pointing's: times must increase", fields={"time": TIME, "time_s": table['time_s'][late[0]]})
    for name in dict.fromkeys(table["setup"]):  # an untimed CPIII pointing: its set-up's first time
        mine = table["setup"] == name
        timed = mine & np.isfinite(table["time_s"])
        if timed.any():
            table["time_s"][mine & ~timed] = table["time_s"][np.flatnonzero(timed)[0]]
    return TotalStationObservations(**table, source=path)


def detect(path: Path, lines: int = 20) -> str | None:
    """``total-station-gsi`` when the first ``lines`` non-empty lines are all GSI blocks and one holds
    a pointing (words 21, 22, 31), ``cpiii-gsi`` when one holds coordinates (81-83), else None."""
    found: set[str] = set()
    try:
        with open(path, encoding="latin-1") as handle:
            for _, content in _lines(handle, path):
                words = content.lstrip("*").split()
                if not all(_WORD.match(w) for w in words):
                    return None
                found |= {w[:2] for w in words}
                lines -= 1
                if lines == 0:
                    break
    except (OSError, InputError):  # unreadable, binary or an endless line: not GSI
        return None
    if {HZ, V, SLOPE} <= found:
        return "total-station-gsi"
    return "cpiii-gsi" if set(TARGET_ENH) <= found else None


def _check_id(point: str) -> str:
    if not point or len(point) > _DATA_WIDTH or point.startswith("0") or not re.fullmatch(r"[^\s*]+", point):
        raise ValueError(f"point id {point!r} cannot be written to GSI-16: 1 to {_DATA_WIDTH} characters without "
                         "blanks or '*', not starting with 0 (GSI pads ids with zeros)")
    return point.rjust(_DATA_WIDTH, "0")


def _word(index: str, info: str, value: int | str) -> str:
    """One GSI-16 word: WI, information, sign and 16 data characters."""
    if isinstance(value, str):
        return f"{index}{info}+{value}"
    if abs(value) >= 10**_DATA_WIDTH:
        raise ValueError(f"word {index}: {value} does not fit into {_DATA_WIDTH} digits")
    return f"{index}{info}{'-' if value < 0 else '+'}{abs(value):0{_DATA_WIDTH}d}"


def _write_blocks(path: str | Path, blocks) -> None:
    with atomic_write(path) as handle:
        for number, words in enumerate(blocks, start=1):
            handle.write("*" + _WORD_GAP.join([_word(POINT_ID, f"{number % 10_000:04d}", words[0]), *words[1:]])
                         + _WORD_GAP + "\n")


def write_total_station_gsi(path: str | Path, observations: TotalStationObservations) -> None:
    """Write GSI-16 (module docstring): per set-up a station block (name, instrument height 0), then its
    pointings in gon (1e-5 gon) and metres (0.01 mm), each with its time in remark 1 (0.1 ms);
    atomically. A set-up's pointings are written together, in their order."""
    gon = 200.0 / math.pi
    blocks = []
    for setup in dict.fromkeys(observations.setup):
        blocks.append([_check_id(str(setup)), _word(STATION[3], "..08", 0)])
        for k in np.flatnonzero(observations.setup == setup):
            time_s = float(observations.time_s[k])
            if not 0.0 <= time_s < 1e10:
                raise ValueError(f"pointing {k + 1}: time {time_s} s cannot be written (s of GPS week expected)")
            target = str(observations.target[k])
            blocks.append([_check_id(target.upper() if target == PRISM_TARGET else target),
                           _word(HZ, ".102", round(gon * 1e5 * float(observations.hz_rad[k])) % 40_000_000),
                           _word(V, ".102", round(gon * 1e5 * float(observations.zenith_rad[k]))),
                           _word(SLOPE, "..08", round(1e5 * float(observations.slope_m[k]))),
                           _word(TIME, "....", f"{time_s:.4f}".rjust(_DATA_WIDTH, "0"))])
    _write_blocks(path, blocks)


def read_cpiii_gsi(path: str | Path) -> ControlPoints:
    """Leica GSI-16 (or GSI-8) coordinates -> ControlPoints: every block with words 81-83 is a point
    named by its WI 11 (module docstring); the same id twice is an error."""
    path = Path(path)
    ids, coordinates, seen = [], [], {}
    for block in _blocks(path):
        present = block.has(*TARGET_ENH)
        if not present:
            continue
        if len(present) < 3 or POINT_ID not in block.words:
            missing = [w for w in (POINT_ID, *TARGET_ENH) if w not in block.words]
            block.fail("a point needs words 11 (id), 81 (E), 82 (N) and 83 (H): word {missing} missing", fields={"missing": list(missing)})
        point = block.text(POINT_ID)
        if point in seen:
            block.fail("word {position}: point {point} is given twice (first on line "
                       "{first_line})", fields={"position": block.words[POINT_ID].position, "point": point, "first_line": seen[point]})
        seen[point] = block.line
        ids.append(point)
        coordinates.append([block.length(w) for w in TARGET_ENH])
    if not ids:
        raise InputError(path, None, "no point: expected blocks with words 11, 81, 82 and 83")
    east, north, height = np.array(coordinates).T
    return ControlPoints(point_id=np.array(ids), east_m=east, north_m=north, height_m=height, source=path)


def write_cpiii_gsi(path: str | Path, points: ControlPoints) -> None:
    """Write GSI-16 coordinate blocks (11, 81-83 in metres with 0.01 mm), atomically."""
    _write_blocks(path, ([_check_id(str(p)), *(_word(w, "..08", round(1e5 * float(v))) for w, v in zip(TARGET_ENH, enh))]
                         for p, *enh in zip(points.point_id, points.east_m, points.north_m, points.height_m)))
