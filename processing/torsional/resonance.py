"""Resonances of a speed sweep: order amplitudes against speed, the engine's major orders.

Torsional records taken every 100–200 min⁻¹ (finer near a resonance) give, for every engine
order k, its amplitude against speed. A resonance of order k is a peak of that curve where
the order dominates the record (the manual's K = ν/n); its speed is found between the
records by a parabola through 1/A² (:func:`resonance_speed`: exact for a lightly damped
mode near its peak), and the natural frequency it implies is k·n_res/60
(:func:`locate_resonances`). The Campbell diagram draws the orders' frequencies against
speed (:func:`campbell_lines`). Which orders a multi-cylinder engine excites strongly
follows from the phase sum of its cylinders (:func:`phase_sum`, :func:`major_orders`).

References
----------
.. [1] Dynamics of internal-combustion engines: lab manual, Vladimir State University, 2003,
       lab 7 (the amplitude–speed curve, resonant regimes, K = ν/n).
.. [2] W. Ker Wilson, Practical Solution of Torsional Vibration Problems, vol. 2, 3rd ed.,
       Chapman & Hall, 1963, ch. 12–13 (phase diagrams, major and minor critical orders).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.signal import find_peaks, peak_prominences

from processing.crank.dynamics import firing_phases
from processing.result import Record

PROMINENCE = 0.3
"""A peak of an order's amplitude–speed curve counts as a resonance when it stands this share
of its height above the lower of the curve's minima on either side."""

FIT_LEVEL = 0.5
"""Records around a peak whose amplitude is at least this share of the peak's are fitted."""

EDGE_SLOPE = 4.0
"""An order still rising at an end of the sweep points to a resonance beyond it when its
amplitude changes faster than n^±4 over the last speed step. Below a mode, an inertia
torque's response rises as n²/(1 − x²) (x the order's frequency over the mode's), steeper
than n⁴ only within x > 0.7 of the mode. At the low end the test is weaker: the rigid-body
swing falls as n⁻² under a steady gas torque, but faster where the order's inertia torque
cancels more of its gas torque as the speed rises (order 2 of a four-cylinder engine falls
as n⁻⁵ near 1400 min⁻¹), so a steep low end may be the speed irregularity itself."""


# ------------------------------------------------------------------------ engine orders

def phase_sum(order, phases, amplitudes=None):
    r"""Resultant of the cylinders' order-k excitation: the phase (vector) sum.

    .. math:: \Sigma_k = \Big|\sum_c a_c\, e^{ik\varphi_c}\Big|

    φ_c the cylinder's phase lag in crank angle (:func:`processing.crank.dynamics.firing_phases`),
    a_c the relative amplitude of the mode at its crank (1 each: the engine's own phase
    diagram). An order whose sum equals the sum of the a_c is a major order: every cylinder
    excites it in phase.

    Parameters
    ----------
    order : float or ndarray
        k, harmonics per revolution. [1]
    phases : array_like
        φ_c of the cylinders. [rad]
    amplitudes : array_like, optional
        a_c (default 1 for each). [1]

    Returns
    -------
    float or ndarray
        Σ_k, shaped like ``order``. [1]

    Examples
    --------
    In-line four-stroke four, firing 1-3-4-2: orders 2 and 4 add up, 1 cancels.

    >>> phi = firing_phases(4, firing_order=[1, 3, 4, 2])
    >>> np.round(phase_sum([1.0, 2.0, 4.0], phi), 9).tolist()
    [0.0, 4.0, 4.0]
    """
    k = np.asarray(order, dtype=float)
    phi = np.asarray(phases, dtype=float)
    a = np.ones_like(phi) if amplitudes is None else np.asarray(amplitudes, dtype=float)
    return np.abs((a * np.exp(1j * k[..., None] * phi)).sum(axis=-1))


def relative_phase_sum(order, phases, amplitudes):
    r"""The phase sum of order k with a mode's relative amplitudes, over its largest possible
    value: how much of the cylinders' excitation adds up in that mode.

    .. math:: \bar\Sigma_k = \frac{\big|\sum_c a_c\, e^{ik\varphi_c}\big|}{\sum_c |a_c|}

    1 where every crank's excitation does work on the mode in phase (a major order of a mode
    whose cranks swing alike), 0 where the cranks' work cancels: the resonance of that order
    with that mode is then not excited, whatever its speed [1]_.

    Parameters
    ----------
    order : float or ndarray
        k. [1]
    phases : array_like
        φ_c of the cylinders. [rad]
    amplitudes : array_like
        a_c, the mode's relative amplitude at each cylinder's crank, along the last axis
        (leading axes: a stack of modes, broadcast against ``order``). [1]

    Returns
    -------
    float or ndarray
        Σ̄_k, 0 … 1. [1]

    References
    ----------
    .. [1] W. Ker Wilson, Practical Solution of Torsional Vibration Problems, vol. 2, 3rd ed.,
           Chapman & Hall, 1963, ch. 12 (vector summation, relative amplitudes of the cranks).

    Examples
    --------
    Four cylinders, firing 1-3-4-2 (φ = 0, 540°, 180°, 360° for cylinders 1–4), the cranks
    swinging 1, 0.9, 0.7, 0.4: order 2 adds fully; orders 1 and ½, which cancel between equal
    cranks, keep |1 − 0.9 − 0.7 + 0.4|/3 and |0.6 − 0.2i|/3:

    >>> phi = firing_phases(4, firing_order=[1, 3, 4, 2])
    >>> np.round(relative_phase_sum([2.0, 1.0, 0.5], phi, [1.0, 0.9, 0.7, 0.4]), 4).tolist()
    [1.0, 0.0667, 0.2108]
    """
    a = np.asarray(amplitudes, dtype=float)
    return phase_sum(order, phases, a) / np.abs(a).sum(axis=-1)


def major_orders(cylinders: int, *, strokes: int = 4, firing_order=None,
                 max_order: float = 12.0) -> np.ndarray:
    """The engine's major orders up to ``max_order``: those all cylinders excite in phase.

    Parameters
    ----------
    cylinders : int
        i.
    strokes : {4, 2}, keyword-only
        Half orders for a four-stroke engine, whole orders for a two-stroke one.
    firing_order : sequence of int, keyword-only, optional
        Cylinder numbers in firing order, from 1 (default 1, 2, …, i); even firing intervals.
    max_order : float, keyword-only
        Highest order considered.

    Returns
    -------
    ndarray
        The major orders, ascending. [1]

    Notes
    -----
    For even firing the major orders are the multiples of i/2 (four-stroke) or of i
    (two-stroke), whatever the firing order: the firing order decides how the other, minor
    orders add up with the mode's relative amplitudes (:func:`phase_sum`).

    Examples
    --------
    >>> major_orders(4, firing_order=[1, 3, 4, 2], max_order=8).tolist()
    [2.0, 4.0, 6.0, 8.0]
    >>> major_orders(6, firing_order=[1, 5, 3, 6, 2, 4], max_order=9).tolist()
    [3.0, 6.0, 9.0]
    """
    phases = firing_phases(cylinders, strokes=strokes, firing_order=firing_order)
    step = 0.5 if strokes == 4 else 1.0
    k = step * np.arange(1, int(np.floor(max_order / step + 1e-9)) + 1)
    return k[np.isclose(phase_sum(k, phases), cylinders, atol=1e-9 * cylinders)]


def campbell_lines(orders, angular_speed):
    """Frequency of each order at each speed: the rays of a Campbell diagram.

    .. math:: f = k\\,\\frac{\\omega}{2\\pi} = \\frac{k n}{60}

    Parameters
    ----------
    orders : array_like
        k. [1]
    angular_speed : array_like
        ω. [rad/s]

    Returns
    -------
    ndarray
        Shape ``orders.shape + angular_speed.shape``. [Hz]

    Examples
    --------
    >>> campbell_lines([2.0, 6.0], [100 * np.pi]).round(9).tolist()      # 3000 min⁻¹
    [[100.0], [300.0]]
    """
    k = np.asarray(orders, dtype=float)
    w = np.asarray(angular_speed, dtype=float)
    return k.reshape(k.shape + (1,) * w.ndim) * w / (2 * np.pi)


# ------------------------------------------------------------------------ resonances

def resonance_speed(speed, amplitude, weights=None):
    r"""Speed of a resonance peak from records around it: the vertex of a parabola in 1/A².

    Near a lightly damped mode the response of an order k is
    :math:`A \propto 1/\sqrt{(1 - x^2)^2 + (2\zeta x)^2}`, x = n/n_res, so that
    :math:`1/A^2 \approx 4\,(1 - x)^2 + 4\zeta^2` is a parabola in n whose vertex is the
    resonance:

    .. math:: \frac{1}{A^2} = c_0 + c_1 n + c_2 n^2, \qquad n_{res} = -\frac{c_1}{2 c_2},
              \qquad \Delta n_{0.7} = 2\sqrt{\frac{1/A^2_{min}}{c_2}}

    (Δn_0.7: the width at 1/√2 of the peak, 2ζ n_res). Fitted by weighted least squares (an
    exact parabola through three records).

    Parameters
    ----------
    speed : array_like
        Speeds of the records, (…, p), p ≥ 3 along the last axis. [rad/s]
    amplitude : array_like
        The order's amplitude in each record, (…, p). [any unit]
    weights : array_like, optional
        Weights of the points (default A⁴: the same relative error in every amplitude).

    Returns
    -------
    n_res, width : ndarray
        Shaped like the leading axes; width NaN where the parabola opens downwards. [rad/s]

    Examples
    --------
    >>> n = np.array([180.0, 200.0, 210.0, 230.0])
    >>> a = 1 / np.sqrt(4 * (1 - n / 205.0) ** 2 + 4 * 0.03 ** 2)
    >>> np.round(resonance_speed(n, a), 6).tolist()
    [205.0, 12.3]
    """
    n = np.asarray(speed, dtype=float)
    a = np.asarray(amplitude, dtype=float)
    n, a = np.broadcast_arrays(n, a)
    y = 1.0 / a ** 2
    w = a ** 4 if weights is None else np.broadcast_to(np.asarray(weights, float), a.shape)
    centre = n.mean(axis=-1, keepdims=True)
    scale = np.ptp(n, axis=-1, keepdims=True)
    x = (n - centre) / scale
    X = np.stack([np.ones_like(x), x, x * x], axis=-1)
    normal = np.einsum("...p,...pi,...pj->...ij", w, X, X)
    right = np.einsum("...p,...pi,...p->...i", w, X, y)
    c = np.linalg.solve(normal, right[..., None])[..., 0]
    c0, c1, c2 = c[..., 0], c[..., 1], c[..., 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        vertex = -c1 / (2 * c2)
        low = c0 - c1 ** 2 / (4 * c2)
        width = np.where((c2 > 0) & (low > 0), 2 * np.sqrt(low / c2), np.nan)
    return centre[..., 0] + scale[..., 0] * vertex, scale[..., 0] * width


@dataclass(frozen=True)
class Resonance(Record):
    """A resonance found in a speed sweep (:func:`locate_resonances`)."""

    order: float
    """k, the resonating order. [1]"""
    peak: int
    """Index (into the speeds as given) of the record at the peak."""
    points: np.ndarray
    """Indices of the records fitted, by increasing speed."""
    speed: float
    """n_res, the interpolated speed of the peak. [rad/s]"""
    width: float
    """Δn_0.7 of the fitted peak (NaN if the fit does not close). [rad/s]"""
    step: float
    """Largest speed step between the fitted records. [rad/s]"""
    span: tuple[float, float]
    """Lowest and highest speed fitted. [rad/s]"""
    dominates: bool = True
    """Whether the order dominates the record at the peak (else only a neighbour: the peak
    fell between two records)."""

    @property
    def frequency(self) -> float:
        """k n_res/60: the natural frequency the resonance implies. [Hz]"""
        return self.order * self.speed / (2 * np.pi)

    @property
    def resolved(self) -> bool:
        """Whether the records sample the peak: it is at least as wide as the speed step
        between them, its vertex lies among them and the order dominates the peak's record."""
        return bool(self.dominates and np.isfinite(self.width) and self.width >= self.step
                    and self.span[0] <= self.speed <= self.span[1])


@dataclass(frozen=True)
class SweepEdge(Record):
    """An order whose amplitude is still rising steeply where the sweep ends."""

    order: float
    index: int
    """The record at the end of the sweep where the order dominates."""
    side: str
    """``"low"`` or ``"high"``: below the lowest or above the highest speed."""
    slope: float
    """d ln A / d ln n over the last speed step (NaN with one record). [1]"""


def locate_resonances(angular_speed, amplitude, orders, dominant, *,
                      prominence: float = PROMINENCE, level: float = FIT_LEVEL,
                      edge_slope: float = EDGE_SLOPE) -> tuple[list[Resonance],
                                                               list[SweepEdge]]:
    """Resonances of a speed sweep from the records' order amplitudes.

    For each order that dominates some record, its amplitude against speed is searched for
    peaks standing ``prominence`` of their height above the curve's lower flank, at a record
    where that order dominates (the manual's resonating order K = ν/n) or beside one (a peak
    that fell between the records: :attr:`Resonance.dominates` is then False); the records around
    the peak down to ``level`` of its height (at least its two neighbours) are fitted by
    :func:`resonance_speed`. An order still rising at either end of the sweep, where it
    dominates, faster than n^± ``edge_slope`` is returned as a :class:`SweepEdge` (a
    resonance beyond the sweep; :data:`EDGE_SLOPE`).

    Parameters
    ----------
    angular_speed : array_like
        Speed of each record, (R,), any order, distinct. [rad/s]
    amplitude : array_like
        Amplitude of each order in each record, (R, M). [any unit]
    orders : array_like
        The M orders. [1]
    dominant : array_like
        Each record's dominant order, (R,). [1]
    prominence, level, edge_slope : float, keyword-only
        See :data:`PROMINENCE`, :data:`FIT_LEVEL` and :data:`EDGE_SLOPE`.

    Returns
    -------
    resonances : list of Resonance
        By increasing speed.
    edges : list of SweepEdge

    Examples
    --------
    One mode at 200 Hz (ζ = 0.03) seen in order 6, recorded every 50 min⁻¹: its peak lies
    at 2000·√(1 − 2ζ²) = 1998 min⁻¹.

    >>> n = np.arange(1700, 2301, 50) * np.pi / 30
    >>> x = 6 * n / (2 * np.pi) / 200
    >>> a6 = 1 / np.sqrt((1 - x ** 2) ** 2 + (0.06 * x) ** 2)
    >>> found, edges = locate_resonances(n, np.c_[0.5 + 0 * n, a6], [4.0, 6.0], [6.0] * 13)
    >>> [(r.order, round(r.speed * 30 / np.pi), round(r.frequency, 1)) for r in found]
    [(6.0, 1997, 199.7)]
    """
    w = np.asarray(angular_speed, dtype=float)
    amp = np.asarray(amplitude, dtype=float)
    orders = np.asarray(orders, dtype=float)
    dom = np.asarray(dominant, dtype=float)
    by_speed = np.argsort(w)
    w, amp, dom = w[by_speed], amp[by_speed], dom[by_speed]
    found, edges = [], []
    for k in np.unique(dom):
        col = int(np.argmin(np.abs(orders - k)))
        y = amp[:, col]
        peaks, _ = find_peaks(np.r_[-np.inf, y, -np.inf])
        peaks = peaks - 1
        for j in peaks:
            beside = [i for i in (j - 1, j + 1) if 0 <= i < w.size]
            if dom[j] != k and not any(dom[i] == k for i in beside):
                continue
            if j in (0, w.size - 1):
                slope = _edge_slope(w, y, j)
                if not abs(slope) <= edge_slope:
                    edges.append(SweepEdge(float(k), int(by_speed[j]),
                                           "low" if j == 0 else "high", slope))
                continue
            prom = peak_prominences(y, [j])[0][0]
            if prom < prominence * y[j]:
                continue
            lo = j - 1
            while lo > 0 and y[lo - 1] >= level * y[j] and y[lo - 1] < y[lo]:
                lo -= 1
            hi = j + 1
            while hi < w.size - 1 and y[hi + 1] >= level * y[j] and y[hi + 1] < y[hi]:
                hi += 1
            pts = np.arange(lo, hi + 1)
            n_res, width = resonance_speed(w[pts], y[pts])
            found.append(Resonance(order=float(k), peak=int(by_speed[j]),
                                   points=by_speed[pts], speed=float(n_res),
                                   width=float(width), step=float(np.diff(w[pts]).max()),
                                   span=(float(w[lo]), float(w[hi])),
                                   dominates=bool(dom[j] == k)))
    found.sort(key=lambda r: r.speed)
    return found, edges


def _edge_slope(speed, amplitude, j: int) -> float:
    """d ln A / d ln n between the end record ``j`` and its neighbour (NaN with one)."""
    if speed.size < 2:
        return np.nan
    i = 1 if j == 0 else j - 1
    with np.errstate(divide="ignore", invalid="ignore"):
        return float(np.log(amplitude[j] / amplitude[i]) / np.log(speed[j] / speed[i]))
