"""Savitzky–Golay smoothing against scipy's own (mode "interp"), ends included."""
import numpy as np
import pytest
from scipy.signal import savgol_filter

from processing.oscillations.savgol import savgol


@pytest.mark.parametrize("size, window, order", [(100, 11, 2), (37, 21, 2), (2000, 11, 2),
                                                 (500, 7, 3), (11, 11, 2), (12, 11, 3),
                                                 (5, 11, 2)])
def test_as_scipy_interp_mode(size, window, order):
    x = np.random.default_rng(size).standard_normal(size).cumsum()
    if size < window:
        with pytest.raises(ValueError):
            savgol_filter(x, window, order)
        with pytest.raises(ValueError):
            savgol(x, window, order)
        return
    assert np.max(np.abs(savgol(x, window, order) - savgol_filter(x, window, order))) \
        < 1e-12 * np.max(np.abs(x))


def test_polynomial_of_the_filters_degree_passes_unchanged():
    t = np.linspace(-1, 1, 41)
    x = 2 - t + 3 * t**2 - 5 * t**3
    assert np.allclose(savgol(x, 9, 3), x, rtol=0, atol=1e-12)
