"""The PDF section of a tamping re-design (``insrail redesign``): the settings and fixed stretches, the
largest movements, where the bounds hold and what cannot pass, and per chord check the values before
and after the job (the measured rails, and the same rails moved by tamping.csv's amounts)."""

from __future__ import annotations

import tomllib

import numpy as np
from reportlab.lib.units import mm
from reportlab.platypus import Flowable, PageBreak, Paragraph

from insrail.report.charts import Series, StripChart, strip_drawing
from insrail.report.content import ReportContent
from insrail.report.pdf import BODY, H1, H2, MARGIN, Heading, page_size, table, text


def redesign_page(content: ReportContent) -> list[Flowable]:
    """Nothing for a survey without a re-design."""
    from insrail.export.tamping import read_tamping
    from insrail.project.redesign import REDESIGN_FOLDER, SUMMARY_FILE, TAMPING_FILE, measured_geometry
    from insrail.track.exceedance import assess
    from insrail.track.redesign import judged_only, moved

    folder = content.results.folder / REDESIGN_FOLDER
    if not (folder / SUMMARY_FILE).is_file():
        return []
    summary = tomllib.loads((folder / SUMMARY_FILE).read_text(encoding="utf-8"))
    tamping = read_tamping(folder / TAMPING_FILE)
    settings, movement, count = summary["settings"], summary["movement"], summary["exceedances"]
    story: list[Flowable] = [PageBreak(), Heading("Tamping re-design"), Paragraph("Tamping re-design", H1), Paragraph(text(
        f"The least lift and slew per sleeper after which the track passes the chord checks of {summary['profile']} "
        f"(each held {settings['margin_mm']:g} mm inside its limit): {'lift only' if settings['lift_only'] else 'lift or lower'}, "
        f"lift {settings['min_lift_mm']:g} to {settings['max_lift_mm']:g} mm, slew at most {settings['max_slew_mm']:g} mm; "
        f"largest lift {movement['largest_lift_mm']:.1f} mm at {movement['largest_lift_at_m']:.1f} m, largest slew "
        f"{movement['largest_slew_mm']:.1f} mm at {movement['largest_slew_at_m']:.1f} m, {movement['sleepers_moved']} "
        f"sleepers moved; exceedances {count['before']} before, {count['after']} after the job. Signs: "
        f"{tamping.metadata.get('convention', '')}."), BODY)]
    rows = [[f"{f['from_m']:.1f}", f"{f['to_m']:.1f}", f"{f['tolerance_mm']:g}", f["source"]] for f in settings["fixed"]]
    story += [Paragraph("Fixed stretches", H2),
              table(["from (m)", "to (m)", "tolerance (mm)", "from"], rows or [["-", "-", "-", "none"]],
                    [25 * mm, 25 * mm, 28 * mm, 100 * mm])]
    bound = [[s["what"], f"{s['from_m']:.1f}", f"{s['to_m']:.1f}", f"{s['value_mm']:.1f}"]
             for s in summary["active"] + [dict(c, what=f"cannot pass: {c['what']}") for c in summary["cannot_pass"]]]
    story += [Paragraph("Where a bound holds, and what cannot pass", H2),
              table(["what", "from (m)", "to (m)", "value (mm)"], bound or [["none", "-", "-", "-"]],
                    [90 * mm, 25 * mm, 25 * mm, 25 * mm])]
    sleepers = np.array([not m for m in tamping.mark])
    columns = content.results.columns
    geometry, judged = measured_geometry(columns, content.results.number)
    station = columns["station_m"]
    lift = np.column_stack([np.interp(station, tamping.station_m[sleepers], tamping.values[k][sleepers])
                            for k in ("lift_left", "lift_right")]) * 1e-3
    slew = np.interp(station, tamping.station_m[sleepers], tamping.values["slew"][sleepers]) * 1e-3
    profile = content.profile
    before = assess(judged_only(geometry, judged), profile)
    after = assess(judged_only(moved(geometry, lift, slew), judged), profile)
    page = page_size(content)
    width = page[0] - 2 * MARGIN
    for b, a in zip(before.channels, after.channels):
        if b.kind not in ("versine", "differential_versine") or b.rail != "left":
            continue
        chart = StripChart(f"{b.check}, {b.direction}, left rail: before (measured) and after the job", "mm",
                           (Series("before", 1e3 * b.values), Series("after", 1e3 * a.values)),
                           limits=(1e3 * b.lower, 1e3 * b.upper))
        story.append(strip_drawing(chart, station, judged, float(station[0]), float(station[-1]), width, 48 * mm,
                                   ticks=content.chainage.ticks, axis_title=content.chainage.title))
    return story
