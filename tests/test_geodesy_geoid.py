"""Geoid grids: explicit files only, clear errors, and no silent ballpark fallback."""

import math
import pickle
import warnings
from pathlib import Path

import numpy as np
import pytest

from insrail.geodesy import GeoidGrid, GeoidGridError, checked_transformer, find_egm96_grid
from insrail.geodesy import geoid as geoid_module


def test_egm96_check_values():
    grid = GeoidGrid.egm96()
    # geodesy.md check value: 117.5E 31.8N -> N = -3.684 m; EGM96 at (0, 0) is +17.16 m.
    n = grid.undulation_m(np.radians([31.8, 0.0]), np.radians([117.5, 0.0]))
    np.testing.assert_allclose(n, [-3.684, 17.16], atol=0.005)
    assert pickle.loads(pickle.dumps(grid)).undulation_m(math.radians(31.8), math.radians(117.5)) == n[0]


def test_points_outside_the_grid_are_an_error():
    grid = GeoidGrid.egm96()
    with pytest.raises(GeoidGridError, match=r"1 point\(s\) lie outside the grid, first at latitude 95"):
        grid.undulation_m(np.radians([31.8, 95.0]), np.radians([117.5, 0.0]))


def test_egm96_ships_inside_the_package_with_its_licence():
    # no system package (Debian's proj-data) needed: the grid is package data, beside its licence note
    path = find_egm96_grid()
    assert path.parent == Path(geoid_module.__file__).resolve().parent / "grids"
    assert "public domain" in (path.parent / "EGM96_LICENCE.md").read_text(encoding="utf-8").lower()


def test_a_missing_shipped_grid_is_named_as_an_incomplete_install(tmp_path, monkeypatch):
    monkeypatch.setattr(geoid_module, "SHIPPED_GRIDS_DIR", tmp_path)
    with pytest.raises(GeoidGridError, match="egm96_15.gtx: the EGM96 geoid grid that ships with insrail is missing"):
        GeoidGrid.egm96()


def test_missing_and_unreadable_grid_files_are_an_error(tmp_path):
    with pytest.raises(GeoidGridError, match="geoid grid file not found"):
        GeoidGrid(tmp_path / "egm96_15.gtx")
    junk = tmp_path / "junk.gtx"
    junk.write_bytes(b"not a grid" * 20)
    with pytest.raises(GeoidGridError, match="PROJ cannot read this as a vertical grid"):
        GeoidGrid(junk)


def test_ballpark_fallback_is_refused():
    # EGM2008 (us_nga_egm08_25.tif) is not shipped by pyproj nor Debian's proj-data and the
    # network is off, so PROJ would silently return heights unchanged.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(GeoidGridError, match="ballpark .* leave heights unchanged.*us_nga_egm08_25.tif"):
            checked_transformer("EPSG:4979", "EPSG:4326+3855")


def test_checked_transformer_passes_real_transformations():
    transformer = checked_transformer("EPSG:4490", "EPSG:4549")
    east, north = transformer.transform(120.5, 31.0)
    assert east == pytest.approx(547_752.418, abs=1e-3) and north == pytest.approx(3_431_081.638, abs=1e-3)
