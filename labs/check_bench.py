"""Benchmark of ``dynlab check`` (topic ``check`` of ``python -m processing.bench``): a class
of seeded variants with slips injected at known places, checked in one run.

For each lab with a scene and slips (labs 1, 2 and 9) and each seed, the variant is written
(:func:`write_synthetic`) and reduced; its submission reports every result of the answer key,
each either right — our value written to 3–6 significant figures at random — or through one
slip drawn from those that apply to it (the generic factors of
:data:`processing.grading.FACTOR_SLIPS` by the result's unit, the lab's own ``SLIPS`` for the
results they change) and that move it by more than 5 % and out of what agrees with ours (a
"slip" within a residual's own uncertainty is no mistake to find). The class is then checked file by file
as ``dynlab check DIR`` does, timed.

Targets: every injected slip found and named (recall 100 %), no right value called anything
but right, rounded or over-precise (0 false alarms), and the class of 200 submissions checked
within a minute on one core (the quick plan scales the time to its size).
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
from processing.grading import FACTOR_SLIPS, Policy, Reported, agrees
from processing.measurement import load, read_toml

from .check import _lab_slips, check
from .registry import LABS, evaluate

LABS_CHECKED = ("lab1", "lab2", "lab9")
FULL_SEEDS, QUICK_SEEDS = 67, 7
"""Seeds per lab: 3 × 67 = 201 submissions (21 in the quick plan)."""
CLASS_SECONDS = 60.0
"""A class of 200 submissions checked within this. [s]"""
CLASS_SIZE = 200
SLIP_SHIFT = 0.05
"""A slip is injected only where it moves the value by more than this (relative)."""


def _text(value: float, unit: str, figures: int) -> str:
    return f"{value:.{figures}g} {unit}".strip() if unit else f"{value:.{figures}g}"


def _submission(lab_id: str, seed: int, folder: Path, rng) -> list[dict]:
    """Write one variant and its submission; the truth of every reported value."""
    module = LABS[lab_id]
    written = module.write_synthetic(folder, seed)
    ours = evaluate(written["toml"], n_samples=500).results
    data = read_toml(written["toml"])
    inputs = load(written["toml"], module.SPEC, data)
    lab_slips = _lab_slips(module, inputs, {"n_samples": 500})
    names = [n for n in ours if math.isfinite(ours[n].value) and ours[n].value != 0]
    lines, injected = [], []
    for name in names:
        r = ours[name]
        candidates = [(s.name, s.candidate(name, r.value, r.unit))
                      for s in list(FACTOR_SLIPS) + lab_slips]
        candidates = [(n, v) for n, v in candidates
                      if v is not None and abs(v / r.value - 1) > SLIP_SHIFT
                      and not agrees(Reported(name, v, digits=4), r.value, r.u, Policy())[0]]
        if candidates and rng.random() < 0.5:
            slip, value = candidates[rng.integers(len(candidates))]
            figures = 4
        else:
            slip, value, figures = None, r.value, int(rng.integers(3, 7))
        lines.append(f'{name} = "{_text(value, r.unit, figures)}"')
        injected.append({"lab": lab_id, "seed": seed, "name": name, "injected": slip})
    with written["toml"].open("a", encoding="utf-8") as f:
        f.write("\n[reported]\n" + "\n".join(lines) + "\n")
    for row in injected:
        row["file"] = str(written["toml"])
    return injected


def run(out, *, quick: bool = False,
        log: Callable[[str], None] = print) -> tuple[pd.DataFrame, list[Target]]:
    """Write the class, check it, write ``bench.csv`` and ``targets.json`` to ``out``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    seeds = QUICK_SEEDS if quick else FULL_SEEDS
    rng = np.random.default_rng(2026)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        log(f"check: {len(LABS_CHECKED)} labs x {seeds} variants, slips injected")
        for lab_id in LABS_CHECKED:
            for seed in range(seeds):
                rows += _submission(lab_id, seed, Path(tmp) / lab_id / str(seed), rng)
        files = sorted({r["file"] for r in rows})
        start = time.perf_counter()
        checks = {f: {v.name: v for v in check(f).verdicts} for f in files}
        seconds = time.perf_counter() - start
    for row in rows:
        v = checks[row["file"]][row["name"]]
        row.update(verdict=v.verdict, found=None if v.slip is None else v.slip.name,
                   seconds=seconds / len(files))
    frame = write_rows(rows, out / "bench.csv")
    slipped = frame[frame["injected"].notna()]
    right = frame[frame["injected"].isna()]
    recall = float((slipped["found"] == slipped["injected"]).mean())
    alarms = int((right["verdict"] == "wrong").sum())
    per_class = seconds / len(files) * CLASS_SIZE
    targets = [
        Target("injected slips found and named", recall, 1.0, "min",
               detail=f"{len(slipped)} slipped values"),
        Target("right values called wrong", alarms, 0, detail=f"{len(right)} right values"),
        Target(f"a class of {CLASS_SIZE} submissions checked", per_class, CLASS_SECONDS,
               unit="s", detail=f"measured on {len(files)}"),
    ]
    write_targets(targets, out / "targets.json", environment())
    return frame, targets


def summary_lines(frame: pd.DataFrame) -> list[str]:
    slipped = frame[frame["injected"].notna()]
    lines = [f"{frame['file'].nunique()} submissions, {len(frame)} values, "
             f"{len(slipped)} slipped"]
    for name, group in slipped.groupby("injected"):
        found = int((group["found"] == name).sum())
        lines.append(f"  {name:32} {found}/{len(group)} found")
    return lines
