"""The prediction tables shared by `insrail predict` and the GUI's Plan survey dialog."""

import math

import pytest

from insrail.quality.prediction import AccuracyFigures
from insrail.quality.tables import ROWS, accuracy_rows, accuracy_table, figure_names


def figures(**values) -> AccuracyFigures:
    base = dict.fromkeys(ROWS, 0.0005)
    base.update(outage_growth_lateral_m=math.nan, outage_growth_vertical_m=math.nan)
    base.update(values)
    return AccuracyFigures(**base)


def test_verdicts_compare_three_sigma_with_the_check_limit():
    rows = {row.name: row for row in accuracy_rows(figures(lag5_lateral_m=0.0007, lag150_vertical_m=0.0034),
                                                   with_outage=False)}
    assert list(rows) == figure_names(False) and "outage_growth_lateral_m" not in rows
    assert rows["lag5_lateral_m"].three_sigma_mm == pytest.approx(2.1) and rows["lag5_lateral_m"].verdict.startswith(
        "exceeds")
    assert rows["lag150_vertical_m"].within_limit is False and rows["lag5_vertical_m"].verdict == "ok"
    assert rows["position_lateral_m"].within_limit is None and rows["position_lateral_m"].verdict == ""


def test_text_table_marks_figures_that_do_not_apply():
    lines = accuracy_table(accuracy_rows(figures(cant_m=0.001), with_outage=True))
    assert lines[0].split()[:4] == ["figure", "1", "sigma", "3"]
    outage = next(line for line in lines if line.startswith("outage: lateral"))
    assert outage.split()[-2:] == ["-", "-"]
    cant = next(line for line in lines if line.startswith("cant"))
    assert cant[36:].split() == ["1.000", "3.000", "2.0", "exceeds", "the", "limit", "at", "3", "sigma"]
