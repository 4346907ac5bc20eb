"""Tolerance profiles: which checks a track must pass and their limits, read from TOML files.

A profile is a data file (shipped in ``resources/tolerance_profiles``; users copy one with
:func:`copy_tolerance_profile` and edit it). Values in the files are in millimetres (``*_mm``)
or dimensionless ratios (``*_ratio``, a number or a string "1/1500"); inside a
:class:`ToleranceProfile` every limit is in metres or a plain ratio.

File layout::

    name = "cn_hsr_ballastless"
    description = "..."
    source = "TB 10754-2018 ..."
    nominal_gauge_mm = 1435.0

    [checks.versine_10m]          # one table per check; the key names the check in reports
    kind = "versine"              # see KINDS
    chord_m = 10.0
    directions = ["lateral", "vertical"]
    max_abs_mm = 2.0              # or lower_mm / upper_mm (one of them may be omitted)

Every problem is reported as ``SettingsFileError(path, key path, message)`` (also used for the
fastener types of :mod:`insrail.track.adjustment`).
"""

from __future__ import annotations

import math
import shutil
import tomllib
from dataclasses import dataclass
from pathlib import Path

from insrail.io.atomic import atomic_write
from insrail.resources import resources_dir
from insrail.track.irregularity import BANDS_M

PROFILE_FOLDER = "tolerance_profiles"
DEFAULT_PROFILE = "cn_hsr_ballastless"
DIRECTIONS = ("lateral", "vertical")

# kind -> (unit suffix of its limits, parameter keys it accepts beyond the limits)
KINDS: dict[str, tuple[str, frozenset[str]]] = {
    "gauge_deviation": ("mm", frozenset()),
    "gauge_change_rate": ("ratio", frozenset({"base_m"})),
    "cross_level": ("mm", frozenset()),
    "twist": ("mm", frozenset({"base_m", "relative_to_design"})),
    "versine": ("mm", frozenset({"chord_m", "back_m", "directions"})),
    "differential_versine": ("mm", frozenset({"chord_m", "pair_m", "directions"})),
    "band_peak": ("mm", frozenset({"band", "directions"})),
    "cant_change_rate": ("ratio", frozenset({"base_m"})),
    "deviation_change_rate": ("ratio", frozenset({"base_m", "directions"})),  # alignment / height change rate
    "cant_deficiency": ("mm", frozenset()),  # needs [track] line_speed_kmh in the project
    "cant_deficiency_rate": ("mm_per_s", frozenset({"base_m"})),
}
REQUIRED = {
    "twist": ("base_m",),
    "versine": ("chord_m",),
    "differential_versine": ("chord_m", "pair_m"),
    "band_peak": ("band",),
    "cant_change_rate": ("base_m",),
    "deviation_change_rate": ("base_m",),
    "cant_deficiency_rate": ("base_m",),
}
#: Unit of a limit in the profile file -> factor to SI (m, ratio, m/s).
_SCALE = {"mm": 1e-3, "ratio": 1.0, "mm_per_s": 1e-3}
#: Kinds whose values need the project's line speed (and the curvature of the design or fitted line).
SPEED_KINDS = ("cant_deficiency", "cant_deficiency_rate")


def limit_unit(kind: str) -> str:
    """The unit a check kind's values are reported in: "mm", "ratio" or "mm_per_s"."""
    return KINDS[kind][0]


class SettingsFileError(ValueError):
    """A settings file (tolerance profile, fastener type) that cannot be used: file, key path
    inside it, what was expected."""

    def __init__(self, path: Path | str, key: str, message: str):
        self.path = Path(path)
        self.key = key
        self.message = message
        super().__init__(f"{path}: {key}: {message}" if key else f"{path}: {message}")


@dataclass(frozen=True)
class Check:
    """One check of a profile. ``lower``/``upper`` in metres (ratio for rates); +-inf when open.

    ``base_m`` None for a gauge change rate means sleeper to sleeper.
    """

    name: str
    kind: str
    lower: float
    upper: float
    directions: tuple[str, ...] = ()
    chord_m: float | None = None
    back_m: float | None = None
    pair_m: float | None = None
    base_m: float | None = None
    band: str | None = None
    relative_to_design: bool = True
    note: str = ""


@dataclass(frozen=True)
class ToleranceProfile:
    name: str
    description: str
    source: str
    nominal_gauge_m: float
    checks: tuple[Check, ...]
    path: Path


def read_number(path: Path, key: str, raw: object, positive: bool = False) -> float:
    if isinstance(raw, bool) or not isinstance(raw, (int, float)) or not math.isfinite(raw):
        raise SettingsFileError(path, key, f"expected a number, found {raw!r}")
    if positive and raw <= 0:
        raise SettingsFileError(path, key, f"expected a positive number, found {raw!r}")
    return float(raw)


def _ratio(path: Path, key: str, raw: object) -> float:
    """A ratio given as a number or as "1/N"."""
    if isinstance(raw, str):
        numerator, slash, denominator = raw.partition("/")
        try:
            value = float(numerator) / float(denominator) if slash else float(raw)
        except (ValueError, ZeroDivisionError):
            raise SettingsFileError(path, key, f'expected a number or a ratio like "1/1500", found {raw!r}') from None
        return read_number(path, key, value)
    return read_number(path, key, raw)


def _limits(path: Path, key: str, table: dict, unit: str) -> tuple[float, float]:
    read = _ratio if unit == "ratio" else read_number
    names = {f"max_abs_{unit}", f"lower_{unit}", f"upper_{unit}"}
    given = names & table.keys()
    if f"max_abs_{unit}" in given:
        if len(given) > 1:
            raise SettingsFileError(path, key, f"give either max_abs_{unit} or lower_{unit}/upper_{unit}, not both")
        limit = read(path, f"{key}.max_abs_{unit}", table[f"max_abs_{unit}"])
        if limit <= 0:
            raise SettingsFileError(path, f"{key}.max_abs_{unit}", f"expected a positive limit, found {limit}")
        return -limit * _SCALE[unit], limit * _SCALE[unit]
    if not given:
        raise SettingsFileError(path, key, f"no limit: expected max_abs_{unit} or lower_{unit}/upper_{unit}")
    lower = read(path, f"{key}.lower_{unit}", table[f"lower_{unit}"]) if f"lower_{unit}" in given else -math.inf
    upper = read(path, f"{key}.upper_{unit}", table[f"upper_{unit}"]) if f"upper_{unit}" in given else math.inf
    if not lower < upper:
        raise SettingsFileError(path, key, f"lower_{unit} ({lower}) must be below upper_{unit} ({upper})")
    return lower * _SCALE[unit], upper * _SCALE[unit]


def _check(path: Path, name: str, table: object) -> Check:
    key = f"checks.{name}"
    if not isinstance(table, dict):
        raise SettingsFileError(path, key, "expected a table")
    kind = table.get("kind")
    if kind not in KINDS:
        raise SettingsFileError(path, f"{key}.kind", f"expected one of {', '.join(KINDS)}, found {kind!r}")
    unit, parameters = KINDS[kind]
    allowed = parameters | {"kind", "note", f"max_abs_{unit}", f"lower_{unit}", f"upper_{unit}"}
    unknown = sorted(set(table) - allowed)
    if unknown:
        raise SettingsFileError(
            path, f"{key}.{unknown[0]}", f"not a setting of a {kind} check (expected {', '.join(sorted(allowed))})"
        )
    for required in REQUIRED.get(kind, ()):
        if required not in table:
            raise SettingsFileError(path, f"{key}.{required}", f"a {kind} check needs {required}")
    lower, upper = _limits(path, key, table, unit)
    fields: dict[str, object] = {}
    for length in ("chord_m", "back_m", "pair_m"):
        if length in table:
            fields[length] = read_number(path, f"{key}.{length}", table[length], positive=True)
    if "base_m" in table:
        base = table["base_m"]
        if not (kind == "gauge_change_rate" and base == "sleeper"):
            fields["base_m"] = read_number(path, f"{key}.base_m", base, positive=True)
    if kind == "gauge_change_rate" and "base_m" not in table:
        raise SettingsFileError(path, f"{key}.base_m", 'expected a base length in metres or "sleeper"')
    if "pair_m" in fields and not fields["pair_m"] < fields["chord_m"]:
        raise SettingsFileError(path, f"{key}.pair_m", "the point pair must be shorter than the chord")
    if "back_m" in fields and not fields["back_m"] < fields["chord_m"]:
        raise SettingsFileError(path, f"{key}.back_m", "the back part must be shorter than the chord")
    if "band" in table and table["band"] not in BANDS_M:
        raise SettingsFileError(path, f"{key}.band", f"expected one of {', '.join(BANDS_M)}, found {table['band']!r}")
    if "relative_to_design" in table and not isinstance(table["relative_to_design"], bool):
        raise SettingsFileError(path, f"{key}.relative_to_design", "expected true or false")
    directions = table.get("directions", list(DIRECTIONS) if "directions" in parameters else [])
    if not isinstance(directions, list) or not set(directions) <= set(DIRECTIONS) or len(set(directions)) != len(directions):
        raise SettingsFileError(path, f"{key}.directions", f'expected a list of "lateral" and/or "vertical", found {directions!r}')
    if "directions" in parameters and not directions:
        raise SettingsFileError(path, f"{key}.directions", "expected at least one direction")
    return Check(
        name=name,
        kind=kind,
        lower=lower,
        upper=upper,
        directions=tuple(directions),
        band=table.get("band"),
        relative_to_design=table.get("relative_to_design", True),
        note=str(table.get("note", "")),
        **fields,
    )


def profile_path(name_or_path: str | Path) -> Path:
    """The file of a shipped profile name, or the given path of a ``.toml`` file."""
    path = Path(name_or_path)
    if path.suffix == ".toml":
        return path
    return resources_dir() / PROFILE_FOLDER / f"{name_or_path}.toml"


def shipped_tolerance_profiles() -> list[str]:
    return sorted(p.stem for p in (resources_dir() / PROFILE_FOLDER).glob("*.toml"))


def load_tolerance_profile(name_or_path: str | Path = DEFAULT_PROFILE) -> ToleranceProfile:
    """Load and validate a profile by shipped name or file path (SettingsFileError if unusable)."""
    path = profile_path(name_or_path)
    if not path.is_file():
        raise SettingsFileError(path, "", f"no such tolerance profile (shipped: {', '.join(shipped_tolerance_profiles())})")
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as err:
        raise SettingsFileError(path, "", f"not valid TOML: {err}") from None
    except UnicodeDecodeError as err:
        raise SettingsFileError(path, "", f"not UTF-8 text: {err}") from None
    unknown = sorted(set(data) - {"name", "description", "source", "nominal_gauge_mm", "checks"})
    if unknown:
        raise SettingsFileError(path, unknown[0], "unknown key (expected name, description, source, nominal_gauge_mm, checks)")
    for text_key in ("name", "description", "source"):
        if text_key in data and not isinstance(data[text_key], str):
            raise SettingsFileError(path, text_key, f"expected text, found {data[text_key]!r}")
    checks = data.get("checks")
    if not isinstance(checks, dict) or not checks:
        raise SettingsFileError(path, "checks", "expected at least one [checks.<name>] table")
    gauge = read_number(path, "nominal_gauge_mm", data.get("nominal_gauge_mm", 1435.0), positive=True)
    return ToleranceProfile(
        name=data.get("name", path.stem),
        description=data.get("description", ""),
        source=data.get("source", ""),
        nominal_gauge_m=gauge * 1e-3,
        checks=tuple(_check(path, name, table) for name, table in checks.items()),
        path=path,
    )


def copy_tolerance_profile(name_or_path: str | Path, destination: str | Path) -> Path:
    """Copy a profile to ``destination`` (atomically) for the user to edit; refuses to overwrite."""
    source = profile_path(name_or_path)
    load_tolerance_profile(source)  # only a valid profile is worth copying
    destination = Path(destination)
    if destination.exists():
        raise FileExistsError(f"{destination}: already exists; choose another name")
    with atomic_write(destination, "wb") as handle, source.open("rb") as original:
        shutil.copyfileobj(original, handle)
    return destination
