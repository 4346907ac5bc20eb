"""The track reconstruction of a long survey by parts, its memory independent of the survey's length.

:func:`reconstruct_track_streamed` gives the same reconstruction, to the bit, as
:func:`~insrail.track.sleeper_table.reconstruct_track` on the whole trajectory (which stays the
reference of the tests), reading the trajectory file by record ranges of :data:`CHUNK_EPOCHS`
and keeping the per-epoch quantities in a spool of plain files (one per quantity, float64,
written and read with plain IO: neither they nor a memory map count towards the process's memory):

* pass A, per chunk: the rails in the trolley's frame (pointwise: made by two threads ahead of the
  rest, :data:`RAILS_THREADS`) are spooled (the forward axis only without a design: the distance
  travelled along it is the stationing then); the facing's
  whole-run reductions are carried (with a design: the count of the cosines to the design's
  tangent, of the negative ones and the two middle candidates, which decide the sign of their
  median exactly; without one: the distance travelled along the x axis, a carried ``cumsum``,
  and the first and last track points); the reference rail's design stations are spooled (the
  projection carries its warm start from chunk to chunk: :func:`projection_carry`);
* pass B, per chunk: the rails turned to the stationing, their stations (on the design, the
  centreline's projected by a second thread meanwhile; or the travelled distance carried again),
  spooled with each chunk's station range (the rails' only: the centreline's go to the epochs' file;
  on the design the reference rail's are pass A's);
* the sleepers: the monotone (time, station) track of the reference rail is made per chunk (its
  running maximum, or minimum, carried) and interpolated by parts (:func:`chunked_interp`:
  ``np.interp`` to the bit, a query going to the chunk that holds its left neighbour);
* the table, by bands of :data:`BAND_SLEEPERS` sleepers: each band's rail points are those of
  the chunks whose station range meets the band widened by half a window, in epoch order, so
  ``sliding_window_fit`` sums each window's points in the same order as on the whole run;
  gauge and cant (:func:`~insrail.track.resample.interpolate_in_station`) widen the band until
  the nearest station with a reading on either side is in it (a gauge gap);
* σ and the attitude at the sleepers by :func:`chunked_interp` (the heading unwrapped with its
  correction's ``cumsum`` carried).

The memory held: a chunk's arrays (~0.4 kB per epoch of a chunk; in pass A up to
``RAILS_THREADS + 2`` chunks), a band's points and the
sleeper-level results; the epochs' stations go to a file
(:class:`~insrail.track.sleeper_table.EpochStationsFile`). A back-and-forth run puts more epochs
into one band: documented, not capped.
"""

from __future__ import annotations

import itertools
import os
import shutil
import tempfile
import threading
from collections import deque
from collections.abc import Callable, Iterator
from concurrent.futures import ThreadPoolExecutor
from contextlib import closing, nullcontext
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from insrail.background import cpu_budget
from insrail.geodesy.ellipsoid import Ellipsoid
from insrail.io.atomic import write_at
from insrail.io.survey import TrolleyGeometry
from insrail.io.types import GaugeData, SleeperPulses
from insrail.nav.trajectory import load_trajectory, trajectory_records
from insrail.track.alignment import DesignAlignment, projection_carry
from insrail.track.chainage import (
    WITH_TRAVEL,
    along_steps,
    design_cosines,
    facing_from,
    in_stationing_frame,
    reference_stations_on_design,
    stations_from_travelled,
    stations_on_design,
    track_and_forward,
)
from insrail.track.by_parts import chunked_interp, station_track_by_parts
from insrail.track.deviations import NOMINAL_GAUGE_M
from insrail.track.linefit_windows import DEFAULT_OVERLAP_M as DEFAULT_FIT_OVERLAP_M
from insrail.track.linefit_windows import DEFAULT_WINDOW_M as DEFAULT_FIT_WINDOW_M
from insrail.nav import earth
from insrail.nav.rotation import euler_to_dcm
from insrail.track.rails import POSE_FIELDS, RailPoints, ToEngineering, curve_corrected_gauge, rails_from_pose
from insrail.track.resample import DEFAULT_WINDOW_M, interpolate_in_station, sliding_window_fit
from insrail.track.sleeper_table import (
    EpochStations,
    EpochStationsWriter,
    TrackReconstruction,
    finished_reconstruction,
    grid_sleepers,
    sleeper_table_of,
)
from insrail.track.sleepers import (
    SleeperAnchor,
    StationTrack,
    anchor_numbering,
    number_on_track,
    sleeper_detector_ahead_m,
)

#: Trajectory epochs worked on at a time (~0.3 km at a walking 2 m/s and 200 Hz; 2**17 holds 70 MB more at the peak).
CHUNK_EPOCHS = 1 << 15
#: Sleepers resampled at a time (the table's bands).
BAND_SLEEPERS = 500
#: Threads making the parts' rails (at most the CPU budget): their time goes to numpy, the compiled
#: ECEF -> geodetic kernel (nogil) and PROJ, which release the GIL.
RAILS_THREADS = 2
#: Threads fitting the table's bands (at most the CPU budget): most of their time goes to numpy's
#: loops (the windows' powers above all), which release the GIL.
BAND_THREADS = 2

#: The spooled per-epoch quantities and their widths. Rails, cant and forward axis in the
#: trolley's frame (turned to the stationing when read); stations in the stationing's.
_WIDTHS = {"time": 1, "left": 3, "right": 3, "forward": 3, "gauge": 1, "cant": 1, "sigma_pos": 3, "sigma_roll": 1,
           "rpy": 3, "reference_station": 1, "left_station": 1, "right_station": 1}


class _Spool:
    """Per-epoch columns in plain float64 files under a temporary folder (removed by :meth:`close`).
    Written and read at given positions (``pwrite``, ``preadv``): threads may read at once."""

    def __init__(self, folder: Path | None):
        self.folder = Path(tempfile.mkdtemp(prefix=".track-spool-", dir=folder))
        self.handles: dict[str, object] = {}
        self._opening = threading.Lock()

    def _handle(self, name: str):
        with self._opening:
            if name not in self.handles:
                self.handles[name] = open(self.folder / f"{name}.f64", "w+b")
            return self.handles[name]

    def write(self, name: str, start: int, values: np.ndarray) -> None:
        write_at(self.folder / f"{name}.f64", self._handle(name).fileno(), np.ascontiguousarray(values, dtype=np.float64),
                 start * _WIDTHS[name] * 8)

    def read(self, name: str, start: int, count: int) -> np.ndarray:
        width = _WIDTHS[name]
        values = np.empty(count * width)
        into, offset, done = memoryview(values).cast("B"), start * width * 8, 0
        while done < len(into):
            got = os.preadv(self._handle(name).fileno(), [into[done:]], offset + done)
            if not got:
                raise ValueError(f"{self.folder / name}: spool ends before record {start + count}")
            done += got
        return values if width == 1 else values.reshape(count, width)

    def close(self) -> None:
        for handle in self.handles.values():
            handle.close()
        shutil.rmtree(self.folder, ignore_errors=True)


class _MedianSign:
    """Whether the median of a stream of values is >= 0, as ``np.median(values) >= 0.0`` says:
    the count, the count of negatives, the largest negative and the smallest non-negative value
    (for an even count with as many negatives as not, the two middle values are those)."""

    def __init__(self):
        self.n, self.negative, self.nan = 0, 0, False
        self.largest_negative, self.smallest_other = -np.inf, np.inf

    def add(self, values: np.ndarray) -> None:
        self.n += len(values)
        self.nan |= bool(np.isnan(values).any())
        negative = values[values < 0.0]
        other = values[values >= 0.0]
        self.negative += len(negative)
        if len(negative):
            self.largest_negative = max(self.largest_negative, float(negative.max()))
        if len(other):
            self.smallest_other = min(self.smallest_other, float(other.min()))

    def non_negative(self) -> bool:
        if self.nan:  # np.median is NaN
            return False
        if self.n % 2:
            return self.negative <= (self.n - 1) // 2
        if self.negative != self.n // 2:
            return self.negative < self.n // 2
        return bool(np.mean(np.array([self.largest_negative, self.smallest_other])) >= 0.0)


def _unwrapped(previous: float | None, carried: float, angle: np.ndarray) -> tuple[np.ndarray, float]:
    """``np.unwrap`` of a series continued from its ``previous`` value and the correction ``carried``
    so far (its cumulative sum); the part's unwrapped values and the new carried correction."""
    series = angle if previous is None else np.concatenate([[previous], angle])
    step = np.diff(series)
    wrapped = np.mod(step + np.pi, 2 * np.pi) - np.pi
    np.copyto(wrapped, np.pi, where=(wrapped == -np.pi) & (step > 0))
    correction = wrapped - step
    np.copyto(correction, 0, where=np.abs(step) < np.pi)
    total = np.cumsum(np.concatenate([[carried], correction]))[1:]
    if previous is None:
        return np.concatenate([angle[:1], angle[1:] + total]), (float(total[-1]) if len(total) else carried)
    return angle + total, (float(total[-1]) if len(total) else carried)


@dataclass
class _Range:
    """Finite minimum and maximum of a station column per chunk (NaN for a chunk without any)."""

    low: list
    high: list

    def add(self, values: np.ndarray) -> None:
        finite = values[np.isfinite(values)]
        self.low.append(float(finite.min()) if len(finite) else np.nan)
        self.high.append(float(finite.max()) if len(finite) else np.nan)

    def meets(self, chunk: int, low: float, high: float) -> bool:
        return bool(self.low[chunk] <= high and self.high[chunk] >= low)


class _Streamed:
    """The passes of :func:`reconstruct_track_streamed` over one trajectory file."""

    def __init__(self, trajectory_file, ellipsoid: Ellipsoid, trolley: TrolleyGeometry, gauge: GaugeData,
                 to_engineering: ToEngineering, spool: _Spool, check: Callable[[], None]):
        self.file, self.ellipsoid = trajectory_file, ellipsoid
        self.trolley, self.gauge, self.to_engineering = trolley, gauge, to_engineering
        self.spool, self.check = spool, check
        self.n = trajectory_records(trajectory_file)
        self.parts = [(start, min(CHUNK_EPOCHS, self.n - start)) for start in range(0, self.n, CHUNK_EPOCHS)]
        self.facing = 1.0

    # ------------------------------------------------------------------ pass A
    def rails_pass(self, design: DesignAlignment | None, stationing) -> float:
        """Spools the rails (and the reference rail's design stations); the facing."""
        median, carry = _MedianSign(), projection_carry()
        travelled, last, ends, with_position = 0.0, None, [], 0
        with closing(self._rails_in_order()) as parts:  # closed on any exit: no thread left making parts
            for start, rpy, rails in parts:
                for name, values in (("time", rails.time_s), ("left", rails.left_rail_enh_m),
                                     ("right", rails.right_rail_enh_m), ("gauge", rails.gauge_m),
                                     ("cant", rails.cant_m), ("sigma_pos", rails.sigma_pos_ned_m),
                                     ("sigma_roll", rails.sigma_roll_rad), ("rpy", rpy)):
                    self.spool.write(name, start, values)
                if design is not None:
                    station = reference_stations_on_design(rails, design, carry)
                    self.spool.write("reference_station", start, station)
                    median.add(design_cosines(rails, design, station))
                else:
                    self.spool.write("forward", start, rails.forward_enh)
                    track, forward = track_and_forward(rails)
                    steps, last = self._steps(track, forward, last)
                    travelled = float(np.cumsum(np.concatenate([[travelled], steps]))[-1])
                    positioned = track[np.all(np.isfinite(track), axis=1)]
                    with_position += len(positioned)
                    ends.extend(positioned[[0, -1]] if len(positioned) else [])
        if design is not None:
            self.facing = 1.0 if median.n == 0 or median.non_negative() else -1.0
            return self.facing
        # the run's first and last points with a position (finite_ends)
        self.ends = np.asarray(ends)[[0, -1]] if with_position >= 2 else None
        self.facing = facing_from(travelled, self.ends, stationing)
        # turned to the stationing the x axis, so the distance travelled along it, change sign
        self.direction = facing_from(travelled if self.facing > 0 else -travelled, self.ends, stationing)
        return self.facing

    def _part_rails(self, start: int, count: int) -> tuple[int, np.ndarray, RailPoints]:
        """The first epoch, the attitude and the rails of one part (point by point: any part on its own)."""
        trajectory = replace(load_trajectory(self.file, only=POSE_FIELDS, start=start, count=count),
                             ellipsoid=self.ellipsoid)
        return start, trajectory.rpy_rad, rails_from_pose(trajectory, self.trolley, self.gauge, self.to_engineering)

    def _rails_in_order(self) -> Iterator[tuple[int, np.ndarray, RailPoints]]:
        """:meth:`_part_rails` of every part, in order, :data:`RAILS_THREADS` threads making the
        next ones meanwhile (the same numbers as one at a time: each part's are its own). ``check``
        runs in the calling thread before each part is handed over; on any exit the parts not yet
        begun are dropped and the ones being made waited for."""
        threads = min(RAILS_THREADS, cpu_budget())
        if threads < 2:
            for start, count in self.parts:
                self.check()
                yield self._part_rails(start, count)
            return
        waiting = iter(self.parts)
        with ThreadPoolExecutor(threads, thread_name_prefix="rails") as pool:
            ahead = deque(pool.submit(self._part_rails, *part) for part in itertools.islice(waiting, threads + 1))
            try:
                while ahead:
                    self.check()
                    rails = ahead.popleft().result()
                    ahead.extend(pool.submit(self._part_rails, *part) for part in itertools.islice(waiting, 1))
                    yield rails
            finally:
                for future in ahead:
                    future.cancel()

    @staticmethod
    def _steps(track: np.ndarray, forward: np.ndarray, last):
        """:func:`along_steps` of a part continued from the previous part's last point and axis."""
        if last is not None:
            track, forward = np.concatenate([last[0], track]), np.concatenate([last[1], forward])
        return along_steps(track, forward), (track[-1:], forward[-1:])

    def rails(self, start: int, count: int, design: DesignAlignment | None) -> RailPoints:
        """The spooled rails of a part, turned to the stationing (the cross slope is not spooled: NaN;
        with a ``design`` neither is the forward axis)."""
        left, right = self.spool.read("left", start, count), self.spool.read("right", start, count)
        forward = self.spool.read("forward", start, count) if design is None else np.full((count, 3), np.nan)
        trolley_rails = RailPoints(
            time_s=self.spool.read("time", start, count), reference_rail=self.trolley.reference_rail,
            left_rail_enh_m=left, right_rail_enh_m=right, centre_enh_m=0.5 * (left + right),
            forward_enh=forward, gauge_m=self.spool.read("gauge", start, count),
            cross_slope_rad=np.full(count, np.nan), cant_m=self.spool.read("cant", start, count),
            sigma_pos_ned_m=np.full((count, 3), np.nan), sigma_roll_rad=np.full(count, np.nan))
        return in_stationing_frame(trolley_rails, self.facing)

    # ------------------------------------------------------------------ pass B
    def stations_pass(self, design: DesignAlignment | None, start_station_m: float | None,
                      epochs: EpochStationsWriter) -> None:
        """Spools the stations in the stationing's frame and writes the epochs' stations."""
        carries = {"centre": projection_carry(), "left": projection_carry(), "right": projection_carry()}
        self.ranges = {name: _Range([], []) for name in ("reference_station", "left_station", "right_station")}
        self.kept = {"gauge": [np.inf, -np.inf], "cant": [np.inf, -np.inf]}
        # with a design a second thread projects the centreline meanwhile (within the CPU budget)
        with (ThreadPoolExecutor(1, thread_name_prefix="centreline") if design is not None and cpu_budget() > 1
              else nullcontext()) as pool:
            self._stations_by_parts(design, start_station_m, epochs, carries, pool)

    def _stations_by_parts(self, design, start_station_m, epochs, carries, pool) -> None:
        """The parts of :meth:`stations_pass` in order (``pool``: where the centreline is projected)."""
        travelled, last = 0.0, None
        for start, count in self.parts:
            self.check()
            rails = self.rails(start, count, design)
            if design is not None:
                stations = stations_on_design(rails, design, self.spool.read("reference_station", start, count),
                                              carries, pool)
            else:
                track, forward = track_and_forward(rails)
                steps, last = self._steps(track, forward, last)
                if start == 0:
                    distance = np.concatenate([[0.0], np.cumsum(steps)])
                else:
                    distance = np.cumsum(np.concatenate([[travelled], steps]))[1:]
                travelled = float(distance[-1])
                stations = stations_from_travelled(rails, track, forward, distance, start_station_m,
                                                   self.direction)
            epochs.write(EpochStations(rails.time_s, stations.reference_m, stations.centre_m))
            for name, values in (("reference_station", stations.reference_m), ("left_station", stations.left_m),
                                 ("right_station", stations.right_m)):
                if design is None or name != "reference_station":  # on the design: pass A's, as spooled
                    self.spool.write(name, start, values)
                self.ranges[name].add(values)
            for name, values in (("gauge", rails.gauge_m), ("cant", rails.cant_m)):
                kept = stations.reference_m[np.isfinite(stations.reference_m) & np.isfinite(values)]
                if len(kept):
                    self.kept[name] = [min(self.kept[name][0], kept.min()), max(self.kept[name][1], kept.max())]

    # ------------------------------------------------------------------ the sleepers
    def station_track(self) -> StationTrack:
        """The reference rail's monotone (time, station) track, interpolated by parts."""
        return station_track_by_parts(len(self.parts), self._finite_reference)

    def _finite_reference(self, k: int) -> tuple[np.ndarray, np.ndarray]:
        start, count = self.parts[k]
        t, s = self.spool.read("time", start, count), self.spool.read("reference_station", start, count)
        finite = np.isfinite(s)
        return t[finite], s[finite]

    # ------------------------------------------------------------------ the table
    def _stationing_name(self, name: str) -> str:
        """The spooled (trolley's) rail of the stationing's ``name``."""
        if self.facing > 0 or name not in ("left", "right"):
            return name
        return "right" if name == "left" else "left"

    def _values(self, name: str, start: int, count: int) -> np.ndarray:
        values = self.spool.read(self._stationing_name(name), start, count)
        return -values if name == "cant" and self.facing < 0 else values

    def band(self, station: str, value: str, low: float, high: float) -> tuple[np.ndarray, np.ndarray]:
        """The epochs whose ``station`` lies in [low, high] and whose station and ``value`` are
        finite, in epoch order: (stations, values)."""
        ranges = self.ranges["reference_station" if station == "reference_station" else station]
        stations, values = [], []
        for k, (start, count) in enumerate(self.parts):
            if not ranges.meets(k, low, high):
                continue
            s, v = self.spool.read(station, start, count), self._values(value, start, count)
            keep = np.isfinite(s) & (s >= low) & (s <= high)
            keep &= np.isfinite(v) if v.ndim == 1 else np.all(np.isfinite(v), axis=1)
            stations.append(s[keep])
            values.append(v[keep])
        width = _WIDTHS[self._stationing_name(value)]
        if not stations:
            return np.empty(0), np.empty((0, width) if width > 1 else 0)
        return np.concatenate(stations), np.concatenate(values)

    def interpolated(self, value: str, at: np.ndarray, margin: float) -> np.ndarray:
        """``interpolate_in_station`` of ``value`` in the reference rail's station at ``at``, on a band
        widened until it holds the nearest reading on each side of ``at`` (when there is one)."""
        lowest, highest = self.kept[value]
        while True:
            s, v = self.band("reference_station", value, at.min() - margin, at.max() + margin)
            below = (s <= at.min()).any() or lowest > at.min()
            above = (s > at.max()).any() or highest <= at.max()
            if below and above:
                return interpolate_in_station(s, v, at)
            margin *= 8.0

    def epoch_blocks(self, names: tuple[str, ...], unwrap_last: bool = False) -> Iterator:
        """(time, values) per chunk: the named columns side by side; ``unwrap_last``: the last
        column unwrapped as ``np.unwrap`` does over the whole run."""
        previous, carried = None, 0.0
        for start, count in self.parts:
            values = np.column_stack([self.spool.read(name, start, count) for name in names])
            if unwrap_last:
                angle = values[:, -1]
                values[:, -1], carried = _unwrapped(previous, carried, angle.copy())
                previous = float(angle[-1])
            yield self.spool.read("time", start, count), values

    def first_last_time(self) -> tuple[float, float] | None:
        if self.n < 2:
            return None
        return float(self.spool.read("time", 0, 1)[0]), float(self.spool.read("time", self.n - 1, 1)[0])


def _each_band(firsts, fit: Callable[[int], None], check: Callable[[], None]) -> None:
    """``fit`` of every band (its first sleeper), :data:`BAND_THREADS` at a time; ``check`` runs in the
    calling thread before each band is begun. The bands write disjoint rows: the table is the same,
    to the bit, as one band after the other."""
    threads = min(BAND_THREADS, cpu_budget())
    if threads < 2:
        for first in firsts:
            check()
            fit(first)
        return
    with ThreadPoolExecutor(threads, thread_name_prefix="bands") as pool:  # on any exit: the running ones waited for
        running: deque = deque()
        for first in firsts:
            check()
            if len(running) == threads:
                running.popleft().result()
            running.append(pool.submit(fit, first))
        for band in running:
            band.result()


def path_at_times(trajectory_file, ellipsoid: Ellipsoid, trolley: TrolleyGeometry, time_s: np.ndarray
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The IMU's path at ``time_s`` in a local plane tangent at its first point (north, east [m])
    and the trolley's x axis there (north, east components), read from the trajectory file by parts:
    what the gauge's curve correction takes (over a survey's few kilometres the plane's scale
    error, below 1e-3, changes a curvature by as little)."""
    x_v_b = euler_to_dcm(*np.asarray(trolley.mounting_rpy_rad, dtype=float))[0]
    n = trajectory_records(trajectory_file)

    def blocks():
        for start in range(0, n, CHUNK_EPOCHS):
            part = load_trajectory(trajectory_file, only=("time_s", "lat_rad", "lon_rad", "rpy_rad"), start=start,
                                   count=min(CHUNK_EPOCHS, n - start))
            rpy = part.rpy_rad
            forward = euler_to_dcm(rpy[:, 0], rpy[:, 1], rpy[:, 2]) @ x_v_b
            yield part.time_s, np.column_stack([part.lat_rad, part.lon_rad, forward[:, 0], forward[:, 1]])

    at = chunked_interp(np.asarray(time_s, dtype=float), blocks())
    lat0, lon0 = at[0, 0], at[0, 1]
    r_m, r_n = earth.radii(lat0, ellipsoid)
    return (at[:, 0] - lat0) * r_m, (at[:, 1] - lon0) * r_n * np.cos(lat0), at[:, 2:4]


def attitude_at_times(time_s: np.ndarray, span: tuple[float, float] | None,
                      interpolated: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
    """(n, 3) roll, pitch, heading [rad, heading in [0, 2 pi)] at ``time_s`` from ``interpolated``
    (times -> (m, 3) roll, pitch and unwrapped heading at them) within the trajectory's first and
    last time ``span`` (None: fewer than two epochs); NaN outside it."""
    at = np.asarray(time_s, dtype=float)
    out = np.full((at.size, 3), np.nan)
    if span is None or not at.size:
        return out
    inside = (at >= span[0]) & (at <= span[1])
    out[inside] = interpolated(at[inside])
    out[:, 2] = np.mod(out[:, 2], 2 * np.pi)
    return out


def reconstruct_track_streamed(
    trajectory_file,
    ellipsoid: Ellipsoid,
    trolley: TrolleyGeometry,
    gauge: GaugeData,
    to_engineering: ToEngineering,
    design: DesignAlignment | None = None,
    pulses: SleeperPulses | None = None,
    start_station_m: float | None = None,
    spacing_m: float = 0.625,
    window_m: float = DEFAULT_WINDOW_M,
    first_number: int = 1,
    design_gauge_m: float = NOMINAL_GAUGE_M,
    fit_line: bool = True,
    fit_window_m: float = DEFAULT_FIT_WINDOW_M,
    fit_overlap_m: float = DEFAULT_FIT_OVERLAP_M,
    stationing: str | float = WITH_TRAVEL,
    anchor: SleeperAnchor | None = None,
    beam_wheel_spacing_m: float = 0.0,
    spool_folder: Path | None = None,
    epochs_file: Path | None = None,
    check: Callable[[], None] = lambda: None,
) -> tuple[TrackReconstruction, np.ndarray]:
    """:func:`~insrail.track.sleeper_table.reconstruct_track` of the trajectory in
    ``trajectory_file`` (read by parts, on ``ellipsoid``, the one the fusion ran on;
    ``beam_wheel_spacing_m`` > 0: each gauge reading corrected for the curve,
    :func:`~insrail.track.rails.curve_corrected_gauge`, at its own time on the path of
    :func:`path_at_times`, where the whole-run function corrects the epochs) and the fused attitude at its sleepers
    (:func:`~insrail.project.sleeper_parameters.sleeper_attitude_rad`), the same to the bit, in
    memory independent of the survey's length (see the module docstring). The reconstruction
    carries no rails and stations; its epochs' stations are written to ``epochs_file``
    (:class:`~insrail.track.sleeper_table.EpochStationsFile`; None: held in memory).
    ``spool_folder``: where the temporary spool goes (removed on every exit); ``check``: called
    per chunk (cancel)."""
    if design is None and start_station_m is None:
        raise ValueError("without a design alignment the start station (start_station_m) must be given")
    if beam_wheel_spacing_m:
        gauge = curve_corrected_gauge(gauge, *path_at_times(trajectory_file, ellipsoid, trolley, gauge.time_s),
                                      beam_wheel_spacing_m, trolley.reference_rail)
    spool = _Spool(spool_folder)
    epochs = EpochStationsWriter(epochs_file or spool.folder / "epochs.npy", trajectory_records(trajectory_file))
    try:
        run = _Streamed(trajectory_file, ellipsoid, trolley, gauge, to_engineering, spool, check)
        facing = run.rails_pass(design, stationing)
        run.stations_pass(design, start_station_m, epochs)
        epochs = epochs.commit()
        track = run.station_track()
        if pulses is None:
            sleepers = grid_sleepers(track, spacing_m, first_number)
        else:
            sleepers = number_on_track(pulses.time_s, track, facing * sleeper_detector_ahead_m(trolley), spacing_m,
                                       first_number=first_number)
        if anchor is not None:
            sleepers = anchor_numbering(sleepers, anchor, spacing_m)
        at, half = sleepers.station_m, 0.5 * window_m
        n = len(at)
        left, right = np.full((n, 3), np.nan), np.full((n, 3), np.nan)
        gauge_at, cant_at = np.full(n, np.nan), np.full(n, np.nan)

        def fit_band(first: int) -> None:  # each band's sleepers are its own
            part = slice(first, first + BAND_SLEEPERS)
            band = at[part]
            low, high = band.min() - half, band.max() + half
            left[part] = sliding_window_fit(*run.band("left_station", "left", low, high), band, window_m)
            right[part] = sliding_window_fit(*run.band("right_station", "right", low, high), band, window_m)
            gauge_at[part] = run.interpolated("gauge", band, half)
            cant_at[part] = run.interpolated("cant", band, half)

        _each_band(range(0, n, BAND_SLEEPERS), fit_band, check)
        sigma = chunked_interp(sleepers.time_s, run.epoch_blocks(("sigma_pos", "sigma_roll")))
        table = sleeper_table_of(sleepers, left, right, gauge_at, cant_at, sigma[:, :3], sigma[:, 3], design,
                                 design_gauge_m, trolley.rail_centre_spacing_m)
        attitude = attitude_at_times(sleepers.time_s, run.first_last_time(),
                                     lambda at: chunked_interp(at, run.epoch_blocks(("rpy",), unwrap_last=True)))
        if epochs_file is None:  # in memory (the spool goes)
            epochs = epochs.load()
    finally:
        spool.close()
        if isinstance(epochs, EpochStationsWriter):  # not committed: failed or cancelled
            epochs.discard()
    recon = finished_reconstruction(sleepers, table, {"epochs": epochs}, fit_line and design is None, fit_window_m,
                                    fit_overlap_m, design_gauge_m, trolley.rail_centre_spacing_m)
    return recon, attitude
