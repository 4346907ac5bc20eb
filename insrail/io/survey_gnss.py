"""The ``[gnss_raw]`` table of ``survey.toml``: raw GNSS observations instead of a GNSS solution.

A survey holds either ``[files.gnss]`` (a finished solution) or ``[gnss_raw]``, from which the
project's pipeline computes the solution by PPK (RTKLIB) before the fusion::

    [gnss_raw]
    rover = "rover.obs"              # RINEX observation file of the trolley's receiver, or
    rover_log = "rover.ubx"          #   a receiver log, converted to RINEX first (RTKLIB convbin)
    rover_log_format = "ubx"         #   optional; default from the extension (.ubx, .sbf, .rtcm3, ...)
    base = "base.obs"                # RINEX observation file of the base receiver
    navigation = ["brdc.nav"]        # RINEX navigation file(s); a converted log's own .nav is added
    precise = ["igs.sp3", "igs.clk"] # optional SP3 / CLK products (set pos1-sateph = precise in the config)
    antex = "igs20.atx"              # optional ANTEX file for the antennas' phase centres
    config = "ppk.conf"              # optional RTKLIB .conf instead of the trolley defaults
    base_point = "CP2-017"           # a control point of the project ([geodesy.control_points.<name>]),
                                     #   or "rinex-header": the base file's APPROX POSITION XYZ
                                     #   (metre level; every position carries its error; warned)
    base_antenna_height_m = 1.5320   # vertical height of the base antenna's reference point (ARP)
                                     #   above the mark; required with a control point. With
                                     #   "rinex-header" the header's ANTENNA: DELTA H is used.
    base_antenna_type = "TRM55971.00     NONE"  # optional ANTEX name (phase centre with antex)

Paths are relative to the survey folder. Problems are reported with their key paths
(``gnss_raw.base: file not found: base.obs``), all at once, as for the rest of survey.toml.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from insrail.notices import Phrase

BASE_FROM_RINEX_HEADER = "rinex-header"
_KEYS = ("rover", "rover_log", "rover_log_format", "base", "navigation", "precise", "antex", "config",
         "base_point", "base_antenna_height_m", "base_antenna_type")


@dataclass(frozen=True)
class RawGnss:
    """The ``[gnss_raw]`` table; paths relative to the survey folder.

    Exactly one of ``rover`` (RINEX) and ``rover_log`` (receiver log) is set.
    ``base_point`` names a project control point, or is :data:`BASE_FROM_RINEX_HEADER`.
    """

    base: str
    navigation: tuple[str, ...]
    base_point: str
    rover: str | None = None
    rover_log: str | None = None
    rover_log_format: str | None = None
    precise: tuple[str, ...] = ()
    antex: str | None = None
    config: str | None = None
    base_antenna_height_m: float | None = None
    base_antenna_type: str = ""

    @property
    def base_from_header(self) -> bool:
        return self.base_point == BASE_FROM_RINEX_HEADER

    def input_files(self) -> tuple[str, ...]:
        """Every file the PPK reads, in a fixed order (for hashing)."""
        optional = (self.rover, self.rover_log, self.antex, self.config)
        return (self.base, *self.navigation, *self.precise, *(p for p in optional if p is not None))

    def to_settings(self) -> dict:
        settings: dict = {}
        for key in _KEYS:
            value = getattr(self, key)
            if value is None or value == "" or value == ():
                continue
            settings[key] = list(value) if isinstance(value, tuple) else value
        return settings


def parse_raw_gnss(folder: Path, table, problems: list[str]) -> RawGnss | None:
    """Validate a ``[gnss_raw]`` table (files relative to ``folder``); problems go to ``problems``."""
    if not isinstance(table, dict):
        problems.append(Phrase("gnss_raw: expected a table (rover, base, navigation, base_point, ...)"))
        return None
    before = len(problems)
    for key in table:
        if key not in _KEYS:
            problems.append(Phrase("gnss_raw.{key}: unknown key (expected {keys})", {"key": key, "keys": list(_KEYS)}))

    def file(key: str, required: bool = False) -> str | None:
        value = table.get(key)
        if value is None:
            if required:
                problems.append(Phrase("gnss_raw.{key}: missing (a file name relative to the survey folder)", {"key": key}))
            return None
        if not isinstance(value, str) or not value:
            problems.append(Phrase("gnss_raw.{key}: expected a file name relative to the survey folder, found {value!r}", {"key": key, "value": value}))
            return None
        if not (folder / value).is_file():
            problems.append(Phrase("gnss_raw.{key}: file not found: {value}", {"key": key, "value": value}))
        return value

    def files(key: str, required: bool) -> tuple[str, ...]:
        value = table.get(key, [] if not required else None)
        if isinstance(value, str):
            value = [value]
        if not isinstance(value, list) or (required and not value):
            problems.append(Phrase("gnss_raw.{key}: expected a list of file names relative to the survey folder{least}",
                                   {"key": key, "least": Phrase(" (at least one)" if required else "")}))
            return ()
        names = []
        for i, name in enumerate(value):
            if not isinstance(name, str) or not name:
                problems.append(Phrase("gnss_raw.{key}[{i}]: expected a file name, found {name!r}", {"key": key, "i": i, "name": name}))
            elif not (folder / name).is_file():
                problems.append(Phrase("gnss_raw.{key}[{i}]: file not found: {name}", {"key": key, "i": i, "name": name}))
            else:
                names.append(name)
        return tuple(names)

    rover, rover_log = file("rover"), file("rover_log")
    if ("rover" in table) == ("rover_log" in table):
        problems.append(Phrase("gnss_raw.rover: give either rover (RINEX observations) or rover_log (a receiver log)"))
    log_format = table.get("rover_log_format")
    if log_format is not None and (not isinstance(log_format, str) or "rover_log" not in table):
        problems.append(Phrase("gnss_raw.rover_log_format: expected a receiver format name with rover_log, "
                        "found {log_format!r}", {"log_format": log_format}))
    base = file("base", required=True)
    navigation = files("navigation", required=rover_log is None)
    precise = files("precise", required=False)
    antex, config = file("antex"), file("config")
    base_point = table.get("base_point")
    if not isinstance(base_point, str) or not base_point:
        problems.append(Phrase("gnss_raw.base_point: expected a control point name of the project or "
                        "\"{base_from_rinex_header}\", found {base_point!r}", {"base_from_rinex_header": BASE_FROM_RINEX_HEADER, "base_point": base_point}))
    height = table.get("base_antenna_height_m")
    if height is not None and (isinstance(height, bool) or not isinstance(height, (int, float))
                               or not math.isfinite(height) or not -1.0 <= height <= 100.0):
        problems.append(Phrase("gnss_raw.base_antenna_height_m: expected a height above the mark in metres, found {height!r}", {"height": height}))
    if base_point == BASE_FROM_RINEX_HEADER and height is not None:
        problems.append(Phrase("gnss_raw.base_antenna_height_m: not used with base_point = \"rinex-header\" "
                        "(the header's ANTENNA: DELTA H applies); remove it or name a control point"))
    elif isinstance(base_point, str) and base_point and base_point != BASE_FROM_RINEX_HEADER and height is None:
        problems.append(Phrase("gnss_raw.base_antenna_height_m: missing (the base antenna's reference point above "
                        "control point {base_point}, metres)", {"base_point": base_point}))
    antenna_type = table.get("base_antenna_type", "")
    if not isinstance(antenna_type, str) or len(antenna_type) > 20:
        problems.append(Phrase("gnss_raw.base_antenna_type: expected an ANTEX antenna name (up to 20 characters), "
                        "found {antenna_type!r}", {"antenna_type": antenna_type}))
    if len(problems) > before:
        return None
    return RawGnss(base=base, navigation=navigation, base_point=base_point, rover=rover, rover_log=rover_log,
                   rover_log_format=log_format, precise=precise, antex=antex, config=config,
                   base_antenna_height_m=None if height is None else float(height),
                   base_antenna_type=antenna_type)
