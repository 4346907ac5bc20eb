"""What the results of a relative survey (``insrail.nav.relative``: no GNSS, no prism fixes) hold.

Its trajectory is the track's shape in a frame of its own (the start's point and azimuth), drifting
with the IMU over the run. Gauge, cant, twist and the chord checks are relative quantities and are
reported; the deviations from the design (and so nothing that reads them as the rail's place on the
line) are not: the sleeper table's deviation columns are left empty, and so are its adjustment amounts
(a fastener amount moves the rail towards the design by its deviation, which here holds the IMU's drift:
150 m lag sigmas of several mm; ``summary.toml [adjustment] withheld`` says why). The rail coordinates stay in the
table, named in ``summary.toml [relative]`` as the survey's own frame, for the plots' shape.

A chord check is assessed per section by the one rule of ``insrail.project.assessable`` (:func:`decides`:
three of its stated 1-sigma within its limit; the 5 m lag's for the 30 m/5 m check and the 10 m versine,
the 150 m lag's for the 300 m/150 m check), which also leaves its values and exceedances out where it is
not. Here a warning names the check and the sections; ``[relative.sections]`` gives each section's figures
and verdicts (a section with no figure, too short for its lag, not assessed).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from insrail.notices import Notice, Phrase
from insrail.project.assessable import RESOLVE_SIGMAS, check_limit_m, decides, section_sigma_m
from insrail.track.adjustment import Adjustment

CHORD_KINDS = ("versine", "differential_versine")


def _chord_sigmas(profile, quality) -> dict[str, tuple[object, np.ndarray]]:
    """Per chord check of ``profile`` with a stated figure: (the check, the larger of its directions' stated
    1-sigma per section; ``assessable.section_sigma_m``)."""
    found = {}
    for check in profile.checks:
        if check.kind not in CHORD_KINDS:
            continue
        sigmas = [section_sigma_m(check, quality, d) for d in (check.directions or ("lateral", "vertical"))]
        if any(s is None for s in sigmas):
            continue
        found[check.name] = (check, np.max(sigmas, axis=0))
    return found


def chord_verdicts(profile, quality) -> dict[str, np.ndarray]:
    """Per chord check of ``profile`` with a stated figure: per section of ``quality`` (``SectionQuality``)
    whether it can be assessed (``assessable.decides``)."""
    return {name: decides(sigma, check_limit_m(check)) for name, (check, sigma) in _chord_sigmas(profile, quality).items()}


#: a relative survey's warning per chord check (:func:`relative_notices`); a section of such runs says it
#: itself, for its own rows (``insrail.project.section``: the runs' copies are left out)
NOTICE = ("relative survey: the {check} check cannot be assessed in {count} of {sections} sections, where the stated "
          "1-sigma of its error exceeds 1/{sigmas:g} of its {limit_mm:g} mm limit: {where}; its values and exceedances "
          "there are left out")


def relative_notices(profile, quality) -> list[Notice]:
    """A warning for each chord check that cannot be assessed in some sections (see the module docstring)."""
    notices = []
    for name, (check, sigma) in _chord_sigmas(profile, quality).items():
        assessed = decides(sigma, check_limit_m(check))
        if assessed.all():
            continue
        where = [Phrase("{from_m:.0f}-{to_m:.0f} m ({sigma_mm:.2f} mm)", {"from_m": a, "to_m": b, "sigma_mm": 1e3 * s})
                 if np.isfinite(s) else Phrase("{from_m:.0f}-{to_m:.0f} m (too short for its lag)", {"from_m": a, "to_m": b})
                 for a, b, s, ok in zip(quality.station_from_m, quality.station_to_m, sigma, assessed) if not ok]
        notices.append(Notice("track", NOTICE, station_m=float(quality.station_from_m[0]),
                              fields={"check": name, "count": int((~assessed).sum()), "sections": len(assessed),
                                      "sigmas": RESOLVE_SIGMAS, "limit_mm": 1e3 * check_limit_m(check), "where": where}))
    return notices


def absolute_sigma_m(frame, length_m: float) -> float:
    """The 1-sigma [m] of a relative survey's position against the line ``length_m`` from a start on the design
    (survey.toml ``[start]``): the start point's and the azimuth's times the distance (the IMU's drift comes on
    top); NaN for a frame not placed on the line."""
    if not frame.sigma_m:
        return float("nan")
    return float(np.hypot(frame.sigma_m, length_m * frame.sigma_azimuth_rad))


def relative_section(frame, profile, quality) -> dict:
    """summary.toml's ``[relative]``: the frame, what is and is not measured, and per section the stated
    1-sigma of the chord checks' errors [mm] and whether each chord check is assessed there. A frame started
    on the design (survey.toml ``[start]``) adds ``[relative.absolute]``: the start's 1-sigma and the
    position's at the run's end (:func:`absolute_sigma_m`), and why nothing absolute is reported: at its
    best, at the start point itself, a deviation from the design would hold the start's 1-sigma, tens of
    times the millimetre an amount for the crew is given to."""
    verdicts = chord_verdicts(profile, quality)
    sections = []
    for i in range(len(quality.station_from_m)):
        row = {"station_from_m": float(quality.station_from_m[i]), "station_to_m": float(quality.station_to_m[i])}
        for name in ("sigma_lag5_lateral_m", "sigma_lag5_vertical_m", "sigma_lag150_lateral_m",
                     "sigma_lag150_vertical_m", "sigma_cross_level_m"):
            value = float(getattr(quality, name)[i])
            row[name[:-2] + "_mm"] = round(1e3 * value, 3) if np.isfinite(value) else -1.0
        row["assessed"] = [name for name, ok in verdicts.items() if ok[i]]
        row["not_assessed"] = [name for name, ok in verdicts.items() if not ok[i]]
        sections.append(row)
    section = {"frame": frame.source.to_dict(),  # a phrase's table (insrail.notices): the report says it in its language
               "measured": "gauge, cant, twist and the chord checks (versines, short and long wave where assessed)",
               "not_measured": "coordinates on the line and deviations from the design (the sleeper table's deviation "
                               "columns are empty; its rail coordinates are in the survey's own frame, which drifts "
                               "with the IMU)",
               "sections": sections}
    if frame.sigma_m and len(quality.station_from_m):
        length = float(quality.station_to_m[-1] - quality.station_from_m[0])
        end = absolute_sigma_m(frame, length)
        section["absolute"] = {
            "start_sigma_mm": round(1e3 * frame.sigma_m, 3),
            "azimuth_sigma_deg": round(float(np.degrees(frame.sigma_azimuth_rad)), 4),
            "end_sigma_mm": round(1e3 * end, 1), "length_m": round(length, 1),
            "reported": Phrase("nothing absolute: {why}", {"why": Phrase(ABSOLUTE_NOT_REPORTED, {
                "start_mm": 1e3 * frame.sigma_m, "end_mm": 1e3 * end, "length_m": length})}).to_dict()}
    return section


#: why a relative survey started on the design reports no coordinates or deviations (summary.toml
#: ``[relative.absolute] reported`` and its notice)
ABSOLUTE_NOT_REPORTED = ("the trajectory starts on the design with a 1-sigma of {start_mm:.0f} mm and reaches "
                         "{end_mm:.0f} mm at {length_m:.0f} m from the azimuth's alone (the IMU's drift on top), "
                         "so no deviation from the design nor any adjustment amount is given")


def absolute_notice(frame, quality) -> list[Notice]:
    """The warning of a relative survey started on the design: what its start's 1-sigma allows (nothing
    absolute; :func:`relative_section`)."""
    if not frame.sigma_m or not len(quality.station_from_m):
        return []
    length = float(quality.station_to_m[-1] - quality.station_from_m[0])
    return [Notice("track", "relative survey started on {frame}: {why}", station_m=float(quality.station_from_m[0]),
                   fields={"frame": frame.source,
                           "why": Phrase(ABSOLUTE_NOT_REPORTED, {"start_mm": 1e3 * frame.sigma_m,
                                                                 "end_mm": 1e3 * absolute_sigma_m(frame, length),
                                                                 "length_m": length})})]


def without_deviations(table):
    """The sleeper table as a relative survey writes it: no deviations from the design."""
    return replace(table, lateral_deviation_m=np.full_like(table.lateral_deviation_m, np.nan),
                   vertical_deviation_m=np.full_like(table.vertical_deviation_m, np.nan))


#: why a relative survey gives no adjustment amounts (summary.toml ``[adjustment] withheld``; the reports
#: and ``insrail process`` print it in the report's language)
AMOUNTS_WITHHELD = ("relative survey: no adjustment amounts, they would move the rails by the IMU's drift "
                    "against the design; the crew needs a survey with GNSS or prism fixes")


def no_amounts(sleepers: int, fastener: str):
    """The adjustment of a relative survey: no amounts (NaN) at any of its ``sleepers``, none unresolved."""
    empty = np.zeros((sleepers, 2), dtype=bool)
    return Adjustment(lateral_m=np.full((sleepers, 2), np.nan), vertical_m=np.full((sleepers, 2), np.nan),
                      unresolved_lateral=empty, unresolved_vertical=empty.copy(), fastener=fastener,
                      reason_lateral=np.zeros((sleepers, 2), dtype=np.uint8),
                      reason_vertical=np.zeros((sleepers, 2), dtype=np.uint8))


def withheld_adjustment_section(adjustment) -> dict:
    """summary.toml's ``[adjustment]`` of a relative survey: the fastener and why there are no amounts."""
    return {"fastener": adjustment.fastener, "withheld": AMOUNTS_WITHHELD}
