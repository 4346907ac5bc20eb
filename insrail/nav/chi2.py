"""Chi-square quantiles of the filter's gates and consistency tests, without importing scipy.special.

The fusion asks for few of them: the gate of each measurement's dimension (1 to
``insrail.nav.measurements.MAX_ROWS`` rows) at the gate probability, the 95 % quantile a loud return
after a gap is judged by, and the medians the self-calibration's robust NIS is divided by. Importing
scipy.special for them took some 0.1-0.2 s of the 2-3 s of ``insrail fuse`` on a short survey (its
array-API layer; scipy.linalg, which numba's kernels need anyway, shares only part of it). The
quantiles of the probabilities the code uses are tabulated here: scipy.special's values to the bit
(``tests/test_nav_chi2.py`` checks them against it, so a scipy that computes one differently is
noticed); any other probability or number of degrees of freedom is computed by scipy.special,
imported then.
"""

from __future__ import annotations

import numpy as np

#: ``chdtri(dof, tail)`` for dof = 1, 2, ...: keyed by the tail probability exactly as the callers form it
_UPPER = {
    1.0 - 0.9999: (15.136705226623606, 18.420680743952584, 21.107513466160444, 23.512742444991076,
                   25.74483195905612, 27.85634123601417),
    1.0 - 0.95: (3.841458820694124, 5.991464547107979, 7.814727903251179, 9.487729036781154, 11.070497693516351,
                 12.591587243743977),
}
#: the medians ``2 gammaincinv(dof / 2, 1/2)`` for dof = 1, 2, ... (what scipy.stats' chi2.median computes)
_MEDIAN = (0.454936423119572, 1.386294361119891, 2.3659738843753377, 3.3566939800333224, 4.351460191095526,
           5.348120627447118)


def upper_quantile(dof, tail: float) -> float:
    """The value a chi-square variable of ``dof`` degrees of freedom exceeds with probability ``tail``
    (scipy.special.chdtri)."""
    table = _UPPER.get(tail)
    if table is not None and dof == int(dof) and 1 <= dof <= len(table):
        return table[int(dof) - 1]
    from scipy.special import chdtri

    return float(chdtri(dof, tail))


def median(dof: np.ndarray) -> np.ndarray:
    """The chi-square medians of the degrees of freedom ``dof`` (an array), 2 x scipy.special's
    ``gammaincinv(dof / 2, 0.5)``."""
    dof = np.asarray(dof, dtype=float)
    whole = dof.astype(np.int64)
    if np.all((whole == dof) & (whole >= 1) & (whole <= len(_MEDIAN))):
        return np.array(_MEDIAN)[whole - 1]
    from scipy.special import gammaincinv

    return 2.0 * gammaincinv(dof / 2, 0.5)
