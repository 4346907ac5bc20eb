"""Work around a reference-count bug of the installed Qt binding on Python 3.11.

shiboken6 6.12 (PySide6 6.12, an abi3 wheel) returns ``None`` from every void method without a new
reference, as if ``None`` were immortal (true from Python 3.12 on). On 3.11 each ``painter.setPen()``
takes one reference away; after a few minutes of panning a plot ``None`` is deallocated and the
interpreter aborts ("Fatal Python error: none_dealloc"). ``True``/``False`` suffer the same at exit.
Giving the three singletons a reference count no session can exhaust (2**40) makes them immortal as
on 3.12. Remove this module once the project requires Python >= 3.12 or a fixed PySide6.
"""

from __future__ import annotations

import ctypes
import sys

IMMORTAL_REFERENCES = 1 << 40


def make_singletons_immortal() -> None:
    if sys.version_info >= (3, 12) or sys.implementation.name != "cpython":
        return
    for singleton in (None, True, False):
        count = ctypes.c_ssize_t.from_address(id(singleton))  # ob_refcnt is PyObject's first field
        if count.value < IMMORTAL_REFERENCES:
            count.value += IMMORTAL_REFERENCES
