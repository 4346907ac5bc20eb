"""Each test's CPU time (setup, call and teardown; the process's threads and its waited-for children),
written to the file named by INSRAIL_TEST_CPU_LOG (one per xdist worker, the worker's id appended): a line
``cpu_s<TAB>wall_s<TAB>nodeid``. The machine is shared, so test cost is compared in CPU, not wall time.
``python tests/cpu_log.py LOG...`` sums them per module."""

from __future__ import annotations

import os
import resource
import sys
import time
from collections import defaultdict

import pytest


def _cpu_s() -> float:
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


class CpuLog:
    def __init__(self, path: str):
        self._file = open(path, "a", buffering=1)

    @pytest.hookimpl(hookwrapper=True)
    def pytest_runtest_protocol(self, item, nextitem):
        cpu, wall = _cpu_s(), time.perf_counter()
        yield
        self._file.write(f"{_cpu_s() - cpu:.3f}\t{time.perf_counter() - wall:.3f}\t{item.nodeid}\n")


def register(config) -> None:
    path = os.environ.get("INSRAIL_TEST_CPU_LOG")
    if path:
        config.pluginmanager.register(CpuLog(path + "." + os.environ.get("PYTEST_XDIST_WORKER", "main")))


def summary(paths: list[str], top: int = 40) -> None:
    tests, modules = [], defaultdict(float)
    for path in paths:
        for line in open(path):
            cpu, wall, nodeid = line.rstrip("\n").split("\t")
            tests.append((float(cpu), float(wall), nodeid))
            modules[nodeid.split("::")[0]] += float(cpu)
    print(f"total CPU {sum(t[0] for t in tests):.0f} s over {len(tests)} tests")
    for module, cpu in sorted(modules.items(), key=lambda m: -m[1])[:top]:
        print(f"{cpu:8.1f}  {module}")
    print()
    for cpu, wall, nodeid in sorted(tests, reverse=True)[:top]:
        print(f"{cpu:8.1f} {wall:8.1f}  {nodeid}")


if __name__ == "__main__":
    summary(sys.argv[1:])
