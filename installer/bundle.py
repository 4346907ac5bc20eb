"""What the bundle carries besides Python modules, and where it goes inside the bundle."""

from __future__ import annotations

from pathlib import Path

from insrail.geodesy.geoid import EGM96_GRID_NAME, GeoidGridError, find_egm96_grid

#: pyproj looks for grids in its own data folder first (pyproj.datadir.get_data_dir()).
PYPROJ_DATA_IN_BUNDLE = "pyproj/proj_dir/share/proj"


def bundle_datas(root: Path) -> list[tuple[str, str]]:
    """(source, folder in bundle) pairs: the resources and the EGM96 geoid grid.

    The grid comes from the build machine's PROJ data (Debian's proj-data); without it the bundle
    still builds, and height models using EGM96 then ask the user for a grid file.
    """
    datas = [(str(root / "resources"), "resources")]
    try:
        datas.append((str(find_egm96_grid()), PYPROJ_DATA_IN_BUNDLE))
    except GeoidGridError:
        print(f"warning: {EGM96_GRID_NAME} not found on this machine; the bundle will not contain it")
    return datas
