"""One uncertainty mechanism for every lab: GUM linear propagation with a Monte Carlo check.

Formulas stay plain vectorised numpy functions of named inputs. :func:`propagate` evaluates
such a model *once* on a stacked array holding the best estimates, the finite-difference
points for the sensitivity coefficients (GUM, JCGM 100:2008, §5.1) and the Monte Carlo draws
(GUM Supplement 1, JCGM 101:2008). Inputs carry their own budget (:class:`Measured`): type A
from repeated readings (mean, s/√n, Student t with n − 1 degrees of freedom) and type B from an
instrument's limit of error (rectangular) or a stated standard uncertainty (normal).

Nonlinearity is detected without distribution-shape artefacts: the Monte Carlo draws are also
pushed through the *linearised* model, and the central 68 % intervals (about ± u) of the two
are compared. Where an end differs by more than 10 % of the linear half-width, u from linear
propagation does not describe the output and the estimate is flagged ``nonlinear``; labs turn
that into a :class:`~processing.diagnostics.NonlinearityWarning`. (The 68 % interval, not the
95 % one, because Student-t draws for three repeats reach ± 4.3 u, where any curved formula
departs from its tangent without u being wrong.)
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from collections.abc import Callable, Mapping

import numpy as np
from scipy import stats

NONLINEAR_TOLERANCE = 0.10
"""Allowed shift of a 68 % interval end, as a fraction of the linear half-width."""


COVERAGE = math.erf(math.sqrt(2.0))
"""The coverage probability of an expanded uncertainty, 95.45 % (the normal law's ± 2σ, the p
of GUM Table G.2): its t factor is k = 2 for infinite degrees of freedom, so that an estimate
of type B parts alone keeps U = 2u, while one dominated by a few readings gets Student's wider
factor."""


@functools.lru_cache(maxsize=4096)
def coverage_factor(dof: float) -> float:
    """Coverage factor k = t_p(ν_eff) for p = :data:`COVERAGE` (JCGM 100:2008, G.4.1, Table
    G.2): the Student t quantile at the effective degrees of freedom of Welch–Satterthwaite.

    With few readings the normal law's k = 2 understates the interval (three readings alone:
    ν = 2, a k = 2 interval covers the truth only 82 % of the time); t_p(ν) restores the
    coverage and agrees with the Monte Carlo interval of GUM Supplement 1.

    Parameters
    ----------
    dof : float
        Effective degrees of freedom ν_eff (``inf`` for type B only).

    Returns
    -------
    float
        k; 2 for infinite ν_eff.

    Examples
    --------
    >>> round(coverage_factor(2), 2), round(coverage_factor(10), 2), coverage_factor(math.inf)
    (4.53, 2.28, 2.0)
    """
    if not math.isfinite(dof):
        return 2.0
    return float(stats.t.ppf(0.5 + COVERAGE / 2, dof))


@dataclass(frozen=True)
class Measured:
    """A measured input quantity with its uncertainty budget, in SI units.

    Parameters
    ----------
    value : float
        Best estimate (the mean of the readings, if any).
    u_a : float
        Type A standard uncertainty of the mean, s/√n.
    dof_a : float
        Degrees of freedom of ``u_a`` (n − 1); ``inf`` when there is no type A part.
    limit : float
        Type B: half-width a of a rectangular distribution (an instrument's limit of error,
        "± 0.5 mm"); its standard uncertainty is a/√3.
    u_b : float
        Type B: a standard uncertainty stated directly (normal distribution).
    readings : tuple of float
        The raw readings in SI, kept for the report.

    Examples
    --------
    >>> t = Measured.from_readings([24.31, 24.28, 24.40], limit=0.005)
    >>> round(t.value, 3), round(t.u, 4), t.dof_a
    (24.33, 0.0362, 2)
    """

    value: float
    u_a: float = 0.0
    dof_a: float = math.inf
    limit: float = 0.0
    u_b: float = 0.0
    readings: tuple = ()

    @classmethod
    def from_readings(cls, readings, *, limit: float = 0.0, u_b: float = 0.0) -> Measured:
        """Mean of repeated readings with type A u = s/√n (n − 1 degrees of freedom)."""
        x = np.asarray(readings, dtype=float)
        n = x.size
        u_a = float(x.std(ddof=1) / math.sqrt(n)) if n > 1 else 0.0
        return cls(float(x.mean()), u_a, n - 1 if n > 1 else math.inf, limit, u_b, tuple(x.tolist()))

    @property
    def u_type_b(self) -> float:
        return math.hypot(self.limit / math.sqrt(3.0), self.u_b)

    @property
    def u(self) -> float:
        """Combined standard uncertainty."""
        return math.hypot(self.u_a, self.u_type_b)

    @property
    def dof(self) -> float:
        """Effective degrees of freedom (Welch–Satterthwaite over the A and B parts)."""
        if self.u_a == 0.0 or not math.isfinite(self.dof_a):
            return math.inf
        return self.u**4 / (self.u_a**4 / self.dof_a)

    def scaled(self, factor: float) -> Measured:
        """The same measurement multiplied by a known constant (e.g. a unit factor)."""
        f = abs(factor)
        return Measured(self.value * factor, self.u_a * f, self.dof_a, self.limit * f, self.u_b * f,
                        tuple(r * factor for r in self.readings))

    def sample(self, rng: np.random.Generator, size: int) -> np.ndarray:
        """Draws from the input's distribution (GUM S1 §6.4): t for type A, rectangular and
        normal for type B, added."""
        x = np.full(size, self.value)
        if self.u_a > 0.0:
            x += self.u_a * (rng.standard_t(self.dof_a, size) if math.isfinite(self.dof_a)
                             else rng.standard_normal(size))
        if self.limit > 0.0:
            x += rng.uniform(-self.limit, self.limit, size)
        if self.u_b > 0.0:
            x += self.u_b * rng.standard_normal(size)
        return x


@dataclass(frozen=True)
class Estimate:
    """An output quantity: value, standard uncertainty and how it was obtained.

    Attributes
    ----------
    value : float
        The model evaluated at the best estimates of the inputs.
    u : float
        Combined standard uncertainty, linear propagation (GUM).
    dof : float
        Effective degrees of freedom (Welch–Satterthwaite).
    contributions : dict
        |c_i| u(x_i) for each uncertain input, the uncertainty budget.
    interval95 : tuple
        Monte Carlo 95 % probabilistically symmetric coverage interval (GUM S1).
    u_mc : float
        Monte Carlo standard deviation of the output.
    nonlinear : bool
        True when the central 68 % Monte Carlo intervals of the model and of its
        linearisation differ by more than :data:`NONLINEAR_TOLERANCE` of the linear
        half-width.
    """

    value: float
    u: float
    dof: float
    contributions: Mapping[str, float] = field(default_factory=dict)
    interval95: tuple[float, float] = (math.nan, math.nan)
    u_mc: float = math.nan
    nonlinear: bool = False

    @property
    def k(self) -> float:
        """The coverage factor of :attr:`U`: :func:`coverage_factor` of the effective degrees
        of freedom (2 where they are infinite, 4.53 for three readings alone)."""
        return coverage_factor(self.dof)

    @property
    def U(self) -> float:
        """Expanded uncertainty U = k·u, k = t₉₅.₄₅(ν_eff) (:func:`coverage_factor`)."""
        return self.k * self.u

    @property
    def relative_U(self) -> float:
        return self.U / abs(self.value) if self.value else math.inf


class Propagation:
    """Outputs of a model propagated through :func:`propagate`.

    Index it by output name to get an :class:`Estimate`; :meth:`difference` gives the
    estimate of ``a − b`` with the correlations of shared inputs taken into account.
    """

    def __init__(self, nominal, jacobian, inputs, u_inputs, dof_inputs, mc, mc_linear):
        self._nominal = nominal
        self._jac = jacobian
        self._inputs = inputs
        self._u = u_inputs
        self._dof = dof_inputs
        self._finite_dof = np.isfinite(dof_inputs)
        self._mc = mc
        self._mc_lin = mc_linear
        self._cache: dict[str, Estimate] = {}

    def __contains__(self, name: str) -> bool:
        return name in self._nominal

    def __getitem__(self, name: str) -> Estimate:
        if name not in self._cache:
            self.estimates([name])
        return self._cache[name]

    def estimates(self, names) -> dict[str, Estimate]:
        """The estimates of the outputs ``names``, their linear parts found together (a
        lab's hundreds of outputs in a few array operations, not one by one)."""
        todo = [n for n in dict.fromkeys(names) if n not in self._cache]
        if todo:
            jac = np.array([self._jac[n] for n in todo]).reshape(len(todo), self._u.size)
            found = self._estimates([self._nominal[n] for n in todo], jac,
                                    [self._mc[n] for n in todo], [self._mc_lin[n] for n in todo])
            self._cache.update(zip(todo, found))
        return {n: self._cache[n] for n in names}

    def names(self) -> list[str]:
        return list(self._nominal)

    def samples(self, name: str) -> np.ndarray:
        """The Monte Carlo draws of an output (for histograms)."""
        return self._mc[name]

    def difference(self, a: str, b: str) -> Estimate:
        """Estimate of output ``a`` minus output ``b``, correlations included."""
        return self._estimates([self._nominal[a] - self._nominal[b]],
                               (self._jac[a] - self._jac[b])[None, :],
                               [self._mc[a] - self._mc[b]],
                               [self._mc_lin[a] - self._mc_lin[b]])[0]

    def _estimates(self, values, jac: np.ndarray, mcs, mc_lins) -> list[Estimate]:
        """Estimates of outputs of ``values`` and sensitivities the rows of ``jac``: u and
        the Welch–Satterthwaite ν of all at once, then each one's budget and Monte Carlo
        interval."""
        c = np.abs(jac) * self._u
        u = np.sqrt([row @ row for row in c])
        finite = self._finite_dof
        denom = np.sum(c[:, finite] ** 4 / self._dof[finite], axis=1)
        with np.errstate(divide="ignore", invalid="ignore"):
            dof = np.where(denom > 0, u ** 4 / denom, math.inf)
        contrib = [{} for _ in values]
        rows, cols = np.nonzero(c)
        for row, col, share in zip(rows.tolist(), cols.tolist(), c[rows, cols].tolist()):
            contrib[row][self._inputs[col]] = share
        return [self._estimate(float(value), ui, nu, budget, mc, mc_lin)
                for value, ui, nu, budget, mc, mc_lin
                in zip(values, u.tolist(), dof.tolist(), contrib, mcs, mc_lins)]

    @staticmethod
    def _estimate(value, u, dof, contrib, mc, mc_lin) -> Estimate:
        if mc.size == 0:
            return Estimate(value, u, dof, contrib, (value, value), 0.0, False)
        ok = np.isfinite(mc)
        if ok.sum() < 0.99 * mc.size:
            return Estimate(value, u, dof, contrib, (math.nan, math.nan), math.nan, True)
        lo, a, b, hi = np.quantile(mc[ok], [0.025, 0.16, 0.84, 0.975])
        a_l, b_l = np.quantile(mc_lin[ok], [0.16, 0.84])
        half = 0.5 * (b_l - a_l)
        nonlinear = bool(half > 0 and max(abs(a - a_l), abs(b - b_l)) > NONLINEAR_TOLERANCE * half)
        return Estimate(value, u, dof, contrib, (float(lo), float(hi)), float(mc[ok].std()), nonlinear)


def propagate(model: Callable[..., Mapping[str, np.ndarray]],
              inputs: Mapping[str, Measured | float | int | str], *,
              n_samples: int = 20000, seed: int = 20031,
              rel_step: float = 1e-3) -> Propagation:
    """Propagate input uncertainties through a vectorised model.

    Parameters
    ----------
    model : callable
        ``model(**inputs) -> {output_name: array}``; called once with every uncertain input an
        array of the same length (constants are passed as they are). It must broadcast.
    inputs : mapping
        Keyword arguments of ``model``: :class:`Measured` for measured quantities, anything
        else is passed through as a constant.
    n_samples : int
        Monte Carlo draws (GUM S1 adaptive schemes settle near 10⁴–10⁵ for two significant
        digits; 2·10⁴ by default).
    seed : int
        Seed of the draws, so a report is reproducible.
    rel_step : float
        Finite-difference step for the sensitivity coefficients, as a fraction of u(x_i).

    Returns
    -------
    Propagation
        Indexable by output name, giving an :class:`Estimate` for each.

    Notes
    -----
    Linear: :math:`u_c^2(y) = \\sum_i (\\partial f/\\partial x_i)^2 u^2(x_i)` with central
    differences; effective degrees of freedom by Welch–Satterthwaite
    :math:`\\nu_{eff} = u_c^4 / \\sum_i (c_i u_i)^4/\\nu_i`.
    Monte Carlo: GUM S1, probabilistically symmetric 95 % interval.

    References
    ----------
    .. [1] JCGM 100:2008, Guide to the expression of uncertainty in measurement.
    .. [2] JCGM 101:2008, Supplement 1: Propagation of distributions using a Monte Carlo method.

    Examples
    --------
    >>> p = propagate(lambda a, b: {"y": a * b},
    ...               {"a": Measured(2.0, u_b=0.1), "b": Measured(3.0, u_b=0.2)})
    >>> e = p["y"]
    >>> round(e.value, 6), round(e.u, 4)
    (6.0, 0.5)
    """
    uncertain = [k for k, v in inputs.items() if isinstance(v, Measured) and v.u > 0.0]
    p = len(uncertain)
    rng = np.random.default_rng(seed)
    args = {}
    certain = inputs.keys() - set(uncertain)
    for k, v in inputs.items():
        if k in certain:
            args[k] = v.value if isinstance(v, Measured) else v
    # one row per uncertain input: its best estimate, ± its step in its own two columns,
    # then its draws
    length = 1 + 2 * p + n_samples
    best = np.array([inputs[k].value for k in uncertain], dtype=float)
    h = rel_step * np.array([inputs[k].u for k in uncertain])
    rows = np.empty((p, length))
    rows[:, :1 + 2 * p] = best[:, None]
    rows[np.arange(p), 1 + 2 * np.arange(p)] += h
    rows[np.arange(p), 2 + 2 * np.arange(p)] -= h
    if n_samples:
        for row, k in zip(rows, uncertain):
            row[1 + 2 * p:] = inputs[k].sample(rng, n_samples)
    args.update(zip(uncertain, rows))
    with np.errstate(all="ignore"):
        out = model(**args)
    nominal, jac, mc, mc_lin = {}, {}, {}, {}
    deltas = rows[:, 1 + 2 * p:] - best[:, None]
    for name, y in out.items():
        y = np.asarray(y, dtype=float)
        if not p:
            y = y.reshape(-1)
        elif y.shape != (length,):
            y = np.broadcast_to(y, (length,))
        nominal[name] = float(y[0])
        jac[name] = (y[1:1 + 2 * p:2] - y[2:2 + 2 * p:2]) / (2 * h)
        mc[name] = np.asarray(y[1 + 2 * p:])
        mc_lin[name] = (nominal[name] + jac[name] @ deltas if n_samples and p
                        else np.zeros(0))
    return Propagation(nominal, jac, uncertain, np.array([inputs[k].u for k in uncertain]),
                       np.array([inputs[k].dof for k in uncertain], dtype=float), mc, mc_lin)
