"""The PDF page of a joined line section (:mod:`insrail.project.section`): its runs and the
run-to-run differences of every overlap, beside the predicted sigma of a difference."""

from __future__ import annotations

from reportlab.lib.units import mm
from reportlab.platypus import Flowable, Paragraph

from insrail.report.content import ReportContent
from insrail.report.pdf import BODY, H1, H2, Heading, table, text


def section_page(content: ReportContent) -> list[Flowable]:
    """Runs and overlaps of a section (nothing for a survey's own report)."""
    section = content.summary.get("section")
    if not section:
        return []
    story: list[Flowable] = [Heading("Line section"), Paragraph("Line section: joined runs", H1),
                             Paragraph(text(f"Runs {', '.join(section['surveys'])}, joined on the stationing; in the "
                                            f"overlaps each sleeper {'takes the run with the better predicted accuracy' if section['overlap'] == 'best' else 'is the weighted mean of the runs (weights 1/sigma^2)'}. "
                                            "Sleepers are numbered continuously; the sleeper table's source columns say "
                                            "which run each row came from. Differential versines are compared by "
                                            "magnitude (the sign of their worst value over the chord placements flips "
                                            "where two placements tie) and not within a chord of an overlap's ends."), BODY)]
    for overlap in section.get("overlaps", []):
        rows = [[name.removesuffix("_mm").replace("_", " ") + (" (by magnitude)" if v.get("compared") == "magnitude" else ""),
                 v["count"], f"{v['mean_mm']:.2f}", f"{v['std_mm']:.2f}",
                 f"{v['rms_mm']:.2f}", f"{v['max_abs_mm']:.2f}",
                 f"{v['predicted_sigma_mm']:.2f}" if "predicted_sigma_mm" in v else "-",
                 "yes" if v.get("exceeds") else ""] for name, v in overlap["parameters"].items()]
        story += [Paragraph(text(f"Overlap {overlap['runs'][1]} - {overlap['runs'][0]}: {overlap['from_m']:.1f} to "
                                 f"{overlap['to_m']:.1f} m, {overlap['sleepers']} sleepers"), H2),
                  table(["parameter", "sleepers", "mean (mm)", "std (mm)", "RMS (mm)", "max |d| (mm)",
                         "predicted sigma (mm)", "> 3 sigma"], rows,
                        [95 * mm, 20 * mm, 22 * mm, 22 * mm, 22 * mm, 25 * mm, 32 * mm, 20 * mm])]
    if not section.get("overlaps"):
        story.append(Paragraph("The runs do not overlap.", BODY))
    return story
