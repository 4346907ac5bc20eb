"""Inertial navigation: earth model, rotations, strapdown, aided-INS filter, smoother.

Frames and conventions (written once here, used by every module of the package):

* e  : earth-centred earth-fixed (ECEF), metres.
* n  : local-level navigation frame, North-East-Down, at the current position.
* b  : IMU body frame, forward-right-down (x forward, y right, z down).
* v  : trolley (vehicle) frame, forward-right-down; x along the track in the
       direction of travel. ``C_b^v`` is built from the mounting angles.
* Attitude: Euler angles roll, pitch, heading (yaw) of b relative to n, rotation
  sequence z-y-x, so that ``C_b^n = Rz(heading) Ry(pitch) Rx(roll)``.
* DCM naming: ``C_a^b`` (written ``c_ba`` in code is avoided; functions say
  ``dcm_nav_from_body`` etc.) maps a vector resolved in frame a into frame b:
  ``v^b = C_a^b v^a``.
* Quaternions are scalar first ``[q0, q1, q2, q3]`` with the Hamilton product.
* Errors are "computed minus true". Position errors are NED metres.
* Units are SI: radians, metres, seconds. Latitude/longitude are geodetic, radians.
* IMU increments: ``dtheta = integral of omega_ib^b dt`` and
  ``dvel = integral of f^b dt`` over the sample interval ending at the time stamp.
"""
