"""The exceedance table of the track view as a Qt model: a 10 km survey has thousands of
exceedances, and a cell object each (QTableWidget) cost most of a second to build on every survey
shown. The model keeps the rows as the results give them, formats a cell only when the view asks
for it, and sorts by index arrays (peaks and limits by magnitude, stations as numbers)."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence

import numpy as np
from PySide6.QtCore import QAbstractTableModel, QModelIndex, Qt

from insrail.names import DIRECTION_NAMES, RAIL_NAMES, t
from insrail.project.results import ExceedanceRow
from insrail.report.content import exceedance_display
from insrail.gui.translation import tr, tr_noop

COLUMNS = (tr_noop("Check"), tr_noop("Rail"), tr_noop("Direction"), tr_noop("From [m]"), tr_noop("To [m]"),
           tr_noop("Peak"), tr_noop("Limit"), tr_noop("Unit"), tr_noop("Sleepers"))
#: The columns holding numbers (right-aligned, sorted by value).
NUMERIC = frozenset({3, 4, 5, 6, 8})
#: The column the table starts sorted by: along the track, as walked.
START_COLUMN = 3


class ExceedanceModel(QAbstractTableModel):
    """Rows of :class:`ExceedanceRow`; :data:`Qt.UserRole` of any cell is the row's index in the
    results, whatever the sort order."""

    def __init__(self, parent=None):
        super().__init__(parent)
        self._rows: tuple[ExceedanceRow, ...] = ()
        self._names: tuple[str, ...] = ()
        self._keys: tuple[np.ndarray, ...] = ()
        self._order = np.zeros(0, dtype=int)

    def set_rows(self, rows: Sequence[ExceedanceRow], check_names: Mapping[str, str]) -> None:
        """New rows; ``check_names`` maps a check id to its display name (never shown: the id)."""
        self.beginResetModel()
        self._rows = tuple(rows)
        self._names = tuple(check_names.get(e.check, e.kind.replace("_", " ")) for e in self._rows)
        self._keys = (np.array(self._names, dtype=object),
                      np.array([t(RAIL_NAMES.get(e.rail, e.rail)) for e in self._rows], dtype=object),
                      np.array([t(DIRECTION_NAMES.get(e.direction, e.direction)) for e in self._rows], dtype=object),
                      np.array([e.station_from_m for e in self._rows], dtype=float),
                      np.array([e.station_to_m for e in self._rows], dtype=float),
                      np.abs(np.array([e.peak for e in self._rows], dtype=float)),
                      np.abs(np.array([e.limit for e in self._rows], dtype=float)),
                      np.array([exceedance_display(e)[2] for e in self._rows], dtype=object),
                      np.array([e.first_sleeper for e in self._rows], dtype=float))
        self._order = np.argsort(self._keys[START_COLUMN], kind="stable") if self._rows else np.zeros(0, dtype=int)
        self.endResetModel()

    def exceedance_at(self, row: int) -> int:
        """The index in the results of the exceedance in table row ``row`` (-1: none)."""
        return int(self._order[row]) if 0 <= row < len(self._order) else -1

    def row_of(self, index: int) -> int:
        """The table row showing exceedance ``index`` of the results (-1: none)."""
        found = np.flatnonzero(self._order == index)
        return int(found[0]) if found.size else -1

    def column_widths(self, text_width: Callable[[str], int], sample: int = 200) -> list[int]:
        """Each column's width for its header and texts (every check name, the first ``sample`` rows
        otherwise): asking the view to size from contents would format every cell of every row."""
        rows = range(min(sample, len(self._rows)))
        widths = []
        for column, title in enumerate(COLUMNS):
            texts = {title, *(self._text(int(self._order[row]), column) for row in rows)}
            if column == 0:
                texts.update(self._names)
            widths.append(max(text_width(text) for text in texts))
        return widths

    # ------------------------------------------------------------------ QAbstractTableModel

    def rowCount(self, parent=QModelIndex()) -> int:  # noqa: B008 (Qt's signature)
        return 0 if parent.isValid() else len(self._rows)

    def columnCount(self, parent=QModelIndex()) -> int:  # noqa: B008
        return 0 if parent.isValid() else len(COLUMNS)

    def headerData(self, section: int, orientation, role=Qt.DisplayRole):
        if role == Qt.DisplayRole and orientation == Qt.Horizontal:
            return tr(COLUMNS[section])
        return None

    def data(self, index: QModelIndex, role=Qt.DisplayRole):
        if not index.isValid():
            return None
        at = int(self._order[index.row()])
        if role == Qt.DisplayRole:
            return self._text(at, index.column())
        if role == Qt.UserRole:
            return at
        if role == Qt.TextAlignmentRole and index.column() in NUMERIC:
            return int(Qt.AlignRight | Qt.AlignVCenter)
        return None

    def sort(self, column: int, order=Qt.AscendingOrder) -> None:
        if not self._rows:
            return
        self.layoutAboutToBeChanged.emit()
        old = self._order
        new = np.argsort(self._keys[column], kind="stable")
        if order == Qt.DescendingOrder:
            new = new[::-1]
        position = np.empty_like(new)
        position[new] = np.arange(len(new))
        for index in self.persistentIndexList():  # the selection follows its rows
            self.changePersistentIndex(index, self.index(int(position[old[index.row()]]), index.column()))
        self._order = new
        self.layoutChanged.emit()

    def _text(self, at: int, column: int) -> str:
        e = self._rows[at]
        if column in (0, 1, 2, 7):
            return str(self._keys[column][at])
        if column in (5, 6):
            peak, limit, _unit = exceedance_display(e)
            return f"{peak if column == 5 else limit:.3f}"
        return (f"{e.station_from_m:.3f}", f"{e.station_to_m:.3f}", f"{e.first_sleeper}–{e.last_sleeper}")[
            (3, 4, 8).index(column)]
