"""Digital Butterworth band-pass filters as second-order sections, applied forward and backward:
``scipy.signal.butter(order, [low, high], "bandpass", fs=fs, output="sos")`` and
``scipy.signal.sosfiltfilt(sos, x)`` (odd extension, scipy's default padding), bit for bit.

Done here because ``import scipy.signal`` imports scipy.stats, scipy.optimize and
scipy.interpolate: 0.85 s of CPU beyond the pipeline's other imports in every ``insrail process``
(the band-passed EN 13848 figures of summary.toml) and in every rerun after a tolerance edit, for a
few filters of a few thousand samples. The steps are scipy 1.17's (buttap, lp2bp_zpk, bilinear_zpk, zpk2sos with
"nearest" pairing, sosfilt_zi, odd_ext, the _sosfilt loop), written out for the digital band-pass
only, in the same floating-point operations and order, so the results are scipy's to the bit
(tests/test_butterworth.py compares them). Frequencies in cycles per unit of the samples' spacing
(here per metre: 1 / wavelength).
"""

from __future__ import annotations

import numpy as np

from insrail.jit import cached_njit


def band_pass_sos(order: int, low: float, high: float, fs: float) -> np.ndarray:
    """Second-order sections (order, 6) of the digital Butterworth band-pass from ``low`` to
    ``high`` (0 < low < high < fs / 2) for samples at ``fs`` (scipy.signal.butter's, to the bit)."""
    if int(order) != order or order < 1:
        raise ValueError(f"Butterworth order {order}: expected a positive integer")
    wn = np.asarray([low, high], dtype=np.float64) / (float(fs) / 2)
    if np.any(wn <= 0) or np.any(wn >= 1) or not wn[0] < wn[1]:
        raise ValueError(f"band {low}..{high} at a sampling rate of {fs}: expected 0 < low < high < {fs / 2}")
    # analog low-pass prototype (buttap): the middle pole is exactly real
    m = np.arange(-order + 1, order, 2, dtype=np.float64)
    poles = -np.exp(1j * np.pi * m / (2 * order))
    # pre-warped band edges of the bilinear transform at fs = 2
    warped = 2 * 2.0 * np.tan(np.pi * wn / 2.0)
    bw = float(warped[1] - warped[0])
    wo = float(np.sqrt(warped[0] * warped[1]))
    # low-pass to band-pass (lp2bp_zpk): no finite zeros, so `order` zeros at the origin
    p_lp = (poles * bw / 2).astype(np.complex128)
    p_bp = np.concatenate((p_lp + np.sqrt(p_lp**2 - wo**2), p_lp - np.sqrt(p_lp**2 - wo**2)))
    z_bp = np.concatenate((np.zeros(0, np.complex128), np.zeros(order)))
    k_bp = 1.0 * bw**order
    # bilinear transform (bilinear_zpk, fs = 2): the zeros at infinity to the Nyquist frequency
    fs2 = 2.0 * 2.0
    z_z = np.concatenate(((fs2 + z_bp) / (fs2 - z_bp), -np.ones(order)))
    p_z = (fs2 + p_bp) / (fs2 - p_bp)
    k_z = k_bp * np.real(np.prod(fs2 - z_bp) / np.prod(fs2 - p_bp))
    return _zpk2sos(z_z, p_z, k_z)


def _cplxreal(z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The complex roots (one of each conjugate pair, averaged) and the real roots, sorted (scipy's
    _cplxreal)."""
    z = np.atleast_1d(z)
    if z.size == 0:
        return z, z
    tol = 100 * np.finfo((1.0 * z).dtype).eps
    z = z[np.lexsort((abs(z.imag), z.real))]
    real_indices = abs(z.imag) <= tol * abs(z)
    zr = z[real_indices].real
    if len(zr) == len(z):
        return np.array([]), zr
    z = z[~real_indices]
    zp = z[z.imag > 0]
    zn = z[z.imag < 0]
    if len(zp) != len(zn):
        raise ValueError("a complex root without its conjugate")
    same_real = np.diff(zp.real) <= tol * abs(zp[:-1])
    diffs = np.diff(np.concatenate(([0], same_real, [0])))
    run_starts = np.nonzero(diffs > 0)[0]
    run_stops = np.nonzero(diffs < 0)[0]
    for start, stop in zip(run_starts, run_stops + 1):
        for chunk in (zp[start:stop], zn[start:stop]):
            chunk[...] = chunk[np.lexsort([abs(chunk.imag)])]
    if any(abs(zp - zn.conj()) > tol * abs(zn)):
        raise ValueError("a complex root without its conjugate")
    return (zp + zn.conj()) / 2, zr


def _poly(roots) -> np.ndarray:
    """The monic polynomial of ``roots`` (scipy.signal's poly: real when they come in conjugate pairs)."""
    roots = np.atleast_1d(np.asarray(roots))
    a = np.ones((1,), dtype=roots.dtype)
    one = np.ones_like(roots[0])
    for zero in roots:
        a = np.convolve(a, np.stack((one, -zero)), mode="full")
    if np.iscomplexobj(a):
        complex_roots = np.asarray(roots, dtype=np.complex128)
        if np.all(np.sort(np.imag(complex_roots)) == np.sort(np.imag(np.conj(complex_roots)))):
            a = np.real(a).copy()
    return a


def _section(zeros: list, poles: list) -> np.ndarray:
    """One second-order section of unit gain (scipy's _single_zpksos)."""
    section = np.zeros(6)
    zeros, poles = np.asarray(zeros), np.asarray(poles)
    b = np.multiply(np.asarray(1, dtype=np.result_type(np.real(zeros), np.real(poles), 1)),
                    _poly(zeros) if zeros.size else np.asarray(1.0, dtype=np.real(zeros).dtype))
    a = np.atleast_1d(_poly(poles))
    b = np.atleast_1d(b)
    section[3 - len(b):3] = b
    section[6 - len(a):6] = a
    return section


def _nearest(fro: np.ndarray, to, which: str) -> int:
    """Index of the root of ``fro`` nearest ``to`` among the real, complex or any ones."""
    order = np.argsort(np.abs(fro - to))
    if which == "any":
        return order[0]
    mask = np.isreal(fro[order])
    if which == "complex":
        mask = ~mask
    return order[np.nonzero(mask)[0][0]]


def _zpk2sos(z: np.ndarray, p: np.ndarray, k) -> np.ndarray:
    """Second-order sections of a digital filter's zeros, poles and gain (scipy's zpk2sos, "nearest"
    pairing: the poles nearest the unit circle in the last section)."""
    p = np.concatenate((p, np.zeros(max(len(z) - len(p), 0))))
    z = np.concatenate((z, np.zeros(max(len(p) - len(z), 0))))
    n_sections = (max(len(p), len(z)) + 1) // 2
    if len(p) % 2 == 1:
        p = np.concatenate((p, [0.0]))
        z = np.concatenate((z, [0.0]))
    z = np.concatenate(_cplxreal(z))
    p = np.concatenate(_cplxreal(p))
    k = np.asarray(k).real

    def worst(roots):
        return np.argmin(np.abs(1 - np.abs(roots)))

    sos = np.zeros((n_sections, 6))
    for si in range(n_sections - 1, -1, -1):
        p1_idx = worst(p)
        p1 = p[p1_idx]
        p = np.delete(p, p1_idx)
        if np.isreal(p1) and np.isreal(p).sum() == 0:  # the last real pole
            z1_idx = _nearest(z, p1, "real")
            z1 = z[z1_idx]
            z = np.delete(z, z1_idx)
            sos[si] = _section([z1, 0], [p1, 0])
        elif len(p) + 1 == len(z) and not np.isreal(p1) and np.isreal(p).sum() == 1 and np.isreal(z).sum() == 1:
            z1_idx = _nearest(z, p1, "complex")  # one real pole and one real zero left: a complex zero here
            z1 = z[z1_idx]
            z = np.delete(z, z1_idx)
            sos[si] = _section([z1, z1.conj()], [p1, p1.conj()])
        else:
            if np.isreal(p1):
                real_poles = np.flatnonzero(np.isreal(p))
                p2_idx = real_poles[worst(p[real_poles])]
                p2 = p[p2_idx]
                p = np.delete(p, p2_idx)
            else:
                p2 = p1.conj()
            if len(z) > 0:
                z1_idx = _nearest(z, p1, "any")
                z1 = z[z1_idx]
                z = np.delete(z, z1_idx)
                if not np.isreal(z1):
                    sos[si] = _section([z1, z1.conj()], [p1, p2])
                elif len(z) > 0:
                    z2_idx = _nearest(z, p1, "real")
                    z2 = z[z2_idx]
                    z = np.delete(z, z2_idx)
                    sos[si] = _section([z1, z2], [p1, p2])
                else:
                    sos[si] = _section([z1], [p1, p2])
            else:
                sos[si] = _section([], [p1, p2])
    sos[0][:3] *= k
    return sos


def _steady_state(sos: np.ndarray) -> np.ndarray:
    """Each section's state (n_sections, 2) in the steady state of a unit step (scipy's sosfilt_zi)."""
    zi = np.empty((sos.shape[0], 2))
    scale = 1.0
    for section in range(sos.shape[0]):
        b, a = sos[section, :3], sos[section, 3:]
        if a[0] != 1.0:
            b, a = b / a[0], a / a[0]
        companion = np.zeros((2, 2))
        companion[0, :] = -a[1:] / (1.0 * a[0:1])
        companion[1, 0] = 1
        zi[section, ...] = scale * np.linalg.solve(np.eye(2) - companion.T, b[1:] - a[1:] * b[0])
        scale *= np.sum(b) / np.sum(a)
    return zi


@cached_njit(nogil=True)
def _filter_sections(sos: np.ndarray, x: np.ndarray, zi: np.ndarray) -> None:
    """The cascade of sections over ``x`` in place from the states ``zi`` (updated): scipy's _sosfilt
    loop, the same products and sums in the same order (transposed direct form II)."""
    for n in range(x.shape[0]):
        x_cur = x[n]
        for s in range(sos.shape[0]):
            x_new = sos[s, 0] * x_cur + zi[s, 0]
            zi[s, 0] = sos[s, 1] * x_cur - sos[s, 4] * x_new + zi[s, 1]
            zi[s, 1] = sos[s, 2] * x_cur - sos[s, 5] * x_new
            x_cur = x_new
        x[n] = x_cur


def zero_phase(sos: np.ndarray, x: np.ndarray) -> np.ndarray:
    """``x`` (1-D) filtered forward and backward by ``sos`` after an odd extension of 3 x (2 x sections
    + 1) samples at each end, from the steady state of its end samples (scipy's sosfiltfilt)."""
    sos = np.atleast_2d(np.asarray(sos, dtype=np.float64))
    if sos.ndim != 2 or sos.shape[1] != 6 or not np.all(sos[:, 3] == 1):
        raise ValueError("second-order sections: expected shape (n, 6) with a0 = 1")
    x = np.asarray(x, dtype=np.float64)
    n_sections = sos.shape[0]
    edge = 3 * (2 * n_sections + 1 - min((sos[:, 2] == 0).sum(), (sos[:, 5] == 0).sum()))
    if x.shape[0] <= edge:
        raise ValueError(f"The length of the input vector x must be greater than padlen, which is {edge}.")
    ext = np.concatenate((2 * x[0:1] - x[edge:0:-1], x, 2 * x[-1:] - x[-2:-(edge + 2):-1]))
    zi = _steady_state(sos)
    y = ext.copy()
    _filter_sections(sos, y, np.ascontiguousarray(zi * ext[0:1]))
    y = np.ascontiguousarray(y[::-1])
    _filter_sections(sos, y, np.ascontiguousarray(zi * y[0:1]))
    return y[::-1][edge:-edge]
