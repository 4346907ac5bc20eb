"""The per-user cache of parsed sleeper tables: what comes back is always what sleepers.csv says now."""

import numpy as np
import pytest

from insrail.project import results, table_cache
from insrail.project.results import columns_csv


def _table(path, gauge=(1435.0, np.nan, 1436.5), reasons=("", "turnout, switch", "")):
    path.write_text("".join(columns_csv(np.array([1, 2, 3]), ("K0+000.000", "K0+000.600", "K0+001.200"),
                                {"station_m": (np.array([0.0, 0.6, 1.2]), "%.4f"),
                                 "gauge_mm": (np.array(gauge), "%.3f")}, reasons)), encoding="utf-8")
    return path


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "user-cache"))
    return tmp_path / "user-cache" / "insrail" / "tables"


def test_a_table_parsed_once_comes_back_from_the_cache_equal(tmp_path, cache, monkeypatch):
    path = _table(tmp_path / "sleepers.csv")
    parsed = results._read_sleepers(path)
    assert len(list(cache.glob("*.npz"))) == 1

    def no_parsing(_path):
        raise AssertionError("parsed again although cached")

    monkeypatch.setattr(results, "_parse_sleepers", no_parsing)
    cached = results._read_sleepers(path)
    number, label, columns, not_assessed, notes = cached
    assert number.tolist() == [1, 2, 3] and label == parsed[1]
    assert columns.keys() == parsed[2].keys()
    for name in columns:
        np.testing.assert_array_equal(columns[name], parsed[2][name])  # NaN where the cell was empty
    assert np.isnan(columns["gauge_mm"][1])
    assert not_assessed == ("", "turnout, switch", "") == parsed[3] and notes == parsed[4] == ()


def test_an_edited_file_is_parsed_again_never_served_stale(tmp_path, cache):
    path = _table(tmp_path / "sleepers.csv")
    assert results._read_sleepers(path)[2]["gauge_mm"][0] == 1435.0
    _table(path, gauge=(1440.0, 1437.0, 1436.5))  # processed again, or edited in a spreadsheet
    assert results._read_sleepers(path)[2]["gauge_mm"].tolist() == [1440.0, 1437.0, 1436.5]


def test_a_damaged_entry_or_no_cache_folder_is_no_error(tmp_path, cache, monkeypatch):
    path = _table(tmp_path / "sleepers.csv")
    results._read_sleepers(path)
    for entry in cache.glob("*.npz"):
        entry.write_bytes(b"not a zip file")
    assert results._read_sleepers(path)[0].tolist() == [1, 2, 3]
    monkeypatch.delenv("XDG_CACHE_HOME")
    monkeypatch.delenv("HOME", raising=False)
    monkeypatch.delenv("USERPROFILE", raising=False)
    assert table_cache.cache_folder() is None
    assert results._read_sleepers(path)[0].tolist() == [1, 2, 3]


def test_a_bad_file_still_names_its_line(tmp_path, cache):
    path = _table(tmp_path / "sleepers.csv")
    path.write_text(path.read_text(encoding="utf-8").replace("1436.500", "14x6.5"), encoding="utf-8")
    with pytest.raises(results.InputError, match="sleepers.csv.*4"):
        results._read_sleepers(path)


def test_only_the_newest_entries_are_kept(tmp_path, cache, monkeypatch):
    monkeypatch.setattr(table_cache, "MAX_ENTRIES", 2)
    for k in range(4):
        results._read_sleepers(_table(tmp_path / f"s{k}.csv", gauge=(1435.0 + k, 1435.0, 1435.0)))
    assert len(list(cache.glob("*.npz"))) == 2


def test_the_fast_reading_gives_what_reading_cell_by_cell_gives(tmp_path, cache, monkeypatch):
    """Quoted reasons, empty cells (NaN), signs and exponents: numpy's parser over the whole table
    and the row-by-row reading agree to the bit; a short row still names its line."""
    path = tmp_path / "sleepers.csv"
    path.write_text("".join(columns_csv(np.array([7, 8, 9, 10]), ("K0+000.000", "K0+000.600", "K0+001.200", "K0+001.800"),
                                {"station_m": (np.array([0.0, 0.6, 1.2, 1.8]), "%.4f"),
                                 "gauge_mm": (np.array([-0.0, np.nan, 1.5e-7, -1436.123]), "%.6g"),
                                 "valid": (np.array([1, 0, 1, 1]), "%d")},
                                ("", 'turnout, "W12"', "", "joint; bridge"), ("", "", "fastener range, exhausted", ""))),
                    encoding="utf-8")
    fast = results._parse_sleepers(path)
    monkeypatch.setattr(results, "_regular_rows", lambda *_args: None)
    slow = results._parse_sleepers(path)
    assert fast[0].tolist() == slow[0].tolist() == [7, 8, 9, 10] and fast[1] == slow[1]
    for name in slow[2]:
        np.testing.assert_array_equal(fast[2][name], slow[2][name])
        assert fast[2][name].tobytes() == slow[2][name].tobytes()  # -0.0 stays -0.0
    assert fast[3] == slow[3] == ("", 'turnout, "W12"', "", "joint; bridge")
    assert fast[4] == slow[4] == ("", "", "fastener range, exhausted", "")
    monkeypatch.undo()
    lines = path.read_text(encoding="utf-8").splitlines()
    lines[3] = lines[3].replace(",1.5e-07", "", 1)
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    with pytest.raises(results.InputError, match="sleepers.csv.*line 4.*expected"):
        results._parse_sleepers(path)
