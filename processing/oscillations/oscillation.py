"""Periods of free oscillations: stopwatch timing and finite-amplitude corrections.

Every pendulum method of the lab manual (trifilar, unifilar, physical pendulum, a connecting
rod swung on a prism) uses the small-oscillation period T₀. A swing of finite amplitude θ₀
is slower; these functions give the factor T(θ₀)/T₀ so that a timed period can be reduced to
T₀ before the small-swing formula is applied.
"""
from __future__ import annotations

import numpy as np
from scipy import special

_NODES, _WEIGHTS = np.polynomial.legendre.leggauss(48)
# Gauss–Legendre on θ ∈ [0, π/2]: the substitution q = q₀ sin θ removes the turning-point
# singularity of the period integral.
_THETA = (0.25 * np.pi * (_NODES + 1.0))[:, None]
_W = (0.25 * np.pi * _WEIGHTS)[:, None]


def period_from_total(total_time, n_oscillations):
    """Period of one full oscillation from a stopwatch reading.

    Parameters
    ----------
    total_time : float or ndarray
        Time of ``n_oscillations`` full oscillations. [s]
    n_oscillations : int
        Number of full oscillations timed (the manual: 20 for the trifilar, 10–20 for a rod).

    Returns
    -------
    float or ndarray
        Period T = t / n. [s]
    """
    return np.asarray(total_time) / n_oscillations


def pendulum_period_factor(amplitude):
    """T(θ₀)/T₀ of a pendulum (physical or simple) swinging with amplitude θ₀.

    Parameters
    ----------
    amplitude : float or ndarray
        Angular amplitude θ₀ (from the vertical). [rad]

    Returns
    -------
    float or ndarray
        The exact factor :math:`2K(\\sin^2(\\theta_0/2))/\\pi`.

    Notes
    -----
    From the equation of motion J φ̈ = −m g c sin φ (lab manual, lab 1, eq. 13):

    .. math:: \\frac{T}{T_0} = \\frac{2}{\\pi} K(m), \\quad m = \\sin^2\\frac{\\theta_0}{2}
              = 1 + \\frac{\\theta_0^2}{16} + \\frac{11\\theta_0^4}{3072} + \\dots

    References
    ----------
    .. [1] L. D. Landau, E. M. Lifshitz, Mechanics, §11, problem 1.

    Examples
    --------
    >>> round(float(pendulum_period_factor(np.radians(10.0))), 5)
    1.00191
    """
    return 2.0 / np.pi * special.ellipk(np.sin(0.5 * np.asarray(amplitude)) ** 2)


def period_factor(amplitude, potential, inertia, stiffness):
    """T(q₀)/T₀ of any symmetric one-degree-of-freedom conservative oscillator.

    Parameters
    ----------
    amplitude : float or ndarray
        Amplitude q₀ of the coordinate. [rad]
    potential : callable
        V(q), potential energy (V(0) = 0), vectorised. [J]
    inertia : callable
        M(q), generalised inertia of the kinetic energy ½ M(q) q̇², vectorised. [kg·m²]
    stiffness : float or ndarray
        V''(0), giving T₀ = 2π √(M(0)/V''(0)). [N·m/rad]

    Returns
    -------
    float or ndarray
        The factor T/T₀.

    Notes
    -----
    .. math:: T = 4\\int_0^{q_0}\\sqrt{\\frac{M(q)}{2\\,[V(q_0) - V(q)]}}\\,dq

    evaluated with q = q₀ sin θ and 48-point Gauss–Legendre quadrature in θ. Write V
    without cancellation (2 sin²(q/2), not 1 − cos q) for accuracy at small amplitudes.

    Examples
    --------
    >>> f = period_factor(np.radians(10.0), lambda q: 2 * np.sin(q / 2) ** 2,
    ...                   lambda q: np.ones_like(q), 1.0)
    >>> bool(np.isclose(f, pendulum_period_factor(np.radians(10.0)), rtol=1e-12))
    True
    """
    q0 = np.asarray(amplitude, dtype=float)
    q = q0 * np.sin(_THETA)
    with np.errstate(invalid="ignore", divide="ignore"):
        drop = potential(q0) - potential(q)
        integrand = q0 * np.cos(_THETA) * np.sqrt(inertia(q) / (2.0 * drop))
        period = 4.0 * np.sum(_W * integrand, axis=0)
        t0 = 2.0 * np.pi * np.sqrt(inertia(np.zeros_like(q0)) / stiffness)
        ratio = period / t0
    return np.where(q0 == 0.0, 1.0, ratio)[()]


def check_amplitude(amplitude, method: str | dict[str, str], *,
                    limit=np.radians(10.0)) -> None:
    """Warn (:class:`~processing.diagnostics.AmplitudeTooLargeWarning`) above ``limit``.

    Parameters
    ----------
    amplitude : float or Measured
        Amplitude of the swing or twist. [rad] A measured one whose limit of error reaches
        zero (a film whose arc hardly sags: its own warning says so) is not known to be
        above anything, and is not warned of.
    method : str or dict
        What swung, for the message (e.g. "trifilar"), or its name by language
        (``{"en": "Physical pendulum", "ru": "Физический маятник"}``).
    limit : float
        Largest amplitude the method's small-swing formula is meant for. [rad]
    """
    import warnings

    from processing.diagnostics import AmplitudeTooLargeWarning

    names = {"en": method} if isinstance(method, str) else method
    reach = getattr(amplitude, "limit", 0.0) or 0.0
    amplitude = getattr(amplitude, "value", amplitude)
    if reach >= amplitude:
        return
    deg, lim = np.degrees(amplitude), np.degrees(limit)
    if deg > lim:
        factor = float(pendulum_period_factor(amplitude)) ** 2 - 1.0
        warnings.warn(AmplitudeTooLargeWarning(
            f"{names['en']}: amplitude {deg:.1f}° is above {lim:.0f}°; the period was corrected for "
            f"it (uncorrected, J would be about {100 * factor:.1f} % high), but the amplitude "
            f"decays while you time the swings, so the correction is uncertain: swing at 5–8°",
            f"{names.get('ru', names['en'])}: амплитуда {deg:.1f}° больше {lim:.0f}°; период исправлен на конечную "
            f"амплитуду (без поправки J завышен примерно на {100 * factor:.1f} %), но амплитуда "
            f"затухает за время отсчёта, поэтому поправка неточна: отклоняйте на 5–8°"))
