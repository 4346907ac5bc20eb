"""The project settings as the forms name them: the core reports a problem with its key path in
project.toml ("geodesy.height.benchmarks: file not found: x.txt"); a form shows it beside the
field, in the field's words ("Benchmarks file: file not found: x.txt")."""

from __future__ import annotations

import re

#: project.toml key path -> the label of its field in the wizard and the settings editor.
FIELD_LABELS = {
    "project.name": "Project name",
    "project.description": "Description",
    "geodesy.crs": "Coordinate system",
    "geodesy.crs.ellipsoid": "Ellipsoid",
    "geodesy.crs.central_meridian_deg": "Central meridian",
    "geodesy.crs.latitude_of_origin_deg": "Latitude of origin",
    "geodesy.crs.scale_factor": "Scale factor",
    "geodesy.crs.false_easting_m": "False easting",
    "geodesy.crs.false_northing_m": "False northing",
    "geodesy.crs.projection_height_m": "Projection height",
    "geodesy.crs.projection_height_convention": "Projection height applied as",
    "geodesy.crs.mean_radius_m": "Mean earth radius",
    "geodesy.height.benchmarks": "Benchmarks file",
    "geodesy.height.model": "Height-anomaly model",
    "geodesy.height.geoid_grid": "Geoid grid",
    "trolley": "Trolley geometry",
    "trolley.imu_to_antenna_m": "IMU → GNSS antenna",
    "trolley.imu_to_odometer_m": "IMU → odometer wheel contact",
    "trolley.imu_to_reference_rail_m": "IMU → reference rail gauge point",
    "trolley.imu_to_sleeper_detector_m": "IMU → sleeper detector",
    "trolley.imu_to_prism_m": "IMU → prism",
    "trolley.mounting_rpy_deg": "Mounting roll, pitch, heading",
    "trolley.reference_rail": "Reference rail",
    "trolley.rail_centre_spacing_m": "Rail centre spacing",
    "processing": "Processing",
    "processing.imu_profile": "IMU profile",
    "processing.use_gnss_velocity": "Use the GNSS velocity",
    "processing.use_odometer": "Use the odometer",
    "processing.use_nhc": "Non-holonomic constraints (NHC)",
    "processing.use_zupt": "Zero-velocity updates at stops (ZUPT)",
    "processing.smoother": "RTS smoother",
    "processing.update_rate_hz": "Filter update rate (Hz)",
    "processing.gnss_sigma_scale": "GNSS sigma scale",
    "processing.gnss_sigma_floor_m": "GNSS sigma floor (m)",
    "processing.gnss_correlated_tau_s": "GNSS error correlation time (s)",
    "processing.odometer_sigma_mps": "Odometer sigma (m/s)",
    "processing.nhc_sigma_mps": "NHC sigma (m/s)",
    "processing.zupt_sigma_mps": "ZUPT sigma (m/s)",
    "processing.min_static_s": "Shortest stop for a ZUPT (s)",
    "track": "Track",
    "geodesy": "Geodesy",
    "geodesy.control_points": "Control points",
    "report": "Report",
    "track.design": "Design alignment",
    "track.start_station_m": "Start station",
    "track.first_sleeper_number": "First sleeper number",
    "track.tolerance_profile": "Tolerance profile",
    "track.fastener": "Fastener type",
    "surveys": "Surveys",
    "surveys.name": "Survey name",
    "surveys.folder": "Survey folder",
}
_PROBLEM = re.compile(r"^(?P<key>[A-Za-z0-9_.\[\]]+): (?P<message>.*)$", re.DOTALL)
_INDEX = re.compile(r"\[\d+\]")


def split_problem(problem: str) -> tuple[str, str]:
    """(key path with list indices removed, message) of one of the core's problems ("" key: none)."""
    match = _PROBLEM.match(problem)
    if match is None:
        return "", problem
    return _INDEX.sub("", match.group("key")), match.group("message")


def field_label(key: str) -> str:
    """The words for a key path: its own label, else the nearest enclosing one's with the rest
    in words ("processing.use_nhc" -> "Processing: use nhc")."""
    if key in FIELD_LABELS:
        return FIELD_LABELS[key]
    parts = key.split(".")
    for cut in range(len(parts) - 1, 0, -1):
        head = ".".join(parts[:cut])
        if head in FIELD_LABELS:
            return f"{FIELD_LABELS[head]}: {' '.join(parts[cut:]).replace('_', ' ')}"
    return key.replace(".", ": ").replace("_", " ").capitalize()


def in_words(problem: str) -> str:
    """A problem of the core with its key path replaced by the field's label."""
    key, message = split_problem(problem)
    return f"{field_label(key)}: {message}" if key else message
