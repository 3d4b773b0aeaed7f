"""Each lab's own classic slips (``SLIPS`` of labs 3–9) found by name through ``dynlab check``.

Every slip is reproduced as the student makes it — the measurement file changed as the slip
changes it and reduced, or the student's arithmetic done with the slip — and the value so made
is reported in the right file: the check must call it wrong and name that slip.
"""
import math
from pathlib import Path

import numpy as np
import pytest

from labs import (lab3_speed_irregularity as lab3, lab4_vibration as lab4, lab5_valve_stiffness as lab5, lab6_valve_dynamics as lab6,
                  lab7_torsiograph as lab7, lab8_balancing as lab8, lab9_damper as lab9)
from labs.teachers.check import check
from labs.registry import evaluate

SEED = 1


def written(folder: Path, module, **options) -> Path:
    return module.write_synthetic(folder, SEED, **options)["toml"]


@pytest.fixture(scope="module")
def variants(tmp_path_factory):
    """One variant per lab (the recorded labs with few records), written once."""
    root = tmp_path_factory.mktemp("slips")
    return {
        "lab3": written(root / "lab3", lab3),
        "lab4": written(root / "lab4", lab4, speeds=(1000.0, 2000.0), step=1000.0,
                        cut_speed=2000.0, duration=1.2),
        "lab5": written(root / "lab5", lab5),
        "lab6": written(root / "lab6", lab6, speeds=(1500.0, 2000.0), clearances=(0.5e-3,)),
        "lab7": written(root / "lab7", lab7, speeds=(1400.0, 1600.0), step=200.0),
        "lab8": written(root / "lab8", lab8),
        "lab9": written(root / "lab9", lab9),
    }


@pytest.fixture(scope="module")
def ours(variants):
    return {lab: evaluate(path, n_samples=500).results for lab, path in variants.items()}


def reduced(path: Path, module) -> dict:
    """The results of a file as the lab reduces it (a slipped file's results may make no
    physical sense, which ``evaluate`` would refuse)."""
    from processing.measurement import load

    return module.reduce(load(path, module.SPEC), n_samples=500).results


def slipped_file(path: Path, old: str, new: str) -> Path:
    """A copy of the measurement file beside it, with one text changed as the slip changes it."""
    text = path.read_text(encoding="utf-8")
    assert old in text, old
    out = path.with_name(f"slipped_{path.name}")
    out.write_text(text.replace(old, new), encoding="utf-8")
    return out


def found(path: Path, name: str, value: float, unit: str):
    """The verdict on ``value`` reported for ``name`` in a copy of the file."""
    sub = path.with_name(f"submitted_{path.name}")
    sub.write_text(path.read_text(encoding="utf-8")
                   + f'\n[reported]\n{name} = "{value:.4g} {unit}"\n', encoding="utf-8")
    (v,) = check(sub, n_samples=500).verdicts
    return v


def assert_named(variants, ours, lab: str, name: str, value: float, slip: str,
                 shift: float = 0.05):
    """The slipped value, off ours by more than ``shift``, is wrong and named ``slip``."""
    r = ours[lab][name]
    assert abs(value / r.value - 1) > shift, (name, value, r.value)
    v = found(variants[lab], name, value, r.unit)
    assert v.verdict == "wrong" and v.slip is not None and v.slip.name == slip, \
        (name, value, r.value, v.verdict, v.slip and v.slip.name)


# ----------------------------------------------------------------------------- lab 3

def test_lab3_slips(variants, ours):
    """The teeth counted for the pitches (n = 60 f/z with z = 58 on the 60−2 wheel), and δ
    from half the swing."""
    r = ours["lab3"]
    z, missing = 60, 2
    assert "z = 60\nmissing = 2" in variants["lab3"].read_text()
    tooth_frequency = r["omega_mean_1"].value * z / (2 * np.pi)
    assert_named(variants, ours, "lab3", "omega_mean_1",
                 2 * np.pi * tooth_frequency / (z - missing), "teeth_for_pitches",
                 shift=0.03)          # 60/58: 3.4 %, beyond the 1 % tolerance
    half = (r["omega_max_2"].value - r["omega_min_2"].value) / (2 * r["omega_mean_2"].value)
    assert_named(variants, ours, "lab3", "delta_2", half, "half_swing")


# ----------------------------------------------------------------------------- lab 4

@pytest.mark.parametrize("chart, read_as, name, slip", [
    ("mV/(m/s^2)", "mV/g", "a_rms_1", "sensitivity_per_g"),
    ("mV/g", "mV/(m/s^2)", "v_pp_2", "sensitivity_per_m_s2")])
def test_lab4_sensitivity_in_the_wrong_unit(variants, ours, chart, read_as, name, slip):
    """The chart's number taken with the other unit: the record's volts divided by it."""
    S = lab4.sensitivity("10.2 mV/(m/s^2)").value
    number = 10.2 if chart == "mV/(m/s^2)" else 10.2 * lab4.G_RATIO
    read = lab4.sensitivity(f"{number} {read_as}").value
    volts = ours["lab4"][name].value * S
    assert_named(variants, ours, "lab4", name, volts / read, slip)


def test_lab4_amplitude_for_the_range(variants, ours):
    swing = ours["lab4"]["x_pp_3"].value
    assert_named(variants, ours, "lab4", "x_pp_3", swing / 2, "amplitude_for_range")


# ----------------------------------------------------------------------------- lab 5

@pytest.mark.parametrize("old, new, names, slip", [
    ('i1 = "10 ± 0.05"', 'i1 = "1 ± 0.05"', ("c_rocker", "c_total", "nu_natural"),
     "lever_ratio_forgotten"),
    (None, None, ("c_shaft", "c_rod_load", "c_cam"), "rocker_ratio_inverted")])
def test_lab5_ratio_slips(variants, ours, old, new, names, slip):
    """The file as the student used it, reduced: the weights for the load, or 1/i."""
    path = variants["lab5"]
    if old is None:
        i = float(next(line for line in path.read_text().splitlines()
                       if line.startswith("i = ")).split('"')[1].split()[0])
        old = f'i = "{i:.3f} ± 0.01"'
        new = f'i = "{1 / i:.6f} ± 0.01"'
    student = reduced(slipped_file(path, old, new), lab5)
    for name in names:
        assert_named(variants, ours, "lab5", name, student[name].value, slip)


# ----------------------------------------------------------------------------- lab 6

def test_lab6_valves_swapped(variants, ours):
    """Each valve's channel named for the other's: the timing read off the other trace."""
    path = variants["lab6"]
    text = path.read_text(encoding="utf-8")
    swapped = text.replace('name = "in"\n', 'name = "in"\nchannel = "ex"\n').replace(
        'name = "ex"\n', 'name = "ex"\nchannel = "in"\n')
    assert swapped != text
    slipped = path.with_name("swapped.toml")
    slipped.write_text(swapped, encoding="utf-8")
    student = reduced(slipped, lab6)
    for name in ("advance_in_1", "lag_ex_2"):
        assert_named(variants, ours, "lab6", name, student[name].value, "valves_swapped")


def test_a_stretch_fitted_again_is_the_fit_made_before(monkeypatch):
    """The valves-swapped slip reduces every trace again: inside one scope a free oscillation
    over the same stretch (another preload moves the closing, not the stretch fitted) is the
    fit made before, the same as a fresh one; another trace, or the same outside the scope,
    is fitted anew."""
    from processing.inputs.reuse import scope
    from processing.valvetrain import valve_force as vf

    fits, fit = [], vf.fit_baselines_each
    monkeypatch.setattr(vf, "fit_baselines_each", lambda *a, **k: fits.append(1) or fit(*a, **k))
    t = np.arange(0, 0.04, 1e-4)
    x = 50 + 300 * t + 20 * np.exp(-150 * t) * np.cos(2 * np.pi * 450 * t)
    with scope():
        fresh = vf.free_oscillation(t, x, 0.0, 0.04)
        again = vf.free_oscillation(t, x, 0.0, 0.0395)
        assert len(fits) == 1
        vf.free_oscillation(t, 1.01 * x, 0.0, 0.04)
        assert len(fits) == 2 and fresh.fit.delta == again.fit.delta
    anew = vf.free_oscillation(t, x, 0.0, 0.0395)
    assert len(fits) == 3
    assert (anew.frequency, anew.u_frequency) == (again.frequency, again.u_frequency)


def test_lab6_camshaft_and_crank_angles(variants, ours):
    """φ = 360 T_open/T_cam with T_cam one crankshaft revolution, and the cam angle reported
    for the crank angle."""
    r = ours["lab6"]
    T_rev = 2 * np.pi / r["n_1"].value
    T_open = r["phi_in_1"].value / (2 * np.pi) * 2 * T_rev
    assert_named(variants, ours, "lab6", "phi_in_1", 2 * np.pi * T_open / T_rev,
                 "camshaft_turn_as_crank_turn")
    assert_named(variants, ours, "lab6", "phi_crank_ex_2", r["phi_ex_2"].value,
                 "cam_angle_for_crank_angle")


# ----------------------------------------------------------------------------- lab 7

def test_lab7_slips(variants, ours):
    r = ours["lab7"]
    assert_named(variants, ours, "lab7", "phi_max", 2 * r["phi_max"].value,
                 "range_for_amplitude")
    path = variants["lab7"]
    R = float(path.read_text().split("[calibration]\nR = \"")[1].split()[0]) * 1e-3
    assert_named(variants, ours, "lab7", "l", r["l"].value * R / (2 * R),
                 "lever_diameter_for_radius")
    nu_hz, n_rpm = r["nu_2"].value, r["n_2"].value * 30 / math.pi
    assert_named(variants, ours, "lab7", "K_2", nu_hz / n_rpm, "order_from_rpm")


# ----------------------------------------------------------------------------- lab 8

@pytest.mark.parametrize("change, names, slip", [
    ("swap", ("M_r", "M_j1_max"), "rod_shares_swapped"),
    ("m_shp", ("P_j2_max", "D_2"), "piston_only_reciprocating"),
    ("m_shk", ("M_r", "m_x"), "crank_end_left_out")])
@pytest.mark.filterwarnings("ignore::processing.diagnostics.ImplausibleValueWarning")
def test_lab8_mass_slips(variants, ours, change, names, slip):
    path = variants["lab8"]
    lines = path.read_text(encoding="utf-8").splitlines()
    line = {k: next(x for x in lines if x.startswith(f"{k} =")) for k in ("m_shp", "m_shk")}
    if change == "swap":
        text = path.read_text(encoding="utf-8").replace(line["m_shp"], "@").replace(
            line["m_shk"], line["m_shp"].replace("m_shp", "m_shk")).replace(
            "@", line["m_shk"].replace("m_shk", "m_shp"))
        slipped = path.with_name("slipped.toml")
        slipped.write_text(text, encoding="utf-8")
    else:
        slipped = slipped_file(path, line[change], f'{change} = "1e-9 kg"')  # none
    student = reduced(slipped, lab8)
    for name in names:
        assert_named(variants, ours, "lab8", name, student[name].value, slip)


# ----------------------------------------------------------------------------- lab 9

def test_lab9_slips(variants, ours):
    r = ours["lab9"]
    ratio = math.exp(r["log_decrement"].value)             # φ_n/φ_{n+1}
    assert_named(variants, ours, "lab9", "log_decrement", math.log10(ratio), "common_logarithm")
    I = float(variants["lab9"].read_text().split('I = "')[1].split()[0])
    xi = I * r["omega_d"].value * math.log10(ratio) / math.pi
    assert_named(variants, ours, "lab9", "xi_dynamic", xi, "common_logarithm")
    M_phi = 2 * r["E_max"].value                             # M_max φ_max
    assert_named(variants, ours, "lab9", "E_max", M_phi, "energy_without_half")
    assert_named(variants, ours, "lab9", "xi_static_1",
                 r["E_loss_1"].value / (2 * r["E_max_1"].value), "energy_without_half")


def test_a_stage_reused_by_content_gives_a_copy_and_its_warnings_again():
    """Inside a scope a stage marked by_content runs once per content of what decides it
    (an array's bytes, not its identity), the caller gets its own copy, and the warnings it
    raised are raised again; outside every scope it runs each time."""
    import warnings

    from processing.inputs.reuse import by_content, scope

    runs = []

    @by_content(lambda x, label: x)
    def stage(x, label):
        runs.append(label)
        warnings.warn(UserWarning(f"seen {label}"))
        return {"sum": float(x.sum()), "label": label}

    x = np.arange(5.0)
    with scope(), warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        first = stage(x, "a")
        first["sum"] = -1.0
        again = stage(x.copy(), "b")
        stage(x + 1, "c")
    assert runs == ["a", "c"] and again == {"sum": 10.0, "label": "a"}
    assert [str(w.message) for w in caught] == ["seen a", "seen a", "seen c"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        stage(x, "d")
    assert runs[-1] == "d"


def test_a_stage_of_many_items_computes_only_the_items_not_met_before():
    """Inside a scope a stage marked by_content_each is passed only the items whose content
    it has not met (each once), and returns every item's result in order; outside every
    scope it is passed them all."""
    from processing.inputs.reuse import by_content_each, scope

    passed = []

    @by_content_each
    def stage(items):
        passed.append(len(items))
        return [float(x.sum()) for x in items]

    a, b = np.arange(3.0), np.arange(4.0)
    with scope():
        assert stage([a, b, a.copy()]) == [3.0, 6.0, 3.0]
        assert stage([b.copy(), a + 1, b]) == [6.0, 6.0, 6.0]
    assert passed == [2, 1]
    assert stage([a, a]) == [3.0, 3.0] and passed[-1] == 2


# ------------------------------------------------------------ formula slips, recorded labs

@pytest.mark.parametrize("lab, slip, symbol", [
    ("lab3", "rpm_as_rad_s_in_formula", "n"),
    ("lab7", "diameter_for_radius_in_formula", "R")])
def test_a_formula_slip_is_named_in_a_recorded_lab(variants, ours, lab, slip, symbol):
    """A lab whose file names recordings is reduced again for the slips of its formula's
    inputs (the recordings' analysis reused): a result the slip moves, written as the slipped
    reduction gives it, is named by that slip — where no other slip gives the same value."""
    from labs.teachers.check import _lab_slips
    from processing.checking.grading import CONSTANT_SLIPS, FACTOR_SLIPS
    from processing.checking.input_slips import slipped_inputs
    from processing.measurement import load

    module = {"lab3": lab3, "lab4": lab4, "lab7": lab7}[lab]
    inputs = load(variants[lab], module.SPEC)
    changed = next(c for s, sym, c in slipped_inputs(inputs) if s.name == slip and sym == symbol)
    student = module.reduce(changed, n_samples=500).results
    r = ours[lab]
    own = _lab_slips(module, r, inputs, {"n_samples": 500})

    def alone(name: str) -> bool:
        value = student[name].value
        others = [s.candidate(name, r[name].value, r[name].unit)
                  for s in (*FACTOR_SLIPS, *CONSTANT_SLIPS, *own)]
        return abs(value / r[name].value - 1) > 0.05 and not any(
            o is not None and abs(o / value - 1) < 0.02 for o in others)

    name = next(n for n in r if n in student and r[n].value and alone(n))
    assert_named(variants, ours, lab, name, student[name].value, slip)
