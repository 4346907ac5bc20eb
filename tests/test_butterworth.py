"""The Butterworth band-pass done without scipy.signal (insrail.track.butterworth) gives scipy's numbers
to the bit: the sections of scipy.signal.butter and the output of scipy.signal.sosfiltfilt, so the
band-passed figures of the results did not change when scipy.signal stopped being imported."""

import numpy as np
import pytest
from scipy import signal

from insrail.track.butterworth import band_pass_sos, zero_phase
from insrail.track.irregularity import BANDS_M, band_pass

SPACINGS_M = (0.25, 0.5, 0.6, 0.625, 0.65, 1.0)
#: (shortest, longest) wavelengths [m]: EN 13848's bands and narrow, wide and odd ones.
BANDS = (*BANDS_M.values(), (1.5, 3.0), (2.0, 100.0), (5.0, 8.0), (1.3, 400.0), (10.0, 11.0))


@pytest.mark.parametrize("order", [1, 2, 3, 4, 5, 6])
def test_the_sections_and_the_zero_phase_output_are_scipys_bit_for_bit(order):
    rng = np.random.default_rng(order)
    for spacing in SPACINGS_M:
        for shortest, longest in BANDS:
            if shortest <= 2 * spacing:
                continue
            fs = 1.0 / spacing
            expected = signal.butter(order, [1.0 / longest, 1.0 / shortest], btype="bandpass", fs=fs, output="sos")
            sos = band_pass_sos(order, 1.0 / longest, 1.0 / shortest, fs)
            assert sos.tobytes() == expected.tobytes(), (order, spacing, shortest, longest)
            for size in (3 * (2 * order + 1) + 1, 97, 2000):  # the shortest input the padding allows, and longer
                x = 1e-3 * rng.normal(size=size).cumsum()
                assert zero_phase(sos, x).tobytes() == signal.sosfiltfilt(expected, x).tobytes()


def test_band_pass_of_stretches_with_gaps_is_scipys_bit_for_bit():
    """band_pass (the grid, the stretches, the filter) on deviations with NaN gaps: the same array as
    with scipy.signal's design and filter on each stretch."""
    rng = np.random.default_rng(5)
    station = np.arange(3000) * 0.625 + 1000.0
    deviation = 1e-3 * rng.normal(size=station.size).cumsum()
    deviation[700:720] = np.nan  # a gap longer than the grid bridges: two stretches
    deviation[2950:] = np.nan
    for band in BANDS_M:
        ours = band_pass(station, deviation, band)
        shortest, longest = BANDS_M[band]
        sos = signal.butter(4, [1.0 / longest, 1.0 / shortest], btype="bandpass", fs=1 / 0.625, output="sos")
        expected = np.full(station.size, np.nan)
        for start, stop in ((0, 700), (720, 2950)):
            expected[start:stop] = signal.sosfiltfilt(sos, deviation[start:stop])
        assert ours.tobytes() == expected.tobytes(), band


def test_a_stretch_no_longer_than_the_padding_and_bad_bands_are_refused():
    sos = band_pass_sos(4, 1 / 25.0, 1 / 3.0, 1.6)
    with pytest.raises(ValueError, match="padlen, which is 27"):
        zero_phase(sos, np.zeros(27))
    with pytest.raises(ValueError, match="expected 0 < low < high"):
        band_pass_sos(4, 1 / 3.0, 1 / 25.0, 1.6)
    with pytest.raises(ValueError, match="expected 0 < low < high"):
        band_pass_sos(4, 1 / 25.0, 1.0, 1.6)  # beyond the Nyquist frequency
    with pytest.raises(ValueError, match="positive integer"):
        band_pass_sos(0, 1 / 25.0, 1 / 3.0, 1.6)
