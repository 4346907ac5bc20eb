"""insrail export --format tamping / tamping-template: each file read back gives tamping.csv's rows."""

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from insrail.export import write_export
from insrail.export.tamping import load_template, read_tamping, read_template_export
from insrail.io.errors import InputError
from insrail.project.redesign import REDESIGN_FOLDER, TAMPING_FILE, TampingRow, tamping_csv_text

ROWS = (
    TampingRow(1000.0, "K1+000.000", 0.0, 0.0, 0.0, 0.0, ""),
    TampingRow(1000.625, "K1+000.625", 3.4, 2.9, -1.2, 0.5, ""),
    TampingRow(1001.0, "K1+001.000", 4.0, 3.0, -2.0, 1.0, "TS"),
    TampingRow(1001.25, "K1+001.250", 12.5, 11.0, 4.5, 1.5, ""),
    TampingRow(1001.875, "K1+001.875", 0.0, 0.0, 0.0, 0.0, "fixed start (bridge, Xiaohe)"),
)


def _results(tmp_path: Path):
    folder = tmp_path / "results" / "run1"
    (folder / REDESIGN_FOLDER).mkdir(parents=True)
    (folder / REDESIGN_FOLDER / TAMPING_FILE).write_text(tamping_csv_text(ROWS, "run1", "cn_conventional_160"))
    return SimpleNamespace(folder=folder, survey="run1"), SimpleNamespace(name="line 3 tamping", report=SimpleNamespace(language="en"))


def test_generic_layout_reads_back_with_its_conventions(tmp_path):
    results, project = _results(tmp_path)
    path = write_export(project, results, "tamping", tmp_path / "out.csv")
    table = read_tamping(path)
    assert table.metadata["project"] == "line 3 tamping"
    assert "lift + up" in table.metadata["convention"] and "slew + to the right" in table.metadata["convention"]
    assert np.allclose(table.station_m, [r.station_m for r in ROWS])
    assert np.allclose(table.values["slew"], [r.slew_mm for r in ROWS])
    assert table.mark[-1] == "fixed start (bridge, Xiaohe)"
    assert table.label[2] == "K1+001.000"


def test_template_layout_units_signs_spacing_read_back(tmp_path):
    results, project = _results(tmp_path)
    template_path = tmp_path / "machine.toml"
    # written the way a user writes one: only what differs from the defaults
    template_path.write_text(
        'name = "machine X"\nseparator = ";"\nspacing_m = 0.5\ncomment = "//"\n'
        '[[columns]]\nfield = "station"\ntitle = "KM"\nunit = "km"\n'
        '[[columns]]\nfield = "lift_left"\ntitle = "HL"\nunit = "cm"\n'
        '[[columns]]\nfield = "slew"\ntitle = "RICHT"\nsign = -1\n'
        '[[columns]]\nfield = "mark"\n')
    template = load_template(template_path)
    path = write_export(project, results, "tamping-template", tmp_path / "out.txt", template=template)
    text = path.read_text()
    assert text.startswith("// machine X")
    assert "// RICHT [mm]: - = track to the right" in text and "// HL [cm]: + = rail up" in text
    assert "KM;HL;RICHT;mark" in text and "-0.0" not in text
    back = read_template_export(path, template)
    # rows every 0.5 m (interpolated) and the marked rows as they are
    # km to the template's decimals + 3 (0.1 m)
    assert np.allclose(back["station"], [1000.0, 1000.5, 1001.0, 1001.0, 1001.5, 1001.875], atol=0.051)
    assert back["mark"][3] == "TS" and back["mark"][-1] == "fixed start (bridge, Xiaohe)"
    assert back["lift_left"][3] == pytest.approx(4.0, abs=0.05)
    assert back["slew"][3] == pytest.approx(-2.0, abs=0.05)  # the sign turned back
    expected = np.interp(1000.5, [1000.0, 1000.625, 1001.25], [0.0, -1.2, 4.5])
    assert back["slew"][1] == pytest.approx(expected, abs=0.05)


def test_a_template_layouts_notes_are_in_the_report_language_and_its_columns_are_not(tmp_path):
    results, project = _results(tmp_path)
    project.report.language = "zh-CN"
    template_path = tmp_path / "machine.toml"
    template_path.write_text('[[columns]]\nfield = "station"\n[[columns]]\nfield = "lift_left"\n'
                             '[[columns]]\nfield = "slew"\nsign = -1\n[[columns]]\nfield = "cant"\n')
    template = load_template(template_path)
    text = write_export(project, results, "tamping-template", tmp_path / "out.txt", template=template).read_text()
    assert text.startswith("# machine：line 3 tamping 捣固量，测量 run1（insrail）")
    assert "# lift_left [mm]: + = 钢轨抬高" in text and "# slew [mm]: - = 面向里程增加方向线路向右" in text
    assert "# cant [mm]: + = 左轨较高" in text and "# station [m]: 测站里程" in text
    assert "station,lift_left,slew,cant" in text
    assert np.allclose(read_template_export(tmp_path / "out.txt", template)["slew"], [r.slew_mm for r in ROWS])


@pytest.mark.parametrize("text, key", [
    ('[[columns]]\nfield = "lift"\n', "columns[0].field"),
    ('[[columns]]\nfield = "slew"\nunit = "inch"\n', "columns[0].unit"),
    ('[[columns]]\nfield = "mark"\nsign = -1\n', "columns[0].sign"),
    ('comment = ""\n[[columns]]\nfield = "slew"\n', "comment"),
    ('name = "x"\n', "columns"),
])
def test_a_bad_template_is_refused_naming_the_key(tmp_path, text, key):
    path = tmp_path / "t.toml"
    path.write_text(text)
    with pytest.raises(InputError, match=key.replace("[", r"\[").replace("]", r"\]")):
        load_template(path)


def test_a_file_that_is_not_a_tamping_table_is_refused(tmp_path):
    path = tmp_path / "x.csv"
    path.write_text("station,lift\n1,2\n")
    with pytest.raises(InputError, match="insrail tamping 1"):
        read_tamping(path)
