"""Notices: what a stage must tell the user about its input or its result, without failing.

A stage that repairs or doubts something (an IMU gap bridged, a record removed as an outlier,
a filter reset, a height anomaly extrapolated, a plausibility check that is borderline) returns
:class:`Notice` objects beside its result; it never prints. The pipeline gathers them, in the
order they happened, into ``summary.toml`` as ``[[notices]]`` tables; from there ``insrail
process`` prints them (``  warning: ...``), the PDF's processing page lists them and the GUI
log shows them, so a notice reaches every place the user looks.

An error (the result would be wrong) is an exception, not a notice: ``InputError`` for a file,
``ValueError`` with the survey and what to do otherwise.

``stage`` is a short word for where it happened (``imu``, ``fusion``, ``gnss``, ``heights``,
``track``, ``assessment``, ``adjustment``, ...); ``message`` is a whole sentence that names the
file and the unit where they matter; ``file``, ``time_s`` (the survey's time scale, GPS seconds
of week) and ``station_m`` (chainage) locate it when known.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

SEVERITIES = ("warning", "info")


@dataclass(frozen=True)
class Notice:
    stage: str
    message: str
    file: str = ""
    time_s: float | None = None
    station_m: float | None = None
    severity: str = "warning"

    def __post_init__(self):
        if self.severity not in SEVERITIES:
            raise ValueError(f"notice severity {self.severity!r}: expected one of {', '.join(SEVERITIES)}")

    def text(self) -> str:
        """One line for a log or a report: ``stage: message``."""
        return f"{self.stage}: {self.message}"

    def to_dict(self) -> dict:
        """The ``[[notices]]`` table (TOML has no null: unknown places are left out)."""
        table = {"stage": self.stage, "severity": self.severity, "message": self.message}
        if self.file:
            table["file"] = self.file
        if self.time_s is not None and math.isfinite(self.time_s):
            table["time_s"] = float(self.time_s)
        if self.station_m is not None and math.isfinite(self.station_m):
            table["station_m"] = float(self.station_m)
        return table

    @classmethod
    def from_dict(cls, table: dict) -> Notice:
        return cls(stage=str(table.get("stage", "")), message=str(table.get("message", "")),
                   file=str(table.get("file", "")), time_s=table.get("time_s"), station_m=table.get("station_m"),
                   severity=str(table.get("severity", "warning")))


def notices_of(summary: dict) -> list[Notice]:
    """The notices recorded in a survey's summary (``[[notices]]``), in order."""
    return [Notice.from_dict(table) for table in summary.get("notices", [])]
