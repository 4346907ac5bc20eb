"""The IMU path is read and judged a chunk of records at a time (memory bounded for any survey
length): the reader, the screening and the stop detection give with tiny chunks exactly what they
give in one chunk, and so does the fusion of the `short` survey (every epoch within 0.01 mm)."""

import threading
from contextlib import ExitStack
from dataclasses import replace
from functools import partial, partialmethod

import numpy as np
import pytest

from insrail.background import BackgroundJob
from insrail.io import imu as imu_io
from insrail.io.survey import read_survey
from insrail.io.types import ImuIncrements
from insrail.nav import alignment, fusion, imu_screening
from insrail.nav.earth import CGCS2000
from insrail.nav.imu_profile import load_imu_profile
from insrail.sim import gnss_faults

TINY = 997  # records per chunk: hundreds of chunk boundaries in `short`
WHOLE = 1 << 40


@pytest.fixture(scope="module")
def survey(short_nav_survey):
    return read_survey(short_nav_survey)


def test_reader_in_chunks_reads_what_one_chunk_reads(survey, short_nav_survey, monkeypatch):
    path = short_nav_survey / survey.manifest.files["imu"].path
    whole = imu_io.read_imu_npy(path)
    monkeypatch.setattr(imu_io, "NPY_READ_CHUNK", TINY)
    chunked = imu_io.read_imu_npy(path)
    for name in ("time_s", "dtheta_rad", "dvel_mps"):
        np.testing.assert_array_equal(getattr(chunked, name), getattr(whole, name))


def test_reader_names_a_bad_record_in_a_later_chunk(tmp_path, monkeypatch):
    records = np.zeros(5000, dtype=imu_io.IMU_NPY_DTYPE)
    records["time_s"] = 100.0 + 0.005 * np.arange(5000)
    records["dvel_mps"][:, 2] = -9.8 * 0.005
    records["dvel_mps"][3210, 1] = np.nan
    np.save(tmp_path / "imu.npy", records)
    monkeypatch.setattr(imu_io, "NPY_READ_CHUNK", TINY)
    with pytest.raises(imu_io.InputError) as info:
        imu_io.read_imu_npy(tmp_path / "imu.npy")
    assert info.value.line == 3210 and "dvel_mps" in info.value.message


def test_screening_in_chunks_finds_the_outliers_one_chunk_finds(survey):
    imu = survey.imu
    n = 20 * TINY
    dtheta, dvel = imu.dtheta_rad[:n].copy(), imu.dvel_mps[:n].copy()
    spikes = [0, TINY - 1, TINY + 1, 2 * TINY, 5 * TINY + 2, n - 1]  # at and next to chunk boundaries
    dvel[spikes, 0] += 0.3  # 60 m/s^2 for one 5 ms record
    dtheta[7 * TINY, 2] += 0.01
    dvel[3 * TINY, 1] = np.nan
    short = ImuIncrements(imu.time_s[:n].copy(), dtheta, dvel, source=imu.source)
    profile = load_imu_profile("nav")
    whole = imu_screening.screen_imu(short, profile, chunk=WHOLE)
    chunked = imu_screening.screen_imu(short, profile, chunk=TINY)
    assert [o.index for o in whole[1]] == sorted([*spikes, 7 * TINY, 3 * TINY])
    assert repr(chunked[1]) == repr(whole[1])  # (a NaN value is not == itself)
    np.testing.assert_array_equal(chunked[0].time_s, whole[0].time_s)


@pytest.mark.parametrize("with_odometer", [True, False])
def test_stops_in_chunks_are_the_stops_of_one_chunk(survey, with_odometer):
    profile = load_imu_profile("nav")
    gyro, accel = alignment.stop_thresholds(profile.gyro_arw, profile.accel_vrw, survey.imu.rate_hz)
    odometer = survey.odometer if with_odometer else None
    kwargs = {"max_gyro_std_radps": gyro, "max_accel_std_mps2": None if with_odometer else accel}
    whole = alignment.detect_stops(survey.imu, odometer, chunk=WHOLE, **kwargs)
    assert len(whole) >= 3  # the static start, two stops (and the end)
    assert alignment.detect_stops(survey.imu, odometer, chunk=TINY, **kwargs) == whole


def test_fusion_in_tiny_chunks_is_the_fusion_in_one_chunk(survey, short_nav_survey, monkeypatch):
    profile = load_imu_profile(survey.manifest.imu_profile)
    options = fusion.FusionOptions()

    def fused():
        imu = read_survey(short_nav_survey).imu
        return fusion.fuse(imu, fusion.aiding_for(survey, options, profile), profile, options, CGCS2000).trajectory

    monkeypatch.setattr(fusion, "screen_imu", partial(imu_screening.screen_imu, chunk=WHOLE))
    monkeypatch.setattr(fusion, "detect_stops", partial(alignment.detect_stops, chunk=WHOLE))
    monkeypatch.setattr(imu_io, "NPY_READ_CHUNK", WHOLE)
    whole = fused()
    monkeypatch.setattr(fusion, "screen_imu", partial(imu_screening.screen_imu, chunk=TINY))
    monkeypatch.setattr(fusion, "detect_stops", partial(alignment.detect_stops, chunk=TINY))
    monkeypatch.setattr(imu_io, "NPY_READ_CHUNK", TINY)
    chunked = fused()
    assert len(chunked) == len(whole) > 250_000
    np.testing.assert_array_equal(chunked.time_s, whole.time_s)
    north = (chunked.lat_rad - whole.lat_rad) * 6.36e6
    east = (chunked.lon_rad - whole.lon_rad) * 6.39e6 * np.cos(whole.lat_rad)
    up = chunked.height_m - whole.height_m
    assert np.abs(np.column_stack([north, east, up])).max() <= 1e-5  # 0.01 mm


def _fused_files(survey, imu, tmp_path, label):
    """The fusion of ``imu`` with the survey's aiding: (trajectory.npy's bytes, what it said)."""
    profile = load_imu_profile(survey.manifest.imu_profile)
    options = fusion.FusionOptions()
    path = tmp_path / f"{label}.npy"
    result = fusion.fuse(imu, fusion.aiding_for(survey, options, profile), profile, options, CGCS2000,
                         trajectory_file=path)
    said = (result.rejections, result.stops, result.resets, result.statistics, result.info["imu_gaps"],
            [n.message for n in result.info["notices"]], result.info["imu_outliers"], result.integrity)
    return path.read_bytes(), repr(said)


@pytest.fixture(scope="module")
def faulty_imu(survey):
    """The first 600 s of `short` in memory, with a 0.2 s dropout (bridged) and a spike (removed)
    at chunk edges of TINY, and the GNSS with two outliers (rejected)."""
    imu = survey.imu
    n = 120_000
    keep = np.ones(n, dtype=bool)
    keep[50 * TINY - 20 : 50 * TINY + 20] = False  # 40 records: 0.2 s
    dvel = imu.dvel_mps[:n].copy()
    dvel[70 * TINY - 1, 0] += 0.3
    first = survey.gnss.time_s[0]
    gnss = gnss_faults.outliers(survey.gnss, [first + 200.0, first + 400.0], [(0.8, 0.6, 0.0), (0.0, 0.9, 0.0)])
    return replace(survey, gnss=gnss), ImuIncrements(imu.time_s[:n][keep], imu.dtheta_rad[:n][keep].copy(),
                                                     dvel[keep], gaps=imu_io.find_gaps(imu.time_s[:n][keep]),
                                                     source=imu.source)


def test_the_filter_fed_in_imu_chunks_gives_the_same_files_and_events(faulty_imu, tmp_path, monkeypatch):
    """trajectory.npy byte-identical with the IMU fed to the filter 997 records at a time (and the
    filter-rate record kept 37 update epochs at a time), by the default chunks and whole; the same rejections, stops, resets, statistics, gaps and notices."""
    survey, imu = faulty_imu
    runs = {}
    for label, chunk, rows in (("tiny", TINY, 37), ("default", fusion.IMU_CHUNK, fusion.HIST_CHUNK),
                               ("whole", len(imu), len(imu))):
        monkeypatch.setattr(fusion, "IMU_CHUNK", chunk)
        monkeypatch.setattr(fusion, "HIST_CHUNK", rows)  # update epochs of the filter-rate record held at a time
        runs[label] = _fused_files(survey, imu, tmp_path, label)
    said = runs["whole"][1]
    assert "rejected" in said and "removed as an outlier" in said and "missing samples bridged" in said
    assert runs["tiny"] == runs["whole"] and runs["default"] == runs["whole"]


def test_the_mapped_imu_file_fuses_as_the_record_in_memory(survey, short_nav_survey, tmp_path, monkeypatch):
    """read_imu_npy maps the increments of a record above MAPPED_ABOVE_BYTES (not held in memory);
    fused from the map, with its pages let go behind the filter, the trajectory is the one fused
    from a copy in memory."""
    path = short_nav_survey / survey.manifest.files["imu"].path
    n = 100_000
    monkeypatch.setattr(imu_io, "MAPPED_ABOVE_BYTES", 0)  # this survey's record is held in memory
    mapped = imu_io.read_imu_npy(path)
    assert isinstance(mapped.dtheta_rad.base, np.memmap) or isinstance(mapped.dtheta_rad, np.memmap)
    mapped = replace(mapped, time_s=mapped.time_s[:n], dtheta_rad=mapped.dtheta_rad[:n], dvel_mps=mapped.dvel_mps[:n])
    in_memory = replace(mapped, dtheta_rad=np.array(mapped.dtheta_rad), dvel_mps=np.array(mapped.dvel_mps))
    monkeypatch.setattr(fusion, "IMU_CHUNK", TINY)
    assert _fused_files(survey, mapped, tmp_path, "mapped") == _fused_files(survey, in_memory, tmp_path, "memory")


def test_the_text_imu_file_is_copied_as_the_binary_one(survey, short_nav_survey, tmp_path, monkeypatch):
    """read_imu_kfgins hands the parsed increments over to the copy read_imu_npy makes: mapped above
    MAPPED_ABOVE_BYTES (a 10 km survey's 100 MB table is not held beside the fusion, which lets the
    pages go behind it), in memory below; the same bits as the binary file's either way, read-only."""
    n = 50_000
    binary = imu_io.read_imu_npy(short_nav_survey / survey.manifest.files["imu"].path)
    binary = replace(binary, time_s=binary.time_s[:n], dtheta_rad=binary.dtheta_rad[:n], dvel_mps=binary.dvel_mps[:n])
    imu_io.write_imu_kfgins(tmp_path / "imu.txt", binary)
    for mapped_above, mapped in ((n * 48 - 1, True), (n * 48, False)):
        monkeypatch.setattr(imu_io, "MAPPED_ABOVE_BYTES", mapped_above)
        text = imu_io.read_imu_kfgins(tmp_path / "imu.txt")
        for name in ("dtheta_rad", "dvel_mps"):
            values = getattr(text, name)
            assert (isinstance(values.base, np.memmap) or isinstance(values, np.memmap)) == mapped, name
            assert np.array_equal(values, getattr(binary, name)), name
            assert not values.flags.writeable
        assert np.allclose(text.time_s, binary.time_s, rtol=0, atol=1e-9)  # written to 1 ns
        imu_io.release_pages(text.dtheta_rad, text.dvel_mps)
        assert np.array_equal(text.dvel_mps, binary.dvel_mps)  # read back after the pages were let go


def test_fusion_and_its_covariance_analysis_grow_only_at_the_filter_rate(survey, tmp_path, monkeypatch):
    """tracemalloc peaks of fuse + the analysis of its record (the pipeline's path: the smoother's
    record, no IMU data, the fusion result let go first) on the first L and 2L epochs of `short`,
    chunks shrunk: nothing is held per IMU epoch (the increments, their intervals, the output
    indices) nor the filter-rate record (sensor estimates, sigmas, smoother corrections: 1.1 kB
    per update epoch); what still grows is the forward solution at the update epochs, the
    schedule and the innovations at the end of the fusion (0.40 kB per update epoch measured,
    1.6 kB before; the analysis alone: the next test)."""
    from memory_support import peak_growth_bytes

    from insrail.quality.survey import UpdateEpochs, recorded_quality

    # the forward pass's records on disk, as a survey's above RECORDS_IN_MEMORY_BYTES (below it they are held in
    # memory by design: 7.4 kB per update epoch, bounded by that constant)
    monkeypatch.setattr(fusion, "RECORDS_IN_MEMORY_BYTES", 0)
    monkeypatch.setattr(fusion, "IMU_CHUNK", TINY)
    monkeypatch.setattr(fusion, "HIST_CHUNK", 37)
    monkeypatch.setattr(fusion, "TRAJECTORY_CHUNK", TINY)
    monkeypatch.setattr(imu_screening, "UNITS_CHUNK", TINY)
    monkeypatch.setattr(fusion, "screen_imu", partial(imu_screening.screen_imu, chunk=TINY))
    monkeypatch.setattr(fusion, "detect_stops", partial(alignment.detect_stops, chunk=TINY))
    profile = load_imu_profile(survey.manifest.imu_profile)
    options = fusion.FusionOptions()
    aiding = fusion.aiding_for(survey, options, profile)
    imu = survey.imu
    inputs = {n: ImuIncrements(imu.time_s[:n].copy(), np.array(imu.dtheta_rad[:n]), np.array(imu.dvel_mps[:n]),
                               source=imu.source) for n in (20_000, 40_000)}
    updates = {}

    def run(n):
        with fusion.SmootherStore(chunk=37) as store:
            result = fusion.fuse(inputs[n], aiding, profile, options, CGCS2000, covariance_store=store,
                                 trajectory_file=tmp_path / f"{n}.npy")  # as the pipeline streams it
            updates[n] = len(result.timeline.time_s)
            epochs = UpdateEpochs.of(survey.odometer, result)
            del result  # as the pipeline does
            recorded_quality(epochs, store)

    run(20_000)  # compiled and cached once, outside the traced runs
    short, long = peak_growth_bytes(run, 20_000)
    more = updates[40_000] - updates[20_000]
    assert more > 900
    assert long - short <= 700 * more + (1 << 16), (long - short) / more


def test_the_analysis_of_the_record_grows_only_by_its_own_figures(survey, tmp_path):
    """tracemalloc peak of the covariance analysis alone (``recorded_quality``; the fusions run
    outside the trace and their results are let go, as in the pipeline) on L and 2L update
    epochs: per update epoch only its variances and figures grow (64 B measured; 147 B with the
    whole survey's projections, and the pipeline held the forward solution and innovations
    through it before, 0.3 kB more)."""
    from memory_support import peak_growth_bytes

    from insrail.quality.survey import UpdateEpochs, recorded_quality

    profile = load_imu_profile(survey.manifest.imu_profile)
    options = fusion.FusionOptions()
    aiding = fusion.aiding_for(survey, options, profile)
    imu = survey.imu
    with ExitStack() as stack:
        records = {}
        for n in (20_000, 40_000):
            store = stack.enter_context(fusion.SmootherStore(chunk=37))
            result = fusion.fuse(ImuIncrements(imu.time_s[:n].copy(), np.array(imu.dtheta_rad[:n]),
                                               np.array(imu.dvel_mps[:n]), source=imu.source),
                                 aiding, profile, options, CGCS2000, covariance_store=store,
                                 trajectory_file=tmp_path / f"{n}.npy")
            records[n] = UpdateEpochs.of(survey.odometer, result), store
        del result
        recorded_quality(*records[20_000])  # compiled and cached once, outside the traced runs
        short, long = peak_growth_bytes(lambda n: recorded_quality(*records[n]), 20_000)
    more = len(records[40_000][0].time_s) - len(records[20_000][0].time_s)
    assert more > 900
    assert long - short <= 100 * more + (1 << 16), (long - short) / more


def test_the_running_sum_of_the_odometer_check_is_numpys_to_the_bit(survey, monkeypatch):
    from insrail.project import plausibility

    dvel = survey.imu.dvel_mps  # mapped from the file
    records = [0, 5, TINY - 1, TINY, 3 * TINY + 7, 20 * TINY, len(dvel) - 1]
    whole = np.cumsum(np.asarray(dvel[:, 0]))[records]
    monkeypatch.setattr(plausibility, "RUNNING_SUM_CHUNK", TINY)
    got, values = plausibility.running_sum_at(dvel, 0, records)
    assert got == records
    np.testing.assert_array_equal(values, whole)



def test_the_records_held_in_memory_fuse_as_the_records_on_disk(faulty_imu, tmp_path, monkeypatch):
    """The forward pass's records (the smoother's store, the navigation file) in memory below
    RECORDS_IN_MEMORY_BYTES, in temporary files above it, or moved to them when more comes than
    was held (a store held for 500 records): trajectory.npy byte-identical, the same events."""
    survey, imu = faulty_imu
    in_memory = _fused_files(survey, imu, tmp_path, "memory")
    monkeypatch.setattr(fusion, "RECORDS_IN_MEMORY_BYTES", 0)
    assert _fused_files(survey, imu, tmp_path, "disk") == in_memory
    monkeypatch.setattr(fusion, "RECORDS_IN_MEMORY_BYTES", 1 << 40)
    hold = fusion.SmootherStore.hold_in_memory
    monkeypatch.setattr(fusion.SmootherStore, "hold_in_memory", lambda store, count: hold(store, 500))
    assert _fused_files(survey, imu, tmp_path, "spilled") == in_memory


def test_a_callers_covariance_store_keeps_its_records_on_disk(faulty_imu, tmp_path):
    """The store ``insrail process`` keeps for the covariance analysis outlives the fusion into the track
    reconstruction, where a run peaks: its records go to the temporary file however small they are."""
    survey, imu = faulty_imu
    profile = load_imu_profile(survey.manifest.imu_profile)
    options = fusion.FusionOptions()
    with fusion.SmootherStore() as store:
        fusion.fuse(imu, fusion.aiding_for(survey, options, profile), profile, options, CGCS2000,
                    trajectory_file=tmp_path / "t.npy", covariance_store=store)
        assert store.count > 0 and store.spool.memory is None and store.spool.file is not None


def test_a_spool_moves_to_its_file_when_more_comes_than_it_holds():
    """Bytes appended past the memory held go, with the ones before them, to the temporary file:
    read back the same, read-only; bytes never appended are an error, not a short read."""
    spool = fusion._Spool("insrail-test-", "the test's temporary file")
    spool.hold_in_memory(100)
    data = np.arange(150, dtype=np.uint8)
    spool.append(data[:60])
    assert spool.memory is not None and spool.file is None
    spool.append(data[60:])
    assert spool.memory is None and spool.file is not None
    for into in (None, np.zeros(200, dtype=np.uint8)):
        back = spool.read(10, 140, into)
        np.testing.assert_array_equal(back, data[10:])
        assert not back.flags.writeable
    with pytest.raises(OSError, match="not written"):
        spool.read(100, 51)
    spool.close()

def test_records_written_in_place_in_the_stores_memory_are_appended_records():
    """The filter writes its records straight into the memory that holds them (a chunk at a time, the last room
    what is left); a full memory, or one not held, gives no room (the records are then appended)."""
    records = np.arange(5 * fusion.RECORD_SIZE, dtype=float).reshape(5, fusion.RECORD_SIZE)
    with fusion.SmootherStore(chunk=3) as store, fusion.SmootherStore(chunk=3) as appended:
        assert store.room() is None  # not held in memory
        store.hold_in_memory(5)
        for first in (0, 3):
            room = store.room()
            assert room.shape == (min(3, 5 - first), fusion.RECORD_SIZE) and room.flags.writeable
            room[:] = records[first : first + len(room)]
            store.filled(len(room))
        assert store.room() is None and store.count == 5
        appended.hold_in_memory(5)
        appended.append_records(records)
        assert [(f, c.tobytes()) for f, c in store.reversed_chunks()] == [(f, c.tobytes()) for f, c in appended.reversed_chunks()]


@pytest.mark.parametrize("in_file", [True, False])
def test_the_trajectory_made_beside_the_smoother_is_the_one_made_after_it(faulty_imu, tmp_path, monkeypatch, in_file):
    """The smoother in a thread of its own and the trajectory's chunks made last first as its rows come
    (tiny chunks: every readiness wait), or one after the other: the same trajectory to the bit."""
    survey, imu = faulty_imu
    profile = load_imu_profile(survey.manifest.imu_profile)
    options = fusion.FusionOptions()
    threads = []

    def fused(label, threaded):
        path = tmp_path / f"{label}.npy" if in_file else None
        monkeypatch.setattr(fusion, "BackgroundJob", partial(BackgroundJob, threaded=threaded))
        result = fusion.fuse(imu, fusion.aiding_for(survey, options, profile), profile, options, CGCS2000,
                             trajectory_file=path, progress=lambda f, m: threads.append((threading.get_ident(), f)))
        return path.read_bytes() if in_file else np.asarray(result.trajectory.lat_rad).tobytes() + \
            np.asarray(result.trajectory.sigma_rpy_rad).tobytes() + np.asarray(result.trajectory.odometer_scale).tobytes()

    smoothed_in = []
    rts = fusion._rts
    monkeypatch.setattr(fusion, "_rts", lambda *a, **k: (smoothed_in.append(threading.current_thread().name), rts(*a, **k)))
    serial = fused("serial", False)
    monkeypatch.setattr(fusion, "TRAJECTORY_CHUNK", TINY)
    monkeypatch.setattr(fusion.SmootherStore, "__init__", partialmethod(fusion.SmootherStore.__init__, chunk=53))
    said = len(threads)
    assert fused("beside", True) == serial
    assert smoothed_in == [threading.current_thread().name, "insrail-smoother"]
    assert {ident for ident, _ in threads} == {threading.get_ident()}  # the progress said in the caller's thread only
    fractions = [f for _, f in threads[said:]]
    assert fractions == sorted(fractions)


def test_a_smoother_failing_beside_the_trajectory_fails_the_fusion(faulty_imu, tmp_path, monkeypatch):
    """The smoother's failure in its thread is the fusion's (not a wait for rows that never come), and
    nothing of the trajectory is left."""
    survey, imu = faulty_imu
    profile = load_imu_profile(survey.manifest.imu_profile)
    options = fusion.FusionOptions()
    rts = fusion._rts

    def failing(*args, made, **kwargs):
        def made_then_fail(first):
            made(first)
            raise OSError(28, "No space left on device", "the smoother's temporary file")
        rts(*args, made=made_then_fail, **kwargs)

    monkeypatch.setattr(fusion, "_rts", failing)
    monkeypatch.setattr(fusion, "BackgroundJob", partial(BackgroundJob, threaded=True))
    with pytest.raises(OSError, match="No space left"):
        fusion.fuse(imu, fusion.aiding_for(survey, options, profile), profile, options, CGCS2000,
                    trajectory_file=tmp_path / "trajectory.npy")
    assert list(tmp_path.iterdir()) == []
    assert not [t for t in threading.enumerate() if t.name == "insrail-smoother"]


def test_the_smoother_records_written_beside_the_filter_are_the_ones_written_by_it(faulty_imu, monkeypatch):
    """The forward pass's records go to the store from a background job while the filter fills the other
    buffer: the same records in the same order as written one after the other (a small chunk: many
    appends); an append that fails (a full disk) fails the fusion."""
    survey, imu = faulty_imu
    profile = load_imu_profile(survey.manifest.imu_profile)
    options = fusion.FusionOptions(smoother=False)
    stored = {}
    for threaded in (False, True):
        monkeypatch.setattr(fusion, "BackgroundJob", partial(BackgroundJob, threaded=threaded))
        with fusion.SmootherStore(chunk=61) as store:
            fusion.fuse(imu, fusion.aiding_for(survey, options, profile), profile, options, CGCS2000,
                        covariance_store=store)
            stored[threaded] = (store.count, store.spool.read(0, store.spool.size).tobytes())
    assert stored[True] == stored[False] and stored[True][0] > 1000
    appended = []

    def full_disk(self, records):
        appended.append(threading.current_thread().name)
        if len(appended) == 3:
            raise OSError(28, "No space left on device", "the smoother's temporary file")

    monkeypatch.setattr(fusion.SmootherStore, "append_records", full_disk)
    with fusion.SmootherStore(chunk=61) as store, pytest.raises(OSError, match="No space left"):
        fusion.fuse(imu, fusion.aiding_for(survey, options, profile), profile, options, CGCS2000,
                    covariance_store=store)
    assert appended[:3] == ["insrail-records"] * 3 and len(appended) <= 4
