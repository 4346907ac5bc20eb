"""The RINEX observation simulator: broadcast orbits against RTKLIB's, RINEX headers RTKLIB needs,
and PPK of simulated rover/base files against the simulated truth."""


import numpy as np
import pytest
from real_data import REAL

from insrail.gnss import BasePosition, ppk
from insrail.gnss.rinex import read_obs_info
from insrail.io.errors import InputError
from insrail.io.rinex import read_gps_ephemerides
from insrail.nav import earth
from insrail.sim.gnss_obs import (
    GnssObsSpec,
    ReceiverTrack,
    satellite_positions,
    simulate_gnss_observations,
)

DATA = REAL / "rinex_0759_3040"
NAV = DATA / "07590920.05n"
WEEK = 1316  # 2005-04-02 is in GPS week 1316 (Saturday)
START = 558000.0  # 11:00 GPST: eight satellites with ephemerides above 15 deg at the simulated line


def test_satellite_positions_and_clocks_agree_with_rtklib():
    pyrtklib = pytest.importorskip("pyrtklib")
    eph = read_gps_ephemerides(NAV)
    nav, obs, sta = pyrtklib.nav_t(), pyrtklib.obs_t(), pyrtklib.sta_t()
    assert pyrtklib.readrnx(str(NAV), 1, "", obs, nav, sta) == 1
    assert nav.n == len(eph) == 162
    rs, dts, var = pyrtklib.Arr1Ddouble(6), pyrtklib.Arr1Ddouble(2), pyrtklib.Arr1Ddouble(1)
    worst_position, worst_clock = 0.0, 0.0
    for i in range(nav.n):
        e = nav.eph[i]
        row = np.flatnonzero((eph.prn == e.sat) & (eph.toe_s == e.toes) & (eph.m0_rad == e.M0))
        assert len(row) == 1
        for offset in (-3600.0, 0.0, 5400.0):
            pyrtklib.eph2pos(pyrtklib.timeadd(e.toe, offset), e, rs, dts, var)
            t = (e.week - WEEK) * 604800.0 + e.toes + offset
            position, clock = satellite_positions(eph, row, np.array([t]), WEEK)
            worst_position = max(worst_position, np.linalg.norm(position[0] - [rs[0], rs[1], rs[2]]))
            worst_clock = max(worst_clock, abs(clock[0] - dts[0]))
    assert worst_position < 1e-6  # m
    assert worst_clock < 1e-15  # s


def test_ephemeris_reader_names_the_bad_file(tmp_path):
    with pytest.raises(InputError, match="file not found"):
        read_gps_ephemerides(tmp_path / "missing.nav")
    with pytest.raises(InputError, match="07590920.05o.*navigation file"):
        read_gps_ephemerides(DATA / "07590920.05o")
    broken = tmp_path / "broken.05n"
    lines = NAV.read_text().splitlines()
    end = next(i for i, line in enumerate(lines) if "END OF HEADER" in line)
    lines[end + 3] = lines[end + 3][:3] + "  x.ABCD+01" + lines[end + 3][13:]
    broken.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError, match=f"broken.05n, line {end + 4}: expected a number"):
        read_gps_ephemerides(broken)


@pytest.fixture(scope="module")
def simulated(tmp_path_factory):
    """A rover standing 30 s, then driving a 60 m radius circle at 1.5 m/s, beside a base on a known mark."""
    out = tmp_path_factory.mktemp("gnss_obs")
    t = START + np.arange(0.0, 300.0, 1.0)
    lat0, lon0, h0 = np.radians(30.49), np.radians(114.43), 30.0
    angle = 1.5 * np.maximum(t - t[0] - 30.0, 0.0) / 60.0
    north, east = 60.0 * np.sin(angle), 60.0 * (1.0 - np.cos(angle))
    rover = earth.geodetic_to_ecef(lat0 + north / 6.36e6, lon0 + east / (6.38e6 * np.cos(lat0)),
                                   h0 + 0.5 * np.sin(angle))
    mark = earth.geodetic_to_ecef(lat0 + 200.0 / 6.36e6, lon0, h0 - 3.0)
    result = simulate_gnss_observations(NAV, ReceiverTrack(t, rover), t, mark, 1.6, WEEK, out, seed=11)
    return out, t, rover, mark, result


def test_rinex_headers_hold_what_rtklib_needs(simulated):
    out, t, rover, mark, result = simulated
    rover_info, base_info = read_obs_info(result.rover_obs), read_obs_info(result.base_obs)
    for info in (rover_info, base_info):
        assert info.version == 2.11 and info.epochs == len(t) == result.epochs
        assert info.first_s == WEEK * 604800.0 + t[0] and info.last_s == WEEK * 604800.0 + t[-1]
    assert 0.01 < np.linalg.norm(np.subtract(base_info.approx_position_ecef_m, mark)) < 10.0  # approximate
    assert np.linalg.norm(np.subtract(rover_info.approx_position_ecef_m, rover[0])) < 10.0
    assert base_info.antenna_delta_hen_m == (1.6, 0.0, 0.0)
    header = result.base_obs.read_text().split("END OF HEADER")[0]
    for label in ("# / TYPES OF OBSERV", "INTERVAL", "TIME OF FIRST OBS", "  2005     4     2    11     0"):
        assert label in header
    assert "     4    C1    L1    P2    L2" in header
    assert result.satellites_per_epoch_min >= 7


def test_ppk_of_simulated_observations_fixes_and_matches_the_truth(simulated):
    out, t, rover, mark, result = simulated
    lat, lon, h = earth.ecef_to_geodetic(mark)
    solution = ppk(result.rover_obs, result.base_obs, [NAV], out / "rover.pos",
                   base_position=BasePosition(float(lat), float(lon), float(h), antenna_height_m=1.6))
    assert solution.qc.fix_rate >= 0.95
    sol = solution.solution
    k = np.searchsorted(t, sol.time_s)
    assert np.allclose(t[k], sol.time_s)
    error = earth.geodetic_to_ecef(sol.lat_rad, sol.lon_rad, sol.height_m) - rover[k]
    ned = np.einsum("nij,ni->nj", earth.dcm_ecef_from_ned(sol.lat_rad, sol.lon_rad), error)
    horizontal, vertical = np.hypot(ned[:, 0], ned[:, 1]), ned[:, 2]
    # Single-epoch fixed positions (kinematic, no dynamics): 8 satellites, 2 mm phase noise.
    assert np.sqrt(np.mean(horizontal**2)) < 0.005 and np.percentile(horizontal, 95) < 0.008
    assert np.sqrt(np.mean(vertical**2)) < 0.008 and np.percentile(np.abs(vertical), 95) < 0.015
    # RTKLIB's combined solution starts from the forward filter's float first epoch (here 4 cm off in height).
    assert horizontal[1:].max() < 0.015 and np.abs(vertical[1:]).max() < 0.025
    assert horizontal[0] < 0.03 and abs(vertical[0]) < 0.06
    assert np.abs(ned.mean(axis=0)).max() < 0.003  # no bias: orbits, clocks, Sagnac, atmosphere consistent


def test_noise_free_simulation_and_rtklib_agree_to_a_fraction_of_a_millimetre(tmp_path):
    """With (almost) no noise, what is left is the difference between the simulator's model and RTKLIB's:
    orbits, clocks, light time, Sagnac, troposphere per receiver height (the base antenna 5 m above
    its mark: RTKLIB is given the antenna reference point), common ionosphere."""
    t = START + np.arange(0.0, 120.0, 1.0)
    rover = np.tile(earth.geodetic_to_ecef(np.radians(30.49), np.radians(114.43), 30.0), (len(t), 1))
    mark = earth.geodetic_to_ecef(np.radians(30.49) + 300.0 / 6.36e6, np.radians(114.43), 22.0)
    quiet = GnssObsSpec(code_sigma_m=0.05, phase_sigma_m=0.0001)
    result = simulate_gnss_observations(NAV, ReceiverTrack(t, rover), t, mark, 5.0, WEEK, tmp_path, seed=5, spec=quiet)
    lat, lon, h = earth.ecef_to_geodetic(mark)
    solution = ppk(result.rover_obs, result.base_obs, [NAV], tmp_path / "rover.pos",
                   base_position=BasePosition(float(lat), float(lon), float(h), antenna_height_m=5.0)).solution
    error = earth.geodetic_to_ecef(solution.lat_rad, solution.lon_rad, solution.height_m) - rover[0]
    ned = np.einsum("nij,ni->nj", earth.dcm_ecef_from_ned(solution.lat_rad, solution.lon_rad), error)
    # After the combined solution's float first epoch; the .pos prints 0.1 mm.
    assert np.abs(ned[1:].mean(axis=0)).max() < 0.0003 and np.abs(ned[1:]).max() < 0.001
