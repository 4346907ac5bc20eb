"""Faults a real GNSS solution carries, put into a clean (simulated) one: the test cases of the
fusion's integrity (``benchmarks/integrity.py``, ``tests/test_nav_integrity.py``).

Each function returns a new ``GnssSolution``; offsets are NED metres, times seconds of week.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from insrail.io.types import GnssSolution
from insrail.nav import earth


def _shifted(gnss: GnssSolution, mask: np.ndarray, offset_ned_m: np.ndarray) -> GnssSolution:
    """The positions of the epochs in ``mask`` moved by ``offset_ned_m`` ((3,) or (k, 3))."""
    r_m, r_n = earth.radii(gnss.lat_rad[mask])
    offset = np.broadcast_to(offset_ned_m, (int(mask.sum()), 3))
    lat, lon, h = gnss.lat_rad.copy(), gnss.lon_rad.copy(), gnss.height_m.copy()
    lat[mask] += offset[:, 0] / (r_m + h[mask])
    lon[mask] += offset[:, 1] / ((r_n + h[mask]) * np.cos(gnss.lat_rad[mask]))
    h[mask] -= offset[:, 2]
    return replace(gnss, lat_rad=lat, lon_rad=lon, height_m=h)


def false_fix(gnss: GnssSolution, start_s: float, duration_s: float, offset_ned_m) -> GnssSolution:
    """A wrong ambiguity fix: a constant offset for ``duration_s`` while the flag still says fix
    (Q = 1) and the sigmas stay those of a fix."""
    mask = (gnss.time_s >= start_s) & (gnss.time_s < start_s + duration_s)
    out = _shifted(gnss, mask, np.asarray(offset_ned_m, dtype=float))
    return replace(out, quality=np.where(mask, 1, gnss.quality))


def float_stretch(gnss: GnssSolution, start_s: float, duration_s: float, error_m: float, seed: int = 0) -> GnssSolution:
    """A float stretch (Q = 2): an error wandering smoothly with an RMS of ``error_m`` per axis,
    sigmas as the file had them for the fix (the float solution's own sigmas are often optimistic)."""
    mask = (gnss.time_s >= start_s) & (gnss.time_s < start_s + duration_s)
    k = int(mask.sum())
    rng = np.random.default_rng(seed)
    walk = np.cumsum(rng.normal(size=(k, 3)), axis=0)
    walk -= walk.mean(axis=0)
    walk *= error_m / max(float(np.sqrt(np.mean(walk**2))), 1e-12)
    out = _shifted(gnss, mask, walk)
    return replace(out, quality=np.where(mask, 2, gnss.quality))


def outliers(gnss: GnssSolution, times_s, offsets_ned_m) -> GnssSolution:
    """Single wrong epochs: the epoch nearest each time moved by its offset."""
    mask = np.zeros(len(gnss), dtype=bool)
    idx = np.array([int(np.argmin(np.abs(gnss.time_s - t))) for t in times_s])
    if len(set(idx.tolist())) < len(idx) or np.abs(gnss.time_s[idx] - np.asarray(times_s)).max() > 1.0:
        raise ValueError("an outlier time has no GNSS epoch of its own within 1 s (an outage, or the end)")
    mask[idx] = True
    order = np.argsort(idx)
    return _shifted(gnss, mask, np.asarray(offsets_ned_m, dtype=float)[order])
