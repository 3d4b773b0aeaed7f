"""The result of a lab's reduction: named values ± uncertainty, tables, figures, warnings.

One :class:`LabResult` class serves every lab, so that one report engine renders them all
and the JSON contract of ARCHITECTURE.md ("Result JSON") holds for each. Result names are
stable: teachers' checks key on them.
"""
from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, fields
from typing import Any

from .diagnostics import Notice
from .uncertainty import Estimate, Propagation
from .units import convert, dimension, si_unit, unit_text


class Record:
    """Mixin of the result dataclasses of the formula modules: ``to_dict()`` of the named
    fields, nested records as dicts (values as stored: floats or arrays)."""

    def to_dict(self) -> dict:
        return {f.name: (v.to_dict() if isinstance(v := getattr(self, f.name), Record) else v)
                for f in fields(self)}


POSITIVE = {dimension(u): name for u, name in (
    ("kg", "mass"), ("kg*m^2", "moment of inertia"), ("N/m", "linear stiffness"),
    ("kg/m^3", "density"))}
"""Dimensions of results that cannot be negative by their nature (a torsional stiffness
shares its dimension with a torque, which may be negative, and is left to the lab)."""

SIGNED = "signed"
"""Marks a declared result of a :data:`POSITIVE` dimension that may be negative (a residual)."""

@dataclass(frozen=True)
class Within:
    """Marks a declared result that lies between ``low`` and ``high`` (SI) by its nature, and
    says what to check (``fix``) when it comes out beyond them: a valve's timing within 90° of
    its dead centre."""

    low: float
    high: float
    fix: str


KEY = "key"
"""Marks a declared result the lab's summary opens with: what the student writes as the
lab's answer (δ of each regime, the moments of inertia, the stiffnesses)."""


@dataclass(frozen=True)
class Typical:
    """Marks a declared result that the manual gives a typical range for (``low``…``high``,
    SI; ``source`` says whose range, e.g. {"en": "automotive engines", "ru": …}): the report's
    summary says whether the result lies in it."""

    low: float
    high: float
    source: Mapping[str, str]

    def verdict(self, value: float) -> str:
        """"below", "within" or "above" the range."""
        return "below" if value < self.low else "above" if value > self.high else "within"


STRICTLY_POSITIVE = "strictly positive"
"""Marks a declared result that is > 0 by its nature whatever its dimension: a speed
irregularity δ, an amplitude, a decrement, a natural frequency, a stiffness."""


@dataclass(frozen=True)
class ResultValue:
    """One result: value, standard uncertainty u, and how to print it.

    ``unit`` is SI (what JSON carries); ``display_unit`` is what a report prints.
    """

    name: str
    estimate: Estimate
    unit: str
    label: Mapping[str, str]
    symbol: str = ""
    display_unit: str = ""
    signed: bool = False
    """A difference or residual: may be negative whatever its dimension."""
    positive: bool = False
    """> 0 by its nature (:data:`STRICTLY_POSITIVE`)."""
    within: Within | None = None
    """The interval it lies in by its nature, if declared."""
    key: bool = False
    """One of the lab's key results (:data:`KEY`): the report's summary shows it."""
    typical: Typical | None = None
    """The manual's typical range for it, if declared."""

    @property
    def value(self) -> float:
        return self.estimate.value

    @property
    def u(self) -> float:
        return self.estimate.u

    def shown(self, x: float) -> float:
        """``x`` (SI) in the display unit."""
        return convert(x, self.unit, self.display_unit) if self.display_unit else x

    def to_dict(self) -> dict:
        e = self.estimate
        return {"value": e.value, "u": _finite(e.u), "U": _finite(e.U), "k": _finite(e.k), "unit": self.unit,
                "relative_U": _finite(e.relative_U),
                "interval95": [_finite(x) for x in e.interval95],
                "dof": _finite(e.dof), "nonlinear": e.nonlinear,
                "symbol": self.symbol, "label": dict(self.label), "key": self.key,
                **({"typical": {"low": self.typical.low, "high": self.typical.high,
                                "source": dict(self.typical.source),
                                "verdict": self.typical.verdict(e.value)}}
                   if self.typical else {})}


def _finite(x: float) -> float | None:
    """``x``, or None (JSON null) where it is infinite or undefined."""
    return x if math.isfinite(x) else None


@dataclass(frozen=True)
class Comparison:
    """Two results for one quantity (two methods): their difference and its uncertainty."""

    a: str
    b: str
    difference: Estimate

    @property
    def agree(self) -> bool:
        """Whether |a − b| ≤ U(a − b), the expanded uncertainty of the difference (k from its
        effective degrees of freedom, :func:`~processing.uncertainty.coverage_factor`)."""
        return abs(self.difference.value) <= self.difference.U

    def relative_to(self, reference: float) -> float:
        return self.difference.value / reference if reference else math.nan

    def to_dict(self, results: Mapping[str, ResultValue]) -> dict:
        d = self.difference
        return {"a": self.a, "b": self.b, "difference": d.value, "u": d.u, "U": d.U, "k": _finite(d.k),
                "relative": self.relative_to(results[self.b].value), "agree": self.agree}


@dataclass(frozen=True)
class Table:
    """A table of the report (e.g. the manual's method × quantity table).

    ``columns`` are ``(key, {"en", "ru"} heading)``; ``rows`` are dicts keyed by column key,
    holding text, or a ``{"en", "ru"}`` dict where the text depends on the language.
    """

    title: Mapping[str, str]
    columns: tuple[tuple[str, Mapping[str, str]], ...]
    rows: tuple[Mapping[str, Any], ...]
    kind: str = "results"
    """What the table holds: ``"results"`` (named results: every number of it but its
    :attr:`keys` is one in the JSON's ``results`` or ``inputs``), ``"worked"`` (a worked calculation step by step, or the points a
    result was found from: the JSON's ``tables`` carries it as printed), ``"readings"`` (the
    manual's table of readings) or ``"reference"`` (the manual's printed data, beside ours)."""
    keys: int = 1
    """How many first columns name the row (a regime, a record, a mode and an order)."""

    def to_dict(self) -> dict:
        """The table as the English report prints it: title, column headings, cells."""
        def cell(x):
            return x["en"] if isinstance(x, Mapping) else str(x)

        return {"title": self.title["en"], "kind": self.kind,
                "columns": [h["en"] for _, h in self.columns],
                "rows": [[cell(r.get(k, "")) for k, _ in self.columns] for r in self.rows]}


@dataclass(frozen=True)
class Figure:
    """A figure of the report: ``draw(fig, lang)`` draws on a matplotlib Figure."""

    name: str
    caption: Mapping[str, str]
    draw: Callable[[Any, str], None]
    size: tuple[float, float] = (6.4, 3.6)


@dataclass
class LabResult:
    """What a lab's ``reduce`` returns; what every renderer takes.

    Index it by result name (``res["J_trifilar"].value``); :meth:`to_dict` gives the JSON
    contract; :meth:`to_pandas` a table of the results.
    """

    lab: str
    number: str
    title: Mapping[str, str]
    goal: Mapping[str, str]
    meta: Mapping[str, str]
    inputs: list[dict]
    results: dict[str, ResultValue]
    comparisons: list[Comparison] = field(default_factory=list)
    tables: list[Table] = field(default_factory=list)
    measurements: list[Table] = field(default_factory=list)
    """The manual's tables of readings (rows of runs, the manual's columns): the report's
    measurements section."""
    figures: list[Figure] = field(default_factory=list)
    formulas: list[Mapping[str, str]] = field(default_factory=list)
    references: list[Mapping[str, str]] = field(default_factory=list)
    warnings: list[Notice] = field(default_factory=list)
    conclusion: list[Mapping[str, str]] = field(default_factory=list)
    source: str = ""

    @classmethod
    def of(cls, inputs, results: dict[str, ResultValue], **parts) -> LabResult:
        """The result of reducing ``inputs`` (a :class:`~processing.measurement.Inputs`): the
        title block, goal, input table, source and the tables of readings its lab's spec
        declares (before any the lab adds in ``parts["measurements"]``) come from the file and
        its lab's spec."""
        spec = inputs.spec
        declared = [Table(t.title, (("run", t.run), *((c.heading["en"], c.heading)
                                                      for c in t.columns
                                                      if c.heading["en"] in rows[0])),
                          tuple(rows), "readings")
                    for t, rows in inputs.readings()]
        parts["measurements"] = declared + list(parts.get("measurements", ()))
        return cls(spec.id, spec.number, spec.title, spec.goal, inputs.meta, inputs.rows(),
                   results, source=inputs.file, **parts)

    def __getitem__(self, name: str) -> ResultValue:
        return self.results[name]

    def check_sense(self) -> None:
        """Raise :class:`~processing.diagnostics.InputError` if a result is not a finite
        number, is a mass, a moment of inertia, a linear stiffness or a density below zero
        (:data:`POSITIVE`, unless declared :data:`SIGNED`; zero may mean "none", e.g. no
        flywheel needed), is declared :data:`STRICTLY_POSITIVE` and is not above zero, or lies
        outside the interval it is declared :class:`Within`: its inputs lie where the lab's
        formulas do not hold, or a record was misread."""
        from .diagnostics import InputError

        fix = ("check the inputs' values and units against the template "
               f"('dynlab template {self.lab}')")
        for name, r in self.results.items():
            if not math.isfinite(r.value):
                raise InputError(f"{name} ({r.label['en']}) cannot be computed from these "
                                 f"inputs (it comes out {r.value})", fix, file=self.source)
            if r.value < 0 and not r.signed and dimension(r.unit) in POSITIVE:
                raise InputError(f"{name} ({r.label['en']}) comes out {r.value:.4g} {r.unit}: "
                                 f"a {POSITIVE[dimension(r.unit)]} cannot be negative", fix,
                                 file=self.source)
            if r.positive and not r.value > 0:
                raise InputError(f"{name} ({r.label['en']}) comes out {r.value:.4g} "
                                 f"{r.unit}".rstrip() + ", but it is above zero by its nature: "
                                 "the inputs or a record were read wrongly", fix,
                                 file=self.source)
            if r.within is not None and not r.within.low <= r.value <= r.within.high:
                low, high, value = (r.shown(x) for x in (r.within.low, r.within.high, r.value))
                unit = unit_text(r.display_unit)
                raise InputError(f"{name} ({r.label['en']}) comes out {value:.4g} {unit}, "
                                 f"outside {low:.4g}…{high:.4g} {unit} where it lies by its "
                                 "nature", r.within.fix, file=self.source)

    def __contains__(self, name: str) -> bool:
        return name in self.results

    def to_dict(self) -> dict:
        from . import __version__

        return {
            "lab": self.lab, "title": dict(self.title), "meta": dict(self.meta),
            "inputs": {f"{row['section']}.{row['name']}": _input_json(row) for row in self.inputs},
            "results": {k: v.to_dict() for k, v in self.results.items()},
            "comparisons": [c.to_dict(self.results) for c in self.comparisons],
            "tables": [t.to_dict() for t in (*self.measurements, *self.tables)],
            "warnings": [w.to_dict() for w in self.warnings],
            "toolkit": {"name": "dynlab", "version": __version__},
        }

    def to_pandas(self):
        """The results as a DataFrame: value, u, k, U = k·u, unit, Monte Carlo 95 % interval."""
        import pandas as pd

        return pd.DataFrame(
            [{"name": k, "value": v.value, "u": v.u, "k": v.estimate.k, "U": v.estimate.U,
              "unit": v.unit,
              "low95": v.estimate.interval95[0], "high95": v.estimate.interval95[1]}
             for k, v in self.results.items()]).set_index("name")


def _input_json(row: dict) -> dict:
    """An input in SI (the JSON contract); counts, choices and text as they are."""
    if "si" not in row:
        return {"value": row["value"], "unit": ""}
    if row.get("series"):
        return {"readings": row["si"]["readings"], "unit": row["si"]["unit"]}
    out = {k: row["si"][k] for k in ("value", "u", "unit")}
    if row["si"]["readings"]:
        out["readings"] = row["si"]["readings"]
    return out


def result_values(prop: Propagation, declared: Mapping[str, tuple]) -> dict[str, ResultValue]:
    """Wrap a propagation's outputs as :class:`ResultValue` s.

    ``declared`` maps output name → ``(label dict, symbol, display unit)``, followed by any of
    the markers: :data:`SIGNED` for a difference or residual that may be negative although
    its dimension is a mass's or an inertia's, :data:`STRICTLY_POSITIVE` for a result that
    must come out above zero, a :class:`Within` for one that lies in an interval, :data:`KEY`
    for one of the lab's key results, a :class:`Typical` for one the manual gives a typical
    range for. Outputs not declared are left out (they are internal, e.g. intermediate
    quantities).
    """
    def marker(rest, kind):
        return next((r for r in rest if isinstance(r, kind)), None)

    estimates = prop.estimates([name for name in declared if name in prop])
    return {name: ResultValue(name, estimates[name], _si(disp), label, symbol,
                              disp, signed=SIGNED in rest, positive=STRICTLY_POSITIVE in rest,
                              within=marker(rest, Within), key=KEY in rest,
                              typical=marker(rest, Typical))
            for name, (label, symbol, disp, *rest) in declared.items() if name in estimates}


def computed(estimates: Mapping[str, Estimate | float],
             declared: Mapping[str, tuple]) -> dict[str, ResultValue]:
    """Results found outside a propagation (a loop's area from the readings as they are, a
    line's slope with its fit's own type A uncertainty), declared as :func:`result_values`
    takes them: ``name → (label, symbol, display unit)``. A plain number is exact (its
    report shows no U). Names not in ``estimates`` are left out.

    Examples
    --------
    >>> r = computed({"A": 2.5}, {"A": ({"en": "area", "ru": "площадь"}, "A", "N*mm")})
    >>> r["A"].unit, r["A"].u
    ('kg*m^2/s^2', 0.0)
    """
    def estimate(x):
        return x if isinstance(x, Estimate) else Estimate(float(x), 0.0, math.inf)

    return {name: ResultValue(name, estimate(estimates[name]), _si(disp), label, symbol, disp)
            for name, (label, symbol, disp, *_) in declared.items() if name in estimates}


def _si(unit: str) -> str:
    """The SI unit a result declared in ``unit`` is carried in (JSON); "" for a pure
    number."""
    return si_unit(unit) if unit else ""


def with_key(declared: Mapping[str, tuple], names) -> dict[str, tuple]:
    """``declared`` (as :func:`result_values` takes it) with :data:`KEY` added to the
    results ``names``."""
    return {name: (*d, *((KEY,) if name in names else ())) for name, d in declared.items()}


def compare(prop: Propagation, pairs) -> list[Comparison]:
    """Comparisons of the result pairs ``(a, b)`` present in ``prop``, correlations included."""
    return [Comparison(a, b, prop.difference(a, b)) for a, b in pairs if a in prop and b in prop]


def flag_estimates(results: Mapping[str, ResultValue], comparisons, lang_names=None) -> None:
    """Warn about nonlinear estimates and methods that disagree (inside ``collect_notices``)."""
    import warnings

    from .diagnostics import MethodsDisagreeWarning, NonlinearityWarning

    for name, r in results.items():
        if r.estimate.nonlinear:
            lo, hi = (r.shown(x) for x in r.estimate.interval95)
            warnings.warn(NonlinearityWarning(
                f"{name}: the linear uncertainty is not reliable (the formula is strongly "
                f"nonlinear over the input uncertainties); trust the Monte Carlo 95 % interval "
                f"[{lo:.4g}, {hi:.4g}] {unit_text(r.display_unit)}",
                f"{r.label['ru']} ({r.symbol}): линейная оценка погрешности ненадёжна (формула сильно нелинейна в "
                f"пределах погрешностей входных данных); верен интервал Монте-Карло 95 % "
                f"[{lo:.4g}, {hi:.4g}] {unit_text(r.display_unit, 'ru')}"))
    for c in comparisons:
        if not c.agree:
            b = results[c.b]
            if b.value:
                gap = f"{100 * c.relative_to(b.value):+.2f} %"
                bound = f"{100 * c.difference.U / abs(b.value):.2f} %"
                gap_ru, bound_ru = gap, bound
            else:                       # nothing to scale by: the difference as it is
                (gap, bound), (gap_ru, bound_ru) = (
                    [f"{b.shown(v):+.4g} {unit_text(b.display_unit, lang)}".rstrip()
                     for v in (c.difference.value, c.difference.U)] for lang in ("en", "ru"))
            warnings.warn(MethodsDisagreeWarning(
                f"{c.a} and {c.b} differ by {gap}, more than the expanded uncertainty of "
                f"their difference ({bound}): look for a systematic error (a misread length, "
                f"a wrong count of oscillations)",
                f"«{results[c.a].label['ru']}» и «{b.label['ru']}» различаются на {gap_ru}, больше расширенной "
                f"неопределённости разности ({bound_ru}): ищите систематическую ошибку (неверно измеренная длина, "
                f"счёт колебаний)"))
