"""insrail.geodesy: engineering coordinate systems, similarity transformations, height anomaly.

Conventions (on top of the package-wide ones in ``insrail``):

* One ellipsoid type for the package (:class:`Ellipsoid`, ``insrail.geodesy.ellipsoid``: the
  named ones, and which datum the GNSS positions are taken in).
* Geodetic latitude/longitude in radians, on the ellipsoid of the CRS in use; ellipsoidal
  heights h and normal heights H in metres; height anomaly ζ = h − H.
* Plane coordinates are (east_m, north_m) in that order, whatever axis order an EPSG
  definition prefers (Chinese Gauss-Krüger zones list X = north first).
* Meridian convergence γ = grid north minus true north (positive east of the central
  meridian in the northern hemisphere); grid azimuth = geodetic azimuth − γ.
* Length distortion is (grid length / ground length − 1) in mm per km (= ppm).
* 7-parameter Helmert uses the coordinate frame rotation convention (EPSG 1032).
* Settings are plain dicts (tables of the project TOML); ``from_settings`` reports every
  problem at once as ``key.path: what is wrong`` in a ``SettingsError``.
* All errors are ``GeodesyError`` (a ``ValueError``) or subclasses.
"""

from insrail.lazy import lazy_exports

_EXPORTS = {
    "crs": ["PROJECTION_HEIGHT_CONVENTIONS", "EngineeringCRS"],
    "ellipsoid": ["ELLIPSOIDS", "Ellipsoid"],
    "errors": ["FitError", "GeodesyError", "GeoidGridError", "SettingsError"],
    "geoid": ["GeoidGrid", "PlaneGeoid", "checked_transformer", "find_egm96_grid"],
    "height_anomaly": [
        "MODELS", "CandidateFit", "ChainageSplineModel", "HeightAnomalyFit", "HeightAnomalyModel",
        "HeightAnomalySettings", "SurfaceModel", "fit_height_anomaly"
    ],
    "similarity": [
        "Helmert7", "Helmert7Fit", "Similarity2D", "Similarity2DFit", "fit_helmert_7", "fit_similarity_2d"
    ],
}
__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

__all__ = [
    "ELLIPSOIDS", "Ellipsoid", "PROJECTION_HEIGHT_CONVENTIONS", "EngineeringCRS",
    "FitError", "GeodesyError", "GeoidGridError", "SettingsError",
    "GeoidGrid", "PlaneGeoid", "checked_transformer", "find_egm96_grid",
    "MODELS", "CandidateFit", "ChainageSplineModel", "HeightAnomalyFit", "HeightAnomalyModel",
    "HeightAnomalySettings", "SurfaceModel", "fit_height_anomaly",
    "Helmert7", "Helmert7Fit", "Similarity2D", "Similarity2DFit", "fit_helmert_7", "fit_similarity_2d",
]
