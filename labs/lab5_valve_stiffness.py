"""Lab 5. Stiffness of the valve-train parts.

The manual's chapter: the valve sits at the end of a long chain of elastic links (rocker,
rocker shaft with its stand, push rod, camshaft span), whose vibration distorts the valve's
motion. The chain is loaded statically through a lever, P = Q i₁ (i₁ = 10), up to 1000 N in
100 N steps and back; four dial gauges (0.01 mm a division) read Δl₁ the total deformation,
Δl₂ the rocker shaft with its stand, Δl₃ the push rod with the camshaft and Δl₄ the camshaft's
bending. Each part's deformation, reduced to the valve axis, gives its stiffness; together
they give the drive's stiffness c at the valve. The valve springs' stiffness c_n comes from
their characteristic on a dynamometer (1 mm = 145 N), the oscillating mass M from the parts'
masses, and the drive's lowest natural frequency is ν = √((c + c_n)/M).

The manual's formulas are in :mod:`processing.valvetrain.valve_train` (the chain of springs seen
from the valve: reduced deformations, link stiffnesses, reduced mass, ν). Here every slope comes
from least squares over the whole table (:func:`processing.oscillations.load_cycle.fit_branches`:
slope ± its type A u from the residuals), for the loading branch, the unloading branch and their
mean Δl = (Δl_load + Δl_unload)/2 as the manual asks; the gauges' scale error (type B) and the
lever's enter through
:func:`processing.uncertainty.propagate`. The intercept of each line (settling, lash taken
up) is reported; the loop between the branches
(:func:`processing.oscillations.load_cycle.hysteresis`) and its share of the work say how much
friction and contact slip the chain has.

Notation: i is the rocker ratio (valve arm over push-rod arm); "reduced to the valve" means
the valve's displacement that a part's deformation causes.

References
----------
.. [1] Dynamics of internal-combustion engines: lab manual, Vladimir State University, 2003,
       lab 5 ("Исследование жесткости деталей механизма газораспределения двигателя").
"""
from __future__ import annotations

import json
import math
import warnings
from dataclasses import replace
from pathlib import Path

import numpy as np

from processing.diagnostics import collect_notices
from processing.oscillations.load_cycle import BRANCHES, LoadCycle, fit_branches, hysteresis
from processing.measurement import (ENGINE_SPEED, GRAVITY, LENGTH, MASS, STROKES, Field, Inputs,
                                    LabSpec, Section, bi)
from processing.result import LabResult, compare, flag_estimates, result_values
from processing.inputs.text_table import TextTable, format_table, read_table
from processing.inputs.toml_writer import dumps
from processing.uncertainty import Measured, propagate
from processing.valvetrain.valve_train import (at_valve, cam_order, natural_frequency,
                                               part_deformations, reduced_mass, span_mass,
                                               stiffnesses)

from . import catalogue, lab5_valve_stiffness_report as report
from .lab5_valve_stiffness_report import PARTS, result_name

GAUGES = ("dl1", "dl2", "dl3", "dl4")
"""The gauges' columns: Δl₁ total, Δl₂ rocker shaft, Δl₃ push rod + camshaft, Δl₄ camshaft."""

USES = {"rocker": (0, 1, 2), "shaft": (1,), "rod": (2, 3), "cam": (3,), "total": (0,)}
"""The gauges (0…3) each stiffness is computed from."""

RESTS_ON = {"M_reduced": ("c_total", "c_rod", "c_cam"), "nu_natural": ("M_reduced", "c_spring"),
            "f_natural": ("nu_natural",), "cam_order": ("f_natural",)}
"""Results computed from other results: reported only where those are."""

HYSTERESIS_SHARE = 0.20
"""Loop area over the loading branch's work above which the loop is called too wide. The
manual asks to explain the loop (friction, contact hysteresis) but prints no figure; a chain
of oiled steel joints whose friction is 1–3 % of the load loses 4–12 % of the work (a Coulomb
friction F makes the loop ≈ 2F wide: share ≈ 4F/P_max); 20 % means F ≈ 5 % of the load: a
binding rocker, a dry ball end or a sticking gauge stem."""

CURVATURE_LEVEL = 0.01
"""Significance level of the quadratic term (:func:`processing.regression.curvature_test`)."""

CURVATURE_BEND = 0.02
"""Relative bend (the quadratic term's share of the line's rise) below which a significant
bend is not called out: the turning points of a friction loop bend the mean table by about
F/(5 P_max) without the stiffness depending on the load; contact stiffening bends it more."""

DIVISION_TENTHS = 10
"""A dial gauge is read to a tenth of a division at best: finer fractions are not divisions."""

FORCE = {"N": "a force", "kg": "a mass (the weights)"}
LENGTH_UNITS = {"mm": "a length"}


# -------------------------------------------------------------------- the measurement file

SPEC = LabSpec(
    id="lab5", number="5",
    title=catalogue.title("lab5"),
    goal=bi("To study the methods of measuring the stiffness of the valve-drive parts and to "
            "find the drive's lowest natural frequency.",
            "Изучить методы экспериментального исследования жесткости деталей привода клапана "
            "и определить его частоту собственных колебаний."),
    sections=(
        Section("rig", bi("Rig and rocker", "Установка и коромысло"), required=True, fields=(
            Field("i", bi("rocker ratio (valve arm over push-rod arm)",
                          "передаточное отношение коромысла"), unit="", limit="0.01",
                  symbol="i", example=1.5, plausible=("0.5", "3")),
            Field("i1", bi("loading lever ratio", "передаточное отношение рычага"), unit="",
                  default="10", limit="0.05", symbol="i₁", plausible=("1", "50")),
            Field("g", bi("acceleration of gravity (weights given as masses)",
                          "ускорение свободного падения (грузы заданы массой)"), **GRAVITY),
        )),
        Section("gauges", bi("Dial gauges", "Индикаторы"), required=True, fields=(
            Field("unit", bi("unit of the gauge readings: divisions or mm",
                             "единицы показаний индикаторов: деления или мм"),
                  kind="choice", choices={"div": bi("divisions", "деления"), "mm": bi("mm", "мм")}),
            Field("division", bi("scale value of a division", "цена деления"), unit="mm",
                  default="0.01 mm", symbol="e", plausible=("0.001 mm", "0.1 mm")),
            Field("scale_limit", bi("limit of a gauge's proportional (scale) error",
                                    "предел погрешности масштаба индикатора"), unit="%",
                  default="2 %", symbol="δ_e", plausible=("0.1 %", "10 %")),
            Field("range", bi("measuring range of the gauges", "диапазон измерений индикатора"),
                  unit="mm", default="10 mm", plausible=("1 mm", "100 mm")),
        )),
        Section("run", bi("Loading run", "Цикл нагружения"), required=True, many=True,
                help=report.TABLE_HELP, fields=(
                    Field("table", bi("the run's table: load and gauges dl1…dl4, a line per "
                                      "load", "таблица цикла: нагрузка и индикаторы dl1…dl4, по "
                                      "строке на нагрузку"), kind="text"),
                )),
        Section("spring", bi("Valve springs on the dynamometer", "Клапанные пружины на "
                             "динамометре"), help=report.SPRING_HELP, fields=(
            Field("table", bi("the characteristic: h and d (or P), a line per lift",
                              "характеристика: h и d (или P), по строке на перемещение"),
                  kind="text"),
            Field("k_dyn", bi("dynamometer characteristic", "характеристика динамометра"),
                  unit="N/mm", default="145 N/mm", limit="1.5 N/mm", symbol="k_d",
                  plausible=("1 N/mm", "10000 N/mm")),
        )),
        Section("masses", bi("Oscillating parts", "Колеблющиеся детали"), fields=(
            Field("m_valve", bi("valve with retainer and cotters", "клапан с тарелкой и "
                                "сухарями"), **MASS, symbol="m_кл"),
            Field("m_spring", bi("valve springs", "клапанные пружины"), **MASS, symbol="m_n"),
            Field("J_rocker", bi("rocker's moment of inertia about its shaft",
                                 "момент инерции коромысла относительно оси"),
                  unit="kg*mm^2", symbol="J_кор", example="105 ± 5 kg*mm^2",
                  plausible=("1 kg*mm^2", "10000 kg*mm^2")),
            Field("a", bi("rocker's valve-side arm", "плечо коромысла со стороны клапана"),
                  **LENGTH, symbol="a"),
            Field("m_rod", bi("push rod", "штанга"), **MASS, symbol="m_ш"),
            Field("m_tappet", bi("tappet", "толкатель"), **MASS, symbol="m_m"),
            Field("m_span", bi("camshaft span between its bearings",
                               "пролёт распределительного вала"), **MASS, symbol="m′_г"),
            Field("l", bi("cam-to-bearing distance", "расстояние от кулачка до опоры"),
                  **LENGTH, required=False, symbol="l"),
            Field("L", bi("distance between the camshaft bearings",
                          "расстояние между опорами вала"), **LENGTH, required=False,
                  symbol="L"),
        )),
        Section("engine", bi("Engine speed (for cam orders)", "Частота вращения (для "
                             "порядков)"), fields=(
            Field("n", bi("crankshaft speed", "частота вращения коленчатого вала"),
                  **ENGINE_SPEED, symbol="n", example=2000),
            Field("strokes", bi("strokes per cycle", "тактность"), **STROKES),
        )),
    ),
)


# ------------------------------------------------------------------------ the tables

def _division(inputs: Inputs) -> dict:
    """The gauges' own unit for :meth:`TextTable.si`."""
    return {"div": (inputs["gauges"]["division"].value, "m")}


def _force(inputs: Inputs, table: TextTable, name: str):
    """A load column in N (a mass unit: the weights' masses, times g)."""
    value, kind = table.si(name, "N", FORCE)
    return value * (inputs["rig"]["g"].value if kind == "kg" else 1.0)


def load_tables(inputs: Inputs) -> list[LoadCycle]:
    """Every run's table in SI (x = P at the valve [N], y = Δl₁…Δl₄ from their first
    readings [m]), checked: one load column and the four gauges, loads rising then falling,
    readings plausible in their unit, every gauge moving.

    Raises
    ------
    InputError
    """
    default, i1 = inputs["gauges"]["unit"], inputs["rig"]["i1"].value
    tables = []
    for r, entry in enumerate(inputs["run"]):
        t = read_table(entry["table"], ("P", "Q", *GAUGES), file=inputs.file,
                       field=f"run[{r}].table")
        loads = [k for k in ("P", "Q") if k in t]
        missing = [g for g in GAUGES if g not in t]
        if len(loads) != 1 or missing:
            raise t.error(f"the header names {', '.join(t.columns)}: " + (
                f"gauge column(s) {', '.join(missing)} missing" if missing else
                f"the load is given {'twice' if loads else 'nowhere'}"),
                "name one load column, P (at the valve) or Q (the weights), and the four "
                "gauges: e.g. Q[N]  dl1  dl2  dl3  dl4")
        P = _force(inputs, t, loads[0]) * (i1 if loads[0] == "Q" else 1.0)
        peak = t.rise_then_fall(loads[0], "load")
        _check_gauge_unit(inputs, t)
        dl = []
        for g in GAUGES:
            reading = t.si(g, default, LENGTH_UNITS, named=_division(inputs))[0]
            if np.ptp(reading) == 0:
                raise t.error(f"gauge {g} reads {t[g].values[0]:g} at every load: it did not "
                              "move", "check that the gauge's stem touches the part and is "
                              "preloaded, and repeat the run")
            dl.append(reading - reading[0])
        tables.append(LoadCycle(P, np.stack(dl), peak))
    return tables


def _check_gauge_unit(inputs: Inputs, t: TextTable) -> None:
    """Readings that cannot be in their unit: an InputError naming the likely one."""
    default = inputs["gauges"]["unit"]
    div = {g: t[g].values for g in GAUGES if (t[g].unit or default) == "div"}
    for name, r in div.items():
        fine = np.flatnonzero(np.abs(r * DIVISION_TENTHS - np.round(r * DIVISION_TENTHS)) > 1e-6)
        if fine.size:
            raise t.error(f"{t.row(int(fine[0]))}, column {name}: reading {r[fine[0]]:g} is "
                          "finer than a tenth of a division: these look like millimetres, not "
                          "divisions", f"write the readings in divisions (0.35 mm on a 0.01 mm "
                          f"gauge is 35), or mark the column {name}[mm] (or set [gauges] "
                          "unit = \"mm\")")
    if "dl1" in div and np.ptp(div["dl1"]) < 5 and any((v != np.round(v)).any()
                                                       for v in div.values()):
        raise t.error(f"gauge dl1 moved only {np.ptp(div['dl1']):g} divisions under the whole "
                      "load, with fractional readings: these look like millimetres, not "
                      "divisions", "mark the columns [mm] (or set [gauges] unit = \"mm\"), or "
                      "write divisions")
    limit = inputs["gauges"]["range"].value
    for name in GAUGES:
        if name not in div:
            v = t.si(name, default, LENGTH_UNITS, named=_division(inputs))[0]
            k = int(np.argmax(np.abs(v)))
            if abs(v[k]) > limit:
                raise t.error(f"{t.row(k)}, column {name}: reading {t[name].values[k]:g} is "
                              f"beyond the gauge's range of {1e3 * limit:g} mm: these look "
                              "like divisions, not millimetres", f"mark the column {name}[div] "
                              "(or set [gauges] unit = \"div\"), or convert the readings to "
                              "millimetres")


def spring_cycle(inputs: Inputs) -> tuple[LoadCycle, bool]:
    """The springs' characteristic in SI (x = h [m], y = [P] [N]), checked like a run, and
    whether the force was read on the dynamometer's indicator (P = k_d d)."""
    t = read_table(inputs["spring"]["table"], ("h", "d", "P"), file=inputs.file,
                   field="spring.table")
    forces = [k for k in ("d", "P") if k in t]
    if "h" not in t or len(forces) != 1:
        raise t.error(f"the header names {', '.join(t.columns)}",
                      "name the lift h and one force column, d (the dynamometer's indicator) "
                      "or P (the force): e.g. h[mm]  d[mm]")
    h = t.si("h", "mm", LENGTH_UNITS, named=_division(inputs))[0]
    peak = t.rise_then_fall("h", "lift")
    if forces[0] == "d":
        force = t.si("d", "mm", LENGTH_UNITS, named=_division(inputs))[0] \
            * inputs["spring"]["k_dyn"].value
    else:
        force = _force(inputs, t, "P")
    return LoadCycle(h, force[None, :], peak), forces[0] == "d"


# ------------------------------------------------------------------------ reduction

def _measured_inputs(inputs: Inputs, lines, spring_lines, dynamometer: bool) -> dict:
    """The measurement model's inputs: slopes and intercepts (type A), the gauges', lever's
    and dynamometer's scale factors (type B), and the file's quantities."""
    flat = {k: v for k, v in inputs.flat().items() if isinstance(v, Measured)
            and (k == "rig.i" or k.startswith(("masses.", "engine.")))}
    limit = inputs["gauges"]["scale_limit"].value
    for (j, b), line in lines.items():
        flat[f"s{j}.{b}"] = line.measured_slope()
    for j in range(4):
        flat[f"a{j}"] = lines[j, "mean"].measured_intercept()
        flat[f"gauge{j}"] = Measured(1.0, limit=limit)
    flat["lever"] = inputs["rig"]["i1"].scaled(1.0 / inputs["rig"]["i1"].value)
    if spring_lines is not None:
        for b in BRANCHES:
            flat[f"sp.{b}"] = spring_lines[0, b].measured_slope()
        flat["sp.P0"] = spring_lines[0, "mean"].measured_intercept()
        flat["lift_gauge"] = Measured(1.0, limit=limit)
        if dynamometer:
            k = inputs["spring"]["k_dyn"]
            flat["dynamometer"] = k.scaled(1.0 / k.value)
    return flat


def _model(masses: bool, strokes: int):
    """The measurement model: a reading is the truth times its instrument's scale factor."""
    def model(**x):
        out = {}
        i = x["rig.i"]
        for b in BRANCHES:
            slopes = [x[f"s{j}.{b}"] / x[f"gauge{j}"] / x["lever"] for j in range(4)]
            chain = stiffnesses(1.0, *slopes, i)
            for p in (*PARTS, "total"):
                out[result_name(f"c_{p}", b)] = getattr(chain, p)
        for j in range(4):
            out[f"dl{j + 1}_0"] = x[f"a{j}"] / x[f"gauge{j}"]
        if "sp.mean" in x:
            k = x.get("dynamometer", 1.0)
            for b in BRANCHES:
                out[result_name("c_spring", b)] = k * x[f"sp.{b}"] / x["lift_gauge"]
            out["P_preload"] = k * x["sp.P0"]
        if masses:
            out["m_g"] = m_g = span_mass(x["masses.m_span"], x.get("masses.l"), x.get("masses.L"))
            out["M_reduced"] = M = reduced_mass(
                x["masses.m_valve"], x["masses.m_spring"], x["masses.J_rocker"], x["masses.a"],
                x["masses.m_rod"], x["masses.m_tappet"], m_g, out["c_total"], out["c_rod"],
                out["c_cam"], i).total
            if "c_spring" in out:
                out["nu_natural"] = nu = natural_frequency(out["c_total"], out["c_spring"], M)
                out["f_natural"] = nu / (2 * np.pi)
                if "engine.n" in x:
                    out["cam_order"] = cam_order(out["f_natural"], x["engine.n"], strokes)
        return out

    return model


def reduce(inputs: Inputs, *, n_samples: int = 20000, seed: int = 20031) -> LabResult:
    """Reduce lab 5's tables into the links' stiffnesses, the springs', M and ν.

    Parameters
    ----------
    inputs : Inputs
        A validated measurement file (:func:`processing.measurement.load` with :data:`SPEC`).
    n_samples, seed : int
        Monte Carlo draws and their seed.

    Returns
    -------
    LabResult
        ``c_rocker``, ``c_shaft``, ``c_rod``, ``c_cam``, ``c_total`` (the mean of loading and
        unloading) and the same with ``_load``, ``_unload``; ``dl1_0`` … ``dl4_0``; with a
        [spring] table ``c_spring`` (and per branch), ``P_preload``; with [masses] ``m_g``,
        ``M_reduced``, and with both ``nu_natural``, ``f_natural`` and, with [engine],
        ``cam_order``. A result that comes out ≤ 0 or undefined is left out, with a warning.

    Raises
    ------
    InputError
        A table that cannot be read: a column missing or unknown, a unit unknown, a cell not
        a number, loads out of order, fewer than three steps each way, readings not in the
        declared unit, a gauge that never moved.
    """
    _check_file(inputs)
    tables = load_tables(inputs)
    spring, dynamometer = spring_cycle(inputs) if "spring" in inputs else (None, False)
    masses = inputs.sections.get("masses")
    i = inputs["rig"]["i"].value
    reading = inputs["gauges"]["division"].value / math.sqrt(12)   # read to a division
    with collect_notices() as notices:
        lines = fit_branches(tables, reading)
        spring_lines = (fit_branches([spring], reading * inputs["spring"]["k_dyn"].value
                                     if dynamometer else 0.0)
                        if spring is not None else None)
        loops = [[hysteresis(t.x, t.y[j], t.peak) for j in range(4)] for t in tables]
        spring_loop = (hysteresis(spring.y[0], spring.x, spring.peak) if spring is not None
                       else None)
        _check_lines(lines, spring_lines, loops, spring_loop, i)
        strokes = inputs["engine"]["strokes"] if "engine" in inputs else 4
        prop = propagate(_model(masses is not None, strokes),
                         _measured_inputs(inputs, lines, spring_lines, dynamometer),
                         n_samples=n_samples, seed=seed)
        results = _reported(result_values(prop, report.RESULTS), lines, spring_lines)
        results.update(report.loop_results(lines, loops, spring_loop))
        # the branches' own values are there to show the loop: their Monte Carlo intervals
        # are printed (and marked when nonlinear); only the manual's results warn in words
        flag_estimates({k: v for k, v in results.items()
                        if not k.endswith(("_load", "_unload"))}, [])
        pairs = [(f"c_{p}_load", f"c_{p}_unload") for p in (*PARTS, "total", "spring")]
        comparisons = compare(prop, [(a, b) for a, b in pairs if a in results and b in results])
    mean = [results[f"c_{p}"].value for p in PARTS if f"c_{p}" in results]
    terms = {}
    if "M_reduced" in results:
        m = {k: q.value for k, q in masses.items()}
        terms = reduced_mass(m["m_valve"], m["m_spring"], m["J_rocker"], m["a"], m["m_rod"],
                             m["m_tappet"], results["m_g"].value, results["c_total"].value,
                             results["c_rod"].value, results["c_cam"].value, i).to_dict()
    reduced = dict(zip(PARTS, at_valve(*mean, i))) if len(mean) == 4 else {}
    results.update(report.valve_results(reduced))
    data = report.Data(
        inputs=inputs, tables=tables,
        parts=[(P, np.stack(part_deformations(*dl, i))) for P, dl in
               (t.branch("mean") for t in tables)],
        lines=lines, loops=loops, spring=spring, spring_lines=spring_lines,
        spring_loop=spring_loop, results=results, mass_terms=terms,
        at_valve=reduced)
    res = LabResult.of(inputs, results, comparisons=comparisons, tables=report.tables(data),
                       measurements=report.measurements(data), figures=report.figures(data),
                       formulas=report.FORMULAS,
                       references=report.REFERENCES, warnings=notices,
                       conclusion=report.conclusion(data))
    res.inputs = report.input_rows(res.inputs, data)
    return res


def _check_file(inputs: Inputs) -> None:
    """Relations between fields that no single field can check."""
    m = inputs.sections.get("masses")
    if m is not None and ("l" in m) != ("L" in m):
        raise inputs.error("only one of l and L is given",
                           "give both the cam-to-bearing distance l and the bearing span L, or "
                           "neither (then m_g ≈ (2/3) m′_g)",
                           "masses.l" if "l" in m else "masses.L")
    if m is not None and "l" in m and m["l"].value >= m["L"].value:
        raise inputs.error(f"l = {1e3 * m['l'].value:g} mm is not inside the span L = "
                           f"{1e3 * m['L'].value:g} mm", "l is measured from the cam to the "
                           "nearer bearing: 0 < l < L", "masses.l")


def _check_lines(lines, spring_lines, loops, spring_loop, i: float) -> None:
    """Named warnings: gauges running backwards, inconsistent gauges, bent tables, wide loops."""
    slope = [lines[j, "mean"].fit.slope for j in range(4)]
    backwards = {j for j in range(4) if slope[j] <= 0}
    for j in sorted(backwards):
        warnings.warn(report.gauge_backwards(j, slope[j]))
    if spring_lines is not None and spring_lines[0, "mean"].fit.slope <= 0:
        warnings.warn(report.spring_backwards(spring_lines[0, "mean"].fit.slope))
    rocker, _, rod, _ = part_deformations(*slope, i)
    for part, value in (("rocker", rocker), ("rod", rod)):
        if value <= 0 and not backwards & set(USES[part]):
            warnings.warn(report.inconsistent_part(part))
    bent = [(j, lines[j, "mean"].curvature) for j in range(4)]
    if spring_lines is not None:
        bent.append((None, spring_lines[0, "mean"].curvature))
    for j, c in bent:
        if c is not None and c.significant(CURVATURE_LEVEL) and c.relative_bend > CURVATURE_BEND:
            warnings.warn(report.bent_table(j, c.p_value, c.relative_bend))
    wide = [(j, max(run[j].share for run in loops)) for j in range(4)]
    if spring_loop is not None:
        wide.append((None, spring_loop.share))
    for j, share in wide:
        if share > HYSTERESIS_SHARE:
            warnings.warn(report.wide_loop(j, share, HYSTERESIS_SHARE))


def _reported(results: dict, lines, spring_lines) -> dict:
    """The results a report may show: a stiffness, mass or frequency that comes out ≤ 0 or
    undefined, rests on a gauge running backwards, or on such a result, is left out (one
    warning names them)."""
    backwards = {j for j in range(4) if lines[j, "mean"].fit.slope <= 0}
    spring_back = spring_lines is not None and spring_lines[0, "mean"].fit.slope <= 0
    kept, left = {}, []
    for name, r in results.items():
        e, base = r.estimate, name.removesuffix("_load").removesuffix("_unload")
        sound = all(math.isfinite(v) for v in (e.value, e.u, *e.interval95))
        sound &= not backwards & set(USES.get(base.removeprefix("c_"), ()))
        sound &= not (spring_back and base in ("c_spring", "P_preload"))
        sound &= name == "P_preload" or name.endswith("_0") or e.value > 0
        sound &= all(dep in kept for dep in RESTS_ON.get(name, ()))
        if sound:
            kept[name] = r
        else:
            left.append(name)
    if left:
        warnings.warn(report.withheld(left))
    return kept


# ------------------------------------------------------------------------ slips

def _lever_forgotten(inputs: Inputs) -> Inputs | None:
    """The weights Q taken for the load at the valve: P = Q, the lever's i₁ not applied."""
    if inputs["rig"]["i1"].value == 1.0:
        return None
    return inputs.changed("rig", i1=Measured(1.0))


def _rocker_ratio_inverted(inputs: Inputs) -> Inputs:
    """The rocker ratio taken the wrong way round: the push-rod arm over the valve arm, 1/i."""
    return inputs.changed("rig", i=Measured(1.0 / inputs["rig"]["i"].value))


LINKS = r"c_(rocker|shaft|rod|cam)(_load|_unload)?"
"""The links' stiffnesses (either branch and their mean)."""
FROM_LINKS = ("M_reduced", "nu_natural", "f_natural", "cam_order")
"""The results that follow the links' stiffnesses."""

ASKED = ("M_reduced",)
"""What the manual asks a student to report beside the key results (each link's stiffness
and the drive's, the springs', ν in Hz and in cam orders): the reduced mass M."""

SLIPS = [
    ("lever_ratio_forgotten",
     bi("the weights Q taken for the load at the valve (P = Q i₁ without i₁ = 10): every "
        "stiffness ten times too small",
        "нагрузка на клапан взята равной весу грузов Q (P = Q i₁ без i₁ = 10): все жёсткости "
        "вдесятеро меньше"),
     (LINKS, r"c_total(_load|_unload)?", *FROM_LINKS), _lever_forgotten),
    ("rocker_ratio_inverted",
     bi("the rocker ratio inverted (push-rod arm over valve arm, 1/i) in reducing the "
        "deformations to the valve",
        "передаточное отношение коромысла перевёрнуто (1/i) при приведении деформаций к "
        "клапану"), (LINKS, *FROM_LINKS), _rocker_ratio_inverted),
]
"""The lab's classic slips (:mod:`labs.teachers.check`): name, text, the results they change, and
the inputs as the slip leaves them."""


# ------------------------------------------------------------------------ synthetic files

def synthetic(seed: int = 0, *, runs: int = 1, friction: float = 8.0, contact: float = 0.0,
              lash: float = 0.0, resolution: float = 1.0, scatter: float = 0.25,
              top: float = 1000.0, step: float = 100.0, train=None,
              part: int | None = None) -> tuple[dict, dict]:
    """A synthetic lab 5 measurement as a document and its answer key.

    The rig of seed 0: a push-rod valve train
    (:class:`processing.synth.valve_table.ValveTrain`, i = 1.5, c = 2.055 kN/mm at the valve)
    loaded 0 → 1000 N in 100 N steps and back through the manual's lever (i₁ = 10, true ratio
    within ± 0.5 %), read on 0.01 mm dial gauges (scale errors within ± 2 %), and its springs
    (45 N/mm, 250 N preload) lifted 0 → 10 mm on the manual's dynamometer (1 mm = 145 N
    within ± 1 %); masses on a ± 1 g balance, lengths ± 0.5 mm, the rocker's inertia ± 3 %.
    The file states each of those tolerances. Any other seed draws a train, springs and
    masses of its own (:func:`_part`, over :data:`VALVE_TRAINS`).

    Parameters
    ----------
    seed : int
        Seed of the readings and their errors (and of the part, unless ``part`` is given).
    runs : int
        Loading–unloading runs (the same gauges and lever).
    friction : float
        Coulomb friction of the joints at the valve. [N]
    contact : float
        Hertzian deformation of the push rod's ends at 1000 N (0: none). [m]
    lash : float
        Clearance taken up at the first load step. [m]
    resolution, scatter : float
        What the student writes down, and the reading scatter before rounding. [divisions]
    top, step : float
        Largest load at the valve and its step. [N]
    train : ValveTrain, optional
        Overrides the drawn train (``friction``, ``contact``, ``lash`` then ignored).
    part : int, optional
        Seed of the part: the train, springs and masses (default ``seed``; 0: the scene's
        defaults, whatever ``seed`` draws the readings).

    Returns
    -------
    document : dict
        The measurement file's content (:func:`processing.inputs.toml_writer.dumps` writes it).
    answer : dict
        ``{"seed": …, "results": {name: true value in SI}}``: the stiffnesses that straight
        lines through the exact table give (:meth:`ValveTrain.line_stiffness`: the links' own
        without ``contact``; with it, the stiffness over the load programme), the springs',
        M and ν.
    """
    from processing.synth.valve_table import DialGauges, load_steps, spring_run, stiffness_run

    rng = np.random.default_rng([seed, 5])
    drawn, spring, masses = _part(seed if part is None else part)
    train = train or replace(drawn, friction=friction, contact=contact, lash=lash)
    gauges = DialGauges(resolution=resolution, scatter=scatter)
    lever_error = rng.uniform(-0.005, 0.005)
    scale_error = rng.uniform(-gauges.scale_limit, gauges.scale_limit, 4)
    doc = {"lab": "lab5",
           "meta": {"student": f"synthetic (dynlab synth lab5 --seed {seed})",
                    "notes": "generated; the true answers are in answer_key.json"},
           "rig": {"i": f"{train.i + rng.uniform(-0.01, 0.01):.3f} ± 0.01", "i1": "10 ± 0.05"},
           "gauges": {"unit": "div", "division": "0.01 mm", "scale_limit": "2 %"},
           "run": []}
    for _ in range(runs):
        t = stiffness_run(train, gauges, rng, top=top, step=step, lever_error=lever_error,
                          scale_error=scale_error)
        doc["run"].append({"table": format_table(
            {"Q[N]": t.Q, **{f"dl{j + 1}": t.readings[j] + 0.0 for j in range(4)}})})
    sp = spring_run(spring, rng)
    doc["spring"] = {"table": format_table({"h[mm]": np.round(sp.h * 1e3, 3),
                                            "d[mm]": np.round(sp.reading * 1e3, 3)}),
                     "k_dyn": "145 N/mm"}
    kg = ("m_valve", "m_spring", "m_rod", "m_tappet", "m_span")
    J = 1e6 * masses.J_rocker
    doc["masses"] = {**{k: f"{getattr(masses, k) + rng.uniform(-1e-3, 1e-3):.4f} kg" for k in kg},
                     "J_rocker": f"{J * (1 + rng.uniform(-0.03, 0.03)):.1f} ± {0.03 * J:.1f} "
                                 "kg*mm^2",
                     **{k: f"{1e3 * getattr(masses, k) + rng.uniform(-0.5, 0.5):.1f} mm"
                        for k in ("a", "l", "L")}}
    doc["engine"] = {"n": "2000 rpm", "strokes": 4}
    line = train.line_stiffness(np.unique(load_steps(top, step)))
    c = {p: getattr(line, p) for p in (*PARTS, "total")}
    m_g = span_mass(masses.m_span, masses.l, masses.L)
    M = reduced_mass(masses.m_valve, masses.m_spring, masses.J_rocker, masses.a, masses.m_rod,
                     masses.m_tappet, m_g, c["total"], c["rod"], c["cam"], train.i).total
    nu = natural_frequency(c["total"], spring.c_n, M)
    truth = {**{result_name(f"c_{p}", b): c[p] for b in BRANCHES for p in c},
             **{result_name("c_spring", b): spring.c_n for b in BRANCHES},
             "P_preload": spring.preload, "m_g": m_g, "M_reduced": M, "nu_natural": nu,
             "f_natural": nu / (2 * np.pi), "cam_order": cam_order(nu / (2 * np.pi),
                                                                   2000 * np.pi / 30)}
    return doc, {"seed": seed, "results": {k: float(v) for k, v in truth.items()}}


def write_synthetic(out_dir, seed: int = 0, *, runs: int = 1, friction: float = 8.0,
                    contact: float = 0.0, lash: float = 0.0, resolution: float = 1.0,
                    scatter: float = 0.25, top: float = 1000.0, step: float = 100.0,
                    part: int | None = None) -> dict[str, Path]:
    """Write a synthetic lab 5 measurement and its answer key.

    Seed 0 is the scene's default valve train; any other seed draws its own (:func:`_part`).

    Parameters
    ----------
    out_dir : str or Path
        Folder to write into (created).
    seed : int
    runs, friction, contact, lash, resolution, scatter, top, step, part
        As :func:`synthetic`: loading runs, joint friction [N], contact deformation at
        1000 N [m], lash [m], what the student writes down and the reading scatter
        [divisions], largest load and its step at the valve [N], the part's seed.

    Returns
    -------
    dict
        Paths written: ``toml``, ``answer``.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    doc, answer = synthetic(seed, runs=runs, friction=friction, contact=contact, lash=lash,
                            resolution=resolution, scatter=scatter, top=top, step=step,
                            part=part)
    written = {"toml": out / f"lab5_seed{seed}.toml", "answer": out / "answer_key.json"}
    written["toml"].write_text(dumps(doc), encoding="utf-8")
    written["answer"].write_text(json.dumps(answer, indent=1), encoding="utf-8")
    return written


VALVE_TRAINS = {"i": (1.4, 1.6), "scale": (0.8, 1.2), "rocker": (0.75, 0.95),
                "link": (0.95, 1.1), "c_n": (30e3, 50e3), "preload": (230.0, 290.0),
                "mass": (0.85, 1.15), "length": (0.9, 1.1)}
"""Ranges a variant's valve train is drawn from, about the scene's push-rod train of a
D-240 class diesel (:class:`processing.synth.valve_table.ValveTrain`, ``ValveSpring``,
``ValveMasses``): the rocker ratio; one scale on the four links' stiffnesses (c at the valve
1.4–2.7 kN/mm against the scene's 2.055; the least-moving gauges, Δl₂ and Δl₄, still move
3.5–9 divisions at the manual's 1000 N, 5 in the scene, and Δl₁ stays under 0.8 mm of the
gauge's 10), times the rocker's own factor and each other link's: the rocker no stiffer
than the scale makes it, so that its deformation — Δl₁ less the others' reduced, the
method's one difference of large readings — keeps at least the scene's 29 % of the total
(its Monte Carlo interval stays the linear one, as in the scene); the springs' stiffness and
preload between lab 6's drive (30 N/mm, 260 N) and lab 5's springs (45 N/mm, 250 N) and a
little beyond (the manual's dynamometer then reads 1.6–5.5 mm at 10 mm of lift); every mass
and the rocker's inertia within ± 15 %, the rocker's arm and the camshaft's span and cam
position within ± 10 % (so l < L). [1] each, [N/m], [N], [1], [1]"""


def _part(seed: int):
    """A variant's valve train, springs and masses (:data:`VALVE_TRAINS`); seed 0 the scene's
    defaults (i = 1.5, c = 2.055 kN/mm, c_n = 45 N/mm, 250 N, M = 0.237 kg).

    Returns
    -------
    tuple
        (:class:`~processing.synth.valve_table.ValveTrain`, ``ValveSpring``, ``ValveMasses``)
    """
    from processing.synth.valve_table import ValveMasses, ValveSpring, ValveTrain

    if seed == 0:
        return ValveTrain(), ValveSpring(), ValveMasses()
    rng = np.random.default_rng([seed, 51])
    r = VALVE_TRAINS
    scale = rng.uniform(*r["scale"])
    own = {"c_rocker": "rocker", "c_shaft": "link", "c_rod": "link", "c_cam": "link"}
    train = ValveTrain(i=rng.uniform(*r["i"]), **{
        k: getattr(ValveTrain, k) * scale * rng.uniform(*r[v]) for k, v in own.items()})
    spring = ValveSpring(c_n=rng.uniform(*r["c_n"]), preload=rng.uniform(*r["preload"]))
    kind = {"m_valve": "mass", "m_spring": "mass", "J_rocker": "mass", "m_rod": "mass",
            "m_tappet": "mass", "m_span": "mass", "a": "length", "l": "length", "L": "length"}
    masses = ValveMasses(**{k: getattr(ValveMasses, k) * rng.uniform(*r[v])
                            for k, v in kind.items()})
    return train, spring, masses
