"""The Python fusion engine the compiled one replaced (insrail.nav.fusion before issue 24), kept
as the reference the compiled engine is held to (tests/test_nav_fusion_compiled.py): the same
setup (``fusion._prepare``), then per update epoch in Python the covariance propagation with the
dense Phi of ``error_model``, the measurement models' Python methods, numpy's gated Joseph
update, the feedback, and the dense RTS pass and trajectory of the old engine."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from insrail.nav import earth, fusion
from insrail.nav.error_model import (
    ATT,
    BG,
    GNSS,
    N_STATES,
    ODO,
    POS,
    SA,
    VEL,
    discretise,
    dynamics_matrix,
    play_noise,
)
from insrail.nav.measurements import NavSnapshot
from insrail.nav.mechanization import (
    euler_from_q_bn,
    lat_lon_from_q_ne,
    q_ne_from_lat_lon,
)
from insrail.nav.rotation import quat_multiply, quat_to_dcm, rotvec_to_quat


def gated_update(x, P, z, H, R, gate):
    nu = z - H @ x
    S = H @ P @ H.T + R
    nis = float(nu @ np.linalg.solve(S, nu))
    if not nis <= gate:
        return x, P, nu, nis, False
    K = np.linalg.solve(S, H @ P).T
    x = x + K @ nu
    I_KH = np.eye(P.shape[0]) - K @ H
    return x, I_KH @ P @ I_KH.T + K @ R @ K.T, nu, nis, True


def inflate(P, states, sigma_floor):
    P = P.copy()
    P[states, states] += np.maximum(np.square(sigma_floor) - P[states, states], 0.0)
    return P


def rts_step(e_next, P_s_next, phi_next, p_minus_next, p_plus):
    A = np.linalg.solve(p_minus_next.T, (p_plus @ phi_next.T).T).T
    return A @ e_next, p_plus + A @ (P_s_next - p_minus_next) @ A.T


def feedback(nav, dx, sensor, gnss_error, odo_scale, ell):
    lat, lon = lat_lon_from_q_ne(nav[0:4])
    h = nav[4]
    r_m, r_n = earth.radii(lat, ell)
    lat -= dx[POS] / (r_m + h)
    lon -= dx[POS + 1] / ((r_n + h) * np.cos(lat))
    nav[0:4] = q_ne_from_lat_lon(lat, lon)
    nav[4] = h + dx[POS + 2]
    nav[5:8] -= dx[VEL : VEL + 3]
    q = quat_multiply(rotvec_to_quat(dx[ATT : ATT + 3]), nav[8:12])
    nav[8:12] = q / np.linalg.norm(q)
    sensor += dx[BG : SA + 3]
    gnss_error += dx[GNSS : GNSS + 3]
    return odo_scale + dx[ODO]


@dataclass
class ReferenceResult:
    trajectory: object
    forward: object
    statistics: dict
    rejections: list
    resets: list
    nis: np.ndarray
    accepted: np.ndarray


def python_fusion(imu, aiding, profile, options, ellipsoid, output_every=1, gap_returns=()) -> ReferenceResult:
    """``gap_returns``: the compiled fusion's (``info["gap_returns"]``), whose grown error its last pass ran with."""
    setup = fusion._prepare(imu, aiding, profile, options, ellipsoid)
    if gap_returns:
        setup = replace(setup, bridged_q=fusion.with_gap_noise(setup.bridged_q, tuple(gap_returns),
                                                               setup.imu.time_s[setup.epochs]))
    imu, epochs, plan = setup.imu, setup.epochs, setup.plan
    dt = np.concatenate([[setup.dt0], np.diff(imu.time_s)])
    t = imu.time_s
    n = len(imu)
    nav = np.array(setup.start.nav, dtype=float)
    k0 = setup.start.epoch
    nav_store = np.empty((n, 12))
    nav_store[: k0 + 1] = nav[:12]
    sources = plan.measurements
    P = setup.P0.copy()
    accepted = np.zeros(len(plan.epoch), dtype=bool)
    nis_all = np.full(len(plan.epoch), np.nan)
    runs = fusion._RejectionRuns(sources, options, np.sqrt(np.diag(setup.P0)))
    resets, rejections, stats = [], [], {}
    pending_reset = None
    sensor, gnss_error, odo_scale = np.zeros(12), np.zeros(3), 0.0
    m_epochs = len(epochs)
    sensor_hist = np.empty((m_epochs, 13))
    sigma_hist = np.empty((m_epochs, N_STATES))
    sensor_hist[0, :12], sensor_hist[0, 12] = sensor, odo_scale
    sigma_hist[0] = np.sqrt(np.diag(P))
    earth_c = fusion._kernels.earth_constants(ellipsoid)
    sums = np.zeros(16)
    records = []
    for j in range(1, m_epochs):
        a, b = epochs[j - 1] + 1, epochs[j] + 1
        fusion._propagate_segment(nav, imu.dtheta_rad, imu.dvel_mps, dt, a, b, sensor, earth_c, nav_store, 0, sums, 0)
        seg = sums[9]
        lat, lon = lat_lon_from_q_ne(nav[0:4])
        snap = NavSnapshot(
            time_s=t[b - 1], lat=float(lat), lon=float(lon), h=float(nav[4]), vel_ned=nav[5:8].copy(),
            c_bn=quat_to_dcm(nav[8:12]), omega_ib_b=sums[10:13] / dt[b - 1], f_b=sums[13:16] / dt[b - 1],
            mean_vel_ned=sums[0:3] / seg, mean_omega_ib_b=sums[3:6] / seg, segment_s=seg,
            odometer_scale=odo_scale, rate_span_s=dt[b - 1], ellipsoid=ellipsoid, gnss_error_ned_m=gnss_error.copy(),
        )
        F = dynamics_matrix(snap.lat, snap.h, snap.vel_ned, snap.c_bn, sums[6:9] / seg, sums[3:6] / seg,
                            setup.noise, ellipsoid)
        phi, q = discretise(F, setup.gqg, seg)
        q = q + setup.bridged_q.get(j, 0.0)
        q[:3, :3] += play_noise(sums[0:3], seg, setup.play)
        P_minus = phi @ P @ phi.T + q
        if pending_reset is not None:
            P_minus = inflate(P_minus, *pending_reset)
            pending_reset = None
        P = P_minus.copy()
        x = np.zeros(N_STATES)
        gnss_error *= math.exp(-seg / options.gnss_correlated_tau_s)
        entries = plan.at(j)
        for e in entries:
            meas, i = sources[plan.source[e]], int(plan.observation[e])
            z, H, R = meas.model(snap, i)
            gate = setup.gates[len(z)]
            x, P, nu, nis, ok = gated_update(x, P, z, H, R, gate)
            st = stats.setdefault(meas.name, fusion.MeasurementStats())
            nis_all[e] = nis
            if not ok:
                st.rejected += 1
                rejections.append(fusion.Rejection(float(meas.time_s[i]), meas.name, nis, gate, tuple(nu)))
                reset = runs.rejected(int(plan.source[e]), i, float(meas.time_s[i]), nu)
                if reset is not None:
                    reset = fusion.realign_at_reset(reset, nav, setup, options, ellipsoid)
                    resets.append(reset)
                    floors = reset.floors()
                    pending_reset = (np.flatnonzero(~np.isnan(floors)), floors[~np.isnan(floors)])
                continue
            st.add(nu, nis)
            runs.accepted(int(plan.source[e]))
            accepted[e] = True
        if len(entries):
            odo_scale = feedback(nav, x, sensor, gnss_error, odo_scale, ellipsoid)
        P = 0.5 * (P + P.T)
        records.append((phi, P_minus, P, x))
        sensor_hist[j, :12], sensor_hist[j, 12] = sensor, odo_scale
        sigma_hist[j] = np.sqrt(np.diag(P))

    forward = trajectory(t, nav_store, epochs, sensor_hist, sigma_hist, None, ellipsoid, output_every)
    smoothed = forward
    if options.smoother:
        corrections = np.zeros((m_epochs, 2, N_STATES))
        sigma = np.zeros((m_epochs, N_STATES))
        e_next = P_s_next = phi_next = p_minus_next = None
        for j in range(m_epochs - 1, 0, -1):
            phi, p_minus, p_plus, dx = records[j - 1]
            if P_s_next is None:
                e, P_s = np.zeros(N_STATES), p_plus
            else:
                e, P_s = rts_step(e_next, P_s_next, phi_next, p_minus_next, p_plus)
            corrections[j, 0], corrections[j, 1] = e, e + dx
            sigma[j] = np.sqrt(np.maximum(np.diag(P_s), 0.0))
            e_next, P_s_next, phi_next, p_minus_next = e + dx, P_s, phi, p_minus
        e, P_s = rts_step(e_next, P_s_next, phi_next, p_minus_next, setup.P0)
        corrections[0, 0] = corrections[0, 1] = e
        sigma[0] = np.sqrt(np.maximum(np.diag(P_s), 0.0))
        smoothed = trajectory(t, nav_store, epochs, sensor_hist, sigma, corrections, ellipsoid, output_every)
    return ReferenceResult(smoothed, forward, {k: s.summary() for k, s in stats.items()}, rejections, resets, nis_all,
                           accepted)


def trajectory(t, nav_store, epochs, sensor_hist, sigma_hist, corrections, ell, output_every):
    """The old engine's trajectory (the fields the comparison needs), in one piece."""
    idx = np.arange(epochs[0], epochs[-1] + 1, output_every)
    seg = np.clip(np.searchsorted(epochs, idx, side="left"), 1, len(epochs) - 1)
    left, right = epochs[seg - 1], epochs[seg]
    w = ((t[idx] - t[left]) / (t[right] - t[left]))[:, None]
    nav = nav_store[idx]
    lat, lon = lat_lon_from_q_ne(nav[:, 0:4])
    h, vel, q_bn = nav[:, 4], nav[:, 5:8], nav[:, 8:12]
    sensors = sensor_hist[seg - 1].copy()
    if corrections is not None:
        c = (1.0 - w) * corrections[seg - 1, 0] + w * corrections[seg, 1]
        r_m, r_n = earth.radii(lat, ell)
        lat = lat - c[:, POS] / (r_m + h)
        lon = lon - c[:, POS + 1] / ((r_n + h) * np.cos(lat))
        h = h + c[:, POS + 2]
        vel = vel - c[:, VEL : VEL + 3]
        q_bn = quat_multiply(rotvec_to_quat(c[:, ATT : ATT + 3]), q_bn)
        sensors[:, :12] += c[:, BG : SA + 3]
        sensors[:, 12] += c[:, ODO]
    sig = (1.0 - w) * sigma_hist[seg - 1] + w * sigma_hist[seg]
    return dict(time_s=t[idx], lat_rad=lat, lon_rad=lon, height_m=h, vel_ned_mps=vel,
                rpy_rad=np.column_stack(euler_from_q_bn(q_bn)), sigma_pos_ned_m=sig[:, POS : POS + 3],
                odometer_scale=sensors[:, 12])
