"""insrail keeps OpenBLAS to one thread (its own threads run the pipeline) unless the user said otherwise."""

import os
import subprocess
import sys

SAID = "import os, insrail, numpy; print(os.environ['OPENBLAS_NUM_THREADS'])"


def _said(env_value):
    env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"}
    if env_value is not None:
        env["OPENBLAS_NUM_THREADS"] = env_value
    return subprocess.run([sys.executable, "-c", SAID], env=env, capture_output=True, text=True,
                          check=True).stdout.strip()


def test_openblas_runs_one_thread_unless_the_user_set_it():
    assert _said(None) == "1"
    assert _said("3") == "3"
