"""A chainage axis for the plots along the track: ticks at round K-chainage ("K12+350"), as the
sleeper table, the workbook and the PDF print it, across station equations (broken chainage).

The labels come from :class:`insrail.report.content.ChainageAxis` (the PDF charts' own), built from
the survey's sleeper labels off the GUI thread; without chainage labels (no design alignment) the
axis is pyqtgraph's own, in metres of station."""

from __future__ import annotations

import math

import pyqtgraph as pg

from insrail.report.content import ChainageAxis

#: Room for one tick label ("K123+450") and the gap to the next [px].
LABEL_ROOM_PX = 80
#: The tick steps, in metres of chainage, the labels are whole metres.
_MANTISSAS = (1, 2, 5)


def tick_step(window_m: float, length_px: float) -> float:
    """The smallest round step (1, 2, 5 x 10^k m, at least 1 m) that leaves each label its room."""
    wanted = window_m * LABEL_ROOM_PX / max(length_px, 1.0)
    exponent = max(0, math.floor(math.log10(wanted))) if wanted > 0 else 0
    while True:
        for mantissa in _MANTISSAS:
            step = mantissa * 10.0 ** exponent
            if step >= wanted:
                return step
        exponent += 1


class ChainageAxisItem(pg.AxisItem):
    """A plot's chainage axis (top or bottom); :meth:`set_chainage` gives it the survey's labels."""

    def __init__(self, orientation: str):
        super().__init__(orientation)
        self.chainage: ChainageAxis | None = None

    def set_chainage(self, chainage: ChainageAxis | None) -> None:
        self.chainage = chainage if chainage is not None and chainage.prefix is not None else None
        self.picture = None  # drawn again with the new labels
        self.update()

    def tickValues(self, minVal, maxVal, size):
        if self.chainage is None or maxVal <= minVal:
            return super().tickValues(minVal, maxVal, size)
        step = tick_step(maxVal - minVal, size)
        return [(step, [station for station, _ in self.chainage.ticks(minVal, maxVal, step)])]

    def tickStrings(self, values, scale, spacing):
        if self.chainage is None:
            return super().tickStrings(values, scale, spacing)
        return [self.chainage.label(value) for value in values]


class ChainageRuler(pg.GraphicsView):
    """The chainage axis of a stack of plots that scrolls, as a bar of its own under it: in sight
    wherever the stack is scrolled. :meth:`place` lines it up with the plots' data area,
    :meth:`set_window` follows their chainage window."""

    def __init__(self, parent=None):
        super().__init__(parent)
        self.setBackground(None)  # the window's colour: a ruler, not a plot
        self.frame = pg.GraphicsLayout()
        self.axis = ChainageAxisItem("bottom")
        self.frame.addItem(self.axis)
        self.setCentralItem(self.frame)
        self.setFixedHeight(RULER_HEIGHT_PX[True])
        self.window: tuple[float, float] | None = None

    def set_chainage(self, chainage: ChainageAxis | None) -> None:
        """K-chainage ticks say what they are; plain numbers are named "station [m]" under them."""
        self.axis.set_chainage(chainage)
        titled = self.axis.chainage is None
        self.axis.setLabel("station [m]" if titled else None)
        self.setFixedHeight(RULER_HEIGHT_PX[titled])

    def set_window(self, low: float, high: float) -> None:
        if (low, high) != self.window:  # called at every frame of a pan: a new range only when it moved
            self.window = (low, high)
            self.axis.setRange(low, high)

    def place(self, left_px: float, width_px: float) -> None:
        """The axis from ``left_px`` (from this bar's left edge) over ``width_px``: the plots' data area."""
        right = max(self.width() - left_px - width_px, 0.0)
        self.frame.setContentsMargins(max(left_px, 0.0), 0.0, right, 0.0)


#: The ruler's height: the axis line and its tick labels, with (True) or without their title [px].
RULER_HEIGHT_PX = {True: 46, False: 30}
