"""The PDF section of a tamping re-design (``insrail redesign``): the settings and fixed stretches, the
largest movements, where the bounds hold and where the track is not predicted to pass (cannot pass,
passes by less than the survey's uncertainty, not assessed), and per chord check the values before
and after the job (the measured rails, and the same rails moved by tamping.csv's amounts; a check the
survey cannot assess there has no value, as in the processing's assessment)."""

from __future__ import annotations

import tomllib

import numpy as np
from reportlab.lib.units import mm
from reportlab.platypus import Flowable, PageBreak, Paragraph

from insrail.names import channel_name, profile_name, t
from insrail.report.charts import Series, StripChart, strip_drawing
from insrail.report.content import ReportContent, fixed_source_name, redesign_bound_name, redesign_not_passing
from insrail.report.pdf import BODY, H1, H2, MARGIN, Heading, page_size, table, text


def redesign_page(content: ReportContent) -> list[Flowable]:
    """Nothing for a survey without a re-design."""
    from insrail.export.tamping import read_tamping
    from insrail.project.redesign import REDESIGN_FOLDER, SUMMARY_FILE, TAMPING_FILE, measured_geometry, survey_uncertainty
    from insrail.track.exceedance import assess
    from insrail.track.redesign import judged_only, moved

    folder = content.results.folder / REDESIGN_FOLDER
    if not (folder / SUMMARY_FILE).is_file():
        return []
    summary = tomllib.loads((folder / SUMMARY_FILE).read_text(encoding="utf-8"))
    tamping = read_tamping(folder / TAMPING_FILE)
    settings, movement, count = summary["settings"], summary["movement"], summary["exceedances"]
    heading = t("Tamping re-design")
    story: list[Flowable] = [PageBreak(), Heading(heading), Paragraph(heading, H1), Paragraph(text(t(
        "The least lift and slew per sleeper after which the track passes the chord checks of {profile} (each held "
        "inside its limit by three of the survey's stated 1-sigma of it, at least {margin_mm:g} mm): {direction}, "
        "lift {min_lift_mm:g} to {max_lift_mm:g} mm, slew at most {max_slew_mm:g} mm; largest lift {lift_mm:.1f} mm at {lift_at_m:.1f} m, largest slew {slew_mm:.1f} mm at "
        "{slew_at_m:.1f} m, {sleepers} sleepers moved; exceedances {before} before, {after} after the job. Signs: "
        "{convention}.").format(
        profile=profile_name(content.profile) if content.profile.name == summary["profile"] else summary["profile"],
        margin_mm=settings["margin_mm"],
        direction=t("lift only") if settings["lift_only"] else t("lift or lower"),
        min_lift_mm=settings["min_lift_mm"], max_lift_mm=settings["max_lift_mm"], max_slew_mm=settings["max_slew_mm"],
        lift_mm=movement["largest_lift_mm"], lift_at_m=movement["largest_lift_at_m"],
        slew_mm=movement["largest_slew_mm"], slew_at_m=movement["largest_slew_at_m"],
        sleepers=movement["sleepers_moved"], before=count["before"], after=count["after"],
        convention=t(tamping.metadata.get("convention", "")))), BODY)]
    if "uncertain" in summary:  # a re-design that took the survey's accuracy
        story.append(Paragraph(text(t(
            "Where a check's value after the job is within its limit by less than three of the survey's stated 1-sigma "
            "({uncertain} stretches), the true track may not pass it; where the stated 1-sigma is too large for the "
            "limit ({not_assessed} checks), the check is not assessed after the job, as the processing does not "
            "assess it: neither is said to pass; both are listed below.").format(
            uncertain=len(summary["uncertain"]), not_assessed=len(summary["not_assessed"]))), BODY))
    rows = [[f"{f['from_m']:.1f}", f"{f['to_m']:.1f}", f"{f['tolerance_mm']:g}", fixed_source_name(f["source"])]
            for f in settings["fixed"]]
    story += [Paragraph(t("Fixed stretches"), H2),
              table([t("from (m)"), t("to (m)"), t("tolerance (mm)"), t("from")], rows or [["-", "-", "-", t("none")]],
                    [25 * mm, 25 * mm, 28 * mm, 100 * mm])]
    profile = content.profile
    bound = [[redesign_bound_name(s["what"], profile), f"{s['from_m']:.1f}", f"{s['to_m']:.1f}", f"{s['value_mm']:.1f}"]
             for s in summary["active"]]
    bound += [[what, f"{start:.1f}", f"{end:.1f}", f"{value:.1f}"]
              for what, start, end, value in redesign_not_passing(summary, profile)]
    story += [Paragraph(t("Where a bound holds, and where the track is not said to pass"), H2),
              table([t("what"), t("from (m)"), t("to (m)"), t("value (mm)")], bound or [[t("none"), "-", "-", "-"]],
                    [90 * mm, 25 * mm, 25 * mm, 25 * mm])]
    sleepers = np.array([not m for m in tamping.mark])
    columns = content.results.columns
    geometry, judged = measured_geometry(columns, content.results.number)
    station = columns["station_m"]
    lift = np.column_stack([np.interp(station, tamping.station_m[sleepers], tamping.values[k][sleepers])
                            for k in ("lift_left", "lift_right")]) * 1e-3
    slew = np.interp(station, tamping.station_m[sleepers], tamping.values["slew"][sleepers]) * 1e-3
    not_assessed = survey_uncertainty(profile, content.results.quality, station).masks()
    before = assess(judged_only(geometry, judged), profile, not_assessed=not_assessed)
    after = assess(judged_only(moved(geometry, lift, slew), judged), profile, not_assessed=not_assessed)
    page = page_size(content)
    width = page[0] - 2 * MARGIN
    checks = {check.name: check for check in profile.checks}
    for b, a in zip(before.channels, after.channels):
        if b.kind not in ("versine", "differential_versine") or b.rail != "left":
            continue
        chart = StripChart(t("{channel}: before (measured) and after the job").format(channel=channel_name(
                               checks[b.check], b.rail, b.direction)), "mm",
                           (Series(t("before"), 1e3 * b.values), Series(t("after"), 1e3 * a.values)),
                           limits=(1e3 * b.lower, 1e3 * b.upper))
        story.append(strip_drawing(chart, station, judged, float(station[0]), float(station[-1]), width, 48 * mm,
                                   ticks=content.chainage.ticks, axis_title=content.chainage.title))
    return story
