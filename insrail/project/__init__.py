"""insrail.project: project files (``project.toml``) and the end-to-end processing of a survey.

A project folder holds ``project.toml`` (see :mod:`insrail.project.model`), the survey folders it
names, and ``results/<survey>/`` written by :func:`process` (see :mod:`insrail.project.pipeline`).
:func:`compare_surveys` compares repeat runs (:mod:`insrail.project.compare`); :func:`run_batch`
processes many projects in parallel, locally or on a Dask cluster (:mod:`insrail.project.batch`).
"""

from insrail.lazy import lazy_exports

# Each name's submodule is imported when the name is first used: `insrail fuse` imports the lock
# (insrail.project.lock) without the pipeline, the tracks and the quality it does not use.
_EXPORTS = {
    "batch": ["BatchOutcome", "run_batch"],
    "compare": ["compare_surveys"],
    "model": ["HEIGHT_MODELS", "PROJECT_FILE", "HeightSettings", "Project", "ProjectError", "SurveyEntry",
              "load_project", "project_from_settings", "save_project"],
    "pipeline": ["SurveyResults", "fit_heights", "process", "read_design"],
    "results": ["StoredResults", "load_results"],
}
__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

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
