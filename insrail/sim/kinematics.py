"""Exact kinematics of a trolley riding a rail, and the true IMU increments.

The trolley's reference point (top of the reference rail at its gauge face) is given
in ECEF at stations on a fine uniform grid, with the roll of the running plane.
Quintic interpolating splines in station make the path and the attitude smooth
functions; with the station as a closed-form function of time (``motion``) every
derivative is analytic. Attitude of the trolley frame v: heading and pitch from the
path tangent in the local NED frame, roll from the running plane; the IMU frame b is
v rotated by the mounting angles, and the IMU sits at ``-C_b^e l`` from the rail
point, l being the IMU-to-rail lever arm in b.

Body play: the trolley frame need not point exactly along the rail. Optional small
pitch and yaw deviations (functions of station, on the same grid) turn the frame about
the reference rail point, which stays on the rail; so the rail point's velocity has a
small vertical and lateral component in the trolley frame, the physical content of the
non-holonomic constraint's noise. The IMU position follows from the deviated attitude,
so position, attitude, rates and increments remain one consistent motion.

Angular rate and specific force (e-frame mechanisation, no approximation):
    omega_ib^b = omega_nb^b + C_n^b (omega_ie^n + omega_en^n)        (n at the rail point)
    f^b        = C_e^b (a^e + 2 omega_ie^e x v^e - g^e)              (at the IMU)
with a^e, v^e the IMU's acceleration and velocity relative to the earth and g^e the
normal gravity vector along the ellipsoid normal at the IMU.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import make_interp_spline

from insrail.nav import earth
from insrail.nav.rotation import euler_rates_to_body_rate, euler_to_dcm, dcm_to_euler
from insrail.sim.motion import SpeedProfile

# Gauss-Legendre nodes and weights on [-1, 1]: 4 points integrate degree-7 polynomials
# exactly; over a 5 ms interval the trolley's motion is far smoother than that.
_GL_NODES, _GL_WEIGHTS = np.polynomial.legendre.leggauss(4)


@dataclass(frozen=True)
class KinematicState:
    """True state of the IMU at a set of times (ECEF quantities relative to the earth)."""

    position_ecef_m: np.ndarray  # (n, 3)
    velocity_ecef_mps: np.ndarray  # (n, 3)
    dcm_ecef_from_body: np.ndarray  # (n, 3, 3) C_b^e
    omega_ib_body_radps: np.ndarray  # (n, 3)
    specific_force_body_mps2: np.ndarray  # (n, 3)


class TrolleyKinematics:
    """Smooth trajectory of the trolley and its IMU as functions of station and time."""

    def __init__(
        self,
        station_m: np.ndarray,
        rail_ecef_m: np.ndarray,
        running_plane_roll_rad: np.ndarray,
        imu_to_rail_body_m: np.ndarray,
        dcm_vehicle_from_body: np.ndarray,
        profile: SpeedProfile,
        ellipsoid: earth.Ellipsoid = earth.WGS84,
        play_pitch_yaw_rad: np.ndarray | None = None,
    ):
        self.ellipsoid = ellipsoid
        self.profile = profile
        self.c_vb = np.asarray(dcm_vehicle_from_body, dtype=float)
        self.origin = rail_ecef_m[0].copy()  # splines hold offsets: keeps full precision
        self._rail = make_interp_spline(station_m, rail_ecef_m - self.origin, k=5)
        self._rail_d1 = self._rail.derivative(1)

        lat, lon, _ = earth.ecef_to_geodetic(rail_ecef_m, ellipsoid)
        c_ne = earth.dcm_ecef_from_ned(lat, lon)
        tangent_n = np.einsum("nji,nj->ni", c_ne, self._rail_d1(station_m))
        heading = np.unwrap(np.arctan2(tangent_n[:, 1], tangent_n[:, 0]))
        pitch = np.arctan2(-tangent_n[:, 2], np.hypot(tangent_n[:, 0], tangent_n[:, 1]))
        # The running plane's cross slope is measured from the horizontal; the Euler
        # roll follows the pitched x axis: sin(cross slope) = sin(roll) cos(pitch).
        roll = np.arcsin(np.sin(running_plane_roll_rad) / np.cos(pitch))
        if play_pitch_yaw_rad is not None:
            pitch = pitch + play_pitch_yaw_rad[:, 0]
            heading = heading + play_pitch_yaw_rad[:, 1]
        self._euler = make_interp_spline(station_m, np.column_stack([roll, pitch, heading]), k=5)
        self._euler_d1 = self._euler.derivative(1)

        c_be = c_ne @ euler_to_dcm(roll, pitch, heading) @ self.c_vb
        imu = rail_ecef_m - c_be @ np.asarray(imu_to_rail_body_m, dtype=float)
        self._imu = make_interp_spline(station_m, imu - self.origin, k=5)
        self._imu_d1 = self._imu.derivative(1)
        self._imu_d2 = self._imu.derivative(2)

    def state(self, t) -> KinematicState:
        """True IMU state at times ``t`` [s]."""
        ell = self.ellipsoid
        s, s_dot, s_ddot = self.profile.evaluate(t)

        rail = self._rail(s) + self.origin
        lat_r, lon_r, h_r = earth.ecef_to_geodetic(rail, ell)
        c_ne_r = earth.dcm_ecef_from_ned(lat_r, lon_r)
        v_rail_n = np.einsum("nji,nj->ni", c_ne_r, self._rail_d1(s) * s_dot[:, None])

        euler = self._euler(s)
        euler_rate = self._euler_d1(s) * s_dot[:, None]
        c_vn = euler_to_dcm(euler[:, 0], euler[:, 1], euler[:, 2])
        c_bn = c_vn @ self.c_vb
        omega_nv_v = euler_rates_to_body_rate(euler[:, 0], euler[:, 1], *euler_rate.T)
        omega_nb_b = omega_nv_v @ self.c_vb  # C_v^b omega = (C_b^v)^T omega, row form
        omega_in_n = earth.earth_rate_ned(lat_r, ell) + earth.transport_rate_ned(lat_r, h_r, v_rail_n, ell)
        omega_ib_b = omega_nb_b + np.einsum("nji,nj->ni", c_bn, omega_in_n)
        c_be = c_ne_r @ c_bn

        pos = self._imu(s) + self.origin
        vel = self._imu_d1(s) * s_dot[:, None]
        acc = self._imu_d2(s) * (s_dot**2)[:, None] + self._imu_d1(s) * s_ddot[:, None]
        lat_i, lon_i, h_i = earth.ecef_to_geodetic(pos, ell)
        g_e = earth.dcm_ecef_from_ned(lat_i, lon_i)[:, :, 2] * earth.normal_gravity(lat_i, h_i, ell)[:, None]
        omega_ie_e = np.array([0.0, 0.0, ell.omega])
        f_e = acc + 2.0 * np.cross(omega_ie_e, vel) - g_e
        f_b = np.einsum("nji,nj->ni", c_be, f_e)
        return KinematicState(pos, vel, c_be, omega_ib_b, f_b)

    def increments(self, t_end, dt: float, wheel_lever_arm_body_m=None):
        """Exact (dtheta [rad], dvel [m/s], wheel path [m]) over the intervals (t_end - dt, t_end].

        dtheta and dvel are in the body frame. The wheel path is the distance travelled
        over each interval by the point at ``wheel_lever_arm_body_m`` from the IMU (the
        odometer wheel's contact with the rail), None when no lever arm is given; for k lever
        arms (a (k, 3) array: two odometers) one column each, (n, k). The
        quadrature weights use ``dt`` itself: an interval length taken as the difference of
        two GPS times of week (about 2e5 s) would be off by up to 3e-11 s, a systematic
        micro-Gal in the increments.
        """
        t_end = np.asarray(t_end, dtype=float)
        half = 0.5 * dt
        nodes = (t_end[:, None] - half * (1.0 - _GL_NODES)).ravel()
        st = self.state(nodes)
        w = np.tile(half * _GL_WEIGHTS, len(t_end))[:, None]
        n, m = len(t_end), len(_GL_NODES)
        dtheta = (st.omega_ib_body_radps * w).reshape(n, m, 3).sum(axis=1)
        dvel = (st.specific_force_body_mps2 * w).reshape(n, m, 3).sum(axis=1)
        wheel_path = None
        if wheel_lever_arm_body_m is not None:
            levers = np.asarray(wheel_lever_arm_body_m, dtype=float)
            paths = [(np.linalg.norm(self._point_velocity(st, lever), axis=1) * w[:, 0]).reshape(n, m).sum(axis=1)
                     for lever in np.atleast_2d(levers)]
            wheel_path = paths[0] if levers.ndim == 1 else np.column_stack(paths)
        return dtheta, dvel, wheel_path

    def _point_velocity(self, st: KinematicState, lever_arm_body_m) -> np.ndarray:
        """ECEF velocity of the point at ``lever_arm_body_m`` from the IMU: v + C_b^e (omega_eb^b x l)."""
        lever = np.asarray(lever_arm_body_m, dtype=float)
        omega_ie_b = np.einsum("nji,j->ni", st.dcm_ecef_from_body, np.array([0.0, 0.0, self.ellipsoid.omega]))
        omega_eb_b = st.omega_ib_body_radps - omega_ie_b
        return st.velocity_ecef_mps + np.einsum("nij,nj->ni", st.dcm_ecef_from_body, np.cross(omega_eb_b, lever))

    def navigation_truth(self, t):
        """IMU truth at ``t``: (lat, lon, h, vel_ned, roll, pitch, heading), the attitude
        of b relative to the NED frame at the IMU."""
        st = self.state(t)
        lat, lon, h = earth.ecef_to_geodetic(st.position_ecef_m, self.ellipsoid)
        c_en = np.swapaxes(earth.dcm_ecef_from_ned(lat, lon), -1, -2)
        vel_ned = np.einsum("nij,nj->ni", c_en, st.velocity_ecef_mps)
        roll, pitch, heading = dcm_to_euler(c_en @ st.dcm_ecef_from_body)
        return lat, lon, h, vel_ned, roll, pitch, heading

    def point_ecef(self, t, lever_arm_body_m):
        """ECEF position and velocity of a point fixed on the trolley at ``lever_arm_body_m`` from the IMU."""
        st = self.state(t)
        pos = st.position_ecef_m + st.dcm_ecef_from_body @ np.asarray(lever_arm_body_m, dtype=float)
        return pos, self._point_velocity(st, lever_arm_body_m)
