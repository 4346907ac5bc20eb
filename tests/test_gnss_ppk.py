"""PPK with RTKLIB on real data (GEONET 0759/3040), UBX conversion, and bad input."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from real_data import real_path

from insrail.gnss import (
    ApproximateBaseWarning,
    BasePosition,
    LongBaselineWarning,
    OptionError,
    convert_to_rinex,
    ppk,
)
from insrail.gnss.rinex import read_obs_info
from insrail.io.errors import InputError
from insrail.io.rtklib import read_rtklib_pos
from insrail.nav.earth import dcm_ecef_from_ned, geodetic_to_ecef
from insrail.progress import Cancelled

ROVER, BASE = "30400920.05o", "07590920.05o"
NAV = ("07590920.05n", "30400920.05n")


@pytest.fixture(scope="module")
def geonet() -> Path:
    return real_path("rinex_0759_3040")


@pytest.fixture(scope="module")
def walk() -> Path:
    return real_path("walk_0827")


def _run(geonet: Path, out: Path, **kwargs):
    kwargs.setdefault("base_position", None)
    with pytest.warns(ApproximateBaseWarning, match=BASE):
        return ppk(geonet / ROVER, geonet / BASE, [geonet / n for n in NAV], out, **kwargs)


def _ned_about(reference_ecef: np.ndarray, lat, lon, height) -> np.ndarray:
    """(n, 3) north-east-down offsets [m] of geodetic points from ``reference_ecef``."""
    xyz = geodetic_to_ecef(lat, lon, height) - reference_ecef
    ref_lat, ref_lon = float(np.mean(lat)), float(np.mean(lon))
    return xyz @ dcm_ecef_from_ned(ref_lat, ref_lon)


def test_kinematic_against_static(geonet, tmp_path):
    kinematic = _run(geonet, tmp_path / "kinematic.pos")
    static = _run(geonet, tmp_path / "static.pos",
                  options_overrides={"pos1-posmode": "static", "out-solstatic": "single"})
    assert kinematic.base_from_header
    assert kinematic.baseline_m == pytest.approx(3300, abs=100)  # README: about 3.3 km
    solution = kinematic.solution
    assert solution.source == tmp_path / "kinematic.pos"
    assert read_rtklib_pos(solution.source).time_s.tolist() == solution.time_s.tolist()
    assert len(solution) >= 110  # 1 h at 30 s, a few epochs without a common solution
    fix_rate = kinematic.qc.fix_rate
    assert len(static.solution) == 1  # out-solstatic = single: the one static solution
    reference = geodetic_to_ecef(static.solution.lat_rad, static.solution.lon_rad, static.solution.height_m)[0]
    ned = _ned_about(reference, solution.lat_rad, solution.lon_rad, solution.height_m)
    std = ned.std(axis=0)
    horizontal_std = float(np.hypot(std[0], std[1]))
    mean_offset = ned.mean(axis=0)
    print(f"\nkinematic: {len(solution)} epochs, fix rate {100 * fix_rate:.1f} %, std N/E/D "
          f"{1e3 * std[0]:.1f}/{1e3 * std[1]:.1f}/{1e3 * std[2]:.1f} mm (horizontal {1e3 * horizontal_std:.1f} mm), "
          f"mean - static N/E/D {1e3 * mean_offset[0]:.2f}/{1e3 * mean_offset[1]:.2f}/{1e3 * mean_offset[2]:.2f} mm, "
          f"RTKLIB {kinematic.elapsed_s:.2f} s")
    assert fix_rate >= 0.95
    assert horizontal_std <= 0.01
    assert std[2] <= 0.02
    assert np.all(np.abs(mean_offset) <= 0.005)
    # Baseline 3040 - 0759 is about 3.3 km (README).
    assert 3000 < np.linalg.norm(reference - np.array([-3976219.5082, 3382372.5671, 3652512.9849])) < 3600
    assert "fix rate" in kinematic.qc.report()


def test_base_position_given_moves_the_rover_by_the_base_offset(geonet, tmp_path):
    """A base given 1 m higher than its header position lifts the whole rover solution by 1 m."""
    header = np.array(read_obs_info(geonet / BASE).approx_position_ecef_m)
    from insrail.nav.earth import ecef_to_geodetic

    lat, lon, height = (float(v) for v in ecef_to_geodetic(header))
    forward = {"pos1-soltype": "forward"}
    from_header = _run(geonet, tmp_path / "a.pos", options_overrides=forward)
    raised = ppk(geonet / ROVER, geonet / BASE, [geonet / NAV[0]], tmp_path / "b.pos", options_overrides=forward,
                 base_position=BasePosition(lat, lon, height, antenna_height_m=1.0))
    assert not raised.base_from_header
    # RTKLIB gets the antenna reference point itself (its troposphere then refers to the antenna).
    assert raised.options["ant2-antdelu"] == "0.0" and raised.options["ant2-postype"] == "xyz"
    arp = [float(raised.options[f"ant2-pos{i}"]) for i in (1, 2, 3)]
    assert np.allclose(arp, geodetic_to_ecef(lat, lon, height + 1.0), atol=1e-6)
    lift = raised.solution.height_m - from_header.solution.height_m
    np.testing.assert_allclose(lift, 1.0, atol=0.003)


def test_ubx_converts_to_rinex(walk, tmp_path):
    paths = convert_to_rinex(walk / "gnss_1730.ubx", tmp_path)
    assert [p.name for p in paths] == ["gnss_1730.obs", "gnss_1730.nav"]
    obs = read_obs_info(paths[0])
    solution = read_rtklib_pos(walk / "gnss_1730_sf.pos")
    first = solution.gps_week * 604800 + solution.time_s[0]
    last = solution.gps_week * 604800 + solution.time_s[-1]
    print(f"\nUBX -> RINEX: {obs.epochs} epochs, {obs.first_s - first:+.4f} s / {obs.last_s - last:+.4f} s "
          "against the .pos")
    assert obs.epochs == len(solution) == 536
    # The .pos rounds its time tags to the ms the receiver is off by (17:30:39.748 -> .749).
    assert obs.first_s == pytest.approx(first, abs=0.002)
    assert obs.last_s == pytest.approx(last, abs=0.002)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["gnss_1730.nav", "gnss_1730.obs"]


def test_receiver_format_given_or_unknown(walk, tmp_path):
    copy = tmp_path / "log.dat"
    copy.write_bytes((walk / "gnss_1730.ubx").read_bytes()[:200_000])
    with pytest.raises(InputError, match="log.dat.*extension '.dat'"):
        convert_to_rinex(copy, tmp_path)
    assert convert_to_rinex(copy, tmp_path, format="ubx")[0].name == "log.obs"


def test_unreadable_receiver_log(tmp_path):
    log = tmp_path / "garbage.ubx"
    log.write_bytes(np.random.default_rng(3).integers(0, 256, 50_000, dtype=np.uint8).tobytes())
    out = tmp_path / "out"
    out.mkdir()
    with pytest.raises(InputError, match="garbage.ubx.*unreadable receiver log"):
        convert_to_rinex(log, out)
    assert list(out.iterdir()) == []


# --- bad input: clear errors naming the file, nothing written ------------------------------------

def _split_rinex(path: Path) -> tuple[str, list[str]]:
    """(header, epoch blocks) of a RINEX 2 observation file."""
    text = path.read_text()
    header, _, body = text.partition("END OF HEADER\n")
    starts = [m.start() for m in re.finditer(r"^ \d\d [ \d]\d [ \d]\d [ \d]\d [ \d]\d [ \d]\d\.\d{7}  0", body, re.MULTILINE)]
    return header + "END OF HEADER\n", [body[a:b] for a, b in zip(starts, starts[1:] + [len(body)])]


def _expect_nothing_written(folder: Path, out: Path) -> None:
    assert not out.exists()
    assert not [p for p in folder.iterdir() if p.name.startswith(f".{out.name}")]


def test_no_navigation_data(geonet, tmp_path):
    out = tmp_path / "out.pos"
    with pytest.raises(InputError, match=f"{ROVER}.*no navigation data"):
        ppk(geonet / ROVER, geonet / BASE, [], out)
    empty_nav = tmp_path / "empty.05n"
    text = (geonet / NAV[0]).read_text()
    empty_nav.write_text(text[:text.index("END OF HEADER") + len("END OF HEADER\n")])
    with pytest.raises(InputError, match="empty.05n.*no navigation data"):
        ppk(geonet / ROVER, geonet / BASE, [empty_nav], out)
    with pytest.raises(InputError, match=f"{BASE}.*expected a RINEX navigation file"):
        ppk(geonet / ROVER, geonet / BASE, [geonet / BASE], out)
    _expect_nothing_written(tmp_path, out)


def test_base_and_rover_not_overlapping(geonet, tmp_path):
    header, blocks = _split_rinex(geonet / ROVER)
    early = tmp_path / "early.05o"
    early.write_text(header + "".join(blocks[:40]))
    header, blocks = _split_rinex(geonet / BASE)
    late = tmp_path / "late.05o"
    late.write_text(header + "".join(blocks[-40:]))
    out = tmp_path / "out.pos"
    with pytest.raises(InputError, match="late.05o.*do not overlap in time.*early.05o"):
        ppk(early, late, [geonet / NAV[0]], out)
    _expect_nothing_written(tmp_path, out)


def test_unknown_base_position(geonet, tmp_path):
    base = tmp_path / "nopos.05o"
    zero = f"{0.0:14.4f}" * 3 + " " * 18 + "APPROX POSITION XYZ"
    base.write_text("\n".join(zero if line.rstrip().endswith("APPROX POSITION XYZ") else line
                              for line in (geonet / BASE).read_text().splitlines()) + "\n")
    assert read_obs_info(base).approx_position_ecef_m is None
    out = tmp_path / "out.pos"
    with pytest.raises(InputError, match="nopos.05o.*unknown base position"):
        ppk(geonet / ROVER, base, [geonet / NAV[0]], out)
    _expect_nothing_written(tmp_path, out)


def test_not_rinex_and_missing_files(geonet, tmp_path):
    junk = tmp_path / "junk.05o"
    junk.write_text("hello\n")
    out = tmp_path / "out.pos"
    with pytest.raises(InputError, match="junk.05o.*not a RINEX file"):
        ppk(junk, geonet / BASE, [geonet / NAV[0]], out)
    with pytest.raises(InputError, match="missing.05o: file not found"):
        ppk(tmp_path / "missing.05o", geonet / BASE, [geonet / NAV[0]], out)
    _expect_nothing_written(tmp_path, out)


def test_bad_options_and_cancel_leave_the_old_file(geonet, tmp_path):
    out = tmp_path / "out.pos"
    out.write_text("previous result\n")
    with pytest.raises(OptionError, match="pos1-posmod.*unknown RTKLIB option"):
        ppk(geonet / ROVER, geonet / BASE, [geonet / NAV[0]], out, options_overrides={"pos1-posmod": "static"})
    with pytest.raises(OptionError, match="pos2-armode.*expected one of"):
        ppk(geonet / ROVER, geonet / BASE, [geonet / NAV[0]], out, options_overrides={"pos2-armode": "hold"})
    with pytest.raises(OptionError, match="out-solformat"):
        ppk(geonet / ROVER, geonet / BASE, [geonet / NAV[0]], out, options_overrides={"out-solformat": "xyz"})
    with pytest.raises(OptionError, match="out-height"):
        ppk(geonet / ROVER, geonet / BASE, [geonet / NAV[0]], out, options_overrides={"out-height": "1"})
    with pytest.raises(Cancelled), pytest.warns(ApproximateBaseWarning):
        ppk(geonet / ROVER, geonet / BASE, [geonet / NAV[0]], out, cancel=lambda: True)
    assert out.read_text() == "previous result\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.pos"]


def test_long_baseline_warns(geonet, tmp_path):
    far = tuple(np.array(read_obs_info(geonet / BASE).approx_position_ecef_m) + [0.0, 20_000.0, 0.0])
    out = tmp_path / "out.pos"
    with pytest.warns(LongBaselineWarning, match=r"baseline \d+\.\d km is longer than the 15 km"), \
            pytest.raises(Cancelled):
        ppk(geonet / ROVER, geonet / BASE, [geonet / NAV[0]], out, base_position=BasePosition(ecef_m=far),
            cancel=lambda: True)
    _expect_nothing_written(tmp_path, out)


def test_backward_solution_is_written_in_time_order(geonet, tmp_path):
    backward = _run(geonet, tmp_path / "backward.pos", options_overrides={"pos1-soltype": "backward"})
    forward = _run(geonet, tmp_path / "forward.pos", options_overrides={"pos1-soltype": "forward"})
    assert np.all(np.diff(backward.solution.time_s) > 0)
    assert backward.solution.time_s[-1] == forward.solution.time_s[-1]
    assert np.isin(forward.solution.time_s, backward.solution.time_s).all()
    assert backward.qc.fix_rate >= 0.95
