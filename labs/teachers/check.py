"""Checking a submission: a measurement file with what the student reported, reduced here and
judged value by value (:mod:`processing.checking.grading`).

A submission is a measurement file with a ``[reported]`` table — names as in the result JSON,
values with their units, optionally the student's own ± u::

    [reported]
    J_trifilar = "0.1234 kg*m^2"
    delta_1 = { value = 0.0183, u = 0.0004 }

Each reported value is judged against the reduction of the same file; a wrong one is tried against
the generic slips (:data:`processing.checking.grading.FACTOR_SLIPS`) and the lab's own (``SLIPS`` of
the lab module: inputs changed as the slip changes them, reduced again, or a factor on the results a
slip of the arithmetic changes; only the slips that change a value reported wrong are made); a wrong
value none of those explains is tried against the formula's transcendental constants
(:data:`processing.checking.grading.TRANSCENDENTAL_SLIPS`: 4π², π²), then against the slips of the
formula's inputs (:mod:`processing.checking.input_slips`, reduced again) and its plain constants (½,
2, g = 10).

A class (:func:`read_class`, :func:`check_class`) is every submission checked, the refused
ones with their reasons, the copies (:func:`copies`) and the roster: what the summary
(:mod:`labs.teachers.check_report`) and the marks (:func:`mark`) are made from.

A lab with tables to check (:data:`TABLE_CHECKS`: the coursework) also takes
``[reported.tables]``, a CSV file per table, judged row by row by the lab's checker.
"""
from __future__ import annotations

import difflib
import importlib
import inspect
import math
import re
import tomllib
import warnings
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from processing.diagnostics import InputError
from processing.files import MEASUREMENT_NAMES
from processing.checking.grading import (CONSTANT_SLIPS, FACTOR_SLIPS, SQUARED_SPEED_SLIPS,
                                         TRANSCENDENTAL_SLIPS, Z_LIMIT, Policy, Reported, Slip,
                                         Verdict, judge, written_digits)
from processing.inputs.reuse import scope

from labs.registry import LABS, lab_module, read_inputs, reduce_loaded

CHECK_SAMPLES = 0
"""Monte Carlo draws of a checking reduction: none, the verdicts use the value and the linear
u, which the draws do not change (measured on every lab's variant; the draws cost lab 4 a
seventh of its check)."""

TABLE_CHECKS = {"dyncalc": "labs.teachers.dyncalc_check"}
"""Labs whose tables a submission may report, and the module that checks them (its
``check_tables(path, entries, inputs, policy, confine=)`` returns verdicts with ``to_dict()``)."""


@dataclass(frozen=True)
class Check:
    """One submission checked: the file, its lab, the student and a verdict per value."""

    file: str
    lab: str
    student: str
    verdicts: list[Verdict]
    readings: tuple[str, ...]
    """Every number the file's measurements hold, as written, in order (:func:`_readings`:
    for telling copies)."""
    tables: list = field(default_factory=list)
    """The reported tables judged (:class:`labs.teachers.dyncalc_check.TableVerdict`)."""
    results: tuple[str, ...] = ()
    """The names of the results our reduction of the submission gives."""
    sid: str | None = None
    """The student's id (the roster's), where the submission is bound to one (``--keys``)."""
    readings_of: str | None = None
    """The id of another student whose variant the readings are (their key's results are
    what our reduction of them gives), or None."""
    values_of: str | None = None
    """The id of another student whose key the reported values are (where the readings are
    not that student's too), or None."""
    shown: dict = field(default_factory=dict)
    """Each result's display unit, symbol and SI unit, ``name → (unit, symbol, si)``: how the
    lab's report prints it (kN/mm, not N/m)."""
    recordings: tuple[tuple[str, str], ...] = ()
    """(name, digest) of every file the measurements name (:func:`_recordings`): a copied
    recording has the same samples, however it was saved again (:func:`copies`)."""
    expected: tuple[str, ...] = ()
    """What the submission had to report (the policy's ``expected``, or what the lab asks
    where the submission has a key): what its mark counts; every value judged where empty."""

    def to_dict(self) -> dict:
        out = {"file": self.file, "lab": self.lab, "student": self.student,
               **({"id": self.sid} if self.sid else {}),
               **({"readings_of": self.readings_of} if self.readings_of else {}),
               **({"values_of": self.values_of} if self.values_of else {}),
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
            "slip_text": None if v.slip is None else v.slip.text,
            **({} if v.problem is None else {"problem": {"en": v.problem.text("en"),
                                                         "ru": v.problem.text("ru")}})}


POLICY_RULES = ("rel_tol", "sig_figs", "expected", "student_u", "points", "partial")
"""The keys of a policy, at its top and in a lab's table."""

POINTS = 1.0
"""Points a right value earns, where the policy gives no ``points``."""

PARTIAL = 0.5
"""Share of its points a right value written rounded or over-precise earns, where the policy
gives no ``partial``."""

MOST_SIG_FIGS = 15
"""Most significant figures a policy may ask for: what a double holds."""


@dataclass(frozen=True)
class PolicyFile:
    """A teacher's policy, validated (:func:`read_policy`): the rules at the file's top and
    each lab's table of rules, which override them for that lab."""

    file: str | None = None
    top: dict = field(default_factory=dict)
    labs: dict = field(default_factory=dict)

    def for_lab(self, lab: str, knows=lambda name: True) -> Policy:
        """The :class:`Policy` of ``lab``. The top's ``expected`` holds for every lab that
        ``knows`` a name (a class may mix labs); a lab's own ``expected`` replaces it."""
        rules = {**self.top, **self.labs.get(lab, {})}
        expected = self.labs.get(lab, {}).get("expected")
        if expected is None:
            expected = tuple(n for n in self.top.get("expected", ()) if knows(n))
        return Policy(rules.get("rel_tol", Policy.rel_tol), rules.get("sig_figs", Policy.sig_figs),
                      expected, rules.get("student_u", Policy.student_u))

    def marking(self, lab: str) -> tuple[float, float]:
        """``lab``'s points per value and the share of them a right value written rounded or
        over-precise earns (:data:`POINTS`, :data:`PARTIAL` without a rule)."""
        rules = {**self.top, **self.labs.get(lab, {})}
        return rules.get("points", POINTS), rules.get("partial", PARTIAL)

    def expects(self, lab: str, knows=lambda name: True) -> bool:
        """Whether the policy says what ``lab``'s submissions must report: an ``expected``
        of its table, or a top ``expected`` naming one of its results."""
        return "expected" in self.labs.get(lab, {}) or any(
            knows(n) for n in self.top.get("expected", ()))


def read_policy(path: str | Path | None) -> PolicyFile:
    """The teacher's policy from a TOML file: top-level ``rel_tol``, ``sig_figs``,
    ``expected``, ``student_u`` (whether a student's plausible u may widen what is right),
    ``points`` (per value) and ``partial`` (the share of them a rounded or over-precise value
    earns), overridden by a ``[labN]`` table; the defaults of :class:`Policy` without
    a file.

    Raises
    ------
    InputError
        A file that is not a policy (:mod:`processing.files`, TOML syntax); an unknown key or
        lab (with a did-you-mean); ``rel_tol`` not a fraction in [0, 1), ``sig_figs`` not a
        whole number from 1 to :data:`MOST_SIG_FIGS`, ``expected`` not a list of names,
        ``student_u`` not true or false, ``points`` not positive, ``partial`` not in [0, 1].
    """
    from processing.files import POLICY, read_text

    if path is None:
        return PolicyFile()
    file = str(path)
    try:
        data = tomllib.loads(read_text(path, POLICY, fix="give a TOML file with rel_tol, "
                                                        "sig_figs and expected"))
    except tomllib.TOMLDecodeError as exc:
        from processing.measurement import toml_place

        raise InputError(f"not a valid TOML file ({exc})", "give a TOML file with rel_tol, "
                         "sig_figs and expected", file=file,
                         ru=(f"файл не по правилам TOML{toml_place(str(exc))}", "укажите файл "
                             "TOML с rel_tol, sig_figs и expected")) from None
    top, labs = {}, {}
    for key, value in data.items():
        if key in LABS:
            if not isinstance(value, dict):
                raise InputError(f"'{key}' must be a table [{key}] of rules",
                                 f"write the rules of {key} under a line [{key}]", file=file,
                                 field=key, ru=(f"'{key}' должно быть таблицей правил [{key}]",
                                                f"запишите правила {key} под строкой [{key}]"))
            labs[key] = {k: _rule(file, f"{key}.{k}", k, v) for k, v in value.items()}
        else:
            top[key] = _rule(file, key, key, value)
    return PolicyFile(file, top, labs)


def _rule(file: str, where: str, key: str, value):
    """One rule of a policy, checked."""
    def bad(problem, fix, ru=None):
        return InputError(problem, fix, file=file, field=where, ru=ru)

    if key not in POLICY_RULES:
        if "." in where:
            raise bad(f"unknown policy key '{key}' in [{where.split('.')[0]}]",
                      _close(key, list(POLICY_RULES), "a lab's rules are"),
                      ru=(f"неизвестный ключ '{key}' в [{where.split('.')[0]}]",
                          _close(key, list(POLICY_RULES), "правила работы", "ru")))
        if isinstance(value, dict):
            raise bad(f"'{key}' is not a lab", _close(key, list(LABS), "the labs are"),
                      ru=(f"'{key}' — не работа", _close(key, list(LABS), "работы", "ru")))
        raise bad(f"unknown policy key '{key}'", _close(key, [*POLICY_RULES, *LABS],
                                                        "use rel_tol, sig_figs, expected or a "
                                                        "[labN] table of them; the keys are"),
                  ru=(f"неизвестный ключ допусков '{key}'",
                      _close(key, [*POLICY_RULES, *LABS], "используйте rel_tol, sig_figs, "
                             "expected или таблицу [labN] из них; ключи", "ru")))
    if key == "rel_tol":
        if isinstance(value, bool) or not isinstance(value, (int, float)) \
                or not math.isfinite(value):
            raise bad(f"rel_tol = {value!r} is not a number", "write the relative tolerance "
                      "as a fraction: rel_tol = 0.01 for 1 %",
                      ru=(f"rel_tol = {value!r} — не число", "запишите относительный допуск "
                          "долей: rel_tol = 0.01 для 1 %"))
        if not 0 <= value < 1:
            raise bad(f"rel_tol = {value!r} is {'negative' if value < 0 else 'not below 1'}: "
                      "it is a fraction of the value, from 0 up to (not including) 1",
                      "write e.g. rel_tol = 0.01 for 1 %" + (
                          f", rel_tol = {value / 100:g} for {value:g} %" if value >= 1 else ""),
                      ru=(f"rel_tol = {value!r} "
                          f"{'отрицательно' if value < 0 else 'не меньше 1'}: это доля "
                          "значения, от 0 до 1 (не включая 1)",
                          "напишите, например, rel_tol = 0.01 для 1 %" + (
                              f", rel_tol = {value / 100:g} для {value:g} %" if value >= 1
                              else "")))
        return float(value)
    if key == "sig_figs":
        if isinstance(value, bool) or not isinstance(value, int) \
                or not 1 <= value <= MOST_SIG_FIGS:
            raise bad(f"sig_figs = {value!r} is not a whole number from 1 to {MOST_SIG_FIGS}",
                      "write how many significant figures a value must have, e.g. "
                      "sig_figs = 3",
                      ru=(f"sig_figs = {value!r} — не целое число от 1 до {MOST_SIG_FIGS}",
                          "укажите, сколько значащих цифр должно быть у значения, например "
                          "sig_figs = 3"))
        return value
    if key in ("points", "partial"):
        if isinstance(value, bool) or not isinstance(value, (int, float)) \
                or not math.isfinite(value) or not (0 < value if key == "points"
                                                    else 0 <= value <= 1):
            if key == "points":
                raise bad(f"points = {value!r} is not a positive number", "write the points a "
                          "right value earns, e.g. points = 2",
                          ru=(f"points = {value!r} — не положительное число", "укажите, "
                              "сколько баллов даёт верное значение, например points = 2"))
            raise bad(f"partial = {value!r} is not a share from 0 to 1", "write the share of "
                      "the points a rounded or over-precise value earns, e.g. partial = 0.5",
                      ru=(f"partial = {value!r} — не доля от 0 до 1", "укажите долю баллов "
                          "за округлённое или слишком точное значение, например "
                          "partial = 0.5"))
        return float(value)
    if key == "student_u":
        if not isinstance(value, bool):
            raise bad(f"student_u = {value!r} is not true or false", "write student_u = true "
                      "to let a student's own plausible u widen what counts as right, or "
                      "leave it out",
                      ru=(f"student_u = {value!r} — не true и не false", "напишите "
                          "student_u = true, чтобы правдоподобная u студента расширяла допуск, "
                          "или уберите строку"))
        return value
    if not isinstance(value, list) or not all(isinstance(n, str) and n.strip()
                                              for n in value):
        raise bad(f"expected = {value!r} is not a list of result names",
                  "write expected = [\"J_trifilar\", \"J_pendulum_cm\"] (the names of the "
                  "result JSON)",
                  ru=(f"expected = {value!r} — не список имён результатов",
                      "напишите expected = [\"J_trifilar\", \"J_pendulum_cm\"] (имена из JSON "
                      "результата)"))
    return tuple(dict.fromkeys(n.strip() for n in value))


def _close(word: str, options: list[str], listing: str, lang: str = "en") -> str:
    """The option nearest ``word`` as a question, else ``listing`` and every option."""
    close = difflib.get_close_matches(word, options, n=1, cutoff=0.6)
    if close:
        return f"может быть, '{close[0]}'?" if lang == "ru" else f"did you mean '{close[0]}'?"
    return f"{listing}: {', '.join(options)}"


def lab_knows(lab: str, names) -> Callable[[str], bool]:
    """Whether a name is a result of ``lab``: one of ``names`` (the results of its
    submissions), of the lab's declared ``RESULTS`` (its module's or its report's), or a
    numbered result (``delta_3``) of a kind one of those holds (``delta_1``)."""
    known = set(names) | _declared(lab)
    stems = {_stem(n) for n in known}
    return lambda name: name in known or _stem(name) in stems


def _stem(name: str) -> str:
    """A result's name without its number: ``delta_2`` → ``delta_#``."""
    return re.sub(r"_\d+$", "_#", name)


def _declared(lab: str) -> set[str]:
    """The results a lab declares whatever its data (``RESULTS`` of its module and of its
    report module, where it has them)."""
    module = lab_module(lab)
    names = set(getattr(module, "RESULTS", {}) or {})
    try:
        report = importlib.import_module(f"{module.__name__}_report")
    except ModuleNotFoundError:
        return names
    return names | set(getattr(report, "RESULTS", {}) or {})


def unknown_expected(checks: list[Check], policy: PolicyFile) -> None:
    """Refuse a policy that expects a result no submission checked can give: a name of a
    lab's table unknown to that lab, a name at the top unknown to every lab checked.

    Raises
    ------
    InputError
        Naming the policy, the rule and the name, with the closest result as the fix.
    """
    by_lab: dict[str, set[str]] = {}
    for c in checks:
        by_lab.setdefault(c.lab, set()).update(c.results)
    knows = {lab: lab_knows(lab, names) for lab, names in by_lab.items()}
    asked = [(f"{lab}.expected", [lab], policy.labs[lab]["expected"]) for lab in by_lab
             if "expected" in policy.labs.get(lab, {})]
    if "expected" in policy.top:
        asked.append(("expected", list(by_lab), policy.top["expected"]))
    for where, labs, names in asked:
        for name in names:
            if any(knows[lab](name) for lab in labs):
                continue
            results = sorted(set().union(*(by_lab[lab] | _declared(lab) for lab in labs)))
            count = sum(c.lab in labs for c in checks)
            raise InputError(
                f"'{name}' is not a result of {' or '.join(labs)} (none of the {count} "
                f"submission(s) checked gives it)",
                _close(name, results, "correct the name in expected; the results are"),
                file=policy.file, field=where,
                ru=(f"'{name}' — не результат {' или '.join(labs)} (ни одна из {count} "
                    f"проверенных работ его не даёт)",
                    _close(name, results, "исправьте имя в expected; результаты", "ru")))


REPORTED_KEYS = ("value", "u")
"""The keys of a reported value written as a table."""


def _reported(path: str, table, results,
              unreadable: dict[str, InputError] | None = None) -> dict[str, Reported]:
    """The ``[reported]`` table in SI, each value's unit checked against the result's.

    A value that cannot be read (its number, its unit, its u) raises, or, given
    ``unreadable``, is left out and its error put there under its name: the class's other
    values are judged all the same."""
    if table is not None and not isinstance(table, dict):
        raise InputError(f"'reported' must be a table, got {table!r}",
                         "write the values you got under a line [reported], named as in the "
                         "result JSON (e.g. J_trifilar = \"0.1234 kg*m^2\")", file=path,
                         field="reported",
                         ru=(f"'reported' должно быть таблицей, а не {table!r}",
                             "запишите полученные значения под строкой [reported], с именами "
                             "из JSON результата (например, J_trifilar = \"0,1234 кг*м^2\")"))
    if not table:
        raise InputError("the file has no [reported] table: nothing to check",
                         "add a [reported] table with the values you got, named as in the "
                         "result JSON (e.g. J_trifilar = \"0.1234 kg*m^2\")", file=path,
                         field="reported",
                         ru=("в файле нет таблицы [reported]: проверять нечего",
                             "добавьте таблицу [reported] с полученными значениями, с именами "
                             "из JSON результата (например, J_trifilar = \"0,1234 кг*м^2\")"))
    out = {}
    for name, entry in table.items():
        field = f"reported.{name}"
        if name not in results:
            raise InputError(f"'{name}' is not a result of this lab",
                             _close(name, list(results), "the results are"), file=path,
                             field=field, ru=(f"'{name}' — не результат этой работы",
                                              _close(name, list(results), "результаты", "ru")))
        try:
            value, u = _entry(path, field, entry)
            out[name] = _quantity(path, field, value, u, _expected_unit(results[name]))
        except InputError as exc:
            if unreadable is None:
                raise
            unreadable[name] = exc
    return out


def _entry(path: str, field: str, entry) -> tuple:
    """(value, u) of a reported value: a plain value, or a table ``{value = …, u = …}``."""
    if not isinstance(entry, dict):
        return entry, None
    for key in entry:
        if key not in REPORTED_KEYS:
            close = difflib.get_close_matches(key, REPORTED_KEYS, n=1, cutoff=0.5)
            raise InputError(f"unknown key '{key}' in the table of '{field.split('.', 1)[1]}'",
                             (f"did you mean '{close[0]}'? " if close else "") + "a reported "
                             "value's table holds value and, optionally, u (your standard "
                             "uncertainty)", file=path, field=f"{field}.{key}",
                             ru=(f"неизвестный ключ '{key}' в таблице '{field.split('.', 1)[1]}'",
                                 (f"может быть, '{close[0]}'? " if close else "") + "таблица "
                                 "значения содержит `value` и, если нужно, `u` (вашу "
                                 "стандартную неопределённость)"))
    if "value" not in entry:
        raise InputError("the table gives no value", "write { value = \"0.1234 kg*m^2\", "
                         "u = \"0.0004 kg*m^2\" }, or the value alone", file=path, field=field,
                         ru=("в таблице нет значения", "напишите { value = \"0,1234 кг*м^2\", "
                             "u = \"0,0004 кг*м^2\" } или одно значение"))
    return entry["value"], entry.get("u")


_STATED = re.compile(r"^\s*(?:[^\W\d]\w*\s*=\s*)?(?:[≈~]\s*)?")
"""What a student may write before the value itself: the result's name or symbol and "="
(``c = 42,96 Н/мм``), "about" (``≈2,03 кН/мм``, ``~5,8 kN/mm``)."""


def _expected_unit(result) -> str:
    """The unit a student is asked for a result in: the lab's display unit (kN/mm, not
    kg/s²) where it is one of the result's kind, else the result's SI unit."""
    from processing.units import same_kind

    shown = result.display_unit
    try:
        return shown if shown and same_kind(shown, result.unit) else result.unit
    except Exception:                   # a display unit pint cannot read
        return result.unit


def _quantity(path: str, field: str, value, u, unit: str) -> Reported:
    from processing.units import parse_quantity, plain_notation

    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise InputError(f"{value!r} is not a value", "write a number with its unit, e.g. "
                         "\"0.1234 kg*m^2\"", file=path, field=field,
                         ru=(f"{value!r} — не значение", "напишите число с единицей, например "
                             "\"0,1234 кг*м^2\""))
    text = _STATED.sub("", value) if isinstance(value, str) else repr(value)
    if unit and not isinstance(value, str):
        raise InputError(f"{value!r} has no unit", f"write the value with its unit, as a "
                         f"string: \"{value} {unit}\" (or in the unit you used)", file=path,
                         field=field, ru=(f"у {value!r} нет единицы", "напишите значение с "
                                          f"единицей строкой: \"{value} {unit}\" (или в той "
                                          "единице, в которой считали)"))
    wanted, wanted_ru = _wanted(unit)
    try:
        si, limit = parse_quantity(text, unit or "")
    except ValueError as exc:
        raise InputError(str(exc), f"write the value as a number and a unit of {wanted}",
                         file=path, field=field,
                         ru=(getattr(exc, "problem_ru", None) or str(exc),
                             f"запишите значение числом и единицей: {wanted_ru}")) from None
    if not math.isfinite(si):
        raise InputError(f"{text!r} is not a finite number", f"write the value you got, a "
                         f"number and a unit of {wanted}", file=path, field=field,
                         ru=(f"{text!r} — не конечное число", "запишите полученное значение "
                             f"числом и единицей: {wanted_ru}"))
    u_si = limit or 0.0
    if u is not None:
        if limit is not None:
            raise InputError(f"the uncertainty is given twice: ± in the value and u = {u!r}",
                             "keep one of them", file=path, field=f"{field}.u",
                             ru=(f"неопределённость дана дважды: ± в значении и u = {u!r}",
                                 "оставьте одно из двух"))
        u_si = _uncertainty(path, f"{field}.u", u, unit)
    text = plain_notation(text, unit or "")     # "0,1708" has the digits of 0.1708
    digits, exponent = written_digits(text)
    scale = si / float(text.split()[0]) if _plain_number(text) and float(text.split()[0]) \
        else 1.0
    return Reported(field.split(".", 1)[1], si, u_si, digits, abs(scale) * 10.0 ** exponent)


def _wanted(unit: str) -> tuple[str, str]:
    """What a reported value's unit must be, in English and Russian."""
    from processing.units import unit_text

    return (unit or "a pure number", unit_text(unit, "ru") if unit else "безразмерное число")


def _uncertainty(path: str, field: str, u, unit: str) -> float:
    """A reported standard uncertainty in SI: a number (a pure result) or a string with the
    result's unit, finite and ≥ 0."""
    from processing.units import parse_quantity

    wanted, wanted_ru = _wanted(unit)
    if isinstance(u, bool) or not isinstance(u, (int, float, str)):
        raise InputError(f"u = {u!r} is not an uncertainty", f"write u as a number and a unit "
                         f"of {wanted}", file=path, field=field,
                         ru=(f"u = {u!r} — не неопределённость", "запишите u числом и "
                             f"единицей: {wanted_ru}"))
    if unit and not isinstance(u, str):
        raise InputError(f"the uncertainty {u!r} has no unit", f"write it with its unit, as a "
                         f"string: u = \"{u} {unit}\"", file=path, field=field,
                         ru=(f"у неопределённости {u!r} нет единицы", "напишите её с единицей "
                             f"строкой: u = \"{u} {unit}\""))
    try:
        u_si, limit = parse_quantity(u if isinstance(u, str) else repr(u), unit or "")
    except ValueError as exc:
        raise InputError(str(exc), f"write u as a number and a unit of {wanted}", file=path,
                         field=field, ru=(getattr(exc, "problem_ru", None) or str(exc),
                                          f"запишите u числом и единицей: {wanted_ru}")) from None
    if limit is not None or not math.isfinite(u_si) or u_si < 0:
        raise InputError(f"u = {u!r} is not a standard uncertainty (a finite number ≥ 0)",
                         "give your standard uncertainty, a positive number with its unit, or "
                         "leave u out", file=path, field=field,
                         ru=(f"u = {u!r} — не стандартная неопределённость (конечное число "
                             "≥ 0)", "укажите свою стандартную неопределённость, положительное "
                             "число с единицей, или уберите u"))
    return u_si


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
    inputs : Inputs
        The submission's (those our reduction read).
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
        slipped = change(inputs) if callable(change) else change
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


def _input_slips(module, inputs, options, names) -> list[Slip]:
    """The slips of the formula's inputs (:data:`processing.checking.input_slips.INPUT_SLIPS`: min⁻¹
    used as rad/s, g = 10, a diameter for a radius, T for T² …), each reduced again from the
    inputs it leaves, as the values of ``names`` it gives."""
    from processing.checking.input_slips import slipped_inputs

    out = []
    for slip, symbol, changed in slipped_inputs(inputs):
        try:
            with warnings.catch_warnings():     # the slipped data's warnings are not the file's
                warnings.simplefilter("ignore")
                result = module.reduce(changed, **options)
        except (InputError, ValueError, ZeroDivisionError, FloatingPointError):
            continue
        out.append(Slip(slip.name, {lang: t.format(symbol=symbol) for lang, t in
                                    slip.text.items()},
                        reduced={k: result.results[k].value for k in names
                                 if k in result.results}))
    return out


def read_key(path: str | Path) -> dict[str, float]:
    """The ``"results"`` of an answer key (``dynlab synth``): result names to true values.

    Raises
    ------
    InputError
        No key there; not a JSON answer key (:mod:`processing.files`, syntax, no
        ``"results"`` object); a result that is not a finite number.
    """
    import json

    from processing.files import ANSWER_KEY, read_text

    if not Path(path).exists():
        raise InputError("no answer key for this submission", "name each submission's folder "
                         "by the student's id, as in the roster the variants were written for",
                         file=str(path),
                         ru=("для этой работы нет ключа ответов", "назовите папку каждой работы "
                             "номером студента, как в списке, по которому писались варианты"))
    fix = "give the answer_key.json that dynlab synth wrote"
    fix_ru = "укажите answer_key.json, записанный dynlab synth"
    try:
        results = json.loads(read_text(path, ANSWER_KEY, fix=fix))["results"]
    except (ValueError, KeyError, TypeError) as exc:
        raise InputError(f"not an answer key ({type(exc).__name__}: {exc})", fix,
                         file=str(path), field="results",
                         ru=(f"это не ключ ответов ({type(exc).__name__}: {exc})",
                             fix_ru)) from None
    if not isinstance(results, dict):
        raise InputError("\"results\" is not a table of result names and values", fix,
                         file=str(path), field="results",
                         ru=("\"results\" — не таблица имён и значений результатов", fix_ru))
    for name, value in results.items():
        if isinstance(value, bool) or not isinstance(value, (int, float)) \
                or not math.isfinite(value):
            raise InputError(f"the true value of '{name}' is {value!r}, not a finite number",
                             fix, file=str(path), field=f"results.{name}",
                             ru=(f"истинное значение '{name}' — {value!r}, а не конечное число",
                                 fix_ru))
    return {str(k): float(v) for k, v in results.items()}


@dataclass(frozen=True)
class Variants:
    """The answer keys of a class's variants (:func:`read_variants`): each student's id to
    the ``"results"`` of their key, and to their name (the roster's, where one is given)."""

    keys: dict[str, dict[str, float]]
    names: dict[str, str] = field(default_factory=dict)
    bad: dict[str, InputError] = field(default_factory=dict)
    """The keys that could not be read, by id: each refuses its student's submission alone."""


def keys_folder(path: str | Path) -> Path:
    """The folder of the students' answer keys: ``path/keys`` where ``dynlab synth
    --students`` wrote its two folders there, else ``path`` itself."""
    path = Path(path)
    return path / "keys" if (path / "keys").is_dir() else path


def read_variants(path: str | Path, roster: list[tuple[str, str]] | None = None) -> Variants:
    """Every answer key of a class: ``KEYDIR/<id>/answer_key.json`` for each id of the
    roster (:func:`labs.teachers.variants.read_roster`), or for each folder of KEYDIR holding one
    without a roster. A roster's student without a key has no variant to be checked against
    (refused if they hand in: :func:`student_key`)."""
    folder = keys_folder(path)
    def there(sid: str) -> bool:
        try:
            return (folder / sid / "answer_key.json").exists()
        except OSError:
            return True                 # read_key says why
    ids = [sid for sid, _ in roster] if roster is not None else sorted(
        p.name for p in folder.iterdir() if there(p.name))
    keys, bad = {}, {}
    for sid in filter(there, ids):
        try:
            keys[sid] = read_key(folder / sid / "answer_key.json")
        except InputError as exc:
            bad[sid] = exc
    return Variants(keys, dict(roster or ()), bad)


def student_key(variants: Variants, folder_id: str | None, meta_id: str | None,
                path: str | Path, keydir: str | Path) -> str:
    """The id a submission is bound to: the name of its folder in the class folder where
    that is a student's id with a key, else its ``[meta] id``.

    Raises
    ------
    InputError
        Neither is the id of a student with a key; that student's key could not be read.
    """
    for sid in (folder_id, meta_id):
        if sid is not None and sid in variants.bad:
            raise variants.bad[sid]
        if sid is not None and sid in variants.keys:
            return sid
    tried = " or ".join(repr(s) for s in (folder_id, meta_id) if s) or "no id"
    raise InputError(f"no answer key for this submission ({tried}: no "
                     f"{keys_folder(keydir)}/<id>/answer_key.json of that id)",
                     "name each submission's folder by the student's id, as in the roster the "
                     "variants were written for, or write the id in [meta] id = \"…\"",
                     file=str(path), field="meta.id",
                     ru=(f"для этой работы нет ключа ответов ({tried}: нет "
                         f"{keys_folder(keydir)}/<id>/answer_key.json с таким номером)",
                         "назовите папку каждой работы номером студента, как в списке, по "
                         "которому писались варианты, или впишите номер в [meta] id = \"…\""))


def asked(lab: str, results) -> tuple[str, ...]:
    """What a student of ``lab`` is asked to report: the lab's key results (:data:`KEY`,
    what its report's summary opens with) and the module's ``ASKED`` (what else its manual
    asks for), among ``results``."""
    extra = set(getattr(lab_module(lab), "ASKED", ()))
    return tuple(n for n, r in results.items() if r.key or n in extra)


NOT_OWN = 9.0
"""Misfit (:func:`_misfit`) beyond which a submission's readings or values are not of the
student's own variant: their RMS distance from its key is over three scales."""

CLOSER = 9.0
"""How many times smaller another variant's misfit must be to name it (three times closer
in RMS): among 200 variants of lab 5 one is often about as close as the student's own (a
reduction's u is wider than the variants' spread in some results), never that much closer."""


def _misfit(pairs) -> float:
    """Mean square distance of values from a key's, each in its scale: the larger of the
    default tolerance (1 %) and the value's u, Σ((x − k)/max(0.01·|k|, u))²/n; infinite
    where nothing is compared.

    Parameters
    ----------
    pairs : iterable of (x, k, u)
        A value, the key's value, the value's standard uncertainty (SI).
    """
    terms = [((x - k) / max(Policy.rel_tol * abs(k), u)) ** 2 for x, k, u in pairs
             if max(Policy.rel_tol * abs(k), u) > 0]
    return sum(terms) / len(terms) if terms else math.inf


def _whose(misfits: dict[str, float], own: str, worked_out: float = math.inf) -> str | None:
    """The other student whose key a submission is: the closest (least misfit), where the
    student's own key is far (:data:`NOT_OWN`) and the closest is :data:`CLOSER` times closer
    than it (and than ``worked_out``); None where the submission is its own student's (or
    nobody's)."""
    if not misfits:
        return None
    best = min(misfits, key=misfits.get)
    far = min(misfits.get(own, math.inf), worked_out)
    if best == own or far <= NOT_OWN or CLOSER * misfits[best] >= far:
        return None
    return best


def _variant_slips(results, reported, variants: Variants, sid: str):
    """Whose variant the readings and the reported values are (another student's id or
    None each), and the slips that name them: our reduction of the readings (the readings
    of X's variant), X's key (the values of X's variant).

    The readings are X's where our reduction of them is far from the student's own key and
    many times closer to X's (:func:`_whose`, :func:`_misfit` over every result the keys
    hold); the values are X's where they are so to X's key, far from the student's own and
    from our reduction of the readings (values worked out from the readings are the
    readings' variant's)."""
    readings_of = _whose({other: _misfit((r.value, k[n], r.u) for n, r in results.items()
                                         if n in k and math.isfinite(r.value))
                          for other, k in variants.keys.items()}, sid)
    values = [(r.value, n, results[n]) for n, r in reported.items() if n in results
              and math.isfinite(results[n].value)]
    worked_out = _misfit((x, ours.value, ours.u) for x, _, ours in values)
    values_of = _whose({other: _misfit((x, k[n], ours.u) for x, n, ours in values if n in k)
                        for other, k in variants.keys.items()}, sid, worked_out)
    slips = []
    if readings_of:
        text = {"en": f"the readings of {readings_of}'s variant, not the student's own",
                "ru": f"замеры варианта {readings_of}, а не свои"}
        slips.append(Slip("readings_of_variant", text,
                          reduced={n: r.value for n, r in results.items()}))
        # a copy with readings edited to hide it: the values are the other variant's own
        slips.append(Slip("readings_of_variant", text,
                          reduced=dict(variants.keys[readings_of])))
    if values_of == readings_of:
        values_of = None                # the values follow from the readings
    if values_of:
        slips.append(Slip("values_of_variant",
                          {"en": f"the values of {values_of}'s variant, not the student's own",
                           "ru": f"значения варианта {values_of}, а не свои"},
                          reduced=dict(variants.keys[values_of])))
    return readings_of, values_of, slips


@scope()
def check(path: str | Path, *, policy: str | Path | None = None, confine: bool = False,
          key: dict[str, float] | None = None, variants: Variants | None = None,
          sid: str | None = None, strict: bool = True, **options) -> Check:
    """Reduce a submission and judge every reported value.

    Parameters
    ----------
    path : str or Path
        The measurement file with its ``[reported]`` table.
    policy : str, Path or PolicyFile, optional
        The teacher's policy (a file, or as :func:`read_policy` read it).
    confine : bool
        Read no file outside the submission's folder.
    key : dict, optional
        The variant's answer key (:func:`read_key`); with ``variants`` and ``sid``, the
        student's key there. What a student is asked for (:func:`asked`) among its results
        is expected (absent ones are *missing*), unless the policy says what is expected.
    variants : Variants, optional
        Every key of the class, and ``sid`` the student's id: readings that are another
        student's variant (our reduction agrees with that key, not with the student's) are
        judged against the student's own key, and the reported values that are another
        variant's are named so (:func:`_variant_slips`).
    strict : bool
        Refuse the submission for a reported value that cannot be read (a student's single
        file: the message says what to fix). False (a class): that value is *unreadable*,
        with the message, and the others are judged.
    **options
        For the lab's ``reduce``.

    Returns
    -------
    Check

    Notes
    -----
    One :func:`processing.inputs.reuse.scope`: the reductions of the slips find the analyses
    of the recordings they leave as they were done.

    Raises
    ------
    InputError
        Bad measurements (as ``dynlab run``), no ``[reported]`` table, an unknown name, a
        value without the unit its result needs, a bad reported table.
    """
    from processing.measurement import read_toml

    data = read_toml(path)
    table = data.pop("reported", None)
    tables = table.pop("tables", None) if isinstance(table, dict) else None
    module, loaded, notices = read_inputs(path, data=data, confine=confine)
    options = {"n_samples": CHECK_SAMPLES, **_results_only(module), **options}
    result = reduce_loaded(module, loaded, notices, **options)
    unreadable = None if strict else {}
    reported = _reported(str(path), table, result.results, unreadable) \
        if table or tables is None else {}
    policy = policy if isinstance(policy, PolicyFile) else read_policy(policy)
    knows = lab_knows(result.lab, result.results)
    rules = policy.for_lab(result.lab, knows)
    if variants is not None and sid is not None:
        key = variants.keys[sid]
    if key and not policy.expects(result.lab, knows):
        rules = Policy(rules.rel_tol, rules.sig_figs, tuple(
            n for n in asked(result.lab, result.results) if n in key), rules.student_u)
    names = list(dict.fromkeys([*reported, *(unreadable or ()), *rules.expected]))
    reference = {n: (r.value, r.u, r.unit, r.estimate.k) for n, r in result.results.items()}
    readings_of = values_of = None
    own_slips = []
    if key and variants is not None and sid is not None:
        readings_of, values_of, own_slips = _variant_slips(result.results, reported, variants,
                                                          sid)
    if readings_of:
        # the student's own variant, by the policy's tolerance alone: the noise of readings
        # that are not theirs is no allowance
        reference.update({n: (key[n], 0.0, unit, k) for n, (_, _, unit, k) in reference.items()
                          if n in key})

    def judged(name: str, slips) -> Verdict:
        value, u, unit, k = reference.get(name, (math.nan, math.nan, "", Z_LIMIT))
        if unreadable and name in unreadable:
            return Verdict(name, "unreadable", None, value, u, problem=unreadable[name])
        return judge(name, reported.get(name), value, u, unit, rules, slips, k=k)

    verdicts = [judged(n, own_slips + list(FACTOR_SLIPS)) for n in names]
    wrong = {v.name for v in verdicts if v.verdict == "wrong"}
    if getattr(module, "SLIPS", ()) and wrong:
        # the lab's own slips are reductions of slipped inputs: made only for a wrong value
        # the lab's first: where a generic factor gives the same value, the lab's cause is
        # the likelier
        slips = own_slips + _lab_slips(module, result.results, loaded, options, wrong) \
            + list(FACTOR_SLIPS)
        verdicts = [judged(v.name, slips) if v.verdict == "wrong" else v for v in verdicts]
    for stage in (lambda names: list(TRANSCENDENTAL_SLIPS),
                  lambda names: _input_slips(module, loaded, options, names)
                  + list(CONSTANT_SLIPS),
                  lambda names: list(SQUARED_SPEED_SLIPS)):
        # slips inside the formula, for a wrong value nothing else explains: the constants
        # no input makes (cheap), then the inputs, each reduced again
        unexplained = {v.name for v in verdicts if v.verdict == "wrong" and v.slip is None}
        if not unexplained or readings_of:
            break
        slips = stage(unexplained)
        verdicts = [judged(v.name, slips) if v.name in unexplained else v for v in verdicts]
    judged_tables = []
    if tables is not None:
        if result.lab not in TABLE_CHECKS:
            raise InputError(f"{result.lab} has no tables to check", "report its values in "
                             "[reported] and delete [reported.tables]", file=str(path),
                             field="reported.tables",
                             ru=(f"в {result.lab} нет таблиц для проверки", "укажите её "
                                 "значения в [reported] и удалите [reported.tables]"))
        checker = importlib.import_module(TABLE_CHECKS[result.lab])
        judged_tables = checker.check_tables(path, tables, loaded, rules, confine=confine)
    student = result.meta.get("student", Path(path).stem)
    if variants is not None and sid:    # the roster's name; the file's, if the file is theirs
        student = variants.names.get(sid) or (
            student if result.meta.get("id", sid) == sid else sid)
    shown = {n: (r.display_unit or r.unit, r.symbol or n, r.unit)
             for n, r in result.results.items()}
    return Check(str(path), result.lab, student, verdicts, _readings(data), judged_tables,
                 tuple(result.results), sid, readings_of, values_of, shown,
                 _recordings(loaded), rules.expected)


def _results_only(module) -> dict:
    """``report=False`` for a lab whose ``reduce`` can leave its report's tables and figures
    out: a check and its slips read the results alone."""
    return {"report": False} if "report" in inspect.signature(module.reduce).parameters else {}


_NUMBER_TEXT = re.compile(r"(?<![\w^.*/])[-+]?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?(?![\w.])")
"""A number as written in a measurement file's text (a table's cell, a value before its
unit); not a digit of a unit (``mm^2``) or of a name (``dl1``)."""


def _readings(data: dict) -> tuple[str, ...]:
    """Every number of the measurement sections as written, in order (meta left out): the
    values, the cells of the tables, the ± limits. A text with one comma has it read as a
    decimal comma."""
    out = []

    def walk(x):
        if isinstance(x, bool):
            return
        if isinstance(x, (int, float)):
            out.append(repr(x))
        elif isinstance(x, str):
            out.extend(_NUMBER_TEXT.findall(x.replace(",", ".") if x.count(",") == 1 else x))
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


def _recordings(inputs) -> tuple[tuple[str, str], ...]:
    """(name, digest) of each file the inputs name, in order, each once: a recording's
    samples (:func:`processing.inputs.signals.sample_digest`: the same recording saved again
    in another format or layout has the same), another file's bytes (a photograph)."""
    import hashlib

    from processing.inputs.signals import sample_digest

    paths = []

    def walk(x):
        if isinstance(x, Path):
            paths.append(x)
        elif isinstance(x, dict):
            for v in x.values():
                walk(v)
        elif isinstance(x, (list, tuple)):
            for v in x:
                walk(v)

    walk(inputs.sections)
    out = {}
    for p in paths:
        if p.name in out:
            continue
        try:
            out[p.name] = sample_digest(p) or hashlib.sha256(p.read_bytes()).hexdigest()
        except OSError:                 # the reduction read it; a file gone since is no copy
            continue
    return tuple(out.items())


COPY_DIFFERING = 2
"""Readings two submissions may differ in (edited, added or dropped) and still be a copy; a
tenth of the readings where that is more."""

COPY_SURPRISE = 3.0
"""How unlikely by chance the readings two copies share must be: their rarity (:func:`_rarity`,
in decades) at least this plus the decades of pairs compared (a class of 200 compares 19 900
pairs: 7.3 decades), so that an honest class has a false pair in about one of 1000."""

COMMON_SHARE = 0.5
"""A reading written in at least this share of a lab's submissions (three at least) is the
class's common one (the programme, a constant), no evidence of a copy."""


@dataclass(frozen=True)
class Copy:
    """Two submissions whose readings are one student's: the evidence a teacher gives.

    Attributes
    ----------
    a, b : Check
    same : int
        Readings written identically, in the same order.
    rounded : int
        Readings identical up to rounding (one written to fewer decimals), in the same place.
    differing : int
        Readings of the longer that match none of the other (edited, added, dropped).
    evidence : tuple of str
        The shared readings that are not the class's common ones, as written (the first few
        are shown).
    recordings : tuple of str
        The files (recordings, photographs) of the same content (:func:`_recordings`), by name.
    """

    a: Check
    b: Check
    same: int
    rounded: int
    differing: int
    evidence: tuple[str, ...]
    recordings: tuple[str, ...] = ()

    def text(self, lang: str = "en") -> str:
        """The evidence in words."""
        n = max(len(self.a.readings), len(self.b.readings))
        shown = ", ".join(self.evidence[:6]) + (" …" if len(self.evidence) > 6 else "")
        files = ", ".join(self.recordings[:4]) + (" …" if len(self.recordings) > 4 else "")
        if lang == "ru":
            return (f"{self.same + self.rounded} из {n} замеров совпадают в том же порядке "
                    f"({self.rounded} с точностью до округления), {self.differing} отличаются; "
                    f"общие: {shown}" + (f"; те же записи (те же отсчёты, как бы файл ни "
                                         f"был пересохранён): {files}" if files else ""))
        return (f"{self.same + self.rounded} of {n} readings the same in the same order "
                f"({self.rounded} up to rounding), {self.differing} differ; shared: {shown}"
                + (f"; the same recordings (the same samples, however the file was saved "
                   f"again): {files}" if files else ""))


def _decimals(text: str) -> int:
    """Decimal places written (``"12.30"`` → 2; an exponent counts: ``"1.5e-3"`` → 4)."""
    mantissa, _, exponent = text.lower().partition("e")
    places = len(mantissa.split(".")[1]) if "." in mantissa else 0
    return places - int(exponent or 0)


def _same_rounded(x: str, y: str) -> bool:
    """Whether two readings are one up to rounding: the one with more decimals, rounded to
    the other's, is it (1.347 and 1.35)."""
    (coarse, fine) = (x, y) if _decimals(x) <= _decimals(y) else (y, x)
    if _decimals(coarse) == _decimals(fine):
        return False
    half = 0.5 * 10.0 ** -_decimals(coarse)
    return abs(float(coarse) - float(fine)) <= half * (1 + 1e-9)


def _rarity(values: list[list[str]]) -> dict[str, float]:
    """How rare each reading of a lab's class is, in decades: log10(N/m), m the other
    submissions of the N that write it (one at least); 0 for the class's common readings
    (:data:`COMMON_SHARE`: the programme, a constant). ``values``: each submission's
    :func:`_values`."""
    seen = Counter(v for vs in values for v in set(vs))
    n = len(values)
    least = max(3, COMMON_SHARE * n)
    return {v: 0.0 if k >= least else math.log10(n / max(k - 1, 1)) for v, k in seen.items()}


def _values(c: Check) -> list[str]:
    """The readings of a submission as numbers written in one form (``"2.50"`` and ``"2.5"``
    are one value; rounding is told apart by :func:`_same_rounded`)."""
    return [repr(float(t)) for t in c.readings]


def _aligned(a: Check, b: Check, va: list[str], vb: list[str]) -> tuple[int, int, list[int]]:
    """The readings of ``a`` and ``b`` aligned in order (:class:`difflib.SequenceMatcher`):
    how many identical, how many identical up to rounding in the places where they differ,
    and the indices in ``a`` of both kinds; ``va``, ``vb`` their :func:`_values`."""
    same = rounded = 0
    shared = []
    matcher = difflib.SequenceMatcher(None, va, vb, autojunk=False)
    for op, i1, i2, j1, j2 in matcher.get_opcodes():
        if op == "equal":
            same += i2 - i1
            shared += range(i1, i2)
        elif op == "replace":
            for i, j in zip(range(i1, i2), range(j1, j2)):
                if _same_rounded(a.readings[i], b.readings[j]):
                    rounded += 1
                    shared.append(i)
    return same, rounded, shared


def _copy(a: Check, b: Check, va: list[str], vb: list[str], rarity: dict[str, float],
          surprise: float, recordings: tuple[str, ...] = ()) -> Copy | None:
    """The evidence that ``a`` and ``b`` are copies, or None: their readings aligned in order
    (:func:`_aligned`); a copy differs in at most :data:`COPY_DIFFERING` readings (or a
    tenth) and the readings it shares are rarer than ``surprise`` decades (:func:`_rarity`:
    the class's common ones count nothing) — or it shares ``recordings``, files of the same
    samples that no other submissions share (a recording copied, saved again or not); ``va``,
    ``vb`` their :func:`_values`."""
    n = max(len(va), len(vb))
    allowed = max(COPY_DIFFERING, n // 10)
    if not recordings and (not n or abs(len(va) - len(vb)) > allowed):
        return None
    same, rounded, shared = _aligned(a, b, va, vb)
    differing = n - same - rounded
    evidence = [i for i in shared if rarity.get(va[i], 0.0) > 0]
    if not recordings and (differing > allowed or sum(rarity.get(va[i], 0.0)
                                                      for i in evidence) < surprise):
        return None
    return Copy(a, b, same, rounded, differing, tuple(a.readings[i] for i in evidence),
                recordings)


COPY_SHARED = 0.5
"""Share of the fewer uncommon values two submissions must have in common (in any order) to
be compared in order: honest lab 5 variants share at most 0.47 of them (200 variants, 19 900
pairs), a copy with two readings edited 0.9 or more."""


def _own_recordings(group: list[Check]) -> list[set[str]]:
    """The digests of each submission's files that are not the class's common ones (a file
    in :data:`COMMON_SHARE` of the submissions, three at least: one handed to everyone)."""
    seen = Counter(d for c in group for d in {d for _, d in c.recordings})
    least = max(3, COMMON_SHARE * len(group))
    return [{d for _, d in c.recordings if seen[d] < least} for c in group]


def copies(checks: list[Check]) -> list[Copy]:
    """Pairs of submissions of one lab whose readings are one student's, as a teacher tells
    them (:func:`_copy`): most readings identical or identical up to rounding, in the same
    order, sharing readings too rare in the class to share by chance (:data:`COPY_SURPRISE`).
    Only pairs sharing :data:`COPY_SHARED` of their uncommon values (as sets, quick) are
    aligned."""
    out = []
    by_lab: dict[str, list[Check]] = {}
    for c in checks:
        by_lab.setdefault(c.lab, []).append(c)
    for group in by_lab.values():
        values = [_values(c) for c in group]
        rarity = _rarity(values)
        surprise = COPY_SURPRISE + math.log10(max(len(group) * (len(group) - 1) // 2, 1))
        own = [{v for v in vs if rarity[v] > 0} for vs in values]
        files = _own_recordings(group)
        for i, a in enumerate(group):
            for j in range(i + 1, len(group)):
                same_files = tuple(name for name, digest in a.recordings
                                   if digest in files[i] & files[j])
                fewer = min(len(own[i]), len(own[j]))
                if not same_files and (not fewer
                                       or len(own[i] & own[j]) < COPY_SHARED * fewer):
                    continue
                found = _copy(a, group[j], values[i], values[j], rarity, surprise, same_files)
                if found is not None:
                    out.append(found)
    return out


CREDIT = {"right": 1.0, "rounded": None, "over-precise": None, "wrong": 0.0, "missing": 0.0,
          "unreadable": 0.0}
"""Share of a value's points each verdict earns (None: the policy's ``partial``)."""


def mark(c: Check, policy: PolicyFile) -> tuple[float, float]:
    """A submission's mark by the policy (:meth:`PolicyFile.marking`): the points its values
    earn and the points it could earn. The values counted are those it had to report
    (:attr:`Check.expected`), or every value judged where nothing was expected; a reported
    table counts as a value, earning its points where all of it is right."""
    points, partial = policy.marking(c.lab)
    counted = [v for v in c.verdicts if not c.expected or v.name in c.expected]
    shares = [partial if CREDIT[v.verdict] is None else CREDIT[v.verdict] for v in counted]
    shares += [1.0 if t.verdict == "right" else 0.0 for t in c.tables]
    return points * sum(shares), points * len(shares)


@dataclass(frozen=True)
class ClassCheck:
    """A class checked (:func:`check_class`): what a summary is made from.

    Attributes
    ----------
    checks : list of Check
    refused : dict
        A submission that could not be checked: its file → the reason, in the class's
        language.
    pairs : list of Copy
        The copies found (:func:`copies`).
    policy : PolicyFile
    variants : Variants or None
        The keys (``--keys``) and the roster's names: every student of the roster has a row
        of the summary, handed in or not.
    refused_ids : dict
        A refused submission's file → the student's id, where its folder names one.
    problems : dict
        A refused submission's file → the :class:`InputError` (or the line of a failure of
        the toolkit), for a caller to say in its own language.
    """

    checks: list[Check]
    refused: dict[str, str]
    pairs: list[Copy]
    policy: PolicyFile = field(default_factory=PolicyFile)
    variants: Variants | None = None
    refused_ids: dict[str, str] = field(default_factory=dict)
    problems: dict = field(default_factory=dict)

    def roster(self) -> list[tuple[str, str]]:
        """(id, name) of every student the class has: the roster's, or every key's."""
        if self.variants is None:
            return []
        ids = list(self.variants.names) or sorted({*self.variants.keys, *self.variants.bad})
        return [(sid, self.variants.names.get(sid, sid)) for sid in ids]


def folder_id(path: Path, folders) -> str | None:
    """The <id> of a submission in ``<folder>/<id>/…`` for one of ``folders`` (None for a file
    at a folder's top, or in none of them)."""
    from processing.files import resolved

    for folder in folders:
        try:
            parts = resolved(path).relative_to(resolved(folder)).parts
        except ValueError:
            continue
        return parts[0] if len(parts) > 1 else None
    return None


def _meta_id(path: Path) -> str | None:
    """The ``[meta] id`` of a measurement file, if it gives one."""
    from processing.measurement import read_toml

    sid = read_toml(path).get("meta", {}).get("id")
    return sid if isinstance(sid, str) else None


BLAS_THREADS = 1
"""Threads of numpy's BLAS while a class is checked (threadpoolctl): a check's linear algebra
is small (fits of a few parameters), so more threads only spin; one per process leaves the
other cores to other work (or to a pool of checking processes)."""


def check_class(files, folders=(), *, policy: PolicyFile | None = None,
                variants: Variants | None = None, keys: str | Path | None = None,
                lang: str = "en", progress=lambda items: items, crash=None) -> ClassCheck:
    """Check the submissions of a class: each file bound to its student (by its folder
    ``<folder>/<id>/`` of ``folders``, or its ``[meta] id``) where ``variants`` (read from
    ``keys``) are given, checked with ``confine`` where the files come from ``folders``; a
    submission that cannot be checked is refused with its reason (in ``lang``), the others
    checked, with numpy's BLAS on :data:`BLAS_THREADS` thread; the copies found.

    Parameters
    ----------
    crash : callable, optional
        ``crash(exc, path)`` for a failure of the toolkit on one file (not bad input): the
        line that refuses it, or it raises. Without it, the failure is raised.

    Raises
    ------
    InputError
        A policy's ``expected`` no submission gives (:func:`unknown_expected`).
    """
    from threadpoolctl import threadpool_limits

    policy = policy or PolicyFile()
    checks, refused, ids, problems = [], {}, {}, {}
    with threadpool_limits(limits=BLAS_THREADS):
        for path in progress(files):
            sid = folder_id(path, folders)
            try:
                if variants is not None:
                    sid = student_key(variants, sid, _meta_id(path), path, keys)
                checks.append(check(path, policy=policy, confine=bool(folders),
                                    variants=variants, sid=sid, strict=False))
                continue
            except InputError as exc:
                refused[str(path)], problems[str(path)] = exc.text(lang), exc
            except Exception as exc:
                if crash is None:
                    raise
                refused[str(path)] = problems[str(path)] = crash(exc, str(path))
            ids.update({str(path): sid} if sid else {})
    unknown_expected(checks, policy)
    return ClassCheck(checks, refused, copies(checks), policy, variants, ids, problems)



def submissions(folder: Path) -> list[Path]:
    """The measurement files below a class folder: each ``.toml``, in any letter case, and
    each ``.toml.txt`` (Notepad saving a "Text Document" adds ``.txt`` to the name); whatever
    they are (a FIFO or a folder named so is refused when it is checked, not passed over)."""
    return sorted(p for p in Path(folder).rglob("*") if p.name.lower().endswith(MEASUREMENT_NAMES))

def read_class(folder: str | Path, *, policy: str | Path | None = None,
               keys: str | Path | None = None, roster: str | Path | None = None,
               lang: str = "en", crash=None) -> ClassCheck:
    """Check a class folder as ``dynlab check FOLDER [--policy P] [--keys K [--roster R]]``
    does (:func:`check_class` of every ``.toml`` under it): the entry point for a program
    (the web page) that checks a class and writes its summary
    (:func:`labs.teachers.check_report.write_summary`). ``crash`` is :func:`check_class`'s.

    Raises
    ------
    InputError
        A bad policy, roster or keys folder; no submission in the folder; a policy's
        ``expected`` no submission gives.
    """
    from .variants import read_roster

    folder = Path(folder)
    files = submissions(folder)
    if not files:
        raise InputError("no .toml submission in the folder", "give the folder holding the "
                         "students' measurement files", file=str(folder),
                         ru=("в папке нет ни одного файла .toml",
                             "укажите папку с файлами измерений студентов"))
    variants = None if keys is None else read_variants(
        keys, None if roster is None else read_roster(roster))
    return check_class(files, [folder], policy=read_policy(policy), variants=variants,
                       keys=keys, lang=lang, crash=crash)
