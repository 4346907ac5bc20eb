"""Run insrail end to end on the built-in demo: a project around a simulated survey.

Simulates the 1.2 km `short` survey (``--preset long``: the 10 km `long` one) with a
navigation-grade IMU into DIR/surveys/<preset> (replacing an earlier demo there), writes
DIR/project.toml (the simulation's engineering CRS, its GNSS-levelling benchmarks for the height
model, its design alignment, a turnout and a level crossing as track events) and processes the
survey like `insrail process DIR`: fusion, engineering coordinates, rails, chainage and sleepers,
deviations, irregularities, exceedances and adjustment amounts into DIR/results/<preset>, the Excel
workbook and the PDF report into DIR/reports. Then compares the results with the simulator's truth.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from insrail.cli.progressbar import TerminalProgress


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", type=Path, default=Path("insrail-demo"), help="demo folder (default: ./insrail-demo)")
    p.add_argument("--seed", type=int, default=1, help="random seed of the simulated survey (default: 1)")
    p.add_argument("--preset", choices=PRESETS, default="short",
                   help="the simulated survey: short (1.2 km, the default), long (10 km) or ballasted (the short line "
                        "due for tamping: 10-30 mm long waves and dips, a bridge and a level crossing; docs/tamping.md)")


def truth_comparison(table, truth) -> dict[str, float]:
    """Largest errors [m] of the sleeper table against the simulator's sleepers (matched by station).

    The mean of the two rails' deviations is the centreline's, which the simulator injects
    directly, so it is compared without modelling the gauge and cant terms.
    """
    import numpy as np

    order = np.argsort(truth["station"])
    stations = truth["station"][order]
    k = np.clip(np.searchsorted(stations, table.station_m), 1, len(stations) - 1)
    nearest = order[np.where(np.abs(stations[k - 1] - table.station_m) < np.abs(stations[k] - table.station_m), k - 1, k)]
    ok = table.valid
    return {
        "chainage": np.abs(table.station_m - truth["station"][nearest])[ok].max(),
        "gauge": np.abs(table.gauge_m - truth["gauge"][nearest])[ok].max(),
        "cant": np.abs(table.cant_m - truth["cant"][nearest])[ok].max(),
        "lateral": np.abs(table.lateral_deviation_m.mean(axis=1) - truth["lateral"][nearest])[ok].max(),
        "vertical": np.abs(table.vertical_deviation_m.mean(axis=1) - truth["vertical"][nearest])[ok].max(),
    }


#: The demo's track events, on the `short` design's chainage: a turnout (the length of a No. 18 turnout)
#: and a level crossing, both left out of the assessment (docs/formats.md "Track events").
DEMO_EVENTS = (("turnout", 1300.0, 1369.0, "No. 18"), ("level_crossing", 1800.0, 1808.0, "of the service road"))
#: The same on the `long` design's chainage (its survey runs from 20 050 to 30 250 m).
LONG_DEMO_EVENTS = (("turnout", 22300.0, 22369.0, "No. 18"), ("level_crossing", 27800.0, 27808.0, "of the service road"))
#: The simulator presets the demo offers (the ballasted preset's events are the simulator's own fixed
#: stretches, sim.scenario.BALLASTED_EVENTS, looked up when it runs: `insrail --help` imports no simulator).
PRESETS = ("short", "long", "ballasted")


def preset_events(name: str) -> tuple:
    """The track events of a demo preset."""
    if name == "ballasted":
        from insrail.sim.scenario import BALLASTED_EVENTS
        return BALLASTED_EVENTS
    return {"short": DEMO_EVENTS, "long": LONG_DEMO_EVENTS}[name]
#: The tolerance profile of a preset whose line is not the default profile's: the ballasted line is
#: accepted after tamping with the conventional line's maintenance checks.
PRESET_PROFILES = {"ballasted": "cn_conventional_160"}


def demo_events(project, events=DEMO_EVENTS):
    """The project with the demo's event file (``events``, replacing one an earlier demo wrote there),
    named in its project.toml."""
    from dataclasses import replace

    from insrail.io.events import Event, EventList, write_events
    from insrail.project.event_marking import DEFAULT_EVENTS_FILE
    from insrail.project.model import save_project

    write_events(project.resolve(DEFAULT_EVENTS_FILE),
                 EventList(tuple(Event(kind, start, end, "station_m", text=text) for kind, start, end, text in events)))
    project = replace(project, events=DEFAULT_EVENTS_FILE)
    save_project(project)
    return project


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from insrail.cli.process import describe, profile_checks
    from insrail.cli.report import default_paths, write_reports
    from insrail.project import process
    from insrail.project.demo import project_for_simulated_survey
    from insrail.sim.evaluation import trajectory_errors
    from insrail.sim.scenario import preset
    from insrail.sim.simulate import simulate
    from insrail.sim.truth import read_nav_truth, read_sleeper_truth

    name = args.preset
    survey_dir = args.out / "surveys" / name
    bar = TerminalProgress("demo")
    result = simulate(preset(name), args.seed, survey_dir, overwrite=True, imu_format="npy",
                      progress=lambda f, m: bar(0.25 * f, m))
    print(f"insrail demo: simulated a {result.length_m:.0f} m trolley survey ({result.duration_s:.0f} s of data)")
    print(f"Survey folder: {result.folder.resolve()}")
    project = demo_events(project_for_simulated_survey(args.out, survey_dir, name="insrail demo"), preset_events(name))
    if name in PRESET_PROFILES:
        from dataclasses import replace

        from insrail.project.model import save_project

        project = replace(project, tolerance_profile=PRESET_PROFILES[name])
        save_project(project)
    print(f"Project file: {project.path.resolve()}")
    results = process(project, name, progress=lambda f, m: bar(0.25 + 0.75 * f, m))
    elapsed = bar.done()
    print("\n".join(describe(results, profile_checks(project))))
    for path in write_reports(project, name, *default_paths(project.folder, name)):
        print(f"Report: {path.resolve()}")

    errors = trajectory_errors(results.trajectory, read_nav_truth(survey_dir / "truth" / "nav.npy"), project.crs.reference_ellipsoid)
    lat5, ver5 = errors.lag_difference_sigma_m(5.0)
    rpy = np.rad2deg(errors.rms_attitude_rad())
    track = truth_comparison(results.table, read_sleeper_truth(survey_dir / "truth" / "sleepers.csv"))
    print("Against the simulator's truth:")
    print(f"  trajectory RMS horizontal {1e3 * errors.rms_horizontal_m():.1f} mm, vertical "
          f"{1e3 * errors.rms_vertical_m():.1f} mm; attitude RMS roll {rpy[0]:.4f}, pitch {rpy[1]:.4f}, "
          f"heading {rpy[2]:.4f} deg; 5 m apart (1 sigma) lateral {1e3 * lat5:.2f} mm, vertical {1e3 * ver5:.2f} mm")
    print(f"  sleepers, largest error: chainage {1e3 * track['chainage']:.1f} mm, gauge {1e3 * track['gauge']:.2f} mm, "
          f"cant {1e3 * track['cant']:.2f} mm, centreline lateral {1e3 * track['lateral']:.1f} mm, "
          f"vertical {1e3 * track['vertical']:.1f} mm (absolute, GNSS-limited)")
    print(f"Done in {elapsed:.1f} s. Process again with: insrail process {args.out}")
    return 0
