"""Slips inside a lab's formulas (:mod:`processing.checking.input_slips`, the constants of
:data:`processing.checking.grading.CONSTANT_SLIPS`) named through ``dynlab check``, and a student's
Russian and min⁻¹ read in ``[reported]``.

Each slip is reproduced as the student makes it — the inputs changed as the slip changes them
and reduced again, or the constant slipped in the arithmetic — and reported in the sample's
file: the check must call it wrong and name it; the right values of the same file stay right.
"""
import math
import warnings
from pathlib import Path

import pytest

from labs.teachers.check import check
from labs.registry import lab_module
from processing.checking.input_slips import slipped_inputs
from processing.measurement import load, read_toml

ROOT = Path(__file__).resolve().parents[1]
LAB1 = ROOT / "sample_data" / "lab1" / "flywheel.toml"
LAB8 = ROOT / "sample_data" / "lab8" / "d120.toml"
DYNCALC = ROOT / "sample_data" / "dyncalc" / "car_petrol.toml"


def reported(folder: Path, sample: Path, lines: list[str]) -> Path:
    path = folder / sample.name
    path.write_text(sample.read_text(encoding="utf-8") + "\n[reported]\n" + "\n".join(lines)
                    + "\n", encoding="utf-8")
    return path


def slipped(sample: Path, slip: str, symbol: str):
    """Our results and the results of the sample's inputs as ``slip`` of ``symbol`` leaves
    them."""
    data = read_toml(sample)
    module = lab_module(data["lab"])
    inputs = load(sample, module.SPEC, data)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ours = module.reduce(inputs, n_samples=0).results
        changed = next(c for s, sym, c in slipped_inputs(inputs)
                       if s.name == slip and sym == symbol)
        return ours, module.reduce(changed, n_samples=0).results


@pytest.mark.parametrize("sample, slip, symbol, name", [
    (LAB1, "period_not_squared", "t, t_p", "J_trifilar"),
    (LAB1, "diameter_for_radius_in_formula", "R₁", "J_trifilar"),
    (LAB1, "diameters_for_radii_in_formula", "R, r", "J_analytic"),
    (LAB1, "diameters_for_radii_in_formula", "R, r", "m_analytic"),
    (LAB8, "rpm_as_rad_s_in_formula", "n", "M_r"),
    (LAB8, "radius_for_diameter_in_formula", "r", "M_r"),
    (DYNCALC, "diameter_for_radius_in_formula", "S", "N_i"),
])
def test_a_slip_inside_the_formula_is_named_by_its_input(tmp_path, sample, slip, symbol, name):
    ours, theirs = slipped(sample, slip, symbol)
    right = next(n for n, r in ours.items() if n != name and r.key and math.isfinite(r.value)
                 and r.value and r.unit)
    path = reported(tmp_path, sample, [f'{name} = "{theirs[name].value:.4g} {ours[name].unit}"',
                                       f'{right} = "{ours[right].value:.5g} '
                                       f'{ours[right].unit}"'])
    found = {v.name: v for v in check(path).verdicts}
    assert found[name].verdict == "wrong" and found[name].slip.name == slip, found[name]
    assert symbol.split(",")[0] in found[name].slip.text["en"]
    assert found[right].verdict in ("right", "over-precise"), found[right]


@pytest.mark.parametrize("factor, slip", [(1 / (4 * math.pi ** 2), "four_pi_squared_dropped"),
                                          (1 / math.pi, "pi_for_pi_squared")])
def test_a_constant_slipped_in_the_arithmetic_is_named(tmp_path, factor, slip):
    ours, _ = slipped(LAB1, "period_not_squared", "t, t_p")
    value = factor * ours["J_pendulum_cm"].value
    found = check(reported(tmp_path, LAB1, [f'J_pendulum_cm = "{value:.4g} kg*m^2"']))
    (v,) = found.verdicts
    assert v.verdict == "wrong" and v.slip.name == slip


@pytest.mark.parametrize("factor, slip", [((30 / math.pi) ** 2, "omega_for_n_squared"),
                                          ((math.pi / 30) ** 2, "n_for_omega_squared")])
def test_omega_for_n_in_the_flywheels_formula_alone_is_named(tmp_path, factor, slip):
    """ω put for n only in the flywheel's I = 900·A/(π²·n²·δ) (n stays right in the forces):
    I and m of the flywheel ×(30/π)², named; the rest of the file right."""
    ours, _ = slipped(DYNCALC, "diameter_for_radius_in_formula", "S")
    lines = [f'{n} = "{factor * ours[n].value:.4g} {ours[n].unit}"'
             for n in ("I_flywheel", "m_flywheel")]
    found = check(reported(tmp_path, DYNCALC, [*lines, f'M_mean = "{ours["M_mean"].value:.4g} '
                                                        f'{ours["M_mean"].unit}"']))
    verdicts = {v.name: v for v in found.verdicts}
    assert {verdicts[n].slip.name for n in ("I_flywheel", "m_flywheel")} == {slip}
    assert verdicts["M_mean"].verdict == "right"


def test_gauge_for_absolute_pressure_fires_on_the_courseworks_pressures(tmp_path):
    ours, _ = slipped(DYNCALC, "diameter_for_radius_in_formula", "S")
    assert ours["p_b"].unit == "kg/m/s^2"
    value = (ours["p_b"].value - 1e5) / 1e6
    (v,) = check(reported(tmp_path, DYNCALC, [f'p_b = "{value:#.4g} MPa"'])).verdicts
    assert v.verdict == "wrong" and v.slip.name == "gauge_pressure_minus"


def test_a_students_russian_and_min_1_are_read(tmp_path):
    """A decimal comma, кг*м^2, об/мин and a right ω written in min⁻¹ (as inputs read it:
    revolutions a minute) are read and judged; nothing is refused."""
    ours, _ = slipped(LAB8, "rpm_as_rad_s_in_formula", "n")
    n = ours["omega"].value * 30 / math.pi
    m_r = f'{ours["M_r"].value:.4g}'.replace(".", ",")
    found = check(reported(tmp_path, LAB8, [f'omega = "{n:.0f} min^-1"', f'M_r = "{m_r} Н*м"']))
    verdicts = {v.name: v.verdict for v in found.verdicts}
    assert verdicts["omega"] in ("right", "over-precise"), found.verdicts
    assert verdicts["M_r"] in ("right", "rounded"), found.verdicts
    ours1, _ = slipped(LAB1, "period_not_squared", "t, t_p")
    j = f'{ours1["J_trifilar"].value:.4f}'.replace(".", ",")
    found = check(reported(tmp_path, LAB1, [f'J_trifilar = "{j} кг*м^2"']))
    assert found.verdicts[0].verdict == "right"
    found = check(reported(tmp_path, LAB8, [f'omega = "{n:.0f} об/мин"']))
    assert found.verdicts[0].verdict == "right"
