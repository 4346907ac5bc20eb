"""Entry point of the bundled ``insrail`` executable (the same ``console`` as the console script)."""

import multiprocessing

from insrail.cli.main import console

if __name__ == "__main__":
    # PPK runs RTKLIB in a child process: a frozen executable must hand such children to it.
    multiprocessing.freeze_support()
    console()
