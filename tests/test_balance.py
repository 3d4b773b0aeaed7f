"""In-line engine balance: the textbook identities of the classic layouts, time histories
against the phasor amplitudes, the series against the kinematics module, input checks.

Sources of the identities: the lab manual, lab 8 (the 180° twin); Lukanin (ed.), vol. 2 and
Taylor, vol. 2 (inline-3, -4, -6 and the single cylinder). They are exact algebra, so the
tolerance is round-off (1e-12 of one cylinder's force or moment).
"""
import numpy as np
import pytest
from numpy.testing import assert_allclose

from processing.crank import balance as bal
from processing.crank import kinematics as kin
from processing.diagnostics import InputError

M_J, M_R, R, W, LAM, A = 2.806, 4.4, 0.06, 209.4395, 0.279, 0.14
F1 = M_J * R * W**2          # one cylinder's first-order force amplitude, N
FR = M_R * R * W**2          # one crank's centrifugal force, N
ALPHA = np.radians(np.arange(0.0, 360.0, 0.25))


def layout(degrees, spacing=A):
    theta = np.radians(degrees)
    return theta, spacing * np.arange(len(degrees))


def balance(degrees, **kw):
    theta, x = layout(degrees)
    return bal.inline_balance(theta, x, M_J, M_R, R, W, LAM, **kw)


def history(degrees, **kw):
    theta, x = layout(degrees)
    return bal.inline_history(ALPHA, theta, x, M_J, M_R, R, W, LAM, **kw)


def test_twin_180_first_order_forces_cancel_second_add():
    b = balance([0, 180])
    assert b.first.force == 0 and b.rotating.force == 0, "ΣP_j1 = 0, ΣK_r = 0"
    assert b.second.force == pytest.approx(2 * LAM * F1, rel=1e-14), "ΣP_j2 max = 2λ m_j r ω²"
    assert b.first.moment == pytest.approx(F1 * A, rel=1e-14), "M_j1 max = m_j r ω² a"
    assert b.rotating.moment == pytest.approx(FR * A, rel=1e-14)
    assert b.second.moment == 0, "M_j2 = 0"
    # the manual's signs: M_j1 = m_j r ω² a cos α (phase 0), ΣP_j2 = 2λ m_j r ω² cos 2α
    assert b.first.moment_phase == 0 and b.second.force_phase == 0
    assert np.isnan(b.first.force_phase), "a zero force has no phase"


def test_inline4_flat_crank():
    b = balance([0, 180, 180, 0])
    for name in ("rotating", "first"):
        o = getattr(b, name)
        assert o.force == 0 and o.moment == 0, name
    assert b.second.force == pytest.approx(4 * LAM * F1, rel=1e-14), "4λ m_j r ω²"
    assert b.second.moment == 0


def test_inline6_is_fully_balanced():
    b = balance([0, 120, 240, 240, 120, 0])
    for o in b:
        assert abs(o.force) <= 1e-12 * F1 and abs(o.moment) <= 1e-12 * F1 * A, o.kind


def test_inline3_free_moments_are_sqrt3():
    # cranks 120° apart: every force cancels, the moments are √3 times one cylinder's × a
    b = balance([0, 120, 240])
    for o in b:
        assert o.force == 0, o.kind
    assert b.rotating.moment == pytest.approx(np.sqrt(3) * FR * A, rel=1e-13)
    assert b.first.moment == pytest.approx(np.sqrt(3) * F1 * A, rel=1e-13)
    assert b.second.moment == pytest.approx(np.sqrt(3) * LAM * F1 * A, rel=1e-13)


def test_single_cylinder():
    b = bal.inline_balance([0.0], [0.0], M_J, M_R, R, W, LAM)
    assert b.first.force == pytest.approx(F1, rel=1e-15), "F_j1 = m_j r ω²"
    assert b.second.force == pytest.approx(LAM * F1, rel=1e-15), "F_j2 = λ m_j r ω²"
    assert b.rotating.force == pytest.approx(FR, rel=1e-15), "K_r = m_r r ω²"
    assert b.about == 0 and all(o.moment == 0 for o in b), "no lever about its own axis"
    # about another point the moment is the force times the distance
    off = bal.inline_balance([0.0], [0.0], M_J, M_R, R, W, LAM, about=0.1)
    assert off.first.moment == pytest.approx(0.1 * F1, rel=1e-14)


@pytest.mark.parametrize("degrees", [[0, 180], [0, 180, 180, 0], [0, 120, 240], [0, 90, 270, 180],
                                     [0.0, 37.0, 250.0, 111.0, 300.0], [0, 0]])
def test_history_peaks_equal_amplitudes(degrees):
    # uneven masses and spacings too: the phasors must hold for any layout
    rng = np.random.default_rng(len(degrees))
    theta = np.radians(degrees)
    x = np.cumsum(rng.uniform(0.08, 0.15, len(degrees)))
    m_j = M_J * rng.uniform(0.9, 1.1, len(degrees))
    m_r = M_R * rng.uniform(0.9, 1.1, len(degrees))
    b = bal.inline_balance(theta, x, m_j, m_r, R, W, LAM)
    h = bal.inline_history(ALPHA, theta, x, m_j, m_r, R, W, LAM)
    step = ALPHA[1] - ALPHA[0]
    for order, force, moment in ((b.first, h.first_order_force, h.first_order_moment),
                                 (b.second, h.second_order_force, h.second_order_moment)):
        # a cosine sampled every Δ misses its peak by at most 1 - cos(kΔ/2) ≈ (kΔ)²/8
        rel = (order.order * step) ** 2 / 8 + 1e-12
        assert_allclose(force.max(), order.force, rtol=rel, atol=1e-9 * F1, err_msg=order.kind)
        assert_allclose(moment.max(), order.moment, rtol=rel, atol=1e-9 * F1,
                        err_msg=order.kind + " moment")
        # and at the stated peak angle it is exact
        if order.force > 0:
            peak = bal.inline_history([float(order.force_peak_angle)], theta, x, m_j, m_r, R, W, LAM)
            value = peak.first_order_force if order.kind == "first" else peak.second_order_force
            assert_allclose(value, order.force, rtol=1e-12, err_msg=order.kind + " at the peak")
    # the centrifugal resultant is a vector of constant length turning with the shaft
    assert_allclose(np.hypot(h.rotating_force_along, h.rotating_force_across), b.rotating.force,
                    rtol=1e-12, atol=1e-9 * FR)
    assert_allclose(np.hypot(h.rotating_moment_along, h.rotating_moment_across), b.rotating.moment,
                    rtol=1e-12, atol=1e-9 * FR * A)


def test_series_orders_are_the_approximate_kinematics():
    theta, x = layout([0, 90, 270, 180])
    h = bal.inline_history(ALPHA, theta, x, M_J, 0.0, R, W, LAM)
    j = kin.piston_acceleration(theta[:, None] + ALPHA, R, W, LAM, method="approx")
    assert_allclose(h.first_order_force + h.second_order_force, M_J * j.sum(axis=0),
                    atol=1e-10 * F1, err_msg="m_j rω²(cos α + λ cos 2α) summed")
    # the exact total differs from the series by the higher orders, O(λ³): |Δj| < λ³ rω² per cylinder
    assert np.max(np.abs(h.reciprocating_force - h.first_order_force - h.second_order_force)) \
        < 4 * LAM**3 * F1
    assert h.reciprocating_force[0] == pytest.approx(
        M_J * kin.piston_acceleration(theta, R, W, LAM).sum(), rel=1e-12)


def test_shaft_masses_in_their_own_planes():
    # one crank, webs at ±c about its plane: no extra force, no extra moment about the crank
    c = 0.03
    b = bal.inline_balance([0.0], [0.0], 0.0, 1.0, R, W, LAM,
                           shaft_masses=([0.0, 0.0], [-c, c], [0.5, 0.5]))
    assert b.rotating.force == pytest.approx(2.0 * R * W**2) and b.rotating.moment == 0
    # a counterweight opposite the crank in an offset plane leaves a couple
    b = bal.inline_balance([0.0], [0.0], 0.0, 1.0, R, W, LAM,
                           shaft_masses=([np.pi], [c], [1.0]))
    assert b.rotating.force == 0
    assert b.rotating.moment == pytest.approx(c * R * W**2, rel=1e-12)


def test_monte_carlo_draws_broadcast_like_a_loop():
    rng = np.random.default_rng(3)
    theta, x = layout([0, 180, 180, 0])
    m_j = M_J + 0.001 * rng.standard_normal((50, 4))        # each piston weighed
    r = R + 1e-5 * rng.standard_normal(50)
    b = bal.inline_balance(theta, x, m_j, M_R, r, W, LAM)
    for i in (0, 17, 49):
        one = bal.inline_balance(theta, x, m_j[i], M_R, r[i], W, LAM)
        assert b.first.force[i] == pytest.approx(one.first.force, rel=1e-12)
        assert b.second.moment[i] == pytest.approx(one.second.moment, rel=1e-12)
    assert np.all(b.first.force > 0), "unequal pistons leave a small first-order force"
    h = bal.inline_history(ALPHA[:10], theta, x, m_j[:, None, :], M_R, r[:, None], W, LAM)
    assert h.first_order_force.shape == (50, 1, 10)
    # a common mass drawn N times goes in as shape (N, 1)
    common = bal.inline_balance(theta, x, np.full((7, 1), M_J), M_R, R, W, LAM)
    assert common.second.force.shape == (7,)


def test_to_dict_and_peak_angles():
    b = balance([0, 90])
    d = b.to_dict()
    assert set(d) == {"rotating", "first", "second", "about"}
    assert d["first"]["force"] == b.first.force and d["second"]["order"] == 2
    # F_j1 = F1 (cos α + cos(α + 90°)) = √2 F1 cos(α + 45°): peak at α = -45° = 315°
    assert b.first.force == pytest.approx(np.sqrt(2) * F1, rel=1e-14)
    assert np.degrees(b.first.force_peak_angle) == pytest.approx(315.0)


def test_stechkin_klimov_does_not_depend_on_speed():
    xi = [bal.stechkin_klimov(2 * LAM * M_J * R * w**2, 295.0, w, 0.105) for w in (50.0, 300.0)]
    assert xi[0] == pytest.approx(xi[1], rel=1e-14)
    assert xi[0] == pytest.approx(0.5 * LAM * M_J * R / (295.0 * 0.105), rel=1e-14)


@pytest.mark.parametrize("kwargs, match", [
    (dict(crank_angles=0.0), "one entry per cylinder"),
    (dict(crank_angles=[0.0, 1.0, 2.0]), "do not broadcast"),
    (dict(reciprocating_mass=[-1.0, 1.0]), "reciprocating_mass must be ≥ 0"),
    (dict(crank_radius=0.0), "crank_radius must be > 0"),
    (dict(lambda_=1.2), r"lambda_ must be in \(0, 1\)"),
    (dict(angular_speed=-1.0), "angular_speed must be ≥ 0"),
    (dict(shaft_masses=([0.0], [0.0])), "shaft_masses must be three arrays"),
])
def test_bad_inputs_say_what_to_fix(kwargs, match):
    args = dict(crank_angles=[0.0, np.pi], positions=[0.0, A], reciprocating_mass=M_J,
                rotating_mass=M_R, crank_radius=R, angular_speed=W, lambda_=LAM)
    args.update(kwargs)
    with pytest.raises(InputError, match=match):
        bal.inline_balance(**args)


def test_history_needs_one_dimensional_angles():
    with pytest.raises(InputError, match="1-D"):
        bal.inline_history(np.zeros((2, 2)), [0.0], [0.0], M_J, M_R, R, W, LAM)


def test_plot_draws_on_a_given_figure():
    from matplotlib.figure import Figure

    fig = Figure()
    ax_f, ax_m = history([0, 180]).plot(fig, "ru")
    assert [l.get_label() for l in ax_f.get_lines() if not l.get_label().startswith("_")] \
        == ["F_j2", "ΣP_j (точно)"], "zero curves are left out"
    assert any("F_r" in t.get_text() for t in ax_f.texts)
