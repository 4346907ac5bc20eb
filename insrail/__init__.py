"""insrail: office software for inertial track-geometry trolleys.

Data flows one way, stage by stage (see ``docs/architecture.md``)::

    raw files --io--> SurveyData --nav--> Trajectory --track--> rails, sleepers,
    geometry, irregularities --report--> xlsx / pdf

Conventions used everywhere in the package (each sub-package restates the ones it
uses in its own docstring):

* Units are SI inside the core: metres, seconds, radians, m/s, m/s^2. Millimetres
  and degrees appear only at the reporting edge (files the user reads, reports,
  plots) and in names that say so (``gauge_mm``).
* Time is GPS time, seconds of the GPS week, unless a name says otherwise.
* Navigation frame n = local-level North-East-Down; body frame b = the IMU's
  forward-right-down axes; vehicle frame v = the trolley's forward-right-down axes
  (x along the rails in the direction of travel).
* Attitude is roll, pitch, heading (Euler z-y-x) of b (or v) relative to n.
* Geodetic coordinates are on the ellipsoid of the project's engineering CRS (CGCS2000,
  WGS84, Xian80, Krassovsky or a custom one), one :class:`insrail.geodesy.ellipsoid.Ellipsoid`
  object handed to every stage; the GNSS positions are taken in that datum (that module's
  docstring). Latitude/longitude in radians inside the core.
"""

import os as _os

__version__ = "0.1.0"

# The pipeline runs its own threads (the fusion's passes, the covariance analysis, the rails) over small
# matrices (21 states): OpenBLAS's threads only spin-wait against them (10 km, `benchmarks/pipeline.py`:
# process 61.7 -> 49.7 s CPU, 37.0 -> 31.5 s wall with one). A value the user set is kept; it holds where
# numpy is first imported after insrail (every insrail command, the GUI, the batch's processes).
_os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
