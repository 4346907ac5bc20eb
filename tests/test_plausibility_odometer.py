"""The odometer's plausibility against GNSS (insrail.project.plausibility.check_odometer): a unit or a
calibration is refused, a wheel stuck or slipping for a while is not taken for one."""

from __future__ import annotations

import math

import numpy as np
import pytest

from insrail.io.errors import InputError
from insrail.io.types import GnssSolution, OdometerData
from insrail.project.plausibility import check_odometer

SPEED_MPS = 1.2


def straight_walk(duration_s: float = 300.0) -> tuple[GnssSolution, np.ndarray]:
    """A 1 Hz fixed GNSS solution walking north at SPEED_MPS from 30 deg N, and the true distance at 100 Hz."""
    time_s = 230400.0 + np.arange(0.0, duration_s + 0.5)
    n = time_s.size
    gnss = GnssSolution(time_s, math.radians(30.0) + SPEED_MPS * (time_s - time_s[0]) / 6.36e6, np.full(n, 2.0),
                        np.full(n, 30.0), np.full((n, 3), 0.01), np.ones(n, int), np.full(n, 20), np.full(n, np.nan))
    odometer_time = np.arange(time_s[0], time_s[-1], 0.01)
    return gnss, odometer_time


def odometer(time_s, speed_factor) -> OdometerData:
    """The distance of a wheel turning at ``speed_factor(t)`` times the walking speed."""
    speed = SPEED_MPS * speed_factor(time_s - time_s[0])
    return OdometerData(time_s, np.concatenate([[0.0], np.cumsum(0.5 * (speed[1:] + speed[:-1]) * np.diff(time_s))]))


@pytest.mark.parametrize(("factor", "says"), [
    (lambda t: np.full(t.shape, 1000.0), "a distance in millimetres"),
    (lambda t: np.full(t.shape, 0.92), "a distance in another unit, or a wrong calibration"),
    (lambda t: np.where((t // 30) % 3 == 0, 0.5, 1.0), "slipping wheel"),  # a third of the time at half the speed
])
def test_a_wrong_unit_scale_or_a_wheel_slipping_throughout_is_refused(factor, says):
    gnss, time_s = straight_walk()
    with pytest.raises(InputError, match=says):
        check_odometer(odometer(time_s, factor), gnss, "odometer.txt", "gnss.pos")


@pytest.mark.parametrize("factor", [
    lambda t: np.where((t > 150.0) & (t < 165.0), 0.0, 1.0),  # stuck for 15 s (it took a 300 m survey's ratio to 0.94)
    lambda t: np.where((t > 150.0) & (t < 170.0), 0.5, 1.0),  # slipping for 20 s
    lambda t: np.full(t.shape, 1.02),  # a calibration 2 % off: the fusion estimates it
])
def test_a_wheel_stuck_or_slipping_for_a_while_is_left_to_the_fusion(factor):
    gnss, time_s = straight_walk()
    assert check_odometer(odometer(time_s, factor), gnss, "odometer.txt", "gnss.pos") == []
