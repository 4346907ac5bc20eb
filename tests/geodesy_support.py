"""Shared helper for the geodesy tests that need the EGM96 grid from Debian's proj-data."""

import os

import pytest

from insrail.geodesy import GeoidGrid, GeoidGridError


def egm96_or_skip() -> GeoidGrid:
    """The EGM96 grid; skip when it is not installed locally, but fail on CI (CI is set there)."""
    try:
        return GeoidGrid.egm96()
    except GeoidGridError:
        if os.environ.get("CI"):
            raise
        pytest.skip("egm96_15.gtx not installed here (apt-get install proj-data)")
