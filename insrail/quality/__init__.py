"""Accuracy before and after a survey, from the fusion's own error model (no Qt, no I/O).

* :func:`predict` - covariance analysis of a planned run (``prediction``)
* :func:`survey_quality` - the same along a fused survey's measurement timeline, per section (``survey``);
  :func:`epoch_quality` and :func:`sections_along` split it for the pipeline (sections on the chainage)
* :func:`sweep` - one parameter at a time from a baseline, like the thesis's chapter 3 (``sweep``)

The engine, with the exact forward and smoothed cross-covariances behind the lag
differences, is ``insrail.quality.covariance``. See docs/accuracy.md.
"""

from insrail.quality.prediction import AccuracyFigures, GnssQuality, Prediction, predict
from insrail.quality.survey import (
           EpochQuality,
           SectionQuality,
           epoch_quality,
           sections,
           sections_along,
           survey_quality,
)
from insrail.quality.sweep import SweepTable, sweep

__all__ = ["AccuracyFigures", "EpochQuality", "GnssQuality", "Prediction", "SectionQuality", "SweepTable",
           "epoch_quality", "predict", "sections", "sections_along", "survey_quality", "sweep"]
