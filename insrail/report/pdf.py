"""The PDF survey report (reportlab platypus, landscape on the project's paper, ``[report] paper``
A3 or A4 as the workbook, vector charts).

Order: cover; survey and processing summary (data spans, GNSS availability and outages, fusion
quality, heights, assessment, TQI per section, predicted accuracy per section); charts along chainage, one range of
``CHART_RANGE_M`` per page group with the range in the page header; the plan view; any extra
sections (``sections``: e.g. repeatability when several runs exist); the exceedance table; the adjustment
amounts per sleeper and rail (the workbook's, :mod:`insrail.report.labels`). Every
page carries the project and survey, its section or chainage range and "page i of n".
"""

from __future__ import annotations

import contextlib
import datetime
import itertools
import math
from collections.abc import Callable, Sequence
from dataclasses import replace
from functools import cache, partial
from html import escape  # as xml.sax.saxutils's (& < >) with quote=False, without its import of urllib and http
from pathlib import Path

import numpy as np
from reportlab.lib import colors
from reportlab.lib.pagesizes import A3, A4, landscape
from reportlab.lib.styles import ParagraphStyle, getSampleStyleSheet
from reportlab.lib.units import mm
from reportlab.lib.rl_accel import fp_str, unicode2T1
from reportlab.pdfbase.pdfmetrics import getFont, stringWidth
from reportlab.pdfgen.canvas import Canvas
from reportlab.platypus import (
    BaseDocTemplate,
    CondPageBreak,
    Flowable,
    Frame,
    KeepInFrame,
    LongTable,
    PageBreak,
    PageTemplate,
    Paragraph,
    Spacer,
    Table,
    TableStyle,
)

from insrail.io.atomic import atomic_write
from insrail.io.errors import InputError
from insrail.names import (
    UnknownName,
    check_name,
    column_name,
    fastener_name,
    in_language,
    joined,
    language,
    profile_name,
    quantity_name,
    rail_direction,
    t,
)
from insrail.nav.imu_profile import load_imu_profile
from insrail.notices import Phrase, notices_of
from insrail.progress import CancelToken, ProgressFn, StepProgress, check_cancel
from insrail.project.compare import (
    BASE_PARAMETERS,
    StoredRepeatability,
    load_repeatability,
)
from insrail.project.model import Project
from insrail.project.results import SUMMARY_FILE, TRAJECTORY_FILE, StoredResults, check_column, trajectory_section
from insrail.project.run_settings import NOT_RECORDED, report_language
from insrail.report.charts import (
    EVENT_COLOUR,
    LIMIT_COLOUR,
    OUTAGE_COLOUR,
    WEAK_COLOUR,
    Band,
    PlanMark,
    Series,
    StripChart,
    plan_drawing,
    section_steps,
    strip_drawing,
)
from insrail.report.content import (
    ADJUSTMENT_KEYS,
    OTHER_CHECKS_GROUP,
    RAIL_KINDS,
    RELATIVE_SURVEY_TEXT,
    SEVERITIES,
    SEVERITY_RULE,
    ReportContent,
    after_adjustment_text,
    check_description,
    crew_sections,
    exceedance_check,
    exceedance_display,
    exceedances_by_severity,
    excess_share,
    limits_text,
    load_report_content,
    mounting_text,
    odometer_pair_text,
    sleeper_repair_text,
    is_relative,
    survey_start,
    survey_title,
    threshold_text,
)
from insrail.report.fonts import font_for, font_runs, helvetica_can_show
from insrail.report.labels import amounts_text, amounts_withheld_text, deviation_reference
from insrail.track.exceedance import RAILS

#: [report] paper -> the page (landscape), width and height in points
PAGES = {"A3": landscape(A3), "A4": landscape(A4)}
MARGIN = 14 * mm
CHART_RANGE_M = 500.0  # the longest chainage span of a chart page
CHART_ROUND_M = 50.0  # chart spans start on and last a multiple of this
CHART_MIN_HEIGHT = 24 * mm  # a chart is never drawn lower (pages hold as many as fit)
PARAGRAPH_FONT = "Helvetica"  # the paragraphs' own font (a run in it keeps the paragraph's weight)
def page_size(content: ReportContent) -> tuple[float, float]:
    """The report's page (width, height) in points: the project's paper, landscape."""
    return PAGES[content.project.report.paper]


def chart_area_height(page: tuple[float, float]) -> float:
    """The height the charts of a page share."""
    return page[1] - 2 * MARGIN - 4


#: A section added to the report: content -> flowables (e.g. repeatability of several runs), starting
#: with a :class:`Heading` to name its pages in the page header; it ends with a page break.
Section = Callable[[ReportContent], list[Flowable]]

_styles = getSampleStyleSheet()
BODY = ParagraphStyle("body", parent=_styles["BodyText"], fontSize=9, leading=11.5)
SMALL = ParagraphStyle("small", parent=BODY, fontSize=7.5, leading=9)
H1 = ParagraphStyle("h1", parent=_styles["Heading1"], fontSize=16, spaceAfter=6)
H1_COVER = ParagraphStyle("h1_cover", parent=H1, fontSize=14, spaceBefore=2, spaceAfter=0)
H2 = ParagraphStyle("h2", parent=_styles["Heading2"], fontSize=12, spaceBefore=6, spaceAfter=3)
H3 = ParagraphStyle("h3", parent=_styles["Heading3"], fontSize=9.5, spaceBefore=5, spaceAfter=2)
TITLE = ParagraphStyle("title", parent=_styles["Title"], fontSize=18, leading=21, alignment=0, spaceAfter=0)
TABLE_STYLE = TableStyle([
    ("FONT", (0, 0), (-1, -1), "Helvetica", 8),
    ("FONT", (0, 0), (-1, 0), "Helvetica-Bold", 8),
    ("BACKGROUND", (0, 0), (-1, 0), colors.HexColor("#ddebf7")),
    ("LINEBELOW", (0, 0), (-1, 0), 0.6, colors.black),
    ("ROWBACKGROUNDS", (0, 1), (-1, -1), [colors.white, colors.HexColor("#f4f4f4")]),
    ("VALIGN", (0, 0), (-1, -1), "TOP"),
    ("TOPPADDING", (0, 0), (-1, -1), 1.5),
    ("BOTTOMPADDING", (0, 0), (-1, -1), 1.5),
])
KEY_VALUE_STYLE = TableStyle([
    ("FONT", (0, 0), (-1, -1), "Helvetica", 8.5),
    ("FONT", (0, 0), (0, -1), "Helvetica-Bold", 8.5),
    ("VALIGN", (0, 0), (-1, -1), "TOP"),
    ("TOPPADDING", (0, 0), (-1, -1), 1.2),
    ("BOTTOMPADDING", (0, 0), (-1, -1), 1.2),
])


def text(value) -> str:
    """Paragraph markup for any text: escaped, the runs Helvetica cannot show (Chinese, σ) in a CJK font
    and the rest in the paragraph's own font."""
    return "".join(escape(run, quote=False) if font == PARAGRAPH_FONT
                   else f'<font name="{font}">{escape(run, quote=False)}</font>'
                   for run, font in font_runs(str(value), PARAGRAPH_FONT))


def _cell(value, style: ParagraphStyle = SMALL) -> Paragraph:
    return Paragraph(text(value), style)


def key_values(rows: list[tuple[str, object]], widths=(55 * mm, 150 * mm)) -> Table:
    return Table([[_cell(k, BODY), _cell(v, BODY)] for k, v in rows], colWidths=list(widths), style=KEY_VALUE_STYLE,
                 hAlign="LEFT")


#: :func:`table`'s style where its plain-text cells are strings in the SMALL paragraphs' font, size and leading.
SMALL_TEXT_TABLE_STYLE = TableStyle([*TABLE_STYLE.getCommands(),
                                     ("FONT", (0, 0), (-1, -1), SMALL.fontName, SMALL.fontSize, SMALL.leading)])
CELL_PADDING = 6.0  # reportlab's left and right padding of a table cell


def _small_cell(value, width: float) -> str | Paragraph:
    """A cell of :func:`table` in a column ``width`` wide: a SMALL paragraph, or the text itself where the
    paragraph would be one line of it as it is (Helvetica shows it, no whitespace to collapse, narrower than
    the column). A string is drawn at the paragraph's baseline (a font size below the cell's top) and is as
    high (one leading), but costs a fraction of its layout: a 10 km report's exceedance tables hold some
    8 000 cells."""
    value = str(value)
    if (value and value == " ".join(value.split()) and helvetica_can_show(value)
            and stringWidth(value, SMALL.fontName, SMALL.fontSize) < width - 2 * CELL_PADDING - 0.5):
        return value
    return _cell(value)


def table(header: list[str], rows: list[list], widths: list[float] | None = None) -> Table:
    """A table with a header row repeated on each page; its cells SMALL paragraphs (:func:`_small_cell`
    where the column widths are given). A LongTable: laid out a page at a time, not measured whole for each
    page it runs over."""
    if widths is None:
        data = [[_cell(h) for h in header]] + [[_cell(v) for v in row] for row in rows]
        return LongTable(data, repeatRows=1, style=TABLE_STYLE, hAlign="LEFT")
    data = [[_small_cell(v, width) for v, width in zip(row, widths, strict=True)] for row in [header, *rows]]
    return LongTable(data, colWidths=widths, repeatRows=1, style=SMALL_TEXT_TABLE_STYLE, hAlign="LEFT")


class Heading(Flowable):
    """Sets the page header's right-hand text (section or chainage range) from where it is drawn on."""

    def __init__(self, heading: str):
        super().__init__()
        self.heading = heading

    def wrap(self, available_width, available_height):
        return 0, 0

    def draw(self):
        self.canv._insrail_heading = self.heading


class Scaled(Flowable):
    """``child`` laid out on a page ``scale`` times smaller and drawn enlarged (the first page on A3
    is the A4 one, scaled by √2: a client signs the same page on either paper)."""

    def __init__(self, child: Flowable, scale: float):
        super().__init__()
        self.child, self.scale = child, scale

    def wrap(self, available_width, available_height):
        width, height = self.child.wrapOn(self.canv, available_width / self.scale, available_height / self.scale)
        self.width, self.height = width * self.scale, height * self.scale
        return self.width, self.height

    def draw(self):
        self.canv.saveState()
        self.canv.scale(self.scale, self.scale)
        self.child.drawOn(self.canv, 0, 0)
        self.canv.restoreState()


_STRING_OPTIONS = {"mode", "charSpace", "direction", "wordSpace", "shaping"}  # of Canvas.drawString


class NumberedCanvas(Canvas):
    """Writes "page i of n" once the number of pages is known: each page ends by drawing its own form
    (a PDF XObject, drawn in the page's graphics state), and the forms are written at the end. A
    page goes out as soon as it is complete; no page is held to the end of the document.

    A plain string (the tables' cells, the charts' labels: some 70 000 at 10 km) is written without
    reportlab's text object: :meth:`_plain_text` writes the operators its drawString would."""

    def drawString(self, x, y, text, *args, **kwargs):  # noqa: N802 - reportlab's names
        self._draw_plain(x, y, text, 0.0, args, kwargs) or super().drawString(x, y, text, *args, **kwargs)

    def drawRightString(self, x, y, text, *args, **kwargs):  # noqa: N802
        self._draw_plain(x, y, text, 1.0, args, kwargs) or super().drawRightString(x, y, text, *args, **kwargs)

    def drawCentredString(self, x, y, text, *args, **kwargs):  # noqa: N802
        self._draw_plain(x, y, text, 0.5, args, kwargs) or super().drawCentredString(x, y, text, *args, **kwargs)

    def _draw_plain(self, x: float, y: float, text, anchor: float, args: tuple, kwargs: dict) -> bool:
        """Write ``text`` at x (its start, end or centre: ``anchor`` 0, 1, 0.5 of its width) when it is plain
        (no text mode, spacing, direction or shaping asked for); False where reportlab must write it."""
        plain = not args and (not kwargs or (  # most calls pass no option
            set(kwargs) <= _STRING_OPTIONS and kwargs.get("mode") is None and kwargs.get("direction") is None
            and not any(kwargs.get(k) for k in ("charSpace", "wordSpace", "shaping"))))
        if not plain:
            return False
        code = self._plain_text(x, y, text, anchor)
        if code is None:
            return False
        self._code.append(code)
        return True

    def _plain_text(self, x: float, y: float, text, anchor: float) -> str | None:
        """The operators ``Canvas.drawString`` (and its right-aligned and centred kin) writes for ``text`` in a
        standard font whose encoding holds all of it: a text object positioned, one string shown; None for
        anything else (an embedded font, characters of another font, an empty string, a top-down page)."""
        if not isinstance(text, str) or not self.bottomup:
            return None
        font = getFont(self._fontname)
        if font._dynamicFont or font._multiByte:
            return None
        runs = unicode2T1(text, [font] + font.substitutionFonts)
        if len(runs) != 1 or runs[0][0] is not font:
            return None
        if anchor:
            width = stringWidth(text, self._fontname, self._fontsize)
            x = x - width if anchor == 1.0 else x - 0.5 * width
        return f"BT 1 0 0 1 {fp_str(x, y)} Tm ({self._escape(runs[0][1])}) Tj T* ET"

    def showPage(self):
        self.doForm(self._page_number_form(self._pageNumber))
        super().showPage()

    @staticmethod
    def _page_number_form(number: int) -> str:
        return f"pageNumber{number}"

    def save(self):
        pages = self._pageNumber - 1
        for number in range(1, pages + 1):
            self.beginForm(self._page_number_form(number))
            words = t("page {number} of {pages}").format(number=number, pages=pages)
            self.setFont(font_for(words), 8)
            self.drawRightString(self._pagesize[0] - MARGIN, MARGIN - 16, words)
            self.endForm()
        super().save()


class Deferred(Flowable):
    """A flowable made by ``make`` only when it is laid out and let go once drawn: the chart pages of a
    long survey are never all in memory at once."""

    def __init__(self, make: Callable[[], Flowable]):
        super().__init__()
        self._make = make
        self._made: Flowable | None = None

    def _flowable(self) -> Flowable:
        if self._made is None:
            self._made = self._make()
        return self._made

    def wrap(self, available_width, available_height):
        return self._flowable().wrap(available_width, available_height)

    def drawOn(self, canvas, x, y, _sW=0):
        self._flowable().drawOn(canvas, x, y, _sW)
        self._made = None


def _fmt(value, digits: int = 1, unit: str = "") -> str:
    if value is None or (isinstance(value, float) and not np.isfinite(value)):
        return "-"
    return f"{value:.{digits}f}" + (f" {unit}" if unit else "")


# --------------------------------------------------------------------------- pages

def _not_stated(value) -> str:
    return str(value) if value else t("not stated")


def _instrument(name: str, calibrated) -> str:
    return (t("{name}; calibrated {date}").format(name=name, date=calibrated.isoformat()) if calibrated
            else t("{name}; calibration date not stated").format(name=name))


def _imu(content: ReportContent) -> str:
    """The IMU as the project names it, else the error model the fusion used (from the project or survey.toml)."""
    project = content.project
    if project.report.imu:
        return project.report.imu
    recorded = content.recorded.record.get("imu_profile")
    if recorded is not None:  # the profile the fusion used
        return t("not stated; error model {name}: {description}").format(
            name=recorded["name"], description=t(recorded.get("description", ""))).rstrip(": ")
    name = project.imu_profile
    if name is None:
        try:
            name = project.manifest(content.survey).imu_profile
        except (InputError, OSError, KeyError):
            return t("not stated (survey folder not readable)")
    try:
        profile = load_imu_profile(project.resource(name))
        return t("not stated; error model {name}: {description}").format(name=profile.name,
                                                                         description=t(profile.description))
    except (ValueError, OSError):
        return t("not stated; error model {name}: {description}").format(name=name, description="").rstrip(": ")


def crs_text(crs) -> str:
    """The engineering coordinate system with every parameter a client needs to check it."""
    projection = t("Transverse Mercator on {ellipsoid} (a = {a:.3f} m, 1/f = {f:.9g}); central meridian {lon:g}°, "
                   "latitude of origin {lat:g}°, scale factor {k:.9g}, false easting {east:.3f} m, false northing "
                   "{north:.3f} m").format(ellipsoid=crs.ellipsoid, a=crs.semi_major_axis_m,
                                           f=crs.inverse_flattening_value, lon=crs.central_meridian_deg,
                                           lat=crs.latitude_of_origin_deg, k=crs.scale_factor,
                                           east=crs.false_easting_m, north=crs.false_northing_m)
    if crs.projection_height_m:
        convention = (t("in the scale factor, mean radius {radius:.0f} m").format(radius=crs.mean_radius_m)
                      if crs.projection_height_convention == "scale_factor" else t("on the semi-major axis"))
        projection += t("; projection height {height:.3f} m ({convention})").format(
            height=crs.projection_height_m, convention=convention)
    return (f"EPSG:{crs.epsg} {crs.pyproj_crs.name}: " if crs.epsg is not None else "") + projection


def height_text(content: ReportContent) -> str:
    """The height datum: normal heights from the fitted height anomaly, or ellipsoidal heights."""
    project, heights = content.project, content.summary.get("heights", {})
    ellipsoid = content.crs.ellipsoid
    recorded = content.recorded.record.get("heights")  # the height model the results were processed with
    benchmarks = (recorded.get("benchmarks") or None) if recorded is not None else project.height.benchmarks
    if benchmarks is None:
        return t("ellipsoidal heights on {ellipsoid} (no benchmarks in the project: H = h)").format(ellipsoid=ellipsoid)
    model = recorded.get("model") if recorded is not None else project.height.anomaly.model
    grid = recorded.get("geoid_grid") if recorded is not None else project.height.anomaly.geoid_grid
    text = t("normal heights H = h - height anomaly, fitted ({model}) on the benchmarks of {benchmarks}").format(
        model=t(heights.get("model", model)), benchmarks=benchmarks)
    if grid:
        text += t(" over the geoid grid {grid} (remove-restore)").format(grid=grid)
    if "internal_rms_mm" in heights:
        text += t("; benchmark RMS {rms:.1f} mm").format(rms=heights["internal_rms_mm"])
        if heights.get("loo_rms_mm", -1) >= 0:
            text += t(", leave-one-out {rms:.1f} mm").format(rms=heights["loo_rms_mm"])
    return text


def _direction_of_travel(content: ReportContent) -> str:
    time = content.results.columns.get("time_s")
    station = content.station_m
    if time is None or station.size < 2 or not np.isfinite(time).any():
        return t("not recorded")
    first, last = int(np.nanargmin(time)), int(np.nanargmax(time))
    labels = content.results.label
    towards = (t("towards increasing chainage ({first} to {last})") if station[last] >= station[first]
               else t("towards decreasing chainage ({first} to {last})"))
    return towards.format(first=labels[first], last=labels[last])


def _survey_rows(content: ReportContent) -> list[tuple[str, object]]:
    project, report, track = content.project, content.project.report, content.summary.get("track", {})
    profile = content.profile
    valid = track.get("valid_sleepers", int(content.valid.sum()))
    length = float(content.station_m[-1] - content.station_m[0]) if content.station_m.size else 0.0
    return [
        (t("Client"), _not_stated(report.client)),
        (t("Line section"), _not_stated(report.line_section or project.description)),
        (t("Track"), _not_stated(report.track_name)),
        (t("Survey"), f"{survey_title(content)}, {survey_start(content) or t('date not recorded')}"),
        *(((t("Survey kind"), t(RELATIVE_SURVEY_TEXT)),) if is_relative(content.summary) else ()),
        (t("Direction of travel"), _direction_of_travel(content)),
        (t("Chainage"), t("{chainage} ({length:.0f} m, {sleepers} sleepers, {valid} valid)").format(
            chainage=content.chainage_range, length=length, sleepers=track.get("sleepers", len(content.results)),
            valid=valid)),
        (t("Trolley"), _instrument(_not_stated(report.trolley), report.trolley_calibrated)),
        (t("IMU"), _instrument(_imu(content), report.imu_calibrated)),
        (t("Coordinate system"), crs_text(content.crs)),
        (t("Height datum"), height_text(content)),
        (t("Design"), t("{design}; deviations {reference}").format(design=content.design,
                                                                   reference=deviation_reference(content.summary))
         if content.design else t("none: fitted line types, deviations {reference}").format(
            reference=deviation_reference(content.summary))),
        (t("Tolerance profile"), f"{profile_name(profile)}; {t(profile.source)}"),
        (t("Operator"), _not_stated(report.operator)),
    ]


#: Channels listed by name in the first page's exceedance table (the rest are counted in one line).
CONCLUSION_CHANNELS = 6


def _exceedance_conclusion(content: ReportContent) -> list[Flowable]:
    groups = exceedances_by_severity(content)
    total = sum(len(rows) for _, rows in groups)
    valid = int(content.valid.sum())
    if not total:
        return [Paragraph(text(t("No sleeper is beyond a limit of tolerance profile {profile} ({valid} valid sleepers "
                                 "assessed).").format(profile=profile_name(content.profile), valid=valid)), BODY)]
    severities = [name for name, _ in SEVERITIES]
    counts: dict[str, dict[str, int]] = {}
    for name, rows in groups:
        for e in rows:
            counts.setdefault(exceedance_check(content, e), dict.fromkeys(severities, 0))[name] += 1
    ordered = sorted(counts.items(), key=lambda item: tuple(-item[1][name] for name in severities))
    rows = [[channel, *(counts_[name] or "" for name in severities), sum(counts_.values())]
            for channel, counts_ in ordered[:CONCLUSION_CHANNELS]]
    if len(ordered) > CONCLUSION_CHANNELS:
        rest = ordered[CONCLUSION_CHANNELS:]
        rows.append([t("{count} more channels").format(count=len(rest)),
                     *(sum(c[name] for _, c in rest) or "" for name in severities),
                     sum(sum(c.values()) for _, c in rest)])
    rows.append([t("all channels"), *(sum(len(r) for n, r in groups if n == name) for name in severities), total])
    summary = joined(f"{len(r)} {t(name)}" for name, r in groups)
    return [Paragraph(text((t("{total} exceedance (runs of sleepers beyond a limit) in {valid} valid sleepers: "
                              "{summary}.") if total == 1 else
                            t("{total} exceedances (runs of sleepers beyond a limit) in {valid} valid sleepers: "
                              "{summary}.")).format(total=total, valid=valid, summary=summary)), BODY),
            table([t("channel"), *(t(name) for name in severities), t("all")], rows,
                  [62 * mm, 15 * mm, 15 * mm, 15 * mm, 13 * mm]),
            Paragraph(text(_sentence(t(SEVERITY_RULE))), SMALL)]


def _sentence(words: str) -> str:
    """A clause written as a sentence: capitalised, with its full stop (。 in Chinese)."""
    return words[:1].upper() + words[1:] + t(".")


def accuracy_rows(content: ReportContent) -> list[list[str]]:
    """The predicted accuracy against the checks it bears on: the 30 m / 5 m and 300 m / 150 m differential
    versines take the 1-sigma of the 5 m and 150 m lag differences (quality.csv); a check passes when 3 sigma of
    its weakest section is within the limit (as ``insrail predict`` judges a plan)."""
    quality = content.results.quality
    if quality is None or not len(quality):
        return []
    lag_of_pair = {5.0: "lag5", 150.0: "lag150"}
    rows = []
    for check in content.profile.checks:
        lag = lag_of_pair.get(check.pair_m) if check.kind == "differential_versine" else None
        if lag is None:
            continue
        limit = 1e3 * min(abs(check.lower), abs(check.upper))
        for direction in check.directions:
            sigma = getattr(quality, f"sigma_{lag}_{direction}_mm")
            if not np.isfinite(sigma).any():
                continue
            weakest = float(np.nanmax(sigma))
            verdict = t("within the limit") if 3 * weakest <= limit else t("NOT within the limit")
            rows.append([joined((check_name(check), t(direction))), f"±{limit:.1f}", f"{np.nanmedian(sigma):.2f}",
                         f"{3 * weakest:.2f}", verdict])
    return rows


def _accuracy_conclusion(content: ReportContent) -> list[Flowable]:
    rows = accuracy_rows(content)
    if not rows:
        return [Paragraph(text(t("Predicted accuracy: not available for these results (processed by an older "
                                 "insrail, or no differential-versine check in the profile).")), BODY)]
    passes = (t("forward filter and RTS smoother") if content.results.quality.smoothed
              else t("forward filter only"))
    return [table([t("check"), t("limit (mm)"), t("1σ median (mm)"), t("3σ weakest (mm)"), t("predicted")], rows,
                  [50 * mm, 17 * mm, 21 * mm, 22 * mm, 26 * mm]),
            Paragraph(text(t("From the fusion's error model along this survey ({passes}), per 200 m section; a check "
                             "is met when 3σ of its weakest section is within the limit.").format(passes=passes)), SMALL)]


def _adjustment_conclusion(content: ReportContent) -> str:
    if (withheld := amounts_withheld_text(content.summary)) is not None:
        return "<b>" + text(withheld + t(".")) + "</b>"
    adjustment = content.summary.get("adjustment", {})
    amounts = [content.column(key).values for key in ADJUSTMENT_KEYS]
    moving = int(np.count_nonzero(np.any([np.nan_to_num(a) != 0 for a in amounts], axis=0)))
    fastener = (t(content.fastener.description) or fastener_name(content.fastener) if content.fastener
                else fastener_name(None, adjustment.get("fastener", "")))
    unresolved = adjustment.get("unresolved_sleepers", 0)
    return (text(t("{moving} sleepers to adjust ({fastener}); largest lateral {lateral}, vertical {vertical}; total "
                   "movement {total}; ").format(moving=moving, fastener=fastener,
                                                lateral=_fmt(adjustment.get("max_lateral_mm"), 1, "mm"),
                                                vertical=_fmt(adjustment.get("max_vertical_mm"), 1, "mm"),
                                                total=_fmt(adjustment.get("total_movement_mm"), 0, "mm")))
            + ("<b>" + text(t("{count} sleepers where the checks still fail after adjustment").format(count=unresolved))
               + "</b>" + text(t(".")) if unresolved else text(t("every check met after adjustment.")))
            + (" " + text(after + t(".")) if (after := after_adjustment_text(content.summary)) else "")
            + (" " + text(threshold + t(".")) if (threshold := threshold_text(content.summary)) else ""))


SIGN_OFF_STYLE = TableStyle([
    ("FONT", (0, 0), (-1, -1), "Helvetica", 8.5),
    ("FONT", (0, 0), (-1, 0), "Helvetica-Bold", 8.5),
    ("FONT", (0, 0), (0, -1), "Helvetica-Bold", 8.5),
    ("GRID", (0, 0), (-1, -1), 0.5, colors.black),
    ("BACKGROUND", (0, 0), (-1, 0), colors.HexColor("#ddebf7")),
    ("VALIGN", (0, 0), (-1, -1), "MIDDLE"),
])


def _sign_off(content: ReportContent) -> Table:
    report = content.project.report
    rows = [["", t("name"), t("signature"), t("date")],
            [t("Surveyed and processed by"), report.operator, "", ""],
            [t("Checked by"), report.checked_by, "", ""],
            [t("Approved by"), report.approved_by, "", ""]]
    cells = [[_cell(v, BODY) if v else "" for v in row] for row in rows]
    return Table(cells, colWidths=[55 * mm, 75 * mm, 85 * mm, 54 * mm], rowHeights=[5 * mm] + [9 * mm] * 3,
                 style=SIGN_OFF_STYLE, hAlign="LEFT")


def _settings_line(content: ReportContent) -> list[Flowable]:
    """The settings the project now states differently from those the results were processed with."""
    if not content.settings_changes:
        return []
    if content.recorded.missing:
        return [Paragraph("<b>" + text(t("Settings not recorded")) + "</b>" + text(
            t(": these results were {why}; this report states the project's settings as they are now.").format(
                why=t(NOT_RECORDED))), BODY)]
    return [Paragraph("<b>" + text(t("The project has changed since processing")) + "</b>" + text(
        t("; this report states the settings the results were processed with: ") + "; ".join(content.settings_changes)),
        BODY)]


def _notice_line(content: ReportContent) -> list[Flowable]:
    notices = notices_of(content.summary)
    if not notices:
        return []
    return [Paragraph("<b>" + text((t("{count} warning from processing") if len(notices) == 1 else
                                    t("{count} warnings from processing")).format(count=len(notices))) + "</b>"
                      + text(t(" (see Survey and processing): ") + t("; ").join(n.said() for n in notices[:2])
                             + ("; ..." if len(notices) > 2 else "")), BODY)]


def _cover(content: ReportContent) -> list[Flowable]:
    """The page a client signs off: what was surveyed with what, in which coordinate system and heights,
    against which tolerances, the conclusion, and the signatures."""
    project = content.project
    title = [Paragraph(text(t("Track geometry survey report")), TITLE),
             Paragraph(text(project.name) + (f'<font size="10"> &nbsp; {text(project.description)}</font>'
                                              if project.description else ""), H1_COVER)]
    left = [Paragraph(text(t("Survey")), H2), key_values(_survey_rows(content), widths=(32 * mm, 100 * mm))]
    right = [Paragraph(text(t("Conclusion")), H2), *_settings_line(content), *_notice_line(content),
             *_exceedance_conclusion(content),
             Paragraph(text(t("Predicted accuracy against the tolerances")), H3), *_accuracy_conclusion(content),
             Paragraph(text(t("Adjustment")), H3), Paragraph(_adjustment_conclusion(content), BODY)]
    page_width, page_height = PAGES["A4"]  # laid out on A4, enlarged on A3
    columns = Table([[left, right]], colWidths=[136 * mm, page_width - 2 * MARGIN - 136 * mm],
                    style=TableStyle([("VALIGN", (0, 0), (-1, -1), "TOP"), ("LEFTPADDING", (0, 0), (-1, -1), 0)]))
    written = f"{content.software}, {datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC"
    page = [*title, columns, Spacer(1, 3 * mm), _sign_off(content),
            Paragraph(text(t("Report written by {written} from the results of {folder}.").format(
                written=written, folder=content.results.folder.name)), SMALL)]
    # one page whatever it holds (long names, many channels): shrunk to fit rather than run over
    fitted = KeepInFrame(page_width - 2 * MARGIN, page_height - 2 * MARGIN - 2, page, mode="shrink")
    return [Heading(t("Survey report")), Scaled(fitted, (page_size(content)[0] - 2 * MARGIN) / (page_width - 2 * MARGIN)),
            PageBreak()]


def _gnss_rows(gnss: dict) -> list[tuple[str, object]]:
    if not gnss:
        return [("GNSS", t("not recorded in the results (processed by an older insrail)"))]
    span = gnss.get("span_s", [0.0, 0.0])
    duration = max(span[1] - span[0], 1e-9)
    expected = duration / gnss["interval_s"] if gnss.get("interval_s") else float("nan")
    outages = gnss.get("outages", [])
    listed = "; ".join(f"{a:.0f} - {b:.0f} s ({b - a:.0f} s)" for a, b in outages[:12])
    if len(outages) > 12:
        listed += t("; and {count} more").format(count=len(outages) - 12)
    return [
        (t("GNSS solutions"), t("{solutions} at {interval:g} s ({share:.1f} % of the survey span), {fixed} fixed").format(
            solutions=gnss["solutions"], interval=gnss.get("interval_s", 0),
            share=100 * gnss["solutions"] / expected, fixed=gnss["fixed"])),
        (t("GNSS outages"), t("{count} longer than 3 s, {total:.0f} s in all").format(
            count=len(outages), total=gnss.get("outage_total_s", 0))
         + (t(": {listed} (GPS seconds of week)").format(listed=listed) if outages else "")),
    ]


def trajectory_statistics(results: StoredResults) -> dict | None:
    """The trajectory's figures the report states: summary.toml's ``[trajectory]`` (computed when the
    survey was processed), for results of older versions the same figures read from trajectory.npy
    (:func:`insrail.project.results.trajectory_section`, a chunk at a time); None without either."""
    if "trajectory" in results.summary:
        return results.summary["trajectory"]
    try:
        return trajectory_section(results.folder / TRAJECTORY_FILE)
    except (OSError, ValueError):  # the report still stands without the trajectory's statistics
        return None


def _trajectory_rows(statistics: dict | None, smoother: bool) -> list[tuple[str, object]]:
    """``statistics``: :func:`trajectory_statistics`."""
    if not statistics or not statistics["epochs"]:
        return [(t("Trajectory"), t("not available"))]
    start, end = statistics["start_s"], statistics["end_s"]
    horizontal, vertical = statistics["sigma_horizontal_mm"], statistics["sigma_vertical_mm"]
    rows = [
        (t("Trajectory"), t("{epochs} epochs, {start:.1f} - {end:.1f} s of week ({span:.0f} s), {passes}").format(
            epochs=statistics["epochs"], start=start, end=end, span=end - start,
            passes=t("forward filter and RTS smoother") if smoother else t("forward filter only"))),
        *((name, t("median {median:.1f} mm, 95 % {p95:.1f} mm, largest {max:.1f} mm").format(**sigma))
          for name, sigma in ((t("Position sigma, horizontal"), horizontal), (t("Position sigma, vertical"), vertical))),
    ]
    scale = statistics["odometer_scale"]
    if scale["used"]:  # a state of the filter: 0 throughout when the odometer was not used
        spread = scale["max"] - scale["min"]
        rows.append((t("Odometer scale error"), t("{last:+.2f} per mille at the end").format(last=1e3 * scale["last"])
                     + (t(" (from {low:+.2f} to {high:+.2f} along the survey)").format(low=1e3 * scale["min"],
                                                                                        high=1e3 * scale["max"])
                        if spread > 5e-6 else "")))
    return rows


def _processing(content: ReportContent, trajectory: dict | None) -> list[Flowable]:
    s = content.summary
    survey, fusion, heights = s.get("survey", {}), s.get("fusion", {}), s.get("heights", {})
    rows = [("IMU", t("{epochs} epochs").format(epochs=survey.get("imu_epochs", "-"))), *_gnss_rows(s.get("gnss", {})),
            *_trajectory_rows(trajectory, content.project.fusion.smoother),
            (t("Fusion"), t("{how}; {rejections} measurements rejected, {stops} stops (ZUPT)").format(
                how=t("reused from the cache") if fusion.get("from_cache") else t("computed"),
                rejections=fusion.get("rejections", "-"), stops=fusion.get("stops", "-"))),
            (t("Heights"), t("{model} height-anomaly model").format(model=t(heights.get("model", "-")))
             + (t(", benchmark RMS {rms:.1f} mm (leave-one-out {loo:.1f} mm)").format(
                 rms=heights["internal_rms_mm"], loo=heights["loo_rms_mm"]) if "internal_rms_mm" in heights else ""))]
    rows += [(t("Sleeper detector"), repair)] if (repair := sleeper_repair_text(s)) else []
    rows += [(t("IMU mounting"), mounting)] if (mounting := mounting_text(s)) else []
    rows += [(t("Two odometers"), pair)] if (pair := odometer_pair_text(s)) else []
    rows += _local_control_rows(s.get("local_control"))
    rows += [(t("Warning") if notice.severity == "warning" else t("Note"), notice.said()) for notice in notices_of(s)]
    rows += [(t("Note"), note) for note in content.notes]
    story: list[Flowable] = [Heading(t("Survey and processing")), Paragraph(text(t("Survey and processing")), H1),
                             key_values(rows, widths=(45 * mm, 215 * mm))]
    story += _local_control_table(s.get("local_control"))
    story += [Paragraph(text(t("Tolerance profile")), H2),
              Paragraph(text(profile_name(content.profile)), BODY)]
    counts = s.get("assessment", {}).get("by_check", {})
    story.append(table([t("check"), t("what"), t("limit"), t("exceedances")],
                       [[check_name(c), check_description(c), limits_text(c), counts.get(c.name, 0)]
                        for c in content.profile.checks],
                       [60 * mm, 110 * mm, 30 * mm, 25 * mm]))
    quality = s.get("track_quality", {})
    if quality.get("tqi_mm"):
        channels = quality["channels"]
        rows = []
        for k, start in enumerate(quality["start_m"]):
            rows.append([_section_label(content, start, start + quality["section_m"])]
                        + [_fmt(quality[f"sd_{c}_mm"][k] if quality[f"sd_{c}_mm"][k] >= 0 else None, 2) for c in channels]
                        + [_fmt(quality["tqi_mm"][k] if quality["tqi_mm"][k] >= 0 else None, 2)])
        story += [CondPageBreak(60 * mm),
                  Paragraph(text(t("Track quality per {section:g} m section (standard deviations, mm; level and "
                                   "alignment in the {band} band)").format(section=quality["section_m"],
                                                                          band=quality.get("band", "D1"))), H2),
                  table([t("section")] + [quantity_name(c).name for c in channels] + [t("TQI")], rows,
                        [45 * mm] + [24 * mm] * len(channels) + [22 * mm])]
    story += _predicted_accuracy(content)
    story.append(PageBreak())
    return story


def _local_control_rows(local: dict | None) -> list[tuple[str, object]]:
    """The local-control transformation in one line (summary.toml [local_control])."""
    if not local:
        return []
    p = local["parameters"]
    what = (t("rotation {rotation_deg:.6f}°, scale {scale_ppm:+.2f} ppm, height shift {height_shift_m:+.4f} m")
            if local["model"] == "4-parameter" else
            t('rotations {rx_arcsec:.2f}" {ry_arcsec:.2f}" {rz_arcsec:.2f}", scale {scale_ppm:+.2f} ppm')).format(**p)
    line = t("{model} transformation on {points} common points: {what}; residual RMS {rms:.1f} mm, leave-one-out RMS "
             "{loo} mm; every coordinate in this report is in the local grid").format(
        model=local["model"], points=local["points"], what=what, rms=local["rms_mm"], loo=_fmt(local.get("loo_rms_mm"), 1))
    return [(t("Local control"), line)]


def _local_control_table(local: dict | None) -> list[Flowable]:
    if not local:
        return []
    rows = [[r["name"], *(_fmt(r.get(k), 1) for k in (
        "east_mm", "north_mm", "height_mm", "loo_east_mm", "loo_north_mm", "loo_height_mm"))] for r in local["residuals"]]
    return [Paragraph(text(t("Local control: residuals of the common points (observed - transformed, mm)")), H2),
            table([t(title) for title in ("point", "east", "north", "height", "leave-one-out east", "north", "height")],
                  rows,
                  [45 * mm] + [30 * mm] * 6)]


def _section_label(content: ReportContent, start_m: float, end_m: float) -> str:
    """A section of stations as the chainage labels of its first and last sleeper (metres without sleepers)."""
    station = content.station_m
    inside = np.flatnonzero((station >= start_m) & (station < end_m))
    if not inside.size:
        return f"{start_m:.0f} - {end_m:.0f} m"
    labels = content.column("label").values
    return f"{labels[inside[0]]} - {labels[inside[-1]]}"


#: Sections listed by name in the predicted-accuracy table (the chart shows them all).
WEAKEST_LISTED = 3


def _predicted_accuracy(content: ReportContent) -> list[Flowable]:
    """The 1-sigma the fusion's error model predicts per section (quality.csv): a chart along
    chainage of the 5 m and 150 m lag differences with the weakest section shaded, and a table
    of the weakest sections and the median."""
    quality = content.results.quality
    if quality is None or not len(quality):
        return []
    weakest = quality.weakest_sections(WEAKEST_LISTED)
    first = int(weakest[0])
    band = (Band(float(quality.station_from_m[first]), float(quality.station_to_m[first]), WEAK_COLOUR,
                 t("weakest section")),)
    stations, lag5_lat, lag5_ver, lag150_lat, lag150_ver = section_steps(
        quality.station_from_m, quality.station_to_m, quality.sigma_lag5_lateral_mm, quality.sigma_lag5_vertical_mm,
        quality.sigma_lag150_lateral_mm, quality.sigma_lag150_vertical_mm)
    charts = (StripChart(t("1-sigma of the 5 m lag difference (30 m / 5 m check)"), "mm",
                         (Series(t("lateral"), lag5_lat), Series(t("vertical"), lag5_ver)), bands=band,
                         include_zero=True),
              StripChart(t("1-sigma of the 150 m lag difference (300 m / 150 m check)"), "mm",
                         (Series(t("lateral"), lag150_lat), Series(t("vertical"), lag150_ver)), bands=band,
                         include_zero=True))
    low, high = float(np.nanmin(stations)), float(np.nanmax(stations))
    width = page_size(content)[0] - 2 * MARGIN
    drawings = [strip_drawing(chart, stations, np.ones(len(stations), dtype=bool), low, high, width, 42 * mm,
                              ticks=content.chainage.ticks, axis_title=content.chainage.title) for chart in charts]
    figures = ("sigma_lateral_mm", "sigma_vertical_mm", "sigma_lag5_lateral_mm", "sigma_lag5_vertical_mm",
               "sigma_lag150_lateral_mm", "sigma_lag150_vertical_mm")
    rows = [[t("weakest {rank}").format(rank=rank) if len(weakest) > 1 else t("weakest"),
             _section_label(content, quality.station_from_m[k], quality.station_to_m[k])]
            + [_fmt(getattr(quality, name)[k], 2) for name in figures] for rank, k in enumerate(weakest, start=1)]
    rows.append([t("median"), t("{count} sections").format(count=len(quality))]
                + [_fmt(float(np.nanmedian(getattr(quality, name))), 2) for name in figures])
    passes = t("forward filter and RTS smoother") if quality.smoothed else t("forward filter")
    return [CondPageBreak(120 * mm), Paragraph(text(t("Predicted accuracy per section")), H2),
            Paragraph(text(t("1-sigma of the {passes} from the fusion's error model along this survey's measurements "
                             "(its GNSS outages, stops and rejected data); lag differences are the errors behind the "
                             "30 m / 5 m and 300 m / 150 m checks. Shaded: the section whose figures stand furthest "
                             "above the survey's median.").format(passes=passes)), BODY),
            *drawings,
            table([t(title) for title in ("1-sigma (mm)", "section", "position lateral", "position vertical",
                                          "5 m lag lateral", "5 m lag vertical", "150 m lag lateral",
                                          "150 m lag vertical")], rows,
                  [24 * mm, 45 * mm] + [30 * mm] * 6)]


def chart_specs(content: ReportContent) -> list[StripChart]:
    """The quantities drawn along chainage, in the order of the sleeper table, titled with their display names."""
    c = {column.key: column for column in content.columns}
    reference = deviation_reference(content.summary)
    charts = [StripChart(t("Lateral deviation, {reference}").format(reference=reference), "mm",
                         (Series(t("left rail"), c["lateral_deviation_left_mm"].values),
                          Series(t("right rail"), c["lateral_deviation_right_mm"].values))),
              StripChart(t("Vertical deviation, {reference}").format(reference=reference), "mm",
                         (Series(t("left rail"), c["vertical_deviation_left_mm"].values),
                          Series(t("right rail"), c["vertical_deviation_right_mm"].values)))]
    profile_checks = {check.name: check for check in content.profile.checks}
    seen = set()
    for column in content.columns:
        check = profile_checks.get(column.check) if column.check else None
        if check is None or check.kind not in RAIL_KINDS or check.name in seen:
            continue
        seen.add(check.name)
        for direction in check.directions:
            shown = [c[check_column(check.name, check.kind, rail, direction)] for rail in RAILS]
            charts.append(StripChart(joined((check_name(check), t(direction))), shown[0].unit,
                                     tuple(Series(rail_direction(rail, ""), col.values) for rail, col in zip(RAILS, shown)),
                                     column.limits, shown[0].exceeding | shown[1].exceeding))

    def kind(column) -> str | None:
        return profile_checks[column.check].kind if column.check else None

    gauge = next(col for col in content.columns if col.key == "gauge_deviation_mm" or kind(col) == "gauge_deviation")
    charts.append(StripChart(gauge.name, "mm", (Series(gauge.name, gauge.values),), gauge.limits, gauge.exceeding))
    charts.append(StripChart(t("Cant"), "mm", (Series(t("measured"), c["cant_mm"].values),
                                               Series(t("design"), c["design_cant_mm"].values))))
    track_kinds = ("cross_level", "twist", "gauge_change_rate", "cant_change_rate", "cant_deficiency",
                   "cant_deficiency_rate")
    stored = ("cross_level_mm", "twist_3m_mm", "gauge_change_rate_2_5m_ratio", "cant_change_rate_ratio",
              "cant_deficiency_mm", "cant_deficiency_rate_mm_per_s")
    for column in content.columns:
        if column.key in stored or kind(column) in track_kinds or (
                column.group == t(OTHER_CHECKS_GROUP) and kind(column) != "gauge_deviation"):
            charts.append(StripChart(column.name, column.unit, (Series(column.name, column.values),), column.limits,
                                     column.exceeding))
    return charts


def chart_spans(station_from: float, station_to: float, longest_m: float = CHART_RANGE_M,
                round_m: float = CHART_ROUND_M) -> list[tuple[float, float]]:
    """The chainage span of each chart page: as few spans of at most ``longest_m`` as cover the survey,
    all of one length (a multiple of ``round_m``, from a round station), so the last page is as full as the first."""
    start = math.floor(station_from / round_m) * round_m
    length = max(station_to - start, round_m)
    count = math.ceil(length / longest_m - 1e-9)
    span = math.ceil(length / count / round_m - 1e-9) * round_m
    while start + count * span < station_to:  # rounding up the span never leaves data out
        count += 1
    return [(start + k * span, start + (k + 1) * span) for k in range(count)]


def pages_of_charts(count: int, height: float, smallest: float = CHART_MIN_HEIGHT) -> list[int]:
    """How many charts each page of one span holds: as few pages as keep every chart at least ``smallest``
    high, the charts shared out evenly (each page filled: its charts share the page's height)."""
    per_page = max(int(height // smallest), 1)
    pages = math.ceil(count / per_page)
    return [count // pages + (1 if k < count % pages else 0) for k in range(pages)]


def _charts(content: ReportContent, progress: StepProgress, cancel: CancelToken) -> list[Flowable]:
    station = content.station_m
    if not station.size:
        return []
    marks = tuple(Band(e.station_from_m, e.station_to_m, EVENT_COLOUR, e.name) for e in content.events)
    charts = [replace(chart, events=marks) for chart in chart_specs(content)]
    page = page_size(content)
    width = page[0] - 2 * MARGIN
    available = chart_area_height(page)
    layout = pages_of_charts(len(charts), available)
    labels = content.column("label").values
    axis = content.chainage
    ticks = cache(axis.ticks)  # the same ticks for every chart of a span (their labels cost more than the chart)
    story: list[Flowable] = []
    spans = chart_spans(float(station[0]), float(station[-1]))
    for number, (start, end) in enumerate(spans):
        check_cancel(cancel)
        progress(number / len(spans), Phrase("charts {station_m:.0f} m", {"station_m": start}))
        inside = np.flatnonzero((station >= start) & (station < end))
        if not inside.size:
            continue
        heading = t("Charts {first} - {last}").format(first=labels[inside[0]], last=labels[inside[-1]])
        first = 0
        for on_page in layout:
            story.append(Heading(heading))
            height = available / on_page - 2
            for chart in charts[first:first + on_page]:
                story.append(Deferred(partial(strip_drawing, chart, station, content.valid, start, end, width, height,
                                              ticks=ticks, axis_title=axis.title)))
            first += on_page
            story.append(PageBreak())
    return story


def _plan(content: ReportContent) -> list[Flowable]:
    c = content.results.columns
    east = 0.5 * (c["left_E_m"] + c["right_E_m"])
    north = 0.5 * (c["left_N_m"] + c["right_N_m"])
    row_of = {int(n): i for i, n in enumerate(content.results.number)}
    peaks = np.array([row_of[e.first_sleeper] for e in content.results.exceedances], dtype=int)
    marks = (PlanMark(east[peaks], north[peaks], LIMIT_COLOUR, t("exceedance")),) if peaks.size else ()
    highlight = []
    outages = content.summary.get("gnss", {}).get("outages", [])
    if outages:
        time = c["time_s"]
        during = np.zeros(len(time), dtype=bool)
        for a, b in outages:
            during |= (time >= a) & (time <= b)
        highlight.append((during, OUTAGE_COLOUR, t("GNSS outage")))
    page = page_size(content)
    width, height = page[0] - 2 * MARGIN, page[1] - 2 * MARGIN - 40
    return [Heading(t("Plan view")), Paragraph(text(t("Plan view (engineering coordinates, stations in m)")), H2),
            plan_drawing(east, north, content.station_m, width, height, marks, tuple(highlight)), PageBreak()]


def _percent(value: float) -> str:
    return f"{value:.0f} %" if value >= 1 else f"{value:.1f} %"


def _events(content: ReportContent) -> list[Flowable]:
    """The survey's events: which stretches were not assessed (their sleepers greyed), which only marked."""
    if not content.events:
        return []
    not_assessed = content.summary.get("assessment", {}).get("not_assessed_sleepers", 0)
    rows = [[e.kind, text(e.text), f"{e.station_from_m:.3f}", f"{e.station_to_m:.3f}", e.sleepers, e.assessment,
             text(e.source)] for e in content.events]
    return [Paragraph(text(t("Events and stretches not assessed")), H2),
            Paragraph(text(t("{count} measured sleepers lie in events not assessed with the tolerance profile (greyed "
                             "in the charts and the workbook, never counted as exceedances).").format(count=not_assessed)),
                      BODY),
            table([t(title) for title in ("event", "text", "from (m)", "to (m)", "sleepers", "assessment", "written in")],
                  rows,
                  [28 * mm, 55 * mm, 22 * mm, 22 * mm, 16 * mm, 60 * mm, 45 * mm])]


def _exceedances(content: ReportContent) -> list[Flowable]:
    """The exceedances grouped by severity (the most severe first), each group in chainage order."""
    story: list[Flowable] = [Heading(t("Exceedances")), Paragraph(text(t("Exceedances")), H1)]
    groups = exceedances_by_severity(content)
    if not groups:
        return story + [Paragraph(text(t("No sleeper is beyond a limit of the tolerance profile.")), BODY)] + _events(content)
    story.append(Paragraph(text(_sentence(t(SEVERITY_RULE))), BODY))
    label_of = dict(zip(content.results.number.tolist(), content.results.label))
    widths = [12 * mm, 78 * mm, 30 * mm, 30 * mm, 18 * mm, 18 * mm, 18 * mm, 16 * mm, 18 * mm, 28 * mm]
    index = 0
    for severity, rows in groups:
        data = []
        for e in rows:
            index += 1
            peak, limit, unit = exceedance_display(e)
            digits = 3 if unit == "‰" else 2  # enough to see the peak beyond the limit
            data.append([index, exceedance_check(content, e), label_of.get(e.first_sleeper, ""),
                         label_of.get(e.last_sleeper, ""), f"{e.station_to_m - e.station_from_m:.2f}",
                         f"{peak:.{digits}f}", f"{limit:.{digits}f}", t("per mille") if unit == "‰" else unit,
                         _percent(100 * excess_share(e)), f"{e.first_sleeper} - {e.last_sleeper}"])
        story += [CondPageBreak(30 * mm), Paragraph(text(f"{_sentence(t(severity))[:-len(t('.'))]}: {len(rows)}"), H2),
                  table([t(title) for title in ("no.", "check", "from", "to", "length (m)", "peak", "limit", "unit",
                                                "beyond by", "sleepers")], data, widths)]
    return story + _events(content)


#: The PDF's adjustment table: a line per sleeper (the crew's sheet has one per rail, with the parts); the
#: amounts written out, 0 too.
ADJUSTMENT_TITLES = ["no.", "sleeper", "chainage", "lateral left (mm)", "lateral right (mm)", "vertical left (mm)",
                     "vertical right (mm)", "checks still failed"]
ADJUSTMENT_WIDTHS = [14 * mm, 20 * mm, 30 * mm, 26 * mm, 26 * mm, 26 * mm, 26 * mm, 100 * mm]


def _amount(value: float) -> str:
    return f"{value:+.0f}" if round(value) else "0"


def _adjustment(content: ReportContent) -> list[Flowable]:
    """The amounts per sleeper, the crew sheet's lines (:func:`insrail.report.content.crew_sections`) a sleeper
    to a line, one table per work section."""
    story: list[Flowable] = [Heading(t("Adjustment")), Paragraph(text(t("Adjustment amounts")), H1),
                             Paragraph(text(t("Amounts: ") + amounts_text(content.summary, content.profile,
                                                                          content.fastener)
                                            + t(". The fastener parts per rail are on the workbook's Adjustment sheet.")),
                                       BODY),
                             Paragraph(_adjustment_conclusion(content), BODY)]
    work_sections = crew_sections(content)
    if not work_sections:
        return story + [Paragraph(text(t("No rail to move: every check of the tolerance profile passes as measured.")),
                                  BODY)]
    numbers, labels = content.column("number").values, content.column("label").values
    header = [_cell(t(title)) for title in ADJUSTMENT_TITLES]  # every section's table repeats it, as a page does
    for section in work_sections:
        first, last = section.rows[0].sleeper, section.rows[-1].sleeper
        rows: list[list] = [header]
        for sleeper, lines in itertools.groupby(section.rows, key=lambda row: row.sleeper):
            by_rail = {row.rail: row for row in lines}
            lateral = [by_rail[rail].lateral_mm if rail in by_rail else 0.0 for rail in (0, 1)]
            vertical = [by_rail[rail].vertical_mm if rail in by_rail else 0.0 for rail in (0, 1)]
            failing = "; ".join(dict.fromkeys(row.failing for row in by_rail.values() if row.failing))
            rows.append([str(next(iter(by_rail.values())).count), str(int(numbers[sleeper])), text_cell(labels[sleeper]),
                         *(_amount(value) for value in (*lateral, *vertical)), _cell(failing) if failing else []])
        story += [CondPageBreak(40 * mm),
                  Paragraph(text(t("Work section {number} of {count}: {first} – {last}").format(
                      number=section.number, count=len(work_sections), first=labels[first], last=labels[last])), H2),
                  LongTable(rows, colWidths=ADJUSTMENT_WIDTHS, repeatRows=1, style=TABLE_STYLE, hAlign="LEFT")]
    return story


def text_cell(value) -> str | Paragraph:
    """A table cell: the text itself where Helvetica shows it (quick to lay out), else a paragraph."""
    value = str(value)
    return value if helvetica_can_show(value) else _cell(value)


def _compared_name(content: ReportContent, column: str) -> str:
    """The display name of a compared sleepers.csv column."""
    try:
        return column_name(column, content.profile.checks).name
    except UnknownName:  # a check of the profile the runs were compared with, no longer in the project's
        return t("{column} (a check no longer in tolerance profile {profile})").format(
            column=column, profile=profile_name(content.profile))


def _repeatability(stored: StoredRepeatability, results_written_s: float) -> Section:
    """Repeat runs compared by chainage (thesis §5.4.2): statistics per parameter and run, and the
    differences along chainage of the deviations, gauge and cant."""
    def section(content: ReportContent) -> list[Flowable]:
        story: list[Flowable] = [Heading(t("Repeatability")), Paragraph(text(t("Repeatability of repeat runs")), H1),
                                 Paragraph(text(t(
            "Reference run {reference}, compared: {compared}; {count} valid sleepers of the reference compared by "
            "chainage (each run interpolated onto the reference stations, never across a gap of more than two "
            "sleepers). A run minus the reference carries the noise of both: the repeatability of one run is the "
            "pooled standard deviation / √2. A mean away from zero is a systematic shift between runs, not noise. "
            "Checks marked by magnitude (the differential versines) are compared by their absolute value: their worst "
            "value over the chord placements changes sign between runs wherever two placements of opposite sign "
            "nearly tie.").format(reference=stored.reference, compared=", ".join(stored.compared),
                                  count=stored.station_m.size)), BODY)]
        if stored.written_s < results_written_s:
            story.append(Paragraph(text(t("Note: this comparison was made before the current results of this survey "
                                          "were written; run insrail compare again to bring it up to date.")), BODY))
        rows = []
        for parameter, entry in stored.statistics.items():
            for run in stored.compared:
                stats = entry[run]
                if not stats["count"]:  # e.g. a 300 m chord on a run shorter than 300 m
                    continue
                shown_name = _compared_name(content, parameter + "_mm") + (
                    t(" (by magnitude)") if entry.get("compared") == "magnitude" else "")
                rows.append([shown_name, f"{run} - {stored.reference}", stats["count"],
                             *(f"{stats[key]:.2f}" for key in ("mean_mm", "std_mm", "rms_mm", "p95_abs_mm", "max_abs_mm")),
                             f"{entry['single_run_std_mm']:.2f}"])
        story += [Spacer(1, 4), table([t(title) for title in ("parameter", "runs", "sleepers", "mean (mm)", "std (mm)",
                                                              "RMS (mm)", "95 % |d| (mm)", "max |d| (mm)",
                                                              "one run std (mm)")], rows,
                                      [70 * mm, 45 * mm, 18 * mm, 20 * mm, 20 * mm, 20 * mm, 24 * mm, 24 * mm, 26 * mm]),
                  PageBreak()]
        shown = [name for name in BASE_PARAMETERS if name in stored.difference_mm]
        station = stored.station_m
        if not station.size or not shown:
            return story
        page = page_size(content)
        width = page[0] - 2 * MARGIN
        height = (page[1] - 2 * MARGIN - 24) / len(shown) - 2
        story.append(Heading(t("Repeatability")))
        for name in shown:
            differences = stored.difference_mm[name]
            chart = StripChart(t("{name}: run minus reference").format(name=_compared_name(content, name)), "mm",
                               tuple(Series(run, values) for run, values in zip(stored.compared, differences)))
            story.append(strip_drawing(chart, station, np.isfinite(differences).any(axis=0), float(station[0]),
                                       float(station[-1]), width, height, ticks=content.chainage.ticks,
                                       axis_title=content.chainage.title))
        return story

    return section


def _on_page(canvas: Canvas, doc) -> None:
    """Header and footer, drawn after the page's flowables so the heading they set is known."""
    canvas.saveState()
    canvas.setFont("Helvetica", 8)
    canvas.setStrokeColor(colors.grey)
    page_width, page_height = doc.pagesize
    top = page_height - MARGIN + 6
    canvas.line(MARGIN, top - 3, page_width - MARGIN, top - 3)
    canvas.setFont(font_for(doc.report_title), 8)
    canvas.drawString(MARGIN, top, doc.report_title)
    heading = getattr(canvas, "_insrail_heading", "")
    canvas.setFont(font_for(heading, "Helvetica-Bold"), 8)
    canvas.drawRightString(page_width - MARGIN, top, heading)
    canvas.setFont(font_for(doc.report_footer), 8)
    canvas.drawString(MARGIN, MARGIN - 16, doc.report_footer)
    canvas.restoreState()


def _layout_progress(progress: StepProgress, cancel: CancelToken) -> Callable[[str, int], None]:
    """reportlab's build callback -> progress and cancel checks while the pages are laid out."""
    total = [1]

    def callback(kind: str, value: int) -> None:
        if kind == "SIZE_EST":
            total[0] = max(int(value), 1)
        elif kind == "PROGRESS":
            check_cancel(cancel)
            progress(min(value / total[0], 1.0), "laying out the pages")

    return callback


def write_pdf(project: Project, results: StoredResults, path, progress: ProgressFn | None = None,
              cancel: CancelToken = None, sections: Sequence[Section] = (), content: ReportContent | None = None) -> Path:
    """Write the survey report for one survey's results to ``path`` (atomically); returns the path.

    ``sections`` are added after the plan view, each a function of the report content returning
    flowables; the repeatability of repeat runs follows by itself when the project's last
    comparison (``insrail compare``) includes this survey. ``content``: the results'
    :func:`insrail.report.content.report_content`, where the caller made it already."""
    with in_language(report_language(project)), _wrapped_as_the_language_writes():
        return _write_pdf(project, results, Path(path), StepProgress(progress), cancel, sections, content)


#: The paragraph styles, wrapped between words in English and between any two characters in Chinese (no spaces).
_STYLES = (BODY, SMALL, H1, H1_COVER, H2, H3, TITLE)


@contextlib.contextmanager
def _wrapped_as_the_language_writes():
    wrap = "CJK" if language() == "zh-CN" else None
    before = [style.wordWrap for style in _STYLES]
    for style in _STYLES:
        style.wordWrap = wrap
    try:
        yield
    finally:
        for style, value in zip(_STYLES, before):
            style.wordWrap = value


def _write_pdf(project: Project, results: StoredResults, path: Path, step: StepProgress, cancel: CancelToken,
               sections: Sequence[Section], content: ReportContent | None) -> Path:
    content = content or load_report_content(project, results)
    step(0.02, "the trajectory's statistics")
    trajectory = trajectory_statistics(results)
    check_cancel(cancel)
    compared = load_repeatability(project.folder)
    if compared is not None and compared.includes(results.survey):
        sections = (*sections, _repeatability(compared, (results.folder / SUMMARY_FILE).stat().st_mtime))
    story = _cover(content) + _processing(content, trajectory)
    story += _charts(content, step.sub(0.05, 0.45), cancel)
    story += _plan(content)
    from insrail.report.redesign_page import redesign_page  # here: it imports this module's styles

    sections = (*sections, redesign_page)
    for section in sections:
        story += section(content) + [PageBreak()]
    story += _exceedances(content) + [PageBreak()] + _adjustment(content)
    check_cancel(cancel)
    step(0.5, "laying out the pages")
    with atomic_write(path, "wb") as handle:
        page = page_size(content)
        doc = BaseDocTemplate(handle, pagesize=page, leftMargin=MARGIN, rightMargin=MARGIN, topMargin=MARGIN,
                              bottomMargin=MARGIN, title=t("{project} - {survey}: track geometry survey report").format(
                                  project=project.name, survey=results.survey),
                              author=content.software, creator=content.software)
        doc.report_title = t("{project} - survey {survey} - {profile}").format(
            project=project.name, survey=results.survey, profile=profile_name(content.profile))
        doc.report_footer = t("{software}; results {folder}").format(software=content.software,
                                                                      folder=results.folder.name)
        frame = Frame(MARGIN, MARGIN, page[0] - 2 * MARGIN, page[1] - 2 * MARGIN, leftPadding=0, rightPadding=0,
                      topPadding=0, bottomPadding=0)
        doc.addPageTemplates([PageTemplate("page", frames=[frame], onPageEnd=_on_page)])
        doc.setProgressCallBack(_layout_progress(step.sub(0.5, 0.98), cancel))
        doc.build(story, canvasmaker=NumberedCanvas)
    step(1.0, Phrase("report written: {file}", {"file": path.name}))
    return path
