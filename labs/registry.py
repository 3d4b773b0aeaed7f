"""Which labs exist, and running one measurement file through its lab."""
from __future__ import annotations

from pathlib import Path

from processing.diagnostics import InputError, collect_notices
from processing.measurement import load, read_toml
from processing.result import LabResult

from . import (dyncalc, lab1_inertia, lab2_conrod, lab3_speed_irregularity, lab5_valve_stiffness,
               lab7_torsiograph, lab8_balancing, lab9_damper)

LABS = {m.SPEC.id: m for m in (lab1_inertia, lab2_conrod, lab3_speed_irregularity,
                                 lab5_valve_stiffness, lab7_torsiograph, lab8_balancing,
                                 lab9_damper, dyncalc)}


def lab_module(lab_id: str, file: str | None = None):
    """The module of lab ``lab_id``, or an :class:`InputError` listing the known labs."""
    if lab_id not in LABS:
        raise InputError(f"unknown lab {lab_id!r}",
                         f"use one of {', '.join(LABS)} ('dynlab list' shows them)",
                         file=file, field="lab" if file else None)
    return LABS[lab_id]


def evaluate(path: str | Path, *, confine: bool = False, **options) -> LabResult:
    """Read, validate and reduce one measurement file; warnings of both steps are kept.

    ``confine`` keeps every file the measurement names inside its folder (see
    :func:`processing.measurement.load`)."""
    data = read_toml(path)
    lab_id = data.get("lab")
    if lab_id is None:
        raise InputError("the file does not say which lab it is",
                         f"add a first line lab = \"lab1\" (one of {', '.join(LABS)})",
                         file=str(path), field="lab")
    module = lab_module(str(lab_id), str(path))
    with collect_notices() as notices:
        inputs = load(path, module.SPEC, data, confine=confine)
    result = module.reduce(inputs, **options)
    result.check_sense()
    result.warnings = notices + [w for w in result.warnings if w not in notices]
    return result
