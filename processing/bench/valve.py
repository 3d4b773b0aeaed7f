"""Benchmark families of the static stiffness test (lab 5's valve train): the drive's
stiffness against its truth and its stated uncertainty over reading noise, gauge resolution
and friction, and where the straight line breaks down (too few load steps, lash, contact
stiffening).

Every table is made by :mod:`processing.synth.valve_table`: the default :class:`ValveTrain`
(i = 1.5, c = 2.055 kN/mm at the valve) loaded 0 → 1000 N in ``steps`` equal steps and back,
through a lever whose true ratio is off by up to ± 0.5 %, read on four dial gauges
(0.01 mm a division, scale errors within ± 2 %) with the given scatter and rounded to the
given resolution. Truth: :meth:`ValveTrain.line_stiffness`, the stiffness straight lines
give through the exact table (the links' own without contact stiffening).

Families
--------
``stiffness``
    c (the drive at the valve) and c_rod (the link read as the difference of two small gauges) by
    ``midway lines`` (:func:`processing.oscillations.load_cycle.fit_branches`: a line through each
    branch without its turning point, the line midway between them; what lab 5 reports), ``pointwise
    mean`` (the manual's Δl = (Δl_load + Δl_unload)/2 at each load, one line through it), ``loading
    branch`` (a line through the loading readings alone) and ``top secant`` (c = P/Δl at the largest
    load, the manual's formula on one row). Error c/c_true − 1; ``covered``: the truth inside the
    method's Monte Carlo 95 % interval (:func:`processing.uncertainty.propagate` over the slopes,
    the gauges' and the lever's scale errors; the lab's method states its slopes' type A topped up
    to the gauges' resolution, the others their type A alone).
``stability``
    ``midway lines`` and ``pointwise mean`` over load steps × friction × lash: where the
    fit is refused (fewer than three steps beyond a turning point) and where it drifts.
``curvature``
    ``midway lines`` over contact stiffening × lash (friction 8 N, ten steps).
"""
from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from processing.oscillations.load_cycle import LoadCycle, fit_branches
from ..regression import fit_line
from ..synth.valve_table import DialGauges, ValveTrain, stiffness_run
from ..uncertainty import Measured, propagate
from processing.valvetrain.valve_train import stiffnesses
from .harness import (Case, Family, MapAxes, Method, Target, abs_error, coverage_targets,
                      environment, plot_error_time, plot_map, run_family, summary,
                      write_rows, write_targets)

TOLERANCE = 0.04
"""|c/c_true − 1| the lab's method must keep in the target region, at the 95th percentile."""

TARGET_SCATTER, TARGET_RESOLUTION, TARGET_FRICTION = 0.25, 1.0, 30.0
"""The target region: reading scatter 0.1–0.25 division (below 0.1 the rounding is no longer
random from row to row), whole divisions, friction ≤ 30 N (3 % of the largest load)."""

BIAS = 0.005
"""|median of c/c_true − 1| the lab's method may keep at 30 N of friction (the manual's
pointwise mean is tilted by about 0.7 F/P_max there, 2 %)."""

SCALE_LIMIT, LEVER_LIMIT = 0.02, 0.005
"""The gauges' and the lever's scale errors are drawn within these (and so stated)."""

DIVISION = DialGauges().division
"""The gauges' division: the resolution the lab's method states for a reading. [m]"""

FAILURES = (ValueError,)
"""What a fit raises when a branch has too few steps."""


@dataclass(frozen=True)
class Plan:
    """How much to run: the accuracy grid, the two stability grids and the timed runs."""

    scatter: tuple[float, ...]
    resolution: tuple[float, ...]
    friction: tuple[float, ...]
    seeds: int
    map_steps: tuple[int, ...]
    map_friction: tuple[float, ...]
    map_lash: tuple[float, ...]
    map_contact: tuple[float, ...]
    map_seeds: int
    repeat: int


FULL = Plan(scatter=(0.1, 0.25, 0.5), resolution=(0.5, 1.0), friction=(0.0, 8.0, 30.0),
            seeds=200, map_steps=(2, 3, 4, 5, 10), map_friction=(0.0, 8.0, 30.0, 60.0),
            map_lash=(0.0, 10e-6, 30e-6, 60e-6), map_contact=(0.0, 20e-6, 40e-6, 80e-6),
            map_seeds=10, repeat=3)
QUICK = Plan(scatter=(0.1, 0.25), resolution=(1.0,), friction=(8.0, 30.0), seeds=200,
             map_steps=(2, 3, 5, 10), map_friction=(0.0, 30.0, 60.0), map_lash=(0.0, 30e-6),
             map_contact=(0.0, 40e-6, 80e-6), map_seeds=3, repeat=1)

STABILITY_AXES = MapAxes(x="steps", y="friction", column="lash",
                         labels={"steps": "load steps each way", "friction": "friction [N]",
                                 "lash": "lash [m]"})
CURVATURE_AXES = MapAxes(x="contact", y="lash", column="friction",
                         labels={"contact": "contact deformation at 1000 N [m]",
                                 "lash": "lash [m]", "friction": "friction [N]"})


# --- cases -----------------------------------------------------------------------------------

@dataclass(frozen=True)
class Tables:
    """One loading–unloading run as the methods get it: x = P [N], y = Δl₁…Δl₄ [m]."""

    cycles: list
    i: float


def table_cases(scatter, resolution, friction, seeds: int, *, steps=(10,), lash=(0.0,),
                contact=(0.0,)) -> Iterator[Case]:
    """One case per (scatter, resolution, friction, steps, lash, contact, seed): a run and
    the true stiffnesses of its straight lines."""
    gauges_of = {(s, r): DialGauges(resolution=r, scatter=s)
                 for s, r in itertools.product(scatter, resolution)}
    for s, r, f, n, gap, hertz, seed in itertools.product(scatter, resolution, friction, steps,
                                                           lash, contact, range(seeds)):
        rng = np.random.default_rng([seed, 5])
        train = ValveTrain(friction=f, lash=gap, contact=hertz)
        gauges = gauges_of[s, r]
        run = stiffness_run(train, gauges, rng, step=1000.0 / n,
                            lever_error=rng.uniform(-LEVER_LIMIT, LEVER_LIMIT),
                            scale_error=rng.uniform(-SCALE_LIMIT, SCALE_LIMIT, 4))
        dl = run.readings * gauges.division
        cycle = LoadCycle(run.P, dl - dl[:, :1], int(np.argmax(run.P)))
        yield Case({"scatter": s, "resolution": r, "friction": f, "steps": n, "lash": gap,
                    "contact": hertz, "seed": seed}, Tables([cycle], train.i),
                   train.line_stiffness(np.unique(run.P)), run.P.size)


# --- the methods -----------------------------------------------------------------------------

@dataclass(frozen=True)
class Answer:
    """A method's c and c_rod, and c's 95 % interval (NaN: none stated)."""

    c: float
    c_rod: float
    low: float = math.nan
    high: float = math.nan


def _propagated(slopes: list[Measured], i: float) -> Answer:
    """c and c_rod from the four gauges' slopes, their 95 % interval from the slopes' own
    uncertainty and the gauges' and lever's scale errors."""
    inputs = {f"s{j}": s for j, s in enumerate(slopes)}
    inputs.update({f"g{j}": Measured(1.0, limit=SCALE_LIMIT) for j in range(4)})
    inputs["lever"] = Measured(1.0, limit=LEVER_LIMIT)

    def model(**x):
        chain = stiffnesses(1.0, *(x[f"s{j}"] / x[f"g{j}"] / x["lever"] for j in range(4)), i)
        return {"c": chain.total, "c_rod": chain.rod}

    prop = propagate(model, inputs, n_samples=2000, seed=1)
    return Answer(prop["c"].value, prop["c_rod"].value, *prop["c"].interval95)


def _midway(t: Tables) -> Answer:
    lines = fit_branches(t.cycles, DIVISION / math.sqrt(12))
    return _propagated([lines[j, "mean"].measured_slope() for j in range(4)], t.i)


def _pooled_fit(t: Tables, branch: str) -> Answer:
    parts = [c.branch(branch) for c in t.cycles]
    x = np.concatenate([p for p, _ in parts])
    y = np.concatenate([d for _, d in parts], axis=1)
    return _propagated([fit_line(x, y[j]).measured_slope() for j in range(4)], t.i)


def _top_secant(t: Tables) -> Answer:
    c = t.cycles[0]
    chain = stiffnesses(c.x[c.peak], *c.y[:, c.peak], t.i)
    return Answer(chain.total, chain.rod)


def stiffness_error(answer: Answer, truth) -> dict:
    """c/c_true − 1, c_rod/c_rod,true − 1 and whether the stated interval holds c_true."""
    covered = answer.low <= truth.total <= answer.high if math.isfinite(answer.low) else np.nan
    return {"error": answer.c / truth.total - 1, "rod": answer.c_rod / truth.rod - 1,
            "covered": covered, "u_rel": (answer.high - answer.low) / 3.92 / truth.total}


def stiffness_family(name: str = "stiffness", methods=("midway lines", "pointwise mean",
                                                      "loading branch", "top secant")) -> Family:
    """The stiffness methods of the module's notes."""
    calls: dict[str, Callable] = {"midway lines": _midway,
                                  "pointwise mean": lambda t: _pooled_fit(t, "mean"),
                                  "loading branch": lambda t: _pooled_fit(t, "load"),
                                  "top secant": _top_secant}
    return Family(name, [Method(m, calls[m]) for m in methods], stiffness_error,
                  error_label="|c/c_true − 1|", failures=FAILURES)


# --- targets and summaries -------------------------------------------------------------------

def target_region(frame: pd.DataFrame, family: str = "stiffness") -> pd.DataFrame:
    """Rows of ``family`` with scatter 0.1–0.25 division, divisions read to at most one,
    friction ≤ 30 N."""
    f = frame[frame["family"] == family]
    return f[f["scatter"].between(0.1, TARGET_SCATTER) & (f["resolution"] <= TARGET_RESOLUTION)
             & (f["friction"] <= TARGET_FRICTION)]


def targets(frame: pd.DataFrame) -> list[Target]:
    """The performance targets from the rows of :func:`run`."""
    out = []
    region = target_region(frame)
    lab = region[region["method"] == "midway lines"]
    if not lab.empty:
        err = abs_error(lab)
        out.append(Target("c, midway lines, target region: 95th percentile of |c/c_true − 1|",
                          float(np.quantile(err, 0.95)), TOLERANCE, unit="relative",
                          detail=f"{len(lab)} tables; worst {err.max():.4g}"))
        out += coverage_targets("c, midway lines", lab["covered"], "tables")
        rough = lab[lab["friction"] >= TARGET_FRICTION]
        if not rough.empty:
            out.append(Target(f"c, midway lines at {TARGET_FRICTION:g} N of friction: |median "
                              "of c/c_true − 1|", abs(float(rough["error"].median())), BIAS,
                              unit="relative", detail=f"{len(rough)} tables"))
    stab = frame[(frame["family"] == "stability") & (frame["method"] == "midway lines")]
    if not stab.empty:
        few = stab[stab["steps"] < 3]
        if not few.empty:
            refused = (few["failed"].fillna("") != "").mean()
            out.append(Target("tables of fewer than three steps each way refused", refused, 1.0,
                              "min", detail=f"{len(few)} tables"))
        silent = silent_failures(stab)
        out.append(Target("stability cells (≥ 3 steps) beyond the tolerance and outside the "
                          "stated U", float(len(silent)), 0, unit="cells",
                          detail=", ".join(f"{n:g} steps, {f:g} N, lash {g:g} m"
                                           for n, f, g in silent) or "none"))
    return out


def silent_failures(part: pd.DataFrame) -> list[tuple]:
    """Cells (steps, friction, lash) whose median |error| exceeds :data:`TOLERANCE` while
    the median stated 95 % half-width is smaller and most tables are not refused."""
    part = part.assign(abs_error=abs_error(part), U=1.96 * part["u_rel"],
                       refused=part["failed"].fillna("") != "")
    cells = part.groupby(["steps", "friction", "lash"]).agg(
        err=("abs_error", "median"), U=("U", "median"), refused=("refused", "mean"))
    bad = cells[(cells["err"] > TOLERANCE) & (cells["refused"] < 0.5)
                & ~(cells["U"] >= cells["err"])]
    return list(bad.index)


def accuracy_table(frame: pd.DataFrame) -> pd.DataFrame:
    """Per method, friction and scatter: median |error| of c and c_rod [%], its median
    signed error [%] and the coverage of c [%]."""
    part = frame[frame["family"] == "stiffness"]
    part = part.assign(abs_error=100 * abs_error(part), bias=100 * part["error"],
                       rod=100 * part["rod"].abs(), covered=100 * part["covered"].astype(float))
    return part.groupby(["method", "friction", "scatter"]).agg(
        median_err=("abs_error", "median"), bias=("bias", "median"), rod=("rod", "median"),
        covered=("covered", "mean"))


def stability_table(frame: pd.DataFrame, family: str, index, columns: str) -> pd.DataFrame:
    """Median |error| of c [%] (midway lines) over a stability grid; refused tables count
    as failed."""
    part = frame[(frame["family"] == family) & (frame["method"] == "midway lines")]
    part = part.assign(abs_error=100 * abs_error(part))
    return part.groupby([*index, columns])["abs_error"].median().unstack(columns)


def summary_lines(frame: pd.DataFrame) -> list[str]:
    """The summary printed after the run."""
    def fmt(v):
        return f"{v:.3g}"

    return ["Summary (median over cases; |err| relative):",
            summary(frame).to_string(index=False, float_format=fmt), "",
            "c by case: median |c/c_true − 1| [%], median signed error [%], median |c_rod "
            "error| [%], coverage of the stated 95 % interval [%]:",
            accuracy_table(frame).to_string(float_format=fmt), "",
            "Stability of the midway lines: median |c/c_true − 1| [%] (inf: refused) by load "
            "steps and friction, columns lash [m]:",
            stability_table(frame, "stability", ["friction", "steps"], "lash")
            .to_string(float_format=fmt), "",
            "Contact stiffening and lash: median |c/c_true − 1| [%], columns contact [m]:",
            stability_table(frame, "curvature", ["lash"], "contact").to_string(float_format=fmt)]


def run(out, *, quick: bool = False,
        log: Callable[[str], None] = print) -> tuple[pd.DataFrame, list[Target]]:
    """Run every family, write ``bench.csv``, the charts and ``targets.json`` to ``out``.

    Parameters
    ----------
    out : str or Path
        Output folder (made if missing).
    quick : bool
        The coarse plan (:data:`QUICK`, well under a minute) instead of :data:`FULL`.
    log : callable
        Where progress lines go.

    Returns
    -------
    frame : pandas.DataFrame
        All rows (also ``bench.csv``).
    targets : list of Target
    """
    plan = QUICK if quick else FULL
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    log(f"stiffness: scatter {plan.scatter} div x resolution {plan.resolution} div x friction "
        f"{plan.friction} N x {plan.seeds} seeds")
    rows = run_family(stiffness_family(), table_cases(plan.scatter, plan.resolution,
                                                      plan.friction, plan.seeds),
                      repeat=plan.repeat)
    log(f"stability: steps {plan.map_steps} x friction {plan.map_friction} N x lash "
        f"{plan.map_lash} m x {plan.map_seeds} seeds")
    rows += run_family(stiffness_family("stability", ("midway lines", "pointwise mean")),
                       table_cases((TARGET_SCATTER,), (TARGET_RESOLUTION,), plan.map_friction,
                                   plan.map_seeds, steps=plan.map_steps, lash=plan.map_lash),
                       repeat=1)
    log(f"curvature: contact {plan.map_contact} m x lash {plan.map_lash} m")
    rows += run_family(stiffness_family("curvature", ("midway lines",)),
                       table_cases((TARGET_SCATTER,), (TARGET_RESOLUTION,), (8.0,),
                                   plan.map_seeds, lash=plan.map_lash,
                                   contact=plan.map_contact), repeat=1)
    frame = write_rows(rows, out / "bench.csv")
    plot_error_time(frame, out / "error_vs_time.png",
                    {"stiffness": stiffness_family().error_label})
    plot_map(frame[frame["family"] == "stability"], out / "stability_map.png", STABILITY_AXES,
             threshold=TOLERANCE)
    plot_map(frame[frame["family"] == "curvature"], out / "curvature_map.png", CURVATURE_AXES,
             threshold=TOLERANCE)
    found = targets(frame)
    write_targets(found, out / "targets.json", environment())
    return frame, found
