"""Accuracy before and after a survey, from the fusion's own error model (no Qt, no I/O).

* :func:`predict` - covariance analysis of a planned run (``prediction``)
* :func:`survey_quality` - the same along a fused survey's measurement timeline, per section (``survey``);
  :func:`epoch_quality` and :func:`sections_along` split it for the pipeline (sections on the chainage)
* ``sweep.sweep`` - one parameter at a time from a baseline, like the thesis's chapter 3 (imported from
  ``insrail.quality.sweep``: a lazily imported name cannot share its module's name)

The engine, with the exact forward and smoothed cross-covariances behind the lag
differences, is ``insrail.quality.covariance``. See docs/accuracy.md. A name's submodule is imported
when the name is first used (:func:`insrail.lazy.lazy_exports`): the results and the reports read
:class:`SectionQuality` (``section_quality``) without importing the filter and its compiled kernels.
"""

from insrail.lazy import lazy_exports

_EXPORTS = {
    "prediction": ["AccuracyFigures", "GnssQuality", "Prediction", "predict"],
    "section_quality": ["SectionQuality"],
    "survey": ["EpochQuality", "epoch_quality", "sections", "sections_along", "survey_quality"],
    "sweep": ["SweepTable"],
}
__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

__all__ = ["AccuracyFigures", "EpochQuality", "GnssQuality", "Prediction", "SectionQuality", "SweepTable",
           "epoch_quality", "predict", "sections", "sections_along", "survey_quality"]
