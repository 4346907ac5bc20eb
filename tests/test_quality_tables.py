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


def test_in_chinese_the_rows_verdicts_and_heading_are_chinese():
    """The Plan survey dialog shows them in the application's language (insrail.names' language)."""
    from types import SimpleNamespace

    from insrail.names import in_language
    from insrail.quality.tables import prediction_heading

    inputs = {"gnss": None, "imu": "navigation", "speed_mps": 1.0, "length_m": 240.0, "stops": [(60.0, 10.0), (120.0, 10.0)],
              "outages": [(120.0, 30.0)]}
    with in_language("zh-CN"):
        rows = {row.name: row for row in accuracy_rows(figures(lag5_lateral_m=0.0007), with_outage=True)}
        heading = prediction_heading(SimpleNamespace(inputs=inputs), smoothed=True)
        assert rows["lag5_lateral_m"].verdict == "3 倍标准差超出限值" and rows["cant_m"].verdict == "合格"
    assert rows["lag5_lateral_m"].label == "30 m 弦 5 m 检测轨向（5 m 间隔）"
    assert heading == ("预测精度，平滑解：IMU navigation，相对测量（无 GNSS、无棱镜：里程计、非完整约束与停车点），1 m/s，240 m，"
                       "每 60 m 停车 10 s，120 m 处失锁 30 s")
    english = SimpleNamespace(inputs=dict(inputs, gnss=SimpleNamespace(white_horizontal_m=0.01, white_vertical_m=0.02)))
    assert prediction_heading(english, smoothed=False) == ("Predicted accuracy, forward solution: IMU navigation, GNSS "
                                                           "10/20 mm, 1 m/s, 240 m, 30 s outage at 120 m")
