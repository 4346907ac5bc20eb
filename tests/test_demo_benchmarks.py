"""The demo project with h and H swapped in its benchmark file is refused naming the file, on any
install: the EGM96 grid the check compares with ships inside the package (no system package)."""

from __future__ import annotations

import shutil
from pathlib import Path

from insrail.cli.demo import demo_events
from insrail.cli.main import main
from insrail.geodesy.geoid import SHIPPED_GRIDS_DIR, find_egm96_grid
from insrail.project.demo import project_for_simulated_survey


def swap_h_and_big_h(path: Path) -> None:
    """What a user does when pasting the levelling sheet's columns in the wrong order: id lat lon H h."""
    lines = []
    for line in path.read_text().splitlines():
        if line.startswith("#"):
            lines.append(line)
            continue
        point, lat, lon, h, big_h = line.split()
        lines.append(" ".join([point, lat, lon, big_h, h]))
    path.write_text("\n".join(lines) + "\n")


def test_the_demo_with_h_and_H_swapped_in_its_benchmarks_is_refused_naming_the_file(short_nav_survey, tmp_path, capsys):
    assert find_egm96_grid().parent == SHIPPED_GRIDS_DIR  # not Debian's /usr/share/proj
    root = tmp_path / "demo"
    survey = root / "surveys" / "short"
    shutil.copytree(short_nav_survey, survey)  # `short`, seed 1, as `insrail demo` simulates it (a copy: it is edited)
    project = demo_events(project_for_simulated_survey(root, survey, name="insrail demo"))
    benchmarks = project.resolve(project.height.benchmarks)
    swap_h_and_big_h(benchmarks)
    capsys.readouterr()

    assert main(["process", str(root)]) == 1
    error = capsys.readouterr().err
    assert str(benchmarks) in error and "h and H are swapped" in error, error
    assert "EGM96" in error and "Traceback" not in error
    assert not (root / "results" / "short").exists()
    assert not list((root / "results" / ".cache").glob("fusion-*"))  # refused before the fusion
