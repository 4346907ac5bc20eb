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
from insrail.notices import Phrase

#: gaps longer than this [s] are bridged with the warning that the aiding carries the solution
LONG_GAP_S = 1.0


def bridge_gaps(imu: ImuIncrements, max_gap_s: float = 5.0, long_gap_s: float = LONG_GAP_S
                ) -> tuple[ImuIncrements, list[Phrase]]:
    """(the increments on a gap-free time grid, one warning per bridged gap)."""
    t = imu.time_s
    if len(t) < 3:
        return imu, []
    nominal = float(np.median(np.diff(t), overwrite_input=True))
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
        warnings.append(Phrase("{source}IMU gap of {gap_s:.3f} s after t = {time_s:.4f} s: {missing} missing samples "
                               "bridged by interpolation{aiding}",
                               {"source": source, "gap_s": step[k], "time_s": t[k], "missing": missing,
                                "aiding": Phrase("; across it the trajectory rests on the aiding (odometer, NHC, GNSS) "
                                                 "and the interpolated motion" if step[k] > long_gap_s else "")}))
        last = k + 2
    pieces_t.append(t[last:])
    pieces_th.append(imu.dtheta_rad[last:])
    pieces_dv.append(imu.dvel_mps[last:])
    bridged = replace(
        imu, time_s=np.concatenate(pieces_t), dtheta_rad=np.concatenate(pieces_th), dvel_mps=np.concatenate(pieces_dv),
        gaps=tuple(Gap(float(t[k]), float(t[k + 1])) for k in gap_at),
    )
    return bridged, warnings


#: stretches of a gap's length either side whose interpolation error stands for the gap's
NEIGHBOUR_STRETCHES = 4


def bridge_uncertainty(imu: ImuIncrements) -> list[tuple[Gap, np.ndarray, np.ndarray]]:
    """Per bridged gap of ``imu`` (its ``gaps``, after :func:`bridge_gaps`): the 1-sigma [rad, m/s]
    of the angle and velocity increment the interpolation misses over the gap, the largest axis,
    estimated from what the same interpolation misses on ``NEIGHBOUR_STRETCHES`` stretches of the
    gap's length before and after it (the trolley's rocking does not stop for a dropout). The
    filter adds it to its process noise over the gap, so its 1-sigma stays honest there."""
    t = imu.time_s
    out = []
    for gap in imu.gaps:
        length = gap.end_s - gap.start_s
        missed_theta, missed_vel = [], []
        for side in (-1, 1):
            for m in range(NEIGHBOUR_STRETCHES):
                a = gap.start_s - (m + 1) * length if side < 0 else gap.end_s + m * length
                i0, i1 = np.searchsorted(t, [a, a + length])
                if i0 < 1 or i1 >= len(t) or i1 - i0 < 2:
                    continue
                span = t[i1] - t[i0]
                for values, missed in ((imu.dtheta_rad, missed_theta), (imu.dvel_mps, missed_vel)):
                    rate_a, rate_b = values[i0] / (t[i0] - t[i0 - 1]), values[i1] / (t[i1] - t[i1 - 1])
                    missed.append(values[i0 + 1 : i1 + 1].sum(axis=0) - 0.5 * (rate_a + rate_b) * span)
        if not missed_theta:
            continue
        out.append((gap, np.sqrt(np.mean(np.square(missed_theta), axis=0)),
                    np.sqrt(np.mean(np.square(missed_vel), axis=0))))
    return out


def bridged_process_noise(imu: ImuIncrements, update_epochs: np.ndarray) -> dict[int, np.ndarray]:
    """Extra process noise (N x N, the error state of ``insrail.nav.error_model``) per filter
    segment j that ends a bridged gap of ``imu`` (segment j: IMU epochs update_epochs[j-1]+1 ..
    update_epochs[j]): attitude and velocity the variance of :func:`bridge_uncertainty`'s largest
    axis (isotropic, the body axes turn), position that velocity over half the gap."""
    from insrail.nav.error_model import ATT, N_STATES, POS, VEL

    extra: dict[int, np.ndarray] = {}
    for gap, sigma_theta, sigma_vel in bridge_uncertainty(imu):
        k = int(np.searchsorted(imu.time_s, gap.end_s - 1e-9))
        j = int(np.searchsorted(update_epochs, k))
        if not 0 < j < len(update_epochs):
            continue
        q = extra.setdefault(j, np.zeros((N_STATES, N_STATES)))
        att, vel = float(np.max(sigma_theta)) ** 2, float(np.max(sigma_vel)) ** 2
        pos = vel * (0.5 * (gap.end_s - gap.start_s)) ** 2
        for first, variance in ((ATT, att), (VEL, vel), (POS, pos)):
            q[first : first + 3, first : first + 3] += variance * np.eye(3)
    return extra
