"""Entry point of the bundled ``insrail`` executable (the same ``main`` as the console script)."""

import multiprocessing
import sys

from insrail.cli.main import main

if __name__ == "__main__":
    # PPK runs RTKLIB in a child process: a frozen executable must hand such children to it.
    multiprocessing.freeze_support()
    sys.exit(main())
