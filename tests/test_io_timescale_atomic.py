"""GPS time conversions and the atomic write helper."""

from __future__ import annotations

import fcntl
import os
import stat

import numpy as np
import pytest

from insrail.io.atomic import NotARegularFile, atomic_write, naming, remove_dead_temporaries, save_npy
from insrail.io.rtklib import read_rtklib_pos
from insrail.io.timescale import (
    calendar_to_week_seconds,
    gpst_minus_utc,
    unix_gpst_to_week_seconds,
    utc_to_gpst,
    week_tow_to_week_seconds,
)


def test_calendar_to_week_seconds_known_epochs():
    # 2025-08-28 (a Thursday) 17:30:39.749 GPST is week 2381, 4 days + 63039.749 s.
    week, sow = calendar_to_week_seconds([2025], [8], [28], [17], [30], [39.749])
    assert week == 2381
    assert sow[0] == pytest.approx(4 * 86400 + 63039.749, abs=1e-9)
    assert calendar_to_week_seconds([1980], [1], [6], [0], [0], [0.0])[0] == 0


def test_leap_seconds():
    week, _ = calendar_to_week_seconds([2016], [12], [31], [0], [0], [0.0])
    assert gpst_minus_utc(week, [86400.0 * 6 - 1.0])[0] == 17    # 2016-12-31 23:59:59 UTC
    week, sow = calendar_to_week_seconds([2017], [1], [1], [0], [0], [0.0])
    assert gpst_minus_utc(week, sow)[0] == 18
    week, sow = calendar_to_week_seconds([1981], [1], [1], [0], [0], [0.0])
    assert gpst_minus_utc(week, sow)[0] == 0


def test_utc_to_gpst_crosses_the_week_end():
    # Saturday 23:59:50 UTC in 2020 is Sunday 00:00:08 GPST of the next week.
    week, sow = calendar_to_week_seconds([2020], [1], [4], [23], [59], [50.0])
    gps_week, gps_sow = utc_to_gpst(week, sow)
    assert (gps_week, gps_sow[0]) == (week + 1, pytest.approx(8.0))


def test_week_tow_series_stays_continuous():
    week, sow = week_tow_to_week_seconds([2380, 2381], [604799.5, 0.5])
    assert week == 2380
    np.testing.assert_allclose(sow, [604799.5, 604800.5])


def test_unix_gpst_keeps_full_resolution():
    week, sow = unix_gpst_to_week_seconds(np.array([1756402240.9610000]))
    assert week == 2381
    assert sow[0] == 1756402240.9610000 - (315964800 + 2381 * 604800)


def test_pos_in_utc_and_jst_become_gpst(tmp_path):
    row = "40.1 -105.1 1601.4 1 25 0.01 0.01 0.02 0 0 0 0.0 3.2"
    results = {}
    for system, clock in (("GPST", "17:30:57.000"), ("UTC", "17:30:39.000"), ("JST", "02:30:39.000")):
        day = "2025/08/29" if system == "JST" else "2025/08/28"
        path = tmp_path / f"{system}.pos"
        path.write_text(f"%  {system}  latitude(deg) longitude(deg)\n{day} {clock} {row}\n")
        gnss = read_rtklib_pos(path)
        results[system] = (gnss.gps_week, gnss.time_s[0])
    assert results["UTC"] == results["GPST"] == results["JST"]


def test_pos_dms_form(tmp_path):
    path = tmp_path / "dms.pos"
    path.write_text("%  GPST  latitude(d'\") longitude(d'\") height(m)\n"
                    "2381 100.0  40 05 48.08976  -105 08 49.79940 1601.4 1 25 0.01 0.01 0.02 0 0 0 0.0 3.2\n"
                    "2381 101.0  -0 30 00.00000    0 15 00.00000 1601.4 1 25 0.01 0.01 0.02 0 0 0 0.0 3.2\n")
    gnss = read_rtklib_pos(path)
    np.testing.assert_allclose(np.degrees(gnss.lat_rad), [40 + 5 / 60 + 48.08976 / 3600, -0.5])
    np.testing.assert_allclose(np.degrees(gnss.lon_rad), [-(105 + 8 / 60 + 49.7994 / 3600), 0.25])


def test_atomic_write_replaces_only_on_success(tmp_path):
    path = tmp_path / "project.toml"
    path.write_text("old")
    os.chmod(path, 0o640)
    with pytest.raises(RuntimeError):
        with atomic_write(path) as handle:
            handle.write("half")
            raise RuntimeError("disk full")
    assert path.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["project.toml"]
    with atomic_write(path) as handle:
        handle.write("new")
    assert path.read_text() == "new"
    assert path.stat().st_mode & 0o777 == 0o640
    with atomic_write(tmp_path / "fresh.bin", "wb") as handle:
        handle.write(b"\x00\x01")
    assert (tmp_path / "fresh.bin").read_bytes() == b"\x00\x01"
    assert (tmp_path / "fresh.bin").stat().st_mode & 0o777 == 0o644


def test_atomic_write_replaces_only_regular_files(tmp_path):
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    with pytest.raises(NotARegularFile, match="FIFO"):
        with atomic_write(fifo) as handle:
            handle.write("x")
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)
    with pytest.raises(NotARegularFile, match="folder"):
        with atomic_write(tmp_path) as handle:
            handle.write("x")
    real = tmp_path / "real.txt"
    real.write_text("old")
    link = tmp_path / "link.txt"
    link.symlink_to(real)
    with atomic_write(link) as handle:  # a link to a regular file is replaced, as editors do
        handle.write("new")
    assert link.read_text() == "new" and not link.is_symlink()


def test_a_killed_writers_temporary_is_removed_by_the_next_write(tmp_path):
    path = tmp_path / "report.pdf"
    dead = tmp_path / ".report.pdf.abc123.tmp"
    dead.write_bytes(b"half a report")  # unlocked: its writer is gone
    alive = tmp_path / ".report.pdf.def456.tmp"
    alive.write_bytes(b"being written")
    with open(alive, "rb") as handle:
        fcntl.flock(handle.fileno(), fcntl.LOCK_EX)  # as a writer alive in another process holds it
        with atomic_write(path, "wb") as out:
            out.write(b"%PDF")
        assert path.read_bytes() == b"%PDF"
        assert not dead.exists() and alive.exists()
    assert remove_dead_temporaries(path) == [alive]  # its writer gone now too


def test_save_npy_writes_what_np_save_writes(tmp_path):
    import io

    records = np.zeros(5, dtype=[("time_s", "f8"), ("dvel_mps", "f8", (3,))])
    records["time_s"] = np.arange(5.0)
    saved = io.BytesIO()
    np.save(saved, records)
    save_npy(tmp_path / "records.npy", records)
    assert (tmp_path / "records.npy").read_bytes() == saved.getvalue()
    with pytest.raises(ValueError, match="an array of Python objects cannot be saved"):  # pointers, not data
        save_npy(tmp_path / "objects.npy", np.array([None, "x"], dtype=object))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["records.npy"]


def test_an_error_without_errno_keeps_its_message_when_named(tmp_path):
    from insrail.cli.main import describe_os_error

    named = naming(OSError("3 requested and 0 written"), tmp_path / "a.npy")  # as numpy's writer raises it
    assert describe_os_error(named) == f"{tmp_path / 'a.npy'}: 3 requested and 0 written"
