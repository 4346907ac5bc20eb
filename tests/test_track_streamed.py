"""The track reconstruction by parts (insrail.track.streamed) gives the whole run's results to the bit,
in memory that does not grow with the survey's length."""

import os
import threading
from dataclasses import fields, replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from memory_support import peak_growth_bytes
from track_truth import truth_reconstruction

from insrail.geodesy.errors import GeodesyError
from insrail.io.track_sensors import read_sleeper_times
from insrail.io.types import GaugeData, Gap
from insrail.nav.trajectory import TRAJECTORY_DTYPE, Trajectory, load_trajectory, save_trajectory
from insrail.project.sleeper_parameters import sleeper_attitude_rad
from insrail.track import streamed
from insrail.track.rails import POSE_FIELDS
from insrail.track.reversed_design import reversed_design
from insrail.track.sleeper_table import reconstruct_track
from insrail.track.sleepers import SleeperAnchor
from insrail.track.by_parts import chunked_interp
from insrail.track.streamed import _MedianSign, _unwrapped, reconstruct_track_streamed


@pytest.fixture(autouse=True)
def small_parts(monkeypatch):
    """Chunks and bands shrunk to primes: the short surveys below span hundreds of them."""
    monkeypatch.setattr(streamed, "CHUNK_EPOCHS", 997)
    monkeypatch.setattr(streamed, "BAND_SLEEPERS", 37)


@pytest.fixture(scope="module")
def truth(short_perfect_survey):
    return truth_reconstruction(short_perfect_survey)


def _part(trajectory: Trajectory, rows) -> Trajectory:
    """The trajectory's epochs ``rows`` (times kept increasing)."""
    return replace(trajectory, **{name: np.asarray(getattr(trajectory, name))[rows] for name in TRAJECTORY_DTYPE.names})


def _both(tmp_path, truth, trajectory, gauge=None, pulses="file", **options):
    """(whole run, its attitude), (by parts, its attitude) of ``trajectory`` written to a file and read back."""
    path = tmp_path / "trajectory.npy"
    save_trajectory(path, trajectory)
    whole_trajectory = replace(load_trajectory(path, only=POSE_FIELDS), ellipsoid=truth.trajectory.ellipsoid)
    gauge = truth.gauge if gauge is None else gauge
    if pulses == "file":
        pulses = read_sleeper_times(truth.folder / "sleepers.txt")
    whole = reconstruct_track(whole_trajectory, truth.trolley, gauge, truth.to_engineering, pulses=pulses, **options)
    attitude = sleeper_attitude_rad(whole_trajectory.time_s, whole_trajectory.rpy_rad, whole.table.time_s)
    recon, parts_attitude = reconstruct_track_streamed(path, truth.trajectory.ellipsoid, truth.trolley, gauge,
                                                       truth.to_engineering, pulses=pulses, spool_folder=tmp_path,
                                                       epochs_file=tmp_path / "epochs.npy", **options)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["epochs.npy", "trajectory.npy"]  # the spool is gone
    assert recon.epochs.path == tmp_path / "epochs.npy"
    _assert_same_track(whole.epochs.station_track(), recon.epochs.station_track(size=997))
    return (whole, attitude), (replace(recon, epochs=recon.epochs.load()), parts_attitude)


def _assert_same_track(whole, parts):
    """Two StationTracks (events are placed on them): the same ends and interpolations both ways."""
    for name in ("first_time_s", "last_time_s", "low_station_m", "high_station_m", "against"):
        assert getattr(whole, name) == getattr(parts, name), name
    times = np.linspace(whole.first_time_s - 1.0, whole.last_time_s + 1.0, 1001)
    stations = np.linspace(whole.low_station_m - 1.0, whole.high_station_m + 1.0, 1001)
    np.testing.assert_array_equal(whole.station_at(times), parts.station_at(times))
    np.testing.assert_array_equal(whole.time_at(stations), parts.time_at(stations))


def _assert_same(whole, parts):
    (recon, attitude), (streamed_recon, streamed_attitude) = whole, parts
    for name in ("sleepers", "table", "epochs"):
        a, b = getattr(recon, name), getattr(streamed_recon, name)
        for field in fields(a):
            x, y = getattr(a, field.name), getattr(b, field.name)
            if isinstance(x, np.ndarray):
                assert np.array_equal(x, y, equal_nan=x.dtype.kind == "f"), f"{name}.{field.name}"
            else:
                assert x == y, f"{name}.{field.name}"
    np.testing.assert_array_equal(attitude, streamed_attitude)
    assert recon.line_fit_error == streamed_recon.line_fit_error
    assert (recon.fitted is None) == (streamed_recon.fitted is None)
    if recon.fitted is not None:
        assert recon.fitted.report() == streamed_recon.fitted.report()


def _stretch(truth, first_s=330.0, seconds=120.0):
    t = truth.trajectory.time_s
    return np.flatnonzero((t >= t[0] + first_s) & (t < t[0] + first_s + seconds))


def test_on_the_design_with_pulses(tmp_path, truth):
    whole, parts = _both(tmp_path, truth, _part(truth.trajectory, _stretch(truth)), design=truth.design)
    assert len(whole[0].table) > 100 and whole[0].table.valid.mean() > 0.9
    _assert_same(whole, parts)


@pytest.mark.parametrize("pulses", [None, "file"], ids=["regular grid", "pulses"])
def test_on_a_design_stationed_against_the_travel(tmp_path, truth, pulses):
    whole, parts = _both(tmp_path, truth, _part(truth.trajectory, _stretch(truth)), pulses=pulses,
                         design=reversed_design(truth.design))
    assert np.all(np.diff(whole[0].table.time_s) < 0)  # against the travel
    _assert_same(whole, parts)



@pytest.mark.parametrize("on_design", [True, False], ids=["on the design", "without a design"])
def test_the_spool_holds_each_column_once_and_only_what_is_read_again(tmp_path, truth, monkeypatch, on_design):
    """Every part's column is written once: the centreline's stations (in the epochs' file) never, nor
    on the design the forward axis (the stations are the projections') or the reference rail's
    stations again in pass B (pass A's)."""
    written = []
    write = streamed._Spool.write
    monkeypatch.setattr(streamed._Spool, "write",
                        lambda spool, name, start, values: (written.append((name, start)), write(spool, name, start, values)))
    options = {"design": truth.design} if on_design else {"start_station_m": 1000.0}
    whole, parts = _both(tmp_path, truth, _part(truth.trajectory, _stretch(truth)), **options)
    _assert_same(whole, parts)
    assert len(written) == len(set(written))
    names = {name for name, _ in written}
    assert "centre_station" not in names and ("forward" in names) is not on_design
    assert {"time", "left", "right", "reference_station", "left_station", "right_station"} <= names


def test_the_trolley_facing_backwards_with_anchor_numbering(tmp_path, truth):
    trajectory = _part(truth.trajectory, _stretch(truth))
    rpy = trajectory.rpy_rad.copy()
    rpy[:, 0], rpy[:, 1], rpy[:, 2] = -rpy[:, 0], -rpy[:, 1], np.mod(rpy[:, 2] + np.pi, 2 * np.pi)
    trajectory = replace(trajectory, rpy_rad=rpy)
    # the anchor: a sleeper of the plain numbering (from 1), numbered 500
    station = reconstruct_track(replace(trajectory, ellipsoid=truth.trajectory.ellipsoid), truth.trolley,
                                truth.gauge, truth.to_engineering, design=truth.design,
                                pulses=read_sleeper_times(truth.folder / "sleepers.txt")).sleepers.station_m[40]
    whole, parts = _both(tmp_path, truth, trajectory, design=truth.design,
                         anchor=SleeperAnchor(number=500, station_m=float(station)))
    assert whole[0].sleepers.number[40] == 500 and whole[0].rails.reference_rail != truth.trolley.reference_rail
    _assert_same(whole, parts)


def test_without_a_design_fitted_line_and_a_gauge_gap(tmp_path, truth):
    t = truth.trajectory.time_s[_stretch(truth, first_s=300.0, seconds=2000.0)]
    middle = 0.5 * (t[0] + t[-1])
    gauge = replace(truth.gauge, gaps=(Gap(middle, middle + 8.0),))  # ~10 m, far wider than half a window
    whole, parts = _both(tmp_path, truth, _part(truth.trajectory, _stretch(truth, first_s=300.0, seconds=2000.0)), gauge=gauge,
                         start_station_m=1000.0)
    assert whole[0].fitted is not None and np.isnan(whole[0].table.gauge_m).any() is np.False_
    _assert_same(whole, parts)


def test_without_a_design_against_a_stationing_azimuth_on_a_grid(tmp_path, truth):
    whole, parts = _both(tmp_path, truth, _part(truth.trajectory, _stretch(truth, seconds=60.0)), pulses=None,
                         start_station_m=0.0, stationing=180.0 + np.degrees(truth.trajectory.rpy_rad[0, 2]),
                         fit_line=False)
    assert whole[0].table.station_m[0] < -50.0  # stations fall as the trolley runs
    _assert_same(whole, parts)


def test_a_reversal_across_chunk_edges(tmp_path, truth):
    rows = _stretch(truth, seconds=40.0)
    back = rows[::-1][: len(rows) // 2]  # the trolley pushed back over half the stretch
    trajectory = _part(truth.trajectory, np.concatenate([rows, back]))
    dt = np.diff(truth.trajectory.time_s[rows[:2]])[0]
    trajectory = replace(trajectory, time_s=trajectory.time_s[0] + dt * np.arange(len(trajectory)))
    gauge = GaugeData(trajectory.time_s, np.full(len(trajectory), 1.435))
    for options in ({"design": truth.design}, {"start_station_m": 500.0}):
        _assert_same(*_both(tmp_path, truth, trajectory, gauge=gauge, pulses=None, **options))


def test_a_long_stop_spanning_many_chunks(tmp_path, truth):
    rows = _stretch(truth, seconds=30.0)
    stop = np.full(30_000, rows[len(rows) // 2])  # 150 s standing at one place: 30 chunks of 997 epochs
    trajectory = _part(truth.trajectory, np.concatenate([rows[: len(rows) // 2], stop, rows[len(rows) // 2 + 1:]]))
    dt = np.diff(truth.trajectory.time_s[rows[:2]])[0]
    trajectory = replace(trajectory, time_s=trajectory.time_s[0] + dt * np.arange(len(trajectory)))
    gauge = GaugeData(trajectory.time_s, 1.435 + 1e-4 * np.sin(np.arange(len(trajectory)) * 0.01))
    _assert_same(*_both(tmp_path, truth, trajectory, gauge=gauge, pulses=None, design=truth.design))


def test_memory_does_not_grow_with_the_length(tmp_path, truth):
    rows = _stretch(truth, 330.0, 300.0)
    for epochs in (20_000, 40_000):
        save_trajectory(tmp_path / f"{epochs}.npy", _part(truth.trajectory, rows[:epochs]))

    def run(epochs: int):
        return reconstruct_track_streamed(tmp_path / f"{epochs}.npy", truth.trajectory.ellipsoid, truth.trolley,
                                          truth.gauge, truth.to_engineering, design=truth.design, pulses=None,
                                          spool_folder=tmp_path, epochs_file=tmp_path / "epochs.npy")

    short, long = peak_growth_bytes(run, 20_000)
    sleepers = len(run(40_000)[0].table) - len(run(20_000)[0].table)
    assert long - short <= 2_000 * sleepers + 64_000, (short, long, sleepers)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.sampled_from([0.0, 1.0, 1.0, 2.5, 3.0]), min_size=1, max_size=60),
       st.lists(st.floats(-1.0, 5.0), min_size=1, max_size=30), st.integers(1, 7))
def test_chunked_interp_is_np_interp(steps, queries, size):
    xp = np.cumsum(steps)  # plateaus, also across the blocks' edges
    fp = np.sin(np.arange(len(xp)) * 1.7)
    x = np.array(queries + [np.nan, xp[0], xp[-1]])
    blocks = [(xp[k:k + size], fp[k:k + size]) for k in range(0, len(xp), size)]
    np.testing.assert_array_equal(chunked_interp(x, iter(blocks)), np.interp(x, xp, fp))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-20.0, 20.0), min_size=1, max_size=50), st.integers(1, 7))
def test_unwrap_by_parts_is_np_unwrap(angles, size):
    angle = np.array(angles)
    previous, carried, parts = None, 0.0, []
    for k in range(0, len(angle), size):
        part, carried = _unwrapped(previous, carried, angle[k:k + size])
        previous = angle[k + size - 1] if k + size <= len(angle) else angle[-1]
        parts.append(part)
    np.testing.assert_array_equal(np.concatenate(parts), np.unwrap(angle))


@settings(max_examples=100, deadline=None)
@given(st.lists(st.sampled_from([-1.0, -0.5, -0.0, 0.0, 0.25, 0.5, 1.0]), min_size=1, max_size=12),
       st.integers(1, 5))
def test_median_sign_by_parts(values, size):
    values = np.array(values)
    sign = _MedianSign()
    for k in range(0, len(values), size):
        sign.add(values[k:k + size])
    assert sign.non_negative() == bool(np.median(values) >= 0.0)


def test_a_cancel_leaves_no_spool_and_no_epochs_file(tmp_path, truth):
    path = tmp_path / "trajectory.npy"
    save_trajectory(path, _part(truth.trajectory, _stretch(truth, seconds=30.0)))
    calls = []

    def cancel_at_the_tenth_part():
        calls.append(1)
        if len(calls) == 10:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        reconstruct_track_streamed(path, truth.trajectory.ellipsoid, truth.trolley, truth.gauge,
                                   truth.to_engineering, design=truth.design, spool_folder=tmp_path,
                                   epochs_file=tmp_path / "epochs.npy", check=cancel_at_the_tenth_part)
    assert [p.name for p in tmp_path.iterdir()] == ["trajectory.npy"]
    assert not any(thread.name.startswith("rails") for thread in threading.enumerate())  # none left making parts


@pytest.mark.parametrize("cpus", [1, 2], ids=["one CPU: serial", "two CPUs: threads"])
def test_the_rails_made_by_threads_or_one_at_a_time_are_the_same(tmp_path, truth, cpus, monkeypatch):
    monkeypatch.setattr(os, "cpu_count", lambda: cpus)
    made_in = set()

    class NotingTheThread:  # the truth, its conversion noting the thread it runs in
        def __getattr__(self, name):
            return getattr(truth, name)

        def to_engineering(self, lat, lon, h):
            made_in.add(threading.current_thread() is threading.main_thread())
            return truth.to_engineering(lat, lon, h)

    whole, parts = _both(tmp_path, NotingTheThread(), _part(truth.trajectory, _stretch(truth, seconds=60.0)),
                         design=truth.design)
    _assert_same(whole, parts)
    assert made_in == ({True} if cpus == 1 else {True, False})  # the whole run's in the caller's thread


def test_a_failure_in_a_thread_making_rails_propagates_with_its_message(tmp_path, truth, monkeypatch):
    monkeypatch.setattr(os, "cpu_count", lambda: 2)
    path = tmp_path / "trajectory.npy"
    save_trajectory(path, _part(truth.trajectory, _stretch(truth, seconds=30.0)))
    calls = []

    def failing_on_the_fifth_part(lat, lon, h):
        calls.append(1)
        if len(calls) == 5 * 3:  # three conversions per part
            raise GeodesyError("3 point(s) lie up to 9.00° from the central meridian 114.3°")
        return truth.to_engineering(lat, lon, h)

    with pytest.raises(GeodesyError, match=r"3 point\(s\) lie up to 9.00° from the central meridian"):
        reconstruct_track_streamed(path, truth.trajectory.ellipsoid, truth.trolley, truth.gauge, failing_on_the_fifth_part,
                                   design=truth.design, spool_folder=tmp_path, epochs_file=tmp_path / "epochs.npy")
    assert [p.name for p in tmp_path.iterdir()] == ["trajectory.npy"]
    assert not any(thread.name.startswith("rails") for thread in threading.enumerate())


@pytest.mark.parametrize("cpus", [1, 2], ids=["one CPU: one band after the other", "two CPUs: two bands at once"])
def test_the_bands_fitted_by_threads_or_one_at_a_time_are_the_same(tmp_path, truth, cpus, monkeypatch):
    monkeypatch.setattr(os, "cpu_count", lambda: cpus)
    fitted_in = set()
    fit = streamed.sliding_window_fit

    def noting_the_thread(*args, **kwargs):
        fitted_in.add(threading.current_thread().name.split("_")[0])
        return fit(*args, **kwargs)

    monkeypatch.setattr(streamed, "sliding_window_fit", noting_the_thread)
    whole, parts = _both(tmp_path, truth, _part(truth.trajectory, _stretch(truth, seconds=60.0)), design=truth.design)
    _assert_same(whole, parts)
    assert fitted_in == ({"MainThread"} if cpus == 1 else {"bands"})


def test_a_cancel_among_the_bands_leaves_no_thread_and_no_spool(tmp_path, truth, monkeypatch):
    monkeypatch.setattr(os, "cpu_count", lambda: 2)
    path = tmp_path / "trajectory.npy"
    save_trajectory(path, _part(truth.trajectory, _stretch(truth, seconds=120.0)))
    fits = []
    fit = streamed.sliding_window_fit
    monkeypatch.setattr(streamed, "sliding_window_fit", lambda *args, **kwargs: fits.append(1) or fit(*args, **kwargs))

    def cancel_among_the_bands():
        if len(fits) >= 2:  # a band fitted (both rails): at the latest at the fourth band's check
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        reconstruct_track_streamed(path, truth.trajectory.ellipsoid, truth.trolley, truth.gauge,
                                   truth.to_engineering, design=truth.design, spool_folder=tmp_path,
                                   epochs_file=tmp_path / "epochs.npy", check=cancel_among_the_bands)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["epochs.npy", "trajectory.npy"]  # the spool is gone (the
    # epochs' file, complete before the bands, is the caller's to seal or leave unsealed)
    assert not any(thread.name.startswith("bands") for thread in threading.enumerate())
