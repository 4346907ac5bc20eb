"""The PDF page of a joined line section (:mod:`insrail.project.section`): its runs and the
run-to-run differences of every overlap, beside the predicted sigma of a difference."""

from __future__ import annotations

from reportlab.lib.units import mm
from reportlab.platypus import Flowable, Paragraph

from insrail.names import UnknownName, column_name, t
from insrail.report.content import ReportContent
from insrail.report.pdf import BODY, H1, H2, Heading, table, text


def section_page(content: ReportContent) -> list[Flowable]:
    """Runs and overlaps of a section (nothing for a survey's own report)."""
    section = content.summary.get("section")
    if not section:
        return []
    joined_as = (t("each sleeper takes the run with the better predicted accuracy") if section["overlap"] == "best"
                 else t("each sleeper is the weighted mean of the runs (weights 1/sigma^2)"))
    story: list[Flowable] = [Heading(t("Line section")), Paragraph(text(t("Line section: joined runs")), H1),
                             Paragraph(text(t(
                                 "Runs {runs}, joined on the stationing; in the overlaps {joined}. Sleepers are "
                                 "numbered continuously; the sleeper table's source columns say which run each row came "
                                 "from. Differential versines are compared by magnitude (the sign of their worst value "
                                 "over the chord placements flips where two placements tie) and not within a chord of an "
                                 "overlap's ends.").format(runs=", ".join(section["surveys"]), joined=joined_as)), BODY)]
    for overlap in section.get("overlaps", []):
        rows = [[_parameter(name) + (t(" (by magnitude)") if v.get("compared") == "magnitude" else ""),
                 v["count"], f"{v['mean_mm']:.2f}", f"{v['std_mm']:.2f}",
                 f"{v['rms_mm']:.2f}", f"{v['max_abs_mm']:.2f}",
                 f"{v['predicted_sigma_mm']:.2f}" if "predicted_sigma_mm" in v else "-",
                 t("yes") if v.get("exceeds") else ""] for name, v in overlap["parameters"].items()]
        story += [Paragraph(text(t("Overlap {later} - {earlier}: {start:.1f} to {end:.1f} m, {sleepers} sleepers").format(
                      later=overlap["runs"][1], earlier=overlap["runs"][0], start=overlap["from_m"], end=overlap["to_m"],
                      sleepers=overlap["sleepers"])), H2),
                  table([t(title) for title in ("parameter", "sleepers", "mean (mm)", "std (mm)", "RMS (mm)",
                                                "max |d| (mm)", "predicted sigma (mm)", "> 3 sigma")], rows,
                        [95 * mm, 20 * mm, 22 * mm, 22 * mm, 22 * mm, 25 * mm, 32 * mm, 20 * mm])]
    if not section.get("overlaps"):
        story.append(Paragraph(text(t("The runs do not overlap.")), BODY))
    return story


def _parameter(name: str) -> str:
    """A compared parameter by its display name where it has one (a column of sleepers.csv), else its id in words."""
    try:
        return column_name(name).name
    except UnknownName:  # a check channel: its id without the unit
        return name.removesuffix("_mm").replace("_", " ")
