"""RTKLIB never sees a user's file name: a hostile name runs nothing, compressed inputs are
decompressed in Python (gzip, Unix compress, Hatanaka) and give the plain file's solution."""

from __future__ import annotations

import gzip
import shutil
from pathlib import Path

import pytest
from real_data import real_path

from insrail.cli.main import main
from insrail.gnss import OptionError, ppk
from insrail.gnss.staging import safe_suffix, stage_file
from insrail.io.errors import InputError
from insrail.io.rtklib import read_rtklib_pos

ROVER, BASE = "30400920.05o", "07590920.05o"
NAV = ("07590920.05n", "30400920.05n")
HOSTILE = 'r";touch PWNED;".gz'


@pytest.fixture(scope="module")
def geonet() -> Path:
    return real_path("rinex_0759_3040")


def _no_pwned(*folders: Path) -> None:
    for folder in folders:
        assert not list(folder.rglob("PWNED")), f"a command ran: PWNED created under {folder}"


def test_hostile_rover_name_through_insrail_ppk_runs_nothing(geonet, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # where `touch PWNED` would land
    hostile = tmp_path / HOSTILE  # plain RINEX: passes insrail's header check, RTKLIB would gunzip it by name
    shutil.copy(geonet / ROVER, hostile)
    out = tmp_path / "out.pos"
    code = main(["ppk", str(hostile), "--base", str(geonet / BASE), "--nav", *[str(geonet / n) for n in NAV],
                 "--out", str(out), "--base-from-header"])
    _no_pwned(tmp_path)
    assert code == 0
    assert len(read_rtklib_pos(out)) >= 110
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([HOSTILE, "out.pos"])  # nothing else left


def test_compressed_and_hatanaka_inputs_give_the_plain_solution(geonet, tmp_path, recwarn):
    hatanaka = pytest.importorskip("hatanaka")
    plain = ppk(geonet / ROVER, geonet / BASE, [geonet / n for n in NAV], tmp_path / "plain.pos")
    crx = tmp_path / "30400920.05d"
    crx.write_bytes(hatanaka.rnx2crx((geonet / ROVER).read_bytes()))
    packed = tmp_path / "07590920.05n.gz"
    packed.write_bytes(gzip.compress((geonet / NAV[0]).read_bytes()))
    packed_crx = tmp_path / "base.crx.gz"
    packed_crx.write_bytes(gzip.compress(hatanaka.rnx2crx((geonet / BASE).read_bytes())))
    result = ppk(crx, packed_crx, [packed, geonet / NAV[1]], tmp_path / "compressed.pos")
    assert result.rover.path == crx and result.base.path == packed_crx  # errors and QC name the user's files
    assert result.solution.time_s.tolist() == plain.solution.time_s.tolist()
    assert result.solution.lat_rad.tolist() == plain.solution.lat_rad.tolist()
    assert crx.read_bytes()[:80].decode()[60:].startswith("CRINEX")  # the user's file is untouched


def test_damaged_gzip_and_zip_are_refused_naming_the_file(tmp_path):
    broken = tmp_path / "rover.obs.gz"
    broken.write_bytes(gzip.compress(bytes(range(256)) * 40)[:100])  # truncated
    with pytest.raises(InputError, match=r"rover\.obs\.gz: damaged gzip file"):
        stage_file(broken, tmp_path, "rover", ".obs")
    archive = tmp_path / "rover.zip"
    archive.write_bytes(b"PK\x03\x04" + b"\0" * 40)
    with pytest.raises(InputError, match=r"rover\.zip: a zip archive"):
        stage_file(archive, tmp_path, "rover", ".obs")


def test_staged_names_never_carry_a_suffix_rtklib_decompresses():
    assert safe_suffix("igs13160.sp3", ".dat") == ".sp3"
    assert safe_suffix("igs13160.clk", ".dat") == ".clk"
    for name in ("x.gz", "x.Z", "x.05d", "x.05D", "x.zip", "x.tar", "x.crx", 'a";b', "x.sp3 ", "x"):
        assert safe_suffix(name, ".dat") == ".dat", name


def test_a_configuration_cannot_make_rtklib_write_elsewhere(geonet, tmp_path):
    config = tmp_path / "handed_over.conf"
    config.write_text(f"file-tracefile = {tmp_path / 'victim.txt'}\n")
    with pytest.raises(OptionError, match="file-tracefile"):
        ppk(geonet / ROVER, geonet / BASE, [geonet / n for n in NAV], tmp_path / "out.pos", config=config)
    assert not (tmp_path / "victim.txt").exists() and not (tmp_path / "out.pos").exists()


def test_error_in_a_staged_file_names_the_users_file(geonet, tmp_path):
    rover = tmp_path / "my rover;.obs"
    shutil.copy(geonet / NAV[0], rover)  # a navigation file given as the rover
    with pytest.raises(InputError, match=r"my rover;\.obs, line 1: expected a RINEX observation file"):
        ppk(rover, geonet / BASE, [geonet / n for n in NAV], tmp_path / "out.pos")
