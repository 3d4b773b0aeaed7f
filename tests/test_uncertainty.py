"""The one uncertainty mechanism: GUM linear propagation checked by Monte Carlo."""
import math

import numpy as np
import pytest

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
    assert e.k == pytest.approx(4.53, abs=0.005), "GUM Table G.2: t for 95.45 % with 2 dof"
    assert e.U == pytest.approx(e.k * e.u)


def test_type_b_alone_keeps_k_2():
    e = propagate(lambda a: {"y": 3 * a}, {"a": Measured(1.0, limit=0.01)})["y"]
    assert e.k == 2.0 and e.U == pytest.approx(2 * e.u)


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


def test_outputs_estimated_together_as_one_by_one():
    # result_values asks for all outputs at once: each estimate is the one a single output
    # gets, its budget (u, ν, contributions) and Monte Carlo interval alike
    inputs = {"x": Measured.from_readings([1.0, 1.1, 0.95]), "y": Measured(2.0, limit=0.2),
              "z": Measured(3.0, u_b=0.1), "k": 4.0}

    def model(x, y, z, k):
        return {"a": x * y, "b": y / z + k, "c": x * 0 + 5.0, "d": z ** 2}

    for n_samples in (0, 500):
        together = propagate(model, inputs, n_samples=n_samples).estimates(["a", "b", "c", "d"])
        alone = propagate(model, inputs, n_samples=n_samples)
        for name, e in together.items():
            assert e == alone[name]
        assert set(together["a"].contributions) == {"x", "y"}
        assert together["c"].u == 0.0 and together["c"].contributions == {}


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


def test_stated_interval_of_three_stopwatch_readings_covers_the_truth():
    """A trifilar-like result J = C·T² from three stopwatch readings of 20 swings (scatter
    0.15 s, the stopwatch's ± 0.01 s limit) and a mass and length known to type B limits: the
    interval the report states, value ± U, must cover the true J in ≥ 90 % of 300 synthetic
    runs (GUM G.4: k = t(ν_eff)); the normal law's k = 2 covers it in about 80 %."""
    rng = np.random.default_rng(29)
    true_t, true_m, true_l = 30.0, 5.0, 0.8

    def model(t, m, l):
        return {"J": m * (t / 20) ** 2 / l}

    truth = model(true_t, true_m, true_l)["J"]
    hits = hits_k2 = 0
    runs = 300
    for _ in range(runs):
        readings = true_t + rng.normal(0.0, 0.15, 3) + rng.uniform(-0.01, 0.01, 3)
        m = true_m + rng.uniform(-0.001, 0.001)
        l = true_l + rng.uniform(-0.0005, 0.0005)
        e = propagate(model, {"t": Measured.from_readings(readings, limit=0.01),
                              "m": Measured(m, limit=0.001), "l": Measured(l, limit=0.0005)},
                      n_samples=0)["J"]
        hits += abs(e.value - truth) <= e.U
        hits_k2 += abs(e.value - truth) <= 2 * e.u
    assert hits / runs >= 0.90, f"stated U covers the truth in {hits / runs:.1%} of runs"
    assert hits_k2 / runs < 0.88, f"k = 2 covers it in {hits_k2 / runs:.1%}: the test has no teeth"
