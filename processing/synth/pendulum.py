"""Swinging bodies integrated from their nonlinear equations, timed by a human stopwatch.

The scenes behind labs 1 and 2: a physical pendulum J φ̈ = −m g c sin φ, and a trifilar
suspension with its exact thread geometry (the platform rises as it twists). The period is
measured on the integrated motion, not taken from a formula, so a reduction that recovers
the true moment of inertia has proven its corrections.
"""
from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp


def period_of(inertia, d_inertia, d_potential, amplitude) -> float:
    """Period of M(q) q̈ + ½ M'(q) q̇² + V'(q) = 0 released at rest from q = amplitude.

    Integrates a quarter swing (release → first zero crossing) with an event, tight
    tolerances; the motion is symmetric so the period is four times that time.

    Parameters
    ----------
    inertia, d_inertia, d_potential : callable
        M(q) [kg·m²], dM/dq, dV/dq [N·m] as scalar functions.
    amplitude : float
        Release angle. [rad]

    Returns
    -------
    float
        The period. [s]
    """
    def rhs(_, y):
        q, w = y
        return [w, -(0.5 * d_inertia(q) * w * w + d_potential(q)) / inertia(q)]

    def crossing(_, y):
        return y[0]

    crossing.terminal, crossing.direction = True, -1
    t_guess = 2 * np.pi * np.sqrt(inertia(0.0) / (d_potential(1e-6) / 1e-6))
    sol = solve_ivp(rhs, (0.0, 2 * t_guess), [amplitude, 0.0], events=crossing,
                    rtol=1e-11, atol=1e-13, method="DOP853")
    return 4.0 * float(sol.t_events[0][0])


def physical_pendulum_period(J_pivot, m, c, amplitude, g=9.81) -> float:
    """True period of a physical pendulum, J_O φ̈ = −m g c sin φ (lab 1, eq. 13)."""
    return period_of(lambda q: J_pivot, lambda q: 0.0, lambda q: m * g * c * np.sin(q), amplitude)


def trifilar_equation(J, m, R1, R2, l, g=9.81):
    """``(M, M', V')`` of a trifilar suspension twisted by φ: its generalised inertia
    M(φ) = J + m h′(φ)², dM/dφ and dV/dφ = −m g h′(φ).

    Lagrangian ½(J + m ḣ²/φ̇²)φ̇² − m g (H − h(φ)), h(φ)² = l² − R₁² − R₂² + 2R₁R₂ cos φ:
    the body rotates and rises; the threads are massless and inextensible.
    """
    a2 = l**2 - R1**2 - R2**2

    def h(q):
        return np.sqrt(a2 + 2 * R1 * R2 * np.cos(q))

    def dh(q):
        return -R1 * R2 * np.sin(q) / h(q)

    def d2h(q):
        return (-R1 * R2 * np.cos(q) - dh(q) ** 2) / h(q)

    return (lambda q: J + m * dh(q) ** 2, lambda q: 2 * m * dh(q) * d2h(q),
            lambda q: -m * g * dh(q))


def trifilar_period(J, m, R1, R2, l, amplitude, g=9.81) -> float:
    """True period of a trifilar suspension twisted by ``amplitude``
    (:func:`trifilar_equation`)."""
    return period_of(*trifilar_equation(J, m, R1, R2, l, g), amplitude)


def stopwatch(period, n_osc, repeats, rng, *, reaction_sd=0.08, resolution=0.01):
    """Hand-timed readings of ``n_osc`` full oscillations.

    Each reading is n T plus the difference of two human reaction errors (start and stop,
    each normal with ``reaction_sd``), rounded to the stopwatch's resolution.

    Returns
    -------
    ndarray
        ``repeats`` readings. [s]
    """
    noise = rng.normal(0.0, reaction_sd, (2, repeats))
    t = n_osc * period + noise[1] - noise[0]
    return np.round(t / resolution) * resolution


def measured(true_value, limit, rng):
    """A reading off an instrument whose limit of error is ``limit`` (uniform error)."""
    return true_value + rng.uniform(-limit, limit)


def free_swing(inertia, d_inertia, d_potential, amplitude, duration, *, viscous=0.0,
               drag=0.0):
    """The free decay of M(q) q̈ + ½ M'(q) q̇² + V'(q) = −c_v q̇ − c_q q̇|q̇|, released at rest
    from q = ``amplitude``: linear (viscous: the pivot, the threads) and quadratic (air) damping.

    Parameters
    ----------
    inertia, d_inertia, d_potential : callable
        M(q) [kg·m²], dM/dq, dV/dq [N·m], vectorised.
    amplitude : float
        Release angle. [rad]
    duration : float
        Time integrated. [s]
    viscous, drag : float
        c_v [N·m·s] and c_q [N·m·s²].

    Returns
    -------
    motion : callable
        q(t) for an array of times within [0, duration] (dense output, relative error
        ~1e-10). [rad]
    crossings : numpy.ndarray
        The times q passes through zero. [s]
    """
    def rhs(_, y):
        q, w = y
        torque = d_potential(q) + viscous * w + drag * w * abs(w)
        return [w, -(0.5 * d_inertia(q) * w * w + torque) / inertia(q)]

    def crossing(_, y):
        return y[0]

    sol = solve_ivp(rhs, (0.0, float(duration)), [float(amplitude), 0.0], events=crossing,
                    dense_output=True, rtol=1e-11, atol=1e-13, method="DOP853")

    def motion(t):
        return sol.sol(np.asarray(t, dtype=float))[0]

    return motion, np.asarray(sol.t_events[0])
