"""`insrail --help`, `insrail fuse` and `insrail report` import only what they use (a fresh interpreter
per command, its sys.modules read after the command returns): the simulator, the quality tables, the
reports, the GUI and the cluster are never loaded for --help and fuse, --help loads no numerical
library, and the reports load neither the filter nor its compiled kernels."""

import subprocess
import sys

import pytest

#: Run ``insrail ARGS...`` in this interpreter, then write the names of the imported modules to FILE.
RUN_AND_LIST = """
import sys
from insrail.cli.main import main
try:
    code = main(sys.argv[2:])
except SystemExit as stop:
    code = stop.code
open(sys.argv[1], "w").write("\\n".join(sorted(sys.modules)))
sys.exit(code)
"""
#: Modules neither command uses (prefixes: a package and its submodules).
NEVER = ("insrail.sim", "insrail.quality", "insrail.report", "insrail.gui", "insrail.track", "insrail.export",
         "openpyxl", "reportlab", "PySide6", "distributed", "dask", "scipy.stats", "scipy.signal", "scipy.spatial",
         "scipy.sparse")


def imported_by(tmp_path, *args: str) -> set[str]:
    listing = tmp_path / "modules.txt"
    done = subprocess.run([sys.executable, "-c", RUN_AND_LIST, str(listing), *args], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return set(listing.read_text().split())


def loaded(modules: set[str], prefixes) -> list[str]:
    return sorted(m for m in modules if any(m == p or m.startswith(p + ".") for p in prefixes))


def test_help_imports_no_numerical_library_and_no_core(tmp_path):
    modules = imported_by(tmp_path, "--help")
    assert loaded(modules, NEVER + ("numpy", "numba", "scipy", "pyproj", "insrail.nav", "insrail.project")) == []


@pytest.mark.parametrize("command", ["process", "simulate", "predict"])
def test_a_commands_help_imports_no_other_commands_core(tmp_path, command):
    modules = imported_by(tmp_path, command, "--help")
    others = {"process": ("insrail.sim", "insrail.quality"), "simulate": ("insrail.quality",),
              "predict": ("insrail.sim",)}[command]
    assert loaded(modules, others) == []


def test_fuse_imports_only_the_reader_and_the_filter(tiny_nav_survey, tmp_path):
    modules = imported_by(tmp_path, "fuse", str(tiny_nav_survey), "--out", str(tmp_path / "out"),
                          "--no-smoother", "--rate", "10")
    assert "insrail.nav.fusion" in modules  # it did fuse
    assert loaded(modules, NEVER) == []
    assert loaded(modules, ("scipy.special",)) == []  # the gates' chi-square quantiles are tabulated (insrail.nav.chi2)


def test_report_imports_neither_the_filter_nor_the_solvers(tmp_path, tmp_path_factory):
    """Nor scipy, HiGHS and pyproj, which the project model's and the results' modules use only to compute."""
    from report_support import SURVEY, saved_project

    project = saved_project(tmp_path_factory)
    modules = imported_by(tmp_path, "report", str(project.folder), "--survey", SURVEY, "--xlsx",
                          str(tmp_path / "book.xlsx"), "--pdf", str(tmp_path / "report.pdf"))
    assert (tmp_path / "book.xlsx").is_file() and (tmp_path / "report.pdf").is_file()  # it did report
    assert loaded(modules, ("numba", "insrail.nav.fusion", "insrail.quality.survey", "insrail.quality.covariance",
                            "insrail.quality.prediction", "insrail.sim", "insrail.gui", "scipy", "highspy",
                            "pyproj", "distributed", "dask")) == []


def test_each_report_alone_imports_only_its_own_writer(tmp_path, tmp_path_factory):
    """`insrail report --pdf` loads no openpyxl (nor urllib and http, xml.sax.saxutils's imports), `--xlsx`
    no reportlab: some 0.1-0.25 s of start-up each, also the parent's when the two are written side by side."""
    from report_support import SURVEY, saved_project

    project = saved_project(tmp_path_factory)
    for option, writer, other in (("--pdf", "reportlab", ("openpyxl", "urllib.request", "http", "xml.sax.saxutils")),
                                  ("--xlsx", "openpyxl", ("reportlab",))):
        out = tmp_path / f"report{option.replace('--', '.')}"
        modules = imported_by(tmp_path, "report", str(project.folder), "--survey", SURVEY, option, str(out))
        assert out.is_file() and writer in modules  # it did report
        assert loaded(modules, other) == [], option


def test_loading_a_project_with_a_design_imports_no_pipeline(tmp_path):
    """The design file is checked when the project is loaded (every command, the reports) by its reader,
    not through the processing pipeline (the fusion, numba, the solvers)."""
    from pathlib import Path

    folder = tmp_path / "project"
    (folder / "surveys" / "a").mkdir(parents=True)
    (folder / "surveys" / "a" / "survey.toml").touch()
    (folder / "design.xml").write_bytes((Path(__file__).parent / "data" / "landxml" / "handmade_spiral_arc.xml").read_bytes())
    (folder / "project.toml").write_text('[[surveys]]\nname = "a"\nfolder = "surveys/a"\n\n[project]\nname = "x"\n\n'
                                         '[track]\ndesign = "design.xml"\n\n'
                                         '[geodesy.crs]\nellipsoid = "CGCS2000"\ncentral_meridian_deg = 114.3\n')
    modules = imported_by(tmp_path, "report", str(folder), "--check")
    assert loaded(modules, ("insrail.project.pipeline", "numba", "insrail.nav.fusion", "openpyxl", "reportlab")) == []


def test_process_imports_neither_scipy_signal_nor_stats(tiny_nav_survey, tmp_path):
    """The band-passed figures are filtered without scipy.signal (insrail.track.butterworth), which
    imports scipy.stats: 0.85 s of CPU of every processing."""
    import shutil
    import tomllib

    from insrail.project.demo import project_for_simulated_survey

    folder = tmp_path / "project"
    shutil.copytree(tiny_nav_survey, folder / "surveys" / "tiny")
    project_for_simulated_survey(folder, folder / "surveys" / "tiny", name="tiny")
    modules = imported_by(tmp_path, "process", str(folder))
    summary = tomllib.loads((folder / "results" / "tiny" / "summary.toml").read_text(encoding="utf-8"))
    assert "insrail.track.butterworth" in modules and summary["track_quality"]  # it did band-pass
    assert loaded(modules, ("scipy.signal", "scipy.stats")) == []


def test_the_pipeline_and_the_project_import_no_scipy_optimize():
    """scipy.optimize (0.1 s beyond the pipeline's imports) is imported by a line-type fit and the
    adjustment's integer repair when they run, not by every processing's start."""
    code = "import sys, insrail.project.model, insrail.project.pipeline; print(sorted(m for m in sys.modules " \
           "if m.startswith('scipy.optimize')))"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"


def test_the_workbooks_process_imports_neither_the_pdf_writer_nor_the_solvers():
    """The process writing the workbook beside the PDF (insrail.report.both) pays only for openpyxl and the
    results: no reportlab, no scipy, HiGHS or pyproj, no urllib/http (xml.sax.saxutils's imports)."""
    listing = "import sys, insrail.report.both, insrail.report.excel; print('\\n'.join(sorted(sys.modules)))"
    done = subprocess.run([sys.executable, "-c", listing], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert loaded(set(done.stdout.split()), ("reportlab", "scipy", "pyproj", "highspy", "numba", "urllib.request",
                                             "http", "insrail.nav.fusion")) == []
