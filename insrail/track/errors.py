"""The error a design-alignment definition raises when it is inconsistent."""

from __future__ import annotations

from collections.abc import Mapping

from insrail.notices import Phrase


class DesignError(ValueError):
    """An inconsistent design definition, pointing at the offending item.

    ``part`` is "horizontal", "profile", "cant" or "station_equations"; ``index`` is
    the 0-based position of the offending item within that part (None when the part
    as a whole is wrong). Readers use them to name the line or element of the file
    the item came from; the message itself counts items from 1, as people do. The message is a
    template with ``fields`` (or a Phrase), so a reader's error says it in the user's language
    (``phrase``); ``message`` is its English.
    """

    def __init__(self, part: str, index: int | None, message: str | Phrase, fields: Mapping[str, object] | None = None):
        self.part = part
        self.index = index
        self.phrase = message if isinstance(message, Phrase) else Phrase(message, fields or {})
        self.message = str(self.phrase)
        super().__init__(self.message)
