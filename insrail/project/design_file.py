"""The design alignment a project names (``[track] design``): an alignment CSV or a LandXML file,
by extension. Its own module so that loading a project (every command, the reports) checks the
file without importing the processing pipeline (the fusion, numba, the adjustment's solver)."""

from __future__ import annotations

from pathlib import Path

from insrail.track.alignment import DesignAlignment
from insrail.track.alignment_csv import read_alignment_csv
from insrail.track.landxml import read_landxml


def read_design(path: Path) -> DesignAlignment:
    """A design alignment from an alignment CSV or a LandXML file (by extension)."""
    return read_landxml(path) if path.suffix.lower() == ".xml" else read_alignment_csv(path)
