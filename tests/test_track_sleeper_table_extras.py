"""The sleeper table's broken-chainage zone, the detector repair counts and the numbering anchor."""

from dataclasses import replace

import numpy as np
import pytest
from track_truth import truth_reconstruction

from insrail.io.track_sensors import read_sleeper_times
from insrail.track.sleeper_table import reconstruct_track
from insrail.track.sleepers import (
    AnchorError,
    SleeperAnchor,
    SleeperNumbering,
    anchor_numbering,
)
from insrail.track.stationing import StationEquation, StationEquations


def _numbering():
    stations = 100.0 + 0.625 * np.arange(10)
    return SleeperNumbering(number=np.arange(1, 11), station_m=stations, time_s=500.0 - 2.0 * np.arange(10),
                            detected=np.ones(10, bool), pulse_time_s=np.arange(12.0), pulse_station_m=np.zeros(12),
                            pulse_accepted=np.r_[np.ones(10, bool), False, False])


def test_anchor_by_station_or_time_renumbers_and_refuses_what_is_not_a_sleeper():
    numbering = _numbering()
    by_station = anchor_numbering(numbering, SleeperAnchor(4711, station_m=101.3))  # the 3rd sleeper, at 101.25 m
    assert by_station.number[2] == 4711 and np.all(np.diff(by_station.number) == 1)
    # a run against the stationing: at 495.9 s the detector is just past the 3rd sleeper (passed at 496 s)
    by_time = anchor_numbering(numbering, SleeperAnchor(20, time_s=495.9))
    assert by_time.number[2] == 20
    with pytest.raises(AnchorError, match="no sleeper of this survey at station 90.000 m"):
        anchor_numbering(numbering, SleeperAnchor(1, station_m=90.0))
    with pytest.raises(AnchorError, match="at time 600.000 s"):
        anchor_numbering(numbering, SleeperAnchor(1, time_s=600.0))
    with pytest.raises(ValueError, match="exactly one"):
        SleeperAnchor(1, station_m=1.0, time_s=2.0)
    assert numbering.repair_counts() == {"pulses": 12, "missed_inserted": 0, "false_rejected": 2}


def test_zone_column_follows_the_station_equations(short_perfect_survey):
    truth = truth_reconstruction(short_perfect_survey)
    # a long chain at 1500 m: displayed 1500 is followed by 1490 (zone 1 after it)
    design = replace(truth.design, station_equations=StationEquations((StationEquation(1500.0, 1490.0),)))
    table = reconstruct_track(truth.trajectory, truth.trolley, truth.gauge, truth.to_engineering, design=design,
                              pulses=read_sleeper_times(short_perfect_survey / "sleepers.txt")).table
    assert np.array_equal(table.chain_zone, (table.station_m >= 1500.0).astype(int))
    after = np.flatnonzero(table.station_m >= 1500.0)[0]
    assert table.label[after].startswith("K1+490") and table.label[after - 1].startswith(("K1+499", "K1+500"))
    plain = reconstruct_track(truth.trajectory, truth.trolley, truth.gauge, truth.to_engineering, design=truth.design,
                              pulses=read_sleeper_times(short_perfect_survey / "sleepers.txt"),
                              anchor=SleeperAnchor(9000, station_m=1600.0))
    row = int(np.argmin(np.abs(plain.table.station_m - 1600.0)))
    assert plain.table.chain_zone is None and plain.table.number[row] == 9000
    counts = plain.sleepers.repair_counts()
    assert counts["missed_inserted"] == int((~plain.table.detected).sum()) > 5 and counts["false_rejected"] > 3
