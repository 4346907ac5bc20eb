"""Shocks in the IMU record: a wheel dropping into a rail joint's gap (thesis §5.3.1.2).

Where the trolley runs over a joint (or a raised weld) it may jump up or shift sideways, and the
non-holonomic constraint (no lateral or vertical velocity of the trolley on the rails) does not
hold for that instant; the thesis finds these instants from the accelerometer record and switches
the NHC off there. A shock is a burst of vertical specific force no push or walk makes: after
removing the specific force's moving mean over :data:`BASELINE_S`, a sample beyond
max(:data:`SHOCK_FLOOR_MPS2`, :data:`NOISE_FACTOR` x the record's robust noise). Samples closer
than :data:`SEPARATION_S` belong to one shock, placed at its largest sample. A wheel's shock rings
(the frame and the wheel bounce for tens of milliseconds), so a lone sample with no neighbour within
:data:`RINGING_SAMPLES` beyond half the threshold is no shock but a fault of that one record: relaxing
the NHC there would hide it from the integrity checks that find it (the IMU screening and the
innovations, insrail.nav.integrity).

The body frame is FRD; specific force f^b = dvel / dt with the record's nominal interval (a
sample after a gap holds one nominal interval, insrail.io).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.ndimage import uniform_filter1d

from insrail.io.types import ImuIncrements

#: The moving mean the shock stands out from: the push, the walk and the track's slopes change the
#: specific force over seconds, a joint's shock within tens of milliseconds [s].
BASELINE_S = 0.25
#: No trolley pushed along a rail changes its vertical specific force by this within a fraction of a
#: second except over a joint or a weld (the thesis's trolley: 0.1 g and more) [m/s^2].
SHOCK_FLOOR_MPS2 = 1.5
#: A shock must also stand this far above the record's own noise (its median absolute deviation).
NOISE_FACTOR = 10.0
#: Samples beyond the threshold closer than this are one shock (its ringing) [s].
SEPARATION_S = 0.3
#: A shock has at least one neighbour this close (samples) beyond half the threshold: its ringing.
RINGING_SAMPLES = 2
#: The NHC is relaxed this long either side of a shock: the wheel's bounce and the frame's ringing [s].
NHC_RELAXED_S = 0.25


@dataclass(frozen=True)
class Shocks:
    """Shocks found in an IMU record: their times [s of GPS week] and peak vertical specific force
    change [m/s^2, signed, FRD: + down]."""

    time_s: np.ndarray
    peak_mps2: np.ndarray
    threshold_mps2: float

    def __len__(self) -> int:
        return len(self.time_s)

    def nhc_relaxed_s(self) -> tuple[np.ndarray, np.ndarray]:
        """(start, end) of the intervals where the NHC does not hold."""
        return self.time_s - NHC_RELAXED_S, self.time_s + NHC_RELAXED_S


def detect_shocks(imu: ImuIncrements) -> Shocks:
    """The shocks of ``imu`` (see the module docstring)."""
    time_s = np.asarray(imu.time_s, dtype=float)
    if len(time_s) < 3:
        return Shocks(np.zeros(0), np.zeros(0), SHOCK_FLOOR_MPS2)
    dt = float(np.median(np.diff(time_s)))
    vertical = np.asarray(imu.dvel_mps, dtype=float)[:, 2] / dt
    window = max(int(round(BASELINE_S / dt)), 3)
    change = vertical - uniform_filter1d(vertical, window, mode="nearest")
    noise = 1.4826 * float(np.median(np.abs(change - np.median(change))))
    threshold = max(SHOCK_FLOOR_MPS2, NOISE_FACTOR * noise)
    beyond = np.flatnonzero(np.abs(change) > threshold)
    if not len(beyond):
        return Shocks(np.zeros(0), np.zeros(0), threshold)
    starts = np.concatenate([[0], np.flatnonzero(np.diff(time_s[beyond]) > SEPARATION_S) + 1])
    peaks = np.array([group[np.argmax(np.abs(change[group]))] for group in np.split(beyond, starts[1:])])
    ringing = np.abs(change) > 0.5 * threshold
    peaks = np.array([peak for peak in peaks if ringing[max(peak - RINGING_SAMPLES, 0):peak].any()
                      or ringing[peak + 1:peak + 1 + RINGING_SAMPLES].any()], dtype=int)
    if not len(peaks):
        return Shocks(np.zeros(0), np.zeros(0), threshold)
    # an increment integrates over the interval ending at its time stamp: the shock at its middle
    return Shocks(time_s[peaks] - 0.5 * dt, change[peaks], threshold)
