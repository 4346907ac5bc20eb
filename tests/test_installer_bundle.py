"""The standalone bundle builds, and runs the demo from a read-only folder in a clean environment."""

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


def test_desktop_entry_names_the_shipped_icon_and_command():
    entry = (ROOT / "resources" / "insrail.desktop").read_text(encoding="utf-8").splitlines()
    assert entry[0] == "[Desktop Entry]"
    fields = dict(line.split("=", 1) for line in entry[1:] if "=" in line)
    assert fields["Exec"].split()[0] == "insrail" and fields["Type"] == "Application"
    assert (ROOT / "resources" / "icons" / f"{fields['Icon']}.svg").is_file()
    assert all((ROOT / "resources" / "icons" / f"insrail_{size}.png").is_file() for size in (16, 32, 48, 256))


@pytest.mark.slow
def test_bundle_builds_and_runs_the_demo(tmp_path):
    run = subprocess.run([sys.executable, str(ROOT / "installer" / "build.py"), "--dist", str(tmp_path)],
                         capture_output=True, text=True, timeout=1800)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    assert "insrail 0." in run.stdout  # --version from the bundle
    assert "Against the simulator's truth" in run.stdout and "Done in" in run.stdout
    assert "desktop application started from the bundle" in run.stdout
