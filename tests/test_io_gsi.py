"""Leica GSI total-station files: write -> read round trips (hypothesis), published example blocks,
face II, units, detection, and errors naming file, line and word."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from insrail.io import detect_format, read_any
from insrail.io.errors import InputError
from insrail.io.gsi import read_cpiii_gsi, read_total_station_gsi, write_cpiii_gsi, write_total_station_gsi
from insrail.io.types import ControlPoints, TotalStationObservations

GON = math.pi / 200.0
ids = st.from_regex(r"[A-Za-z1-9][A-Za-z0-9_.]{0,15}", fullmatch=True).filter(lambda s: not s.lower().startswith("prism"))


@st.composite
def observations(draw):
    setups = draw(st.lists(ids, min_size=1, max_size=3, unique=True))
    rows = {k: [] for k in ("setup", "target", "time_s", "hz_rad", "zenith_rad", "slope_m")}
    clock = draw(st.floats(0.0, 5e5))
    for setup in setups:
        n = draw(st.integers(1, 6))
        for _ in range(n):
            prism = draw(st.booleans())
            clock += draw(st.floats(0.001, 100.0))
            rows["setup"].append(setup)
            rows["target"].append("prism" if prism else draw(ids))
            rows["time_s"].append(clock)
            rows["hz_rad"].append(draw(st.floats(0.0, 2 * math.pi, exclude_max=True)))
            rows["zenith_rad"].append(draw(st.floats(1 * GON, 199 * GON)))
            rows["slope_m"].append(draw(st.floats(0.5, 3000.0)))
    n = len(rows["time_s"])
    return TotalStationObservations(**{k: np.array(v) for k, v in rows.items()}, line=np.zeros(n, dtype=int))


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(obs=observations())
def test_pointings_round_trip(obs, tmp_path):
    path = tmp_path / "setups.gsi"
    write_total_station_gsi(path, obs)
    assert detect_format(path) == "total-station-gsi"
    back = read_any(path)
    np.testing.assert_array_equal(back.setup, obs.setup)
    np.testing.assert_array_equal(back.target, obs.target)
    np.testing.assert_allclose(back.time_s, obs.time_s, rtol=0, atol=0.51e-4)
    hz_error = np.angle(np.exp(1j * (back.hz_rad - obs.hz_rad)))  # 400 gon wraps to 0
    assert np.all(np.abs(hz_error) <= 0.51e-5 * GON)
    np.testing.assert_allclose(back.zenith_rad, obs.zenith_rad, rtol=0, atol=0.51e-5 * GON)
    np.testing.assert_allclose(back.slope_m, obs.slope_m, rtol=0, atol=0.51e-5)
    assert np.all(back.line >= 2)  # each pointing's own line, after its station block


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(points=st.lists(st.tuples(ids, *[st.floats(-1e7, 1e7)] * 3), min_size=1, max_size=8,
                       unique_by=lambda p: p[0]))
def test_cpiii_round_trip(points, tmp_path):
    path = tmp_path / "cpiii.gsi"
    name, e, n, h = (np.array(c) for c in zip(*points))
    write_cpiii_gsi(path, ControlPoints(name, e, n, h))
    assert detect_format(path) == "cpiii-gsi"
    back = read_cpiii_gsi(path)
    np.testing.assert_array_equal(back.point_id, name)
    for got, want in ((back.east_m, e), (back.north_m, n), (back.height_m, h)):
        np.testing.assert_allclose(got, want, rtol=0, atol=0.51e-5)


def test_published_gsi8_and_gsi16_blocks(tmp_path):
    """Blocks as Leica instruments write them (GSI-8 from Autodesk's GSI page, GSI-16 with the words
    a real file holds, 87 and 51 among them), face II and sexagesimal angles, CPIII pointings untimed."""
    path = tmp_path / "crew.gsi"
    path.write_text(
        "\ufeff410001+00000020 42....+00007142\r\n"  # a byte-order mark, Windows line ends, a code block: skipped
        "*110001+0000000000STN001 84..10+0000000000000000 85..10+0000000000000000 88..10+0000000000001600 \n"
        "110002+00130021 21.102+19723700 22.102+10000000 31..00+00045179 51....+0000+000\n"
        "*110003+0000000000CP0017 21...2+0000000014638140 22...2+0000000010175230 31...0+0000000000006627 "
        "87..10+000000000000000 51....+000000000000+017\n"
        "*110004+00000000PRISM001 21.324+0000000027952530 22.324+0000000027000420 31..08+0000000000452914 "
        "71....+000000345600.250\n")
    obs = read_total_station_gsi(path)
    assert list(obs.setup) == ["STN001"] * 3 and list(obs.target) == ["130021", "CP0017", "prism"]
    assert list(obs.line) == [3, 4, 5]
    np.testing.assert_allclose(obs.hz_rad[:2] / GON, [197.237, 146.3814], atol=1e-9)
    np.testing.assert_allclose(obs.zenith_rad[:2] / GON, [100.0, 101.7523], atol=1e-9)
    np.testing.assert_allclose(obs.slope_m, [45.179, 6.627, 4.52914], atol=1e-9)
    # face II, sexagesimal: Hz 279 deg 52' 53.0", V 270 deg 00' 42.0" -> face I
    np.testing.assert_allclose(math.degrees(obs.hz_rad[2]), 279 + 52 / 60 + 53 / 3600 - 180, atol=1e-9)
    np.testing.assert_allclose(math.degrees(obs.zenith_rad[2]), 360 - (270 + 42 / 3600), atol=1e-9)
    np.testing.assert_allclose(obs.time_s, 345600.25)  # the CPIII pointings take their set-up's time


@pytest.mark.parametrize("block, where, says", [
    ("*110002+000000000000CP01 21.102+0000000019723700 22.102+0000000010000000 31..01+0000000000045179",
     "line 2: word 4 (31..01+", "feet is not read"),
    ("*110002+000000000000CP01 21.105+0000000019723700 22.102+0000000010000000 31..00+0000000000045179",
     "line 2: word 2 (21.105+", "mil is not read"),
    ("*110002+000000000000CP01 21.102+0000000019723700 31..00+0000000000045179",
     "line 2:", "word 22 missing"),
    ("*110002+000000000000CP01 21.102+00000000197X3700 22.102+0000000010000000 31..00+0000000000045179",
     "line 2: word 2 (21.102+00000000197X3700)", "expected digits"),
    ("*110002+000000000000CP01 21.102+0000000019723700 22.102 31..00+0000000000045179",
     "line 2: word 3 ('22.102')", "expected a GSI word"),
    ("*110002+00000000000PRISM 21.102+0000000019723700 22.102+0000000010000000 31..00+0000000000045179",
     "line 2:", "prism pointing PRISM: expected its time"),
    ("*110002+000000000000CP01 21.102+0000000019723700 22.102+0000000040000000 31..00+0000000000045179",
     "line 2: word 3 (22.102+", "not a zenith angle"),
])
def test_errors_name_file_line_and_word(tmp_path, block, where, says):
    path = tmp_path / "bad.gsi"
    path.write_text("*110001+0000000000000TS1 88..10+0000000000000000\n" + block + "\n")
    with pytest.raises(InputError) as error:
        read_total_station_gsi(path)
    assert f"bad.gsi, {where}" in str(error.value) and says in str(error.value)


def test_a_pointing_needs_its_station_block_and_cpiii_ids_once(tmp_path):
    path = tmp_path / "bad.gsi"
    path.write_text("*110001+000000000000CP01 21.102+0000000019723700 22.102+0000000010000000 "
                    "31..00+0000000000045179\n")
    with pytest.raises(InputError, match=r"bad.gsi, line 1: a pointing before any station block"):
        read_total_station_gsi(path)
    path.write_text("*110001+000000000000CP01 81..00+0000000000001000 82..00+0000000000002000 83..00+0000000000000030\n"
                    "\n*110002+000000000000CP01 81..00+0000000000001000 82..00+0000000000002000 83..00-0000000000000030\n")
    with pytest.raises(InputError, match=r"line 3: word 1: point CP01 is given twice \(first on line 1\)"):
        read_cpiii_gsi(path)
