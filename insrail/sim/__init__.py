"""Trolley survey simulator: realistic raw data with a known truth.

The simulator builds a design alignment (straight, clothoid, arc, clothoid, straight,
grades with vertical curves, cant ramped on the clothoids) in an engineering plane,
puts known irregularities on it, pushes a trolley along the rails at walking speed
with stops, and writes what the trolley's sensors would record, in the documented
formats of ``insrail.io``, together with the truth:

* navigation truth of the IMU at the IMU rate (position, velocity, attitude);
* per-sleeper truth of the centreline and both rails, gauge, cant and the injected
  irregularities;
* the true sensor errors (biases, scale factors, odometer scale).

Physics: the trolley's reference point (the top of the reference rail at its gauge
face) follows the true rail as a smooth function of design station ``s``. Positions
are mapped to ECEF through the engineering CRS and a height-anomaly surface and
represented by quintic splines in ``s``; the station as a function of time is a
piecewise polynomial (C2 speed profile). Velocity, acceleration, attitude and
angular rate are derivatives of these exact functions, specific force and angular
rate are formed in the e-frame with the WGS84 earth rate and normal gravity, and the
increments are their integrals over each IMU interval by Gauss-Legendre quadrature.
The truth is therefore self-consistent to far below a micrometre; error-free
increments integrated by a strapdown reproduce the truth (tests/test_sim_physics.py).

Conventions: those of ``insrail.nav`` (n = NED, b = v = forward-right-down) and of
``insrail.track`` (station increases in the direction of travel, lateral offsets
positive to the right, vertical positive up, cant positive when the left rail is
higher).
"""
