"""insrail.jit: a kernel loaded from numba's disk cache in a fresh process runs (its linear algebra on scipy's
BLAS and LAPACK) without numba's compiler registries and without the package scipy.linalg; a later import of
scipy.linalg still works."""

import json
import os
import subprocess
import sys

import numpy as np

KERNEL = '''
import numpy as np
from insrail.jit import cached_njit


@cached_njit(nogil=True)
def gain(p_minus, p_plus, phi):
    """the smoother gain's shape: a LAPACK solve and BLAS products"""
    return np.linalg.solve(np.ascontiguousarray(p_minus.T), np.ascontiguousarray((p_plus @ phi.T).T)).T
'''

#: Runs the kernel, then reports its cache hits, its result and which of the watched modules were imported.
RUN = '''
import json, sys
import numpy as np
import kernel

rng = np.random.default_rng(3)
a = rng.normal(size=(21, 21))
p_minus, p_plus, phi = a @ a.T + 21 * np.eye(21), np.eye(21) * 2.0, np.eye(21) + 0.01 * a
result = kernel.gain(p_minus, p_plus, phi)
watched = ("numba.np.arraymath", "numba.typed.typeddict", "scipy.linalg", "scipy.linalg.cython_lapack", "numpy.f2py")
print(json.dumps({"hits": sum(kernel.gain.stats.cache_hits.values()), "result": result.tolist(),
                  "modules": [m for m in watched if m in sys.modules]}))
'''


def _run(folder, code: str) -> dict:
    env = dict(os.environ, NUMBA_CACHE_DIR=str(folder / "cache"), PYTHONPATH=str(folder))
    done = subprocess.run([sys.executable, "-c", code], cwd=folder, env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout.splitlines()[-1])


def test_a_cached_kernel_loads_without_the_compilers_registries_nor_scipy_linalg(tmp_path):
    (tmp_path / "kernel.py").write_text(KERNEL)
    compiled = _run(tmp_path, RUN)
    assert compiled["hits"] == 0 and "numba.np.arraymath" in compiled["modules"]  # compiled: the full set-up
    loaded = _run(tmp_path, RUN)
    assert loaded["hits"] == 1
    assert loaded["modules"] == ["scipy.linalg.cython_lapack"]
    assert np.array_equal(np.array(loaded["result"]), np.array(compiled["result"]))  # the same machine code


def test_scipy_linalg_imports_after_its_blas_modules_were_loaded_alone(tmp_path):
    code = ('import sys, insrail.jit; alone = "scipy.linalg" not in sys.modules; import numpy as np, scipy.linalg; '
            'from scipy.linalg import cython_blas; import json; '
            'print(json.dumps({"alone": alone, "same": cython_blas is sys.modules["scipy.linalg.cython_blas"], '
            '"solved": scipy.linalg.solve(np.eye(2) * 2.0, np.ones(2)).tolist()}))')
    assert _run(tmp_path, code) == {"alone": True, "same": True, "solved": [0.5, 0.5]}
