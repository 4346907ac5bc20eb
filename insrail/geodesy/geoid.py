"""Global geoid grids through PROJ, with no silent fallback.

PROJ quietly replaces a transformation whose grid is missing by a "ballpark" one that
returns heights unchanged; a railway survey would then be off by the whole geoid
undulation (tens of metres) without a sign. This module therefore never lets PROJ look a
grid up by name: a ``GeoidGrid`` is opened from an explicit file (EGM96's ``egm96_15.gtx``,
shipped inside this package in ``grids/`` with its licence note, or any vertical grid PROJ's
``vgridshift`` reads: .gtx, .tif), and ``checked_transformer`` refuses ballpark operations for
code that must go through PROJ's database.

Undulation N is the geoid height above the ellipsoid [m] (h = H + N), evaluated at
geodetic latitude/longitude in radians.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from insrail.geodesy.crs import EngineeringCRS
from insrail.geodesy.errors import GeoidGridError

if TYPE_CHECKING:  # pyproj itself is imported where used (insrail.geodesy.crs)
    from pyproj import Transformer

EGM96_GRID_NAME = "egm96_15.gtx"
#: The package's own grids (package data: every install and the bundle carry them).
SHIPPED_GRIDS_DIR = Path(__file__).resolve().parent / "grids"


def find_egm96_grid() -> Path:
    """Path of the EGM96 grid shipped with insrail; raises when the install lacks it."""
    path = SHIPPED_GRIDS_DIR / EGM96_GRID_NAME
    if not path.is_file():
        raise GeoidGridError(f"{path}: the EGM96 geoid grid that ships with insrail is missing: the install is "
                             "incomplete (install insrail again)")
    return path


@dataclass(frozen=True)
class GeoidGrid:
    """A vertical grid file giving the geoid undulation N [m]."""

    path: Path

    def __post_init__(self) -> None:
        object.__setattr__(self, "path", Path(self.path))
        if not self.path.is_file():
            raise GeoidGridError(f"{self.path}: geoid grid file not found (EGM96 ships with insrail: "
                                 "geoid_grid = \"egm96\")")
        self._transformer  # open it now, so an unreadable file fails here and not mid-pipeline

    @classmethod
    def egm96(cls) -> GeoidGrid:
        return cls(find_egm96_grid())

    @cached_property
    def _transformer(self) -> Transformer:
        # An absolute path and no '@' prefix: PROJ must use this very file or fail.
        from pyproj import Transformer
        from pyproj.exceptions import ProjError

        pipeline = f"+proj=vgridshift +grids={self.path.resolve()} +multiplier=1"
        try:
            return Transformer.from_pipeline(pipeline)
        except ProjError as err:
            raise GeoidGridError(f"{self.path}: PROJ cannot read this as a vertical grid ({err})") from None

    def __getstate__(self) -> dict:
        return {"path": self.path}

    def __setstate__(self, state: dict) -> None:
        object.__setattr__(self, "path", state["path"])

    def undulation_m(self, lat_rad, lon_rad) -> np.ndarray:
        """Geoid undulation N [m] at geodetic latitude/longitude [rad]; raises outside the grid."""
        lat, lon = np.broadcast_arrays(np.asarray(lat_rad, dtype=float), np.asarray(lon_rad, dtype=float))
        _, _, n = self._transformer.transform(lon, lat, np.zeros(lat.shape), radians=True)
        n = np.asarray(n, dtype=float)
        outside = np.isfinite(lat) & np.isfinite(lon) & ~np.isfinite(n)
        if outside.any():
            i = int(np.flatnonzero(outside.ravel())[0])
            raise GeoidGridError(
                f"{self.path}: {int(outside.sum())} point(s) lie outside the grid, first at latitude "
                f"{np.degrees(lat.ravel()[i]):.6f}°, longitude {np.degrees(lon.ravel()[i]):.6f}°")
        return n


@dataclass(frozen=True)
class PlaneGeoid:
    """A geoid grid evaluated at engineering plane coordinates (for remove-restore fitting)."""

    grid: GeoidGrid
    crs: EngineeringCRS

    def undulation_m(self, east_m, north_m) -> np.ndarray:
        lat, lon = self.crs.to_geodetic(east_m, north_m)
        return self.grid.undulation_m(lat, lon)

    def describe(self) -> str:
        return f"{self.grid.path.name} via {self.crs.describe()}"


def checked_transformer(source_crs, target_crs) -> Transformer:
    """``Transformer.from_crs(..., always_xy=True)`` that raises instead of falling back to ballpark.

    Use it whenever a transformation is looked up in PROJ's database (e.g. EPSG:4979 to
    EPSG:4326+5773): if the best operation needs a grid that is not installed, PROJ
    would silently use a ballpark operation that leaves heights unchanged.
    """
    from pyproj import Transformer
    from pyproj.transformer import TransformerGroup

    transformer = Transformer.from_crs(source_crs, target_crs, always_xy=True)
    if "ballpark" not in transformer.description.lower():
        return transformer
    missing = sorted({grid.short_name for op in TransformerGroup(source_crs, target_crs).unavailable_operations
                      for grid in op.grids if not grid.available})
    hint = f"; missing grid(s): {', '.join(missing)}" if missing else ""
    raise GeoidGridError(f"PROJ can only offer a ballpark transformation from {source_crs} to {target_crs} "
                         f"({transformer.description}), which would leave heights unchanged{hint}. "
                         "Install the grid or give its file explicitly")
