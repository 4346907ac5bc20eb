"""Post-processed kinematic GNSS (PPK) of a rover against a base receiver, with RTKLIB.

insrail checks the inputs (RINEX types, navigation data present, base and rover
overlapping in time, a known base position), builds RTKLIB's options from the
trolley defaults plus the user's overrides (:mod:`insrail.gnss.options`), and runs
RTKLIB's ``postpos`` in a child process: RTKLIB keeps its options in static memory
and cannot be interrupted, so a separate process keeps runs independent, lets the
user cancel, and turns an RTKLIB crash into an error instead of a dead application.

RTKLIB never sees a user's file name (it would run some through the shell): every
input goes into a private temporary folder under a name insrail makes, decompressed in
Python (:mod:`insrail.gnss.staging`); RTKLIB writes there too.

The result is an RTKLIB .pos (GPST, latitude/longitude/ellipsoidal height, RTKLIB's
header) copied to a temporary file next to the destination and renamed onto it
only when complete and loadable by :func:`insrail.io.rtklib.read_rtklib_pos`.
"""

from __future__ import annotations

import math
import multiprocessing
import os
import queue
import time
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from insrail.gnss.options import OptionError, apply_options, load_options, rtklib_option_table, same_value
from insrail.gnss.qc import GnssQc, gnss_qc
from insrail.gnss.rinex import RinexObsInfo, check_navigation, read_obs_info
from insrail.gnss.staging import install_output, rtklib_workdir, stage_file
from insrail.io.errors import InputError
from insrail.io.rtklib import read_rtklib_pos
from insrail.io.timescale import calendar_to_week_seconds
from insrail.io.types import GnssSolution
from insrail.nav.earth import ecef_to_geodetic, geodetic_to_ecef
from insrail.notices import Phrase
from insrail.progress import Cancelled, CancelToken, ProgressFn, StepProgress, is_cancelled

# insrail reads lat/lon/height .pos files with RTKLIB's header; the user cannot change these.
FORCED_OUTPUT_OPTIONS = {"out-solformat": "llh", "out-outhead": "on", "out-degform": "deg",
                         "out-height": "ellipsoidal"}
_POLL_INTERVAL_S = 0.1
# Short-baseline PPK reaches 1-2 cm up to about 15 km (thesis seed 002, section 5.2.2.4).
MAX_SHORT_BASELINE_M = 15_000.0


class GnssProcessingError(RuntimeError):
    """RTKLIB failed or crashed on inputs that passed insrail's checks."""


class LongBaselineWarning(UserWarning):
    """Base and rover further apart than short-baseline PPK allows (MAX_SHORT_BASELINE_M)."""


class ApproximateBaseWarning(UserWarning):
    """The base position comes from the RINEX header (APPROX POSITION XYZ), good to metres only."""


@dataclass(frozen=True)
class BasePosition:
    """Position of the surveyed mark under the base antenna, and the antenna on it.

    Either geodetic (``lat_rad``, ``lon_rad``, ``height_m`` ellipsoidal, WGS84 / the
    GNSS frame of the products) or ECEF (``ecef_m``). ``antenna_height_m`` is the
    vertical offset from the mark up to the antenna reference point (ARP), RTKLIB's
    ``ant2-antdelu``; ``antenna_type`` an ANTEX name (used when an ANTEX file is
    configured with ``file-rcvantfile``).
    """

    lat_rad: float | None = None
    lon_rad: float | None = None
    height_m: float | None = None
    ecef_m: tuple[float, float, float] | None = None
    antenna_height_m: float = 0.0
    antenna_type: str = ""

    def __post_init__(self):
        geodetic = (self.lat_rad, self.lon_rad, self.height_m)
        given = sum(v is not None for v in geodetic)
        has_geodetic = given == len(geodetic)
        if given not in (0, len(geodetic)) or has_geodetic == (self.ecef_m is not None):
            raise ValueError("BasePosition: give either lat_rad, lon_rad and height_m, or ecef_m")
        values = geodetic if has_geodetic else self.ecef_m
        if not all(math.isfinite(v) for v in values) or not math.isfinite(self.antenna_height_m):
            raise ValueError(f"BasePosition: non-finite coordinate in {values}")
        if has_geodetic and (abs(self.lat_rad) > math.pi / 2 or abs(self.lon_rad) > 2 * math.pi):
            raise ValueError(f"BasePosition: latitude/longitude out of range: {self.lat_rad}, {self.lon_rad} rad")

    @classmethod
    def from_degrees(cls, lat_deg: float, lon_deg: float, height_m: float, antenna_height_m: float = 0.0,
                     antenna_type: str = "") -> BasePosition:
        return cls(math.radians(lat_deg), math.radians(lon_deg), height_m,
                   antenna_height_m=antenna_height_m, antenna_type=antenna_type)

    def ecef(self) -> np.ndarray:
        """ECEF of the mark [m] (WGS84)."""
        if self.ecef_m is not None:
            return np.array(self.ecef_m, dtype=float)
        return geodetic_to_ecef(self.lat_rad, self.lon_rad, self.height_m)

    def antenna_reference_point_ecef(self) -> np.ndarray:
        """ECEF of the ARP [m]: ``antenna_height_m`` above the mark along the ellipsoid normal."""
        mark = self.ecef()
        lat, lon, height = ecef_to_geodetic(mark)
        return geodetic_to_ecef(lat, lon, height + self.antenna_height_m)

    def rtklib_options(self) -> dict[str, str]:
        """RTKLIB's base options: the ARP itself as the base position, ``ant2-antdelu`` 0.

        RTKLIB evaluates the base's troposphere model at the position it is given and adds
        the antenna delta only to the range; given the mark and the height, its hydrostatic
        delay refers to a point ``antenna_height_m`` too low, which lowers every rover height
        by about 0.8 mm per metre of antenna height (measured with insrail.sim.gnss_obs).
        """
        arp = self.antenna_reference_point_ecef()
        options = {"ant2-postype": "xyz", "ant2-pos1": repr(float(arp[0])), "ant2-pos2": repr(float(arp[1])),
                   "ant2-pos3": repr(float(arp[2])), "ant2-antdele": "0.0", "ant2-antdeln": "0.0",
                   "ant2-antdelu": "0.0"}
        if self.antenna_type:
            options["ant2-anttype"] = self.antenna_type
        return options


@dataclass(frozen=True)
class PpkResult:
    """Outcome of :func:`ppk`.

    out_pos   : the .pos file written
    solution  : its contents as read back by read_rtklib_pos
    qc        : quality summary
    options   : every RTKLIB option used (key -> value text)
    base_from_header : True when the base position is the approximate RINEX header one
    baseline_m : base to rover header position distance (metre level), None when unknown
    warnings  : messages for the processing log
    """

    out_pos: Path
    solution: GnssSolution
    qc: GnssQc
    options: dict[str, str]
    rover: RinexObsInfo
    base: RinexObsInfo
    base_from_header: bool
    baseline_m: float | None
    warnings: tuple[Phrase, ...]
    elapsed_s: float


def _run_postpos(options: dict[str, str], input_files: list[str], out_path: str, errors) -> None:
    """Child process: RTKLIB postpos over the whole observation span."""
    import pyrtklib

    try:
        prcopt, solopt, filopt = apply_options(options)
        status = pyrtklib.postpos(pyrtklib.gtime_t(), pyrtklib.gtime_t(), 0.0, 0.0, prcopt, solopt, filopt,
                                  input_files, len(input_files), pyrtklib.Arr1Dchar(out_path), "", "")
        errors.put(None if status == 0 else f"RTKLIB postpos returned status {status}")
    except Exception as err:  # noqa: BLE001 - any failure goes to the parent, which reports it
        errors.put(f"{type(err).__name__}: {err}")


def _as_user_file(original: Path, staged: Path, check):
    """``check(staged)`` with any InputError naming the user's file instead of the staged copy."""
    try:
        info = check(staged)
    except InputError as err:
        raise InputError(original, err.line, err.phrase, unit=err.unit) from None
    return None if info is None else replace(info, path=original)


def _check_inputs(rover_obs: Path, base_obs: Path, nav_files: Sequence[Path],
                  staged: Mapping[Path, Path]) -> tuple[RinexObsInfo, RinexObsInfo]:
    rover = _as_user_file(rover_obs, staged[rover_obs], read_obs_info)
    base = _as_user_file(base_obs, staged[base_obs], read_obs_info)
    if not nav_files:
        raise InputError(rover_obs, None, "no navigation data: give at least one RINEX navigation file")
    for path in nav_files:
        _as_user_file(path, staged[path], check_navigation)
    start, end = max(rover.first_s, base.first_s), min(rover.last_s, base.last_s)
    if start >= end:
        raise InputError(base_obs, None, "base and rover do not overlap in time: base "
                         "{base_span}, rover {file} {rover_span}", fields={"base_span": _span(base), "file": rover_obs.name, "rover_span": _span(rover)})
    return rover, base


# RTKLIB options naming files: inputs are staged like the observations; outputs RTKLIB would
# write wherever a (handed-over) configuration points are refused.
_INPUT_FILE_OPTIONS = ("file-satantfile", "file-rcvantfile", "file-staposfile", "file-geoidfile", "file-ionofile",
                       "file-dcbfile", "file-eopfile", "file-blqfile")
_REFUSED_FILE_OPTIONS = ("file-tempdir", "file-geexefile", "file-solstatfile", "file-tracefile")


def _stage_option_files(options: dict[str, str], workdir: Path) -> None:
    for key in _REFUSED_FILE_OPTIONS:
        if options.get(key, "").strip():
            raise OptionError(Phrase("{key} = {value!r}: insrail does not let RTKLIB write files of its own; leave it "
                                     "empty", {"key": key, "value": options[key]}))
    for number, key in enumerate(_INPUT_FILE_OPTIONS, 1):
        value = options.get(key, "").strip()
        if value:
            staged = stage_file(value, workdir, f"option{number}", ".dat")
            options[key] = str(staged)


def _stage_inputs(workdir: Path, rover_obs: Path, base_obs: Path, nav_paths: Sequence[Path],
                  precise_files: Sequence[Path]) -> list[tuple[Path, Path]]:
    """Every input under a safe name in ``workdir``: (user path, staged path) in RTKLIB's order."""
    staged = [(rover_obs, stage_file(rover_obs, workdir, "rover", ".obs")),
              (base_obs, stage_file(base_obs, workdir, "base", ".obs"))]
    staged += [(path, stage_file(path, workdir, f"nav{number}", ".nav")) for number, path in enumerate(nav_paths, 1)]
    staged += [(path, stage_file(path, workdir, f"precise{number}", ".dat"))
               for number, path in enumerate(precise_files, 1)]
    return staged


def _span(info: RinexObsInfo) -> str:
    week = int(info.first_s // 604800)
    return (f"GPS week {week} {info.first_s - 604800 * week:.0f} s .. "
            f"{info.last_s - 604800 * week:.0f} s")


def ppk(rover_obs: str | Path, base_obs: str | Path, nav_files: Sequence[str | Path], out_pos: str | Path, *,
        base_position: BasePosition | None = None, config: str | Path | None = None,
        options_overrides: Mapping[str, object] | None = None, precise_files: Sequence[str | Path] = (),
        progress: ProgressFn | None = None, cancel: CancelToken = None) -> PpkResult:
    """Carrier-phase kinematic positioning of ``rover_obs`` against ``base_obs`` with RTKLIB.

    nav_files         : RINEX navigation files (at least one)
    base_position     : the base antenna's known position; None takes the RINEX header's
                        APPROX POSITION XYZ, with an :class:`ApproximateBaseWarning`
    config            : RTKLIB .conf (default ``resources/gnss/ppk_default.conf``)
    options_overrides : any RTKLIB option, e.g. ``{"pos1-soltype": "forward",
                        "pos2-armode": "continuous", "pos1-elmask": 10, "pos1-navsys": 1}``
    precise_files     : SP3 / CLK products passed to RTKLIB with the navigation files
    Raises InputError naming the file for bad input; nothing is left at ``out_pos``
    (nor a temporary file) on any failure or on cancellation.
    """
    started = time.monotonic()
    report = StepProgress(progress)
    rover_obs, base_obs, out_pos = Path(rover_obs), Path(base_obs), Path(out_pos)
    nav_paths = [Path(p) for p in nav_files]
    precise_paths = [Path(p) for p in precise_files]
    if not out_pos.parent.is_dir():
        raise InputError(out_pos, None, "output folder {parent} does not exist", fields={"parent": out_pos.parent})
    report(0.0, "checking the input files")
    with rtklib_workdir() as workdir:
        staged = _stage_inputs(workdir, rover_obs, base_obs, nav_paths, precise_paths)
        rover, base = _check_inputs(rover_obs, base_obs, nav_paths, dict(staged))
        options = load_options(config, options_overrides)
        _stage_option_files(options, workdir)
        options, notes, base_from_header, baseline_m = _base_options(options, rover, base, base_obs,
                                                                       base_position)
        produced = workdir / "solution.pos"
        report(0.05, "RTKLIB post-processing")
        _run_child(options, [str(p) for _, p in staged], str(produced), report.sub(0.05, 0.9), cancel,
                   rover)
        if same_value("pos1-soltype", options.get("pos1-soltype", "forward"), "backward", rtklib_option_table()):
            _reverse_epochs(str(produced))
        report(0.9, "reading the solution")
        try:
            solution = read_rtklib_pos(produced)
        except InputError as err:
            raise InputError(rover_obs, None, "RTKLIB produced no usable solution (check the navigation "
                             "files, the time span and the options): {message}", fields={"message": err.message}) from None
        install_output(produced, out_pos)
    solution = replace(solution, source=out_pos)
    qc = gnss_qc(solution)
    report(1.0, Phrase("fix rate {fix_rate_pct:.1f} %", {"fix_rate_pct": 100 * qc.fix_rate}))
    return PpkResult(out_pos, solution, qc, options, rover, base, base_from_header, baseline_m, tuple(notes),
                     time.monotonic() - started)


def _base_options(options: dict[str, str], rover: RinexObsInfo, base: RinexObsInfo, base_obs: Path,
                  base_position: BasePosition | None) -> tuple[dict[str, str], list[str], bool, float | None]:
    """The output and base options: (options, notes for the log, base from the header, baseline [m])."""
    table = rtklib_option_table()
    forced = {k: options[k] for k, v in FORCED_OUTPUT_OPTIONS.items()
              if k in options and not same_value(k, options[k], v, table)}
    if forced:
        raise OptionError(Phrase("insrail needs {needed}: cannot use {forced}",
                                 {"needed": str(FORCED_OUTPUT_OPTIONS), "forced": str(forced)}))
    options.update(FORCED_OUTPUT_OPTIONS)
    notes: list[Phrase] = []
    if base_position is not None:
        options.update(base_position.rtklib_options())
    elif options.get("ant2-postype", "rinexhead") not in ("rinexhead", "4"):
        notes.append(Phrase("base position from the RTKLIB options: ant2-postype = {postype}",
                            {"postype": str(options["ant2-postype"])}))
    else:
        if base.approx_position_ecef_m is None:
            raise InputError(base_obs, None, "unknown base position: the RINEX header has no APPROX POSITION XYZ; "
                             "give the base position (control point coordinates)")
        options["ant2-postype"] = "rinexhead"
        message = Phrase("base position from the RINEX header of {file} (APPROX POSITION XYZ {xyz}): approximate, "
                         "metre level; every rover position carries its error. Give the control point's coordinates "
                         "for survey work.", {"file": base_obs.name, "xyz": str(base.approx_position_ecef_m)})
        warnings.warn(str(message), ApproximateBaseWarning, stacklevel=3)
        notes.append(message)
    base_from_header = options.get("ant2-postype") in ("rinexhead", "4")
    baseline_m = _baseline_m(rover, base, base_position)
    if baseline_m is not None and baseline_m > MAX_SHORT_BASELINE_M:
        message = Phrase("baseline {baseline_km:.1f} km is longer than the {short_km:.0f} km of short-baseline PPK: "
                         "expect slower fixing and larger errors; use a nearer base",
                         {"baseline_km": baseline_m / 1e3, "short_km": MAX_SHORT_BASELINE_M / 1e3})
        warnings.warn(str(message), LongBaselineWarning, stacklevel=3)
        notes.append(message)
    return options, notes, base_from_header, baseline_m


def _reverse_epochs(path: str) -> None:
    """Put a backward solution in time order: RTKLIB writes it from the last epoch to the first."""
    with open(path, encoding="ascii", errors="replace") as handle:
        lines = handle.readlines()
    header = [line for line in lines if line.startswith("%")]
    epochs = [line for line in lines if line.strip() and not line.startswith("%")]
    with open(path, "w", encoding="ascii") as handle:
        handle.writelines(header + epochs[::-1])


def _baseline_m(rover: RinexObsInfo, base: RinexObsInfo, base_position: BasePosition | None) -> float | None:
    """Base-rover distance from the rover's header position; None when either is unknown."""
    base_ecef = base_position.ecef() if base_position is not None else base.approx_position_ecef_m
    if rover.approx_position_ecef_m is None or base_ecef is None:
        return None
    return float(np.linalg.norm(np.subtract(rover.approx_position_ecef_m, base_ecef)))


def _run_child(options: dict[str, str], inputs: list[str], out_path: str, progress: StepProgress,
               cancel: CancelToken, rover: RinexObsInfo) -> None:
    """Run postpos in a spawned process; progress from the epochs written so far (forward runs)."""
    context = multiprocessing.get_context("spawn")
    errors = context.Queue()
    child = context.Process(target=_run_postpos, args=(options, inputs, out_path, errors), daemon=True)
    child.start()
    span = max(rover.last_s - rover.first_s, 1.0)
    try:
        while child.is_alive():
            if is_cancelled(cancel):
                child.terminate()
                child.join()
                raise Cancelled("GNSS post-processing cancelled by the user")
            progress(_written_fraction(out_path, rover.first_s, span), "RTKLIB post-processing")
            child.join(_POLL_INTERVAL_S)
        try:
            error = errors.get(timeout=1.0)
        except queue.Empty:
            error = f"RTKLIB stopped unexpectedly (exit code {child.exitcode})"
    finally:
        errors.close()
    if error:
        raise GnssProcessingError(Phrase("GNSS post-processing failed: {error}", {"error": str(error)}))


def _written_fraction(out_path: str, first_s: float, span_s: float) -> float:
    """Share of the rover span already in the output (0 until RTKLIB writes; combined mode writes at the end)."""
    try:
        with open(out_path, "rb") as handle:
            handle.seek(0, os.SEEK_END)
            size = handle.tell()
            handle.seek(max(0, size - 400))
            tail = handle.read().decode("ascii", errors="replace").splitlines()
    except OSError:
        return 0.0
    for line in reversed(tail[1:]):
        fields = line.split()
        if len(fields) > 2 and "/" in fields[0]:
            try:
                date = [float(v) for v in fields[0].split("/") + fields[1].split(":")]
            except ValueError:
                return 0.0
            week, seconds = calendar_to_week_seconds(*([value] for value in date))
            return min(max((week * 604800 + float(seconds[0]) - first_s) / span_s, 0.0), 1.0)
    return 0.0
