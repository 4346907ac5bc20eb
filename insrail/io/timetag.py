"""RTKLIB's time tag (``<file>.tag``): when each byte of a logged stream arrived, on GPST.

RTKLIB's stream server writes it beside a file it logs with ``::T``. Layout (little-endian):
a 60-byte text header (``TIMETAG RTKLIB <version>``), uint32 ``tick_f`` (the logger's millisecond
tick when the file was opened), the GPST of that moment as uint32 seconds since 1970-01-01
(counted like Unix time, no leap seconds) and a float64 fraction of a second, then one pair per
write: uint32 tick [ms] and the file position reached [bytes], uint32 (or uint64 in RTKLIB's
``::P=8`` form). Ticks are counted from ``tick_f`` (ticks at or beyond ``tick_f`` are taken as
absolute and ``tick_f`` is subtracted).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from insrail.io.errors import InputError

HEADER_BYTES = 60
MAGIC = b"TIMETAG RTKLIB"
_FIXED = HEADER_BYTES + 4 + 4 + 8


@dataclass(frozen=True)
class TimeTag:
    """start_unix_gpst_s + start_fraction_s: the GPST (Unix-style count) at tick 0;
    ticks_ms (n,) since then; file_positions (n,) bytes of the logged file written by each tick."""

    path: Path
    start_unix_gpst_s: int
    start_fraction_s: float
    ticks_ms: np.ndarray
    file_positions: np.ndarray

    @property
    def span_s(self) -> float:
        """From the file's opening to its last write [s]."""
        return float(self.ticks_ms[-1]) / 1e3


def _pairs(body: bytes, position_bytes: int) -> tuple[np.ndarray, np.ndarray] | None:
    size = 4 + position_bytes
    if len(body) % size:
        return None
    table = np.frombuffer(body, dtype=np.dtype([("tick", "<u4"), ("position", f"<u{position_bytes}")]))
    ticks, positions = table["tick"].astype(np.int64), table["position"].astype(np.int64)
    if np.any(np.diff(ticks) < 0) or np.any(np.diff(positions) < 0):
        return None
    return ticks, positions


def read_time_tag(path: str | Path) -> TimeTag:
    """Read an RTKLIB ``.tag`` file; InputError naming it for anything else."""
    path = Path(path)
    try:
        data = path.read_bytes()
    except FileNotFoundError:
        raise InputError(path, None, "file not found: the record's RTKLIB time tag (<file>.tag) is needed to put "
                         "its logger clock on GPST") from None
    except OSError as exc:
        raise InputError(path, None, "cannot be read: {reason}", fields={"reason": exc.strerror or exc}) from None
    if not data.startswith(MAGIC) or len(data) < _FIXED:
        raise InputError(path, None, "not an RTKLIB time tag: expected a {header_bytes}-byte header starting "
                         "{magic!r} and the start time", fields={"header_bytes": HEADER_BYTES, "magic": MAGIC.decode()})
    tick_f = int(np.frombuffer(data, "<u4", 1, HEADER_BYTES)[0])
    start = int(np.frombuffer(data, "<u4", 1, HEADER_BYTES + 4)[0])
    fraction = float(np.frombuffer(data, "<f8", 1, HEADER_BYTES + 8)[0])
    body = data[_FIXED:]
    pairs = _pairs(body, 4) or _pairs(body, 8)
    if pairs is None or not len(pairs[0]):
        raise InputError(path, None, "{count} bytes of ticks and file positions after the header: expected pairs "
                         "of uint32 tick and uint32 (or uint64) file position, both never decreasing", fields={"count": len(body)})
    ticks, positions = pairs
    if ticks[0] >= tick_f > 0:
        ticks = ticks - tick_f
    if not (0.0 <= fraction < 1.0):
        raise InputError(path, None, "start time fraction {fraction!r}: expected 0 <= fraction < 1", fields={"fraction": fraction})
    return TimeTag(path, start, fraction, ticks, positions)
