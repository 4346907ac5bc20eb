"""Faults around the results and the cache, end to end on a tiny simulated survey: a damaged cache
entry is recomputed with a notice, results never share a file with the cache, a crash in the
results swap leaves the previous results readable, leftovers of killed runs are cleaned."""

from __future__ import annotations

import dataclasses
import errno
import fcntl
import io
import os
import shutil
import subprocess
import sys
import threading
import time
import tomllib
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from insrail.cli.main import describe_os_error, main
from insrail.io import atomic
from insrail.io.errors import InputError
from insrail.project import load_project, pipeline, process
from insrail.project import results as results_module
from insrail.project.demo import project_for_simulated_survey
from insrail.project.lock import cache_entry, project_run
from insrail.project.pipeline import fusion_key
from insrail.project.results import load_results
from insrail.sim.scenario import GnssSpec, preset
from insrail.sim.simulate import simulate

SURVEY = "tiny"


def tiny_scenario():
    short = preset("short")
    return replace(short, name=SURVEY,
                   motion=replace(short.motion, start_station_m=1100.0, end_station_m=1250.0, stops=(),
                                  static_start_s=60.0, static_end_s=10.0),
                   gnss=GnssSpec())


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    """A one-survey project processed once (the clean run the faults are compared with)."""
    root = tmp_path_factory.mktemp("robust") / "clean"
    simulate(tiny_scenario(), 1, root / "surveys" / SURVEY, imu_format="npy")
    project = project_for_simulated_survey(root, root / "surveys" / SURVEY, name="tiny")
    process(project, SURVEY)
    return root


def copy_of(tiny: Path, tmp_path: Path) -> Path:
    target = tmp_path / "project"
    shutil.copytree(tiny, target)
    return target


def cache_of(project: Path) -> Path:
    return project / "results" / ".cache"


def results_of(project: Path) -> Path:
    return project / "results" / SURVEY


def notices(project: Path) -> list[dict]:
    return tomllib.loads((results_of(project) / "summary.toml").read_text())["notices"]


def said_of_the_input(project: Path) -> list[dict]:
    """The notices but the one a clean survey this short always has: its 150 m lag's stated 1-sigma (a
    survey of about 150 m holds one or no such lag) cannot resolve the 300 m/150 m check's 10 mm limit
    (insrail.project.assessable), whatever its input."""
    return [n for n in notices(project)
            if not (n["stage"] == "assessment" and n["message"].startswith("long_wave_300m_150m"))]


def assert_same_results(project: Path, reference: Path) -> None:
    """The same sleepers and exceedances (to the last printed digit: a recomputed stage may round
    a micrometre differently)."""
    ours, theirs = load_results(project, SURVEY), load_results(reference, SURVEY)
    assert ours.number.tolist() == theirs.number.tolist()
    for column, values in theirs.columns.items():
        np.testing.assert_allclose(ours.columns[column], values, rtol=0, atol=1.5e-3, err_msg=column)
    assert [(e.check, e.first_sleeper, e.last_sleeper) for e in ours.exceedances] == [
        (e.check, e.first_sleeper, e.last_sleeper) for e in theirs.exceedances]


def test_results_are_copies_not_links_into_the_cache(tiny, tmp_path):
    project = copy_of(tiny, tmp_path)
    process(load_project(project), SURVEY)
    (cached,) = cache_of(project).glob("fusion-*.npy")
    result = results_of(project) / "trajectory.npy"
    assert os.stat(result).st_ino != os.stat(cached).st_ino and os.stat(cached).st_nlink == 1
    records = np.load(result)
    records["height_m"] += 1.0  # a user edits the result file in place
    with open(result, "r+b") as handle:
        np.save(handle, records)
    again = process(load_project(project), SURVEY)
    assert again.fusion_from_cache
    heights = np.load(results_of(project) / "trajectory.npy")["height_m"]
    assert np.array_equal(heights, np.load(results_of(tiny) / "trajectory.npy")["height_m"])


def _truncate(path: Path) -> None:
    path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])


def _empty(path: Path) -> None:
    path.write_bytes(b"")


def _flip(path: Path) -> None:
    data = bytearray(path.read_bytes())
    data[len(data) * 2 // 3] ^= 0x10
    path.write_bytes(bytes(data))


@pytest.mark.parametrize(("pattern", "damage"), [
    ("fusion-*[0-9a-f].npy", _truncate), ("fusion-*[0-9a-f].npy", _flip), ("fusion-*[0-9a-f].toml", _empty),
    ("fusion-*.quality.npz", _flip), ("track-*[0-9a-f].npz", _truncate), ("adjustment-*[0-9a-f].npz", _empty),
    ("adjustment-*[0-9a-f].npz", _flip)])
def test_a_damaged_cache_entry_is_recomputed_with_a_notice(tiny, tmp_path, pattern, damage):
    project = copy_of(tiny, tmp_path)
    (entry,) = cache_of(project).glob(pattern)
    damage(entry)
    assert main(["process", str(project)]) == 0
    (notice,) = [n for n in notices(project) if n["stage"] == "cache"]
    assert entry.name in notice["message"] and "recomputed" in notice["message"]
    assert_same_results(project, tiny)
    process(load_project(project), SURVEY)  # the recomputed entry is sealed: no notice the next time
    assert not [n for n in notices(project) if n["stage"] == "cache"]


def test_a_crash_between_the_renames_leaves_the_previous_results_readable(tiny, tmp_path, monkeypatch, capsys):
    project = copy_of(tiny, tmp_path)
    before = (results_of(project) / "sleepers.csv").read_bytes()
    monkeypatch.setattr(results_module, "_exchange", lambda a, b: False)  # a system without an atomic exchange
    real_replace = os.replace

    def crash_on_the_second_rename(source, target):
        if Path(source).name.endswith(".new"):
            raise KeyboardInterrupt("killed between the renames")
        real_replace(source, target)

    monkeypatch.setattr(results_module.os, "replace", crash_on_the_second_rename)
    with pytest.raises(KeyboardInterrupt):
        process(load_project(project), SURVEY)
    monkeypatch.undo()
    assert not results_of(project).exists()  # the window the old code had
    assert load_results(project, SURVEY).summary["survey"]  # the previous results, put back by the reader
    assert (results_of(project) / "sleepers.csv").read_bytes() == before
    assert main(["report", str(project), "--xlsx", str(tmp_path / "r.xlsx"), "--pdf", str(tmp_path / "r.pdf")]) == 0


def test_the_swap_exchanges_the_folders_and_leaves_nothing_behind(tiny, tmp_path):
    project = copy_of(tiny, tmp_path)
    process(load_project(project), SURVEY)
    assert sorted(p.name for p in (project / "results").iterdir()) == [".cache", ".locks", SURVEY]


def test_leftovers_of_killed_runs_are_cleaned_by_the_next_run(tiny, tmp_path):
    project = copy_of(tiny, tmp_path)
    results = project / "results"
    leftovers = [results / f".{SURVEY}.abcd.new", results / f".{SURVEY}.old-12345",
                 cache_of(project) / ".rinex-xyz", cache_of(project) / ".track-spool-k2j4"]
    for folder in leftovers:
        folder.mkdir()
        (folder / "part").write_text("half")
    temporary = [cache_of(project) / ".fusion-1234.npy.abcd.tmp", results / ".repeatability.csv.x.tmp"]
    for file in temporary:
        file.write_text("half")  # a second old: no other run holds the project, so they are a killed run's
    process(load_project(project), SURVEY)
    assert not [p for p in [*leftovers, *temporary] if p.exists()]
    other_run = open(results / ".locks" / "project.lock", "rb")  # another run of the project going on
    fcntl.flock(other_run.fileno(), fcntl.LOCK_SH)
    young = cache_of(project) / ".track-5678.npz.efgh.tmp"
    young.write_text("being written")
    os.utime(young, (time.time() - 3600,) * 2)  # its writer slow, but alive
    process(load_project(project), SURVEY)
    assert young.exists()
    other_run.close()


# --------------------------------------------------------------------------- plausibility, end to end

def rewrite_numbers(path: Path, column: int, change) -> None:
    """Apply ``change`` to one whitespace-separated numeric column of a text file (comments kept)."""
    lines = []
    for line in path.read_text().splitlines():
        if line.startswith(("#", "%")) or not line.strip():
            lines.append(line)
            continue
        fields = line.split()
        fields[column] = repr(change(float(fields[column])))
        lines.append(" ".join(fields))
    path.write_text("\n".join(lines) + "\n")


def survey_folder(project: Path) -> Path:
    return project / "surveys" / SURVEY


def _swap_benchmark_heights(project: Path) -> None:
    path = survey_folder(project) / "benchmarks.txt"
    lines = [line if line.startswith("#") else " ".join([*line.split()[:3], line.split()[4], line.split()[3]])
             for line in path.read_text().splitlines()]
    path.write_text("\n".join(lines) + "\n")


def _edit_imu(project: Path, field: str, change) -> None:
    path = survey_folder(project) / "imu.npy"
    records = np.load(path)
    records[field] = change(records[field])
    np.save(path, records)


def _edit_manifest(old: str, new: str):
    def edit(project: Path) -> None:
        path = survey_folder(project) / "survey.toml"
        text = path.read_text()
        assert old in text
        path.write_text(text.replace(old, new))
    return edit


FAULTS = {
    "benchmarks with h and H swapped": (_swap_benchmark_heights, "benchmarks.txt", "h and H are swapped"),
    "GNSS in UTC read as GPST": (lambda p: rewrite_numbers(survey_folder(p) / "gnss.pos", 1, lambda t: t - 18.0),
                                 "gnss.pos", "GNSS times in UTC read as GPST"),
    "odometer distance in mm": (lambda p: rewrite_numbers(survey_folder(p) / "odometer.txt", 1, lambda d: 1e3 * d),
                                "odometer.txt", "a distance in millimetres"),
    "gauge x10": (lambda p: rewrite_numbers(survey_folder(p) / "gauge.txt", 1, lambda g: 10 * g),
                  "gauge.txt", "median gauge 14"),
    "lever arms in mm": (_edit_manifest("imu_to_antenna_m = [\n    0.02,\n    0.18,\n    -1.35,\n]",
                                        "imu_to_antenna_m = [20.0, 180.0, -1350.0]"),
                         "survey.toml", "trolley.imu_to_antenna_m"),
    "rail_centre_spacing_m = 1500": (_edit_manifest("rail_centre_spacing_m = 1.5", "rail_centre_spacing_m = 1500"),
                                     "survey.toml", "millimetres given as metres"),
    "reversed odometer": (lambda p: rewrite_numbers(survey_folder(p) / "odometer.txt", 1, lambda d: -d),
                          "odometer.txt", "the odometer counts backwards"),
    "sleeper file shifted 137 s": (lambda p: rewrite_numbers(survey_folder(p) / "sleepers.txt", 0,
                                                             lambda t: t + 137.0),
                                   "sleepers.txt", "sleeper pulses lie one sleeper spacing"),
    "sleeper file of another day": (lambda p: rewrite_numbers(survey_folder(p) / "sleepers.txt", 0,
                                                              lambda t: t + 86400.0),
                                    "sleepers.txt", "a file of another day or run"),
    "odometer 1 s late": (lambda p: rewrite_numbers(survey_folder(p) / "odometer.txt", 0, lambda t: t + 1.0),
                          "odometer.txt", "time stamps run 1.0"),
    "odometer 2 s late": (lambda p: rewrite_numbers(survey_folder(p) / "odometer.txt", 0, lambda t: t + 2.0),
                          "odometer.txt", "time stamps run 2.0"),
    "sleeper detector 1 s late": (lambda p: rewrite_numbers(survey_folder(p) / "sleepers.txt", 0, lambda t: t + 1.0),
                                  "sleepers.txt", "time stamps run 1.0"),
    "IMU angle increments in degrees": (lambda p: _edit_imu(p, "dtheta_rad", np.degrees), "imu.npy",
                                        "angle increments look like degrees, not radians"),
    "IMU velocity increments in g": (lambda p: _edit_imu(p, "dvel_mps", lambda dv: dv / 9.80665), "imu.npy",
                                     "velocity increments look like velocity increments in g*s"),
}


@pytest.mark.parametrize("fault", FAULTS)
def test_an_implausible_input_is_refused_naming_the_file(tiny, tmp_path, capsys, fault):
    project = copy_of(tiny, tmp_path)
    before = (results_of(project) / "sleepers.csv").read_bytes()
    edit, file_name, cause = FAULTS[fault]
    edit(project)
    capsys.readouterr()
    assert main(["process", str(project)]) == 1
    error = capsys.readouterr().err
    assert file_name in error and cause in error, error
    assert "Traceback" not in error
    assert (results_of(project) / "sleepers.csv").read_bytes() == before  # the previous results stay


def test_an_odometer_clock_03_s_late_is_a_notice_naming_the_file_and_the_offset(tiny, tmp_path, capsys):
    project = copy_of(tiny, tmp_path)
    rewrite_numbers(survey_folder(project) / "odometer.txt", 0, lambda t: t + 0.3)
    capsys.readouterr()
    assert main(["process", str(project)]) == 0
    out = capsys.readouterr().out
    (notice,) = [n for n in notices(project) if n["stage"] == "time"]
    assert notice["file"].endswith("odometer.txt") and "time stamps run 0.3" in notice["message"]
    assert "late against the IMU's clock" in out and "time_offset_s = 0.3" in out


def test_the_clock_check_correlation_is_scipy_signals_bit_for_bit():
    """The odometer clock's cross-correlation is done without scipy.signal (it imports scipy.stats):
    the same numbers as scipy.signal.correlate(..., method="fft")."""
    from scipy.signal import correlate

    from insrail.project.clocks import _correlate_full

    rng = np.random.default_rng(11)
    for n, m in ((4999, 4999), (3001, 2000), (5, 7)):
        a, b = rng.normal(size=n), rng.normal(size=m)
        assert np.array_equal(_correlate_full(a, b), correlate(a, b, mode="full", method="fft"))


def test_a_clock_error_found_while_the_fusion_runs_stops_it_and_comes_first(tiny, tmp_path, monkeypatch):
    """The clocks are checked beside the other checks and the fusion's start (insrail.project.clocks.ClockCheck):
    a verdict reached once the fusion runs stops it, is raised as when the clocks were checked first, and leaves
    nothing in the cache."""
    from insrail.project import clocks

    class LateClock(ValueError):
        pass

    project = copy_of(tiny, tmp_path)
    for entry in cache_of(project).iterdir():  # fused again
        entry.unlink()
    fusing = threading.Event()

    def late_verdict(survey, labels):
        fusing.wait(120)
        raise LateClock("odometer.txt: its time stamps run 2.00 s late")

    from insrail.project import pipeline

    def fuse_and_say(*args, **kwargs):  # the fusion's start, not its progress: a short one says no step in time
        fusing.set()
        return fuse(*args, **kwargs)

    fuse = pipeline.fuse
    monkeypatch.setattr(pipeline, "fuse", fuse_and_say)
    monkeypatch.setattr(clocks, "check_clocks", late_verdict)
    with pytest.raises(LateClock, match="2.00 s late"):
        process(load_project(project), SURVEY)
    assert fusing.is_set()
    assert not any(entry.name.startswith(("fusion-", ".fusion-")) for entry in cache_of(project).iterdir())


def test_a_given_time_offset_is_applied_and_nothing_said(tiny, tmp_path):
    """A known latency written as time_offset_s, as a user writes it: the 1 s odometer is accepted and
    fused as the clean one (no filter reset, every sleeper valid)."""
    project = copy_of(tiny, tmp_path)
    rewrite_numbers(survey_folder(project) / "odometer.txt", 0, lambda t: t + 1.0)
    _edit_manifest('path = "odometer.txt"\n', 'path = "odometer.txt"\ntime_offset_s = 1.0\n')(project)
    assert main(["process", str(project)]) == 0
    assert said_of_the_input(project) == []
    assert_same_results(project, tiny)


def test_a_given_gauge_latency_is_applied(tiny, tmp_path):
    """The gauge's clock cannot be told from the survey (clocks.py: this survey's start moves the trolley 4 mm
    in 0.3 s and 50 mm in 1 s, over which the gauge changes by 0.01-0.02 mm against its 0.1 mm noise): a known
    latency is given, as a user writes it, and the gauge 1 s late is then read as the clean one."""
    project = copy_of(tiny, tmp_path)
    rewrite_numbers(survey_folder(project) / "gauge.txt", 0, lambda t: t + 1.0)
    _edit_manifest('path = "gauge.txt"\n', 'path = "gauge.txt"\ntime_offset_s = 1.0\n')(project)
    assert main(["process", str(project)]) == 0
    assert said_of_the_input(project) == []
    assert_same_results(project, tiny)


def test_a_gauge_outlier_is_removed_and_listed(tiny, tmp_path, capsys):
    project = copy_of(tiny, tmp_path)
    path = survey_folder(project) / "gauge.txt"
    lines = path.read_text().splitlines()
    row = next(i for i, line in enumerate(lines) if not line.startswith("#")) + 400
    time_s = lines[row].split()[0]
    lines[row] = f"{time_s} 99999.0"
    path.write_text("\n".join(lines) + "\n")
    assert main(["process", str(project)]) == 0
    out = capsys.readouterr().out
    assert "gauge.txt" in out and "99999.0 mm" in out and "removed as outliers" in out
    (notice,) = [n for n in notices(project) if n["stage"] == "gauge"]
    assert notice["file"].endswith("gauge.txt")
    ours = load_results(project, SURVEY)
    assert np.nanmax(ours.columns["gauge_mm"]) < 1450  # no 99999 mm reached a sleeper
    assert_same_results(project, tiny)


def test_on_a_clean_survey_the_checks_change_nothing_and_say_nothing(tiny, tmp_path, monkeypatch):
    from insrail.project import clocks, pipeline

    unchecked = copy_of(tiny, tmp_path / "unchecked")
    for entry in cache_of(unchecked).iterdir():  # fused again: the checks run on the raw files
        entry.unlink()
    monkeypatch.setattr(pipeline, "check_survey", lambda survey, nominal: (survey, []))
    monkeypatch.setattr(clocks, "check_clocks", lambda survey, labels: [])
    monkeypatch.setattr(pipeline, "check_trolley", lambda *args: None)
    monkeypatch.setattr(pipeline, "check_benchmarks", lambda *args: None)
    process(load_project(unchecked), SURVEY)
    monkeypatch.undo()
    checked = copy_of(tiny, tmp_path / "checked")
    for entry in cache_of(checked).iterdir():
        entry.unlink()
    process(load_project(checked), SURVEY)
    assert said_of_the_input(checked) == said_of_the_input(unchecked) == []
    for name in ("sleepers.csv", "exceedances.csv", "trajectory.npy", "quality.csv"):
        assert (results_of(checked) / name).read_bytes() == (results_of(unchecked) / name).read_bytes()


# --------------------------------------------------------------------------- faults of the machine and the command line

def _raise(error_number: int, text: str):
    def fail(*args, **kwargs):
        folder = kwargs.get("dir") or (args[2] if len(args) > 2 else None)
        raise OSError(error_number, text, str(folder))
    return fail


def test_a_read_only_project_is_named_and_its_results_kept(tiny, tmp_path, monkeypatch, capsys):
    import errno
    import tempfile

    project = copy_of(tiny, tmp_path)
    before = (results_of(project) / "sleepers.csv").read_bytes()
    monkeypatch.setattr(tempfile, "mkdtemp", _raise(errno.EROFS, "Read-only file system"))
    monkeypatch.setattr(tempfile, "mkstemp", _raise(errno.EROFS, "Read-only file system"))
    assert main(["process", str(project)]) == 1
    error = capsys.readouterr().err
    assert f"{project / 'results'}: Read-only file system (a read-only file system: work on a copy" in error
    assert "Traceback" not in error
    assert (results_of(project) / "sleepers.csv").read_bytes() == before


@pytest.mark.parametrize("full_from, named", [
    ("insrail-imu-", "the IMU record's temporary copy"),  # the first temporary file a fusion writes
    ("insrail-nav-", "the fusion's temporary file"),  # the forward pass's record at the IMU rate
])
def test_a_full_disk_in_the_fusions_temporary_file_is_named(tiny, tmp_path, monkeypatch, capsys, full_from, named):
    import errno

    from insrail.io import imu as imu_io
    from insrail.nav import fusion

    project = copy_of(tiny, tmp_path)
    before = (results_of(project) / "sleepers.csv").read_bytes()
    for entry in cache_of(project).iterdir():  # the fusion runs again
        entry.unlink()

    class FullDisk:
        def write(self, data):
            raise OSError(errno.ENOSPC, "No space left on device")

        def close(self):
            pass

        def __enter__(self):
            return self

        def __exit__(self, *exc):
            self.close()

    real = fusion.tempfile.TemporaryFile
    prefixes = ["insrail-imu-", "insrail-nav-"]
    full = set(prefixes[prefixes.index(full_from):])  # the disk fills at that file and stays full

    def temporary_file(**kwargs):
        return FullDisk() if kwargs.get("prefix") in full else real(**kwargs)

    monkeypatch.setattr(fusion.tempfile, "TemporaryFile", temporary_file)
    # the records in temporary files, as a survey's above RECORDS_IN_MEMORY_BYTES and MAPPED_ABOVE_BYTES (this
    # one's are held in memory)
    monkeypatch.setattr(fusion, "RECORDS_IN_MEMORY_BYTES", 0)
    monkeypatch.setattr(imu_io, "MAPPED_ABOVE_BYTES", 0)
    assert main(["process", str(project)]) == 1
    error = capsys.readouterr().err
    assert f"({named}): No space left on device (the disk is full" in error, error
    assert (results_of(project) / "sleepers.csv").read_bytes() == before
    assert not list(cache_of(project).glob("fusion-*"))  # nothing half-written taken for a cache entry


def test_a_full_disk_while_writing_the_results_keeps_the_previous_ones(tiny, tmp_path, monkeypatch, capsys):
    import errno

    project = copy_of(tiny, tmp_path)
    before = (results_of(project) / "sleepers.csv").read_bytes()
    def full(*args, **kwargs):  # as the system says it: no file name
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(results_module.shutil, "copyfile", full)
    monkeypatch.setattr(results_module.os, "link", full)  # not the previous results' copy linked: copied
    assert main(["process", str(project)]) == 1
    error = capsys.readouterr().err
    assert f"{results_of(project) / 'trajectory.npy'}: No space left on device (the disk is full" in error, error
    assert (results_of(project) / "sleepers.csv").read_bytes() == before
    assert sorted(p.name for p in (project / "results").iterdir()) == [".cache", ".locks", SURVEY]  # no staging left


def test_a_full_disk_in_the_track_reconstructions_spool_is_named(tiny, tmp_path, monkeypatch, capsys):
    project = copy_of(tiny, tmp_path)
    before = (results_of(project) / "sleepers.csv").read_bytes()
    for entry in cache_of(project).glob("track-*"):  # the track reconstructed again, from the cached fusion
        entry.unlink()
    real, filled = os.pwrite, []

    def pwrite(fd, data, offset):  # the spool's files fill the disk: a part of a write taken, then none
        if "/.track-spool-" not in os.readlink(f"/proc/self/fd/{fd}"):
            return real(fd, data, offset)
        if filled:
            raise OSError(errno.ENOSPC, "No space left on device")  # as the system says it: no file name
        filled.append(fd)
        return real(fd, memoryview(data)[:len(data) // 2], offset)

    monkeypatch.setattr(atomic.os, "pwrite", pwrite)
    assert main(["process", str(project)]) == 1
    error = capsys.readouterr().err
    assert f"insrail: {cache_of(project)}/.track-spool-" in error and ".f64: No space left on device (the disk is full" in error, error
    assert (results_of(project) / "sleepers.csv").read_bytes() == before
    assert not list(cache_of(project).glob(".track-spool-*")) and not list(cache_of(project).glob("track-*"))


class _RoomForAHeader(io.FileIO):
    """/dev/full behind a file object with room for an .npy header: the disk fills after it, for the
    file object's writes and for numpy's own (``ndarray.tofile`` writes to the descriptor, /dev/full's,
    and says only "N requested and 0 written")."""

    room = 4096

    def write(self, data):
        if len(data) > self.room:
            raise OSError(errno.ENOSPC, "No space left on device")  # as the system says it: no file name
        self.room -= len(data)
        return len(data)


def _disk_full_in(monkeypatch, name: str) -> None:
    """The atomic writes of the files called ``name`` fill the disk after their header."""
    real = os.fdopen

    def fdopen(fd, mode="r", *args, **kwargs):
        if not Path(os.readlink(f"/proc/self/fd/{fd}")).name.startswith(f".{name}."):  # atomic_write's temporary
            return real(fd, mode, *args, **kwargs)
        os.close(fd)
        return io.BufferedWriter(_RoomForAHeader("/dev/full", "w"))

    monkeypatch.setattr(atomic.os, "fdopen", fdopen)


@pytest.mark.parametrize("name", ["imu.npy", "nav.npy"])  # the raw IMU record; the truth at the IMU rate
def test_a_full_disk_while_simulating_names_the_npy_file_and_keeps_the_previous_survey(tmp_path, monkeypatch, name):
    scenario = tiny_scenario()
    scenario = replace(scenario, motion=replace(scenario.motion, end_station_m=1120.0, static_start_s=5.0,
                                                static_end_s=2.0))
    survey = tmp_path / "survey"
    survey.mkdir()
    (survey / "survey.toml").write_text("# the survey simulated before\n")
    _disk_full_in(monkeypatch, name)
    with pytest.raises(OSError) as failed:
        simulate(scenario, 1, survey, imu_format="npy", overwrite=True)
    message = describe_os_error(failed.value)
    assert f"/{name}: No space left on device (the disk is full" in message and message.startswith(str(tmp_path)), message
    assert (survey / "survey.toml").read_text() == "# the survey simulated before\n"
    assert sorted(tmp_path.iterdir()) == [survey]  # no half-written survey left beside it


@dataclasses.dataclass
class _Times:
    time_s: np.ndarray


def _save_imu(path: Path, time_s: np.ndarray) -> None:
    from insrail.io.imu import write_imu_npy
    from insrail.io.types import ImuIncrements

    write_imu_npy(path, ImuIncrements(time_s, np.zeros((len(time_s), 3)), np.zeros((len(time_s), 3))))


def _save_stage(path: Path, time_s: np.ndarray) -> None:
    from insrail.project.stagecache import save_dataclass

    save_dataclass(path, _Times(time_s))


@pytest.mark.parametrize("name, save", [("imu.npy", _save_imu), ("track.npz", _save_stage)])  # np.save's; np.savez's
def test_a_full_disk_while_saving_arrays_names_the_file_and_keeps_the_previous_one(tmp_path, monkeypatch, name, save):
    path = tmp_path / name
    save(path, np.arange(10.0))
    _disk_full_in(monkeypatch, name)
    with pytest.raises(OSError) as failed:
        save(path, np.arange(100_000.0))
    assert describe_os_error(failed.value).startswith(f"{path}: No space left on device (the disk is full")
    with open(path, "rb") as handle:
        assert np.array_equal(np.load(handle)["time_s"], np.arange(10.0))
    assert [p.name for p in tmp_path.iterdir() if p.suffix != ".sha256"] == [name]  # no temporary left


@pytest.mark.parametrize(("arguments", "message"), [
    (["--speed", "-1"], "argument --speed: -1: expected more than 0"),
    (["--speed", "nan"], "argument --speed: nan: expected more than 0"),
    (["--length", "0"], "argument --length: 0: expected more than 0"),
    (["--imu", "nosuch"], "argument --imu: IMU profile not found: nosuch (shipped profiles: mems, mems_handheld, nav"),
])
def test_predict_refuses_bad_values_with_a_usage_message(arguments, message, capsys):
    with pytest.raises(SystemExit) as leave:
        main(["predict", *arguments])
    assert leave.value.code == 2
    error = capsys.readouterr().err
    assert message in error and "Traceback" not in error


def test_report_to_a_missing_folder_fails_before_building(tiny, tmp_path, monkeypatch, capsys):
    from insrail import report

    def never(*args, **kwargs):
        raise AssertionError("the report was built")

    monkeypatch.setattr(report, "write_workbook", never)
    monkeypatch.setattr(report, "write_pdf", never)
    assert main(["report", str(tiny), "--xlsx", "/nonexistent/x.xlsx"]) == 1
    assert "insrail: --xlsx /nonexistent/x.xlsx: the folder /nonexistent does not exist" in capsys.readouterr().err
    fifo = tmp_path / "report.pdf"
    os.mkfifo(fifo)
    assert main(["report", str(tiny), "--pdf", str(fifo)]) == 1  # a device or FIFO: refused before building too
    assert (f"insrail: --pdf {fifo}: a FIFO (named pipe), not a regular file: refused as an output (nothing written)"
            in capsys.readouterr().err)


def test_a_design_nested_100000_deep_is_an_error_not_a_recursion(tiny, tmp_path, capsys):
    project = copy_of(tiny, tmp_path)
    deep = project / "deep.xml"
    deep.write_text('<?xml version="1.0"?>\n<LandXML>\n' + "<a>" * 100_000 + "</a>" * 100_000 + "</LandXML>\n")
    text = (project / "project.toml").read_text()
    (project / "project.toml").write_text(text.replace('design = "surveys/tiny/truth/design.csv"', 'design = "deep.xml"'))
    assert 'design = "deep.xml"' in (project / "project.toml").read_text()
    assert main(["process", str(project)]) == 1
    error = capsys.readouterr().err
    assert "deep.xml, line 3: elements nested more than 200 deep" in error and "Recursion" not in error


def test_an_internal_error_is_one_line_without_a_traceback(tiny, tmp_path, monkeypatch, capsys):
    from insrail.project import pipeline

    def defect(*args, **kwargs):
        raise ZeroDivisionError("division by zero")

    monkeypatch.setattr(pipeline, "assess", defect)
    project = copy_of(tiny, tmp_path)
    assert main(["process", str(project)]) == 3
    error = capsys.readouterr().err
    assert "insrail: internal error: ZeroDivisionError: division by zero" in error and "Traceback" not in error


def test_a_nan_base_position_in_the_rinex_header_names_the_base_file(tmp_path):
    from insrail.gnss.rinex import read_obs_info

    from real_data import real_path

    text = (real_path("rinex_0759_3040") / "07590920.05o").read_text()
    lines = text.splitlines()
    row = next(i for i, line in enumerate(lines) if line[60:].strip() == "APPROX POSITION XYZ")
    lines[row] = f"{'nan':>14}{'nan':>14}{'nan':>14}{'':18}APPROX POSITION XYZ"
    (tmp_path / "base.obs").write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError, match=rf"base\.obs, line {row + 1}: APPROX POSITION XYZ: non-finite value"):
        read_obs_info(tmp_path / "base.obs")


# --------------------------------------------------------------------------- two runs of one project

def test_two_concurrent_runs_of_one_project_both_succeed_one_after_the_other(tiny, tmp_path, capsys):
    project = copy_of(tiny, tmp_path)
    shutil.rmtree(cache_of(project))  # the fusion computed again: each run writes the cache
    held, release = threading.Event(), threading.Event()

    def gui_run():  # as the GUI's worker thread processing the survey
        with project_run(project, [SURVEY]):
            held.set()
            release.wait(600)

    worker = threading.Thread(target=gui_run)
    worker.start()
    held.wait(60)
    try:
        assert main(["process", str(project), "--no-wait"]) == 1
        err = capsys.readouterr().err
        assert f"insrail: {project.resolve()}: survey {SURVEY} is in use by the run started at " in err
        assert f"by PID {os.getpid()}" in err and "not waiting (--no-wait)" in err
        logs = [tmp_path / f"run{i}.err" for i in range(2)]
        runs = [subprocess.Popen([sys.executable, "-m", "insrail", "process", str(project)], stdout=subprocess.DEVNULL,
                                 stderr=log.open("w")) for log in logs]
        deadline = time.monotonic() + 300
        while not all("insrail: waiting for the run started at " in log.read_text() for log in logs):
            assert time.monotonic() < deadline and all(run.poll() is None for run in runs)
            time.sleep(0.2)
    finally:
        release.set()  # both runs released together: one goes on, the other waits for it
        worker.join()
    assert [run.wait(600) for run in runs] == [0, 0], [log.read_text()[-2000:] for log in logs]
    assert_same_results(project, tiny)


@pytest.mark.parametrize("name, file_format, refusal", [
    ("imu.txt", "kfgins-imu", r"imu.txt, line 1: binary data \(a NUL byte\), not a text file"),
    ("imu.npy", "imu-npy", r"imu.npy: not a readable NumPy .npy file"),
])
def test_a_disk_image_named_as_the_imu_file_is_refused_before_it_is_hashed(tiny, tmp_path, name, file_format,
                                                                           refusal):
    """The cache key hashes the raw files before anything reads them: a 5 GB image is refused at
    its first block, not after hashing it all (57 s before)."""
    project = copy_of(tiny, tmp_path)
    survey = project / "surveys" / SURVEY
    (survey / "imu.npy").unlink()
    with open(survey / name, "wb") as handle:
        handle.truncate(5 << 30)  # sparse: no disk used
    manifest = survey / "survey.toml"
    manifest.write_text(manifest.read_text().replace('path = "imu.npy"\nformat = "imu-npy"',
                                                     f'path = "{name}"\nformat = "{file_format}"'))
    loaded = load_project(project)
    read = []
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(pipeline.hashlib, "sha256", lambda *a, _new=pipeline.hashlib.sha256: Counting(_new(*a), read))
        with pytest.raises(InputError, match=refusal):
            fusion_key(loaded, loaded.manifest(SURVEY), survey)
    assert sum(read) < 64 << 20  # of the 5 GiB


class Counting:
    """A hash that counts the bytes it is given."""

    def __init__(self, digest, counts: list[int]):
        self.digest, self.counts = digest, counts

    def update(self, data: bytes) -> None:
        self.counts.append(len(data))
        self.digest.update(data)

    def hexdigest(self) -> str:
        return self.digest.hexdigest()


def test_two_surveys_with_identical_data_run_at_once_compute_their_shared_fusion_once(tiny, tmp_path):
    """One survey copied under a second name (a batch of both): the same cache key, two survey
    locks; the second to look the fusion up waits for the first and reuses it instead of writing
    the same cache files at the same time."""
    project = copy_of(tiny, tmp_path)
    shutil.rmtree(project / "results")
    shutil.copytree(project / "surveys" / SURVEY, project / "surveys" / "twin")
    settings = project / "project.toml"
    settings.write_text('[[surveys]]\nname = "twin"\nfolder = "surveys/twin"\n\n' + settings.read_text())
    loaded = load_project(project)
    keys = {fusion_key(loaded, loaded.manifest(name), project / "surveys" / name) for name in (SURVEY, "twin")}
    assert len(keys) == 1
    logs = [tmp_path / f"{name}.err" for name in (SURVEY, "twin")]
    with project_run(project, []), cache_entry(project, f"fusion-{keys.pop()}"):  # as a third run computing it
        runs = [subprocess.Popen([sys.executable, "-m", "insrail", "process", str(project), "--survey", name],
                                 stdout=subprocess.PIPE, stderr=log.open("w"), text=True)
                for name, log in zip((SURVEY, "twin"), logs)]
        deadline = time.monotonic() + 300
        while not all("cache-fusion-" in log.read_text() for log in logs):  # both wait for the entry
            assert time.monotonic() < deadline and all(run.poll() is None for run in runs), \
                [log.read_text()[-2000:] for log in logs]
            time.sleep(0.2)
    outputs = [run.communicate(timeout=900)[0] for run in runs]
    assert [run.returncode for run in runs] == [0, 0], [log.read_text()[-2000:] for log in logs]
    assert sorted("fusion: computed" in out for out in outputs) == [False, True], outputs
    assert all("waiting for the run started at " in log.read_text() for log in logs)
    sleepers = [(project / "results" / name / "sleepers.csv").read_text() for name in (SURVEY, "twin")]
    assert sleepers[0] == sleepers[1]


# --------------------------------------------------------------------------- files outside the project

def test_a_data_file_outside_the_project_is_named_and_a_foreign_files_lines_are_not_echoed(tiny, tmp_path, capsys):
    project = copy_of(tiny, tmp_path)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    shutil.move(survey_folder(project) / "gauge.txt", elsewhere / "gauge.txt")
    _edit_manifest('path = "gauge.txt"', f'path = "{elsewhere / "gauge.txt"}"')(project)
    assert main(["process", str(project)]) == 0
    out = capsys.readouterr().out
    assert f"files.gauge: {elsewhere / 'gauge.txt'} lies outside the project and the survey folder" in out
    secret = elsewhere / "keys"
    secret.write_text("# someone's keys\nalice 30.4 AAAAC3NzaC1lZDI1NTE5AAAAIOMqqnkVzrm0SdG6UOoqKLsabgH5C1ok 14.0 26.5\n")
    _edit_manifest('path = "benchmarks.txt"', f'path = "{secret}"')(project)
    assert main(["process", str(project)]) == 1
    err = capsys.readouterr().err
    assert str(secret) in err and "line 2" in err and "characters of text (not shown)" in err
    assert "AAAAC3" not in err


def read_csv(path: Path) -> np.ndarray:
    return np.genfromtxt(path, delimiter=",", names=True, dtype=None, encoding="utf-8", missing_values="",
                         filling_values=np.nan)


@pytest.mark.parametrize("screened", [True, False], ids=["removed by the screening", "seen by the aiding only"])
def test_a_gyro_and_an_accelerometer_spike_below_the_envelope_leave_no_wrong_valid_sleeper(tiny, tmp_path, monkeypatch,
                                                                                            screened):
    """One IMU record 35 ms before a sleeper pulse, at speed, carries 3 mrad more roll (0.6 rad/s for
    5 ms, below the 50 deg/s envelope) and 0.07 m/s more vertical velocity (1.4 g, below 2 g). Before,
    the sleeper passed then was valid with 4.6 mm of cross-level error (the filter reset only made the
    time from the first rejected odometer update suspect). Now no valid sleeper is off the truth by
    more than 0.5 mm of cross-level, nor moved by more than 1 mm in a 30 m/5 m check (issue 33): the
    screening removes the record. Where it could not tell it from the motion (its test switched off
    here), the reset's suspect time begins at the odometer's last agreement, before the fault: the
    sleeper 35 ms after it is not valid, with the reset as its reason."""
    from insrail.nav import imu_screening
    from insrail.sim.truth import read_sleeper_truth

    if not screened:
        monkeypatch.setattr(imu_screening, "QUIET_SPIKE_SIGMAS", np.inf)
    project = copy_of(tiny, tmp_path)
    shutil.rmtree(project / "results")
    survey = project / "surveys" / SURVEY
    truth = read_sleeper_truth(survey / "truth" / "sleepers.csv")
    records = np.load(survey / "imu.npy")
    fault = int(np.searchsorted(records["time_s"], truth["pass_time"][20] - 0.035))
    records["dtheta_rad"][fault, 0] += 3e-3
    records["dvel_mps"][fault, 2] += 0.07
    np.save(survey / "imu.npy", records)
    assert main(["process", str(project)]) == 0
    sleepers = read_csv(results_of(project) / "sleepers.csv")
    rows = np.argmin(np.abs(truth["station"][None, :] - sleepers["station_m"][:, None]), axis=1)
    valid = sleepers["valid"].astype(bool)
    assert valid.sum() > 0.8 * len(sleepers)
    cross_level_error_mm = sleepers["cant_mm"] - 1e3 * truth["cant"][rows]
    assert np.abs(cross_level_error_mm[valid]).max() < 0.5
    assert any("spike below the envelope" in n["message"] for n in notices(project)) is screened
    after = np.flatnonzero(truth["pass_time"][rows] > records["time_s"][fault])[0]  # the sleeper 35 ms after it
    assert bool(valid[after]) is screened or "filter reset" in str(sleepers["not_assessed"][after])
    # the 30 m/5 m checks against the clean run's (the clean run itself is up to 1.3 mm off the checks of
    # the truth's deviations here, the survey's own noise): the spike adds less than 1 mm where valid.
    # Where only the aiding saw it, that holds beyond a chord (30 m) after the fault: the play estimated from
    # the NHC innovations leaves the reset's time out (it was 25-30 x the profile's, and changed the checks
    # 1-2 mm 70 s away); the smoother still carries the reset's correction back over the valid sleepers before
    # the fault (5-6 mm added to the checks whose chord reaches there), a defect of the fusion's reset
    # (nav/fusion.py)
    held = np.ones(len(sleepers), dtype=bool) if screened else sleepers["station_m"] > sleepers["station_m"][after] + 30
    clean = read_csv(results_of(tiny) / "sleepers.csv")
    assert np.allclose(clean["station_m"], sleepers["station_m"], rtol=0, atol=0.01)  # the same sleepers
    # Or the check is not assessed where the reset's stated 1-sigma cannot resolve its limit (values empty,
    # said so): a column left empty throughout is read as booleans, so it is taken as numbers here.
    said = {n["message"].split(":")[0] for n in notices(project) if n["stage"] == "assessment"}
    for rail in ("left", "right"):
        for direction in ("lateral", "vertical"):
            column = f"check_short_wave_30m_5m_{rail}_{direction}_mm"
            spiked = np.asarray(sleepers[column], dtype=float) if sleepers[column].dtype.kind == "f" else \
                np.full(len(sleepers), np.nan)
            added_mm = spiked - clean[column]
            measured = valid & np.isfinite(added_mm) & held
            assert measured.sum() > 0.5 * len(sleepers) or f"short_wave_30m_5m {direction}" in said, (rail, direction)
            assert np.abs(added_mm[measured]).max(initial=0.0) < 1.0, (rail, direction)
