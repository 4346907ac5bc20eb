"""The per-sleeper columns of sleepers.csv beyond the sleeper table's own: centreline coordinates,
attitude, line speed, curvature, cant change rate, alignment and height change rates, cant deficiency
and its rate (thesis §5.6 lists the rates among the parameters a fine-adjustment survey delivers).

Base lengths: each rate is taken over the base of the tolerance profile's first check of its kind
(so the stored column is the value the profile judges), else over the defaults below; the bases used
are written to summary.toml ``[track.parameters]``. The curvature is that of the design alignment,
else of the fitted line (no curvature: no cant deficiency). The attitude is the fused IMU body
attitude (roll, pitch, heading from true north; frames of :mod:`insrail.nav`) at the sleeper's time.
"""

from __future__ import annotations

import numpy as np

from insrail.notices import Notice, Phrase
from insrail.track.alignment import DesignAlignment
from insrail.track.parameters import (
    LineSpeed,
    cant_deficiency_m,
    cant_deficiency_rate_mps,
    rate_over_base,
)
from insrail.track.sleeper_table import SleeperTable
from insrail.track.streamed import attitude_at_times
from insrail.track.tolerance import SPEED_KINDS, ToleranceProfile

#: Bases when the profile has no check of the kind [m]. [U] the thesis names the rates (§5.6)
#: without their bases; 2.5 m is its sleeper table's base of the gauge change rate.
DEFAULT_BASES_M = {"cant_change_rate": 3.0, "deviation_change_rate": 2.5, "cant_deficiency_rate": 3.0}


def parameter_bases(profile: ToleranceProfile) -> dict[str, float]:
    """Base length per rate kind: the profile's first check of that kind, else :data:`DEFAULT_BASES_M`."""
    bases = dict(DEFAULT_BASES_M)
    for kind in DEFAULT_BASES_M:
        check = next((c for c in profile.checks if c.kind == kind), None)
        if check is not None:
            bases[kind] = float(check.base_m)
    return bases


def line_curvature_1pm(alignment: DesignAlignment | None, station_m: np.ndarray) -> np.ndarray | None:
    """Signed curvature of ``alignment`` at the stations (NaN outside it); None without one."""
    if alignment is None:
        return None
    horizontal = alignment.horizontal
    station = np.asarray(station_m, dtype=float)
    inside = (station >= horizontal.start_station_m) & (station <= horizontal.end_station_m)
    curvature = np.full(station.shape, np.nan)
    if inside.any():
        curvature[inside] = horizontal.curvature_at(station[inside])
    return curvature


def sleeper_attitude_rad(trajectory_time_s: np.ndarray, trajectory_rpy_rad: np.ndarray,
                         time_s: np.ndarray) -> np.ndarray:
    """(n, 3) roll, pitch, heading [rad, heading in [0, 2 pi)] of the fused trajectory (its time
    and roll, pitch, heading per epoch) at ``time_s``; NaN outside the trajectory."""
    time, rpy = np.asarray(trajectory_time_s), np.asarray(trajectory_rpy_rad)

    def interpolated(at: np.ndarray) -> np.ndarray:
        return np.column_stack([np.interp(at, time, np.unwrap(rpy[:, axis]) if axis == 2 else rpy[:, axis])
                                for axis in range(3)])

    return attitude_at_times(time_s, (time[0], time[-1]) if time.size >= 2 else None, interpolated)


def parameter_columns(table: SleeperTable, attitude_rad: np.ndarray, curvature_1pm: np.ndarray | None,
                      speed_mps: np.ndarray | None, bases: dict[str, float]) -> dict[str, tuple[np.ndarray, str]]:
    """The extra sleepers.csv columns (name -> (values, format)); NaN at invalid sleepers."""
    n = len(table)
    invalid = ~np.asarray(table.valid, dtype=bool)

    def masked(values) -> np.ndarray:
        values = np.array(values, dtype=float)
        values[invalid] = np.nan
        return values

    station = table.station_m
    cant = masked(table.cant_m)
    curvature = np.full(n, np.nan) if curvature_1pm is None else np.asarray(curvature_1pm, dtype=float)
    speed = np.full(n, np.nan) if speed_mps is None else np.asarray(speed_mps, dtype=float)
    deficiency = cant_deficiency_m(curvature, speed, cant)
    columns: dict[str, tuple[np.ndarray, str]] = {}
    for axis, values in zip("ENH", table.centre_enh_m.T):
        columns[f"centre_{axis}_m"] = (values, "%.4f")
    for name, values in zip(("roll", "pitch", "heading"), np.degrees(attitude_rad).T):
        columns[f"{name}_deg"] = (values, "%.6f")
    columns |= {
        "line_speed_kmh": (3.6 * speed, "%.1f"),
        "curvature_per_km": (1e3 * curvature, "%.6f"),
        "cant_change_rate_ratio": (rate_over_base(station, cant, bases["cant_change_rate"]), "%.6f"),
    }
    for direction, deviation, word in (("lateral", table.lateral_deviation_m, "alignment"),
                                       ("vertical", table.vertical_deviation_m, "height")):
        for side, rail in enumerate(("left", "right")):
            columns[f"{word}_change_rate_{rail}_ratio"] = (
                rate_over_base(station, masked(deviation[:, side]), bases["deviation_change_rate"]), "%.6f")
    columns |= {
        "cant_deficiency_mm": (1e3 * deficiency, "%.3f"),
        "cant_deficiency_rate_mm_per_s": (
            1e3 * cant_deficiency_rate_mps(station, deficiency, speed, bases["cant_deficiency_rate"]), "%.3f"),
    }
    return columns


def parameters_section(bases: dict[str, float], line_speeds: tuple[LineSpeed, ...], curvature_source: str) -> dict:
    """summary.toml's ``[track.parameters]``: the bases of the stored rates, the line speeds, where the
    curvature came from."""
    return {"cant_change_rate_base_m": bases["cant_change_rate"],
            "alignment_change_rate_base_m": bases["deviation_change_rate"],
            "height_change_rate_base_m": bases["deviation_change_rate"],
            "cant_deficiency_rate_base_m": bases["cant_deficiency_rate"],
            "curvature": curvature_source,
            "line_speeds": [{"from_m": r.from_m, "to_m": r.to_m, "kmh": r.kmh} for r in line_speeds]}


def speed_notices(profile: ToleranceProfile, table: SleeperTable, curvature_1pm: np.ndarray | None,
                  speed_mps: np.ndarray | None) -> list[Notice]:
    """A warning when the profile checks cant deficiency but valid sleepers lack a line speed or a curvature
    (those sleepers are not judged: their channel is empty)."""
    checks = [c.name for c in profile.checks if c.kind in SPEED_KINDS]
    if not checks or not len(table):
        return []
    valid = np.asarray(table.valid, dtype=bool)
    missing_speed = valid & (~np.isfinite(speed_mps) if speed_mps is not None else True)
    missing_curvature = valid & (~np.isfinite(curvature_1pm) if curvature_1pm is not None else True)
    notices = []
    for mask, what in ((missing_speed, Phrase("no line speed ([track] line_speed_kmh in project.toml)")),
                       (missing_curvature, Phrase("no curvature (no design alignment and no fitted line there)"))):
        if mask.any():
            station = table.station_m[mask]
            notices.append(Notice("track", "{checks} not checked at {count} sleepers between {from_m:.1f} m and "
                                           "{to_m:.1f} m: {what}", station_m=float(station[0]),
                                  fields={"checks": ", ".join(checks), "count": int(mask.sum()), "from_m": station[0],
                                          "to_m": station[-1], "what": what}))
    return notices
