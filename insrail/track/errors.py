"""The error a design-alignment definition raises when it is inconsistent."""

from __future__ import annotations


class DesignError(ValueError):
    """An inconsistent design definition, pointing at the offending item.

    ``part`` is "horizontal", "profile", "cant" or "station_equations"; ``index`` is
    the 0-based position of the offending item within that part (None when the part
    as a whole is wrong). Readers use them to name the line or element of the file
    the item came from; the message itself counts items from 1, as people do.
    """

    def __init__(self, part: str, index: int | None, message: str):
        self.part = part
        self.index = index
        self.message = message
        super().__init__(message)
