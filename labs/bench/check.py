"""Benchmark of ``dynlab check`` (topic ``check`` of ``python -m processing.bench``): a class
of seeded variants with slips injected at known places, checked in one run.

For each lab with a scene (:data:`LABS_CHECKED`) and each seed, the
variant is written (:func:`write_synthetic`; the coursework's odd seeds vary the marine diesel
instead of the car) and reduced; its submission reports every result of the answer key,
each either right — our value written to 3–6 significant figures at random — or through one
slip drawn from those that apply to it (the generic factors of
:data:`processing.checking.grading.FACTOR_SLIPS` by the result's unit, the lab's own ``SLIPS`` for
the results they change) and that move it by more than 3 % and out of what agrees with ours (a
"slip" within a residual's own uncertainty is no mistake to find), and that no other candidate slip
imitates (two slips giving the same value cannot be told apart by anyone). The coursework's
submissions also report its tables (:func:`_tables`): one cylinder's forces, the summed tangential
force and the compression polytrope, each right or through one table slip
(:data:`labs.teachers.dyncalc_check.TABLE_SLIPS`), at a random step, precision, separator and choice
of exact or two-harmonic kinematics. The class is then checked file by file as ``dynlab check DIR``
does, timed.

The slips drawn include those inside formulas: of the inputs
(:data:`processing.checking.input_slips.INPUT_SLIPS`, re-reduced) and of the constants
(:data:`processing.checking.grading.CONSTANT_SLIPS`); copies are seeded in every lab with readings,
those of labs 3, 4, 6 and 7 handing in the same recordings (saved again or not).

Targets: every injected slip found and named (recall 100 %), the slips inside formulas named
in at least :data:`FORMULA_RECALL` of cases, no right value called anything
but right, rounded or over-precise (0 false alarms), and a class of 200 submissions of each lab
checked within a minute of CPU time on one core (a target per lab, :func:`_class_targets`: its
mean time per submission times 200, its first submission untimed as it pays the imports; the
quick plan extrapolates from three submissions per lab).
"""
from __future__ import annotations

import math
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pandas as pd

from processing.bench.harness import Target, environment, write_rows, write_targets
from processing.diagnostics import InputError
from processing.checking.grading import CONSTANT_SLIPS, FACTOR_SLIPS, Policy, Reported, agrees
from processing.checking.input_slips import INPUT_SLIPS
from processing.inputs.reuse import scope
from processing.measurement import load, read_toml

from labs.teachers.check import (BLAS_THREADS, CHECK_SAMPLES, Check, _input_slips, _lab_slips,
                                 check, copies)
from labs.registry import LABS, evaluate

LABS_CHECKED = ("lab1", "lab2", "lab3", "lab4", "lab5", "lab6", "lab7", "lab8", "lab9", "dyncalc")
FULL_SEEDS, QUICK_SEEDS = 200, 4
"""Seeds per lab: a class of 200 variants of each lab (four of each in the quick plan: the
first check of a lab is not timed, :func:`_checked`)."""
DIESEL_VARIED = {"engine": ("n",), "cycle": ("p_a", "p_z", "eps", "n1", "n2"),
                 "geometry": ("D", "S", "lambda"), "masses": ("m_j",),
                 "flywheel": ("delta", "D_rim")}
"""What a marine-diesel variant of the coursework changes (its m_j is a mass, not per area)."""
TABLE_SHIFT = 0.05
"""A table slip is injected only where it moves some column by more than this share of the
column's largest value, and where no other slip gives the same table."""
CLASS_SECONDS = 60.0
"""A class of 200 submissions checked within this. [s]"""
CLASS_SIZE = 200
SLIP_SHIFT = 0.03
"""A slip is injected only where it moves the value by more than this (relative): three times
the default policy's tolerance, so that the teeth counted for lab 3's pitches (60/58, 3.4 %)
are in the class too."""


def _text(value: float, unit: str, figures: int) -> str:
    """The value as a student writes it to ``figures`` significant figures, trailing zeros
    kept (0.2 to four figures is 0.2000, not 0.2: a figure dropped is a coarser value)."""
    return f"{value:#.{figures}g} {unit}".strip() if unit else f"{value:#.{figures}g}"


def _written(lab_id: str, seed: int, folder: Path) -> dict:
    if lab_id == "dyncalc" and seed % 2:
        from labs.sample_variant import design_variant

        return design_variant("dyncalc", "marine_diesel.toml", folder, seed, DIESEL_VARIED)
    return LABS[lab_id].write_synthetic(folder, seed)


def _unique(candidates: list[tuple[str, float]], name: str, r) -> list[tuple[str, float]]:
    """The candidates no other slip imitates: its value, written to four figures, agrees with
    none of theirs as the check tries a slip (:func:`processing.checking.grading.judge`: the
    candidate's u scaled with it, half the last digit written)."""
    def written(v: float) -> Reported:
        place = 10.0 ** (math.floor(math.log10(abs(v))) - 3) if v else 0.0
        return Reported(name, v, digits=4, last_place=place)

    return [(n, v) for n, v in candidates
            if not any(m != n and agrees(written(v), w, r.u * abs(w / r.value), Policy(),
                                         k=r.estimate.k)[0]
                       for m, w in candidates)]


@scope()
def _submission(lab_id: str, seed: int, folder: Path, rng) -> list[dict]:
    """Write one variant and its submission; the truth of every reported value (the
    variant's reductions in one :func:`processing.inputs.reuse.scope`, as a check's)."""
    module = LABS[lab_id]
    written = _written(lab_id, seed, folder)
    ours = evaluate(written["toml"], n_samples=500).results
    data = read_toml(written["toml"])
    inputs = load(written["toml"], module.SPEC, data)
    names = [n for n in ours if math.isfinite(ours[n].value) and ours[n].value != 0]
    lab_slips = _lab_slips(module, ours, inputs, {"n_samples": 500}) \
        + _input_slips(module, inputs, {"n_samples": CHECK_SAMPLES}, names)
    lines, injected = [], []
    for name in names:
        r = ours[name]
        candidates = [(s.name, s.candidate(name, r.value, r.unit))
                      for s in list(FACTOR_SLIPS) + lab_slips + list(CONSTANT_SLIPS)]
        candidates = _unique([(n, v) for n, v in candidates
                              if v is not None and abs(v / r.value - 1) > SLIP_SHIFT
                              and not agrees(Reported(name, v, digits=4), r.value, r.u,
                                             Policy(), k=r.estimate.k)[0]], name, r)
        if candidates and rng.random() < 0.5:
            slip, value = candidates[rng.integers(len(candidates))]
            figures = 4
        else:
            slip, value, figures = None, r.value, int(rng.integers(3, 7))
        lines.append(f'{name} = "{_text(value, r.unit, figures)}"')
        injected.append({"lab": lab_id, "seed": seed, "name": name, "injected": slip})
    if lab_id == "dyncalc":
        tables = _tables(inputs, folder, rng)
        lines.append("[reported.tables]")
        for kind, (file, slip) in tables.items():
            lines.append(f'{kind} = "{file.name}"')
            injected.append({"lab": lab_id, "seed": seed, "name": f"table:{kind}",
                             "injected": slip})
    with written["toml"].open("a", encoding="utf-8") as f:
        f.write("\n[reported]\n" + "\n".join(lines) + "\n")
    for row in injected:
        row["file"] = str(written["toml"])
    return injected


def _tables(inputs, folder: Path, rng) -> dict[str, tuple[Path, str | None]]:
    """The coursework's tables as a student's spreadsheet exports them, each right or through
    one table slip that shows and that no other slip imitates: file and slip per table."""
    from dataclasses import replace

    from labs.teachers import dyncalc_check as ck

    base = ck.Scene(ck.arguments(inputs))
    base = replace(base, kinematics=str(rng.choice(["exact", "approx"])),
                   factor_kinematics=str(rng.choice(["exact", "approx"])))
    out = {}
    for kind in ("forces", "summed", "compression"):
        step = float(rng.choice([10.0, 15.0, 30.0]))
        x, first = _rows(kind, base.args, step)
        ours = _model(kind, base, x)
        slipped = {}
        for slip in ck.TABLE_SLIPS:
            scene = slip.scene(base, inputs)
            if scene is None:
                continue
            try:
                values = _model(kind, scene, x)
            except (ValueError, ZeroDivisionError):
                continue
            if _shift(values, ours) > TABLE_SHIFT:
                slipped[slip.name] = values
        names = [n for n in slipped if all(_shift(slipped[n], slipped[m]) > TABLE_SHIFT
                                           for m in slipped if m != n)]
        slip = str(rng.choice(names)) if names and rng.random() < 0.5 else None
        values = slipped[slip] if slip else ours
        decimals, sep = int(rng.integers(3, 5)), str(rng.choice([",", ";"]))
        out[kind] = (_write_table(folder / f"{kind}.csv", first, x, values, decimals, sep), slip)
    return out


def _rows(kind: str, args: dict, step: float):
    """The student's abscissa (SI) and its header: α every ``step``° over the cycle (or one
    firing interval), or V_a/V_x = 1 … ε."""
    if kind == "compression":
        top = args["compression_ratio"]
        ratio = np.arange(1.0, math.floor(top) + 1)
        return (ratio if top - ratio[-1] < 1e-9 else np.append(ratio, top)), "V_a/V_x"
    span = 720.0 if kind == "forces" else 720.0 / args["cylinders"]
    return np.radians(np.arange(0.0, span + step / 2, step)), "α, °"


def _model(kind: str, scene, x) -> dict[str, np.ndarray]:
    from labs.teachers import dyncalc_check as ck

    if kind == "forces":
        return ck.cylinder(scene, x)
    if kind == "summed":
        return ck.summed(scene, x)
    return ck.polytrope(scene, "compression", x)


def _shift(a: dict, b: dict) -> float:
    """The largest change of a column, as a share of the column's largest value."""
    shifts = [0.0]
    for k in b:
        change, scale = float(np.max(np.abs(a[k] - b[k]))), float(np.max(np.abs(b[k])))
        shifts.append(change / scale if scale > 0 else math.inf if change > 0 else 0.0)
    return max(shifts)


HEADERS = {"beta": ("β, °", 180 / math.pi), "p_g": ("p_g, MPa", 1e-6),
           "dp_g": ("Δp_g, MPa", 1e-6), "p_j": ("p_j, MPa", 1e-6), "p": ("p, MPa", 1e-6),
           "P": ("P, kN", 1e-3), "tan_beta": ("tg β", 1.0), "inv_cos_beta": ("1/cos β", 1.0),
           "cos_ab": ("cos(α+β)/cos β", 1.0), "sin_ab": ("sin(α+β)/cos β", 1.0),
           "N": ("N, kN", 1e-3), "S": ("S, kN", 1e-3), "K": ("K, kN", 1e-3),
           "T": ("T, kN", 1e-3), "M": ("M, N*m", 1.0), "sum": ("ΣT, kN", 1e-3),
           "V_x": ("V_x, L", 1e3), "p_x": ("p_x, MPa", 1e-6)}
"""The coursework's headers of the bench's tables, and the factor from SI to their units."""


def _write_table(path: Path, first: str, x, values: dict, decimals: int, sep: str) -> Path:
    columns = [k for k in values if k in HEADERS or k[1:].isdigit()]
    heads = [first] + [HEADERS[k][0] if k in HEADERS else f"{k}, kN" for k in columns]
    shown = np.degrees(x) if first.startswith("α") else x

    def cell(v: float) -> str:
        text = f"{v:.{decimals}f}"
        return text.replace(".", ",") if sep == ";" else text

    lines = [sep.join(f'"{h}"' if sep in h else h for h in heads)]
    for r in range(len(x)):
        lines.append(sep.join([cell(shown[r])] + [cell(values[k][r] * (
            HEADERS[k][1] if k in HEADERS else 1e-3)) for k in columns]))
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


FORMULA_SLIPS = {s.name for s in INPUT_SLIPS} | {s.name for s in CONSTANT_SLIPS}
"""The slips inside a formula: of its inputs (re-reduced) and of its constants."""
FORMULA_RECALL = 0.9
"""Share of the slips inside formulas to be named (the issue's target)."""
RECORDED = ("lab3", "lab4", "lab6", "lab7", "lab9")
"""The labs whose files name recordings: their formula slips are counted apart too."""

COPIES_PER_LAB = 20
"""Copies seeded per lab, each of a variant of the class with up to two readings edited."""
COPIES_SEEDED = ("lab1", "lab2", "lab3", "lab4", "lab5", "lab6", "lab7", "lab8", "lab9")
"""Labs whose copies are seeded: every lab with readings (the coursework's data is its
variant's, named by the key). Labs 3, 4, 6 and 7 keep their readings in recordings: a copy
hands in the same files (compared by their samples), its file's readings edited as any."""


def copy_of(check_: Check, rng, edits: int) -> Check:
    """A copy of a submission's readings as a student makes one: ``edits`` readings changed
    (by 0.2, or ±1 in the last place written), added (a reading 3 % off beside one) or
    rounded to a decimal fewer; its recordings the same files."""
    texts = list(check_.readings)
    for _ in range(edits):
        i = int(rng.integers(len(texts)))
        x, kind = texts[i], ("changed", "one off", "added", "rounded")[int(rng.integers(4))]
        places = len(x.split(".")[1]) if "." in x else 0
        if kind == "changed":
            texts[i] = f"{float(x) + 0.2:.{max(places, 1)}f}"
        elif kind == "one off":
            texts[i] = f"{float(x) + rng.choice((-1, 1)) * 10.0 ** -places:.{places}f}"
        elif kind == "added":
            texts.insert(i, f"{float(x) * 1.03 + 0.2:.2f}")
        else:
            texts[i] = f"{float(x):.{max(places - 1, 0)}f}"
    return Check(f"{check_.file} (copy)", check_.lab, "copy", [], tuple(texts),
                 recordings=check_.recordings)


def _copies_found(judged: dict[str, Check], rng) -> tuple[int, int, int, int]:
    """(false pairs among the class's honest variants, pairs compared, seeded copies found,
    seeded): the class of each lab as handed in, then, for :data:`COPIES_SEEDED`, each of
    :data:`COPIES_PER_LAB` copies (0–2 readings edited) added to it alone."""
    by_lab: dict[str, list[Check]] = {}
    for c in judged.values():
        by_lab.setdefault(c.lab, []).append(c)
    false = pairs = found = seeded = 0
    for lab, group in by_lab.items():
        false += len(copies(group))
        pairs += len(group) * (len(group) - 1) // 2
        for _ in range(min(COPIES_PER_LAB, len(group)) if lab in COPIES_SEEDED else 0):
            original = group[int(rng.integers(len(group)))]
            copy = copy_of(original, rng, int(rng.integers(3)))
            seeded += 1
            found += any({p.a.file, p.b.file} == {original.file, copy.file}
                         for p in copies([*group, copy]))
    return false, pairs, found, seeded


def run(out, *, quick: bool = False, log: Callable[[str], None] = print,
        labs: tuple[str, ...] = LABS_CHECKED,
        seeds: int | None = None) -> tuple[pd.DataFrame, list[Target]]:
    """Write the class of ``labs`` (``seeds`` variants of each, :data:`QUICK_SEEDS` or
    :data:`FULL_SEEDS` by default; one leaves nothing timed), check it, write ``bench.csv``
    and ``targets.json`` to ``out``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    seeds = seeds or (QUICK_SEEDS if quick else FULL_SEEDS)
    rng = np.random.default_rng(2026)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        log(f"check: {len(labs)} labs x {seeds} variants, slips injected")
        unreduced = []
        for lab_id in labs:
            for seed in range(seeds):
                try:
                    rows += _submission(lab_id, seed, Path(tmp) / lab_id / str(seed), rng)
                except (InputError, ArithmeticError, ValueError) as exc:
                    # a variant its own lab cannot reduce is a failure of the lab, counted
                    unreduced.append(f"{lab_id} seed {seed}: {type(exc).__name__} {exc}")
                    log(f"check: {unreduced[-1]}")
        files = sorted({r["file"] for r in rows})
        judged_all, seconds = _checked(files, {r["file"]: r["lab"] for r in rows})
        checks = {f: {v.name: v for v in c.verdicts} | {f"table:{t.name}": t for t in c.tables}
                  for f, c in judged_all.items()}
        start = time.process_time()
        false_pairs, pairs, copies_found, seeded = _copies_found(judged_all, rng)
        copy_seconds = time.process_time() - start
    for row in rows:
        v = checks[row["file"]][row["name"]]
        row.update(verdict=v.verdict, found=None if v.slip is None else v.slip.name,
                   seconds=seconds[row["file"]])
    frame = write_rows(rows, out / "bench.csv")
    slipped = frame[frame["injected"].notna()]
    right = frame[frame["injected"].isna()]
    recall = float((slipped["found"] == slipped["injected"]).mean())
    formula = slipped[slipped["injected"].isin(FORMULA_SLIPS)]
    formula_recall = float((formula["found"] == formula["injected"]).mean()) \
        if len(formula) else math.nan
    alarms = int((right["verdict"] == "wrong").sum())
    targets = [
        Target("injected slips found and named", recall, 1.0, "min",
               detail=f"{len(slipped)} slipped values"),
        Target("slips inside formulas (inputs, constants) named", formula_recall,
               FORMULA_RECALL, "min", detail=_formula_detail(formula)),
        Target("right values called wrong", alarms, 0, detail=f"{len(right)} right values"),
        *_class_targets(frame),
        Target("variants their lab could not reduce", len(unreduced), 0,
               detail="; ".join(unreduced)[:500] or f"{len(files)} reduced"),
        Target("honest variants named as copies", false_pairs, 0,
               detail=f"{pairs} pairs compared in {copy_seconds:.1f} s with the seeded copies"),
        Target("seeded copies (0-2 readings edited, added or rounded) found",
               copies_found / max(seeded, 1), 1.0, "min", detail=f"{seeded} seeded"),
    ]
    write_targets(targets, out / "targets.json", environment())
    return frame, targets


def _formula_detail(formula: pd.DataFrame) -> str:
    """How many formula slips were seeded, and how many of them (and of their inputs' slips,
    re-reduced) in the labs whose files name recordings (:data:`RECORDED`)."""
    recorded = formula[formula["lab"].isin(RECORDED)]
    named = recorded[recorded["found"] == recorded["injected"]]
    inputs = recorded[recorded["injected"].isin({s.name for s in INPUT_SLIPS})]
    return (f"{len(formula)} slipped values; in {', '.join(RECORDED)}: {len(named)} of "
            f"{len(recorded)} named ({len(inputs)} slips of an input, re-reduced)")


def _checked(files: list[str], lab_of: dict[str, str]) -> tuple[dict, dict]:
    """Every file checked as ``dynlab check`` checks a class (numpy's BLAS on
    :data:`~labs.teachers.check.BLAS_THREADS` thread: one core), and the CPU time of each
    check but each lab's first: that one pays the imports and the per-process caches a class
    pays once, not a submission's cost (NaN for it). [s]"""
    from threadpoolctl import threadpool_limits

    judged, seconds, warm = {}, {}, set()
    with threadpool_limits(limits=BLAS_THREADS):
        for f in files:
            start = time.process_time()
            judged[f] = check(f)
            seconds[f] = time.process_time() - start if lab_of[f] in warm else math.nan
            warm.add(lab_of[f])
    return judged, seconds


def _class_targets(frame: pd.DataFrame) -> list[Target]:
    """A class of :data:`CLASS_SIZE` of each lab checked within :data:`CLASS_SECONDS` of
    CPU time on one core (``python -m processing.bench`` sets one thread): the mean time per
    submission times :data:`CLASS_SIZE`, extrapolated where fewer were checked (the quick
    plan's one)."""
    out = []
    for lab, group in frame.drop_duplicates("file").groupby("lab", sort=False):
        n = int(group["seconds"].notna().sum())
        out.append(Target(f"{lab}: a class of {CLASS_SIZE} in under a minute on one core",
                          float(group["seconds"].mean()) * CLASS_SIZE, CLASS_SECONDS,
                          unit="s", detail=f"CPU time, {group['seconds'].mean():.3f} s per "
                                           f"submission" + (f" x {CLASS_SIZE}, extrapolated "
                                                            f"from {n}" if n < CLASS_SIZE
                                                            else f" over {n}")))
    return out


def summary_lines(frame: pd.DataFrame) -> list[str]:
    slipped = frame[frame["injected"].notna()]
    lines = [f"{frame['file'].nunique()} submissions, {len(frame)} values, "
             f"{len(slipped)} slipped"]
    for lab, group in frame.groupby("lab", sort=False):
        hit = group[group["injected"].notna()]
        right = group[group["injected"].isna()]
        per_file = group.drop_duplicates("file")["seconds"]
        lines.append(f"  {lab:8} {int((hit['found'] == hit['injected']).sum())}/{len(hit)} "
                     f"slips named, {int((right['verdict'] == 'wrong').sum())}/{len(right)} "
                     f"right values called wrong, a class of {CLASS_SIZE} in "
                     f"{per_file.mean() * CLASS_SIZE:.0f} s")
    for name, group in slipped.groupby("injected"):
        found = int((group["found"] == name).sum())
        lines.append(f"  {name:32} {found}/{len(group)} found")
    return lines
