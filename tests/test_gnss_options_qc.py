"""RTKLIB option handling, solution QC, and the ppk command line."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from insrail.gnss import OptionError, gnss_qc, load_options, rtklib_option_table
from insrail.gnss.options import apply_options, parse_config
from insrail.io.errors import InputError
from insrail.io.textparse import find_gaps
from insrail.io.types import GnssSolution


def test_option_table_is_rtklibs():
    table = rtklib_option_table()
    assert table["pos1-posmode"][0] == 3 and "2:kinematic" in table["pos1-posmode"][1]
    assert table["pos1-elmask"][0] == 1
    assert "file-satantfile" in table and "ant2-antdelu" in table
    assert len(table) > 100


def test_default_config_is_valid_and_applied():
    options = load_options()
    assert options["pos1-posmode"] == "kinematic"
    assert options["pos1-soltype"] == "combined"
    prcopt, _solopt, _ = apply_options(options)
    assert prcopt.mode == 2 and prcopt.soltype == 2 and prcopt.modear == 3  # kinematic, combined, fix-and-hold
    assert prcopt.elmin == pytest.approx(np.radians(15.0))
    assert prcopt.navsys == 1 + 4 + 8 + 32


def test_overrides_by_name_or_number():
    options = load_options(overrides={"pos1-posmode": "3", "pos2-armode": "continuous", "pos1-elmask": 10})
    prcopt, _, _ = apply_options(options)
    assert prcopt.mode == 3 and prcopt.modear == 1
    assert prcopt.elmin == pytest.approx(np.radians(10.0))


@pytest.mark.parametrize("key, value, message", [
    ("pos1-posmod", "static", "unknown RTKLIB option 'pos1-posmod'"),
    ("pos2-armode", "hold", "expected one of 0:off,1:continuous"),
    ("pos1-elmask", "ten", "expected a number"),
    ("pos2-arminfix", "1.5", "expected an integer"),
])
def test_bad_overrides(key, value, message):
    with pytest.raises(OptionError, match=f"options_overrides\\['{key}'\\]: .*{message}"):
        load_options(overrides={key: value})


def test_config_file_errors_name_the_line(tmp_path):
    conf = tmp_path / "my.conf"
    conf.write_text("# mine\npos1-posmode = static   # comment\n\npos1-elmask 10\n")
    with pytest.raises(InputError, match="my.conf, line 4: expected 'key = value'"):
        parse_config(conf)
    conf.write_text("pos1-posmode = static\nstats-nonsense = 1\n")
    with pytest.raises(InputError, match="my.conf, line 2: unknown RTKLIB option 'stats-nonsense'"):
        parse_config(conf)
    conf.write_text("pos1-posmode = static   # comment\npos1-elmask = 20\n")
    assert load_options(conf) == {"pos1-posmode": "static", "pos1-elmask": "20"}
    with pytest.raises(InputError, match="absent.conf: RTKLIB configuration file not found"):
        load_options(tmp_path / "absent.conf")


# --- QC ----------------------------------------------------------------------------------------

def _solution(time_s, quality, ratio, sigma):
    n = len(time_s)
    return GnssSolution(time_s=np.asarray(time_s, float), lat_rad=np.full(n, 0.6), lon_rad=np.full(n, 2.4),
                        height_m=np.zeros(n), sigma_ned_m=np.asarray(sigma, float),
                        quality=np.asarray(quality), num_sats=np.full(n, 9), ratio=np.asarray(ratio, float),
                        gaps=find_gaps(np.asarray(time_s, float)))


def test_qc_by_hand():
    time_s = np.r_[0:10.0, 20:25.0]  # a 10 s gap after t = 9
    quality = np.array([1] * 10 + [2] * 3 + [5] * 2)
    ratio = np.r_[np.arange(3.0, 13.0), np.zeros(5)]
    sigma = np.column_stack([np.full(15, 0.003), np.full(15, 0.004), np.full(15, 0.010)])
    sigma[10:] *= 10
    qc = gnss_qc(_solution(time_s, quality, ratio, sigma))
    assert qc.epochs == 15 and qc.interval_s == 1.0
    assert qc.epochs_by_quality == {"fix": 10, "float": 3, "single": 2}
    assert qc.fix_rate == pytest.approx(10 / 15)
    assert qc.ratio_min == 3.0 and qc.ratio_median == pytest.approx(7.5)
    assert qc.sigma_by_quality["fix"].horizontal_median_m == pytest.approx(0.005)
    assert qc.sigma_by_quality["float"].vertical_max_m == pytest.approx(0.1)
    assert len(qc.gaps) == 1 and (qc.gaps[0].start_s, qc.gaps[0].end_s) == (9.0, 20.0)
    assert qc.gap_total_s == 11.0
    report = qc.report()
    assert "fix rate         : 66.67 %" in report and "9.000 .. 20.000  (11.0 s)" in report


def test_qc_empty_and_no_fix():
    assert gnss_qc(_solution([], [], [], np.zeros((0, 3)))).epochs == 0
    qc = gnss_qc(_solution([0.0, 1.0, 2.0], [2, 2, 5], [0.0, 0.0, 0.0], np.full((3, 3), 0.5)))
    assert qc.fix_rate == 0.0 and np.isnan(qc.ratio_median)
    assert "fix rate         : 0.00 %" in qc.report()


@settings(max_examples=40, deadline=None)
@given(st.lists(st.sampled_from([1, 2, 4, 5]), min_size=3, max_size=60))
def test_qc_counts_add_up(qualities):
    n = len(qualities)
    qc = gnss_qc(_solution(np.arange(n) * 0.2, qualities, np.full(n, 5.0), np.full((n, 3), 0.01)))
    assert sum(qc.epochs_by_quality.values()) == n
    assert qc.fix_rate == pytest.approx(qualities.count(1) / n)
    assert set(qc.sigma_by_quality) == set(qc.epochs_by_quality)
    assert qc.gaps == ()


# --- CLI ---------------------------------------------------------------------------------------

def test_cli_ppk(tmp_path, capsys):
    from real_data import real_path
    from test_gnss_ppk import BASE, NAV, ROVER

    from insrail.cli.main import main
    from insrail.io.rtklib import read_rtklib_pos

    geonet = real_path("rinex_0759_3040")
    out = tmp_path / "rover.pos"
    args = ["ppk", str(geonet / ROVER), "--base", str(geonet / BASE), "--nav", *(str(geonet / n) for n in NAV),
            "--out", str(out)]
    with pytest.raises(SystemExit):  # a base position source is required
        main(args)
    assert main(args + ["--base-from-header", "--set", "pos1-soltype=forward"]) == 0
    printed = capsys.readouterr().out
    assert "approximate" in printed and "fix rate" in printed
    assert len(read_rtklib_pos(out)) > 100
    assert main(args + ["--base-from-header"]) == 1  # exists, no --force
    assert main(args + ["--base-pos", "35.1", "139.6", "80", "--set", "pos1-bogus=1", "--force"]) == 1
    assert "unknown RTKLIB option 'pos1-bogus'" in capsys.readouterr().err


def test_base_position_options():
    from insrail.gnss import BasePosition
    from insrail.nav.earth import geodetic_to_ecef

    # RTKLIB gets the antenna reference point (1.5 m above the mark) with a zero antenna delta.
    geodetic = BasePosition.from_degrees(35.5, 139.25, 60.0, antenna_height_m=1.5).rtklib_options()
    assert geodetic["ant2-postype"] == "xyz" and geodetic["ant2-antdelu"] == "0.0"
    prcopt, _, _ = apply_options(load_options(overrides=geodetic))
    arp = geodetic_to_ecef(np.radians(35.5), np.radians(139.25), 61.5)
    assert [prcopt.rb[i] for i in range(3)] == pytest.approx(arp, abs=1e-6)
    assert [prcopt.antdel[1, i] for i in range(3)] == [0.0, 0.0, 0.0]
    ecef = BasePosition(ecef_m=(-3976219.5, 3382372.5, 3652512.9)).rtklib_options()
    assert ecef["ant2-postype"] == "xyz" and float(ecef["ant2-pos3"]) == pytest.approx(3652512.9, abs=1e-6)
    prcopt, _, _ = apply_options(load_options(overrides=ecef))
    assert [prcopt.rb[i] for i in range(3)] == pytest.approx([-3976219.5, 3382372.5, 3652512.9], abs=1e-6)
    for bad in ({"lat_rad": 0.6, "lon_rad": 2.4}, {}, {"lat_rad": 0.6, "lon_rad": 2.4, "height_m": 1.0,
                                                       "ecef_m": (1.0, 2.0, 3.0)}, {"ecef_m": (np.nan, 0.0, 0.0)}):
        with pytest.raises(ValueError, match="BasePosition"):
            BasePosition(**bad)
