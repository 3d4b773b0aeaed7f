"""A free decay whose frequency changes with its amplitude: a wide swing's period.

A pendulum's period grows with its amplitude (T = T₀(1 + θ₀²/16 + …)), and so does any
symmetric oscillator's, by its own κ: T(a) = T₀(1 + κa² + O(a⁴)). As a swing decays, its
period shortens along the record: at 19° by 0.7 % × the share the amplitude loses. A
sinusoid of one frequency fitted over such a record finds a frequency between the first
swings' and the last ones', weighted by where the record holds most information, and its
covariance knows nothing of the drift: the u it states is too small, and the amplitude the
period belongs to is unsaid.

:func:`fit_anharmonic_decay` fits the record with the frequency a function of the envelope,

.. math:: x(τ) = c_0 + c_1 τ/τ_{max} + E(τ)\\,(a\\cos φ(τ) + b\\sin φ(τ)),\\qquad
          E(τ) = e^{-στ - γ(τ/τ_{max})^2},

.. math:: φ(τ) = \\bar ω\\left[τ - k\\left(\\int_0^τ E^2\\,ds - m τ\\right)\\right],\\qquad
          m = \\frac{1}{τ_{max}}\\int_0^{τ_{max}} E^2\\,ds,

so that the instantaneous frequency is ω̄(1 − k(E² − m)) — the quadratic dependence on the
amplitude A₀E with k = κ'A₀² for any oscillator, κ' not assumed but fitted — and φ(τ_max) −
φ(0) = ω̄τ_max: ω̄ is the mean frequency over the record, 2π/ω̄ its mean period (the record's
span over the oscillations it holds, what a stopwatch started and stopped with it measures),
and that period belongs to the RMS amplitude A₀√m of the record's envelope to first order in
κ'a² (the next term, O(a⁴) over the amplitude's spread along the record, is below 10⁻⁵ of
T at 19°). k's own uncertainty enters ω̄'s u through the fit's covariance.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize

from .decay import DampedSineFit

MAX_EVALUATIONS = 1000
"""Evaluations of the model the fit may take (a short film's few oscillations leave its
decay and drift loosely bound: 200 did not always reach the tolerances on 3.5 oscillations)."""

LEAST_DECAY = 0.02
"""Relative fall of E² over the record below which k is not fitted (the frequency cannot
drift with an amplitude that does not change; its column would vanish)."""


@dataclass(frozen=True)
class AnharmonicFit:
    """The fit of :func:`fit_anharmonic_decay`.

    Attributes
    ----------
    omega_d : float
        ω̄, the mean angular frequency over the record. [rad/s]
    drift : float
        k: the instantaneous frequency is ω̄(1 − k(E² − m)). [1]
    amplitude : float
        A₀ at the record's start. [record's unit]
    reference_amplitude : float
        A₀√m, the RMS of the envelope over the record: the amplitude the mean period belongs
        to. [record's unit]
    params : tuple of str
        Names of the fitted parameters, in the order of ``normal``.
    normal : numpy.ndarray
        (JᵀJ)⁻¹ over all parameters: the covariance per unit residual variance.
    residual_sd : float
    start, span : float
        t₀ and τ_max. [s]
    jacobian : numpy.ndarray
        J: each sample's derivative by each parameter, at the fit (rows the samples).
    """

    omega_d: float
    drift: float
    amplitude: float
    reference_amplitude: float
    params: tuple
    normal: np.ndarray
    residual_sd: float
    start: float
    span: float
    jacobian: np.ndarray
    _p: np.ndarray
    _fit_drift: bool

    @property
    def period(self) -> float:
        """2π/ω̄, the mean period over the record. [s]"""
        return 2.0 * math.pi / self.omega_d

    def sensitivity(self, name: str) -> np.ndarray:
        """How the parameter ``name`` moves with each sample: its row of (JᵀJ)⁻¹Jᵀ (a
        parameter's error is this row times the samples' errors, to first order)."""
        return self.normal[self.params.index(name)] @ self.jacobian.T

    def predict(self, time) -> np.ndarray:
        """The fitted record at ``time`` (within the record's span). [record's unit]"""
        return _model(self._p, np.asarray(time, float) - self.start, self.span,
                      self._fit_drift)


def _envelope_integral(tau: np.ndarray, e2: np.ndarray) -> np.ndarray:
    """∫₀^τ E² ds at each τ (trapezoids over the samples)."""
    steps = np.diff(tau) * 0.5 * (e2[1:] + e2[:-1])
    return np.concatenate([[0.0], np.cumsum(steps)])


def _model(p, tau, span, fit_drift: bool) -> np.ndarray:
    sigma, gamma, omega = p[0], p[1], p[2]
    k = p[3] if fit_drift else 0.0
    a, b, c0, c1 = p[-4:]
    E = np.exp(-sigma * tau - gamma * (tau / span) ** 2)
    e2 = E * E
    integral = _envelope_integral(tau, e2)
    m = integral[-1] / span
    phase = omega * (tau - k * (integral - m * tau))
    return c0 + c1 * tau / span + E * (a * np.cos(phase) + b * np.sin(phase))


def fit_anharmonic_decay(time, x, start: DampedSineFit) -> AnharmonicFit:
    """Fit a free decay whose frequency depends on its amplitude (see the module's notes),
    starting from a damped sinusoid's fit of the same record (baseline of order 1).

    Parameters
    ----------
    time, x : array_like
        Sample times [s] and the record [any unit]; the times must be those ``start`` was
        fitted on (its t₀ is their first).
    start : DampedSineFit

    Returns
    -------
    AnharmonicFit

    Raises
    ------
    RuntimeError
        The fit did not converge, or its normal matrix is singular.
    """
    t, x = np.asarray(time, float), np.asarray(x, float)
    tau = t - start.start
    span = float(tau[-1]) or 1.0
    sigma = start.delta * start.omega_d / (2 * math.pi)
    fit_drift = 1.0 - math.exp(-2 * sigma * span) > LEAST_DECAY
    c = np.asarray(start.baseline, float)
    c0 = c[0] if c.size else 0.0
    c1 = c[1] if c.size > 1 else 0.0
    a, b = start.amplitude * math.cos(start.phase), -start.amplitude * math.sin(start.phase)
    p0 = np.array([sigma, 0.0, start.omega_d] + ([0.0] if fit_drift else []) + [a, b, c0, c1])
    scale = np.array([abs(sigma) + 1.0 / span, 0.1, start.omega_d * 1e-3]
                     + ([1e-3] if fit_drift else []) + [abs(start.amplitude)] * 2
                     + [abs(start.amplitude) + 1e-9] * 2)

    def residual(p):
        return _model(p, tau, span, fit_drift) - x

    sol = optimize.least_squares(residual, p0, x_scale=scale, method="trf", jac="3-point",
                                 xtol=1e-12, ftol=1e-12, gtol=1e-12, max_nfev=MAX_EVALUATIONS)
    if not sol.success:
        raise RuntimeError(f"fit_anharmonic_decay: the fit did not converge ({sol.message})")
    J = sol.jac
    try:
        normal = np.linalg.inv(J.T @ J)
    except np.linalg.LinAlgError:
        raise RuntimeError("fit_anharmonic_decay: the normal matrix is singular") from None
    p = sol.x
    r = sol.fun
    names = ("sigma", "gamma", "omega_d") + (("drift",) if fit_drift else ()) + \
        ("a", "b", "c0", "c1")
    E = np.exp(-p[0] * tau - p[1] * (tau / span) ** 2)
    m = _envelope_integral(tau, E * E)[-1] / span
    amplitude = math.hypot(p[-4], p[-3])
    return AnharmonicFit(float(p[2]), float(p[3]) if fit_drift else 0.0, amplitude,
                         amplitude * math.sqrt(m), names, normal,
                         float(math.sqrt(r @ r / max(r.size - p.size, 1))), start.start, span,
                         J, p, fit_drift)
