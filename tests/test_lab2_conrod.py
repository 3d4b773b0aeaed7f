"""Lab 2: the two-mass model, weighing, swinging and its failure at the Kater point."""
import numpy as np
import pytest

from labs import lab2_conrod as lab
from processing.synth.pendulum import measured, physical_pendulum_period, stopwatch

G = 9.8156


def ideal_period(k2, l, g=G):
    """Small-swing period about a pivot l from the centre of mass: T² g/4π² = (k² + l²)/l."""
    return 2 * np.pi * np.sqrt((k2 + l * l) / (g * l))


def test_two_mass_model_keeps_mass_and_centre():
    m, l_shp, l_shk = 1.0, np.array([0.11, 0.12]), np.array([0.05, 0.04])
    m_shp, m_shk = lab.two_mass(m, l_shp, l_shk)
    np.testing.assert_allclose(m_shp + m_shk, m, err_msg="condition (1)")
    np.testing.assert_allclose(m_shp * l_shp, m_shk * l_shk, err_msg="condition (3)")


def test_weighing_gives_the_balance_reading_as_small_end_mass():
    # From (6), (8): m_shp = m l_shk / l_sh = R_A exactly.
    l_shp, l_shk = lab.weighing(0.266, 1.013, 0.1601)
    assert lab.two_mass(1.013, l_shp, l_shk)[0] == pytest.approx(0.266, rel=1e-14)


def test_swinging_formula_inverts_the_pendulum_exactly():
    l_C, l_D = np.array([0.129, 0.1, 0.08]), np.array([0.07, 0.06, 0.08])
    k2 = 0.5 * l_C * l_D
    got = lab.swinging(ideal_period(k2, l_C), ideal_period(k2, l_D), l_C + l_D, G)
    np.testing.assert_allclose(got, (l_C, l_D), rtol=1e-12)


@pytest.mark.parametrize("q", [0.2, 0.5, 0.8, 0.95])
def test_condition_number_closed_form(q):
    l_C, l_D = 0.12, 0.07
    k2 = q * l_C * l_D
    kappa = lab.condition_number(ideal_period(k2, l_C), ideal_period(k2, l_D), l_C + l_D, G)
    assert kappa == pytest.approx(2 / (1 - q) - 4 * l_C * l_D / (l_C + l_D) ** 2, rel=1e-9)


def _rod_data(rng, q=None, J_ratio=0.9, amplitude_deg=7.0, noise=True):
    """A ~1 kg rod measured by weighing and swinging. ``q`` = k²/(l_C l_D) if given."""
    m, l_shp, l_shk, d_C, d_D = 1.013, 0.118, 0.042, 0.022, 0.056
    l_C, l_D = l_shp + d_C / 2, l_shk + d_D / 2
    k2 = q * l_C * l_D if q is not None else J_ratio * l_shp * l_shk
    amp = np.radians(amplitude_deg)
    T_C = physical_pendulum_period(m * (k2 + l_C**2), m, l_C, amp, G)
    T_D = physical_pendulum_period(m * (k2 + l_D**2), m, l_D, amp, G)
    clock = (lambda T: list(stopwatch(T, 20, 3, rng))) if noise else (lambda T: [20 * T] * 3)
    err = (lambda v, a: measured(v, a, rng)) if noise else (lambda v, a: v)
    data = {
        "rod": {"m_sh": err(m, 0.001), "l_sh": err(1e3 * (l_shp + l_shk), 0.1), "g": G},
        "weighing": {"R_A": err(1e3 * m * l_shk / (l_shp + l_shk), 1.0)},
        "swinging": {"l_CD": err(1e3 * (l_C + l_D), 0.5), "d_C": err(1e3 * d_C, 0.05),
                     "d_D": err(1e3 * d_D, 0.05), "n_osc": 20, "t_C": clock(T_C),
                     "t_D": clock(T_D), "amplitude": amplitude_deg},
    }
    return data, {"l_shp": l_shp, "m_shp": m * l_shk / (l_shp + l_shk), "J": m * k2,
                  "dJ": m * k2 - m * l_shp * l_shk}


def test_noiseless_rod_recovers_everything(make_inputs):
    data, true = _rod_data(np.random.default_rng(0), noise=False)
    res = lab.reduce(make_inputs(lab.SPEC, data)[0], n_samples=2000)
    for method in ("weighing", "swinging"):
        assert res[f"l_shp_{method}"].value == pytest.approx(true["l_shp"], abs=1e-7), method
        assert res[f"m_shp_{method}"].value == pytest.approx(true["m_shp"], abs=1e-7), method
    assert res["J_cm_swinging"].value == pytest.approx(true["J"], rel=1e-6)
    assert res["dJ_third_condition"].value == pytest.approx(true["dJ"], rel=1e-5)
    assert res["m_shp_statistics"].value == pytest.approx(0.25 * 1.013)
    assert not [w for w in res.warnings if w.code != "single_reading"]


def test_swinging_uncertainty_covers_truth(make_inputs):
    trials, hits = 40, {"l_shp_swinging": 0, "m_shp_swinging": 0, "m_shp_weighing": 0}
    for seed in range(trials):
        data, true = _rod_data(np.random.default_rng(500 + seed))
        res = lab.reduce(make_inputs(lab.SPEC, data)[0], n_samples=4000, seed=seed)
        for name in hits:
            lo, hi = res[name].estimate.interval95
            hits[name] += lo <= true[name.rsplit("_", 1)[0]] <= hi
    for name, h in hits.items():
        assert h / trials >= 0.85, f"{name}: 95 % interval held the truth in {h}/{trials}"


@pytest.mark.parametrize("q, fires", [(0.3, False), (0.5, False), (0.7, False),
                                      (0.95, True), (0.99, True)])
def test_kater_warning_fires_near_the_singular_point_only(make_inputs, q, fires):
    data, _ = _rod_data(np.random.default_rng(11), q=q)
    res = lab.reduce(make_inputs(lab.SPEC, data)[0], n_samples=4000)
    codes = [w.code for w in res.warnings]
    assert ("ill_conditioned" in codes) == fires, f"q = {q}: {codes}"
    if fires:
        assert any(f.name == "l_C_mc" for f in res.figures), "the Monte Carlo histogram is shown"
        assert "Kater" in next(w.message for w in res.warnings if w.code == "ill_conditioned")


def test_symmetric_rod_equal_periods_is_not_kater(make_inputs):
    # l_C = l_D and k² < l_C l_D: T_C = T_D, yet formula (10) is finite (l_C = l_CD/2)
    l = 0.09
    T = ideal_period(0.5 * l * l, l)
    data = {"rod": {"m_sh": 1.0, "l_sh": 140.0, "g": G},
            "swinging": {"l_CD": 180.0, "d_C": 40.0, "d_D": 40.0, "n_osc": 20,
                         "t_C": [20 * T] * 3, "t_D": [20 * T] * 3}}
    res = lab.reduce(make_inputs(lab.SPEC, data)[0], n_samples=2000)
    assert res["l_C_swinging"].value == pytest.approx(0.09, rel=1e-9)
    assert "ill_conditioned" not in [w.code for w in res.warnings]


def test_diesel_statistics_and_single_reading_warning(make_inputs):
    data = {"rod": {"m_sh": 2.0, "l_sh": 200.0, "engine": "diesel"},
            "swinging": {"l_CD": 250.0, "d_C": 30.0, "d_D": 70.0, "n_osc": 20,
                         "t_C": 18.0, "t_D": 16.5}}
    inputs, notices = make_inputs(lab.SPEC, data)
    assert "single_reading" in [n.code for n in notices], "a stopwatch read once is flagged"
    res = lab.reduce(inputs, n_samples=2000)
    assert res["m_shp_statistics"].value == pytest.approx(0.6)
    # the statistical share's spread dominates: u ≈ m · 0.05/√3 (plus 1 g of weighing)
    assert res["m_shp_statistics"].u == pytest.approx(2.0 * 0.05 / np.sqrt(3), rel=1e-4)
