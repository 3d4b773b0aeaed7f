"""One variant of a lab per student: a synthetic measurement (its own part, readings and
noise) with its answer key, reproducible from the class's seed and the student's id."""
from __future__ import annotations

import csv
import hashlib
import tomllib
from pathlib import Path

import numpy as np

from processing.diagnostics import InputError
from processing.toml_writer import dumps


def read_roster(path: str | Path) -> list[tuple[str, str]]:
    """(id, name) of every student of a roster CSV with the columns ``id`` and ``name``
    (``name`` optional), ids unique and usable as folder names."""
    path = Path(path)
    try:
        rows = list(csv.DictReader(path.read_text(encoding="utf-8-sig").splitlines()))
    except (OSError, UnicodeDecodeError, csv.Error) as exc:
        raise InputError(f"cannot read the roster ({exc})", "give a CSV file with a header "
                         "row: id,name", file=str(path)) from None
    if not rows or "id" not in rows[0]:
        raise InputError("the roster has no 'id' column", "write a header row id,name and a "
                         "row per student", file=str(path), field="id")
    students, seen = [], {}
    for line, row in enumerate(rows, start=2):
        sid = (row.get("id") or "").strip()
        if not sid or any(c in sid for c in '/\\:*?"<>|') or sid in (".", ".."):
            raise InputError(f"row {line}: id {sid!r} cannot name a folder",
                             "give each student a plain id (letters, digits, - or _)",
                             file=str(path), field="id")
        if sid in seen:
            raise InputError(f"id {sid!r} is in rows {seen[sid]} and {line}",
                             "give every student a different id", file=str(path), field="id")
        seen[sid] = line
        students.append((sid, (row.get("name") or sid).strip()))
    return students


def student_seed(seed: int, student_id: str) -> int:
    """The variant's seed: the class's seed and the student's id, hashed (stable across
    machines and Python versions)."""
    digest = hashlib.sha256(f"{seed}:{student_id}".encode()).digest()
    return int.from_bytes(digest[:4], "little")


def write_variants(write, out_dir: str | Path, roster: str | Path, seed: int,
                   **options) -> dict[str, dict[str, Path]]:
    """``write(folder, seed, **options)`` (a lab's ``write_synthetic``) once per student of
    the roster into ``out_dir/<id>/``, the measurement file's ``[meta] student`` set to the
    student's name and ``id`` recorded in it."""
    students = read_roster(roster)
    written = {}
    for sid, name in students:
        files = write(Path(out_dir) / sid, student_seed(seed, sid), **options)
        doc = tomllib.loads(files["toml"].read_text(encoding="utf-8"))
        doc.setdefault("meta", {}).update(student=name, notes=f"variant of {sid}, class seed "
                                          f"{seed}; the true answers are in answer_key.json")
        files["toml"].write_text(dumps(doc), encoding="utf-8")
        written[sid] = files
    return written


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
    import json
    import re

    from .registry import evaluate
    from .samples import sample_dir

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
