"""Checking a submission: a measurement file with what the student reported, reduced here and
judged value by value (:mod:`processing.grading`).

A submission is a measurement file with a ``[reported]`` table — names as in the result JSON,
values with their units, optionally the student's own ± u::

    [reported]
    J_trifilar = "0.1234 kg*m^2"
    delta_1 = { value = 0.0183, u = 0.0004 }

Each reported value is judged against the reduction of the same file; a wrong one is tried
against the generic slips (:data:`processing.grading.FACTOR_SLIPS`) and the lab's own
(``SLIPS`` of the lab module: inputs changed as the slip changes them, reduced again, or a
factor on the results a slip of the arithmetic changes; only the slips that change a value
reported wrong are made).

A lab with tables to check (:data:`TABLE_CHECKS`: the coursework) also takes
``[reported.tables]``, a CSV file per table, judged row by row by the lab's checker.
"""
from __future__ import annotations

import difflib
import importlib
import math
import re
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from processing.diagnostics import InputError
from processing.grading import FACTOR_SLIPS, Policy, Reported, Slip, Verdict, judge, \
    written_digits

from .registry import evaluate, lab_module

CHECK_SAMPLES = 0
"""Monte Carlo draws of a checking reduction: none, the verdicts use the value and the linear
u, which the draws do not change (measured on every lab's variant; the draws cost lab 4 a
seventh of its check)."""

TABLE_CHECKS = {"dyncalc": "labs.dyncalc_check"}
"""Labs whose tables a submission may report, and the module that checks them (its
``check_tables(path, entries, inputs, policy, confine=)`` returns verdicts with ``to_dict()``)."""


@dataclass(frozen=True)
class Check:
    """One submission checked: the file, its lab, the student and a verdict per value."""

    file: str
    lab: str
    student: str
    verdicts: list[Verdict]
    readings: tuple[float, ...]
    """Every number the file's measurements hold, in order (for telling copied readings)."""
    tables: list = field(default_factory=list)
    """The reported tables judged (:class:`labs.dyncalc_check.TableVerdict`)."""

    def to_dict(self) -> dict:
        out = {"file": self.file, "lab": self.lab, "student": self.student,
               "verdicts": [_verdict_dict(v) for v in self.verdicts]}
        if self.tables:
            out["tables"] = [t.to_dict() for t in self.tables]
        return out


def _verdict_dict(v: Verdict) -> dict:
    def num(x):
        return None if x is None or not math.isfinite(x) else x

    return {"name": v.name, "verdict": v.verdict,
            "reported": None if v.reported is None else v.reported.value,
            "reported_u": None if v.reported is None else num(v.reported.u),
            "value": num(v.value), "u": num(v.u), "z": num(v.z), "relative": num(v.relative),
            "slip": None if v.slip is None else v.slip.name,
            "slip_text": None if v.slip is None else v.slip.text}


def read_policy(path: str | Path | None, lab: str) -> Policy:
    """The teacher's policy for ``lab`` from a TOML file: top-level ``rel_tol``, ``sig_figs``,
    ``expected``, overridden by a ``[labN]`` table; the defaults of :class:`Policy` without
    a file."""
    if path is None:
        return Policy()
    try:
        data = tomllib.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise InputError(f"cannot read the policy ({exc})", "give a TOML file with rel_tol, "
                         "sig_figs and expected", file=str(path)) from None
    merged = {k: v for k, v in data.items() if not isinstance(v, dict)}
    merged.update(data.get(lab, {}))
    unknown = set(merged) - {"rel_tol", "sig_figs", "expected"}
    if unknown:
        raise InputError(f"unknown policy key '{sorted(unknown)[0]}'",
                         "use rel_tol, sig_figs, expected", file=str(path),
                         field=sorted(unknown)[0])
    try:
        return Policy(float(merged.get("rel_tol", 0.01)), int(merged.get("sig_figs", 3)),
                      tuple(str(x) for x in merged.get("expected", ())))
    except (TypeError, ValueError) as exc:
        raise InputError(f"a policy value is not a number ({exc})", "write rel_tol = 0.01, "
                         "sig_figs = 3", file=str(path)) from None


def _reported(path: str, table, results) -> dict[str, Reported]:
    """The ``[reported]`` table in SI, each value's unit checked against the result's."""
    if not isinstance(table, dict) or not table:
        raise InputError("the file has no [reported] table: nothing to check",
                         "add a [reported] table with the values you got, named as in the "
                         "result JSON (e.g. J_trifilar = \"0.1234 kg*m^2\")", file=path,
                         field="reported")
    out = {}
    for name, entry in table.items():
        field = f"reported.{name}"
        if name not in results:
            close = difflib.get_close_matches(name, list(results), n=1, cutoff=0.6)
            hint = f"did you mean '{close[0]}'?" if close else \
                f"the results are: {', '.join(results)}"
            raise InputError(f"'{name}' is not a result of this lab", hint, file=path,
                             field=field)
        result = results[name]
        value, u = (entry.get("value"), entry.get("u")) if isinstance(entry, dict) \
            else (entry, None)
        out[name] = _quantity(path, field, value, u, result.unit)
    return out


def _quantity(path: str, field: str, value, u, unit: str) -> Reported:
    from processing.units import parse_quantity

    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise InputError(f"{value!r} is not a value", "write a number with its unit, e.g. "
                         "\"0.1234 kg*m^2\"", file=path, field=field)
    text = value if isinstance(value, str) else repr(value)
    if unit and not isinstance(value, str):
        raise InputError(f"{value!r} has no unit", f"write the value with its unit, as a "
                         f"string: \"{value} {unit}\" (or in the unit you used)", file=path,
                         field=field)
    try:
        si, limit = parse_quantity(text, unit or "")
        u_si = 0.0
        if u is not None:
            u_text = u if isinstance(u, str) else repr(u)
            if unit and not isinstance(u, str):
                raise ValueError(f"the uncertainty {u!r} has no unit")
            u_si = parse_quantity(u_text, unit or "")[0]
    except ValueError as exc:
        wanted = unit or "a pure number"
        raise InputError(str(exc), f"write the value as a number and a unit of {wanted}",
                         file=path, field=field) from None
    digits, exponent = written_digits(text)
    scale = si / float(text.split()[0]) if _plain_number(text) and float(text.split()[0]) \
        else 1.0
    return Reported(field.split(".", 1)[1], si, u_si or (limit or 0.0), digits,
                    abs(scale) * 10.0 ** exponent)


def _plain_number(text: str) -> bool:
    try:
        float(text.split()[0])
        return True
    except (ValueError, IndexError):
        return False


def _slip_names(changes, results) -> list[str]:
    """The results a lab slip changes: each of ``changes`` is a result's name or a pattern of
    numbered ones (``phi_max_\\d+``), matched whole."""
    return [k for k in results if any(re.fullmatch(p, k) for p in changes)]


def _lab_slips(module, results, inputs, options, wrong=None) -> list[Slip]:
    """The lab's own slips (``SLIPS`` of its module): the value of each result a slip changes
    as the slip leaves it.

    A slip's ``change`` is a function of the inputs that returns them as the slip leaves them
    (reduced again), or returns a number, or is a number: a slip of the arithmetic after the
    reduction (a range for an amplitude, a common logarithm for a natural one, the teeth
    counted for the pitches), the results it names times that factor.

    Parameters
    ----------
    module : module
        The lab's.
    results : dict
        Our reduction's results (:class:`processing.result.Result` by name).
    inputs : callable
        Returns the submission's inputs (called only for a slip that needs them).
    options : dict
        For the lab's ``reduce``.
    wrong : set of str, optional
        The results reported wrong: only the slips that change one of them are made (all,
        without it).
    """
    out = []
    for name, text, changes, change in getattr(module, "SLIPS", ()):
        names = _slip_names(changes, results)
        if wrong is not None and not wrong.intersection(names):
            continue
        slipped = change(inputs()) if callable(change) else change
        if slipped is None:
            continue
        if isinstance(slipped, (int, float)):
            out.append(Slip(name, text, reduced={k: slipped * results[k].value
                                                 for k in names}))
            continue
        try:
            result = module.reduce(slipped, **options)
        except (InputError, ValueError, ZeroDivisionError):
            continue
        out.append(Slip(name, text, reduced={k: result.results[k].value for k in names
                                             if k in result.results}))
    return out


def read_key(path: str | Path) -> dict[str, float]:
    """The ``"results"`` of an answer key (``dynlab synth``): result names to true values."""
    import json

    if not Path(path).is_file():
        raise InputError("no answer key for this submission", "name each submission's folder "
                         "by the student's id, as in the roster the variants were written for",
                         file=str(path))
    try:
        results = json.loads(Path(path).read_text(encoding="utf-8"))["results"]
    except (OSError, UnicodeDecodeError, ValueError, KeyError, TypeError) as exc:
        raise InputError(f"not an answer key ({type(exc).__name__}: {exc})",
                         "give the answer_key.json that dynlab synth wrote", file=str(path),
                         field="results") from None
    return {str(k): float(v) for k, v in results.items()}


def check(path: str | Path, *, policy: str | Path | None = None, confine: bool = False,
          key: dict[str, float] | None = None, **options) -> Check:
    """Reduce a submission and judge every reported value.

    Parameters
    ----------
    path : str or Path
        The measurement file with its ``[reported]`` table.
    policy : str or Path, optional
        The teacher's policy file (:func:`read_policy`).
    confine : bool
        Read no file outside the submission's folder.
    key : dict, optional
        The variant's answer key (:func:`read_key`): its results are expected (absent ones
        are *missing*) on top of the policy's.
    **options
        For the lab's ``reduce``.

    Returns
    -------
    Check

    Raises
    ------
    InputError
        Bad measurements (as ``dynlab run``), no ``[reported]`` table, an unknown name, a
        value without the unit its result needs, a bad reported table.
    """
    from processing.measurement import load, read_toml

    options = {"n_samples": CHECK_SAMPLES, **options}
    data = read_toml(path)
    table = data.pop("reported", None)
    tables = table.pop("tables", None) if isinstance(table, dict) else None
    result = evaluate(path, data=data, confine=confine, **options)
    reported = _reported(str(path), table, result.results) if table or tables is None else {}
    rules = read_policy(policy, result.lab)
    if key:
        rules = Policy(rules.rel_tol, rules.sig_figs, tuple(dict.fromkeys(
            [*rules.expected, *(k for k in key if k in result.results)])))
    names = list(reported) + [n for n in rules.expected if n not in reported]

    def judged(name: str, slips) -> Verdict:
        r = result.results.get(name)
        value, u, unit = (r.value, r.u, r.unit) if r else (math.nan, math.nan, "")
        return judge(name, reported.get(name), value, u, unit, rules, slips)

    verdicts = [judged(n, FACTOR_SLIPS) for n in names]
    module = lab_module(result.lab)
    loaded = []

    def inputs():                       # loaded once, and only when needed
        if not loaded:
            loaded.append(load(path, module.SPEC, data, confine=confine))
        return loaded[0]

    wrong = {v.name for v in verdicts if v.verdict == "wrong"}
    if getattr(module, "SLIPS", ()) and wrong:
        # the lab's own slips are reductions of slipped inputs: made only for a wrong value
        # the lab's first: where a generic factor gives the same value, the lab's cause is
        # the likelier
        slips = _lab_slips(module, result.results, inputs, options, wrong) + list(FACTOR_SLIPS)
        verdicts = [judged(v.name, slips) if v.verdict == "wrong" else v for v in verdicts]
    judged_tables = []
    if tables is not None:
        if result.lab not in TABLE_CHECKS:
            raise InputError(f"{result.lab} has no tables to check", "report its values in "
                             "[reported] and delete [reported.tables]", file=str(path),
                             field="reported.tables")
        checker = importlib.import_module(TABLE_CHECKS[result.lab])
        judged_tables = checker.check_tables(path, tables, inputs(), rules, confine=confine)
    return Check(str(path), result.lab, result.meta.get("student", Path(path).stem), verdicts,
                 _readings(data), judged_tables)


def _readings(data: dict) -> tuple[float, ...]:
    """Every number of the measurement sections, in order (meta left out)."""
    out = []

    def walk(x):
        if isinstance(x, bool):
            return
        if isinstance(x, (int, float)):
            out.append(float(x))
        elif isinstance(x, str):
            head = x.split()[0] if x.split() else ""
            if _plain_number(head):
                out.append(float(head))
        elif isinstance(x, dict):
            for v in x.values():
                walk(v)
        elif isinstance(x, list):
            for v in x:
                walk(v)

    for key, value in data.items():
        if key not in ("lab", "meta"):
            walk(value)
    return tuple(out)


def copied_pairs(checks: list[Check], tolerance: float = 1e-3) -> list[tuple[str, str]]:
    """Pairs of submissions of one lab whose raw readings are the same, or all within
    ``tolerance`` (relative) of each other: likely copied."""
    pairs = []
    for i, a in enumerate(checks):
        for b in checks[i + 1:]:
            if a.lab != b.lab or len(a.readings) != len(b.readings) or not a.readings:
                continue
            if all(abs(x - y) <= tolerance * max(abs(x), abs(y), 1e-300)
                   for x, y in zip(a.readings, b.readings)):
                pairs.append((a.file, b.file))
    return pairs

