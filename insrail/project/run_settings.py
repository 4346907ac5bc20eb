"""The settings one processing run used: resolved once, recorded once.

``process()`` resolves the project and the survey into one frozen :class:`RunSettings` at its
start: the engineering CRS and its ellipsoid (the one object the fusion and the track stage
take), the height model with the benchmarks file's hash, the trolley, the IMU, tolerance and
fastener profiles (loaded, each with a digest of its contents), the design file with its hash,
the fusion options and the adjustment settings. The stages take their parts from it; each
stage's cache key hashes the parts that stage reads (:func:`insrail.project.pipeline.fusion_key`,
``track_key``); and :meth:`RunSettings.record` is written into ``summary.toml`` as
``[settings]`` (with its digest).

Reports, exports and the GUI print the RECORDED settings (:class:`RecordedSettings`, read back
from a summary), not today's ``project.toml``, and say when the project has changed since
(:meth:`RecordedSettings.changes`: "processed with ...; the project now says ...: process
again"). Results written before the settings were recorded read back with
:attr:`RecordedSettings.missing` set and say so instead of guessing.
"""

from __future__ import annotations

import hashlib
import json
import tomllib
import dataclasses
from dataclasses import asdict, dataclass, replace
from functools import cached_property
from pathlib import PurePath
from typing import Any

import numpy as np

from insrail.geodesy.crs import EngineeringCRS
from insrail.geodesy.ellipsoid import Ellipsoid, wgs84_baseline_scale_ppm
from insrail.geodesy.errors import SettingsError
from insrail.io.survey import SurveyManifest, TrolleyGeometry
from insrail.nav.fusion_options import FusionOptions
from insrail.nav.imu_profile import ImuProfile, load_imu_profile
from insrail.names import DEFAULT_LANGUAGE
from insrail.notices import Notice, Phrase
from insrail.project.model import FUSION_FLAGS, FUSION_NUMBERS, AdjustmentSettings, HeightSettings, Project
from insrail.project.stagecache import file_sha256
from insrail.track.adjustment import FastenerType, load_fastener_type
from insrail.track.tolerance import ToleranceProfile, load_tolerance_profile

#: summary.toml's table of the recorded settings.
SETTINGS_SECTION = "settings"
#: A GNSS baseline scale [ppm] beyond which the datum's ellipsoid is worth a notice (a tenth of the
#: 10 mm/km length distortion TB 10601 allows a CRS).
BASELINE_SCALE_NOTICE_PPM = 1.0
NOT_RECORDED = "processed before settings were recorded: process again to record them"


def _same(recorded, now) -> bool:
    """Equal as recorded (through TOML: tuples read back as lists, NaN lever arms equal to NaN)."""
    return json.dumps(recorded, sort_keys=True) == json.dumps(_plain(now), sort_keys=True)


def _contents_digest(value) -> str:
    """A digest of a loaded profile's contents: every field but where its file was read from, so results
    processed by an insrail installed elsewhere (its built-in profiles in another folder) still match."""
    return hashlib.sha256(repr(_without_paths(value)).encode()).hexdigest()[:16]


def _legacy_digest(value) -> str:
    """The digest results recorded before the path was left out (the repr, the file's path in it)."""
    return hashlib.sha256(repr(value).encode()).hexdigest()[:16]


def _without_paths(value):
    """``value``'s fields, nested, leaving out the file paths (a path says where, not what)."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return (type(value).__name__,
                tuple((f.name, _without_paths(getattr(value, f.name))) for f in dataclasses.fields(value)
                      if not isinstance(getattr(value, f.name), PurePath)))
    if isinstance(value, (list, tuple)):
        return tuple(_without_paths(v) for v in value)
    if isinstance(value, dict):
        return tuple((k, _without_paths(v)) for k, v in value.items())
    return value


def _plain(value):
    """TOML-able copy: arrays and tuples as lists (TOML has no None: entries holding None are left out)."""
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items() if v is not None}
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    return value


@dataclass(frozen=True)
class RunSettings:
    """Everything a run of ``process()`` takes from the project (module docstring)."""

    crs: EngineeringCRS
    height: HeightSettings
    benchmarks_sha256: str  # "" without benchmarks
    trolley: TrolleyGeometry
    imu_profile_name: str
    imu_profile: ImuProfile
    tolerance_profile: ToleranceProfile
    fastener: FastenerType
    fastener_name: str
    design: str | None  # the design file as project.toml names it (None: fitted lines)
    design_sha256: str  # "" without a design
    fusion: FusionOptions
    adjustment: AdjustmentSettings
    #: the language of the reports and exports (``[report] language``; a report's text, not its numbers:
    #: not in the record, so a change of language writes the reports again without processing again)
    report_language: str = DEFAULT_LANGUAGE

    @property
    def ellipsoid(self) -> Ellipsoid:
        """The one ellipsoid of the run (the CRS's; :mod:`insrail.geodesy.ellipsoid` says why)."""
        return self.crs.reference_ellipsoid

    def notices(self) -> list[Notice]:
        """What the settings themselves make worth saying: a datum whose ellipsoid stretches GNSS
        baselines computed with WGS84's formulas (:func:`wgs84_baseline_scale_ppm`)."""
        scale = wgs84_baseline_scale_ppm(self.ellipsoid)
        if abs(scale) <= BASELINE_SCALE_NOTICE_PPM:
            return []
        return [Notice("geodesy", "the CRS is on {ellipsoid}: GNSS positions are taken in its datum; a GNSS solution "
                                  "computed with WGS84's formulas from a base given in that datum reads baselines "
                                  "{scale_ppm:+.1f} ppm long ({at_5km_mm:+.0f} mm at 5 km from the base): lengths and "
                                  "chainage read that much long, absolute positions need common points "
                                  "([geodesy.local]) or a solution made on this ellipsoid",
                       fields={"ellipsoid": self.ellipsoid.describe(), "scale_ppm": scale, "at_5km_mm": scale * 5.0})]

    def record(self) -> dict[str, Any]:
        """The ``[settings]`` table of summary.toml (plain TOML data; :class:`RecordedSettings` reads it)."""
        ell = self.ellipsoid
        record = {
            "crs": self.crs.to_settings(),
            "crs_text": self.crs.describe(),
            "ellipsoid": {"name": ell.name, "a_m": ell.a, "inverse_flattening": ell.inverse_flattening},
            "heights": {**self.height.anomaly.to_settings(), "benchmarks": self.height.benchmarks or "",
                        "benchmarks_sha256": self.benchmarks_sha256},
            "trolley": _plain(asdict(self.trolley)),
            "imu_profile": {"name": self.imu_profile_name, "description": self.imu_profile.description,
                            "digest": _contents_digest(self.imu_profile)},
            "tolerance_profile": {"name": self.tolerance_profile.name,
                                  "digest": _contents_digest(self.tolerance_profile)},
            "fastener": {"name": self.fastener_name, "digest": _contents_digest(self.fastener)},
            "design": {"file": self.design or "", "sha256": self.design_sha256},
            "fusion": {**_plain({name: getattr(self.fusion, name) for name in FUSION_FLAGS + FUSION_NUMBERS}),
                       "digest": _contents_digest(self.fusion)},
            "adjustment": _plain(asdict(self.adjustment)),
        }
        return {**record, "digest": hashlib.sha256(json.dumps(record, sort_keys=True).encode()).hexdigest()[:32]}


def resolve_run_settings(project: Project, manifest: SurveyManifest) -> RunSettings:
    """The project's settings for one survey, resolved now (``manifest``: the survey's, with the
    project's trolley already applied). Raises what loading a profile or reading a file raises."""
    imu_name = project.imu_profile or manifest.imu_profile
    return RunSettings(
        crs=project.crs,
        height=project.height,
        benchmarks_sha256=(file_sha256(project.resolve(project.height.benchmarks))
                           if project.height.benchmarks is not None else ""),
        trolley=manifest.trolley,
        imu_profile_name=imu_name,
        imu_profile=load_imu_profile(project.resource(imu_name)),
        tolerance_profile=load_tolerance_profile(project.resource(project.tolerance_profile)),
        fastener=load_fastener_type(project.resource(project.fastener)),
        fastener_name=project.fastener,
        design=project.design,
        design_sha256=file_sha256(project.resolve(project.design)) if project.design is not None else "",
        fusion=project.fusion,
        adjustment=project.adjustment,
        report_language=report_language(project),
    )


def report_language(project: Project) -> str:
    """The language the project's reports and exports are written in (``[report] language``, checked when
    the project was loaded): what :func:`insrail.names.in_language` takes while one is written."""
    return project.report.language


# --------------------------------------------------------------------------- read back

#: (record key, what it is called, how a recorded value reads) for the comparison with the project now.
#: each recorded setting: its key, what it is in words, and its value in words (a Phrase or a name verbatim)
_DESCRIBED = (
    ("crs", "coordinate system", lambda c: EngineeringCRS.from_settings(c).describe()),
    ("heights", "height model", lambda h: (Phrase("{model} on {benchmarks}", {"model": h.get("model", "?"),
                                                                               "benchmarks": h["benchmarks"]})
                                           if h.get("benchmarks") else Phrase("ellipsoidal heights (no benchmarks)"))),
    ("imu_profile", "IMU profile", lambda p: p.get("name", "?")),
    ("tolerance_profile", "tolerance profile", lambda p: p.get("name", "?")),
    ("fastener", "fastener type", lambda p: p.get("name", "?")),
    ("design", "design", lambda d: d.get("file") or Phrase("none (fitted lines)")),
    ("trolley", "trolley geometry", lambda t: Phrase("[{section}] of summary.toml", {"section": f"{SETTINGS_SECTION}.trolley"})),
    ("fusion", "fusion options", lambda f: Phrase("[{section}] of summary.toml", {"section": f"{SETTINGS_SECTION}.fusion"})),
    ("adjustment", "adjustment settings", lambda a: ", ".join(f"{k} {v}" for k, v in a.items())),
)


@dataclass(frozen=True)
class RecordedSettings:
    """The ``[settings]`` a survey's results were processed with (empty ``record``: written before
    settings were recorded)."""

    record: dict

    @classmethod
    def of(cls, summary: dict) -> RecordedSettings:
        return cls(summary.get(SETTINGS_SECTION, {}))

    @property
    def missing(self) -> bool:
        return not self.record

    @cached_property
    def crs(self) -> EngineeringCRS | None:
        """The CRS the results are in (None when not recorded)."""
        if self.missing:
            return None
        try:
            return EngineeringCRS.from_settings(self.record["crs"], f"summary.toml {SETTINGS_SECTION}.crs")
        except (KeyError, SettingsError):
            return None

    def same_tolerance_profile(self, profile: ToleranceProfile) -> bool:
        """Whether ``profile`` has the contents the results were assessed with (True when not recorded)."""
        digest = self.record.get("tolerance_profile", {}).get("digest")
        return digest is None or digest in (_contents_digest(profile), _legacy_digest(profile))

    def changes(self, project: Project, survey: str) -> list[Phrase]:
        """What the project says now that differs from what the results were processed with, one
        line each ("processed with ...; the project now says ...: process again"); the missing
        record is one line too. A project that no longer resolves (a profile file gone) says so."""
        if self.missing:
            return [Phrase(NOT_RECORDED)]
        try:
            manifest = project.manifest(survey)
            trolley = project.trolley()
            if trolley is not None:
                manifest = replace(manifest, trolley=trolley)
            settings = resolve_run_settings(project, manifest)
            now = settings.record()
        except (ValueError, OSError, KeyError) as error:
            return [Phrase("the project's settings cannot be resolved now ({error}): the results stand as recorded",
                           {"error": str(error)})]
        lines = []
        digested = {"imu_profile": settings.imu_profile, "tolerance_profile": settings.tolerance_profile,
                    "fastener": settings.fastener, "fusion": settings.fusion}
        for key, what, describe in _DESCRIBED:
            then, today = self.record.get(key), now[key]
            loaded = digested.get(key)
            if loaded is not None and then is not None and then.get("digest") == _legacy_digest(loaded):
                then = {**then, "digest": today["digest"]}  # recorded with the path in the digest: the same contents
            if then is None or _same(then, today):
                continue
            old, new = describe(then), describe(today)
            if old == new:  # the same name, other contents: a profile or file edited, a lever arm changed
                new = Phrase("other values") if key in ("trolley", "fusion") else Phrase("{setting} with other contents",
                                                                                         {"setting": new})
            lines.append(Phrase("{what}: processed with {old}; the project now says {new}: process again",
                                {"what": Phrase(what), "old": old, "new": new}))
        return lines




def processed_crs_text(project: Project, summary: dict) -> str:
    """The CRS a survey's results are in, in one line: the recorded one; for results that predate
    the record the project's, saying so."""
    crs = RecordedSettings.of(summary).crs
    return crs.describe() if crs is not None else f"{project.crs.describe()} (the project's now; {NOT_RECORDED})"


def settings_change_lines(project: Project, survey: str) -> list[Phrase]:
    """What the project now says differently from the settings the survey's stored results were
    processed with ([] without results or changes): the warning lines of ``insrail report``,
    ``insrail export`` and the GUI's log."""
    from insrail.project.results import RESULTS_FOLDER, SUMMARY_FILE

    path = project.folder / RESULTS_FOLDER / survey / SUMMARY_FILE
    try:
        summary = tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, tomllib.TOMLDecodeError, UnicodeDecodeError):
        return []
    first = summary.get("section", {}).get("surveys", [survey])[0]
    return RecordedSettings.of(summary).changes(project, first)
