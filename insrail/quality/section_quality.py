"""A survey's predicted accuracy per section (:class:`SectionQuality`) and the weakest section
(:func:`weakness`), apart from the covariance analysis that makes them (``insrail.quality.survey``):
the results and the reports read them without importing the filter and its compiled kernels."""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from insrail.quality.covariance import CovarianceProfile

#: The lags [m] of the ``sigma_lag5_*`` and ``sigma_lag150_*`` figures (here, not with the prediction that makes
#: them, so that the rule of what a survey can assess, insrail.project.assessable, loads without the filter)
SHORT_LAG_M, LONG_LAG_M = 5.0, 150.0
_COLUMNS = ("sigma_lateral_m", "sigma_vertical_m", "sigma_lag5_lateral_m", "sigma_lag5_vertical_m",
            "sigma_lag150_lateral_m", "sigma_lag150_vertical_m", "sigma_cross_level_m", "sigma_along_track_m")


@dataclass(frozen=True)
class SectionQuality:
    """Predicted 1-sigma per section of the survey [m]; NaN where a section has no data
    (no moving epoch, or no lag pair with its midpoint there)."""

    station_from_m: np.ndarray
    station_to_m: np.ndarray
    sigma_lateral_m: np.ndarray
    sigma_vertical_m: np.ndarray
    sigma_lag5_lateral_m: np.ndarray
    sigma_lag5_vertical_m: np.ndarray
    sigma_lag150_lateral_m: np.ndarray
    sigma_lag150_vertical_m: np.ndarray
    sigma_cross_level_m: np.ndarray  # the cross-level (cant): the roll's 1-sigma over the rails' spacing
    sigma_along_track_m: np.ndarray
    smoothed: bool
    profile: CovarianceProfile | None = None  # the covariance analysis behind the figures, when kept

    def weakest(self, figure: str = "sigma_lag5_lateral_m") -> int:
        """Index of the section with the largest value of ``figure``."""
        if figure not in _COLUMNS:
            raise ValueError(f"unknown figure {figure!r}; choose one of {', '.join(_COLUMNS)}")
        return int(np.nanargmax(getattr(self, figure)))

    def weakest_section(self) -> int:
        """Index of the weakest section (:func:`weakness`)."""
        return int(np.argmax(weakness(*(getattr(self, name) for name in _COLUMNS if "lag" in name))))

    def to_rows(self) -> list[dict]:
        """One dict per section for CSV and reports: stations in m, sigmas in mm."""
        rows = []
        for i in range(len(self.station_from_m)):
            row = {"station_from_m": round(float(self.station_from_m[i]), 3),
                   "station_to_m": round(float(self.station_to_m[i]), 3)}
            for name in _COLUMNS:
                row[name[:-2] + "_mm"] = round(1e3 * float(getattr(self, name)[i]), 3)
            rows.append(row)
        return rows


def weakness(*lag_sigmas: np.ndarray) -> np.ndarray:
    """Per section, how far its irregularity figures (the 5 m and 150 m lag sigmas, lateral and
    vertical, in any one unit) stand above the survey's median: the largest ratio to the median
    over the figures; -inf for a section without any. Ratios, because the figures differ by an
    order of magnitude. The weakest section has the largest value."""
    lags = np.column_stack(lag_sigmas).astype(float)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = lags / np.nanmedian(lags, axis=0)
    return np.max(np.where(np.isfinite(ratio), ratio, -np.inf), axis=1)
