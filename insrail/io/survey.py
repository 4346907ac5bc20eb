"""The survey folder: one trolley run's raw files plus ``survey.toml`` describing them.

``survey.toml`` names each raw file with its role and format, the trolley's
geometry (lever arms, mounting angles) and the IMU profile. Paths inside it are
relative to the folder. Instead of ``[files.gnss]`` (a finished GNSS solution) a survey may hold
raw GNSS observations in ``[gnss_raw]`` (:mod:`insrail.io.survey_gnss`), which a project turns into
a solution by PPK before the fusion. Lever arms are vectors from the IMU measurement centre to
the named point, resolved in the IMU body frame b (forward-right-down), metres.
"""

from __future__ import annotations

import dataclasses
import types
import typing
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import tomli_w

from insrail.io.atomic import atomic_write
from insrail.io.errors import InputError, ManifestError
from insrail.io.events import EventList
from insrail.io.formats import FORMATS
from insrail.io.survey_gnss import RawGnss, parse_raw_gnss
from insrail.io.tomlfile import read_toml
from insrail.io.types import (
    Benchmarks,
    ControlPoints,
    GaugeData,
    Gap,
    GnssSolution,
    ImuIncrements,
    OdometerData,
    PrismObservations,
    SleeperPulses,
    TotalStationObservations,
)
from insrail.notices import Phrase
from insrail.progress import CancelToken, ProgressFn, StepProgress, check_cancel


@dataclass(frozen=True)
class TrolleyGeometry:
    """Calibrated geometry of the trolley (b-frame lever arms in metres, angles in radians).

    imu_to_antenna_m          : to the GNSS antenna phase centre
    imu_to_odometer_m         : to the contact point of the odometer wheel with the rail top
                                (``imu_to_odometer_left_m`` in survey.toml is the same key)
    imu_to_odometer_right_m   : to the contact point of the second odometer's wheel, on the other
                                rail (``[files.odometer_right]``): its lateral (y) offset from the
                                first wheel is the spacing of the two rails' running points
    imu_to_prism_m            : to the total-station prism centre
    imu_to_sleeper_detector_m : to the sleeper detector's sensing point
    imu_to_reference_rail_m   : to the top-of-rail point above the gauge face of the
                                reference rail, the rail the trolley's fixed wheels run on
    reference_rail            : "left" or "right" of the trolley (seen along its x axis; results follow the stationing)
    mounting_rpy_rad          : roll, pitch, heading of b relative to the trolley frame v,
                                C_b^v = euler_to_dcm(*mounting_rpy_rad)
    rail_centre_spacing_m     : base of the cant definition, cant = base * sin(roll) (1.5 m)
    beam_wheel_spacing_m      : d_w, the spacing of the two side wheels of the twin-wheel beam
                                leaning on the reference rail's gauge face; > 0 turns on the
                                gauge's curve correction (thesis eq. 5.2), 0 (default) leaves it off

    A lever arm is None where survey.toml does not give it: each is needed only with the data
    using it (:data:`FUSION_LEVER_ARMS`, :data:`TRACK_LEVER_ARMS`), and a missing one is an error
    naming the key before that data is used, never a number.
    """

    imu_to_antenna_m: np.ndarray | None = None
    imu_to_odometer_m: np.ndarray | None = None
    imu_to_odometer_right_m: np.ndarray | None = None
    imu_to_prism_m: np.ndarray | None = None
    imu_to_sleeper_detector_m: np.ndarray | None = None
    imu_to_reference_rail_m: np.ndarray | None = None
    reference_rail: str = "left"
    mounting_rpy_rad: np.ndarray = field(default_factory=lambda: np.zeros(3))
    rail_centre_spacing_m: float = 1.5
    beam_wheel_spacing_m: float = 0.0

    def lever_arm_m(self, key: str) -> np.ndarray:
        """The lever arm ``key`` as floats; ValueError when survey.toml does not give it (a use the
        checks before it should have refused: never a NaN offset)."""
        arm = getattr(self, key)
        if arm is None:
            raise ValueError(f"trolley.{key}: not given, but used")
        return np.asarray(arm, dtype=float)

    def given_lever_arms(self) -> dict[str, np.ndarray]:
        """The lever arms survey.toml gives, by key."""
        return {key: getattr(self, key) for key in LEVER_ARMS if getattr(self, key) is not None}


@dataclass(frozen=True)
class SurveyFile:
    """One raw file of a survey: its path (relative to the folder), format and options.

    time_offset_s: how late the file's time stamps run against the IMU's clock (a sensor's known
    latency, or its logger's clock offset) [s]; subtracted from every time stamp as it is read.
    """

    path: str
    format: str
    options: dict = field(default_factory=dict)
    time_offset_s: float = 0.0

    def read(self, folder: Path):
        """The file's data, on the IMU's clock."""
        data = FORMATS[self.format].read(Path(folder) / self.path, **self.options)
        return on_imu_clock(data, self.time_offset_s) if self.time_offset_s else data


def on_imu_clock(data, time_offset_s: float):
    """``data`` with ``time_offset_s`` taken off its time stamps (and its gaps')."""
    shifted = {"time_s": np.asarray(data.time_s, dtype=float) - time_offset_s}
    if hasattr(data, "gaps"):
        shifted["gaps"] = tuple(Gap(gap.start_s - time_offset_s, gap.end_s - time_offset_s) for gap in data.gaps)
    return dataclasses.replace(data, **shifted)


#: the 1-sigma [m] of a start on the design where survey.toml gives none: a trolley set on a station marked
#: on the track (a centimetre along it) on a track within a centimetre or two of its design
START_SIGMA_M = 0.02


@dataclass(frozen=True)
class SurveyStart:
    """Where the survey starts on the project's design (``[start]`` of survey.toml; thesis 5.3.1.1): the
    trolley's track centre at ``station_m``, ``offset_m`` right of the design's centreline and
    ``height_m`` above its profile, the trolley facing increasing stations (``facing_increasing``) or not;
    ``sigma_m`` the 1-sigma of that place in each axis (the station marked on the track, the track
    against its design). The fusion starts there from the design's position, azimuth, grade and cant
    (``insrail.project.design_start``), without waiting for GNSS or a prism fix."""

    station_m: float
    offset_m: float = 0.0
    height_m: float = 0.0
    sigma_m: float = START_SIGMA_M
    facing_increasing: bool = True


@dataclass(frozen=True)
class SurveyManifest:
    """Contents of ``survey.toml``.

    files maps a role (``imu gnss odometer odometer_right gauge sleepers prism total_station cpiii
    benchmarks events``) to a :class:`SurveyFile`; ``[files.odometer_left]`` in survey.toml is read as
    the role ``odometer`` (the first odometer; ``odometer_right`` is a second one on the other rail,
    :mod:`insrail.nav.odometer_pair`). Only imu is required; the survey also needs a source of
    position: a GNSS solution (gnss), raw GNSS observations (``raw_gnss``, the ``[gnss_raw]``
    table, which replaces the gnss role) or total-station prism fixes (prism, a survey in a
    tunnel; or total_station, the raw pointings of free stations, with cpiii, the points they are
    resected on). Without an odometer the along-track scale comes from the position source alone.
    With an odometer and no position source at all it is a relative survey (:attr:`relative`).
    """

    name: str
    files: dict[str, SurveyFile]
    trolley: TrolleyGeometry
    imu_profile: str = "nav"
    gps_week: int | None = None
    description: str = ""
    raw_gnss: RawGnss | None = None
    start: SurveyStart | None = None  # [start]: the survey starts on a known station of the design

    @property
    def relative(self) -> bool:
        """A relative survey: no position source at all, the odometer and the stops carry it
        (``insrail.nav.relative``); it measures the track's shape, not its coordinates."""
        return self.raw_gnss is None and not any(role in self.files for role in POSITION_ROLES)


@dataclass(frozen=True)
class SurveyData:
    """All raw data of one survey, loaded and validated."""

    manifest: SurveyManifest
    folder: Path
    imu: ImuIncrements
    gnss: GnssSolution | None = None  # None: a survey without GNSS (prism fixes only)
    odometer: OdometerData | None = None  # None: no odometer (along-track scale from the positions)
    odometer_right: OdometerData | None = None  # a second odometer, on the other rail (with the first only)
    gauge: GaugeData | None = None
    sleepers: SleeperPulses | None = None
    prism: PrismObservations | None = None
    total_station: TotalStationObservations | None = None  # raw pointings (with cpiii): placed as prism fixes
    cpiii: ControlPoints | None = None
    benchmarks: Benchmarks | None = None
    events: EventList | None = None


# --- survey.toml ------------------------------------------------------------------------------

MANIFEST_NAME = "survey.toml"
ROLE_TYPES: dict[str, type] = {
    "imu": ImuIncrements,
    "gnss": GnssSolution,
    "odometer": OdometerData,
    "odometer_right": OdometerData,
    "gauge": GaugeData,
    "sleepers": SleeperPulses,
    "prism": PrismObservations,
    "total_station": TotalStationObservations,
    "cpiii": ControlPoints,
    "benchmarks": Benchmarks,
    "events": EventList,
}
REQUIRED_ROLES = ("imu",)
#: roles whose files may name a ``time_offset_s`` (the IMU's clock is the reference the others are put on)
TIMED_ROLES = ("gnss", "odometer", "odometer_right", "gauge", "sleepers", "prism", "total_station")
#: roles of which a survey needs at least one (``[gnss_raw]`` counts as gnss): where the trolley is
POSITION_ROLES = ("gnss", "prism", "total_station")
LEVER_ARMS = ("imu_to_antenna_m", "imu_to_odometer_m", "imu_to_odometer_right_m", "imu_to_prism_m",
              "imu_to_sleeper_detector_m", "imu_to_reference_rail_m")
#: The lever arms the fusion uses (``insrail fuse`` and ``insrail process``), each with the roles
#: whose data need it: reading survey.toml requires one only when the survey holds such data.
FUSION_LEVER_ARMS = {"imu_to_antenna_m": ("gnss",), "imu_to_odometer_m": ("odometer",),
                     "imu_to_odometer_right_m": ("odometer_right",),
                     "imu_to_prism_m": ("prism", "total_station")}
#: The lever arms only the track reconstruction (``insrail process``) uses, and why: a survey that is
#: only fused (a walk, a road test) need not give them. None: needed by every processed survey.
TRACK_LEVER_ARMS = {"imu_to_reference_rail_m": (None, Phrase("the rails are placed from the reference rail's point")),
                    "imu_to_sleeper_detector_m": ("sleepers",
                                                  Phrase("the sleeper pulses are placed on the track at the detector"))}
#: left/right names survey.toml accepts for the first odometer's role and lever arm (a survey of one
#: odometer keeps ``[files.odometer]`` and ``imu_to_odometer_m``)
ROLE_ALIASES = {"odometer_left": "odometer"}
TROLLEY_ALIASES = {"imu_to_odometer_left_m": "imu_to_odometer_m"}
#: a clock offset beyond a minute is not a latency but another time scale (leap seconds: 18 s)
MAX_GIVEN_TIME_OFFSET_S = 60.0
_SURVEY_KEYS = ("name", "gps_week", "imu_profile", "description")
_TROLLEY_KEYS = LEVER_ARMS + tuple(TROLLEY_ALIASES) + ("reference_rail", "mounting_rpy_deg", "rail_centre_spacing_m", "beam_wheel_spacing_m")
#: The longest twin-wheel beam a trolley carries [m]: a spacing beyond it is a unit slip (mm as m)
MAX_BEAM_WHEEL_SPACING_M = 3.0


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and np.isfinite(value)


def _vector3(value) -> np.ndarray | None:
    if isinstance(value, list) and len(value) == 3 and all(_is_number(v) for v in value):
        return np.array(value, dtype=float)
    return None


def _option_problem(hint, value) -> str | None:
    """Why a TOML value does not fit a reader parameter's type hint, or None if it does."""
    allowed = typing.get_args(hint) if isinstance(hint, types.UnionType) else (hint,)
    for kind in allowed:
        if kind is type(None):
            continue
        if kind is float and _is_number(value):
            return None
        if kind is int and isinstance(value, int) and not isinstance(value, bool):
            return None
        if kind is str and isinstance(value, str):
            return None
        if typing.get_origin(kind) is tuple and isinstance(value, list):
            items = typing.get_args(kind)
            if len(value) == len(items) and all(
                    _option_problem(item, v) is None for item, v in zip(items, value)):
                return None
            return f"expected a list of {len(items)} {items[0].__name__} values"
    return f"expected {' or '.join(k.__name__ for k in allowed if k is not type(None))}, found {value!r}"


def _with_aliases(table: dict, aliases: dict[str, str], what: str, problems: list[str]) -> dict:
    """``table`` with each alias key renamed to the key it names; both given is a problem."""
    table = dict(table)
    for alias, key in aliases.items():
        if alias in table:
            if key in table:
                problems.append(Phrase("{what}.{alias}: the same as {what}.{key}; give one of them", {"what": what, "alias": alias, "key": key}))
            table[key] = table.pop(alias)
    return table


def _parse_files(folder: Path, table, problems: list[str], raw_gnss: bool = False) -> dict[str, SurveyFile]:
    files: dict[str, SurveyFile] = {}
    if not isinstance(table, dict):
        problems.append(Phrase("files: missing table [files.<role>] (the imu role is required)"))
        return files
    table = _with_aliases(table, ROLE_ALIASES, "files", problems)
    if "odometer_right" in table and "odometer" not in table:
        problems.append(Phrase("files.odometer_right: a second odometer needs the first, [files.odometer] (or "
                        "[files.odometer_left]); a survey with one odometer gives it as [files.odometer], on "
                        "whichever rail, with its lever arm trolley.imu_to_odometer_m"))
    for role in REQUIRED_ROLES:
        if role not in table:
            problems.append(Phrase("files.{role}: missing (required role)", {"role": role}))
    if raw_gnss and "gnss" in table:
        problems.append(Phrase("files.gnss: give either a GNSS solution [files.gnss] or raw observations "
                        "[gnss_raw], not both"))
    if not raw_gnss and not any(role in table for role in POSITION_ROLES) and "odometer" not in table:
        problems.append(Phrase("files: no position source: give a GNSS solution [files.gnss], raw GNSS observations "
                        "[gnss_raw], total-station prism fixes [files.prism] or raw total-station observations "
                        "[files.total_station]; or, for a relative survey (gauge, cant, twist and chord checks, no "
                        "coordinates), the odometer [files.odometer] with stops about every 60 m"))
    if ("total_station" in table) != ("cpiii" in table):
        problems.append("files.total_station: the raw total-station observations need the CPIII points they are "
                        "resected on [files.cpiii], and the CPIII points are used only with them"
                        if "total_station" in table else
                        "files.cpiii: CPIII points are used with raw total-station observations [files.total_station]")
    for role, entry in table.items():
        key = f"files.{role}"
        if role not in ROLE_TYPES:
            problems.append(Phrase("{key}: unknown role (expected one of {roles})", {"key": key, "roles": list([*ROLE_TYPES, *ROLE_ALIASES])}))
            continue
        if not isinstance(entry, dict):
            problems.append(Phrase("{key}: expected a table with path and format", {"key": key}))
            continue
        options = {k: v for k, v in entry.items() if k not in ("path", "format", "time_offset_s")}
        path, name = entry.get("path"), entry.get("format")
        time_offset_s = entry.get("time_offset_s", 0.0)
        if "time_offset_s" in entry and role not in TIMED_ROLES:
            problems.append(Phrase("{key}.time_offset_s: only the files of {timed_roles} take one (the IMU's "
                            "clock is the survey's time reference)", {"key": key, "timed_roles": list(TIMED_ROLES)}))
        elif not (_is_number(time_offset_s) and abs(time_offset_s) <= MAX_GIVEN_TIME_OFFSET_S):
            problems.append(Phrase("{key}.time_offset_s: expected the seconds the file's time stamps run late against the "
                            "IMU's clock (a number within ±{max_given_time_offset_s:g} s), found {time_offset_s!r}", {"key": key, "max_given_time_offset_s": MAX_GIVEN_TIME_OFFSET_S, "time_offset_s": time_offset_s}))
            time_offset_s = 0.0
        if not isinstance(path, str) or not path:
            problems.append(Phrase("{key}.path: expected a file name relative to the survey folder", {"key": key}))
        elif not (folder / path).is_file():
            problems.append(Phrase("{key}.path: file not found: {path}", {"key": key, "path": path}))
        if not isinstance(name, str):
            problems.append(Phrase("{key}.format: expected a format name ({formats})", {"key": key, "formats": list(FORMATS)}))
        elif name not in FORMATS:
            problems.append(Phrase("{key}.format: unknown format {name!r} (expected one of {formats})", {"key": key, "name": name, "formats": list(FORMATS)}))
        elif FORMATS[name].data_type is not ROLE_TYPES[role]:
            fitting = [f for f, spec in FORMATS.items() if spec.data_type is ROLE_TYPES[role]]
            problems.append(Phrase("{key}.format: {name} does not hold {role} data (use one of {fitting})", {"key": key, "name": name, "role": role, "fitting": list(fitting)}))
        else:
            hints = FORMATS[name].option_hints()
            for option, value in options.items():
                if option not in hints:
                    known = ", ".join(hints) or "none"
                    problems.append(Phrase("{key}.{option}: unknown option for format {name} (known: {known})", {"key": key, "option": option, "name": name, "known": known}))
                elif (why := _option_problem(hints[option], value)) is not None:
                    problems.append(Phrase("{key}.{option}: {why}", {"key": key, "option": option, "why": why}))
            if FORMATS[name].check_options is not None and all(
                    option in hints and _option_problem(hints[option], value) is None
                    for option, value in options.items()):
                problems += [Phrase("{key}.{option}: {why}", {"key": key, "option": option, "why": why})
                             for option, why in FORMATS[name].check_options(options)]
        if isinstance(path, str) and isinstance(name, str):
            files[role] = SurveyFile(path=path, format=name, options=options, time_offset_s=float(time_offset_s))
    return files


def parse_trolley(table, roles: set[str], problems: list[str]) -> TrolleyGeometry | None:
    """A ``[trolley]`` table (as in survey.toml or project.toml) as TrolleyGeometry; ``roles`` are
    the survey's file roles: a lever arm the fusion uses is required only with the data using it
    (:data:`FUSION_LEVER_ARMS`; those of the track, :data:`TRACK_LEVER_ARMS`, are checked where the
    track is reconstructed, :func:`track_lever_arm_problems`). Problems are appended to ``problems``
    as ``trolley.<key>: ...``; None when there are any."""
    if not isinstance(table, dict):
        problems.append(Phrase("trolley: missing table [trolley] (lever arms and reference rail)"))
        return None
    table = _with_aliases(table, TROLLEY_ALIASES, "trolley", problems)
    for key in table:
        if key not in _TROLLEY_KEYS:
            problems.append(Phrase("trolley.{key}: unknown key (expected {keys})", {"key": key, "keys": list(_TROLLEY_KEYS)}))
    arms: dict[str, np.ndarray | None] = {}
    for key in LEVER_ARMS:
        if key not in table:
            users = [role for role in FUSION_LEVER_ARMS.get(key, ()) if role in roles]
            if users:
                problems.append(Phrase("trolley.{key}: missing (required with files.{users}; 3 numbers [m], IMU body "
                                "frame FRD)", {"key": key, "users": users[0]}))
            arms[key] = None
            continue
        arms[key] = _vector3(table[key])
        if arms[key] is None:
            problems.append(Phrase("trolley.{key}: expected 3 numbers [m], found {table!r}", {"key": key, "table": table[key]}))
    reference_rail = table.get("reference_rail", "left")
    if reference_rail not in ("left", "right"):
        problems.append(Phrase("trolley.reference_rail: expected \"left\" or \"right\", found {reference_rail!r}", {"reference_rail": reference_rail}))
    mounting = _vector3(table.get("mounting_rpy_deg", [0.0, 0.0, 0.0]))
    if mounting is None:
        problems.append(Phrase("trolley.mounting_rpy_deg: expected 3 numbers [deg], found {table!r}", {"table": table['mounting_rpy_deg']}))
    spacing = table.get("rail_centre_spacing_m", 1.5)
    if not (_is_number(spacing) and spacing > 0):
        problems.append(Phrase("trolley.rail_centre_spacing_m: expected a positive number [m], found {spacing!r}", {"spacing": spacing}))
    beam = table.get("beam_wheel_spacing_m", 0.0)
    if not (_is_number(beam) and 0.0 <= beam <= MAX_BEAM_WHEEL_SPACING_M):
        problems.append(Phrase("trolley.beam_wheel_spacing_m: expected the spacing of the twin-wheel beam's side wheels, "
                        "0 .. {max_beam_wheel_spacing_m:g} m (0: no curve correction), found {beam!r}", {"max_beam_wheel_spacing_m": MAX_BEAM_WHEEL_SPACING_M, "beam": beam}))
    if problems:
        return None
    return TrolleyGeometry(**arms, reference_rail=reference_rail, mounting_rpy_rad=np.radians(mounting),
                           rail_centre_spacing_m=float(spacing), beam_wheel_spacing_m=float(beam))


def track_lever_arm_problems(trolley: TrolleyGeometry, roles: set[str]) -> list[Phrase]:
    """``trolley.<key>: missing ...`` for each lever arm the track reconstruction needs with the
    survey's data (``roles``) that ``trolley`` does not give (:data:`TRACK_LEVER_ARMS`)."""
    problems = []
    for key, (role, why) in TRACK_LEVER_ARMS.items():
        if getattr(trolley, key) is None and (role is None or role in roles):
            given = Phrase("files.{role} is given: ", {"role": role}) if role is not None else ""
            problems.append(Phrase("trolley.{key}: missing; insrail process needs it because {given}{why} "
                                   "(3 numbers [m], IMU body frame FRD)", {"key": key, "given": given, "why": why}))
    return problems


def read_manifest(folder: str | Path, trolley_from_project: bool = False) -> SurveyManifest:
    """Read and validate ``<folder>/survey.toml``.

    ``trolley_from_project``: the survey is processed in a project whose ``[trolley]`` replaces the
    survey's own, which may then be left out (and requires no lever arm; one given is still read).

    Raises :class:`ManifestError` listing every problem found, each with its key
    path (``files.gnss.path: file not found: gnss.pos``).
    """
    folder = Path(folder)
    path = folder / MANIFEST_NAME
    if not path.is_file():
        raise InputError(path, None, "file not found: the survey folder needs a survey.toml")
    document = read_toml(path)

    problems: list[str] = []
    for key in document:
        if key not in ("survey", "files", "trolley", "gnss_raw", "start"):
            problems.append(Phrase("{key}: unknown table (expected [survey], [files.<role>], [trolley], [gnss_raw], "
                            "[start])", {"key": key}))
    survey = document.get("survey")
    if not isinstance(survey, dict):
        problems.append(Phrase("survey: missing table [survey] (name, gps_week, imu_profile, description)"))
        survey = {}
    for key in survey:
        if key not in _SURVEY_KEYS:
            problems.append(Phrase("survey.{key}: unknown key (expected {keys})", {"key": key, "keys": list(_SURVEY_KEYS)}))
    name = survey.get("name")
    if not isinstance(name, str) or not name:
        problems.append(Phrase("survey.name: expected a non-empty text"))
    gps_week = survey.get("gps_week")
    if gps_week is not None and not (isinstance(gps_week, int) and not isinstance(gps_week, bool)
                                     and gps_week >= 0):
        problems.append(Phrase("survey.gps_week: expected a whole GPS week number, found {gps_week!r}", {"gps_week": gps_week}))
    for key in ("imu_profile", "description"):
        if key in survey and not isinstance(survey[key], str):
            problems.append(Phrase("survey.{key}: expected text, found {survey!r}", {"key": key, "survey": survey[key]}))
    raw_gnss = parse_raw_gnss(folder, document["gnss_raw"], problems) if "gnss_raw" in document else None
    files = _parse_files(folder, document.get("files"), problems, raw_gnss="gnss_raw" in document)
    roles = set(files) | ({"gnss"} if "gnss_raw" in document else set())
    if trolley_from_project:
        trolley = parse_trolley(document["trolley"], set(), problems) if "trolley" in document else TrolleyGeometry()
    else:
        trolley = parse_trolley(document.get("trolley"), roles, problems)
    imu_profile = survey.get("imu_profile", "nav")
    if isinstance(imu_profile, str) and imu_profile.endswith(".toml"):
        # a profile file of the survey's own: relative to the survey folder, wherever the user runs from
        resolved = (folder / imu_profile).resolve()
        if not resolved.is_file():
            problems.append(Phrase("survey.imu_profile: file not found: {imu_profile} (a .toml path is relative to the "
                            "survey folder; or name a shipped profile)", {"imu_profile": imu_profile}))
        imu_profile = str(resolved)
    start = parse_start(document["start"], problems) if "start" in document else None
    if problems:
        raise ManifestError(path, problems)
    return SurveyManifest(name=name, files=files, trolley=trolley,
                          imu_profile=imu_profile, gps_week=gps_week,
                          description=survey.get("description", ""), raw_gnss=raw_gnss, start=start)


_START_KEYS = ("station_m", "offset_m", "height_m", "sigma_m", "facing")


def parse_start(table, problems: list[str]) -> SurveyStart | None:
    """survey.toml's ``[start]`` as :class:`SurveyStart` (problems appended as ``start.<key>: ...``)."""
    if not isinstance(table, dict):
        problems.append(Phrase("start: expected a table [start] with station_m"))
        return None
    found = len(problems)
    for key in table:
        if key not in _START_KEYS:
            problems.append(Phrase("start.{key}: unknown key (expected {keys})", {"key": key, "keys": list(_START_KEYS)}))
    if not _is_number(table.get("station_m")):
        problems.append(Phrase("start.station_m: expected the design station [m] the trolley starts on, found "
                        "{value!r}", {"value": table.get('station_m')}))
    for key in ("offset_m", "height_m"):
        if key in table and not (_is_number(table[key]) and abs(table[key]) <= 10.0):
            problems.append(Phrase("start.{key}: expected metres from the design (within 10 m), found {table!r}", {"key": key, "table": table[key]}))
    sigma = table.get("sigma_m", START_SIGMA_M)
    if not (_is_number(sigma) and 0.001 <= sigma <= 10.0):
        problems.append(Phrase("start.sigma_m: expected the 1-sigma [m] of the start point, 0.001 .. 10, found {sigma!r}", {"sigma": sigma}))
    facing = table.get("facing", "increasing")
    if facing not in ("increasing", "decreasing"):
        problems.append(Phrase("start.facing: expected \"increasing\" or \"decreasing\" (the stations the trolley's x axis "
                        "points to), found {facing!r}", {"facing": facing}))
    if len(problems) > found:
        return None
    return SurveyStart(float(table["station_m"]), float(table.get("offset_m", 0.0)), float(table.get("height_m", 0.0)),
                       float(sigma), facing == "increasing")


def manifest_to_toml(manifest: SurveyManifest) -> str:
    """The TOML text of a manifest (lever arms not given are left out)."""
    survey = {"name": manifest.name, "imu_profile": manifest.imu_profile}
    if manifest.gps_week is not None:
        survey["gps_week"] = manifest.gps_week
    if manifest.description:
        survey["description"] = manifest.description
    files = {role: {"path": f.path, "format": f.format, **f.options,
                    **({"time_offset_s": f.time_offset_s} if f.time_offset_s else {})}
             for role, f in manifest.files.items()}
    geometry = manifest.trolley
    trolley: dict = {key: [float(v) for v in arm] for key, arm in geometry.given_lever_arms().items()}
    trolley.update(reference_rail=geometry.reference_rail,
                   mounting_rpy_deg=[float(v) for v in np.degrees(geometry.mounting_rpy_rad)],
                   rail_centre_spacing_m=float(geometry.rail_centre_spacing_m))
    if geometry.beam_wheel_spacing_m:
        trolley["beam_wheel_spacing_m"] = float(geometry.beam_wheel_spacing_m)
    document = {"survey": survey, "files": files, "trolley": trolley}
    if manifest.raw_gnss is not None:
        document["gnss_raw"] = manifest.raw_gnss.to_settings()
    if manifest.start is not None:
        start = manifest.start
        document["start"] = {"station_m": start.station_m, "offset_m": start.offset_m, "height_m": start.height_m,
                             "sigma_m": start.sigma_m, "facing": "increasing" if start.facing_increasing else "decreasing"}
    return tomli_w.dumps(document)


def write_manifest(folder: str | Path, manifest: SurveyManifest) -> Path:
    """Write ``<folder>/survey.toml`` atomically; returns its path."""
    path = Path(folder) / MANIFEST_NAME
    profile = Path(manifest.imu_profile)
    if profile.suffix == ".toml" and profile.is_absolute():  # kept relative to the folder it lies in
        try:
            manifest = dataclasses.replace(manifest, imu_profile=profile.relative_to(Path(folder).resolve()).as_posix())
        except ValueError:
            pass
    text = manifest_to_toml(manifest)
    with atomic_write(path) as handle:
        handle.write(text)
    return path


# --- loading a survey -------------------------------------------------------------------------

def _check_time_overlap(imu: ImuIncrements, other, role: str, entry: SurveyFile | None, problems: list[str]) -> None:
    """An aiding series that never overlaps the IMU is almost always a time-scale mix-up, or a
    file of another day or run."""
    if other.time_s[-1] < imu.time_s[0] or other.time_s[0] > imu.time_s[-1]:
        name = f" ({entry.path})" if entry is not None else ""
        problems.append(
            Phrase("files.{role}{name}: time span {time_s:.3f}..{time_s2:.3f} s does not overlap "
            "the IMU's {time_s3:.3f}..{time_s4:.3f} s (different time scales, or a file of another "
            "day or run?)", {"role": role, "name": name, "time_s": other.time_s[0], "time_s2": other.time_s[-1], "time_s3": imu.time_s[0], "time_s4": imu.time_s[-1]}))


def _with_week(data, role: str, gps_week: int | None, problems: list[str]):
    """Fill in the manifest's GPS week; a file that states another week is a problem."""
    if gps_week is None or not hasattr(data, "gps_week"):
        return data
    if data.gps_week is None:
        return dataclasses.replace(data, gps_week=gps_week)
    if data.gps_week != gps_week:
        problems.append(Phrase("files.{role}: data is from GPS week {gps_week}, "
                        "survey.gps_week says {gps_week2}", {"role": role, "gps_week": data.gps_week, "gps_week2": gps_week}))
    return data


def read_survey(folder: str | Path, progress: ProgressFn | None = None,
                cancel: CancelToken = None, gnss: GnssSolution | None = None,
                trolley_from_project: bool = False) -> SurveyData:
    """Load every file of a survey folder by its role and format.

    Every file is read even after one fails, so the user sees all bad files at
    once: one bad file raises its own InputError, several raise a ManifestError
    listing them. Then the aiding data must overlap the IMU in time.
    ``gnss`` is the solution computed from ``[gnss_raw]`` (a project's GNSS stage);
    it is required for such a survey and refused for one with ``[files.gnss]``. ``trolley_from_project``:
    as for :func:`read_manifest`.
    """
    folder = Path(folder)
    manifest = read_manifest(folder, trolley_from_project)
    if (manifest.raw_gnss is not None) != (gnss is not None):
        raise InputError(folder / MANIFEST_NAME, None, "gnss_raw: the survey holds raw GNSS observations; "
                         "process it in a project (PPK) first" if gnss is None else
                         "files.gnss: the survey has its own GNSS solution; a computed one is not used")
    step = StepProgress(progress)
    loaded: dict = {}
    errors: list[InputError] = []
    roles = list(manifest.files.items())
    for index, (role, entry) in enumerate(roles):
        check_cancel(cancel)
        step(index / len(roles), Phrase("reading {role}: {file}", {"role": role, "file": str(entry.path)}))
        try:
            loaded[role] = entry.read(folder)
        except InputError as exc:
            errors.append(exc)
    if gnss is not None:
        loaded["gnss"] = gnss
    if len(errors) == 1:
        raise errors[0]
    if errors:
        raise ManifestError(folder / MANIFEST_NAME, [str(e) for e in errors])

    problems: list[str] = []
    loaded = {role: _with_week(data, role, manifest.gps_week, problems) for role, data in loaded.items()}
    for role in TIMED_ROLES:
        if role in loaded:
            _check_time_overlap(loaded["imu"], loaded[role], role, manifest.files.get(role), problems)
    if problems:
        raise ManifestError(folder / MANIFEST_NAME, problems)
    step(1.0, "survey loaded")
    return SurveyData(manifest=manifest, folder=folder, **loaded)
