"""The workbook and the PDF written side by side (insrail.report.both): the workbook in a spawned
or a forked process gives the same workbook as in this one; its failure, the PDF's and a cancel reach the caller
with their messages, and leave no file half-written."""

from __future__ import annotations

import multiprocessing
import threading

import pytest
from openpyxl import load_workbook
from report_support import shared_project, stored

from insrail.progress import Cancelled
from insrail.report import write_workbook
from insrail.report.both import write_both


def _values(path) -> dict:
    """Every cell's value of a workbook but the time it was written."""
    book = load_workbook(path, read_only=True)
    return {(sheet, row, column): value for sheet in book.sheetnames
            for row, cells in enumerate(book[sheet].iter_rows(values_only=True))
            for column, value in enumerate(cells) if not (isinstance(value, str) and value.endswith(" UTC"))}


def _left_over(folder) -> list[str]:
    return sorted(path.name for path in folder.iterdir() if path.name.endswith(".tmp"))


@pytest.mark.parametrize("method", ["spawn", "fork"])
def test_side_by_side_writes_the_same_workbook_and_a_pdf(tmp_path_factory, tmp_path, monkeypatch, method):
    """The workbook's own process, spawned (the GUI, the batch) or forked (insrail report), writes the
    workbook this process would, beside the PDF, with one progress for both."""
    import insrail.report.both as both

    monkeypatch.setattr(both, "start_method", lambda: method)
    project = shared_project(tmp_path_factory)
    results = stored(project)
    seen = []
    written = write_both(project, results, tmp_path / "book.xlsx", tmp_path / "report.pdf",
                         progress=lambda fraction, message: seen.append(fraction), concurrent=True)
    assert written == [tmp_path / "book.xlsx", tmp_path / "report.pdf"]
    assert (tmp_path / "report.pdf").read_bytes().startswith(b"%PDF")
    write_workbook(project, results, tmp_path / "here.xlsx")
    assert _values(tmp_path / "book.xlsx") == _values(tmp_path / "here.xlsx")
    assert seen and max(seen) == 1.0 and all(0.0 <= f <= 1.0 for f in seen)  # one progress for both
    assert not multiprocessing.active_children() and _left_over(tmp_path) == []


def test_the_child_is_forked_only_from_a_process_of_one_thread():
    import subprocess
    import sys

    import insrail.report.both as both

    alone = subprocess.run([sys.executable, "-c", "from insrail.report.both import start_method; print(start_method())"],
                           capture_output=True, text=True, check=True).stdout.strip()
    assert alone == "fork"  # as `insrail report` runs it (Linux: /proc/self/task)
    release = threading.Event()
    other = threading.Thread(target=release.wait)
    other.start()
    try:
        assert both.start_method() == "spawn"  # another thread might hold a lock the child would copy held
    finally:
        release.set()
        other.join()


@pytest.mark.parametrize("method", ["spawn", "fork"])
def test_a_failing_workbook_reaches_the_caller_with_its_message(tmp_path_factory, tmp_path, monkeypatch, method):
    import insrail.report.both as both

    monkeypatch.setattr(both, "start_method", lambda: method)
    project = shared_project(tmp_path_factory)
    (tmp_path / "book.xlsx").mkdir()  # the workbook's process refuses a folder as its file
    with pytest.raises(OSError) as failed:
        write_both(project, stored(project), tmp_path / "book.xlsx", tmp_path / "report.pdf", concurrent=True)
    assert "book.xlsx" in str(failed.value)
    pdf = tmp_path / "report.pdf"  # stopped by the failure, or finished before it: never half-written
    assert not pdf.exists() or pdf.read_bytes().rstrip().endswith(b"%%EOF")
    assert not multiprocessing.active_children() and _left_over(tmp_path) == []


@pytest.mark.parametrize("method", ["spawn", "fork"])
def test_a_failing_pdf_stops_the_workbook_and_reaches_the_caller(tmp_path_factory, tmp_path, monkeypatch, method):
    import insrail.report.both as both

    monkeypatch.setattr(both, "start_method", lambda: method)
    project = shared_project(tmp_path_factory)
    (tmp_path / "report.pdf").mkdir()
    with pytest.raises(OSError) as failed:
        write_both(project, stored(project), tmp_path / "book.xlsx", tmp_path / "report.pdf", concurrent=True)
    assert "report.pdf" in str(failed.value)
    assert not (tmp_path / "book.xlsx").exists() or _values(tmp_path / "book.xlsx")  # absent or whole
    assert not multiprocessing.active_children() and _left_over(tmp_path) == []


@pytest.mark.parametrize("method", ["spawn", "fork"])
def test_cancel_stops_both_and_writes_nothing(tmp_path_factory, tmp_path, monkeypatch, method):
    import insrail.report.both as both

    monkeypatch.setattr(both, "start_method", lambda: method)
    project = shared_project(tmp_path_factory)
    cancel = threading.Event()
    cancel.set()
    with pytest.raises(Cancelled):
        write_both(project, stored(project), tmp_path / "book.xlsx", tmp_path / "report.pdf", cancel=cancel,
                   concurrent=True)
    assert sorted(path.name for path in tmp_path.iterdir()) == []
    assert not multiprocessing.active_children()


def test_one_after_the_other_where_no_second_cpu_is_free(tmp_path_factory, tmp_path, monkeypatch):
    import insrail.report.both as both

    monkeypatch.setattr(both, "side_by_side", lambda sleepers, method: False)
    monkeypatch.setattr(both.multiprocessing, "get_context", lambda method: pytest.fail("a process was started"))
    project = shared_project(tmp_path_factory)
    write_both(project, stored(project), tmp_path / "book.xlsx", tmp_path / "report.pdf")
    assert (tmp_path / "book.xlsx").is_file() and (tmp_path / "report.pdf").is_file()


def test_one_after_the_other_the_content_is_made_once(tmp_path_factory, tmp_path, monkeypatch):
    """In one process both reports present one content (its columns, chainage axis, adjustment work made once)."""
    import insrail.report.both as both
    import insrail.report.content as content
    import insrail.report.excel as excel
    import insrail.report.pdf as pdf

    made = []
    load = content.load_report_content
    for module in (content, excel, pdf):
        monkeypatch.setattr(module, "load_report_content", lambda *args: made.append(load(*args)) or made[-1])
    monkeypatch.setattr(both, "side_by_side", lambda sleepers, method: False)
    project = shared_project(tmp_path_factory)
    write_both(project, stored(project), tmp_path / "book.xlsx", tmp_path / "report.pdf")
    assert len(made) == 1 and (tmp_path / "book.xlsx").is_file() and (tmp_path / "report.pdf").is_file()


def test_an_error_that_does_not_pickle_keeps_its_kind_and_message():
    from insrail.io.atomic import NotARegularFile
    from insrail.report.both import _portable

    error = NotARegularFile("/x/book.xlsx", "a folder")
    sent = _portable(error)
    assert isinstance(sent, OSError) and str(sent) == str(error)


def test_a_short_survey_or_a_busy_machine_is_written_in_one_process(monkeypatch):
    import insrail.report.both as both

    monkeypatch.setattr(both.os, "sched_getaffinity", lambda pid: {0, 1, 2, 3})
    monkeypatch.setattr(both, "running_tasks", lambda: 1.0)
    assert both.side_by_side(both.SIDE_BY_SIDE_MIN_SLEEPERS)
    assert not both.side_by_side(both.SIDE_BY_SIDE_MIN_SLEEPERS - 1)  # its workbook is quicker than a start-up
    assert both.side_by_side(both.FORKED_MIN_SLEEPERS, "fork")  # a forked child starts at once
    assert not both.side_by_side(both.FORKED_MIN_SLEEPERS - 1, "fork")
    monkeypatch.setattr(both, "running_tasks", lambda: 4.0)
    assert not both.side_by_side(16_000)  # no CPU idle
    assert not both.side_by_side(16_000, "fork")
    monkeypatch.setattr(both, "running_tasks", lambda: 1.0)
    monkeypatch.setattr(both.os, "sched_getaffinity", lambda pid: {0})
    assert not both.side_by_side(16_000)  # one CPU


def test_the_running_tasks_are_counted_now_this_process_included():
    import insrail.report.both as both

    assert both.running_tasks() >= 1.0  # this test is running
