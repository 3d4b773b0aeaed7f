"""Crank-slider kinematics: published figures, derivatives, identities, inverse round trips.

Sources: FORMULAS.md section A; the Russian notes "Кинематика кривошипно-шатунного механизма"
(seeds/kinematics_crank_mechanism_ru.txt); Li Bin et al., Machinery 2006 no. 1
(seeds/crank_mechanism_analysis_zh.txt), which prints the λ = 0.32 error figures.
"""

import numpy as np
import pytest
from numpy.testing import assert_allclose, assert_array_less

from processing.crank import kinematics as kin

DEG = np.pi / 180
LAMBDAS = np.array([0.2, 0.25, 0.32])[:, None]  # broadcast against crank angles (columns)
OFFSETS = np.array([0.0, 0.05, -0.1])[:, None, None]  # and against λ


# --- published figures at λ = 0.32 -----------------------------------------------------------


def test_acceleration_error_at_lambda_032_matches_li_bin_2006():
    # Li Bin 2006, after eq. (12): "λ = 0.32 时,近似式算出的 j_90 和 j_270 比准确值小 0.0178 rω²,
    # 相对误差约为 5.3%". Printed to 4 decimals (atol 5e-5) and to 0.1 % (atol 5e-4).
    # By hand: exact j(90°) = -tan β = -0.32/sqrt(1 - 0.32²) = -0.337760, approx = -λ = -0.32.
    r = kin.max_approximation_error(0.32, quantity="j")
    assert_allclose(r.max_abs_error, 0.0178, atol=5e-5, err_msg="max |Δj|/(Rω²) at λ = 0.32")
    assert (
        min(abs(r.crank_angle - 90 * DEG), abs(r.crank_angle - 270 * DEG)) < 1e-4
    ), f"max error of j should sit at 90° or 270°, found {np.degrees(r.crank_angle):.4f}°"
    # "about 5.3 %" is relative to the EXACT j at that angle; to the approximate j (-λ) it is
    # 0.01776/0.32 = 5.55 %, which would print as 5.6 %
    assert_allclose(
        abs(r.relative_error), 0.053, atol=5e-4, err_msg="5.3 % is |Δj| / |j_exact(90°)|"
    )
    approx_90 = kin.relative_acceleration(90 * DEG, 0.32, method="approx")
    assert_allclose(abs(r.error / approx_90), 0.056, atol=5e-4, err_msg="|Δj| / |j_approx(90°)|")
    # "比准确值小": the approximate j is smaller in magnitude than the exact one
    assert abs(approx_90) < abs(kin.relative_acceleration(90 * DEG, 0.32)), "|j_approx| < |j_exact|"
    # relative error of j has no finite bound: exact j crosses zero where the approximation does not
    assert np.isinf(r.max_relative_error), "relative error of j must be unbounded"


def test_velocity_error_at_lambda_032_matches_li_bin_2006():
    # Li Bin 2006, after eq. (7): no error at 0°, 90°, 180°, 270°; "即使对 λ = 0.32 的机构,
    # 最大误差也不大于 0.0057 rω, 相对误差小于 0.83%". Printed to 4 decimals / 0.01 %.
    r = kin.max_approximation_error(0.32, quantity="v")
    assert (
        r.max_abs_error <= 0.0057
    ), f"max |Δv| = {r.max_abs_error:.6f} Rω exceeds the published bound"
    assert_allclose(r.max_abs_error, 0.0057, atol=5e-5, err_msg="max |Δv|/(Rω), printed 0.0057")
    # the 0.83 % is the largest error relative to the local exact v (at 127.5°/232.5°),
    # not relative to v_max (0.54 %) nor at the point of the largest absolute error (0.56 %)
    assert r.max_relative_error < 0.0083, "largest relative v error should be below 0.83 %"
    assert_allclose(r.max_relative_error, 0.0083, atol=5e-5, err_msg="largest relative error of v")
    exact_zero = kin.approximation_error(np.array([0, 90, 180, 270]) * DEG, 0.32, quantity="v")
    assert_allclose(exact_zero, 0, atol=1e-12, err_msg="approximate v is exact at 0, 90, 180, 270°")


def test_displacement_error_at_lambda_032_matches_formulas_md():
    # FORMULAS.md A: "the approximate s at most about 0.4 %" (not in the seeds themselves).
    # Largest relative error 0.42 % (at 73.6°); at 90°, where |Δs| is largest (0.0043 R), 0.37 %.
    r = kin.max_approximation_error(0.32, quantity="s")
    assert_allclose(
        r.max_relative_error, 0.004, atol=5e-4, err_msg="about 0.4 %, one printed digit"
    )
    assert_allclose(r.crank_angle, 90 * DEG, atol=1e-4, err_msg="largest |Δs| at 90°")
    assert_allclose(abs(r.relative_error), 0.004, atol=5e-4, err_msg="relative Δs at 90°")


@pytest.mark.parametrize("quantity", ["s", "v", "j"])
def test_no_approximation_error_at_dead_centres(quantity):
    # FORMULAS.md A: "No error at α = 0 and 180°" (axial).
    err = kin.approximation_error(np.array([0.0, np.pi]), LAMBDAS, quantity=quantity)
    assert_allclose(
        err, 0, atol=1e-12, err_msg=f"{quantity}: approx must equal exact at TDC and BDC"
    )


@pytest.mark.parametrize("quantity", ["s", "v", "j"])
def test_approximation_is_third_order_in_lambda(quantity):
    # the series drops λ³ and higher: halving λ divides the largest error by 8 (to O(λ²), 1 %)
    big = kin.max_approximation_error(0.02, quantity=quantity).max_abs_error
    small = kin.max_approximation_error(0.01, quantity=quantity).max_abs_error
    assert_allclose(big / small, 8, rtol=1e-2, err_msg=f"{quantity}: error should scale as λ³")


def test_max_approximation_error_broadcasts_over_lambda_and_offset():
    r = kin.max_approximation_error(np.array([0.25, 0.32]), np.array([[0.0], [0.05]]), quantity="j")
    assert r.max_abs_error.shape == (2, 2), "result should broadcast to (offset, lambda)"
    single = kin.max_approximation_error(0.32, 0.05, quantity="j")
    assert_allclose(
        r.max_abs_error[1, 1],
        single.max_abs_error,
        rtol=1e-12,
        err_msg="broadcast entry equals the scalar call",
    )


# --- derivatives: the exact forms are the true derivatives ------------------------------------


def _central(func, alpha, h=1e-4):
    return (func(alpha + h) - func(alpha - h)) / (2 * h)


ALPHA = np.linspace(0, 2 * np.pi, 97)


@pytest.mark.parametrize("method", ["exact", "approx"])
def test_velocity_and_acceleration_are_derivatives_of_displacement(method):
    # v/(Rω) = ds/dα and j/(Rω²) = d²s/dα² for constant ω, axial and desaxial, all λ;
    # central difference h = 1e-4: truncation h²/6·|s'''| < 1e-8, rounding 1e-16/h = 1e-12.
    for z in np.ravel(OFFSETS):
        s = lambda a: kin.relative_displacement(a, LAMBDAS, z, method=method)
        v = lambda a: kin.relative_velocity(a, LAMBDAS, z, method=method)
        j = kin.relative_acceleration(ALPHA, LAMBDAS, z, method=method)
        assert_allclose(
            _central(s, ALPHA), v(ALPHA), atol=1e-7, err_msg=f"ds/dα ≠ v ({method}, z = {z})"
        )
        assert_allclose(_central(v, ALPHA), j, atol=1e-7, err_msg=f"dv/dα ≠ j ({method}, z = {z})")


def test_rod_speed_and_acceleration_are_derivatives_of_rod_angle():
    omega = 1.0
    for z in np.ravel(OFFSETS):
        beta = lambda a: kin.rod_angle(a, LAMBDAS, z)
        speed = lambda a: kin.rod_angular_speed(a, omega, LAMBDAS, z)
        assert_allclose(
            _central(beta, ALPHA), speed(ALPHA), atol=1e-7, err_msg=f"dβ/dα ≠ ω_rod/ω (z = {z})"
        )
        assert_allclose(
            _central(speed, ALPHA),
            kin.rod_angular_acceleration(ALPHA, omega, LAMBDAS, z),
            atol=1e-7,
            err_msg=f"dω_rod/dα ≠ ε_rod/ω (z = {z})",
        )


def test_absolute_forms_scale_with_radius_and_speed():
    R, omega, alpha = 0.06, 300.0, 40 * DEG
    assert_allclose(
        kin.piston_displacement(alpha, R, 0.27),
        R * kin.relative_displacement(alpha, 0.27),
        err_msg="S = R s",
    )
    assert_allclose(
        kin.piston_velocity(alpha, R, omega, 0.27),
        R * omega * kin.relative_velocity(alpha, 0.27),
        err_msg="v = Rω · v/(Rω)",
    )
    assert_allclose(
        kin.piston_acceleration(alpha, R, omega, 0.27, method="approx"),
        R * omega**2 * (np.cos(alpha) + 0.27 * np.cos(2 * alpha)),
        err_msg="j = Rω²(cos α + λ cos 2α)",
    )
    with pytest.raises(ValueError, match="crank_radius must be > 0 m, got -0.06"):
        kin.piston_displacement(alpha, -R, 0.27)


# --- identities --------------------------------------------------------------------------------


def test_axial_exact_forms_reduce_to_the_textbook_axial_formulas():
    lam = LAMBDAS
    beta = np.arcsin(lam * np.sin(ALPHA))
    assert_allclose(
        kin.relative_displacement(ALPHA, lam),
        (1 - np.cos(ALPHA)) + (1 - np.cos(beta)) / lam,
        atol=1e-13,
        err_msg="S = R[(1 - cos α) + (1/λ)(1 - cos β)]",
    )
    # Li Bin 2006 table 1: β̈ = -λ(1 - λ²)ω² sin α / cos³β
    assert_allclose(
        kin.rod_angular_acceleration(ALPHA, 2.0, lam),
        -lam * (1 - lam**2) * 4.0 * np.sin(ALPHA) / np.cos(beta) ** 3,
        atol=1e-12,
        err_msg="ε_rod = -λ(1 - λ²)ω² sin α / cos³β for z = 0",
    )


def test_acceleration_extremes():
    # FORMULAS.md A / Li Bin eq. (13): j(0) = 1 + λ, j(180°) = -(1 - λ) (exact and approximate);
    # for λ > 1/4 a third extremum at arccos(-1/(4λ)) of -(λ + 1/(8λ)) in the approximate form.
    ext = kin.acceleration_extremes(np.array([0.2, 0.32]))
    for method in ("exact", "approx"):
        assert_allclose(
            kin.relative_acceleration(0.0, np.array([0.2, 0.32]), method=method),
            ext.at_tdc,
            rtol=1e-14,
            err_msg=f"j(0) = 1 + λ ({method})",
        )
        assert_allclose(
            kin.relative_acceleration(np.pi, np.array([0.2, 0.32]), method=method),
            ext.at_bdc,
            rtol=1e-14,
            err_msg=f"j(π) = -(1 - λ) ({method})",
        )
    grid = np.linspace(0, np.pi, 180001)
    approx = kin.relative_acceleration(grid, 0.32, method="approx")
    # λ = 0.32: by hand arccos(-1/1.28) = 141.38°, -(0.32 + 1/2.56) = -0.710625
    assert_allclose(approx.min(), -0.710625, rtol=1e-9, err_msg="third extremum value")
    assert_allclose(ext.third_value[1], -0.710625, rtol=1e-12, err_msg="-(λ + 1/(8λ)) at λ = 0.32")
    assert_allclose(
        grid[np.argmin(approx)], ext.third_angle[1], atol=2e-4, err_msg="third extremum angle"
    )
    assert_allclose(
        np.degrees(ext.third_angle[1]),
        141.38,
        atol=5e-3,
        err_msg="arccos(-1/(4λ)) = 141.38° at λ = 0.32",
    )
    assert np.isnan(ext.third_angle[0]) and np.isnan(
        ext.third_value[0]
    ), "no third extremum for λ ≤ 1/4"
    assert_allclose(
        kin.relative_acceleration(grid, 0.2, method="approx").min(),
        -0.8,
        rtol=1e-12,
        err_msg="λ = 0.2 ≤ 1/4: the minimum is at BDC, -(1 - λ)",
    )


def test_rod_angle_extremes_and_speed():
    lam = np.array([0.2, 0.25, 0.32])
    grid = np.linspace(0, 2 * np.pi, 3601)[:, None]
    # β_max = arcsin λ (axial) and arcsin(λ(1 + |z|)) with offset
    assert_allclose(
        np.abs(kin.rod_angle(grid, lam)).max(axis=0),
        kin.max_rod_angle(lam),
        rtol=1e-12,
        err_msg="grid max of |β| equals max_rod_angle",
    )
    assert_allclose(kin.max_rod_angle(lam), np.arcsin(lam), rtol=1e-14, err_msg="β_max = arcsin λ")
    assert_allclose(
        np.abs(kin.rod_angle(grid, lam, 0.1)).max(axis=0),
        np.arcsin(lam * 1.1),
        rtol=1e-12,
        err_msg="β_max = arcsin(λ(1 + |z|)) with offset",
    )
    # Li Bin table 1: β_max ≈ ±λ(1 + λ²/6), the series to λ³ (error 3λ⁵/40 < 2.7e-4 at λ = 0.32)
    assert_allclose(
        kin.max_rod_angle(lam),
        lam * (1 + lam**2 / 6),
        atol=3 * 0.32**5 / 40 * 1.1,
        err_msg="β_max ≈ λ(1 + λ²/6) to O(λ⁵)",
    )
    # "当 α = 0°, 180° 时, β̇max = ±λω" (exact at the dead centres of an axial mechanism)
    assert_allclose(
        kin.rod_angular_speed(np.array([[0.0], [np.pi]]), 150.0, lam),
        [150 * lam, -150 * lam],
        rtol=1e-14,
        err_msg="ω_rod = ±λω at 0° and 180°",
    )
    # 15-18° in modern engines (Russian notes) ⇔ λ = 0.26-0.31
    assert (
        15 < np.degrees(kin.max_rod_angle(0.26)) < np.degrees(kin.max_rod_angle(0.31)) < 18.1
    ), "β_max of 15-18° corresponds to λ = 0.26-0.31"


def test_mean_piston_speed():
    # Russian notes: v_ср = S n/30; S = 0.1 m, n = 3000 min⁻¹ → 10 m/s (ω = π·3000/30)
    assert_allclose(
        kin.mean_piston_speed(0.1, np.pi * 3000 / 30), 10.0, rtol=1e-14, err_msg="c_m = S n / 30"
    )
    # Li Bin eq. (10): C_m = (2/π) rω = 0.6366 rω (4 decimals)
    assert_allclose(kin.mean_piston_speed(2.0, 1.0), 0.6366, atol=5e-5, err_msg="c_m = 0.6366 Rω")
    # it is the mean of |v| over a revolution
    grid = np.linspace(0, 2 * np.pi, 20001)
    assert_allclose(
        np.trapezoid(np.abs(kin.relative_velocity(grid, 0.3)), grid) / (2 * np.pi),
        kin.mean_piston_speed(2.0, 1.0),
        rtol=1e-6,
        err_msg="c_m is the mean of |v| over a revolution",
    )


def test_dead_centres_of_a_desaxial_mechanism():
    lam, z = 0.3, 0.08
    c = kin.dead_centres(lam, z)
    assert_allclose(kin.relative_displacement(c.tdc, lam, z), 0, atol=1e-14, err_msg="s = 0 at TDC")
    assert_allclose(
        kin.relative_displacement(c.bdc, lam, z),
        c.stroke_ratio,
        atol=1e-14,
        err_msg="s = stroke ratio at BDC",
    )
    assert_allclose(
        kin.relative_velocity(np.array([c.tdc, c.bdc]), lam, z),
        0,
        atol=1e-14,
        err_msg="v = 0 at both dead centres",
    )
    grid = np.linspace(0, 2 * np.pi, 100001)
    assert_allclose(
        kin.relative_displacement(grid, lam, z).max(),
        c.stroke_ratio,
        rtol=1e-9,
        err_msg="largest s over a revolution is the stroke ratio",
    )
    assert c.stroke_ratio > 2, "an offset lengthens the stroke"
    assert_allclose(
        kin.dead_centres(lam).stroke_ratio, 2, rtol=1e-15, err_msg="axial stroke ratio is 2"
    )


# --- inverse -------------------------------------------------------------------------------------


@pytest.mark.parametrize("z", [0.0, 0.06, -0.1])
@pytest.mark.parametrize("lam", [0.2, 0.32])
def test_inverse_round_trip_exact(lam, z):
    c = kin.dead_centres(lam, z)
    down = np.linspace(c.tdc, c.bdc, 181)
    up = np.linspace(c.bdc, c.tdc + 2 * np.pi, 181)
    for angles, stroke in ((down, "down"), (up, "up")):
        s = kin.relative_displacement(angles, lam, z)
        back = kin.crank_angle_from_displacement(s, lam, z, stroke=stroke)
        # near the dead centres ds/dα → 0 so α is only as good as sqrt(rounding): 1e-7 rad
        assert_allclose(
            back, angles, atol=1e-7, err_msg=f"α(s(α)) on the {stroke} stroke, λ={lam}, z={z}"
        )


def test_inverse_round_trip_approximate():
    # FORMULAS.md A: cos α from the quadratic of the approximate s; its printed root
    # (1/λ)[(1 + λ) - sqrt((1 + λ)² - 2λs)] gives cos α = 0 at s = 0 and is wrong; the
    # root is cos α = (sqrt((1 + λ)² - 2λs) - 1)/λ (s = 0 → 1, s = 2 → -1).
    lam = 0.28
    alpha = np.linspace(0, np.pi, 181)
    s = kin.relative_displacement(alpha, lam, method="approx")
    assert_allclose(
        kin.crank_angle_from_displacement(s, lam, method="approx"),
        alpha,
        atol=1e-7,
        err_msg="approximate inverse, down stroke",
    )
    assert_allclose(
        kin.crank_angle_from_displacement(s, lam, method="approx", stroke="up"),
        2 * np.pi - alpha,
        atol=1e-7,
        err_msg="approximate inverse, up stroke",
    )
    # small s: α ≈ sqrt(2s/(1 + λ))
    small = 1e-6
    assert_allclose(
        kin.crank_angle_from_displacement(small, lam, method="approx"),
        np.sqrt(2 * small / (1 + lam)),
        rtol=1e-5,
        err_msg="α ≈ sqrt(2s/(1 + λ)) for small s",
    )
    with pytest.raises(ValueError, match="axial approximate displacement only"):
        kin.crank_angle_from_displacement(0.5, lam, 0.05, method="approx")


def test_inverse_rejects_positions_outside_the_stroke():
    with pytest.raises(ValueError, match=r"displacement must lie in \[0, stroke ratio\], got 2.1"):
        kin.crank_angle_from_displacement(2.1, 0.3)
    with pytest.raises(ValueError, match="stroke must be 'down' or 'up'"):
        kin.crank_angle_from_displacement(1.0, 0.3, stroke="sideways")


# --- table, broadcasting, validation ----------------------------------------------------------


def test_kinematics_table():
    table = kin.kinematics_table(0.25, step_deg=5)
    assert list(table.columns) == ["alpha_deg", "beta_deg", "s", "v", "j"], "table columns"
    assert len(table) == 73 and table["alpha_deg"].iloc[-1] == 360, "0..360° in 5° steps is 73 rows"
    row = table.set_index("alpha_deg").loc[90.0]
    # by hand, λ = 0.25 at 90°: β = arcsin 0.25 = 14.4775°, s = 1 + (1 - cos β)/λ = 1.127017,
    # v = 1, j = -tan β = -0.258199
    assert_allclose(
        row[["beta_deg", "s", "v", "j"]].to_numpy(float),
        [14.477512, 1.127017, 1.0, -0.258199],
        atol=5e-7,
        err_msg="λ = 0.25 row at 90°",
    )
    approx = kin.kinematics_table(0.25, step_deg=30, method="approx").set_index("alpha_deg")
    assert_allclose(
        approx.loc[90.0, ["s", "v", "j"]].to_numpy(float),
        [1.125, 1.0, -0.25],
        atol=1e-15,
        err_msg="approximate row at 90°: s = 1 + λ/2, v = 1, j = -λ",
    )
    assert table.attrs["lambda_"] == 0.25, "attrs carry λ"
    with pytest.raises(ValueError, match="step_deg must divide 360 evenly, got 7"):
        kin.kinematics_table(0.25, step_deg=7)


def test_formulas_broadcast_and_keep_scalars():
    out = kin.relative_acceleration(ALPHA, LAMBDAS, OFFSETS)
    assert out.shape == (3, 3, ALPHA.size), "broadcast over offset × lambda × angle"
    assert np.ndim(kin.relative_velocity(0.3, 0.3)) == 0, "scalar in, scalar out"
    assert_array_less(0, kin.relative_displacement(ALPHA[1:-1], LAMBDAS) + 1e-15)


def test_input_checks_name_the_parameter_and_the_fix():
    with pytest.raises(
        ValueError, match=r"lambda_ must be in \(0, 1\), got 1.3.*Fix: give lambda_ = R/L"
    ):
        kin.relative_displacement(0.0, 1.3)
    with pytest.raises(
        ValueError, match=r"offset_ratio must satisfy lambda_\*\(1 \+ \|z\|\) < 1, got z = 3"
    ):
        kin.rod_angle(0.0, 0.3, np.array([0.0, 3.0]))
    with pytest.raises(ValueError, match="method must be 'exact' or 'approx', got 'series'"):
        kin.relative_velocity(0.0, 0.3, method="series")
    with pytest.raises(ValueError, match="quantity must be 's', 'v' or 'j', got 'a'"):
        kin.max_approximation_error(0.3, quantity="a")
