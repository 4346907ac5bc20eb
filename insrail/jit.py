"""insrail's compiled (numba) functions: cached on disk, and loaded from that cache without numba's compiler set-up.

:func:`cached_njit` is ``numba.njit(cache=True, ...)`` with one difference, in how a kernel is loaded from the
on-disk cache. numba's cache loads a kernel only after ``target_context.refresh()``: the set-up its *compiler*
needs, the typing and lowering registries of every numba extension (numba.np.arraymath, numba.np.linalg,
numba.typed, numba.experimental, the random generators, ...), which imports them all, numba.np.arraymath's BLAS
check importing scipy.linalg and through scipy's array-API layer numpy.f2py and numpy.testing. A cached kernel is
machine code that needs none of it: only the runtime it links against (``rtsys.initialize``, numba's reference
counting and allocation, which the full refresh begins with too) and the modules named by the environments
pickled with it (imported as they are unpickled). In a fresh process the refresh took 0.3 s of CPU time, half of it
importing numba.np.arraymath with scipy.linalg: a seventh of `insrail fuse` on the short survey (2.4 s). A kernel's
environment naming numba.np.arraymath imports it all the same (the forward kernel's searchsorted is written out for
that: ``insrail.nav.fusion._first_not_below``).

A kernel not in the cache (the first run, a new signature, a changed source) is compiled as numba always does:
the compiler refreshes the registries itself (``numba.core.compiler.compile_extra``). The loaded machine code
and so the results are the same either way.

The kernels' linear algebra (``@``, ``np.linalg.solve``) runs scipy's BLAS and LAPACK, which numba's C helpers
find by importing ``scipy.linalg.cython_blas`` and ``scipy.linalg.cython_lapack`` at the first call. Importing them
the usual way runs the package ``scipy.linalg`` first: its whole namespace, scipy's array-API layer, numpy.f2py and
numpy.testing, 0.16 s of CPU time for two extension modules that need none of it (they link to the BLAS library
themselves). :func:`_load_scipy_blas` loads the two modules alone into ``sys.modules`` when this module is imported,
where numba's import finds them (a later ``import scipy.linalg`` imports the package as always, and
``scipy.linalg.cython_blas`` is then the module loaded here).

What a first run compiles (an install's, every CI run's: most of a first `insrail process`'s CPU time) the
kernels keep small by three rules. No slice assignment between arrays (``a[:] = b``, ``a[i] = row``): numba
compiles with each the message of a shape mismatch, both shapes formatted into a string, which pulls in its
string formatting (str of an integer, join, ...), seconds for the first of each dimension; the kernels copy element
by element (:func:`copy_rows`), and call np.linalg.solve's LAPACK routine themselves, as solve copies its input so
(``insrail.nav.kalman.solve_transposed``). One signature per kernel: a constant integer argument is a type of its
own (``Literal[int]``; ``np.int64(0)`` is not), as is each layout and writability of an array, and each signature
is compiled anew. And scalar code is math's (``math.isfinite``, ``abs``), not numpy's ufuncs, each of which is
compiled too. None of it changes an operation or its order: the results are the same to the bit.

The loader uses two private methods of numba's cache (``_guard_against_spurious_io_errors``,
``_load_overload``, as in numba 0.68): tests/test_jit.py loads a kernel so in a fresh process, runs it and checks
that the registries and scipy.linalg stay unloaded.
"""

from __future__ import annotations

import importlib.machinery
import importlib.util
import sys
from collections.abc import Callable

from numba import njit
from numba.core.caching import FunctionCache
from numba.core.runtime import rtsys


#: numba's cache has the private methods the loader calls (numba 0.59-0.68 have): a numba without them loads
#: kernels its own way, with the compiler's set-up, only slower
_NUMBA_CACHE_AS_KNOWN = all(hasattr(FunctionCache, name) for name in ("_guard_against_spurious_io_errors", "_load_overload"))


class _CachedMachineCode(FunctionCache):
    """numba's per-function disk cache, whose load skips the compiler's registries (module docstring)."""

    def load_overload(self, sig, target_context):
        rtsys.initialize(target_context)  # the runtime the cached code calls (idempotent)
        with self._guard_against_spurious_io_errors():
            return self._load_overload(sig, target_context)
        # None (not in the cache) when the guard swallowed an error, as numba's own load_overload


def cached_njit(**options) -> Callable:
    """``numba.njit(cache=True, **options)`` as a decorator, loading from the cache as the module docstring says."""

    def decorate(function):
        dispatcher = njit(cache=True, **options)(function)
        if _NUMBA_CACHE_AS_KNOWN:
            dispatcher._cache = _CachedMachineCode(dispatcher.py_func)
        return dispatcher

    return decorate


@cached_njit(nogil=True)
def copy_rows(source, out):  # pragma: no cover - compiled
    """out[:, :] = source for 2-d arrays of one shape, element by element (module docstring). Callers pass views
    of whole rows, C-ordered and writable like the arrays they come from: one signature for every caller."""
    for r in range(source.shape[0]):
        for c in range(source.shape[1]):
            out[r, c] = source[r, c]


def _load_scipy_blas() -> None:
    """``scipy.linalg.cython_blas`` and ``scipy.linalg.cython_lapack`` into ``sys.modules`` without the package
    ``scipy.linalg`` (module docstring). Where they cannot be found so (a bundle that keeps them elsewhere), or
    the package is imported already, nothing is done: numba then imports them the usual way."""
    if "scipy.linalg" in sys.modules:
        return
    try:
        folders = importlib.util.find_spec("scipy.linalg").submodule_search_locations
    except ImportError:  # no scipy: numba says so at the first call that needs it
        return
    for name in ("cython_blas", "cython_lapack"):  # cython_lapack calls into cython_blas
        qualified = f"scipy.linalg.{name}"
        found = importlib.machinery.PathFinder.find_spec(name, folders)
        if qualified in sys.modules or found is None or not isinstance(found.loader, importlib.machinery.ExtensionFileLoader):
            return
        spec = importlib.util.spec_from_file_location(qualified, found.origin)
        module = importlib.util.module_from_spec(spec)
        sys.modules[qualified] = module
        try:
            spec.loader.exec_module(module)
        except BaseException:
            del sys.modules[qualified]
            raise


_load_scipy_blas()
