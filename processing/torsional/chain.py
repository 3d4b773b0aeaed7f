"""Torsional vibration of an equivalent chain: discs on massless elastic shafts.

A crankshaft with its damper, cranks and flywheel is reduced, for torsional vibration, to a
chain of n discs of moments of inertia J_i joined by n − 1 shafts of torsional stiffness c_i
(the "equivalent torsional system" of the textbooks), free at both ends. Optionally a last
shaft c_n ties the last disc to an immovable ground (a brake much heavier than the engine).
Damping is viscous: at a disc against the ground (piston and bearing friction, a damper's
ring) and across a shaft (the material's own).

Equation of motion for the angles θ (one per disc) under torques T:

.. math:: M\\ddot\\theta + C\\dot\\theta + K\\theta = T, \\qquad
          M = \\mathrm{diag}(J_i), \\quad
          K = \\sum_i c_i\\,(e_i - e_{i+1})(e_i - e_{i+1})^T

- :func:`chain_matrices` assembles M, K, C;
- :func:`natural_modes` solves K v = ω² M v (undamped natural frequencies and mode shapes);
  the free chain's rigid-body mode (ω = 0) is left out;
- :func:`forced_response` gives the steady complex amplitudes under harmonic torques,
  (K − ω²M + iωC) Θ = T, damping included.

Everything broadcasts over leading axes: a stack of chains (Monte Carlo draws of uncertain
J and c) is solved in one call.

References
----------
.. [1] W. Ker Wilson, Practical Solution of Torsional Vibration Problems, vol. 1, 3rd ed.,
       Chapman & Hall, 1956, ch. 4–6 (equivalent systems, natural frequencies, relative
       amplitudes).
.. [2] V. P. Terskikh, Torsional vibrations of shaft lines of power plants (Крутильные
       колебания валопровода силовых установок), vol. 1, Sudostroenie, 1969.
.. [3] Dynamics of internal-combustion engines: lab manual, Vladimir State University, 2003,
       labs 7 and 9 (the equivalent torsional system, relative amplitudes at the damper).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from processing.result import Record


def _chain(inertia, stiffness):
    J = np.asarray(inertia, dtype=float)
    c = np.asarray(stiffness, dtype=float)
    if J.ndim < 1 or J.shape[-1] < 1:
        raise ValueError("torsion: inertia must list at least one disc along its last axis")
    n = J.shape[-1]
    if c.ndim < 1 or c.shape[-1] not in (n - 1, n):
        raise ValueError(f"torsion: {n} discs need {n - 1} shaft stiffnesses (free chain) or "
                         f"{n} (the last shaft grounded), got {c.shape[-1] if c.ndim else 0}")
    if not np.all(J > 0):
        raise ValueError("torsion: every moment of inertia must be > 0 kg·m²")
    if not np.all(c > 0):
        raise ValueError("torsion: every shaft stiffness must be > 0 N·m/rad")
    if n == 1 and c.shape[-1] == 0:
        raise ValueError("torsion: a single free disc has no elastic mode")
    return J, c


def _shaft_matrix(k, n: int) -> np.ndarray:
    """Σ k_i (e_i − e_{i+1})(e_i − e_{i+1})ᵀ for shafts k (…, m), m = n − 1 or n (the last
    one grounded)."""
    out = np.zeros(k.shape[:-1] + (n, n))
    m = k.shape[-1]
    idx = np.arange(m)
    diag = np.zeros(k.shape[:-1] + (n,))
    diag[..., :m] += k
    diag[..., 1:min(m, n - 1) + 1] += k[..., :n - 1]
    out[..., np.arange(n), np.arange(n)] = diag
    inner = idx[idx < n - 1]
    out[..., inner, inner + 1] = -k[..., inner]
    out[..., inner + 1, inner] = -k[..., inner]
    return out


def chain_matrices(inertia, stiffness, *, damping=None, shaft_damping=None):
    """Mass, stiffness and damping matrices of a chain of discs.

    Parameters
    ----------
    inertia : array_like
        J_i of the discs, along the last axis (n ≥ 1). [kg·m²]
    stiffness : array_like
        c_i of the shafts between discs i and i + 1 (n − 1 values: a free chain), or n
        values (the last ties disc n to the ground). [N·m/rad]
    damping : array_like, optional
        Viscous damping of each disc against the ground (n values). [N·m·s/rad]
    shaft_damping : array_like, optional
        Viscous damping across each shaft (as many as ``stiffness``). [N·m·s/rad]

    Returns
    -------
    M, K, C : ndarray
        (…, n, n) each. [kg·m²], [N·m/rad], [N·m·s/rad]

    Examples
    --------
    >>> M, K, C = chain_matrices([1.0, 2.0], [10.0])
    >>> K.tolist(), np.diag(M).tolist(), float(abs(C).sum())
    ([[10.0, -10.0], [-10.0, 10.0]], [1.0, 2.0], 0.0)
    """
    J, c = _chain(inertia, stiffness)
    n = J.shape[-1]
    shape = np.broadcast_shapes(J.shape[:-1], c.shape[:-1])
    J = np.broadcast_to(J, shape + (n,))
    c = np.broadcast_to(c, shape + c.shape[-1:])
    M = np.zeros(shape + (n, n))
    M[..., np.arange(n), np.arange(n)] = J
    K = _shaft_matrix(c, n)
    C = np.zeros(shape + (n, n))
    if shaft_damping is not None:
        C = C + _shaft_matrix(np.broadcast_to(np.asarray(shaft_damping, float),
                                              shape + c.shape[-1:]), n)
    if damping is not None:
        C[..., np.arange(n), np.arange(n)] += np.broadcast_to(np.asarray(damping, float),
                                                              shape + (n,))
    return M, K, C


@dataclass(frozen=True)
class Modes(Record):
    """Undamped natural modes of a chain (:func:`natural_modes`), lowest first."""

    angular_frequency: np.ndarray
    """ω_k of the elastic modes, (…, m). [rad/s]"""
    shape: np.ndarray
    """Mode shapes, (…, n, m): column k is mode k, mass-normalised (vᵀ M v = 1) with a
    positive amplitude at the reference disc. [1/√(kg·m²)]"""
    reference: int
    """The disc (0-based) whose amplitude the relative amplitudes are taken to (the damper or
    the crankshaft nose, where the torsiograph sits)."""

    @property
    def frequency(self) -> np.ndarray:
        """f_k = ω_k/2π. [Hz]"""
        return self.angular_frequency / (2 * np.pi)

    def relative(self, at: int | None = None) -> np.ndarray:
        """Relative amplitudes a_i = v_i / v_at of each mode: 1 at disc ``at`` (default: the
        reference disc). NaN where that disc is a node of the mode. [1]"""
        at = self.reference if at is None else at
        ref = self.shape[..., at:at + 1, :]
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(np.abs(ref) > 1e-12 * np.abs(self.shape).max(axis=-2, keepdims=True),
                            self.shape / ref, np.nan)


def natural_modes(inertia, stiffness, *, reference: int = 0) -> Modes:
    r"""Natural frequencies and mode shapes of a chain of discs (undamped).

    Parameters
    ----------
    inertia : array_like
        J_i along the last axis (leading axes: a stack of chains). [kg·m²]
    stiffness : array_like
        c_i: n − 1 values for a free chain, n with the last disc grounded. [N·m/rad]
    reference : int, keyword-only
        Disc (0-based) the mode shapes are signed to and relative amplitudes refer to.

    Returns
    -------
    Modes
        n − 1 elastic modes of a free chain (its rigid rotation, ω = 0, left out), n of a
        grounded one.

    Notes
    -----
    The generalized symmetric eigenproblem

    .. math:: K v = \omega^2 M v

    with M = diag(J) is solved as the standard one :math:`M^{-1/2} K M^{-1/2} w = \omega^2 w`,
    :math:`v = M^{-1/2} w` (so that a stack of chains goes through one batched
    :func:`numpy.linalg.eigh`); it is the same problem :func:`scipy.linalg.eigh` solves as
    ``eigh(K, M)`` (the tests compare the two, and OpenTorsion's finite-element model).

    Closed forms: two discs, :math:`\omega^2 = c (J_1 + J_2)/(J_1 J_2)`; a uniform free chain
    of n equal discs J and shafts c, :math:`\omega_k = 2\sqrt{c/J}\,\sin(k\pi/2n)`,
    k = 1 … n − 1.

    Examples
    --------
    >>> m = natural_modes([1.0, 1.0], [100.0])
    >>> round(float(m.angular_frequency[0]) ** 2, 9)      # c (J1 + J2)/(J1 J2)
    200.0
    >>> m.relative()[:, 0].round(6).tolist()            # the two discs swing against each other
    [1.0, -1.0]
    """
    J, c = _chain(inertia, stiffness)
    n = J.shape[-1]
    free = c.shape[-1] == n - 1
    _, K, _ = chain_matrices(J, c)
    scale = 1.0 / np.sqrt(np.broadcast_to(J, K.shape[:-1]))
    A = K * scale[..., :, None] * scale[..., None, :]
    lam, w = np.linalg.eigh(A)
    v = w * scale[..., :, None]
    if free:
        lam, v = lam[..., 1:], v[..., :, 1:]
    sign = np.where(v[..., reference:reference + 1, :] < 0, -1.0, 1.0)
    omega = np.sqrt(np.clip(lam, 0.0, None))
    return Modes(angular_frequency=omega, shape=v * sign, reference=reference)


def forced_response(inertia, stiffness, torque, angular_frequency, *, damping=None,
                    shaft_damping=None):
    r"""Steady complex amplitudes of the discs under harmonic torques.

    Parameters
    ----------
    inertia, stiffness : array_like
        The chain, as :func:`natural_modes`. [kg·m²], [N·m/rad]
    torque : array_like
        Complex torque amplitudes T (real part: the torque at t = 0), one per disc on the
        last axis, broadcast against ``angular_frequency[..., None]``. [N·m]
    angular_frequency : array_like
        Ω of each harmonic, > 0. [rad/s]
    damping, shaft_damping : array_like, optional
        As :func:`chain_matrices`. [N·m·s/rad]

    Returns
    -------
    ndarray
        Θ, complex amplitudes of the discs' angles, shape ``angular_frequency.shape + (n,)``
        (broadcast with ``torque``): θ_i(t) = Re(Θ_i e^{iΩt}). [rad]

    Notes
    -----
    .. math:: (K - \Omega^2 M + i\Omega C)\,\Theta = T

    Examples
    --------
    One disc on a grounded shaft, below and at resonance (ζ = C/(2√(KJ)) = 0.05):

    >>> t = forced_response([1.0], [100.0], [1.0], [1.0, 10.0], damping=[1.0])
    >>> np.round(np.abs(t[:, 0]), 6).tolist()     # 1/|100 − 1 + i|, 1/|i·10|
    [0.0101, 0.1]
    """
    M, K, C = chain_matrices(inertia, stiffness, damping=damping, shaft_damping=shaft_damping)
    omega = np.asarray(angular_frequency, dtype=float)
    if not np.all(omega > 0):
        raise ValueError("forced_response: every angular frequency must be > 0 rad/s")
    o = omega[..., None, None]
    D = K - o ** 2 * M + 1j * o * C
    T = np.asarray(torque, dtype=complex)
    T = np.broadcast_to(T, np.broadcast_shapes(T.shape, D.shape[:-1]))
    D = np.broadcast_to(D, T.shape[:-1] + D.shape[-2:])
    return np.linalg.solve(D, T[..., None])[..., 0]
