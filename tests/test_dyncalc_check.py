"""The coursework's tables checked row by row (``[reported.tables]``,
:mod:`labs.teachers.dyncalc_check`).

Every student's table here is made as a student makes it — from the task's data with the
textbook's formulas (Kolchin: the two-harmonic piston displacement and acceleration, the exact
rod angle β = arcsin(λ sin α)), at the student's own step, written to the decimals a
spreadsheet shows. Right tables must be right whatever the step, the separator or the units;
each slip is reproduced in that independent arithmetic, then the check must find its root
column and name it.
"""
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from labs import dyncalc as dc
from labs.teachers.check import check
from labs.teachers.dyncalc_check import FLOOR_SHARE
from labs.teachers.dyncalc_tables import read_table
from processing.diagnostics import InputError
from processing.units import parse_quantity

SAMPLES = Path(__file__).resolve().parents[1] / "sample_data" / "dyncalc"
CAR, DIESEL = SAMPLES / "car_petrol.toml", SAMPLES / "marine_diesel.toml"


def task(sample: Path) -> dict:
    """The task's data in SI, read from the file as a student reads the assignment."""
    d = tomllib.loads(sample.read_text(encoding="utf-8"))
    e, c, g, m = d["engine"], d["cycle"], d["geometry"], d["masses"]
    order = [int(x) for x in e.get("firing_order", "").split("-") if x] or \
        list(range(1, e["i"] + 1))
    return {"i": e["i"], "order": order, "omega": math.pi * e["n"] / 30,
            "p_a": c["p_a"] * 1e6, "p_z": c["p_z"] * 1e6, "p_r": c["p_r"] * 1e6,
            "p_0": c["p_0"] * 1e6, "eps": c["eps"], "rho": c.get("rho", 1.0), "n1": c["n1"],
            "n2": c["n2"], "D": g["D"] / 1e3, "R": g["S"] / 2e3, "lambda": g["lambda"],
            "m_j": parse_quantity(m["m_j"], "kg")[0] if "m_j" in m else None,
            "m_spec": parse_quantity(m["m_j_spec"], "kg/m^2")[0] if "m_j_spec" in m else None}


def forces(e: dict, alpha_deg, slip: str = "") -> dict:
    """One cylinder's table by Kolchin's formulas (four-stroke, α from TDC of intake; at a
    stroke's start the new stroke's pressure), with ``slip`` made as a student makes it."""
    a = np.radians(np.asarray(alpha_deg, dtype=float))
    R, lam, w = e["R"], e["lambda"], e["omega"]
    area = math.pi * e["D"] ** 2 / 4
    used = 4 * area if slip == "bore_as_radius" else area
    m = e["m_spec"] if e["m_spec"] is not None else \
        e["m_j"] if slip == "mass_not_per_area" else e["m_j"] / used
    swept = area * 2 * R
    V_c = swept / (e["eps"] - 1)
    V_a, V_z = V_c + swept, e["rho"] * V_c
    V = V_c + area * R * ((1 - np.cos(a)) + lam / 4 * (1 - np.cos(2 * a)))
    stroke = (np.floor(a / np.pi + 1e-9) % 4).astype(int)
    n1, n2 = (e["n2"], e["n1"]) if slip == "exponents_swapped" else (e["n1"], e["n2"])
    p_g = np.select([stroke == 0, stroke == 1, stroke == 2, stroke == 3],
                    [e["p_a"] + 0 * a, e["p_a"] * (V_a / V) ** n1,
                     e["p_z"] * (V_z / np.maximum(V, V_z)) ** n2, e["p_r"] + 0 * a])
    dp_g = p_g - (0.0 if slip == "p0_not_subtracted" else e["p_0"])
    p_j = -m * R * w ** 2 * (np.cos(a) + lam * np.cos(2 * a)) * (-1 if slip == "pj_sign" else 1)
    p = dp_g + p_j
    P = p * used
    beta = np.arcsin(lam * np.sin(a))
    b, x = beta, a
    if slip == "beta_neglected":
        b = 0 * beta
    elif slip == "beta_sign":
        b = -beta
    elif slip == "beta_degrees":
        b = np.degrees(beta)
    elif slip == "alpha_degrees":
        x = np.degrees(a)
        b = np.arcsin(lam * np.sin(x))
    out = {"beta": beta, "p_g": p_g, "dp_g": dp_g, "p_j": p_j, "p": p, "P": P,
           "tan_beta": np.tan(b), "inv_cos_beta": 1 / np.cos(b),
           "cos_ab": np.cos(x + b) / np.cos(b), "sin_ab": np.sin(x + b) / np.cos(b)}
    for force, factor in (("N", "tan_beta"), ("S", "inv_cos_beta"), ("K", "cos_ab"),
                          ("T", "sin_ab")):
        out[force] = (-1 if slip == f"{force}_sign" else 1) * P * out[factor]
    out["M"] = out["T"] * R
    return out


def summed(e: dict, alpha_deg, slip: str = "") -> dict:
    """T of every cylinder at cylinder 1's α (cylinder c lags θ × its place in the firing
    order, θ = 720°/i), ΣT and M."""
    theta = (360.0 if slip == "firing_interval" else 720.0) / e["i"]
    order = list(range(1, e["i"] + 1)) if slip == "firing_order_ignored" else e["order"]
    alpha = np.asarray(alpha_deg, dtype=float)
    out = {f"T{c}": forces(e, alpha - theta * order.index(c), slip)["T"]
           for c in range(1, e["i"] + 1)}
    out["sum"] = sum(out.values())
    out["M"] = out["sum"] * e["R"]
    return out


def polytrope(e: dict, kind: str, slip: str = "") -> tuple[np.ndarray, dict]:
    """V_a/V_x = 1 … ε (compression) or V_x/V_z = 1 … ε/ρ (expansion), V_x and p_x."""
    area = math.pi * e["D"] ** 2 / 4
    V_c = area * 2 * e["R"] / (e["eps"] - 1)
    top = e["eps"] if kind == "compression" else e["eps"] / e["rho"]
    ratio = np.arange(1.0, math.floor(top) + 1)
    if top - ratio[-1] > 1e-9:
        ratio = np.append(ratio, top)
    n1, n2 = (e["n2"], e["n1"]) if slip == "exponents_swapped" else (e["n1"], e["n2"])
    if kind == "compression":
        return ratio, {"V_x": V_c * e["eps"] / ratio, "p_x": e["p_a"] * ratio ** n1}
    return ratio, {"V_x": e["rho"] * V_c * ratio, "p_x": e["p_z"] * ratio ** -n2}


# header, factor from SI, decimals
COLUMN = {"beta": ("β, °", 180 / math.pi, 2), "p_g": ("p_g, MPa", 1e-6, 4),
          "dp_g": ("Δp_g, MPa", 1e-6, 4), "p_j": ("p_j, MPa", 1e-6, 4), "p": ("p, MPa", 1e-6, 4),
          "P": ("P, kN", 1e-3, 3), "tan_beta": ("tg β", 1, 4), "inv_cos_beta": ("1/cos β", 1, 4),
          "cos_ab": ("cos(α+β)/cos β", 1, 4), "sin_ab": ("sin(α+β)/cos β", 1, 4),
          "N": ("N, kN", 1e-3, 3), "S": ("S, kN", 1e-3, 3), "K": ("K, kN", 1e-3, 3),
          "T": ("T, kN", 1e-3, 3), "M": ("M, N·m", 1, 1), "sum": ("ΣT, kN", 1e-3, 3),
          "V_x": ("V_x, L", 1e3, 5), "p_x": ("p_x, MPa", 1e-6, 4),
          # the same quantities in other units: T in N, per piston area, as drawn
          "T_N": ("T, N", 1, 1), "T_spec": ("p_T, MPa", 1e-6, 4), "T_mm": ("T, mm", 1e3, 1)}


def write_csv(path: Path, first: tuple[str, np.ndarray, int], columns: dict, sep: str = ",",
              heads: dict | None = None) -> Path:
    """A spreadsheet's CSV export: the header, then each row as shown (a decimal comma when
    the separator is a semicolon, as a Russian Excel writes it)."""
    heads = heads or {}
    names = [first[0]] + [heads.get(k) or COLUMN.get(k, (f"{k}, kN",))[0] for k in columns]
    rows = [sep.join(f'"{n}"' if sep in n else n for n in names)]
    for r in range(len(first[1])):
        cells = [f"{first[1][r]:.{first[2]}f}"]
        for k, v in columns.items():
            _, factor, decimals = COLUMN.get(k, ("", 1e-3, 3))
            cells.append(f"{v[r] * factor:.{decimals}f}")
        if sep == ";":
            cells = [c.replace(".", ",") for c in cells]
        rows.append(sep.join(cells))
    path.write_text("\n".join(rows) + "\n", encoding="utf-8")
    return path


def submit(folder: Path, sample: Path, tables: dict, extra: str = "") -> Path:
    """The sample with the tables (name → file) reported."""
    lines = "\n".join(f'{k} = "{v.name}"' for k, v in tables.items())
    path = folder / "coursework.toml"
    path.write_text(sample.read_text(encoding="utf-8") + f"\n{extra}\n[reported.tables]\n"
                    f"{lines}\n", encoding="utf-8")
    return path


def table_csv(folder: Path, e: dict, kind: str, slip: str = "", step: float = 15.0,
              sep: str = ",") -> Path:
    if kind == "forces":
        alpha = np.arange(0.0, 720.0 + step / 2, step)
        return write_csv(folder / "forces.csv", ("α, °", alpha, 0), forces(e, alpha, slip), sep)
    if kind == "summed":
        alpha = np.arange(0.0, 720.0 / e["i"] + step / 2, step)
        cols = summed(e, alpha, slip)
        return write_csv(folder / "summed.csv", ("α₁, °", alpha, 0), cols, sep,
                         {f"T{c}": f"T{c}, kN" for c in range(1, e["i"] + 1)})
    ratio, cols = polytrope(e, kind, slip)
    head = "V_a/V_x" if kind == "compression" else "V_x/V_z"
    return write_csv(folder / f"{kind}.csv", (head, ratio, 3), cols, sep)


def judged(folder: Path, sample: Path, kinds, **kw) -> dict:
    e = task(sample)
    files = {k: table_csv(folder, e, k, **kw) for k in kinds}
    return {t.name: t for t in check(submit(folder, sample, files)).tables}


# ----------------------------------------------------------------------------- right tables

@pytest.mark.parametrize("sample", [CAR, DIESEL], ids=["car", "diesel"])
@pytest.mark.parametrize("step, sep", [(15.0, ","), (10.0, ";"), (30.0, "\t")])
def test_right_tables_at_any_step_and_separator_are_right(tmp_path, sample, step, sep):
    found = judged(tmp_path, sample, ("forces", "summed", "compression", "expansion"),
                   step=step, sep=sep)
    assert {n: t.verdict for n, t in found.items()} == dict.fromkeys(found, "right"), \
        {n: t.cause() for n, t in found.items()}
    assert found["forces"].cells == 15 * len(np.arange(0, 720 + step / 2, step))


def test_either_side_of_a_pressure_jump_is_right(tmp_path):
    """At 360° the diagram jumps from p_c to p_z: a student may list either."""
    e = task(CAR)
    alpha = np.arange(0.0, 721.0, 15.0)
    cols = forces(e, alpha)
    before = forces(e, alpha - 1e-5)          # the end of compression at 360°
    k = int(np.flatnonzero(alpha == 360.0)[0])
    assert before["p_g"][k] < 0.5 * cols["p_g"][k]       # p_c, not p_z
    for name in cols:
        cols[name][k] = before[name][k]
    path = write_csv(tmp_path / "forces.csv", ("α, °", alpha, 0), cols)
    (t,) = check(submit(tmp_path, CAR, {"forces": path})).tables
    assert t.verdict == "right", t.cause()


def test_the_tolerance_floor_near_a_zero_crossing(tmp_path):
    """T is 0 at the dead centres: a cell there is judged within FLOOR_SHARE × rel_tol × the
    column's largest |T| (plus half its last digit), not within 1 % of 0."""
    e = task(CAR)
    alpha = np.arange(0.0, 721.0, 15.0)
    cols = {"P": forces(e, alpha)["P"], "T": forces(e, alpha)["T"]}
    t_max = np.max(np.abs(forces(e, np.arange(0.0, 720.0, 1.0))["T"]))
    floor = FLOOR_SHARE * 0.01 * t_max
    k = int(np.flatnonzero(alpha == 180.0)[0])     # BDC: T = 0
    for shift, verdict in ((0.5 * floor, "right"), (3 * floor, "wrong")):
        cols["T"][k] = shift
        path = write_csv(tmp_path / "forces.csv", ("α, °", alpha, 0),
                         {"P": cols["P"], "T_N": cols["T"]})
        (t,) = check(submit(tmp_path, CAR, {"forces": path})).tables
        assert t.verdict == verdict, (shift, floor, t.cause())
    assert t.first_row == k + 2 and t.first_column == "T" and t.wrong == 1


def test_forces_per_piston_area_and_as_drawn(tmp_path):
    """A force in MPa is per piston area; in mm, its ordinate at the drawing's μ_p."""
    e = task(CAR)
    area = math.pi * e["D"] ** 2 / 4
    alpha = np.arange(0.0, 721.0, 15.0)
    f = forces(e, alpha)
    mu_p = 0.05e6 / 1e-3                     # 0.05 MPa/mm
    specific = write_csv(tmp_path / "forces.csv", ("α, °", alpha, 0), {"T_spec": f["T"] / area})
    drawn = write_csv(tmp_path / "crank.csv", ("α, °", alpha, 0), {"T_mm": f["T"] / area / mu_p})
    drawing = "[drawing]\nmu_p = 0.05\n"
    tables = check(submit(tmp_path, CAR, {"forces": specific, "crank": drawn}, drawing)).tables
    assert [t.verdict for t in tables] == ["right", "right"], [t.cause() for t in tables]
    with pytest.raises(InputError) as exc:
        check(submit(tmp_path, CAR, {"crank": drawn}))
    assert "drawing" in exc.value.fix and "'T, mm'" in exc.value.field


def test_russian_headers_and_units(tmp_path):
    e = task(CAR)
    alpha = np.arange(0.0, 721.0, 30.0)
    f = forces(e, alpha)
    path = write_csv(tmp_path / "forces.csv", ("α, град", alpha, 0),
                     {"p_g": f["p_g"], "P": f["P"], "M": f["M"]}, ";",
                     heads={"p_g": "p_г, МПа", "P": "P, кН", "M": "M, Н·м"})
    (t,) = check(submit(tmp_path, CAR, {"forces": path})).tables
    assert t.verdict == "right" and t.cells == 3 * alpha.size, t.cause()


# ----------------------------------------------------------------------------- slips: reproduced, then found

@pytest.mark.parametrize("sample, kind, slip, root", [
    (CAR, "forces", "T_sign", "T"),
    (CAR, "forces", "N_sign", "N"),
    (CAR, "forces", "K_sign", "K"),
    (CAR, "forces", "pj_sign", "p_j"),
    (CAR, "forces", "p0_not_subtracted", "Δp_g"),
    (DIESEL, "forces", "p0_not_subtracted", "Δp_g"),
    (CAR, "forces", "beta_neglected", "tg β"),
    (CAR, "forces", "beta_sign", "tg β"),
    (CAR, "forces", "beta_degrees", "tg β"),
    (CAR, "forces", "alpha_degrees", "tg β"),
    (CAR, "forces", "bore_as_radius", "P"),
    (DIESEL, "forces", "bore_as_radius", "p_j"),
    (DIESEL, "forces", "mass_not_per_area", "p_j"),
    (CAR, "summed", "firing_interval", "T2"),
    (DIESEL, "summed", "firing_interval", "T2"),
    (CAR, "summed", "firing_order_ignored", "T2"),
    (DIESEL, "summed", "firing_order_ignored", "T2"),
    (CAR, "summed", "T_sign", "T1"),
    (DIESEL, "compression", "exponents_swapped", "p_x"),
    (CAR, "expansion", "exponents_swapped", "p_x"),
], ids=lambda x: x.stem if isinstance(x, Path) else x)
def test_a_slip_reproduced_is_found_at_its_root(tmp_path, sample, kind, slip, root):
    (t,) = judged(tmp_path, sample, (kind,), slip=slip).values()
    assert t.verdict == "wrong"
    assert t.roots[0].column == root, t.cause()
    assert {r.slip.name if r.slip else None for r in t.roots} == {slip}, t.cause()


def test_a_cascade_is_reported_once_at_its_root(tmp_path):
    """p₀ not subtracted makes Δp_g wrong, and through it p, P and every force: one root."""
    (t,) = judged(tmp_path, CAR, ("forces",), slip="p0_not_subtracted").values()
    (root,) = t.roots
    assert root.column == "Δp_g" and {"p", "P", "N", "S", "K", "T", "M"} <= set(root.follows)
    assert t.first_row == 2 and t.first_column == "Δp_g"
    assert "p, P, N" in t.cause() and "follow from it" in t.cause()


def test_an_arithmetic_slip_in_one_cell_is_located_without_a_cause(tmp_path):
    """A student's P at α = 150° typed wrong (×1.37), and carried into N, S, K, T, M there."""
    e = task(CAR)
    alpha = np.arange(0.0, 721.0, 15.0)
    f = forces(e, alpha)
    k = int(np.flatnonzero(alpha == 150.0)[0])
    f["P"][k] *= 1.37
    for force, factor in (("N", "tan_beta"), ("S", "inv_cos_beta"), ("K", "cos_ab"),
                          ("T", "sin_ab")):
        f[force][k] = f["P"][k] * f[factor][k]
    f["M"][k] = f["T"][k] * e["R"]
    path = write_csv(tmp_path / "forces.csv", ("α, °", alpha, 0), f)
    (t,) = check(submit(tmp_path, CAR, {"forces": path})).tables
    assert (t.wrong, t.first_row, t.first_at, t.first_column) == (6, k + 2, 150.0, "P")
    (root,) = t.roots
    assert root.slip is None and set(root.follows) == {"N", "S", "K", "T", "M"}


# ----------------------------------------------------------------------------- bad tables

@pytest.mark.parametrize("text, field, problem", [
    ("α, °,P, kN,Q, kN\n0,1.0,2.0\n", "column 'Q, kN'", "unknown column"),
    ("P, kN,T, kN\n1.0,2.0\n", "reported.tables.forces", "no column α"),
    ("α, °,P\n0,1.0\n", "column 'P'", "has no unit"),
    ("α, °,P, kg\n0,1.0\n", "column 'P, kg'", "not a unit of this column"),
    ("α, °,P, kN\n0,1.0\n15,1.2\n30,abc\n", "column 'P, kN', row 4", "not a number"),
])
def test_bad_tables_name_the_table_column_row_and_fix(tmp_path, text, field, problem):
    (tmp_path / "forces.csv").write_text(text.replace("α, °", '"α, °"')
                                         .replace("P, kN", '"P, kN"').replace("Q, kN", '"Q, kN"')
                                         .replace("T, kN", '"T, kN"').replace("P, kg", '"P, kg"'),
                                         encoding="utf-8")
    with pytest.raises(InputError) as exc:
        check(submit(tmp_path, CAR, {"forces": tmp_path / "forces.csv"}))
    assert field in exc.value.field and problem in exc.value.problem, exc.value
    assert exc.value.fix and exc.value.file.endswith("forces.csv")


def test_an_unknown_table_or_a_missing_file_is_refused(tmp_path):
    path = submit(tmp_path, CAR, {"force": tmp_path / "forces.csv"})
    with pytest.raises(InputError, match="not a table of the coursework"):
        check(path)
    path = submit(tmp_path, CAR, {"forces": tmp_path / "nowhere.csv"})
    with pytest.raises(InputError, match="not found"):
        check(path)


def test_read_table_converts_to_si_and_keeps_the_written_digits(tmp_path):
    (tmp_path / "t.csv").write_text('"α, °";"P, kN";"p_T, MPa"\n0;1,25;0,5\n15;-2,5;−0,125\n',
                                    encoding="utf-8")
    t = read_table(tmp_path / "t.csv", "forces", cylinders=4, piston_area=0.005, mu_p=None,
                   shown="t.csv")
    got = {c.key: c for c in t.columns}
    np.testing.assert_allclose(t.abscissa, np.radians([0.0, 15.0]))
    np.testing.assert_allclose(got["P"].values, [1250.0, -2500.0])
    np.testing.assert_allclose(got["T"].values, [0.5e6 * 0.005, -0.125e6 * 0.005])
    np.testing.assert_allclose(got["P"].half_digit, [5.0, 50.0])


def test_the_drawing_scale_in_the_spec():
    assert dc.SPEC.section("drawing").field("mu_p").unit == "MPa/mm"


def test_a_slip_that_blows_up_does_not_take_every_table_for_its_own(tmp_path):
    """Variant 102: β in degrees taken as radians puts tg β near a pole on the reference
    grid. Its tolerance floor, scaled by that peak, took the summed table of p₀ not
    subtracted (and of four other slips) for its own; the floor now scales with the smaller
    of the student's column and the model's, and each slip is named as itself."""
    from dataclasses import replace

    from labs.bench import check as cb
    from labs.teachers import dyncalc_check as ck
    from labs.registry import LABS
    from processing.measurement import load, read_toml

    written = cb._written("dyncalc", 102, tmp_path)
    inputs = load(written["toml"], LABS["dyncalc"].SPEC, read_toml(written["toml"]))
    scene = replace(ck.Scene(ck.arguments(inputs)), kinematics="exact",
                    factor_kinematics="exact")
    x, first = cb._rows("summed", scene.args, 10.0)
    blown = ck.summed(next(s for s in ck.TABLE_SLIPS if s.name == "beta_degrees")
                      .scene(scene, inputs), np.radians(np.linspace(0, 180, 721)))
    assert max(np.max(np.abs(v)) for k, v in blown.items() if k.startswith("T")) > \
        10 * max(np.max(np.abs(v)) for k, v in ck.summed(scene, x).items() if k.startswith("T"))
    for name in ("p0_not_subtracted", "exponents_swapped"):
        slip = next(s for s in ck.TABLE_SLIPS if s.name == name)
        table = cb._write_table(tmp_path / "summed.csv", first, x,
                                cb._model("summed", slip.scene(scene, inputs), x), 3, ",")
        (t,) = ck.check_tables(written["toml"], {"summed": table.name}, inputs)
        assert t.verdict == "wrong" and {r.slip.name for r in t.roots if r.slip} == {name}, \
            t.cause()
