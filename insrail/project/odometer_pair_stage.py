"""A survey's second odometer (``[files.odometer_right]``), checked and compared with the first before
the fusion: the checks the first odometer has (scale against GNSS, direction, clock) and the wheels'
spacing across the track, then :func:`insrail.nav.odometer_pair.compare_odometers`: a slipping wheel's
stretches left out (the other wheel bridges them), each named in a notice and, once the track is
reconstructed, placed on its chainage as a ``note`` event (:func:`slip_events`)."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from insrail.io.errors import InputError
from insrail.io.events import Event
from insrail.io.survey import MANIFEST_NAME, SurveyData
from insrail.nav.odometer_pair import OdometerPair, compare_odometers
from insrail.nav.rotation import euler_to_dcm
from insrail.notices import Notice
from insrail.project.clocks import MAX_OFFSET_S, NOTICE_OFFSET_S, estimate_odometer_offset
from insrail.project.plausibility import check_odometer, check_odometer_direction, read_as
from insrail.track.events import TrackEvent, place_event_on
from insrail.track.sleeper_table import TrackReconstruction

#: how far [m] the wheels' lateral spacing may lie from the rail-centre spacing: each runs somewhere
#: on its rail's head (about 0.07 m wide)
MAX_SPACING_OFFSET_M = 0.15
#: a relative scale of the two wheels beyond this is not wear but a wrong pulse length or wheel
MAX_RELATIVE_SCALE = 0.02


def with_odometer_pair(survey: SurveyData, labels: dict[str, str]) -> tuple[SurveyData, list[Notice], dict | None]:
    """The survey with its two odometers ready for the fusion (the right one on the left one's scale,
    slipping stretches left out), the notices, and the ``[fusion.odometer_pair]`` table; unchanged
    (and None) without a second odometer. ``labels``: the files by role
    (:func:`insrail.project.plausibility.file_labels`). InputError naming the file or survey.toml
    for a second odometer that cannot be right."""
    right = survey.odometer_right
    if right is None or survey.odometer is None:
        return survey, [], None
    label, left_label = labels["odometer_right"], labels["odometer"]
    path = right.source or Path(label)
    trolley = survey.manifest.trolley
    if trolley.imu_to_odometer_right_m is None:  # a project's [trolley] in force that leaves it out
        raise InputError(survey.folder / MANIFEST_NAME, None, "trolley.imu_to_odometer_right_m: missing, and "
                         "files.odometer_right is given (the second wheel's contact point: 3 numbers [m], IMU body "
                         "frame FRD; in project.toml's [trolley] when the project gives one)")
    c_vb = euler_to_dcm(*trolley.mounting_rpy_rad)
    lever_left, lever_right = trolley.lever_arm_m("imu_to_odometer_m"), trolley.lever_arm_m("imu_to_odometer_right_m")
    spacing = float((c_vb @ (lever_right - lever_left))[1])
    if abs(abs(spacing) - trolley.rail_centre_spacing_m) > MAX_SPACING_OFFSET_M:
        raise InputError(survey.folder / MANIFEST_NAME, None,
                         "trolley.imu_to_odometer_right_m: the two odometer wheels lie {spacing:.3f} m apart across "
                         "the track (the lever arms' y, in the trolley frame); on the two rails they run about "
                         "trolley.rail_centre_spacing_m = {rail_centre_spacing_m:g} m apart (within "
                         "{max_spacing_offset_m:g} m)", fields={"spacing": abs(spacing), "rail_centre_spacing_m": trolley.rail_centre_spacing_m, "max_spacing_offset_m": MAX_SPACING_OFFSET_M})
    notices: list[Notice] = []
    if survey.gnss is not None:
        notices += check_odometer(right, survey.gnss, label, labels["gnss"])
    notices += check_odometer_direction(survey.imu, right, label)
    offset = estimate_odometer_offset(survey.imu, right, trolley.mounting_rpy_rad)
    if offset is not None and abs(offset.offset_s) >= NOTICE_OFFSET_S:
        where = "late" if offset.offset_s > 0 else "early"
        text = (f"{label}: its time stamps run {abs(offset.offset_s):.2f} s {where} against the IMU's clock (from "
                f"{offset.method}); give time_offset_s in [files.odometer_right] of survey.toml if it is the "
                "sensor's latency")
        if abs(offset.offset_s) >= MAX_OFFSET_S:
            raise InputError(path, None, "{read_as}{partition}; an offset of {max_offset_s:g} s "
                             "or more is refused", fields={"read_as": read_as(label), "partition": text.partition(': ')[2], "max_offset_s": MAX_OFFSET_S})
        notices.append(Notice("time", text, file=str(path)))
    pair = compare_odometers(survey.imu, survey.odometer, right, lever_left, lever_right, c_vb)
    if abs(pair.relative_scale) > MAX_RELATIVE_SCALE:
        raise InputError(path, None, "{read_as}the right wheel counts {scale_pct:+.2f} % against "
                         "the left one ({left_label}) where both roll; two wheels on the rails differ by far less: "
                         "likely a wrong pulse length or another survey's file", fields={"read_as": read_as(label), "scale_pct": 100 * pair.relative_scale, "left_label": left_label})
    notices += slip_notices(pair, label, left_label, right.source, survey.odometer.source)
    survey = replace(survey, odometer=pair.left, odometer_right=pair.right)
    return survey, notices, pair.to_dict()


#: Where a slip's event says it came from (summary.toml ``[[events]] source``).
SLIP_SOURCE = "odometer comparison"


def slip_events(odometer_pair: dict | None, recon: TrackReconstruction) -> tuple[TrackEvent, ...]:
    """Each slipping stretch of the fusion's ``[fusion.odometer_pair]`` (None: one odometer) as a ``note``
    event on the survey's chainage: it marks the track (the charts, the events table, summary.toml
    ``[[events]]``) and leaves the assessment alone."""
    if not odometer_pair:
        return ()
    track = recon.epochs.station_track()
    events = []
    for slip in odometer_pair.get("slips", []):
        start, end = max(slip["start_s"], track.first_time_s), min(slip["end_s"], track.last_time_s)
        if start > end:
            continue
        what = (f"the {slip['wheel']} odometer wheel slipped {abs(slip['slip_percent']):.1f} %: its speeds left out, "
                "the other wheel bridging" if slip["wheel"] != "either" else
                f"the odometer wheels disagree by {abs(slip['slip_percent']):.1f} %: both left out")
        events.append(place_event_on(Event("note", start, end, "time_s", text=what), track, None, SLIP_SOURCE))
    return tuple(events)


def slip_notices(pair: OdometerPair, right_label: str, left_label: str, right_path: Path | None,
                 left_path: Path | None) -> list[Notice]:
    """One notice per slipping stretch: the file, the times, the distance travelled and the slip."""
    notices = []
    for slip in pair.slips:
        where = (f"from {slip.start_s:.1f} to {slip.end_s:.1f} s (travelled {slip.from_m:.1f}-{slip.to_m:.1f} m "
                 "from the start)")
        counted = f"{100 * abs(slip.slip):.1f} % {'less' if slip.slip > 0 else 'more'} than it rolled"
        if slip.wheel == "either":
            text = (f"{left_label} and {right_label}: the two wheels disagree by {counted} {where}, and the IMU cannot "
                    "tell which one slipped: both odometers' speeds are left out there, the INS with the NHC bridges it")
            path = left_path
        else:
            bad, good = (left_label, right_label) if slip.wheel == "left" else (right_label, left_label)
            text = (f"{bad}: the wheel slipped {where}, counting {counted}: its speeds are left out there, the other "
                    f"wheel ({good}) carries the along-track speed")
            path = left_path if slip.wheel == "left" else right_path
        notices.append(Notice("odometer", text, file=str(path or ""), time_s=slip.start_s))
    return notices
