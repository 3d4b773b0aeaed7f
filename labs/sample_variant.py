"""A design-calculation variant of a bundled sample (lab 8, the coursework): the example's data
with chosen quantities scaled, and its answer key by this toolkit's own calculation."""
from __future__ import annotations

import json
import re
import tomllib
from pathlib import Path

import numpy as np

from processing.inputs.toml_writer import dumps

from .registry import evaluate
from .samples import sample_dir


def design_variant(lab_id: str, sample: str, out_dir: str | Path, seed: int,
                   vary: dict[str, tuple[str, ...]], spread: float = 0.1) -> dict[str, Path]:
    """A design-calculation variant (lab 8, the coursework): the bundled example's data with
    the quantities in ``vary`` (section → keys) each scaled by a factor drawn uniformly in
    1 ± ``spread`` and rounded to four significant figures, in the example's units; its answer
    key is this toolkit's own calculation of the variant (the formulas the tests hold to the
    manual's printed values), as a coursework's key is.

    Returns
    -------
    dict
        Paths written: ``toml`` and ``answer``.
    """
    doc = tomllib.loads((sample_dir() / lab_id / sample).read_text(encoding="utf-8"))
    rng = np.random.default_rng([seed, 17])
    for section, keys in vary.items():
        for key in keys:
            value = doc[section][key]
            factor = rng.uniform(1 - spread, 1 + spread)
            if isinstance(value, str):
                number, unit = re.match(r"\s*([-+0-9.eE]+)\s*(.*)", value).groups()
                doc[section][key] = f"{float(f'{float(number) * factor:.4g}'):g} {unit}".strip()
            else:
                doc[section][key] = float(f"{value * factor:.4g}")
    doc["meta"] = {"student": f"variant (dynlab synth {lab_id} --seed {seed})",
                   "notes": "generated; the answers are in answer_key.json"}
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    written = {"toml": out / f"{lab_id}_seed{seed}.toml", "answer": out / "answer_key.json"}
    written["toml"].write_text(dumps(doc), encoding="utf-8")
    results = evaluate(written["toml"], n_samples=200).results
    written["answer"].write_text(json.dumps(
        {"seed": seed, "results": {k: v.value for k, v in results.items()},
         "notes": "the toolkit's own calculation of this variant's data"}, indent=1),
        encoding="utf-8")
    return written
