"""Strict, fast parsing and writing of the numeric text tables every text format is made of.

Accepted layout (all text readers share it):

* Lines starting with ``#`` or ``%`` are comments; so is anything after such a
  marker on a data line. Blank lines are skipped.
* The first non-comment line may be a header row of column names (a line none of
  whose fields is a number); it is skipped and kept in :attr:`NumericTable.header`.
* Fields are separated by whitespace, or by commas when the first data line holds
  a comma (spaces around the commas are allowed).

Bounds (a disk image or a log copied in by mistake must not take the machine's memory): a text
file holds no NUL byte (:func:`check_text_file` refuses it as binary, echoing none of its bytes), no
line longer than :data:`MAX_LINE_CHARS` and at most :data:`MAX_LINES` lines (a 200 Hz IMU records
17 million lines a day; a numeric table of more does not fit this machine's memory anyway). The scan
streams the file in blocks, so refusing a 5 GB file takes seconds and a few megabytes.

Speed: the fast path is a compiled reader (:mod:`insrail.io.fastparse`: numba over the
memory-mapped bytes, exact Eisel-Lemire conversion), about 4x quicker than np.loadtxt and giving
its values bit for bit. What it does not handle for sure (any malformed line, words, ``nan``, rare
numbers) goes to numpy's C parser (``np.loadtxt``, one comment marker) on the file itself.
Nothing Python-level runs per line unless the parse fails or a check finds a bad row; only then
a slow scan walks the lines to name the exact line number and field for the error message.
"""

from __future__ import annotations

import contextvars
import io
import math
import os
import re
import warnings
from contextlib import contextmanager
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Callable, Collection, Iterator, NoReturn, Sequence

import numpy as np

from insrail.io.atomic import atomic_write
from insrail.io.errors import InputError
from insrail.notices import Phrase
from insrail.io.types import GAP_FACTOR, Gap

COMMENT_MARKERS = ("#", "%")
MAX_LINE_CHARS = 1 << 16
MAX_LINES = 100_000_000
MAX_QUOTED_CHARS = 24
_SCAN_BLOCK = 1 << 24
_BINARY = Phrase("binary data (a NUL byte), not a text file: a disk image, an archive or a file in UTF-16? "
                 "Save text as UTF-8 or ASCII")

_WRITE_CHUNK_ROWS = 20_000
# latin-1 decodes any byte: numbers are ASCII, and a comment in another 8-bit
# encoding (GBK from a Chinese logger, say) must not stop the parse.
_NUMERIC_ENCODING = "latin-1"


def strip_comment(line: str) -> str:
    """The data part of a line: text before the first comment marker, stripped."""
    cut = len(line)
    for marker in COMMENT_MARKERS:
        at = line.find(marker)
        if 0 <= at < cut:
            cut = at
    return line[:cut].strip()


def split_fields(content: str, delimiter: str | None) -> list[str]:
    if delimiter is None:
        return content.split()
    return [f.strip() for f in content.split(delimiter)]


def is_number(token: str) -> bool:
    try:
        float(token)
    except ValueError:
        return False
    return True


def header_value(comments: Sequence[str], key: str) -> str | None:
    """Value of a ``key = value`` (or ``key: value``) comment line, e.g. ``pulse_length_m = 0.001``."""
    pattern = re.compile(rf"^\s*{re.escape(key)}\s*[=:]\s*(\S+)")
    for comment in comments:
        match = pattern.match(comment)
        if match:
            return match.group(1)
    return None


def header_gps_week(path: Path, comments: Sequence[str]) -> int | None:
    """The GPS week of a ``# gps_week = 2381`` comment line, None without one."""
    value = header_value(comments, "gps_week")
    if value is None:
        return None
    try:
        return int(value)
    except ValueError:
        raise InputError(path, None, "header gps_week = {value!r}: expected an integer", fields={"value": value}) from None


def quoted(token: str) -> str:
    """A field of a file for an error message: quoted when it is short printable text (what a user
    typed: ``'1,5'``, ``'n/a'``), else only described, so that a message never echoes a line of a
    file that is not a survey file (``/etc/passwd`` named by mistake, or by a project handed over)."""
    if len(token) <= MAX_QUOTED_CHARS and token.isascii() and token.isprintable():
        return repr(token)
    return f"{len(token)} characters of text (not shown)"


def _column_label(col: int, names: Sequence[str]) -> Phrase:
    return (Phrase("column {number} ({name})", {"number": col + 1, "name": names[col]}) if col < len(names)
            else Phrase("column {number}", {"number": col + 1}))


@dataclass(frozen=True)
class _Layout:
    """What the head of a file says about its layout."""

    delimiter: str | None
    skip_lines: int            # lines before the first data row (comments and header row)
    header: tuple[str, ...]
    comments: tuple[str, ...]  # leading comment lines, marker stripped
    first_data_line: int       # 1-based


def bounded_lines(handle, path: Path) -> Iterator[tuple[int, str]]:
    """(line number, line) of an open text file, refusing a line longer than :data:`MAX_LINE_CHARS`
    or holding a NUL character (binary data) before it is all in memory."""
    for lineno, raw in enumerate(iter(lambda: handle.readline(MAX_LINE_CHARS + 1), ""), start=1):
        if "\0" in raw:
            raise InputError(path, lineno, _BINARY)
        if len(raw) > MAX_LINE_CHARS and not raw.endswith("\n"):
            raise InputError(path, lineno, _too_long())
        yield lineno, raw


def _too_long() -> Phrase:
    return Phrase("line longer than the limit of {max_line_chars:,} characters: not a text table of this kind",
                  {"max_line_chars": MAX_LINE_CHARS})


#: The text files checked within :func:`checked_once` (None outside it): their identity -> line count.
_CHECKED: contextvars.ContextVar[dict | None] = contextvars.ContextVar("insrail_checked_text_files", default=None)


@contextmanager
def checked_once() -> Iterator[None]:
    """Within the block (and the threads started from it with its context) :func:`check_text_file`
    scans a file it checked already only when it changed since (its device, inode, size or modification
    time): ``insrail process`` hashes a survey's files for the fusion's key and reads them right after,
    and the 45 MB of a short survey's IMU text took some 0.05 s to scan again."""
    token = _CHECKED.set({} if _CHECKED.get() is None else _CHECKED.get())
    try:
        yield
    finally:
        _CHECKED.reset(token)


def check_text_file(path: Path, max_lines: int = MAX_LINES, each_block: Callable[[bytes], object] | None = None
                    ) -> int:
    """Refuse ``path`` when it is binary, has an overlong line or more than ``max_lines`` lines
    (see the module docstring); one pass in blocks of :data:`_SCAN_BLOCK` bytes, each handed to
    ``each_block`` once it passed (a cache key hashes the file in the same pass, and a disk image
    is refused at its first block, not after hashing gigabytes). Returns the number of lines (a
    last line without a line end counts). Within :func:`checked_once` a file checked before and
    unchanged is not scanned again (unless ``each_block`` asks for its bytes)."""
    checked = _CHECKED.get()
    if checked is not None:
        stat = os.stat(path)
        identity = (os.fspath(path), stat.st_dev, stat.st_ino, stat.st_size, stat.st_mtime_ns, max_lines)
        if each_block is None and identity in checked:
            return checked[identity]
        lines = _scan_text_file(path, max_lines, each_block)
        checked[identity] = lines
        return lines
    return _scan_text_file(path, max_lines, each_block)


def _scan_text_file(path: Path, max_lines: int, each_block: Callable[[bytes], object] | None) -> int:
    """:func:`check_text_file`'s pass over the file."""
    from insrail.io.fastparse import line_scan  # numba: only when a file is read

    lineno, run = 1, 0  # the current line, and the bytes of it seen so far
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(_SCAN_BLOCK), b""):
            nul = block.find(b"\0")
            if nul >= 0:
                raise InputError(path, lineno + block.count(b"\n", 0, nul), _BINARY)
            ended, long, run = line_scan(np.frombuffer(block, dtype=np.uint8), run, MAX_LINE_CHARS)
            if long >= 0:
                raise InputError(path, lineno + long, _too_long())
            if run > MAX_LINE_CHARS:
                raise InputError(path, lineno + ended, _too_long())
            lineno += ended
            if lineno - 1 > max_lines:
                raise InputError(path, max_lines + 1, "more than the limit of {max_lines:,} lines: not a "
                                 "plausible survey file (a 200 Hz IMU records 17 million lines a day)", fields={"max_lines": max_lines})
            if each_block is not None:
                each_block(block)
    return lineno if run else lineno - 1


def _iter_lines(path: Path, text: str | None) -> Iterator[tuple[int, str]]:
    if text is not None:
        yield from enumerate(io.StringIO(text, newline=None), start=1)
        return
    with open(path, encoding="utf-8", errors="replace") as handle:
        yield from bounded_lines(handle, path)


def _sniff(path: Path, text: str | None) -> _Layout:
    comments: list[str] = []
    for lineno, raw in _iter_lines(path, text):
        stripped = raw.strip().lstrip("\ufeff")
        if stripped[:1] in COMMENT_MARKERS:
            comments.append(stripped[1:].strip())
            continue
        content = strip_comment(stripped)
        if not content:
            continue
        delimiter = "," if "," in content else None
        fields = split_fields(content, delimiter)
        if not any(is_number(f) for f in fields):
            return _Layout(delimiter, lineno, tuple(fields), tuple(comments), lineno + 1)
        return _Layout(delimiter, lineno - 1, (), tuple(comments), lineno)
    raise InputError(path, None, "empty file: no data lines")


@dataclass(frozen=True)
class NumericTable:
    """A parsed numeric text file.

    values       : (rows, columns) float64, all finite
    column_names : names used in messages (the reader's, else the header row's)
    header       : the header row found in the file, () if none
    comments     : the leading comment lines, marker stripped
    """

    path: Path
    values: np.ndarray
    column_names: tuple[str, ...]
    header: tuple[str, ...]
    comments: tuple[str, ...]
    layout: _Layout = field(repr=False)
    text: str | None = field(default=None, repr=False)

    def __len__(self) -> int:
        return len(self.values)

    @cached_property
    def line_numbers(self) -> np.ndarray:
        """1-based file line of every row (slow scan, used only to report errors)."""
        lines = [lineno for lineno, raw in _iter_lines(self.path, self.text)
                 if lineno > self.layout.skip_lines and strip_comment(raw)]
        return np.asarray(lines, dtype=np.int64)

    def line_of_row(self, row: int) -> int:
        return int(self.line_numbers[row])

    def fail(self, row: int, message: str, fields: dict | None = None) -> NoReturn:
        raise InputError(self.path, self.line_of_row(row), message, fields=fields)

    def column(self, col: int) -> np.ndarray:
        return self.values[:, col]


def _diagnose(path: Path, text: str | None, layout: _Layout, columns: Collection[int] | None,
              names: Sequence[str], parser_message: str) -> InputError:
    """Slow scan for the first line the C parser rejected: wrong field count or a non-number."""
    expected = None if columns is None else sorted(columns)
    first_count = None
    for lineno, raw in _iter_lines(path, text):
        if lineno <= layout.skip_lines:
            continue
        content = strip_comment(raw)
        if not content:
            continue
        fields = split_fields(content, layout.delimiter)
        if first_count is None:
            first_count = len(fields)
        allowed = expected if expected is not None else [first_count]
        if len(fields) not in allowed:
            wanted = " or ".join(str(c) for c in allowed)
            return InputError(path, lineno, "expected {wanted} columns, found {count}", fields={"wanted": wanted, "count": len(fields)})
        for col, token in enumerate(fields):
            if not token:
                return InputError(path, lineno, "{column} is empty", fields={"column": _column_label(col, names)})
            if not is_number(token):
                return InputError(path, lineno,
                                  "{column}: expected a number, found {quoted}", fields={"column": _column_label(col, names), "quoted": quoted(token)})
    return InputError(path, None, "could not be parsed as numbers ({parser_message})", fields={"parser_message": parser_message})


def _load(path: Path, text: str | None, layout: _Layout, comments) -> np.ndarray:
    source = path if text is None else io.StringIO(text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return np.loadtxt(source, dtype=np.float64, comments=comments, delimiter=layout.delimiter,
                          skiprows=layout.skip_lines, ndmin=2, encoding=_NUMERIC_ENCODING)


def _load_general(path: Path, text: str | None, layout: _Layout, columns: Collection[int] | None,
                  names: Sequence[str]) -> np.ndarray:
    """np.loadtxt's values, or the InputError naming the first line it rejects."""
    try:
        return _load(path, text, layout, COMMENT_MARKERS[0])
    except ValueError:
        # numpy strips a single comment marker in C but several only in Python
        # (2 s on 2 million lines); the rare file with "%" comments inside its
        # body pays that, and a real error still fails here and is diagnosed.
        try:
            return _load(path, text, layout, COMMENT_MARKERS)
        except ValueError as exc:
            raise _diagnose(path, text, layout, columns, names, str(exc)) from None


def read_numeric_table(path: str | Path, *, columns: Collection[int] | None = None,
                       column_names: Sequence[str] = (), text: str | None = None) -> NumericTable:
    """Parse a numeric text table strictly.

    columns      : the allowed column counts (None: any, but the same on every line)
    column_names : names for error messages
    text         : the file's content already transformed in memory (e.g. dates
                   turned into numbers); line numbers still refer to ``path``

    Raises InputError for a missing or empty file, a wrong column count, a field
    that is not a number, and NaN or infinite values, naming the line.
    """
    path = Path(path)
    if text is None:
        if not path.exists():
            raise InputError(path, None, "file not found")
        if path.is_dir():
            raise InputError(path, None, "is a folder, expected a file")
    try:
        line_count = check_text_file(path) if text is None else 0
        layout = _sniff(path, text)
        header = layout.header
        names = tuple(column_names) or header
        values = None
        if text is None:  # the compiled reader; None for what only the general parser handles
            from insrail.io.fastparse import parse_numeric_file  # numba: only when a table is read

            values = parse_numeric_file(path, layout.skip_lines, layout.delimiter == ",", line_count)
        if values is None:
            values = _load_general(path, text, layout, columns, names)
    except OSError as exc:
        raise InputError(path, None, "cannot be read: {reason}", fields={"reason": exc.strerror or exc}) from None

    table = NumericTable(path, values, names, header, layout.comments, layout, text)
    if values.shape[0] == 0:
        raise InputError(path, None, "empty file: no data lines")
    if columns is not None and values.shape[1] not in columns:
        wanted = " or ".join(str(c) for c in sorted(columns))
        table.fail(0, "expected {wanted} columns, found {shape}", fields={"wanted": wanted, "shape": values.shape[1]})
    finite = np.isfinite(values)
    if not finite.all():
        row, col = np.argwhere(~finite)[0]
        table.fail(row, "{column} is {value}: expected a finite number", fields={"column": _column_label(col, names), "value": values[row, col]})
    return table


def check_time_order(time_s: np.ndarray, fail, unit: str = "line", where=lambda row: row + 1) -> None:
    """Raise (through ``fail(row, message)``) at the first time stamp that does not increase.

    ``where(row)`` gives the line (or row) number shown for the previous stamp.
    """
    step = np.diff(time_s)
    bad = np.flatnonzero(step <= 0)
    if bad.size == 0:
        return
    row = int(bad[0]) + 1
    previous = f"{unit} {where(row - 1)}"
    if step[bad[0]] == 0:
        fail(row, "duplicate time stamp {time_s:.6f} (same as {previous})", fields={"time_s": time_s[row], "previous": previous})
    fail(row, "time stamp {time_s:.6f} is earlier than {time_s2:.6f} on {previous}: "
              "time stamps must increase", fields={"time_s": time_s[row], "time_s2": time_s[row - 1], "previous": previous})


def check_table_time(table: NumericTable, col: int = 0) -> np.ndarray:
    """The strictly increasing time column ``col`` of a table (InputError otherwise)."""
    time_s = table.column(col)
    check_time_order(time_s, table.fail, where=table.line_of_row)
    return time_s


def find_gaps(time_s: np.ndarray, factor: float = GAP_FACTOR) -> tuple[Gap, ...]:
    """Intervals longer than ``factor`` x the median interval, as Gap(start, end)."""
    if len(time_s) < 3:
        return ()
    nominal = np.median(np.diff(time_s), overwrite_input=True)  # one whole-run temporary at a time
    step = np.diff(time_s)
    return tuple(Gap(float(time_s[i]), float(time_s[i + 1]))
                 for i in np.flatnonzero(step > factor * nominal))


# --- tables with text fields (small files: CPIII observations, benchmarks) -----------------

@dataclass(frozen=True)
class TokenTable:
    """A small text table parsed field by field (files with text columns such as point ids)."""

    path: Path
    rows: tuple[tuple[str, ...], ...]
    line_numbers: tuple[int, ...]
    column_names: tuple[str, ...]
    header: tuple[str, ...]
    comments: tuple[str, ...]

    def __len__(self) -> int:
        return len(self.rows)

    def line_of_row(self, row: int) -> int:
        return self.line_numbers[row]

    def fail(self, row: int, message: str, fields: dict | None = None) -> NoReturn:
        raise InputError(self.path, self.line_numbers[row], message, fields=fields)

    def numbers(self, col: int) -> np.ndarray:
        """Column ``col`` as finite floats; rows lacking it are an error."""
        out = np.empty(len(self.rows))
        for i, (row, lineno) in enumerate(zip(self.rows, self.line_numbers)):
            try:
                value = float(row[col])
            except ValueError:
                raise InputError(self.path, lineno, "{label}: expected a number, found {quoted}", fields={
                    "label": _column_label(col, self.column_names), "quoted": quoted(row[col])}) from None
            if not math.isfinite(value):
                raise InputError(self.path, lineno, "{label} is {value}: expected a finite number", fields={
                    "label": _column_label(col, self.column_names), "value": value})
            out[i] = value
        return out

    def unique_ids(self, what: str) -> tuple[str, ...]:
        """The first column as ids, each once: the same id twice is an error naming both lines
        (``what``: how the message names an id, e.g. "benchmark")."""
        ids = tuple(row[0] for row in self.rows)
        seen: dict[str, int] = {}
        for row, point in enumerate(ids):
            if point in seen:
                self.fail(row, "{what} {point!r} appears twice (also on line {line_of_row})", fields={"what": what, "point": point, "line_of_row": self.line_of_row(seen[point])})
            seen[point] = row
        return ids

    def texts(self, col: int, default: str = "") -> np.ndarray:
        """Column ``col`` as strings, ``default`` where a row is shorter."""
        return np.array([row[col] if col < len(row) else default for row in self.rows], dtype=str)


def read_token_table(path: str | Path, *, min_columns: int, max_columns: int,
                     column_names: Sequence[str] = ()) -> TokenTable:
    """Split a small text table into fields, checking each line's field count."""
    path = Path(path)
    if not path.exists():
        raise InputError(path, None, "file not found")
    if path.is_dir():
        raise InputError(path, None, "is a folder, expected a file")
    try:
        check_text_file(path)
        layout = _sniff(path, None)
        rows: list[tuple[str, ...]] = []
        line_numbers: list[int] = []
        for lineno, raw in _iter_lines(path, None):
            content = strip_comment(raw)
            if lineno <= layout.skip_lines or not content:
                continue
            fields = tuple(split_fields(content, layout.delimiter))
            if not min_columns <= len(fields) <= max_columns:
                wanted = (f"{min_columns}" if min_columns == max_columns
                          else f"{min_columns} to {max_columns}")
                raise InputError(path, lineno, "expected {wanted} columns, found {count}", fields={"wanted": wanted, "count": len(fields)})
            rows.append(fields)
            line_numbers.append(lineno)
    except OSError as exc:
        raise InputError(path, None, "cannot be read: {reason}", fields={"reason": exc.strerror or exc}) from None
    if not rows:
        raise InputError(path, None, "empty file: no data lines")
    names = tuple(column_names) or layout.header
    return TokenTable(path, tuple(rows), tuple(line_numbers), names, layout.header, layout.comments)


# --- writing --------------------------------------------------------------------------------

def write_numeric_table(path: str | Path, columns: Sequence[np.ndarray], formats: Sequence[str],
                        header: Sequence[str], marker: str = "#") -> None:
    """Write columns as a whitespace-separated table with comment header lines, atomically.

    ``formats`` are printf formats, one per column (a 2-D column array takes one
    format per sub-column). Rows are formatted a block at a time with one C-level
    ``%`` so 2 million rows take seconds, not minutes.
    """
    data = np.column_stack([np.asarray(c, dtype=np.float64) for c in columns])
    if data.shape[1] != len(formats):
        raise ValueError(f"{len(formats)} formats for {data.shape[1]} columns")
    row_format = " ".join(formats) + "\n"
    with atomic_write(path) as handle:
        for line in header:
            handle.write(f"{marker} {line}\n")
        for start in range(0, len(data), _WRITE_CHUNK_ROWS):
            block = data[start:start + _WRITE_CHUNK_ROWS]
            handle.write((row_format * len(block)) % tuple(block.ravel().tolist()))
