"""Display names: what every id a user can see is called on screen and on paper.

The one table of human names for the GUI, the workbook and the PDF. Internal ids (tolerance
check names such as ``short_wave_30m_5m``, sleepers.csv columns such as ``gauge_mm``, TQI
channels, predicted-accuracy figures) never reach a user: a shell asks this module.

* :func:`check_name` names a check of a tolerance profile. A check's id is free text in the
  profile file, so the name is built from the check's definition (its kind and parameters):
  a shipped id has its own wording (``short_wave_30m_5m`` -> "30 m / 5 m short wave"), any other
  id the wording of its kind ("20 m versine"), always with the check's own lengths, so a copied
  profile with a changed chord is never misnamed.
* :func:`channel_name` one rail/direction channel of a check ("30 m / 5 m short wave, left rail,
  lateral"); :func:`rail_direction` the part that tells the channels of one check apart.
* :func:`column_name` a sleepers.csv column (the check channels ``check_*`` need the profile);
  :func:`quantity_name` any other id shown (TQI channels, quality.csv figures, parameters).
* :func:`setting_name` a project.toml setting by its key path (the forms' labels, the properties
  panel, a problem of the project file in words).

Units are those displayed at the reporting edge: lengths in mm or m, ratios (gauge change rates)
in per mille (‰). A lookup of an id this module does not know raises :class:`UnknownName`, never
returns the id: a new column or quantity gets its name here before it is shown.

Languages (:data:`LANGUAGES`): every wording of this module and every text the reports and exports
print is written in English, in the code, and passed through :func:`t`, which gives it in the
language in use; the other languages' tables map the English wording to theirs (Simplified Chinese:
:data:`insrail.names_zh.ZH_CN`, with the field's standard terms: 轨距, 水平, 轨向, 高低, 扭曲, 里程 ...).
Adding a text is one entry there; ``tests/test_languages.py`` fails on a text without one. A
template's fields (``"{chord_m:g} m versine"``) are filled after translation. The language in use is
the report's (``[report] language`` of project.toml, :func:`in_language` while a report is written)
or, outside one, the process's (:func:`set_language`: the desktop application's).
"""

from __future__ import annotations

import contextlib
import contextvars
import re
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from typing import Protocol

# --------------------------------------------------------------------------- languages

#: The languages of the reports and the application (project.toml ``[report] language``), each in its own words.
LANGUAGES = {"en": "English", "zh-CN": "简体中文 (Simplified Chinese)"}
DEFAULT_LANGUAGE = "en"
_process_language = DEFAULT_LANGUAGE
_report_language: contextvars.ContextVar[str | None] = contextvars.ContextVar("insrail_language", default=None)


def language() -> str:
    """The language texts are given in now (module docstring)."""
    return _report_language.get() or _process_language


def set_language(code: str) -> None:
    """The process's language (the desktop application's, from the locale or the preferences)."""
    global _process_language
    _process_language = code if code in LANGUAGES else DEFAULT_LANGUAGE


@contextlib.contextmanager
def in_language(code: str) -> Iterator[None]:
    """Texts in ``code`` in this thread while the block runs (a report in its project's language)."""
    token = _report_language.set(code)
    try:
        yield
    finally:
        _report_language.reset(token)


def language_of_locale(name: str) -> str:
    """The language for a locale name ("zh_CN", "zh-Hans-CN", "en_US"): Chinese for any Chinese locale."""
    return "zh-CN" if name.lower().startswith("zh") else DEFAULT_LANGUAGE


def _table(code: str) -> dict[str, str]:
    from insrail.names_zh import ZH_CN  # one module per language; English is the code's own wording

    return {"zh-CN": ZH_CN}[code]


def t(text: str) -> str:
    """``text`` (English, as written in the code) in the language in use; a text the language's table
    lacks stays English (the tests name it; a report is never refused for a missing word)."""
    code = language()
    if code == DEFAULT_LANGUAGE or not text:
        return text
    return _table(code).get(text, text)


def joined(parts: Iterable[str]) -> str:
    """Parts of a name joined as the language lists them ("left rail, lateral"; "左轨，横向")."""
    return ("，" if language() == "zh-CN" else ", ").join(p for p in parts if p)

FOOT_M = 0.3048
PER_MILLE = "‰"


class UnknownName(KeyError):
    """An id without a display name (add it to this module's tables)."""

    def __init__(self, key: str, what: str = "id"):
        self.key = key
        super().__init__(f"no display name for the {what} {key!r} (add it to insrail/names.py)")


@dataclass(frozen=True)
class Name:
    """A display name and the unit its values are shown in ("" for none)."""

    name: str
    unit: str = ""

    @property
    def translated(self) -> Name:
        """This name in the language in use (the tables hold the English wording)."""
        return Name(t(self.name), self.unit)

    @property
    def with_unit(self) -> str:
        """"Gauge (mm)", or the bare name without a unit."""
        return f"{self.name} ({self.unit})" if self.unit else self.name


class CheckLike(Protocol):
    """What naming needs of :class:`insrail.track.tolerance.Check`."""

    name: str
    kind: str
    directions: tuple[str, ...]
    chord_m: float | None
    back_m: float | None
    pair_m: float | None
    base_m: float | None
    band: str | None
    relative_to_design: bool


# --------------------------------------------------------------------------- checks

#: Wording of each check kind; fields are the check's own (lengths in m, ``*_ft`` in feet). A twist of the
#: cross level (measured - design cant, the designed ramp removed) is plain "Twist"; one of the measured
#: cant says so.
KIND_NAMES = {
    "gauge_deviation": "Gauge deviation",
    "gauge_change_rate": "Gauge change rate {base}",
    "cross_level": "Cross level",
    "twist": "Twist {base_m:g} m{twist_of}",
    "versine": "{chord_m:g} m versine",
    "differential_versine": "{chord_m:g} m / {pair_m:g} m differential versine",
    "band_peak": "{band} band peak",
    "cant_change_rate": "Cant change rate {base}",
    "deviation_change_rate": "Alignment and height change rate {base}",
    "cant_deficiency": "Cant deficiency",
    "cant_deficiency_rate": "Cant deficiency rate {base}",
}
#: The shipped profiles' check ids, each with the kind it names and its wording.
CHECK_NAMES = {
    "gauge": ("gauge_deviation", "Gauge deviation"),
    "gauge_change_rate": ("gauge_change_rate", "Gauge change rate {base}"),
    "cross_level": ("cross_level", "Cross level"),
    "twist_3m": ("twist", "Twist {base_m:g} m{twist_of}"),
    "twist_6_25m": ("twist", "Twist {base_m:g} m{twist_of}"),
    "twist_62ft": ("twist", "Twist {base_ft:g} ft{twist_of}"),
    "versine_10m": ("versine", "{chord_m:g} m versine"),
    "short_wave_30m_5m": ("differential_versine", "{chord_m:g} m / {pair_m:g} m short wave"),
    "long_wave_300m_150m": ("differential_versine", "{chord_m:g} m / {pair_m:g} m long wave"),
    "alignment_62ft": ("versine", "Alignment {chord_ft:g} ft chord"),
    "profile_62ft": ("versine", "Profile {chord_ft:g} ft chord"),
    "alignment_d1": ("band_peak", "Alignment {band}"),
    "level_d1": ("band_peak", "Longitudinal level {band}"),
}
RAIL_NAMES = {"left": "left rail", "right": "right rail", "track": ""}
DIRECTION_NAMES = {"lateral": "lateral", "vertical": "vertical", "": ""}


def _fields(check: CheckLike) -> dict[str, object]:
    def feet(value):
        return round(value / FOOT_M, 1) if value is not None else None

    base = t("sleeper to sleeper") if check.base_m is None else f"{check.base_m:g} m"
    return {"chord_m": check.chord_m, "pair_m": check.pair_m, "back_m": check.back_m, "base_m": check.base_m,
            "chord_ft": feet(check.chord_m), "base_ft": feet(check.base_m), "band": check.band, "base": base,
            "twist_of": "" if check.relative_to_design else t(" of the measured cant")}


def check_name(check: CheckLike) -> str:
    """The display name of a tolerance check (see the module docstring)."""
    kind, wording = CHECK_NAMES.get(check.name, (None, None))
    if kind != check.kind:
        if check.kind not in KIND_NAMES:
            raise UnknownName(check.kind, "check kind")
        wording = KIND_NAMES[check.kind]
    return t(wording).format(**_fields(check))


#: Check kinds whose values are neither lengths nor ratios.
_KIND_UNITS = {"cant_deficiency_rate": "mm/s"}


def check_unit(kind: str) -> str:
    """The unit a check's values and limits are displayed in."""
    return _KIND_UNITS.get(kind) or (PER_MILLE if kind.endswith("rate") else "mm")


def rail_direction(rail: str, direction: str) -> str:
    """"left rail, lateral", "right rail", "" (a track channel)."""
    try:
        parts = (RAIL_NAMES[rail], DIRECTION_NAMES[direction])
    except KeyError as error:
        raise UnknownName(error.args[0], "rail or direction") from None
    if all(parts):  # a language may have one word for both: 左轨向 (left rail, lateral), 右高低 (right, vertical)
        return t(", ".join(parts))
    return joined(t(p) for p in parts)


def channel_name(check: CheckLike, rail: str, direction: str) -> str:
    """One channel of a check: "30 m / 5 m short wave, left rail, lateral"; "Cross level"."""
    detail = rail_direction(rail, direction)
    return joined((check_name(check), detail))


# --------------------------------------------------------------------------- sleepers.csv columns

def _per_rail(pattern: str, name: str, unit: str) -> dict[str, Name]:
    """``pattern`` with {direction} and {rail} -> Name for both directions and rails."""
    return {pattern.format(direction=d, rail=r): Name(name.format(direction=d.capitalize(), rail=RAIL_NAMES[r]), unit)
            for d in ("lateral", "vertical") for r in ("left", "right")}


#: sleepers.csv columns that do not depend on the tolerance profile, and the derived columns of the reports.
COLUMN_NAMES: dict[str, Name] = {
    "number": Name("Sleeper number"),
    "label": Name("Chainage"),
    "station_m": Name("Station", "m"),
    "time_s": Name("GPS time of week", "s"),
    "detected": Name("Detected by the sleeper sensor"),
    "valid": Name("Valid sleeper"),
    "not_assessed": Name("Not assessed because"),
    "chain_zone": Name("Broken-chainage zone"),
    **{f"{rail}_{axis}_m": Name(f"{RAIL_NAMES[rail].capitalize()} {what}", "m")
       for rail in ("left", "right") for axis, what in (("E", "easting"), ("N", "northing"), ("H", "height"))},
    "gauge_mm": Name("Gauge", "mm"),
    "cant_mm": Name("Cant", "mm"),
    "design_cant_mm": Name("Design cant", "mm"),
    "gauge_change_mm": Name("Gauge change to the previous sleeper", "mm"),
    "gauge_change_rate_2_5m_ratio": Name("Gauge change rate 2.5 m", PER_MILLE),
    "twist_3m_mm": Name("Twist 3 m", "mm"),
    "guiding_rail_right": Name("Guiding rail"),
    # the parameters of insrail.project.sleeper_parameters
    **{f"centre_{axis}_m": Name(f"Centreline {what}", "m")
       for axis, what in (("E", "easting"), ("N", "northing"), ("H", "height"))},
    "roll_deg": Name("Roll", "°"),
    "pitch_deg": Name("Pitch", "°"),
    "heading_deg": Name("Heading", "°"),
    "line_speed_kmh": Name("Line speed", "km/h"),
    "curvature_per_km": Name("Curvature", "1/km"),
    "cant_change_rate_ratio": Name("Cant change rate", PER_MILLE),
    **{f"{word}_change_rate_{rail}_ratio": Name(f"{word.capitalize()} change rate, {RAIL_NAMES[rail]}", PER_MILLE)
       for word in ("alignment", "height") for rail in ("left", "right")},
    "cant_deficiency_mm": Name("Cant deficiency", "mm"),
    "cant_deficiency_rate_mm_per_s": Name("Cant deficiency rate", "mm/s"),
    **_per_rail("{direction}_deviation_{rail}_mm", "{direction} deviation, {rail}", "mm"),
    **_per_rail("adjust_{direction}_{rail}_mm", "{direction} adjustment, {rail}", "mm"),
    **_per_rail("unresolved_{direction}_{rail}", "{direction} checks still failed after adjustment, {rail}", ""),
    # derived in the reports (insrail.report.content)
    "row": Name("Row"),
    "runs": Name("Runs"),
    "gauge_deviation_mm": Name("Gauge deviation", "mm"),
    "cross_level_mm": Name("Cross level", "mm"),
    "guiding_rail": Name("Guiding rail"),
    "unresolved": Name("Checks still failed after adjustment"),
}

_CHANNEL = re.compile(r"^(?:_(left|right))?(?:_(lateral|vertical))?_(mm|ratio|mm_per_s)$")


def column_name(key: str, checks: Iterable[CheckLike] = ()) -> Name:
    """The display name of a sleepers.csv column; ``checks`` (a profile's checks) name the
    ``check_<check>[_<rail>][_<direction>]_<unit>`` channel columns."""
    if key in COLUMN_NAMES:
        return COLUMN_NAMES[key].translated
    if key.startswith("source_"):  # a joined line section: the run's weight in the row (insrail.project.section)
        return Name(t("Share of run {survey}").format(survey=key.removeprefix("source_")))
    if key.startswith("check_"):
        # the longest check id first: "twist_3m" must not claim the columns of a check "twist_3m_design"
        for check in sorted(checks, key=lambda c: -len(c.name)):
            prefix = f"check_{check.name}"
            match = _CHANNEL.match(key[len(prefix):]) if key.startswith(prefix) else None
            if match:
                rail, direction, _unit = match.groups()
                return Name(channel_name(check, rail or "track", direction or ""), check_unit(check.kind))
        raise UnknownName(key, "check column (is its check in the tolerance profile?)")
    raise UnknownName(key, "column")


# --------------------------------------------------------------------------- other quantities

QUANTITY_NAMES: dict[str, Name] = {
    # TQI channels (summary.toml [track_quality] channels, insrail.track.exceedance.track_quality)
    "left_level": Name("Longitudinal level, left rail", "mm"),
    "right_level": Name("Longitudinal level, right rail", "mm"),
    "left_alignment": Name("Alignment, left rail", "mm"),
    "right_alignment": Name("Alignment, right rail", "mm"),
    "gauge": Name("Gauge", "mm"),
    "cross_level": Name("Cross level", "mm"),
    "twist": Name("Twist", "mm"),
    "tqi": Name("Track quality index (TQI)", "mm"),
    # predicted 1-sigma per section (quality.csv)
    "sigma_lateral_mm": Name("Predicted 1σ, lateral position", "mm"),
    "sigma_vertical_mm": Name("Predicted 1σ, vertical position", "mm"),
    "sigma_lag5_lateral_mm": Name("Predicted 1σ, 5 m lag difference, lateral", "mm"),
    "sigma_lag5_vertical_mm": Name("Predicted 1σ, 5 m lag difference, vertical", "mm"),
    "sigma_lag150_lateral_mm": Name("Predicted 1σ, 150 m lag difference, lateral", "mm"),
    "sigma_lag150_vertical_mm": Name("Predicted 1σ, 150 m lag difference, vertical", "mm"),
    "sigma_cross_level_mm": Name("Predicted 1σ, cross-level (cant)", "mm"),
    "sigma_along_track_mm": Name("Predicted 1σ, along-track position", "mm"),
    # the parameters a survey plan sweeps (insrail.quality.sweep.PARAMETERS, in their units there)
    "gyro_bias": Name("Gyro bias", "deg/h"),
    "accel_bias": Name("Accelerometer bias", "mGal"),
    "arw": Name("Gyro angle random walk", "deg/sqrt(h)"),
    "vrw": Name("Accelerometer velocity random walk", "m/s/sqrt(h)"),
    "gnss_sigma": Name("GNSS position 1σ", "m"),
    "speed": Name("Pushing speed", "m/s"),
}


def quantity_name(key: str) -> Name:
    """The display name of a quantity that is not a sleepers.csv column (TQI channel, quality figure)."""
    try:
        return QUANTITY_NAMES[key].translated
    except KeyError:
        raise UnknownName(key, "quantity") from None


# --------------------------------------------------------------------------- project settings

#: project.toml key path -> its display name (the label of its field in the wizard and the settings editor, the
#: properties panel, and the problems of a project file in words).
SETTING_NAMES = {
    "project.name": "Project name",
    "project.description": "Description",
    "geodesy.crs": "Coordinate system",
    "geodesy.crs.ellipsoid": "Ellipsoid",
    "geodesy.crs.a_m": "Semi-major axis (custom ellipsoid)",
    "geodesy.crs.inverse_flattening": "Inverse flattening (custom ellipsoid)",
    "geodesy.crs.central_meridian_deg": "Central meridian",
    "geodesy.crs.latitude_of_origin_deg": "Latitude of origin",
    "geodesy.crs.scale_factor": "Scale factor",
    "geodesy.crs.false_easting_m": "False easting",
    "geodesy.crs.false_northing_m": "False northing",
    "geodesy.crs.projection_height_m": "Projection height",
    "geodesy.crs.projection_height_convention": "Projection height applied as",
    "geodesy.crs.mean_radius_m": "Mean earth radius",
    "geodesy.height.benchmarks": "Benchmarks file",
    "geodesy.height.model": "Height-anomaly model",
    "geodesy.height.geoid_grid": "Geoid grid",
    "trolley": "Trolley geometry",
    "trolley.imu_to_antenna_m": "IMU → GNSS antenna",
    "trolley.imu_to_odometer_m": "IMU → odometer wheel contact",
    "trolley.imu_to_odometer_right_m": "IMU → second (right) odometer wheel contact",
    "trolley.imu_to_reference_rail_m": "IMU → reference rail gauge point",
    "trolley.imu_to_sleeper_detector_m": "IMU → sleeper detector",
    "trolley.imu_to_prism_m": "IMU → prism",
    "trolley.mounting_rpy_deg": "Mounting roll, pitch, heading",
    "trolley.reference_rail": "Reference rail",
    "trolley.rail_centre_spacing_m": "Rail centre spacing",
    "trolley.beam_wheel_spacing_m": "Gauge beam wheel spacing (curve correction)",
    "processing": "Processing",
    "processing.imu_profile": "IMU profile",
    "processing.use_gnss_velocity": "Use the GNSS velocity",
    "processing.use_odometer": "Use the odometer",
    "processing.use_nhc": "Non-holonomic constraints (NHC)",
    "processing.use_zupt": "Zero-velocity updates at stops (ZUPT)",
    "processing.smoother": "RTS smoother",
    "processing.update_rate_hz": "Filter update rate (Hz)",
    "processing.gnss_sigma_scale": "GNSS sigma scale",
    "processing.gnss_sigma_floor_m": "GNSS sigma floor (m)",
    "processing.gnss_correlated_tau_s": "GNSS error correlation time (s)",
    "processing.odometer_sigma_mps": "Odometer sigma (m/s)",
    "processing.nhc_sigma_mps": "NHC sigma (m/s)",
    "processing.zupt_sigma_mps": "ZUPT sigma where a stop shows no motion (m/s)",
    "processing.min_static_s": "Shortest stop for a ZUPT (s)",
    "track": "Track",
    "geodesy": "Geodesy",
    "geodesy.control_points": "Control points",
    "report": "Report",
    "report.client": "Client",
    "report.line_section": "Line section",
    "report.track_name": "Track (as the railway names it)",
    "report.operator": "Operator",
    "report.checked_by": "Checked by",
    "report.approved_by": "Approved by",
    "report.trolley": "Trolley (make, model, serial number)",
    "report.trolley_calibrated": "Trolley calibrated on",
    "report.imu": "IMU (make, model, serial number)",
    "report.imu_calibrated": "IMU calibrated on",
    "report.paper": "Paper (landscape)",
    "report.language": "Language of the reports",
    "track.design": "Design alignment",
    "track.start_station_m": "Start station",
    "track.first_sleeper_number": "First sleeper number",
    "track.tolerance_profile": "Tolerance profile",
    "track.fastener": "Fastener type",
    "track.events": "Track events file",
    "track.stationing_direction": "Stationing direction",
    "track.sleeper_anchor": "Sleeper number anchor",
    "track.line_speed_kmh": "Line speed (km/h)",
    "surveys": "Surveys",
    "surveys.name": "Survey name",
    "surveys.folder": "Survey folder",
}


def setting_name(key: str) -> str:
    """The words for a key path: its own label, else the nearest enclosing one's with the rest
    in words ("processing.use_nhc" -> "Processing: use nhc")."""
    if key in SETTING_NAMES:
        return t(SETTING_NAMES[key])
    parts = key.split(".")
    for cut in range(len(parts) - 1, 0, -1):
        head = ".".join(parts[:cut])
        if head in SETTING_NAMES:  # an unknown key's own words are its id's (a problem names what was written)
            return f"{t(SETTING_NAMES[head])}: {' '.join(parts[cut:]).replace('_', ' ')}"
    return key.replace(".", ": ").replace("_", " ").capitalize()


# --------------------------------------------------------------------------- the desktop application's lists

#: The values of a setting chosen from a list, in words (the settings editor's and the wizard's lists, the
#: properties panel). The shipped tolerance profiles, fastener types and IMU profiles are named by their own
#: files' descriptions (:func:`resource_name`); a file of one's own by its path.
CHOICE_NAMES: dict[str, dict[str, str]] = {
    "geodesy.crs.projection_height_convention": {
        "scale_factor": "Scale factor k × (1 + H0 / R)",
        "semi_major_axis": "Expanded ellipsoid, a + H0",
    },
    "geodesy.height.model": {
        "auto": "Best fit to the benchmarks (leave-one-out)",
        "constant": "Constant height anomaly",
        "plane": "Plane through the benchmarks",
        "quadratic": "Quadratic surface through the benchmarks",
    },
    "trolley.reference_rail": {"left": "Left rail", "right": "Right rail"},
    "report.language": {"en": "English", "zh-CN": "Simplified Chinese"},
}
#: The settings that name a shipped resource (or a file of one's own), and the resources folder it is in.
RESOURCE_SETTINGS = {"track.tolerance_profile": "tolerance_profiles", "track.fastener": "fastener_types",
                     "processing.imu_profile": "imu_profiles", "survey.imu_profile": "imu_profiles"}


def choice_name(key: str, value: str) -> str:
    """A value of setting ``key`` chosen from its list, in words ("scale_factor" -> "Scale factor k × (1 + H0 / R)")."""
    try:
        return t(CHOICE_NAMES[key][value])
    except KeyError:
        raise UnknownName(f"{key} = {value}", "choice") from None


# --------------------------------------------------------------------------- reports and exports

#: The shipped fastener types' ids; any other fastener file is named by its description's first part.
FASTENER_NAMES = {"wj7": "WJ-7", "wj8": "WJ-8"}


class DescribedLike(Protocol):
    """What naming needs of a tolerance profile or a fastener type: its id and its file's description."""

    name: str
    description: str


def resource_name(name: str, description: str = "", *, short: bool = False) -> str:
    """A shipped resource (tolerance profile, fastener type, IMU profile) or a file of one's own, in the
    language in use: its file's description (a list in the application), or with ``short`` the part of it
    before its first colon as the reports name it ("WJ-7: lateral ..." -> "WJ-7", a shipped fastener type
    by its standard name); a file without a description by its id in words."""
    if short and name in FASTENER_NAMES:
        return FASTENER_NAMES[name]
    text = description.split(":", 1)[0] if short else description
    return t(text.strip()) or name.replace("_", " ")


def profile_name(profile: DescribedLike) -> str:
    """A tolerance profile as the reports name it ("High-speed ballastless track, static acceptance (TB
    10754-2018)")."""
    return resource_name(profile.name, profile.description, short=True)


def fastener_name(fastener: DescribedLike | None, stored: str = "") -> str:
    """A fastener type as the reports name it ("WJ-8"); ``stored``: the id recorded in the results when the
    fastener file is not readable."""
    return (resource_name(fastener.name, fastener.description, short=True) if fastener is not None
            else resource_name(stored, short=True))
