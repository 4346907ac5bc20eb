"""The start on the design (survey.toml ``[start]``, thesis 5.3.1.1): where the trolley stands at the first
IMU record and how it is turned, from the design at the start station, for a survey whose first position
fix comes later (GNSS after a tunnel portal or a cutting, prism fixes after the first free station) or
never (a relative survey on the design).

The point is the track centre at the rail tops (the design's centreline, ``offset_m`` right of it and
``height_m`` above its profile), on the project's plane (the design's) and heights (normal heights, the
height model's zeta added as for prism fixes). Without a height model the fusion's ellipsoidal height
there is not known from the design: the height anomaly (tens of metres) is unknown, so the start's
vertical 1-sigma is :data:`UNKNOWN_ANOMALY_SIGMA_M` and the first GNSS heights set it (a notice says so). The trolley frame's heading is the design's true azimuth
(grid azimuth + meridian convergence; turned by pi for a trolley facing decreasing stations), its pitch
the profile's grade, its roll the design cant's cross slope (``asin(cant / rail_centre_spacing_m)``, the
trolley's left rail high for positive cant when it faces increasing stations).

Its 1-sigma, as stated to the filter: ``[start] sigma_m`` in each axis (the station marked on the track,
the track against its design); the heading's :data:`insrail.nav.startup.DESIGN_TRACK_SIGMA_RAD` with the
curvature times the along-track 1-sigma; the level's the same constant (the track's grade and cross-level
against the design's: a millimetre or two over the trolley's 1.5 m base). The filter is started on
exactly these; what it then reports absolutely depends on what aids it later: with GNSS or prism fixes
the smoother carries their accuracy back to the start (the stated 1-sigma shows where it does not); a
relative survey has none and reports no coordinates (``insrail.project.relative_survey``).

With local control the design lies on the local grid, whose relation to the CRS is fitted only after the
fusion: no start on the design then (refused, naming the key).
"""

from __future__ import annotations

import math

import numpy as np

from insrail.nav.rotation import euler_to_dcm
from insrail.notices import Phrase
from insrail.nav.startup import DESIGN_TRACK_SIGMA_RAD, KnownStart, StartupError

#: the vertical 1-sigma [m] of a start on the design without a height model: the height anomaly between the
#: design's normal heights and the fusion's ellipsoidal ones is unknown (it lies within about 100 m on earth)
UNKNOWN_ANOMALY_SIGMA_M = 100.0
#: the nominal gauge [m] from the reference rail's point to the track centre is half of (its error, a few
#: mm, is far below the start's 1-sigma)
NOMINAL_GAUGE_M = 1.435


def design_point(project, design, crs, start, height_fit=None):
    """(lat [rad], lon [rad], ellipsoidal height [m], true azimuth of increasing stations [rad], curvature
    [1/m], grade, cant [m]) of the design at survey.toml's ``start`` (:class:`insrail.io.survey.SurveyStart`).
    Raises :class:`StartupError` where the project cannot place it."""
    if design is None:
        raise StartupError(f"survey.toml [start] station_m = {start.station_m:g}: the start on the design needs "
                           "the project's design ([track] design)")
    if project.local_control is not None:
        raise StartupError(f"survey.toml [start] station_m = {start.station_m:g}: the design is on the local "
                           "control's grid, which is fitted to the CRS only after the fusion; leave out [start]")
    plan = design.horizontal
    if not float(plan.start_station_m) <= start.station_m <= float(plan.end_station_m):
        raise StartupError(f"survey.toml [start] station_m = {start.station_m:g}: outside the design "
                           f"({float(plan.start_station_m):.3f} - {float(plan.end_station_m):.3f} m)")
    east, north = (float(v) for v in plan.point_at(start.station_m, start.offset_m))
    lat, lon = (float(v) for v in crs.to_geodetic(east, north))
    elevation = float(design.vertical.elevation_at(start.station_m)) if design.vertical is not None else None
    if elevation is None:
        raise StartupError(f"survey.toml [start] station_m = {start.station_m:g}: the design has no profile, so "
                           "no height to start from")
    zeta = float(height_fit.zeta_m(east, north)) if height_fit is not None else 0.0
    azimuth = float(plan.azimuth_at(start.station_m)) + float(crs.meridian_convergence_rad(lat, lon))
    grade = float(design.vertical.grade_at(start.station_m))
    cant = float(design.cant.cant_at(start.station_m)) if design.cant is not None else 0.0
    return lat, lon, elevation + start.height_m + zeta, azimuth, float(plan.curvature_at(start.station_m)), grade, cant


def known_start(project, design, crs, start, trolley, height_fit=None) -> KnownStart:
    """The filter's :class:`KnownStart` at survey.toml's ``start`` on the design (see the module docstring);
    ``trolley``: the survey's :class:`insrail.io.survey.TrolleyGeometry` (the track centre from its
    reference rail's point)."""
    lat, lon, height, azimuth, curvature, grade, cant = design_point(project, design, crs, start, height_fit)
    if trolley.imu_to_reference_rail_m is None:
        raise StartupError("survey.toml [start]: the start on the design places the track centre from "
                           "trolley.imu_to_reference_rail_m, which is not given")
    ahead = 1.0 if start.facing_increasing else -1.0
    heading = azimuth if start.facing_increasing else azimuth + math.pi
    roll = ahead * math.asin(max(-1.0, min(1.0, cant / trolley.rail_centre_spacing_m)))
    pitch = ahead * math.atan(grade)
    # from the reference rail's point across to the track centre: + along the trolley's y axis from a left rail
    across = (0.5 if trolley.reference_rail == "left" else -0.5) * NOMINAL_GAUGE_M
    c_vb = euler_to_dcm(*trolley.mounting_rpy_rad)
    lever = np.asarray(trolley.imu_to_reference_rail_m, float) + c_vb.T @ np.array([0.0, across, 0.0])
    sigma = float(start.sigma_m)
    where = Phrase("the design at station {station_m:.3f} m{offset}{height}{facing}", {
        "station_m": start.station_m,
        "offset": Phrase(", {offset_m:+.3f} m right", {"offset_m": start.offset_m}) if start.offset_m else "",
        "height": Phrase(", {height_m:+.3f} m above", {"height_m": start.height_m}) if start.height_m else "",
        "facing": "" if start.facing_increasing else Phrase(", facing decreasing stations")})
    vertical = sigma if height_fit is not None else UNKNOWN_ANOMALY_SIGMA_M
    return KnownStart(lat, lon, height, lever, np.array([sigma, sigma, vertical]), (roll, pitch, heading),
                      DESIGN_TRACK_SIGMA_RAD, math.hypot(DESIGN_TRACK_SIGMA_RAD, curvature * sigma), where)

