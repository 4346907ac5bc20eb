"""Vector charts for the PDF report, drawn with reportlab's own graphics (no raster images).

A chart of 16 000 sleepers must stay light and never lose a peak: :func:`decimate_min_max`
keeps, per pixel column, the points holding the column's minimum and maximum (in their
original order), so every spike a reader could see at full resolution is still drawn.
NaN (invalid sleepers) breaks a line instead of bridging it.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from reportlab import rl_config

# reportlab checks every attribute set on a shape against its declared type ("slows down shapes but is
# a big help when developing", its shapes.py): at 10 km some 250 000 settings; without the check the
# PDF took 8.3 s of CPU instead of 11.3-11.6 s. Read once, when reportlab.graphics.shapes is first
# imported (the next line).
rl_config.shapeChecking = 0
from reportlab.graphics.renderbase import renderScaledDrawing  # noqa: E402
from reportlab.graphics.renderPDF import _PDFRenderer  # noqa: E402
from reportlab.graphics.shapes import Circle, Drawing, Line, Path, PolyLine, Rect, String  # noqa: E402
from reportlab.lib import colors  # noqa: E402
from reportlab.lib.rl_accel import fp_str  # noqa: E402
from reportlab.pdfbase.pdfmetrics import stringWidth  # noqa: E402

from insrail.names import t
from insrail.report.fonts import font_for, font_runs

SERIES_COLOURS = (colors.HexColor("#1f4e9c"), colors.HexColor("#d9641e"), colors.HexColor("#2b8a3e"))
LIMIT_COLOUR = colors.HexColor("#c0141e")
INVALID_COLOUR = colors.HexColor("#e3e3e3")
EVENT_COLOUR = colors.HexColor("#7b5ea7")
OUTAGE_COLOUR = colors.HexColor("#f0a030")
WEAK_COLOUR = colors.HexColor("#fde2c4")
GRID_COLOUR = colors.HexColor("#d0d0d0")
FONT = "Helvetica"


class _PathCode:
    """A path's PDF operators, ready for ``Canvas.drawPath`` (which asks a path for its code)."""

    def __init__(self, code: str):
        self.code = code

    def getCode(self) -> str:  # noqa: N802 - reportlab's name
        return self.code


def polyline_code(points: list[float]) -> str:
    """The path operators reportlab writes for a polyline through ``points`` (x0, y0, x1, y1, ...): "n x0 y0 m
    x1 y1 l ...", its numbers formatted by one ``fp_str`` call for all instead of one per point."""
    numbers = fp_str(*points).split(" ")
    operators = ["l"] * (len(numbers) // 2)
    operators[0] = "m"
    words = [""] * (3 * len(operators))
    words[0::3], words[1::3], words[2::3] = numbers[0::2], numbers[1::2], operators
    return "n " + " ".join(words)


class _ChartRenderer(_PDFRenderer):
    """reportlab's PDF renderer, a polyline's path written at once (:func:`polyline_code`): the charts of a
    10 km survey hold some 400 000 points, and a path operator and a number formatting per point took some
    8 % of the PDF's CPU. The page's operators are the same."""

    def drawPolyLine(self, polyline):  # noqa: N802 - reportlab's name
        if self._stroke:
            self._canvas.drawPath(_PathCode(polyline_code(polyline.points)))


class ChartDrawing(Drawing):
    """A Drawing drawn by :class:`_ChartRenderer`."""

    def draw(self, showBoundary=rl_config._unset_):  # noqa: N803 - reportlab's name
        if showBoundary is rl_config._unset_:
            showBoundary = getattr(self, "_showBoundary", rl_config._unset_)
        _ChartRenderer().draw(renderScaledDrawing(self), self.canv, 0, 0, showBoundary=showBoundary)


def decimate_min_max(x: np.ndarray, y: np.ndarray, x_from: float, x_to: float, columns: int) -> np.ndarray:
    """Indices of the points to draw of ``y(x)`` (``x`` increasing) over ``columns`` pixel columns
    of [x_from, x_to]: each column's minimum and maximum and the first and last point, in order.
    Non-finite values are left out (callers break lines there); a short series is kept whole."""
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    finite = np.flatnonzero(np.isfinite(y))
    if finite.size <= 2 * columns:
        return finite
    column = np.clip(((x[finite] - x_from) / (x_to - x_from) * columns).astype(int), 0, columns - 1)
    order = np.lexsort((y[finite], column))  # by column, then by value
    starts = np.searchsorted(column[order], np.arange(columns), side="left")
    stops = np.searchsorted(column[order], np.arange(columns), side="right")
    present = stops > starts
    keep = np.concatenate([order[starts[present]], order[stops[present] - 1], [0, finite.size - 1]])
    return finite[np.unique(keep)]


def line_runs(indices: np.ndarray, y: np.ndarray) -> list[np.ndarray]:
    """Split drawn indices into runs that do not cross a non-finite value of ``y``."""
    if not indices.size:
        return []
    bad = np.cumsum(~np.isfinite(np.asarray(y, dtype=float)))
    breaks = np.flatnonzero(np.diff(bad[indices]) != 0) + 1
    return [run for run in np.split(indices, breaks) if run.size > 1]


def _runs(indices: np.ndarray) -> list[np.ndarray]:
    """Consecutive stretches of sorted indices."""
    return np.split(indices, np.flatnonzero(np.diff(indices) > 1) + 1) if indices.size else []


def nice_step(span: float, target: int) -> float:
    """A 1-2-5 step giving about ``target`` intervals over ``span``."""
    if not span > 0:
        return 1.0
    raw = span / target
    power = 10.0 ** math.floor(math.log10(raw))
    return next(m * power for m in (1.0, 2.0, 5.0, 10.0) if m * power >= raw)


@dataclass(frozen=True)
class Series:
    name: str
    values: np.ndarray


@dataclass(frozen=True)
class Band:
    """A stretch of chainage shaded behind a chart's lines and named in its legend."""

    station_from_m: float
    station_to_m: float
    colour: object
    name: str


@dataclass(frozen=True)
class StripChart:
    """One quantity along chainage: series, tolerance limits, the sleepers of the exceedance
    runs (marked in red along the bottom of the plot) and shaded bands."""

    title: str
    unit: str
    series: tuple[Series, ...]
    limits: tuple[float, float] | None = None
    exceeding: np.ndarray | None = None
    bands: tuple[Band, ...] = ()
    include_zero: bool = False  # the value axis starts at zero (sigmas, magnitudes)
    events: tuple[Band, ...] = ()  # turnouts, level crossings, joints ...: marked along the top edge, named


def section_steps(station_from_m: np.ndarray, station_to_m: np.ndarray, *values: np.ndarray):
    """Per-section values as a step line for :func:`strip_drawing`: (stations, values...) with
    each section's value held from its start to its end (a NaN section breaks the line)."""
    stations = np.column_stack([station_from_m, station_to_m]).ravel()
    return (stations, *(np.repeat(np.asarray(v, dtype=float), 2) for v in values))


def _value_range(chart: StripChart, window: np.ndarray) -> tuple[float, float]:
    finite = [s.values[window][np.isfinite(s.values[window])] for s in chart.series]
    values = np.concatenate(finite) if finite else np.zeros(0)
    low, high = (float(values.min()), float(values.max())) if values.size else (-1.0, 1.0)
    if chart.limits is not None:
        for limit in chart.limits:
            if np.isfinite(limit):
                low, high = min(low, 1.15 * limit if limit < 0 else -0.15 * limit), max(high, 1.15 * limit if limit > 0 else 0.0)
    if chart.include_zero:
        low, high = min(low, 0.0), max(high, 0.0)
    if high - low < 1e-9:
        low, high = low - 1.0, high + 1.0
    pad = 0.05 * (high - low)
    return (0.0 if chart.include_zero and low == 0.0 else low - pad), high + pad


#: (station from, station to, step) -> (station, label) of the x ticks, e.g. round K-chainage.
Ticks = Callable[[float, float, float], list[tuple[float, str]]]


def metre_ticks(station_from: float, station_to: float, step: float) -> list[tuple[float, str]]:
    """Ticks in metres of station."""
    return [(float(t), f"{t:.0f}") for t in np.arange(math.ceil(station_from / step) * step, station_to + 1e-9, step)]


def strip_drawing(chart: StripChart, station_m: np.ndarray, valid: np.ndarray, station_from: float, station_to: float,
                  width: float, height: float, label_axis: bool = True, ticks: Ticks = metre_ticks,
                  axis_title: str = "station (m)") -> Drawing:
    """A chart of ``chart`` over [station_from, station_to] m; x ticks from ``ticks`` (metres of station by
    default, or the survey's K-chainage), the axis titled ``axis_title`` at the left of the tick labels."""
    left, right, bottom, top = 46.0, 8.0, 14.0 if label_axis else 6.0, 14.0
    plot_w, plot_h = width - left - right, height - bottom - top
    drawing = ChartDrawing(width, height)
    window = np.flatnonzero((station_m >= station_from) & (station_m <= station_to))
    low, high = _value_range(chart, window)

    def px(s):
        return left + (np.asarray(s) - station_from) / (station_to - station_from) * plot_w

    def py(v):
        return bottom + (np.asarray(v) - low) / (high - low) * plot_h

    # bands and invalid stretches first, under everything
    for band in chart.bands:
        x0, x1 = (float(np.clip(px(s), left, left + plot_w)) for s in (band.station_from_m, band.station_to_m))
        if x1 > x0:
            drawing.add(Rect(x0, bottom, x1 - x0, plot_h, fillColor=band.colour, strokeColor=None))
    for run in _runs(window[~valid[window]]):
        x0, x1 = px(station_m[run[0]] - 0.3), px(station_m[run[-1]] + 0.3)
        drawing.add(Rect(max(x0, left), bottom, min(x1, left + plot_w) - max(x0, left), plot_h,
                         fillColor=INVALID_COLOUR, strokeColor=None))
    for run in _runs(window[chart.exceeding[window]] if chart.exceeding is not None else np.zeros(0, dtype=int)):
        x0, x1 = px(station_m[run[0]] - 0.3), px(station_m[run[-1]] + 0.3)
        drawing.add(Rect(float(x0), bottom, float(max(x1 - x0, 1.0)), 3.0, fillColor=LIMIT_COLOUR, strokeColor=None))
    for event in chart.events:
        if event.station_to_m < station_from or event.station_from_m > station_to:
            continue
        x0, x1 = (float(np.clip(px(s), left, left + plot_w)) for s in (event.station_from_m, event.station_to_m))
        drawing.add(Rect(x0, bottom + plot_h - 3.0, max(x1 - x0, 1.0), 3.0, fillColor=event.colour, strokeColor=None))
        drawing.add(Line(x0, bottom, x0, bottom + plot_h, strokeColor=event.colour, strokeWidth=0.3))
        drawing.add(String(x0 + 1.5, bottom + plot_h - 9.0, event.name, fontName=font_for(event.name, FONT), fontSize=5.5,
                           fillColor=event.colour))
    # each direction's grid lines are one path (the same strokes): a shape node costs reportlab more than its line
    step = nice_step(high - low, 5)
    grid = _grid_path()
    for tick in np.arange(math.ceil(low / step) * step, high, step):
        y = float(py(tick))
        grid.moveTo(left, y)
        grid.lineTo(left + plot_w, y)
        drawing.add(String(left - 3, y - 2.5, f"{tick:g}", fontName=FONT, fontSize=6.5, textAnchor="end"))
    if grid.points:
        drawing.add(grid)
    x_step = nice_step(station_to - station_from, 10)
    grid = _grid_path()
    for tick, label in ticks(station_from, station_to, x_step):
        x = float(px(tick))
        grid.moveTo(x, bottom)
        grid.lineTo(x, bottom + plot_h)
        if label_axis:
            drawing.add(String(x, bottom - 9, label, fontName=FONT, fontSize=6.5, textAnchor="middle"))
    if grid.points:
        drawing.add(grid)
    if label_axis and axis_title:
        drawing.add(String(left - 17, bottom - 9, axis_title, fontName=font_for(axis_title, FONT), fontSize=6, textAnchor="end",
                           fillColor=colors.HexColor("#555555")))
    if chart.limits is not None:
        for limit in chart.limits:
            if np.isfinite(limit) and low < limit < high:
                y = float(py(limit))
                drawing.add(Line(left, y, left + plot_w, y, strokeColor=LIMIT_COLOUR, strokeWidth=0.6,
                                 strokeDashArray=[3, 2]))
    if low < 0 < high:
        drawing.add(Line(left, float(py(0)), left + plot_w, float(py(0)), strokeColor=colors.grey, strokeWidth=0.4))
    columns = int(plot_w)
    for colour, series in zip(SERIES_COLOURS, chart.series):
        values = series.values[window]
        drawn = decimate_min_max(station_m[window], values, station_from, station_to, columns)
        for run in line_runs(drawn, values):
            points = np.column_stack([px(station_m[window][run]), py(values[run])]).ravel().tolist()
            drawing.add(PolyLine(points, strokeColor=colour, strokeWidth=0.5))
    drawing.add(Rect(left, bottom, plot_w, plot_h, fillColor=None, strokeColor=colors.black, strokeWidth=0.5))
    title = f"{chart.title} ({chart.unit})" if chart.unit else chart.title
    if chart.limits is not None:
        title += "   - - " + t("limit") + ("   " + t("red: exceedances") if chart.exceeding is not None
                                             and chart.exceeding[window].any() else "")
    x = left
    for run, font in font_runs(title, "Helvetica-Bold"):
        drawing.add(String(x, height - 10, run, fontName=font, fontSize=8))
        x += stringWidth(run, font, 8)
    x = left + plot_w
    legend = [(colour, series.name) for colour, series in zip(SERIES_COLOURS, chart.series)] if len(chart.series) > 1 else []
    for colour, name in reversed(legend):
        drawing.add(String(x, height - 10, name, fontName=font_for(name, FONT), fontSize=7, textAnchor="end", fillColor=colour))
        x -= 7 * 0.55 * len(name) + 10
    for band in reversed(chart.bands):
        width_text = 7 * 0.55 * len(band.name)
        drawing.add(Rect(x - width_text - 2, height - 12, width_text + 4, 9, fillColor=band.colour, strokeColor=None))
        drawing.add(String(x, height - 10, band.name, fontName=font_for(band.name, FONT), fontSize=7, textAnchor="end"))
        x -= width_text + 14
    return drawing


def _grid_path() -> Path:
    return Path(strokeColor=GRID_COLOUR, strokeWidth=0.3, fillColor=None)


@dataclass(frozen=True)
class PlanMark:
    east_m: np.ndarray
    north_m: np.ndarray
    colour: object
    name: str


def plan_drawing(east_m: np.ndarray, north_m: np.ndarray, station_m: np.ndarray, width: float, height: float,
                 marks: tuple[PlanMark, ...] = (), highlight: tuple[tuple[np.ndarray, object, str], ...] = ()) -> Drawing:
    """The centreline in plan at one scale for both axes, station ticks, north arrow and scale bar;
    ``highlight`` draws (mask, colour, name) stretches over the line, ``marks`` dots."""
    drawing = ChartDrawing(width, height)
    finite = np.isfinite(east_m) & np.isfinite(north_m)
    if finite.sum() < 2:
        words = t("no coordinates")
        drawing.add(String(10, height / 2, words, fontName=font_for(words, FONT), fontSize=9))
        return drawing
    e0, e1 = east_m[finite].min(), east_m[finite].max()
    n0, n1 = north_m[finite].min(), north_m[finite].max()
    margin = 30.0
    scale = min((width - 2 * margin) / max(e1 - e0, 1.0), (height - 2 * margin) / max(n1 - n0, 1.0))
    ox = margin + (width - 2 * margin - scale * (e1 - e0)) / 2
    oy = margin + (height - 2 * margin - scale * (n1 - n0)) / 2

    def xy(e, n):
        return ox + scale * (np.asarray(e) - e0), oy + scale * (np.asarray(n) - n0)

    # a plan is not a function of x: keep a point per 0.5 pt of drawn length (no peak to lose at this scale)
    stride = max(1, int(len(east_m) / max(1.0, 2 * scale * np.nansum(np.hypot(np.diff(east_m), np.diff(north_m))))))

    def polylines(mask, colour, width_pt):
        index = np.flatnonzero(mask & finite)
        for run in np.split(index, np.flatnonzero(np.diff(index) > 1) + 1) if index.size else []:
            picked = np.unique(np.concatenate([run[::stride], run[-1:]]))
            if picked.size > 1:
                x, y = xy(east_m[picked], north_m[picked])
                drawing.add(PolyLine(np.column_stack([x, y]).ravel().tolist(), strokeColor=colour, strokeWidth=width_pt))

    polylines(np.ones(len(east_m), dtype=bool), SERIES_COLOURS[0], 1.2)
    for mask, colour, _ in highlight:
        polylines(mask, colour, 3.0)
    for mark in marks:
        x, y = xy(mark.east_m, mark.north_m)
        for px_, py_ in zip(np.atleast_1d(x), np.atleast_1d(y)):
            drawing.add(Circle(float(px_), float(py_), 1.8, fillColor=mark.colour, strokeColor=None))
    # station ticks perpendicular to the line
    span = station_m[finite][-1] - station_m[finite][0]
    step = nice_step(span, 8)
    for tick in np.arange(math.ceil(station_m[finite][0] / step) * step, station_m[finite][-1], step):
        k = int(np.clip(np.searchsorted(station_m, tick), 1, len(station_m) - 1))
        if not (finite[k] and finite[k - 1]):
            continue
        de, dn = east_m[k] - east_m[k - 1], north_m[k] - north_m[k - 1]
        norm = math.hypot(de, dn) or 1.0
        x, y = xy(east_m[k], north_m[k])
        nx, ny = -dn / norm, de / norm
        drawing.add(Line(float(x), float(y), float(x + 6 * nx), float(y + 6 * ny), strokeColor=colors.black, strokeWidth=0.6))
        drawing.add(String(float(x + 9 * nx), float(y + 9 * ny) - 2, f"{tick:.0f}", fontName=FONT, fontSize=6.5,
                           textAnchor="start" if nx >= 0 else "end"))
    # north arrow and scale bar
    drawing.add(Line(width - 20, height - 40, width - 20, height - 15, strokeColor=colors.black, strokeWidth=1))
    drawing.add(PolyLine([width - 24, height - 22, width - 20, height - 14, width - 16, height - 22], strokeColor=colors.black))
    drawing.add(String(width - 20, height - 50, "N", fontName="Helvetica-Bold", fontSize=8, textAnchor="middle"))
    bar_m = nice_step((width - 2 * margin) / scale, 5)
    drawing.add(Line(margin, 12, margin + bar_m * scale, 12, strokeColor=colors.black, strokeWidth=2))
    drawing.add(String(margin + bar_m * scale + 4, 9, f"{bar_m:g} m", fontName=FONT, fontSize=7))
    x = width - margin
    for colour, name in [(SERIES_COLOURS[0], t("centreline"))] + [(c, n) for _, c, n in highlight] + \
            [(m.colour, m.name) for m in marks]:
        drawing.add(String(x, 9, name, fontName=font_for(name, FONT), fontSize=7, fillColor=colour, textAnchor="end"))
        x -= 7 * 0.55 * len(name) + 12
    return drawing
