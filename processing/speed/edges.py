"""Tooth-edge timing in a sampled pulse train (an inductive speed sensor, any pulse channel).

An inductive (variable-reluctance) sensor gives one bipolar pulse per tooth, u = ω dΦ/dα:
positive while the tooth approaches, negative as it leaves. The *edge* of a tooth is the
falling crossing of the signal's mean level between the two lobes: it sits at the tooth's
centre whatever the amplitude (which grows with speed), so it is the timing point of choice
(a clipped input or a DC offset do not move it either).

The detector is a comparator with hysteresis, run block by block:

* per block of ``block`` samples the level L is the block mean (removes a DC offset, follows
  a drift) and the arming threshold is L + ``hysteresis`` · RMS (follows the amplitude as
  the speed changes);
* the comparator arms when two consecutive samples exceed the threshold and fires at the
  first falling crossing of L that stays below L for two samples; a one-sample spike can
  neither arm nor fire it;
* the crossing is placed between samples by one of :data:`METHODS`.

Everything is computed on fixed blocks at absolute sample positions, so feeding a recording
in chunks of any size (:class:`EdgeDetector`) returns exactly the edges of the in-memory call
(:func:`detect_edges`); memory is bounded by the batch, whatever the recording's length.
The large passes compare the stored samples (``int16`` codes stay integers) against
per-block thresholds; only the few samples around each edge are ever converted to float.
"""
from __future__ import annotations

from collections.abc import Iterable
from functools import lru_cache

import numpy as np

from processing.diagnostics import InputError
from .pulse_template import PulseTemplate, learn_template, steady, windows

METHODS = ("linear", "cubic", "fit", "matched")
"""Sub-sample placement of a crossing between samples:

``linear``
    the straight line through the two samples around the crossing;
``cubic``
    the cubic through the four samples around it (Lagrange), root by Newton's method;
``fit``
    the least-squares cubic through ``2·window`` samples around it, root by Newton's method
    (anywhere within the middle half of the window): averages the noise of the samples over
    the whole steep part of the pulse and, unlike a least-squares line, follows the
    waveform's curvature, so it has no bias that depends on where the crossing falls
    between samples (which would repeat tooth by tooth when the sampling locks to them).
    With the window fitted to the pulse (:func:`fit_window`) its timing noise is within 2×
    of the Cramér–Rao bound for a known pulse shape in white noise.
``matched``
    ``fit``, then least squares against the record's own mean pulse over a whole tooth
    period (:mod:`processing.speed.pulse_template`, learned on the first block): uses the lobes
    too and comes within 30 % of the Cramér–Rao bound. Edges beside a gap or a missed tooth
    (their neighbours are not where the mean pulse has them), pulses the mean shape does not
    fit (a spike, a clipped lobe) and pulses more than 15 % faster or slower than the first
    block's keep the ``fit`` crossing. Because the window spans the neighbours' lobes, an
    edge moves with its neighbours' pitch errors too (by about 15 % of them on the synthetic
    sensor): a wheel calibrated on a coast-down must be calibrated with the same method.
"""

FIT_SPAN = 0.3
"""``fit`` half-width over the peak-to-trough distance D of the pulses (the lobes of an
inductive sensor's bipolar pulse): 0.3 D spans the steep middle of the crossing (±0.6σ of a
Gaussian flux bump, ±54° of a sine), where the cubic's shape error stays below 10⁻⁴ of a
pitch even when the neighbouring teeth are off pitch (the calibration needs that); wider
windows average more noise but the cubic no longer follows the pulse."""

MIN_WINDOW, MAX_WINDOW = 4, 32
"""Range of the automatic ``fit`` half-width [samples]: above 32 the noise per pitch is
already far below the wheel's pitch errors, and the fit's cost grows with the window."""


MATCH_BATCH = 4096
"""Edges timed against the template per vectorised step (bounds the temporary memory)."""


def _as_samples(chunk) -> np.ndarray:
    x = np.asarray(chunk)
    if x.ndim != 1:
        raise InputError(f"a signal chunk must be one-dimensional, got shape {x.shape}",
                         "pass one channel at a time")
    if x.dtype.kind not in "iuf":
        raise InputError(f"signal samples must be numbers, got dtype {x.dtype}",
                         "convert the channel to integers or floats")
    if x.dtype.kind == "f" and x.dtype.itemsize < 4:
        x = x.astype(np.float32)
    return x


def _block_thresholds(x2d: np.ndarray, hysteresis: float, stride: int = 4):
    """Per-block level (mean) and arming threshold in the samples' own dtype.

    Integers compare against integer thresholds with the same result as the real ones
    (x < L ⇔ x < ⌈L⌉, x > H ⇔ x > ⌊H⌋), so no float copy of the block is made.
    The RMS about the mean is taken on every ``stride``-th sample (thousands per block).
    """
    level = x2d.mean(axis=1, dtype=np.float64)
    sub = x2d[:, ::stride].astype(np.float64)
    sub -= level[:, None]
    rms = np.sqrt(np.einsum("ij,ij->i", sub, sub) / sub.shape[1])
    high = level + hysteresis * rms
    if x2d.dtype.kind in "iu":
        info = np.iinfo(x2d.dtype)
        low_cmp = np.clip(np.ceil(level), info.min, info.max).astype(x2d.dtype)
        high_cmp = np.clip(np.floor(high), info.min, info.max).astype(x2d.dtype)
    else:
        low_cmp, high_cmp = level.astype(x2d.dtype), high.astype(x2d.dtype)
    return level, low_cmp, high_cmp


def _place(y: np.ndarray, method: str, window: int) -> np.ndarray:
    """Crossing offset (in samples, from the window's first sample) of each row of ``y``.

    ``y`` holds, per crossing, the level-removed samples from ``c - window`` to
    ``c + window - 1`` where the signal is above the level at ``c - 1`` and below at ``c``.
    """
    w = window
    y0, y1 = y[:, w - 1], y[:, w]
    linear = (w - 1) + y0 / (y0 - y1)
    if method == "linear":
        return linear
    if method == "cubic":
        p = y[:, w - 2: w + 2]
        s = linear - (w - 2)
        for _ in range(3):
            d = (s[:, None] - np.arange(4.0))
            # Lagrange basis on nodes 0..3 and their derivatives at s
            l0 = -d[:, 1] * d[:, 2] * d[:, 3] / 6
            l1 = d[:, 0] * d[:, 2] * d[:, 3] / 2
            l2 = -d[:, 0] * d[:, 1] * d[:, 3] / 2
            l3 = d[:, 0] * d[:, 1] * d[:, 2] / 6
            f = l0 * p[:, 0] + l1 * p[:, 1] + l2 * p[:, 2] + l3 * p[:, 3]
            dl0 = -(d[:, 2] * d[:, 3] + d[:, 1] * d[:, 3] + d[:, 1] * d[:, 2]) / 6
            dl1 = (d[:, 2] * d[:, 3] + d[:, 0] * d[:, 3] + d[:, 0] * d[:, 2]) / 2
            dl2 = -(d[:, 1] * d[:, 3] + d[:, 0] * d[:, 3] + d[:, 0] * d[:, 1]) / 2
            dl3 = (d[:, 1] * d[:, 2] + d[:, 0] * d[:, 2] + d[:, 0] * d[:, 1]) / 6
            df = dl0 * p[:, 0] + dl1 * p[:, 1] + dl2 * p[:, 2] + dl3 * p[:, 3]
            s = np.clip(s - f / df, 1.0, 2.0)
        return s + (w - 2)
    # least-squares cubic in coordinates centred between samples c-1 and c; with noise the
    # first sample below the level may be several samples past the crossing, so the root
    # may move within the middle half of the window
    basis, to_cubic = _cubic(w)
    coef = y @ to_cubic
    rows = np.flatnonzero((y[:, 1:] == y[:, :-1]).any(axis=1))   # a value held: clipped?
    flat = _saturated(y[rows])
    usable = flat.any(axis=1) & (np.sum(~flat, axis=1) >= 6)
    rows, flat = rows[usable], flat[usable]
    if rows.size:                       # a clipped input: fit the samples below the clip only
        weighted = basis * (~flat)[:, :, None]
        normal = np.einsum("rik,ril->rkl", weighted, weighted)
        right = np.einsum("rik,ri->rk", weighted, y[rows])[:, :, None]
        coef[rows] = np.linalg.solve(normal, right)[:, :, 0]
    root = (linear - (w - 0.5)).copy()
    for _ in range(6):
        f = coef[:, 0] + root * (coef[:, 1] + root * (coef[:, 2] + root * coef[:, 3]))
        df = coef[:, 1] + root * (2 * coef[:, 2] + 3 * root * coef[:, 3])
        root = np.clip(root - f / df, -w / 2, w / 2)
    return root + (w - 0.5)


@lru_cache(maxsize=16)
def _cubic(window: int) -> tuple[np.ndarray, np.ndarray]:
    """The least-squares cubic of :func:`_place` over 2·``window`` samples, in coordinates
    centred between samples ``window`` − 1 and ``window``: its basis (1, x, x², x³ per
    sample) and the transposed pseudo-inverse that takes a row of samples to the cubic's
    coefficients, made once per window and kept (read-only)."""
    x = np.arange(2 * window, dtype=np.float64) - (window - 0.5)
    basis = np.vander(x, 4, increasing=True)
    rows = np.linalg.pinv(basis).T
    basis.flags.writeable = rows.flags.writeable = False
    return basis, rows


def _saturated(y: np.ndarray) -> np.ndarray:
    """Samples at a row's maximum or minimum where that value repeats (a clipped input or a
    saturated ADC holds it for several samples; only rows holding a value are passed)."""
    top, bottom = y.max(axis=1, keepdims=True), y.min(axis=1, keepdims=True)
    at_top, at_bottom = y == top, y == bottom
    return ((at_top & (at_top.sum(axis=1, keepdims=True) > 1))
            | (at_bottom & (at_bottom.sum(axis=1, keepdims=True) > 1)))


def fit_window(x, *, hysteresis: float = 0.5, default: int = 4) -> int:
    """The ``fit`` half-width suited to the pulses in ``x``: round(:data:`FIT_SPAN` · D).

    Parameters
    ----------
    x : array_like
        A stretch of the channel holding a few pulses (the detector uses its first block).
    hysteresis : float
        As for :class:`EdgeDetector`.
    default : int
        Returned when ``x`` holds fewer than four edges.

    Returns
    -------
    int
        Half-width in samples, in [:data:`MIN_WINDOW`, :data:`MAX_WINDOW`].

    Notes
    -----
    D is the median distance from the positive peak before each edge (searched over half an
    edge interval) to the negative peak after it. The timing noise of the least-squares
    cubic falls as 1/√(window) while the window stays on the pulse's steep part: on a
    60−2 wheel at 111 samples per tooth and 20 dB, 0.30 samples with the window of
    :data:`FIT_SPAN` against 0.65 with a fixed 8-sample window (the Cramér–Rao bound of
    the whole pulse is 0.17).

    Examples
    --------
    >>> t = np.arange(40000)
    >>> fit_window(np.sin(2 * np.pi * t / 100 + np.pi))     # 100 samples per period, D = 50
    15
    """
    x = np.asarray(x)
    edges = np.rint(detect_edges(x, "linear", hysteresis=hysteresis)).astype(np.int64)
    if edges.size < 4:
        return default
    half = max(int(np.median(np.diff(edges))) // 2, 1)
    inner = edges[(edges >= half) & (edges + half <= x.size)]
    if inner.size < 2:
        return default
    before = np.lib.stride_tricks.sliding_window_view(x, half)
    peak = inner - half + np.argmax(before[inner - half], axis=1)
    trough = inner + np.argmin(before[inner], axis=1)
    width = FIT_SPAN * np.median(trough - peak)
    return int(np.clip(np.rint(width), MIN_WINDOW, MAX_WINDOW))


class EdgeDetector:
    """Falling crossings of a pulse train, fed chunk by chunk.

    Parameters
    ----------
    method : {"linear", "cubic", "fit", "matched"}
        Sub-sample placement (:data:`METHODS`).
    hysteresis : float
        Arming threshold above the block mean, in units of the block's RMS. 0.5 rejects
        noise up to an SNR of about 10 dB and arms on lobes above a quarter of the peak.
    window : int, optional
        Half-width of the ``fit`` window in samples (``2·window`` samples are fitted, ≥ 2;
        ``matched`` starts from that fit).
        Default: :func:`fit_window` of the first block, so that the window spans the steep
        part of the pulses at any sampling rate.
    block : int
        Samples per block over which the level and RMS are taken.
    batch : int
        Blocks processed per vectorised pass (bounds the temporary memory).

    Examples
    --------
    >>> t = np.arange(4000) / 1000.0
    >>> x = np.sin(2 * np.pi * 50 * t + np.pi)        # falling crossings at k/50 s
    >>> det = EdgeDetector("linear", block=1000)
    >>> edges = np.concatenate([det.feed(c) for c in np.array_split(x, 7)] + [det.finish()])
    >>> np.round(edges[:3] / 1000.0, 6)
    array([0.02, 0.04, 0.06])
    """

    def __init__(self, method: str = "fit", *, hysteresis: float = 0.5,
                 window: int | None = None, block: int = 2 ** 16, batch: int = 16):
        if method not in METHODS:
            raise InputError(f"unknown edge method {method!r}", f"use one of {', '.join(METHODS)}")
        if not 0 < hysteresis < 3:
            raise InputError(f"hysteresis {hysteresis!r} out of range",
                             "give it in RMS units, between 0.1 and 1")
        self.method, self.hysteresis, self.block, self.batch = method, hysteresis, block, batch
        fit = None if window is None else max(int(window), 2)
        self.window = {"linear": 1, "cubic": 2, "fit": fit, "matched": fit}[method]
        self.template: PulseTemplate | None = None
        self._held = None              # (fit, matched) of the last edge: its next is unknown
        self._before_held = np.nan     # fit position of the edge before it
        self._pending: list[np.ndarray] = []
        self._pending_len = 0
        self._tail = None              # (raw, level, below, above) of the context samples
        self._start = 0                # absolute index of the tail's first sample
        self._armed = False
        self._last_thresholds = None

    def feed(self, chunk) -> np.ndarray:
        """Edges (absolute sample positions, float) confirmed by the samples so far."""
        x = _as_samples(chunk)
        if x.size:
            self._pending.append(x)
            self._pending_len += x.size
        out = []
        step = self.block * self.batch
        while self._pending_len >= self.block:
            data = self._take(min(step, self._pending_len // self.block * self.block))
            out.append(self._process(data))
        return np.concatenate(out) if out else np.empty(0)

    def finish(self) -> np.ndarray:
        """Edges in the last, partial block; the detector is then exhausted."""
        data = self._take(self._pending_len)
        if data.size:
            edges = self._process(data, final=True)
        else:
            edges = self._settle(np.empty(0), np.empty(0), final=True)
        self._tail = None
        return edges

    def _take(self, n: int) -> np.ndarray:
        if not self._pending:
            return np.empty(0)
        data = np.concatenate(self._pending) if len(self._pending) > 1 else self._pending[0]
        rest = data[n:]
        self._pending = [rest] if rest.size else []
        self._pending_len = rest.size
        return data[:n]

    @property
    def _reach(self) -> int:
        """Samples the template's window reaches beyond a crossing (0 without one)."""
        if self.template is None:
            return 0
        return self.template.half_width + self.window // 2 + 3

    @property
    def _fit_left(self) -> int:
        """Samples the crossing's own fit needs before it."""
        return self.window + 2

    @property
    def _left(self) -> int:
        return max(self._fit_left, self._reach)

    @property
    def _right(self) -> int:
        return max(self.window + 1, self._reach)

    def _process(self, data: np.ndarray, final: bool = False) -> np.ndarray:
        if self.window is None:         # the first call's data start with the first block
            self.window = fit_window(data[:self.block], hysteresis=self.hysteresis)
            if self.method == "matched":
                first = data[:self.block]
                crossings = detect_edges(first, "fit", window=self.window,
                                         hysteresis=self.hysteresis, block=self.block)
                self.template = learn_template(first - first.mean(dtype=np.float64), crossings)
        if final:
            x2d = data.reshape(1, -1)
            if data.size < self.block // 8 and self._last_thresholds is not None:
                lv, lo, hi = (np.array([v]) for v in self._last_thresholds)
            else:
                lv, lo, hi = _block_thresholds(x2d, self.hysteresis)
        else:
            x2d = data.reshape(-1, self.block)
            lv, lo, hi = _block_thresholds(x2d, self.hysteresis)
        self._last_thresholds = (lv[-1], lo[-1], hi[-1])
        per = x2d.shape[1]
        t_raw, t_lv, t_below, t_above = self._tail or (
            np.empty(0, data.dtype), np.empty(0), np.empty(0, bool), np.empty(0, bool))
        n_tail = t_raw.size
        raw = np.concatenate([t_raw, data])
        below = np.concatenate([t_below, (x2d < lo[:, None]).ravel()])
        above = np.concatenate([t_above, (x2d > hi[:, None]).ravel()])

        def levels(idx):
            inside = idx >= n_tail
            out = np.empty(idx.shape)
            out[~inside] = t_lv[idx[~inside]]
            out[inside] = lv[(idx[inside] - n_tail) // per]
            return out

        n = raw.size
        # the record's first samples have no tail before them: the fit's own margin will do
        # there (an edge too near the start for the template keeps its fit crossing)
        first = self._left if self._tail is not None else self._fit_left
        stop = n - self._right
        # a crossing at c: below the level at c and c+1, not at c-1
        cross = np.flatnonzero(below[1:-1] & below[2:] & ~below[:-2]) + 1
        cross = cross[(cross >= first) & (cross < stop)]
        # arming at a: the start of a run of >= 2 samples above the threshold
        arm = np.flatnonzero(above[2:] & above[1:-1] & ~above[:-2]) + 2
        arm = arm[(arm >= first) & (arm < stop)]
        after = np.searchsorted(cross, arm, side="right")
        accepted = np.unique(cross[after[after < cross.size]])
        if self._armed and cross.size:
            accepted = np.union1d(accepted, cross[:1])
        self._armed = bool((arm.size and (accepted.size == 0 or arm[-1] > accepted[-1]))
                           or (self._armed and cross.size == 0))
        edges = offset = np.empty(0)
        if accepted.size:
            w = self.window
            idx = accepted[:, None] + np.arange(-w, w)
            y = raw[idx].astype(np.float64) - levels(idx)
            offset = _place(y, "fit" if self.method == "matched" else self.method, w)
            edges = self._start + (accepted - w) + offset      # integers first: exact
        if self.method == "matched":
            edges = self._settle(edges, self._match(raw, levels, (accepted - w) + offset), final)
        if not final:
            t0 = n - self._left - self._right
            self._tail = (raw[t0:].copy(), levels(np.arange(t0, n)), below[t0:].copy(),
                          above[t0:].copy())
            self._start += t0
        return edges

    def _match(self, raw, levels, edges) -> np.ndarray:
        """``edges`` (positions in ``raw``) timed against the template, as absolute positions;
        NaN where it does not apply (no template, window outside ``raw``, a misfit)."""
        out = np.full(edges.size, np.nan)
        if self.template is None:
            return out
        for lo in range(0, edges.size, MATCH_BATCH):
            part = slice(lo, lo + MATCH_BATCH)
            inside, point, phase, index = windows(edges[part], self.template.half_width, raw.size)
            rows = raw[index].astype(np.float64) - levels(index)
            out[part][inside] = (self._start + point) + self.template.shift(rows, phase)
        return out

    def _settle(self, fit: np.ndarray, matched: np.ndarray, final: bool) -> np.ndarray:
        """Each edge's matched position where the template applies (:func:`steady`), else its
        fit position; the last edge is held until its next one is known."""
        if self.template is None:
            return fit
        if self._held is not None:
            fit, matched = np.r_[self._held[0], fit], np.r_[self._held[1], matched]
        if fit.size == 0:
            return fit
        ok = steady(np.r_[self._before_held, fit, np.nan], self.template.period)[1:-1]
        ok &= ~np.isnan(matched)
        out = np.where(ok, matched, fit)
        if final:
            self._held = None
            return out
        if fit.size > 1:
            self._before_held = fit[-2]
        self._held = (fit[-1], matched[-1])
        return out[:-1]


def detect_edges(x, method: str = "fit", **options) -> np.ndarray:
    """Tooth edges of an in-memory signal, in samples from its first sample.

    Parameters
    ----------
    x : array_like
        One channel (integer ADC codes or floats).
    method : {"linear", "cubic", "fit", "matched"}
    **options
        Passed to :class:`EdgeDetector` (``hysteresis``, ``window``, ``block``).

    Returns
    -------
    numpy.ndarray
        Edge positions in samples (divide by the sample rate for seconds).
    """
    return stream_edges([x], method, **options)


def stream_edges(chunks: Iterable, method: str = "fit", **options) -> np.ndarray:
    """Tooth edges of a signal given as consecutive chunks (same result as in memory)."""
    det = EdgeDetector(method, **options)
    parts = [det.feed(c) for c in chunks]
    return np.concatenate(parts + [det.finish()])
