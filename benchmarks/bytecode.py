"""The environment of a timed insrail command: its modules' bytecode compiled once, as installed.

An installed insrail (pip's wheel install, the installer's bundle) runs from compiled bytecode; an
editable checkout under ``PYTHONDONTWRITEBYTECODE=1`` (as this machine's sessions run) compiles some 140
modules at every start, some 0.5 s that no user pays. The benchmarks therefore time the commands with
their bytecode compiled beforehand into a folder of their own (``PYTHONPYCACHEPREFIX``): the checkout
stays untouched, and the start-up they print is a user's.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent


def installed_env(env: dict[str, str], pycache: Path) -> dict[str, str]:
    """``env`` with insrail's bytecode compiled into ``pycache`` and read from there (module docstring)."""
    env = {key: value for key, value in env.items() if key != "PYTHONDONTWRITEBYTECODE"}
    env["PYTHONPYCACHEPREFIX"] = str(pycache)
    subprocess.run([sys.executable, "-m", "compileall", "-q", str(REPO / "insrail")], env=env, check=True)
    return env
