"""Shared fixtures: build a lab's inputs from a plain dict, as a parsed TOML file would be;
fail a case that hangs."""
import signal

import numpy as np
import pytest

from processing.diagnostics import collect_notices
from processing.measurement import load


@pytest.fixture
def make_inputs(tmp_path):
    """``make_inputs(spec, data)`` → (Inputs, notices raised while loading)."""
    def make(spec, data):
        with collect_notices() as notices:
            inputs = load(tmp_path / f"{spec.id}.toml", spec, {"lab": spec.id, **data})
        return inputs, notices
    return make


HANG = 60
"""Seconds after which a case of the hostile corpora counts as hung."""


@pytest.fixture
def no_hang():
    """An alarm fails the test after :data:`HANG` s (a hang), instead of hanging the suite."""
    def hung(signum, frame):
        raise TimeoutError(f"the case ran for {HANG} s: a hang")

    old = signal.signal(signal.SIGALRM, hung)
    signal.alarm(HANG)
    yield
    signal.alarm(0)
    signal.signal(signal.SIGALRM, old)


# ----------------------------------------------------------------------------- an ideal engine's edges

OMEGA0 = 60 * np.pi  # 1800 min⁻¹
HARMONICS = ((0.5, 0.003, 0.4), (2.0, 0.008, 1.1), (4.0, 0.0025, -0.7))  # order, rel. amp, phase
_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(8)


def omega(theta):
    """A four-stroke engine's speed: orders 0.5, 2 and 4, δ ≈ 0.022. [rad/s]"""
    return OMEGA0 * (1 + sum(a * np.cos(k * theta + p) for k, a, p in HARMONICS))


def times_at(angles, theta0=0.0):
    """t(θ) = ∫_{θ0}^{θ} dθ/ω at the given angles: Gauss–Legendre on a grid of ≤ 0.5° steps
    through them (exact to rounding for this smooth ω). [s]"""
    angles = np.asarray(angles, dtype=float)
    nodes = np.union1d(np.arange(theta0, angles.max(), np.radians(0.5)), angles)
    nodes = np.union1d([theta0], nodes)
    half = np.diff(nodes) / 2
    theta = (nodes[1:] + nodes[:-1])[:, None] / 2 + half[:, None] * _NODES
    t = np.concatenate([[0.0], np.cumsum(half * (_WEIGHTS / omega(theta)).sum(axis=1))])
    return t[np.searchsorted(nodes, angles)]
