"""Typed containers for raw survey data, as the readers return them.

Every array is a numpy array; units are in the field names. Time stamps are GPS
time in seconds of the GPS week (``gps_week`` says which week when known). Body
frame b is the IMU's forward-right-down; NED is north-east-down.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np


GAP_FACTOR = 1.5
"""An interval longer than GAP_FACTOR x the median interval is reported as a Gap."""


@dataclass(frozen=True)
class Gap:
    """A gap in a time series longer than the tolerance: from ``start_s`` to ``end_s``."""

    start_s: float
    end_s: float

    @property
    def duration_s(self) -> float:
        return self.end_s - self.start_s


@dataclass(frozen=True)
class ImuIncrements:
    """IMU angle and velocity increments over the interval ending at ``time_s``.

    time_s     : (n,) end of each sample interval [s of GPS week]
    dtheta_rad : (n, 3) integral of the body angular rate omega_ib^b [rad], FRD
    dvel_mps   : (n, 3) integral of the specific force f^b [m/s], FRD
    gaps       : intervals where consecutive samples are further apart than 1.5
                 nominal sample intervals (``GAP_FACTOR``); the sample after a gap holds
                 the increments of one nominal interval, not of the whole gap (every
                 reader keeps this; ``insrail.nav.imu_gaps`` bridges the gap once)
    """

    time_s: np.ndarray
    dtheta_rad: np.ndarray
    dvel_mps: np.ndarray
    gps_week: int | None = None
    gaps: tuple[Gap, ...] = ()
    source: Path | None = None

    def __len__(self) -> int:
        return len(self.time_s)

    @property
    def rate_hz(self) -> float:
        """Nominal sample rate from the median interval."""
        return float(1.0 / np.median(np.diff(self.time_s), overwrite_input=True))


@dataclass(frozen=True)
class GnssSolution:
    """GNSS antenna positions (and optionally velocities), one row per epoch.

    lat_rad, lon_rad, height_m : geodetic position of the antenna phase centre
                                 (ellipsoidal height)
    sigma_ned_m   : (n, 3) standard deviations north, east, down [m]
    quality       : (n,) RTKLIB Q flag (1 fix, 2 float, 3 SBAS, 4 DGPS, 5 single,
                    6 PPP); 0 when the format carries none
    num_sats      : (n,) satellites used, 0 when unknown
    ratio         : (n,) ambiguity ratio test value, NaN when unknown
    vel_ned_mps   : (n, 3) velocity north, east, down or None
    sigma_vel_ned_mps : (n, 3) or None
    """

    time_s: np.ndarray
    lat_rad: np.ndarray
    lon_rad: np.ndarray
    height_m: np.ndarray
    sigma_ned_m: np.ndarray
    quality: np.ndarray
    num_sats: np.ndarray
    ratio: np.ndarray
    vel_ned_mps: np.ndarray | None = None
    sigma_vel_ned_mps: np.ndarray | None = None
    gps_week: int | None = None
    gaps: tuple[Gap, ...] = ()
    source: Path | None = None

    def __len__(self) -> int:
        return len(self.time_s)


@dataclass(frozen=True)
class OdometerData:
    """Cumulative travelled distance of the odometer wheel (signed: backwards decreases).

    distance_m : (n,) cumulative distance [m] as the sensor reports it, i.e. still
                 carrying the sensor's scale-factor error
    pulse_length_m : length of one pulse [m] when the file held pulse counts, else None
    left_out   : stretches whose speeds the fusion does not use (a wheel's slip, found against a
                 second odometer and bridged by it: ``insrail.nav.odometer_pair``)
    """

    time_s: np.ndarray
    distance_m: np.ndarray
    pulse_length_m: float | None = None
    gaps: tuple[Gap, ...] = ()
    source: Path | None = None
    left_out: tuple[Gap, ...] = ()

    def __len__(self) -> int:
        return len(self.time_s)


@dataclass(frozen=True)
class GaugeData:
    """Gauge-sensor readings: track gauge [m] (files hold mm)."""

    time_s: np.ndarray
    gauge_m: np.ndarray
    gaps: tuple[Gap, ...] = ()
    source: Path | None = None

    def __len__(self) -> int:
        return len(self.time_s)


@dataclass(frozen=True)
class SleeperPulses:
    """Time of each sleeper-detector pulse."""

    time_s: np.ndarray
    source: Path | None = None

    def __len__(self) -> int:
        return len(self.time_s)


@dataclass(frozen=True)
class PrismObservations:
    """Total-station positions of the trolley's prism on CPIII control, engineering frame.

    point_id : (n,) str, the CPIII station or point the observation refers to ("" if none)
    east_m, north_m, height_m : prism position [m] in the engineering plane / normal height
    sigma_m  : (n,) standard deviation of each coordinate [m]
    """

    time_s: np.ndarray
    east_m: np.ndarray
    north_m: np.ndarray
    height_m: np.ndarray
    sigma_m: np.ndarray
    point_id: np.ndarray = field(default_factory=lambda: np.array([], dtype=str))
    source: Path | None = None

    def __len__(self) -> int:
        return len(self.time_s)


@dataclass(frozen=True)
class TotalStationObservations:
    """Raw pointings of free total stations (:mod:`insrail.io.total_station`), one row each.

    setup    : (n,) str, the set-up a pointing belongs to
    target   : (n,) str, a CPIII point id, or "prism" for the trolley's prism
    time_s   : (n,) time of the pointing [s of GPS week]
    hz_rad   : (n,) horizontal direction, clockwise from the circle's zero [rad]
    zenith_rad, slope_m : (n,) zenith angle [rad], slope distance [m]
    line     : (n,) the line of the file each row came from (for messages)
    """

    setup: np.ndarray
    target: np.ndarray
    time_s: np.ndarray
    hz_rad: np.ndarray
    zenith_rad: np.ndarray
    slope_m: np.ndarray
    line: np.ndarray
    source: Path | None = None

    def __len__(self) -> int:
        return len(self.time_s)


@dataclass(frozen=True)
class ControlPoints:
    """CPIII points in the engineering frame: id, easting, northing [m], normal height [m]."""

    point_id: np.ndarray
    east_m: np.ndarray
    north_m: np.ndarray
    height_m: np.ndarray
    source: Path | None = None

    def __len__(self) -> int:
        return len(self.point_id)


@dataclass(frozen=True)
class Benchmarks:
    """GNSS-levelling benchmarks: ellipsoidal height h and normal height H at the same point."""

    point_id: tuple[str, ...]
    lat_rad: np.ndarray
    lon_rad: np.ndarray
    h_m: np.ndarray
    normal_height_m: np.ndarray
    source: Path | None = None

    def __len__(self) -> int:
        return len(self.point_id)

    @property
    def height_anomaly_m(self) -> np.ndarray:
        """zeta = h - H at each benchmark [m]."""
        return self.h_m - self.normal_height_m
