"""What the results of a relative survey (``insrail.nav.relative``: no GNSS, no prism fixes) hold.

Its trajectory is the track's shape in a frame of its own (the start's point and azimuth), drifting
with the IMU over the run. Gauge, cant, twist and the chord checks are relative quantities and are
reported; the deviations from the design (and so nothing that reads them as the rail's place on the
line) are not: the sleeper table's deviation columns are left empty, and so are its adjustment amounts
(a fastener amount moves the rail towards the design by its deviation, which here holds the IMU's drift:
150 m lag sigmas of several mm; ``summary.toml [adjustment] withheld`` says why). The rail coordinates stay in the
table, named in ``summary.toml [relative]`` as the survey's own frame, for the plots' shape.

A chord check can be assessed in a section only where the stated 1-sigma of its error (the 5 m lag's
for chords up to :data:`SHORT_CHORD_M`, the 150 m lag's for longer ones: ``insrail.quality``) is
small beside its limit: three of them within it (:data:`SIGMAS_IN_LIMIT`). Elsewhere a warning names
the check and the sections; ``[relative.sections]`` gives each section's figures and verdicts.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from insrail.notices import Notice, Phrase
from insrail.track.adjustment import Adjustment

#: a chord check up to this chord [m] has the 5 m lag's error, a longer one the 150 m lag's
SHORT_CHORD_M = 30.0
#: a check is assessed where its limit holds this many 1-sigma of its stated error
SIGMAS_IN_LIMIT = 3.0
CHORD_KINDS = ("versine", "differential_versine")


def _limit_m(check) -> float:
    return float(min(abs(check.lower), abs(check.upper)))


def _lag_figure(check, quality, direction: str) -> np.ndarray:
    lag = "lag5" if (check.chord_m or 0.0) <= SHORT_CHORD_M else "lag150"
    return getattr(quality, f"sigma_{lag}_{direction}_m")


def chord_verdicts(profile, quality) -> dict[str, np.ndarray]:
    """Per chord check of ``profile``: per section of ``quality`` (``SectionQuality``) whether it can be
    assessed (both of its directions' stated 1-sigma within its limit / :data:`SIGMAS_IN_LIMIT`)."""
    verdicts = {}
    for check in profile.checks:
        if check.kind not in CHORD_KINDS:
            continue
        sigma = np.max([_lag_figure(check, quality, d) for d in (check.directions or ("lateral", "vertical"))], axis=0)
        verdicts[check.name] = np.isfinite(sigma) & (SIGMAS_IN_LIMIT * sigma <= _limit_m(check))
    return verdicts


def relative_notices(profile, quality) -> list[Notice]:
    """A warning for each chord check that cannot be assessed in some sections (see the module docstring)."""
    notices = []
    for check in profile.checks:
        if check.kind not in CHORD_KINDS:
            continue
        assessed = chord_verdicts(profile, quality)[check.name]
        if assessed.all():
            continue
        sigma = np.max([_lag_figure(check, quality, d) for d in (check.directions or ("lateral", "vertical"))], axis=0)
        where = [Phrase("{from_m:.0f}-{to_m:.0f} m ({sigma_mm:.2f} mm)", {"from_m": a, "to_m": b, "sigma_mm": 1e3 * s})
                 if np.isfinite(s) else Phrase("{from_m:.0f}-{to_m:.0f} m (too short for its lag)", {"from_m": a, "to_m": b})
                 for a, b, s, ok in zip(quality.station_from_m, quality.station_to_m, sigma, assessed) if not ok]
        notices.append(Notice("track", "relative survey: the {check} check cannot be assessed in {count} of {sections} "
                              "sections, where the stated 1-sigma of its error exceeds 1/{sigmas:g} of its {limit_mm:g} mm "
                              "limit: {where}; its exceedances there are not measured ones",
                              station_m=float(quality.station_from_m[0]),
                              fields={"check": check.name, "count": int((~assessed).sum()), "sections": len(assessed),
                                      "sigmas": SIGMAS_IN_LIMIT, "limit_mm": 1e3 * _limit_m(check), "where": where}))
    return notices


def relative_section(frame: Phrase, profile, quality) -> dict:
    """summary.toml's ``[relative]``: the frame, what is and is not measured, and per section the stated
    1-sigma of the chord checks' errors [mm] and whether each chord check is assessed there."""
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
    return {"frame": frame.to_dict(),  # a phrase's table (insrail.notices): the report says it in its language
            "measured": "gauge, cant, twist and the chord checks (versines, short and long wave where assessed)",
            "not_measured": "coordinates on the line and deviations from the design (the sleeper table's deviation "
                            "columns are empty; its rail coordinates are in the survey's own frame, which drifts "
                            "with the IMU)",
            "sections": sections}


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
