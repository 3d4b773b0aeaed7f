"""Lab 8. Balancing a two-cylinder in-line engine (the D-120 diesel, cranks at 180°).

The manual's chapter in two parts. **Balance analysis**: the centrifugal moment M_r, the
first-order moment M_j1 (its forces cancel), the second-order force ΣP_j2 (its moment is
zero) and the Stechkin–Klimov criterion ξ. **The balancing mechanism**: counterweights on the
webs (M_pr), lugs on the pulley and the flywheel for the rest of M_r and half of M_j1 (static
moments D_r, D_j1, D = D_r + D_j1), a counter-rotating shaft for the other half (D₂), and the
dummy masses m_x on the crank pins for balancing the shaft on a machine.

Beside the manual's formulas, every file gets the general in-line analysis of
:mod:`processing.crank.balance` (phasor sums over the cylinders): for the two-cylinder engine it
re-derives M_r − M_pr, M_j1 max and ΣP_j2 max from the positions of the pins, webs and
counterweights, and with ``[[cylinder]]`` tables it analyses any in-line layout (inline-3, -4,
-6, a 360° twin, ...).

Speed does not matter for the mechanism: every term of M_r, M_pr, M_j1 is proportional to ω²,
so the static moments D_r = ΔM_r/(l₁ω²), D_j1 = 0.5 m_j r a/l₁, D₂ = 0.5 m_j r a/l₄ [kg·m],
the dummy mass m_x = ΔM_r/(rω²a) [kg] and ξ do not depend on n; a balance made at one speed
holds at all. n sets only the forces and moments themselves.

Notation as in the manual: index ``shp`` — the rod's share at the piston pin (m_шп), ``shk`` —
at the crank pin (m_шк), ``pin`` — the crank pin (m_шш), ``web1`` — an outer web (webs 1 and
4, l₃ apart), ``web2`` — a middle web (2 and 3, l₂ apart), ``pr`` — a counterweight (m_пр).

References
----------
.. [1] Dynamics of internal-combustion engines: lab manual, Vladimir State University, 2003,
       lab 8 ("Исследование системы уравновешивания двухцилиндрового рядного двигателя").
"""
from __future__ import annotations

import warnings

import numpy as np

from processing.crank.balance import (STECHKIN_KLIMOV_LIMIT, inline_balance, inline_history,
                                stechkin_klimov)
from processing.diagnostics import ImbalanceWarning, InconsistentInputWarning, collect_notices
from processing.measurement import (ENGINE_SPEED, LENGTH, MASS, Field, Inputs, LabSpec, Section,
                                    bi)
from processing.reporting.content import fmt_pm
from processing.result import (Figure, LabResult, Table, flag_estimates, result_values,
                               with_key)
from processing.uncertainty import Measured, propagate

from . import catalogue

SPEED_LIMIT = 10000.0
"""n above this [min⁻¹] is queried: an engine of this lab does not turn so fast."""

FREE_FORCE_SHARE = 0.01
"""A free rotating or first-order force above this share of one cylinder's (m r ω²) is called
out: the manual's ξ looks at the second order only and would not see it."""


# ------------------------------------------------------------------------ formulas

def centrifugal_moment(m_pin, m_shk, m_web1, m_web2, a, l2, l3, r, omega):
    """Moment of the centrifugal forces of the two-cylinder crankshaft, M_r.

    .. math:: M_r = (m_{шш} + m_{шк}) a r\\omega^2 + m_{щ1} r\\omega^2 l_3 + m_{щ2} r\\omega^2 l_2

    Parameters
    ----------
    m_pin, m_shk : float or ndarray
        Crank pin and the rod's crank-end share, at each crank pin (pins a apart). [kg]
    m_web1, m_web2 : float or ndarray
        An outer web (1, 4; l₃ apart) and a middle web (2, 3; l₂ apart), reduced to r. [kg]
    a, l2, l3 : float or ndarray
        Cylinder spacing; distance between the middle webs and between the outer webs. [m]
    r : float or ndarray
        Crank radius. [m]
    omega : float or ndarray
        ω. [rad/s]

    Returns
    -------
    float or ndarray
        M_r. [N·m]

    Notes
    -----
    The centrifugal forces themselves cancel (ΣK_r = 0): the cranks are 180° apart.

    References
    ----------
    Lab manual, lab 8; FORMULAS.md "Lab 8".
    """
    return r * omega ** 2 * ((m_pin + m_shk) * a + m_web1 * l3 + m_web2 * l2)


def first_order_moment_max(m_j, r, omega, a):
    """Largest moment of the first-order forces, M_j1 max = m_j r ω² a.

    M_j1 = P_j1 a = m_j r ω² a cos α: the two forces are equal and opposite, a apart.

    Parameters
    ----------
    m_j : float or ndarray
        Reciprocating mass per cylinder, m_п + m_шп. [kg]
    r, a : float or ndarray
        Crank radius; cylinder spacing. [m]
    omega : float or ndarray
        ω. [rad/s]

    Returns
    -------
    float or ndarray
        [N·m]

    Examples
    --------
    >>> round(first_order_moment_max(2.806, 0.06, 200.0, 0.14), 6)
    942.816
    """
    return m_j * r * omega ** 2 * a


def second_order_force_max(m_j, r, omega, lambda_):
    """Largest sum of the second-order forces, ΣP_j2 max = 2λ m_j r ω².

    ΣP_j2 = 2λ m_j r ω² cos 2α: cos 2(180° + α) = cos 2α, the forces add; their moment is 0.

    Parameters
    ----------
    m_j : float or ndarray
        Reciprocating mass per cylinder. [kg]
    r : float or ndarray
        Crank radius. [m]
    omega : float or ndarray
        ω. [rad/s]
    lambda_ : float or ndarray
        λ = r/L. [1]

    Returns
    -------
    float or ndarray
        [N]
    """
    return 2 * lambda_ * m_j * r * omega ** 2


def counterweight_moment(m_pr, r, omega, l2, l3):
    """Moment of the centrifugal forces of the four web counterweights, M_pr.

    .. math:: M_{пр} = m_{пр1} r\\omega^2 l_3 + m_{пр2} r\\omega^2 l_2 = m_{пр} r\\omega^2 (l_3 + l_2)

    Parameters
    ----------
    m_pr : float or ndarray
        Each counterweight's mass reduced to r (all four equal), opposite its crank. [kg]
    r, l2, l3 : float or ndarray
        Crank radius; middle-web and outer-web spacing. [m]
    omega : float or ndarray
        ω. [rad/s]

    Returns
    -------
    float or ndarray
        [N·m]
    """
    return m_pr * r * omega ** 2 * (l3 + l2)


def lug_static_moments(dM_r, m_j, r, a, omega, l1, l4):
    """Static moments of the balancing lugs and weights, the manual's D_r, D_j1, D, D₂.

    .. math::
        D_r = \\frac{\\Delta M_r}{l_1\\omega^2},\\quad
        D_{j1} = \\frac{0.5 M_{j1}^{max}}{l_1\\omega^2} = \\frac{0.5 m_j r a}{l_1},\\quad
        D = D_r + D_{j1},\\quad D_2 = \\frac{0.5 m_j r a}{l_4}

    Parameters
    ----------
    dM_r : float or ndarray
        ΔM_r = M_r − M_pr, the centrifugal moment the counterweights leave. [N·m]
    m_j : float or ndarray
        Reciprocating mass per cylinder. [kg]
    r, a : float or ndarray
        Crank radius; cylinder spacing. [m]
    omega : float or ndarray
        ω. [rad/s]
    l1, l4 : float or ndarray
        Distance between the pulley and flywheel planes; between the weights of the
        counter-rotating shaft. [m]

    Returns
    -------
    D_r, D_j1, D, D_2 : float or ndarray
        Static moments (mass × radius of its centre) of each lug or weight. [kg·m]

    Notes
    -----
    A pair of equal masses at radius ρ, l apart and 180° apart, turning at ω makes a couple
    (mρ) ω² l, so the static moment that cancels a couple M is M/(lω²). ΔM_r and M_j1 grow as
    ω², so D_r = r[(m_шш + m_шк)a + m_щ1 l₃ + m_щ2 l₂ − m_пр(l₃ + l₂)]/l₁ and the others
    contain no ω: the balance holds at every speed. D_r and D_j1 add as scalars because the
    residual centrifugal couple and the forward-turning half of the first-order couple both
    turn with crank 1 (see :mod:`processing.crank.balance`); the backward-turning half needs the
    shaft turning the other way.

    Examples
    --------
    >>> [round(float(v), 6) for v in lug_static_moments(400.0, 2.806, 0.06, 0.14, 200.0, 0.4, 0.3)]
    [0.025, 0.029463, 0.054463, 0.039284]

    References
    ----------
    Lab manual, lab 8; FORMULAS.md "Lab 8".
    """
    D_r = dM_r / (l1 * omega ** 2)
    D_j1 = 0.5 * m_j * r * a / l1
    return D_r, D_j1, D_r + D_j1, 0.5 * m_j * r * a / l4


def dummy_mass(dM_r, r, omega, a):
    """Mass of the dummy weights on the crank pins for balancing the shaft, m_x = ΔM_r/(rω²a).

    Parameters
    ----------
    dM_r : float or ndarray
        ΔM_r = M_r − M_pr. [N·m]
    r, a : float or ndarray
        Crank radius; cylinder spacing (the pins are a apart). [m]
    omega : float or ndarray
        ω. [rad/s]

    Returns
    -------
    float or ndarray
        m_x, independent of ω. [kg]
    """
    return dM_r / (r * omega ** 2 * a)


def two_cylinder_layout(a, l2, l3, m_j, m_crank, m_web1, m_web2, m_pr=None):
    """The manual's two-cylinder crankshaft as the arrays of
    :func:`processing.crank.balance.inline_balance`.

    Cylinders at x = ∓a/2 with cranks at 0° and 180°; the crank pin and the rod's big end
    (``m_crank``) in the cylinder planes; webs 1 and 4 (``m_web1``) at x = ∓l₃/2, webs 2 and 3
    (``m_web2``) at ∓l₂/2, each at its crank's angle; counterweights ``m_pr`` (if given) on all
    four webs, opposite their cranks.

    Parameters
    ----------
    a, l2, l3 : float or ndarray
        [m]
    m_j, m_crank, m_web1, m_web2, m_pr : float or ndarray
        Masses reduced to r; arrays of Monte Carlo draws are allowed (shape (N,)). [kg]

    Returns
    -------
    dict
        Keyword arguments ``crank_angles``, ``positions``, ``reciprocating_mass``,
        ``rotating_mass``, ``shaft_masses`` (moments about the middle, x = 0).
    """
    def stack(*values):
        return np.stack(np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in values)), axis=-1)

    half = 0.5
    webs_x = stack(-half * l3, -half * l2, half * l2, half * l3)
    webs_angle = stack(0.0, 0.0, np.pi, np.pi)
    webs_m = stack(m_web1, m_web2, m_web2, m_web1)
    if m_pr is not None:
        webs_x = np.concatenate(np.broadcast_arrays(webs_x, webs_x), axis=-1)
        webs_angle = np.concatenate(np.broadcast_arrays(webs_angle, stack(np.pi, np.pi, 0.0, 0.0)),
                                    axis=-1)
        webs_m = np.concatenate(np.broadcast_arrays(webs_m, stack(m_pr, m_pr, m_pr, m_pr)), axis=-1)
    webs_angle, webs_x, webs_m = np.broadcast_arrays(webs_angle, webs_x, webs_m)
    return dict(crank_angles=stack(0.0, np.pi), positions=stack(-half * a, half * a),
                reciprocating_mass=np.asarray(m_j, dtype=float)[..., None],
                rotating_mass=np.asarray(m_crank, dtype=float)[..., None],
                shaft_masses=(webs_angle, webs_x, webs_m))


# -------------------------------------------------------------------- the measurement file

SPEC = LabSpec(
    id="lab8", number="8",
    title=catalogue.title("lab8"),
    goal=bi("To analyse the balance of the two-cylinder D-120 diesel and to find the parameters of "
            "the mechanism that balances the moments of the centrifugal forces and of the "
            "first-order inertia forces.",
            "Выполнить анализ уравновешенности двухцилиндрового дизеля Д-120; определить "
            "параметры системы уравновешивания моментов от центробежных сил и сил инерции "
            "первого порядка."),
    sections=(
        Section("engine", bi("The engine", "Двигатель"), required=True, fields=(
            Field("r", bi("crank radius", "радиус кривошипа"), unit="mm", symbol="r",
                  example="60 mm", plausible=("10 mm", "500 mm")),
            Field("lambda", bi("crank radius over connecting-rod length",
                               "отношение радиуса кривошипа к длине шатуна"), unit="",
                  symbol="λ", example=0.279, plausible=("0.1", "0.5")),
            Field("n", bi("crankshaft speed", "частота вращения коленчатого вала"),
                  **ENGINE_SPEED, symbol="n", example=2000),
            Field("D", bi("cylinder bore (for ξ)", "диаметр цилиндра (для ξ)"), unit="mm",
                  required=False, symbol="D", example="105 mm",
                  plausible=("20 mm", "1000 mm")),
            Field("m_engine", bi("mass of the engine (for ξ)", "масса двигателя (для ξ)"),
                  unit="kg", required=False, symbol="m", example="295 kg",
                  plausible=("10 kg", "50000 kg")),
        )),
        Section("masses", bi("Masses of one crank and cylinder", "Массы одного кривошипа и цилиндра"),
                help=bi("Masses reduced to the crank radius where they rotate. In [[cylinder]] mode\n"
                        "they give every cylinder m_j = m_piston + m_shp and\n"
                        "m_r = m_pin + m_shk + m_web1 + m_web2 (webs lumped in the crank plane).",
                        "Вращающиеся массы приведены к радиусу кривошипа. В режиме [[cylinder]]\n"
                        "они задают каждому цилиндру m_j = m_piston + m_shp и\n"
                        "m_r = m_pin + m_shk + m_web1 + m_web2 (щёки — в плоскости кривошипа)."),
                fields=(
            Field("m_piston", bi("piston group", "поршневой комплект"), **MASS, symbol="m_п"),
            Field("m_shp", bi("rod's share at the piston pin", "масса шатуна, отнесённая к оси "
                              "поршневого пальца"), **MASS, symbol="m_шп"),
            Field("m_shk", bi("rod's share at the crank pin", "масса шатуна, отнесённая к "
                              "кривошипу"), **MASS, symbol="m_шк"),
            Field("m_pin", bi("crank pin", "шатунная шейка"), **MASS, symbol="m_шш"),
            Field("m_web1", bi("outer web (1, 4), reduced to r", "крайняя щека (1, 4), "
                               "приведённая к r"), **MASS, symbol="m_щ1"),
            Field("m_web2", bi("middle web (2, 3), reduced to r", "средняя щека (2, 3), "
                               "приведённая к r"), **MASS, symbol="m_щ2"),
        )),
        Section("crankshaft", bi("Two-cylinder crankshaft, cranks at 180° (the manual's D-120)",
                                 "Коленчатый вал двухцилиндрового двигателя, кривошипы под 180° "
                                 "(Д-120)"), fields=(
            Field("a", bi("distance between the cylinder axes", "расстояние между осями "
                          "цилиндров"), **LENGTH, symbol="a"),
            Field("l2", bi("distance between the middle webs", "расстояние между средними щеками"),
                  **LENGTH, symbol="l₂"),
            Field("l3", bi("distance between the outer webs", "расстояние между крайними щеками"),
                  **LENGTH, symbol="l₃"),
        )),
        Section("balancer", bi("Balancing mechanism", "Механизм уравновешивания"), fields=(
            Field("m_pr", bi("each web counterweight, reduced to r", "масса противовеса на щеке, "
                             "приведённая к r"), **MASS, symbol="m_пр"),
            Field("l1", bi("distance between the pulley and flywheel planes",
                           "расстояние между плоскостями шкива и маховика"), **LENGTH, symbol="l₁"),
            Field("l4", bi("distance between the weights of the counter-rotating shaft",
                           "расстояние между грузами дополнительного валика"), **LENGTH,
                  symbol="l₄"),
        )),
        Section("cylinder", bi("Cylinders of any in-line layout", "Цилиндры произвольного "
                               "рядного двигателя"), many=True,
                help=bi("One [[cylinder]] table per cylinder, instead of [crankshaft]: theta = its\n"
                        "crank's angle ahead of crank 1, x = axial position of its axis; m_j, m_r\n"
                        "default to the [masses] section.",
                        "Одна таблица [[cylinder]] на цилиндр, вместо [crankshaft]: theta — угол\n"
                        "кривошипа относительно первого, x — осевая координата цилиндра; m_j, m_r\n"
                        "по умолчанию из раздела [masses]."),
                fields=(
            Field("theta", bi("crank angle ahead of crank 1", "угол кривошипа относительно "
                              "первого"), unit="deg", symbol="θ", allow_zero=True,
                  plausible=("0.1 deg", "720 deg")),
            Field("x", bi("axial position of the cylinder axis", "осевая координата оси "
                          "цилиндра"), unit="mm", symbol="x", allow_zero=True,
                  plausible=("1 mm", "5000 mm")),
            Field("m_j", bi("reciprocating mass", "масса поступательно движущихся частей"),
                  **MASS, required=False, symbol="m_j"),
            Field("m_r", bi("rotating mass reduced to r", "вращающаяся масса, приведённая к r"),
                  **MASS, required=False, allow_zero=True, symbol="m_r"),
        )),
    ),
)

KEY_RESULTS = ("xi_stechkin", "D", "D_2", "m_x", "F_j1", "F_j2", "M_r_free", "M_j1_free",
               "M_j2_free")
"""What the balancing comes to: the criterion, the masses it asks for, the forces and moments
left free."""

_DECLARED = {
    "M_r": (bi("moment of the centrifugal forces", "момент центробежных сил"), "M_r", "N*m"),
    "M_j1_max": (bi("largest moment of the first-order forces",
                    "максимальный момент сил инерции первого порядка"), "M_j1 max", "N*m"),
    "P_j2_max": (bi("largest sum of the second-order forces",
                    "максимальная сумма сил инерции второго порядка"), "ΣP_j2 max", "N"),
    "xi_stechkin": (bi("Stechkin–Klimov criterion", "критерий Стечкина–Климова"), "ξ", ""),
    "M_pr": (bi("moment of the counterweights", "момент центробежных сил противовесов"),
             "M_пр", "N*m"),
    "dM_r": (bi("centrifugal moment left to the lugs, M_r − M_pr",
                "неуравновешенная часть центробежного момента, M_r − M_пр"), "ΔM_r", "N*m"),
    "D_r": (bi("static moment of each lug for ΔM_r (pulley, flywheel)",
               "статический момент прилива для ΔM_r (шкив, маховик)"), "D_r", "kg*m"),
    "D_j1": (bi("static moment of each lug for half of M_j1",
                "статический момент прилива для половины M_j1"), "D_j1", "kg*m"),
    "D": (bi("total static moment of each lug, D_r + D_j1",
             "полный статический момент прилива, D_r + D_j1"), "D", "kg*m"),
    "D_2": (bi("static moment of each weight of the counter-rotating shaft",
               "статический момент груза дополнительного валика"), "D₂", "kg*m"),
    "m_x": (bi("dummy mass on each crank pin (shaft balancing)",
               "масса имитирующего груза на шатунной шейке"), "m_x", "kg"),
    "F_r": (bi("free centrifugal force (amplitude)", "свободная центробежная сила (амплитуда)"),
            "F_r", "N"),
    "F_j1": (bi("free first-order force (amplitude)", "свободная сила инерции I порядка "
                "(амплитуда)"), "F_j1", "N"),
    "F_j2": (bi("free second-order force (amplitude)", "свободная сила инерции II порядка "
                "(амплитуда)"), "F_j2", "N"),
    "M_r_free": (bi("free centrifugal moment, counterweights included (amplitude)",
                    "свободный момент центробежных сил с противовесами (амплитуда)"),
                 "ΣM_r", "N*m"),
    "M_j1_free": (bi("free first-order moment (amplitude)", "свободный момент сил I порядка "
                     "(амплитуда)"), "ΣM_j1", "N*m"),
    "M_j2_free": (bi("free second-order moment (amplitude)", "свободный момент сил II порядка "
                     "(амплитуда)"), "ΣM_j2", "N*m"),
    "omega": (bi("crankshaft angular speed", "угловая скорость коленчатого вала"), "ω", "rad/s"),
}
RESULTS = with_key(_DECLARED, KEY_RESULTS)


FORMULAS = [
    bi("Rotating mass per crank m_k = m_pin + m_web1 + m_web2; centrifugal force "
       "K_r = (m_k + m_shk) r ω², ΣK_r = 0 (cranks at 180°)",
       "Вращающаяся масса кривошипа m_k = m_шш + m_щ1 + m_щ2; центробежная сила "
       "K_r = (m_k + m_шк) r ω², ΣK_r = 0 (кривошипы под 180°)"),
    bi("M_r = (m_pin + m_shk) a r ω² + m_web1 r ω² l₃ + m_web2 r ω² l₂",
       "M_r = (m_шш + m_шк) a r ω² + m_щ1 r ω² l₃ + m_щ2 r ω² l₂"),
    bi("m_j = m_piston + m_shp; P_j1 = ± m_j r ω² cos α, ΣP_j1 = 0; M_j1 = m_j r ω² a cos α, "
       "M_j1 max = m_j r ω² a",
       "m_j = m_п + m_шп; P_j1 = ± m_j r ω² cos α, ΣP_j1 = 0; M_j1 = m_j r ω² a cos α, "
       "M_j1 max = m_j r ω² a"),
    bi("ΣP_j2 = 2λ m_j r ω² cos 2α, ΣP_j2 max = 2λ m_j r ω²; M_j2 = 0",
       "ΣP_j2 = 2λ m_j r ω² cos 2α, ΣP_j2 max = 2λ m_j r ω²; M_j2 = 0"),
    bi("Stechkin–Klimov: ξ = 0.25 P_j2 max/(m ω² D) < 0.002 is satisfactory (ω² cancels: ξ "
       "does not depend on n)",
       "Критерий Стечкина–Климова: ξ = 0,25 P_j2 max/(m ω² D) < 0,002 — удовлетворительно "
       "(ω² сокращается: ξ не зависит от n)"),
    bi("M_pr = m_pr r ω² (l₃ + l₂); ΔM_r = M_r − M_pr",
       "M_пр = m_пр r ω² (l₃ + l₂); ΔM_r = M_r − M_пр"),
    bi("D_r = ΔM_r/(l₁ ω²); D_j1 = 0.5 M_j1 max/(l₁ ω²) = 0.5 m_j r a/l₁; D = D_r + D_j1; "
       "D₂ = 0.5 m_j r a/l₄; m_x = ΔM_r/(r ω² a) — all free of ω",
       "D_r = ΔM_r/(l₁ ω²); D_j1 = 0,5 M_j1 max/(l₁ ω²) = 0,5 m_j r a/l₁; D = D_r + D_j1; "
       "D₂ = 0,5 m_j r a/l₄; m_x = ΔM_r/(r ω² a) — не зависят от ω"),
    bi("General in-line engine (phasors): F_r = r ω² |Σ m_r e^{iθ}|, F_j1 = r ω² |Σ m_j e^{iθ}|, "
       "F_j2 = λ r ω² |Σ m_j e^{2iθ}|; moments with m (x₀ − x) in place of m. The amplitude of "
       "a reciprocating order is the peak of its resultant along the cylinder axis",
       "Рядный двигатель в общем случае (векторные суммы): F_r = r ω² |Σ m_r e^{iθ}|, "
       "F_j1 = r ω² |Σ m_j e^{iθ}|, F_j2 = λ r ω² |Σ m_j e^{2iθ}|; моменты — с m (x₀ − x) "
       "вместо m. Амплитуда силы порядка k — наибольшее значение равнодействующей вдоль оси "
       "цилиндров"),
]
REFERENCES = [
    bi("Dynamics of internal-combustion engines: lab manual. Vladimir State University, 2003, lab 8.",
       "Динамика двигателей внутреннего сгорания: метод. указания к лаб. работам. Владимир: ВлГУ, "
       "2003. Лаб. работа №8."),
    bi("Lukanin V.N. (ed.). Internal combustion engines, vol. 2: Dynamics and design. Moscow: "
       "Vysshaya Shkola, 2009 (balancing of in-line engines).",
       "Двигатели внутреннего сгорания. Т. 2: Динамика и конструирование / под ред. В.Н. Луканина. "
       "М.: Высшая школа, 2009 (уравновешивание рядных двигателей)."),
    bi("Taylor C.F. The Internal-Combustion Engine in Theory and Practice, vol. 2. MIT Press, 1985 "
       "(engine balance by rotating vectors).",
       "Taylor C.F. The Internal-Combustion Engine in Theory and Practice, vol. 2. MIT Press, 1985 "
       "(уравновешивание методом вращающихся векторов)."),
    bi("JCGM 100:2008 (GUM) and JCGM 101:2008 (Monte Carlo) for the uncertainties.",
       "JCGM 100:2008 (GUM) и JCGM 101:2008 (Монте-Карло) — оценка неопределённости."),
]


# ------------------------------------------------------------------------ reduction

def _layout(x: dict, inputs: Inputs, *, counterweights: bool = True) -> dict:
    """The engine as arguments of :func:`inline_balance`, from flat inputs (values or draws)."""
    def col(v):
        return np.asarray(v, dtype=float)

    if "crankshaft" in inputs:
        m_pr = x["balancer.m_pr"] if counterweights and "balancer" in inputs else None
        return two_cylinder_layout(
            x["crankshaft.a"], x["crankshaft.l2"], x["crankshaft.l3"],
            x["masses.m_piston"] + x["masses.m_shp"], x["masses.m_pin"] + x["masses.m_shk"],
            x["masses.m_web1"], x["masses.m_web2"], m_pr)
    theta, pos, m_j, m_r = [], [], [], []
    for i, cyl in enumerate(inputs["cylinder"]):
        key = f"cylinder[{i}]."
        theta.append(col(x[key + "theta"]))
        pos.append(col(x[key + "x"]))
        m_j.append(col(x[key + "m_j"]) if "m_j" in cyl else
                   col(x["masses.m_piston"] + x["masses.m_shp"]))
        m_r.append(col(x[key + "m_r"]) if "m_r" in cyl else
                   col(x["masses.m_pin"] + x["masses.m_shk"] + x["masses.m_web1"]
                       + x["masses.m_web2"]))

    def stack(values):
        return np.stack(np.broadcast_arrays(*values), axis=-1)

    return dict(crank_angles=stack(theta), positions=stack(pos), reciprocating_mass=stack(m_j),
                rotating_mass=stack(m_r))


def _engine(x: dict) -> dict:
    return dict(crank_radius=x["engine.r"], angular_speed=x["engine.n"],
                lambda_=x["engine.lambda"])


def _model(inputs: Inputs):
    manual = "crankshaft" in inputs
    balancer = "balancer" in inputs
    criterion = "D" in inputs["engine"] and "m_engine" in inputs["engine"]

    def model(**x):
        r, lam = x["engine.r"], x["engine.lambda"]
        w = x["engine.n"]
        out = {"omega": w}
        b = inline_balance(**_layout(x, inputs), **_engine(x))
        out.update(F_r=b.rotating.force, F_j1=b.first.force, F_j2=b.second.force,
                   M_r_free=b.rotating.moment, M_j1_free=b.first.moment,
                   M_j2_free=b.second.moment)
        P_j2 = b.second.force
        if manual:
            a, l2, l3 = x["crankshaft.a"], x["crankshaft.l2"], x["crankshaft.l3"]
            m_j = x["masses.m_piston"] + x["masses.m_shp"]
            out["M_r"] = centrifugal_moment(x["masses.m_pin"], x["masses.m_shk"],
                                            x["masses.m_web1"], x["masses.m_web2"], a, l2, l3, r, w)
            out["M_j1_max"] = first_order_moment_max(m_j, r, w, a)
            out["P_j2_max"] = P_j2 = second_order_force_max(m_j, r, w, lam)
            if balancer:
                out["M_pr"] = counterweight_moment(x["balancer.m_pr"], r, w, l2, l3)
                out["dM_r"] = dM_r = out["M_r"] - out["M_pr"]
                out["D_r"], out["D_j1"], out["D"], out["D_2"] = lug_static_moments(
                    dM_r, m_j, r, a, w, x["balancer.l1"], x["balancer.l4"])
                out["m_x"] = dummy_mass(dM_r, r, w, a)
        if criterion:
            out["xi_stechkin"] = stechkin_klimov(P_j2, x["engine.m_engine"], w, x["engine.D"])
        return out

    return model


def _check_sections(inputs: Inputs) -> None:
    if "crankshaft" in inputs and "cylinder" in inputs:
        raise inputs.error("both [crankshaft] and [[cylinder]] tables are given",
                           "give [crankshaft] for the manual's two-cylinder engine, or one "
                           "[[cylinder]] per cylinder for any other layout, not both", "cylinder")
    if "crankshaft" not in inputs and "cylinder" not in inputs:
        raise inputs.error("the engine's layout is missing",
                           "add [crankshaft] (a, l2, l3: the manual's two-cylinder engine) or "
                           "one [[cylinder]] table per cylinder (theta, x)", "crankshaft")
    if "crankshaft" in inputs and "masses" not in inputs:
        raise inputs.error("section [masses] is missing",
                           "the two-cylinder analysis needs m_piston, m_shp, m_shk, m_pin, "
                           "m_web1, m_web2", "masses")
    if "balancer" in inputs and "crankshaft" not in inputs:
        raise inputs.error("[balancer] belongs to the manual's two-cylinder engine",
                           "add [crankshaft] (a, l2, l3), or delete [balancer]", "balancer")
    lam = inputs["engine"]["lambda"].value
    if not 0 < lam < 1:
        raise inputs.error(f"λ = {lam:g} is not a crank mechanism's ratio r/L",
                           "give λ = r/L, between 0 and 1 (typically 0.24–0.32)", "engine.lambda")
    n_min = 30 / np.pi * inputs["engine"]["n"].value
    if n_min > SPEED_LIMIT:
        warnings.warn(InconsistentInputWarning(
            f"n = {n_min:.0f} min⁻¹ is beyond {SPEED_LIMIT:.0f} min⁻¹, faster than an engine of "
            f"this lab turns: check n (a plain number is read in min⁻¹)",
            f"n = {n_min:.0f} мин⁻¹ больше {SPEED_LIMIT:.0f} мин⁻¹ — так быстро двигатели этой "
            f"работы не вращаются: проверьте n (число читается в мин⁻¹)"))
    if "cylinder" in inputs and "masses" not in inputs:
        for i, cyl in enumerate(inputs["cylinder"]):
            for name in ("m_j", "m_r"):
                if name not in cyl:
                    raise inputs.error(f"cylinder {i + 1} has no {name} and there is no [masses]",
                                       f"give {name} in every [[cylinder]], or add [masses]",
                                       f"cylinder[{i}].{name}")
    if "crankshaft" in inputs:
        cs = inputs["crankshaft"]
        a, l2, l3 = (cs[k].value for k in ("a", "l2", "l3"))
        if not l2 < l3:
            raise inputs.error(f"l₂ = {1e3 * l2:g} mm is not smaller than l₃ = {1e3 * l3:g} mm",
                               "l2 is the distance between the middle webs (2, 3), l3 between "
                               "the outer ones (1, 4): swap them?", "crankshaft.l2")
        if not l2 < a < l3:
            warnings.warn(InconsistentInputWarning(
                f"the cylinder spacing a = {1e3 * a:g} mm does not lie between the web spacings "
                f"l₂ = {1e3 * l2:g} mm and l₃ = {1e3 * l3:g} mm, as it does on a crank with the "
                f"pin between its webs: check a, l2, l3",
                f"расстояние между цилиндрами a = {1e3 * a:g} мм не лежит между l₂ = {1e3 * l2:g} "
                f"мм и l₃ = {1e3 * l3:g} мм, как у кривошипа с шейкой между щеками: проверьте "
                f"a, l2, l3"))
        if "balancer" in inputs and inputs["balancer"]["l1"].value <= l3:
            l1 = inputs["balancer"]["l1"].value
            warnings.warn(InconsistentInputWarning(
                f"l₁ = {1e3 * l1:g} mm (pulley to flywheel) is not longer than l₃ = {1e3 * l3:g} mm "
                f"(outer webs), though the pulley and the flywheel sit outside the crankshaft's "
                f"webs: check l1",
                f"l₁ = {1e3 * l1:g} мм (шкив — маховик) не больше l₃ = {1e3 * l3:g} мм (крайние "
                f"щёки), хотя шкив и маховик стоят снаружи щёк: проверьте l1"))


def _warn_balance(inputs: Inputs, prop, nominal: dict) -> None:
    if "xi_stechkin" in prop:
        xi = prop["xi_stechkin"].value
        if xi >= STECHKIN_KLIMOV_LIMIT:
            warnings.warn(ImbalanceWarning(
                f"Stechkin–Klimov criterion ξ = {xi:.4f} ≥ {STECHKIN_KLIMOV_LIMIT}: the free "
                f"second-order force ({prop['F_j2'].value:.4g} N at this speed) is too large for an "
                f"engine of this mass and bore, the balance is unsatisfactory. It cannot be helped "
                f"by counterweights: it needs two shafts turning at 2ω in opposite directions "
                f"(Lanchester balancer), a heavier or softer-mounted engine, or another crank "
                f"arrangement",
                f"критерий Стечкина–Климова ξ = {xi:.4f} ≥ {STECHKIN_KLIMOV_LIMIT}: свободная сила "
                f"инерции второго порядка ({prop['F_j2'].value:.4g} Н при этой частоте) велика для "
                f"двигателя такой массы и диаметра цилиндра, уравновешенность "
                f"неудовлетворительная. Противовесы здесь не помогут: нужны два вала, вращающиеся "
                f"с 2ω в разные стороны (механизм Ланчестера), более тяжёлый или мягче "
                f"подвешенный двигатель либо иная схема коленчатого вала"))
    one = nominal["one_cylinder"]
    loose = [name for name in ("F_r", "F_j1") if prop[name].value > FREE_FORCE_SHARE * one[name]]
    if loose:
        text = ", ".join(f"{n} = {prop[n].value:.4g} N" for n in loose)
        warnings.warn(ImbalanceWarning(
            f"the crank arrangement leaves free forces turning at ω: {text}. ξ of the manual "
            f"looks at the second-order force only and does not see them; a free first-order or "
            f"centrifugal force shakes the engine at the crankshaft's own frequency: add "
            f"counterweights (centrifugal; half of the first order) and a counter-rotating "
            f"balance shaft (the other half), or choose cranks whose phasors sum to zero",
            f"схема коленчатого вала оставляет свободные силы с частотой ω: {text}. Критерий ξ "
            f"учитывает только силу второго порядка и их не замечает; свободная центробежная "
            f"сила или сила первого порядка трясёт двигатель с частотой вращения вала: нужны "
            f"противовесы (центробежная сила; половина силы первого порядка) и "
            f"уравновешивающий вал, вращающийся навстречу (вторая половина), либо схема "
            f"кривошипов с нулевой векторной суммой"))


def _nominal(inputs: Inputs) -> dict:
    """Values at the best estimates: phases, histories, one cylinder's forces."""
    flat = {k: (v.value if hasattr(v, "value") else v) for k, v in inputs.flat().items()}
    engine = _engine(flat)
    layout = _layout(flat, inputs)
    balance = inline_balance(**layout, **engine)
    alpha = np.radians(np.arange(0.0, 360.5, 0.5))
    history = inline_history(alpha, **layout, **engine)
    bare = None
    if "crankshaft" in inputs and "balancer" in inputs:
        bare = inline_history(alpha, **_layout(flat, inputs, counterweights=False), **engine)
    scale = engine["crank_radius"] * engine["angular_speed"] ** 2
    one = {"F_r": scale * float(np.max(np.abs(layout["rotating_mass"]))),
           "F_j1": scale * float(np.max(layout["reciprocating_mass"]))}
    return {"balance": balance, "history": history, "bare": bare, "one_cylinder": one}


_ORDER_ROWS = (("rotating", "F_r", "M_r_free"), ("first", "F_j1", "M_j1_free"),
               ("second", "F_j2", "M_j2_free"))
_KIND_TEXT = {
    "rotating": bi("centrifugal: a vector of constant length turning with the shaft, "
                   "φ ahead of crank 1", "центробежная: вектор постоянной длины, вращается с валом, "
                   "опережает кривошип 1 на φ"),
    "first": bi("first order, along the cylinder axes: A cos(α + φ)",
                "I порядка, вдоль осей цилиндров: A cos(α + φ)"),
    "second": bi("second order, along the cylinder axes: A cos(2α + φ)",
                 "II порядка, вдоль осей цилиндров: A cos(2α + φ)"),
}


def _phase_table(results, nominal) -> Table:
    rows = []

    def deg(v):
        return "—" if not np.isfinite(v) else f"{np.degrees(v):.1f}"

    for order, (_, force_name, moment_name) in zip(nominal["balance"], _ORDER_ROWS):
        kind = order.kind
        for what, name, phase, peak in (
                ("F", force_name, order.force_phase, order.force_peak_angle),
                ("M", moment_name, order.moment_phase, order.moment_peak_angle)):
            r = results[name]
            v, U = fmt_pm(r.shown(r.value), r.shown(r.value + r.estimate.U) - r.shown(r.value))
            unit = {"en": "N" if what == "F" else "N·m", "ru": "Н" if what == "F" else "Н·м"}
            rows.append({"name": name, "amplitude": {k: f"{v} ± {U} {unit[k]}" for k in unit},
                         "phase": deg(float(phase)), "peak": deg(float(peak)),
                         "form": _KIND_TEXT[kind]})
    return Table(bi("Free forces and moments of the crank train: amplitudes (± U) and "
                    "phases (moments about the middle of the cylinder row)",
                    "Свободные силы и моменты: амплитуды (± U) и фазы (моменты "
                    "относительно середины ряда цилиндров)"),
                 (("name", bi("Quantity", "Величина")), ("amplitude", bi("Amplitude", "Амплитуда")),
                  ("phase", bi("φ, deg", "φ, °")),
                  ("peak", bi("α of the peak along the axes, deg", "α максимума вдоль осей, °")),
                  ("form", bi("How it acts", "Как действует"))),
                 tuple(rows))


def _draw(nominal):
    def draw(fig, lang):
        ax_f, ax_m = nominal["history"].plot(fig, lang)
        bare = nominal["bare"]
        if bare is None:
            return
        for line in ax_m.get_lines():
            if line.get_label() == "M_r":
                line.set_label("ΔM_r = M_r − M_пр" if lang == "ru" else "ΔM_r = M_r − M_pr")
        ax_m.plot(np.degrees(bare.crank_angle), bare.rotating_moment_along, "--", color="C0",
                  lw=0.8, label="M_r")
        y = np.concatenate([np.asarray(line.get_ydata(), float) for line in ax_m.get_lines()])
        low, high = y.min(), y.max()
        ax_m.set_ylim(low - 0.05 * (high - low), high + 0.45 * (high - low))
        ax_m.legend(fontsize=7, loc="upper center", ncol=5, frameon=False)
    return draw


def _conclusion(results, inputs: Inputs, notices) -> list[dict]:
    def pm(name):
        r = results[name]
        v, U = fmt_pm(r.shown(r.value), r.shown(r.value + r.estimate.U) - r.shown(r.value))
        return f"{v} ± {U}"

    lines = []
    n_min = 30 / np.pi * inputs["engine"]["n"].value
    if "M_r" in results:
        lines.append(bi(
            f"At n = {n_min:.0f} min⁻¹ the centrifugal forces and the first-order forces cancel; "
            f"their moments do not: M_r = {pm('M_r')} N·m, M_j1 max = {pm('M_j1_max')} N·m. The "
            f"second-order forces add, ΣP_j2 max = {pm('P_j2_max')} N, with no moment; nothing "
            f"balances them and they reach the engine mounts.",
            f"При n = {n_min:.0f} мин⁻¹ центробежные силы и силы первого порядка уравновешены, их "
            f"моменты — нет: M_r = {pm('M_r')} Н·м, M_j1 max = {pm('M_j1_max')} Н·м. Силы второго "
            f"порядка складываются, ΣP_j2 max = {pm('P_j2_max')} Н, момента не дают; они не "
            f"уравновешиваются и передаются на опоры."))
    if "xi_stechkin" in results:
        xi = results["xi_stechkin"].value
        ok = xi < STECHKIN_KLIMOV_LIMIT
        lines.append(bi(
            f"Stechkin–Klimov: ξ = {xi:.5f} {'<' if ok else '≥'} {STECHKIN_KLIMOV_LIMIT}: the "
            f"balance is {'satisfactory' if ok else 'UNSATISFACTORY'} (ξ does not depend on the "
            f"speed).",
            f"Критерий Стечкина–Климова: ξ = {xi:.5f} {'<' if ok else '≥'} "
            f"{str(STECHKIN_KLIMOV_LIMIT).replace('.', ',')}: уравновешенность "
            f"{'удовлетворительная' if ok else 'НЕУДОВЛЕТВОРИТЕЛЬНАЯ'} (ξ не зависит от частоты "
            f"вращения)."))
    if "D" in results:
        share = results["M_pr"].value / results["M_r"].value
        lines.append(bi(
            f"The web counterweights take {100 * share:.0f} % of M_r; the rest, ΔM_r = "
            f"{pm('dM_r')} N·m, and half of M_j1 go to lugs on the pulley and the flywheel with "
            f"D = D_r + D_j1 = {pm('D')} kg·m each; the counter-rotating shaft carries weights "
            f"of D₂ = {pm('D_2')} kg·m; dummy masses on the crank pins m_x = {pm('m_x')} kg.",
            f"Противовесы на щеках уравновешивают {100 * share:.0f} % M_r; остаток ΔM_r = "
            f"{pm('dM_r')} Н·м и половина M_j1 приходятся на приливы шкива и маховика со "
            f"статическим моментом D = D_r + D_j1 = {pm('D')} кг·м каждый; грузы "
            f"дополнительного валика D₂ = {pm('D_2')} кг·м; имитирующие грузы на шатунных "
            f"шейках m_x = {pm('m_x')} кг."))
        lines.append(bi(
            "D_r, D_j1, D, D₂ and m_x contain no ω (every moment they cancel grows as ω²): the "
            "mechanism balances the engine at every speed.",
            "D_r, D_j1, D, D₂ и m_x не содержат ω (все уравновешиваемые моменты растут как ω²): "
            "механизм уравновешивает двигатель на любой частоте вращения."))
        if results["dM_r"].value < 0:
            lines.append(bi(
                "ΔM_r < 0: the counterweights overbalance the crankshaft, so the D_r part of the "
                "lugs goes on the side of the cranks, not opposite them.",
                "ΔM_r < 0: противовесы перекрывают центробежный момент, поэтому часть приливов "
                "D_r ставится со стороны кривошипов, а не напротив."))
    if "M_r" in results:
        pairs = [("M_r_free", "dM_r" if "dM_r" in results else "M_r"), ("M_j1_free", "M_j1_max"),
                 ("F_j2", "P_j2_max")]
        worst = max(abs(results[a].value - results[b].value) / abs(results[b].value)
                    for a, b in pairs)
        same = worst < 1e-9
        sym = results[pairs[0][1]].symbol
        zeros = all(results[n].value == 0 for n in ("F_r", "F_j1", "M_j2_free"))
        tail = " F_r = F_j1 = M_j2 = 0." if zeros else ""
        lines.append(bi(
            f"The general phasor analysis of the same crankshaft (pins, webs and counterweights "
            f"in their own planes) {'reproduces' if same else 'DOES NOT reproduce'} the manual's "
            f"{sym}, M_j1 max and ΣP_j2 max (largest relative difference {worst:.1e}).{tail}",
            f"Общий векторный расчёт того же вала (шейки, щёки и противовесы в своих плоскостях) "
            f"{'воспроизводит' if same else 'НЕ воспроизводит'} {sym}, M_j1 max и ΣP_j2 max "
            f"методички (наибольшее относительное расхождение {worst:.1e}).{tail}"))
    else:
        free = [n for n in ("F_r", "F_j1", "F_j2", "M_r_free", "M_j1_free", "M_j2_free")
                if results[n].value > 0]
        names = ", ".join(free) if free else "—"
        lines.append(bi(
            f"{len(inputs['cylinder'])}-cylinder in-line layout at n = {n_min:.0f} min⁻¹: "
            f"free (non-zero) forces and moments: {names}; the rest cancel.",
            f"Рядный {len(inputs['cylinder'])}-цилиндровый двигатель при n = {n_min:.0f} мин⁻¹: "
            f"неуравновешены {names}; остальные силы и моменты уравновешены."))
    if any(n.code == "imbalance" for n in notices):
        lines.append(bi("See the warnings: the balance is not satisfactory.",
                        "См. предупреждения: уравновешенность неудовлетворительная."))
    return lines


def reduce(inputs: Inputs, *, n_samples: int = 20000, seed: int = 20031) -> LabResult:
    """Reduce lab 8: the balance analysis and the balancing mechanism, with uncertainties.

    Parameters
    ----------
    inputs : Inputs
        A validated measurement file (:func:`processing.measurement.load` with :data:`SPEC`).
    n_samples, seed : int
        Monte Carlo draws and their seed.

    Returns
    -------
    LabResult
        With ``[crankshaft]`` (the manual's engine): ``M_r``, ``M_j1_max``, ``P_j2_max``; with
        ``[balancer]`` also ``M_pr``, ``dM_r``, ``D_r``, ``D_j1``, ``D``, ``D_2``, ``m_x``.
        Always the general analysis ``F_r``, ``F_j1``, ``F_j2``, ``M_r_free`` (counterweights
        included), ``M_j1_free``, ``M_j2_free`` (amplitudes; phases in a table) and ``omega``;
        ``xi_stechkin`` when the bore and the engine mass are given. A figure of the free
        forces and moments over a revolution.

    Raises
    ------
    InputError
        Both or neither of ``[crankshaft]`` and ``[[cylinder]]``; l₂ ≥ l₃; λ outside (0, 1);
        masses missing.
    """
    with collect_notices() as notices:
        _check_sections(inputs)
        prop = propagate(_model(inputs), inputs.flat(), n_samples=n_samples, seed=seed)
        nominal = _nominal(inputs)
        results = result_values(prop, RESULTS)
        _warn_balance(inputs, prop, nominal)
        flag_estimates(results, [])
    figures = [Figure("free_forces", bi(
        "Free forces (top) and moments (bottom) over one revolution: series orders and the exact "
        "total of the reciprocating forces; centrifugal: the component along the cylinder axes",
        "Свободные силы (вверху) и моменты (внизу) за оборот: гармоники ряда и точная сумма сил "
        "инерции поступательно движущихся масс; центробежные — составляющая вдоль осей цилиндров"),
        _draw(nominal), size=(6.4, 5.2))]
    return LabResult.of(inputs, results, tables=[_phase_table(results, nominal)], figures=figures,
                        formulas=FORMULAS, references=REFERENCES, warnings=notices,
                        conclusion=_conclusion(results, inputs, notices))


# ------------------------------------------------------------------------ slips

def _rod_shares_swapped(inputs: Inputs) -> Inputs:
    """The rod's two shares swapped: m_шк taken as reciprocating, m_шп as rotating."""
    masses = inputs["masses"]
    return inputs.changed("masses", m_shp=masses["m_shk"], m_shk=masses["m_shp"])


def _piston_only(inputs: Inputs) -> Inputs:
    """The reciprocating mass taken as the piston group's alone (m_шп left out of m_j)."""
    return inputs.changed("masses", m_shp=Measured(0.0))


def _crank_end_left_out(inputs: Inputs) -> Inputs:
    """The rotating masses without the rod's crank-end share m_шк."""
    return inputs.changed("masses", m_shk=Measured(0.0))


RECIPROCATING = ("M_j1_max", "P_j2_max", "xi_stechkin", "D_j1", "D", "D_2", "F_j1", "F_j2",
                 "M_j1_free", "M_j2_free")
"""Results that follow the reciprocating mass m_j."""
ROTATING = ("M_r", "dM_r", "D_r", "D", "m_x", "F_r", "M_r_free")
"""Results that follow the rotating masses."""

SLIPS = [
    ("rod_shares_swapped",
     bi("the connecting rod's shares swapped: m_шк put into the reciprocating mass, m_шп into "
        "the rotating",
        "перепутаны доли массы шатуна: m_шк отнесена к поступательно движущимся массам, "
        "m_шп — к вращающимся"), RECIPROCATING + ROTATING, _rod_shares_swapped),
    ("piston_only_reciprocating",
     bi("the reciprocating mass taken as the piston group alone, without the rod's share m_шп",
        "масса поступательно движущихся частей взята без доли шатуна m_шп (только поршневой "
        "комплект)"), RECIPROCATING, _piston_only),
    ("crank_end_left_out",
     bi("the rod's crank-end share m_шк left out of the rotating masses",
        "доля шатуна m_шк не включена во вращающиеся массы"), ROTATING, _crank_end_left_out),
]
"""The lab's classic slips (:mod:`labs.teachers.check`): name, text, the results they change, and
the inputs as the slip leaves them."""


# ------------------------------------------------------------------------ variants

VARIED = {"engine": ("r", "lambda", "n", "D"),
          "masses": ("m_piston", "m_shp", "m_shk", "m_pin", "m_web1", "m_web2"),
          "crankshaft": ("a", "l2", "l3"), "balancer": ("m_pr",)}
"""The D-120 data a variant changes (each by up to ± 10 %)."""


def write_synthetic(out_dir, seed: int = 0) -> dict:
    """Write a variant of the manual's D-120 (:data:`VARIED` changed by up to ± 10 %) with its
    answer key (:func:`labs.sample_variant.design_variant`)."""
    from .sample_variant import design_variant

    return design_variant("lab8", "d120.toml", out_dir, seed, VARIED)
