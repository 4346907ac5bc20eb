"""Bridging gaps in the IMU increments: the one place where missing IMU records are filled.

A gap in a trolley logger's IMU stream means records were lost (a dropout) or removed as
outliers (:mod:`insrail.nav.imu_screening`). The contract every IMU reader keeps
(:class:`insrail.io.types.ImuIncrements`): the record after a gap still holds the increments of
one nominal interval, not of the whole gap (a rates reader does not integrate across a dropout).
Left alone, the strapdown would integrate that record over the whole gap and lose the motion
inside it. Gaps up to ``max_gap_s`` are therefore filled with records whose rates are
interpolated linearly between the neighbours, evenly spaced over the gap; the record after the
gap is rescaled to its new interval so its rates are kept. Each bridged gap is a notice; a gap
longer than ``long_gap_s`` is said to rest on the aiding (odometer, NHC, GNSS) across it. Longer
than ``max_gap_s`` is an error with the place and length named.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from insrail.io.types import GAP_FACTOR, Gap, ImuIncrements

#: gaps longer than this [s] are bridged with the warning that the aiding carries the solution
LONG_GAP_S = 1.0


def bridge_gaps(imu: ImuIncrements, max_gap_s: float = 5.0, long_gap_s: float = LONG_GAP_S
                ) -> tuple[ImuIncrements, list[str]]:
    """(the increments on a gap-free time grid, one warning per bridged gap)."""
    t = imu.time_s
    if len(t) < 3:
        return imu, []
    nominal = float(np.median(np.diff(t)))
    step = np.diff(t)
    gap_at = np.flatnonzero(step > GAP_FACTOR * nominal)
    if gap_at.size == 0:
        return imu, []
    source = f"{imu.source}: " if imu.source else ""
    too_long = [k for k in gap_at if step[k] > max_gap_s]
    if too_long:
        k = too_long[0]
        raise ValueError(
            f"{source}IMU data gap of {step[k]:.3f} s after t = {t[k]:.4f} s (record {k + 1}); gaps longer than "
            f"{max_gap_s:g} s cannot be bridged - split the survey there or repair the recording"
        )
    pieces_t, pieces_th, pieces_dv, warnings = [], [], [], []
    last = 0
    for k in gap_at:
        missing = int(round(step[k] / nominal)) - 1
        spacing = step[k] / (missing + 1)
        pieces_t.append(t[last : k + 1])
        pieces_th.append(imu.dtheta_rad[last : k + 1])
        pieces_dv.append(imu.dvel_mps[last : k + 1])
        frac = (np.arange(1, missing + 1) / (missing + 1))[:, None]
        scale = spacing / nominal  # the neighbours hold one nominal interval each
        pieces_t.append(t[k] + spacing * np.arange(1, missing + 1))
        pieces_th.append(scale * ((1 - frac) * imu.dtheta_rad[k] + frac * imu.dtheta_rad[k + 1]))
        pieces_dv.append(scale * ((1 - frac) * imu.dvel_mps[k] + frac * imu.dvel_mps[k + 1]))
        pieces_t.append(t[k + 1 : k + 2])
        pieces_th.append(scale * imu.dtheta_rad[k + 1 : k + 2])
        pieces_dv.append(scale * imu.dvel_mps[k + 1 : k + 2])
        message = (f"{source}IMU gap of {step[k]:.3f} s after t = {t[k]:.4f} s: {missing} missing samples bridged "
                   "by interpolation")
        if step[k] > long_gap_s:
            message += ("; across it the trajectory rests on the aiding (odometer, NHC, GNSS) and the "
                        "interpolated motion")
        warnings.append(message)
        last = k + 2
    pieces_t.append(t[last:])
    pieces_th.append(imu.dtheta_rad[last:])
    pieces_dv.append(imu.dvel_mps[last:])
    bridged = replace(
        imu, time_s=np.concatenate(pieces_t), dtheta_rad=np.concatenate(pieces_th), dvel_mps=np.concatenate(pieces_dv),
        gaps=tuple(Gap(float(t[k]), float(t[k + 1])) for k in gap_at),
    )
    return bridged, warnings
