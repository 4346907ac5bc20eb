"""IMU error profiles: the noise and sensor-error parameters of an IMU grade.

A profile is a TOML file (``resources/imu_profiles/<name>.toml``, or any file the user
copies and edits) in the units of data sheets: deg/sqrt(h), deg/h, m/s/sqrt(h), mGal,
ppm, seconds. :class:`ImuProfile` holds the same values in SI. The simulator draws
its sensor errors from a profile; the fusion filter takes its process noise from one, the
start-up its gyrocompass accuracy and stop thresholds, and the sensor-level screening
(``insrail.nav.imu_screening``) the optional ``[range]`` table: the measurement range and the
largest change between neighbouring records (g, deg/s; defaults :data:`DEFAULT_RANGE`).
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from pathlib import Path

from insrail.notices import ONE_A_LINE, Phrase, one_after_another
from insrail.resources import resources_dir

_DEG = math.pi / 180.0
_MGAL = 1e-5  # m/s^2


@dataclass(frozen=True)
class ImuProfile:
    """Sensor-error model in SI units.

    Gyro: angle random walk [rad/sqrt(s)], turn-on bias [rad/s] (1 sigma, constant over
    a run), Gauss-Markov in-run bias sigma [rad/s] and correlation time [s], scale
    factor [-] (1 sigma) and the correlation time the filter assumes for it. Accel:
    velocity random walk [m/s/sqrt(s)], biases [m/s^2], scale factor [-]. Envelope: the
    measurement range per axis and the largest change between neighbouring records a trolley
    gives [m/s^2, rad/s]; records outside it are outliers.
    """

    name: str
    description: str
    rate_hz: float
    gyro_arw: float
    gyro_bias_turn_on: float
    gyro_bias_gm_sigma: float
    gyro_bias_gm_tau_s: float
    gyro_scale_factor: float
    gyro_scale_factor_tau_s: float
    accel_vrw: float
    accel_bias_turn_on: float
    accel_bias_gm_sigma: float
    accel_bias_gm_tau_s: float
    accel_scale_factor: float
    accel_scale_factor_tau_s: float
    specific_force_range_mps2: float = 20.0 * 9.80665
    rate_range_radps: float = 400.0 * _DEG
    specific_force_jump_mps2: float = 2.0 * 9.80665
    rate_jump_radps: float = 50.0 * _DEG


_FIELDS = {
    # (section, key in the file): (attribute, factor to SI)
    ("gyro", "arw_deg_per_sqrt_h"): ("gyro_arw", _DEG / 60.0),
    ("gyro", "bias_turn_on_deg_per_h"): ("gyro_bias_turn_on", _DEG / 3600.0),
    ("gyro", "bias_gm_sigma_deg_per_h"): ("gyro_bias_gm_sigma", _DEG / 3600.0),
    ("gyro", "bias_gm_tau_s"): ("gyro_bias_gm_tau_s", 1.0),
    ("gyro", "scale_factor_ppm"): ("gyro_scale_factor", 1e-6),
    ("gyro", "scale_factor_gm_tau_s"): ("gyro_scale_factor_tau_s", 1.0),
    ("accel", "vrw_mps_per_sqrt_h"): ("accel_vrw", 1.0 / 60.0),
    ("accel", "bias_turn_on_mgal"): ("accel_bias_turn_on", _MGAL),
    ("accel", "bias_gm_sigma_mgal"): ("accel_bias_gm_sigma", _MGAL),
    ("accel", "bias_gm_tau_s"): ("accel_bias_gm_tau_s", 1.0),
    ("accel", "scale_factor_ppm"): ("accel_scale_factor", 1e-6),
    ("accel", "scale_factor_gm_tau_s"): ("accel_scale_factor_tau_s", 1.0),
}


_G = 9.80665
#: [range] keys: (attribute, factor to SI, default in the file's unit)
_RANGE_FIELDS = {
    "specific_force_g": ("specific_force_range_mps2", _G, 20.0),
    "rate_deg_per_s": ("rate_range_radps", _DEG, 400.0),
    "specific_force_jump_g": ("specific_force_jump_mps2", _G, 2.0),
    "rate_jump_deg_per_s": ("rate_jump_radps", _DEG, 50.0),
}
DEFAULT_RANGE = {key: default for key, (_, _, default) in _RANGE_FIELDS.items()}


def load_imu_profile(name_or_path: str | Path) -> ImuProfile:
    """Load a profile by name (shipped in resources/imu_profiles) or from a TOML file path.

    Raises ValueError naming the file and every missing or invalid key.
    """
    path = Path(name_or_path)
    if path.suffix != ".toml":
        path = resources_dir() / "imu_profiles" / f"{name_or_path}.toml"
    if not path.is_file():
        shipped = sorted(p.stem for p in (resources_dir() / "imu_profiles").glob("*.toml"))
        raise ValueError(Phrase("IMU profile not found: {name} (shipped profiles: {shipped})",
                                {"name": str(name_or_path), "shipped": ", ".join(shipped)}))
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as err:
        raise ValueError(Phrase("{path}: not valid TOML: {error}", {"path": str(path), "error": str(err)})) from None
    values: dict[str, object] = {}
    problems = []
    for (section, key), (attr, factor) in _FIELDS.items():
        raw = data.get(section, {}).get(key)
        if not isinstance(raw, (int, float)) or isinstance(raw, bool) or not math.isfinite(raw) or raw < 0:
            problems.append(Phrase("{section}.{key}: expected a non-negative number, found {raw!r}",
                                   {"section": section, "key": key, "raw": raw}))
        elif key.endswith("tau_s") and raw <= 0:
            problems.append(Phrase("{section}.{key}: a correlation time must be positive", {"section": section, "key": key}))
        else:
            values[attr] = float(raw) * factor
    envelope = data.get("range", {})
    if not isinstance(envelope, dict):
        problems.append(Phrase("range: expected a table [range]"))
        envelope = {}
    for key in envelope:
        if key not in _RANGE_FIELDS:
            problems.append(Phrase("range.{key}: unknown key (expected {expected})",
                                   {"key": key, "expected": ", ".join(_RANGE_FIELDS)}))
    for key, (attr, factor, default) in _RANGE_FIELDS.items():
        raw = envelope.get(key, default)
        if not isinstance(raw, (int, float)) or isinstance(raw, bool) or not math.isfinite(raw) or raw <= 0:
            problems.append(Phrase("range.{key}: expected a positive number, found {raw!r}", {"key": key, "raw": raw}))
        else:
            values[attr] = float(raw) * factor
    rate = data.get("rate_hz", 200.0)
    if not isinstance(rate, (int, float)) or rate <= 0:
        problems.append(Phrase("rate_hz: expected a positive number, found {rate!r}", {"rate": rate}))
    if problems:
        raise ValueError(Phrase("{path}: invalid IMU profile:\n  {problems}",
                                {"path": str(path), "problems": one_after_another(problems, ONE_A_LINE)}))
    return ImuProfile(
        name=str(data.get("name", path.stem)),
        description=str(data.get("description", "")),
        rate_hz=float(rate),
        **values,
    )
