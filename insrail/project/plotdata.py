"""What the GUI's plots show, derived from the result files and the project (pure numpy, no Qt).

The desktop application only draws; every derived value it shows comes from here:

* :func:`plan_data`: trajectory, centreline, GNSS points and outages, benchmarks in the engineering
  plane (E, N metres);
* :func:`navigation_series`: the trajectory's time series with their 1-sigma, in display units;
* :func:`chainage_plots`: which sleepers.csv columns go into which plot along chainage, with the
  tolerance profile's limits in the same units;
* :func:`exceedance_window`: the chainage range to show for one exceedance;
* :func:`stored_ppk`, :func:`quality_epochs`: a PPK solution, its QC report and its epochs by quality
  for the GNSS page;
* :func:`track_data`, :func:`trajectory_views`: everything the views of one survey draw, computed
  off the GUI thread in two steps (the sleepers first: the track view paints before the large
  trajectory file is read);
* :func:`redesign_plot`: the tamping re-design (measured and re-designed track, lift and slew);
* :class:`Envelope`: a band (1-sigma around a series) as min/max per pixel column at any zoom, from a
  pyramid computed once, so a band over millions of epochs draws a few thousand points per frame.
"""

from __future__ import annotations

import re
from collections.abc import Iterable
from dataclasses import dataclass, field

import numpy as np

from insrail.gnss.qc import QUALITY_NAMES
from insrail.io.control import read_benchmarks
from insrail.io.errors import InputError
from insrail.io.formats import read_any
from insrail.io.rtklib import read_rtklib_pos
from insrail.io.tomlfile import read_toml
from insrail.io.types import GnssSolution
from insrail.names import check_name, rail_direction, t
from insrail.nav.earth import Ellipsoid, radii
from insrail.nav.rotation import euler_to_dcm
from insrail.nav.trajectory import Trajectory
from insrail.project.gnss_stage import GNSS_POS_FILE, GNSS_QC_FILE
from insrail.project.model import Project
from insrail.project.sleeper_integrity import said_per_sleeper
from insrail.project.results import (
    RESULTS_FOLDER,
    SUMMARY_FILE,
    ExceedanceRow,
    StoredResults,
)
from insrail.track.events import KIND_NAMES
from insrail.track.tolerance import ToleranceProfile, load_tolerance_profile

#: The plan view's trajectory keeps at most this many epochs (a 10 km survey: one per 0.2 m).
PLAN_POINTS = 50_000
#: Margin shown either side of an exceedance [m]: enough to see the 30 m chord around it.
EXCEEDANCE_MARGIN_M = 20.0


# --------------------------------------------------------------------------- plan view

@dataclass(frozen=True)
class PlanData:
    """Engineering-plane coordinates (E, N in metres) of everything the plan view draws."""

    trajectory_en_m: np.ndarray  # (n, 2) the IMU centre
    centreline_en_m: np.ndarray  # (m, 2) the mean of the two rails at each sleeper
    gnss_en_m: np.ndarray  # (k, 2) GNSS positions used by the fusion (empty if unreadable)
    outages_en_m: tuple[np.ndarray, ...]  # the trajectory during each GNSS gap, (j, 2) each
    benchmark_en_m: np.ndarray  # (b, 2)
    benchmark_ids: tuple[str, ...]


def survey_gnss(project: Project, survey: str) -> GnssSolution:
    """The GNSS solution of one survey, read as the pipeline reads it: the survey's own file, or
    the solution the GNSS stage (PPK) wrote into the results for raw observations."""
    folder = project.resolve(project.survey(survey).folder)
    entry = project.manifest(survey).files.get("gnss")
    if entry is None:
        return read_any(project.folder / RESULTS_FOLDER / survey / GNSS_POS_FILE, "rtklib-pos")
    return entry.read(folder)


def plan_data(project: Project, stored: StoredResults, trajectory: Trajectory,
              gnss: GnssSolution | None) -> PlanData:
    """Everything in the plane; the trajectory thinned to at most ``PLAN_POINTS`` epochs (a line
    in the plane cannot be thinned per pixel column as a time series can, and 2 million epochs
    would cost seconds per frame)."""
    step = max(1, -(-len(trajectory.time_s) // PLAN_POINTS))
    time_s = trajectory.time_s[::step]
    east, north = project.crs.to_plane(trajectory.lat_rad[::step], trajectory.lon_rad[::step])
    track = np.column_stack([east, north])
    columns = stored.columns
    centre = np.column_stack([0.5 * (columns["left_E_m"] + columns["right_E_m"]),
                              0.5 * (columns["left_N_m"] + columns["right_N_m"])])
    if gnss is not None and len(gnss.time_s):
        gnss_en = np.column_stack(project.crs.to_plane(gnss.lat_rad, gnss.lon_rad))
        outages = tuple(track[(time_s >= gap.start_s) & (time_s <= gap.end_s)] for gap in gnss.gaps)
    else:
        gnss_en, outages = np.zeros((0, 2)), ()
    if project.height.benchmarks is not None:
        benchmarks = read_benchmarks(project.resolve(project.height.benchmarks))
        bench_en = np.column_stack(project.crs.to_plane(benchmarks.lat_rad, benchmarks.lon_rad))
        ids = tuple(benchmarks.point_id)
    else:
        bench_en, ids = np.zeros((0, 2)), ()
    return PlanData(track, centre, gnss_en, tuple(o for o in outages if len(o)), bench_en, ids)


# --------------------------------------------------------------------------- navigation time series

@dataclass(frozen=True)
class NavSeries:
    """One plot of the navigation view: ``values`` (n, k) in ``unit``; ``sigma`` the same shape or None;
    ``time_s`` (n,) GPS seconds of week when the series has its own epochs (None: the trajectory's)."""

    key: str
    title: str
    unit: str
    labels: tuple[str, ...]
    values: np.ndarray
    sigma: np.ndarray | None
    time_s: np.ndarray | None = None


def navigation_series(trajectory: Trajectory, ellipsoid: Ellipsoid) -> tuple[NavSeries, ...]:
    """Position (local north/east/up from the first epoch), velocity, attitude with their 1-sigma,
    then the estimated sensor errors (the filter stores no sigma for them)."""
    lat0, lon0, h0 = trajectory.lat_rad[0], trajectory.lon_rad[0], trajectory.height_m[0]
    meridian, normal = radii(lat0, ellipsoid)
    position = np.column_stack([(trajectory.lat_rad - lat0) * (meridian + h0),
                                (trajectory.lon_rad - lon0) * (normal + h0) * np.cos(lat0),
                                trajectory.height_m - h0])
    sigma_position = trajectory.sigma_pos_ned_m  # sigma of down equals sigma of up
    heading = np.unwrap(trajectory.rpy_rad[:, 2])
    attitude = np.rad2deg(np.column_stack([trajectory.rpy_rad[:, :2], heading]))
    ned, rpy = (t("north"), t("east"), t("down")), (t("roll"), t("pitch"), t("heading"))
    degrees_per_hour = np.rad2deg(1.0) * 3600.0
    return (
        NavSeries("position", t("Position from the first epoch"), "m", (t("north"), t("east"), t("up")), position, sigma_position),
        NavSeries("position_sigma", t("Position 1σ"), "mm", ned, 1e3 * sigma_position, None),
        NavSeries("velocity", t("Velocity"), "m/s", ned, trajectory.vel_ned_mps, trajectory.sigma_vel_ned_mps),
        NavSeries("attitude", t("Attitude"), "°", rpy, attitude, np.rad2deg(trajectory.sigma_rpy_rad)),
        NavSeries("attitude_sigma", t("Attitude 1σ"), "°", rpy, np.rad2deg(trajectory.sigma_rpy_rad), None),
        NavSeries("gyro_bias", t("Gyro bias (estimated)"), "°/h", ("x", "y", "z"),
                  degrees_per_hour * trajectory.gyro_bias_radps, None),
        NavSeries("accel_bias", t("Accelerometer bias (estimated)"), "mGal", ("x", "y", "z"),
                  1e5 * trajectory.accel_bias_mps2, None),
        NavSeries("gyro_scale", t("Gyro scale factor (estimated)"), "ppm", ("x", "y", "z"),
                  1e6 * trajectory.gyro_scale, None),
        NavSeries("accel_scale", t("Accelerometer scale factor (estimated)"), "ppm", ("x", "y", "z"),
                  1e6 * trajectory.accel_scale, None),
        NavSeries("odometer_scale", t("Odometer scale factor (estimated)"), "ppm", (t("odometer"),),
                  1e6 * trajectory.odometer_scale[:, None], None),
    )


def gnss_residuals(trajectory: Trajectory, gnss: GnssSolution, imu_to_antenna_m: np.ndarray,
                   ellipsoid: Ellipsoid) -> NavSeries:
    """GNSS position minus the fused antenna position (trajectory + C_b^n lever arm) at the GNSS
    epochs inside the trajectory, north/east/down [mm]: how well the solution agrees with each
    fix (a rejected or float epoch stands out), with the fix's own 1-sigma as the band."""
    fused = trajectory.time_s
    inside = (gnss.time_s >= fused[0]) & (gnss.time_s <= fused[-1])
    time = gnss.time_s[inside]

    def at(values):
        return np.interp(time, fused, values)

    lat, lon, h = at(trajectory.lat_rad), at(trajectory.lon_rad), at(trajectory.height_m)
    c_bn = euler_to_dcm(at(trajectory.rpy_rad[:, 0]), at(trajectory.rpy_rad[:, 1]),
                        at(np.unwrap(trajectory.rpy_rad[:, 2])))
    antenna_ned = c_bn @ np.asarray(imu_to_antenna_m, dtype=float)
    meridian, normal = radii(lat, ellipsoid)
    difference = np.column_stack([(gnss.lat_rad[inside] - lat) * (meridian + h),
                                  (gnss.lon_rad[inside] - lon) * (normal + h) * np.cos(lat),
                                  -(gnss.height_m[inside] - h)]) - antenna_ned
    return NavSeries("gnss_residuals", t("GNSS minus fused antenna position"), "mm", (t("north"), t("east"), t("down")),
                     1e3 * difference, 1e3 * gnss.sigma_ned_m[inside], time)


# --------------------------------------------------------------------------- track view along chainage

@dataclass(frozen=True)
class ChainagePlot:
    """One plot along chainage: curves as (legend label, sleepers.csv column); the column values
    times ``scale`` are in ``unit``; ``lower``/``upper`` tolerance limits in ``unit`` (None: no line)."""

    key: str
    kind: str  # "deviation", "gauge", "cant" or the check's kind (insrail.track.tolerance.KINDS)
    title: str
    unit: str
    curves: tuple[tuple[str, str], ...]
    scale: float = 1.0
    lower: float | None = None
    upper: float | None = None


_CHANNEL = re.compile(r"^(?:_(left|right))?(?:_(lateral|vertical))?_(mm|ratio)$")


def _channels(columns: list[str], check: str) -> list[tuple[str, str]]:
    """(label, column) of the stored channels of one check, e.g. check_versine_10m_left_lateral_mm;
    the label names the rail and direction ("left rail, lateral"; "" for a track channel)."""
    found = []
    prefix = f"check_{check}"
    for column in columns:
        match = _CHANNEL.match(column[len(prefix):]) if column.startswith(prefix) else None
        if match:
            rail, direction, _unit = match.groups()
            found.append((rail_direction(rail or "track", direction or ""), column))
    return found


def _limit(value: float, scale: float) -> float | None:
    return float(value * scale) if np.isfinite(value) else None


def chainage_plots(columns: Iterable[str], profile: ToleranceProfile) -> tuple[ChainagePlot, ...]:
    """The plots of the track view for the columns of a sleepers.csv: deviations, one plot per
    check of the tolerance profile (with its limits), gauge and cant."""
    columns = list(columns)
    rails = tuple(rail_direction(rail, "") for rail in ("left", "right"))
    plots = [
        ChainagePlot("lateral_deviation", "deviation", t("Lateral deviation"), "mm",
                     tuple(zip(rails, ("lateral_deviation_left_mm", "lateral_deviation_right_mm")))),
        ChainagePlot("vertical_deviation", "deviation", t("Vertical deviation"), "mm",
                     tuple(zip(rails, ("vertical_deviation_left_mm", "vertical_deviation_right_mm")))),
    ]
    for check in profile.checks:
        channels = _channels(columns, check.name)
        if not channels:
            continue
        ratio = channels[0][1].endswith("_ratio")
        scale, unit = (1e3, "‰") if ratio else (1.0, "mm")
        limit_scale = 1e3  # limits are in metres or plain ratios; both show x 1000
        plots.append(ChainagePlot(f"check_{check.name}", check.kind, check_name(check), unit,
                                  tuple(channels), scale, _limit(check.lower, limit_scale),
                                  _limit(check.upper, limit_scale)))
    plots.append(ChainagePlot("gauge", "gauge", t("Gauge"), "mm", (("", "gauge_mm"),)))
    plots.append(ChainagePlot("cant", "cant", t("Cant"), "mm", ((t("measured"), "cant_mm"), (t("design"), "design_cant_mm"))))
    return tuple(p for p in plots if all(column in columns for _, column in p.curves))


#: The predicted-accuracy band of the track plots spans +- this many sigma.
BAND_SIGMAS = 3.0


@dataclass(frozen=True)
class QualityBand:
    """The survey's predicted accuracy drawn on one plot: +- ``BAND_SIGMAS`` sigma around zero per
    200 m section, as a step curve (``station_m`` holds each section's start and end; ``half_width``
    the band's half width there, in the plot's unit; 0 where a section has no figure)."""

    station_m: np.ndarray
    half_width: np.ndarray


def quality_bands(plots: Iterable[ChainagePlot], profile: ToleranceProfile, quality) -> dict[str, QualityBand]:
    """The bands of the plots that have a predicted accuracy (``quality``: StoredResults.quality,
    None for results without one): the deviations take the absolute lateral / vertical position
    sigma; the 30 m/5 m and 300 m/150 m checks the sigma of the 5 m and 150 m lag differences
    behind them (the larger of lateral and vertical where a plot shows both)."""
    if quality is None or not len(quality):
        return {}
    lag_of_pair = {5.0: "lag5", 150.0: "lag150"}
    figures = {"lateral_deviation": ("sigma_lateral_mm",), "vertical_deviation": ("sigma_vertical_mm",)}
    for check in profile.checks:
        lag = lag_of_pair.get(check.pair_m) if check.kind == "differential_versine" else None
        if lag is not None:
            figures[f"check_{check.name}"] = tuple(f"sigma_{lag}_{d}_mm" for d in check.directions)
    station = np.column_stack([quality.station_from_m, quality.station_to_m]).ravel()
    bands = {}
    for plot in plots:
        if plot.key in figures and plot.unit == "mm":
            sigma = np.max([getattr(quality, name) for name in figures[plot.key]], axis=0)
            half = np.repeat(np.nan_to_num(BAND_SIGMAS * sigma, nan=0.0), 2)
            bands[plot.key] = QualityBand(station, half)
    return bands


def nearest_sleeper(station_m: np.ndarray, station: float) -> int:
    """Row of the sleeper nearest to ``station`` [m] (``station_m`` sorted, not empty)."""
    i = int(np.clip(np.searchsorted(station_m, station), 1, max(len(station_m) - 1, 1)))
    return i - 1 if len(station_m) < 2 or abs(station_m[i - 1] - station) <= abs(station_m[i] - station) else i


def plot_values(plot: ChainagePlot, columns: dict[str, np.ndarray], row: int) -> tuple[tuple[str, float], ...]:
    """(label, value in the plot's unit) of each curve of ``plot`` at sleeper ``row``."""
    return tuple((label, float(plot.scale * columns[column][row])) for label, column in plot.curves)


_SLEEPER = re.compile(r"^(?:#|sleeper\s*|no\.?\s*)(\d+)$", re.IGNORECASE)
_K_CHAINAGE = re.compile(r"^([A-Z]*)K(\d+)\+(\d+(?:\.\d*)?)$", re.IGNORECASE)


def _k_value(text: str) -> tuple[str, float] | None:
    match = _K_CHAINAGE.match(text.replace(" ", ""))
    return None if match is None else (match.group(1).upper(), 1000.0 * int(match.group(2)) + float(match.group(3)))


def locate(text: str, station_m: np.ndarray, number: np.ndarray, label) -> int | None:
    """The sleeper row a surveyor means by ``text``: "#123" or "sleeper 123" (its number), a
    K-chainage as printed on the sleepers ("K1+234.5", "DK12+300": the sleeper whose printed
    chainage is nearest, so broken chainage is honoured), or a station in metres ("1234.5").
    None when nothing matches (an unknown number, a chainage outside the survey, not a chainage)."""
    text = text.strip()
    if not text or not len(station_m):
        return None
    sleeper = _SLEEPER.match(text)
    if sleeper is not None:
        rows = np.flatnonzero(np.asarray(number) == int(sleeper.group(1)))
        return int(rows[0]) if len(rows) else None
    wanted = _k_value(text)
    if wanted is not None:
        prefix, value = wanted
        printed = [_k_value(str(name)) for name in label]
        candidates = [(abs(v - value), row) for row, k in enumerate(printed) if k is not None
                      for p, v in (k,) if p == prefix or not prefix]
        if not candidates:
            return None
        distance, row = min(candidates)
        return row if distance <= _spacing(station_m) else None
    try:
        station = float(text)
    except ValueError:
        return None
    row = nearest_sleeper(station_m, station)
    return row if abs(station_m[row] - station) <= _spacing(station_m) else None


def _spacing(station_m: np.ndarray) -> float:
    """A sleeper spacing and a half (how far from a sleeper a chainage still means it)."""
    return 1.5 * float(np.median(np.diff(station_m))) if len(station_m) > 1 else 1.0


def exceedance_window(station_from_m: float, station_to_m: float,
                      margin_m: float = EXCEEDANCE_MARGIN_M) -> tuple[float, float]:
    """Chainage range [m] that shows an exceedance with some track either side."""
    low, high = sorted((station_from_m, station_to_m))
    return low - margin_m, high + margin_m


# --------------------------------------------------------------------------- bands at screen resolution

#: The coarsest bins the pyramid stores hold 2**FIRST_LEVEL samples; finer views slice the series
#: itself (at most 2**FIRST_LEVEL samples per pixel column), so the pyramid costs a quarter of it.
FIRST_LEVEL = 3


@dataclass(frozen=True)
class Envelope:
    """A band ``low..high`` over ``x`` (sorted, one contiguous run: no gap inside) ready to be drawn at
    screen resolution: :meth:`visible` returns, for a range of ``x`` and a number of pixel columns,
    one or two points per column whose band covers every sample (min of ``low``, max of
    ``high`` per bin). Level k of ``levels`` holds bins of 2**(FIRST_LEVEL + k) samples as
    (x at the bin's middle, min low, max high)."""

    x: np.ndarray
    low: np.ndarray
    high: np.ndarray
    levels: tuple[tuple[np.ndarray, np.ndarray, np.ndarray], ...]

    @classmethod
    def of(cls, x: np.ndarray, low: np.ndarray, high: np.ndarray) -> Envelope:
        x, low, high = (np.asarray(a, dtype=float) for a in (x, low, high))
        levels = []
        bx, blow, bhigh = x, low, high
        level = 0
        while len(bx) > 2:
            odd = len(bx) % 2
            if odd:  # pair the last sample with itself
                bx, blow, bhigh = (np.append(a, a[-1]) for a in (bx, blow, bhigh))
            bx = 0.5 * (bx[0::2] + bx[1::2])
            blow = np.fmin(blow[0::2], blow[1::2])
            bhigh = np.fmax(bhigh[0::2], bhigh[1::2])
            level += 1
            if level >= FIRST_LEVEL:
                levels.append((bx, blow, bhigh))
        return cls(x, low, high, tuple(levels))

    def visible(self, x_from: float, x_to: float, columns: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(x, low, high) covering ``x_from..x_to`` (one sample beyond each end, so the band reaches
        the edges) with one or two points per pixel column of ``columns`` (more only when zoomed
        in so far that every sample is returned)."""
        first = max(int(np.searchsorted(self.x, x_from, side="left")) - 1, 0)
        last = min(int(np.searchsorted(self.x, x_to, side="right")) + 1, len(self.x))
        count = last - first
        per_column = count / max(columns, 1)
        if per_column <= 2 ** FIRST_LEVEL or not self.levels:
            return self.x[first:last], self.low[first:last], self.high[first:last]
        k = min(max(int(np.floor(np.log2(per_column))) - FIRST_LEVEL, 0), len(self.levels) - 1)
        shift = FIRST_LEVEL + k
        bx, blow, bhigh = self.levels[k]
        start, stop = first >> shift, min((last >> shift) + 1, len(bx))
        return bx[start:stop], blow[start:stop], bhigh[start:stop]


def envelopes(x: np.ndarray, low: np.ndarray, high: np.ndarray, breaks: np.ndarray | None = None,
              ) -> tuple[Envelope, ...]:
    """One :class:`Envelope` per contiguous run of ``x``; ``breaks`` (bool, one per sample) marks the
    last sample before a gap (a series drawn with no line across its gaps)."""
    if breaks is None or not np.any(breaks[:-1]):
        return (Envelope.of(x, low, high),)
    ends = np.flatnonzero(breaks[:-1]) + 1
    return tuple(Envelope.of(*parts) for parts in zip(np.split(x, ends), np.split(low, ends), np.split(high, ends))
                 if len(parts[0]))


def gap_breaks(time_s: np.ndarray) -> np.ndarray:
    """True at the last epoch before a gap of more than 3 median steps (a GNSS outage): the
    navigation view draws no line and no band across it."""
    step = np.diff(time_s)
    if len(step) < 2:
        return np.zeros(len(time_s), bool)
    return np.append(step > 3.0 * np.median(step), True)


# --------------------------------------------------------------------------- one survey's views

@dataclass(frozen=True)
class EventSpan:
    """An event of the survey drawn along the chainage plots (a point event has from = to)."""

    station_from_m: float
    station_to_m: float
    name: str  # "turnout W12", "level crossing LC 3"
    not_assessed: bool  # its sleepers are left out of the assessment (greyed)


#: an invalid sleeper's shading reaches this far either side of it [m] (about half a sleeper spacing, as in the
#: PDF's charts: a single invalid sleeper stays visible)
INVALID_PAD_M = 0.3


def invalid_spans(station_m: np.ndarray, valid: np.ndarray) -> tuple[tuple[float, float], ...]:
    """(from, to) [m] of each run of sleepers that are not valid (not assessed: the fusion cannot vouch for them,
    no design there, ...), widened by :data:`INVALID_PAD_M`; the reports grey the same runs."""
    bad = np.flatnonzero(~np.asarray(valid, dtype=bool))
    if not bad.size:
        return ()
    breaks = np.flatnonzero(np.diff(bad) > 1)
    first, last = np.concatenate([bad[:1], bad[breaks + 1]]), np.concatenate([bad[breaks], bad[-1:]])
    return tuple((float(station_m[a]) - INVALID_PAD_M, float(station_m[b]) + INVALID_PAD_M) for a, b in zip(first, last))


def event_spans(summary: dict) -> tuple[EventSpan, ...]:
    """The events processing placed on the chainage (summary.toml's ``[[events]]``)."""
    return tuple(EventSpan(e["station_from_m"], e["station_to_m"], f"{t(KIND_NAMES[e['kind']])} {e['text']}".strip(),
                           bool(e["not_assessed"])) for e in summary.get("events", []))


@dataclass(frozen=True)
class RedesignPlot:
    """What the re-design view draws for one survey (``insrail redesign``'s files): the measured
    track and the track after the job (deviations from the design, the mean of the two rails [mm]),
    the lift of each rail and the slew per sleeper [mm], the fixed stretches and the marks."""

    survey: str
    station_m: np.ndarray
    measured_mm: dict[str, np.ndarray]  # "vertical", "lateral"
    after_mm: dict[str, np.ndarray]
    lift_left_mm: np.ndarray
    lift_right_mm: np.ndarray
    slew_mm: np.ndarray
    fixed: tuple[tuple[float, float, str], ...]  # (from, to, where it came from)
    marks: tuple[tuple[float, str], ...]  # (station, TS/SC/CS/ST/PVI)
    profile: str
    largest_lift_mm: float
    largest_slew_mm: float
    exceedances_before: int
    exceedances_after: int
    cannot_pass: int
    uncertain: int  # stretches passing by less than the survey's uncertainty (redesign/summary.toml)
    not_assessed: int  # checks the survey cannot assess after the job


def redesign_plot(stored: StoredResults) -> RedesignPlot | None:
    """The survey's re-design as the view draws it (None: not re-designed since it was processed)."""
    from insrail.export.tamping import read_tamping
    from insrail.project.redesign import REDESIGN_FOLDER, SUMMARY_FILE as REDESIGN_SUMMARY, TAMPING_FILE

    folder = stored.folder / REDESIGN_FOLDER
    if not (folder / REDESIGN_SUMMARY).is_file():
        return None
    summary = read_toml(folder / REDESIGN_SUMMARY)
    table = read_tamping(folder / TAMPING_FILE)
    sleeper = np.array([mark == "" for mark in table.mark])
    station = stored.columns["station_m"]
    amount = {name: np.interp(station, table.station_m[sleeper], values[sleeper], left=np.nan, right=np.nan)
              for name, values in table.values.items()}
    measured = {direction: np.nanmean(np.column_stack([stored.columns[f"{direction}_deviation_{rail}_mm"]
                                                        for rail in ("left", "right")]), axis=1)
                for direction in ("vertical", "lateral")}
    after = {"vertical": measured["vertical"] + 0.5 * (amount["lift_left"] + amount["lift_right"]),
             "lateral": measured["lateral"] + amount["slew"]}
    marks = tuple((float(s), mark) for s, mark in zip(table.station_m, table.mark)
                  if mark and not mark.startswith("fixed"))
    movement, count = summary["movement"], summary["exceedances"]
    return RedesignPlot(stored.survey, station, measured, after, amount["lift_left"], amount["lift_right"],
                        amount["slew"], tuple((f["from_m"], f["to_m"], f["source"]) for f in summary["settings"]["fixed"]),
                        marks, summary["profile"], movement["largest_lift_mm"], movement["largest_slew_mm"],
                        count["before"], count["after"], len(summary["cannot_pass"]), len(summary.get("uncertain", [])),
                        len(summary.get("not_assessed", [])))


@dataclass(frozen=True)
class TrackData:
    """What the track view draws for one survey (arrays one per sleeper, in chainage order)."""

    survey: str
    station_m: np.ndarray
    number: np.ndarray
    label: tuple[str, ...]
    columns: dict[str, np.ndarray]
    plots: tuple[ChainagePlot, ...]
    exceedances: tuple[ExceedanceRow, ...]
    bands: dict[str, QualityBand]
    events: tuple[EventSpan, ...] = ()
    redesign: RedesignPlot | None = None  # the tamping re-design, if the survey has one
    invalid: tuple[tuple[float, float], ...] = ()  # the runs of sleepers not valid (:func:`invalid_spans`)
    not_assessed: tuple[str, ...] = ()  # per sleeper, why it is not assessed, in the language in use ("": it is)


def track_data(project: Project, stored: StoredResults) -> TrackData:
    profile = load_tolerance_profile(project.resource(project.tolerance_profile))
    plots = chainage_plots(stored.columns, profile)
    return TrackData(stored.survey, stored.columns["station_m"], stored.number, stored.label, stored.columns,
                     plots, stored.exceedances, quality_bands(plots, profile, stored.quality),
                     event_spans(stored.summary), redesign_plot(stored),
                     invalid_spans(stored.columns["station_m"], stored.columns["valid"] > 0),
                     said_per_sleeper(stored.not_assessed or ("",) * len(stored.number), stored.summary))


@dataclass(frozen=True)
class TrajectoryViews:
    """What the plan and navigation views draw for one survey; ``bands`` the navigation series'
    1-sigma envelopes (by series key, one tuple of runs per component), ``lines`` the series
    themselves as envelopes (drawn at screen resolution); ``warnings`` what could not be shown and why."""

    survey: str
    plan: PlanData
    time_s: np.ndarray
    series: tuple[NavSeries, ...]
    bands: dict[str, tuple[tuple[Envelope, ...], ...]]
    warnings: tuple[str, ...] = ()
    lines: dict[str, tuple[tuple[Envelope, ...], ...]] = field(default_factory=dict)


def series_bands(time_s: np.ndarray, series: Iterable[NavSeries]) -> dict[str, tuple[tuple[Envelope, ...], ...]]:
    """The 1-sigma envelope of every component of the series that have a sigma."""
    return _series_envelopes(time_s, [s for s in series if s.sigma is not None],
                             lambda s, k: (s.values[:, k] - s.sigma[:, k], s.values[:, k] + s.sigma[:, k]))


def series_lines(time_s: np.ndarray, series: Iterable[NavSeries]) -> dict[str, tuple[tuple[Envelope, ...], ...]]:
    """Every component of every series as an envelope of itself: the curve drawn at screen resolution."""
    return _series_envelopes(time_s, series, lambda s, k: (s.values[:, k], s.values[:, k]))


def _series_envelopes(time_s: np.ndarray, series: Iterable[NavSeries], low_high) -> dict[str, tuple[tuple[Envelope, ...], ...]]:
    """Per series key, per component, the envelopes of ``low_high(series, component)`` (no run across a
    gap in a series' own epochs)."""
    found = {}
    for s in series:
        time = time_s if s.time_s is None else s.time_s
        breaks = gap_breaks(time) if s.time_s is not None else None
        found[s.key] = tuple(envelopes(time, *low_high(s, k), breaks) for k in range(s.values.shape[1]))
    return found


def trajectory_views(project: Project, stored: StoredResults) -> TrajectoryViews:
    """Reads the trajectory (the large file) and derives the plan and navigation series from it."""
    trajectory = stored.trajectory()
    warnings = []
    try:
        gnss = survey_gnss(project, stored.survey)
    except (InputError, KeyError) as error:
        warnings.append(f"GNSS points not shown: {error}")
        gnss = None
    ellipsoid = project.crs.reference_ellipsoid
    series = navigation_series(trajectory, ellipsoid)
    if gnss is not None:
        trolley = project.trolley() or project.manifest(stored.survey).trolley
        series += (gnss_residuals(trajectory, gnss, trolley.imu_to_antenna_m, ellipsoid),)
    return TrajectoryViews(stored.survey, plan_data(project, stored, trajectory, gnss), trajectory.time_s, series,
                           series_bands(trajectory.time_s, series), tuple(warnings),
                           series_lines(trajectory.time_s, series))


__all__ = [
    "BAND_SIGMAS",
    "EXCEEDANCE_MARGIN_M",
    "ChainagePlot",
    "Envelope",
    "NavSeries",
    "PlanData",
    "PpkView",
    "QualityBand",
    "TrackData",
    "TrajectoryViews",
    "chainage_plots",
    "envelopes",
    "exceedance_window",
    "gap_breaks",
    "gnss_residuals",
    "locate",
    "navigation_series",
    "nearest_sleeper",
    "plan_data",
    "plot_values",
    "quality_bands",
    "quality_epochs",
    "series_bands",
    "series_lines",
    "stored_ppk",
    "survey_gnss",
    "track_data",
    "trajectory_views",
]


# --------------------------------------------------------------------------- GNSS page (PPK)

@dataclass(frozen=True)
class PpkView:
    """A PPK solution as the GNSS page shows it.

    report : the GNSS stage's QC report (``gnss_qc.toml``: ``base``, ``warnings``, ``baseline_m``, ``qc``)
    fusion : ``[ppk]`` of summary.toml once the survey is processed (what the fusion did with each
             quality), else None
    """

    report: dict
    solution: GnssSolution
    fusion: dict | None = None


def stored_ppk(project: Project, survey: str) -> PpkView | None:
    """The PPK solution and QC in a processed survey's results; None when it has none."""
    folder = project.folder / RESULTS_FOLDER / survey
    if not (folder / GNSS_QC_FILE).is_file():
        return None
    summary = read_toml(folder / SUMMARY_FILE) if (folder / SUMMARY_FILE).is_file() else {}
    return PpkView(read_toml(folder / GNSS_QC_FILE), read_rtklib_pos(folder / GNSS_POS_FILE), summary.get("ppk"))


def quality_epochs(solution: GnssSolution) -> tuple[tuple[int, str, np.ndarray], ...]:
    """(RTKLIB quality flag, its name, epoch times [s]) of each quality present, best first."""
    quality = np.asarray(solution.quality)
    return tuple((int(q), QUALITY_NAMES.get(int(q), f"quality {int(q)}"), solution.time_s[quality == q])
                 for q in np.unique(quality))
