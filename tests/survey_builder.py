"""User-style survey projects from factor levels, and their accuracy against the simulator's truth.

A test of the configuration matrix (``tests/test_config_matrix.py``) picks one level of every factor
(:data:`FACTORS`), ``build_cell`` simulates a short run (insrail's simulator, about 300 m) and writes
from its files a project the way a surveyor writes one from docs/formats.md: raw files in the
documented user forms (no insrail ``# format:`` headers, an RTKLIB .pos in calendar time) and a
``survey.toml`` / ``project.toml`` typed out here with only the keys the documentation requires for
that set-up (never insrail's own writers, which fill every key). ``truth_errors`` then compares the
processed ``sleepers.csv`` with ``truth/sleepers.csv``: each measured rail point is projected onto the
true rail's polyline (plan), which gives its lateral and vertical error and its true station, and
the 30 m/5 m check is applied to those error series (for small errors the check of the measurement
minus the check of the truth is the check of the error).

To add a factor: a new entry in FACTORS, its effect in ``scenario`` (what is simulated) and in
``survey_toml`` / ``project_toml`` / ``write_raw_files`` (what the user writes).
"""

from __future__ import annotations

import datetime
import math
import shutil
from dataclasses import dataclass, fields, replace
from pathlib import Path

import numpy as np
import shared_build
from scipy.spatial import cKDTree

from insrail.io.survey import TrolleyGeometry
from insrail.sim.scenario import INF, DesignSpec, GnssSpec, MotionSpec, PrismSpec, ScenarioConfig, preset
from insrail.sim.simulate import height_anomaly, simulate

#: Every factor and its levels; the first level is the usual one.
FACTORS: dict[str, tuple[str, ...]] = {
    "imu": ("nav", "tactical", "tactical_fog", "mems", "mems_handheld"),
    "position": ("rtklib-pos", "kfgins-gnss", "prism", "gnss+prism"),
    "ellipsoid": ("CGCS2000", "WGS84", "Xian80", "Krassovsky", "custom"),
    "design": ("csv", "landxml", "fitted"),
    "direction": ("with", "against"),
    # the gauge record is required by `insrail process` (test_config_matrix's own test), not a level here
    "left_out": ("none", "sleepers", "odometer"),
    "trolley": ("minimal", "calibrated"),
}

#: The line: a right-hand curve (R 1500 m, 60 m clothoids, 100 mm cant ramped on them) between straights and a
#: crest vertical curve; the run starts and ends on the straights, as the line-type fit needs (420 m).
DESIGN = DesignSpec(
    start_east_m=512340.0, start_north_m=3374210.0, start_azimuth_deg=32.0, start_station_m=1000.0,
    horizontal=(("line", 120.0), ("clothoid", 60.0, INF, 1500.0, "right"), ("arc", 100.0, 1500.0, "right"),
                ("clothoid", 60.0, 1500.0, INF, "right"), ("line", 120.0)),
    pvis=((1000.0, 28.40, 0.0), (1230.0, 29.55, 20000.0), (1460.0, 28.97, 0.0)),
    cant=((1000.0, 0.0), (1120.0, 0.0), (1180.0, 0.100), (1280.0, 0.100), (1340.0, 0.0), (1460.0, 0.0)),
)
FIRST_STATION_M = 1020.0
LAST_STATION_M = 1440.0
#: Total-station fixes of the prism every 60 m (CPIII pairs), at both ends during the static start and end.
PRISM_STATIONS_M = tuple(float(s) for s in np.arange(FIRST_STATION_M, LAST_STATION_M + 1.0, 60.0))
#: A custom ellipsoid (no named one): the `custom` level's a and 1/f.
CUSTOM_ELLIPSOID = {"a_m": 6378160.0, "inverse_flattening": 298.25}
SURVEY_NAME = "run1"
#: The position level of a relative survey (no GNSS, no prism: IMU, odometer and stops; not one of the
#: matrix's FACTORS, its own tests build it): a stop of RELATIVE_STOP_S every RELATIVE_STOP_SPACING_M (seed 000)
RELATIVE = "none"
RELATIVE_STOP_SPACING_M = 60.0
RELATIVE_STOP_S = 10.0


@dataclass(frozen=True)
class Cell:
    """One level of every factor (see FACTORS)."""

    imu: str
    position: str
    ellipsoid: str
    design: str
    direction: str
    left_out: str
    trolley: str

    @property
    def cell_id(self) -> str:
        return "-".join(getattr(self, f.name) for f in fields(self))

    @property
    def gnss(self) -> bool:
        return self.position not in ("prism", RELATIVE)

    @property
    def prism(self) -> bool:
        return "prism" in self.position

    def has(self, sensor: str) -> bool:
        """Whether the optional sensor (gauge, sleepers, odometer) is in the survey."""
        return self.left_out != sensor


def trolley_geometry(level: str) -> TrolleyGeometry:
    """`minimal`: zero mounting angles and the left reference rail, so the survey.toml leaves out every
    key that has a default; `calibrated`: the trolley's measured mounting angles and the right rail."""
    if level == "minimal":
        return TrolleyGeometry(
            imu_to_antenna_m=np.array([0.02, 0.18, -1.35]), imu_to_odometer_m=np.array([0.45, -0.60, 0.31]),
            imu_to_prism_m=np.array([0.02, 0.18, -1.52]), imu_to_sleeper_detector_m=np.array([0.30, -0.45, 0.22]),
            imu_to_reference_rail_m=np.array([0.10, -0.60, 0.31]), reference_rail="left",
            mounting_rpy_rad=np.zeros(3), rail_centre_spacing_m=1.5)
    return TrolleyGeometry(
        imu_to_antenna_m=np.array([-0.05, 0.25, -1.30]), imu_to_odometer_m=np.array([0.40, 0.84, 0.31]),
        imu_to_prism_m=np.array([-0.05, 0.25, -1.48]), imu_to_sleeper_detector_m=np.array([0.25, 0.70, 0.22]),
        imu_to_reference_rail_m=np.array([0.05, 0.84, 0.31]), reference_rail="right",
        mounting_rpy_rad=np.deg2rad([0.05, -0.08, 0.12]), rail_centre_spacing_m=1.5)


def crs_settings(ellipsoid: str) -> dict:
    """The engineering CRS of the simulated line (TM, CM 114.3°, projection height 30 m) on the ellipsoid."""
    crs = dict(preset("short").geodetic.crs, ellipsoid=ellipsoid)
    if ellipsoid == "custom":
        crs |= CUSTOM_ELLIPSOID
    return crs


def scenario(cell: Cell) -> ScenarioConfig:
    """What is simulated for the cell: a 420 m run of DESIGN with a 60 s static start."""
    base = preset("short")
    return replace(
        base,
        name=f"matrix-{cell.cell_id}",
        design=DESIGN,
        motion=MotionSpec(start_station_m=FIRST_STATION_M, end_station_m=LAST_STATION_M, static_start_s=60.0,
                          static_end_s=20.0, reverse=cell.direction == "against",
                          stops=relative_stops() if cell.position == RELATIVE else ()),
        gnss=GnssSpec(),
        prism=PrismSpec(stations_m=PRISM_STATIONS_M if cell.prism else ()),
        geodetic=replace(base.geodetic, crs=crs_settings(cell.ellipsoid)),
        trolley=trolley_geometry(cell.trolley),
        imu_profile=cell.imu,
    )


def relative_stops() -> tuple[tuple[float, float], ...]:
    """The stops of a relative survey: every RELATIVE_STOP_SPACING_M between the run's ends."""
    inner = np.arange(FIRST_STATION_M + RELATIVE_STOP_SPACING_M, LAST_STATION_M - 1.0, RELATIVE_STOP_SPACING_M)
    return tuple((float(s), RELATIVE_STOP_S) for s in inner)


# --- raw files as a user has them ------------------------------------------------------------

def _table(path: Path) -> np.ndarray:
    return np.loadtxt(path, comments=("#", "%"), ndmin=2)


def _gpst_calendar(week: np.ndarray, tow: np.ndarray) -> list[str]:
    epoch = datetime.datetime(1980, 1, 6)
    out = []
    for w, t in zip(week, tow):
        stamp = epoch + datetime.timedelta(weeks=int(w), seconds=float(t))
        out.append(stamp.strftime("%Y/%m/%d %H:%M:%S.") + f"{stamp.microsecond // 1000:03d}")
    return out


def _savetxt(path: Path, values: np.ndarray, fmt: str | list[str]) -> None:
    """np.savetxt's bytes (``fmt``: one row's format, or one format per column joined by spaces), formatted a block
    of rows at a time with one ``%`` (np.savetxt formats row by row: most of a cell's file writing)."""
    values = np.asarray(values, dtype=np.float64).reshape(len(values), -1)
    row = (fmt if isinstance(fmt, str) else " ".join(fmt)) + "\n"
    with open(path, "w") as handle:
        for start in range(0, len(values), 50_000):
            block = values[start:start + 50_000]
            handle.write((row * len(block)) % tuple(block.ravel().tolist()))


def write_raw_files(cell: Cell, simulated: Path, survey: Path) -> dict[str, tuple[str, str]]:
    """The cell's raw files in ``survey`` from the simulator's folder; returns {role: (file, format)}."""
    survey.mkdir(parents=True)
    files: dict[str, tuple[str, str]] = {}
    imu = np.load(simulated / "imu.npy")
    # KF-GINS text as KF-GINS writes it: no header, no week
    _savetxt(survey / "imu.txt", np.column_stack([imu["time_s"], imu["dtheta_rad"], imu["dvel_mps"]]),
               fmt=["%.9f"] + ["%.16e"] * 6)
    files["imu"] = ("imu.txt", "kfgins-imu")
    if cell.gnss:
        pos = _table(simulated / "gnss.pos")  # week tow lat lon h Q ns sdn sde sdu sdne sdeu sdun age ratio
        if cell.position == "kfgins-gnss":
            _savetxt(survey / "gnss.txt", pos[:, [1, 2, 3, 4, 7, 8, 9]], fmt="%.9f %.11f %.11f %.4f %.4f %.4f %.4f")
            files["gnss"] = ("gnss.txt", "kfgins-gnss")
        else:  # RTKLIB's own layout: calendar GPST, its header lines
            with open(survey / "gnss.pos", "w") as handle:
                handle.write("% program   : RTKPOST ver.2.4.3 b34\n% pos mode  : kinematic\n"
                             "%  GPST                  latitude(deg) longitude(deg)  height(m)   Q  ns   sdn(m)   "
                             "sde(m)   sdu(m)  sdne(m)  sdeu(m)  sdun(m) age(s)  ratio\n")
                for stamp, row in zip(_gpst_calendar(pos[:, 0], pos[:, 1]), pos):
                    handle.write(f"{stamp} {row[2]:14.9f} {row[3]:14.9f} {row[4]:10.4f} {int(row[5]):3d} "
                                 f"{int(row[6]):3d} {row[7]:8.4f} {row[8]:8.4f} {row[9]:8.4f}   0.0000   0.0000   "
                                 f"0.0000   0.00 {row[14]:6.1f}\n")
            files["gnss"] = ("gnss.pos", "rtklib-pos")
    if cell.prism:
        rows = [line.split() for line in (simulated / "prism.txt").read_text().splitlines()
                if line.strip() and not line.startswith("#")]
        (survey / "prism.txt").write_text("t E N H sigma id\n" + "".join(" ".join(r) + "\n" for r in rows))
        files["prism"] = ("prism.txt", "prism-enu")
    if cell.gnss and cell.prism:  # GNSS heights are ellipsoidal, the prism's normal: a height model is needed
        bench = [line.split() for line in (simulated / "benchmarks.txt").read_text().splitlines()
                 if line.strip() and not line.startswith("#")]
        (survey / "benchmarks.txt").write_text("id,lat,lon,h,H\n" + "".join(",".join(r) + "\n" for r in bench))
    if cell.has("odometer"):
        odo = _table(simulated / "odometer.txt")
        _savetxt(survey / "odometer.txt", odo, fmt="%.3f %.3f")
        files["odometer"] = ("odometer.txt", "odometer-distance")
    if cell.has("gauge"):
        _savetxt(survey / "gauge.txt", _table(simulated / "gauge.txt"), fmt="%.3f %.2f")
        files["gauge"] = ("gauge.txt", "gauge-mm")
    if cell.has("sleepers"):
        _savetxt(survey / "sleepers.txt", _table(simulated / "sleepers.txt")[:, 0], fmt="%.4f")
        files["sleepers"] = ("sleepers.txt", "sleeper-times")
    return files


# --- survey.toml and project.toml, typed out from docs/formats.md ------------------------------

def _vector(v) -> str:
    return "[" + ", ".join(f"{x:.4f}" for x in v) + "]"


def survey_toml(cell: Cell, files: dict[str, tuple[str, str]]) -> str:
    """Only the keys docs/formats.md requires for these files (lever arms only with the data using them)."""
    geometry = trolley_geometry(cell.trolley)
    lines = ["[survey]", f'name = "{SURVEY_NAME}"', f'imu_profile = "{cell.imu}"', ""]
    for role, (path, fmt) in files.items():
        lines += [f"[files.{role}]", f'path = "{path}"', f'format = "{fmt}"', ""]
    lines += ["[trolley]", f"imu_to_reference_rail_m = {_vector(geometry.imu_to_reference_rail_m)}"]
    for key, role in (("imu_to_antenna_m", "gnss"), ("imu_to_odometer_m", "odometer"), ("imu_to_prism_m", "prism"),
                      ("imu_to_sleeper_detector_m", "sleepers")):
        if role in files:
            lines.append(f"{key} = {_vector(getattr(geometry, key))}")
    if cell.trolley == "calibrated":
        lines += [f'reference_rail = "{geometry.reference_rail}"',
                  f"mounting_rpy_deg = {_vector(np.degrees(geometry.mounting_rpy_rad))}"]
    return "\n".join(lines) + "\n"


def project_toml(cell: Cell, config: ScenarioConfig) -> str:
    """``[[surveys]]``, ``[geodesy.crs]`` (the default ellipsoid CGCS2000 left out) and what ``[track]`` needs."""
    crs = config.geodetic.crs
    lines = ["[[surveys]]", f'name = "{SURVEY_NAME}"', 'folder = "survey"', "", "[geodesy.crs]"]
    if cell.ellipsoid != "CGCS2000":
        lines.append(f'ellipsoid = "{cell.ellipsoid}"')
    if cell.ellipsoid == "custom":
        lines += [f"a_m = {CUSTOM_ELLIPSOID['a_m']}", f"inverse_flattening = {CUSTOM_ELLIPSOID['inverse_flattening']}"]
    lines += [f"central_meridian_deg = {crs['central_meridian_deg']}",
              f"projection_height_m = {crs['projection_height_m']}", ""]
    if cell.gnss and cell.prism:
        lines += ["[geodesy.height]", 'benchmarks = "survey/benchmarks.txt"', ""]
    lines.append("[track]")
    if cell.position == RELATIVE and cell.design != "fitted":  # where on the design the relative run starts
        lines.append(f"start_station_m = {LAST_STATION_M if cell.direction == 'against' else FIRST_STATION_M}")
    if cell.design == "csv":
        lines.append('design = "design.csv"')
    elif cell.design == "landxml":
        lines.append('design = "design.xml"')
    elif cell.direction == "with":
        lines.append(f"start_station_m = {FIRST_STATION_M}")
    else:  # stations grow against the run: towards the line's bearing, from the far end where the run starts
        azimuth = config.design.start_azimuth_deg
        lines += [f"start_station_m = {LAST_STATION_M}", f"stationing_direction = {azimuth + 4.0}"]
    return "\n".join(lines) + "\n"


@dataclass(frozen=True)
class BuiltCell:
    project: Path
    truth: Path  # the simulator's truth/ folder
    config: ScenarioConfig


def build_cell(cell: Cell, folder: Path, seed: int, config: ScenarioConfig | None = None) -> BuiltCell:
    """Simulate the cell's run into ``folder/sim`` and write its user project into ``folder/project``;
    ``config``: the cell's :func:`scenario` with something more simulated (rail joints, say)."""
    config = config or scenario(cell)
    simulated = folder / "sim"
    simulate(config, seed, simulated, imu_format="npy")
    project = folder / "project"
    files = write_raw_files(cell, simulated, project / "survey")
    (project / "survey" / "survey.toml").write_text(survey_toml(cell, files))
    for name in ("design.csv", "design.xml"):
        (project / name).write_bytes((simulated / "truth" / name).read_bytes())
    (project / "project.toml").write_text(project_toml(cell, config))
    return BuiltCell(project, simulated / "truth", config)


def built_cell_copy(cell: Cell, folder: Path, seed: int) -> BuiltCell:
    """:func:`build_cell` (the cell's own :func:`scenario`) made once per test run for every test asking for
    the same cell and seed (``shared_build``); its user project copied into ``folder/project``, to be changed
    and processed there. The simulator's folder (``truth``) is the shared one: read-only."""
    shared = shared_build.built_once(f"cell-{cell.cell_id}-{seed}", lambda out: build_cell(cell, out, seed))
    project = folder / "project"
    shutil.copytree(shared / "project", project)
    return BuiltCell(project, shared / "sim" / "truth", scenario(cell))


# --- accuracy against the truth ------------------------------------------------------------------

SLEEPER_SPACING_M = 0.625
CHORD_30M = 48  # sleeper intervals
PAIR_5M = 8


@dataclass(frozen=True)
class RailErrors:
    """Measured minus true, per valid sleeper of one rail: lateral (+ right of increasing station) and
    vertical [m], at the true station of the measured point."""

    station_m: np.ndarray
    lateral_m: np.ndarray
    vertical_m: np.ndarray

    def check_30m_5m_m(self) -> tuple[np.ndarray, np.ndarray]:
        """Errors of the 30 m/5 m check values (lateral, vertical) on a sleeper-spaced grid of the error
        series, every chord position and pair, in runs without a gap over 2 m."""
        out = ([], [])
        breaks = np.flatnonzero(np.diff(self.station_m) > 2.0) + 1
        for run in np.split(np.arange(len(self.station_m)), breaks):
            s = self.station_m[run]
            if len(s) < 2 or s[-1] - s[0] < CHORD_30M * SLEEPER_SPACING_M:
                continue
            grid = np.arange(s[0], s[-1], SLEEPER_SPACING_M)
            for k, series in enumerate((self.lateral_m[run], self.vertical_m[run])):
                e = np.interp(grid, s, series)
                windows = np.lib.stride_tricks.sliding_window_view(e, CHORD_30M + 1)
                first, last = windows[:, :1], windows[:, -1:]
                offsets = windows - first - np.arange(CHORD_30M + 1) / CHORD_30M * (last - first)
                out[k].append((offsets[:, :-PAIR_5M] - offsets[:, PAIR_5M:]).ravel())
        return tuple(np.concatenate(parts) if parts else np.empty(0) for parts in out)


def _truth_table(truth: Path) -> dict[str, np.ndarray]:
    names = [c.split(" [")[0] for c in (truth / "sleepers.csv").read_text().splitlines()[0].split(",")]
    data = np.loadtxt(truth / "sleepers.csv", delimiter=",", skiprows=1, ndmin=2)
    return {name: data[:, i] for i, name in enumerate(names)}


def _on_polyline(points: np.ndarray, line: np.ndarray, station: np.ndarray):
    """Lateral (+ right), vertical offsets and stations of points (E, N, H) from a polyline in station order."""
    _, nearest = cKDTree(line[:, :2]).query(points[:, :2])
    best = [np.full(len(points), np.inf), None, None, None]
    for k0 in (nearest - 1, nearest):
        k0 = np.clip(k0, 0, len(line) - 2)
        a, b = line[k0], line[k0 + 1]
        ab = b[:, :2] - a[:, :2]
        length = np.linalg.norm(ab, axis=1)
        along = ((points[:, :2] - a[:, :2]) * ab).sum(axis=1) / length**2
        lateral = ((points[:, 0] - a[:, 0]) * ab[:, 1] - (points[:, 1] - a[:, 1]) * ab[:, 0]) / length
        inside = np.abs(along - 0.5) <= 0.5 + 1e-9
        better = inside & (np.abs(lateral) < best[0])
        best[0] = np.where(better, np.abs(lateral), best[0])
        for i, value in ((1, lateral), (2, points[:, 2] - (a[:, 2] + along * (b[:, 2] - a[:, 2]))),
                         (3, station[k0] + along * (station[k0 + 1] - station[k0]))):
            best[i] = np.where(better, value, np.nan if best[i] is None else best[i])
    return best[1], best[2], best[3]


@dataclass(frozen=True)
class TruthComparison:
    rails: dict[str, RailErrors]  # "left", "right" (of the stationing)
    gauge_error_m: np.ndarray  # per valid sleeper with a gauge
    cant_error_m: np.ndarray
    measured_gauge_m: np.ndarray
    true_sleepers_in_reach: int  # truth sleepers between the first and last measured station
    valid_sleepers: int


def truth_errors(sleepers_csv: Path, built: BuiltCell, normal_heights: bool) -> TruthComparison:
    """The processed sleepers against the truth; ``normal_heights``: the results hold normal heights
    (a height model or prism fixes), else ellipsoidal ones (H = h without benchmarks)."""
    measured = np.genfromtxt(sleepers_csv, delimiter=",", names=True, dtype=None, encoding="utf-8")
    measured = measured[measured["valid"] == 1]
    truth = _truth_table(built.truth)
    rails, stations = {}, []
    for side in ("left", "right"):
        line = np.column_stack([truth[f"{side}_e"], truth[f"{side}_n"], truth[f"{side}_h"]])
        if not normal_heights:
            line[:, 2] += height_anomaly(built.config, line[:, 0], line[:, 1])
        points = np.column_stack([measured[f"{side}_E_m"], measured[f"{side}_N_m"], measured[f"{side}_H_m"]])
        lateral, vertical, station = _on_polyline(points, line, truth["station"])
        found = np.isfinite(station)
        order = np.argsort(station[found])
        rails[side] = RailErrors(station[found][order], lateral[found][order], vertical[found][order])
        stations.append(station)
    stations = np.array(stations)
    found = np.isfinite(stations)
    station = np.where(found.any(axis=0), np.where(found, stations, 0.0).sum(axis=0) / np.maximum(found.sum(axis=0), 1),
                       np.nan)
    gauge = np.interp(station, truth["station"], truth["gauge"])
    cant = np.interp(station, truth["station"], truth["cant"])
    reach = (truth["station"] >= np.nanmin(station)) & (truth["station"] <= np.nanmax(station))
    return TruthComparison(rails, 1e-3 * measured["gauge_mm"] - gauge, 1e-3 * measured["cant_mm"] - cant,
                           1e-3 * measured["gauge_mm"], int(reach.sum()), len(measured))


def rms(values: np.ndarray) -> float:
    values = values[np.isfinite(values)]
    return math.sqrt(float(np.mean(values**2))) if len(values) else math.nan


# --- a pairwise selection of cells -----------------------------------------------------------------

def pairwise_cells(factors: dict[str, tuple[str, ...]] = FACTORS, candidates: int = 30, seed: int = 32) -> list[Cell]:
    """Cells covering every pair of levels of any two factors (greedy, AETG-like, deterministic): each new
    cell starts from the first pair not yet covered and fills the other factors, in a random order, with
    the level covering the most uncovered pairs; the best of ``candidates`` such cells is taken."""
    import itertools
    import random

    names = list(factors)
    uncovered = {((a, x), (b, y)) for a, b in itertools.combinations(names, 2)
                 for x in factors[a] for y in factors[b]}
    rng = random.Random(seed)
    cells = []

    def gain(row: dict) -> int:
        return sum(((a, row[a]), (b, row[b])) in uncovered for a, b in itertools.combinations(names, 2)
                   if a in row and b in row)

    while uncovered:
        (a, x), (b, y) = min(uncovered, key=lambda p: (names.index(p[0][0]), names.index(p[1][0]), p))
        best, best_gain = None, -1
        for _ in range(candidates):
            row = {a: x, b: y}
            rest = [n for n in names if n not in row]
            rng.shuffle(rest)
            for name in rest:
                row[name] = max(factors[name], key=lambda level: (gain(row | {name: level}), rng.random()))
            if (g := gain(row)) > best_gain:
                best, best_gain = row, g
        uncovered -= {((p, best[p]), (q, best[q])) for p, q in itertools.combinations(names, 2)}
        cells.append(Cell(**best))
    return cells
