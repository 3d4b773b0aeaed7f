"""Checking the coursework's tables row by row: the student's polytropes, one cylinder's forces
and the summed tangential force, as exported from a spreadsheet, against the calculation.

A submission names its tables in ``[reported.tables]``, each a CSV file beside it::

    [reported.tables]
    forces = "forces.csv"          # α and any of β, p_g, Δp_g, p_j, p, P, tg β, …, N, S, K, T, M
    summed = "summed.csv"          # α₁, T1 … Ti, ΣT, M
    compression = "compression.csv"   # V_a/V_x and/or V_x, p_x
    expansion = "expansion.csv"       # V_x/V_z and/or V_x, p_x

The header names each column as the coursework does, with its unit after a comma or in
brackets (``P, kN``, ``p_g [MPa]``, ``α, °``; Russian units too). A force column in a unit of
pressure is the force per piston area; one in a length is its ordinate on the drawing (at
``[drawing] mu_p``). The cells are judged at the student's own angles (any step).

Each cell is judged as a scalar is (:func:`processing.checking.grading.agrees`): right if within the
policy's ``rel_tol`` of ours plus half a unit of its last written digit — plus an absolute floor of
:data:`FLOOR_SHARE` × ``rel_tol`` × the column's largest value, because near a zero crossing (T at
the dead centres, p where gas and inertia forces cancel) a relative tolerance asks for more digits
than the table has. The largest value is the smaller of the student's column's and the model's: a
slipped model that blows up (tg β of β in degrees taken as radians nears a pole) would otherwise set
a floor that takes any cell for its own. Ours is any of the accepted ways of computing the table:
exact or two-harmonic piston acceleration (j ≈ Rω²(cos α + λ cos 2α)), exact or first-order factors
(tg β ≈ λ sin α, sin(α+β)/cos β ≈ sin α + λ/2 sin 2α, …), and, at the pressure jumps (α = 0°, 180°,
360°, 540°), either side of the jump.

A wrong column whose cells follow from the student's own wrong columns by the coursework's
formulas (p = Δp_g + p_j, P = pF_p, T = P sin(α+β)/cos β, ΣT = ΣT_c, …) is a cascade: it is
reported once, at its root. A root's likely cause is the slip (:data:`TABLE_SLIPS`, and the
input slips of :data:`labs.dyncalc.SLIPS`) under which the whole table, recomputed, reproduces
every cell of the root column.
"""
from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from processing.crank import dynamics as dyn
from processing.diagnostics import InputError
from processing.files import resolved
from processing.checking.grading import Policy
from processing.crank.kinematics import piston_acceleration, rod_angle
from processing.measurement import Inputs, bi
from processing.uncertainty import Measured

from labs import dyncalc as dc
from .dyncalc_tables import KINDS, Column, StudentTable, split_header, read_table

FLOOR_SHARE = 0.1
"""The absolute floor of a cell's tolerance, as a share of ``rel_tol`` × the column's largest
value: a tenth of the relative tolerance at full scale (a 0.1 MPa slip in p₀ stays visible on
a 13 MPa diesel column; a table computed, not read off a drawing, is that precise)."""

JUMP = 1e-9
"""Offset [rad] either side of a pressure jump: both sides are right values there."""

REFERENCE_STEP_DEG = 5.0
"""The grid over which a column's largest value (its scale) is taken. [deg]"""

PARENTS = {
    "dp_g": ("p_g",), "p": ("dp_g", "p_j"), "P": ("p",), "tan_beta": ("beta",),
    "inv_cos_beta": ("beta",), "cos_ab": ("beta",), "sin_ab": ("beta",),
    "N": ("P", "tan_beta"), "S": ("P", "inv_cos_beta"), "K": ("P", "cos_ab"),
    "T": ("P", "sin_ab"), "M": ("T",),
}
"""Columns of one cylinder's table and those each is computed from (:func:`_from_parents`)."""


# ------------------------------------------------------------------------ the tables, computed

@dataclass(frozen=True)
class Scene:
    """How a table is computed: the calculation's keyword arguments
    (:func:`labs.dyncalc.dynamic_calculation`) and the choices of the one computing it —
    the right ones (kinematics exact or two-harmonic, the side of a pressure jump) and the
    slips (columns with the opposite sign, the kinematic factors done wrong)."""

    args: dict
    kinematics: str = "exact"
    """Of the piston's acceleration: ``exact`` or ``approx`` (two harmonics)."""
    factor_kinematics: str = "exact"
    """Of the factors tg β, 1/cos β, …: ``exact`` or ``approx`` (first order in λ)."""
    side: float = 1.0
    signs: tuple[str, ...] = ()
    factors: str = "right"


def _factors(alpha, scene: Scene) -> dict[str, np.ndarray]:
    lam = scene.args["lambda_"]
    if scene.factors == "alpha_degrees":
        alpha = np.degrees(alpha)
    beta = rod_angle(alpha, lam)
    if scene.factors == "right" and scene.factor_kinematics == "approx":
        s = np.sin(alpha)
        return {"beta": beta, "tan_beta": lam * s, "inv_cos_beta": 1 + lam ** 2 * s ** 2 / 2,
                "cos_ab": np.cos(alpha) - lam * s ** 2,
                "sin_ab": s + lam / 2 * np.sin(2 * alpha)}
    used = {"beta_neglected": 0 * beta, "beta_sign": -beta,
            "beta_degrees": np.degrees(beta)}.get(scene.factors, beta)
    return {"beta": beta, "tan_beta": np.tan(used), "inv_cos_beta": 1 / np.cos(used),
            "cos_ab": np.cos(alpha + used) / np.cos(used),
            "sin_ab": np.sin(alpha + used) / np.cos(used)}


def cylinder(scene: Scene, alpha) -> dict[str, np.ndarray]:
    """One cylinder's table at crank angles ``alpha`` [rad]: β [rad], p_g, Δp_g, p_j, p [Pa],
    P [N], the factors [1], N, S, K, T [N], M [N·m] (Kolchin's signs, :data:`labs.dyncalc.SIGNS`).

    Examples
    --------
    At TDC of firing (α = 360°, after the jump) p = p_z − p₀ − (m_j/F_p)Rω²(1 + λ):

    >>> args = dict(p_a=0.1e6, p_z=5.4e6, compression_ratio=9.0, n1=1.5, n2=1.5, p_r=0.1e6,
    ...             p_0=0.1e6, pre_expansion_ratio=1.0, strokes=4, crank_radius=0.04,
    ...             lambda_=0.25, piston_area=5e-3, angular_speed=300.0,
    ...             reciprocating_mass_per_area=100.0)
    >>> row = cylinder(Scene(args), np.radians([360.0]))
    >>> round(float(row["p"][0]) / 1e6, 4), abs(float(row["T"][0])) < 1e-6
    (4.85, True)
    """
    a = scene.args
    alpha = np.asarray(alpha, dtype=float)
    p_g = dyn.indicator_pressure(alpha + scene.side * JUMP, p_a=a["p_a"], p_z=a["p_z"],
                                 compression_ratio=a["compression_ratio"], n1=a["n1"],
                                 n2=a["n2"], lambda_=a["lambda_"], p_r=a["p_r"],
                                 pre_expansion_ratio=a["pre_expansion_ratio"],
                                 strokes=a["strokes"])
    p_j = -a["reciprocating_mass_per_area"] * piston_acceleration(
        alpha, a["crank_radius"], a["angular_speed"], a["lambda_"], method=scene.kinematics)
    out = {"p_g": p_g, "dp_g": p_g - a["p_0"], "p_j": -p_j if "p_j" in scene.signs else p_j}
    out["p"] = out["dp_g"] + out["p_j"]
    out["P"] = out["p"] * a["piston_area"]
    out.update(_factors(alpha, scene))
    for force, factor in (("N", "tan_beta"), ("S", "inv_cos_beta"), ("K", "cos_ab"),
                          ("T", "sin_ab")):
        out[force] = (-1 if force in scene.signs else 1) * out["P"] * out[factor]
    out["M"] = out["T"] * a["crank_radius"]
    return out


def summed(scene: Scene, alpha) -> dict[str, np.ndarray]:
    """The summed table at cylinder 1's crank angles ``alpha`` [rad]: T1 … Ti [N] (cylinder c
    at α − φ_c, in firing order at the firing interval), ΣT [N] and M = ΣT R [N·m]."""
    a = scene.args
    phases = dyn.firing_phases(a["cylinders"], strokes=a["strokes"],
                               firing_order=a["firing_order"])
    if a.get("firing_interval") is not None:
        phases = phases * a["firing_interval"] / (dyn.cycle_period(a["strokes"]) / a["cylinders"])
    alpha = np.asarray(alpha, dtype=float)
    t = cylinder(scene, (alpha[None, :] - phases[:, None]).ravel())["T"].reshape(len(phases), -1)
    out = {f"T{c}": t[c - 1] for c in range(1, len(phases) + 1)}
    out["sum"] = t.sum(axis=0)
    out["M"] = out["sum"] * a["crank_radius"]
    return out


def polytrope(scene: Scene, kind: str, ratio) -> dict[str, np.ndarray]:
    """A polytrope's table at the ratios V_a/V_x (compression) or V_x/V_z (expansion): V_x
    [m³] and p_x [Pa] (:func:`labs.dyncalc.polytrope_points`)."""
    a = scene.args
    v = dyn.cycle_volumes(a["piston_area"] * 2 * a["crank_radius"], a["compression_ratio"],
                          a["pre_expansion_ratio"])
    ratio = np.asarray(ratio, dtype=float)
    if kind == "compression":
        return {"V_x": v.total_volume / ratio, "p_x": a["p_a"] * ratio ** a["n1"]}
    return {"V_x": v.combustion_volume * ratio, "p_x": a["p_z"] * ratio ** -a["n2"]}


def _compute(scene: Scene, table: StudentTable, x) -> dict[str, np.ndarray]:
    if table.kind == "cylinder":
        return cylinder(scene, x)
    if table.kind == "summed":
        return summed(scene, x)
    return polytrope(scene, table.kind, x)


# ------------------------------------------------------------------------ slips

@dataclass(frozen=True)
class TableSlip:
    """A slip in computing a table: its name, text and the scene it leaves (None where the
    file gives no room for it)."""

    name: str
    text: dict[str, str]
    scene: Callable[[Scene, Inputs], Scene | None]


def _styled(**changes) -> Callable[[Scene, Inputs], Scene]:
    return lambda scene, inputs: replace(scene, **changes)


def _from_inputs(change) -> Callable[[Scene, Inputs], Scene | None]:
    def scene(base: Scene, inputs: Inputs) -> Scene | None:
        slipped = change(inputs)
        return None if slipped is None else replace(base, args=arguments(slipped))
    return scene


def _order_ignored(inputs: Inputs) -> Inputs | None:
    order = inputs["engine"].get("firing_order")
    if order is None or [int(x) for x in re.findall(r"\d+", order)] == \
            list(range(1, inputs["engine"]["i"] + 1)):
        return None
    return inputs.changed("engine", firing_order=None)


def _exponents_swapped(inputs: Inputs) -> Inputs:
    cycle = inputs["cycle"]
    return inputs.changed("cycle", n1=cycle["n2"], n2=cycle["n1"])


TABLE_SLIPS = [
    TableSlip("T_sign", bi("T with the opposite sign (positive against the rotation)",
                           "T с обратным знаком (положительна против вращения)"),
              _styled(signs=("T",))),
    TableSlip("N_sign", bi("N with the opposite sign", "N с обратным знаком"),
              _styled(signs=("N",))),
    TableSlip("K_sign", bi("K with the opposite sign (positive away from the crank's axis)",
                           "K с обратным знаком (положительна от оси вала)"),
              _styled(signs=("K",))),
    TableSlip("pj_sign", bi("the inertia force p_j with its sign flipped (p_j = +m_j j/F_p)",
                            "сила инерции p_j с обратным знаком (p_j = +m_j j/F_п)"),
              _styled(signs=("p_j",))),
    TableSlip("beta_neglected", bi("λ dropped from the kinematic factors (β = 0: tg β = 0, "
                                   "sin(α+β)/cos β = sin α, …)",
                                   "λ не учтена в кинематических множителях (β = 0)"),
              _styled(factors="beta_neglected")),
    TableSlip("beta_sign", bi("β with the wrong sign in the kinematic factors",
                              "β с неверным знаком в кинематических множителях"),
              _styled(factors="beta_sign")),
    TableSlip("beta_degrees", bi("β in degrees given to tg, cos, sin as radians",
                                 "β в градусах подставлен в tg, cos, sin как в радианах"),
              _styled(factors="beta_degrees")),
    TableSlip("alpha_degrees", bi("α in degrees taken as radians in the kinematic factors",
                                  "α в градусах принят за радианы в кинематических множителях"),
              _styled(factors="alpha_degrees")),
    TableSlip("firing_order_ignored", bi("the firing order ignored (cylinders taken 1, 2, 3, …)",
                                         "не учтён порядок работы (цилиндры по номерам)"),
              _from_inputs(_order_ignored)),
    TableSlip("exponents_swapped", bi("the polytropic exponents swapped (n₂ for n₁)",
                                      "перепутаны показатели политроп (n₂ вместо n₁)"),
              _from_inputs(_exponents_swapped)),
    *(TableSlip(name, dict(text), _from_inputs(change)) for name, text, _, change in dc.SLIPS),
]
"""Slips in the tables, tried in this order: the way a table is computed (signs, factors)
and the inputs a student took wrongly (:data:`labs.dyncalc.SLIPS` among them)."""


def arguments(inputs: Inputs) -> dict:
    """:func:`labs.dyncalc.dynamic_calculation`'s keyword arguments of a file's nominal values."""
    nominal = {k: (v.value if isinstance(v, Measured) else v) for k, v in inputs.flat().items()}
    return dc._arguments(nominal, inputs)


# ------------------------------------------------------------------------ judging

@dataclass(frozen=True)
class Root:
    """A column that goes wrong by itself: its header, its wrong cells, the slip that
    reproduces it (or None) and the columns that follow from it."""

    column: str
    wrong: int
    slip: TableSlip | None
    follows: tuple[str, ...] = ()


@dataclass(frozen=True)
class TableVerdict:
    """One submitted table judged.

    ``first_row`` is the spreadsheet row (the header is row 1) of the first wrong cell,
    ``first_at`` its abscissa (α in degrees, the polytrope's ratio, or its V_x in m³) and
    ``first_column`` its column's name (the header without the unit)."""

    name: str
    file: str
    cells: int
    wrong: int
    first_row: int | None = None
    first_at: float | None = None
    first_column: str | None = None
    roots: tuple[Root, ...] = ()

    @property
    def verdict(self) -> str:
        return "right" if self.wrong == 0 else "wrong"

    @property
    def slip(self) -> TableSlip | None:
        """The likely cause: the first root's slip."""
        return next((r.slip for r in self.roots if r.slip is not None), None)

    def cause(self, lang: str = "en") -> str:
        """The roots in words: the columns a slip reproduces, the slip, and the columns that
        follow from them (roots no slip explains: each on its own)."""
        groups: dict = {}
        for r in self.roots:
            key = r.slip.name if r.slip else r.column
            columns, follows, slip = groups.get(key, ([], [], r.slip))
            groups[key] = (columns + [r.column], follows + list(r.follows), slip)
        parts = []
        for columns, follows, slip in groups.values():
            why = slip.text[lang] if slip else ("no known slip" if lang == "en" else
                                                "причина не распознана")
            text = f"{', '.join(columns)}: {why}"
            if follows:
                verb = "follows" if len(follows) == 1 else "follow"
                text += (f" ({', '.join(follows)} {verb} from it)" if lang == "en" else
                         f" ({', '.join(follows)} — следствие)")
            parts.append(text)
        return "; ".join(parts)

    def to_dict(self) -> dict:
        return {"table": self.name, "file": self.file, "verdict": self.verdict,
                "cells": self.cells, "wrong": self.wrong, "first_row": self.first_row,
                "first_at": self.first_at, "first_column": self.first_column,
                "slip": None if self.slip is None else self.slip.name,
                "roots": [{"column": r.column, "wrong": r.wrong,
                           "slip": None if r.slip is None else r.slip.name,
                           "slip_text": None if r.slip is None else r.slip.text,
                           "follows": list(r.follows)} for r in self.roots]}


@dataclass(frozen=True)
class _Judged:
    """Columns of one scene's variants at the student's rows and their scales."""

    values: list[dict[str, np.ndarray]]
    scale: dict[str, float] = field(default_factory=dict)


def _variants(scene: Scene, table: StudentTable) -> list[Scene]:
    if table.kind in ("compression", "expansion"):
        return [scene]
    return [replace(scene, kinematics=k, factor_kinematics=f, side=s)
            for k in ("exact", "approx") for f in ("exact", "approx") for s in (1, -1)]


def _evaluate(scene: Scene, table: StudentTable, reference) -> _Judged:
    n = table.abscissa.size
    x = np.concatenate([_abscissa(scene, table), reference])
    values, scale = [], {}
    for variant in _variants(scene, table):
        full = _compute(variant, table, x)
        values.append({k: v[:n] for k, v in full.items()})
        for k, v in full.items():
            scale[k] = max(scale.get(k, 0.0), float(np.max(np.abs(v))))
    return _Judged(values, scale)


def _abscissa(scene: Scene, table: StudentTable) -> np.ndarray:
    """The student's rows as the model's abscissa (a polytrope given by V_x: its ratio)."""
    if table.abscissa_key == "V_x":
        v = dyn.cycle_volumes(scene.args["piston_area"] * 2 * scene.args["crank_radius"],
                              scene.args["compression_ratio"],
                              scene.args["pre_expansion_ratio"])
        return v.total_volume / table.abscissa if table.kind == "compression" else \
            table.abscissa / v.combustion_volume
    return table.abscissa


def _reference(table: StudentTable, args: dict) -> np.ndarray:
    if table.kind == "cylinder":
        return np.radians(np.arange(0.0, 720.0 if args["strokes"] == 4 else 360.0,
                                    REFERENCE_STEP_DEG))
    if table.kind == "summed":
        theta = dyn.cycle_period(args["strokes"]) / args["cylinders"]
        return np.linspace(0.0, theta, 49)
    top = args["compression_ratio"] if table.kind == "compression" else \
        args["compression_ratio"] / args["pre_expansion_ratio"]
    return np.array([1.0, top])


def _agree(column: Column, judged: _Judged, rel_tol: float) -> np.ndarray:
    """Cells of ``column`` within tolerance of any variant (empty cells agree)."""
    ok = np.isnan(column.values)
    written = float(np.max(np.abs(column.values[~ok]))) if not ok.all() else 0.0
    floor = FLOOR_SHARE * rel_tol * min(judged.scale.get(column.key, 0.0), written)
    for values in judged.values:
        x = values[column.key]
        tol = rel_tol * np.abs(x) + floor + np.nan_to_num(column.half_digit)
        ok = ok | (np.abs(column.values - x) <= tol * (1 + 1e-9))
    return ok


def _from_parents(key: str, got: dict[str, Column], ours: dict[str, np.ndarray], args: dict,
                  alpha) -> np.ndarray | None:
    """Column ``key`` computed by the coursework's formula from the student's own columns
    (ours where the student gave none); None for a column computed from none."""
    def v(k):
        return got[k].values if k in got else ours[k]

    if re.fullmatch(r"T\d+", key):
        return None
    if key == "sum":
        cyl = [k for k in got if re.fullmatch(r"T\d+", k)]
        return sum(got[k].values for k in cyl) if len(cyl) == args["cylinders"] else None
    if key == "M" and "sum" in ours:
        return v("sum") * args["crank_radius"]
    beta = v("beta") if "beta" in got else ours.get("beta")
    formulas = {
        "dp_g": lambda: v("p_g") - args["p_0"],
        "p": lambda: (v("dp_g") if "dp_g" in got else v("p_g") - args["p_0"]) + v("p_j"),
        "P": lambda: v("p") * args["piston_area"],
        "tan_beta": lambda: np.tan(beta), "inv_cos_beta": lambda: 1 / np.cos(beta),
        "cos_ab": lambda: np.cos(alpha + beta) / np.cos(beta),
        "sin_ab": lambda: np.sin(alpha + beta) / np.cos(beta),
        "N": lambda: v("P") * v("tan_beta"), "S": lambda: v("P") * v("inv_cos_beta"),
        "K": lambda: v("P") * v("cos_ab"), "T": lambda: v("P") * v("sin_ab"),
        "M": lambda: v("T") * args["crank_radius"]}
    return formulas[key]() if key in formulas else None


def _parents(key: str, got: dict[str, Column]) -> tuple[str, ...]:
    if key == "sum":
        return tuple(k for k in got if re.fullmatch(r"T\d+", k))
    if key == "M" and "sum" in got:
        return ("sum",)
    if key == "p" and "dp_g" not in got:
        return ("p_g", "p_j")
    return PARENTS.get(key, ())


def judge_table(table: StudentTable, inputs: Inputs, policy: Policy = Policy()) -> TableVerdict:
    """Judge a submitted table cell by cell and find the roots of what goes wrong and their
    likely causes (see the module's docstring).

    Parameters
    ----------
    table : StudentTable
    inputs : Inputs
        The submission's validated inputs (:data:`labs.dyncalc.SPEC`).
    policy : Policy
        Its ``rel_tol`` (the floor is :data:`FLOOR_SHARE` of it at the column's scale).

    Returns
    -------
    TableVerdict
    """
    base = Scene(arguments(inputs))
    reference = _reference(table, base.args)
    ours = _evaluate(base, table, reference)
    got = {c.key: c for c in table.columns}
    wrong = {c.key: ~_agree(c, ours, policy.rel_tol) for c in table.columns}
    cells = sum(int(np.sum(~np.isnan(c.values))) for c in table.columns)
    count = sum(int(w.sum()) for w in wrong.values())
    if count == 0:
        return TableVerdict(table.name, table.file, cells, 0)
    row = int(np.argmax(np.any(np.array(list(wrong.values())), axis=0)))
    first = next(c for c in table.columns if wrong[c.key][row])
    alpha = table.abscissa
    root_of: dict[str, str] = {}
    for c in table.columns:
        if not wrong[c.key].any():
            continue
        bad_parents = [q for q in _parents(c.key, got) if q in got and wrong[q].any()]
        formula = _from_parents(c.key, got, ours.values[0], base.args, alpha) \
            if bad_parents else None
        if formula is not None:
            follows = _agree(c, _Judged([{c.key: formula}], ours.scale), policy.rel_tol)
            if follows[wrong[c.key]].all():
                root_of[c.key] = root_of[bad_parents[0]]
                continue
        root_of[c.key] = c.key
    slipped = _slipped(base, inputs, table, reference)
    roots = []
    for key in dict.fromkeys(root_of.values()):
        column = got[key]
        best, most = None, 0
        for slip, judged in slipped:
            if key not in judged.values[0] or not _agree(column, judged, policy.rel_tol).all():
                continue
            reproduced = sum(int((wrong[k] & _agree(got[k], judged, policy.rel_tol)).sum())
                             for k in got if k in judged.values[0])
            if reproduced > most:
                best, most = slip, reproduced
        roots.append(Root(_shown(column), int(wrong[key].sum()), best, tuple(
            _shown(got[k]) for k, r in root_of.items() if r == key and k != key)))
    at = round(float(np.degrees(alpha[row]) if table.kind in ("cylinder", "summed") else
                     alpha[row]), 9)
    return TableVerdict(table.name, table.file, cells, count, int(table.lines[row]), at,
                        _shown(first), tuple(roots))


def _shown(column: Column) -> str:
    """A column as the messages name it: its header without the unit."""
    return split_header(column.header)[0].strip()


def _slipped(base: Scene, inputs: Inputs, table: StudentTable, reference):
    out = []
    for slip in TABLE_SLIPS:
        try:
            scene = slip.scene(base, inputs)
            if scene is None:
                continue
            out.append((slip, _evaluate(scene, table, reference)))
        except (InputError, ValueError, ZeroDivisionError, FloatingPointError):
            continue
    return out


def check_tables(path: str | Path, entries, inputs: Inputs, policy: Policy = Policy(), *,
                 confine: bool = False) -> list[TableVerdict]:
    """Read and judge every table of a submission's ``[reported.tables]``.

    Parameters
    ----------
    path : str or Path
        The submission (the tables' paths are relative to its folder).
    entries : dict
        ``[reported.tables]``: table name (:data:`KINDS`) → CSV path.
    inputs : Inputs
        The submission's validated inputs.
    policy : Policy
    confine : bool
        Read no file outside the submission's folder.

    Returns
    -------
    list of TableVerdict

    Raises
    ------
    InputError
        An unknown table name, a missing or unreadable file, a bad table (:func:`read_table`).
    """
    path = Path(path)
    if not isinstance(entries, dict) or not entries:
        raise InputError("[reported.tables] names no table", "write e.g. forces = "
                         "\"forces.csv\" (tables: " + ", ".join(KINDS) + ")", file=str(path),
                         field="reported.tables",
                         ru=("[reported.tables] не называет ни одной таблицы", "напишите, "
                             "например, forces = \"forces.csv\" (таблицы: " + ", ".join(KINDS)
                             + ")"))
    args = arguments(inputs)
    drawing = inputs.sections.get("drawing")
    out = []
    for name, file in entries.items():
        where = f"reported.tables.{name}"
        if name not in KINDS:
            raise InputError(f"'{name}' is not a table of the coursework",
                             f"name the tables {', '.join(KINDS)}", file=str(path), field=where,
                             ru=(f"'{name}' — не таблица курсовой работы",
                                 f"называйте таблицы {', '.join(KINDS)}"))
        if not isinstance(file, str):
            raise InputError(f"{file!r} is not a file name", f"write {name} = \"{name}.csv\"",
                             file=str(path), field=where,
                             ru=(f"{file!r} — не имя файла", f"напишите {name} = \"{name}.csv\""))
        csv_path = path.parent / file
        if confine and resolved(path.parent) not in resolved(csv_path).parents:
            raise InputError(f"'{file}' lies outside the submission's folder",
                             "put the table beside the submission", file=str(path), field=where,
                             ru=(f"'{file}' лежит вне папки работы",
                                 "положите таблицу рядом с файлом работы"))
        table = read_table(csv_path, name, cylinders=args["cylinders"],
                           piston_area=args["piston_area"],
                           mu_p=drawing["mu_p"].value if drawing else None, shown=str(csv_path))
        out.append(judge_table(table, inputs, policy))
    return out
