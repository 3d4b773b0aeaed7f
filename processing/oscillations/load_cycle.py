"""A static test loaded in steps and unloaded: its branches, their mean, the straight lines
through them, and the loop between them.

A stiffness test sets a load (or a displacement) in steps up to its largest value and back,
and reads one or more responses at each step (dial gauges, a dynamometer). A
:class:`LoadCycle` holds one such run in the order read; :meth:`LoadCycle.branch` gives the
loading branch, the unloading branch, or their pointwise mean at the steps read on both.
:func:`fit_branches` fits a straight line to each response on each branch, pooled over the
runs (:func:`processing.regression.fit_line`), takes the line midway between them as the
elastic line (:func:`midway`), and tests the pointwise mean for curvature
(:func:`processing.regression.curvature_test`); :func:`hysteresis` measures the loop
(:func:`processing.oscillations.loops.loop_area`) against the work of the loading branch
(:func:`processing.oscillations.loops.branch_work`).

Friction holds a part where it stands until the load has moved by twice the friction force:
the loading branch runs the friction's width on one side of the elastic line, the unloading
branch on the other, and the mean of the two is the elastic line. At a turning point (the
first reading, from rest; the largest load, read once) the friction has not reversed yet, so
that reading lies on neither branch's line: each branch's line is fitted without its turning
point. (The manual's pointwise mean keeps both ends; with a friction F they tilt its line by
about 0.7 F/P_max, which is more than the line's own uncertainty once F reaches a few per
cent of the load.)
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .loops import branch_work, loop_area
from processing.regression import CurvatureTest, LineFit, curvature_test, fit_line
from processing.result import Record
from processing.uncertainty import Measured

def out_of_order(x) -> tuple[int, int | None]:
    """Where a loading-then-unloading programme peaks, and its first reading out of order.

    The loads must rise step by step to the largest and then fall; the largest may be read
    twice (at the end of the loading and again at the start of the unloading).

    Parameters
    ----------
    x : array_like
        The loads in the order they were applied.

    Returns
    -------
    peak : int
        Index of the (first) largest load.
    bad : int or None
        Index of the first load that breaks the programme; None if none does.

    Examples
    --------
    >>> out_of_order([0, 1, 2, 2, 1, 0]), out_of_order([0, 2, 1, 2, 0])
    ((2, None), (1, 3))
    """
    x = np.asarray(x, dtype=float)
    peak = int(np.argmax(x))
    step = np.diff(x)
    fall = step[peak:] >= 0
    fall[:1] &= step[peak:peak + 1] > 0            # the largest may be read twice
    bad = np.flatnonzero(np.concatenate([step[:peak] <= 0, fall]))
    return peak, (int(bad[0]) + 1 if bad.size else None)


BRANCHES = ("mean", "load", "unload")
"""The mean of loading and unloading first; then each branch alone."""


@dataclass(frozen=True)
class LoadCycle(Record):
    """One run: the set variable in the order applied and what each response read.

    Attributes
    ----------
    x : ndarray, shape (n,)
        The variable set in steps (a load, a lift), rising to its largest, then falling (the
        largest may be read twice, at the end of the loading and the start of the unloading).
    y : ndarray, shape (g, n)
        The responses read at each step, one per row.
    peak : int
        Index of the (first) largest ``x``: points 0…peak load, peak…n − 1 unload.
    """

    x: np.ndarray
    y: np.ndarray
    peak: int

    def branch(self, name: str, *, settled: bool = False) -> tuple[np.ndarray, np.ndarray]:
        """``(x, y)`` of the ``"load"`` or ``"unload"`` branch (both hold the peak; with
        ``settled``, without their turning point: the loading branch from its second
        reading, the unloading one after the peak), or of the ``"mean"`` branch:
        y = (y_load + y_unload)/2 at the steps read on both (the peak, if read once, is its
        own mean).

        Examples
        --------
        >>> c = LoadCycle(np.array([0., 1, 2, 1, 0]), np.array([[0., 1, 3, 2, 1]]), 2)
        >>> [a.tolist() for a in c.branch("mean")]
        [[0.0, 1.0, 2.0], [[0.5, 1.5, 3.0]]]
        >>> c.branch("unload", settled=True)[0].tolist()
        [1.0, 0.0]
        >>> LoadCycle(np.array([0., 1, 2, 2, 1, 0]), np.zeros((1, 6)), 2).branch(
        ...     "unload", settled=True)[0].tolist()
        [1.0, 0.0]
        """
        top = self.peak + int(self.x.size > self.peak + 1
                              and self.x[self.peak + 1] == self.x[self.peak])
        up, down = slice(int(settled), self.peak + 1), slice(top + 1 if settled else self.peak,
                                                             None)
        if name == "load":
            return self.x[up], self.y[:, up]
        if name == "unload":
            return self.x[down], self.y[:, down]
        if name != "mean":
            raise ValueError(f"branch: {name!r} is not one of {', '.join(BRANCHES)}")
        k_up, k_down = [], []
        for k, v in enumerate(self.x[:self.peak + 1]):
            hit = np.flatnonzero(np.isclose(self.x[self.peak:], v, rtol=1e-9, atol=0.0))
            if hit.size:
                k_up.append(k)
                k_down.append(self.peak + int(hit[-1]))
        return self.x[k_up], 0.5 * (self.y[:, k_up] + self.y[:, k_down])


@dataclass(frozen=True)
class BranchLine(Record):
    """A response's straight line on one branch, pooled over the runs; on the mean branch
    also the test of the pointwise mean's curvature (with four or more different steps).

    Attributes
    ----------
    fit : LineFit
    curvature : CurvatureTest or None
    resolution : tuple of float
        Standard uncertainties of the slope and the intercept that the readings'
        resolution alone gives (independent rounding errors, ``reading_u`` each).
    """

    fit: LineFit
    curvature: CurvatureTest | None = None
    resolution: tuple[float, float] = (0.0, 0.0)

    def measured_slope(self) -> Measured:
        """The slope as a measured input: type A from the residuals, topped up by type B to
        what the readings' resolution alone gives where the residuals show less (readings
        rounded to a division can fall exactly on a line and show no scatter at all)."""
        return self.fit.measured_slope(u_b=_top_up(self.resolution[0], self.fit.u_slope))

    def measured_intercept(self) -> Measured:
        """The intercept as a measured input, as :meth:`measured_slope`."""
        return self.fit.measured_intercept(u_b=_top_up(self.resolution[1],
                                                       self.fit.u_intercept))


def _top_up(floor: float, u: float) -> float:
    """The type B that brings a type A ``u`` up to ``floor`` (0 where it is above)."""
    return math.sqrt(max(floor * floor - u * u, 0.0))


def _reading_u(x: np.ndarray, reading_u: float) -> tuple[float, float]:
    """u of a fitted line's slope and intercept from independent reading errors of u each:
    u/√Sxx and u √(1/n + x̄²/Sxx)."""
    sxx = float(((x - x.mean()) ** 2).sum())
    return reading_u / math.sqrt(sxx), reading_u * math.sqrt(1 / x.size + x.mean() ** 2 / sxx)


def fit_branches(cycles: Sequence[LoadCycle],
                 reading_u=0.0) -> dict[tuple[int, str], BranchLine]:
    """The line y = a + s x of each response on each branch, pooled over the runs.

    The loading and unloading lines leave out their turning points; the mean line is the
    line midway between them (:func:`midway`), its intercept the response's elastic zero.

    Parameters
    ----------
    cycles : sequence of LoadCycle
        The runs (the same responses in each).
    reading_u : float or sequence of float
        Standard uncertainty of one reading from its resolution (a division d read to the
        nearest: d/√12), per response or for all. [unit of y]

    Returns
    -------
    dict
        (response row, branch) → :class:`BranchLine`; rows count from 0.

    Raises
    ------
    ValueError
        A branch with fewer than three different steps beyond its turning point: a line
        through two points has no scatter to state its uncertainty by.

    Examples
    --------
    Coulomb friction 10 on a spring of stiffness 100 preloaded to 100: the loading branch
    runs 10 below the elastic line, the unloading 10 above, the turning points off both.

    >>> x = np.array([0., 1, 2, 3, 4, 3, 2, 1, 0])
    >>> y = 100 + 100 * x + np.array([0, -10, -10, -10, -10, 10, 10, 10, 10])
    >>> f = fit_branches([LoadCycle(x, y[None, :], 4)])[0, "mean"].fit
    >>> round(f.slope, 9), round(f.intercept, 9)
    (100.0, 100.0)
    """
    lines = {}
    pooled = {b: _pooled(cycles, b) for b in BRANCHES}
    for b in ("load", "unload"):
        if np.unique(pooled[b][0]).size < 3:
            raise ValueError(f"fit_branches: the {b}ing branch has {np.unique(pooled[b][0]).size} "
                             "different step(s) beyond its turning point; a line with its "
                             "scatter needs three")
    rows = cycles[0].y.shape[0]
    reading = np.broadcast_to(np.asarray(reading_u, dtype=float), (rows,))
    for j in range(rows):
        for b in ("load", "unload"):
            x, y = pooled[b]
            lines[j, b] = BranchLine(fit_line(x, y[j]), resolution=_reading_u(x, reading[j]))
        x, y = pooled["mean"]
        ends = [lines[j, b].resolution for b in ("load", "unload")]
        lines[j, "mean"] = BranchLine(
            midway(lines[j, "load"].fit, lines[j, "unload"].fit),
            curvature_test(x, y[j]) if np.unique(x).size > 3 else None,
            tuple(0.5 * math.hypot(a, b) for a, b in zip(*ends)))
    return lines


def _pooled(cycles: Sequence[LoadCycle], branch: str):
    """A branch of every run (the settled one for loading and unloading), pooled."""
    parts = [c.branch(branch, settled=branch != "mean") for c in cycles]
    return np.concatenate([x for x, _ in parts]), np.concatenate([y for _, y in parts], axis=1)


def midway(a: LineFit, b: LineFit) -> LineFit:
    r"""The line midway between two independent lines (loading and unloading).

    .. math:: s = \frac{s_a + s_b}{2}, \quad c = \frac{c_a + c_b}{2}, \quad
              u^2(s) = \frac{u^2(s_a) + u^2(s_b)}{4}

    and likewise for the intercept and the covariance; the degrees of freedom of the slope's
    u by Welch–Satterthwaite over the two lines, the residual s pooled.

    Examples
    --------
    >>> f = midway(fit_line([0, 1, 2], [0, 1.1, 1.9]), fit_line([0, 1, 2], [1, 2.1, 2.9]))
    >>> round(f.slope, 6), round(f.intercept, 6), f.dof
    (0.95, 0.55, 2)
    """
    half = [0.5 * a.u_slope, 0.5 * b.u_slope]
    u = math.hypot(*half)
    dof = u**4 / sum(h**4 / f.dof for h, f in zip(half, (a, b)) if f.dof > 0) \
        if u > 0 else a.dof + b.dof
    pooled = math.sqrt((a.residual_sd**2 * a.dof + b.residual_sd**2 * b.dof)
                       / max(a.dof + b.dof, 1))
    return LineFit(0.5 * (a.slope + b.slope), 0.5 * (a.intercept + b.intercept), u,
                   0.5 * math.hypot(a.u_intercept, b.u_intercept), 0.25 * (a.cov + b.cov),
                   pooled, max(int(dof), 1), a.n + b.n)


@dataclass(frozen=True)
class Hysteresis(Record):
    """The loop of one run: its area and the work of the loading branch.

    Attributes
    ----------
    area : float
        Between loading and unloading, in the force–displacement plane. [J]
    work : float
        Work of the loading branch above its starting force, ∫(F − F₀) dx. [J]
    """

    area: float
    work: float

    @property
    def share(self) -> float:
        """The loop's share of the loading work (NaN where no work was done)."""
        return self.area / self.work if self.work > 0 else math.nan


def hysteresis(force, displacement, peak: int) -> Hysteresis:
    r"""The loop of one run, points in the order read (loading, then unloading).

    Parameters
    ----------
    force, displacement : array_like
        Along the run. [N], [m]
    peak : int
        Index of the turning point.

    Returns
    -------
    Hysteresis

    Notes
    -----
    .. math:: A = \oint F\,dx \ (\text{the polygon's area}), \qquad
              W = \int_{load} (F - F_0)\,dx, \qquad \text{share} = A / W

    Examples
    --------
    Unloading one unit of x beside the loading line, closed back to the start at no load: a
    loop of 150 against the loading work 200·2/2.

    >>> h = hysteresis([0, 100, 200, 100, 0], [0, 1.0, 2.0, 2.0, 1.0], 2)
    >>> float(h.area), float(h.work), round(h.share, 3)
    (150.0, 200.0, 0.75)
    """
    F, x = np.asarray(force, dtype=float), np.asarray(displacement, dtype=float)
    up = slice(0, peak + 1)
    return Hysteresis(float(loop_area(x, F)), float(branch_work(x[up], F[up] - F[0])))
