"""Atomic file writing: a file the user saves is either the old one or the complete new one.

The data goes to a temporary file in the destination folder (same file system, so
``os.replace`` is an atomic rename), is flushed and fsync'ed, and only then replaces
the destination. On any exception the temporary file is removed and the destination
is left untouched.
"""

from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path
from typing import IO, Iterator


@contextlib.contextmanager
def atomic_write(path: str | Path, mode: str = "w", *, encoding: str | None = "utf-8",
                 newline: str | None = "\n") -> Iterator[IO]:
    """Open a temporary sibling of ``path`` for writing; move it onto ``path`` on success.

    ``mode`` is "w" (text) or "wb" (binary). Text files get "\\n" line endings on
    every platform so files compare equal across machines.
    """
    if mode not in ("w", "wb"):
        raise ValueError(f"atomic_write mode must be 'w' or 'wb', not {mode!r}")
    path = Path(path)
    fd, tmp_name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    text_args = {"encoding": encoding, "newline": newline} if mode == "w" else {}
    try:
        # mkstemp creates the file private (0600); a saved file keeps the mode of the
        # one it replaces, or gets the usual rw-r--r--.
        os.chmod(tmp_name, path.stat().st_mode & 0o777 if path.exists() else 0o644)
        with os.fdopen(fd, mode, **text_args) as handle:
            yield handle
            handle.flush()
            os.fsync(handle.fileno())
        os.replace(tmp_name, path)
    except OSError as err:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp_name)
        if err.filename:
            raise
        raise OSError(err.errno, err.strerror, str(path)) from None  # a full disk names no file: this one
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp_name)
        raise
