"""Build the standalone insrail bundle (one folder) with PyInstaller and smoke-test it.

    python installer/build.py [--dist DIR] [--no-smoke]

Writes ``DIR/insrail/`` (default ``build/bundle/insrail``) holding the ``insrail`` executable
(CLI, and the desktop application as ``insrail gui``), the resources and the EGM96 grid; prints
the build time and the bundle size, then runs ``insrail --version``, ``insrail demo`` and the
desktop application on the demo project (offscreen, one window drawn to PNG) from the bundle in a
clean environment (no Python on PATH, read-only bundle, empty HOME).
"""

from __future__ import annotations

import argparse
import shutil
import stat
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def build(dist: Path) -> Path:
    """Run PyInstaller on installer/insrail.spec; returns the bundle folder."""
    import PyInstaller.__main__

    work = dist.parent / "pyinstaller-work"
    PyInstaller.__main__.run([str(ROOT / "installer" / "insrail.spec"), "--noconfirm", "--clean",
                              "--log-level", "WARN", "--distpath", str(dist), "--workpath", str(work)])
    return dist / "insrail"


def folder_size_bytes(folder: Path) -> int:
    return sum(p.stat().st_size for p in folder.rglob("*") if p.is_file() and not p.is_symlink())


def clean_environment(home: Path) -> dict[str, str]:
    """A shell with no Python: an empty PATH, no PYTHON* variables, an empty HOME."""
    env = {"PATH": str(home / "bin"), "HOME": str(home), "LANG": "C.UTF-8", "QT_QPA_PLATFORM": "offscreen"}
    return env


def set_read_only(folder: Path, read_only: bool) -> None:
    write = stat.S_IWUSR | stat.S_IWGRP | stat.S_IWOTH
    for path in [folder, *folder.rglob("*")]:
        if path.is_symlink():
            continue
        mode = path.stat().st_mode
        path.chmod(mode & ~write if read_only else mode | stat.S_IWUSR)


def smoke_test(bundle: Path) -> None:
    """``insrail --version`` and ``insrail demo`` from the read-only bundle in a clean environment."""
    executable = bundle.resolve() / "insrail"
    with tempfile.TemporaryDirectory(prefix="insrail-smoke-") as scratch:
        scratch = Path(scratch)
        env = clean_environment(scratch / "home")
        (scratch / "home" / "bin").mkdir(parents=True)
        set_read_only(bundle, True)
        try:
            for arguments in (["--version"], ["demo", "--out", str(scratch / "demo")],
                              ["gui", str(scratch / "demo"), "--screenshot", str(scratch / "gui.png")]):
                started = time.monotonic()
                run = subprocess.run([str(executable), *arguments], env=env, cwd=scratch, capture_output=True,
                                     text=True, timeout=900)
                print(f"$ insrail {' '.join(arguments)}  ({time.monotonic() - started:.1f} s, exit {run.returncode})")
                print(run.stdout.rstrip())
                if run.returncode != 0:
                    print(run.stderr, file=sys.stderr)
                    raise SystemExit(f"smoke test failed: insrail {' '.join(arguments)} exited {run.returncode}")
            shot = scratch / "gui.png"
            if not shot.is_file() or shot.stat().st_size < 20_000:
                raise SystemExit("smoke test failed: the desktop application drew no window")
            print(f"desktop application started from the bundle; window drawn ({shot.stat().st_size // 1024} KiB PNG)")
        finally:
            set_read_only(bundle, False)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dist", type=Path, default=ROOT / "build" / "bundle", help="output folder")
    parser.add_argument("--no-smoke", action="store_true", help="build only")
    args = parser.parse_args(argv)
    dist = args.dist.resolve()
    if (dist / "insrail").exists():
        set_read_only(dist / "insrail", False)
        shutil.rmtree(dist / "insrail")
    started = time.monotonic()
    bundle = build(dist)
    elapsed = time.monotonic() - started
    print(f"bundle: {bundle}  build time {elapsed:.0f} s  size {folder_size_bytes(bundle) / 2**20:.0f} MiB")
    if not args.no_smoke:
        smoke_test(bundle)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
