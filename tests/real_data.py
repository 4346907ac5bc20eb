"""Where the shared real recordings are (`../shared/data/real` in the brief): beside the checkout,
or the workplace's fixed copy for a clone made anywhere else (CI may clone into a temporary folder)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

_CANDIDATES = (Path(__file__).resolve().parents[2] / "shared" / "data" / "real", Path("/work/shared/data/real"))
REAL = next((folder for folder in _CANDIDATES if folder.is_dir()), _CANDIDATES[0])


def real_path(*parts: str) -> Path:
    """A file or folder of the shared recordings: skipped where they are absent, an error under CI."""
    path = REAL.joinpath(*parts)
    if not path.exists():
        if os.environ.get("CI"):
            pytest.fail(f"shared real data missing in CI: {path}")
        pytest.skip(f"shared real data not present: {path}")
    return path
