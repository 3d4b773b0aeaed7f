"""Balance of in-line piston engines: free forces and moments of the rotating masses and of
the first- and second-order reciprocating inertia forces.

Geometry and conventions
------------------------
All cylinders stand in one plane (an in-line engine) and share the crank radius ``r``, the
ratio λ = r/L and the speed ω. Axes: **x** along the crankshaft (``positions`` of the
cylinders, in any origin), **y** along the cylinder axes (towards the heads), **z** across
(the side a crank moves towards just after its TDC).

Cylinder *j* has its crank ``crank_angles[j]`` = θ_j ahead of crank 1 in the direction of
rotation: when crank 1 is at α (from its TDC), crank *j* is at α + θ_j (the manual writes
cos(180° + α) for the second cylinder of a 180° twin). θ_1 = 0 is usual, not required.

Forces are those the moving masses exert on the engine frame:

- rotating (centrifugal): m_r r ω² along the crank, a vector of constant length turning with
  the shaft; its components along y and z are m_r r ω² cos α_j and m_r r ω² sin α_j;
- reciprocating, along y: m_j j(α_j) (j > 0 towards BDC, so the force points at the head at
  TDC), whose series is m_j r ω² (cos α_j + λ cos 2α_j): first order m_j r ω² cos α_j, second
  order λ m_j r ω² cos 2α_j.

Moments are taken about the transverse line through x_0 (``about``; default the middle of the
cylinder row): M = Σ F_j (x_0 - x_j), positive when it lifts the end of smaller x (the front,
with cylinder 1, if x is counted from there) towards the heads. This is the manual's sign: for
its 180° twin M_j1 = m_j r ω² a cos α. The free moment of a force system whose resultant is zero
does not depend on x_0.

Phasors
-------
Every order k is one complex sum over the cylinders (k = 1 for rotating and first-order,
2 for second-order):

.. math:: S_k = \\sum_j m_j e^{i k \\theta_j},\\qquad T_k = \\sum_j m_j (x_0 - x_j) e^{i k\\theta_j}

Rotating: the force vector (y + i z) is r ω² U e^{iα}, U = S_1 over the rotating masses (and
any other masses on the shaft); its **amplitude** r ω² |U| is its constant length. Reciprocating
order k: the force along y is

.. math:: F_k(\\alpha) = c_k r\\omega^2 \\,\\mathrm{Re}\\big(S_k e^{ik\\alpha}\\big)
          = A_k\\cos(k\\alpha + \\varphi_k),\\qquad c_1 = 1,\\ c_2 = \\lambda

with **amplitude** A_k = c_k r ω² |S_k|, the peak of the resultant along the cylinder axis over
a revolution (reached when crank 1 is at α = -φ_k/k), and phase φ_k = arg S_k. As a vector,
Re(z) = (z + z̄)/2: the oscillating force is a pair of vectors of length A_k/2 turning at kω
forwards and backwards. The forward one can be cancelled by masses on the crankshaft (k = 1),
the backward one needs a shaft turning the other way: that is why the manual's first-order
balancer puts half of the moment on the crankshaft and half on a counter-rotating shaft.
Moments follow with T_k in place of S_k.

The real and imaginary parts of a sum are set to exactly zero where they are below 1e-12 of the
sum of the magnitudes of its terms (round-off of e^{iπ} and friends); the phase of a zero sum
is ``nan``.

References
----------
- Lab manual "Dynamics of internal-combustion engines" (Vladimir State University, 2003),
  lab 8 ("Исследование системы уравновешивания двухцилиндрового рядного двигателя").
- dynlab FORMULAS.md, section A (j(α) and its series) and "Lab 8".
- Lukanin V.N. (ed.), "Dvigateli vnutrennego sgoraniya", vol. 2 "Dinamika i konstruirovanie",
  Vysshaya Shkola, 1995 / 2009 (balancing of in-line engines).
- Taylor C.F., "The Internal-Combustion Engine in Theory and Practice", vol. 2, MIT Press,
  1985 (engine balance, the rotating-vector method).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from processing.diagnostics import InputError, check_positive, first
from .kinematics import check_mechanism, piston_acceleration
from processing.result import Record

ROUND_OFF = 1e-12
"""Sums below this fraction of the sum of their terms' magnitudes are exactly zero."""

STECHKIN_KLIMOV_LIMIT = 0.002
"""ξ below this is a satisfactory balance by the Stechkin–Klimov criterion (lab manual, lab 8)."""

KINDS = ("rotating", "first", "second")


@dataclass(frozen=True)
class OrderBalance(Record):
    """Free force and free moment of one kind of inertia force (see the module's conventions).

    Arrays where the inputs carried leading axes (e.g. Monte Carlo draws).
    """

    kind: str
    """``"rotating"`` (centrifugal), ``"first"`` or ``"second"`` (reciprocating orders)."""
    order: int
    """Harmonic order k: the force turns or oscillates at kω (1, 1, 2)."""
    force: float | np.ndarray
    """Amplitude of the free force: the constant length of the rotating vector, or the peak
    of the resultant along the cylinder axis. [N]"""
    force_phase: float | np.ndarray
    """φ in F cos(kα + φ) (rotating: the vector's angle ahead of crank 1); nan if F = 0. [rad]"""
    moment: float | np.ndarray
    """Amplitude of the free moment about the transverse axis through ``about``. [N·m]"""
    moment_phase: float | np.ndarray
    """φ in M cos(kα + φ); nan if M = 0. [rad]"""

    @property
    def force_peak_angle(self):
        """Crank-1 angle in [0, 2π/k) where the force along the cylinder axis peaks. [rad]"""
        return np.mod(-np.asarray(self.force_phase) / self.order, 2 * np.pi / self.order)

    @property
    def moment_peak_angle(self):
        """Crank-1 angle in [0, 2π/k) where the moment (cylinder-axis plane) peaks. [rad]"""
        return np.mod(-np.asarray(self.moment_phase) / self.order, 2 * np.pi / self.order)


@dataclass(frozen=True)
class InlineBalance(Record):
    """Free forces and moments of an in-line engine (:func:`inline_balance`)."""

    rotating: OrderBalance
    """Centrifugal forces of the rotating masses (crank pins, webs, the rods' big ends,
    counterweights)."""
    first: OrderBalance
    """First-order reciprocating forces, m_j r ω² cos α_j."""
    second: OrderBalance
    """Second-order reciprocating forces, λ m_j r ω² cos 2α_j."""
    about: float | np.ndarray
    """x_0, the axial position the moments are taken about. [m]"""

    def __iter__(self):
        return iter((self.rotating, self.first, self.second))


@dataclass(frozen=True)
class InlineHistory(Record):
    """Free forces and moments over crank angle (:func:`inline_history`); arrays (..., n)."""

    crank_angle: np.ndarray
    """α of crank 1. [rad]"""
    rotating_force_along: np.ndarray
    """Resultant centrifugal force along the cylinder axes. [N]"""
    rotating_force_across: np.ndarray
    """Resultant centrifugal force across them (z). [N]"""
    first_order_force: np.ndarray
    """Σ m_j r ω² cos α_j along the cylinder axes. [N]"""
    second_order_force: np.ndarray
    """Σ λ m_j r ω² cos 2α_j. [N]"""
    reciprocating_force: np.ndarray
    """Σ m_j j(α_j) with the exact piston acceleration (all orders). [N]"""
    rotating_moment_along: np.ndarray
    """Moment of the centrifugal components along the cylinder axes (in their plane). [N·m]"""
    rotating_moment_across: np.ndarray
    """Moment of the centrifugal components across (in the plane normal to the axes). [N·m]"""
    first_order_moment: np.ndarray
    """[N·m]"""
    second_order_moment: np.ndarray
    """[N·m]"""
    reciprocating_moment: np.ndarray
    """Exact, all orders. [N·m]"""

    def plot(self, fig, lang: str = "en"):
        """Draw forces (top) and moments (bottom) over one revolution on a matplotlib Figure.

        Curves that vanish identically are left out and named in a note instead.

        Parameters
        ----------
        fig : matplotlib.figure.Figure
            Where to draw (two axes are added).
        lang : {"en", "ru"}

        Returns
        -------
        (Axes, Axes)
            The force and moment axes, for the caller to add to.
        """
        ru = lang == "ru"
        deg = np.degrees(self.crank_angle)
        ax_f, ax_m = fig.subplots(2, 1, sharex=True)
        curves = (
            (ax_f, self.rotating_force_along, "F_r", "C0", "-"),
            (ax_f, self.first_order_force, "F_j1", "C1", "-"),
            (ax_f, self.second_order_force, "F_j2", "C2", "-"),
            (ax_f, self.reciprocating_force, "ΣP_j" + (" (точно)" if ru else " (exact)"), "k", ":"),
            (ax_m, self.rotating_moment_along, "M_r", "C0", "-"),
            (ax_m, self.first_order_moment, "M_j1", "C1", "-"),
            (ax_m, self.second_order_moment, "M_j2", "C2", "-"),
            (ax_m, self.reciprocating_moment, "ΣM_j" + (" (точно)" if ru else " (exact)"), "k", ":"),
        )
        scale = {ax_f: max(1e-300, *(np.max(np.abs(c[1])) for c in curves[:4])),
                 ax_m: max(1e-300, *(np.max(np.abs(c[1])) for c in curves[4:]))}
        zero = {ax_f: [], ax_m: []}
        for ax, y, name, color, style in curves:
            if np.max(np.abs(y)) <= 1e-9 * scale[ax]:
                zero[ax].append(name)
            else:
                ax.plot(deg, y, style, color=color, label=name)
        for ax, unit in ((ax_f, "Н" if ru else "N"), (ax_m, "Н·м" if ru else "N·m")):
            ax.axhline(0, color="grey", lw=0.5)
            ax.set_ylabel(f"{'F' if ax is ax_f else 'M'}, {unit}")
            ax.grid(alpha=0.3)
            if zero[ax]:
                ax.text(0.01, 0.03, ", ".join(zero[ax]) + " = 0", transform=ax.transAxes,
                        fontsize=8, color="grey")
            if ax.get_legend_handles_labels()[0]:
                low, high = ax.get_ylim()
                ax.set_ylim(low, high + 0.4 * (high - low))
                ax.legend(fontsize=7, loc="upper center", ncol=5, frameon=False)
        ax_m.set_xlabel("угол поворота кривошипа 1-го цилиндра α, °" if ru
                        else "crank angle of cylinder 1, α, deg")
        ax_m.set_xlim(deg[0], deg[-1])
        ax_m.set_xticks(np.arange(90 * np.ceil(deg[0] / 90), deg[-1] + 1e-9, 90.0))
        fig.tight_layout()
        return ax_f, ax_m


# ------------------------------------------------------------------------- phasor sums

def phasor_sum(angles, weights, *, order=1):
    """Σ_j w_j e^{i k θ_j} over the last axis, round-off set to exactly zero.

    Parameters
    ----------
    angles : array_like
        θ_j, one per term along the last axis. [rad]
    weights : array_like
        w_j (a mass [kg], or a mass times a lever arm [kg·m]); broadcasts with ``angles``.
    order : int, keyword-only
        k.

    Returns
    -------
    complex or ndarray
        The sum over the last axis; its real and imaginary parts are exactly 0 where they are
        below :data:`ROUND_OFF` · Σ|w_j| (so e^{iπ} sums cancel cleanly).

    Examples
    --------
    Two equal throws at 180°: the first order cancels, the second adds.

    >>> theta = np.radians([0.0, 180.0])
    >>> complex(phasor_sum(theta, 1.0)), complex(phasor_sum(theta, 1.0, order=2))
    (0j, (2+0j))
    """
    theta, w = np.broadcast_arrays(np.asarray(angles, dtype=float), np.asarray(weights, dtype=float))
    return _snap(np.sum(w * np.exp(1j * order * theta), axis=-1), np.sum(np.abs(w), axis=-1))


def _snap(total, scale):
    """Real and imaginary parts below ROUND_OFF · scale set to exactly zero."""
    tol = ROUND_OFF * scale
    total = (np.where(np.abs(total.real) <= tol, 0.0, total.real)
             + 1j * np.where(np.abs(total.imag) <= tol, 0.0, total.imag))
    return total[()] if total.ndim == 0 else total


def _phase(z):
    phase = np.where(z == 0, np.nan, np.angle(z))
    return phase[()] if np.ndim(phase) == 0 else phase


def _scalar(v):
    v = np.asarray(v)
    return v[()] if v.ndim == 0 else v


def _layout(crank_angles, positions, reciprocating_mass, rotating_mass, about, shaft_masses):
    """Validated arrays (..., n) of the cylinders, lever arms x_0 - x, and the shaft masses."""
    theta = np.asarray(crank_angles, dtype=float)
    x = np.asarray(positions, dtype=float)
    if theta.ndim == 0 or x.ndim == 0:
        raise InputError("crank_angles and positions need one entry per cylinder (last axis), "
                         f"got shapes {theta.shape} and {x.shape}",
                         "pass e.g. crank_angles=np.radians([0, 180]), positions=[0.0, 0.14]")
    try:
        theta, x, m_j, m_r = np.broadcast_arrays(theta, x, np.asarray(reciprocating_mass, float),
                                                 np.asarray(rotating_mass, float))
    except ValueError:
        raise InputError(
            f"crank_angles {np.shape(crank_angles)}, positions {np.shape(positions)}, "
            f"reciprocating_mass {np.shape(reciprocating_mass)} and rotating_mass "
            f"{np.shape(rotating_mass)} do not broadcast",
            "give one value per cylinder along the last axis, or one value for all; Monte "
            "Carlo draws of a common mass go in as shape (N, 1)") from None
    for name, v in (("crank_angles", theta), ("positions", x), ("reciprocating_mass", m_j),
                    ("rotating_mass", m_r)):
        if not np.all(np.isfinite(v)):
            raise InputError(f"{name} must be finite, got {first(v[~np.isfinite(v)])}",
                             f"check {name}")
    if np.any(m_j < 0):
        raise InputError(f"reciprocating_mass must be ≥ 0 kg, got {first(m_j[m_j < 0]):g}",
                         "give the piston group plus the rod's small-end share, in kg")
    x0 = 0.5 * (x.min(axis=-1) + x.max(axis=-1)) if about is None else np.asarray(about, float)
    offset = np.asarray(x0)[..., None] - x
    shaft = None
    if shaft_masses is not None:
        try:
            s_theta, s_x, s_m = (np.asarray(v, dtype=float) for v in shaft_masses)
            s_theta, s_x, s_m = np.broadcast_arrays(s_theta, s_x, s_m)
        except (TypeError, ValueError):
            raise InputError("shaft_masses must be three arrays (angles [rad], positions [m], "
                             "masses reduced to the crank radius [kg]) of one shape",
                             "pass shaft_masses=(angles, positions, masses)") from None
        if s_theta.ndim == 0 or not np.all(np.isfinite(s_m)):
            raise InputError("shaft_masses need one finite entry per mass along the last axis",
                             "pass shaft_masses=(angles, positions, masses) as arrays")
        shaft = (s_theta, np.asarray(x0)[..., None] - s_x, s_m)
    return theta, offset, m_j, m_r, _scalar(x0), shaft


def _check_engine(crank_radius, angular_speed, lambda_):
    check_positive("crank_radius", crank_radius, "m")
    w = np.asarray(angular_speed, dtype=float)
    if not np.all(np.isfinite(w)) or np.any(w < 0):
        raise InputError(f"angular_speed must be ≥ 0 rad/s, got {first(w)}",
                         "give ω = πn/30 with n in min⁻¹")
    check_mechanism(lambda_)


def _order(kind, order, scale, force_sum, moment_sum) -> OrderBalance:
    return OrderBalance(kind=kind, order=order, force=_scalar(scale * np.abs(force_sum)),
                        force_phase=_phase(force_sum), moment=_scalar(scale * np.abs(moment_sum)),
                        moment_phase=_phase(moment_sum))


def inline_balance(crank_angles, positions, reciprocating_mass, rotating_mass, crank_radius,
                   angular_speed, lambda_, *, about=None, shaft_masses=None) -> InlineBalance:
    """Free forces and moments of an in-line engine: rotating, first and second order.

    Parameters
    ----------
    crank_angles : array_like
        θ_j, angle of each crank ahead of crank 1 in the direction of rotation, one per
        cylinder along the last axis. [rad]
    positions : array_like
        x_j, axial position of each cylinder's axis (any origin). [m]
    reciprocating_mass : float or array_like
        m_j of each cylinder (piston group plus the rod's small-end share), or one for all.
        Leading axes broadcast (Monte Carlo draws of a common mass: shape (N, 1)). [kg]
    rotating_mass : float or array_like
        m_r of each crank, reduced to the crank radius (crank pin, webs, the rod's big-end
        share, minus what counterweights opposite the crank cancel; may be < 0). [kg]
    crank_radius : float or array_like
        r, common to the cylinders; leading axes only. [m]
    angular_speed : float or array_like
        ω. [rad/s]
    lambda_ : float or array_like
        λ = r/L. [1]
    about : float or array_like, keyword-only
        x_0 for the moments; default the middle of the cylinder row, (min x + max x)/2. [m]
    shaft_masses : tuple of array_like, keyword-only
        ``(angles, positions, masses)`` of further rotating masses on the shaft, e.g. webs
        and counterweights in their own planes: angle ahead of crank 1 [rad], axial
        position [m], mass reduced to the crank radius [kg].

    Returns
    -------
    InlineBalance
        ``rotating``, ``first``, ``second``: each an :class:`OrderBalance` with the amplitude
        and phase of the free force [N, rad] and of the free moment [N·m, rad].

    Raises
    ------
    InputError
        A ``ValueError``: shapes that do not broadcast, r ≤ 0, λ outside (0, 1), ω < 0,
        a negative reciprocating mass.

    Notes
    -----
    .. math::
        F_r = r\\omega^2\\Big|\\sum_j m_{r,j} e^{i\\theta_j}\\Big|,\\quad
        F_{j1} = r\\omega^2\\Big|\\sum_j m_{j,j} e^{i\\theta_j}\\Big|,\\quad
        F_{j2} = \\lambda r\\omega^2\\Big|\\sum_j m_{j,j} e^{2i\\theta_j}\\Big|

    and the moments with m (x_0 - x_j) as weights. Amplitudes: the rotating force is a vector
    of constant length; the reciprocating ones act along the cylinder axes and the amplitude
    is the peak of their resultant over a revolution (see the module's notes). The orders are
    those of the series j ≈ rω²(cos α + λ cos 2α); :func:`inline_history` also gives the
    exact total.

    Examples
    --------
    The manual's two-cylinder engine, cranks at 180°, a = 0.14 m apart, m_j = 2.806 kg,
    r = 0.06 m, λ = 0.279, at ω = 200 rad/s: first-order forces cancel, their moment is
    m_j r ω² a, second-order forces add to 2λ m_j r ω².

    >>> b = inline_balance(np.radians([0, 180]), [0.0, 0.14], 2.806, 0.0, 0.06, 200.0, 0.279)
    >>> float(b.first.force), round(float(b.first.moment), 6), round(float(b.second.force), 6)
    (0.0, 942.816, 3757.7952)
    >>> round(2 * 0.279 * 2.806 * 0.06 * 200.0**2, 6)
    3757.7952

    References
    ----------
    Lab manual, lab 8; FORMULAS.md "Lab 8"; Lukanin (ed.) vol. 2; Taylor vol. 2.
    """
    _check_engine(crank_radius, angular_speed, lambda_)
    theta, offset, m_j, m_r, x0, shaft = _layout(crank_angles, positions, reciprocating_mass,
                                                 rotating_mass, about, shaft_masses)
    scale = np.asarray(crank_radius, float) * np.asarray(angular_speed, float) ** 2
    if shaft is None:
        u_force, u_moment = phasor_sum(theta, m_r), phasor_sum(theta, m_r * offset)
    else:
        s_theta, s_offset, s_m = shaft
        u_force = _joint_sum((theta, m_r), (s_theta, s_m))
        u_moment = _joint_sum((theta, m_r * offset), (s_theta, s_m * s_offset))
    rotating = _order("rotating", 1, scale, u_force, u_moment)
    first = _order("first", 1, scale, phasor_sum(theta, m_j), phasor_sum(theta, m_j * offset))
    second = _order("second", 2, np.asarray(lambda_, float) * scale,
                    phasor_sum(theta, m_j, order=2), phasor_sum(theta, m_j * offset, order=2))
    return InlineBalance(rotating, first, second, x0)


def _joint_sum(a, b):
    """Phasor sum of two sets of terms (their leading axes may differ), one round-off test."""
    (ta, wa), (tb, wb) = a, b
    return _snap(np.sum(wa * np.exp(1j * ta), axis=-1) + np.sum(wb * np.exp(1j * tb), axis=-1),
                 np.sum(np.abs(wa), axis=-1) + np.sum(np.abs(wb), axis=-1))


def inline_history(crank_angle, crank_angles, positions, reciprocating_mass, rotating_mass,
                   crank_radius, angular_speed, lambda_, *, about=None,
                   shaft_masses=None) -> InlineHistory:
    """Free forces and moments of an in-line engine over crank angle, for a figure or a check.

    Parameters
    ----------
    crank_angle : array_like
        α of crank 1, 1-D (e.g. one revolution). [rad]
    crank_angles, positions, reciprocating_mass, rotating_mass, crank_radius, angular_speed,
    lambda_, about, shaft_masses
        As in :func:`inline_balance`.

    Returns
    -------
    InlineHistory
        Arrays (..., len(crank_angle)): the centrifugal resultant along and across the
        cylinder axes and its moments, the first- and second-order resultants and their
        moments (series), and the exact reciprocating resultant and moment (all orders,
        :func:`processing.crank.kinematics.piston_acceleration`). [N, N·m]

    Notes
    -----
    Summed cylinder by cylinder, independently of the phasors of :func:`inline_balance`
    (a sum below 1e-12 of the sum of its terms' magnitudes is round-off, set to 0):

    .. math:: F_{j1}(\\alpha) = r\\omega^2\\sum_j m_j\\cos(\\alpha + \\theta_j),\\qquad
              F_{j2}(\\alpha) = \\lambda r\\omega^2\\sum_j m_j\\cos 2(\\alpha + \\theta_j)

    so the peak of each curve over a revolution is the amplitude found there.

    Examples
    --------
    >>> alpha = np.radians(np.arange(0.0, 360.0, 1.0))
    >>> h = inline_history(alpha, np.radians([0, 180]), [0.0, 0.14], 2.806, 0.0, 0.06, 200.0, 0.279)
    >>> round(float(h.second_order_force.max()), 4), round(float(h.first_order_moment.max()), 4)
    (3757.7952, 942.816)

    References
    ----------
    Lab manual, lab 8; FORMULAS.md A and "Lab 8".
    """
    _check_engine(crank_radius, angular_speed, lambda_)
    alpha = np.asarray(crank_angle, dtype=float)
    if alpha.ndim != 1:
        raise InputError(f"crank_angle must be 1-D, got shape {alpha.shape}",
                         "pass e.g. np.radians(np.arange(0, 360, 1.0))")
    theta, offset, m_j, m_r, _, shaft = _layout(crank_angles, positions, reciprocating_mass,
                                                rotating_mass, about, shaft_masses)

    def lead(v):
        return np.asarray(v, dtype=float)[..., None, None]

    r, w, lam = lead(crank_radius), lead(angular_speed), lead(lambda_)
    angle = theta[..., None] + alpha                      # (..., n_cyl, n_alpha)
    mj, mr, d = m_j[..., None], m_r[..., None], offset[..., None]
    scale = (r * w ** 2)[..., 0, :]

    def total(weights, wave):
        terms = weights * wave
        out = np.sum(terms, axis=-2)
        return np.where(np.abs(out) <= ROUND_OFF * np.sum(np.abs(terms), axis=-2), 0.0, out)

    cos1, sin1, cos2 = np.cos(angle), np.sin(angle), np.cos(2 * angle)
    f_along, f_across = scale * total(mr, cos1), scale * total(mr, sin1)
    m_along, m_across = scale * total(mr * d, cos1), scale * total(mr * d, sin1)
    if shaft is not None:
        s_angle = shaft[0][..., None] + alpha
        s_m, s_d = shaft[2][..., None], shaft[1][..., None]
        f_along = f_along + scale * total(s_m, np.cos(s_angle))
        f_across = f_across + scale * total(s_m, np.sin(s_angle))
        m_along = m_along + scale * total(s_m * s_d, np.cos(s_angle))
        m_across = m_across + scale * total(s_m * s_d, np.sin(s_angle))
    j = piston_acceleration(angle, r, w, lam, method="exact")
    lam2 = lam[..., 0, :]
    return InlineHistory(
        crank_angle=alpha, rotating_force_along=f_along, rotating_force_across=f_across,
        first_order_force=scale * total(mj, cos1), second_order_force=lam2 * scale * total(mj, cos2),
        reciprocating_force=total(mj, j), rotating_moment_along=m_along,
        rotating_moment_across=m_across, first_order_moment=scale * total(mj * d, cos1),
        second_order_moment=lam2 * scale * total(mj * d, cos2),
        reciprocating_moment=total(mj * d, j))


def stechkin_klimov(second_order_force, engine_mass, angular_speed, bore):
    """Stechkin–Klimov balance criterion ξ: the free second-order force against the engine.

    Parameters
    ----------
    second_order_force : float or array_like
        Amplitude of the free second-order force, ΣP_j2 max. [N]
    engine_mass : float or array_like
        m, mass of the engine. [kg]
    angular_speed : float or array_like
        ω. [rad/s]
    bore : float or array_like
        D, cylinder diameter. [m]

    Returns
    -------
    float or ndarray
        ξ; below :data:`STECHKIN_KLIMOV_LIMIT` = 0.002 the balance is satisfactory. [1]

    Notes
    -----
    .. math:: \\xi = \\frac{0.25\\,P_{j2}^{max}}{m\\,\\omega^2 D}

    P_j2 max is proportional to ω², so ξ does not depend on the speed: for an in-line engine
    ξ = 0.25 λ r |Σ m_j e^{2iθ_j}| / (m D). The criterion looks at the second-order force
    only; free rotating or first-order forces and free moments need their own check.

    Examples
    --------
    The manual's D-120 (2λ m_j r ω² with m_j = 2.806 kg, r = 0.06 m, λ = 0.279; m = 295 kg,
    D = 0.105 m), at any ω:

    >>> w = 200.0
    >>> round(float(stechkin_klimov(2 * 0.279 * 2.806 * 0.06 * w**2, 295.0, w, 0.105)), 7)
    0.0007582

    References
    ----------
    Lab manual, lab 8; FORMULAS.md "Lab 8".
    """
    check_positive("engine_mass", engine_mass, "kg")
    check_positive("angular_speed", angular_speed, "rad/s")
    check_positive("bore", bore, "m")
    return 0.25 * second_order_force / (engine_mass * angular_speed ** 2 * bore)
