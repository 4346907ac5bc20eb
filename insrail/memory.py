"""The C allocator set for long surveys (glibc only; a no-op elsewhere).

glibc's malloc serves a block larger than its mmap threshold with its own mapping, returned to the
system when freed. The threshold starts at 128 KiB but rises, after the first large block is
freed, up to 32 MiB: the 8-30 MB whole-run arrays of a stage then live on the heap and stay
resident after they are freed (measured on the 10 km survey: 110-150 MB more in every stage after
the track reconstruction, docs/memory_plan.md). :func:`tune_allocator` fixes the thresholds, as
``MALLOC_MMAP_THRESHOLD_=2097152 MALLOC_TRIM_THRESHOLD_=4194304`` would; :func:`release_free_memory`
gives the heap's free pages back at the end of a stage.

Python's cyclic garbage collector, too, is set for a command's start-up (:func:`collector_paused`).

Why 2 MiB and not lower: every block above the threshold is a fresh mapping whose pages the kernel
must fault in and zero. On `long` (fusion cached; track, assessment, adjustment and result files),
glibc's defaults took 17.1-17.9 s user + 1.0-1.7 s system CPU with stage peaks 840/396/529/541 MB;
256 KiB / 1 MiB took 17.7-18.0 + 5.5-6.9 s for 827/287/371-381/345 MB; 2 MiB / 4 MiB 16.7-17.5 +
3.0-3.6 s for 828/287/392-401/346-349 MB (the chunk buffers of a streamed stage, ~1 MiB, stay on the
heap and are reused).
"""

from __future__ import annotations

import ctypes
import functools
import gc
import os
from collections.abc import Iterator
from contextlib import contextmanager

#: glibc's mallopt parameter numbers (malloc.h).
M_TRIM_THRESHOLD = -1
M_MMAP_THRESHOLD = -3
#: Blocks from this size on get their own mapping (freed at once); the heap's free top is given
#: back from this size on.
MMAP_THRESHOLD_BYTES = 2 * 1024 * 1024
TRIM_THRESHOLD_BYTES = 4 * 1024 * 1024


@functools.cache
def glibc() -> ctypes.CDLL | None:
    """The process's C library when it is glibc (None otherwise: musl, macOS, Windows)."""
    try:
        os.confstr("CS_GNU_LIBC_VERSION")
    except (AttributeError, ValueError, OSError):
        return None
    # the process's own symbols, glibc's among them: ctypes.util.find_library("c") runs `ldconfig -p`, some
    # 40 ms of every command's start
    return ctypes.CDLL(None)


def tune_allocator(libc: ctypes.CDLL | None = None) -> bool:
    """Fix glibc's mmap and trim thresholds (once per process, before the large arrays). True when
    glibc took both settings; False without glibc or when it refused one (memory is then held
    longer, the results are the same)."""
    libc = libc or glibc()
    if libc is None:
        return False
    applied = [libc.mallopt(ctypes.c_int(param), ctypes.c_int(value)) == 1
               for param, value in ((M_MMAP_THRESHOLD, MMAP_THRESHOLD_BYTES), (M_TRIM_THRESHOLD, TRIM_THRESHOLD_BYTES))]
    return all(applied)


def release_free_memory(libc: ctypes.CDLL | None = None) -> None:
    """Give the heap's free pages back to the system (``malloc_trim(0)``; nothing without glibc)."""
    libc = libc or glibc()
    if libc is not None:
        libc.malloc_trim(ctypes.c_size_t(0))


@contextmanager
def collector_paused() -> Iterator[None]:
    """Python's cyclic garbage collector off within the block, a command's start-up; then what the
    block made is frozen out of its later passes (``gc.freeze``) and it runs again as before.

    Why: the imports and the numba kernels loaded from their cache make some 400,000 objects that live
    as long as the process (modules, functions, types, numba's typing registries). The collector's
    passes are triggered by the count of new objects, and each full pass walks all of them again: on
    `insrail fuse` of the short survey 0.09 s of CPU time, a twentieth of the command. Nothing of a
    start-up is garbage in a cycle worth a pass (a few frames of a caught exception at most)."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        gc.freeze()
        if enabled:
            gc.enable()
