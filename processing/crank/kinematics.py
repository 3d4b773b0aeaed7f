"""Crank-slider kinematics: piston and connecting-rod motion, exact and approximate.

Notation of FORMULAS.md section A: ``crank_angle`` α from the cylinder axis (TDC of an axial
mechanism) [rad], ``lambda_`` λ = R/L, ``offset_ratio`` z = k/R (piston-pin offset of a
desaxial mechanism, 0 for an axial one), ``crank_radius`` R [m], ``angular_speed`` ω [rad/s]
(constant), rod angle β.
Dimensionless forms, as published tables list them: s = S/R, v/(Rω), j/(Rω²).

Every formula broadcasts over crank angle, λ and z arrays. The exact forms hold for axial and
desaxial mechanisms alike; the approximate ones are the binomial series to λ² (and to λz).

References
----------
- dynlab FORMULAS.md, section A "Crank-slider kinematics".
- "Кинематика кривошипно-шатунного механизма" (course notes after Lukanin V.N. (ed.),
  Internal combustion engines, vol. 2: Dynamics and design, Vysshaya Shkola, 2009).
- Li Bin, Yang Chunlei, Liu Yong, "Analysis of the kinematic and dynamic characteristics
  of the crank-connecting rod mechanism" (曲柄连杆机构运动及动力特性分析), Machinery (机械),
  2006, no. 1, vol. 33, pp. 10-12.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from processing.diagnostics import InputError, check_positive, first
from processing.result import Record

_METHODS = ("exact", "approx")
_STROKES = ("down", "up")


def check_mechanism(lambda_, offset_ratio=0.0) -> None:
    """Raise :class:`~processing.diagnostics.InputError` unless λ and z make a working mechanism.

    Parameters
    ----------
    lambda_ : float or array_like
        Crank radius over rod length, λ = R/L; must lie in (0, 1). [1]
    offset_ratio : float or array_like, default 0
        Piston-pin offset over crank radius, z = k/R; needs λ(1 + |z|) < 1 so that the rod
        reaches every crank angle (|sin β| < 1). [1]

    Raises
    ------
    InputError
        (a ``ValueError``) naming the parameter, the bad value and the fix.
    """
    if isinstance(lambda_, (int, float)) and isinstance(offset_ratio, (int, float)) \
            and 0 < lambda_ < 1 and lambda_ * (1 + abs(offset_ratio)) < 1:
        return                          # plain numbers that work: no arrays made
    lam = np.asarray(lambda_, dtype=float)
    bad = ~((lam > 0) & (lam < 1))
    if np.any(bad):
        raise InputError(f"lambda_ must be in (0, 1), got {first(lam[bad]):g}",
                         "give lambda_ = R/L, crank radius over rod length (typically 0.24-0.32)")
    z = np.asarray(offset_ratio, dtype=float)
    reach = np.broadcast_to(lam * (1 + np.abs(z)), np.broadcast_shapes(lam.shape, z.shape))
    bad = ~(reach < 1)
    if np.any(bad):
        zb, lb = np.broadcast_arrays(z, lam)
        raise InputError(
            f"offset_ratio must satisfy lambda_*(1 + |z|) < 1, got z = {first(zb[bad]):g} "
            f"with lambda_ = {first(lb[bad]):g}",
            "give offset_ratio = k/R, the pin offset over the crank radius (a few hundredths)")


def _check_method(method: str) -> None:
    if method not in _METHODS:
        raise InputError(f"method must be 'exact' or 'approx', got {method!r}",
                         "pass method='exact' (true geometry) or method='approx' (series to λ²)")


def _cos_rod(crank_angle, lambda_, offset_ratio):
    """cos β = sqrt(1 − λ²(sin α − z)²)."""
    return np.sqrt(1 - (lambda_ * (np.sin(crank_angle) - offset_ratio)) ** 2)


def rod_angle(crank_angle, lambda_, offset_ratio=0.0):
    """Angle of the connecting rod to the cylinder axis, β.

    Parameters
    ----------
    crank_angle : float or array_like
        Crank angle from the cylinder axis (TDC of an axial mechanism), α. [rad]
    lambda_ : float or array_like
        Crank radius over rod length, λ = R/L. [1]
    offset_ratio : float or array_like, default 0
        Piston-pin offset over crank radius, z = k/R. [1]

    Returns
    -------
    float or ndarray
        Rod angle β, positive while the crank pin is on the positive side. [rad]

    Notes
    -----
    .. math:: \\sin\\beta = \\lambda(\\sin\\alpha - z)

    References
    ----------
    FORMULAS.md A; the Russian kinematics notes ("Угол отклонения шатуна").
    """
    check_mechanism(lambda_, offset_ratio)
    return np.arcsin(lambda_ * (np.sin(crank_angle) - offset_ratio))


def max_rod_angle(lambda_, offset_ratio=0.0):
    """Largest rod swing, max |β| over a revolution.

    Parameters
    ----------
    lambda_ : float or array_like
        Crank radius over rod length, λ. [1]
    offset_ratio : float or array_like, default 0
        Pin offset over crank radius, z. [1]

    Returns
    -------
    float or ndarray
        max |β|, reached at α = 90° or 270° (whichever side the offset adds to). [rad]

    Notes
    -----
    .. math:: \\beta_{max} = \\arcsin[\\lambda(1 + |z|)]
              \\approx \\lambda(1 + \\lambda^2/6)\\ \\text{for } z = 0

    Modern engines: 15-18° (Russian notes); the series form is Li Bin et al.'s table 1.

    References
    ----------
    FORMULAS.md A; Li Bin et al. 2006, table 1.
    """
    check_mechanism(lambda_, offset_ratio)
    return np.arcsin(lambda_ * (1 + np.abs(offset_ratio)))


def rod_angular_speed(crank_angle, angular_speed, lambda_, offset_ratio=0.0):
    """Angular speed of the rod's swing, dβ/dt, at constant crank speed.

    Parameters
    ----------
    crank_angle : float or array_like
        Crank angle α. [rad]
    angular_speed : float or array_like
        Crank angular speed ω. [rad/s]
    lambda_ : float or array_like
        λ = R/L. [1]
    offset_ratio : float or array_like, default 0
        z = k/R. [1]

    Returns
    -------
    float or ndarray
        Rod angular speed ω_rod; ±λω at α = 0°, 180° of an axial mechanism. [rad/s]

    Notes
    -----
    .. math:: \\omega_{rod} = \\lambda\\omega\\frac{\\cos\\alpha}
              {\\sqrt{1 - \\lambda^2(\\sin\\alpha - z)^2}} \\approx \\lambda\\omega\\cos\\alpha

    References
    ----------
    FORMULAS.md A; Russian kinematics notes ("Угловая скорость качания шатуна").
    """
    check_mechanism(lambda_, offset_ratio)
    return angular_speed * lambda_ * np.cos(crank_angle) / _cos_rod(crank_angle, lambda_, offset_ratio)


def rod_angular_acceleration(crank_angle, angular_speed, lambda_, offset_ratio=0.0):
    """Angular acceleration of the rod's swing, d²β/dt², at constant crank speed.

    Parameters
    ----------
    crank_angle : float or array_like
        Crank angle α. [rad]
    angular_speed : float or array_like
        Crank angular speed ω. [rad/s]
    lambda_ : float or array_like
        λ = R/L. [1]
    offset_ratio : float or array_like, default 0
        z = k/R. [1]

    Returns
    -------
    float or ndarray
        Rod angular acceleration ε_rod. [rad/s²]

    Notes
    -----
    .. math:: \\varepsilon_{rod} = \\lambda\\omega^2
              \\frac{\\lambda^2\\cos^2\\alpha(\\sin\\alpha - z) - \\sin\\alpha\\cos^2\\beta}
              {\\cos^3\\beta}

    For z = 0 this is -λ(1 - λ²)ω² sin α / cos³β ≈ -λω² sin α (both forms in FORMULAS.md A
    and Li Bin et al. 2006, table 1).

    References
    ----------
    FORMULAS.md A; Russian kinematics notes ("Угловое ускорение качания шатуна").
    """
    check_mechanism(lambda_, offset_ratio)
    cos_b = _cos_rod(crank_angle, lambda_, offset_ratio)
    sin_a = np.sin(crank_angle)
    numerator = lambda_ ** 2 * np.cos(crank_angle) ** 2 * (sin_a - offset_ratio) - sin_a * cos_b ** 2
    return angular_speed ** 2 * lambda_ * numerator / cos_b ** 3


def relative_displacement(crank_angle, lambda_, offset_ratio=0.0, *, method="exact"):
    """Piston displacement from TDC over crank radius, s = S/R.

    Parameters
    ----------
    crank_angle : float or array_like
        Crank angle α. [rad]
    lambda_ : float or array_like
        λ = R/L. [1]
    offset_ratio : float or array_like, default 0
        z = k/R. [1]
    method : {'exact', 'approx'}, keyword-only
        True geometry, or the binomial series to λ² (and λz).

    Returns
    -------
    float or ndarray
        s = S/R, from 0 at TDC to the stroke ratio (2 for z = 0) at BDC. [1]

    Notes
    -----
    .. math::
        s = \\sqrt{(1 + 1/\\lambda)^2 - z^2} - \\frac{\\cos\\beta}{\\lambda} - \\cos\\alpha

        s \\approx 1 + \\frac{\\lambda}{4} - \\cos\\alpha - \\frac{\\lambda}{4}\\cos 2\\alpha
              - \\lambda z \\sin\\alpha

    The exact form for z = 0 is (1 - cos α) + (1 - cos β)/λ. The approximation is O(λ³) off
    (O(λ²z²) for a desaxial mechanism, whose approximate s is not 0 at the true TDC).

    References
    ----------
    FORMULAS.md A; Russian kinematics notes; Li Bin et al. 2006, eqs. (1), (4).
    """
    check_mechanism(lambda_, offset_ratio)
    _check_method(method)
    if method == "approx":
        return (1 + lambda_ / 4 - np.cos(crank_angle) - lambda_ / 4 * np.cos(2 * crank_angle)
                - lambda_ * offset_ratio * np.sin(crank_angle))
    return (np.sqrt((1 + 1 / lambda_) ** 2 - offset_ratio ** 2)
            - _cos_rod(crank_angle, lambda_, offset_ratio) / lambda_ - np.cos(crank_angle))


def relative_velocity(crank_angle, lambda_, offset_ratio=0.0, *, method="exact"):
    """Piston velocity over crank-pin speed, v/(Rω) = ds/dα.

    Parameters
    ----------
    crank_angle : float or array_like
        Crank angle α. [rad]
    lambda_ : float or array_like
        λ = R/L. [1]
    offset_ratio : float or array_like, default 0
        z = k/R. [1]
    method : {'exact', 'approx'}, keyword-only
        True geometry, or the series to λ².

    Returns
    -------
    float or ndarray
        v/(Rω), positive while the piston moves away from TDC. [1]

    Notes
    -----
    .. math::
        \\frac{v}{R\\omega} = \\frac{\\sin(\\alpha + \\beta)}{\\cos\\beta}
        \\approx \\sin\\alpha + \\frac{\\lambda}{2}\\sin 2\\alpha - \\lambda z\\cos\\alpha

    The exact form is the derivative of the exact s for desaxial mechanisms too.

    References
    ----------
    FORMULAS.md A; Russian kinematics notes; Li Bin et al. 2006, eqs. (6), (7).
    """
    check_mechanism(lambda_, offset_ratio)
    _check_method(method)
    if method == "approx":
        return (np.sin(crank_angle) + lambda_ / 2 * np.sin(2 * crank_angle)
                - lambda_ * offset_ratio * np.cos(crank_angle))
    beta = rod_angle(crank_angle, lambda_, offset_ratio)
    return np.sin(crank_angle + beta) / np.cos(beta)


def relative_acceleration(crank_angle, lambda_, offset_ratio=0.0, *, method="exact"):
    """Piston acceleration over crank-pin centripetal acceleration, j/(Rω²) = d²s/dα².

    Parameters
    ----------
    crank_angle : float or array_like
        Crank angle α. [rad]
    lambda_ : float or array_like
        λ = R/L. [1]
    offset_ratio : float or array_like, default 0
        z = k/R. [1]
    method : {'exact', 'approx'}, keyword-only
        True geometry, or the series to λ².

    Returns
    -------
    float or ndarray
        j/(Rω²), positive towards BDC (1 + λ at TDC of an axial mechanism). [1]

    Notes
    -----
    .. math::
        \\frac{j}{R\\omega^2} = \\frac{\\cos(\\alpha + \\beta)}{\\cos\\beta}
        + \\frac{\\lambda\\cos^2\\alpha}{\\cos^3\\beta}
        \\approx \\cos\\alpha + \\lambda\\cos 2\\alpha + \\lambda z\\sin\\alpha

    The Russian notes print the desaxial term λz sin α outside the bracket (a slip; it is
    the derivative of the approximate velocity). Constant ω assumed.

    Examples
    --------
    >>> round(float(relative_acceleration(0.0, 0.25)), 12)   # 1 + λ at TDC
    1.25
    >>> round(float(relative_acceleration(np.pi / 2, 0.32)), 4)  # -tan β at 90°
    -0.3378

    References
    ----------
    FORMULAS.md A; Russian kinematics notes; Li Bin et al. 2006, eqs. (11), (12).
    """
    check_mechanism(lambda_, offset_ratio)
    _check_method(method)
    if method == "approx":
        return (np.cos(crank_angle) + lambda_ * np.cos(2 * crank_angle)
                + lambda_ * offset_ratio * np.sin(crank_angle))
    beta = rod_angle(crank_angle, lambda_, offset_ratio)
    cos_b = np.cos(beta)
    return np.cos(crank_angle + beta) / cos_b + lambda_ * np.cos(crank_angle) ** 2 / cos_b ** 3


def piston_displacement(crank_angle, crank_radius, lambda_, offset_ratio=0.0, *, method="exact"):
    """Piston displacement from TDC, S = R s (see :func:`relative_displacement`).

    Parameters
    ----------
    crank_angle : float or array_like
        Crank angle α. [rad]
    crank_radius : float or array_like
        Crank radius R. [m]
    lambda_, offset_ratio : float or array_like
        λ = R/L and z = k/R. [1]
    method : {'exact', 'approx'}, keyword-only
        As in :func:`relative_displacement`.

    Returns
    -------
    float or ndarray
        S. [m]

    References
    ----------
    FORMULAS.md A.
    """
    check_positive("crank_radius", crank_radius, "m")
    return crank_radius * relative_displacement(crank_angle, lambda_, offset_ratio, method=method)


def piston_velocity(crank_angle, crank_radius, angular_speed, lambda_, offset_ratio=0.0, *,
                    method="exact"):
    """Piston velocity, v = Rω · v/(Rω) (see :func:`relative_velocity`).

    Parameters
    ----------
    crank_angle : float or array_like
        Crank angle α. [rad]
    crank_radius : float or array_like
        Crank radius R. [m]
    angular_speed : float or array_like
        Crank angular speed ω. [rad/s]
    lambda_, offset_ratio : float or array_like
        λ = R/L and z = k/R. [1]
    method : {'exact', 'approx'}, keyword-only
        As in :func:`relative_velocity`.

    Returns
    -------
    float or ndarray
        v. [m/s]

    References
    ----------
    FORMULAS.md A.
    """
    check_positive("crank_radius", crank_radius, "m")
    return crank_radius * angular_speed * relative_velocity(crank_angle, lambda_, offset_ratio,
                                                            method=method)


def piston_acceleration(crank_angle, crank_radius, angular_speed, lambda_, offset_ratio=0.0, *,
                        method="exact"):
    """Piston acceleration, j = Rω² · j/(Rω²) (see :func:`relative_acceleration`).

    Parameters
    ----------
    crank_angle : float or array_like
        Crank angle α. [rad]
    crank_radius : float or array_like
        Crank radius R. [m]
    angular_speed : float or array_like
        Crank angular speed ω (constant). [rad/s]
    lambda_, offset_ratio : float or array_like
        λ = R/L and z = k/R. [1]
    method : {'exact', 'approx'}, keyword-only
        As in :func:`relative_acceleration`.

    Returns
    -------
    float or ndarray
        j. [m/s²]

    References
    ----------
    FORMULAS.md A.
    """
    check_positive("crank_radius", crank_radius, "m")
    return crank_radius * angular_speed ** 2 * relative_acceleration(
        crank_angle, lambda_, offset_ratio, method=method)


@dataclass(frozen=True)
class DeadCentres(Record):
    """Crank angles of the dead centres and the stroke (:func:`dead_centres`)."""

    tdc: float | np.ndarray
    """Crank angle of TDC, α_TDC = arcsin(λz/(1 + λ)). [rad]"""
    bdc: float | np.ndarray
    """Crank angle of BDC, α_BDC = π + arcsin(λz/(1 - λ)). [rad]"""
    stroke_ratio: float | np.ndarray
    """Stroke over crank radius, S_max/R (2 for an axial mechanism). [1]"""


def dead_centres(lambda_, offset_ratio=0.0) -> DeadCentres:
    """Dead-centre crank angles and stroke of an axial or desaxial mechanism.

    Parameters
    ----------
    lambda_ : float or array_like
        λ = R/L. [1]
    offset_ratio : float or array_like, default 0
        z = k/R. [1]

    Returns
    -------
    DeadCentres
        ``tdc``, ``bdc`` [rad] and ``stroke_ratio`` [1].

    Notes
    -----
    At the dead centres crank and rod are in line (R + L, resp. L - R, from the crank axis to
    the pin, which sits k off the axis):

    .. math::
        \\sin\\alpha_{TDC} = \\frac{\\lambda z}{1 + \\lambda},\\quad
        \\alpha_{BDC} = \\pi + \\arcsin\\frac{\\lambda z}{1 - \\lambda},\\quad
        \\frac{S_{max}}{R} = \\sqrt{(1 + 1/\\lambda)^2 - z^2} - \\sqrt{(1/\\lambda - 1)^2 - z^2}

    References
    ----------
    FORMULAS.md A (geometry of the desaxial displacement formula).
    """
    check_mechanism(lambda_, offset_ratio)
    return DeadCentres(
        tdc=np.arcsin(lambda_ * offset_ratio / (1 + lambda_)),
        bdc=np.pi + np.arcsin(lambda_ * offset_ratio / (1 - lambda_)),
        stroke_ratio=(np.sqrt((1 + 1 / lambda_) ** 2 - offset_ratio ** 2)
                      - np.sqrt((1 / lambda_ - 1) ** 2 - offset_ratio ** 2)))


def crank_angle_from_displacement(displacement, lambda_, offset_ratio=0.0, *, method="exact",
                                  stroke="down"):
    """Crank angle at which the piston is a given distance from TDC (inverse kinematics).

    Parameters
    ----------
    displacement : float or array_like
        Relative piston displacement s = S/R, between 0 and the stroke ratio. [1]
    lambda_ : float or array_like
        λ = R/L. [1]
    offset_ratio : float or array_like, default 0
        z = k/R; must be 0 for ``method='approx'``. [1]
    method : {'exact', 'approx'}, keyword-only
        Invert the exact geometry, or the approximate s (axial only).
    stroke : {'down', 'up'}, keyword-only
        'down': TDC → BDC, α in [α_TDC, α_BDC] (= [0, π] for z = 0);
        'up': BDC → TDC, α in [α_BDC, α_TDC + 2π].

    Returns
    -------
    float or ndarray
        Crank angle α. [rad]

    Raises
    ------
    InputError
        If s lies outside the stroke, or ``method='approx'`` with z ≠ 0.

    Notes
    -----
    Exact: with the pin at ξ = x/R = sqrt((1 + 1/λ)² - z²) - s from the crank axis and z off
    it, the rod length gives ξ cos α + z sin α = (ξ² + 1 + z² - 1/λ²)/2, so

    .. math:: \\alpha = \\operatorname{atan2}(z, \\xi) \\pm
              \\arccos\\frac{\\xi^2 + 1 + z^2 - 1/\\lambda^2}{2\\sqrt{\\xi^2 + z^2}}

    Approximate (z = 0), the root of the quadratic in cos α of the approximate s:

    .. math:: \\cos\\alpha = \\frac{\\sqrt{(1 + \\lambda)^2 - 2\\lambda s} - 1}{\\lambda},
              \\qquad \\alpha \\approx \\sqrt{2s/(1 + \\lambda)}\\ \\text{for small } s

    FORMULAS.md prints the root as ((1 + λ) - sqrt(...))/λ, which gives 90° at TDC: wrong.

    References
    ----------
    FORMULAS.md A ("Inverse").
    """
    _check_method(method)
    if stroke not in _STROKES:
        raise InputError(f"stroke must be 'down' or 'up', got {stroke!r}",
                         "pass stroke='down' (TDC to BDC) or stroke='up' (BDC to TDC)")
    centres = dead_centres(lambda_, offset_ratio)
    s = np.asarray(displacement, dtype=float)
    s, span = np.broadcast_arrays(s, centres.stroke_ratio)
    bad = ~((s >= -1e-12) & (s <= span + 1e-12))
    if np.any(bad):
        raise InputError(f"displacement must lie in [0, stroke ratio], got {first(s[bad]):g}",
                         "pass s = S/R measured from TDC, at most the stroke over the crank radius")
    if method == "approx":
        if np.any(np.asarray(offset_ratio) != 0):
            raise InputError("method='approx' inverts the axial approximate displacement only, "
                             f"got offset_ratio = {first(np.asarray(offset_ratio)):g}",
                             "use method='exact' for a desaxial mechanism")
        cos_a = (np.sqrt(np.maximum((1 + lambda_) ** 2 - 2 * lambda_ * s, 0.0)) - 1) / lambda_
        down = np.arccos(np.clip(cos_a, -1, 1))
        return down if stroke == "down" else 2 * np.pi - down
    xi = np.sqrt((1 + 1 / lambda_) ** 2 - offset_ratio ** 2) - s
    half_chord = (xi ** 2 + 1 + offset_ratio ** 2 - 1 / lambda_ ** 2) / (2 * np.hypot(xi, offset_ratio))
    swing = np.arccos(np.clip(half_chord, -1, 1))
    base = np.arctan2(offset_ratio, xi)
    return base + swing if stroke == "down" else base - swing + 2 * np.pi


def approximation_error(crank_angle, lambda_, offset_ratio=0.0, *, quantity="j"):
    """Error of the approximate (series) form: approx - exact.

    Parameters
    ----------
    crank_angle : float or array_like
        Crank angle α. [rad]
    lambda_ : float or array_like
        λ = R/L. [1]
    offset_ratio : float or array_like, default 0
        z = k/R. [1]
    quantity : {'s', 'v', 'j'}, keyword-only
        Displacement s = S/R, velocity v/(Rω) or acceleration j/(Rω²).

    Returns
    -------
    float or ndarray
        Approximate minus exact value, in units of R, Rω or Rω². [1]

    References
    ----------
    FORMULAS.md A; Li Bin et al. 2006 (error discussion after eqs. (7) and (12)).
    """
    func = _quantity(quantity)
    return (func(crank_angle, lambda_, offset_ratio, method="approx")
            - func(crank_angle, lambda_, offset_ratio, method="exact"))


def _quantity(quantity: str):
    table = {"s": relative_displacement, "v": relative_velocity, "j": relative_acceleration}
    if quantity not in table:
        raise InputError(f"quantity must be 's', 'v' or 'j', got {quantity!r}",
                         "pick displacement 's', velocity 'v' or acceleration 'j'")
    return table[quantity]


@dataclass(frozen=True)
class ApproximationError(Record):
    """Largest error of an approximate kinematic form (:func:`max_approximation_error`).

    Errors are dimensionless (units R, Rω, Rω² for s, v, j); angles in [0, 2π).
    """

    quantity: str
    """'s', 'v' or 'j'."""
    max_abs_error: float | np.ndarray
    """max over α of |approx - exact|. [1]"""
    crank_angle: float | np.ndarray
    """A crank angle where that maximum occurs (90° or 270° for j: the tie is rounding). [rad]"""
    error: float | np.ndarray
    """Signed error approx - exact there. [1]"""
    relative_error: float | np.ndarray
    """error / exact at that angle (the seeds' "about 5.3 %" for j). [1]"""
    max_relative_error: float | np.ndarray
    """sup over α of |approx/exact - 1|; inf where the exact value has a zero the
    approximation does not share (j always; v, s of a desaxial mechanism). [1]"""
    crank_angle_relative: float | np.ndarray
    """Where the largest relative error occurs (nan when it is infinite). [rad]"""


def _locate_max(func, shape, points=721, rounds=4):
    """Crank angle in [0, 2π) maximising ``func(α)`` per parameter set, by zooming grids.

    ``func`` takes α of shape (n, 1, ..., 1) broadcasting against ``shape``; each round
    re-grids ± one step around the best point, so the step shrinks (points - 1)/2 times.
    """
    expand = (slice(None),) + (None,) * len(shape)
    step = 2 * np.pi / (points - 1)
    grid = np.linspace(0.0, 2 * np.pi, points)[expand] + np.zeros(shape)
    for _ in range(rounds):
        values = np.broadcast_to(func(grid), grid.shape)
        index = np.argmax(values, axis=0)[None]
        best = np.take_along_axis(grid, index, axis=0)[0]
        grid = best + step * np.linspace(-1.0, 1.0, points)[expand]
        step *= 2 / (points - 1)
    return np.mod(best, 2 * np.pi)


def _unshared_zero(exact, error):
    """Whether ``exact`` changes sign on the grid (axis 0) where ``error`` is not ~0."""
    left, right = exact[:-1], exact[1:]
    crossing = (left == 0) | (left * right < 0)
    weight = np.divide(left, left - right, out=np.zeros_like(left), where=left != right)
    error_at_zero = error[:-1] + (error[1:] - error[:-1]) * weight
    scale = np.max(np.abs(error), axis=0)
    return np.any(crossing & (np.abs(error_at_zero) > 1e-6 * scale), axis=0)


def max_approximation_error(lambda_, offset_ratio=0.0, *, quantity="j") -> ApproximationError:
    """Largest absolute and relative error of the approximate s, v or j over a revolution.

    Parameters
    ----------
    lambda_ : float or array_like
        λ = R/L. [1]
    offset_ratio : float or array_like, default 0
        z = k/R. [1]
    quantity : {'s', 'v', 'j'}, keyword-only
        Which form to assess.

    Returns
    -------
    ApproximationError
        Maximum |error|, the α where it occurs, the signed and relative error there, and the
        largest relative error anywhere with its α. Fields broadcast over λ, z.

    Notes
    -----
    .. math:: \\Delta(\\alpha) = x_{approx}(\\alpha) - x_{exact}(\\alpha),\\quad
              \\max_\\alpha |\\Delta|,\\quad \\sup_\\alpha |\\Delta / x_{exact}|

    Located on a 0.5° grid, then refined by zooming to ~1e-8 rad. At λ = 0.32 (axial) this
    reproduces the published figures: j is off by 0.0178 Rω² at 90° and 270°, 5.3 % of the
    exact j there (5.6 % of the approximate one); v at most 0.0057 Rω (at 60.5°), and the
    largest relative v error is 0.83 % (at 127.5°/232.5°), 0 at 0°, 90°, 180°, 270°; s at most
    0.0043 R at 90° (0.37 % of s there), largest relative s error 0.42 % (at 73.6°).

    Examples
    --------
    >>> r = max_approximation_error(0.32, quantity="j")
    >>> round(float(r.max_abs_error), 4), round(float(abs(r.relative_error)), 3)
    (0.0178, 0.053)

    References
    ----------
    FORMULAS.md A; Li Bin et al. 2006, pp. 10-11.
    """
    func = _quantity(quantity)
    check_mechanism(lambda_, offset_ratio)
    shape = np.broadcast_shapes(np.shape(lambda_), np.shape(offset_ratio))

    def error(alpha):
        return approximation_error(alpha, lambda_, offset_ratio, quantity=quantity)

    def relative(alpha):
        exact = np.broadcast_to(func(alpha, lambda_, offset_ratio, method="exact"), alpha.shape)
        delta = np.broadcast_to(error(alpha), alpha.shape)
        # |exact| < 1e-9 is a zero up to rounding (sin π ≠ 0): the ratio is 0/0 there
        return np.abs(np.divide(delta, exact, out=np.zeros(alpha.shape), where=np.abs(exact) > 1e-9))

    at_max = _locate_max(lambda a: np.abs(error(a)), shape)
    signed = error(at_max)
    exact_there = func(at_max, lambda_, offset_ratio, method="exact")
    grid = np.linspace(0.0, 2 * np.pi, 1441)[(slice(None),) + (None,) * len(shape)] + np.zeros(shape)
    infinite = _unshared_zero(func(grid, lambda_, offset_ratio, method="exact"), error(grid))
    at_rel = _locate_max(relative, shape)
    return ApproximationError(
        quantity=quantity,
        max_abs_error=np.abs(signed),
        crank_angle=at_max,
        error=signed,
        relative_error=np.divide(signed, exact_there, out=np.full(np.shape(signed), np.nan),
                                 where=exact_there != 0)[()],
        max_relative_error=np.where(infinite, np.inf, relative(np.asarray(at_rel)[None])[0])[()],
        crank_angle_relative=np.where(infinite, np.nan, at_rel)[()])


@dataclass(frozen=True)
class AccelerationExtremes(Record):
    """Extremes of the approximate piston acceleration j/(Rω²) (:func:`acceleration_extremes`)."""

    at_tdc: float | np.ndarray
    """j/(Rω²) at α = 0: 1 + λ (exact too). [1]"""
    at_bdc: float | np.ndarray
    """j/(Rω²) at α = 180°: -(1 - λ) (exact too). [1]"""
    third_angle: float | np.ndarray
    """arccos(-1/(4λ)), the third extremum (only for λ > 1/4, else nan). [rad]"""
    third_value: float | np.ndarray
    """-(λ + 1/(8λ)) there, the largest negative j (nan for λ ≤ 1/4). [1]"""


def acceleration_extremes(lambda_) -> AccelerationExtremes:
    """Extremes of the approximate piston acceleration of an axial mechanism.

    Parameters
    ----------
    lambda_ : float or array_like
        λ = R/L. [1]

    Returns
    -------
    AccelerationExtremes
        Values at TDC and BDC, and the third extremum (nan unless λ > 1/4).

    Notes
    -----
    dj/dα = -sin α (1 + 4λ cos α) = 0 at α = 0, π and cos α = -1/(4λ) (real for λ > 1/4):

    .. math:: j_0 = 1 + \\lambda,\\quad j_\\pi = -(1 - \\lambda),\\quad
              j_3 = -\\left(\\lambda + \\frac{1}{8\\lambda}\\right)

    References
    ----------
    FORMULAS.md A; Li Bin et al. 2006, eq. (13).
    """
    check_mechanism(lambda_)
    lam = np.asarray(lambda_, dtype=float)
    has_third = lam > 0.25
    cos_third = np.where(has_third, -1 / (4 * lam), np.nan)
    return AccelerationExtremes(
        at_tdc=(1 + lam)[()], at_bdc=(lam - 1)[()],
        third_angle=np.arccos(cos_third)[()],
        third_value=np.where(has_third, -(lam + 1 / (8 * lam)), np.nan)[()])


def mean_piston_speed(stroke, angular_speed):
    """Mean piston speed over a revolution, c_m.

    Parameters
    ----------
    stroke : float or array_like
        Piston stroke S (2R for an axial mechanism). [m]
    angular_speed : float or array_like
        Crank angular speed ω = πn/30. [rad/s]

    Returns
    -------
    float or ndarray
        c_m. [m/s]

    Notes
    -----
    .. math:: c_m = \\frac{S\\omega}{\\pi} = \\frac{S n}{30} = \\frac{2}{\\pi}R\\omega
              = 0.6366\\,R\\omega

    References
    ----------
    FORMULAS.md A; Russian kinematics notes (v_ср = Sn/30); Li Bin et al. 2006, eq. (10).
    """
    check_positive("stroke", stroke, "m")
    return stroke * angular_speed / np.pi


def kinematics_table(lambda_, offset_ratio=0.0, *, step_deg=5.0, method="exact"):
    """The textbook table of crank-slider kinematics for one mechanism.

    Parameters
    ----------
    lambda_ : float
        λ = R/L. [1]
    offset_ratio : float, default 0
        z = k/R. [1]
    step_deg : float, keyword-only
        Crank-angle step; rows run from 0° to 360° inclusive (360 must be a multiple). [deg]
    method : {'exact', 'approx'}, keyword-only
        Form of s, v, j (β is always exact).

    Returns
    -------
    pandas.DataFrame
        Columns ``alpha_deg`` [deg], ``beta_deg`` [deg], ``s`` (S/R), ``v`` (v/(Rω)),
        ``j`` (j/(Rω²)); ``attrs`` hold ``lambda_``, ``offset_ratio``, ``method`` and the units.

    References
    ----------
    FORMULAS.md A ("Dimensionless forms ... are what published tables list").
    """
    import pandas as pd

    if not (np.ndim(lambda_) == 0 and np.ndim(offset_ratio) == 0):
        raise InputError("kinematics_table takes one mechanism: scalar lambda_ and offset_ratio",
                         "call it once per (lambda_, offset_ratio)")
    count = 360.0 / step_deg if step_deg > 0 else np.nan
    if not (np.isfinite(count) and abs(count - round(count)) < 1e-9):
        raise InputError(f"step_deg must divide 360 evenly, got {step_deg:g}",
                         "use e.g. 1, 2, 5, 10, 15 or 30 degrees")
    alpha = np.radians(np.linspace(0.0, 360.0, int(round(count)) + 1))
    table = pd.DataFrame({
        "alpha_deg": np.degrees(alpha),
        "beta_deg": np.degrees(rod_angle(alpha, lambda_, offset_ratio)),
        "s": relative_displacement(alpha, lambda_, offset_ratio, method=method),
        "v": relative_velocity(alpha, lambda_, offset_ratio, method=method),
        "j": relative_acceleration(alpha, lambda_, offset_ratio, method=method),
    })
    table.attrs.update(lambda_=float(lambda_), offset_ratio=float(offset_ratio), method=method,
                       units={"alpha_deg": "deg", "beta_deg": "deg", "s": "S/R", "v": "v/(R*omega)",
                              "j": "j/(R*omega^2)"})
    return table
