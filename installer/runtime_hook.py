"""Runs inside the bundle before insrail is imported.

numba caches compiled kernels beside the sources, which in an installed bundle are read-only
(and, frozen, absent): numba then falls back to a per-user cache. Point it at insrail's own cache
folder, and at a temporary one when even that is not writable, so the first run never fails.
"""

import os
import sys
import tempfile
from pathlib import Path


def _writable(folder: Path) -> bool:
    try:
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=folder):
            return True
    except OSError:
        return False


if "NUMBA_CACHE_DIR" not in os.environ:
    base = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
    if sys.platform == "win32":
        base = Path(os.environ.get("LOCALAPPDATA") or base)
    cache = base / "insrail" / "numba"
    if not _writable(cache):
        cache = Path(tempfile.gettempdir()) / f"insrail-numba-{os.getuid() if hasattr(os, 'getuid') else 'user'}"
    os.environ["NUMBA_CACHE_DIR"] = str(cache)
