"""The adjustment's track rows built by blocks of sleepers: the same rows as over the whole line,
and memory that does not grow with the line's length (issue 24's 20 km line)."""

from __future__ import annotations

import os

import numpy as np
import pytest
from memory_support import peak_growth_bytes
from test_track_adjustment import consistent_track

import insrail.track.adjustment as adjustment
from insrail.track.adjustment import load_fastener_type, optimise_amounts
from insrail.track.adjustment_programme import TrackRows, TrackRowSource, track_rows
from insrail.track.exceedance import SleeperGeometry
from insrail.track.tolerance import load_tolerance_profile


def gappy_track(count: int, seed: int) -> SleeperGeometry:
    """Uneven spacing, a jump in the stationing (missing sleepers), gauge and cant gaps wider and
    narrower than the interpolation allows, a level crossing of invalid sleepers."""
    rng = np.random.default_rng(seed)
    base = consistent_track(count, seed, design_cant=0.04)
    station = base.station_m + np.cumsum(rng.uniform(-0.02, 0.02, count))
    station[count // 2:] += 3.0
    gauge, cant = base.gauge_m.copy(), base.cant_m.copy()
    gauge[40:43] = np.nan
    gauge[150:175] = np.nan
    cant[90:92] = np.nan
    cant[count - 30:count - 5] = np.nan
    valid = np.ones(count, bool)
    valid[200:215] = False
    return SleeperGeometry.from_arrays(station, base.lateral_deviation_m, base.vertical_deviation_m, gauge, cant,
                                       base.design_cant_m, valid=valid)


FIELDS = ("value0", "lower", "upper", "hard", "first", "last", "owner")


def assert_rows_equal(a: TrackRows, b: TrackRows) -> None:
    for name in FIELDS:
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    assert a.matrix.shape == b.matrix.shape
    for name in ("indptr", "indices", "data"):
        np.testing.assert_array_equal(getattr(a.matrix, name), getattr(b.matrix, name), err_msg=name)


def select(rows: TrackRows, index: np.ndarray) -> TrackRows:
    return TrackRows(rows.matrix[index], *(getattr(rows, name)[index] for name in FIELDS))


@pytest.mark.parametrize("direction", ["lateral", "vertical"])
def test_rows_by_block_are_the_whole_lines_rows(direction):
    """A block of sleepers' rows, built from the block widened by what they read, are the whole
    line's rows of those sleepers, entry for entry and in the same order (so HiGHS sees the same
    programme); the rows that read a range of sleepers are all there."""
    geometry = gappy_track(400, seed=3)
    profile = load_tolerance_profile()
    whole = track_rows(geometry, profile, direction, 1e-3)
    source = TrackRowSource.of(geometry, profile, direction, 1e-3)
    assert whole.size > 1000
    for start in range(0, 400, 37):
        stop = min(400, start + 37)
        assert_rows_equal(source.owned(start, stop),
                          select(whole, np.flatnonzero((whole.owner >= start) & (whole.owner < stop))))
    for start, stop in ((0, 5), (150, 176), (198, 217), (395, 400)):
        near = source.touching(start, stop)
        assert_rows_equal(select(near, np.flatnonzero((near.last >= start) & (near.first < stop))),
                          select(whole, np.flatnonzero((whole.last >= start) & (whole.first < stop))))


@pytest.mark.parametrize("strategy, threshold_m", [("guiding_rail_first", None), ("least_movement", 2e-3)])
def test_amounts_do_not_depend_on_the_block(monkeypatch, strategy, threshold_m):
    """Track rows built by blocks (of 37 sleepers for the line's checks, around each window for the
    programmes) or every time for the whole line, as before: the same amounts to the bit, gaps,
    jumps and invalid sleepers included."""
    geometry = gappy_track(300, seed=5)
    profile, fastener = load_tolerance_profile(), load_fastener_type()

    def whole_line(source, start, stop):
        return track_rows(source.geometry, source.profile, source.direction, source.step_m)

    with monkeypatch.context() as patch:
        patch.setattr(TrackRowSource, "owned", whole_line)
        patch.setattr(TrackRowSource, "touching", whole_line)
        whole = optimise_amounts(geometry, profile, fastener, strategy, threshold_m=threshold_m)
    monkeypatch.setattr(adjustment, "ROW_BLOCK", 37)
    blocks = optimise_amounts(geometry, profile, fastener, strategy, threshold_m=threshold_m)
    assert np.count_nonzero(whole[0]) > 20 and np.count_nonzero(whole[1]) > 20
    for a, b in zip(whole, blocks):
        np.testing.assert_array_equal(a, b)


def repeated_track(tiles: int) -> SleeperGeometry:
    """``tiles`` times 1200 sleepers of straight track with a 3 mm lateral kink and a 4 mm dip of
    the left rail in the middle: the windows the optimisation works on stay apart."""
    count = 1200 * tiles
    lateral, vertical = np.zeros((count, 2)), np.zeros((count, 2))
    for middle in 600 + 1200 * np.arange(tiles):
        lateral[middle - 4:middle + 4] += 3e-3
        vertical[middle:middle + 6, 0] -= 4e-3
    return SleeperGeometry.from_arrays(0.625 * np.arange(count), lateral, vertical,
                                       1.435 + lateral[:, 1] - lateral[:, 0], vertical[:, 0] - vertical[:, 1])


def test_optimise_amounts_memory_does_not_grow_with_the_line(monkeypatch):
    """Traced peak of the optimisation on L and 2L sleepers (blocks shrunk to 97, one thread so
    that the peak does not depend on how the two directions interleave): what grows is the
    sleeper-level arrays of the amounts and deviations (the whole line's track rows, built for
    every window, grew 1.34 kB per sleeper here)."""
    monkeypatch.setattr(adjustment, "ROW_BLOCK", 97)
    monkeypatch.setattr(os, "cpu_count", lambda: 1)
    profile, fastener = load_tolerance_profile(), load_fastener_type()

    moved = []

    def run(tiles):
        lateral, vertical = optimise_amounts(repeated_track(tiles), profile, fastener)
        moved.append((np.count_nonzero(lateral), np.count_nonzero(vertical)))

    short, long = peak_growth_bytes(run, 2)
    assert min(min(m) for m in moved) > 10  # both directions have work in every kink
    assert long - short <= 600 * 2400 + 64_000, (short, long)  # measured 338 B per sleeper (1.34 kB before)
