"""Lab 1: formulas against closed forms; synthetic rigs reduced back to their true J."""
import warnings

import numpy as np
import pytest

from labs import lab1_inertia as lab
from processing.diagnostics import AmplitudeTooLargeWarning, collect_notices
from processing.synth.pendulum import (measured, physical_pendulum_period, stopwatch,
                                       trifilar_period)

G = 9.8156


# ------------------------------------------------------------------ closed forms

def test_hollow_cylinder_is_solid_minus_core():
    rho, R, r, h = 7800.0, 0.15, 0.05, 0.04
    m_out, m_in = rho * np.pi * R**2 * h, rho * np.pi * r**2 * h
    for axis in ("axial", "transverse"):
        hollow = lab.cylinder(m_out - m_in, R, r, h, axis=axis)
        diff = lab.cylinder(m_out, R, 0, h, axis=axis) - lab.cylinder(m_in, r, 0, h, axis=axis)
        assert hollow == pytest.approx(diff, rel=1e-12), axis


def test_long_thin_cylinder_transverse_tends_to_thin_rod():
    m, l = 2.0, 1.0
    assert lab.cylinder(m, 1e-6, 0, l, axis="transverse") == pytest.approx(
        lab.thin_rod(m, l, axis="centre"), rel=1e-9)
    # about the end: Steiner from the centre
    assert lab.thin_rod(m, l) == pytest.approx(lab.parallel_axis(m * l**2 / 12, m, l / 2))


def test_torus_perpendicular_axis_theorem():
    # plane figure limit: J_z = J_x + J_y = 2 J_x for a thin ring (r → 0): J_z = m R², J_x = m R²/2
    m, R = 3.0, 0.2
    assert lab.torus(m, R, 1e-9) == pytest.approx(2 * lab.torus(m, R, 1e-9, axis="transverse"))


def test_wire_polar_moment_uses_fourth_power():
    # c = G π d⁴/(32 l): doubling d multiplies the stiffness by 16 (the OCR's d² would give 4)
    c1, c2 = lab.wire_stiffness(79e9, 0.002, 1.0), lab.wire_stiffness(79e9, 0.004, 1.0)
    assert c2 / c1 == pytest.approx(16.0)
    assert c1 == pytest.approx(79e9 * np.pi * 0.002**4 / 32)


def test_unifilar_reference_removes_clamp():
    c, J_clamp, J_ref, J = 0.6, 0.002, 0.04, 0.17
    T = lambda j: 2 * np.pi * np.sqrt((j + J_clamp) / c)
    assert lab.unifilar_reference(T(J), T(J_ref), J_ref, T(0.0)) == pytest.approx(J, rel=1e-12)
    assert lab.unifilar_wire(T(J), c, T(0.0)) == pytest.approx(J, rel=1e-12)


# ------------------------------------------------------------------ synthetic rigs

def test_trifilar_exact_geometry_recovers_J_where_the_manuals_l_does_not():
    # R1 ≠ R2: the threads slant; formula (17) with l is off by (R1 − R2)²/(2 l²) ≈ 0.125 %
    J, m, R1, R2, l = 0.2, 14.0, 0.10, 0.14, 0.80
    T = trifilar_period(J, m, R1, R2, l, np.radians(0.5), G)
    factor = lab.trifilar_period_factor(np.radians(0.5), m, J, R1, R2, l)
    assert lab.trifilar(T / factor, m, R1, R2, l, G) == pytest.approx(J, rel=1e-8)
    manual = T**2 * m * G * R1 * R2 / (4 * np.pi**2 * l)
    assert manual / J - 1 == pytest.approx(-(R1 - R2) ** 2 / (2 * l**2), rel=0.01)


@pytest.mark.parametrize("deg", [5.0, 10.0, 20.0])
def test_trifilar_amplitude_factor_matches_integrated_rig(deg):
    J, m, R1, R2, l = 0.2, 14.0, 0.10, 0.14, 0.80
    T = trifilar_period(J, m, R1, R2, l, np.radians(deg), G)
    factor = lab.trifilar_period_factor(np.radians(deg), m, J, R1, R2, l)
    assert lab.trifilar(T / factor, m, R1, R2, l, G) == pytest.approx(J, rel=1e-7)


def _rig(rng, J=0.1712, m=11.8, amplitude_deg=7.0):
    """A flywheel timed on the trifilar and as a pendulum, as a student would measure it."""
    R1, R2, l, m_p = 0.100, 0.140, 0.800, 2.105
    J_p = 0.5 * m_p * 0.16**2
    amp = np.radians(amplitude_deg)
    c = 0.035
    T_tot = trifilar_period(J + J_p, m + m_p, R1, R2, l, amp, G)
    T_p = trifilar_period(J_p, m_p, R1, R2, l, amp, G)
    T_pe = physical_pendulum_period(J + m * c**2, m, c, amp, G)
    mm = lambda v: measured(1e3 * v, 0.5, rng)
    return {
        "body": {"m": measured(m, 0.001, rng), "g": G},
        "trifilar": {"R1": mm(R1), "R2": mm(R2), "l": mm(l), "n_osc": 20,
                     "t": list(stopwatch(T_tot, 20, 3, rng)), "m_p": measured(m_p, 0.001, rng),
                     "t_p": list(stopwatch(T_p, 20, 3, rng)),
                     "amplitude": measured(amplitude_deg, 1.0, rng)},
        "pendulum": {"c": mm(c), "n_osc": 20, "t": list(stopwatch(T_pe, 20, 3, rng)),
                     "amplitude": measured(amplitude_deg, 1.0, rng)},
    }


def test_uncertainty_covers_truth_in_seeded_trials(make_inputs):
    # The stated 95 % interval must hold the true J in a large majority of experiments.
    J_true, trials = 0.1712, 40
    hits = {"J_trifilar": 0, "J_pendulum_cm": 0}
    for seed in range(trials):
        rng = np.random.default_rng(100 + seed)
        inputs, _ = make_inputs(lab.SPEC, _rig(rng, amplitude_deg=rng.uniform(4, 9)))
        res = lab.reduce(inputs, n_samples=4000, seed=seed)
        for name in hits:
            lo, hi = res[name].estimate.interval95
            hits[name] += lo <= J_true <= hi
    for name, h in hits.items():
        assert h / trials >= 0.85, f"{name}: 95 % interval held the truth in {h}/{trials}"


def test_large_amplitude_is_corrected_and_warned(make_inputs):
    rng = np.random.default_rng(5)
    data = _rig(rng, amplitude_deg=20.0)
    data["trifilar"]["amplitude"] = data["pendulum"]["amplitude"] = 20.0
    for sec in ("trifilar", "pendulum"):
        data[sec]["t"] = [float(np.mean(data[sec]["t"]))] * 3   # no timing noise: see the bias
    data["trifilar"]["t_p"] = [float(np.mean(data["trifilar"]["t_p"]))] * 3
    inputs, _ = make_inputs(lab.SPEC, data)
    res = lab.reduce(inputs, n_samples=2000)
    assert "amplitude_too_large" in [w.code for w in res.warnings]
    corrected = res["J_pendulum_cm"].value
    del data["pendulum"]["amplitude"]
    res0 = lab.reduce(make_inputs(lab.SPEC, data)[0], n_samples=2000)
    bias = res0["J_pendulum_pivot"].value / res["J_pendulum_pivot"].value - 1
    # uncorrected J is (T/T0)² − 1 ≈ 1.54 % high at 20°
    assert bias == pytest.approx(pendulum_bias(20.0), rel=1e-6)
    assert abs(corrected / 0.1712 - 1) < 0.02


def pendulum_bias(deg):
    from processing.oscillations.oscillation import pendulum_period_factor

    return float(pendulum_period_factor(np.radians(deg))) ** 2 - 1


def test_small_amplitude_does_not_warn():
    from processing.oscillations.oscillation import check_amplitude

    with warnings.catch_warnings():
        warnings.simplefilter("error", AmplitudeTooLargeWarning)
        check_amplitude(np.radians(8.0), "trifilar")
    with collect_notices() as notices:
        check_amplitude(np.radians(12.0), "trifilar")
    assert [n.code for n in notices] == ["amplitude_too_large"]


def test_amplitude_warning_names_the_method_in_russian():
    from processing.oscillations.oscillation import check_amplitude

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_amplitude(np.radians(12.0), lab.SPEC.section("pendulum").label)
    (w,) = caught
    assert str(w.message).startswith(lab.SPEC.section("pendulum").label["en"])
    assert w.message.ru.startswith(lab.SPEC.section("pendulum").label["ru"])


def test_analytic_flywheel_from_parts(make_inputs):
    # rim 150/120 × 40 and web 120/35 × 15, ρ = 7200, minus 6 holes Ø10 at 50 mm
    data = {"body": {"m": 11.8}, "analytic": [
        {"shape": "cylinder", "R": 150.0, "r": 120.0, "h": 40.0, "rho": 7200.0},
        {"shape": "cylinder", "R": 120.0, "r": 35.0, "h": 15.0, "rho": 7200.0},
        {"shape": "cylinder", "R": 5.0, "h": 15.0, "offset": 50.0, "count": 6, "hole": True,
         "rho": 7200.0}]}
    res = lab.reduce(make_inputs(lab.SPEC, data)[0], n_samples=2000)
    rho = 7200.0
    rim = rho * np.pi * (0.15**2 - 0.12**2) * 0.04
    web = rho * np.pi * (0.12**2 - 0.035**2) * 0.015
    hole = rho * np.pi * 0.005**2 * 0.015
    J = 0.5 * rim * (0.15**2 + 0.12**2) + 0.5 * web * (0.12**2 + 0.035**2) \
        - 6 * (0.5 * hole * 0.005**2 + hole * 0.05**2)
    assert res["J_analytic"].value == pytest.approx(J, rel=1e-12)
    assert res["m_analytic"].value == pytest.approx(rim + web - 6 * hole, rel=1e-12)
    assert 0.005 < res["J_analytic"].estimate.relative_U < 0.05, "ρ ± 100 and ± 0.5 mm"


def test_pendulum_far_from_centre_of_mass_warns(make_inputs):
    # c much larger than the radius of gyration: J_c is a small difference of large numbers
    J, m, c = 0.01, 5.0, 0.3
    T = 2 * np.pi * np.sqrt((J + m * c**2) / (m * G * c))
    data = {"body": {"m": 5.0, "g": G}, "pendulum": {"c": 300.0, "n_osc": 20,
                                                      "t": [20 * T] * 3}}
    res = lab.reduce(make_inputs(lab.SPEC, data)[0], n_samples=2000)
    assert "ill_conditioned" in [w.code for w in res.warnings]
