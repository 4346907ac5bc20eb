"""Plausibility of a survey's inputs, checked with the physics before anything is fused.

Each reader checks its own file's syntax; what a file *means* can only be judged against the other
sensors and against the Earth. A wrong unit or time scale otherwise gives a result that looks
normal (the worst defect this product can have), so each check below either raises an
:class:`~insrail.io.errors.InputError` naming the file, its unit and the likely cause, or returns
:class:`~insrail.notices.Notice` objects; on a clean survey none of them says anything or changes
anything (tests/test_project_robustness.py).

* benchmarks: the height anomaly ζ = h − H of every benchmark within ±:data:`MAX_HEIGHT_ANOMALY_M`
  (the geoid's range on Earth), consistent between benchmarks (within :data:`MAX_ANOMALY_SPREAD_M`
  of their median) and within :data:`MAX_EGM96_OFFSET_M` of EGM96 (its grid ships with insrail, so the
  check runs on every install; h and H swapped gives −ζ: 25 m off on the demo);
* trolley: the lever arms the track needs given, those given at most :data:`MAX_LEVER_ARM_M`
  (millimetres written as metres), the
  rail-centre spacing (cant base) the nominal gauge plus one rail head (:data:`RAIL_HEAD_BAND_M`);
* gauge record: its median within :data:`MAX_GAUGE_OFFSET_M` of the nominal gauge (a file in
  another unit); single readings further than that from the median are removed and listed;
* odometer against GNSS: the distance scale over :data:`SCALE_WINDOW_S` windows within
  :data:`MAX_SCALE_ERROR` of 1 (a distance in mm, a wrong pulse length), the speeds agreeing;
* odometer direction: at each start from rest the forward (b-frame x) velocity the IMU gains and the
  odometer's signed speed must have the same sign (a trolley facing backwards has both negative;
  an odometer counting backwards only one).

The clocks (time offsets of the odometer, GNSS and sleeper detector against the IMU, a sleeper
file of another run) are checked by :mod:`insrail.project.clocks`.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from insrail.io.errors import InputError
from insrail.io.formats import FORMATS
from insrail.io.imu import release_pages
from insrail.io.survey import MANIFEST_NAME, SurveyData, TrolleyGeometry, track_lever_arm_problems
from insrail.io.types import (
    Benchmarks,
    GaugeData,
    GnssSolution,
    ImuIncrements,
    OdometerData,
)
from insrail.nav.earth import geodetic_to_ecef
from insrail.nav.imu_profile import load_imu_profile
from insrail.notices import Notice, Phrase, one_after_another

MAX_HEIGHT_ANOMALY_M = 150.0
MAX_ANOMALY_SPREAD_M = 5.0
MAX_EGM96_OFFSET_M = 10.0
MAX_LEVER_ARM_M = 5.0
RAIL_HEAD_BAND_M = (0.03, 0.12)
MAX_GAUGE_OFFSET_M = 0.05
MAX_GAUGE_OUTLIER_SHARE = 0.01
SCALE_WINDOW_S = 10.0
MIN_WINDOW_TRAVEL_M = 3.0
MAX_SCALE_ERROR = 0.05
MAX_SPEED_DISAGREEMENT_SHARE = 0.2
STATIC_BEFORE_START_S = 3.0
START_WINDOW_S = 3.0
GPS_MINUS_UTC_S = range(10, 19)  # 1995 .. today (18 s since 2017)


def describe(path: Path | None, format_name: str | None) -> str:
    """``odometer.txt (odometer cumulative distance [m])``: the file and what insrail read it as."""
    name = path.name if path is not None else "?"
    fmt = FORMATS.get(format_name) if format_name else None
    return f"{name} ({fmt.description})" if fmt is not None else name


def read_as(label: str) -> Phrase:
    """The start of a message about the file itself (its name is already in front): its unit."""
    _, _, what = label.partition(" (")
    return Phrase("read as {format}: ", {"format": what[:-1]}) if what else Phrase("")


def nominal_gauge_m(project) -> float:
    """The nominal gauge of the project's tolerance profile [m]."""
    from insrail.track.tolerance import load_tolerance_profile

    return load_tolerance_profile(project.resource(project.tolerance_profile)).nominal_gauge_m


# --------------------------------------------------------------------------- heights

def check_benchmarks(benchmarks: Benchmarks) -> None:
    """InputError naming the benchmark file for a height anomaly that cannot be one."""
    from insrail.geodesy.geoid import GeoidGrid

    if not len(benchmarks):
        return
    path = benchmarks.source or Path("benchmarks")
    zeta = benchmarks.height_anomaly_m
    columns = "columns id lat lon h H: h ellipsoidal, H normal height, metres"
    worst = int(np.argmax(np.abs(zeta)))
    if abs(zeta[worst]) > MAX_HEIGHT_ANOMALY_M:
        raise InputError(path, None, "benchmark {point_id}: height anomaly h - H = "
                         "{zeta:.3f} m, beyond the ±{max_height_anomaly_m:.0f} m of the geoid anywhere on "
                         "Earth ({columns}): a height in another unit or datum?", fields={"point_id": benchmarks.point_id[worst], "zeta": zeta[worst], "max_height_anomaly_m": MAX_HEIGHT_ANOMALY_M, "columns": columns})
    median = float(np.median(zeta))
    off = np.abs(zeta - median)
    if len(zeta) >= 3 and off.max() > MAX_ANOMALY_SPREAD_M:
        bad = int(np.argmax(off))
        raise InputError(path, None, "benchmark {point_id}: height anomaly h - H = {zeta:.3f} m "
                         "against {median:.3f} m at the others ({columns}): h and H swapped on its line, or a typo?", fields={"point_id": benchmarks.point_id[bad], "zeta": zeta[bad], "median": median, "columns": columns})
    undulation = np.asarray(GeoidGrid.egm96().undulation_m(benchmarks.lat_rad, benchmarks.lon_rad), dtype=float)
    offset = float(np.median(zeta - undulation))
    if abs(offset) > MAX_EGM96_OFFSET_M:
        swapped = abs(float(np.median(-zeta - undulation))) <= MAX_EGM96_OFFSET_M
        cause = Phrase("h and H are swapped (the file's columns are id lat lon h H)" if swapped else
                       "heights in another datum or unit, or H is not a normal height")
        raise InputError(path, None, "height anomaly h - H = {median:.3f} m at the benchmarks, but the geoid "
                         "(EGM96) lies at {median2:.3f} m there, {offset:+.1f} m apart "
                         "(local height datums differ from EGM96 by a few metres at most): likely {cause}", fields={"median": median, "median2": float(np.median(undulation)), "offset": offset, "cause": cause})


# --------------------------------------------------------------------------- trolley

def check_trolley(trolley: TrolleyGeometry, source: Path, nominal_gauge_m: float, roles: set[str]) -> None:
    """InputError naming the file of the ``[trolley]`` table for a lever arm the track reconstruction
    needs with the survey's data (``roles``) but the table leaves out, or geometry no trolley has
    (lever arms not given are not numbers and are not checked as such)."""
    missing = track_lever_arm_problems(trolley, roles)
    if missing:
        raise InputError(source, None, one_after_another(missing))
    for name, arm in trolley.given_lever_arms().items():
        if np.max(np.abs(arm)) > MAX_LEVER_ARM_M:
            raise InputError(source, None, "trolley.{name} = {arm} m: a lever arm on a trolley is at most "
                             "{max_lever_arm_m:g} m (b frame, metres): millimetres given as metres?", fields={"name": name, "arm": str(arm.tolist()), "max_lever_arm_m": MAX_LEVER_ARM_M})
    low, high = (nominal_gauge_m + band for band in RAIL_HEAD_BAND_M)
    spacing = float(trolley.rail_centre_spacing_m)
    if not low <= spacing <= high:
        raise InputError(source, None, "trolley.rail_centre_spacing_m = {spacing:g} m: the distance between the "
                         "rail centres (the cant base) is the gauge plus one rail head, {low:.3f} .. {high:.3f} m "
                         "for the {gauge_mm:.0f} mm gauge of the tolerance profile{hint}",
                         fields={"spacing": spacing, "low": low, "high": high, "gauge_mm": 1e3 * nominal_gauge_m,
                                 "hint": Phrase(": millimetres given as metres?" if spacing > 100 * high else "")})


def check_imu_profile(name_or_path: str, source: Path, key: str) -> None:
    """InputError naming the file and key of an IMU profile that does not load (an unknown name)."""
    try:
        load_imu_profile(name_or_path)
    except (ValueError, OSError) as err:
        raise InputError(source, None, "{key}: {err}", fields={"key": key, "err": err}) from None


# --------------------------------------------------------------------------- gauge

def clean_gauge(gauge: GaugeData | None, nominal_gauge_m: float, label: str) -> tuple[GaugeData | None, list[Notice]]:
    """The gauge record without its outliers (listed in a notice); InputError for a record in another unit."""
    if gauge is None or not len(gauge.gauge_m):
        return gauge, []
    path = gauge.source or Path(label)
    values = np.asarray(gauge.gauge_m, dtype=float)
    finite = np.isfinite(values)
    median = float(np.median(values[finite])) if finite.any() else float("nan")
    if not abs(median - nominal_gauge_m) <= MAX_GAUGE_OFFSET_M:
        ratio = median / nominal_gauge_m
        hint = (Phrase(" (x{ratio:.3g} the nominal: another unit?)", {"ratio": ratio})
                if np.isfinite(ratio) and (ratio > 2 or ratio < 0.5) else Phrase(""))
        raise InputError(path, None, "{read_as}median gauge {median_mm:.1f} mm against the nominal "
                         "{nominal_mm:.0f} mm of the tolerance profile{hint}; the file must hold the "
                         "gauge in mm", fields={"read_as": read_as(label), "median_mm": 1e3 * median, "nominal_mm": 1e3 * nominal_gauge_m, "hint": hint})
    outlier = ~finite | (np.abs(values - median) > MAX_GAUGE_OFFSET_M)
    if not outlier.any():
        return gauge, []
    if outlier.mean() > MAX_GAUGE_OUTLIER_SHARE:
        raise InputError(path, None, "{read_as}{outliers} of {count} readings lie more than "
                         "{max_offset_mm:.0f} mm from the median {median_mm:.1f} mm: a faulty gauge "
                         "sensor; repair or remove the record", fields={"read_as": read_as(label), "outliers": int(outlier.sum()), "count": len(values), "max_offset_mm": 1e3 * MAX_GAUGE_OFFSET_M, "median_mm": 1e3 * median})
    listed = ", ".join(f"{t:.3f} s: {1e3 * v:.1f} mm" for t, v in zip(gauge.time_s[outlier][:5], values[outlier][:5]))
    more = (Phrase(" and {more} more", {"more": int(outlier.sum()) - 5}) if outlier.sum() > 5 else Phrase(""))
    notice = Notice("gauge", "{label}: {count} gauge reading(s) more than {offset_mm:.0f} mm from the median "
                    "{median_mm:.1f} mm removed as outliers ({listed}{more})",
                    file=str(path), time_s=float(gauge.time_s[outlier][0]),
                    fields={"label": label, "count": int(outlier.sum()), "offset_mm": 1e3 * MAX_GAUGE_OFFSET_M,
                            "median_mm": 1e3 * median, "listed": listed, "more": more})
    keep = ~outlier
    return replace(gauge, time_s=gauge.time_s[keep], gauge_m=values[keep]), [notice]


# --------------------------------------------------------------------------- odometer, time, sleepers

def gnss_track(gnss: GnssSolution) -> tuple[np.ndarray, np.ndarray]:
    """GNSS epochs and ECEF positions, the fixed ones when there are enough."""
    keep = np.isfinite(gnss.lat_rad) & np.isfinite(gnss.lon_rad) & np.isfinite(gnss.height_m)
    fixed = keep & (gnss.quality == 1)
    if fixed.sum() >= 30:
        keep = fixed
    xyz = geodetic_to_ecef(gnss.lat_rad[keep], gnss.lon_rad[keep], gnss.height_m[keep])
    return gnss.time_s[keep], xyz


def distance_at(odometer: OdometerData, times: np.ndarray) -> np.ndarray:
    return np.interp(times, odometer.time_s, odometer.distance_m, left=np.nan, right=np.nan)


def check_odometer(odometer: OdometerData, gnss: GnssSolution, odometer_label: str, gnss_label: str) -> list[Notice]:
    """InputError when the odometer's distance scale or speed disagrees with GNSS."""
    time_s, xyz = gnss_track(gnss)
    if len(time_s) < 3 or len(odometer.time_s) < 3:
        return []
    step = max(1, int(round(SCALE_WINDOW_S / max(float(np.median(np.diff(time_s))), 1e-3))))
    start, end = np.arange(len(time_s) - step), np.arange(step, len(time_s))
    duration = time_s[end] - time_s[start]
    gnss_travel = np.linalg.norm(xyz[end] - xyz[start], axis=1)
    odo_travel = np.abs(distance_at(odometer, time_s[end]) - distance_at(odometer, time_s[start]))
    usable = ((duration <= 1.5 * SCALE_WINDOW_S) & (gnss_travel > MIN_WINDOW_TRAVEL_M) & np.isfinite(odo_travel))
    if usable.sum() < 10:
        return []
    # the median window: a unit or a calibration scales every window alike; a wheel stuck or slipping for a
    # while (its own check below, then the fusion's gate) moves only a few (on a 300 m survey a wheel stuck
    # for 15 s took the whole survey's ratio to 0.94, refused as a distance "in another unit")
    ratio = odo_travel[usable] / gnss_travel[usable]
    scale = float(np.median(ratio))
    path = odometer.source or Path(odometer_label)
    if abs(scale - 1.0) > MAX_SCALE_ERROR:
        if 700 < scale < 1400:
            cause = Phrase("a distance in millimetres")
        elif odometer.pulse_length_m is not None:
            cause = Phrase("a wrong pulse length (pulse_length_m = {pulse_length_m:g} m)",
                           {"pulse_length_m": odometer.pulse_length_m})
        else:
            cause = Phrase("a distance in another unit, or a wrong calibration")
        raise InputError(path, None, "{read_as}the odometer travels {scale:.4g} m per metre of GNSS "
                         "({gnss_label}) over {windows} windows of {scale_window_s:g} s; expected 1 within "
                         "{max_error_pct:.0f} %: likely {cause}", fields={"read_as": read_as(odometer_label), "scale": scale, "gnss_label": gnss_label, "windows": int(usable.sum()), "scale_window_s": SCALE_WINDOW_S, "max_error_pct": 100 * MAX_SCALE_ERROR, "cause": cause})
    disagree = float(np.mean(np.abs(ratio / scale - 1.0) > 0.1))
    if disagree > MAX_SPEED_DISAGREEMENT_SHARE:
        raise InputError(path, None, "{read_as}the odometer's speed disagrees with the GNSS speed "
                         "({gnss_label}) by more than 10 % in {disagree_pct:.0f} % of the moving windows: a slipping "
                         "wheel, a wrong time scale or another survey's file", fields={"read_as": read_as(odometer_label), "gnss_label": gnss_label, "disagree_pct": 100 * disagree})
    return []


def check_odometer_direction(imu: ImuIncrements, odometer: OdometerData, odometer_label: str) -> list[Notice]:
    """InputError when the odometer counts backwards against the IMU's forward axis at the starts from rest."""
    t, d = odometer.time_s, odometer.distance_m
    if len(t) < 10 or len(imu.time_s) < 10:
        return []
    step = max(float(np.median(np.diff(t))), 1e-3)
    moving = np.abs(np.gradient(d, t)) > 0.05
    starts = np.flatnonzero(moving[1:] & ~moving[:-1]) + 1
    windows = []  # (t0, IMU records a, b, c) of each start from rest
    for start in starts:
        t0 = float(t[start])
        rest = (t >= t0 - STATIC_BEFORE_START_S) & (t < t0 - step)
        if rest.sum() < STATIC_BEFORE_START_S / step * 0.8 or moving[rest].any():
            continue  # not a start from rest
        a, b, c = np.searchsorted(imu.time_s, [t0 - STATIC_BEFORE_START_S, t0 - 0.5, t0 + START_WINDOW_S])
        if c >= len(imu.time_s) or b - a < 10:
            continue
        windows.append((t0, a, b, c))
    # the running sum of the forward velocity increments at those records only
    forward = dict(zip(*running_sum_at(imu.dvel_mps, 0, sorted({i for _, *abc in windows for i in abc}))))
    votes = []
    for t0, a, b, c in windows:
        static_rate = (forward[b] - forward[a]) / (imu.time_s[b] - imu.time_s[a])  # gravity along x, biases
        gained = forward[c] - forward[b] - static_rate * (imu.time_s[c] - imu.time_s[b])
        odometer_speed = float(np.interp(t0 + START_WINDOW_S, t, np.gradient(d, t)))
        if abs(gained) > 0.1 and abs(odometer_speed) > 0.1:
            votes.append(np.sign(gained) == np.sign(odometer_speed))
    if len(votes) and not any(votes):
        path = odometer.source or Path(odometer_label)
        raise InputError(path, None, "{read_as}the odometer counts backwards: at {count} "
                         "start(s) from rest the IMU moved forwards along its x axis while the distance decreased "
                         "(a reversed odometer, or the sign of its counts); the distance must grow as the trolley "
                         "moves along the IMU's x axis", fields={"read_as": read_as(odometer_label), "count": len(votes)})
    return []


#: IMU records summed at a time by :func:`running_sum_at`
RUNNING_SUM_CHUNK = 1 << 18


def running_sum_at(increments: np.ndarray, axis: int, records: list[int]) -> tuple[list[int], list[float]]:
    """(records, np.cumsum(increments[:, axis])[records]) to the bit, summed a chunk at a time with the
    sum carried over (a mapped IMU file's pages let go behind each chunk)."""
    wanted = np.asarray(records, dtype=np.int64)
    values = np.empty(len(wanted))
    carry = 0.0
    for lo in range(0, int(wanted.max()) + 1 if len(wanted) else 0, RUNNING_SUM_CHUNK):
        hi = lo + RUNNING_SUM_CHUNK
        sums = np.cumsum(increments[lo:hi, axis]) if lo == 0 else np.cumsum(
            np.concatenate([[carry], increments[lo:hi, axis]]))[1:]
        inside = (wanted >= lo) & (wanted < hi)
        values[inside] = sums[wanted[inside] - lo]
        carry = sums[-1]
        release_pages(increments)
    return wanted.tolist(), values.tolist()


# --------------------------------------------------------------------------- one entry per place

def file_labels(survey: SurveyData) -> dict[str, str]:
    """Each loaded file by role, named as :func:`describe` names it (with what it was read as)."""
    manifest = survey.manifest
    labels = {}
    for role, entry in manifest.files.items():
        data = getattr(survey, role, None)
        labels[role] = describe(getattr(data, "source", None) or Path(entry.path), entry.format)
    for role in ("gnss", "odometer", "sleepers", "gauge"):
        labels.setdefault(role, describe(getattr(getattr(survey, role, None), "source", None), None))
    return labels


def check_survey(survey: SurveyData, nominal_gauge_m: float) -> tuple[SurveyData, list[Notice]]:
    """The recorded data checked against each other: the survey with the gauge outliers removed,
    and the notices; InputError naming the file for data that would give a wrong result. The
    clocks are checked by :func:`insrail.project.clocks.check_clocks`."""
    labels = file_labels(survey)
    notices = []
    if survey.odometer is not None and survey.gnss is not None:  # both roles are optional
        notices += check_odometer(survey.odometer, survey.gnss, labels["odometer"], labels["gnss"])
    if survey.odometer is not None:
        notices += check_odometer_direction(survey.imu, survey.odometer, labels["odometer"])
    gauge, gauge_notices = clean_gauge(survey.gauge, nominal_gauge_m, labels["gauge"])
    return replace(survey, gauge=gauge), notices + gauge_notices


def trolley_source(project_file: Path, survey_folder: Path, project_has_trolley: bool) -> Path:
    """The file whose ``[trolley]`` table applies: the project's when it has one, else survey.toml."""
    return project_file if project_has_trolley else survey_folder / MANIFEST_NAME

