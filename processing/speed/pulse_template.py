"""Timing a pulse against the train's own mean pulse shape: a matched filter.

A crossing placed by a local fit uses only the steep middle of each pulse; the lobes on
either side carry as much timing information again. Least squares against the known pulse
shape s over a whole tooth period uses all of it and comes to the Cramér–Rao bound of the
timing (Kay, *Fundamentals of Statistical Signal Processing: Estimation Theory*, 1993,
§3.11: time-delay estimation in white noise).

The shape is learned from the record itself (the mean of its first pulses, aligned on their
fitted crossings), so any sensor's pulse will do. What the learned shape cannot know is how
the engine's speed differs from the learning pulses' and changes within one pulse: an
inductive sensor gives u(t) = ω(t)·Φ'(α(t)), so a pulse at another speed is the shape scaled
in time (x → x(1 + r)), and an angular acceleration tilts the amplitude (ω grows across the
pulse) and stretches the pulse unevenly in time (α is quadratic in t). With g = ω̇/ω per
sample and x the time from the edge in samples, to first order in r and g

.. math:: u(x) = A\\,[s(x) + r\\,x s'(x) + g\\,q(x)], \\qquad q(x) = x\\,s(x) + \\tfrac12 x^2 s'(x).

q is even, like the timing direction s'; left out, it shifts every edge by an amount that
follows the engine's acceleration over the cycle (−0.3 % of δ on the benchmark's engine).
x s' is odd, but a pulse is not quite: left out, a coast-down's edges drift by 0.03 samples
against one another as the speed falls 10 %, and a calibration made on it no longer fits
the running engine's edges. Each pulse is therefore fitted with A s + B s' + C q + D x s'
and its edge moved by −B/A; the two nuisance terms cost about a tenth of the timing
precision.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import make_lsq_spline

PHASES = 64
"""Sub-sample phases at which the shape is tabulated (the linearisation point is the nearest
one; the fit corrects the rest)."""

MAX_HALF_WIDTH = 64
"""Largest half-width of the fitted stretch [samples]: beyond it the timing noise is far
below a wheel's pitch errors and the cost grows with the width."""

MISFIT = 25.0
"""A pulse whose residual mean square exceeds this multiple of the learned one (a spike, a
clipped lobe, a tooth of another shape) keeps its local-fit crossing."""

MAX_SHIFT = 2.0
"""Largest move from the local-fit crossing accepted [samples]."""

GAP_RATIO = 1.5
"""An edge whose intervals to its neighbours differ by more than this ratio sits beside a
gap (or a missed tooth): its neighbours are not where the shape expects them."""

SPEED_RANGE = 0.15
"""Edges whose interval differs from the template's by more than this fraction keep their
local-fit crossing: the first-order stretch term no longer describes the pulse."""

MIN_PULSES = 8
"""Pulses needed to learn the shape."""


@dataclass(frozen=True)
class PulseTemplate:
    """The mean pulse of a train, tabulated for least-squares timing (:func:`learn_template`)."""

    half_width: int
    """h: each edge is timed on the 2h + 1 samples around it. [samples]"""
    period: float
    """Median edge interval of the learning pulses. [samples]"""
    operator: np.ndarray
    """Per phase, the least-squares operator (GᵀG)⁻¹Gᵀ of the basis G = [s, s', q, x s'] on
    the window, shape (PHASES, 4, 2h + 1)."""
    gram: np.ndarray
    """Per phase, GᵀG, shape (PHASES, 4, 4)."""
    noise: float
    """Median residual mean square of the learning pulses (noise and shape variation)."""

    def shift(self, rows: np.ndarray, phase: np.ndarray) -> np.ndarray:
        """Move of each edge from its linearisation point, NaN where the shape does not fit.

        Parameters
        ----------
        rows : ndarray, shape (n, 2h + 1)
            Level-removed samples from h before to h after each edge's linearisation point
            (an integer sample plus ``phase``/:data:`PHASES`).
        phase : ndarray of int, shape (n,)

        Returns
        -------
        ndarray
            ε = −B/A [samples].
        """
        coef, misfit = _fit(self.operator, self.gram, rows, phase)
        with np.errstate(divide="ignore", invalid="ignore"):
            eps = -coef[:, 1] / coef[:, 0]
        good = (coef[:, 0] > 0) & (np.abs(eps) <= MAX_SHIFT) & (misfit <= MISFIT * self.noise)
        return np.where(good, eps, np.nan)


def _fit(operator, gram, rows, phase):
    """Least-squares coefficients of the basis for each row, and the residual mean square."""
    coef = np.einsum("nkw,nw->nk", operator[phase], rows)
    fitted = np.einsum("nk,nkl,nl->n", coef, gram[phase], coef)
    return coef, (np.einsum("nw,nw->n", rows, rows) - fitted) / (rows.shape[1] - coef.shape[1])


def steady(edges: np.ndarray, period: float) -> np.ndarray:
    """Where an edge's neighbours are at about equal intervals (:data:`GAP_RATIO`) and about
    one learned ``period`` away (:data:`SPEED_RANGE`): where the template applies.

    Parameters
    ----------
    edges : ndarray
        Consecutive edge positions, increasing; the first and the last have one neighbour
        only and are never steady.
    period : float
        The template's edge interval. [samples]

    Returns
    -------
    ndarray of bool
    """
    before = np.r_[np.nan, np.diff(edges)]
    after = np.r_[np.diff(edges), np.nan]
    with np.errstate(invalid="ignore"):
        return ((np.fmax(before, after) <= GAP_RATIO * np.fmin(before, after))
                & (np.abs((before + after) / (2 * period) - 1) <= SPEED_RANGE))


def windows(edges: np.ndarray, half_width: int, size: int):
    """Linearisation points of ``edges`` and the sample indices around them.

    Parameters
    ----------
    edges : ndarray
        Edge positions. [samples]
    half_width : int
        h.
    size : int
        Samples available (indices 0 … size − 1).

    Returns
    -------
    inside : ndarray of bool
        Edges whose window lies within the samples.
    point : ndarray
        Linearisation point of each inside edge (a multiple of 1/:data:`PHASES`). [samples]
    phase : ndarray of int
    index : ndarray, shape (inside.sum(), 2h + 1)
    """
    steps = np.rint(np.asarray(edges) * PHASES).astype(np.int64)
    base, phase = np.divmod(steps, PHASES)
    inside = (base - half_width >= 0) & (base + half_width < size)
    index = base[inside, None] + np.arange(-half_width, half_width + 1)
    return inside, steps[inside] / PHASES, phase[inside], index


def learn_template(y, edges) -> PulseTemplate | None:
    """The mean pulse around ``edges`` of the level-removed samples ``y``.

    Parameters
    ----------
    y : array_like
        Samples less their mean level (the detector's first block).
    edges : array_like
        The pulses' crossings in ``y`` by a local fit. [samples]

    Returns
    -------
    PulseTemplate or None
        None when fewer than :data:`MIN_PULSES` pulses lie away from a gap and the ends.

    Notes
    -----
    h is half the median edge interval (one tooth period is fitted), at most
    :data:`MAX_HALF_WIDTH`. The pulses used are those of :func:`steady` edges. They are
    scaled to unit half peak-to-peak and the shape is the least-squares cubic spline through
    all their samples, against their time from the crossing (knots every max(2, h/12)
    samples: two samples at least, so a sampling locked to the teeth still determines it).
    """
    y = np.asarray(y, dtype=np.float64)
    edges = np.asarray(edges, dtype=np.float64)
    if edges.size < MIN_PULSES + 2:
        return None
    period = float(np.median(np.diff(edges)))
    h = int(min(max(np.rint(period / 2), 3), MAX_HALF_WIDTH))
    use = edges[steady(edges, period)]
    start = np.floor(use).astype(np.int64) - h - 1
    fits = (start >= 0) & (start + 2 * h + 4 <= y.size)
    use, start = use[fits], start[fits]
    if use.size < MIN_PULSES:
        return None
    idx = start[:, None] + np.arange(2 * h + 4)
    rows = y[idx]
    scale = (rows.max(axis=1) - rows.min(axis=1)) / 2
    x = (idx - use[:, None]).ravel()
    v = (rows / scale[:, None]).ravel()
    order = np.argsort(x)
    x, v = x[order], v[order]
    lo, hi = -h - 1.0, h + 1.0
    count = max(int((hi - lo) / max(2.0, h / 12)), 4)
    knots = np.r_[[lo] * 3, np.linspace(lo, hi, count + 1), [hi] * 3]
    within = (x >= lo) & (x <= hi)
    try:
        shape = make_lsq_spline(x[within], v[within], knots, k=3)
    except (ValueError, np.linalg.LinAlgError):
        return None
    at = np.arange(-h, h + 1)[None, :] - np.arange(PHASES)[:, None] / PHASES
    s, ds = shape(at), shape.derivative()(at)
    basis = np.stack([s, ds, at * s + 0.5 * at ** 2 * ds, at * ds], axis=1)
    gram = np.einsum("pkw,plw->pkl", basis, basis)
    operator = np.linalg.solve(gram, basis)
    _, _, phase, index = windows(use, h, y.size)
    noise = float(np.median(_fit(operator, gram, y[index], phase)[1]))
    tiny = 1e-12 * float(np.median(scale)) ** 2
    return PulseTemplate(half_width=h, period=period, operator=operator, gram=gram,
                         noise=max(noise, tiny))
