"""A static load–unload cycle (processing.oscillations.load_cycle) in closed form: a linear chain
with Coulomb friction (the play operator of processing.synth.valve_table) read exactly, its
branches, the line midway between them, the manual's pointwise mean and the loop."""
import math

import numpy as np
import pytest

from processing.oscillations.load_cycle import LoadCycle, fit_branches, hysteresis, midway
from processing.regression import fit_line
from processing.synth.valve_table import load_steps, play

C = 2.0e6
"""Stiffness of the chain [N/m]."""


def chain(friction: float, top: float = 1000.0, step: float = 100.0) -> LoadCycle:
    P = load_steps(top, step)
    return LoadCycle(P, (play(P, friction) / C)[None, :], int(np.argmax(P)))


@pytest.mark.parametrize("friction", [0.0, 8.0, 30.0, 50.0])
def test_midway_line_is_the_elastic_line_whatever_the_friction(friction):
    """Each branch runs F/c to one side of the elastic line except at its turning point (for
    load steps of at least 2F); the lines without the turning points are exact, and the line
    midway between them is P/c."""
    lines = fit_branches([chain(friction)])
    mean, load, unload = (lines[0, b].fit for b in ("mean", "load", "unload"))
    assert mean.slope * C == pytest.approx(1.0, rel=1e-12)
    assert mean.intercept * C == pytest.approx(0.0, abs=1e-9)
    assert load.intercept * C == pytest.approx(-friction, abs=1e-9)
    assert unload.intercept * C == pytest.approx(friction, abs=1e-9)
    assert mean.u_slope == pytest.approx(0.0, abs=1e-20)


@pytest.mark.parametrize("friction", [8.0, 30.0, 50.0])
def test_the_manuals_pointwise_mean_is_tilted_by_its_turning_points(friction):
    """The mean table keeps the start (F/2 high: loading from rest, unloading back to +F) and
    the top (F low, read once on the loading line): over 0…1000 N in ten steps its line's
    slope is low by Σ(x − x̄)e/Sxx = (−500·F/2 − 500·F)/1.1·10⁶ = 0.68 F/P_max (the module's
    "about 0.7 F/P_max")."""
    cycle = chain(friction)
    P, dl = cycle.branch("mean")
    assert fit_line(P, dl[0]).slope * C - 1 == pytest.approx(-750 * friction / 1.1e6, rel=1e-9)


@pytest.mark.parametrize("friction", [8.0, 20.0, 50.0])
def test_the_loop_of_coulomb_friction_by_hand(friction):
    """The polygon: a parallelogram 2F/c wide from 100 to 900 N (1600 F/c), the top triangle
    (100 F/c) and the bottom trapezoid from rest (150 F/c); the loading work by trapezoids
    (500000 − 50 F)/c. Their ratio is ≈ 4F/P_max, the rule behind HYSTERESIS_SHARE."""
    cycle = chain(friction)
    h = hysteresis(cycle.x, cycle.y[0], cycle.peak)
    assert h.area == pytest.approx(1850 * friction / C, rel=1e-9)
    assert h.work == pytest.approx((500000 - 50 * friction) / C, rel=1e-9)
    assert h.share == pytest.approx(4 * friction / 1000, rel=0.08)


def test_branches_and_the_mean_of_a_table_read_twice_at_the_top():
    x = np.array([0.0, 1, 2, 3, 3, 2, 1, 0])
    y = np.array([[0.0, 1, 2, 3, 5, 4, 3, 2]])
    c = LoadCycle(x, y, 3)
    assert c.branch("unload", settled=True)[0].tolist() == [2.0, 1.0, 0.0]
    assert c.branch("load", settled=True)[0].tolist() == [1.0, 2.0, 3.0]
    x_mean, y_mean = c.branch("mean")
    assert x_mean.tolist() == [0.0, 1.0, 2.0, 3.0]
    assert y_mean[0].tolist() == [1.0, 2.0, 3.0, 4.0]   # the top: its two readings' mean


def test_midway_adds_the_two_lines_uncertainties_in_quadrature():
    a = fit_line([0, 1, 2, 3], [0.0, 1.1, 1.9, 3.2])
    b = fit_line([3, 2, 1, 0], [3.5, 2.4, 1.2, 0.4])
    m = midway(a, b)
    assert m.slope == pytest.approx((a.slope + b.slope) / 2)
    assert m.u_slope == pytest.approx(math.hypot(a.u_slope, b.u_slope) / 2)
    assert m.u_intercept == pytest.approx(math.hypot(a.u_intercept, b.u_intercept) / 2)
    assert m.cov == pytest.approx((a.cov + b.cov) / 4)
    assert m.n == 8 and 2 <= m.dof <= 4


def test_readings_on_a_line_state_the_resolution_not_zero():
    """Whole divisions that fall exactly on a line show no scatter: the slope's u is then
    the resolution's, d/√12 per reading through each branch, halved in quadrature."""
    d, P = 1e-5, load_steps(1000, 100)
    cycle = LoadCycle(P, (np.round(P / 1e7 / d) * d)[None, :], 10)   # a division a step
    line = fit_branches([cycle], d / math.sqrt(12))[0, "mean"]
    assert line.fit.u_slope < 1e-12 * line.fit.slope
    sxx = 825000.0                                  # 100…1000 N, and 900…0 N: Σ(x − x̄)²
    assert line.measured_slope().u == pytest.approx(
        d / math.sqrt(12) / math.sqrt(sxx) / math.sqrt(2), rel=1e-9)


def test_scatter_larger_than_the_resolution_is_not_topped_up():
    rng = np.random.default_rng(0)
    P = load_steps(1000, 100)
    cycle = LoadCycle(P, (P / C + 2e-5 * rng.standard_normal(P.size))[None, :], 10)
    line = fit_branches([cycle], 1e-5 / math.sqrt(12))[0, "mean"]
    assert line.measured_slope().u == pytest.approx(line.fit.u_slope, rel=1e-12)


def test_a_branch_of_two_steps_is_refused():
    with pytest.raises(ValueError, match="2 different step.*needs three"):
        fit_branches([chain(0.0, top=200.0)])
