"""Bounded reading of hostile input: a disk image, an endless line, too many lines, a decompression
bomb are refused naming the file (and line) and the limit, without reading them into memory."""

from __future__ import annotations

import gzip
import resource

import pytest

from insrail.gnss import staging
from insrail.io.errors import InputError
from insrail.io.formats import read_any
from insrail.io.imu import read_imu_kfgins
from insrail.io.textparse import MAX_LINE_CHARS, check_text_file

IMU_LINE = "100.000 1e-5 2e-5 3e-5 1e-4 2e-4 0.049\n"


def peak_rss_mib() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def test_a_5_gb_disk_image_as_imu_text_is_refused_as_binary_without_reading_it(tmp_path):
    path = tmp_path / "imu.txt"
    with open(path, "wb") as handle:
        handle.truncate(5 << 30)  # sparse: no disk used
    before = peak_rss_mib()
    with pytest.raises(InputError) as caught:
        read_imu_kfgins(path)
    assert str(path) in str(caught.value) and "line 1" in str(caught.value) and "binary data" in str(caught.value)
    with pytest.raises(InputError, match="binary data"):
        read_any(path)  # format detection is bounded too
    assert peak_rss_mib() - before < 200


def test_binary_bytes_are_never_echoed(tmp_path):
    path = tmp_path / "gauge.txt"
    path.write_bytes(b"12.0 1435.2\n13.0 \x00SECRET\xff\xfe\n")
    with pytest.raises(InputError) as caught:
        read_any(path, "gauge-mm")
    assert "line 2" in str(caught.value) and "SECRET" not in str(caught.value)


def test_an_endless_line_is_refused_naming_its_line_and_the_limit(tmp_path):
    path = tmp_path / "imu.txt"
    path.write_text(IMU_LINE * 3 + "1.0 " * (MAX_LINE_CHARS // 2) + "\n" + IMU_LINE)
    with pytest.raises(InputError, match=rf"line 4: line longer than the limit of {MAX_LINE_CHARS:,} characters"):
        read_imu_kfgins(path)
    path.write_text("1.0 " * (50 << 20))  # one line of 200 MB, no newline
    before = peak_rss_mib()
    with pytest.raises(InputError, match="line 1: line longer than the limit"):
        read_imu_kfgins(path)
    assert peak_rss_mib() - before < 200


def test_more_lines_than_plausible_are_refused(tmp_path):
    path = tmp_path / "imu.txt"
    path.write_text(IMU_LINE * 30)
    check_text_file(path, max_lines=30)
    with pytest.raises(InputError, match="line 11: more than the limit of 10 lines"):
        check_text_file(path, max_lines=10)


def test_a_decompression_bomb_is_refused_after_writing_no_more_than_the_limit(tmp_path, monkeypatch):
    monkeypatch.setattr(staging, "MIN_DECOMPRESSED_LIMIT", 1 << 20)
    bomb = tmp_path / "rover.obs.gz"
    bomb.write_bytes(gzip.compress(b" 12345678.901 7" * (8 << 20), 9))  # 120 MB of text, 0.1 MB packed
    work = tmp_path / "work"
    work.mkdir()
    limit = staging.decompressed_limit(bomb.stat().st_size)
    assert limit == 50 * bomb.stat().st_size
    with pytest.raises(InputError, match=rf"rover.obs.gz: inflates to more than {limit / 2**20:.0f} MiB "
                                         r"\(.* bytes compressed; the limit is 50 times the compressed size"):
        staging.stage_file(bomb, work, "rover", ".obs")
    assert sum(f.stat().st_size for f in work.iterdir()) <= limit
    plausible = tmp_path / "base.obs.gz"
    plausible.write_bytes(gzip.compress(bytes(range(256)) * 4096))  # 1 MB, hardly compressible
    assert staging.stage_file(plausible, work, "base", ".obs").stat().st_size == 256 * 4096


@pytest.mark.parametrize("block", [3, 7, 64])
def test_line_count_and_the_first_overlong_line_across_blocks(tmp_path, monkeypatch, block):
    """The compiled scan counts the lines and names the first one over the limit wherever the
    blocks it reads cut the lines."""
    from insrail.io import textparse

    monkeypatch.setattr(textparse, "_SCAN_BLOCK", block)
    monkeypatch.setattr(textparse, "MAX_LINE_CHARS", 10)
    path = tmp_path / "table.txt"
    path.write_bytes(b"1 2 3\n\n123456789\r\n1234567890\n5 6")
    assert check_text_file(path) == 5  # a last line without a line end counts
    path.write_bytes(b"1 2 3\n\n123456789\r\n1234567890\n12345678901\n1\n")
    with pytest.raises(InputError, match="line 5: line longer than the limit"):
        check_text_file(path)
    path.write_bytes(b"1 2\n3 4\n" + b"9" * 30)  # the open last line over the limit
    with pytest.raises(InputError, match="line 3: line longer than the limit"):
        check_text_file(path)


def test_a_file_checked_once_is_scanned_again_only_when_it_changed(tmp_path, monkeypatch):
    import os

    from insrail.io import textparse

    path = tmp_path / "imu.txt"
    path.write_text(IMU_LINE * 3)
    scans = []
    scan = textparse._scan_text_file
    monkeypatch.setattr(textparse, "_scan_text_file", lambda *args: scans.append(args[0]) or scan(*args))
    hashed = []
    with textparse.checked_once():
        assert check_text_file(path, each_block=hashed.append) == 3  # a cache key's pass
        assert check_text_file(path) == 3 and len(scans) == 1  # the reading's: the same file, not scanned again
        assert check_text_file(path, each_block=hashed.append) == 3 and len(scans) == 2  # its bytes asked for
        path.write_bytes(IMU_LINE.encode() * 2 + b"\x00" * len(IMU_LINE))  # same size, binary now
        os.utime(path, ns=(0, path.stat().st_mtime_ns + 1_000_000))
        with pytest.raises(InputError, match="binary data"):
            check_text_file(path)
    path.write_text(IMU_LINE * 4)
    assert check_text_file(path) == 4 and check_text_file(path) == 4 and len(scans) == 5  # outside: every time
