"""Track geometry: design alignment, rails, chainage, sleepers, deviations, irregularities.

Conventions (written once here, used by every module of the package):

* Plane coordinates are engineering grid coordinates east / north [m]; heights are
  normal heights [m]. Files follow their own order: LandXML writes "north east".
* Azimuth is measured clockwise from grid north [rad], in [0, 2 pi) when reported.
* Station (chainage) increases in the direction of the alignment. Inside the core a
  station is the *continuous measure* along the alignment, starting at the
  alignment's start station (LandXML's "internal station"). Broken chainage (station
  equations) only changes the *displayed* station and its label ("DK1+695.917"),
  see :class:`insrail.track.stationing.StationEquations`.
* Lateral offsets are positive to the RIGHT of increasing station; vertical offsets
  are positive UP.
* Horizontal curvature is positive for a curve turning right (clockwise), so the
  azimuth grows with station: d(azimuth)/d(station) = curvature [1/m].
* Vertical curvature is the signed curvature of the profile in the (station,
  height) plane, positive for a sag (concave up, grade increasing) [1/m].
* Grade is d(height)/d(station), dimensionless (0.01 = 10 per mille).
* Signed design cant is positive when the LEFT rail (looking towards increasing
  station) is higher, so a right-hand curve has positive cant. Cant is in metres
  inside the core (mm in files meant for people); its base, the distance between
  the rail-head centres, is 1.5 m: cant = 1.5 m * sin(cross-level angle).
* Element boundaries carry the usual labels: TS/SC/CS/ST at tangent-spiral,
  spiral-curve, curve-spiral and spiral-tangent points (Chinese ZH/HY/YH/HZ),
  PC/PT where an arc meets a tangent directly.
* Deviations are measured minus design (or fitted) line, per rail: lateral + to the right,
  vertical + up. An adjustment amount is the movement that cancels a deviation, in the same
  signs (a rail 2 mm too far left gets +2 mm: move it right). Irregularity values (chords)
  are assigned to the chainage of their check point (thesis eq. 2.2).
* Evaluating a design quantity outside the range where it is defined raises
  ValueError; projecting a point whose foot lies beyond the alignment's ends gives
  NaN (the point is reported, not silently clamped).
"""
