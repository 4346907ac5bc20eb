"""Process every survey of several projects in parallel, locally or on a Dask cluster.

Each survey runs as `insrail process` would (same cache, same result files) in its own worker:
with --workers N local processes (default: one per core; a 10 km survey needs about 2 GB per
worker), or, with --scheduler ADDRESS (e.g. tcp://10.0.0.5:8786), on that Dask distributed
cluster (pip install insrail[cluster]; the workers must see the project folders under the same
paths). A Dask scheduler runs whatever its clients send: keep it on a trusted network, or use
TLS (a tls:// address and --security FILE, a Dask YAML configuration with the
distributed.comm.tls settings; see insrail.project.batch). A failed survey is reported and the others go on. Exit code 0 when every survey was
processed, 1 when some failed, 2 on bad usage, 130 when cancelled (Ctrl-C).

With --section NAME (one PROJECT) the runs of that line section are the surveys processed, in
parallel as above, and the section is then joined and its reports written as `insrail section`
does (--no-reports: join only); a failed run leaves the section unjoined (exit 1).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from insrail.cli.progressbar import TerminalProgress
from insrail.progress import ProgressMessage


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("projects", type=Path, nargs="+", metavar="PROJECT",
                   help="project folder (with project.toml) or project .toml file")
    p.add_argument("--workers", type=int, metavar="N", help="local worker processes (default: one per core)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="Dask scheduler address; the cluster runs the surveys "
                   "(on a trusted network only, or tls:// with --security)")
    p.add_argument("--security", type=Path, metavar="FILE",
                   help="Dask YAML configuration with the TLS settings (distributed.comm.tls: ca-file, "
                   "client cert and key; require-encryption)")
    p.add_argument("--section", action="append", metavar="NAME",
                   help="process the runs of this line section of the (one) PROJECT, then join it as "
                   "`insrail section` does; repeat for several sections")
    p.add_argument("--no-reports", action="store_true", help="with --section: join only; write no workbook and PDF")


#: Dask's address schemes; the secured ones need the TLS settings.
SCHEMES = ("tcp", "tls", "inproc", "ucx", "ws", "wss")
SECURED_SCHEMES = ("tls", "wss")


def scheduler_problem(address: str | None, security: Path | None) -> str | None:
    """What is wrong with a ``--scheduler`` address given with (or without) ``--security``, or None."""
    if address is None:
        return None
    scheme, separator, rest = address.partition("://")
    if not separator:
        scheme, rest = "tcp", address  # host:port, as Dask reads it
    if scheme not in SCHEMES:
        return f"unknown protocol {scheme}:// (expected {', '.join(f'{s}://' for s in SCHEMES)})"
    if not rest:
        return "no host given (expected e.g. tls://10.0.0.5:8786)"
    if scheme in SECURED_SCHEMES and security is None:
        return (f"a {scheme}:// scheduler needs --security FILE (a Dask YAML configuration with "
                "distributed.comm.tls: ca-file, client cert and key)")
    return None


def run(args: argparse.Namespace) -> int:
    from insrail.project.batch import run_batch, run_section_batch

    if args.workers is not None and args.workers < 1:
        print("insrail batch: --workers must be at least 1", file=sys.stderr)
        return 2
    if args.workers is not None and args.scheduler is not None:
        print("insrail batch: --workers is for local processing; the Dask cluster has its own workers",
              file=sys.stderr)
        return 2
    if args.security is not None and args.scheduler is None:
        print("insrail batch: --security is for a Dask scheduler (--scheduler)", file=sys.stderr)
        return 2
    if args.section is not None and len(args.projects) != 1:
        print("insrail batch: --section joins the sections of one PROJECT", file=sys.stderr)
        return 2
    if args.no_reports and args.section is None:
        print("insrail batch: --no-reports is for --section", file=sys.stderr)
        return 2
    problem = scheduler_problem(args.scheduler, args.security)
    if problem:
        print(f"insrail batch: --scheduler {args.scheduler}: {problem}", file=sys.stderr)
        return 2
    security = None
    if args.security is not None:
        from insrail.project.batch import dask_security

        security = dask_security(args.security)
    bar = TerminalProgress("batch")

    def progress(fraction: float, message: ProgressMessage) -> None:
        if not bar.tty:  # plain lines in logs: one per finished survey
            print(f"batch: {100 * fraction:3.0f} %  {message}", file=sys.stderr, flush=True)
        else:
            bar(fraction, message)

    project, names = None, []
    if args.section is not None:
        from insrail.cli.section import section_names
        from insrail.project import load_project

        project = load_project(args.projects[0])
        names = section_names(project, args.section)
        if names is None:
            return 1
    try:
        if project is None:
            outcomes, sections = run_batch(args.projects, workers=args.workers, scheduler=args.scheduler,
                                           progress=progress, security=security), []
        else:
            outcomes, sections = run_section_batch(project, names, workers=args.workers, scheduler=args.scheduler,
                                                   progress=progress, security=security)
    except RuntimeError as error:  # no Dask installed
        print(f"insrail batch: {error}", file=sys.stderr)
        return 2
    except OSError as error:  # a scheduler that cannot be reached
        print(f"insrail batch: cannot reach the scheduler {args.scheduler}: {error}", file=sys.stderr)
        return 2
    except ValueError as err:  # the join refused the runs (e.g. one without a valid sleeper)
        print(f"insrail batch: {err}", file=sys.stderr)
        return 1
    failed = [o for o in outcomes if not o.ok]
    for outcome in outcomes:
        state = f"ok     {outcome.elapsed_s:7.1f} s  {outcome.detail}" if outcome.ok else f"FAILED  {outcome.detail}"
        print(f"{outcome.label:<32} {state}")
    print(f"{len(outcomes) - len(failed)} of {len(outcomes)} surveys processed"
          + (f", {len(failed)} failed" if failed else ""))
    if failed:
        if project is not None:
            print(f"insrail batch: section {', '.join(names)} not joined: a run failed", file=sys.stderr)
        return 1
    _show_sections(project, sections, args.no_reports)
    return 0


def _show_sections(project, sections, no_reports: bool) -> None:
    from insrail.cli.section import show_section, write_section_reports

    for result in sections:
        show_section(result)
        if not no_reports:
            write_section_reports(project, result.name)
