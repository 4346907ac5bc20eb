"""``insrail`` command line. Each sub-command lives in its own module and registers here."""

from __future__ import annotations

import argparse
import sys

from insrail import __version__
from insrail.io.errors import InputError
from insrail.progress import Cancelled

# (name, module) of every sub-command; a module provides add_arguments(parser) and run(args).
COMMANDS = [
    ("simulate", "insrail.cli.simulate"),
    ("fuse", "insrail.cli.fuse"),
    ("demo", "insrail.cli.demo"),
    ("process", "insrail.cli.process"),
    ("report", "insrail.cli.report"),
    ("export", "insrail.cli.export"),
    ("batch", "insrail.cli.batch"),
    ("compare", "insrail.cli.compare"),
    ("ppk", "insrail.cli.ppk"),
    ("gui", "insrail.cli.gui"),
    ("predict", "insrail.cli.predict"),
]


def build_parser() -> argparse.ArgumentParser:
    import importlib

    parser = argparse.ArgumentParser(
        prog="insrail",
        description="Inertial track-geometry trolley processing.",
    )
    parser.add_argument("--version", action="version", version=f"insrail {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name, module_name in COMMANDS:
        module = importlib.import_module(module_name)
        p = sub.add_parser(name, help=module.__doc__.strip().splitlines()[0], description=module.__doc__)
        module.add_arguments(p)
        p.set_defaults(run=module.run)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "run", None):
        parser.print_help()
        return 2
    try:
        return int(args.run(args) or 0)
    except InputError as err:
        print(f"insrail: input error: {err}", file=sys.stderr)
        return 1
    except (FileExistsError, FileNotFoundError) as err:
        print(f"insrail: {err}", file=sys.stderr)
        return 1
    except (Cancelled, KeyboardInterrupt):
        print("insrail: cancelled", file=sys.stderr)
        return 130
