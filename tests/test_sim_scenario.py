"""Speed profile, irregularities, presets, reproducibility and the CLI of the simulator."""

from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from insrail.cli.main import main
from insrail.sim.irregularity import Bump, random_irregularity
from insrail.sim.motion import walking_profile
from insrail.sim.scenario import preset
from insrail.sim.simulate import simulate


@settings(max_examples=40, deadline=None)
@given(
    seed=st.integers(0, 2**31),
    length=st.floats(50.0, 3000.0),
    speed=st.floats(0.5, 2.0),
    stops=st.lists(st.floats(0.05, 0.95), max_size=4, unique=True),
)
def test_walking_profile_reaches_every_stop_smoothly(seed, length, speed, stops):
    stop_stations = tuple(sorted((100.0 + f * length, 10.0) for f in stops))
    if any(b[0] - a[0] < 20.0 for a, b in zip(stop_stations, stop_stations[1:])):
        return  # stops closer than a ramp are not a walking survey
    p = walking_profile(np.random.default_rng(seed), 1000.0, 100.0, 100.0 + length + 30.0, speed, 0.15, 45.0, 6.0, 60.0, 20.0, stop_stations)
    t = np.linspace(p.start_time_s[0], p.end_time_s, 50_001)
    s, v, a = p.evaluate(t)
    assert s[0] == pytest.approx(100.0) and s[-1] == pytest.approx(100.0 + length + 30.0, abs=1e-6)
    assert np.all(v >= -1e-12) and v.max() < 1.16 * speed + 1e-9
    assert np.all(np.diff(s) >= -1e-9)
    # the samples see a stop up to one sample interval late and leave it up to one early
    resolution = 2.0 * (t[1] - t[0])
    for station, duration in stop_stations:
        at_stop = (v == 0.0) & (np.abs(s - station) < 1e-6)
        assert (t[at_stop][-1] - t[at_stop][0]) == pytest.approx(duration, abs=max(0.2, resolution))
    # Speed and acceleration are continuous across every piece boundary.
    edges = p.start_time_s[1:]
    for eps in (1e-7,):
        _, v0, a0 = p.evaluate(edges - eps)
        _, v1, a1 = p.evaluate(edges + eps)
        assert np.abs(v1 - v0).max() < 1e-6 and np.abs(a1 - a0).max() < 1e-5


def test_random_irregularity_has_requested_rms_and_band():
    irr = random_irregularity(np.random.default_rng(2), 1e-3, 3.0, 70.0)
    s = np.arange(0.0, 20000.0, 0.25)
    y = irr.evaluate(s)
    assert np.std(y) == pytest.approx(1e-3, rel=0.1)
    spectrum = np.abs(np.fft.rfft(y)) ** 2
    wavelength = 1.0 / np.maximum(np.fft.rfftfreq(len(s), 0.25), 1e-12)
    in_band = (wavelength >= 2.9) & (wavelength <= 72.0)
    assert spectrum[in_band].sum() / spectrum[1:].sum() > 0.99


def test_bump_is_smooth_and_local():
    irr = random_irregularity(np.random.default_rng(0), 0.0, bumps=(Bump(100.0, 8.0, 3e-3),))
    s = np.array([99.9, 100.0, 104.0, 108.0, 108.1])
    assert irr.evaluate(s) == pytest.approx([0.0, 0.0, 3e-3, 0.0, 0.0], abs=1e-15)
    fine = np.linspace(99.0, 109.0, 100_001)
    second = np.diff(irr.evaluate(fine), 2) / (fine[1] - fine[0]) ** 2
    assert np.abs(np.diff(second)).max() < 1e-5  # curvature continuous: no kink at the ends


def test_unknown_preset_is_refused():
    with pytest.raises(ValueError, match="unknown scenario preset 'medium'"):
        preset("medium")


def _tiny(config):
    motion = replace(config.motion, end_station_m=config.motion.start_station_m + 40.0, stops=(), static_start_s=5.0, static_end_s=2.0)
    return replace(config, motion=motion, gnss=replace(config.gnss, outages=()))


def test_same_seed_same_survey_and_other_seed_differs(tmp_path):
    config = _tiny(preset("short"))
    a = simulate(config, 3, tmp_path / "a")
    b = simulate(config, 3, tmp_path / "b")
    c = simulate(config, 4, tmp_path / "c")
    for name in ("imu.txt", "gnss.pos", "odometer.txt", "gauge.txt", "sleepers.txt"):
        assert (a.folder / name).read_bytes() == (b.folder / name).read_bytes()
        assert (a.folder / name).read_bytes() != (c.folder / name).read_bytes()


def test_existing_folder_is_not_overwritten_and_a_failed_run_leaves_nothing(tmp_path):
    config = _tiny(preset("short"))
    target = tmp_path / "survey"
    target.mkdir()
    (target / "precious.txt").write_text("keep me")
    with pytest.raises(FileExistsError):
        simulate(config, 1, target)
    assert (target / "precious.txt").read_text() == "keep me"

    def cancel_after_start():
        cancel_after_start.calls += 1
        return cancel_after_start.calls > 2

    cancel_after_start.calls = 0
    from insrail.progress import Cancelled

    with pytest.raises(Cancelled):
        simulate(config, 1, tmp_path / "cancelled", cancel=cancel_after_start)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["survey"]


def test_cli_version_and_simulate(tmp_path, capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(["--version"])
    assert exit_info.value.code == 0
    assert "insrail 0.1.0" in capsys.readouterr().out
    assert main(["simulate", "--preset", "short", "--grade", "perfect", "--seed", "2", "--out", str(tmp_path / "s"), "--imu-format", "npy"]) == 0
    out = capsys.readouterr().out
    assert "Survey folder:" in out and "imu.npy" in out
    assert (tmp_path / "s" / "survey.toml").is_file() and (tmp_path / "s" / "truth" / "nav.npy").is_file()
    # A second run into the same folder needs --force.
    assert main(["simulate", "--preset", "short", "--out", str(tmp_path / "s")]) == 1


def test_prism_fixes_at_the_run_ends_are_taken_during_the_static_start_and_end(tmp_path):
    """The `tunnel-no-gnss` preset starts and ends at a fix: those come from the static start and end."""
    from insrail.io.control import read_prism_enu

    config = preset("tunnel-no-gnss")
    assert config.prism.stations_m[0] == config.motion.start_station_m
    assert config.prism.stations_m[-1] == config.motion.end_station_m
    tiny = _tiny(config)
    tiny = replace(tiny, motion=replace(tiny.motion, static_start_s=30.0, static_end_s=30.0),
                   prism=replace(config.prism, stations_m=(tiny.motion.start_station_m, tiny.motion.start_station_m + 20.0,
                                                           tiny.motion.end_station_m)))
    simulate(tiny, 1, tmp_path / "s", imu_format="npy")
    prism = read_prism_enu(tmp_path / "s" / "prism.txt")
    truth = np.load(tmp_path / "s" / "truth" / "nav.npy")
    station = np.interp(prism.time_s, truth["time_s"], truth["station_m"])
    assert len(prism) == 3 and prism.time_s[0] - truth["time_s"][0] == pytest.approx(10.0, abs=0.01)
    np.testing.assert_allclose(station - station[0], [0.0, 20.0, 40.0], atol=0.3)  # the reference point, not the prism
    assert truth["time_s"][-1] - prism.time_s[-1] > 15.0  # inside the 30 s static end


def test_a_reverse_run_writes_its_prism_fixes_in_time_order(tmp_path):
    """Against the stationing the trolley meets the highest station first: the prism file (time stamps must
    increase, docs/formats.md) lists that fix first, each fix where the trolley stood at its time."""
    from insrail.io.control import read_prism_enu

    tiny = _tiny(preset("short"))
    start = tiny.motion.start_station_m
    tiny = replace(tiny, motion=replace(tiny.motion, reverse=True),
                   prism=replace(tiny.prism, stations_m=(start + 10.0, start + 30.0), duration_s=5.0))
    simulate(tiny, 1, tmp_path / "s", imu_format="npy")
    prism = read_prism_enu(tmp_path / "s" / "prism.txt")  # refuses decreasing time stamps
    truth = np.load(tmp_path / "s" / "truth" / "nav.npy")
    np.testing.assert_allclose(np.interp(prism.time_s, truth["time_s"], truth["station_m"]),
                               [start + 30.0, start + 10.0], atol=0.3)
