"""Reports that leave the office: the crews' Excel workbook and the PDF survey report.

Both read a survey's stored results (:func:`insrail.project.results.load_results`) and the
project's settings; they format and compute no track geometry. Both write atomically and take
``progress(fraction, message)`` and a cancel token (:mod:`insrail.progress`). A report written
before its survey's current results is stale (:func:`report_is_stale`).
"""

from insrail.report.excel import write_workbook
from insrail.report.pdf import write_pdf
from insrail.report.stale import report_is_stale, stale_reports

__all__ = ["report_is_stale", "stale_reports", "write_pdf", "write_workbook"]
