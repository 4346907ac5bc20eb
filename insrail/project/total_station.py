"""Raw total-station observations of a survey (``[files.total_station]`` with ``[files.cpiii]``) as
prism fixes: every set-up resected on its CPIII points, the prism pointings placed from it.

Per set-up (:mod:`insrail.geodesy.free_station`): the station's plan position, height and circle
orientation from its CPIII pointings (at least three), each point checked by leave-one-out; a
point whose residual fails the test against its own 1-sigma (the pointing's precision through the
fit, scaled by the set-up's residuals; significance 1e-3 in plan and in height) is named in a notice
and left out, one at a time while three remain. A set-up that cannot be resected (fewer than three
known points, or points that disagree with no majority) is an error naming the file and the set-up's
first line. Each
prism pointing then becomes a prism fix (time, E, N, H; ``point_id`` the set-up), with the
standard deviation

    sigma = max(MIN_SIGMA_M, hypot(station residual RMS (plan or height, the larger),
                                   ANGLE_SIGMA_RAD * horizontal distance, DISTANCE_SIGMA_M))

the set-up's own fit on the CPIII points plus the pointing's precision at its distance. A set-up whose
fit is worse than a total station on CPIII points can give (residual RMS over :data:`MAX_SETUP_RMS_M`)
is an error naming the file and the set-up, with the likely cause when the numbers show it (CPIII
coordinates in millimetres, zenith angles in degrees read as gon): such a set-up fixes nothing, and
fixes with a 1-sigma of metres would pass unnoticed. The fixes
join the survey's ``[files.prism]`` fixes, if it has any, in time order.

A survey without GNSS is held by its fixes alone: where its run goes on beyond the first or the last
fix, the INS and the odometer carry the position on their own and its 1-sigma grows with the distance
(nav grade, fixes every 60 m: 0.8 mm between them, about 1.3, 2.2 and 3.1 mm over the three 60 m beyond
the last, docs/accuracy.md). That stretch is named in a notice (:func:`gnss_free_run_notices`);
sleepers.csv and quality.csv carry its 1-sigma. Between the fixes the stated 1-sigma is the error's
(the trolley's play is in the fusion's process noise, docs/accuracy.md).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from insrail.geodesy.free_station import (
    ANGLE_SIGMA_RAD,
    DISTANCE_SIGMA_M,
    SIGNIFICANCE,
    PolarObservations,
    resect,
)
from insrail.io.errors import InputError
from insrail.io.survey import SurveyData
from insrail.io.total_station import PRISM_TARGET
from insrail.io.types import ControlPoints, PrismObservations, TotalStationObservations
from insrail.notices import Notice, Phrase

MIN_SIGMA_M = 0.0005
#: The worst residual RMS a set-up on CPIII points can have: the pointing gives 0.5 mm at 100 m, the
#: CPIII network about 1 mm, and a point that is off is left out by the leave-one-out test; 25 mm
#: is 25 times that, and past it the set-up is not measuring what its file says.
MAX_SETUP_RMS_M = 0.025
#: A run beyond the first or last prism fix shorter than this is the fix's own stop, not a stretch.
UNCOVERED_RUN_M = 1.0


def _polar(observations: TotalStationObservations, rows: np.ndarray) -> PolarObservations:
    return PolarObservations(tuple(observations.target[rows]), observations.hz_rad[rows],
                             observations.zenith_rad[rows], observations.slope_m[rows])


def _length(metres: float) -> str:
    return f"{metres:.1f} m" if metres >= 1.0 else f"{1e3 * metres:.0f} mm"


def _unit_hint(observations: PolarObservations, known_enh_m: np.ndarray) -> Phrase:
    """What the numbers of a set-up that does not fit show: units mixed up, or points that are not those named."""
    level_gon = 200.0 / np.pi * np.median(observations.zenith_rad)
    if abs(level_gon - 90.0) < 5.0:  # CPIII points lie near the instrument's height: 100 gon, 90 degrees
        return Phrase("its zenith angles are about {level_gon:.0f} where points at the instrument's height read 100 gon: "
                      "angles in degrees read as gon? (set the reader option angle_unit = \"deg\")", {"level_gon": level_gon})
    horizontal = observations.slope_m * np.sin(observations.zenith_rad)
    measured = np.column_stack([horizontal * np.sin(observations.hz_rad), horizontal * np.cos(observations.hz_rad)])
    ratio = np.median(_spacings(known_enh_m[:, :2])) / np.median(_spacings(measured))
    if ratio > 100.0:
        return Phrase("the CPIII points lie {ratio:.0f} times farther apart than measured: coordinates in millimetres? "
                      "(the CPIII file holds metres)", {"ratio": ratio})
    if ratio < 0.01:
        return Phrase("the CPIII points lie {ratio:.0f} times closer together than measured: distances in millimetres?",
                      {"ratio": 1 / ratio})
    return Phrase("check that the CPIII file and the observations belong together (point names, units)")


def _spacings(plan_m: np.ndarray) -> np.ndarray:
    """The plan distances between every pair of points."""
    first, second = np.triu_indices(len(plan_m), 1)
    return np.hypot(*(plan_m[first] - plan_m[second]).T)


def prism_fixes_from_observations(observations: TotalStationObservations, points: ControlPoints,
                                  significance: float = SIGNIFICANCE) -> tuple[PrismObservations, list[Notice]]:
    """The prism fixes of every set-up (module docstring) and the notices of CPIII points left out."""
    source = observations.source or "total-station observations"
    known = {str(p): k for k, p in enumerate(points.point_id)}
    coordinates = np.column_stack([points.east_m, points.north_m, points.height_m])
    order = list(dict.fromkeys(observations.setup))
    fixes, sigma, setup_of_fix, notices = [], [], [], []
    for setup in order:
        rows = np.flatnonzero(observations.setup == setup)
        line = int(observations.line[rows[0]])
        on_points = rows[observations.target[rows] != PRISM_TARGET]
        on_prism = rows[observations.target[rows] == PRISM_TARGET]
        unknown = [str(t) for t in observations.target[on_points] if str(t) not in known]
        if unknown:
            row = on_points[[str(t) for t in observations.target[on_points]].index(unknown[0])]
            raise InputError(source, int(observations.line[row]), "set-up {setup}: CPIII point {point} is not "
                             "in the CPIII file {file}", fields={"setup": setup, "point": unknown[0],
                                                                 "file": points.source or ""})
        try:
            station = resect(_polar(observations, on_points),
                             coordinates[[known[str(t)] for t in observations.target[on_points]]], significance)
        except ValueError as error:
            raise InputError(source, line, "set-up {setup}: {error}", fields={"setup": setup, "error": error}) from None
        fit = max(station.rms_plan_m, station.rms_height_m)
        if not fit <= MAX_SETUP_RMS_M:
            raise InputError(source, line, (
                "set-up {setup}: the CPIII points fit the observations to {fit} RMS, more than the "
                "{max_setup_rms_mm:.0f} mm a total station gives: {hint}"), fields={
                "setup": setup, "fit": _length(fit), "max_setup_rms_mm": 1e3 * MAX_SETUP_RMS_M,
                "hint": _unit_hint(_polar(observations, on_points), coordinates[[known[str(t)] for t in
                                                                                  observations.target[on_points]]])})
        for point in station.points:
            if not point.used:
                notices.append(Notice(
                    "total station", "set-up {setup} (line {line}): CPIII point {point} does not fit (leave-one-out "
                    "residual {plan_mm:.1f} mm in plan, {height_mm:.1f} mm in height, {ratio:.1f} times the limit of the "
                    "test against its 1-sigma): left out; check its coordinates",
                    file=str(source), time_s=float(observations.time_s[rows[0]]),
                    fields={"setup": setup, "line": line, "point": point.name,
                            "plan_mm": 1e3 * point.left_out_residual_plan_m,
                            "height_mm": 1e3 * point.left_out_residual_height_m, "ratio": point.test_ratio}))
        if not on_prism.size:
            continue
        placed = station.place(_polar(observations, on_prism))
        distance = observations.slope_m[on_prism] * np.sin(observations.zenith_rad[on_prism])
        sigma.append(np.maximum(MIN_SIGMA_M, np.sqrt(fit**2 + (ANGLE_SIGMA_RAD * distance) ** 2 + DISTANCE_SIGMA_M**2)))
        fixes.append(np.column_stack([observations.time_s[on_prism], placed]))
        setup_of_fix += [setup] * on_prism.size
    if not fixes:
        raise InputError(source, None, "no prism pointing (target 'prism'): the observations fix no trolley position")
    table = np.concatenate(fixes)
    sigma = np.concatenate(sigma)
    order_in_time = np.argsort(table[:, 0], kind="stable")
    table, sigma = table[order_in_time], sigma[order_in_time]
    return PrismObservations(time_s=table[:, 0], east_m=table[:, 1], north_m=table[:, 2], height_m=table[:, 3],
                             sigma_m=sigma, point_id=np.array(setup_of_fix)[order_in_time], source=observations.source), notices


def with_total_station_fixes(survey: SurveyData) -> tuple[SurveyData, list[Notice]]:
    """The survey with its raw total-station observations placed as prism fixes (joined with its own
    prism fixes); unchanged without observations."""
    if survey.total_station is None or survey.cpiii is None:
        return survey, []
    fixes, notices = prism_fixes_from_observations(survey.total_station, survey.cpiii)
    if survey.prism is not None and len(survey.prism):
        own = survey.prism
        ids = own.point_id if len(own.point_id) else np.full(len(own), "")
        merged = {name: np.concatenate([getattr(own, name), getattr(fixes, name)])
                  for name in ("time_s", "east_m", "north_m", "height_m", "sigma_m")}
        merged["point_id"] = np.concatenate([ids.astype(str), fixes.point_id.astype(str)])
        order = np.argsort(merged["time_s"], kind="stable")
        fixes = PrismObservations(**{k: v[order] for k, v in merged.items()}, source=own.source)
    return replace(survey, prism=fixes), notices


def gnss_free_run_notices(survey: SurveyData) -> list[Notice]:
    """For a survey held by prism fixes without any GNSS (module docstring): a notice for each end whose
    run (odometer distance) goes on more than UNCOVERED_RUN_M beyond its first or last fix; none with
    GNSS, without fixes or without an odometer."""
    if survey.prism is None or not len(survey.prism) or survey.odometer is None or survey.gnss is not None:
        return []
    first, last = float(np.min(survey.prism.time_s)), float(np.max(survey.prism.time_s))
    notices = []
    odometer = survey.odometer
    at_first, at_last = np.interp([first, last], odometer.time_s, odometer.distance_m)
    for run, where, time_s in ((at_first - odometer.distance_m.min(), Phrase("before its first"), first),
                               (odometer.distance_m.max() - at_last, Phrase("beyond its last"), last)):
        if run > UNCOVERED_RUN_M:
            notices.append(Notice("total station", "the run goes on {run_m:.0f} m {where} prism fix (at {time_s:.1f} s) "
                                  "with no GNSS: the sleepers there rest on the INS and the odometer alone, their "
                                  "position 1-sigma growing with the distance (sleepers.csv, quality.csv); start and "
                                  "end a survey without GNSS on a fix", time_s=time_s,
                                  fields={"run_m": run, "where": where, "time_s": time_s}))
    return notices
