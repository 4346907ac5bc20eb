"""The Plan survey dialog: the accuracy a planned run will reach, before going out (``insrail predict``).

The inputs are those of the command: IMU profile, white GNSS sigmas, speed, length, a GNSS
outage mid-run, the aiding used and the solution (smoothed or forward), and optionally one
parameter swept over several values. :func:`insrail.quality.predict` (or ``sweep``) runs in a
worker; the table is :mod:`insrail.quality.tables`, the one the command prints.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import pyqtgraph as pg
from PySide6.QtCore import Qt
from PySide6.QtGui import QColor
from PySide6.QtWidgets import (
    QCheckBox,
    QComboBox,
    QDialog,
    QDialogButtonBox,
    QFormLayout,
    QGroupBox,
    QHBoxLayout,
    QHeaderView,
    QLabel,
    QLineEdit,
    QProgressBar,
    QPushButton,
    QSplitter,
    QTableWidget,
    QTableWidgetItem,
    QVBoxLayout,
    QWidget,
)

from insrail.gui import plotstyle
from insrail.gui.choices import choose, chosen, fill
from insrail.gui.forms import spin_box
from insrail.gui.importer import shipped_names
from insrail.gui.worker import TaskWorker
from insrail.names import quantity_name
from insrail.nav.fusion_options import FusionOptions
from insrail.progress import ProgressMessage, progress_text
from insrail.quality import GnssQuality, Prediction, SweepTable, predict
from insrail.quality.sweep import PARAMETERS, sweep
from insrail.quality.tables import (
    ROWS,
    SWEEP_VALUES,
    FigureRow,
    accuracy_rows,
    prediction_heading,
    sweep_rows,
)
from insrail.gui.translation import tr, tr_noop

NO_SWEEP = "none"
PROGRESS_STEPS = 1000
OK_COLOUR, EXCEEDS_COLOUR = QColor("#1B7F3B"), QColor("#C00000")
#: The figures the sweep plot draws (their 3 sigma against the limits of their checks), with short
#: labels: a long title would widen the plot beyond the dialog.
SWEEP_PLOT = {"lag5_lateral_m": tr_noop("5 m lag lateral"), "lag5_vertical_m": tr_noop("5 m lag vertical"),
              "lag150_lateral_m": tr_noop("150 m lag lateral"), "lag150_vertical_m": tr_noop("150 m lag vertical"),
              "cant_m": tr_noop("cant")}


@dataclass(frozen=True)
class PlanInputs:
    """The dialog's inputs in SI units, as ``insrail predict`` takes them."""

    imu: str
    gnss: GnssQuality
    speed_mps: float
    length_m: float
    outage_s: float
    aiding: FusionOptions
    sweep: str | None
    sweep_values: tuple[float, ...]

    @property
    def outages(self) -> tuple[tuple[float, float], ...]:
        """The command's outage: mid-run, (station [m], duration [s])."""
        return ((0.5 * self.length_m, self.outage_s),) if self.outage_s > 0 else ()

    def run(self, progress, cancel) -> Prediction | SweepTable:
        if self.sweep is None:
            return predict(self.imu, self.gnss, self.aiding, speed_mps=self.speed_mps, length_m=self.length_m,
                           outages=self.outages, progress=progress, cancel=cancel)
        return sweep(self.sweep, self.sweep_values, self.imu, self.gnss, speed_mps=self.speed_mps, aiding=self.aiding,
                     length_m=self.length_m, outages=self.outages, progress=progress, cancel=cancel)


def _cell(text: str, align=Qt.AlignRight | Qt.AlignVCenter) -> QTableWidgetItem:
    item = QTableWidgetItem(text)
    item.setTextAlignment(align)
    item.setFlags(Qt.ItemIsEnabled | Qt.ItemIsSelectable)
    return item


def _mm(value_mm: float) -> str:
    return "–" if math.isnan(value_mm) else f"{value_mm:.3f}"


class PlanSurveyDialog(QDialog):
    """Not modal: the window stays usable while a prediction runs."""

    def __init__(self, parent=None):
        super().__init__(parent)
        plotstyle.configure()
        self.setWindowTitle(tr("Plan survey — predicted accuracy"))
        self.worker: TaskWorker | None = None
        self.result: Prediction | SweepTable | None = None
        self.running_inputs: PlanInputs | None = None
        self.shown_inputs: PlanInputs | None = None

        self.imu = QComboBox()
        fill(self.imu, "processing.imu_profile", shipped_names("imu_profiles"))
        choose(self.imu, "nav")
        self.imu.setToolTip(tr("IMU profile from resources/imu_profiles (bias, random walks)"))
        self.gnss_horizontal = spin_box(0.5, 500.0, 1, 10.0, " mm", 1.0)
        self.gnss_vertical = spin_box(0.5, 500.0, 1, 20.0, " mm", 1.0)
        for box in (self.gnss_horizontal, self.gnss_vertical):
            box.setToolTip(tr("white (epoch-to-epoch) GNSS sigma; the fusion adds its correlated part"))
        self.speed = spin_box(0.05, 20.0, 2, 1.0, " m/s", 0.25)
        self.length = spin_box(200.0, 100_000.0, 0, 1000.0, " m", 100.0)
        self.length.setToolTip(tr("track length after a 300 s static alignment (about 1.5 s of computing per km)"))
        self.outage = spin_box(0.0, 3600.0, 0, 0.0, " s", 10.0)
        self.outage.setSpecialValueText(tr("none"))
        self.outage.setToolTip(tr("a GNSS outage of this duration in the middle of the run"))
        self.smoothed = QComboBox()
        self.smoothed.addItems([tr("smoothed (RTS)"), tr("forward filter")])
        self.odometer = QCheckBox(tr("odometer"))
        self.nhc = QCheckBox(tr("non-holonomic constraint (NHC)"))
        self.zupt = QCheckBox(tr("zero-velocity updates at rest (ZUPT)"))
        for box in (self.odometer, self.nhc, self.zupt):
            box.setChecked(True)
        self.sweep = QComboBox()
        self.sweep.addItem(tr("none"), NO_SWEEP)
        for parameter in SWEEP_VALUES:  # the parameter's name in words, its id the item's data
            self.sweep.addItem(quantity_name(parameter).name, parameter)
        self.sweep.setToolTip(tr("vary one parameter from the baseline, like the thesis's chapter 3"))
        self.sweep_values = QLineEdit()
        self.sweep.currentIndexChanged.connect(lambda _: self._sweep_chosen(self.sweep.currentData()))

        form = QFormLayout()
        form.addRow(tr("IMU profile"), self.imu)
        form.addRow(tr("GNSS σ horizontal"), self.gnss_horizontal)
        form.addRow(tr("GNSS σ vertical"), self.gnss_vertical)
        form.addRow(tr("Speed"), self.speed)
        form.addRow(tr("Track length"), self.length)
        form.addRow(tr("GNSS outage mid-run"), self.outage)
        form.addRow(tr("Solution"), self.smoothed)
        aiding = QGroupBox(tr("Aiding"))
        aiding_layout = QVBoxLayout(aiding)
        for box in (self.odometer, self.nhc, self.zupt):
            aiding_layout.addWidget(box)
        sweep_form = QFormLayout()
        sweep_form.addRow(tr("Sweep"), self.sweep)
        sweep_form.addRow(tr("Values"), self.sweep_values)

        self.run_button = QPushButton(tr("Run"))
        self.run_button.setDefault(True)
        self.run_button.clicked.connect(self.run)
        self.cancel_button = QPushButton(tr("Cancel"))
        self.cancel_button.setEnabled(False)
        self.cancel_button.clicked.connect(self.cancel)
        self.progress = QProgressBar()
        self.progress.setRange(0, PROGRESS_STEPS)
        self.progress.setTextVisible(False)
        self.message = QLabel()
        self.message.setWordWrap(True)
        run_row = QHBoxLayout()
        run_row.addWidget(self.run_button)
        run_row.addWidget(self.cancel_button)

        inputs = QWidget()
        inputs_layout = QVBoxLayout(inputs)
        inputs_layout.addLayout(form)
        inputs_layout.addWidget(aiding)
        inputs_layout.addLayout(sweep_form)
        inputs_layout.addStretch(1)
        inputs_layout.addLayout(run_row)
        inputs_layout.addWidget(self.progress)
        inputs_layout.addWidget(self.message)

        self.heading = QLabel(tr("Set the planned run and press Run."))
        self.heading.setWordWrap(True)
        self.table = QTableWidget()
        self.table.verticalHeader().hide()
        self.table.setAlternatingRowColors(True)
        self.plot = pg.PlotWidget()
        self.plot.hide()
        results = QSplitter(Qt.Vertical)
        results.addWidget(self.table)
        results.addWidget(self.plot)
        results.setSizes([300, 330])
        right = QWidget()
        right_layout = QVBoxLayout(right)
        right_layout.setContentsMargins(0, 0, 0, 0)
        right_layout.addWidget(self.heading)
        right_layout.addWidget(results, 1)

        buttons = QDialogButtonBox(QDialogButtonBox.Close)
        buttons.rejected.connect(self.reject)
        body = QHBoxLayout()
        body.addWidget(inputs)
        body.addWidget(right, 1)
        layout = QVBoxLayout(self)
        layout.addLayout(body, 1)
        layout.addWidget(buttons)
        self._sweep_chosen(NO_SWEEP)
        self.resize(1150, 620)

    # ------------------------------------------------------------------ inputs

    def _sweep_chosen(self, parameter: str) -> None:
        sweeping = parameter != NO_SWEEP
        self.sweep_values.setEnabled(sweeping)
        self.sweep_values.clear()
        if sweeping:
            unit = PARAMETERS[parameter][0]
            self.sweep_values.setPlaceholderText(f"{' '.join(f'{v:g}' for v in SWEEP_VALUES[parameter])}  [{unit}]")
            self.sweep_values.setToolTip(tr("values in {unit}, separated by spaces; empty: the typical range shown").format(
                unit=unit))

    def inputs(self) -> PlanInputs:
        """The inputs as entered; ValueError names a field that cannot be read."""
        parameter = self.sweep.currentData()
        values: tuple[float, ...] = ()
        if parameter != NO_SWEEP:
            text = self.sweep_values.text().strip()
            try:
                values = tuple(float(v) for v in re.split(r"[\s,;]+", text)) if text else SWEEP_VALUES[parameter]
            except ValueError:
                raise ValueError(tr("sweep values: expected numbers separated by spaces, found {text}").format(
                    text=repr(text))) from None
        return PlanInputs(
            imu=chosen(self.imu),
            gnss=GnssQuality(1e-3 * self.gnss_horizontal.value(), 1e-3 * self.gnss_vertical.value()),
            speed_mps=self.speed.value(), length_m=self.length.value(), outage_s=self.outage.value(),
            aiding=FusionOptions(smoother=self.smoothed.currentIndex() == 0, use_odometer=self.odometer.isChecked(),
                                 use_nhc=self.nhc.isChecked(), use_zupt=self.zupt.isChecked()),
            sweep=None if parameter == NO_SWEEP else parameter, sweep_values=values)

    # ------------------------------------------------------------------ running

    def run(self) -> TaskWorker | None:
        if self.worker is not None:
            return None
        try:
            inputs = self.inputs()
        except ValueError as error:
            self._say(str(error), error=True)
            return None
        self.running_inputs = inputs
        # Bound methods of the dialog: the worker's signals reach them as queued calls in the GUI thread.
        self.worker = TaskWorker(tr("prediction"), inputs.run, self)
        self.worker.progressed.connect(self._progressed)
        self.worker.succeeded.connect(self._show)
        self.worker.failed.connect(self._failed)
        self.worker.cancelled.connect(self._cancelled)
        self.worker.finished.connect(self._finished)
        self.progress.setValue(0)
        self._say(tr("predicting…"))
        self.run_button.setEnabled(False)
        self.cancel_button.setEnabled(True)
        self.worker.start()
        return self.worker

    def cancel(self) -> None:
        if self.worker is not None:
            self.worker.cancel()
            self.cancel_button.setEnabled(False)

    def _progressed(self, fraction: float, message: ProgressMessage) -> None:
        self.progress.setValue(round(fraction * PROGRESS_STEPS))
        self.message.setText(progress_text(message))

    def _failed(self, message: str) -> None:
        self._say(message, error=True)

    def _cancelled(self) -> None:
        self._say(tr("cancelled"))

    def _say(self, message: str, error: bool = False) -> None:
        self.message.setStyleSheet("color: #C00000" if error else "")
        self.message.setText(message)

    def _finished(self) -> None:
        self.worker.deleteLater()
        self.worker = None
        self.run_button.setEnabled(True)
        self.cancel_button.setEnabled(False)

    def done(self, code: int) -> None:
        """Closing stops a running prediction first (its thread must not outlive the dialog)."""
        if self.worker is not None:
            self.worker.cancel()
            self.worker.wait()
        super().done(code)

    # ------------------------------------------------------------------ results

    def _show(self, result: Prediction | SweepTable) -> None:
        inputs = self.running_inputs
        self.result, self.shown_inputs = result, inputs
        smoothed = inputs.aiding.smoother
        with_outage = bool(inputs.outages)
        if isinstance(result, Prediction):
            self.heading.setText(prediction_heading(result, smoothed))
            self._fill_figures(accuracy_rows(result.smoothed if smoothed else result.forward, with_outage))
            self.plot.hide()
        else:
            solution = tr("smoothed solution") if smoothed else tr("forward solution")
            self.heading.setText(tr("{solution}, 1 sigma [mm], {parameter} in {unit}; the plot shows 3 sigma against "
                                    "the limits").format(solution=solution, parameter=quantity_name(result.parameter).name,
                                                        unit=result.unit))
            rows = sweep_rows(result, smoothed, with_outage)
            self._fill_sweep(result, rows)
            self._plot_sweep(result, rows)
        self._say(tr("done"))

    def _fill_figures(self, rows: list[FigureRow]) -> None:
        table = self.table
        table.clear()
        table.setColumnCount(5)
        table.setRowCount(len(rows))
        table.setHorizontalHeaderLabels([tr("Figure"), "1σ [mm]", "3σ [mm]", tr("Limit [mm]"), tr("3σ against the limit")])
        for r, row in enumerate(rows):
            table.setItem(r, 0, _cell(row.label, Qt.AlignLeft | Qt.AlignVCenter))
            table.setItem(r, 1, _cell(_mm(row.sigma_mm)))
            table.setItem(r, 2, _cell(_mm(row.three_sigma_mm)))
            table.setItem(r, 3, _cell("" if row.limit_mm is None else f"{row.limit_mm:.1f}"))
            verdict = _cell(row.verdict, Qt.AlignLeft | Qt.AlignVCenter)
            if row.within_limit is not None:
                verdict.setForeground(OK_COLOUR if row.within_limit else EXCEEDS_COLOUR)
            table.setItem(r, 4, verdict)
        header = table.horizontalHeader()
        header.setSectionResizeMode(0, QHeaderView.ResizeToContents)
        header.setSectionResizeMode(4, QHeaderView.Stretch)

    def _fill_sweep(self, result: SweepTable, rows: list[tuple[float, list[FigureRow]]]) -> None:
        """One row per figure, one column per value (the command's table transposed: it fits a dialog)."""
        table = self.table
        table.clear()
        figures = rows[0][1]
        table.setColumnCount(2 + len(rows))
        table.setRowCount(len(figures))
        table.setHorizontalHeaderLabels([tr("Figure, 1σ [mm]"), tr("Limit [mm]"),
                                         *(f"{value:g} {result.unit}" for value, _ in rows)])
        for r, figure in enumerate(figures):
            table.setItem(r, 0, _cell(figure.label, Qt.AlignLeft | Qt.AlignVCenter))
            table.setItem(r, 1, _cell("" if figure.limit_mm is None else f"{figure.limit_mm:.1f}"))
        for c, (_, value_rows) in enumerate(rows, start=2):
            for r, row in enumerate(value_rows):
                cell = _cell(_mm(row.sigma_mm))
                if row.within_limit is False:
                    cell.setForeground(EXCEEDS_COLOUR)
                    cell.setToolTip(f"3σ {row.three_sigma_mm:.3f} mm: {row.verdict}")
                table.setItem(r, c, cell)
        header = table.horizontalHeader()
        header.setSectionResizeMode(QHeaderView.ResizeToContents)
        header.setStretchLastSection(True)

    def _plot_sweep(self, result: SweepTable, rows: list[tuple[float, list[FigureRow]]]) -> None:
        item = self.plot.getPlotItem()
        item.clear()
        values = [value for value, _ in rows]
        logarithmic = max(values) / min(values) >= 10.0
        item.setLogMode(x=logarithmic, y=False)
        # Ticks at the swept values only: pyqtgraph's logarithmic minor ticks crowd into each other.
        item.getAxis("bottom").setTicks([[(math.log10(v) if logarithmic else v, f"{v:g}") for v in values]])
        for index, name in enumerate(SWEEP_PLOT):
            three_sigma = [next(row.three_sigma_mm for row in figures if row.name == name) for _, figures in rows]
            item.plot(values, three_sigma, pen=plotstyle.pen(index, 2), symbol="o", symbolSize=6,
                      symbolBrush=plotstyle.COLOURS[index], symbolPen=None)
        for limit in sorted({ROWS[name][1] for name in SWEEP_PLOT}):
            item.addItem(pg.InfiniteLine(limit, angle=0, pen=plotstyle.LIMIT_PEN,
                                         label=f"{limit:g} mm", labelOpts={"position": 0.04, "color": "#C00000"}))
        item.setTitle(plotstyle.titled("3σ [mm]", [tr(label) for label in SWEEP_PLOT.values()]), size="8pt")
        item.setLabel("bottom", f"{quantity_name(result.parameter).name} [{result.unit}]")
        item.setLabel("left", "3σ [mm]")
        self.plot.show()
