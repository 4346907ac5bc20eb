"""Repeat runs and batches on tiny simulated surveys: three runs (seeds 1, 2, 3) over the same
track (design plus the scenario's fixed bumps, no random roughness), 150 m each."""

import os
import shutil
import subprocess
import sys
import tomllib
from dataclasses import replace

import numpy as np
import pytest

from insrail.cli.main import main
from insrail.project import load_project, process, save_project
from insrail.project.batch import run_batch
from insrail.project.compare import compare_surveys, load_repeatability
from insrail.project.results import load_results
from insrail.report import write_pdf
from insrail.project.demo import project_for_simulated_survey
from insrail.project.model import SurveyEntry
from insrail.sim.scenario import GnssSpec, preset
from insrail.sim.simulate import simulate
from insrail.track.repeatability import on_stations, repeatability

SEEDS = (1, 2, 3)
RESULT_FILES = ("sleepers.csv", "exceedances.csv")


def tiny_scenario():
    short = preset("short")
    return replace(
        short, name="tiny",
        motion=replace(short.motion, start_station_m=1100.0, end_station_m=1250.0, stops=(), static_start_s=60.0,
                       static_end_s=10.0),
        irregularities=replace(short.irregularities, lateral_rms_m=0.0, vertical_rms_m=0.0, gauge_rms_m=0.0,
                               cross_level_rms_m=0.0),
        gnss=GnssSpec(),
    )


@pytest.fixture(scope="module")
def tiny_projects(tmp_path_factory):
    """Three one-survey projects, processed once (the single runs batches are checked against)."""
    root = tmp_path_factory.mktemp("runs")
    projects = []
    for seed in SEEDS:
        survey = root / f"p{seed}" / "surveys" / "tiny"
        simulate(tiny_scenario(), seed, survey, imu_format="npy")
        project = project_for_simulated_survey(root / f"p{seed}", survey, name=f"tiny {seed}")
        process(project, "tiny")
        projects.append(project)
    return projects


def fresh_copies(projects, folder):
    """The projects without their results (nothing cached)."""
    copies = []
    for project in projects:
        shutil.copytree(project.folder, folder / project.folder.name, ignore=shutil.ignore_patterns("results"))
        copies.append(folder / project.folder.name)
    return copies


def copies_with_their_cache(projects, folder):
    """The projects without their result files but with their stage cache (hard links: the cache's files are
    replaced, never written in place): a batch takes the runs' cached fusion, track and adjustment. For the tests
    of what a batch does around its runs (a failed run, its messages, the connection), not of the runs'
    processing, which the tests comparing a batch with the single runs check on :func:`fresh_copies`."""
    copies = fresh_copies(projects, folder)
    for project, copy in zip(projects, copies):
        shutil.copytree(project.folder / "results" / ".cache", copy / "results" / ".cache", copy_function=os.link)
    return copies


def assert_same_results(projects, copies):
    for project, copy in zip(projects, copies):
        for name in RESULT_FILES:
            assert (copy / "results" / "tiny" / name).read_bytes() == (project.folder / "results" / "tiny" / name).read_bytes()


def test_local_batch_gives_the_single_runs_results(tiny_projects, tmp_path):
    copies = fresh_copies(tiny_projects, tmp_path)
    lines = []
    outcomes = run_batch(copies, workers=2, progress=lambda f, m: lines.append((f, m)))
    assert [o.ok for o in outcomes] == [True] * 3
    assert sorted(f for f, _ in lines) == pytest.approx([1 / 3, 2 / 3, 1.0])
    assert all(": done in" in m for _, m in lines)
    assert_same_results(tiny_projects, copies)


def test_dask_batch_gives_the_single_runs_results(tiny_projects, tmp_path):
    from distributed import LocalCluster

    copies = fresh_copies(tiny_projects, tmp_path)
    with LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None) as cluster:
        outcomes = run_batch(copies, scheduler=cluster.scheduler_address)
    assert [o.ok for o in outcomes] == [True] * 3
    assert_same_results(tiny_projects, copies)


#: Four runs of one track, 150 m each with 50 m of overlap: a line section.
SECTION_RUNS = (("run1", 1100.0), ("run2", 1200.0), ("run3", 1300.0), ("run4", 1400.0))


@pytest.fixture(scope="module")
def section_project(tmp_path_factory):
    """A project of four runs joined into the section `line`, processed and joined locally (one survey
    after the other, `insrail section`): the result a distributed batch must give."""
    from insrail.project.model import SectionEntry
    from insrail.project.section import join_section

    root = tmp_path_factory.mktemp("section")
    for seed, (name, start) in enumerate(SECTION_RUNS, start=1):
        config = tiny_scenario()
        config = replace(config, motion=replace(config.motion, start_station_m=start, end_station_m=start + 150.0))
        simulate(config, seed, root / "surveys" / name, imu_format="npy", track_seed=11)
    project = project_for_simulated_survey(root, root / "surveys" / "run1", name="line")
    project = replace(project, surveys=tuple(SurveyEntry(name, f"surveys/{name}") for name, _ in SECTION_RUNS),
                      sections=(SectionEntry("line", tuple(name for name, _ in SECTION_RUNS)),))
    save_project(project)
    project = load_project(root)
    for name, _ in SECTION_RUNS:
        process(project, name)
    join_section(project, "line")
    return project


def test_a_section_batched_on_a_two_worker_dask_cluster_is_the_local_join(section_project, tmp_path, capsys):
    """`insrail batch PROJECT --section line --scheduler ADDRESS`: the four runs processed by two worker
    processes, then joined here with the adjustment's parts solved by the workers; the joined
    section's files are byte for byte those of the local run."""
    from distributed import LocalCluster

    (copy,) = fresh_copies([section_project], tmp_path)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        code = main(["batch", str(copy), "--section", "line", "--scheduler", cluster.scheduler_address,
                     "--no-reports"])
        workers = {info["id"] for info in cluster.scheduler_info["workers"].values()}
        tasks = set(cluster.scheduler.task_prefixes)
    out = capsys.readouterr().out
    assert code == 0, out
    assert len(workers) == 2
    assert {"run_task", "solve_part_in_zone"} <= tasks, tasks
    assert "4 of 4 surveys processed" in out and "section line: " in out
    for name in ("sleepers.csv", "exceedances.csv", "quality.csv"):
        local = section_project.folder / "results" / "line" / name
        assert (copy / "results" / "line" / name).read_bytes() == local.read_bytes(), name
    assert not (copy / "reports").exists() or not list((copy / "reports").glob("track_geometry_line.*"))


def test_batch_tasks_start_with_the_largest_survey(section_project):
    from insrail.project.batch import BatchTask, longest_first, section_tasks

    tasks = section_tasks(section_project, ["line"])
    assert [t.survey for t in tasks] == [name for name, _ in SECTION_RUNS]
    imu = [(section_project.folder / "surveys" / t.survey / "imu.npy").stat().st_size for t in tasks]
    assert all(t.size_bytes > size for t, size in zip(tasks, imu))
    assert [t.survey for t in longest_first(tasks)] == [t.survey for t in sorted(tasks, key=lambda t: -t.size_bytes)]
    same = [BatchTask(section_project.path, name, 5) for name in ("a", "b")]
    assert longest_first([*same, BatchTask(section_project.path, "c", 9)])[0].survey == "c"
    assert longest_first(same) == same  # equal sizes keep their order


def test_a_section_batch_with_a_failed_run_is_not_joined(section_project, tmp_path, capsys):
    (copy,) = copies_with_their_cache([section_project], tmp_path)
    (copy / "surveys" / "run3" / "gauge.txt").write_text("# format: gauge-mm\nnot a number\n")
    assert main(["batch", str(copy), "--section", "line", "--workers", "2", "--no-reports"]) == 1
    out = capsys.readouterr()
    assert "3 of 4 surveys processed, 1 failed" in out.out and "gauge.txt" in out.out
    assert "section line not joined: a run failed" in out.err
    assert not (copy / "results" / "line").exists()
    assert main(["batch", str(copy), "--section", "nope"]) == 1
    assert "no section named nope" in capsys.readouterr().err
    assert main(["batch", str(copy), str(copy), "--section", "line"]) == 2


def test_a_section_batch_leaves_out_what_a_noisy_run_cannot_assess_and_says_so_once(section_project, tmp_path, capsys):
    """`insrail batch PROJECT --section line` with a noisy run2 (its cached covariance analysis states a 1 mm 5 m lag
    figure across the track, where the 30 m / 5 m and 10 m versine lateral checks ask for 0.67 mm: three 1-sigma
    within the 2 mm limit): run2 leaves them out and warns; the joined section leaves them out wherever a row holds
    run2's values (its own and its overlaps') and says so once, naming run2, not beside run2's own warning."""
    from insrail.project.pipeline import fusion_key, quality_cache_file
    from insrail.project.stagecache import load_dataclass, save_dataclass
    from insrail.quality.survey import EpochQuality

    (copy,) = copies_with_their_cache([section_project], tmp_path)  # the runs' fusion and track from the cache
    project = load_project(copy)
    analysis = quality_cache_file(copy / "results" / ".cache" /
                                  f"fusion-{fusion_key(project, project.manifest('run2'), copy / 'surveys' / 'run2')}.npy")
    stated = load_dataclass(analysis, EpochQuality)
    save_dataclass(analysis, replace(stated, lag5_sigma_lateral_m=np.full_like(stated.lag5_sigma_lateral_m, 1e-3)))
    assert main(["batch", str(copy), "--section", "line", "--workers", "1", "--no-reports"]) == 0
    out = capsys.readouterr().out
    def left_out(summary):
        return {(n["check"], n["direction"]): n for n in summary["assessment"]["not_assessable"]}

    run2, joined = load_results(copy, "run2"), load_results(copy, "line")
    noisy = left_out(run2.summary).keys() - left_out(load_results(section_project.folder, "run2").summary).keys()
    assert noisy == {("short_wave_30m_5m", "lateral"), ("versine_10m", "lateral")}  # (the 300 m chord: in any 150 m run)
    station = joined.columns["station_m"]
    held = (station >= run2.columns["station_m"].min() - 0.3) & (station <= run2.columns["station_m"].max() + 0.3)
    assert (joined.columns["source_run2"][~held] == 0).all() and held.sum() > 200
    for key in noisy:
        assert left_out(joined.summary)[key]["surveys"] == [["run2"]]
        assert left_out(joined.summary)[key]["stretches_m"] == [[pytest.approx(station[held][0]),
                                                                 pytest.approx(station[held][-1])]]
    for rail in ("left", "right"):
        values = joined.columns[f"check_short_wave_30m_5m_{rail}_lateral_mm"]
        assert np.isnan(values[held]).all() and np.isfinite(values[~held]).any()
    assert not any((e.check, e.direction) in noisy and station[held][0] <= e.station_from_m <= station[held][-1]
                   for e in joined.exceedances)
    # said once: a warning per check and direction, the section's (its stretches name the runs), none of the runs'
    warned = [n["message"] for n in joined.summary["notices"] if "not assessable" in n["message"]]
    assert len(warned) == len(left_out(joined.summary)) and all(" m (run" in m for m in warned), warned
    assert sum("not assessable" in line for line in out.splitlines()) == len(warned), out


def test_a_section_batch_on_a_dask_cluster_with_a_failed_run_is_not_joined_and_reads_the_others_ahead(
        section_project, tmp_path, capsys, monkeypatch):
    """On the cluster, as locally: a failed run leaves the section unjoined (exit 1). Each run that was
    processed was read as it came (while the others ran): the user's cache of parsed tables holds it."""
    from distributed import LocalCluster

    from insrail.project import table_cache

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    (copy,) = copies_with_their_cache([section_project], tmp_path)
    (copy / "surveys" / "run3" / "gauge.txt").write_text("# format: gauge-mm\nnot a number\n")
    with LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None) as cluster:
        code = main(["batch", str(copy), "--section", "line", "--scheduler", cluster.scheduler_address, "--no-reports"])
    out = capsys.readouterr()
    assert code == 1
    assert "3 of 4 surveys processed, 1 failed" in out.out and "section line not joined: a run failed" in out.err
    assert not (copy / "results" / "line").exists()
    for name in ("run1", "run2", "run4"):
        assert table_cache.load((copy / "results" / name / "sleepers.csv").read_bytes()) is not None, name


def test_batch_cli_reports_a_failed_survey_and_goes_on(tiny_projects, tmp_path, capsys):
    good, broken = copies_with_their_cache(tiny_projects[:2], tmp_path)
    (broken / "surveys" / "tiny" / "gauge.txt").write_text("# format: gauge-mm\nnot a number\n")
    (tmp_path / "not-a-project").mkdir()
    code = main(["batch", str(good), str(broken), str(tmp_path / "not-a-project"), "--workers", "2"])
    out = capsys.readouterr()
    assert code == 1
    assert "1 of 3 surveys processed, 2 failed" in out.out
    assert "project file not found" in out.out and "gauge.txt" in out.out
    assert (good / "results" / "tiny" / "sleepers.csv").is_file() and not (broken / "results" / "tiny").exists()
    assert "batch:" in out.err  # progress lines (not a terminal)
    assert main(["batch", str(good), "--workers", "0"]) == 2


def test_repeat_runs_agree_within_the_fusion_accuracy_and_a_shifted_run_shows(tiny_projects, tmp_path, capsys):
    # One project holding the three runs; run 3's stored lateral deviations of the left rail are
    # shifted by 1.5 mm over 20 m, as a badly set-up run would be.
    project = replace(tiny_projects[0], folder=tmp_path, surveys=tuple(
        SurveyEntry(f"run{seed}", f"surveys/run{seed}") for seed in SEEDS))
    for seed, source in zip(SEEDS, tiny_projects):
        shutil.copytree(source.folder / "surveys" / "tiny", tmp_path / "surveys" / f"run{seed}")
        shutil.copytree(source.folder / "results" / "tiny", tmp_path / "results" / f"run{seed}")
    project = replace(project, design="surveys/run1/truth/design.csv",
                      height=replace(project.height, benchmarks="surveys/run1/benchmarks.txt"))
    save_project(project)
    sleepers = tmp_path / "results" / "run3" / "sleepers.csv"
    lines = sleepers.read_text().splitlines()
    header = lines[0].split(",")
    column, station = header.index("lateral_deviation_left_mm"), header.index("station_m")
    for i, line in enumerate(lines[1:], start=1):
        cells = line.split(",")
        if 1150.0 <= float(cells[station]) <= 1170.0:
            cells[column] = f"{float(cells[column]) + 1.5:.3f}"
            lines[i] = ",".join(cells)
    sleepers.write_text("\n".join(lines) + "\n")

    assert main(["compare", str(tmp_path)]) == 0
    assert "Repeatability against run1" in capsys.readouterr().out
    summary = tomllib.loads((tmp_path / "results" / "repeatability.toml").read_text())
    assert summary["reference"] == "run1" and summary["compared"] == ["run2", "run3"]
    # the worst-over-placements checks by magnitude (their sign flips where placements tie), the rest signed
    assert summary["parameters"]["check_short_wave_30m_5m_left_lateral"]["compared"] == "magnitude"
    assert summary["parameters"]["check_long_wave_300m_150m_right_vertical"]["compared"] == "magnitude"
    assert {summary["parameters"][name]["compared"] for name in ("gauge", "cant", "lateral_deviation_left",
                                                                 "check_versine_10m_left_lateral")} == {"signed"}
    result, path = compare_surveys(load_project(tmp_path), ["run1", "run2", "run3"])
    mm = 1e-3
    # Relative geometry repeats like the fusion's short-lag accuracy (thesis: within 0.2-0.4 mm) ...
    for name in ("check_short_wave_30m_5m_left_lateral_mm", "check_short_wave_30m_5m_right_vertical_mm",
                 "cant_mm", "gauge_mm"):
        parameter = result.parameter(name)
        assert parameter.count.min() > (100 if parameter.by_magnitude else 150)  # checks: not within 30 m of the ends
        assert parameter.single_run_std < 0.3 * mm and parameter.max_abs[0] < 1.0 * mm, name
    # ... absolute deviations like the GNSS: its correlated error (tau 300 s, about one run long) is
    # nearly a constant per run, so two runs differ by up to 3 sigma * sqrt(2) of it.
    gnss = tiny_scenario().gnss
    for name, sigma in (("lateral_deviation_right_mm", gnss.gm_horizontal_m),
                        ("vertical_deviation_left_mm", gnss.gm_vertical_m)):
        assert np.abs(result.parameter(name).mean).max() < 3 * np.sqrt(2) * sigma, name
    # The shifted stretch stands out against run 2's differences.
    shifted = result.parameter("lateral_deviation_left_mm").difference
    station = result.station_m
    inside = (station >= 1151) & (station <= 1169)
    before, after = (station >= 1140) & (station <= 1148), (station >= 1172) & (station <= 1180)
    step = np.median(shifted[1, inside]) - 0.5 * (np.median(shifted[1, before]) + np.median(shifted[1, after]))
    assert step == pytest.approx(1.5 * mm, abs=0.3 * mm)
    assert np.abs(np.median(shifted[0, inside]) - 0.5 * (np.median(shifted[0, before]) + np.median(shifted[0, after]))) < 0.3 * mm
    csv = path.read_text().splitlines()
    assert csv[0].startswith("station_m,label,run2_minus_run1_lateral_deviation_left_mm,run3_minus_run1_")
    assert len(csv) == result.station_m.size + 1

    # Read back as stored, and reported in the PDF of every run compared (thesis §5.4.2's plots).
    stored = load_repeatability(tmp_path)
    assert stored.reference == "run1" and stored.compared == ("run2", "run3") and stored.includes("run3")
    np.testing.assert_allclose(stored.station_m, result.station_m, atol=1e-4)
    np.testing.assert_allclose(stored.difference_mm["lateral_deviation_left_mm"], 1e3 * shifted, atol=6e-4)
    assert stored.statistics["gauge"]["run2"]["count"] == result.parameter("gauge_mm").count[0]
    pdf = write_pdf(load_project(tmp_path), load_results(tmp_path, "run3"), tmp_path / "run3.pdf")
    text = subprocess.run(["pdftotext", "-layout", str(pdf), "-"], capture_output=True, text=True, check=True).stdout
    assert "Repeatability of repeat runs" in text and "run3 - run1" in text
    assert "Lateral deviation, left rail: run minus reference" in text
    row = next(line for line in text.splitlines() if line.strip().startswith("Lateral deviation, left rail")
               and "run3 - run1" in line)
    max_abs = stored.statistics["lateral_deviation_left"]["run3"]["max_abs_mm"]
    assert f"{max_abs:.2f}" in row.split()
    assert "before the current results" not in text
    (tmp_path / "results" / "run3" / "summary.toml").touch()  # the run processed again after the comparison
    os.utime(tmp_path / "results" / "repeatability.toml", (0, 0))
    pdf = write_pdf(load_project(tmp_path), load_results(tmp_path, "run3"), tmp_path / "run3.pdf")
    text = subprocess.run(["pdftotext", str(pdf), "-"], capture_output=True, text=True, check=True).stdout
    assert "before the current results" in " ".join(text.split())


def test_repeatability_of_arrays():
    stations = np.arange(0.0, 100.0, 0.625)
    truth = np.sin(stations / 7.0) * 1e-3
    rng = np.random.default_rng(3)
    runs = {"a": (stations, {"x": truth + rng.normal(0, 1e-4, stations.size)}),
            "b": (stations + 0.01, {"x": np.sin((stations + 0.01) / 7.0) * 1e-3 + rng.normal(0, 1e-4, stations.size)}),
            "c": (stations[::2], {"x": truth[::2] + 5e-4})}
    result = repeatability(runs)
    x = result.parameter("x")
    assert result.compared == ("b", "c")
    assert x.std[0] == pytest.approx(np.sqrt(2) * 1e-4, rel=0.15)  # two runs' noise
    assert x.mean[1] == pytest.approx(5e-4, abs=5e-5)  # a shifted run shows in its mean
    assert x.count[0] == stations.size - 1  # the last reference station lies beyond run b
    with pytest.raises(ValueError, match="at least two runs"):
        repeatability({"a": runs["a"]})
    with pytest.raises(ValueError, match="strictly increasing"):
        repeatability({"a": runs["a"], "d": (stations[::-1], {"x": truth})})
    gap = on_stations(np.array([0.0, 1.0, 5.0]), np.array([0.0, 1.0, 5.0]), np.array([0.5, 3.0, 6.0]))
    assert gap[0] == pytest.approx(0.5) and np.isnan(gap[1:]).all()


def test_cancelling_a_batch_drops_the_surveys_not_started(tiny_projects, tmp_path):
    import threading

    from insrail.progress import Cancelled

    broken, *good = fresh_copies(tiny_projects, tmp_path)
    # the largest survey (comment lines) though given last: started first, longest processing time first
    (broken / "surveys" / "tiny" / "gauge.txt").write_text("# format: gauge-mm\n" + "# a long header\n" * 200_000
                                                           + "not a number\n")
    stop = threading.Event()
    messages = []

    def progress(fraction, message):
        messages.append(message)
        stop.set()  # the user cancels as soon as the first survey is reported

    with pytest.raises(Cancelled):
        run_batch([*good, broken], workers=1, progress=progress, cancel=stop)
    assert "FAILED" in messages[0]
    assert not (good[-1] / "results" / "tiny").exists()  # never started



def test_dask_batch_over_tls_with_the_security_settings_of_a_config_file(tiny_projects, tmp_path, capsys):
    """A scheduler that requires TLS: the batch connects with the certificates named in a Dask
    YAML configuration file (insrail batch --security FILE); a missing certificate is named."""
    import shutil as _shutil

    from distributed import LocalCluster
    from distributed.security import Security

    if _shutil.which("openssl") is None:
        pytest.skip("openssl is needed to make a test certificate")
    key, cert = tmp_path / "key.pem", tmp_path / "cert.pem"
    subprocess.run(["openssl", "req", "-x509", "-newkey", "rsa:2048", "-nodes", "-keyout", str(key), "-out", str(cert),
                    "-days", "1", "-subj", "/CN=localhost"], check=True, capture_output=True)
    config = tmp_path / "dask-tls.yaml"
    config.write_text("distributed:\n  comm:\n    require-encryption: true\n    tls:\n"
                      f"      ca-file: {cert}\n      client:\n        cert: {cert}\n        key: {key}\n")
    cluster_security = Security(tls_ca_file=str(cert), tls_scheduler_cert=str(cert), tls_scheduler_key=str(key),
                                tls_worker_cert=str(cert), tls_worker_key=str(key), tls_client_cert=str(cert),
                                tls_client_key=str(key), require_encryption=True)
    (copy,) = copies_with_their_cache(tiny_projects[:1], tmp_path)
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None,
                      protocol="tls://", security=cluster_security) as cluster:
        assert cluster.scheduler_address.startswith("tls://")
        code = main(["batch", str(copy), "--scheduler", cluster.scheduler_address, "--security", str(config)])
    assert code == 0, capsys.readouterr()
    assert (copy / "results" / "tiny" / "sleepers.csv").is_file()
    config.write_text(config.read_text().replace(str(key), str(tmp_path / "nokey.pem")))
    assert main(["batch", str(copy), "--scheduler", "tls://127.0.0.1:1", "--security", str(config)]) == 1
    assert "dask-tls.yaml: distributed.comm.tls.client.key: file not found" in capsys.readouterr().err


@pytest.mark.parametrize("address, expected", [
    ("tls://127.0.0.1:8786", "a tls:// scheduler needs --security FILE"),
    ("wss://127.0.0.1:8786", "a wss:// scheduler needs --security FILE"),
    ("tsl://127.0.0.1:8786", "unknown protocol tsl://"),
    ("tcp://", "no host given"),
])
def test_batch_refuses_a_scheduler_address_it_cannot_use_as_bad_usage(tmp_path, capsys, address, expected):
    assert main(["batch", str(tmp_path), "--scheduler", address]) == 2
    assert f"insrail batch: --scheduler {address}: {expected}" in capsys.readouterr().err


def test_the_batch_stops_the_dask_workers_statistical_profiler_on_python_3_11():
    """Dask's profiler can deadlock a Python 3.11 worker process (CPython gh-106883): the batch's client stops it
    on the workers it finds, here one started with the profiler on."""
    import dask
    from distributed import LocalCluster

    from insrail.project.batch import _dask_client

    with dask.config.set({"distributed.worker.profile.enabled": True}), \
            LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as cluster:
        worker = next(iter(cluster.workers.values()))
        assert "profile" in worker.periodic_callbacks  # the cluster's default, which the test must see stopped
        with _dask_client(cluster.scheduler_address):
            profiling = {"profile", "profile-cycle"} & set(worker.periodic_callbacks)
    assert profiling == (set() if sys.version_info < (3, 12) else {"profile", "profile-cycle"})
