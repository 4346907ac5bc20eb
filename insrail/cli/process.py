"""Process the surveys of a project end to end (fusion, coordinates, track, assessment, adjustment).

Reads PROJECT/project.toml (or the given .toml), processes the named survey (or every survey
of the project, in order) and writes PROJECT/results/<survey>/: trajectory.npy, sleepers.csv,
exceedances.csv and summary.toml. A fusion already computed with the same raw data and
settings is reused from PROJECT/results/.cache. Exit code 0 when every survey was processed,
1 on bad input or a processing error (reported with the file and key path), 130 when cancelled.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from insrail.cli.progressbar import TerminalProgress
from insrail.notices import notices_of


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("project", type=Path, help="project folder (with project.toml) or project .toml file")
    p.add_argument("--survey", action="append", metavar="NAME",
                   help="survey to process (repeatable; default: every survey of the project)")


def _line_fit_lines(line_fit: dict | None) -> list[str]:
    """The line-type fit of a survey without a design alignment."""
    if line_fit is None:
        return []
    if not line_fit["fitted"]:
        return [f"  line-type fit failed, deviations left empty: {line_fit['error']}"]
    elements = ", ".join(f"{count} {kind}" for kind, count in line_fit["elements"].items())
    return [(f"  line-type fit (no design): {elements}, {line_fit['pvis']} PVIs; residual RMS plan "
             f"{line_fit['plan_rms_mm']:.2f} mm, profile {line_fit['profile_rms_mm']:.2f} mm; deviations from "
             f"{line_fit['windows']} overlapping windows; fitted_alignment.csv/.xml usable as the design")]


def _quality_lines(quality: dict | None) -> list[str]:
    """The predicted accuracy per section (1 sigma of the 5 m and 150 m lag differences)."""
    if quality is None:
        return []
    median, weakest = quality["median"], quality["weakest"]

    def figures(values: dict) -> str:
        return (f"5 m lag {values['sigma_lag5_lateral_mm']:.2f}/{values['sigma_lag5_vertical_mm']:.2f} mm, "
                f"150 m lag {values['sigma_lag150_lateral_mm']:.2f}/{values['sigma_lag150_vertical_mm']:.2f} mm, "
                f"cross-level {values['sigma_cross_level_mm']:.2f} mm, along-track {values['sigma_along_track_mm']:.1f} mm")

    return [(f"  predicted accuracy ({quality['pass']}, 1 sigma lateral/vertical, {quality['sections']} sections): "
             f"median {figures(median)}; weakest {weakest['station_from_m']:.0f}..{weakest['station_to_m']:.0f} m "
             f"{figures(weakest)}")]


def check_counts(by_check: dict[str, int], checks=()) -> str:
    """``by_check`` of a summary in words: each check by its display name (``checks``: the
    tolerance profile's, see :func:`insrail.names.check_name`), its id only when the profile
    no longer has it."""
    from insrail.names import check_name

    names = {check.name: check_name(check) for check in checks}
    return ", ".join(f"{names.get(check, check)} {count}" for check, count in by_check.items()) or "none"


def describe(results, checks=()) -> list[str]:
    """Headline lines for one survey's results (shared with ``insrail demo``); ``checks``: the
    project's tolerance-profile checks, which name the exceedance counts."""
    s = results.summary
    track, assessment, adjustment = s["track"], s["assessment"], s["adjustment"]
    heights = s["heights"]
    height_line = (f"height anomaly: {heights['model']} model, benchmark RMS {heights['internal_rms_mm']:.1f} mm"
                   if "internal_rms_mm" in heights else f"heights: {heights['model']}")
    by_check = check_counts(assessment["by_check"], checks)
    prism = s["fusion"].get("prism_fixes", 0)
    prism_text = f", {prism} total-station prism fixes on CPIII points" if prism else ""
    gnss_lines = []
    if "ppk" in s:
        gnss = s["ppk"]
        qualities = ", ".join(f"{name} {count}" for name, count in gnss["epochs_by_quality"].items())
        gnss_lines = [(f"  GNSS (PPK, {'reused from the cache' if gnss['from_cache'] else 'computed'}): "
                      f"fix rate {100 * gnss['fix_rate']:.1f} % of {gnss['epochs']} epochs ({qualities}); "
                      f"fusion inflated {gnss['fusion_inflated_epochs']}, excluded {gnss['fusion_excluded_epochs']}; "
                      f"base {gnss['base']['point']}")]
    return [
        f"Survey {results.survey}{' (relative survey)' if s['survey'].get('kind') == 'relative' else ''}: "
        f"results in {results.folder.resolve()}",
        *gnss_lines,
        (f"  fusion: {'reused from the cache' if s['fusion']['from_cache'] else 'computed'}, "
         f"{s['fusion']['rejections']} measurements rejected{prism_text}; {height_line}"),
        (f"  track: {track['sleepers']} sleepers ({track['valid_sleepers']} valid), "
         f"stations {track['station_from_m']:.3f} .. {track['station_to_m']:.3f} m"),
        *_pulse_lines(track.get("sleeper_pulses")),
        *_line_fit_lines(track.get("line_fit")),
        *_joint_lines(s.get("joints")),
        *_event_lines(s.get("events", []), assessment.get("not_assessed_sleepers", 0)),
        *(f"  {'warning' if notice.severity == 'warning' else 'note'}: {notice.text()}" for notice in notices_of(s)),
        *_quality_lines(s.get("quality")),
        f"  {assessment['tolerance_profile']}: {assessment['exceedances']} exceedances ({by_check})",
        (f"  adjustment: none, {adjustment['withheld']}" if "withheld" in adjustment else
         f"  adjustment ({adjustment['fastener']}): max lateral {adjustment['max_lateral_mm']:.1f} mm, "
         f"max vertical {adjustment['max_vertical_mm']:.1f} mm, {adjustment['unresolved_sleepers']} sleepers unresolved"),
        *after_adjustment_lines(adjustment, checks),
        "  files: " + ", ".join(dict.fromkeys([*s["files"].values(), "summary.toml"])),
    ]


def _pulse_lines(pulses: dict | None) -> list[str]:
    """How the sleeper numbering repaired the detector's pulses (thesis 5.2.2.5)."""
    if not pulses:
        return []
    if not pulses["pulses"]:
        return ["  sleepers: no detector pulses, a regular grid"]
    return [(f"  sleeper detector: {pulses['pulses']} pulses, {pulses['missed_inserted']} missed sleepers inserted, "
             f"{pulses['false_rejected']} false pulses rejected")]


def _joint_lines(joints: dict | None) -> list[str]:
    """The rail joints found as IMU shocks (listed one by one in summary.toml's [[events]])."""
    if not joints or not joints["detected"]:
        return []
    spacing = f", median spacing {joints['median_spacing_m']:.2f} m" if "median_spacing_m" in joints else ""
    return [f"  rail joints: {joints['detected']} detected from IMU shocks (over {joints['threshold_mps2']:.2f} m/s^2)"
            f"{spacing}; the NHC relaxed {joints['nhc_relaxed_s']:g} s either side (summary.toml [[events]])"]


def _event_lines(events: list[dict], not_assessed: int) -> list[str]:
    """The survey's events written in its event files (the detected joints: :func:`_joint_lines`): which are not
    assessed, how many sleepers that takes out of the assessment."""
    from insrail.project.track_events import DETECTED_JOINT_SOURCE
    from insrail.track.events import KIND_NAMES

    events = [e for e in events if e["source"] != DETECTED_JOINT_SOURCE]
    if not events:
        return []

    lines = [f"  events: {len(events)}, {not_assessed} sleepers not assessed with the track's profile"]
    for e in events:
        what = ("not assessed" if e["not_assessed"] else
                f"assessed with {e['profile']}: {e.get('exceedances', 0)} exceedances" if e["profile"] else "marked")
        lines.append(f"    {KIND_NAMES[e['kind']]} {e['text']} {e['station_from_m']:.3f} .. {e['station_to_m']:.3f} m, "
                     f"{e['sleepers']} sleepers: {what} ({e['source']})")
    return lines


def after_adjustment_lines(adjustment: dict, checks=()) -> list[str]:
    """The re-assessment of the adjusted geometry (results of older versions have none)."""
    after = adjustment.get("after")
    if after is None:
        return []
    by_check = check_counts(after["by_check"], checks)
    reasons = ", ".join(f"{name.replace('_', ' ')} {count}" for name, count in adjustment["unresolved_reasons"].items()
                        if count)
    return [f"  after adjustment: {after['exceedances']} exceedances ({by_check}), {after['new_exceedances']} new; "
            f"{adjustment['sleepers_to_work_on']} sleepers to work on"
            + (f"; still failing: {reasons}" if reasons else "")]


def chosen_surveys(project, requested: list[str] | None) -> list[str] | None:
    """The surveys a command works on (``--survey``, default all); None after saying which are unknown."""
    names = requested or [s.name for s in project.surveys]
    known = {s.name for s in project.surveys}
    unknown = [n for n in names if n not in known]
    if unknown:
        print(f"insrail: {project.path}: no survey named {', '.join(unknown)} (surveys: {', '.join(sorted(known))})",
              file=sys.stderr)
        return None
    return names


def profile_checks(project) -> tuple:
    """The checks of the project's tolerance profile (they name what the output counts)."""
    from insrail.track.tolerance import load_tolerance_profile

    return load_tolerance_profile(project.resource(project.tolerance_profile)).checks


def run(args: argparse.Namespace) -> int:
    from insrail.memory import collector_paused

    with collector_paused():  # the start-up's imports
        from insrail.project import load_project, process
        from insrail.report.stale import stale_report_lines

    project = load_project(args.project)
    names = chosen_surveys(project, args.survey)
    if names is None:
        return 1
    for name in names:
        bar = TerminalProgress(name)
        try:
            results = process(project, name, progress=bar)
        except ValueError as err:  # geodesy fits, tolerance/fastener files, reconstruction limits
            bar.stopped()
            print(f"insrail: survey {name}: {err}", file=sys.stderr)
            return 1
        elapsed = bar.done()
        print("\n".join(describe(results, profile_checks(project))))
        print(f"  processed in {elapsed:.1f} s")
        for line in stale_report_lines(project.folder, name):  # the reports now describe results that are gone
            print(line)
    return 0
