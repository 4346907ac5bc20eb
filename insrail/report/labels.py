"""What the numbers on paper and in the exports are: one wording for every file.

Two kinds of per-rail millimetres leave insrail, and no file may confuse them:

* a **deviation** is a measurement: the rail's position minus its reference, ``measured − design
  (<design file>)`` with a design alignment, else ``measured − fitted line`` (the line types fitted
  to the measured centreline), + right / + up looking towards increasing chainage
  (:func:`deviation_reference`, taken from the results' summary: the reference the processing used);
* an **amount** is the crew's instruction: how far to move the rail at a sleeper (+ right / + up), the
  adjustment planning's result (:mod:`insrail.track.adjustment`, sleepers.csv ``adjust_*_mm``). Every
  file that carries amounts carries these, unchanged, and says what they bring the rail to
  (:func:`amounts_text`): the re-assessed track passes the tolerance profile; they do not put the rail
  onto its reference (that would be −deviation, which no file offers as an instruction).
"""

from __future__ import annotations

from pathlib import PurePosixPath

from insrail.names import fastener_name, profile_name, t
from insrail.track.adjustment import DEFAULT_STRATEGY, STRATEGIES

#: The sign of deviations and amounts alike, looking towards increasing chainage.
SIGNS = "lateral + right, vertical + up, looking towards increasing chainage"


def design_name(summary: dict) -> str:
    """The design alignment the results were processed with, by its file name ("" without one)."""
    design = summary.get("track", {}).get("design", "")
    return PurePosixPath(str(design).replace("\\", "/")).name if design else ""


def deviation_reference(summary: dict) -> str:
    """What the deviations are: "measured − design (design.csv)" or "measured − fitted line" (U+2212: it reads
    as a difference, not a hyphenated word)."""
    design = design_name(summary)
    return (t("measured − design ({design})").format(design=design) if design else t("measured − fitted line"))


def deviation_group(summary: dict) -> str:
    """The sleeper table's and the charts' group title of the deviations."""
    return t("Deviation [{reference}]").format(reference=deviation_reference(summary))


def reference_line(summary: dict) -> str:
    """The line the deviations are taken against, in words ("the design alignment design.csv")."""
    design = design_name(summary)
    return (t("the design alignment {design}").format(design=design) if design
            else t("the line fitted to the measured centreline"))


def amounts_withheld_text(summary: dict) -> str | None:
    """Why the results hold no adjustment amounts (a relative survey: summary.toml ``[adjustment] withheld``),
    in the report's language; None where they hold amounts."""
    if "withheld" not in summary.get("adjustment", {}):
        return None
    return t("No adjustment amounts: a relative survey (no GNSS, no prism fixes) knows the track's shape, not its "
             "place against the design; amounts would move the rails by the IMU's drift")


def amounts_text(summary: dict, profile, fastener) -> str:
    """What moving each rail by its amount achieves, from the results' summary ([adjustment]) and the
    profile and fastener type the amounts were planned with (``fastener`` None: its file is not readable)."""
    if (withheld := amounts_withheld_text(summary)) is not None:
        return withheld
    adjustment = summary.get("adjustment", {})
    strategy = t(STRATEGIES.get(adjustment.get("strategy", DEFAULT_STRATEGY), adjustment.get("strategy", "")))
    failing = adjustment.get("unresolved_sleepers", 0)
    verdict = (t("after it the track passes every check of tolerance profile {profile}").format(
                   profile=profile_name(profile))
               + (t(" except at {count} sleepers marked as still failing").format(count=failing) if failing else "")
               if "after" in adjustment else  # results of an insrail before the re-assessment: no verdict to state
               t("planned for tolerance profile {profile}, not re-assessed after the adjustment in these results").format(
                   profile=profile_name(profile)))
    return t("move the rail by the amount ({signs}); planned by insrail for fastener {fastener} in whole fastener "
             "steps ({strategy}): {verdict}; it does not put the rail onto {reference}").format(
        signs=t(SIGNS), fastener=fastener_name(fastener, adjustment.get("fastener", "")), strategy=strategy,
        verdict=verdict, reference=reference_line(summary))
