"""A project around a simulated survey: what ``insrail demo`` builds and processes.

The simulator writes the survey plus ``truth/``; the project takes the engineering CRS the
simulation used (truth/scenario.toml), the survey's GNSS-levelling benchmarks for the height
model, and the simulated design alignment (truth/design.csv).
"""

from __future__ import annotations

import tomllib
from pathlib import Path

from insrail.geodesy.crs import EngineeringCRS
from insrail.project.model import HeightSettings, Project, SurveyEntry, save_project


def project_for_simulated_survey(project_folder: str | Path, survey_folder: str | Path, name: str = "demo") -> Project:
    """Write ``project.toml`` in ``project_folder`` for the simulated survey in ``survey_folder``
    (which must lie inside the project folder) and return the project."""
    project_folder = Path(project_folder)
    survey_folder = Path(survey_folder)
    relative = survey_folder.resolve().relative_to(project_folder.resolve()).as_posix()
    scenario = tomllib.loads((survey_folder / "truth" / "scenario.toml").read_text(encoding="utf-8"))
    project = Project(
        folder=project_folder,
        name=name,
        description=f"Simulated survey {scenario['scenario']['name']!r}, seed {scenario['seed']}",
        crs=EngineeringCRS.from_settings(scenario["engineering_crs"], "engineering_crs"),
        height=HeightSettings(benchmarks=f"{relative}/benchmarks.txt"),
        surveys=(SurveyEntry(survey_folder.name, relative),),
        design=f"{relative}/truth/design.csv",
    )
    save_project(project)
    return project
