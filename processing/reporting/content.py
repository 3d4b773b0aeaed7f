"""What a report says, formatted once for every renderer (terminal, HTML, PDF).

:func:`build` turns a :class:`~processing.result.LabResult` into plain strings and rows in
the chosen language; renderers only lay them out.
"""
from __future__ import annotations

import math
import re

from processing.numerals import localize_numbers
from processing.units import unit_text

from .i18n import text

UNIVERSITY = {"en": "Vladimir State University", "ru": "Владимирский государственный университет"}
DEPARTMENT = {"en": "Department of Internal Combustion Engines",
              "ru": "Кафедра двигателей внутреннего сгорания"}


def fmt_pm(value: float, U: float) -> tuple[str, str]:
    """Value and uncertainty rounded together: U to two significant digits.

    >>> fmt_pm(0.123456, 0.0012345)
    ('0.1235', '0.0012')
    >>> fmt_pm(1234.5, 0.0)
    ('1234.5', '0')
    """
    if not (U > 0 and math.isfinite(U)):
        return f"{value:.6g}", "0"
    decimals = max(0, 1 - int(math.floor(math.log10(U))))
    return f"{value:.{decimals}f}", f"{U:.{decimals}f}"


def result_pm(results, name: str, scale: float = 1.0) -> str:
    """``value ± U`` of a result in its display unit (times ``scale``), rounded together; "—"
    if the lab has no such result. For a lab's own tables."""
    if name not in results:
        return "—"
    r = results[name]
    v, U = (scale * r.shown(x) for x in (r.value, r.value + r.estimate.U))
    return " ± ".join(fmt_pm(v, U - v))


def _budget(r, lang: str, names: dict[str, str], top: int = 3) -> str:
    """The largest shares of u² of a result, each input named by ``names`` (its key in the
    file → how the report names it) or, failing that, by its key."""
    items = sorted(r.estimate.contributions.items(), key=lambda kv: -kv[1])
    total = sum(c * c for _, c in items) or 1.0
    return ", ".join(f"{_named(k, names)} {100 * c * c / total:.0f} %"
                     for k, c in items[:top] if c * c / total >= 0.005)


def _named(key: str, names: dict[str, str]) -> str:
    """A budget's input as ``names`` names it: by its key, or, under a part that is a word
    (``decay.log_decrement_peaks``), by its last part; else by :func:`_model_name` (no
    ``names``: by its key).

    >>> _named("decay.log_decrement_peaks", {"log_decrement_peaks": "δ_p"})
    'δ_p'
    """
    head, _, last = key.rpartition(".")
    if key in names or not names:
        return names.get(key, key)
    return names.get(last) if _WORD.fullmatch(head) and last in names else _model_name(key)


GREEK = {"alpha": "α", "beta": "β", "gamma": "γ", "delta": "δ", "epsilon": "ε", "zeta": "ζ",
         "eta": "η", "theta": "θ", "kappa": "κ", "lambda": "λ", "mu": "μ", "nu": "ν", "xi": "ξ",
         "pi": "π", "rho": "ρ", "sigma": "σ", "tau": "τ", "phi": "φ", "chi": "χ", "psi": "ψ",
         "omega": "ω"}
"""Greek letters a key spells in Latin (``omega``), as a Russian report prints them."""

_WORD = re.compile(r"[a-z]{3,}(?:_[a-z0-9]+)*")
"""A key that is an English word (``tdc_channel``, ``shape``), not a symbol (``m_ref``)."""


def _symbol(symbol: str, lang: str) -> str:
    """An input's symbol as a report prints it: in Russian, a key that is an English word
    (an input the manual gives no symbol) is left out, its description says what it is.

    >>> _symbol("tdc_channel", "ru"), _symbol("m_ref", "ru"), _symbol("shape", "en")
    ('', 'm_ref', 'shape')
    """
    return "" if lang == "ru" and _WORD.fullmatch(symbol) and symbol not in GREEK else symbol


MODEL_WORDS_RU = {"advance": "опережение", "lag": "запаздывание", "loss": "потеря",
                  "compliance": "податливость", "dynamometer": "динамометр",
                  "gauge": "индикатор", "lift_gauge": "индикатор подъёма", "lever": "рычаг",
                  "load": "нагрузка", "unload": "разгрузка", "mean": "среднее",
                  "model": "модель", "order": "порядок", "share": "доля", "slope": "наклон",
                  "half_period": "полупериод"}
"""The inputs of the labs' measurement models that are no field of the file and are named
by a word (lab 5's gauges, lever and branches, lab 2's statistical share, lab 6's phases,
lab 7's model, slope and orders, lab 9's compliance), as a Russian budget names them."""

_NUMBERED = re.compile(r"([a-z_]*[a-z])(\d*)")


def _model_word(word: str) -> str:
    """A model input's own name in Russian: a word of :data:`MODEL_WORDS_RU` (its number
    kept), a Greek letter spelt out written as the letter, in a symbol's parts too.

    >>> _model_word("gauge3"), _model_word("omega_max"), _model_word("phi4"), _model_word("A_min")
    ('индикатор 3', 'ω_max', 'φ4', 'A_min')
    """
    numbered = _NUMBERED.fullmatch(word)
    if numbered and numbered[1] in MODEL_WORDS_RU:
        return " ".join(filter(None, (MODEL_WORDS_RU[numbered[1]], numbered[2])))

    def part(p: str) -> str:
        m = _NUMBERED.fullmatch(p)
        return GREEK[m[1]] + m[2] if m and m[1] in GREEK else p
    return "_".join(part(p) for p in word.split("_"))


def _model_name(key: str) -> str:
    """A measurement model's input that is no field of the file, as a Russian budget names it:
    its last part in Russian (:func:`_model_word`) and the part before it where that is a
    symbol, not an English word (``r7.omega`` → ``ω (r7)``).

    >>> _model_name("r7.omega"), _model_name("chain.c4"), _model_name("lever")
    ('ω (r7)', 'c4', 'рычаг')
    >>> _model_name("s3.unload"), _model_name("r11.order6")
    ('разгрузка (s3)', 'порядок 6 (r11)')
    """
    head, _, last = key.rpartition(".")
    last = _model_word(last)
    return f"{last} ({head})" if head and not _WORD.fullmatch(head) else last


def _input_names(rows, lang: str) -> dict[str, str]:
    """How a Russian report names each input in a budget: its symbol, numbered where its
    section holds many entries (``analytic[1].R`` → ``R (2)``); an English one keeps the
    file's keys.

    >>> _input_names([{"section": "analytic[1]", "name": "R", "symbol": "R"},
    ...               {"section": "trifilar", "name": "R1", "symbol": "R₁"}], "ru")
    {'analytic[1].R': 'R (2)', 'trifilar.R1': 'R₁'}
    """
    if lang == "en":
        return {}
    names = {}
    for row in rows:
        index = row["section"].partition("[")[2].rstrip("]")
        names[f"{row['section']}.{row['name']}"] = \
            f"{row['symbol']} ({int(index) + 1})" if index else row["symbol"]
    return names


SHOWN_READINGS = 10
"""Readings of one input listed in a report; a longer series is shown by its ends."""


def _readings(values, lang: str) -> str:
    """Repeated readings as a report cell: all of them, or the first and last few and n.

    >>> _readings([1, 2, 3], "en")
    '1, 2, 3'
    >>> _readings(range(100), "en")
    '0, 1, 2, 3, 4, …, 95, 96, 97, 98, 99 (n = 100)'
    """
    values = list(values)
    if len(values) <= SHOWN_READINGS:
        return ", ".join(f"{x:g}" for x in values)
    half = SHOWN_READINGS // 2
    return (", ".join(f"{x:g}" for x in values[:half]) + ", …, "
            + ", ".join(f"{x:g}" for x in values[-half:]) + f" (n = {len(values)})")


def _plain_value(row: dict, lang: str) -> str:
    """An input that is no quantity as a report prints it: a choice in its words, a flag as
    yes or no, a count or a text as written.

    >>> _plain_value({"value": True}, "ru"), _plain_value({"value": "in",
    ...     "value_label": {"en": "inlet", "ru": "впускной"}}, "ru")
    ('да', 'впускной')
    """
    if "value_label" in row:
        return row["value_label"][lang]
    if isinstance(row["value"], bool):
        return text(lang)["yes" if row["value"] else "no_flag"]
    return str(row["value"])


def _section(row: dict, lang: str) -> str:
    """The section of an input as a report names it: the file's name of it in English
    (``analytic[0]``), its title in Russian, numbered from 1 in a section of many entries.

    >>> row = {"section": "analytic[1]", "section_label": {"en": "Parts", "ru": "Части"}}
    >>> _section(row, "en"), _section(row, "ru")
    ('analytic[1]', 'Части, 2')
    """
    if lang == "en" or "section_label" not in row:
        return row["section"]
    index = row["section"].partition("[")[2]
    label = row["section_label"][lang]
    return f"{label}, {int(index.rstrip(']')) + 1}" if index else label


def _cell(value, lang: str) -> str:
    return value[lang] if isinstance(value, dict) else str(value)


PM = "\u00a0±\u00a0"
"""Between a value and its U: no-break spaces keep ``0.01815 ± 0.00084`` on one line."""

def _localized(x, lang: str):
    """Every string in ``x`` (nested lists, tuples, dicts' values) through
    :func:`localize_numbers`."""
    if isinstance(x, str):
        return localize_numbers(x, lang)
    if isinstance(x, dict):
        return {k: _localized(v, lang) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return type(x)(_localized(v, lang) for v in x)
    return x


def _summary(res, results: list[dict], lang: str) -> list[dict]:
    """The lab's key results (:data:`~processing.result.KEY`) as the summary's rows, each with
    its verdict against the manual's typical range where one is declared."""
    t = text(lang)
    rows = []
    for row in results:
        r = res.results[row["name"]]
        if not r.key:
            continue
        verdict, ok = "", True
        if r.typical is not None:
            lo, hi = (f"{r.shown(x):.4g}" for x in (r.typical.low, r.typical.high))
            kind = r.typical.verdict(r.value)
            ok = kind == "within"
            verdict = t[f"typical_{kind}"].format(range=f"{lo}–{hi}",
                                                  source=r.typical.source[lang])
        rows.append({**row, "pm": row["value"] if row["exact"] else
                     f"{row['value']}{PM}{row['U']}", "verdict": verdict, "ok": ok})
    return rows


def build(res, lang: str = "en") -> dict:
    """Every piece of the report, in ``lang``, as strings and rows (numbers written as
    ``lang`` writes them, :func:`localize_numbers`; the names the student typed as typed)."""
    t = text(lang)
    meta = dict(res.meta)
    results, names = [], _input_names(res.inputs, lang)
    if lang == "ru":     # a result named by a word that is another's input: by its symbol
        names = {**{n: r.symbol for n, r in res.results.items()
                    if r.symbol and _WORD.fullmatch(n)}, **names}
    for name, r in res.results.items():
        e = r.estimate
        v, U = fmt_pm(r.shown(e.value), r.shown(e.value + e.U) - r.shown(e.value))
        exact = e.U == 0
        lo, hi = (r.shown(x) for x in e.interval95)
        results.append({
            "name": name, "label": r.label[lang], "symbol": r.symbol, "value": v,
            "U": "—" if exact else U, "k": "—" if exact else f"{e.k:.2g}", "exact": exact,
            "unit": unit_text(r.display_unit, lang), "rel": f"{100 * e.relative_U:.2g}\u00a0%"
            if math.isfinite(e.relative_U) and not exact else "—",
            "interval": f"[{lo:.5g}, {hi:.5g}]" if math.isfinite(lo) and not exact else "—",
            "budget": _budget(r, lang, names), "nonlinear": e.nonlinear})
    comparisons = []
    for c in res.comparisons:
        a, b = res.results[c.a], res.results[c.b]
        d, U = fmt_pm(a.shown(c.difference.value) - a.shown(0.0),
                      a.shown(c.difference.U) - a.shown(0.0))
        comparisons.append({
            "a": a.label[lang], "b": b.label[lang], "diff": f"{d}{PM}{U}",
            "unit": unit_text(a.display_unit, lang), "rel": f"{100 * c.relative_to(b.value):+.2f}\u00a0%",
            "agree": t["yes"] if c.agree else t["no"], "ok": c.agree})
    inputs = []
    for row in res.inputs:
        if row.get("series"):           # a programme of steps: the steps, no mean or u
            v, u, readings = "", "", _readings(row["readings"], lang)
        elif "u" in row:
            v, u = fmt_pm(row["value"], row["u"])
            u = u if row["u"] > 0 else ""       # a reading without a stated u shows none
            readings = _readings(row.get("readings", []), lang)
        else:
            v, u, readings = _plain_value(row, lang), "", ""
        inputs.append({"section": _section(row, lang), "symbol": _symbol(row["symbol"], lang),
                       "label": row["label"][lang], "value": v, "u": u,
                       "unit": unit_text(row["unit"], lang), "readings": readings})
    tables, measurements = ([{"title": tb.title[lang], "columns": [h[lang] for _, h in tb.columns],
                              "rows": [[_cell(r.get(k, ""), lang) for k, _ in tb.columns]
                                       for r in tb.rows]} for tb in group]
                            for group in (res.tables, res.measurements))
    return _localized({
        "summary": _summary(res, results, lang),
        "university": meta.pop("university", UNIVERSITY[lang]),
        "department": meta.pop("department", DEPARTMENT[lang]),
        "lab_heading": f"{t['lab']} {res.number}" if res.number else t["coursework"], "title": res.title[lang],
        "goal": res.goal[lang],
        "inputs": inputs, "results": results,
        "uncertain": any(not r["exact"] for r in results),
        "inputs_uncertain": any(row.get("u", 0) for row in res.inputs), "comparisons": comparisons, "tables": tables,
        "measurements": measurements,
        "formulas": [f[lang] for f in res.formulas],
        "warnings": [w.text(lang) for w in res.warnings],
        "warning_codes": [w.code for w in res.warnings],
        "conclusion": [c[lang] for c in res.conclusion],
        "figures": [(f.name, f.caption[lang]) for f in res.figures],
    }, lang) | {"t": t, "lang": lang, "source": res.source,
                "references": [r[lang] for r in res.references],   # cited as published
                "meta": [(t.get(k, k), v) for k, v in meta.items() if v]}
