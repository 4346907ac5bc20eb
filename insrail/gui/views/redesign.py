"""Re-design view: the tamping re-design of the survey shown (``insrail redesign``, Run > Re-design
for tamping): the measured track and the track after the job along chainage, vertical and lateral,
and the lift of each rail and the slew, with the fixed stretches shaded and the re-designed line's
key points marked. Everything it draws comes from :func:`insrail.project.plotdata.redesign_plot`."""

from __future__ import annotations

import numpy as np
import pyqtgraph as pg
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QLabel, QVBoxLayout, QWidget

from insrail.gui import plotstyle
from insrail.gui.lazy import DrawWhenShown
from insrail.gui.translation import tr
from insrail.project.plotdata import RedesignPlot

#: The fixed stretches (the machine must not move the track there) behind the curves.
FIXED_BRUSH = pg.mkBrush(123, 94, 167, 40)
MARK_PEN = pg.mkPen("#7b5ea7", width=1, style=Qt.DotLine)
MARK_TEXT = "#7b5ea7"


class RedesignView(DrawWhenShown, QWidget):
    """``set_data(plot)``: the survey's re-design (None: none yet; the note says how to make one)."""

    def __init__(self, parent=None):
        super().__init__(parent)
        self.note = QLabel()
        self.note.setWordWrap(True)
        self.plots = pg.GraphicsLayoutWidget()
        self.items: list[pg.PlotItem] = []
        for row in range(3):
            item = self.plots.addPlot(row=row, col=0)
            plotstyle.make_fluid(item)
            item.showGrid(x=False, y=False)
            if self.items:
                item.setXLink(self.items[0])
            self.items.append(item)
        self.items[-1].setLabel("bottom", tr("chainage [m]"))
        layout = QVBoxLayout(self)
        layout.setContentsMargins(2, 2, 2, 2)
        layout.addWidget(self.note)
        layout.addWidget(self.plots, 1)
        self.data: RedesignPlot | None = None
        self.set_data(None)

    def set_data(self, data: RedesignPlot | None) -> None:
        self.data = data
        if data is None:
            self.note.setText(tr("No re-design of this survey: Run > Re-design for tamping computes the lift and "
                                 "slew after which the track passes the tolerance profile."))
        else:
            self.note.setText(tr("Survey {survey}, profile {profile}: largest lift {lift:.1f} mm, largest slew "
                                 "{slew:.1f} mm; exceedances {before} before, {after} after the job; {cannot} "
                                 "stretches cannot pass under the constraints, {uncertain} pass by less than the "
                                 "survey's uncertainty, {not_assessed} checks not assessed (the log lists them).").format(
                survey=data.survey, profile=data.profile, lift=data.largest_lift_mm, slew=data.largest_slew_mm,
                before=data.exceedances_before, after=data.exceedances_after, cannot=data.cannot_pass,
                uncertain=data.uncertain, not_assessed=data.not_assessed))
        self.request_draw(now=data is None)

    def _draw(self) -> None:
        for item in self.items:
            item.clear()
        data = self.data
        if data is None:
            return
        station = data.station_m
        measured, after = tr("measured"), tr("after tamping")
        panels = (
            (tr("Vertical (mean of the rails) [mm]"), ((measured, data.measured_mm["vertical"]),
                                                       (after, data.after_mm["vertical"]))),
            (tr("Lateral (mean of the rails) [mm]"), ((measured, data.measured_mm["lateral"]),
                                                      (after, data.after_mm["lateral"]))),
            (tr("Lift and slew [mm]"), ((tr("lift left rail"), data.lift_left_mm),
                                        (tr("lift right rail"), data.lift_right_mm), (tr("slew"), data.slew_mm))),
        )
        for index, (item, (title, curves)) in enumerate(zip(self.items, panels)):
            item.setTitle(plotstyle.titled(title, [label for label, _ in curves]))
            for from_m, to_m, _source in data.fixed:
                region = pg.LinearRegionItem((from_m, to_m), movable=False, brush=FIXED_BRUSH, pen=pg.mkPen(None))
                region.setZValue(-8)
                item.addItem(region, ignoreBounds=True)
            for at, mark in data.marks:
                line = pg.InfiniteLine(at, angle=90, pen=MARK_PEN)
                item.addItem(line, ignoreBounds=True)
                if index == len(self.items) - 1:
                    text = pg.TextItem(mark, color=MARK_TEXT, anchor=(0, 1))
                    text.setPos(at, 0.0)
                    item.addItem(text, ignoreBounds=True)
            for colour, (_label, values) in enumerate(curves):
                item.plot(station, values, pen=plotstyle.pen(colour, width=1.5 if colour == 1 and index < 2 else 1.0),
                          connect="finite")
            item.addLine(y=0.0, pen=plotstyle.ZERO_PEN)
        finite = np.isfinite(station)
        if finite.any():
            self.items[0].setXRange(float(np.min(station[finite])), float(np.max(station[finite])), padding=0.01)
        for item in self.items:
            item.enableAutoRange(axis="y")
