"""The GNSS stage of the pipeline: PPK of a survey's raw observations (``[gnss_raw]`` in survey.toml).

When a survey holds raw GNSS observations instead of a solution, :func:`run_gnss_stage` runs
first: a receiver log is converted to RINEX (RTKLIB convbin), the base position is taken from
the project's control point (or, with a warning, from the base file's RINEX header), and
:func:`insrail.gnss.ppk` computes the rover's solution. Both are cached in
``<project>/results/.cache/`` under a hash of what determines them (the contents of every
input file, the RTKLIB configuration, the base position, antenna height and type, the
RTKLIB version), so reprocessing with other track settings does not run RTKLIB again, while
a changed base point does. The fusion's cache key includes the hash of the resulting .pos.

Result files (``results/<survey>/``): ``gnss.pos`` (the RTKLIB solution) and ``gnss_qc.toml``
(epochs by quality, fix rate, ratio and sigma statistics, gaps, base point, warnings).
"""

from __future__ import annotations

import hashlib
import importlib.metadata
import json
import math
import os
import shutil
import tempfile
import tomllib
import warnings
from dataclasses import asdict, dataclass
from pathlib import Path

import tomli_w

from insrail.gnss import (
    ApproximateBaseWarning,
    BasePosition,
    GnssQc,
    LongBaselineWarning,
    convert_to_rinex,
    gnss_qc,
    ppk,
)
from insrail.gnss.options import DEFAULT_CONFIG
from insrail.io.atomic import atomic_write
from insrail.io.errors import InputError
from insrail.io.rtklib import read_rtklib_pos
from insrail.io.survey import MANIFEST_NAME, SurveyManifest
from insrail.io.survey_gnss import RawGnss
from insrail.io.types import GnssSolution
from insrail.nav.fusion import gnss_by_quality
from insrail.notices import Phrase, phrase_of
from insrail.progress import CancelToken, ProgressFn, StepProgress, check_cancel
from insrail.project.control_points import resolve_control_point
from insrail.project.lock import cache_entry
from insrail.project.model import Project
from insrail.project.stagecache import intact, seal
from insrail.resources import resource

GNSS_POS_FILE = "gnss.pos"
GNSS_QC_FILE = "gnss_qc.toml"
#: Bumped when the meaning of a cached PPK result changes.
PPK_CACHE_VERSION = 1


@dataclass(frozen=True)
class GnssStageResult:
    """The PPK solution of a survey and where it lies in the cache.

    pos_file, qc_file : cached ``.pos`` and QC report (copied into the results)
    pos_sha256        : hash of the .pos contents (part of the fusion's cache key)
    report            : the QC report's contents (also the ``gnss`` part of summary.toml)
    """

    solution: GnssSolution
    qc: GnssQc
    pos_file: Path
    qc_file: Path
    pos_sha256: str
    from_cache: bool
    report: dict

    def result_files(self) -> dict[str, Path]:
        return {GNSS_POS_FILE: self.pos_file, GNSS_QC_FILE: self.qc_file}

    def summary(self, quality_policy) -> dict:
        """For summary.toml: the QC headline, the cache, and what the fusion does with each quality."""
        _, used = gnss_by_quality(self.solution, quality_policy)
        fusion = {name: {"epochs": u["epochs"],
                         "use": "excluded" if not u["used"] else f"sigma x {u['sigma_factor']:g}"}
                  for name, u in used.items()}
        inflated = sum(u["epochs"] for u in used.values() if u["used"] and u["sigma_factor"] != 1.0)
        excluded = sum(u["epochs"] for u in used.values() if not u["used"])
        base = self.report["base"]  # its texts as phrases (insrail.notices): summary.toml has them in English
        return {"source": "ppk", "from_cache": self.from_cache, "file": GNSS_POS_FILE, "qc_file": GNSS_QC_FILE,
                "epochs": self.qc.epochs, "fix_rate": self.qc.fix_rate,
                "epochs_by_quality": dict(self.qc.epochs_by_quality),
                "fusion_inflated_epochs": inflated, "fusion_excluded_epochs": excluded,
                "fusion_by_quality": fusion, "base": {**base, **({"derivation": str(phrase_of(base["derivation"]))} if "derivation" in base else {}),
                                                      "warnings": [str(phrase_of(w)) for w in base.get("warnings", [])]},
                "warnings": [str(warning) for warning in self.warnings()]}

    def warnings(self) -> list[Phrase]:
        """The base's and the solution's warnings (the QC report keeps them as phrases: :mod:`insrail.notices`)."""
        return [phrase_of(w) for w in (*self.report["base"].get("warnings", []), *self.report["warnings"])]


def _hash_files(digest, folder: Path, names) -> None:
    for name in names:
        digest.update(name.encode() + b"\0")
        with open(folder / name, "rb") as handle:
            for block in iter(lambda: handle.read(1 << 20), b""):
                digest.update(block)


def _base_position(project: Project, folder: Path, raw: RawGnss) -> tuple[BasePosition | None, dict]:
    """The base receiver's mark, antenna height and type; None for the RINEX header position."""
    if raw.base_from_header:
        return None, {"point": raw.base_point, "approximate": True,
                      "derivation": Phrase("APPROX POSITION XYZ of {file}: metre level", {"file": raw.base}).to_dict()}
    point = project.control_point(raw.base_point)
    if point is None:
        known = ", ".join(p.name for p in project.control_points) or "none"
        raise InputError(folder / MANIFEST_NAME, None, "gnss_raw.base_point: unknown control point "
                         "{base_point!r}: not in the project's [geodesy.control_points] (known: {known}); "
                         "or write base_point = \"rinex-header\" for the approximate header position", fields={"base_point": raw.base_point, "known": known})
    from insrail.project.pipeline import fit_heights  # the pipeline imports this module

    resolved = resolve_control_point(point, project.crs, fit_heights(project))
    # The base's coordinates in the CRS's datum go to RTKLIB as latitude, longitude and height (its
    # WGS84 formulas make them ECEF and the rover's ECEF back), so the rover's solution comes out
    # in that datum, as the fusion takes it (insrail.geodesy.ellipsoid); on a datum with another
    # ellipsoid the baseline's length changes by Δa/a (0.5 ppm on Xian80). ECEF made with the
    # datum's own ellipsoid would put the rover metres off (3 m in height on Xian80).
    base = BasePosition(resolved.lat_rad, resolved.lon_rad, resolved.height_m,
                        antenna_height_m=raw.base_antenna_height_m, antenna_type=raw.base_antenna_type)
    return base, {"point": resolved.name, "approximate": False, "lat_deg": math.degrees(resolved.lat_rad),
                  "lon_deg": math.degrees(resolved.lon_rad), "ellipsoidal_height_m": resolved.height_m,
                  "antenna_height_m": raw.base_antenna_height_m, "antenna_type": raw.base_antenna_type,
                  "derivation": resolved.derivation.to_dict(), "warnings": [w.to_dict() for w in resolved.warnings]}


def _converted_log(project_folder: Path, cache: Path, folder: Path, raw: RawGnss, progress: ProgressFn | None,
                   cancel: CancelToken) -> tuple[Path, tuple[Path, ...]]:
    """The rover log as RINEX (observations, navigation files), converted once per log contents."""
    digest = hashlib.sha256()
    _hash_files(digest, folder, [raw.rover_log])
    digest.update(str(raw.rover_log_format).encode())
    target = cache / f"rinex-{digest.hexdigest()[:32]}"
    with cache_entry(project_folder, target.name, progress, cancel):
        if target.is_dir() and not intact("receiver log conversion", *_converted_files(target)):
            shutil.rmtree(target, ignore_errors=True)
        if not target.is_dir():
            staging = Path(tempfile.mkdtemp(prefix=".rinex-", dir=cache))
            try:
                seal(*convert_to_rinex(folder / raw.rover_log, staging, raw.rover_log_format))
                os.replace(staging, target)
            finally:
                shutil.rmtree(staging, ignore_errors=True)
    stem = Path(raw.rover_log).stem
    navigation = target / f"{stem}.nav"
    return target / f"{stem}.obs", (navigation,) if navigation.is_file() else ()


def _converted_files(target: Path) -> list[Path]:
    """The RINEX files of a cached conversion (an observation file at least: absent means damaged)."""
    files = sorted(p for p in target.iterdir() if p.suffix in (".obs", ".nav"))
    return files if any(p.suffix == ".obs" for p in files) else [target / "missing.obs"]


def _ppk_key(folder: Path, raw: RawGnss, base: BasePosition | None) -> str:
    digest = hashlib.sha256()
    _hash_files(digest, folder, raw.input_files())
    if raw.config is None:
        digest.update(Path(resource(*DEFAULT_CONFIG)).read_bytes())
    settings = {"version": PPK_CACHE_VERSION, "rtklib": importlib.metadata.version("pyrtklib"),
                "gnss_raw": raw.to_settings(), "base": None if base is None else repr(base)}
    digest.update(json.dumps(settings, sort_keys=True).encode())
    return digest.hexdigest()[:32]


def _qc_report(qc: GnssQc) -> dict:
    report = {k: v for k, v in asdict(qc).items() if k not in ("gaps", "sigma_by_quality")}
    report["sigma_by_quality_m"] = {name: asdict(stats) for name, stats in qc.sigma_by_quality.items()}
    report["gaps"] = [{"start_s": g.start_s, "end_s": g.end_s, "duration_s": g.duration_s} for g in qc.gaps]
    return report


def run_gnss_stage(project: Project, folder: Path, manifest: SurveyManifest, cache: Path,
                   progress: ProgressFn | None = None, cancel: CancelToken = None) -> GnssStageResult:
    """PPK of the survey in ``folder`` (its ``[gnss_raw]``), from the ``cache`` folder when already computed."""
    raw = manifest.raw_gnss
    step = StepProgress(progress)
    cache.mkdir(parents=True, exist_ok=True)
    base, base_report = _base_position(project, folder, raw)
    key = _ppk_key(folder, raw, base)
    pos_file, qc_file = cache / f"ppk-{key}.pos", cache / f"ppk-{key}.toml"
    with cache_entry(project.folder, pos_file.stem, progress, cancel):  # one run computes it, another reuses it
        from_cache = intact("GNSS solution", pos_file, qc_file)
        if from_cache:
            step(1.0, "GNSS solution reused from the cache")
            report = tomllib.loads(qc_file.read_text(encoding="utf-8"))
        else:
            step(0.0, "GNSS: preparing the observations")
            navigation = [folder / n for n in raw.navigation]
            if raw.rover_log is not None:
                rover, log_navigation = _converted_log(project.folder, cache, folder, raw, progress, cancel)
                navigation += log_navigation
            else:
                rover = folder / raw.rover
            check_cancel(cancel)
            overrides = {}
            if raw.antex is not None:
                # Phase-centre offsets and variations of both antennas; "*" takes the type from the RINEX
                # header (ANT # / TYPE), base_antenna_type (BasePosition) overrides it for the base.
                overrides = {"file-rcvantfile": str(folder / raw.antex), "ant1-anttype": "*", "ant2-anttype": "*"}
            with warnings.catch_warnings():  # kept in the QC report and the summary instead
                for category in (ApproximateBaseWarning, LongBaselineWarning):
                    warnings.simplefilter("ignore", category)
                result = ppk(rover, folder / raw.base, navigation, pos_file, base_position=base,
                             config=None if raw.config is None else folder / raw.config,
                             options_overrides=overrides, precise_files=[folder / p for p in raw.precise],
                             progress=step.sub(0.05, 0.95), cancel=cancel)
            report = {"base": base_report, "warnings": [w.to_dict() for w in result.warnings], "rtklib_seconds": result.elapsed_s,
                      **({"baseline_m": result.baseline_m} if result.baseline_m is not None else {}),
                      "qc": _qc_report(result.qc)}
            try:
                with atomic_write(qc_file, "wb") as handle:
                    tomli_w.dump(report, handle)
                seal(pos_file, qc_file)
            except BaseException:
                pos_file.unlink(missing_ok=True)  # a .pos without its report is never taken for a cache entry
                raise
    solution = read_rtklib_pos(pos_file)
    pos_sha256 = hashlib.sha256(pos_file.read_bytes()).hexdigest()
    step(1.0, "GNSS solution ready")
    return GnssStageResult(solution, gnss_qc(solution), pos_file, qc_file, pos_sha256, from_cache, report)
