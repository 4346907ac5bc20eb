"""Reports that leave the office: the crews' Excel workbook and the PDF survey report.

Both read a survey's stored results (:func:`insrail.project.results.load_results`) and the
project's settings; they format and compute no track geometry. Both write atomically and take
``progress(fraction, message)`` and a cancel token (:mod:`insrail.progress`). A report written
before its survey's current results is stale (:func:`report_is_stale`).
"""

from insrail.lazy import lazy_exports

# Each name's submodule is imported when the name is first used: the workbook's writer (openpyxl)
# without the PDF's (reportlab), e.g. in the process that writes the workbook beside the PDF.
_EXPORTS = {
    "excel": ["write_workbook"],
    "pdf": ["write_pdf"],
    "stale": ["report_is_stale", "stale_reports"],
}
__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

__all__ = ["report_is_stale", "stale_reports", "write_pdf", "write_workbook"]
