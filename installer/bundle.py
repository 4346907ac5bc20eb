"""What the bundle carries besides Python modules, and where it goes inside the bundle."""

from __future__ import annotations

from pathlib import Path

from insrail.geodesy.geoid import SHIPPED_GRIDS_DIR, find_egm96_grid

#: Where the package's grids lie inside the bundle: beside the bundled insrail.geodesy modules,
#: where insrail.geodesy.geoid looks for them.
GRIDS_IN_BUNDLE = "insrail/geodesy/grids"
#: The desktop application's translations (Qt .qm files), where insrail.gui.translation looks for them.
TRANSLATIONS_IN_BUNDLE = "insrail/gui/i18n"


def bundle_datas(root: Path) -> list[tuple[str, str]]:
    """(source, folder in bundle) pairs: the resources, the package's geoid grids (EGM96 with its
    licence note) and the application's translations; a checkout without the grid cannot build a bundle."""
    find_egm96_grid()  # raises when the grid is missing
    return [(str(root / "resources"), "resources"), (str(SHIPPED_GRIDS_DIR), GRIDS_IN_BUNDLE),
            (str(root / TRANSLATIONS_IN_BUNDLE), TRANSLATIONS_IN_BUNDLE)]
