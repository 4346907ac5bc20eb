"""``insrail`` command line. Each sub-command lives in its own module and registers here."""

from __future__ import annotations

import argparse
import atexit
import errno
import os
import sys
import threading
import traceback
from typing import NoReturn

from insrail import __version__
from insrail.io.errors import InputError
from insrail.memory import tune_allocator
from insrail.progress import Cancelled

# (name, module) of every sub-command; a module provides add_arguments(parser) and run(args).
COMMANDS = [
    ("simulate", "insrail.cli.simulate"),
    ("fuse", "insrail.cli.fuse"),
    ("demo", "insrail.cli.demo"),
    ("process", "insrail.cli.process"),
    ("report", "insrail.cli.report"),
    ("export", "insrail.cli.export"),
    ("section", "insrail.cli.section"),
    ("redesign", "insrail.cli.redesign"),
    ("batch", "insrail.cli.batch"),
    ("compare", "insrail.cli.compare"),
    ("ppk", "insrail.cli.ppk"),
    ("gui", "insrail.cli.gui"),
    ("predict", "insrail.cli.predict"),
    ("calibrate", "insrail.cli.calibrate"),
]
#: The sub-commands that write or read a project's results under its lock (insrail.project.lock).
LOCKING_COMMANDS = ("process", "report", "export", "section", "demo")


def build_parser(argv: list[str] | None = None) -> argparse.ArgumentParser:
    """The parser; only the sub-command named first in ``argv`` gets its options (the others are
    listed with their one-line help), so building it imports no more than that command needs: a
    command's options may need its core (``simulate --preset`` the simulator's presets, ``predict
    --sweep`` the quality tables), and ``insrail fuse`` or ``insrail --help`` must not pay for them.
    ``argv`` None: every command's options (the full parser, for documentation and tests)."""
    import importlib

    parser = argparse.ArgumentParser(
        prog="insrail",
        description="Inertial track-geometry trolley processing.",
    )
    parser.add_argument("--version", action="version", version=f"insrail {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    chosen = argv[0] if argv else None
    for name, module_name in COMMANDS:
        module = importlib.import_module(module_name)
        p = sub.add_parser(name, help=module.__doc__.strip().splitlines()[0], description=module.__doc__)
        if argv is not None and name != chosen:
            continue
        module.add_arguments(p)
        if name in LOCKING_COMMANDS:
            p.add_argument("--no-wait", action="store_true",
                           help="exit with an error when another run is using the project (default: wait for it)")
        p.set_defaults(run=module.run)
    return parser


def main(argv: list[str] | None = None) -> int:
    tune_allocator()
    if argv is None:
        argv = sys.argv[1:]
    parser = build_parser(argv)
    args = parser.parse_args(argv)
    if not getattr(args, "run", None):
        parser.print_help()
        return 2
    from insrail.project.lock import waiting_policy

    try:
        with waiting_policy(announce=lambda message: print(f"insrail: {message}", file=sys.stderr, flush=True),
                         wait=not getattr(args, "no_wait", False)):
            return int(args.run(args) or 0)
    except InputError as err:
        print(f"insrail: input error: {err}", file=sys.stderr)
        return 1
    except (FileExistsError, FileNotFoundError) as err:
        print(f"insrail: {err}", file=sys.stderr)
        return 1
    except OSError as err:  # a read-only folder, a full disk, a share gone away
        print(f"insrail: {describe_os_error(err)}", file=sys.stderr)
        return 1
    except ValueError as err:  # settings, profiles and values refused by the core, which names them
        print(f"insrail: {err}", file=sys.stderr)
        return 1
    except (Cancelled, KeyboardInterrupt):
        print("insrail: cancelled", file=sys.stderr)
        return 130
    except MemoryError:
        print("insrail: out of memory: close other programs, or process the survey on a larger machine",
              file=sys.stderr)
        return 1
    except Exception as err:  # a defect: one line for the user, the traceback on request
        print(f"insrail: internal error: {type(err).__name__}: {err}. Results written before are unchanged; "
              f"run again with {DEBUG_VARIABLE}=1 for the details and report them.", file=sys.stderr)
        if os.environ.get(DEBUG_VARIABLE):
            traceback.print_exc()
        return 3


def console() -> NoReturn:
    """The ``insrail`` command (``python -m insrail`` too): :func:`main`, then :func:`exit_at_once`."""
    exit_at_once(main())


def exit_at_once(code: int) -> NoReturn:
    """End the process with ``code`` without the interpreter's teardown. What an exit does for others is
    done first, as the interpreter does it: the threads Python started joined (and the thread pools told
    to stop), the atexit functions run (multiprocessing's children, ``weakref.finalize``'s temporary
    folders, logging), the output flushed; then ``os._exit``. Skipped is only the teardown that frees
    every object and module one by one, some 0.1 s of CPU after ``insrail report`` and 0.14 s after
    ``insrail process`` of a short survey, where the kernel takes the whole address space back at once.
    Every file a command writes is closed before it returns (atomic writes), so no buffer is lost."""
    threading._shutdown()  # what Py_FinalizeEx calls first (private): the pools told to stop, the threads joined
    atexit._run_exitfuncs()  # and then (private too)
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a closed pipe: the exit status the interpreter gives then
            code = code or 120
    os._exit(code)


#: Environment variable that makes an internal error print its traceback.
DEBUG_VARIABLE = "INSRAIL_DEBUG"
_OS_ERROR_HINTS = {
    errno.ENOSPC: "the disk is full: free some space and run again (nothing half-written was kept)",
    errno.EDQUOT: "the disk quota is used up: free some space and run again (nothing half-written was kept)",
    errno.EROFS: "a read-only file system: work on a copy of the project in a writable folder",
    errno.EACCES: "no permission to write there: work on a copy of the project, or ask for write access",
    errno.EPERM: "no permission to write there: work on a copy of the project, or ask for write access",
}


def describe_os_error(err: OSError) -> str:
    """``PATH: No space left on device (the disk is full: ...)``: the path first, then what to do."""
    where = f"{err.filename}: " if err.filename else ""
    hint = _OS_ERROR_HINTS.get(err.errno)
    return f"{where}{err.strerror or err}" + (f" ({hint})" if hint else "")
