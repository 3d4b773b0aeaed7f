"""A cylinder without combustion, found from a vibration record's orders against a healthy
record at the same speed.

When one cylinder of an i-cylinder four-stroke engine does not fire, the torque reaction on
the block loses one pulse per working cycle: the deficit (the record with the cylinder cut,
less the healthy record, order by order against the same crank angle) is that pulse's
spectrum, and it lives at every order, the half orders included, which a healthy engine with
even firing hardly excites. So

- *whether* a cylinder is cut: the half orders rise (their RMS over the healthy record's,
  ``rise``), and their change stands out of the two fits' noise (a χ² test on their
  covariance, ``p_value``);
- *which* one: the deficit is a pulse centred a little after the cut cylinder's firing TDC;
  its envelope |Σ_k d_k e^{ikθ}| (free of the unknown sign with which the block's motion
  carries a torque to the accelerometer) is largest in that cylinder's firing sector
  [φ_c, φ_c + 720°/i). Drawing the deficit from its uncertainty gives each cylinder's share of
  the draws: the confidence. With one mark per revolution the angle is known modulo 360°
  only, and cylinders 360° apart in the firing order cannot be told apart (their shares are
  summed and split).

References
----------
.. [1] Dynamics of internal-combustion engines: lab manual, Vladimir State University, 2003,
       lab 4 ("cut the ignition of one cylinder on the chosen regime and assess the change of
       the vibration").
.. [2] R. B. Randall, Vibration-based Condition Monitoring, Wiley, 2011, §6.4.3 (misfire
       detection from the torque's low harmonics: the half orders of a four-stroke engine).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import stats

from processing.inputs.reuse import by_content
from processing.torsional.orders import OrderFit
from processing.result import Record

HIGHEST_ORDER = 8.0
"""Highest order of the deficit used: a combustion pulse spans about a quarter of a cycle."""

RISE = 2.0
"""Rise of the half orders' RMS (cut over healthy) at least this to call a cylinder cut:
6 dB, far above the spread between healthy cylinders and far below a missing pulse."""

SIGNIFICANCE = 1e-4
"""p-value below which the deficit is not noise (many channels and records are tested)."""

DRAWS = 1000
"""Monte Carlo draws of the deficit for the confidence."""


@dataclass(frozen=True)
class CutCylinder(Record):
    """What :func:`find_cut_cylinder` found."""

    found: bool
    """A cylinder is cut: the half orders rose by :data:`RISE` and the deficit is
    significant."""
    cylinder: int
    """The most likely cut cylinder (1-based; 0 if none found)."""
    confidence: float
    """Share of the draws of the deficit that point at ``cylinder``. [1]"""
    shares: np.ndarray
    """Every cylinder's share. [1]"""
    rise: float
    """RMS of the half orders, suspect over healthy. [1]"""
    p_value: float
    """Probability of so large a deficit from the fits' noise alone. [1]"""
    envelope: np.ndarray
    """|deficit| over the working cycle at :attr:`angle`. [record unit]"""
    angle: np.ndarray
    """Crank angle from cylinder 1's firing TDC. [rad]"""


def _pairs(fit: OrderFit, keep: np.ndarray):
    """(a, b) and their 2×2 covariances for the orders kept."""
    m = fit.order.size
    idx = np.flatnonzero(keep)
    ab = np.stack([fit.coefficient.real[idx], -fit.coefficient.imag[idx]], axis=1)
    c = fit.covariance
    cov = np.stack([np.stack([c[idx, idx], c[idx, m + idx]], -1),
                    np.stack([c[m + idx, idx], c[m + idx, m + idx]], -1)], -2)
    return ab, cov


def _envelope(ab: np.ndarray, order: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """|Σ_k (a_k − i b_k) e^{ikθ}| at the angles; ab of shape (..., m, 2)."""
    c = ab[..., 0] - 1j * ab[..., 1]
    return np.abs(c @ np.exp(1j * np.outer(order, angle)))


def _significance(healthy: OrderFit, suspect: OrderFit, half: np.ndarray,
                  cycle_marks: bool) -> float:
    """p-value of the half orders' change from the fits' noise: a χ² of their complex
    deficit (phases known from cycle marks), else of their amplitudes' change (1 degree of
    freedom each). The whole orders are left out: a strong order's phase jitters with the
    marks' timing (half a sample is 3° of order 8 at 3000 min⁻¹) far beyond its noise."""
    if cycle_marks:
        ab_s, cov_s = _pairs(suspect, half)
        ab_h, cov_h = _pairs(healthy, half)
        d = ab_s - ab_h
        chi2 = float(np.einsum("ki,kij,kj->", d, np.linalg.pinv(cov_s + cov_h), d))
        return float(stats.chi2.sf(chi2, 2 * d.shape[0]))
    change = suspect.amplitude[half] - healthy.amplitude[half]
    var = suspect.u[half] ** 2 + healthy.u[half] ** 2
    return float(stats.chi2.sf(float(np.sum(change ** 2 / var)), int(half.sum())))


def _decisive(healthy: OrderFit, suspect: OrderFit, phases, *, cycle_marks: bool = True,
              seed: int = 0) -> tuple:
    """What :func:`find_cut_cylinder` reads of its arguments: the fits' orders, coefficients
    and covariances (not their drift and fitted signal, each as long as the record), the
    phases and the options: its result is kept by their content alone."""
    return (*((f.order, f.coefficient, f.covariance) for f in (healthy, suspect)), phases,
            cycle_marks, seed)


@by_content(_decisive, shared=True)
def find_cut_cylinder(healthy: OrderFit, suspect: OrderFit, phases, *, cycle_marks: bool = True,
                      seed: int = 0) -> CutCylinder:
    """Which cylinder, if any, does not fire in ``suspect``, against ``healthy``.

    Parameters
    ----------
    healthy, suspect : OrderFit
        The two records' orders (:func:`processing.torsional.orders.order_fit`, half orders, angle
        from cylinder 1's firing TDC), one channel, the same speed.
    phases : array_like
        φ_c: each cylinder's firing TDC after cylinder 1's
        (:func:`processing.crank.dynamics.firing_phases`). [rad]
    cycle_marks : bool, keyword-only
        The angle comes from a mark per working cycle (an ignition pickup on cylinder 1);
        False: a mark per revolution (the half orders' phases are then unknown).
    seed : int, keyword-only
        Seed of the draws.

    Returns
    -------
    CutCylinder

    Raises
    ------
    ValueError
        The fits' orders differ or hold no half order.
    """
    if healthy.order.size != suspect.order.size or not np.allclose(healthy.order, suspect.order):
        raise ValueError("find_cut_cylinder: the two fits hold different orders")
    order = healthy.order
    phases = np.asarray(phases, dtype=float)
    i = phases.size
    half = (np.abs(order % 1 - 0.5) < 1e-9) & (order <= HIGHEST_ORDER)
    if not half.any():
        raise ValueError("find_cut_cylinder: the fits hold no half order")
    rise = float(np.sqrt(np.sum(suspect.amplitude[half] ** 2)
                         / max(np.sum(healthy.amplitude[half] ** 2), 1e-300)))
    use = order <= HIGHEST_ORDER
    if not cycle_marks:
        use &= np.abs(order % 1) < 1e-9
    ab_s, cov_s = _pairs(suspect, use)
    ab_h, cov_h = _pairs(healthy, use)
    d, cov = ab_s - ab_h, cov_s + cov_h
    p_value = _significance(healthy, suspect, half, cycle_marks)
    span = 4 * np.pi if cycle_marks else 2 * np.pi
    angle = np.linspace(0, span, 721 if cycle_marks else 361)[:-1]
    k = order[use]
    rng = np.random.default_rng(seed)
    chol = np.linalg.cholesky(cov + 1e-30 * np.eye(2))
    noise = rng.standard_normal((DRAWS, d.shape[0], 2))
    draws = d + (chol[:, :, 0] * noise[:, :, :1] + chol[:, :, 1] * noise[:, :, 1:])  # L z
    envelope = _envelope(draws, k, angle)
    sector = 4 * np.pi / i
    owner = np.floor(np.mod(angle[None, :] - phases[:, None], span) / sector) == 0
    score = envelope @ owner.T.astype(float) / np.maximum(owner.sum(axis=1), 1)
    votes = np.bincount(np.argmax(score, axis=1), minlength=i) / DRAWS
    if not cycle_marks:       # cylinders 360° apart share a sector: split their votes
        twin = np.abs(np.mod(phases[:, None] - phases[None, :], 2 * np.pi)) < 1e-6
        votes = twin @ votes / twin.sum(axis=1)
    found = bool(rise >= RISE and p_value < SIGNIFICANCE)
    best = int(np.argmax(votes))
    return CutCylinder(found=found, cylinder=best + 1 if found else 0,
                       confidence=float(votes[best]) if found else 0.0, shares=votes,
                       rise=rise, p_value=p_value, envelope=_envelope(d, k, angle), angle=angle)
