"""Rails from pose: the trolley's fused trajectory -> 3-D points of both rails and the centreline.

The IMU pose (geodetic position, attitude of the body frame b relative to NED) and the
trolley's calibrated geometry give, per epoch:

* the reference-rail point  P_ref = P_imu + C_b^n l_ref  (l_ref = imu_to_reference_rail_m,
  the top-of-rail point above the gauge face of the rail the fixed wheels run on);
* the other rail            P_other = P_ref +/- g y_v   (g = measured gauge, y_v = the trolley's
  cross axis: the y axis of v in the running plane, + for a left reference rail);
* the centreline            C = (P_left + P_right) / 2.

The gauge is measured 16 mm below the rail tops, between the gauge faces; both faces lie
16 mm below their top points along the running plane's normal, so the distance between the
top points above the faces is the gauge itself and needs no correction for cant.

Cross slope and cant: the running plane's cross slope phi has sin(phi) = the downward
component of y_v (the y axis points down the slope when the left rail is high), and the
measured cant is ``rail_centre_spacing_m * sin(phi)``, positive when the LEFT rail is higher
(see :mod:`insrail.track`). The conversion to engineering coordinates is the caller's
``to_engineering(lat_rad, lon_rad, h_m) -> (east_m, north_m, normal_height_m)`` (the project's
EngineeringCRS plus its height-anomaly model), so this module needs no project.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace

import numpy as np

from insrail.io.survey import TrolleyGeometry
from insrail.io.types import GaugeData
from insrail.nav import earth
from insrail.nav.rotation import euler_to_dcm
from insrail.nav.trajectory import Trajectory

ToEngineering = Callable[[np.ndarray, np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray, np.ndarray]]

#: The fields of the trajectory the rails are made of (:func:`rails_from_pose`; the sleepers'
#: attitude takes ``rpy_rad`` too): a long survey's trajectory is read with just these
#: (``insrail.nav.trajectory.load_trajectory(..., only=POSE_FIELDS)``).
POSE_FIELDS = ("time_s", "lat_rad", "lon_rad", "height_m", "rpy_rad", "sigma_pos_ned_m", "sigma_rpy_rad")

#: Epochs converted at a time: bounds the memory of the per-epoch rotation matrices.
CHUNK_EPOCHS = 200_000

#: Along-track base over which the path curvature for the gauge curve correction is differenced [m]:
#: long enough to average out the curvature of the rail's own short-wave irregularities
#: (1 mm at 5 m wavelength is a curvature of 1.6e-3 1/m, more than a 2000 m curve's).
CURVATURE_BASE_M = 10.0


@dataclass(frozen=True)
class RailPoints:
    """Per-epoch rail geometry in the engineering frame (arrays (n,) or (n, 3) = E, N, H [m]).

    ``forward_enh`` is the unit x axis of the trolley (direction of its fixed wheels' rail) in
    the engineering frame; ``gauge_m`` already includes the curve correction if one was applied.
    Epochs without a gauge reading (outside the gauge record or in one of its gaps) hold NaN
    for the non-reference rail, the centreline and the gauge.
    """

    time_s: np.ndarray
    reference_rail: str
    left_rail_enh_m: np.ndarray
    right_rail_enh_m: np.ndarray
    centre_enh_m: np.ndarray
    forward_enh: np.ndarray
    gauge_m: np.ndarray
    cross_slope_rad: np.ndarray
    cant_m: np.ndarray
    sigma_pos_ned_m: np.ndarray
    sigma_roll_rad: np.ndarray

    @property
    def reference_rail_enh_m(self) -> np.ndarray:
        return self.left_rail_enh_m if self.reference_rail == "left" else self.right_rail_enh_m

    def __len__(self) -> int:
        return len(self.time_s)


def gauge_curve_correction_m(curvature_per_m, beam_wheel_spacing_m: float, beam_rail: str) -> np.ndarray:
    """Curve correction Delta d of the gauge measured from a twin-wheel beam (thesis eq. 5.2).

    The beam's two side wheels, ``beam_wheel_spacing_m`` apart, lean on the gauge face of
    ``beam_rail`` ("left" or "right"); the gauge is measured from the midpoint of the chord
    between them, which lies a versine |Delta d| = R - sqrt(R^2 - d_w^2 / 4) inside the rail's
    circle. On the outer rail of a curve that point is closer to the other rail (the reading is
    short: Delta d > 0); on the inner rail it is farther away (Delta d < 0); 0 on straights.
    ``curvature_per_m`` is signed as in :mod:`insrail.track` (positive turning right, so the
    left rail is outer). Returns the correction to ADD to the reading [m].
    """
    if beam_rail not in ("left", "right"):
        raise ValueError(f"beam_rail must be 'left' or 'right', not {beam_rail!r}")
    if not beam_wheel_spacing_m >= 0.0:
        raise ValueError(f"beam_wheel_spacing_m must be >= 0, not {beam_wheel_spacing_m!r}")
    kappa = np.asarray(curvature_per_m, dtype=float)
    half_chord = 0.5 * beam_wheel_spacing_m
    # R - sqrt(R^2 - c^2) written without the cancellation: kappa c^2 / (1 + sqrt(1 - kappa^2 c^2))
    versine = np.abs(kappa) * half_chord**2 / (1.0 + np.sqrt(1.0 - (kappa * half_chord) ** 2))
    outer_is_left = kappa > 0.0
    on_outer = outer_is_left if beam_rail == "left" else ~outer_is_left & (kappa != 0.0)
    return np.where(on_outer, versine, -versine)


def gauge_at_times(gauge: GaugeData, time_s: np.ndarray) -> np.ndarray:
    """Gauge readings linearly interpolated to ``time_s``; NaN outside the record and in its gaps."""
    t = np.asarray(time_s, dtype=float)
    if len(gauge) < 2:
        raise ValueError(f"{gauge.source or 'gauge data'}: at least two gauge readings are needed, got {len(gauge)}")
    values = np.interp(t, gauge.time_s, gauge.gauge_m, left=np.nan, right=np.nan)
    for gap in gauge.gaps:
        values[(t > gap.start_s) & (t < gap.end_s)] = np.nan
    return values


def path_curvature_per_m(forward_enh: np.ndarray, east_m: np.ndarray, north_m: np.ndarray,
                         base_m: float = CURVATURE_BASE_M) -> np.ndarray:
    """Horizontal curvature of a point's path (positive turning right) from the change of the
    trolley's azimuth over ``base_m`` of travelled plane distance (robust to stops)."""
    step = np.hypot(np.diff(east_m), np.diff(north_m))
    travelled = np.concatenate([[0.0], np.cumsum(step)])
    azimuth = np.unwrap(np.arctan2(forward_enh[:, 0], forward_enh[:, 1]))
    ahead = np.interp(travelled + 0.5 * base_m, travelled, azimuth)
    behind = np.interp(travelled - 0.5 * base_m, travelled, azimuth)
    span = np.interp(travelled + 0.5 * base_m, travelled, travelled) - np.interp(travelled - 0.5 * base_m, travelled, travelled)
    return np.where(span > 0.0, (ahead - behind) / np.where(span > 0.0, span, 1.0), 0.0)


def curve_corrected_gauge(gauge: GaugeData, north_m: np.ndarray, east_m: np.ndarray, forward_ne: np.ndarray,
                          beam_wheel_spacing_m: float, beam_rail: str) -> GaugeData:
    """The gauge record with the curve correction (:func:`gauge_curve_correction_m`) added to each
    reading; ``north_m``, ``east_m`` (a local plane [m]) and ``forward_ne`` (the trolley's x axis,
    north and east components) are the trolley's path at the readings' times. The curvature is
    the path's over :data:`CURVATURE_BASE_M`, signed for travel along the trolley's x axis (a run
    pushed backwards, x against the travel, turns the other way per metre travelled)."""
    forward_enh = np.column_stack([forward_ne[:, 1], forward_ne[:, 0], np.zeros(len(north_m))])
    curvature = path_curvature_per_m(forward_enh, east_m, north_m)
    along_x = np.sum(np.diff(east_m) * forward_enh[1:, 0] + np.diff(north_m) * forward_enh[1:, 1])
    if along_x < 0.0:
        curvature = -curvature
    correction = gauge_curve_correction_m(curvature, beam_wheel_spacing_m, beam_rail)
    return replace(gauge, gauge_m=np.asarray(gauge.gauge_m, dtype=float) + correction)


def _trolley_axes_enh(trajectory: Trajectory, part: slice, trolley: TrolleyGeometry,
                      to_engineering: ToEngineering, ell: earth.Ellipsoid):
    """Reference-rail point, the trolley's unit x and y axes in the engineering frame, and the
    sine of the running plane's cross slope, for the epochs ``part``.

    The axes are the grid images of 1 m steps from the rail point: the map is conformal and,
    over the 1.4 m of a gauge, linear to 1e-7 m, so the other rail is the rail point plus the
    gauge times the mapped y axis.
    """
    lat, lon, h = trajectory.lat_rad[part], trajectory.lon_rad[part], trajectory.height_m[part]
    rpy = trajectory.rpy_rad[part]
    c_nb = euler_to_dcm(rpy[:, 0], rpy[:, 1], rpy[:, 2])
    c_eb = earth.dcm_ecef_from_ned(lat, lon) @ c_nb
    # Trolley axes in b: rows of C_b^v are v's axes expressed in b.
    c_vb = euler_to_dcm(*np.asarray(trolley.mounting_rpy_rad, dtype=float))
    x_v_b, y_v_b = c_vb[0], c_vb[1]
    ref_e = earth.geodetic_to_ecef(lat, lon, h, ell) + c_eb @ trolley.lever_arm_m("imu_to_reference_rail_m")

    def engineering(points_e: np.ndarray) -> np.ndarray:
        la, lo, hh = earth.ecef_to_geodetic(points_e, ell)
        return np.column_stack(to_engineering(la, lo, hh))

    ref = engineering(ref_e)
    forward = engineering(ref_e + c_eb @ x_v_b) - ref
    forward /= np.linalg.norm(forward, axis=1)[:, None]
    cross = engineering(ref_e + c_eb @ y_v_b) - ref
    sin_slope = np.clip((c_nb @ y_v_b)[:, 2], -1.0, 1.0)
    return ref, forward, cross, sin_slope


def rails_from_pose(
    trajectory: Trajectory,
    trolley: TrolleyGeometry,
    gauge: GaugeData,
    to_engineering: ToEngineering,
    beam_wheel_spacing_m: float = 0.0,
    curvature_per_m: np.ndarray | None = None,
) -> RailPoints:
    """Both rails and the centreline at every trajectory epoch (see the module docstring).

    ``beam_wheel_spacing_m`` > 0 applies the gauge curve correction
    (:func:`gauge_curve_correction_m`) with the beam on the reference rail; the curvature per
    epoch is ``curvature_per_m`` (e.g. the design's at each epoch's station, as the thesis does)
    or, when None, that of the reference rail's measured path over :data:`CURVATURE_BASE_M`.
    0 (default) leaves the readings as they are. The lever arms go through ECEF on the
    trajectory's ellipsoid (``trajectory.ellipsoid``, the one the fusion ran on).
    """
    if trolley.reference_rail not in ("left", "right"):
        raise ValueError(f"trolley.reference_rail must be 'left' or 'right', not {trolley.reference_rail!r}")
    n = len(trajectory)
    ref, forward, cross = np.empty((n, 3)), np.empty((n, 3)), np.empty((n, 3))
    sin_slope = np.empty(n)
    for start in range(0, n, CHUNK_EPOCHS):
        part = slice(start, min(start + CHUNK_EPOCHS, n))
        ref[part], forward[part], cross[part], sin_slope[part] = _trolley_axes_enh(
            trajectory, part, trolley, to_engineering, trajectory.ellipsoid)

    gauge_m = gauge_at_times(gauge, trajectory.time_s)
    if beam_wheel_spacing_m:
        curvature = (path_curvature_per_m(forward, ref[:, 0], ref[:, 1]) if curvature_per_m is None
                     else np.asarray(curvature_per_m, dtype=float))
        gauge_m = gauge_m + gauge_curve_correction_m(curvature, beam_wheel_spacing_m, trolley.reference_rail)
    side = 1.0 if trolley.reference_rail == "left" else -1.0
    other = ref + side * gauge_m[:, None] * cross
    left, right = (ref, other) if side > 0 else (other, ref)
    cant = trolley.rail_centre_spacing_m * sin_slope
    return RailPoints(
        time_s=np.asarray(trajectory.time_s, dtype=float),
        reference_rail=trolley.reference_rail,
        left_rail_enh_m=left,
        right_rail_enh_m=right,
        centre_enh_m=0.5 * (left + right),
        forward_enh=forward,
        gauge_m=gauge_m,
        cross_slope_rad=np.arcsin(sin_slope),
        cant_m=cant,
        sigma_pos_ned_m=np.asarray(trajectory.sigma_pos_ned_m, dtype=float),
        sigma_roll_rad=np.asarray(trajectory.sigma_rpy_rad, dtype=float)[:, 0],
    )
