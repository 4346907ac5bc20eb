"""The `insrail` command ends without the interpreter's teardown (insrail.cli.main.exit_at_once), having
done what an exit does for others first: the threads joined (a thread pool never shut down told to
stop), the atexit functions run and the output flushed, with the command's exit status."""

import subprocess
import sys

import pytest

SCRIPT = """
import atexit, sys, threading, time
from concurrent.futures import ThreadPoolExecutor
from insrail.cli.main import exit_at_once

atexit.register(lambda: print("atexit ran", flush=True))
pool = ThreadPoolExecutor(1)  # never shut down
pool.submit(time.sleep, 0.2)
threading.Thread(target=lambda: (time.sleep(0.3), print("thread done"))).start()
sys.stdout.write("buffered ")
exit_at_once(int(sys.argv[1]))
"""


@pytest.mark.parametrize("code", [0, 3])
def test_the_exit_joins_the_threads_runs_atexit_and_flushes_the_output(code):
    run = subprocess.run([sys.executable, "-c", SCRIPT, str(code)], capture_output=True, text=True, timeout=120)
    assert run.returncode == code, run.stderr
    assert run.stdout == "buffered thread done\natexit ran\n"


def test_python_m_insrail_ends_with_the_commands_status_and_message(tmp_path):
    run = subprocess.run([sys.executable, "-m", "insrail", "process", str(tmp_path / "none")], capture_output=True,
                         text=True, timeout=300)
    assert run.returncode == 1
    assert run.stderr.strip().endswith("project file not found")
