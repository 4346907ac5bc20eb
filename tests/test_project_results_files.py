"""Result files written from the cache: copies (never links into the cache), a rerun's unchanged large
file linked from the previous results, and the trajectory's fields read a chunk at a time."""

import os
import tomllib
from unittest import mock

import numpy as np
import pytest
import tomli_w
from hypothesis import given, settings
from hypothesis import strategies as st

from insrail.nav.trajectory import TRAJECTORY_DTYPE, load_trajectory, read_trajectory_fields, save_trajectory
from insrail.project import results
from insrail.project.results import write_results
from insrail.track.exceedance import Assessment, Exceedance


def _cached_file(tmp_path):
    cache = tmp_path / "cache.npy"
    cache.write_bytes(os.urandom(1000))
    return cache


def test_a_rerun_links_the_previous_copy_and_never_the_cache(tmp_path):
    results = tmp_path / "results"
    cache = _cached_file(tmp_path)
    first = write_results(results, "s", {"big.npy": cache, "summary.toml": "a = 1\n"}) / "big.npy"
    assert first.read_bytes() == cache.read_bytes() and first.stat().st_ino != cache.stat().st_ino
    inode = first.stat().st_ino
    second = write_results(results, "s", {"big.npy": cache, "summary.toml": "a = 2\n"}) / "big.npy"
    assert second.stat().st_ino == inode and second.stat().st_nlink == 1  # the old folder is gone
    # a result edited by hand is not carried on: copied again from the cache
    with open(second, "r+b") as handle:
        handle.write(b"edited")
    third = write_results(results, "s", {"big.npy": cache, "summary.toml": "a = 3\n"}) / "big.npy"
    assert third.stat().st_ino != inode and third.read_bytes() == cache.read_bytes()
    # editing a result never changes the cache
    third.write_bytes(b"x")
    assert cache.stat().st_size == 1000


def test_trajectory_fields_are_those_of_the_whole_file(tmp_path):
    n = 2501
    rng = np.random.default_rng(3)
    records = np.zeros(n, dtype=TRAJECTORY_DTYPE)
    for name in TRAJECTORY_DTYPE.names:
        records[name] = rng.standard_normal(records[name].shape)
    path = tmp_path / "trajectory.npy"
    np.save(path, records)
    whole = load_trajectory(path)
    fields = read_trajectory_fields(path, ("time_s", "rpy_rad", "sigma_pos_ned_m"), chunk=1000)
    for name, values in fields.items():
        np.testing.assert_array_equal(values, getattr(whole, name))
    save_trajectory(tmp_path / "other.npy", whole)
    np.testing.assert_array_equal(read_trajectory_fields(tmp_path / "other.npy", ("lat_rad",))["lat_rad"], whole.lat_rad)
    with open(path, "r+b") as handle:
        handle.truncate(path.stat().st_size - 300)
    with pytest.raises(ValueError, match="ends after"):
        read_trajectory_fields(path, ("time_s",), chunk=1000)
    np.save(tmp_path / "plain.npy", np.zeros(10))
    with pytest.raises(ValueError, match="not an insrail trajectory"):
        read_trajectory_fields(tmp_path / "plain.npy", ("time_s",))
    with pytest.raises(ValueError, match="not an insrail trajectory"):
        load_trajectory(tmp_path / "plain.npy")


def test_a_trajectory_read_for_its_pose_holds_nan_elsewhere(tmp_path):
    """``load_trajectory(..., only=POSE_FIELDS)`` (the track reconstruction's read): those fields
    as in the whole file, every other one NaN, read-only and without memory of its own."""
    from insrail.track.rails import POSE_FIELDS

    records = np.zeros(1234, dtype=TRAJECTORY_DTYPE)
    rng = np.random.default_rng(5)
    for name in TRAJECTORY_DTYPE.names:
        records[name] = rng.standard_normal(records[name].shape)
    np.save(tmp_path / "trajectory.npy", records)
    whole = load_trajectory(tmp_path / "trajectory.npy")
    pose = load_trajectory(tmp_path / "trajectory.npy", only=POSE_FIELDS)
    for name in TRAJECTORY_DTYPE.names:
        values = getattr(pose, name)
        assert values.shape == getattr(whole, name).shape
        if name in POSE_FIELDS:
            np.testing.assert_array_equal(values, getattr(whole, name))
        else:
            assert np.isnan(values).all() and not values.flags.writeable and values.strides[0] == 0
    with pytest.raises(ValueError, match="not trajectory fields: speed"):
        load_trajectory(tmp_path / "trajectory.npy", only=("time_s", "speed"))


def test_result_tables_written_in_blocks_are_the_whole_text(tmp_path, monkeypatch):
    """sleepers.csv and exceedances.csv go to the file a block of rows at a time: the same bytes as one
    block of every row (NaN as empty, -0.0, quoted reasons, notes, a last short block)."""
    n = 23
    rng = np.random.default_rng(5)
    gauge = rng.normal(1435.0, 2.0, n)
    gauge[[0, 6, 7, 22]] = [np.nan, -0.0, np.nan, 1.5e-7]
    columns = {"station_m": (np.arange(n) * 0.6, "%.4f"), "gauge_mm": (gauge, "%.3f"),
               "valid": (rng.integers(0, 2, n), "%d")}
    number, label = np.arange(100, 100 + n), tuple(f"K0+{600 * i:03d}" for i in range(n))
    reasons = tuple(rng.choice(["", "turnout, switch", 'level "crossing"']) for _ in range(n))
    notes = tuple(rng.choice(["", "fastener range, exhausted"]) for _ in range(n))
    cases = [(number, label, columns, reasons, notes), (number, label, columns), (number[:0], (), {
        name: (values[:0], fmt) for name, (values, fmt) in columns.items()})]

    def texts(rows: int) -> list[str]:
        monkeypatch.setattr(results, "CSV_BLOCK_ROWS", rows)
        return ["".join(results.columns_csv(*case)) for case in cases]

    whole = texts(10**9)
    assert whole[0].count("\n") == n + 1 and '"level ""crossing"""' in whole[0] and ",,1435" not in whole[0]
    for rows in (1, 7):
        assert texts(rows) == whole
    written = write_results(tmp_path / "results", "s", {"sleepers.csv": results.columns_csv(*cases[0])})
    assert (written / "sleepers.csv").read_text(encoding="utf-8") == whole[0]

    # read back a block of lines at a time (also with CR LF line ends): the same table as in one block
    (tmp_path / "crlf.csv").write_bytes(whole[0].replace("\n", "\r\n").encode("utf-8"))
    parsed = {}
    for rows in (10**9, 7):
        monkeypatch.setattr(results, "CSV_BLOCK_ROWS", rows)
        for name in ("sleepers.csv", "crlf.csv"):
            path = written / name if name == "sleepers.csv" else tmp_path / name
            parsed[rows, name] = results._parse_sleepers(path)
    for table in parsed.values():
        reference = parsed[10**9, "sleepers.csv"]
        assert table[0].tolist() == number.tolist() and table[1] == reference[1] == label
        assert table[2].keys() == columns.keys() and table[3:] == reference[3:] == (reasons, notes)
        for name, (values, _) in columns.items():
            assert table[2][name].tobytes() == reference[2][name].tobytes()
        np.testing.assert_allclose(table[2]["gauge_mm"], gauge, atol=6e-4)

    exceedances = tuple(Exceedance("gauge", kind, "track", "", 0.6 * i, 0.6 * i + 1.2, 1e-3 * i, 2e-3, i, i + 2,
                                   100 + i, 102 + i) for i, kind in zip(range(11), ["gauge_deviation", "gauge_change_rate"] * 6))
    monkeypatch.setattr(results, "CSV_BLOCK_ROWS", 10**9)
    whole = "".join(results.exceedances_csv(Assessment("p", (), exceedances)))
    assert whole.count("\n") == 12
    monkeypatch.setattr(results, "CSV_BLOCK_ROWS", 4)
    assert "".join(results.exceedances_csv(Assessment("p", (), exceedances))) == whole


def _same(got, want) -> bool:
    return got == want or (np.isnan(got) and np.isnan(want))


@settings(max_examples=300, deadline=None)
@given(values=st.lists(st.one_of(st.floats(width=64, allow_nan=False), st.sampled_from([0.0, -0.0, 1.0, 2.5, 1e300])),
                       min_size=1, max_size=300),
       chunk=st.integers(1, 40), limit=st.sampled_from([0, 2, 1 << 16]), q=st.floats(0.0, 100.0), nan=st.booleans())
def test_exact_quantiles_are_numpys_median_percentile_and_max(values, chunk, limit, q, nan):
    """Median, percentile (linear) and largest, fed in chunks over several passes, are the numbers numpy gives
    for the whole array: ties, odd and even counts, infinities, chunk edges anywhere, bins sorted or split
    down to their last bits; NaN when one value is."""
    values = np.array(values + ([np.nan] if nan else []))
    selection = results.ExactQuantiles((q,))
    with mock.patch.object(results, "SELECTION_SORT_LIMIT", limit), np.errstate(invalid="ignore", over="ignore"):
        while True:
            for start in range(0, len(values), chunk):
                selection.feed(values[start:start + chunk])
            if not selection.more():
                break
        assert selection.passes <= 4
        assert _same(selection.median(), np.median(values))
        assert _same(selection.percentile(q), np.percentile(values, q))
        assert _same(selection.maximum(), np.max(values))


def test_the_trajectory_section_is_the_whole_files_figures(tmp_path, monkeypatch):
    """summary.toml's [trajectory], read 997 records at a time, holds the numbers of the whole arrays (the
    report's figures: epochs, time span, median / 95 % / largest position sigma, odometer scale)."""
    n = 5003
    rng = np.random.default_rng(8)
    records = np.zeros(n, dtype=TRAJECTORY_DTYPE)
    records["time_s"] = 230000.0 + 0.005 * np.arange(n)
    records["sigma_pos_ned_m"] = np.round(rng.gamma(4.0, 0.002, (n, 3)), 5)  # rounded: ties
    records["odometer_scale"] = 1.5e-3 + 1e-5 * np.sin(np.arange(n) / 400)
    path = tmp_path / "trajectory.npy"
    np.save(path, records)
    monkeypatch.setattr(results, "STATISTICS_CHUNK_RECORDS", 997)
    section = tomllib.loads(tomli_w.dumps({"trajectory": results.trajectory_section(path)}))["trajectory"]
    sigma = records["sigma_pos_ned_m"]
    horizontal, vertical = 1e3 * np.hypot(sigma[:, 0], sigma[:, 1]), 1e3 * sigma[:, 2]
    scale = records["odometer_scale"]
    assert section == {
        "epochs": n, "start_s": records["time_s"][0], "end_s": records["time_s"][-1],
        **{name: {"median": np.median(v), "p95": np.percentile(v, 95), "max": v.max()}
           for name, v in (("sigma_horizontal_mm", horizontal), ("sigma_vertical_mm", vertical))},
        "odometer_scale": {"last": scale[-1], "min": scale.min(), "max": scale.max(), "used": True}}
    np.save(path, records[:0])
    assert results.trajectory_section(path) == {"epochs": 0}
    records["odometer_scale"] = 0.0
    np.save(path, records)
    assert results.trajectory_section(path)["odometer_scale"]["used"] is False
    np.save(path, np.zeros(3))
    with pytest.raises(ValueError, match="not an insrail trajectory"):
        results.trajectory_section(path)


def test_an_amount_of_no_millimetres_is_written_0_0_never_minus_0_0():
    """The optimiser leaves some zero amounts negative (-0.0): a crew reads "-0.0" as an instruction."""
    from insrail.track.adjustment import Adjustment

    amounts = np.array([[-0.0, 0.0], [-0.002, 0.001]])
    flags = np.zeros((2, 2), dtype=bool)
    adjustment = Adjustment(amounts, -amounts, flags, flags, "f", np.zeros((2, 2), np.uint8),
                            np.zeros((2, 2), np.uint8))
    columns = results.sleeper_check_columns(Assessment("p", (), ()), adjustment)
    written = {name: [fmt % value for value in values] for name, (values, fmt) in columns.items()
               if name.startswith("adjust_")}
    assert written == {"adjust_lateral_left_mm": ["0.0", "-2.0"], "adjust_lateral_right_mm": ["0.0", "1.0"],
                       "adjust_vertical_left_mm": ["0.0", "2.0"], "adjust_vertical_right_mm": ["0.0", "-1.0"]}
