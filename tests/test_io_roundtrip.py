"""Write -> read round trips: arbitrary finite values and increasing times survive to the stated precision."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from insrail.io import (
    detect_format,
    read_any,
    read_benchmarks,
    read_gauge_mm,
    read_gnss_kfgins,
    read_imu_kfgins,
    read_imu_npy,
    read_odometer_distance,
    read_odometer_pulses,
    read_prism_enu,
    read_rtklib_pos,
    read_sleeper_times,
    write_benchmarks,
    write_gauge_mm,
    write_gnss_kfgins,
    write_imu_kfgins,
    write_imu_npy,
    write_odometer_distance,
    write_odometer_pulses,
    write_prism_enu,
    write_rtklib_pos,
    write_sleeper_times,
)
from insrail.io.types import (
    Benchmarks,
    GaugeData,
    GnssSolution,
    ImuIncrements,
    OdometerData,
    PrismObservations,
    SleeperPulses,
)

PROPERTY = settings(max_examples=25, deadline=None,
                    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
TIME_TOL_S = 1e-9
DEG = np.pi / 180


@st.composite
def times(draw, min_size=1, max_size=30, min_step_us=1, start_max=604_000.0):
    """Strictly increasing GPS seconds of week (steps of whole microseconds)."""
    start = draw(st.floats(0.0, start_max, allow_nan=False))
    steps = draw(st.lists(st.integers(min_step_us, 10**8), min_size=min_size - 1, max_size=max_size - 1))
    return start + np.concatenate(([0], np.cumsum(steps))) * 1e-6


def finite(n, lo, hi, shape=None):
    return hnp.arrays(np.float64, shape if shape is not None else n,
                      elements=st.floats(lo, hi, allow_nan=False, allow_infinity=False))


def assert_time(actual, expected):
    np.testing.assert_allclose(actual, expected, rtol=0, atol=TIME_TOL_S)


@st.composite
def imu_data(draw):
    # Steps of at least 1 ms keep increments of up to 0.01 rad and m/s physically plausible.
    t = draw(times(min_step_us=1000))
    n = len(t)
    return ImuIncrements(time_s=t, dtheta_rad=draw(finite(n, -0.01, 0.01, (n, 3))),
                         dvel_mps=draw(finite(n, -0.01, 0.01, (n, 3))),
                         gps_week=draw(st.none() | st.integers(0, 5000)))


@PROPERTY
@given(imu=imu_data())
def test_imu_kfgins_is_lossless(imu, tmp_path):
    path = tmp_path / "imu.txt"
    write_imu_kfgins(path, imu)
    back = read_imu_kfgins(path)
    assert_time(back.time_s, imu.time_s)
    np.testing.assert_array_equal(back.dtheta_rad, imu.dtheta_rad)
    np.testing.assert_array_equal(back.dvel_mps, imu.dvel_mps)
    assert back.gps_week == imu.gps_week
    assert detect_format(path) == "kfgins-imu"


@PROPERTY
@given(imu=imu_data())
def test_imu_npy_is_exact(imu, tmp_path):
    path = tmp_path / "imu.npy"
    write_imu_npy(path, imu)
    back = read_imu_npy(path)
    np.testing.assert_array_equal(back.time_s, imu.time_s)
    np.testing.assert_array_equal(back.dtheta_rad, imu.dtheta_rad)
    np.testing.assert_array_equal(back.dvel_mps, imu.dvel_mps)
    assert detect_format(path) == "imu-npy"


@st.composite
def gnss_data(draw, with_velocity=None, rtklib=False):
    # .pos time of week has 1 us resolution: keep stamps further apart than that.
    t = draw(times(start_max=600_000.0, min_step_us=10 if rtklib else 1))
    n = len(t)
    if with_velocity is None:
        with_velocity = draw(st.booleans())
    return GnssSolution(
        time_s=t,
        lat_rad=draw(finite(n, -90, 90)) * DEG,
        lon_rad=draw(finite(n, -180, 180)) * DEG,
        height_m=draw(finite(n, -500, 9000)),
        sigma_ned_m=draw(finite(n, 0, 100, (n, 3))),
        quality=draw(hnp.arrays(np.int64, n, elements=st.integers(0, 6))) if rtklib else np.zeros(n, int),
        num_sats=draw(hnp.arrays(np.int64, n, elements=st.integers(0, 99))) if rtklib else np.zeros(n, int),
        ratio=draw(finite(n, 0, 999)) if rtklib else np.full(n, np.nan),
        vel_ned_mps=draw(finite(n, -100, 100, (n, 3))) if with_velocity else None,
        sigma_vel_ned_mps=draw(finite(n, 0, 10, (n, 3))) if with_velocity else None,
        gps_week=draw(st.integers(0, 5000)),
    )


def assert_gnss(back: GnssSolution, gnss: GnssSolution, angle_tol_deg: float, time_tol_s: float):
    np.testing.assert_allclose(back.time_s, gnss.time_s, rtol=0, atol=time_tol_s)
    np.testing.assert_allclose(back.lat_rad, gnss.lat_rad, rtol=0, atol=angle_tol_deg * DEG)
    np.testing.assert_allclose(back.lon_rad, gnss.lon_rad, rtol=0, atol=angle_tol_deg * DEG)
    np.testing.assert_allclose(back.height_m, gnss.height_m, rtol=0, atol=1e-6)
    np.testing.assert_allclose(back.sigma_ned_m, gnss.sigma_ned_m, rtol=0, atol=1e-6)
    assert (back.vel_ned_mps is None) == (gnss.vel_ned_mps is None)
    if gnss.vel_ned_mps is not None:
        np.testing.assert_allclose(back.vel_ned_mps, gnss.vel_ned_mps, rtol=0, atol=1e-6)
        np.testing.assert_allclose(back.sigma_vel_ned_mps, gnss.sigma_vel_ned_mps, rtol=0, atol=1e-6)
    assert back.gps_week == gnss.gps_week


@PROPERTY
@given(gnss=gnss_data())
def test_gnss_kfgins_round_trip(gnss, tmp_path):
    path = tmp_path / "gnss.txt"
    write_gnss_kfgins(path, gnss)
    back = read_gnss_kfgins(path)
    assert_gnss(back, gnss, 1e-12, TIME_TOL_S)
    assert detect_format(path) == "kfgins-gnss"


@PROPERTY
@given(gnss=gnss_data(rtklib=True))
def test_rtklib_pos_round_trip(gnss, tmp_path):
    path = tmp_path / "gnss.pos"
    write_rtklib_pos(path, gnss)
    back = read_rtklib_pos(path)
    assert_gnss(back, gnss, 1e-11, 0.5e-6 + 1e-9)  # tow is written to 1 us
    np.testing.assert_array_equal(back.quality, gnss.quality)
    np.testing.assert_array_equal(back.num_sats, gnss.num_sats)
    np.testing.assert_allclose(back.ratio, gnss.ratio, rtol=0, atol=0.05 + 1e-9)
    assert detect_format(path) == "rtklib-pos"


def test_rtklib_pos_needs_a_week(tmp_path):
    gnss = GnssSolution(np.array([1.0]), np.array([0.5]), np.array([0.1]), np.array([10.0]),
                        np.zeros((1, 3)), np.ones(1, int), np.ones(1, int), np.ones(1))
    with pytest.raises(ValueError, match="GPS week"):
        write_rtklib_pos(tmp_path / "x.pos", gnss)


def test_rtklib_writer_carries_the_week_over(tmp_path):
    """A series running past the end of the week is written with week+1 and read back continuous."""
    gnss = GnssSolution(np.array([604799.0, 604800.5]), np.full(2, 0.5), np.full(2, 0.1), np.full(2, 10.0),
                        np.zeros((2, 3)), np.ones(2, int), np.ones(2, int), np.ones(2), gps_week=2380)
    path = tmp_path / "x.pos"
    write_rtklib_pos(path, gnss)
    data_lines = [line for line in path.read_text().splitlines() if not line.startswith("%")]
    assert [line.split()[:2] for line in data_lines] == [["2380", "604799.000000"], ["2381", "0.500000"]]
    back = read_rtklib_pos(path)
    assert back.gps_week == 2380
    np.testing.assert_allclose(back.time_s, gnss.time_s)


@PROPERTY
@given(t=times(), data=st.data())
def test_odometer_distance_round_trip(t, data, tmp_path):
    odo = OdometerData(time_s=t, distance_m=data.draw(finite(len(t), -1e6, 1e6)))
    path = tmp_path / "odo.txt"
    write_odometer_distance(path, odo)
    back = read_odometer_distance(path)
    assert_time(back.time_s, odo.time_s)
    np.testing.assert_allclose(back.distance_m, odo.distance_m, rtol=0, atol=1e-9)
    assert back.pulse_length_m is None


@PROPERTY
@given(t=times(), data=st.data())
def test_odometer_pulses_round_trip(t, data, tmp_path):
    pulse = data.draw(st.floats(1e-5, 1.0))
    counts = data.draw(hnp.arrays(np.int64, len(t), elements=st.integers(-10**9, 10**9)))
    odo = OdometerData(time_s=t, distance_m=counts * pulse, pulse_length_m=pulse)
    path = tmp_path / "odo.txt"
    write_odometer_pulses(path, odo)
    back = read_odometer_pulses(path)
    assert_time(back.time_s, odo.time_s)
    assert back.pulse_length_m == pulse
    np.testing.assert_array_equal(back.distance_m, odo.distance_m)


@PROPERTY
@given(t=times(), data=st.data())
def test_gauge_round_trip(t, data, tmp_path):
    gauge = GaugeData(time_s=t, gauge_m=data.draw(finite(len(t), 0.6, 1.8)))
    path = tmp_path / "gauge.txt"
    write_gauge_mm(path, gauge)
    back = read_gauge_mm(path)
    assert_time(back.time_s, gauge.time_s)
    np.testing.assert_allclose(back.gauge_m, gauge.gauge_m, rtol=0, atol=1e-9)


@PROPERTY
@given(t=times())
def test_sleeper_times_round_trip(t, tmp_path):
    path = tmp_path / "sleepers.txt"
    write_sleeper_times(path, SleeperPulses(time_s=t))
    assert_time(read_sleeper_times(path).time_s, t)


POINT_IDS = st.text(alphabet="ABCDEFGHJKLMNPQRSTUVWXYZ0123456789-_.", min_size=1, max_size=10)


@PROPERTY
@given(t=times(), data=st.data())
def test_prism_round_trip(t, data, tmp_path):
    n = len(t)
    ids = data.draw(st.lists(POINT_IDS | st.just(""), min_size=n, max_size=n))
    prism = PrismObservations(time_s=t, east_m=data.draw(finite(n, -1e6, 1e7)),
                              north_m=data.draw(finite(n, -1e6, 1e7)), height_m=data.draw(finite(n, -500, 5000)),
                              sigma_m=data.draw(finite(n, 0, 1)), point_id=np.array(ids, dtype=str))
    path = tmp_path / "prism.txt"
    write_prism_enu(path, prism)
    back = read_prism_enu(path)
    assert_time(back.time_s, prism.time_s)
    for field in ("east_m", "north_m", "height_m", "sigma_m"):
        np.testing.assert_allclose(getattr(back, field), getattr(prism, field), rtol=0, atol=1e-6)
    assert list(back.point_id) == ids


@PROPERTY
@given(data=st.data())
def test_benchmarks_round_trip(data, tmp_path):
    ids = data.draw(st.lists(POINT_IDS, min_size=1, max_size=20, unique=True))
    n = len(ids)
    marks = Benchmarks(point_id=tuple(ids), lat_rad=data.draw(finite(n, -90, 90)) * DEG,
                       lon_rad=data.draw(finite(n, -180, 180)) * DEG, h_m=data.draw(finite(n, -100, 5000)),
                       normal_height_m=data.draw(finite(n, -100, 5000)))
    path = tmp_path / "bm.txt"
    write_benchmarks(path, marks)
    back = read_any(path)
    assert isinstance(back, Benchmarks) and back.point_id == marks.point_id
    np.testing.assert_allclose(back.lat_rad, marks.lat_rad, rtol=0, atol=1e-11 * DEG)
    np.testing.assert_allclose(back.height_anomaly_m, marks.height_anomaly_m, rtol=0, atol=2e-6)


def test_writer_refuses_ids_it_cannot_write(tmp_path):
    marks = Benchmarks(point_id=("BM 1",), lat_rad=np.zeros(1), lon_rad=np.zeros(1), h_m=np.zeros(1),
                       normal_height_m=np.zeros(1))
    with pytest.raises(ValueError, match="whitespace"):
        write_benchmarks(tmp_path / "bm.txt", marks)
    assert not (tmp_path / "bm.txt").exists()


def test_benchmarks_csv_with_header(tmp_path):
    path = tmp_path / "bm.csv"
    path.write_text("id,lat,lon,h,H\nBM1, 30.5, 114.25, 25.3, 36.1\nBM2,30.6,114.3,26.0,36.7\n")
    marks = read_benchmarks(path)
    assert marks.point_id == ("BM1", "BM2")
    np.testing.assert_allclose(marks.height_anomaly_m, [-10.8, -10.7])
    dup = tmp_path / "dup.csv"
    dup.write_text("BM1,30.5,114.25,25.3,36.1\nBM1,30.6,114.3,26.0,36.7\n")
    with pytest.raises(Exception, match="appears twice"):
        read_benchmarks(dup)
