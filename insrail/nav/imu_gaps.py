"""Bridging short gaps in the IMU increments.

A gap in a trolley logger's IMU stream means samples were lost: each sample that is
there still holds the increments of one nominal interval. Left alone, the strapdown
would integrate the sample after the gap over the whole gap (the ImuIncrements
contract) and lose the motion inside it. Gaps up to ``max_gap_s`` are therefore filled
with samples whose rates are interpolated linearly between the neighbours, and each
bridged gap is reported; longer gaps are refused with the place and length named.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from insrail.io.types import Gap, ImuIncrements


def bridge_gaps(imu: ImuIncrements, max_gap_s: float = 1.0) -> tuple[ImuIncrements, list[str]]:
    """(the increments on a gap-free time grid, one warning per bridged gap)."""
    t = imu.time_s
    if len(t) < 3:
        return imu, []
    nominal = float(np.median(np.diff(t)))
    step = np.diff(t)
    gap_at = np.flatnonzero(step > 1.5 * nominal)
    if gap_at.size == 0:
        return imu, []
    source = f"{imu.source}: " if imu.source else ""
    too_long = [k for k in gap_at if step[k] > max_gap_s]
    if too_long:
        k = too_long[0]
        raise ValueError(
            f"{source}IMU data gap of {step[k]:.3f} s after t = {t[k]:.4f} s (sample {k + 1}); gaps longer than "
            f"{max_gap_s:g} s cannot be bridged - split the survey there or repair the recording"
        )
    pieces_t, pieces_th, pieces_dv, warnings = [], [], [], []
    last = 0
    for k in gap_at:
        missing = int(round(step[k] / nominal)) - 1
        pieces_t.append(t[last : k + 1])
        pieces_th.append(imu.dtheta_rad[last : k + 1])
        pieces_dv.append(imu.dvel_mps[last : k + 1])
        frac = (np.arange(1, missing + 1) / (missing + 1))[:, None]
        pieces_t.append(t[k] + nominal * np.arange(1, missing + 1))
        pieces_th.append((1 - frac) * imu.dtheta_rad[k] + frac * imu.dtheta_rad[k + 1])
        pieces_dv.append((1 - frac) * imu.dvel_mps[k] + frac * imu.dvel_mps[k + 1])
        warnings.append(
            f"{source}IMU gap of {step[k]:.3f} s after t = {t[k]:.4f} s: {missing} missing samples bridged by interpolation"
        )
        last = k + 1
    pieces_t.append(t[last:])
    pieces_th.append(imu.dtheta_rad[last:])
    pieces_dv.append(imu.dvel_mps[last:])
    time_s = np.concatenate(pieces_t)
    bridged = replace(
        imu, time_s=time_s, dtheta_rad=np.concatenate(pieces_th), dvel_mps=np.concatenate(pieces_dv),
        gaps=tuple(Gap(float(t[k]), float(t[k + 1])) for k in gap_at),
    )
    return bridged, warnings
