"""The swing of a periodic trace (processing.speed.cycle_range): restoring what a blur flattened."""
import numpy as np
import pytest

from processing.speed.cycle_range import cycle_range


def test_deblurred_restores_the_ripple_a_gaussian_blur_flattened():
    """Orders 2 and 4 of a cycle, each flattened as a Gaussian of σ flattens it
    (exp(−(2πmσ/τ)²/2)): restored, the mean cycle's δ is the unblurred trace's."""
    tau, sigma = 0.1, 0.004
    t = np.linspace(0.0, 0.8, 16001)

    def trace(s):
        gain = [np.exp(-0.5 * (2 * np.pi * m * s / tau) ** 2) for m in (2, 4)]
        return (1 + 0.008 * gain[0] * np.cos(2 * np.pi * 2 * t / tau)
                + 0.004 * gain[1] * np.sin(2 * np.pi * 4 * t / tau + 0.5))

    starts = np.arange(0.0, 0.81, tau)
    sharp = cycle_range(t, trace(0.0), starts, orders=6).relative_swing()[0]
    blurred = cycle_range(t, trace(sigma), starts, orders=6)
    assert blurred.relative_swing()[0] < 0.93 * sharp
    assert blurred.deblurred(sigma).relative_swing()[0] == pytest.approx(sharp, rel=1e-9)
    assert blurred.deblurred(0.0).relative_swing()[0] == blurred.relative_swing()[0]
