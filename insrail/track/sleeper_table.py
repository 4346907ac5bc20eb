"""The sleeper table: the measured track resampled at every sleeper, with its deviations.

This is the contract between the reconstruction (rails, chainage, sleepers, resampling,
deviations) and the irregularity / parameter / adjustment computations. One row per sleeper,
ordered by station; lengths in metres, frames and signs as in :mod:`insrail.track` and
:mod:`insrail.track.deviations`.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from insrail.io.atomic import named_write
from insrail.io.survey import TrolleyGeometry
from insrail.io.types import GaugeData, SleeperPulses
from insrail.nav.trajectory import NPY_HEADER_LOCK, Trajectory
from insrail.track.alignment import DesignAlignment
from insrail.track.by_parts import station_track_by_parts
from insrail.track.chainage import (
    WITH_TRAVEL,
    RailStations,
    epoch_station_track,
    facing_along_path,
    facing_on_design,
    in_stationing_frame,
    reference_stations_on_design,
    stations_along_path,
    stations_on_design,
)
from insrail.track.deviations import (
    CANT_BASE_M,
    NOMINAL_GAUGE_M,
    design_cant_m,
    rail_deviations,
    rail_deviations_from_reference,
)
from insrail.track.linefit import AlignmentFit, LineFitError, fit_alignment
from insrail.track.linefit_windows import DEFAULT_OVERLAP_M as DEFAULT_FIT_OVERLAP_M
from insrail.track.linefit_windows import DEFAULT_WINDOW_M as DEFAULT_FIT_WINDOW_M
from insrail.track.linefit_windows import WindowedReference, fit_windows
from insrail.track.rails import RailPoints, ToEngineering, rails_from_pose
from insrail.track.resample import (
    DEFAULT_WINDOW_M,
    interpolate_in_station,
    sliding_window_fit,
)
from insrail.track.sleepers import (
    SleeperAnchor,
    SleeperNumbering,
    StationTrack,
    anchor_numbering,
    number_sleepers,
    sleeper_detector_ahead_m,
)


@dataclass(frozen=True)
class SleeperTable:
    """Per sleeper (arrays of length n; (n, 3) = E, N, H; (n, 2) = [left, right]).

    number            sleeper number (int)
    station_m         continuous station of the sleeper (see :mod:`insrail.track`)
    label             displayed chainage ("DK1+695.917") when a design gives the station equations, else ""
    time_s            when the trolley passed it (GPS seconds of week)
    detected          False where the sleeper detector missed it (inserted) or for a regular grid
    centre_enh_m, left_rail_enh_m, right_rail_enh_m   resampled points (rail: top above the gauge face)
    gauge_m           measured gauge
    cant_m            measured cant, + left rail higher (1.5 m * sin(cross slope))
    design_cant_m     design cant (0 without a design or a cant table)
    lateral_deviation_m   (n, 2) + = rail to the RIGHT of its design (or fitted) position
    vertical_deviation_m  (n, 2) + = rail ABOVE its design (or fitted) position
    sigma_pos_ned_m   (n, 3) 1-sigma of the trajectory's position at ``time_s``
    sigma_roll_rad    1-sigma of the roll at ``time_s``
    valid             every quantity above is finite and the sleeper is to be assessed
    not_assessed      per sleeper, why it is left out of the assessment although measured (events
                      such as a turnout or a level crossing, reasons joined by "; "); () for none
    chain_zone        broken-chainage zone (断链属性, thesis Fig. 5-7): the number of station equations
                      passed at the sleeper (0 before the first; None: 0 everywhere)
    """

    number: np.ndarray
    station_m: np.ndarray
    label: tuple[str, ...]
    time_s: np.ndarray
    detected: np.ndarray
    centre_enh_m: np.ndarray
    left_rail_enh_m: np.ndarray
    right_rail_enh_m: np.ndarray
    gauge_m: np.ndarray
    cant_m: np.ndarray
    design_cant_m: np.ndarray
    lateral_deviation_m: np.ndarray
    vertical_deviation_m: np.ndarray
    sigma_pos_ned_m: np.ndarray
    sigma_roll_rad: np.ndarray
    valid: np.ndarray
    not_assessed: tuple[str, ...] = ()
    chain_zone: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.number)


def regular_sleepers(rails: RailPoints, stations: RailStations, spacing_m: float = 0.625,
                     first_number: int = 1) -> SleeperNumbering:
    """A regular grid of "sleepers" every ``spacing_m`` over the stations the survey covers, for
    tracks without detector pulses; the grid starts at the first whole multiple of the spacing."""
    return grid_sleepers(StationTrack.of(*epoch_station_track(rails.time_s, stations.reference_m)), spacing_m,
                         first_number)


def grid_sleepers(track: StationTrack, spacing_m: float = 0.625, first_number: int = 1) -> SleeperNumbering:
    """:func:`regular_sleepers` over a :class:`~insrail.track.sleepers.StationTrack`."""
    first, last = np.ceil(track.low_station_m / spacing_m), np.floor(track.high_station_m / spacing_m)
    grid = np.arange(first, last + 1) * spacing_m
    times = track.time_at(grid)
    return SleeperNumbering(
        number=np.arange(len(grid)) + first_number,
        station_m=grid,
        time_s=times,
        detected=np.zeros(len(grid), dtype=bool),
        pulse_time_s=np.empty(0),
        pulse_station_m=np.empty(0),
        pulse_accepted=np.empty(0, dtype=bool),
    )


def build_sleeper_table(
    rails: RailPoints,
    stations: RailStations,
    sleepers: SleeperNumbering,
    design: DesignAlignment | None = None,
    window_m: float = DEFAULT_WINDOW_M,
    design_gauge_m: float = NOMINAL_GAUGE_M,
    cant_base_m: float = CANT_BASE_M,
) -> SleeperTable:
    """Resample the dense rail points at the sleepers and compute the deviations from ``design``.

    Each rail is fitted against its own stations (a rail point slightly ahead of the
    centreline is not mistaken for the section at the centreline's station); gauge and cant,
    measured at the trolley's reference cross-section, are interpolated in its station.
    Without a design the deviations are NaN (a fitted alignment can be passed as ``design``).
    """
    at = sleepers.station_m
    left = sliding_window_fit(stations.left_m, rails.left_rail_enh_m, at, window_m)
    right = sliding_window_fit(stations.right_m, rails.right_rail_enh_m, at, window_m)
    gauge = interpolate_in_station(stations.reference_m, rails.gauge_m, at)
    cant = interpolate_in_station(stations.reference_m, rails.cant_m, at)
    sigma_pos = np.column_stack([np.interp(sleepers.time_s, rails.time_s, rails.sigma_pos_ned_m[:, i]) for i in range(3)])
    sigma_roll = np.interp(sleepers.time_s, rails.time_s, rails.sigma_roll_rad)
    return sleeper_table_of(sleepers, left, right, gauge, cant, sigma_pos, sigma_roll, design, design_gauge_m,
                            cant_base_m)


def sleeper_table_of(sleepers: SleeperNumbering, left: np.ndarray, right: np.ndarray, gauge: np.ndarray,
                     cant: np.ndarray, sigma_pos: np.ndarray, sigma_roll: np.ndarray,
                     design: DesignAlignment | None = None, design_gauge_m: float = NOMINAL_GAUGE_M,
                     cant_base_m: float = CANT_BASE_M) -> SleeperTable:
    """The table of :func:`build_sleeper_table` from what was resampled at the sleepers."""
    at = sleepers.station_m
    n = len(at)
    if design is not None:
        lateral, vertical = rail_deviations(design, left, right, design_gauge_m, cant_base_m)
        design_cant = design_cant_m(design, at)
        labels = tuple(design.station_equations.label(at)) if n else ()
        zone = design.station_equations.zone_at(at) if design.station_equations.equations else None
    else:
        lateral = vertical = np.full((n, 2), np.nan)
        design_cant = np.zeros(n)
        labels = ("",) * n
        zone = None
    valid = (np.all(np.isfinite(left), axis=1) & np.all(np.isfinite(right), axis=1) & np.isfinite(gauge)
             & np.isfinite(cant))
    if design is not None:
        valid &= np.all(np.isfinite(lateral), axis=1)
        if design.vertical is not None:
            valid &= np.all(np.isfinite(vertical), axis=1)
    return SleeperTable(
        number=np.asarray(sleepers.number, dtype=int),
        station_m=at,
        label=labels,
        time_s=sleepers.time_s,
        detected=sleepers.detected,
        centre_enh_m=0.5 * (left + right),
        left_rail_enh_m=left,
        right_rail_enh_m=right,
        gauge_m=gauge,
        cant_m=cant,
        design_cant_m=design_cant,
        lateral_deviation_m=lateral,
        vertical_deviation_m=vertical,
        sigma_pos_ned_m=sigma_pos,
        sigma_roll_rad=sigma_roll,
        valid=valid,
        chain_zone=zone,
    )


def deviations_from_fitted_line(
    table: SleeperTable,
    window_m: float = DEFAULT_FIT_WINDOW_M,
    overlap_m: float = DEFAULT_FIT_OVERLAP_M,
    design_gauge_m: float = NOMINAL_GAUGE_M,
    cant_base_m: float = CANT_BASE_M,
    fit_rows: np.ndarray | None = None,
) -> tuple[SleeperTable, AlignmentFit, WindowedReference]:
    """The table with deviations "measured - best" (thesis Fig. 5-7, 偏差量 [实测-最优]).

    Plan, profile and cant are fitted to the valid rows' centreline and cant
    (:func:`~insrail.track.linefit.fit_alignment`), or only to those of them ``fit_rows`` (bool
    per row) allows, e.g. not where the fusion is not consistent; the deviations are taken from
    the windowed best-fit reference (:func:`~insrail.track.linefit_windows.fit_windows`) at the
    fitted rows (NaN at the others), the design cant column holds the fitted cant. Raises
    LineFitError when the centreline cannot be fitted.
    """
    usable = np.asarray(table.valid, dtype=bool)
    if fit_rows is not None:
        usable = usable & np.asarray(fit_rows, dtype=bool)
    rows = np.flatnonzero(usable)
    if rows.size < 2:
        raise LineFitError("line fitting: the sleeper table has fewer than two valid rows")
    centre = table.centre_enh_m[rows]
    fit = fit_alignment(table.station_m[rows], *centre.T, cant_m=table.cant_m[rows], name="fitted")
    reference = fit_windows(fit, table.station_m[rows], *centre.T, window_m=window_m, overlap_m=overlap_m)
    fitted_cant = fit.alignment.cant.cant_at(np.clip(reference.station_m, fit.alignment.horizontal.start_station_m,
                                                     fit.alignment.horizontal.end_station_m))
    n = len(table)
    lateral, vertical = np.full((n, 2), np.nan), np.full((n, 2), np.nan)
    lateral[rows], vertical[rows] = rail_deviations_from_reference(
        reference.reference_enh_m, reference.azimuth_rad, fitted_cant, table.left_rail_enh_m[rows],
        table.right_rail_enh_m[rows], design_gauge_m, cant_base_m,
    )
    design_cant = np.zeros(n)
    design_cant[rows] = fitted_cant
    updated = replace(table, lateral_deviation_m=lateral, vertical_deviation_m=vertical, design_cant_m=design_cant)
    return updated, fit, reference


#: Epochs read at a time from an :class:`EpochStationsFile`.
EPOCH_CHUNK = 1 << 17


@dataclass(frozen=True)
class EpochStations:
    """Per trajectory epoch, what places things on the chainage once the rails are built: the
    time and the stations of the reference rail and the centreline (NaN where none)."""

    time_s: np.ndarray
    reference_m: np.ndarray
    centre_m: np.ndarray

    @classmethod
    def of(cls, rails: RailPoints, stations: RailStations) -> EpochStations:
        return cls(rails.time_s, stations.reference_m, stations.centre_m)

    def track(self) -> tuple[np.ndarray, np.ndarray]:
        """(time, station) made invertible (:func:`~insrail.track.chainage.epoch_station_track`)."""
        return epoch_station_track(self.time_s, self.reference_m)

    def station_track(self) -> StationTrack:
        """:meth:`track` as a :class:`~insrail.track.sleepers.StationTrack`."""
        return StationTrack.of(*self.track())

    def chunks(self, size: int = EPOCH_CHUNK) -> Iterator[EpochStations]:
        """The epochs ``size`` at a time, in order."""
        for first in range(0, len(self.time_s), size):
            part = slice(first, first + size)
            yield EpochStations(self.time_s[part], self.reference_m[part], self.centre_m[part])


@dataclass(frozen=True)
class EpochStationsFile:
    """:class:`EpochStations` kept on disk (a ``.npy`` of (n, 3) float64: time, reference, centre),
    read by parts (plain reads: never held whole, never mapped)."""

    path: Path

    def _layout(self) -> tuple[int, int]:
        """(where the data begin, the number of epochs)."""
        with open(self.path, "rb") as handle:
            version = np.lib.format.read_magic(handle)
            with NPY_HEADER_LOCK:  # the header's parser is not safe in two threads at once (nav.trajectory)
                shape, _, _ = (np.lib.format.read_array_header_1_0 if version == (1, 0)
                               else np.lib.format.read_array_header_2_0)(handle)
            return handle.tell(), shape[0]

    def _part(self, offset: int, n: int, first: int, size: int) -> EpochStations:
        count = min(size, n - first)
        rows = np.fromfile(self.path, dtype=np.float64, count=3 * count, offset=offset + 24 * first)
        if len(rows) != 3 * count:
            raise ValueError(f"{self.path}: the file ends before epoch {first + count} of {n}")
        return EpochStations(*(np.ascontiguousarray(column) for column in rows.reshape(count, 3).T))

    def chunks(self, size: int = EPOCH_CHUNK) -> Iterator[EpochStations]:
        offset, n = self._layout()
        for first in range(0, n, size):
            yield self._part(offset, n, first, size)

    def load(self) -> EpochStations:
        """All epochs in memory (24 B each)."""
        parts = list(self.chunks())
        return EpochStations(*(np.concatenate([getattr(p, name) for p in parts]) if parts else np.empty(0)
                               for name in ("time_s", "reference_m", "centre_m")))

    def station_track(self, size: int = EPOCH_CHUNK) -> StationTrack:
        """:meth:`EpochStations.station_track`, read and interpolated by parts."""
        offset, n = self._layout()
        firsts = range(0, n, size)

        def finite_part(k: int) -> tuple[np.ndarray, np.ndarray]:
            part = self._part(offset, n, firsts[k], size)
            finite = np.isfinite(part.reference_m)
            return part.time_s[finite], part.reference_m[finite]

        return station_track_by_parts(len(firsts), finite_part)


class EpochStationsWriter:
    """Writes an :class:`EpochStationsFile` of ``n`` epochs part by part under a temporary name:
    :meth:`commit` puts it in place, :meth:`discard` removes what was written."""

    def __init__(self, path: Path, n: int):
        self.path, self.tmp = Path(path), Path(path).with_name(f".{Path(path).name}.tmp")
        self.handle = open(self.tmp, "wb")
        named_write(self.path, np.lib.format.write_array_header_1_0, self.handle,
                      {"descr": "<f8", "fortran_order": False, "shape": (n, 3)})

    def write(self, part: EpochStations) -> None:
        named_write(self.path, self.handle.write, np.column_stack([part.time_s, part.reference_m, part.centre_m]).tobytes())

    def commit(self) -> EpochStationsFile:
        named_write(self.path, self.handle.close)
        os.replace(self.tmp, self.path)
        return EpochStationsFile(self.path)

    def discard(self) -> None:
        self.handle.close()
        self.tmp.unlink(missing_ok=True)


@dataclass(frozen=True)
class TrackReconstruction:
    """Everything the reconstruction produced, for reports and diagnostics.

    Without a design: ``fitted`` is the line-type fit of the measured centreline (the
    alignment to export as CSV / LandXML), ``reference`` the windowed best-fit line the
    deviations were taken from; ``line_fit_error`` says why they are None when the fit was
    asked for but failed (then the deviations are NaN, as with line fitting off).
    ``rails`` and ``stations`` (25 doubles per epoch) are None in a reconstruction kept for
    later (the pipeline's stage cache): ``epochs`` holds what the later stages take from them
    (on disk, :class:`EpochStationsFile`, from :func:`~insrail.track.streamed.reconstruct_track_streamed`).
    """

    sleepers: SleeperNumbering
    table: SleeperTable
    epochs: EpochStations | EpochStationsFile
    rails: RailPoints | None = None  # in the stationing's frame (chainage.in_stationing_frame)
    stations: RailStations | None = None
    fitted: AlignmentFit | None = None
    reference: WindowedReference | None = None
    line_fit_error: str = ""


def reconstruct_track(
    trajectory: Trajectory,
    trolley: TrolleyGeometry,
    gauge: GaugeData,
    to_engineering: ToEngineering,
    design: DesignAlignment | None = None,
    pulses: SleeperPulses | None = None,
    start_station_m: float | None = None,
    spacing_m: float = 0.625,
    window_m: float = DEFAULT_WINDOW_M,
    first_number: int = 1,
    beam_wheel_spacing_m: float = 0.0,
    design_gauge_m: float = NOMINAL_GAUGE_M,
    fit_line: bool = True,
    fit_window_m: float = DEFAULT_FIT_WINDOW_M,
    fit_overlap_m: float = DEFAULT_FIT_OVERLAP_M,
    stationing: str | float = WITH_TRAVEL,
    anchor: SleeperAnchor | None = None,
) -> TrackReconstruction:
    """Rails from pose -> turned to the stationing -> stations (on ``design``, else along the
    path from ``start_station_m``, growing as ``stationing`` says:
    :func:`~insrail.track.chainage.facing_along_path`) -> sleepers (numbered from ``pulses``,
    else a regular grid every ``spacing_m``; from ``first_number`` at the lowest station, or as
    ``anchor`` places a field number) -> table. The run may go with or against the
    stationing and the trolley face either way: rails, cant and numbers follow the stationing.

    Without a design and with ``fit_line`` the deviations are "measured - best": see
    :func:`deviations_from_fitted_line` (windows of ``fit_window_m`` overlapping by
    ``fit_overlap_m``)."""
    if design is None and start_station_m is None:
        raise ValueError("without a design alignment the start station (start_station_m) must be given")
    trolley_rails = rails_from_pose(trajectory, trolley, gauge, to_engineering, beam_wheel_spacing_m)
    # the reference rail's points are the same in both namings of the rails: projected once
    reference = reference_stations_on_design(trolley_rails, design) if design is not None else None
    facing = (facing_on_design(trolley_rails, design, reference) if design is not None
              else facing_along_path(trolley_rails, stationing))
    rails = in_stationing_frame(trolley_rails, facing)
    stations = (stations_on_design(rails, design, reference) if design is not None
                else stations_along_path(rails, start_station_m, stationing))
    if pulses is None:
        sleepers = regular_sleepers(rails, stations, spacing_m, first_number)
    else:
        t, s = epoch_station_track(rails.time_s, stations.reference_m)
        sleepers = number_sleepers(pulses.time_s, t, s, facing * sleeper_detector_ahead_m(trolley), spacing_m,
                                   first_number=first_number)
    if anchor is not None:
        sleepers = anchor_numbering(sleepers, anchor, spacing_m)
    table = build_sleeper_table(rails, stations, sleepers, design, window_m, design_gauge_m,
                                trolley.rail_centre_spacing_m)
    dense = {"epochs": EpochStations.of(rails, stations), "rails": rails, "stations": stations}
    return finished_reconstruction(sleepers, table, dense, fit_line and design is None, fit_window_m, fit_overlap_m,
                                   design_gauge_m, trolley.rail_centre_spacing_m)


def finished_reconstruction(sleepers: SleeperNumbering, table: SleeperTable, dense: dict, fit_line: bool,
                            fit_window_m: float = DEFAULT_FIT_WINDOW_M, fit_overlap_m: float = DEFAULT_FIT_OVERLAP_M,
                            design_gauge_m: float = NOMINAL_GAUGE_M,
                            cant_base_m: float = CANT_BASE_M, fit_rows: np.ndarray | None = None) -> TrackReconstruction:
    """The reconstruction of a table, with the deviations from the fitted line when ``fit_line``
    (:func:`deviations_from_fitted_line`, on the rows ``fit_rows`` allows); ``dense``: its epochs
    (and rails and stations). A fit that fails leaves the rest whole and says why in
    ``line_fit_error`` (the reconstruction is kept whatever the fit does)."""
    if not fit_line:
        return TrackReconstruction(sleepers, table, **dense)
    try:
        table, fitted, reference = deviations_from_fitted_line(table, fit_window_m, fit_overlap_m, design_gauge_m,
                                                               cant_base_m, fit_rows)
    except ValueError as error:  # LineFitError, or anything else the fit's numbers run into
        return TrackReconstruction(sleepers, table, **dense, line_fit_error=str(error))
    return TrackReconstruction(sleepers, table, **dense, fitted=fitted, reference=reference)
