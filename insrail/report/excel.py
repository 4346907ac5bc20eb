"""The Excel workbook for the adjustment crews (openpyxl, write-only: a 16 000-sleeper table in seconds).

Sheets: ``Sleepers`` (the thesis's Figure 5-7 table and more, see :mod:`insrail.report.content`),
``Adjustment`` (only the sleepers to move, in the order the crew walks: by chainage),
``Exceedances``, ``Summary`` (statistics per parameter, per 200 m section, TQI) and
``Processing log`` (software, settings, QC figures of summary.toml).

Cell fills carry meaning and nothing else: red = inside one of the pipeline's exceedance runs,
grey = invalid sleeper (crossing, switch, flagged data); header rows have their own style.
Numbers are stored unrounded (as read from the result files) and formatted to 0.1 mm.
"""

from __future__ import annotations

import datetime
import io
import math
import re
import shutil
import tempfile
import tomllib
import unicodedata
import zipfile
from collections.abc import Callable, Sequence
from functools import cache
from html import escape  # as xml.sax.saxutils's (& < >) with quote=False, without its import of urllib and http
from pathlib import Path
from typing import IO

import numpy as np
from openpyxl import Workbook
from openpyxl.cell import WriteOnlyCell
from openpyxl.cell.cell import Cell
from openpyxl.styles import Alignment, Border, Font, PatternFill, Side
from openpyxl.utils import get_column_letter
from openpyxl.worksheet.pagebreak import Break
from openpyxl.worksheet.worksheet import Worksheet

from insrail.io.atomic import atomic_write
from insrail.names import check_name, fastener_name, in_language, profile_name, quantity_name, t
from insrail.notices import Phrase, notices_of, phrase_of
from insrail.progress import CancelToken, ProgressFn, StepProgress, check_cancel
from insrail.project.model import Project
from insrail.project.results import StoredResults
from insrail.project.run_settings import report_language
from insrail.report.content import (
    RELATIVE_SURVEY_TEXT,
    SEVERITY_RULE,
    Column,
    ReportContent,
    after_adjustment_text,
    crew_sections,
    check_description,
    exceedance_check,
    exceedance_display,
    exceedances_by_severity,
    excess_share,
    limits_text,
    load_report_content,
    parameter_statistics,
    sections,
    sleeper_repair_text,
    is_relative,
    survey_start,
    survey_title,
    redesign_not_passing,
    tamping_mark_name,
    threshold_text,
)
from insrail.report.labels import SIGNS, amounts_text, amounts_withheld_text, deviation_reference

EXCEEDANCE_FILL = PatternFill("solid", fgColor="FFC7CE")  # the spreadsheet's usual "bad" red
INVALID_FILL = PatternFill("solid", fgColor="D9D9D9")
HEADER_FILL = PatternFill("solid", fgColor="DDEBF7")
BODY_FONT = "Calibri"  # the workbook's default font, named so that a font of its own keeps the family
TITLE_FONT = Font(name=BODY_FONT, bold=True, size=14)
BOLD = Font(name=BODY_FONT, bold=True)
RED_FONT = Font(name=BODY_FONT, color="9C0006")
HEADER_ALIGNMENT = Alignment(horizontal="center", vertical="center", wrap_text=True)
WRAPPED = Alignment(wrap_text=True)
GROUP_ALIGNMENT = Alignment(horizontal="center", vertical="center", wrap_text=True)  # merged over its columns
#: Columns (0-based) of label, value, label, value ... in the header blocks above the tables.
BLOCK_ANCHORS = (0, 4, 12, 16, 24, 28)
THIN = Side(style="thin", color="808080")
HEADER_BORDER = Border(bottom=THIN)
GROUP_BORDER = Border(left=THIN, right=THIN, top=THIN, bottom=THIN)
SECTION_M = 200.0
#: Rows of a big table (:meth:`_Sheet.table`) formatted at once, and the bytes copied at a time from its
#: temporary file into the workbook: what the writer holds, whatever the survey's length.
TABLE_BLOCK_ROWS = 2048
SPOOL_COPY_BYTES = 1 << 20
PAPER_CODES = {"A3": 8, "A4": 9}  # OOXML paper size codes
#: Paper width and height [mm] (portrait), the side margins [inch] and the body font [pt] of a printed sheet.
PAPER_MM = {"A3": (297.0, 420.0), "A4": (210.0, 297.0)}
SIDE_MARGIN_IN = 0.4
BODY_FONT_PT = 11.0
#: The smallest printed text [pt] on a sheet a crew or a reader works from.
READABLE_PT = 9.0
#: The sleeper table's print scale [%]: 11 pt printed at 9.35 pt, the columns in groups of pages.
SLEEPER_PRINT_SCALE = 85
#: Header text metrics at the default zoom: characters of the bold 11 pt header font per unit of column
#: width (a unit is one digit of the body font; bold letters are wider), and the height of a text line [pt].
BOLD_CHARACTER_WIDTH = 1.15
BODY_CHARACTER_WIDTH = 0.9  # the body font's letters, for wrapping text cells
LINE_HEIGHT_PT = 14.5


class _Sheet:
    """Rows appended to a write-only worksheet.

    A write-only sheet streams its rows to disk, and the file format puts the sheet's layout
    (frozen panes, column widths, fit-to-page) before the rows: rows appended before
    :meth:`start` wait in memory (the header block) until the layout is known.

    Big tables go through :meth:`table`: without lxml, openpyxl serialises about 25 000 cells a
    second, so a 16 000-sleeper table would take half a minute. :meth:`table` writes the rows'
    SpreadsheetML itself (styles registered with openpyxl, so styles.xml stays openpyxl's), a block
    of rows at a time, to a temporary file (:attr:`spool`), and :func:`_splice_tables` copies them
    to the end of the sheet's data when the workbook is saved: the table's text is never held whole.
    """

    def __init__(self, sheet: Worksheet):
        self.sheet = sheet
        self.rows = 0
        self._pending: list[list] | None = []
        self._heights: dict[int, float] = {}
        self.spool: IO[bytes] | None = None  # the table rows' SpreadsheetML (UTF-8), once there is a table
        self.last_cell = "A1"
        self.widths: list[float] | None = None
        self._header_titles: dict[int, list[tuple[str, int]]] = {}  # row -> (title, columns it spans)
        self._later_titles: list[list[tuple[str, int]]] = []  # headers to come below the layout

    def style_id(self, number_format: str | None = None, fill: PatternFill | None = None,
                 font: Font | None = None, alignment: Alignment | None = None) -> int:
        """The workbook's index of a cell style (registered when new)."""
        return self.cell(None, number_format, font=font, fill=fill, alignment=alignment).style_id

    def table(self, columns: list[tuple[Sequence, Sequence[int] | int]], progress: StepProgress | None = None,
              cancel: CancelToken = None, heights: list[float | None] | None = None) -> None:
        """Rows below everything appended so far: one (values, style id per row or for all) per column.
        Values (a list or an array; an object array's items are written as text) are float (NaN:
        empty cell), int, or str ("" empty); ``heights`` [pt] per row (None: the default height).
        Formatted :data:`TABLE_BLOCK_ROWS` rows at a time into :attr:`spool`."""
        if self._pending is not None:
            raise RuntimeError("start() the sheet before its table")
        if not columns or not len(columns[0][0]):
            return
        first = self.rows + 1
        count = len(columns[0][0])
        letters = [get_column_letter(index + 1) for index in range(len(columns))]
        if self.spool is None:
            self.spool = tempfile.TemporaryFile()
        for start in range(0, count, TABLE_BLOCK_ROWS):
            check_cancel(cancel)
            if progress is not None:
                progress(start / count, "writing the table")
            block = slice(start, min(start + TABLE_BLOCK_ROWS, count))
            numbers = [str(r) for r in range(first + block.start, first + block.stop)]
            cells = [_cells(letter, numbers, _listed(values[block]),
                            [styles] * len(numbers) if isinstance(styles, int) else _listed(styles[block]))
                     for letter, (values, styles) in zip(letters, columns)]
            rows = [f'<row r="{r}"' + (f' ht="{h:g}" customHeight="1"' if h else "") for r, h in
                    zip(numbers, heights[block] if heights else [None] * len(numbers))]
            self.spool.write("".join(f'{start}>{"".join(row)}</row>' for start, *row in zip(rows, *cells)).encode("utf-8"))
        self.rows += count
        self.last_cell = f"{get_column_letter(len(columns))}{self.rows}"

    def close(self) -> None:
        """Delete the table's temporary file."""
        if self.spool is not None:
            self.spool.close()

    def cell(self, value, number_format: str | None = None, font: Font | None = None, fill: PatternFill | None = None,
             alignment: Alignment | None = None, border: Border | None = None) -> WriteOnlyCell:
        cell = WriteOnlyCell(self.sheet, value=_cell_value(value))
        if number_format:
            cell.number_format = number_format
        if font:
            cell.font = font
        if fill:
            cell.fill = fill
        if alignment:
            cell.alignment = alignment
        if border:
            cell.border = border
        return cell

    def append(self, row: list) -> int:
        self.rows += 1
        if self._pending is None:
            self.sheet.append(row)
        else:
            self._pending.append(row)
        return self.rows

    def title(self, text: str) -> None:
        self.append([self.cell(text, font=TITLE_FONT)])

    def pairs(self, *pairs: tuple[str, object], anchors: tuple[int, ...] = BLOCK_ANCHORS) -> None:
        """One row of label: value pairs, label and value at the given columns (0-based) so that
        text runs on over the empty cells between them."""
        row: list = [None] * (anchors[2 * len(pairs) - 1] + 1)
        for index, (label, value) in enumerate(pairs):
            row[anchors[2 * index]] = self.cell(label, font=BOLD)
            row[anchors[2 * index + 1]] = value if isinstance(value, Cell) else self.cell(value)
        self.append(row)

    def set_height(self, row: int, height: float) -> None:
        """The height [pt] of a row appended before :meth:`start` (streamed with it)."""
        self._heights[row] = height

    def header(self, titles: list[str]) -> int:
        """A row of column titles; its height (and, before :meth:`start`, the column widths) fit the titles."""
        self._fit_header(self.rows + 1, [(title, 1) for title in titles])
        return self.append([self.cell(t, font=BOLD, fill=HEADER_FILL, alignment=HEADER_ALIGNMENT, border=HEADER_BORDER)
                            for t in titles])

    def header_below(self, titles: list[str]) -> None:
        """Widen the columns (at :meth:`start`) for a header row that will be appended below the layout."""
        self._later_titles.append([(title, 1) for title in titles])

    def group_header(self, groups: list[str]) -> int:
        """A row of group titles, one per column: each run of equal titles becomes one merged cell over its
        columns (the other developers' columns get it by naming their group)."""
        runs: list[tuple[str, int, int]] = []  # title, first and last column (1-based)
        for index, group in enumerate(groups, start=1):
            if runs and runs[-1][0] == group:
                runs[-1] = (group, runs[-1][1], index)
            else:
                runs.append((group, index, index))
        cells: list = [None] * len(groups)
        for group, first, last in runs:
            cells[first - 1] = self.cell(group, font=BOLD, fill=HEADER_FILL, alignment=GROUP_ALIGNMENT, border=GROUP_BORDER)
        self._fit_header(self.rows + 1, [(group, last - first + 1) for group, first, last in runs])
        row = self.append(cells)
        for _, first, last in runs:
            if last > first:
                self.sheet.merged_cells.add(f"{get_column_letter(first)}{row}:{get_column_letter(last)}{row}")
        return row

    def _fit_header(self, row: int, titles: list[tuple[str, int]]) -> None:
        """Record a header row's titles (before it is appended: a streamed row's height goes out with it)."""
        self._header_titles[row] = titles
        if self.widths is not None:  # a header below the table's layout: only its height can still fit
            self._heights[row] = _header_height(titles, self.widths)
            self.sheet.row_dimensions[row].height = self._heights[row]

    def fitted_widths(self, widths: list[float]) -> list[float]:
        """``widths`` with every column widened where the longest word of a header title above it would not fit."""
        widths = list(widths)
        for titles in [*self._header_titles.values(), *self._later_titles]:
            column = 0
            for title, span in titles:
                if span == 1 and column < len(widths):
                    widths[column] = max(widths[column], _longest_word(title) * BOLD_CHARACTER_WIDTH + 1.5)
                column += span
        return widths

    def long_pair(self, label: str, text: str) -> tuple[int, str]:
        """A label and a long text wrapped in its cell (at the header block's value column); (row, text) for
        :meth:`wrap_over`."""
        return self.append([self.cell(label, font=BOLD), None, None, None,
                            self.cell(text, alignment=Alignment(wrap_text=True, vertical="top"))]), text

    def wrap_over(self, row: int, text: str, widths: list[float], first: int, stop: int) -> None:
        """Merge a :meth:`long_pair` text's cell over columns [first, stop) (0-based) and make its row as high as
        the text wraps there (before :meth:`start`)."""
        self.sheet.merged_cells.add(f"{get_column_letter(first + 1)}{row}:{get_column_letter(stop)}{row}")
        self.set_height(row, LINE_HEIGHT_PT * _wrapped_lines(text, sum(widths[first:stop]), BODY_CHARACTER_WIDTH) + 2.0)

    def start(self, widths: list[float], freeze: str | None = None, paper: str = "A3",
              page_header: tuple[str, str, str] = ("", "", ""), orientation: str = "landscape",
              scale: int | None = None) -> None:
        """Fix the layout (column widths, frozen panes, printing) and write the rows held so far.

        A column is widened where the longest word of a title above it would not fit (nothing in a
        header is clipped or broken inside a word), and each header row is as high as its titles wrap."""
        widths = self.fitted_widths(widths)
        self.widths = widths
        for row, titles in self._header_titles.items():
            self._heights[row] = _header_height(titles, widths)
        for index, width in enumerate(widths, start=1):
            self.sheet.column_dimensions[get_column_letter(index)].width = width
        if freeze:
            self.sheet.freeze_panes = freeze
        _printable(self.sheet, paper, page_header, orientation, scale)
        pending, self._pending = self._pending or [], None
        for index, row in enumerate(pending, start=1):
            if index in self._heights:
                self.sheet.row_dimensions[index].height = self._heights[index]
            self.sheet.append(row)

    def finish_table(self, header_row: int, first_header_row: int, columns: int) -> None:
        """Filter the table below ``header_row``; print the header rows on every page."""
        if self.rows > header_row:
            self.sheet.auto_filter.ref = f"A{header_row}:{get_column_letter(columns)}{self.rows}"
        self.sheet.print_title_rows = f"{first_header_row}:{header_row}"


#: Chinese characters and punctuation: the spreadsheet wraps a line between any two of them.
_CJK = re.compile(r"([\u2e80-\u9fff\u3000-\u303f\uff00-\uffef])")


def _pieces(word: str) -> list[str]:
    """The parts of a word no line break splits: the word, or in Chinese each character."""
    return [piece for piece in _CJK.split(word) if piece]


#: Width of a Chinese character in digits of the body font (LibreOffice sets it in the system's CJK font: a
#: line of the crew sheet's notes held 45 Latin characters and 23 Chinese in 103 digits).
CJK_CHARACTER_WIDTH = 2.5


def _text_width(text: str) -> float:
    """Width in characters of the body font (a Chinese character: :data:`CJK_CHARACTER_WIDTH`)."""
    return sum(CJK_CHARACTER_WIDTH if unicodedata.east_asian_width(c) in "WF" else 1 for c in text)


def _longest_word(text: str) -> float:
    return max((_text_width(piece) for word in str(text).split() for piece in _pieces(word)), default=0)


def _wrapped_lines(text: str, width: float, character_width: float = BOLD_CHARACTER_WIDTH) -> int:
    """Lines ``text`` wraps to in a cell ``width`` wide (word wrap as the spreadsheet does it, Chinese
    between any two characters)."""
    characters = max(int((width - 1.0) / character_width), 1)
    lines, used = 1, 0
    for word in str(text).split():
        for index, piece in enumerate(_pieces(word)):
            size, gap = _text_width(piece), 1 if used and index == 0 else 0
            if used and used + gap + size > characters:
                lines, used = lines + 1, size
            else:
                used += gap + size
    return lines


def _header_height(titles: list[tuple[str, int]], widths: list[float]) -> float:
    """Height [pt] of a header row holding ``titles`` (title, columns spanned), left to right."""
    lines, column = 1, 0
    for title, span in titles:
        width = sum(widths[column:column + span]) if column < len(widths) else 10.0
        lines = max(lines, _wrapped_lines(title, width))
        column += span
    return LINE_HEIGHT_PT * lines + 4.0


def _listed(values: Sequence) -> list:
    """A block of a column as Python values: an array's numbers as float or int, an object array's items as text."""
    if isinstance(values, np.ndarray):
        return values.tolist() if values.dtype != object else [str(v) for v in values]
    return list(values)


def _cells(letter: str, rows: list[str], values: list, styles: list[int]) -> list[str]:
    """The <c> elements of one column; floats as the shortest text that reads back the same number."""
    out = []
    for row, value, style in zip(rows, values, styles):
        if isinstance(value, str):
            out.append(f'<c r="{letter}{row}" s="{style}" t="inlineStr"><is><t>{escape(value, quote=False)}</t></is></c>' if value
                       else f'<c r="{letter}{row}" s="{style}"/>')
        elif value is None or not math.isfinite(value):  # an empty, styled cell (NaN: not computable)
            out.append(f'<c r="{letter}{row}" s="{style}"/>')
        else:
            out.append(f'<c r="{letter}{row}" s="{style}"><v>{value!r}</v></c>')
    return out


def _splice_tables(xlsx: bytes, sheets: list[_Sheet], handle) -> None:
    """Copy the workbook ``xlsx`` to ``handle`` with each sheet's :meth:`_Sheet.table` rows at the
    end of its sheetData and its dimension covering them: the sheet's own XML before them, the rows
    copied from the spool in blocks of :data:`SPOOL_COPY_BYTES`, then the rest of the sheet's XML."""
    tables = {sheet.sheet.path.lstrip("/"): sheet for sheet in sheets if sheet.spool is not None}
    with zipfile.ZipFile(io.BytesIO(xlsx)) as source, \
            zipfile.ZipFile(handle, "w", zipfile.ZIP_DEFLATED, compresslevel=1) as target:
        for info in source.infolist():
            data = source.read(info.filename)
            sheet = tables.get(info.filename)
            if sheet is None:
                target.writestr(info.filename, data)
                continue
            text = data.decode("utf-8")
            text = re.sub(r'<dimension ref="[^"]*"\s*/>', f'<dimension ref="A1:{sheet.last_cell}"/>', text, count=1)
            if "</sheetData>" in text:
                head, tail = text.split("</sheetData>", 1)
            else:
                head, tail = text.split("<sheetData/>", 1)
                head += "<sheetData>"
            with target.open(info.filename, "w") as member:
                member.write(head.encode("utf-8"))
                sheet.spool.seek(0)
                shutil.copyfileobj(sheet.spool, member, SPOOL_COPY_BYTES)
                member.write(("</sheetData>" + tail).encode("utf-8"))


def _cell_value(value):
    """Cells hold numbers or text; NaN (not computable) is an empty cell, numpy scalars plain Python."""
    if isinstance(value, (float, np.floating)):
        return None if not np.isfinite(value) else float(value)
    if isinstance(value, np.integer):
        return int(value)
    return value


def _header_text(text: str) -> str:
    """Text for a print header or footer ("&" starts a field code there)."""
    return text.replace("&", "&&")


def column_width_mm(width: float) -> float:
    """The printed width [mm] at 100 % of a column ``width`` units wide (a unit is one digit of the 11 pt body
    font, 7 px at 96 dpi, plus 5 px of padding)."""
    return (7.0 * width + 5.0) * 25.4 / 96.0


def printable_width_mm(paper: str, orientation: str) -> float:
    """The width [mm] between the side margins of a page."""
    short, long = PAPER_MM[paper]
    return (long if orientation == "landscape" else short) - 2 * 25.4 * SIDE_MARGIN_IN


def _printable(sheet: Worksheet, paper: str = "A3", page_header: tuple[str, str, str] = ("", "", ""),
               orientation: str = "landscape", scale: int | None = None) -> None:
    """On the project's paper, one page wide (``scale`` None) or at ``scale`` percent (the sheet says
    where its pages break); print header: project, survey, sheet; footer: software and "page x of y"."""
    sheet.page_setup.orientation = orientation
    sheet.page_setup.paperSize = PAPER_CODES[paper]
    sheet.page_margins.left = sheet.page_margins.right = SIDE_MARGIN_IN
    project, survey, software = page_header
    sheet.HeaderFooter.oddHeader.left.text = _header_text(project)
    sheet.HeaderFooter.oddHeader.center.text = _header_text(survey)
    sheet.HeaderFooter.oddHeader.right.text = "&A"
    sheet.HeaderFooter.oddFooter.left.text = _header_text(software)
    sheet.HeaderFooter.oddFooter.right.text = t("page {number} of {pages}").format(number="&P", pages="&N")
    if scale is None:
        sheet.page_setup.fitToWidth = 1
        sheet.page_setup.fitToHeight = 0  # as many pages as the rows need
        sheet.sheet_properties.pageSetUpPr.fitToPage = True
    else:
        sheet.page_setup.scale = scale
        sheet.sheet_properties.pageSetUpPr.fitToPage = False
    sheet.print_options.gridLines = True


def page_header(content: ReportContent) -> tuple[str, str, str]:
    """What every printed page of the workbook names: project, survey and chainage, software."""
    return (content.project.name, t("survey {survey} {start}, {chainage}").format(
        survey=survey_title(content), start=survey_start(content), chainage=content.chainage_range), content.software)


def _start(sheet: _Sheet, content: ReportContent, widths: list[float], freeze: str | None = None,
           scale: int | None = None) -> None:
    """Lay out a sheet for the project's paper (landscape) with the page header of the report."""
    sheet.start(widths, freeze, content.project.report.paper, page_header(content), scale=scale)


def _context(content: ReportContent) -> str:
    """Project, survey, chainage and tolerance profile in one line (above the smaller tables)."""
    return t("{project}, survey {survey} {start}, {chainage}, tolerance profile {profile}; {software}").format(
        project=content.project.name, survey=survey_title(content), start=survey_start(content),
        chainage=content.chainage_range, profile=profile_name(content.profile), software=content.software)


def _header_block(sheet: _Sheet, content: ReportContent, title: str) -> None:
    project, summary = content.project, content.summary
    track = summary.get("track", {})
    sheet.title(title)
    sleepers = t("{sleepers} ({valid} valid)").format(sleepers=track.get("sleepers", len(content.results)),
                                                      valid=track.get("valid_sleepers", int(content.valid.sum())))
    if repair := sleeper_repair_text(summary):
        sleepers += f"; {repair}"
    sheet.pairs((t("Project"), project.name), (t("Line"), project.description or project.name),
                (t("Survey"), survey_title(content)))
    if is_relative(summary):
        sheet.pairs((t("Survey kind"), t(RELATIVE_SURVEY_TEXT)))
    sheet.pairs((t("Chainage"), content.chainage_range), (t("Sleepers"), sleepers),
                (t("Survey start"), survey_start(content)))
    profile = content.profile
    sheet.pairs((t("Tolerance profile"), profile_name(profile)), (t("Standard"), t(profile.source)),
                (t("Design"), content.design or t("fitted lines (no design alignment)")))
    if content.settings_changes:  # the project says otherwise now: the results stand as processed
        sheet.pairs((t("Settings"), "; ".join(content.settings_changes)), anchors=(0, 4))
    sheet.pairs((t("Nominal gauge"), f"{1e3 * profile.nominal_gauge_m:.1f} mm"), (t("Software"), content.software),
                (t("Operator"), content.project.report.operator or t("not stated")))



# --------------------------------------------------------------------------- sleepers

def _sleeper_sheet(sheet: _Sheet, content: ReportContent, progress: StepProgress, cancel: CancelToken) -> None:
    _header_block(sheet, content, t("Track geometry per sleeper"))
    sheet.pairs((t("Legend"), sheet.cell(t("beyond a limit"), fill=EXCEEDANCE_FILL)),
                ("", sheet.cell(t("invalid sleeper"), fill=INVALID_FILL)))
    long_texts = [sheet.long_pair(t("Limits"), "; ".join(f"{check_name(c)} {limits_text(c)}"
                                                         for c in content.profile.checks)),
                  sheet.long_pair(t("Deviations"), t("{reference}: where the rail is ({signs})").format(
                      reference=deviation_reference(content.summary), signs=t(SIGNS))),
                  sheet.long_pair(t("Adjustment"), amounts_text(content.summary, content.profile, content.fastener))]
    columns = content.columns
    first_header = sheet.group_header([column.group for column in columns])
    sheet.header([limits_text_for(column) for column in columns])
    header = sheet.header([f"{c.title} ({c.unit})" if c.unit else c.title for c in columns])
    # printed in readable column groups: the sleeper's identity on every page, a page break between groups; the
    # long texts above wrapped within the first page
    widths = sheet.fitted_widths([c.width for c in columns])
    starts = column_pages(widths, [c.group for c in columns], SLEEPER_TITLE_COLUMNS,
                          printable_width_mm(content.project.report.paper, "landscape") * 100 / SLEEPER_PRINT_SCALE)
    for row, text in long_texts:
        sheet.wrap_over(row, text, widths, BLOCK_ANCHORS[1], starts[1] if len(starts) > 1 else len(columns))
    _start(sheet, content, widths, freeze=f"E{header + 1}", scale=SLEEPER_PRINT_SCALE)
    for first in starts[1:]:
        sheet.sheet.col_breaks.append(Break(id=first, max=1048575))
    sheet.sheet.print_title_cols = f"A:{get_column_letter(SLEEPER_TITLE_COLUMNS)}"

    # a style per column and state: plain, inside an exceedance run, invalid sleeper
    plain = [sheet.style_id(c.number_format) for c in columns]
    red = [sheet.style_id(c.number_format, EXCEEDANCE_FILL) for c in columns]
    grey = [sheet.style_id(c.number_format, INVALID_FILL) for c in columns]
    valid = content.valid
    table = []
    for index, column in enumerate(columns):
        styles = np.where(valid, plain[index], grey[index])
        if column.exceeding is not None:
            styles = np.where(column.exceeding, red[index], styles)
        table.append((column.values, styles.astype(np.uint16)))  # a few style ids: 2 bytes a cell
    sheet.table(table, progress, cancel)
    sheet.finish_table(header, first_header, len(columns))


#: The sleeper table's columns printed on every page: row, sleeper number, chainage, station.
SLEEPER_TITLE_COLUMNS = 4


def column_pages(widths: list[float], groups: list[str], title_columns: int, page_mm: float) -> list[int]:
    """The first column (0-based) of each printed page of a wide table: whole groups of columns per
    page as far as they fit beside the ``title_columns`` repeated on every page (a group wider than a
    page on its own is broken between its columns)."""
    room = page_mm - sum(column_width_mm(w) for w in widths[:title_columns])
    starts, used = [title_columns], 0.0
    index = title_columns
    while index < len(widths):
        stop = index
        while stop < len(widths) and groups[stop] == groups[index]:
            stop += 1
        size = sum(column_width_mm(w) for w in widths[index:stop])
        if used and used + size > room:
            starts.append(index)
            used = 0.0
        for column in range(index, stop):  # within a group too wide for any page
            width = column_width_mm(widths[column])
            if used and used + width > room:
                starts.append(column)
                used = 0.0
            used += width
        index = stop
    return starts


def limits_text_for(column: Column) -> str:
    if column.limits is None:
        return ""
    lower, upper = column.limits
    digits = 2 if column.unit == "‰" else 1
    if np.isfinite(lower) and np.isfinite(upper) and np.isclose(-lower, upper):
        return t("limit {limits}").format(limits=f"±{upper:.{digits}f}")
    return t("limit {limits}").format(limits=" / ".join(f"{v:.{digits}f}" for v in (lower, upper) if np.isfinite(v)))


# --------------------------------------------------------------------------- adjustment

def _adjustment_header(sheet: _Sheet, content: ReportContent, title: str) -> None:
    sheet.title(title)
    sheet.append([sheet.cell(_context(content))])
    sheet.append([sheet.cell(_fastener_line(content))])
    for text in (threshold_text(content.summary), after_adjustment_text(content.summary)):
        if text:
            sheet.append([sheet.cell(text)])


#: The crew's sheet: its columns, their widths (A4 portrait at 100 %: 188 of the 190 mm between the margins)
#: and the paper it is printed on whatever the project's paper (the crews' clipboards hold A4).
CREW_TITLES = ("no.", "sleeper", "chainage", "rail", "lateral (mm)", "vertical (mm)", "fastener parts",
               "checks still failed")
CREW_WIDTHS = (5, 9, 11, 5, 9, 10, 35, 9)
CREW_PAPER = "A4"


def _note(sheet: _Sheet, text: str, widths: Sequence[float], font: Font | None = None) -> None:
    """A line of text above a table, merged over its columns and wrapped (nothing runs off the page)."""
    row = sheet.append([sheet.cell(text, font=font, alignment=WRAPPED)])
    sheet.sheet.merged_cells.add(f"A{row}:{get_column_letter(len(widths))}{row}")
    letters = BOLD_CHARACTER_WIDTH if font is not None and font.b else BODY_CHARACTER_WIDTH
    sheet.set_height(row, LINE_HEIGHT_PT * _wrapped_lines(text, sum(widths), letters) + 2.0)


def _adjustment_sheet(sheet: _Sheet, content: ReportContent, progress: StepProgress, cancel: CancelToken) -> None:
    """The crew's sheet: A4 portrait, 11 pt at 100 %, one line per rail to move, a page per work section."""
    widths = CREW_WIDTHS
    sheet.title(t("Adjustment sheet"))
    _note(sheet, t("The rails to move, in working order (increasing chainage). ") + _context(content), widths)
    _note(sheet, t("Amounts: ") + amounts_text(content.summary, content.profile, content.fastener) + t("."), widths,
          BOLD)
    for text in (_fastener_line(content), threshold_text(content.summary), after_adjustment_text(content.summary)):
        if text:
            _note(sheet, text, widths)
    _note(sheet, t("Parts: outer = on the field side of the rail foot, inner = on the gauge side; No. 9→11: replace "
                   "the No. 9 part by a No. 11; shims are added; * size assumed, not a published figure. The Materials "
                   "sheet sums the parts."), widths)
    header = sheet.header([t(title) for title in CREW_TITLES])
    # at 100 % with the body font's widths; fitted to the page width where a substitute font is wider
    sheet.start(list(widths), f"A{header + 1}", CREW_PAPER, page_header(content), orientation="portrait")
    work_sections = crew_sections(content)
    numbers, labels = content.column("number").values, content.column("label").values
    plain, bold, amount = sheet.style_id(), sheet.style_id(font=BOLD), sheet.style_id("+0;-0;")
    wrapped, red = sheet.style_id(alignment=WRAPPED), sheet.style_id(font=RED_FONT, alignment=WRAPPED)
    columns: list[list] = [[] for _ in CREW_TITLES]
    styles: list[list[int]] = [[] for _ in CREW_TITLES]
    heights: list[float | None] = []

    @cache  # the same parts and notes recur on thousands of lines
    def lines_of(text: str, width: float) -> int:
        return _wrapped_lines(text, width, BODY_CHARACTER_WIDTH)

    for section in work_sections:
        first, last = section.rows[0].sleeper, section.rows[-1].sleeper
        sleepers = len({row.sleeper for row in section.rows})
        heading = t("Work section {number} of {count}: {first} – {last}, {sleepers} sleepers, {rails} rails to "
                    "move").format(number=section.number, count=len(work_sections), first=labels[first],
                                   last=labels[last], sleepers=sleepers, rails=len(section.rows))
        row_number = sheet.rows + len(heights) + 1
        if section.number > 1:  # each work section starts on a sheet of paper of its own
            sheet.sheet.row_breaks.append(Break(id=row_number - 1))
        sheet.sheet.merged_cells.add(f"A{row_number}:{get_column_letter(len(widths))}{row_number}")
        for k, value in enumerate([heading] + [""] * (len(CREW_TITLES) - 1)):
            columns[k].append(value)
            styles[k].append(bold)
        heights.append(LINE_HEIGHT_PT + 6.0)
        for row in section.rows:
            values = [row.count, int(numbers[row.sleeper]), str(labels[row.sleeper]), (t("left"), t("right"))[row.rail], row.lateral_mm,
                      row.vertical_mm, "\n".join(row.parts), row.failing]
            for k, (value, style) in enumerate(zip(values, [plain, plain, plain, plain, amount, amount, wrapped, red])):
                columns[k].append(value)
                styles[k].append(style)
            lines = max(sum(lines_of(part, widths[6]) for part in row.parts) or 1, lines_of(row.failing, widths[7]))
            heights.append(LINE_HEIGHT_PT * lines + 2.0 if lines > 1 else None)
    if not work_sections:
        columns[0].append(t("no rail to move: every check of the tolerance profile passes as measured"))
        styles[0].append(bold)
        for k in range(1, len(CREW_TITLES)):
            columns[k].append("")
            styles[k].append(plain)
        heights.append(None)
    sheet.table([(values, style) for values, style in zip(columns, styles)], cancel=cancel, heights=heights)
    sheet.sheet.print_title_rows = f"{header}:{header}"
    progress(1.0, "adjustment sheet")


TAMPING_TITLES = ("chainage", "station (m)", "lift left (mm)", "lift right (mm)", "slew (mm)", "cant after (mm)", "mark")
TAMPING_WIDTHS = (13, 11, 9, 9, 9, 9, 40)
#: Sleepers moved less than this [mm] (and the marks among them) close a work section of the Tamping sheet.
TAMPING_SECTION_GAP_MM = 0.5
#: Runs of moved sleepers this few rows apart (about 12 m) are one work section.
TAMPING_SECTION_JOIN = 20


def _tamping_sheet(sheet: _Sheet, content: ReportContent, progress: StepProgress, cancel: CancelToken) -> None:
    """The tamping re-design (``insrail redesign``) for the machine's crew: A4 portrait, the stretches to
    tamp as work sections, each sleeper moved with its lift, slew and the cant after the job, and the marks."""
    from insrail.export.tamping import read_tamping
    from insrail.project.redesign import REDESIGN_FOLDER, SUMMARY_FILE as REDESIGN_SUMMARY, TAMPING_FILE

    table = read_tamping(content.results.folder / REDESIGN_FOLDER / TAMPING_FILE)
    widths = TAMPING_WIDTHS
    sheet.title(t("Tamping sheet"))
    _note(sheet, t("The tamping re-design, in working order (increasing chainage). ") + _context(content), widths)
    _note(sheet, t("{amounts}. Signs: {convention}.").format(amounts=t(table.metadata.get("amounts", "")),
                                                             convention=t(table.metadata.get("convention", ""))),
          widths, BOLD)
    header = sheet.header([t(title) for title in TAMPING_TITLES])
    sheet.start(list(widths), f"A{header + 1}", CREW_PAPER, page_header(content), orientation="portrait")
    values = table.values
    moved = np.max(np.abs([values["lift_left"], values["lift_right"], values["slew"]]), axis=0) >= TAMPING_SECTION_GAP_MM
    runs = np.flatnonzero(np.diff(np.concatenate([[0], moved.astype(int), [0]])))
    sections: list[list[int]] = []
    for first, last in zip(runs[::2], runs[1::2] - 1):  # runs closer than TAMPING_SECTION_JOIN rows: one section
        if sections and first - sections[-1][1] <= TAMPING_SECTION_JOIN:
            sections[-1][1] = last
        else:
            sections.append([first, last])
    amount = "0.0"
    for number, (first, last) in enumerate(sections, start=1):
        row = sheet.append([sheet.cell(t("Work section {number} of {count}: {first} – {last}, {rows} rows").format(
            number=number, count=len(sections), first=table.label[first], last=table.label[last],
            rows=last - first + 1), font=BOLD)])
        if number > 1:
            sheet.sheet.row_breaks.append(Break(id=row - 1))
        for i in range(first, last + 1):
            sheet.append([sheet.cell(table.label[i]), sheet.cell(table.station_m[i], "0.000"),
                          *(sheet.cell(values[k][i], amount) for k in ("lift_left", "lift_right", "slew", "cant")),
                          sheet.cell(tamping_mark_name(table.mark[i]))])
    marks = [i for i, m in enumerate(table.mark) if m]
    sheet.append([sheet.cell(t("Marks of the re-designed line and the fixed stretches"), font=BOLD)])
    for i in marks:
        sheet.append([sheet.cell(table.label[i]), sheet.cell(table.station_m[i], "0.000"),
                      *(sheet.cell(values[k][i], amount) for k in ("lift_left", "lift_right", "slew", "cant")),
                      sheet.cell(tamping_mark_name(table.mark[i]))])
    summary_path = content.results.folder / REDESIGN_FOLDER / REDESIGN_SUMMARY
    if summary_path.is_file():  # where the crew must not take the track for passing after the job
        summary = tomllib.loads(summary_path.read_text(encoding="utf-8"))
        sheet.append([sheet.cell(t("Where the track is not said to pass after the job"), font=BOLD)])
        for what, start, end, value in redesign_not_passing(summary, content.profile) or [(t("none"), None, None, None)]:
            sheet.append([sheet.cell("" if start is None else f"{start:.1f} – {end:.1f} m"), sheet.cell(None),
                          *(sheet.cell(None) for _ in range(4)),
                          sheet.cell(what if value is None else f"{what}: {value:.1f} mm")])
    sheet.sheet.print_title_rows = f"{header}:{header}"
    progress(1.0, "tamping sheet")


def _fastener_line(content: ReportContent) -> str:
    """The fastener type, the total movement and how many sleepers still fail (summary.toml [adjustment])."""
    if (withheld := amounts_withheld_text(content.summary)) is not None:
        return withheld
    fastener = content.fastener
    adjustment = content.summary.get("adjustment", {})
    kind = ((t(fastener.description) or t("{name}, steps of {step:g} mm").format(name=fastener.name,
                                                                                  step=1e3 * fastener.step_m))
            if fastener else t("{name} (the fastener type file is not readable: no parts)").format(
                name=fastener_name(None, adjustment.get("fastener", ""))))
    return t("Fastener {kind}; total movement {movement:.0f} mm at {sleepers} sleepers; {failing} sleepers where the "
             "checks still fail").format(kind=kind, movement=adjustment.get("total_movement_mm", 0.0),
                                        sleepers=adjustment.get("sleepers_to_work_on", 0),
                                        failing=adjustment.get("unresolved_sleepers", 0))


def _materials_sheet(sheet: _Sheet, content: ReportContent, progress: StepProgress, cancel: CancelToken) -> None:
    _adjustment_header(sheet, content, t("Materials list: the fastener parts the adjustment sheet needs"))
    work = content.adjustment
    for note in work.notes:
        sheet.append([sheet.cell(t("No parts for {note}").format(note=note))])
    sheet.append([sheet.cell(t("Parts marked * have sizes not taken from published figures: check them against the "
                               "fastener type file before ordering."), font=BOLD)])
    titles = [t("part"), t("size"), t("left rails"), t("right rails"), t("total")]
    header = sheet.header(titles)
    _start(sheet, content, [40, 10, 10, 10, 10], freeze=f"A{header + 1}")
    for part, size, left, right in work.materials:
        sheet.append([sheet.cell(part), sheet.cell(size), sheet.cell(left), sheet.cell(right),
                      sheet.cell(left + right, font=BOLD)])
    if not work.materials:
        sheet.append([sheet.cell(t("no parts: no sleeper to work on") if not work.order.size
                                 else t("no parts listed for this fastener type"))])
    progress(1.0, "materials list")
    sheet.finish_table(header, header, len(titles))


# --------------------------------------------------------------------------- exceedances

def _exceedance_sheet(sheet: _Sheet, content: ReportContent, progress: StepProgress, cancel: CancelToken) -> None:
    sheet.title(t("Exceedances, the most severe first, each severity in chainage order"))
    sheet.append([sheet.cell(_context(content))])
    rule = t(SEVERITY_RULE)
    sheet.append([sheet.cell(rule[0].upper() + rule[1:])])
    titles = [t(title) for title in ("no.", "severity", "check", "what", "from", "to", "from (m)", "to (m)",
                                     "length (m)", "peak", "limit", "unit", "beyond the limit by (%)", "first sleeper",
                                     "last sleeper")]
    header = sheet.header(titles)
    _start(sheet, content, [6, 9, 40, 34, 13, 13, 11, 11, 9, 8, 8, 6, 10, 9, 9], freeze=f"D{header + 1}")
    checks = {c.name: c for c in content.profile.checks}
    label_of = dict(zip(content.results.number.tolist(), content.results.label))
    index = 0
    for severity, rows in exceedances_by_severity(content):
        for e in rows:
            index += 1
            peak, limit, unit = exceedance_display(e)
            fmt = "0.000" if unit == "‰" else "0.00"  # enough to see the peak beyond the limit
            sheet.append([sheet.cell(index), sheet.cell(t(severity), font=RED_FONT if severity == "severe" else None),
                          sheet.cell(exceedance_check(content, e)), sheet.cell(check_description(checks[e.check])),
                          sheet.cell(label_of.get(e.first_sleeper, "")), sheet.cell(label_of.get(e.last_sleeper, "")),
                          sheet.cell(e.station_from_m, "0.000"), sheet.cell(e.station_to_m, "0.000"),
                          sheet.cell(e.station_to_m - e.station_from_m, "0.000"), sheet.cell(peak, fmt),
                          sheet.cell(limit, fmt), sheet.cell(unit), sheet.cell(100 * excess_share(e), "0"),
                          sheet.cell(e.first_sleeper), sheet.cell(e.last_sleeper)])
    progress(1.0, "exceedance sheet")
    sheet.finish_table(header, header, len(titles))
    _events_table(sheet, content)


def _events_table(sheet: _Sheet, content: ReportContent) -> None:
    """The survey's events below the exceedances: the stretches not assessed (greyed in the sleeper
    sheet, never counted as exceedances) and the ones only marked."""
    if not content.events:
        return
    not_assessed = content.summary.get("assessment", {}).get("not_assessed_sleepers", 0)
    sheet.append([])
    sheet.append([sheet.cell(t("Events: {count} measured sleepers not assessed with the tolerance profile").format(
        count=not_assessed), font=BOLD)])
    sheet.header([t(title) for title in ("no.", "event", "text", "from (m)", "to (m)", "sleepers", "assessment",
                                         "written in")])
    for index, e in enumerate(content.events, start=1):
        sheet.append([sheet.cell(index), sheet.cell(e.kind), sheet.cell(e.text), sheet.cell(e.station_from_m, "0.000"),
                      sheet.cell(e.station_to_m, "0.000"), sheet.cell(e.sleepers), sheet.cell(e.assessment),
                      sheet.cell(e.source)])


# --------------------------------------------------------------------------- summary

def _summary_sheet(sheet: _Sheet, content: ReportContent, progress: StepProgress, cancel: CancelToken) -> None:
    sheet.title(t("Summary"))
    sheet.append([sheet.cell(_context(content))])
    sheet.append([sheet.cell(t("Statistics per parameter (valid sleepers)"), font=BOLD)])
    titles = [t(title) for title in ("parameter", "unit", "limit", "valid sleepers", "minimum", "maximum", "mean",
                                     "standard deviation", "sleepers beyond", "exceedances")]
    sheet.header(titles)
    quality = content.summary.get("track_quality", {})
    channels = list(quality.get("channels", []))
    checks = [(check, [c for c in content.columns if c.check == check.name]) for check in content.profile.checks]
    checks = [(check, columns) for check, columns in checks if columns]
    # The survey's predicted accuracy per section (quality.csv, same sections): where the measurement is weak.
    predicted = content.results.quality
    figures = PREDICTED_FIGURES if predicted is not None else ()
    section_titles = ([t(title) for title in ("from (m)", "to (m)", "from", "to", "sleepers", "valid",
                                              "exceedances starting")]
                      + [t("max |{name}| ({unit})").format(name=check_name(check), unit=columns[0].unit)
                         for check, columns in checks]
                      + [t("SD {name} (mm)").format(name=quantity_name(name).name) for name in channels]
                      + ([t("TQI (mm)")] if channels else [])
                      + [f"{quantity_name(name).name} (mm)" for name in figures])
    sheet.header_below(section_titles)
    widths = [44, 9, 12, 10, 10, 10, 10, 11, 10, 11]
    _start(sheet, content, widths + [10] * max(len(section_titles) - len(widths), 0))
    for s in parameter_statistics(content):
        fmt = s.column.number_format
        sheet.append([sheet.cell(s.column.name), sheet.cell(s.column.unit),
                      sheet.cell(limits_text_for(s.column)), sheet.cell(s.valid_count), sheet.cell(s.minimum, fmt),
                      sheet.cell(s.maximum, fmt), sheet.cell(s.mean, fmt), sheet.cell(s.standard_deviation, "0.00"),
                      sheet.cell(s.exceeding_sleepers if s.column.limits else None),
                      sheet.cell(s.exceedances if s.column.limits else None)])
    progress(0.5, "summary: parameters")
    sheet.append([])
    tqi_start = np.asarray(quality.get("start_m", []), dtype=float)
    section_m = float(quality.get("section_m", SECTION_M))
    sheet.append([sheet.cell(t("Per {section:g} m section: the largest magnitude of every check of the profile (over "
                               "its rails and directions), the standard deviations of the TQI channels ({band} band for "
                               "level and alignment) and their sum, the TQI").format(
        section=section_m, band=quality.get("band", "D1")), font=BOLD)])
    sheet.header(section_titles)
    starts = np.array([e.station_from_m for e in content.results.exceedances])
    labels = content.column("label").values
    for start, end, rows in sections(content, section_m):
        match = np.flatnonzero(np.isclose(tqi_start, start, atol=1e-3)) if tqi_start.size else []
        tqi = ([quality[f"sd_{name}_mm"][match[0]] for name in channels] + [quality["tqi_mm"][match[0]]]
               if len(match) else [None] * (len(channels) + bool(channels)))
        same = np.flatnonzero(np.isclose(predicted.station_from_m, start, atol=1e-3)) if figures else []
        sigma = [float(getattr(predicted, name)[same[0]]) if len(same) else np.nan for name in figures]
        sheet.append([sheet.cell(start, "0.000"), sheet.cell(end, "0.000"), sheet.cell(labels[rows[0]]),
                      sheet.cell(labels[rows[-1]]), sheet.cell(len(rows)), sheet.cell(int(content.valid[rows].sum())),
                      sheet.cell(int(np.count_nonzero((starts >= start) & (starts < end))) if starts.size else 0)]
                     + [sheet.cell(_largest_magnitude(columns, rows), columns[0].number_format) for _, columns in checks]
                     + [sheet.cell(v if v is None or v >= 0 else None, "0.00") for v in tqi]
                     + [sheet.cell(v if np.isfinite(v) else None, "0.00") for v in sigma])
    progress(1.0, "summary sheet")


#: quality.csv columns shown per section in the summary sheet.
PREDICTED_FIGURES = ("sigma_lag5_lateral_mm", "sigma_lag5_vertical_mm", "sigma_lag150_lateral_mm",
                     "sigma_lag150_vertical_mm")


def _largest_magnitude(columns: list[Column], rows: np.ndarray) -> float:
    """max |value| over the columns at ``rows``; NaN where none is finite."""
    values = np.abs(np.concatenate([c.values[rows] for c in columns]))
    values = values[np.isfinite(values)]
    return float(values.max()) if values.size else math.nan


# --------------------------------------------------------------------------- processing log

def _flatten(prefix: str, value, rows: list[tuple[str, object]]) -> None:
    if isinstance(value, dict) and isinstance(value.get("template"), str) and set(value) <= {"template", "fields"}:
        rows.append((prefix, phrase_of(value).said()))  # a text of insrail's own, kept as a phrase (insrail.notices)
    elif isinstance(value, dict):
        for key, item in value.items():
            if key != "warnings":  # a stage's warnings are notices, listed in the report's language below
                _flatten(f"{prefix}.{key}" if prefix else str(key), item, rows)
    elif isinstance(value, list):
        if value and all(isinstance(item, dict) for item in value):
            for index, item in enumerate(value):
                _flatten(f"{prefix}[{index}]", item, rows)
        elif len(value) > 12:
            rows.append((prefix, t("{count} values (see the Summary sheet)").format(count=len(value))))
        else:
            rows.append((prefix, "; ".join("–".join(map(str, v)) if isinstance(v, list) else str(v) for v in value)))
    elif isinstance(value, str):  # a sentence of insrail's own in the language; a name or an id (no space) as it is
        rows.append((prefix, t(value) if " " in value else value))
    else:
        rows.append((prefix, value if isinstance(value, (int, float, bool)) else str(value)))


def _log_sheet(sheet: _Sheet, content: ReportContent, progress: StepProgress, cancel: CancelToken) -> None:
    sheet.title(t("Processing log"))
    _start(sheet, content, [42, 90])
    now = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    for label, value in (("Software", content.software), ("Report written", now),
                         ("Project file", str(content.project.path)), ("Results", str(content.results.folder)),
                         *(("Note", note) for note in content.notes)):
        sheet.pairs((t(label), value), anchors=(0, 1))
    sheet.append([])
    for title, document in ((t("summary.toml (QC figures of the processing)"), content.summary),
                            (t("project.toml (settings)"), content.project.to_settings())):
        sheet.append([sheet.cell(title, font=BOLD)])
        sheet.header([t("key"), t("value")])
        rows: list[tuple[str, object]] = []
        _flatten("", {key: value for key, value in document.items() if key != "notices"}, rows)
        rows += [(f"notices[{index}]", notice.said()) for index, notice in enumerate(notices_of(document))]
        for key, value in rows:
            sheet.append([sheet.cell(key), sheet.cell(value, "0.000" if isinstance(value, float) else None)])
        sheet.append([])
    progress(1.0, "processing log")


def _discard(workbook: Workbook) -> None:
    """End the row streams of an abandoned write-only workbook and delete their temporary files
    (openpyxl keeps them until the workbook is saved)."""
    for sheet in workbook.worksheets:
        if not sheet.closed:
            sheet.close()
        if sheet._writer is not None and Path(sheet._writer.out).exists():
            sheet._writer.cleanup()


#: The sheets in workbook order (the Summary first: what a reader opens the file for), each with its
#: share of the writing time.
SHEETS: tuple[tuple[str, Callable, float], ...] = (
    ("Summary", _summary_sheet, 0.04),
    ("Sleepers", _sleeper_sheet, 0.6),
    ("Adjustment", _adjustment_sheet, 0.04),
    ("Materials", _materials_sheet, 0.01),
    ("Exceedances", _exceedance_sheet, 0.04),
    ("Processing log", _log_sheet, 0.01),
)
#: The sheet of a re-designed survey (``insrail redesign``), before the Processing log.
TAMPING_SHEET = ("Tamping", _tamping_sheet, 0.02)


def write_workbook(project: Project, results: StoredResults, path, progress: ProgressFn | None = None,
                   cancel: CancelToken = None, content: ReportContent | None = None) -> Path:
    """Write the crews' workbook for one survey's results to ``path`` (atomically); returns the path.
    ``content``: the results' :func:`insrail.report.content.report_content`, where the caller made it already."""
    with in_language(report_language(project)):
        return _write_workbook(project, results, Path(path), StepProgress(progress), cancel, content)


def _write_workbook(project: Project, results: StoredResults, path: Path, step: StepProgress,
                    cancel: CancelToken, content: ReportContent | None) -> Path:
    content = content or load_report_content(project, results)
    workbook = Workbook(write_only=True)
    workbook.properties.title = t("{project} – {survey}: track geometry").format(project=project.name,
                                                                                 survey=results.survey)
    workbook.properties.creator = content.software
    position = 0.0
    sheets = []
    chosen = list(SHEETS)
    if (results.folder / "redesign" / "tamping.csv").is_file():  # a re-designed survey: its sheet before the log
        chosen.insert(len(chosen) - 1, TAMPING_SHEET)
    try:
        for name, build, share in chosen:
            check_cancel(cancel)
            sheets.append(_Sheet(workbook.create_sheet(t(name))))
            build(sheets[-1], content, step.sub(position, position + share), cancel)
            position += share
        check_cancel(cancel)
        step(position, "saving the workbook")
        assembled = io.BytesIO()
        workbook.save(assembled)
        with atomic_write(path, "wb") as handle:
            _splice_tables(assembled.getvalue(), sheets, handle)
    except BaseException:
        _discard(workbook)
        raise
    finally:
        for sheet in sheets:
            sheet.close()
    step(1.0, Phrase("workbook written: {file}", {"file": path.name}))
    return path
