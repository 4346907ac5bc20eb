"""insrail.project: project files (``project.toml``) and the end-to-end processing of a survey.

A project folder holds ``project.toml`` (see :mod:`insrail.project.model`), the survey folders it
names, and ``results/<survey>/`` written by :func:`process` (see :mod:`insrail.project.pipeline`).
:func:`compare_surveys` compares repeat runs (:mod:`insrail.project.compare`); :func:`run_batch`
processes many projects in parallel, locally or on a Dask cluster (:mod:`insrail.project.batch`).
"""

from insrail.project.batch import BatchOutcome, run_batch
from insrail.project.compare import compare_surveys
from insrail.project.model import (
    HEIGHT_MODELS,
    PROJECT_FILE,
    HeightSettings,
    Project,
    ProjectError,
    SurveyEntry,
    load_project,
    project_from_settings,
    save_project,
)
from insrail.project.pipeline import SurveyResults, fit_heights, process, read_design
from insrail.project.results import StoredResults, load_results

__all__ = [
    "HEIGHT_MODELS",
    "PROJECT_FILE",
    "BatchOutcome",
    "HeightSettings",
    "Project",
    "ProjectError",
    "StoredResults",
    "SurveyEntry",
    "SurveyResults",
    "compare_surveys",
    "fit_heights",
    "load_project",
    "load_results",
    "process",
    "project_from_settings",
    "read_design",
    "run_batch",
    "save_project",
]
