"""Straight-line fits of a measured table, with the type A uncertainty of their coefficients.

Calibrations and stiffness tables (a force against a dial-gauge reading, a trace deflection
against a micrometer's angle) are reduced by least squares over the whole table rather than
from one pair of readings. :func:`fit_line` returns the slope and intercept with their
standard uncertainties from the scatter of the residuals (ν = n − 2 degrees of freedom), as
:class:`~processing.uncertainty.Measured` quantities ready for :func:`~processing.uncertainty.
propagate`; :func:`curvature_test` says whether a table bends significantly (a quadratic term
tested against the straight line).

References
----------
.. [1] JCGM 100:2008 (GUM), annex H.3: calibration of a thermometer by a straight-line fit.
.. [2] N. R. Draper, H. Smith, Applied Regression Analysis, 3rd ed., Wiley, 1998, ch. 1 and 6.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import stats

from .diagnostics import Reason
from .result import Record
from .uncertainty import Measured


@dataclass(frozen=True)
class LineFit(Record):
    """A least-squares straight line y = intercept + slope·x.

    Attributes
    ----------
    slope, intercept : float
        The coefficients. [unit of y / unit of x], [unit of y]
    u_slope, u_intercept : float
        Their standard uncertainties from the residual scatter (0 through two points).
    cov : float
        Covariance of slope and intercept.
    residual_sd : float
        Standard deviation of the residuals, s = √(Σr²/(n − p)).
    dof : int
        Degrees of freedom n − p (p = 2, or 1 through the origin).
    n : int
        Points fitted.
    through_origin : bool
        Whether the intercept was held at 0.
    """

    slope: float
    intercept: float
    u_slope: float
    u_intercept: float
    cov: float
    residual_sd: float
    dof: int
    n: int
    through_origin: bool = False

    def predict(self, x):
        """The line at ``x``."""
        return self.intercept + self.slope * np.asarray(x, dtype=float)

    def measured_slope(self, *, u_b: float = 0.0) -> Measured:
        """The slope as a measured input: type A from the residuals (ν = n − p) and an
        optional type B standard uncertainty ``u_b`` (e.g. an instrument's scale error)."""
        return Measured(self.slope, self.u_slope, self.dof if self.dof > 0 else math.inf,
                        u_b=u_b)

    def measured_intercept(self, *, u_b: float = 0.0) -> Measured:
        """The intercept as a measured input, as :meth:`measured_slope`."""
        return Measured(self.intercept, self.u_intercept, self.dof if self.dof > 0 else math.inf,
                        u_b=u_b)


def fit_line(x, y, *, through_origin: bool = False) -> LineFit:
    r"""Least-squares straight line through measured points.

    Parameters
    ----------
    x, y : array_like
        The table, same length (NaN rows are dropped). [any units]
    through_origin : bool
        Hold the intercept at 0 (a secant stiffness y = c·x).

    Returns
    -------
    LineFit

    Raises
    ------
    ValueError
        Fewer than two usable points (one through the origin), or all x equal.

    Notes
    -----
    .. math:: b = \frac{\sum (x_i - \bar x)(y_i - \bar y)}{\sum (x_i - \bar x)^2}, \quad
              u^2(b) = \frac{s^2}{\sum (x_i - \bar x)^2}, \quad
              s^2 = \frac{\sum r_i^2}{n - 2}

    Through the origin: :math:`b = \sum x y / \sum x^2`, :math:`u^2(b) = s^2/\sum x^2`,
    ν = n − 1 (Draper & Smith, §1.2 and §1.4).

    Examples
    --------
    >>> f = fit_line([0, 1, 2, 3], [1.0, 3.1, 4.9, 7.0])
    >>> round(f.slope, 3), round(f.intercept, 3), f.dof
    (1.98, 1.03, 2)
    >>> round(fit_line([1, 2], [2.0, 4.0], through_origin=True).slope, 12)
    2.0
    """
    x, y = np.asarray(x, dtype=float).ravel(), np.asarray(y, dtype=float).ravel()
    if x.shape != y.shape:
        raise ValueError(f"fit_line: x and y differ in length ({x.size} and {y.size})")
    keep = np.isfinite(x) & np.isfinite(y)
    x, y = x[keep], y[keep]
    p = 1 if through_origin else 2
    if x.size < p:
        raise ValueError(f"fit_line: {x.size} usable point(s), at least {p} needed")
    if through_origin:
        sxx = float(x @ x)
        if sxx == 0.0:
            raise ValueError("fit_line: every x is 0")
        b, a = float(x @ y) / sxx, 0.0
    else:
        xm, ym = x.mean(), y.mean()
        sxx = float(((x - xm) ** 2).sum())
        if sxx == 0.0:
            raise ValueError("fit_line: every x is the same; a slope needs two different x")
        b = float(((x - xm) * (y - ym)).sum()) / sxx
        a = float(ym - b * xm)
    r = y - (a + b * x)
    dof = x.size - p
    s = math.sqrt(float(r @ r) / dof) if dof > 0 else 0.0
    u_b = s / math.sqrt(sxx)
    if through_origin:
        return LineFit(b, 0.0, u_b, 0.0, 0.0, s, dof, x.size, True)
    u_a = s * math.sqrt(1.0 / x.size + xm**2 / sxx)
    return LineFit(b, a, u_b, u_a, -xm * u_b**2, s, dof, x.size, False)


CALIBRATION_WORDS_RU = {"load": ("нагрузка", "нагрузкой"),
                        "twist": ("угол закрутки", "углом закрутки"),
                        "deflection": ("прогибы", "прогиб", "прогиба"),
                        "reading": ("показания", "показание", "показания")}
"""The words of :func:`calibration_fault`'s names in Russian: a set value's nominative and
instrumental, a reading's plural, singular and genitive."""


def calibration_fault(applied, reading, *, names: tuple[str, str] = ("load", "reading"),
                      resolution: float = 0.0) -> Reason | None:
    """What keeps a calibration table from giving a scale, in words (None if nothing does).

    A calibration sets known values (loads, twists) and reads the instrument at each; a
    scale is the slope of the line through them. It fails when the readings never change
    (a dead channel, or readings copied down), and it is misread when they turn back: a
    reading that moves against the others' direction by more than its own limit of error
    twice over (the two readings each off by their limit) was written beside the wrong
    value. The set values' own count is the caller's to check.

    Parameters
    ----------
    applied, reading : array_like
        The values set and the instrument's reading at each, one length. [any units]
    names : (str, str)
        What they are called in the message: keys of :data:`CALIBRATION_WORDS_RU`.
    resolution : float
        The readings' limit of error (0: none stated). [unit of ``reading``]

    Returns
    -------
    Reason or None
        The fault in English (``str``) and in Russian (``.ru``).

    Examples
    --------
    >>> calibration_fault([0, 300, 600, 900], [0.0, 18.1, 36.0, 54.2]) is None
    True
    >>> fault = calibration_fault([0, 300, 600, 900], [5, 5, 5, 5], names=("load", "deflection"))
    >>> str(fault), fault.ru
    ('the deflections never change: every one of the 4 is 5', 'прогибы не меняются: все 4 равны 5')
    >>> fault = calibration_fault([0, 300, 600, 900], [0, 18, 36, 10],
    ...                           names=("load", "deflection"), resolution=0.2)
    >>> str(fault)
    'deflection 4 (10) turns back past deflection 3 (36), although its load is larger: the others rise with the load'
    >>> fault.ru
    'прогиб 4 (10) меньше прогиба 3 (36), хотя нагрузка у него больше: остальные растут с нагрузкой'
    """
    x, y = np.asarray(applied, dtype=float).ravel(), np.asarray(reading, dtype=float).ravel()
    what, read = names
    (what_ru, what_ins), (reads_ru, read_ru, read_gen) = (CALIBRATION_WORDS_RU[what],
                                                          CALIBRATION_WORDS_RU[read])
    if np.ptp(y) <= 2 * resolution:
        if np.ptp(y) == 0:
            return Reason(f"the {read}s never change: every one of the {y.size} is {y[0]:g}",
                          f"{reads_ru} не меняются: все {y.size} равны {y[0]:g}")
        return Reason(f"the {read}s never change by more than their limit of error twice "
                      f"over: they span {np.ptp(y):g} ({2 * resolution:g} allowed)",
                      f"{reads_ru} меняются не больше удвоенного предела погрешности: их "
                      f"размах {np.ptp(y):g} (допустимо {2 * resolution:g})")
    order = np.argsort(x, kind="stable")
    direction = math.copysign(1.0, fit_line(x, y).slope) if np.ptp(x) > 0 else 1.0
    ahead = order[0]
    for k in order[1:]:
        if x[k] > x[ahead] and direction * (y[k] - y[ahead]) < -2 * resolution:
            trend, trend_ru, side = (("rise", "растут", "меньше") if direction > 0 else
                                     ("fall", "убывают", "больше"))
            return Reason(f"{read} {k + 1} ({y[k]:g}) turns back past {read} {ahead + 1} "
                          f"({y[ahead]:g}), although its {what} is larger: the others "
                          f"{trend} with the {what}",
                          f"{read_ru} {k + 1} ({y[k]:g}) {side} {read_gen} {ahead + 1} "
                          f"({y[ahead]:g}), хотя {what_ru} у него больше: остальные "
                          f"{trend_ru} с {what_ins}")
        if direction * (y[k] - y[ahead]) > 0:
            ahead = k
    return None


@dataclass(frozen=True)
class CurvatureTest(Record):
    """Whether a table bends: a quadratic term c₂ tested against the straight line.

    Attributes
    ----------
    c2 : float
        Quadratic coefficient of y = c₀ + c₁x + c₂x². [unit of y / unit of x²]
    u_c2 : float
        Its standard uncertainty.
    p_value : float
        Two-sided p-value of t = c₂/u(c₂) with n − 3 degrees of freedom (1 when n ≤ 3).
    relative_bend : float
        The quadratic term's largest share of the straight line's rise over the table,
        |c₂|·(x_max − x_min)²/4 / |c₁ (x_max − x_min)|: how large the bend is, not only
        whether it is significant.
    """

    c2: float
    u_c2: float
    p_value: float
    relative_bend: float

    def significant(self, level: float = 0.01) -> bool:
        """True when the bend is significant at ``level``."""
        return self.p_value < level


def curvature_test(x, y) -> CurvatureTest:
    """Fit y = c₀ + c₁x + c₂x² and test c₂ = 0 (Student t, ν = n − 3).

    Parameters
    ----------
    x, y : array_like
        The table (NaN rows dropped); needs three distinct x.

    Returns
    -------
    CurvatureTest

    Examples
    --------
    >>> x = np.arange(10.0)
    >>> curvature_test(x, 2 * x + 0.01 * np.sin(7 * x)).significant()
    False
    >>> curvature_test(x, 2 * x + 0.05 * x**2 + 0.01 * np.sin(7 * x)).significant()
    True
    """
    x, y = np.asarray(x, dtype=float).ravel(), np.asarray(y, dtype=float).ravel()
    keep = np.isfinite(x) & np.isfinite(y)
    x, y = x[keep], y[keep]
    if np.unique(x).size < 3:
        raise ValueError("curvature_test: three different x are needed")
    span = float(x.max() - x.min())
    t = (x - x.mean()) / span  # conditioned basis
    A = np.column_stack([np.ones_like(t), t, t * t])
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    dof = x.size - 3
    r = y - A @ coef
    s2 = float(r @ r) / dof if dof > 0 else 0.0
    u = math.sqrt(s2 * float(np.linalg.inv(A.T @ A)[2, 2]))
    c2, u_c2 = coef[2] / span**2, u / span**2
    if dof > 0 and u > 0:
        p = float(2 * stats.t.sf(abs(coef[2]) / u, dof))
    else:
        p = 1.0 if dof <= 0 else float(coef[2] == 0)
    rise = abs(coef[1])
    bend = abs(coef[2]) / 4 / rise if rise > 0 else math.inf
    return CurvatureTest(float(c2), float(u_c2), p, float(bend))
