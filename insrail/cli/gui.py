"""Open the desktop application (optionally with a project).

Needs PySide6 and pyqtgraph. PROJECT is a project folder or its project.toml.
"""

from __future__ import annotations

import argparse
from pathlib import Path


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("project", type=Path, nargs="?", help="project folder (with project.toml) to open")
    p.add_argument("--screenshot", type=Path, metavar="PNG",
                   help="draw the window once (with the project's results), save it as PNG and quit")


def run(args: argparse.Namespace) -> int:
    from insrail.gui.app import run as run_gui

    return run_gui(args.project, screenshot=args.screenshot)
