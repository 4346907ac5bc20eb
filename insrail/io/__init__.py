"""Readers and writers of raw survey data, one function per format.

Conventions: time stamps are GPS seconds of the week (a series that crosses the
end of a week keeps counting past 604800 s from the week of its first stamp);
body frame b is the IMU's forward-right-down; positions in files are geodetic
degrees and ellipsoidal metres unless the format says otherwise (prism
observations are in the engineering frame); gauge files are in mm, everything
returned is SI. Every reader raises :class:`~insrail.io.errors.InputError` naming
the file, the line and what was expected; none lets a bare numpy/parser traceback
through. Every writer writes atomically (:func:`~insrail.io.atomic.atomic_write`).
Formats are registered by name in :mod:`insrail.io.formats`; docs/formats.md
describes each one.
"""

from insrail.lazy import lazy_exports

_EXPORTS = {
    "atomic": ["atomic_write"],
    "control": ["read_benchmarks", "read_prism_enu", "write_benchmarks", "write_prism_enu"],
    "errors": ["InputError", "ManifestError"],
    "formats": ["FORMATS", "FileFormat", "detect_format", "read_any"],
    "gnss": ["read_gnss_kfgins", "write_gnss_kfgins"],
    "imu": ["read_imu_kfgins", "read_imu_npy", "read_imu_rates_csv", "write_imu_kfgins", "write_imu_npy"],
    "odometer": [
        "read_odometer_distance", "read_odometer_pulses", "write_odometer_distance", "write_odometer_pulses"
    ],
    "rtklib": ["read_rtklib_pos", "write_rtklib_pos"],
    "survey": ["read_manifest", "read_survey", "write_manifest"],
    "track_sensors": ["read_gauge_mm", "read_gauge_volts", "read_sleeper_times", "write_gauge_mm", "write_sleeper_times"],
}
__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS)

__all__ = [
    "FORMATS", "FileFormat", "InputError", "ManifestError", "atomic_write", "detect_format", "read_any",
    "read_benchmarks", "read_gauge_mm", "read_gauge_volts", "read_gnss_kfgins", "read_imu_kfgins", "read_imu_npy",
    "read_imu_rates_csv", "read_manifest", "read_odometer_distance", "read_odometer_pulses",
    "read_prism_enu", "read_rtklib_pos", "read_sleeper_times", "read_survey", "write_benchmarks",
    "write_gauge_mm", "write_gnss_kfgins", "write_imu_kfgins", "write_imu_npy", "write_manifest",
    "write_odometer_distance", "write_odometer_pulses", "write_prism_enu", "write_rtklib_pos",
    "write_sleeper_times",
]
