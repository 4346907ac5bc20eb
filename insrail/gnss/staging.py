"""Every file RTKLIB sees goes under a name insrail made, in a private temporary folder.

Why: RTKLIB (inside pyrtklib) decompresses its RINEX inputs by *name*, through the shell:
a file ending in ``.gz``/``.Z``/``.zip``/``.tar``, ``.crx`` or with a fourth extension
letter ``d`` (``.05d``, Hatanaka) is handed to ``system("gzip -d -c \\"NAME\\" ...")`` or
``crx2rnx``; it also expands ``*`` wildcards and ``%Y``-style keywords in names. A name
taken from a project someone handed over (``[gnss_raw]`` in survey.toml) or from the
command line would then run as a command. So insrail never passes a user's path:

* :func:`rtklib_workdir` makes a private folder (``mkdtemp``, mode 0700) whose path holds
  only ``[A-Za-z0-9_./-]``, and removes it afterwards;
* :func:`stage_file` puts each input there under a fixed safe name (``rover.obs``,
  ``nav1.nav``, ``precise1.sp3``...): decompressed in Python when it is gzip or Unix
  ``compress`` (recognised by their magic bytes, not the name), Compact RINEX (Hatanaka)
  restored with the ``hatanaka`` package (refused with a message when it is not
  installed), otherwise a symbolic link (a copy where links are not possible);
* :func:`install_output` moves what RTKLIB wrote there to the user's destination
  atomically (temporary sibling, fsync, rename).

Errors name the user's file, never the staged name.

Decompression is bounded (:func:`decompressed_limit`): RINEX compresses 3 to 10 times, so a file that
inflates past :data:`MAX_DECOMPRESSION_RATIO` times its size (and past :data:`MIN_DECOMPRESSED_LIMIT`),
or past :data:`MAX_DECOMPRESSED_BYTES` (more than a 20 Hz multi-GNSS day), is refused naming the file
and the limit, after writing no more than the limit: a 13 MB "decompression bomb" that would inflate to
3 GB, and then be read by RTKLIB into memory, stops at a few hundred megabytes on disk.
"""

from __future__ import annotations

import contextlib
import gzip
import os
import re
import shutil
import tempfile
import zlib
from collections.abc import Iterator
from pathlib import Path

from insrail.io.errors import InputError

_SAFE_PATH = re.compile(r"[A-Za-z0-9_./-]+")
_SAFE_SUFFIX = re.compile(r"\.[a-z0-9]{1,4}")
# Suffixes RTKLIB would decompress through the shell (rtk_uncompress): never on a staged name.
_COMPRESSED_SUFFIXES = (".z", ".gz", ".zip", ".tar", ".crx")
_GZIP_MAGIC, _COMPRESS_MAGIC, _ZIP_MAGIC = b"\x1f\x8b", b"\x1f\x9d", b"PK\x03\x04"
_CRINEX_LABEL = "CRINEX VERS   / TYPE"
MAX_DECOMPRESSION_RATIO = 50
MIN_DECOMPRESSED_LIMIT = 256 << 20
MAX_DECOMPRESSED_BYTES = 4 << 30


def decompressed_limit(compressed_bytes: int) -> int:
    """The most bytes a compressed input of ``compressed_bytes`` may inflate to (module docstring)."""
    return min(MAX_DECOMPRESSED_BYTES, max(MIN_DECOMPRESSED_LIMIT, MAX_DECOMPRESSION_RATIO * compressed_bytes))


class _BoundedOutput:
    """A binary file that refuses (InputError naming ``source``) to grow past ``limit`` bytes."""

    def __init__(self, handle, source: Path, limit: int):
        self.handle, self.source, self.limit, self.written = handle, source, limit, 0

    def write(self, data) -> int:
        self.written += len(data)
        if self.written > self.limit:
            raise InputError(self.source, None, "inflates to more than {limit_mib:,.0f} MiB "
                             "({st_size:,} bytes compressed; the limit is "
                             "{max_decompression_ratio} times the compressed size, at least "
                             "{min_mib} MiB, at most {max_gib} GiB): "
                             "not a plausible RINEX file (a damaged or hostile archive?)", fields={"limit_mib": self.limit / 2**20, "st_size": self.source.stat().st_size, "max_decompression_ratio": MAX_DECOMPRESSION_RATIO, "min_mib": MIN_DECOMPRESSED_LIMIT >> 20, "max_gib": MAX_DECOMPRESSED_BYTES >> 30})
        return self.handle.write(data)


@contextlib.contextmanager
def rtklib_workdir() -> Iterator[Path]:
    """A private temporary folder with a shell-safe absolute path, removed on exit."""
    folder = Path(tempfile.mkdtemp(prefix="insrail-rtklib-"))
    try:
        if not _SAFE_PATH.fullmatch(str(folder)):
            raise OSError(f"the temporary folder {folder} has characters RTKLIB cannot be given safely; "
                          "set TMPDIR to a plain path (letters, digits, _ . / -)")
        yield folder
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def safe_suffix(name: str, default: str) -> str:
    """The file's last suffix when harmless for RTKLIB (lower case, 1-4 letters or digits), else ``default``.

    ``.sp3``/``.clk``/``.atx`` tell RTKLIB the product type, so they are kept; a suffix RTKLIB
    would decompress (``.gz``, ``.Z``, ``.05d``...) is never kept.
    """
    suffix = Path(name).suffix.lower()
    if (not _SAFE_SUFFIX.fullmatch(suffix) or suffix in _COMPRESSED_SUFFIXES
            or (len(suffix) == 4 and suffix[3] == "d")):
        return default
    return suffix


def _magic(path: Path) -> bytes:
    with open(path, "rb") as handle:
        return handle.read(4)


def _decompressed_name(path: Path) -> str:
    """``igs13160.sp3.Z`` -> ``igs13160.sp3``: the name the file has once decompressed."""
    return path.stem if path.suffix.lower() in _COMPRESSED_SUFFIXES else path.name


def stage_file(source: str | Path, workdir: Path, stem: str, default_suffix: str) -> Path:
    """``source`` as ``workdir/<stem><suffix>``, decompressed when compressed; InputError naming ``source``."""
    source = Path(source)
    if not source.is_file():
        raise InputError(source, None, "file not found")
    try:
        magic = _magic(source)
    except OSError as err:
        raise InputError(source, None, "cannot read the file: {strerror}", fields={"strerror": err.strerror}) from None
    name = source.name
    if magic[:2] in (_GZIP_MAGIC, _COMPRESS_MAGIC):
        name = _decompressed_name(source)
    target = workdir / f"{stem}{safe_suffix(name, default_suffix)}"
    limit = decompressed_limit(source.stat().st_size)
    if magic[:2] == _GZIP_MAGIC:
        try:
            with gzip.open(source, "rb") as packed, open(target, "wb") as plain:
                shutil.copyfileobj(packed, _BoundedOutput(plain, source, limit), 1 << 20)
        except (OSError, EOFError, zlib.error) as err:
            raise InputError(source, None, "damaged gzip file: {err}", fields={"err": err}) from None
    elif magic[:2] == _COMPRESS_MAGIC:
        _uncompress_z(source, target, limit)
    elif magic == _ZIP_MAGIC:
        raise InputError(source, None, "a zip archive: unpack it and give the RINEX files it holds")
    else:
        try:
            os.symlink(source.resolve(), target)
        except OSError:
            shutil.copyfile(source, target)
    if _is_compact_rinex(target):
        _restore_hatanaka(source, target)
    return target


def _uncompress_z(source: Path, target: Path, limit: int) -> None:
    try:
        import ncompress
    except ImportError:
        raise InputError(source, None, "Unix-compressed (.Z) file and the ncompress package is not installed: "
                         "decompress it first (uncompress / gzip -d)") from None
    try:
        with open(source, "rb") as packed, open(target, "wb") as plain:
            ncompress.decompress(packed, _BoundedOutput(plain, source, limit))
    except InputError:
        raise
    except (OSError, ValueError) as err:
        raise InputError(source, None, "damaged .Z (compress) file: {err}", fields={"err": err}) from None


def _is_compact_rinex(path: Path) -> bool:
    with open(path, "rb") as handle:
        first = handle.readline(200).decode("ascii", errors="replace")
    return first[60:].strip() == _CRINEX_LABEL.strip()


def _restore_hatanaka(source: Path, target: Path) -> None:
    """Compact RINEX (Hatanaka) -> RINEX in place, with the maintained ``hatanaka`` package."""
    try:
        import hatanaka
    except ImportError:
        raise InputError(source, None, "Compact RINEX (Hatanaka) and the hatanaka package is not installed: "
                         "pip install hatanaka, or restore it with CRX2RNX first") from None
    if target.stat().st_size > MAX_DECOMPRESSED_BYTES // 4:  # restored in memory, about 4 times larger
        raise InputError(source, None, "Compact RINEX of more than {limit_gib} GiB: "
                         "restore it with CRX2RNX first", fields={"limit_gib": (MAX_DECOMPRESSED_BYTES // 4) >> 30})
    try:
        plain = hatanaka.crx2rnx(target.read_bytes())
    except hatanaka.HatanakaException as err:
        raise InputError(source, None, "damaged Compact RINEX (Hatanaka) file: {err}", fields={"err": err}) from None
    target.unlink()  # may be a link to the user's file: never write through it
    target.write_bytes(plain)


def install_output(produced: Path, destination: Path) -> None:
    """Copy ``produced`` onto ``destination`` atomically (temporary sibling, fsync, rename)."""
    fd, tmp_name = tempfile.mkstemp(prefix=f".{destination.name}.", suffix=".tmp", dir=destination.parent)
    try:
        with os.fdopen(fd, "wb") as out, open(produced, "rb") as data:
            shutil.copyfileobj(data, out, 1 << 20)
            out.flush()
            os.fsync(out.fileno())
        os.chmod(tmp_name, 0o644)
        os.replace(tmp_name, destination)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp_name)
        raise
