"""The design alignment's azimuth at a position, for the fusion's start (``insrail.nav.startup``).

The fusion knows geodetic positions and true north; the design lives on the project's plane
(grid north). A position is projected with the project's CRS, located on the design (station,
offset) and the design's tangent there turned from grid to true north by the meridian convergence
(true azimuth = grid azimuth + gamma, ``insrail.geodesy.crs``). With local control the design is on
the local grid, whose rotation against the CRS is fitted only after the fusion: no design azimuth
then (the start uses the track alone); nor for an IMU that gyrocompasses, which needs none (so the
design is an input of the fusion, and of its cache key, only where it can change the start).
"""

from __future__ import annotations

import math

from insrail.nav.startup import DESIGN_TRACK_SIGMA_RAD, finds_north
from insrail.notices import Phrase


def uses_design(project, profile) -> bool:
    """Whether the fusion of a survey with ``profile`` may take its start heading from the project's
    design (then the design is one of the fusion's inputs): a design, no local control, and an IMU
    that cannot gyrocompass."""
    return (project.design is not None and project.local_control is None
            and not finds_north(profile, project.fusion.min_static_s))


def design_azimuth_for(project, design, profile):
    """``design_azimuth(lat, lon) -> (true azimuth [rad], curvature [1/m], station [m], offset [m])``
    or None off the design; None where :func:`uses_design` says no."""
    if design is None or not uses_design(project, profile):
        return None
    crs, plan = project.crs, design.horizontal

    def design_azimuth(lat_rad: float, lon_rad: float):
        east, north = crs.to_plane(lat_rad, lon_rad)
        station, offset = plan.station_offset(float(east), float(north))
        station, offset = float(station), float(offset)
        if not math.isfinite(station):
            return None
        grid = float(plan.azimuth_at(station))
        gamma = float(crs.meridian_convergence_rad(lat_rad, lon_rad))
        return grid + gamma, float(plan.curvature_at(station)), station, offset

    return design_azimuth


def relative_frame(project, design, crs, start=None, trolley=None, height_fit=None):
    """The start frame of a relative survey (``insrail.nav.relative.RelativeFrame``): with survey.toml's
    ``start`` (:class:`insrail.io.survey.SurveyStart`) the trolley's track centre on the design there
    (``insrail.project.design_start``: point, azimuth of the trolley's facing, its 1-sigma); else the
    design's point, height and true azimuth at the project's start station (``track.start_station_m``,
    else the design's first station) where the project has a design (not on a local grid: its rotation is
    fitted after the fusion), else a local frame on the CRS's central meridian, its latitude from the earth
    rate."""
    from insrail.nav.relative import RelativeFrame  # the fusion's type; imported where a relative survey needs it

    if start is not None:
        from insrail.project.design_start import known_start

        known = known_start(project, design, crs, start, trolley, height_fit)
        return RelativeFrame(known.lat_rad, known.lon_rad, known.height_m, known.rpy_v_rad[2], known.sigma_heading_rad,
                             known.source, lever_arm_m=known.lever_arm_m, sigma_m=float(start.sigma_m))
    if design is None or project.local_control is not None:
        return RelativeFrame.local(math.radians(float(crs.central_meridian_deg or 0.0)), on_meridian=True)
    plan = design.horizontal
    station = project.start_station_m if project.start_station_m is not None else float(plan.start_station_m)
    station = min(max(station, float(plan.start_station_m)), float(plan.end_station_m))
    east, north = plan.point_at(station)
    lat, lon = (float(v) for v in crs.to_geodetic(float(east), float(north)))
    height = float(design.vertical.elevation_at(station)) if design.vertical is not None else 0.0
    azimuth = float(plan.azimuth_at(station)) + float(crs.meridian_convergence_rad(lat, lon))
    return RelativeFrame(lat, lon, height, azimuth, DESIGN_TRACK_SIGMA_RAD,
                         Phrase("the design at station {station_m:.3f} m", {"station_m": station}))
