"""Views draw when they are seen: a hidden tab only keeps its data until it is shown."""

from __future__ import annotations


class DrawWhenShown:
    """Mix into a QWidget with a ``_draw()``: :meth:`request_draw` draws now if the widget is
    visible, else at its next show (the navigation view of a long survey costs seconds to draw;
    nobody should wait for it while looking at the track)."""

    _stale = False

    def request_draw(self, now: bool = False) -> None:
        """Draw the data just set (``now``: even when hidden; clearing is cheap and must not wait:
        a hidden tab must never keep another survey's plots)."""
        self._stale = True
        if now or self.isVisible():
            self._draw_now()

    def _draw_now(self) -> None:
        self._stale = False
        self._draw()

    def showEvent(self, event) -> None:
        super().showEvent(event)
        if self._stale:
            self._draw_now()

    @property
    def stale(self) -> bool:
        """True while data set since the last draw waits for the view to be shown."""
        return self._stale
