"""A report in Chinese ([report] language = "zh-CN"): the PDF and the workbook read back (pdftotext,
openpyxl) carry the field's standard terms, embed the CJK font, and hold no English word of insrail's own;
project.toml takes the language as a user writes it."""

from __future__ import annotations

import re
import shutil
import subprocess
import tomllib
from dataclasses import replace

import openpyxl
import pytest
from report_support import processed_project, stored

from insrail.project import ProjectError, load_project
from insrail.project.redesign import REDESIGN_FOLDER, SUMMARY_FILE, TAMPING_FILE, TampingRow, tamping_csv_text
from insrail.project.results import summary_toml
from insrail.project.model import ReportSettings
from insrail.report import write_pdf, write_workbook

#: The terms of the thesis and TB 10754 a Chinese report must use (issue 38).
TERMS = ("轨距", "水平", "超高", "轨向", "高低", "扭曲", "三角坑", "轨距变化率", "30 m 弦 5 m 检测", "调整量", "里程")
#: What may stay in Latin letters: the user's own names, file names, units, standards and abbreviations a
#: Chinese railway document writes so (GNSS, IMU, TQI, RTS, ZUPT, WJ-8, TB 10754, insrail), and project.toml's
#: keys as the file writes them (a fixed stretch of the re-design from ``redesign.fixed[0]``).
LATIN = {"insrail", "mm", "km", "ppm", "ft", "deg", "sqrt", "GPST", "Synthetic", "line", "Test", "down", "track",
         "run1", "csv", "toml", "surveys", "survey", "design", "results", "summary", "project", "reports", "thesis", "Chen",
         "TB", "WJ", "No", "Helvetica", "redesign"}
WORD = re.compile(r"[A-Za-z][A-Za-z_.\d]*[a-z][A-Za-z_.\d]*")


def processing_notices() -> list[dict]:
    """Notices as the pipeline's stages make them (summary.toml's ``[[notices]]``), one of each kind of field:
    numbers, a file name, phrases within phrases, a list of phrases, a key of survey.toml."""
    import numpy as np

    from insrail.geodesy.height_anomaly import fit_height_anomaly
    from insrail.nav.fusion import FilterReset, GapReturn
    from insrail.nav.imu_screening import Outlier
    from insrail.nav.mounting import MountingEstimate
    from insrail.notices import Notice
    from insrail.project.mounting_stage import mounting_notices

    reset = FilterReset(230100.0, "gnss_position", 4.0, 20, 230096.0, ("odometer_nhc",), ("position", "velocity"), (1.0,) * 6,
                        0.02)
    gap = GapReturn("gnss_position", 230200.0, 230230.0, (0.3, 0.3, 0.5), (0.01, 0.01, 0.01))
    outlier = Outlier(230300.0, 41, "angular rate", "z", 2.0, 0.01, "spike")
    mounting = MountingEstimate(np.zeros(3), np.radians([0.0, 0.5, 0.0]), np.radians([np.nan, 0.02, 0.05]),
                                {"roll": "no design cant to compare the cant with"})
    rng = np.random.default_rng(1)
    benchmarks = rng.uniform(0.0, 1000.0, (6, 2))
    heights = fit_height_anomaly(benchmarks, 0.001 * benchmarks[:, 0], model="plane")
    notices = [Notice("fusion", reset.message(), time_s=reset.time_s), Notice("fusion", gap.message(), severity="info"),
               Notice("imu", outlier.describe("imu.txt"), file="imu.txt", time_s=outlier.time_s),
               *mounting_notices(mounting, "survey.toml"),
               *(Notice("heights", w) for w in heights.warnings_for(np.array([5000.0]), np.array([5000.0])))]
    return [notice.to_dict() for notice in notices]


@pytest.fixture(scope="module")
def chinese(tmp_path_factory):
    project = processed_project(tmp_path_factory.mktemp("zh"))
    results = stored(project)
    summary = tomllib.loads((results.folder / "summary.toml").read_text(encoding="utf-8"))
    summary["notices"] = processing_notices()
    (results.folder / "summary.toml").write_bytes(summary_toml(summary))
    return replace(project, report=ReportSettings(language="zh-CN"))


def pdf_text(path) -> str:
    pages = subprocess.run(["pdftotext", "-layout", str(path), "-"], capture_output=True, text=True, check=True).stdout
    return " ".join(pages.split())


def english_words(text: str) -> set[str]:
    """Words in Latin letters with a lower-case letter (abbreviations in capitals are names) not allowed; a word
    with an underscore or a dot is a key or a file name (``trolley.mounting_rpy_deg``, ``imu.txt``), as written."""
    return {word for word in WORD.findall(text) if word.split(".")[0] not in LATIN and word not in LATIN
            and "_" not in word and "." not in word}


@pytest.mark.skipif(shutil.which("pdftotext") is None or shutil.which("pdffonts") is None,
                    reason="poppler-utils not installed; .ci/run installs it")
def test_a_chinese_pdf_uses_the_standard_terms_embeds_its_font_and_has_no_english(chinese, tmp_path):
    path = write_pdf(chinese, stored(chinese), tmp_path / "report.pdf")
    text = pdf_text(path)
    for term in TERMS + ("轨道几何测量报告", "结论", "超限", "左轨", "右轨", "第 1 页"):
        assert term in text, term
    assert "滤波器重置" in text and "作为粗差剔除" in text and "高程异常为外推" in text  # the notices, in Chinese
    assert english_words(text) == set()
    fonts = subprocess.run(["pdffonts", str(path)], capture_output=True, text=True, check=True).stdout
    cjk = [line for line in fonts.splitlines() if "WenQuanYi" in line]
    assert cjk and all(line.split()[-5] == "yes" for line in cjk), fonts  # the "emb" column


def test_a_chinese_workbook_has_chinese_sheets_headers_and_notes(chinese, tmp_path):
    path = write_workbook(chinese, stored(chinese), tmp_path / "report.xlsx")
    book = openpyxl.load_workbook(path, read_only=True)
    assert book.sheetnames == ["汇总", "轨枕", "调整", "材料", "超限", "处理记录"]
    texts = {sheet.title: " ".join(str(value) for row in sheet.iter_rows(values_only=True) for value in row
                                   if isinstance(value, str)) for sheet in book.worksheets}
    sleepers = texts["轨枕"]
    for term in ("轨距", "水平", "超高", "左轨向", "右轨向", "左高低", "右高低", "短波不平顺", "长波不平顺", "30 m 弦 5 m 检测",
                 "扭曲（三角坑）", "轨距变化率", "调整量", "里程", "导向轨", "轨枕编号"):
        assert term in sleepers, term
    assert "调整量" in texts["调整"] and "作业段" in texts["调整"]
    for title in ("汇总", "轨枕", "调整", "材料", "超限"):
        assert english_words(texts[title]) == set(), title
    # the processing log: summary.toml's and project.toml's keys as the files write them, their values and the
    # notices in Chinese
    log = [(key, value) for key, value in book["处理记录"].iter_rows(min_row=1, max_col=2, values_only=True)]
    values = " ".join(value for _, value in log  # a sentence: not an id, a path or a list of ids ("a; b")
                      if isinstance(value, str) and " " in value.replace("; ", ""))
    assert "滤波器重置" in values and "安装角" in values
    assert english_words(values) == set()


USER_PROJECT = """[project]
name = "K12"

[geodesy.crs]
ellipsoid = "CGCS2000"
central_meridian_deg = 114.0

[track]
start_station_m = 0.0

[[surveys]]
name = "run1"
folder = "run1"
"""


def test_project_toml_takes_the_report_language_as_a_user_writes_it(tmp_path):
    (tmp_path / "run1").mkdir()
    (tmp_path / "run1" / "survey.toml").touch()
    (tmp_path / "project.toml").write_text(USER_PROJECT)
    assert load_project(tmp_path).report.language == "en"
    (tmp_path / "project.toml").write_text(USER_PROJECT + '\n[report]\nlanguage = "zh-CN"\n')
    assert load_project(tmp_path).report.language == "zh-CN"
    (tmp_path / "project.toml").write_text(USER_PROJECT + '\n[report]\nlanguage = "chinese"\n')
    with pytest.raises(ProjectError, match=r"report\.language: expected one of 'en', 'zh-CN', found 'chinese'"):
        load_project(tmp_path)


def test_a_chinese_header_wraps_between_characters_at_twice_the_width_of_a_digit():
    """The workbook sizes its header rows by the lines a title wraps to: Chinese has no spaces, wraps between
    any two characters and each character is wider than a digit (one word of 20 characters fills 10 lines of
    a 10-wide column and was sized as one line)."""
    from insrail.report.excel import BOLD_CHARACTER_WIDTH, CJK_CHARACTER_WIDTH, _longest_word, _wrapped_lines

    title = "轨距与水平实测标准轨距设计超高偏差量调整"  # 20 characters
    per_line = int(int(9.0 / BOLD_CHARACTER_WIDTH) // CJK_CHARACTER_WIDTH)  # in the 7 digits of a 10-wide column
    assert _wrapped_lines(title, 10.0) == -(-20 // per_line) == 10
    assert _longest_word(title) == CJK_CHARACTER_WIDTH  # nothing to widen a column for: it breaks anywhere
    assert _wrapped_lines("Gauge and cross level", 10.0) == 4  # English: between words, as before (7 a line)


def _redesigned(project) -> None:
    """``insrail redesign``'s files for survey run1 as the re-design writes them (its summary.toml and tamping.csv,
    filled by hand: the re-design's solve is tests/test_project_redesign.py's), with every kind of mark and bound."""
    results = stored(project)
    station, label = results.columns["station_m"], results.label
    at = [0, 200, 400, 600, 800]
    marks = ("TS", "SC", "PVI", "fixed start (redesign.fixed[0])", "fixed end (turnout W12)")
    rows = [TampingRow(float(station[i]), label[i], 3.0 + i % 5, 2.5, -1.5 + i % 3, 1.0, "") for i in range(len(label))]
    rows += [TampingRow(float(station[i]), label[i], 0.0, 0.0, 0.0, 1.0, mark) for i, mark in zip(at, marks)]
    rows.sort(key=lambda row: (row.station_m, row.mark != ""))
    stretch = {"from_m": float(station[10]), "to_m": float(station[20]), "value_mm": 40.0}
    summary = {
        "survey": "run1", "profile": project.tolerance_profile,
        "settings": {"lift_only": True, "min_lift_mm": 0.0, "max_lift_mm": 40.0, "max_slew_mm": 30.0, "margin_mm": 0.5,
                     "fixed": [{"from_m": float(station[600]), "to_m": float(station[620]), "tolerance_mm": 0.0,
                                "source": "redesign.fixed[0]"},
                               {"from_m": float(station[800]), "to_m": float(station[810]), "tolerance_mm": 0.0,
                                "source": "turnout W12"}]},
        "movement": {"largest_lift_mm": 7.0, "largest_lift_at_m": float(station[4]), "smallest_lift_mm": 2.5,
                     "largest_slew_mm": 1.5, "largest_slew_at_m": float(station[2]), "total_movement_m": 1.2,
                     "sleepers_moved": len(label)},
        "exceedances": {"before": 12, "after": 1},
        "active": [dict(stretch, what=what) for what in ("lift at max_lift", "slew at max_slew", "fixed stretch")],
        "cannot_pass": [dict(stretch, what="short_wave_30m_5m left lateral")],
        "uncertain": [dict(stretch, what="versine_10m right vertical", value_mm=1.9)],
        "not_assessed": [{"check": "versine_10m", "direction": "lateral", "sigma_mm": 1.2, "limit_mm": 2.0,
                          "sleepers": 10, "exceedances_not_listed": 0,
                          "stretches_m": [[float(station[30]), float(station[40])]]}],
    }
    folder = results.folder / REDESIGN_FOLDER
    folder.mkdir()
    (folder / SUMMARY_FILE).write_bytes(summary_toml(summary))
    (folder / TAMPING_FILE).write_text(tamping_csv_text(tuple(rows), "run1", project.tolerance_profile), encoding="utf-8")


@pytest.fixture(scope="module")
def redesigned(tmp_path_factory):
    project = processed_project(tmp_path_factory.mktemp("zh-redesign"))
    _redesigned(project)
    return replace(project, report=ReportSettings(language="zh-CN"))


def test_a_chinese_workbook_of_a_redesigned_survey_has_a_tamping_sheet_without_english(redesigned, tmp_path):
    path = write_workbook(redesigned, stored(redesigned), tmp_path / "report.xlsx")
    book = openpyxl.load_workbook(path, read_only=True)
    assert book.sheetnames[-2:] == ["捣固", "处理记录"]
    tamping = " ".join(str(value) for row in book["捣固"].iter_rows(values_only=True) for value in row
                       if isinstance(value, str))
    for term in ("起道", "拨道", "超高", "里程", "直缓点", "缓圆点", "变坡点", "固定点起点（redesign.fixed[0]）",
                 "固定点终点（道岔 W12）", "作业段 1/", "作业后不能判定通过的区段", "通过余量小于测量不确定度：",
                 "不评定："):
        assert term in tamping, term
    assert english_words(tamping) == set()


@pytest.mark.skipif(shutil.which("pdftotext") is None, reason="poppler-utils not installed; .ci/run installs it")
def test_a_chinese_pdf_of_a_redesigned_survey_has_no_english(redesigned, tmp_path):
    text = pdf_text(write_pdf(redesigned, stored(redesigned), tmp_path / "report.pdf"))
    for term in ("捣固重新设计", "起道", "拨道", "固定点区段", "只起不落", "起道达到最大起道量", "无法通过：短波不平顺", "作业前",
                 "通过余量小于测量不确定度：", "不评定："):
        assert term in text, term
    assert english_words(text) == set()


def test_a_chinese_report_of_a_relative_survey_names_it_and_its_mounting_without_english(chinese, tmp_path):
    """A relative survey (no GNSS, no prism) with the IMU mounting estimated from the survey."""
    results = stored(chinese)
    summary = {**results.summary, "survey": {**results.summary["survey"], "kind": "relative"},
               "fusion": {**results.summary["fusion"], "mounting": {
                   "given_rpy_deg": [0.0, 0.0, 0.0], "applied_rpy_deg": [0.0, 0.512, 0.0],
                   "roll": {"not_estimated": "no design cant to compare the cant with"},
                   "pitch": {"estimate_deg": 0.512, "sigma_deg": 0.02, "applied": True},
                   "yaw": {"not_estimated": "no GNSS: only the NHC gives the direction of travel in the IMU's axes"}}}}
    relative = replace(results, summary=summary)
    book = openpyxl.load_workbook(write_workbook(chinese, relative, tmp_path / "report.xlsx"), read_only=True)
    texts = " ".join(str(value) for sheet in book.worksheets if sheet.title != "处理记录"
                     for row in sheet.iter_rows(values_only=True) for value in row if isinstance(value, str))
    assert "run1（相对测量）" in texts and "相对测量：无 GNSS" in texts
    assert english_words(texts) == set()
    if shutil.which("pdftotext") is None:
        return
    text = pdf_text(write_pdf(chinese, relative, tmp_path / "report.pdf"))
    for term in ("run1（相对测量）", "相对测量：无 GNSS", "IMU 安装角", "俯仰 +0.512°", "（已采用）", "横滚 未估计（无设计超高"):
        assert term in text, term
    assert english_words(text) == set()


def _cjk_system_font() -> bool:
    fonts = subprocess.run(["fc-list", ":lang=zh"], capture_output=True, text=True, check=False) if shutil.which("fc-list") \
        else None
    return bool(fonts and fonts.stdout.strip())


@pytest.mark.slow  # LibreOffice sets every sheet: minutes on a loaded machine
@pytest.mark.skipif(shutil.which("soffice") is None or shutil.which("pdffonts") is None or not _cjk_system_font(),
                    reason="LibreOffice, poppler-utils or a CJK system font (fonts-wqy-microhei) missing; .ci/run "
                           "installs them")
def test_libreoffice_renders_a_chinese_workbook_in_a_cjk_font(chinese, tmp_path):
    """The workbook names no font file: LibreOffice sets its Chinese in a system CJK font (boxes without one)."""
    path = write_workbook(chinese, stored(chinese), tmp_path / "report.xlsx")
    result = subprocess.run(["soffice", f"-env:UserInstallation=file://{tmp_path}/profile", "--headless", "--convert-to",
                             "pdf", "--outdir", str(tmp_path / "pdf"), str(path)],
                            capture_output=True, text=True, timeout=300, check=False)
    assert result.returncode == 0, result.stderr
    rendered = tmp_path / "pdf" / "report.pdf"
    fonts = subprocess.run(["pdffonts", str(rendered)], capture_output=True, text=True, check=True).stdout
    assert any(word in fonts for word in ("WenQuanYi", "NotoSansCJK", "NotoSerifCJK", "Droid")), fonts
    text = pdf_text(rendered)
    for term in ("汇总", "轨距", "水平", "轨向", "高低", "调整量", "里程"):
        assert term in text, term


def not_assessed_reasons():
    """Reasons as the processing makes them: a fusion section's (a list of phrases, its commas written as "; "), a
    turnout's (the user's name of it verbatim, assessed with its profile) and a bridged IMU gap's."""
    from insrail.notices import Phrase
    from insrail.project.gap_sleepers import gap_reason
    from insrail.project.sleeper_integrity import fusion_reasons
    from insrail.track.events import TrackEvent

    section = Phrase("{reasons}", {"reasons": [
        Phrase("{source} {share_pct:.0f} % rejected", {"source": Phrase("gnss_position"), "share_pct": 40.0}),
        Phrase("{source} residuals {ratio:.1f} x their 1-sigma", {"source": Phrase("odometer_nhc"), "ratio": 3.2})]})
    integrity = {"not_valid": [{"time_from_s": 0.0, "time_to_s": 1.0, "reason": str(section), "why": section.to_dict()}]}
    turnout = TrackEvent("turnout", 100.0, 130.0, text="W12", profile="turnout_speed_up")
    return [*(reason for _, _, reason in fusion_reasons(integrity)), turnout.described(), gap_reason(10.0, 10.5)]


def test_a_sleepers_reasons_are_english_in_sleepers_csv_and_chinese_in_the_workbook(chinese, tmp_path):
    from insrail.names import in_language
    from insrail.project.sleeper_integrity import reasons_of, reasons_section, said_reasons, written

    fusion, turnout, gap = not_assessed_reasons()
    column = "; ".join([written(fusion), written(turnout), written(gap)])
    assert column == ("fusion: gnss_position 40 % rejected; odometer_nhc residuals 3.2 x their 1-sigma; "
                      "turnout W12 (assessed with turnout_speed_up); IMU gap of 0.50 s bridged")  # sleepers.csv's
    summary = {"assessment": {"not_assessed_reasons": reasons_section([fusion, turnout, gap, turnout])}}
    with in_language("zh-CN"):
        said = said_reasons(column, reasons_of(summary))
        assert said_reasons("an older insrail's reason", reasons_of(summary)) == "an older insrail's reason"
    assert said == ("组合导航：GNSS 位置 40 % 被拒，里程计与非完整约束 残差为其 1σ 的 3.2 倍；道岔 W12（按 turnout_speed_up 评定）；"
                    "已桥接 0.50 s 的 IMU 数据中断")
    results = stored(chinese)
    reasons = tuple(column if k % 7 == 3 else "" for k in range(len(results)))
    marked = replace(results, not_assessed=reasons,
                     summary={**results.summary, "assessment": {**results.summary["assessment"], **summary["assessment"]}})
    book = openpyxl.load_workbook(write_workbook(chinese, marked, tmp_path / "report.xlsx"), read_only=True)
    texts = [value for row in book["轨枕"].iter_rows(values_only=True) for value in row if isinstance(value, str)]
    assert said in texts and column not in texts
    assert english_words(" ".join(texts)) == set()


def test_the_mountings_reasons_are_said_in_the_reports_language():
    """Why an axis of the IMU's mounting is not estimated reaches the PDF's processing page: a reason with a number
    is a phrase in summary.toml (its English beside it), said in Chinese."""
    import numpy as np

    from insrail.names import in_language
    from insrail.nav.mounting import MountingEstimate, roll_from_cant
    from insrail.report.content import mounting_text

    table = roll_from_cant(np.zeros(3), np.zeros(10), np.zeros(10), 1.5, np.ones(10, dtype=bool)).to_dict()
    assert table["roll"]["not_estimated"] == "fewer than 96 valid sleepers with a design cant"
    assert MountingEstimate.from_dict(table, np.zeros(3)).to_dict() == table
    with in_language("zh-CN"):
        text = mounting_text({"fusion": {"mounting": table}})
    assert "横滚 未估计（具有设计超高的有效轨枕少于 96 根）" in text
    assert english_words(text) == set()
