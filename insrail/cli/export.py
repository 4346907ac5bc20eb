"""Export a processed survey for the machines and CAD: lift/lining table, DXF, LandXML, coordinates.

Reads PROJECT/project.toml and the results of `insrail process`. --format lift-lining writes the
per-sleeper lift and lining of each rail onto its reference (docs/formats.md); dxf the rails,
centreline, sleepers with numbers and exceedance markers on layers; landxml the measured centreline
and rails as LandXML 1.2 lines; csv the per-sleeper coordinates; tamping the lift and slew of
`insrail redesign` (generic layout), tamping-template the same in a user's layout (--template FILE). Default file:
PROJECT/reports/<survey>_lift_lining.csv, <survey>.dxf, <survey>_centreline.xml, <survey>_points.csv.
Exit code 0 when written, 1 on missing results or bad input.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

FORMAT_NAMES = ("lift-lining", "dxf", "landxml", "csv", "tamping", "tamping-template")


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("project", type=Path, help="project folder (with project.toml) or project .toml file")
    p.add_argument("--survey", metavar="NAME", help="the survey to export (needed when the project has several)")
    p.add_argument("--section", metavar="NAME", help="a joined line section instead (insrail section)")
    p.add_argument("--format", required=True, choices=FORMAT_NAMES, help="what to write")
    p.add_argument("--template", type=Path, metavar="FILE",
                   help="with --format tamping-template: the machine layout (TOML, docs/formats.md)")
    p.add_argument("--out", type=Path, metavar="FILE", help="the file to write (default: in PROJECT/reports/)")


def run(args: argparse.Namespace) -> int:
    from insrail.cli.process import chosen_surveys
    from insrail.export import default_export_path, write_export
    from insrail.project import load_project
    from insrail.project.lock import project_run
    from insrail.project.results import load_results
    from insrail.project.run_settings import settings_change_lines

    project = load_project(args.project)
    if args.section:
        if args.section not in {s.name for s in project.sections}:
            print(f"insrail: {project.path}: no section named {args.section} (sections: "
                  f"{', '.join(s.name for s in project.sections) or 'none'})", file=sys.stderr)
            return 1
        names = [args.section]
    else:
        names = chosen_surveys(project, [args.survey] if args.survey else None)
    if names is None:
        return 1
    if len(names) > 1:
        print(f"insrail: {project.path}: choose the survey to export with --survey ({', '.join(names)})", file=sys.stderr)
        return 1
    path = args.out or default_export_path(project.folder, names[0], args.format)
    with project_run(project.folder, names):  # no run replaces the results while they are read
        options = {}
        if args.format == "tamping-template":
            from insrail.export.tamping import load_template

            if args.template is None:
                print("insrail: --format tamping-template needs --template FILE", file=sys.stderr)
                return 1
            options["template"] = load_template(args.template)
        written = write_export(project, load_results(project.folder, names[0]), args.format, path, **options)
    print(f"{names[0]} {args.format}: {written.resolve()}")
    for line in settings_change_lines(project, names[0]):  # the export states the settings processed with
        print(f"{names[0]}: warning: {line}", file=sys.stderr)
    return 0
