"""The PDF survey report (reportlab platypus, A4 landscape, vector charts).

Order: cover; survey and processing summary (data spans, GNSS availability and outages, fusion
quality, heights, assessment, TQI per section, predicted accuracy per section); charts along chainage, one range of
``CHART_RANGE_M`` per page group with the range in the page header; the plan view; any extra
sections (``sections``: e.g. repeatability when several runs exist); the exceedance table. Every
page carries the project and survey, its section or chainage range and "page i of n".
"""

from __future__ import annotations

import datetime
from collections.abc import Callable, Sequence
from pathlib import Path
from xml.sax.saxutils import escape

import numpy as np
from reportlab.lib import colors
from reportlab.lib.pagesizes import A4, landscape
from reportlab.lib.styles import ParagraphStyle, getSampleStyleSheet
from reportlab.lib.units import mm
from reportlab.pdfbase import pdfmetrics
from reportlab.pdfbase.cidfonts import UnicodeCIDFont
from reportlab.pdfgen.canvas import Canvas
from reportlab.platypus import (
    BaseDocTemplate,
    CondPageBreak,
    Flowable,
    Frame,
    PageBreak,
    PageTemplate,
    Paragraph,
    Spacer,
    Table,
    TableStyle,
)

from insrail.io.atomic import atomic_write
from insrail.names import check_name, rail_direction
from insrail.nav.trajectory import Trajectory
from insrail.notices import notices_of
from insrail.progress import CancelToken, ProgressFn, StepProgress, check_cancel
from insrail.project.compare import (
    BASE_PARAMETERS,
    StoredRepeatability,
    load_repeatability,
)
from insrail.project.model import Project
from insrail.project.results import SUMMARY_FILE, StoredResults, check_column
from insrail.report.charts import (
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
    DEVIATION_GROUP,
    OTHER_CHECKS_GROUP,
    RAIL_KINDS,
    ReportContent,
    check_description,
    exceedance_display,
    limits_text,
    load_report_content,
    survey_start,
)
from insrail.track.exceedance import RAILS

PAGE = landscape(A4)
MARGIN = 14 * mm
CHART_RANGE_M = 500.0
CHARTS_PER_PAGE = 5
CJK_FONT = "STSong-Light"  # an Adobe CID font every PDF viewer provides; Helvetica has no CJK glyphs
#: A section added to the report: content -> flowables (e.g. repeatability of several runs), starting
#: with a :class:`Heading` to name its pages in the page header; it ends with a page break.
Section = Callable[[ReportContent], list[Flowable]]

_styles = getSampleStyleSheet()
BODY = ParagraphStyle("body", parent=_styles["BodyText"], fontSize=9, leading=11.5)
SMALL = ParagraphStyle("small", parent=BODY, fontSize=7.5, leading=9)
H1 = ParagraphStyle("h1", parent=_styles["Heading1"], fontSize=16, spaceAfter=6)
H2 = ParagraphStyle("h2", parent=_styles["Heading2"], fontSize=12, spaceBefore=6, spaceAfter=3)
TITLE = ParagraphStyle("title", parent=_styles["Title"], fontSize=26, leading=32, alignment=0)
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
    """Paragraph markup for any text: escaped, and in a CJK font when Helvetica cannot show it."""
    value = escape(str(value))
    font = _font_for(value)
    return value if font == "Helvetica" else f'<font name="{font}">{value}</font>'


def _register_cjk() -> None:
    if CJK_FONT not in pdfmetrics.getRegisteredFontNames():
        pdfmetrics.registerFont(UnicodeCIDFont(CJK_FONT))


def _cell(value, style: ParagraphStyle = SMALL) -> Paragraph:
    return Paragraph(text(value), style)


def key_values(rows: list[tuple[str, object]], widths=(55 * mm, 150 * mm)) -> Table:
    return Table([[_cell(k, BODY), _cell(v, BODY)] for k, v in rows], colWidths=list(widths), style=KEY_VALUE_STYLE,
                 hAlign="LEFT")


def table(header: list[str], rows: list[list], widths: list[float] | None = None) -> Table:
    data = [[_cell(h) for h in header]] + [[_cell(v) for v in row] for row in rows]
    return Table(data, colWidths=widths, repeatRows=1, style=TABLE_STYLE, hAlign="LEFT")


class Heading(Flowable):
    """Sets the page header's right-hand text (section or chainage range) from where it is drawn on."""

    def __init__(self, heading: str):
        super().__init__()
        self.heading = heading

    def wrap(self, available_width, available_height):
        return 0, 0

    def draw(self):
        self.canv._insrail_heading = self.heading


class NumberedCanvas(Canvas):
    """Writes "page i of n" once the number of pages is known."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._pages: list[dict] = []

    def showPage(self):
        self._pages.append(dict(self.__dict__))
        self._startPage()

    def save(self):
        for state in self._pages:
            self.__dict__.update(state)
            self.setFont("Helvetica", 8)
            self.drawRightString(PAGE[0] - MARGIN, MARGIN - 16, f"page {self._pageNumber} of {len(self._pages)}")
            super().showPage()
        super().save()


def _fmt(value, digits: int = 1, unit: str = "") -> str:
    if value is None or (isinstance(value, float) and not np.isfinite(value)):
        return "-"
    return f"{value:.{digits}f}" + (f" {unit}" if unit else "")


# --------------------------------------------------------------------------- pages

def _cover(content: ReportContent, trajectory: Trajectory | None) -> list[Flowable]:
    s = content.summary
    assessment, adjustment, track = s.get("assessment", {}), s.get("adjustment", {}), s.get("track", {})
    tqi = [v for v in s.get("track_quality", {}).get("tqi_mm", []) if v >= 0]
    story: list[Flowable] = [Heading("Cover"), Spacer(1, 25 * mm), Paragraph("Track geometry survey report", TITLE),
                             Paragraph(text(content.project.name), H1)]
    if content.project.description:
        story.append(Paragraph(text(content.project.description), BODY))
    story += [Spacer(1, 10 * mm), key_values([
        ("Survey", content.survey),
        ("Survey start", survey_start(content) or "-"),
        ("Chainage", f"{content.chainage_range} (stations {track.get('station_from_m', 0):.3f} - {track.get('station_to_m', 0):.3f} m)"),
        ("Design", content.project.design or "fitted line types (no design alignment)"),
        ("Sleepers", f"{track.get('sleepers', len(content.results))}, {track.get('valid_sleepers', int(content.valid.sum()))} valid"),
        ("Tolerance profile", f"{content.profile.name}: {content.profile.description}"),
        ("Exceedances", f"{assessment.get('exceedances', len(content.results.exceedances))} runs of sleepers beyond a limit"),
        ("Adjustment", (f"{adjustment.get('fastener', '')}: largest lateral {_fmt(adjustment.get('max_lateral_mm'), 0, 'mm')}, "
                       f"vertical {_fmt(adjustment.get('max_vertical_mm'), 0, 'mm')}, "
                       f"{adjustment.get('unresolved_sleepers', 0)} sleepers where the checks still fail")),
        ("TQI", f"mean {np.mean(tqi):.2f} mm, largest {max(tqi):.2f} mm over {len(tqi)} sections of "
                f"{s['track_quality'].get('section_m', 200):g} m" if tqi else "-"),
        ("Report", f"{content.software}, {datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC"),
    ], widths=(40 * mm, 200 * mm)), PageBreak()]
    return story


def _gnss_rows(gnss: dict) -> list[tuple[str, object]]:
    if not gnss:
        return [("GNSS", "not recorded in the results (processed by an older insrail)")]
    span = gnss.get("span_s", [0.0, 0.0])
    duration = max(span[1] - span[0], 1e-9)
    expected = duration / gnss["interval_s"] if gnss.get("interval_s") else float("nan")
    outages = gnss.get("outages", [])
    listed = "; ".join(f"{a:.0f} - {b:.0f} s ({b - a:.0f} s)" for a, b in outages[:12])
    if len(outages) > 12:
        listed += f"; and {len(outages) - 12} more"
    return [
        ("GNSS solutions", (f"{gnss['solutions']} at {gnss.get('interval_s', 0):g} s "
                           f"({100 * gnss['solutions'] / expected:.1f} % of the survey span), {gnss['fixed']} fixed")),
        ("GNSS outages", f"{len(outages)} longer than 3 s, {gnss.get('outage_total_s', 0):.0f} s in all"
                         + (f": {listed} (GPS seconds of week)" if outages else "")),
    ]


def _trajectory_rows(trajectory: Trajectory | None, smoother: bool) -> list[tuple[str, object]]:
    if trajectory is None or not len(trajectory):
        return [("Trajectory", "not available")]
    sigma = trajectory.sigma_pos_ned_m
    horizontal = 1e3 * np.hypot(sigma[:, 0], sigma[:, 1])
    vertical = 1e3 * sigma[:, 2]
    rows = [
        ("Trajectory", (f"{len(trajectory)} epochs, {trajectory.time_s[0]:.1f} - {trajectory.time_s[-1]:.1f} s of week "
                       f"({trajectory.time_s[-1] - trajectory.time_s[0]:.0f} s), "
                       f"{'forward filter and RTS smoother' if smoother else 'forward filter only'}")),
        ("Position sigma, horizontal", (f"median {np.median(horizontal):.1f} mm, 95 % {np.percentile(horizontal, 95):.1f} mm, "
                                       f"largest {horizontal.max():.1f} mm")),
        ("Position sigma, vertical", (f"median {np.median(vertical):.1f} mm, 95 % {np.percentile(vertical, 95):.1f} mm, "
                                     f"largest {vertical.max():.1f} mm")),
    ]
    scale = trajectory.odometer_scale
    if np.any(scale != 0):  # a state of the filter: 0 throughout when the odometer was not used
        spread = scale.max() - scale.min()
        rows.append(("Odometer scale error", f"{1e3 * scale[-1]:+.2f} per mille at the end"
                     + (f" (from {1e3 * scale.min():+.2f} to {1e3 * scale.max():+.2f} along the survey)" if spread > 5e-6 else "")))
    return rows


def _processing(content: ReportContent, trajectory: Trajectory | None) -> list[Flowable]:
    s = content.summary
    survey, fusion, heights = s.get("survey", {}), s.get("fusion", {}), s.get("heights", {})
    rows = [("IMU", f"{survey.get('imu_epochs', '-')} epochs"), *_gnss_rows(s.get("gnss", {})),
            *_trajectory_rows(trajectory, content.project.fusion.smoother),
            ("Fusion", (f"{'reused from the cache' if fusion.get('from_cache') else 'computed'}; "
                       f"{fusion.get('rejections', '-')} measurements rejected, {fusion.get('stops', '-')} stops (ZUPT)")),
            ("Heights", f"{heights.get('model', '-')} height-anomaly model"
                        + (f", benchmark RMS {heights['internal_rms_mm']:.1f} mm (leave-one-out "
                           f"{heights['loo_rms_mm']:.1f} mm)" if "internal_rms_mm" in heights else ""))]
    rows += [("Warning", notice.text()) for notice in notices_of(s)]
    rows += [("Note", note) for note in content.notes]
    story: list[Flowable] = [Heading("Survey and processing"), Paragraph("Survey and processing", H1),
                             key_values(rows, widths=(45 * mm, 215 * mm))]
    story += [Paragraph("Tolerance profile", H2),
              Paragraph(text(f"{content.profile.name}: {content.profile.description}"), BODY)]
    counts = s.get("assessment", {}).get("by_check", {})
    story.append(table(["check", "what", "limit", "exceedances"],
                       [[c.name, check_description(c), limits_text(c), counts.get(c.name, 0)] for c in content.profile.checks],
                       [45 * mm, 110 * mm, 30 * mm, 25 * mm]))
    quality = s.get("track_quality", {})
    if quality.get("tqi_mm"):
        channels = quality["channels"]
        rows = []
        for k, start in enumerate(quality["start_m"]):
            rows.append([_section_label(content, start, start + quality["section_m"])]
                        + [_fmt(quality[f"sd_{c}_mm"][k] if quality[f"sd_{c}_mm"][k] >= 0 else None, 2) for c in channels]
                        + [_fmt(quality["tqi_mm"][k] if quality["tqi_mm"][k] >= 0 else None, 2)])
        story += [CondPageBreak(60 * mm),
                  Paragraph(f"Track quality per {quality['section_m']:g} m section (standard deviations, mm; level and "
                            f"alignment in the {quality.get('band', 'D1')} band)", H2),
                  table(["section"] + [c.replace("_", " ") for c in channels] + ["TQI"], rows,
                        [45 * mm] + [24 * mm] * len(channels) + [22 * mm])]
    story += _predicted_accuracy(content)
    story.append(PageBreak())
    return story


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
                 "weakest section"),)
    stations, lag5_lat, lag5_ver, lag150_lat, lag150_ver = section_steps(
        quality.station_from_m, quality.station_to_m, quality.sigma_lag5_lateral_mm, quality.sigma_lag5_vertical_mm,
        quality.sigma_lag150_lateral_mm, quality.sigma_lag150_vertical_mm)
    charts = (StripChart("1-sigma of the 5 m lag difference (30 m / 5 m check)", "mm",
                         (Series("lateral", lag5_lat), Series("vertical", lag5_ver)), bands=band, include_zero=True),
              StripChart("1-sigma of the 150 m lag difference (300 m / 150 m check)", "mm",
                         (Series("lateral", lag150_lat), Series("vertical", lag150_ver)), bands=band,
                         include_zero=True))
    low, high = float(np.nanmin(stations)), float(np.nanmax(stations))
    width = PAGE[0] - 2 * MARGIN
    drawings = [strip_drawing(chart, stations, np.ones(len(stations), dtype=bool), low, high, width, 42 * mm)
                for chart in charts]
    figures = ("sigma_lateral_mm", "sigma_vertical_mm", "sigma_lag5_lateral_mm", "sigma_lag5_vertical_mm",
               "sigma_lag150_lateral_mm", "sigma_lag150_vertical_mm")
    rows = [[f"weakest {rank}" if len(weakest) > 1 else "weakest",
             _section_label(content, quality.station_from_m[k], quality.station_to_m[k])]
            + [_fmt(getattr(quality, name)[k], 2) for name in figures] for rank, k in enumerate(weakest, start=1)]
    rows.append(["median", f"{len(quality)} sections"]
                + [_fmt(float(np.nanmedian(getattr(quality, name))), 2) for name in figures])
    passes = "forward filter and RTS smoother" if quality.smoothed else "forward filter"
    return [CondPageBreak(120 * mm), Paragraph("Predicted accuracy per section", H2),
            Paragraph(text(f"1-sigma of the {passes} from the fusion's error model along this survey's measurements "
                           f"(its GNSS outages, stops and rejected data); lag differences are the errors behind the "
                           f"30 m / 5 m and 300 m / 150 m checks. Shaded: the section whose figures stand furthest "
                           f"above the survey's median."), BODY),
            *drawings,
            table(["1-sigma (mm)", "section", "position lateral", "position vertical", "5 m lag lateral",
                   "5 m lag vertical", "150 m lag lateral", "150 m lag vertical"], rows,
                  [24 * mm, 45 * mm] + [30 * mm] * 6)]


def chart_specs(content: ReportContent) -> list[StripChart]:
    """The quantities drawn along chainage, in the order of the sleeper table, titled with their display names."""
    c = {column.key: column for column in content.columns}
    charts = [StripChart(f"Lateral deviation {DEVIATION_GROUP.removeprefix('Deviation ')}", "mm",
                         (Series("left rail", c["lateral_deviation_left_mm"].values),
                          Series("right rail", c["lateral_deviation_right_mm"].values))),
              StripChart(f"Vertical deviation {DEVIATION_GROUP.removeprefix('Deviation ')}", "mm",
                         (Series("left rail", c["vertical_deviation_left_mm"].values),
                          Series("right rail", c["vertical_deviation_right_mm"].values)))]
    profile_checks = {check.name: check for check in content.profile.checks}
    seen = set()
    for column in content.columns:
        check = profile_checks.get(column.check) if column.check else None
        if check is None or check.kind not in RAIL_KINDS or check.name in seen:
            continue
        seen.add(check.name)
        for direction in check.directions:
            shown = [c[check_column(check.name, check.kind, rail, direction)] for rail in RAILS]
            charts.append(StripChart(f"{check_name(check)}, {direction}", shown[0].unit,
                                     tuple(Series(rail_direction(rail, ""), col.values) for rail, col in zip(RAILS, shown)),
                                     column.limits, shown[0].exceeding | shown[1].exceeding))

    def kind(column) -> str | None:
        return profile_checks[column.check].kind if column.check else None

    gauge = next(col for col in content.columns if col.key == "gauge_deviation_mm" or kind(col) == "gauge_deviation")
    charts.append(StripChart(gauge.name, "mm", (Series(gauge.name, gauge.values),), gauge.limits, gauge.exceeding))
    charts.append(StripChart("Cant", "mm", (Series("measured", c["cant_mm"].values), Series("design", c["design_cant_mm"].values))))
    track_kinds = ("cross_level", "twist", "gauge_change_rate", "cant_change_rate", "cant_deficiency",
                   "cant_deficiency_rate")
    stored = ("cross_level_mm", "twist_3m_mm", "gauge_change_rate_2_5m_ratio", "cant_change_rate_ratio",
              "cant_deficiency_mm", "cant_deficiency_rate_mm_per_s")
    for column in content.columns:
        if column.key in stored or kind(column) in track_kinds or (
                column.group == OTHER_CHECKS_GROUP and kind(column) != "gauge_deviation"):
            charts.append(StripChart(column.name, column.unit, (Series(column.name, column.values),), column.limits,
                                     column.exceeding))
    return charts


def _charts(content: ReportContent, progress: StepProgress, cancel: CancelToken) -> list[Flowable]:
    station = content.station_m
    if not station.size:
        return []
    charts = chart_specs(content)
    width = PAGE[0] - 2 * MARGIN
    height = (PAGE[1] - 2 * MARGIN - 24) / CHARTS_PER_PAGE - 2
    labels = content.column("label").values
    story: list[Flowable] = []
    starts = np.arange(np.floor(station[0] / CHART_RANGE_M) * CHART_RANGE_M, station[-1], CHART_RANGE_M)
    for number, start in enumerate(starts):
        check_cancel(cancel)
        progress(number / len(starts), f"charts {start:.0f} m")
        end = start + CHART_RANGE_M
        inside = np.flatnonzero((station >= start) & (station < end))
        if not inside.size:
            continue
        heading = f"Charts {labels[inside[0]]} - {labels[inside[-1]]}"
        for first in range(0, len(charts), CHARTS_PER_PAGE):
            story.append(Heading(heading))
            page = charts[first:first + CHARTS_PER_PAGE]
            for chart in page:
                story.append(strip_drawing(chart, station, content.valid, start, end, width, height))
            story.append(PageBreak())
    return story


def _plan(content: ReportContent) -> list[Flowable]:
    c = content.results.columns
    east = 0.5 * (c["left_E_m"] + c["right_E_m"])
    north = 0.5 * (c["left_N_m"] + c["right_N_m"])
    row_of = {int(n): i for i, n in enumerate(content.results.number)}
    peaks = np.array([row_of[e.first_sleeper] for e in content.results.exceedances], dtype=int)
    marks = (PlanMark(east[peaks], north[peaks], LIMIT_COLOUR, "exceedance"),) if peaks.size else ()
    highlight = []
    outages = content.summary.get("gnss", {}).get("outages", [])
    if outages:
        time = c["time_s"]
        during = np.zeros(len(time), dtype=bool)
        for a, b in outages:
            during |= (time >= a) & (time <= b)
        highlight.append((during, OUTAGE_COLOUR, "GNSS outage"))
    width, height = PAGE[0] - 2 * MARGIN, PAGE[1] - 2 * MARGIN - 40
    return [Heading("Plan view"), Paragraph("Plan view (engineering coordinates, stations in m)", H2),
            plan_drawing(east, north, content.station_m, width, height, marks, tuple(highlight)), PageBreak()]


def _exceedances(content: ReportContent) -> list[Flowable]:
    story: list[Flowable] = [Heading("Exceedances"), Paragraph("Exceedances", H1)]
    rows = content.results.exceedances
    if not rows:
        return story + [Paragraph("No sleeper is beyond a limit of the tolerance profile.", BODY)]
    label_of = dict(zip(content.results.number.tolist(), content.results.label))
    data = []
    for index, e in enumerate(rows, start=1):
        peak, limit, unit = exceedance_display(e)
        digits = 3 if unit == "‰" else 2  # enough to see the peak beyond the limit
        data.append([index, e.check, "" if e.rail == "track" else e.rail, e.direction,
                     label_of.get(e.first_sleeper, ""), label_of.get(e.last_sleeper, ""),
                     f"{e.station_to_m - e.station_from_m:.2f}", f"{peak:.{digits}f}", f"{limit:.{digits}f}",
                     "per mille" if unit == "‰" else unit, f"{e.first_sleeper} - {e.last_sleeper}"])
    widths = [12 * mm, 45 * mm, 15 * mm, 18 * mm, 30 * mm, 30 * mm, 18 * mm, 18 * mm, 18 * mm, 18 * mm, 28 * mm]
    story.append(table(["no.", "check", "rail", "direction", "from", "to", "length (m)", "peak", "limit", "unit", "sleepers"],
                       data, widths))
    return story


def _repeatability(stored: StoredRepeatability, results_written_s: float) -> Section:
    """Repeat runs compared by chainage (thesis §5.4.2): statistics per parameter and run, and the
    differences along chainage of the deviations, gauge and cant."""
    def section(content: ReportContent) -> list[Flowable]:
        story: list[Flowable] = [Heading("Repeatability"), Paragraph("Repeatability of repeat runs", H1), Paragraph(
            f"Reference run <b>{escape(stored.reference)}</b>, compared: {escape(', '.join(stored.compared))}; "
            f"{stored.station_m.size} valid sleepers of the reference compared by chainage (each run interpolated "
            "onto the reference stations, never across a gap of more than two sleepers). A run minus the reference "
            "carries the noise of both: the repeatability of one run is the pooled standard deviation / &radic;2. "
            "A mean away from zero is a systematic shift between runs, not noise.", BODY)]
        if stored.written_s < results_written_s:
            story.append(Paragraph("<b>Note:</b> this comparison was made before the current results of this survey "
                                   "were written; run <i>insrail compare</i> again to bring it up to date.", BODY))
        rows = []
        for parameter, entry in stored.statistics.items():
            for run in stored.compared:
                stats = entry[run]
                if not stats["count"]:  # e.g. a 300 m chord on a run shorter than 300 m
                    continue
                rows.append([parameter.replace("_", " "), f"{run} - {stored.reference}", stats["count"],
                             *(f"{stats[key]:.2f}" for key in ("mean_mm", "std_mm", "rms_mm", "p95_abs_mm", "max_abs_mm")),
                             f"{entry['single_run_std_mm']:.2f}"])
        story += [Spacer(1, 4), table(["parameter", "runs", "sleepers", "mean (mm)", "std (mm)", "RMS (mm)",
                                       "95 % |d| (mm)", "max |d| (mm)", "one run std (mm)"], rows,
                                      [70 * mm, 45 * mm, 18 * mm, 20 * mm, 20 * mm, 20 * mm, 24 * mm, 24 * mm, 26 * mm]),
                  PageBreak()]
        shown = [name for name in BASE_PARAMETERS if name in stored.difference_mm]
        station = stored.station_m
        if not station.size or not shown:
            return story
        width = PAGE[0] - 2 * MARGIN
        height = (PAGE[1] - 2 * MARGIN - 24) / len(shown) - 2
        story.append(Heading("Repeatability"))
        for name in shown:
            differences = stored.difference_mm[name]
            chart = StripChart(f"{name.removesuffix('_mm').replace('_', ' ').capitalize()}: run minus reference", "mm",
                               tuple(Series(run, values) for run, values in zip(stored.compared, differences)))
            story.append(strip_drawing(chart, station, np.isfinite(differences).any(axis=0), float(station[0]),
                                       float(station[-1]), width, height))
        return story

    return section


def _on_page(canvas: Canvas, doc) -> None:
    """Header and footer, drawn after the page's flowables so the heading they set is known."""
    canvas.saveState()
    canvas.setFont("Helvetica", 8)
    canvas.setStrokeColor(colors.grey)
    top = PAGE[1] - MARGIN + 6
    canvas.line(MARGIN, top - 3, PAGE[0] - MARGIN, top - 3)
    canvas.setFont(_font_for(doc.report_title), 8)
    canvas.drawString(MARGIN, top, doc.report_title)
    canvas.setFont("Helvetica-Bold", 8)
    canvas.drawRightString(PAGE[0] - MARGIN, top, getattr(canvas, "_insrail_heading", ""))
    canvas.setFont(_font_for(doc.report_footer), 8)
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


def _font_for(value: str) -> str:
    """Helvetica, or the CJK font for text Helvetica cannot show (a project named in Chinese)."""
    try:
        value.encode("cp1252")
    except UnicodeEncodeError:
        _register_cjk()
        return CJK_FONT
    return "Helvetica"


def write_pdf(project: Project, results: StoredResults, path, progress: ProgressFn | None = None,
              cancel: CancelToken = None, sections: Sequence[Section] = ()) -> Path:
    """Write the survey report for one survey's results to ``path`` (atomically); returns the path.

    ``sections`` are added after the plan view, each a function of the report content returning
    flowables; the repeatability of repeat runs follows by itself when the project's last
    comparison (``insrail compare``) includes this survey."""
    step = StepProgress(progress)
    path = Path(path)
    content = load_report_content(project, results)
    step(0.02, "reading the trajectory")
    try:
        trajectory = results.trajectory()
    except (OSError, ValueError):  # the report still stands without the trajectory's statistics
        trajectory = None
    check_cancel(cancel)
    compared = load_repeatability(project.folder)
    if compared is not None and compared.includes(results.survey):
        sections = (*sections, _repeatability(compared, (results.folder / SUMMARY_FILE).stat().st_mtime))
    story = _cover(content, trajectory) + _processing(content, trajectory)
    story += _charts(content, step.sub(0.05, 0.45), cancel)
    story += _plan(content)
    for section in sections:
        story += section(content) + [PageBreak()]
    story += _exceedances(content)
    check_cancel(cancel)
    step(0.5, "laying out the pages")
    with atomic_write(path, "wb") as handle:
        doc = BaseDocTemplate(handle, pagesize=PAGE, leftMargin=MARGIN, rightMargin=MARGIN, topMargin=MARGIN,
                              bottomMargin=MARGIN, title=f"{project.name} - {results.survey}: track geometry survey report",
                              author=content.software, creator=content.software)
        doc.report_title = f"{project.name} - survey {results.survey} - {content.profile.name}"
        doc.report_footer = f"{content.software}; results {results.folder.name}"
        frame = Frame(MARGIN, MARGIN, PAGE[0] - 2 * MARGIN, PAGE[1] - 2 * MARGIN, leftPadding=0, rightPadding=0,
                      topPadding=0, bottomPadding=0)
        doc.addPageTemplates([PageTemplate("page", frames=[frame], onPageEnd=_on_page)])
        doc.setProgressCallBack(_layout_progress(step.sub(0.5, 0.98), cancel))
        doc.build(story, canvasmaker=NumberedCanvas)
    step(1.0, f"report written: {path.name}")
    return path
