"""The tabulated chi-square quantiles are scipy.special's to the bit, and any other is still computed."""

import numpy as np
import pytest
from scipy.special import chdtri, gammaincinv

from insrail.nav import chi2
from insrail.nav.fusion import LOUD_RETURN_QUANTILE
from insrail.nav.fusion_options import FusionOptions
from insrail.nav.measurements import MAX_ROWS


@pytest.mark.parametrize("tail", [1.0 - FusionOptions().gate_probability, 1.0 - LOUD_RETURN_QUANTILE])
def test_the_tabulated_quantiles_are_scipys(tail):
    assert tail in chi2._UPPER  # the probabilities the fusion uses are the tabulated ones
    for dof in range(1, MAX_ROWS + 1):
        assert chi2.upper_quantile(dof, tail) == chdtri(dof, tail)
        assert chi2.upper_quantile(np.int64(dof), tail) == chdtri(dof, tail)


def test_other_quantiles_are_computed():
    assert chi2.upper_quantile(3, 0.01) == chdtri(3, 0.01)
    assert chi2.upper_quantile(MAX_ROWS + 1, 1.0 - LOUD_RETURN_QUANTILE) == chdtri(MAX_ROWS + 1, 1.0 - LOUD_RETURN_QUANTILE)
    assert chi2.upper_quantile(2.5, 1.0 - LOUD_RETURN_QUANTILE) == chdtri(2.5, 1.0 - LOUD_RETURN_QUANTILE)


@pytest.mark.parametrize("dof", [np.arange(1.0, MAX_ROWS + 1), np.array([3.0, 1.0, 3.0, 2.0]), np.array([2.0, 7.0]),
                                 np.array([0.5, 2.0]), np.zeros(0)])
def test_the_medians_are_scipys_to_the_bit(dof):
    expected = 2.0 * gammaincinv(dof / 2, 0.5)
    assert chi2.median(dof).tobytes() == expected.tobytes()
