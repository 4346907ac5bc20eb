"""The adjustment's windows in colours and independent parts, solved side by side (threads here, a
Dask cluster's workers in a section batch): the amounts of solving them one after the other."""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import insrail.track.adjustment as adjustment
from insrail.track.adjustment import (
    colours,
    direction_problem,
    independent_parts,
    load_fastener_type,
    optimise_amounts,
    rail_checks,
    reassess,
)
from insrail.track.exceedance import SleeperGeometry
from insrail.track.tolerance import load_tolerance_profile

#: The shipped profile's longest chord (300 m: 480 sleepers) and twice the part margin.
GAP = 480 + 2 * adjustment.PART_MARGIN


def kinked_track(middles: list[int], count: int) -> SleeperGeometry:
    """Straight track with a 3 mm lateral kink and a 4 mm dip of the left rail at each of ``middles``."""
    lateral, vertical = np.zeros((count, 2)), np.zeros((count, 2))
    for middle in middles:
        lateral[middle - 4:middle + 4] += 3e-3
        vertical[middle:middle + 6, 0] -= 4e-3
    return SleeperGeometry.from_arrays(0.625 * np.arange(count), lateral, vertical,
                                       1.435 + lateral[:, 1] - lateral[:, 0], vertical[:, 0] - vertical[:, 1])


def test_a_colours_windows_lie_a_chord_apart_and_the_colours_follow_from_the_windows():
    checks = rail_checks(load_tolerance_profile(), "lateral")
    windows = [(0, 100), (150, 300), (400, 500), (1000, 1100), (1200, 1300), (2400, 2500)]
    classes = colours(windows, checks)
    assert classes == [[(0, 100), (1000, 1100), (2400, 2500)], [(150, 300), (1200, 1300)], [(400, 500)]]
    for members in classes:
        assert all(b[0] - a[1] >= GAP for a, b in zip(members, members[1:]))
    problem = direction_problem(kinked_track([], 3000), load_tolerance_profile(), load_fastener_type(), "lateral")
    parts = independent_parts(problem, checks, classes[0])
    assert [p.windows for p in parts] == [((0, 100),), ((1000, 1100),), ((2400, 2500),)]
    assert parts[1].zone == (1000 - adjustment.PART_MARGIN, 1100 + adjustment.PART_MARGIN)
    # windows closer than the gap are one part, solved in order
    assert [p.windows for p in independent_parts(problem, checks, windows[:3])] == [tuple(windows[:3])]


class CountingExecutor(ThreadPoolExecutor):
    def __init__(self):
        super().__init__(2)
        self.tasks = 0

    def submit(self, fn, *args, **kwargs):
        self.tasks += 1
        return super().submit(fn, *args, **kwargs)


def test_parts_side_by_side_give_the_amounts_of_one_after_the_other(monkeypatch):
    """Kinks closer than a chord (one part, or two colours) and far apart (independent parts): the
    amounts through an executor (the parts as tasks that see neither the cancel token nor the
    progress, as on a cluster), through the default threads, and solved here in order are equal;
    a part that changed a sleeper outside its zone has its round solved again in order."""
    profile, fastener = load_tolerance_profile(), load_fastener_type()
    geometry = kinked_track([400, 700, 1100, 1900, 2700], 3200)
    monkeypatch.setattr(os, "cpu_count", lambda: 2)
    executor = CountingExecutor()
    with executor:
        remote = optimise_amounts(geometry, profile, fastener, executor=executor)
    assert executor.tasks >= 6  # both directions, several parts of a colour
    threads = optimise_amounts(geometry, profile, fastener)
    in_order = {}
    for direction in adjustment.DIRECTIONS:
        problem = direction_problem(geometry, profile, fastener, direction)
        in_order[direction] = adjustment._optimise_direction(problem, rail_checks(profile, direction)) * fastener.step_m
    for got in (remote, threads):
        for direction, amounts in zip(adjustment.DIRECTIONS, got):
            np.testing.assert_array_equal(amounts, in_order[direction], err_msg=direction)
    assert all(np.count_nonzero(a[m - 50:m + 50]) for a in remote for m in (400, 1900, 2700))

    solve = adjustment.solve_part_in_zone
    monkeypatch.setattr(adjustment, "solve_part_in_zone", lambda *args: (solve(*args)[0], True))
    for direction, amounts in zip(adjustment.DIRECTIONS, optimise_amounts(geometry, profile, fastener)):
        np.testing.assert_array_equal(amounts, in_order[direction], err_msg=direction)


def test_cancelled_while_the_executor_solves_the_parts():
    from insrail.progress import Cancelled

    executor = CountingExecutor()

    def cancel():  # once a part was submitted (a count of polls depends on how the work before is split)
        return executor.tasks > 0

    with executor, pytest.raises(Cancelled):
        optimise_amounts(kinked_track([400, 1900], 2400), load_tolerance_profile(), load_fastener_type(),
                         cancel=cancel, executor=executor)


def test_a_chord_check_the_survey_cannot_assess_is_not_held_there():
    """Where the survey's stated accuracy cannot resolve a chord check (insrail.project.assessable), its values
    are noise as much as track: no amount chases them and the re-assessment lists none (a hand-held MEMS survey,
    every check beyond its noise, made the whole line one programme with every row violated: minutes of HiGHS).
    Two kinks 70 sleepers apart, the second where the lateral chord checks cannot be assessed: the first one's
    programme reaches over the second, and brings only the first inside the limits."""
    profile, fastener = load_tolerance_profile(), load_fastener_type()
    geometry = kinked_track([700, 770], 1600)
    blind = np.arange(1600) >= 740
    chords = [c.name for c in profile.checks if c.kind in ("versine", "differential_versine") and "lateral" in c.directions]
    not_assessed = {(name, "lateral"): blind for name in chords}

    def chord_exceedances(lateral, vertical, masks=None):
        after, _ = reassess(geometry, lateral, vertical, profile, fastener, masks)
        return [e.first_index for e in after.exceedances if e.check in chords]

    assert chord_exceedances(*optimise_amounts(geometry, profile, fastener)) == []  # both kinks worth moving
    lateral, vertical = optimise_amounts(geometry, profile, fastener, not_assessed=not_assessed)
    assert chord_exceedances(lateral, vertical, not_assessed) == []
    left = chord_exceedances(lateral, vertical)
    assert left and min(left) >= 740  # the second kink left to itself
