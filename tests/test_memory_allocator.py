"""The C allocator's settings (insrail.memory): in effect under glibc, harmless elsewhere."""

from __future__ import annotations

import subprocess
import sys
import textwrap

import pytest

from insrail import memory

# A fresh interpreter (the thresholds are per process and fixed for good once set): glibc's
# dynamic threshold is first raised by freeing a mapped 16 MiB block, then a 4 MiB block is taken
# and the number of mapped blocks (mallinfo2's hblks) tells whether it got a mapping of its own.
PROBE = textwrap.dedent("""
    import ctypes, sys
    from insrail.memory import glibc, tune_allocator
    libc = glibc()
    class Info(ctypes.Structure):
        _fields_ = [(name, ctypes.c_size_t) for name in
                    ("arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks", "fsmblks", "uordblks", "fordblks",
                     "keepcost")]
    libc.mallinfo2.restype = Info
    libc.malloc.restype = ctypes.c_void_p
    libc.malloc.argtypes = [ctypes.c_size_t]
    libc.free.argtypes = [ctypes.c_void_p]
    libc.free(libc.malloc(16 << 20))
    tuned = tune_allocator() if sys.argv[1] == "tune" else None
    before = libc.mallinfo2().hblks
    block = libc.malloc(4 << 20)
    mapped = libc.mallinfo2().hblks - before
    libc.free(block)
    print(tuned, mapped)
""")


def _probe(mode: str) -> list[str]:
    out = subprocess.run([sys.executable, "-c", PROBE, mode], capture_output=True, text=True, check=True)
    return out.stdout.split()


@pytest.mark.skipif(memory.glibc() is None or not hasattr(memory.glibc(), "mallinfo2"),
                    reason="glibc >= 2.33 only")
def test_fixed_threshold_maps_a_block_the_dynamic_one_keeps_on_the_heap():
    assert _probe("plain") == ["None", "0"]  # the dynamic threshold rose to 16 MiB: 4 MiB on the heap
    assert _probe("tune") == ["True", "1"]  # fixed at 2 MiB: its own mapping, returned when freed


class FakeLibc:
    def __init__(self, answer: int):
        self.answer, self.calls, self.trimmed = answer, [], 0

    def mallopt(self, param, value):
        self.calls.append((param.value, value.value))
        return self.answer

    def malloc_trim(self, pad):
        self.trimmed += 1
        return 1


def test_settings_and_a_refusal_reported():
    accepted, refused = FakeLibc(1), FakeLibc(0)
    assert memory.tune_allocator(accepted) is True
    assert accepted.calls == [(-3, 2 << 20), (-1, 4 << 20)]
    assert memory.tune_allocator(refused) is False
    memory.release_free_memory(accepted)
    assert accepted.trimmed == 1


def test_without_glibc_nothing_happens(monkeypatch):
    monkeypatch.setattr(memory, "glibc", lambda: None)
    assert memory.tune_allocator() is False
    memory.release_free_memory()  # nothing raised


@pytest.mark.skipif(memory.glibc() is None, reason="glibc only")
def test_glibc_is_found_without_searching_the_library_path(monkeypatch):
    """The C library is the process's own (no `ldconfig -p` run by ctypes.util.find_library at every start)."""
    import ctypes.util

    def no_search(name):
        raise AssertionError(f"find_library({name!r}) searched the library path")

    monkeypatch.setattr(ctypes.util, "find_library", no_search)
    libc = memory.glibc.__wrapped__()
    assert hasattr(libc, "mallopt") and hasattr(libc, "malloc_trim")
