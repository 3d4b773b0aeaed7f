"""Orders of a record against the crank angle, fitted together with its drift.

A record of a steady regime (a torsiograph's trace, a strain gauge's) is periodic in the crank
angle θ over a working cycle: it is a sum of orders k (harmonics per revolution; half orders
for a four-stroke engine) riding on the recorder's slow baseline drift, plus noise.
:func:`order_fit` fits both at once by least squares on the crank angle of every sample (from
the revolution marks, :func:`processing.torsional.torsiogram.crank_angle`), so a drift of any size
does not leak into the orders; :class:`OrderFit` keeps the coefficients' covariance, so anything
linear in them (the record synthesised at chosen angles, with each order multiplied by a known
complex gain such as an instrument's correction) carries its uncertainty (:meth:`OrderFit.design`,
:meth:`OrderFit.variance`). The covariance is not the white-noise one alone: each order's share is
scaled by the residual's spectral density around that order's frequency (:func:`noise_ratio`), so
that a drift faster than its polynomial follows, or any disturbance near an order, widens that
order's uncertainty instead of hiding in it.

References
----------
.. [1] Dynamics of internal-combustion engines: lab manual, Vladimir State University, 2003,
       lab 7: "the curve of the torsional oscillations is often not sinusoidal, so its
       frequencies and amplitudes are found by a harmonic analysis".
.. [2] N. R. Draper, H. Smith, Applied Regression Analysis, 3rd ed., Wiley, 1998, ch. 5
       (the covariance of least-squares coefficients, s² (AᵀA)⁻¹).
.. [3] P. Stoica, R. Moses, Spectral Analysis of Signals, Prentice Hall, 2005, §4.3 (the
       least-squares amplitude of a sinusoid in coloured noise: its variance follows the
       noise's spectral density at the sinusoid's frequency).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from processing.result import Record

DRIFT_DEGREE = 6
"""Degree of the Legendre polynomial in time fitted for the drift beside the orders: slow
baseline wander of up to about two waves per record."""


@dataclass(frozen=True)
class OrderFit(Record):
    """Orders of a record fitted with its drift (:func:`order_fit`).

    The record is x(t) = Σ_k Re(c_k e^{ikθ(t)}) + drift(t) + e(t), c_k = a_k − i b_k.
    """

    order: np.ndarray
    """Orders k: harmonics per revolution (0.5, 1, 1.5, … for a four-stroke engine). [1]"""
    coefficient: np.ndarray
    """Complex amplitude c_k of each order. [record unit]"""
    covariance: np.ndarray
    """Covariance of (a_1 … a_m, b_1 … b_m), (2m, 2m): s²(AᵀA)⁻¹ with each order's rows and
    columns scaled by √``noise_ratio``. [record unit²]"""
    noise_ratio: np.ndarray
    """Spectral density of the residual around each order over its white level (1 for white
    noise; large where a drift or a disturbance reaches the order's frequency). [1]"""
    residual_sd: float
    """Standard deviation of what the orders and the drift leave: noise and cycle-to-cycle
    scatter. [record unit]"""
    dof: int
    """Degrees of freedom of ``residual_sd``: samples less fitted coefficients."""
    drift: np.ndarray
    """The fitted drift at every sample (its mean included). [record unit]"""
    periodic: np.ndarray
    """The fitted orders at every sample. [record unit]"""

    @property
    def amplitude(self) -> np.ndarray:
        """|c_k|. [record unit]"""
        return np.abs(self.coefficient)

    @property
    def white_covariance(self) -> np.ndarray:
        """The covariance as if the residual were white noise, s²(AᵀA)⁻¹. [record unit²]"""
        s = np.sqrt(np.concatenate([self.noise_ratio, self.noise_ratio]))
        return self.covariance / s[:, None] / s[None, :]

    @property
    def u(self) -> np.ndarray:
        """Standard uncertainty of |c_k|, √((u²(a_k) + u²(b_k))/2). [record unit]"""
        m = self.order.size
        var = np.diag(self.covariance)
        return np.sqrt(0.5 * (var[:m] + var[m:]))

    def significant(self, *, factor: float = 4.0, share: float = 0.01) -> np.ndarray:
        """Orders standing out of the fit's noise (|c| > factor·u) and above ``share`` of the
        largest order (a mask)."""
        a = self.amplitude
        return (a > factor * self.u) & (a > share * a.max())

    def design(self, angle, gain=None) -> np.ndarray:
        """Rows D with D @ (a, b) = Σ_k Re(G_k c_k e^{ikθ}) at the given crank angles.

        Parameters
        ----------
        angle : array_like
            θ. [rad]
        gain : array_like, optional
            Complex factor G_k of each order (default 1: the record as fitted).

        Returns
        -------
        ndarray
            (len(angle), 2m). [1]
        """
        phase = np.asarray(angle, dtype=float)[:, None] * self.order
        g = np.ones(self.order.size, complex) if gain is None else np.asarray(gain, complex)
        c, s = np.cos(phase), np.sin(phase)
        return np.hstack([g.real * c - g.imag * s, g.imag * c + g.real * s])

    def synthesize(self, angle, gain=None) -> np.ndarray:
        """Σ_k Re(G_k c_k e^{ikθ}) at the given crank angles. [record unit]

        The orders k = j·s (j = 1 … m, as :func:`order_fit` makes them) are summed by
        Horner's rule in z = e^{isθ}, one complex exponential per angle; other orders term
        by term."""
        s = self.order[0] if self.order.size else 1.0
        if not np.allclose(self.order, s * np.arange(1, self.order.size + 1)):
            return self.design(angle, gain) @ np.concatenate([self.coefficient.real,
                                                              -self.coefficient.imag])
        theta = np.asarray(angle, dtype=float)
        d = self.coefficient * (1.0 if gain is None else np.asarray(gain, complex))
        z = np.exp(1j * s * theta)
        total = np.zeros(theta.shape, complex)
        for c in d[::-1]:
            total += c
            total *= z
        return total.real

    def variance(self, rows, *, white: bool = False) -> np.ndarray:
        """Variance of the linear combinations ``rows @ (a, b)`` (rows from :meth:`design`,
        or combinations of them); ``white``: as if the residual were white. [record unit²]"""
        rows = np.atleast_2d(rows)
        cov = self.white_covariance if white else self.covariance
        return np.einsum("ij,jk,ik->i", rows, cov, rows)


def noise_ratio(residual, sample_rate: float, frequencies, spacing: float) -> np.ndarray:
    """Spectral density of a residual around given frequencies, over its white level.

    The periodogram of the residual is averaged over the bins within ± ``spacing``/2 of each
    frequency, leaving out the bin nearest to each of the ``frequencies`` (what their fit
    took out), and divided by the white level: the median of the bins above the lowest
    frequency less half the spacing, over ln 2 (the median of an exponential variable).

    Parameters
    ----------
    residual : array_like
        What a fit left, uniformly sampled. [any unit]
    sample_rate : float
        [Hz]
    frequencies : array_like
        The fitted frequencies (orders times the revolution frequency). [Hz]
    spacing : float
        Distance between neighbouring fitted frequencies. [Hz]

    Returns
    -------
    ndarray
        One ratio per frequency; 1 where no bin lies near it. [1]

    Examples
    --------
    White noise has ratios near 1; a slow wave of ten times the noise raises the lowest:

    >>> rng = np.random.default_rng(1)
    >>> t = np.arange(8000) / 1000.0
    >>> e = rng.standard_normal(t.size)
    >>> r = noise_ratio(e, 1000.0, [10.0, 20.0, 30.0], 10.0)
    >>> bool(np.all((r > 0.5) & (r < 2)))
    True
    >>> r = noise_ratio(e + 10 * np.sin(2 * np.pi * 7.3 * t), 1000.0, [10.0, 20.0, 30.0], 10.0)
    >>> bool(r[0] > 100 and r[2] < 2)
    True
    """
    r = np.asarray(residual, dtype=float)
    power = np.abs(np.fft.rfft(r - r.mean())) ** 2
    f = np.fft.rfftfreq(r.size, 1.0 / sample_rate)
    fk = np.asarray(frequencies, dtype=float)
    df = sample_rate / r.size
    free = f > 0
    fitted, within = _bins_within(f, fk, 0.5 * df, df, strict=True)
    free[fitted[within]] = False
    white = np.median(power[free & (f >= fk.min() - 0.5 * spacing)]) / np.log(2)
    if not white > 0:
        return np.ones(fk.size)
    near, within = _bins_within(f, fk, 0.5 * spacing, df)
    within &= free[near]
    count = within.sum(axis=1)
    mean = np.where(within, power[near], 0.0).sum(axis=1) / np.maximum(count, 1)
    return np.where(count > 0, mean / white, 1.0)


def _bins_within(f, centre, half: float, df: float, *,
                 strict: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """The bins f (uniform, spacing ``df``, from 0) within ``half`` of each of ``centre``:
    abs(f − centre) < ``half`` (``strict``) or ≤ it. Only the bins the distance can reach are
    compared (one more either side against rounding), not every bin with every centre: a row
    of candidate indices per centre (clipped to the bins) and a mask of those within, each
    bin once in its row. [Hz]"""
    centre = np.atleast_1d(np.asarray(centre, dtype=float))
    reach = int(np.ceil(half / df)) + 1
    first = np.rint(centre / df).astype(int)
    candidate = first[:, None] + np.arange(-reach, reach + 1)[None, :]
    index = np.clip(candidate, 0, f.size - 1)
    gap = np.abs(f[index] - centre[:, None])
    return index, (candidate == index) & (gap < half if strict else gap <= half)


def order_fit(time, angle, x, *, step: float = 0.5, max_order: float = 12.0,
              drift_degree: int = DRIFT_DEGREE) -> OrderFit:
    r"""Order spectrum of a record by least squares on the crank angle of every sample.

    .. math:: x(t) = \sum_k \mathrm{Re}\,(c_k e^{ik\theta(t)})
              + \sum_{j=0}^{D} d_j P_j\!\Big(\frac{2(t - t_0)}{T} - 1\Big) + e(t)

    k = step, 2·step, … ≤ max_order (step 0.5: the half orders of a four-stroke cycle), P_j
    Legendre polynomials (the slow drift, D = ``drift_degree``), θ(t) the crank angle of each
    sample. Fitting the drift together with the orders leaves no leakage of a drift into the
    orders, whatever its size; the coefficients' covariance s²(AᵀA)⁻¹ counts what the drift's
    columns share with the orders' (a short record, whose half orders a polynomial can
    mimic, gets a large one).

    Parameters
    ----------
    time, angle : array_like
        Time [s] and crank angle [rad] of each sample.
    x : array_like
        The record. [any unit]
    step, max_order : float, keyword-only
        Order spacing and the highest order fitted. [1]
    drift_degree : int, keyword-only
        D.

    Returns
    -------
    OrderFit

    Raises
    ------
    ValueError
        Fewer samples than coefficients to fit.

    Notes
    -----
    The samples are taken as uniformly spaced in time (the residual's spectrum gives the
    orders' noise ratios, :func:`noise_ratio`), at a steady speed (an order k at k n/60 Hz).

    Examples
    --------
    >>> t = np.linspace(0, 1, 4001); th = 2 * np.pi * 20 * t
    >>> s = order_fit(t, th, 3 * np.cos(2 * th + 0.5) + 0.4 * np.sin(4.5 * th) + 5 * t)
    >>> np.round(s.amplitude[[3, 8]], 6).tolist(), round(float(np.angle(s.coefficient[3])), 6)
    ([3.0, 0.4], 0.5)
    >>> np.round(s.synthesize([0.0, np.pi]), 6).tolist()     # 3 cos 0.5 + 0.4 sin 4.5θ
    [2.632748, 3.032748]
    """
    return order_fits(time, angle, [x], step=step, max_order=max_order,
                      drift_degree=drift_degree)[0]


def order_fits(time, angle, records, *, step: float = 0.5, max_order: float = 12.0,
               drift_degree: int = DRIFT_DEGREE) -> list[OrderFit]:
    """:func:`order_fit` of several records sampled alike (the channels of one recording):
    the design matrix and the inverse of its normal equations, which depend on the time and
    the crank angle alone, are made once; each record's coefficients, residual and noise
    ratios are its own, computed as :func:`order_fit` computes them.

    Parameters
    ----------
    time, angle : array_like
        Time [s] and crank angle [rad] of each sample, shared by the records.
    records : sequence of array_like
        The records, each as long as ``time``. [any unit]
    step, max_order, drift_degree
        As :func:`order_fit`.

    Returns
    -------
    list of OrderFit
        One per record, in their order.

    Raises
    ------
    ValueError
        Fewer samples than coefficients to fit.
    """
    t = np.asarray(time, dtype=float)
    th = np.asarray(angle, dtype=float)
    order = step * np.arange(1, int(np.floor(max_order / step + 1e-9)) + 1)
    m = order.size
    if t.size <= 2 * m + drift_degree + 1:
        raise ValueError(f"order_fit: {t.size} samples cannot fit {m} orders and a drift of "
                         f"degree {drift_degree}")
    u = 2 * (t - t[0]) / (t[-1] - t[0]) - 1
    A = np.empty((t.size, 2 * m + drift_degree + 1))
    # e^{ijsθ} as the running product of e^{isθ}: one complex exponential per sample
    # instead of a cosine and a sine per sample and order (rounding grows as j·ε); column
    # by column, each a product of whole columns (a cumulative product along the rows'
    # m orders costs four times as much, for the same products)
    z = np.exp(1j * step * th)
    powers = np.empty((t.size, m), complex)
    powers[:, 0] = z
    for j in range(1, m):
        np.multiply(powers[:, j - 1], z, out=powers[:, j])
    A[:, :m], A[:, m:2 * m] = powers.real, powers.imag
    A[:, 2 * m:] = drift_cols = np.polynomial.legendre.legvander(u, drift_degree)
    # the normal equations: their inverse is the covariance's anyway, and the columns
    # (sines, cosines and Legendre polynomials over the record) are near orthogonal; AᵀA is
    # symmetric, so its pseudo-inverse comes from its eigenvalues (half an SVD's cost)
    normal = np.linalg.pinv(A.T @ A, hermitian=True)
    dof = t.size - A.shape[1]
    rate = (t.size - 1) / (t[-1] - t[0])
    f_rev = (th[-1] - th[0]) / (2 * np.pi * (t[-1] - t[0]))
    fits = []
    for x in records:
        x = np.asarray(x, dtype=float)
        coef = normal @ (A.T @ x)
        fitted_orders = A[:, :2 * m] @ coef[:2 * m]
        drift = drift_cols @ coef[2 * m:]
        r = x - fitted_orders - drift
        s2 = float(r @ r) / dof
        ratio = noise_ratio(r, rate, order * f_rev, step * f_rev)
        scale = np.sqrt(np.concatenate([ratio, ratio]))
        covariance = s2 * normal[:2 * m, :2 * m] * scale[:, None] * scale[None, :]
        a, b = coef[:m], coef[m:2 * m]
        fits.append(OrderFit(order=order, coefficient=a - 1j * b, covariance=covariance,
                             noise_ratio=ratio, residual_sd=float(np.sqrt(s2)), dof=int(dof),
                             drift=drift, periodic=fitted_orders))
    return fits
