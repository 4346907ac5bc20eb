"""Atomic file writing: a file the user saves is either the old one or the complete new one.

The data goes to a temporary file in the destination folder (same file system, so
``os.replace`` is an atomic rename), is flushed and fsync'ed, and only then replaces
the destination. On any exception the temporary file is removed and the destination
is left untouched.

Only a regular file (or a new path) is ever replaced: a device, FIFO, socket or folder given
as the output is refused (:class:`NotARegularFile`) before anything is written, so that
``--out /dev/full`` run as root does not swap the device node for a CSV. A symbolic link to a
regular file is replaced by the new file, as editors do.

Temporary files are named ``.<name>.<random>.tmp`` and held under an exclusive ``flock`` while
written; a writer killed mid-write leaves its temporary behind, unlocked, and the next write of
the same file removes it (:func:`remove_dead_temporaries`). A temporary still locked belongs to a
writer alive in another process and is left alone.
"""

from __future__ import annotations

import contextlib
import errno
import os
import stat
import tempfile
import time
from pathlib import Path
from typing import IO, Iterator

try:
    import fcntl
except ImportError:  # Windows: no flock; its temporaries are not cleaned by a later write
    fcntl = None

#: A temporary younger than this [s] and still empty may be one whose writer has not yet taken
#: its lock (mkstemp and flock are two calls): never removed.
FRESH_TEMPORARY_S = 5.0

_KINDS = ((stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
          (stat.S_ISSOCK, "a socket"), (stat.S_ISDIR, "a folder"))


class NotARegularFile(OSError):
    """An output path that exists and is not a regular file (nothing was written)."""

    def __init__(self, path: Path, kind: str):
        super().__init__(errno.EINVAL, f"{kind}, not a regular file: refused as an output (nothing written)", str(path))


def check_output_path(path: str | Path) -> Path:
    """``path`` when it is new or a regular file (through symbolic links); :class:`NotARegularFile` otherwise."""
    path = Path(path)
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        return path
    if stat.S_ISREG(mode):
        return path
    kind = next((name for test, name in _KINDS if test(mode)), "not a regular file")
    raise NotARegularFile(path, kind)


def remove_dead_temporaries(path: Path, now: float | None = None) -> list[Path]:
    """Remove the temporaries of ``path`` left by killed writers (unlocked; see the module docstring)."""
    now = time.time() if now is None else now
    removed = []
    if fcntl is None:
        return removed
    try:
        candidates = list(path.parent.glob(f".{_glob_escape(path.name)}.*.tmp"))
    except OSError:
        return removed
    for item in candidates:
        try:
            info = os.lstat(item)
            if not stat.S_ISREG(info.st_mode) or (info.st_size == 0 and now - info.st_mtime < FRESH_TEMPORARY_S):
                continue
            fd = os.open(item, os.O_RDONLY | os.O_NOFOLLOW)
        except OSError:
            continue
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            os.unlink(item)
            removed.append(item)
        except OSError:  # locked: a writer alive elsewhere; or not ours to remove
            pass
        finally:
            os.close(fd)
    return removed


def _glob_escape(name: str) -> str:
    return "".join(f"[{c}]" if c in "*?[" else c for c in name)


@contextlib.contextmanager
def atomic_write(path: str | Path, mode: str = "w", *, encoding: str | None = "utf-8",
                 newline: str | None = "\n") -> Iterator[IO]:
    """Open a temporary sibling of ``path`` for writing; move it onto ``path`` on success.

    ``mode`` is "w" (text) or "wb" (binary). Text files get "\\n" line endings on
    every platform so files compare equal across machines. ``path`` must be new or a
    regular file (:func:`check_output_path`).
    """
    if mode not in ("w", "wb"):
        raise ValueError(f"atomic_write mode must be 'w' or 'wb', not {mode!r}")
    path = check_output_path(path)
    remove_dead_temporaries(path)
    try:
        fd, tmp_name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    except OSError as err:
        raise naming(err, path) from None
    if fcntl is not None:
        fcntl.flock(fd, fcntl.LOCK_EX)  # held until closed: tells remove_dead_temporaries this writer is alive
    text_args = {"encoding": encoding, "newline": newline} if mode == "w" else {}
    try:
        # mkstemp creates the file private (0600); a saved file keeps the mode of the
        # one it replaces, or gets the usual rw-r--r--.
        os.chmod(tmp_name, path.stat().st_mode & 0o777 if path.exists() else 0o644)
        with os.fdopen(fd, mode, **text_args) as handle:
            yield handle
            handle.flush()
            os.fsync(handle.fileno())
            check_output_path(path)  # the same check, just before the rename: a node made meanwhile
            os.replace(tmp_name, path)
    except OSError as err:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp_name)
        raise naming(err, path) from None
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp_name)
        raise


def save_npy(path: str | Path, array) -> None:
    """``array`` as ``np.save`` writes it, atomically (:func:`atomic_write`); a full disk raises ENOSPC naming ``path``.

    The data goes through the file object, not numpy's own writer (``ndarray.tofile``, which ``np.save``
    uses on a real file): that one reports a full disk as an OSError with neither errno nor file name
    ("Not enough free space to write 24737240 bytes after offset 256"), which no one can act on.
    """
    import numpy as np

    array = np.asarray(array, order="C")  # a Fortran-ordered array is saved in C order: read back the same
    if array.dtype.hasobject:  # its buffer holds pointers; np.save would pickle it, which no reader here allows
        raise ValueError(f"{path}: an array of Python objects cannot be saved")
    with atomic_write(path, "wb") as handle:
        np.lib.format.write_array_header_1_0(handle, np.lib.format.header_data_from_array_1_0(array))
        handle.write(array)  # its bytes, in place (any dtype: a plain buffer)


def write_at(path: str | Path, fd: int, data, offset: int) -> None:
    """All of ``data`` (a buffer) at ``offset`` of the open file ``fd`` of ``path`` (``os.pwrite``); an OSError names
    ``path``. A regular file takes it all at once but at the end of the disk's space: there a part, then ENOSPC."""
    data = memoryview(data).cast("B")
    while data:
        done = named_write(path, os.pwrite, fd, data, offset)
        if not done:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))
        data, offset = data[done:], offset + done


def naming(err: OSError, path: str | Path) -> OSError:
    """``err`` naming ``path`` when it names no file (a full disk names none): what a writer raises."""
    if err.filename:
        return err
    return OSError(err.errno, err.strerror or str(err), str(path))  # no errno: its message is all there is


def named_write(path: str | Path, write, *args):
    """``write(*args)`` of a writer of ``path``; an OSError naming no file (a full disk) names ``path``."""
    try:
        return write(*args)
    except OSError as err:
        raise naming(err, path) from None
