"""Sensitivity sweeps like the thesis's chapter 3: one parameter at a time from a baseline.

Parameters (values in the units surveyors quote):

=============  ===========  ==========================================================
gyro_bias      deg/h        in-run (Gauss-Markov) RMS; the turn-on bias scales with it
accel_bias     mGal         in-run RMS; the turn-on bias scales with it
arw            deg/sqrt(h)  gyro angle random walk
vrw            m/s/sqrt(h)  accelerometer velocity random walk
gnss_sigma     m            white horizontal sigma; vertical twice that (thesis 1/2 cm)
speed          m/s          trolley speed
=============  ===========  ==========================================================
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from insrail.names import quantity_name
from insrail.nav.imu_profile import ImuProfile, load_imu_profile
from insrail.notices import Phrase
from insrail.progress import CancelToken, ProgressFn, StepProgress, check_cancel
from insrail.quality.prediction import AccuracyFigures, GnssQuality, predict

_DEG_PER_H = math.radians(1.0) / 3600.0
_MGAL = 1e-5

#: name -> (unit, SI factor)
PARAMETERS = {
    "gyro_bias": ("deg/h", _DEG_PER_H),
    "accel_bias": ("mGal", _MGAL),
    "arw": ("deg/sqrt(h)", math.radians(1.0) / 60.0),
    "vrw": ("m/s/sqrt(h)", 1.0 / 60.0),
    "gnss_sigma": ("m", 1.0),
    "speed": ("m/s", 1.0),
}


@dataclass(frozen=True)
class SweepTable:
    parameter: str
    unit: str
    values: tuple[float, ...]
    forward: tuple[AccuracyFigures, ...]
    smoothed: tuple[AccuracyFigures | None, ...]


def _with(profile: ImuProfile, parameter: str, si: float) -> ImuProfile:
    if parameter == "gyro_bias":
        scale = si / profile.gyro_bias_gm_sigma
        return replace(profile, gyro_bias_gm_sigma=si, gyro_bias_turn_on=profile.gyro_bias_turn_on * scale)
    if parameter == "accel_bias":
        scale = si / profile.accel_bias_gm_sigma
        return replace(profile, accel_bias_gm_sigma=si, accel_bias_turn_on=profile.accel_bias_turn_on * scale)
    if parameter == "arw":
        return replace(profile, gyro_arw=si)
    if parameter == "vrw":
        return replace(profile, accel_vrw=si)
    return profile


def sweep(
    parameter: str,
    values,
    profile: ImuProfile | str = "nav",
    gnss: GnssQuality = GnssQuality(),
    speed_mps: float = 1.0,
    progress: ProgressFn | None = None,
    cancel: CancelToken = None,
    **predict_kwargs,
) -> SweepTable:
    """Predict the figures for each value of ``parameter``, the rest at the baseline
    (the profile, ``gnss``, ``speed_mps`` and ``predict_kwargs`` as for :func:`predict`)."""
    if parameter not in PARAMETERS:
        raise ValueError(f"unknown sweep parameter {parameter!r}; choose one of {', '.join(PARAMETERS)}")
    values = tuple(float(v) for v in values)
    if not values or min(values) <= 0.0:
        raise ValueError(f"sweep values must be positive, got {values}")
    unit, factor = PARAMETERS[parameter]
    base = load_imu_profile(profile) if isinstance(profile, str) else profile
    step = StepProgress(progress)
    forward, smoothed = [], []
    for i, value in enumerate(values):
        check_cancel(cancel)
        step(i / len(values), Phrase("{parameter} = {value:g} {unit}",
                                          {"parameter": Phrase(quantity_name(parameter).name), "value": value, "unit": unit}))
        si = value * factor
        kwargs = dict(predict_kwargs, speed_mps=si if parameter == "speed" else speed_mps)
        gnss_i = replace(gnss, white_horizontal_m=si, white_vertical_m=2.0 * si) if parameter == "gnss_sigma" else gnss
        p = predict(_with(base, parameter, si), gnss_i, cancel=cancel, **kwargs)
        forward.append(p.forward)
        smoothed.append(p.smoothed)
    step(1.0, "sweep done")
    return SweepTable(parameter, unit, values, tuple(forward), tuple(smoothed))
