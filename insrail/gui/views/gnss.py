"""GNSS page: a survey's raw GNSS inputs (``[gnss_raw]``), the PPK stage's QC and the solution's
quality along time.

Inputs and QC are key/value trees as in the properties panel; the plots share the time axis
(seconds from the solution's first epoch): the quality of every epoch (fix on top) and its
horizontal and vertical sigma, with the gaps shaded.
"""

from __future__ import annotations

import math

import numpy as np
import pyqtgraph as pg
from PySide6.QtCore import Qt, Signal
from PySide6.QtWidgets import (
    QComboBox,
    QHBoxLayout,
    QLabel,
    QSplitter,
    QToolButton,
    QTreeWidget,
    QTreeWidgetItem,
    QVBoxLayout,
    QWidget,
)

from insrail.gui import plotstyle
from insrail.io.survey_gnss import RawGnss
from insrail.project.control_points import ControlPoint
from insrail.notices import phrase_of
from insrail.project.plotdata import PpkView, quality_epochs
from insrail.gui.translation import tr, tr_noop

#: Colours of the RTKLIB qualities (fix, float, single; others grey), as in the surveyor's PPK tools.
QUALITY_COLOURS = {1: "#009E73", 2: "#E69F00", 5: "#D55E00"}
OTHER_QUALITY_COLOUR = "#7F7F7F"
#: The RTKLIB qualities' names (insrail.gnss.qc.QUALITY_NAMES) as the view shows them, in the application's language.
QUALITY_LABELS = {"fix": tr_noop("fix"), "float": tr_noop("float"), "sbas": tr_noop("sbas"), "dgps": tr_noop("dgps"),
                  "single": tr_noop("single"), "ppp": tr_noop("ppp")}


def quality_label(name: str) -> str:
    """An RTKLIB quality's name ("fix", "float", ...) in the application's language ("固定解", ...)."""
    return tr(QUALITY_LABELS[name]) if name in QUALITY_LABELS else name


def fusion_use(use: str) -> str:
    """What the fusion does with a quality's epochs (summary.toml ``fusion_by_quality.*.use``) in words."""
    if use == "excluded":
        return tr("excluded")
    factor = use.removeprefix("sigma x ")
    return tr("sigma x {factor}").format(factor=factor) if factor != use else use
GAP_BRUSH = pg.mkBrush(213, 94, 0, 40)


def _percent(part: float, whole: float) -> str:
    return f"{100.0 * part / whole:.1f} %" if whole else "–"


def _number(value, unit: str = "", digits: int = 1) -> str:
    return "–" if value is None or (isinstance(value, float) and math.isnan(value)) else f"{value:.{digits}f}{unit}"


def input_rows(raw: RawGnss, folder, base: ControlPoint | None) -> list[tuple[str, list[tuple[str, str]]]]:
    """(group, [(key, value)]) of the raw inputs: files with their state, the base point."""

    def file(name: str) -> str:
        return name if (folder / name).is_file() else tr("{file} (missing)").format(file=name)

    files = []
    if raw.rover is not None:
        files.append((tr("rover (RINEX)"), file(raw.rover)))
    else:
        files.append((tr("rover log"), file(raw.rover_log) + (f" ({raw.rover_log_format})" if raw.rover_log_format
                                                           else "")))
    files.append((tr("base (RINEX)"), file(raw.base)))
    files += [(tr("navigation"), file(name)) for name in raw.navigation]
    files += [(tr("precise"), file(name)) for name in raw.precise]
    files += [(key, file(name)) for key, name in (("antex", raw.antex), (tr("RTKLIB config"), raw.config))
              if name is not None]
    if raw.config is None:
        files.append((tr("RTKLIB config"), tr("trolley defaults (resources/gnss)")))
    if raw.base_from_header:
        point = [(tr("base point"), tr("RINEX header APPROX POSITION (metre level)"))]
    else:
        point = [(tr("base point"), raw.base_point)]
        if base is None:
            point.append((tr("coordinates"), tr("not in the project's control points")))
        elif base.geodetic is not None:
            lat, lon, h = base.geodetic
            point.append((tr("lat, lon, h"), f"{lat:.9f}°, {lon:.9f}°, {h:.4f} m"))
        else:
            east, north, height = base.engineering
            point.append((tr("E, N, H (normal)"), f"{east:.4f}, {north:.4f}, {height:.4f} m"))
        point.append((tr("antenna height (ARP)"), f"{raw.base_antenna_height_m:.4f} m"))
        point.append((tr("antenna type"), raw.base_antenna_type or tr("not given")))
    return [(tr("Files"), files), (tr("Base"), point)]


def qc_rows(view: PpkView) -> list[tuple[str, list[tuple[str, str]]]]:
    """(group, [(key, value)]) of the QC report: solution, qualities, sigmas, gaps, base, warnings."""
    report, qc = view.report, view.report["qc"]
    epochs = qc["epochs"]
    solution = [(tr("epochs"), tr("{epochs} over {span_s:.0f} s (interval {interval_s:g} s)").format(
                    epochs=epochs, span_s=qc["last_s"] - qc["first_s"], interval_s=qc["interval_s"])),
                (tr("fix rate"), _percent(qc["fix_rate"], 1.0)),
                (tr("ratio of fixed epochs"), tr("min {min}, 5 % {p05}, median {median}").format(
                    min=_number(qc["ratio_min"]), p05=_number(qc["ratio_p05"]), median=_number(qc["ratio_median"])))]
    if "rtklib_seconds" in report:
        solution.append((tr("RTKLIB time"), f"{report['rtklib_seconds']:.1f} s"))
    fusion = (view.fusion or {}).get("fusion_by_quality", {})
    qualities = []
    for name, count in qc["epochs_by_quality"].items():
        use = tr("; fusion: {use}").format(use=fusion_use(fusion[name]["use"])) if name in fusion else ""
        qualities.append((quality_label(name), f"{count} ({_percent(count, epochs)}){use}"))
    sigmas = [(quality_label(name), tr("horizontal median {h_median:.1f} mm, 95 % {h_p95:.1f} mm; vertical median {v_median:.1f} mm, "
                        "95 % {v_p95:.1f} mm").format(
        h_median=1e3 * s["horizontal_median_m"], h_p95=1e3 * s["horizontal_p95_m"],
        v_median=1e3 * s["vertical_median_m"], v_p95=1e3 * s["vertical_p95_m"]))
              for name, s in qc["sigma_by_quality_m"].items()]
    gaps = [(f"+{g['start_s'] - qc['first_s']:.0f} s", tr("to +{end_s:.0f} s ({duration_s:.0f} s)").format(
        end_s=g["end_s"] - qc["first_s"], duration_s=g["duration_s"])) for g in qc["gaps"]]
    base = report["base"]
    base_rows = [(tr("point"), base["point"] + (tr(" (approximate)") if base["approximate"] else ""))]
    if "baseline_m" in report:
        base_rows.append((tr("baseline"), f"{report['baseline_m'] / 1e3:.3f} km"))
    if "lat_deg" in base:
        base_rows.append((tr("mark lat, lon, h"), (f"{base['lat_deg']:.9f}°, {base['lon_deg']:.9f}°, "
                                                  f"{base['ellipsoidal_height_m']:.4f} m")))
    base_rows.append((tr("derivation"), phrase_of(base["derivation"]).said()))
    warnings = [(f"{i + 1}", phrase_of(text).said()) for i, text in enumerate(report["warnings"])] or [("", tr("none"))]
    return [(tr("Solution"), solution), (tr("Epochs by quality"), qualities), (tr("Sigma by quality"), sigmas),
            (tr("Gaps ({count})").format(count=len(gaps)), gaps or [("", tr("none"))]), (tr("Base"), base_rows),
            (tr("Warnings"), warnings)]


class KeyValueTree(QTreeWidget):
    def __init__(self, title: str, parent=None):
        super().__init__(parent)
        self.setHeaderLabels([title, tr("Value")])
        self.setColumnWidth(0, 160)
        self.setWordWrap(True)

    def show_groups(self, groups: list[tuple[str, list[tuple[str, str]]]]) -> None:
        self.clear()
        for group, rows in groups:
            parent = QTreeWidgetItem(self, [group])
            font = parent.font(0)
            font.setBold(True)
            parent.setFont(0, font)
            for key, value in rows:
                item = QTreeWidgetItem(parent, [key, value])
                item.setToolTip(1, value)
        self.expandAll()

    def value(self, group: str, key: str) -> str:
        """The value shown for ``key`` under the group whose name starts with ``group``."""
        for i in range(self.topLevelItemCount()):
            parent = self.topLevelItem(i)
            if parent.text(0).startswith(group):
                for j in range(parent.childCount()):
                    if parent.child(j).text(0) == key:
                        return parent.child(j).text(1)
        raise KeyError(f"{group} / {key}")


class GnssView(QWidget):
    surveyChosen = Signal(str)

    def __init__(self, parent=None):
        super().__init__(parent)
        self.survey = QComboBox()
        self.survey.setSizeAdjustPolicy(QComboBox.AdjustToContents)
        self.survey.currentTextChanged.connect(lambda name: name and self.surveyChosen.emit(name))
        self.run_button = QToolButton()
        self.run_button.setToolButtonStyle(Qt.ToolButtonTextOnly)
        self.headline = QLabel(tr("Not post-processed yet: Run > Post-process GNSS."))
        self.headline.setWordWrap(True)  # the page must not widen the window's minimum
        self.inputs = KeyValueTree(tr("Input"))
        self.qc = KeyValueTree(tr("QC"))
        self.plots = pg.GraphicsLayoutWidget()
        self.quality_plot = self.plots.addPlot(row=0, col=0)
        self.sigma_plot = self.plots.addPlot(row=1, col=0)
        self.sigma_plot.setXLink(self.quality_plot)
        for item in (self.quality_plot, self.sigma_plot):
            plotstyle.make_fluid(item)
            item.getAxis("left").setWidth(56)
        self.quality_plot.invertY(True)  # fix on top
        self.quality_plot.setMouseEnabled(y=False)
        self.sigma_plot.setLabel("bottom", tr("time from the first epoch [s]"))
        self.sigma_plot.setLabel("left", "mm")
        self.plots.ci.layout.setRowStretchFactor(0, 2)
        self.plots.ci.layout.setRowStretchFactor(1, 3)

        top = QHBoxLayout()
        top.addWidget(QLabel(tr("Survey")))
        top.addWidget(self.survey)
        top.addWidget(self.run_button)
        top.addSpacing(16)
        top.addWidget(self.headline, 1)
        tables = QSplitter(Qt.Vertical)
        tables.addWidget(self.inputs)
        tables.addWidget(self.qc)
        tables.setSizes([220, 430])
        body = QSplitter(Qt.Horizontal)
        body.addWidget(tables)
        body.addWidget(self.plots)
        body.setSizes([600, 800])
        layout = QVBoxLayout(self)
        layout.setContentsMargins(4, 4, 4, 4)
        layout.addLayout(top)
        layout.addWidget(body, 1)
        self.shown: PpkView | None = None

    def set_surveys(self, names: list[str]) -> None:
        """The project's surveys with raw GNSS observations (the first is chosen)."""
        self.survey.blockSignals(True)
        self.survey.clear()
        self.survey.addItems(names)
        self.survey.blockSignals(False)
        if names:
            self.surveyChosen.emit(names[0])
        else:  # nothing of another project stays behind the hidden tab
            self.inputs.clear()
            self.set_ppk(None)

    def set_inputs(self, groups: list[tuple[str, list[tuple[str, str]]]]) -> None:
        self.inputs.show_groups(groups)

    def set_ppk(self, view: PpkView | None, source: str = "") -> None:
        """Show a PPK solution's QC and quality along time (None: not post-processed yet)."""
        self.shown = view
        for item in (self.quality_plot, self.sigma_plot):
            item.clear()
        if view is None:
            self.qc.clear()
            self.headline.setText(tr("Not post-processed yet: Run > Post-process GNSS."))
            return
        qc = view.report["qc"]
        gaps = len(qc["gaps"])
        headline = tr("<b>Fix rate {fix_rate:.1f} %</b> of {epochs} epochs, 1 gap") if gaps == 1 else tr(
            "<b>Fix rate {fix_rate:.1f} %</b> of {epochs} epochs, {gaps} gaps")
        self.headline.setText(headline.format(fix_rate=100.0 * qc["fix_rate"], epochs=qc["epochs"], gaps=gaps) + source)
        self.qc.show_groups(qc_rows(view))
        self._plot(view)

    def _plot(self, view: PpkView) -> None:
        solution = view.solution
        if not len(solution.time_s):
            return
        first = solution.time_s[0]
        ticks = []
        labels = []
        for flag, name, time_s in quality_epochs(solution):
            colour = QUALITY_COLOURS.get(flag, OTHER_QUALITY_COLOUR)
            self.quality_plot.plot(time_s - first, np.full(len(time_s), flag), pen=None, symbol="s", symbolSize=4,
                                   symbolPen=None, symbolBrush=colour)
            ticks.append((flag, quality_label(name)))
            labels.append(f"<span style='color:{colour}'>■ {quality_label(name)} {len(time_s)}</span>")
        self.quality_plot.getAxis("left").setTicks([ticks])
        flags = [flag for flag, _ in ticks]
        self.quality_plot.setYRange(min(flags) - 0.5, max(flags) + 0.5, padding=0)
        self.quality_plot.setTitle(tr("<b>Solution quality</b>") + "&nbsp;&nbsp;&nbsp;" + "&nbsp;&nbsp;".join(labels),
                                   size="8pt")
        sigma = solution.sigma_ned_m
        horizontal_mm = 1e3 * np.hypot(sigma[:, 0], sigma[:, 1])
        for index, values in enumerate((horizontal_mm, 1e3 * sigma[:, 2])):
            self.sigma_plot.plot(solution.time_s - first, values, pen=plotstyle.pen(index, 1.5), connect="finite")
        self.sigma_plot.setTitle(plotstyle.titled(tr("Position σ [mm]"), [tr("horizontal"), tr("vertical")]), size="8pt")
        for gap in solution.gaps:
            for item in (self.quality_plot, self.sigma_plot):
                region = pg.LinearRegionItem((gap.start_s - first, gap.end_s - first), movable=False, brush=GAP_BRUSH,
                                             pen=pg.mkPen(None))
                item.addItem(region)
        self.quality_plot.setXRange(0.0, solution.time_s[-1] - first, padding=0.01)
