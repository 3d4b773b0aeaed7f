"""Which labs exist, and running one measurement file through its lab."""
from __future__ import annotations

import re

from collections.abc import Iterator, Mapping
from importlib import import_module
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING

from processing.diagnostics import InputError, collect_notices

from .catalogue import CATALOGUE

if TYPE_CHECKING:
    from processing.measurement import Inputs
    from processing.result import LabResult


class _Labs(Mapping):
    """The lab modules by id, each imported when first asked for."""

    def __getitem__(self, lab_id: str) -> ModuleType:
        return import_module(CATALOGUE[lab_id].module)

    def __iter__(self) -> Iterator[str]:
        return iter(CATALOGUE)

    def __len__(self) -> int:
        return len(CATALOGUE)


LABS = _Labs()
"""Every lab's module, by its id (:data:`labs.catalogue.CATALOGUE`)."""


def lab_module(lab_id: str, file: str | None = None):
    """The module of lab ``lab_id``, or an :class:`InputError` listing the known labs."""
    if lab_id not in LABS:
        meant = _meant(lab_id)
        raise InputError(f"unknown lab {lab_id!r}",
                         (f"write lab = \"{meant}\"; " if meant else "")
                         + f"use one of {', '.join(LABS)} ('dynlab list' shows them)",
                         file=file, field="lab" if file else None,
                         ru=(f"неизвестная работа {lab_id!r}",
                             (f"напишите lab = \"{meant}\"; " if meant else "")
                             + f"укажите одну из {', '.join(LABS)} (их показывает 'dynlab "
                             "list')"))
    return LABS[lab_id]


def _meant(lab_id: str) -> str | None:
    """The lab a misspelt id means (``Lab1``, ``lab 1``, ``лаб01``, ``1``), or None."""
    text = re.sub(r"[\s_\-№#]", "", str(lab_id).lower()).replace("лаб", "lab")
    number = re.fullmatch(r"(?:lab)?0*(\d)", text)
    meant = f"lab{number.group(1)}" if number else text
    return meant if meant in LABS else None


def evaluate(path: str | Path, *, data: dict | None = None, confine: bool = False,
             **options) -> LabResult:
    """Read, validate and reduce one measurement file; warnings of both steps are kept.

    ``data`` is the file already parsed (a submission with its ``[reported]`` table taken
    out); ``confine`` keeps every file the measurement names inside its folder (see
    :func:`processing.measurement.load`)."""
    return reduce_loaded(*read_inputs(path, data=data, confine=confine), **options)


def read_inputs(path: str | Path, *, data: dict | None = None,
                confine: bool = False) -> tuple[ModuleType, Inputs, list]:
    """The lab's module, the validated inputs of one measurement file and the warnings their
    reading raised (the first step of :func:`evaluate`, for a caller that uses the inputs
    again: a check's slips)."""
    from processing.measurement import load, read_toml  # pint and numpy: only when reducing

    data = read_toml(path) if data is None else data
    lab_id = data.get("lab")
    if lab_id is None:
        raise InputError("the file does not say which lab it is",
                         f"add a first line lab = \"lab1\" (one of {', '.join(LABS)})",
                         file=str(path), field="lab",
                         ru=("в файле не сказано, к какой работе он относится",
                             f"добавьте первой строкой lab = \"lab1\" (одну из {', '.join(LABS)})"))
    module = lab_module(str(lab_id), str(path))
    with collect_notices() as notices:
        inputs = load(path, module.SPEC, data, confine=confine)
    return module, inputs, notices


def reduce_loaded(module: ModuleType, inputs: Inputs, notices: list = (),
                  **options) -> LabResult:
    """Reduce inputs read by :func:`read_inputs` (the second step of :func:`evaluate`): the
    result checked for sense, the reading's warnings ``notices`` first among its own."""
    result = module.reduce(inputs, **options)
    result.check_sense()
    result.warnings = list(notices) + [w for w in result.warnings if w not in notices]
    return result
