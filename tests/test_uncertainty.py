"""The one uncertainty mechanism: GUM linear propagation checked by Monte Carlo."""
import math

import numpy as np
import pytest
from scipy import stats

from processing.uncertainty import Measured, propagate


def test_product_adds_relative_uncertainties_in_quadrature():
    # y = a b: (u_y/y)² = (u_a/a)² + (u_b/b)²  (GUM 5.1.6)
    p = propagate(lambda a, b: {"y": a * b},
                  {"a": Measured(2.0, u_b=0.02), "b": Measured(5.0, u_b=0.1)})
    e = p["y"]
    assert e.value == pytest.approx(10.0)
    assert e.u == pytest.approx(10.0 * math.hypot(0.01, 0.02), rel=1e-6)
    assert e.u_mc == pytest.approx(e.u, rel=0.03), "Monte Carlo agrees for a near-linear model"
    assert not e.nonlinear


def test_readings_give_type_a_with_student_dof():
    x = [10.1, 10.3, 10.2]
    m = Measured.from_readings(x, limit=0.0)
    assert m.value == pytest.approx(10.2)
    assert m.u == pytest.approx(np.std(x, ddof=1) / math.sqrt(3))
    assert m.dof == 2
    e = propagate(lambda t: {"y": t}, {"t": m})["y"]
    assert e.k95 == pytest.approx(stats.t.ppf(0.975, 2)), "k for 95 % from t with 2 dof (4.30)"


def test_rectangular_limit_gives_a_over_sqrt3():
    m = Measured(0.8, limit=0.0005)
    assert m.u == pytest.approx(0.0005 / math.sqrt(3))
    assert math.isinf(m.dof)


def test_difference_of_correlated_outputs_cancels_shared_input():
    # a and b share x: the difference x·2 − x·2 has no uncertainty at all
    p = propagate(lambda x, y: {"a": 2 * x + y, "b": 2 * x}, {"x": Measured(1.0, u_b=0.5),
                                                                 "y": Measured(0.0, u_b=0.01)})
    d = p.difference("a", "b")
    assert d.u == pytest.approx(0.01, rel=1e-6), "only y's uncertainty survives in a − b"
    assert p["a"].u > 0.9


def test_strongly_nonlinear_model_is_flagged_and_linear_is_not():
    p = propagate(lambda x: {"inv": 1.0 / x, "lin": 3.0 * x},
                  {"x": Measured(1.0, u_b=0.3)})
    assert p["inv"].nonlinear, "1/x over ± 30 % is far from its tangent"
    assert not p["lin"].nonlinear


def test_constants_pass_through_and_outputs_without_uncertainty():
    p = propagate(lambda x, n: {"y": x / n}, {"x": Measured(4.0), "n": 2})
    assert p["y"].value == 2.0 and p["y"].u == 0.0 and not p["y"].nonlinear


def test_monte_carlo_interval_covers_truth_for_three_repeats():
    # Three readings of a normal quantity: the t-based 95 % interval must cover the true mean
    # in about 95 % of experiments (GUM S1 6.4.9). 400 trials: binomial sd ≈ 1.1 %.
    rng = np.random.default_rng(7)
    hits = 0
    trials = 400
    for i in range(trials):
        x = rng.normal(5.0, 0.1, 3)
        lo, hi = propagate(lambda t: {"y": t}, {"t": Measured.from_readings(x)},
                           n_samples=4000, seed=i)["y"].interval95
        hits += lo <= 5.0 <= hi
    assert 0.91 <= hits / trials <= 0.99, f"coverage {hits / trials:.3f}"
