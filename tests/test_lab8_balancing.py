"""Lab 8: the manual's D-120 case by hand, the ω-independence of the mechanism, the general
phasor analysis against the manual's formulas, a balancing round trip, the verdict warnings.

The D-120 data are the lab manual's (lab 8, "Исходные данные для расчета"); n, l₁, l₄ are not
in the manual and are the sample file's assumptions (sample_data/lab8/README.md).
"""
import json
from pathlib import Path

import numpy as np
import pytest

from labs import lab8_balancing as lab
from processing.crank import balance as bal
from processing.measurement import load, template
from processing.reporting.content import fmt_pm
from processing.reporting.render import to_json

ROOT = Path(__file__).resolve().parents[1]
D120 = ROOT / "sample_data" / "lab8" / "d120.toml"
INLINE4 = ROOT / "sample_data" / "lab8" / "inline4.toml"

ENGINE = {"r": "60 mm", "lambda": 0.279, "n": 2000, "D": "105 mm", "m_engine": "295 kg"}
MASSES = {"m_piston": "2.006 kg", "m_shp": "0.8 kg", "m_shk": "1.784 kg", "m_pin": "0.875 kg",
          "m_web1": "1.044 kg", "m_web2": "0.697 kg"}
CRANKSHAFT = {"a": "140 mm", "l2": "72 mm", "l3": "210 mm"}
BALANCER = {"m_pr": "1.7 kg", "l1": "400 mm", "l4": "300 mm"}


def d120(**changes):
    data = {"engine": dict(ENGINE), "masses": dict(MASSES), "crankshaft": dict(CRANKSHAFT),
            "balancer": dict(BALANCER)}
    for key, value in changes.items():
        section, _, field = key.partition("__")
        if value is None:
            data[section].pop(field) if field else data.pop(section)
        else:
            data[section][field] = value
    return data


def run(make_inputs, data, **kw):
    inputs, _ = make_inputs(lab.SPEC, data)
    return lab.reduce(inputs, n_samples=kw.pop("n_samples", 2000), **kw)


# Hand arithmetic, D-120 at n = 2000 min⁻¹ (manual's data; l₁ = 0.4 m, l₄ = 0.3 m assumed):
#   ω = π·2000/30 = 209.43951 rad/s, ω² = 43864.908 s⁻², r ω² = 0.06·43864.908 = 2631.8945 m/s²
#   m_j = m_п + m_шп = 2.006 + 0.8 = 2.806 kg
#   M_r/(rω²) = (0.875 + 1.784)·0.140 + 1.044·0.210 + 0.697·0.072
#             = 0.37226 + 0.21924 + 0.050184 = 0.641684 kg·m    → M_r = 1688.845 N·m
#   M_j1 max  = 2.806·0.140·2631.8945 = 0.39284·2631.8945     = 1033.913 N·m
#   ΣP_j2 max = 2·0.279·2.806·2631.8945 = 1.565748·2631.8945  = 4120.884 N
#   ξ = 0.25·ΣP_j2max/(m ω² D) = 0.5·0.279·2.806·0.06/(295·0.105) = 0.02348622/30.975 = 0.00075823
#   M_pr/(rω²) = 1.7·(0.210 + 0.072) = 0.4794 kg·m            → M_pr = 1261.730 N·m
#   ΔM_r/(rω²) = 0.641684 − 0.4794 = 0.162284 kg·m            → ΔM_r = 427.114 N·m
#   D_r  = ΔM_r/(l₁ω²) = 0.162284·0.06/0.4 = 0.0243426 kg·m
#   D_j1 = 0.5·2.806·0.06·0.14/0.4 = 0.0117852/0.4 = 0.029463 kg·m
#   D    = 0.0243426 + 0.029463 = 0.0538056 kg·m
#   D₂   = 0.0117852/0.3 = 0.039284 kg·m
#   m_x  = ΔM_r/(rω²a) = 0.162284/0.14 = 1.1591714 kg
HAND = {"M_r": 0.641684 * 0.06 * (np.pi * 2000 / 30) ** 2, "M_j1_max": 1033.913,
        "P_j2_max": 4120.884, "xi_stechkin": 0.02348622 / 30.975, "M_pr": 1261.730,
        "dM_r": 427.114, "D_r": 0.0243426, "D_j1": 0.029463, "D": 0.0538056, "D_2": 0.039284,
        "m_x": 1.1591714}
# what the report prints with the lab's default uncertainties (masses ± 1 g, lengths ± 0.5 mm)
PRINTED = {"M_r": "1688.8", "M_j1_max": "1033.9", "P_j2_max": "4120.9", "xi_stechkin": "0.00075823",
           "M_pr": "1261.7", "dM_r": "427.1", "D_r": "0.02434", "D_j1": "0.02946", "D": "0.05381",
           "D_2": "0.03928", "m_x": "1.1592"}


def test_d120_matches_the_hand_arithmetic(make_inputs):
    res = run(make_inputs, d120())
    for name, value in HAND.items():
        # the hand values carry 7 significant digits: rtol 1e-6
        assert res[name].value == pytest.approx(value, rel=1e-6), name
        r = res[name]
        shown = fmt_pm(r.shown(r.value), r.shown(r.value + r.estimate.U) - r.shown(r.value))[0]
        assert shown == PRINTED[name], f"{name}: the report prints {shown}"
    assert res["omega"].value == pytest.approx(209.43951, rel=1e-8)
    assert not res.warnings, [w.message for w in res.warnings]
    assert any("satisfactory" in c["en"] for c in res.conclusion)


def test_d120_sample_file_is_the_manual_case():
    res = lab.reduce(load(D120, lab.SPEC), n_samples=2000)
    for name, value in HAND.items():
        assert res[name].value == pytest.approx(value, rel=1e-6), name
    json.loads(to_json(res))  # exact zeros (F_r, F_j1, M_j2) must not break the JSON


def test_uncertainty_of_the_second_order_force(make_inputs):
    # ΣP_j2 = 2λ r ω² (m_п + m_шп); only the two masses are uncertain, each ± 1 g rectangular
    res = run(make_inputs, d120())
    u = 2 * 0.279 * 0.06 * (np.pi * 2000 / 30) ** 2 * np.sqrt(2) * 0.001 / np.sqrt(3)
    assert res["P_j2_max"].u == pytest.approx(u, rel=1e-6)


def test_static_moments_and_xi_do_not_depend_on_speed(make_inputs):
    slow = run(make_inputs, d120(engine__n=1800))
    fast = run(make_inputs, d120(engine__n=2000))
    for name in ("D_r", "D_j1", "D", "D_2", "m_x", "xi_stechkin"):
        assert slow[name].value == pytest.approx(fast[name].value, rel=1e-12), name
        assert slow[name].u == pytest.approx(fast[name].u, rel=1e-6), name
    for name in ("M_r", "M_j1_max", "P_j2_max", "M_pr", "dM_r"):
        assert fast[name].value / slow[name].value == pytest.approx((2000 / 1800) ** 2, rel=1e-12)


def test_general_analysis_reproduces_the_manual(make_inputs):
    res = run(make_inputs, d120())
    assert res["M_r_free"].value == pytest.approx(res["dM_r"].value, rel=1e-12), \
        "phasors of pins, webs and counterweights = M_r − M_pr"
    assert res["M_j1_free"].value == pytest.approx(res["M_j1_max"].value, rel=1e-12)
    assert res["F_j2"].value == pytest.approx(res["P_j2_max"].value, rel=1e-12)
    assert res["F_r"].value == res["F_j1"].value == res["M_j2_free"].value == 0
    # without counterweights the phasors give the manual's M_r itself
    bare = run(make_inputs, d120(balancer=None))
    assert bare["M_r_free"].value == pytest.approx(bare["M_r"].value, rel=1e-12)
    assert "D" not in bare and "m_x" not in bare


def test_lugs_and_balance_shaft_cancel_the_moments():
    """Round trip: put the computed lugs on the pulley and the flywheel and the computed weights
    on the counter-rotating shaft; the moments they leave must vanish at every crank angle."""
    r, w, lam, a, l2, l3, l1, l4 = 0.06, 180.0, 0.279, 0.14, 0.072, 0.21, 0.4, 0.3
    m_j, m_crank, m_web1, m_web2, m_pr = 2.806, 0.875 + 1.784, 1.044, 0.697, 1.7
    M_r = lab.centrifugal_moment(0.875, 1.784, m_web1, m_web2, a, l2, l3, r, w)
    dM_r = M_r - lab.counterweight_moment(m_pr, r, w, l2, l3)
    D_r, D_j1, D, D_2 = lab.lug_static_moments(dM_r, m_j, r, a, w, l1, l4)
    layout = lab.two_cylinder_layout(a, l2, l3, m_j, m_crank, m_web1, m_web2, m_pr)

    def with_lugs(static_moment):
        # pulley (x = −l₁/2) lug opposite crank 1, flywheel (x = +l₁/2) lug in line with it;
        # masses reduced to the crank radius: static moment / r
        angles, positions, masses = layout["shaft_masses"]
        extra = dict(layout, shaft_masses=(np.append(angles, [np.pi, 0.0]),
                                           np.append(positions, [-l1 / 2, l1 / 2]),
                                           np.append(masses, [static_moment / r] * 2)))
        return extra

    only_r = bal.inline_balance(**with_lugs(D_r), crank_radius=r, angular_speed=w, lambda_=lam)
    assert only_r.rotating.moment <= 1e-12 * M_r, "D_r lugs cancel ΔM_r"
    full = bal.inline_balance(**with_lugs(D), crank_radius=r, angular_speed=w, lambda_=lam)
    M_j1 = lab.first_order_moment_max(m_j, r, w, a)
    assert full.rotating.moment == pytest.approx(0.5 * M_j1, rel=1e-12), "D_j1 takes half"
    assert D_2 * w**2 * l4 == pytest.approx(0.5 * M_j1, rel=1e-12), "D₂ takes the other half"
    alpha = np.radians(np.arange(0.0, 360.0, 1.0))
    h = bal.inline_history(alpha, **with_lugs(D), crank_radius=r, angular_speed=w, lambda_=lam)
    # the balance shaft's weights turn at −α, placed so that at α = 0 they oppose M_j1
    shaft_along, shaft_across = -D_2 * w**2 * l4 * np.cos(alpha), D_2 * w**2 * l4 * np.sin(alpha)
    np.testing.assert_allclose(h.rotating_moment_along + h.first_order_moment + shaft_along, 0,
                               atol=1e-9 * M_j1, err_msg="moment in the plane of the cylinders")
    np.testing.assert_allclose(h.rotating_moment_across + shaft_across, 0, atol=1e-9 * M_j1,
                               err_msg="moment across the cylinders")


def test_manual_formula_matches_webs_in_their_planes():
    # M_r of the manual = phasor sum with pins at ±a/2, webs 1, 4 at ±l₃/2 and 2, 3 at ±l₂/2
    layout = lab.two_cylinder_layout(0.14, 0.072, 0.21, 2.806, 2.659, 1.044, 0.697)
    b = bal.inline_balance(**layout, crank_radius=0.06, angular_speed=100.0, lambda_=0.279)
    assert b.rotating.moment == pytest.approx(
        lab.centrifugal_moment(0.875, 1.784, 1.044, 0.697, 0.14, 0.072, 0.21, 0.06, 100.0), rel=1e-14)
    assert b.rotating.moment_phase == 0, "the couple turns with crank 1, as the manual draws it"


def test_verdict_warning_fires_for_a_light_engine_only(make_inputs):
    # ξ ∝ 1/m: 295 kg → 0.00076; 80 kg → 0.0028 ≥ 0.002
    good = run(make_inputs, d120())
    assert "imbalance" not in [w.code for w in good.warnings]
    bad = run(make_inputs, d120(engine__m_engine="80 kg"))
    assert bad["xi_stechkin"].value == pytest.approx(0.02348622 / (80 * 0.105), rel=1e-6)
    notes = [w for w in bad.warnings if w.code == "imbalance"]
    assert len(notes) == 1 and "Stechkin" in notes[0].message and "Стечкина" in notes[0].ru
    assert any("UNSATISFACTORY" in c["en"] for c in bad.conclusion)


def test_parallel_twin_warns_about_free_first_order_force(make_inputs):
    # cranks together (360° twin): the first-order and centrifugal forces add, ξ does not see them
    data = {"engine": dict(ENGINE), "masses": dict(MASSES),
            "cylinder": [{"theta": 0, "x": 0}, {"theta": 0, "x": 140}]}
    res = run(make_inputs, data)
    w = 209.43951 ** 2
    assert res["F_j1"].value == pytest.approx(2 * 2.806 * 0.06 * w, rel=1e-6)
    assert res["F_r"].value == pytest.approx(2 * (0.875 + 1.784 + 1.044 + 0.697) * 0.06 * w, rel=1e-6)
    assert res["M_j1_free"].value == 0
    notes = [n for n in res.warnings if n.code == "imbalance"]
    assert len(notes) == 1 and "F_j1" in notes[0].message and "F_r" in notes[0].message
    assert res["xi_stechkin"].value < bal.STECHKIN_KLIMOV_LIMIT, "ξ alone would pass it"


def test_inline4_sample(make_inputs):
    res = lab.reduce(load(INLINE4, lab.SPEC), n_samples=2000)
    w2 = (np.pi * 2000 / 30) ** 2
    assert res["F_j2"].value == pytest.approx(4 * 0.279 * 2.806 * 0.06 * w2, rel=1e-12)
    for name in ("F_r", "F_j1", "M_r_free", "M_j1_free", "M_j2_free"):
        assert res[name].value == 0, name
    assert res["xi_stechkin"].value == pytest.approx(0.279 * 2.806 * 0.06 / (400 * 0.105), rel=1e-12)
    assert "M_r" not in res and not res.warnings


def test_per_cylinder_masses_leave_a_small_residual(make_inputs):
    # pistons weighed one by one, 3 g apart: an inline-4 keeps a tiny first-order force
    cyl = [{"theta": t, "x": x, "m_j": m, "m_r": "4.4 kg"}
           for t, x, m in ((0, 0, "2.806 kg"), (180, 140, "2.809 kg"), (180, 280, "2.806 kg"),
                           (0, 420, "2.806 kg"))]
    res = run(make_inputs, {"engine": dict(ENGINE), "cylinder": cyl})
    assert res["F_j1"].value == pytest.approx(0.003 * 0.06 * (np.pi * 2000 / 30) ** 2, rel=1e-9)
    assert "imbalance" not in [w.code for w in res.warnings], "below 1 % of one cylinder's"


@pytest.mark.parametrize("data, field, match", [
    (dict(d120(), cylinder=[{"theta": 0, "x": 0}]), "cylinder", "both"),
    ({"engine": dict(ENGINE), "masses": dict(MASSES)}, "crankshaft", "layout is missing"),
    (d120(crankshaft__l2="250 mm"), "crankshaft.l2", "not smaller than"),
    (d120(masses=None), "masses", "section \\[masses\\] is missing"),
    (d120(engine__lambda=1.5), "engine.lambda", "λ = 1.5"),
    ({"engine": dict(ENGINE), "cylinder": [{"theta": 0, "x": 0}]}, "cylinder[0].m_j", "no m_j"),
    ({"engine": dict(ENGINE), "masses": dict(MASSES), "balancer": dict(BALANCER),
      "cylinder": [{"theta": 0, "x": 0}]}, "balancer", "belongs to"),
])
def test_bad_files_say_what_to_fix(make_inputs, data, field, match):
    inputs, _ = make_inputs(lab.SPEC, data)
    with pytest.raises(ValueError, match=match) as err:
        lab.reduce(inputs, n_samples=100)
    assert err.value.field == field


def test_odd_geometry_warns(make_inputs):
    res = run(make_inputs, d120(balancer__l1="200 mm"))
    assert [w.code for w in res.warnings] == ["inconsistent_input"]
    assert "l1" in res.warnings[0].message


def test_speed_units_all_mean_revolutions_per_minute(make_inputs):
    # "2000 rpm", "2000 min^-1", "2000 1/min" and a plain 2000 are one speed: ω = 209.44 rad/s
    for n in ("2000 rpm", "2000 min^-1", "2000 1/min", 2000):
        res = run(make_inputs, d120(engine__n=n))
        assert res["omega"].value == pytest.approx(np.pi * 2000 / 30), n
        assert not res.warnings, (n, [w.code for w in res.warnings])


def test_implausible_speed_is_queried(make_inputs):
    res = run(make_inputs, d120(engine__n=20000))
    assert [w.code for w in res.warnings] == ["inconsistent_input"]


def test_template_and_report_pieces(make_inputs):
    text = template(lab.SPEC, "ru")
    assert "[[cylinder]]" in text and "m_щ1" in text
    res = run(make_inputs, d120())
    table = res.tables[0]
    rows = {row["name"]: row for row in table.rows}
    assert rows["M_j1_free"]["phase"] == "0.0" and rows["F_j1"]["phase"] == "—"
    assert rows["F_j2"]["amplitude"]["ru"].endswith("Н")
    from matplotlib.figure import Figure

    fig = Figure()
    res.figures[0].draw(fig, "ru")
    labels = [l.get_label() for l in fig.axes[1].get_lines()]
    assert "ΔM_r = M_r − M_пр" in labels and "M_r" in labels
