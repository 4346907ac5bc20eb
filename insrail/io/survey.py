"""The survey folder: one trolley run's raw files plus ``survey.toml`` describing them.

``survey.toml`` names each raw file with its role and format, the trolley's
geometry (lever arms, mounting angles) and the IMU profile. Paths inside it are
relative to the folder. Lever arms are vectors from the IMU measurement centre to
the named point, resolved in the IMU body frame b (forward-right-down), metres.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from insrail.io.types import (
    Benchmarks,
    GaugeData,
    GnssSolution,
    ImuIncrements,
    OdometerData,
    PrismObservations,
    SleeperPulses,
)


@dataclass(frozen=True)
class TrolleyGeometry:
    """Calibrated geometry of the trolley (b-frame lever arms in metres, angles in radians).

    imu_to_antenna_m          : to the GNSS antenna phase centre
    imu_to_odometer_m         : to the contact point of the odometer wheel with the rail top
    imu_to_prism_m            : to the total-station prism centre
    imu_to_sleeper_detector_m : to the sleeper detector's sensing point
    imu_to_reference_rail_m   : to the top-of-rail point above the gauge face of the
                                reference rail, the rail the trolley's fixed wheels run on
    reference_rail            : "left" or "right" (seen in the direction of travel)
    mounting_rpy_rad          : roll, pitch, heading of b relative to the trolley frame v,
                                C_b^v = euler_to_dcm(*mounting_rpy_rad)
    rail_centre_spacing_m     : base of the cant definition, cant = base * sin(roll) (1.5 m)
    """

    imu_to_antenna_m: np.ndarray
    imu_to_odometer_m: np.ndarray
    imu_to_prism_m: np.ndarray
    imu_to_sleeper_detector_m: np.ndarray
    imu_to_reference_rail_m: np.ndarray
    reference_rail: str = "left"
    mounting_rpy_rad: np.ndarray = field(default_factory=lambda: np.zeros(3))
    rail_centre_spacing_m: float = 1.5


@dataclass(frozen=True)
class SurveyFile:
    """One raw file of a survey: its path (relative to the folder), format and options."""

    path: str
    format: str
    options: dict = field(default_factory=dict)


@dataclass(frozen=True)
class SurveyManifest:
    """Contents of ``survey.toml``.

    files maps a role (``imu gnss odometer gauge sleepers prism benchmarks``) to a
    :class:`SurveyFile`; imu, gnss and odometer are required, the rest optional.
    """

    name: str
    files: dict[str, SurveyFile]
    trolley: TrolleyGeometry
    imu_profile: str = "nav"
    gps_week: int | None = None
    description: str = ""


@dataclass(frozen=True)
class SurveyData:
    """All raw data of one survey, loaded and validated."""

    manifest: SurveyManifest
    folder: Path
    imu: ImuIncrements
    gnss: GnssSolution
    odometer: OdometerData
    gauge: GaugeData | None = None
    sleepers: SleeperPulses | None = None
    prism: PrismObservations | None = None
    benchmarks: Benchmarks | None = None
