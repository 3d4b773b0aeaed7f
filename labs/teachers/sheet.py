"""The sheet of readings a student gets with a variant (``dynlab synth --students``): a
printable page, in English and Russian, that reads like the manual's tables — each section of
the measurement file under its name, each reading with what it is, its symbol and its unit,
repeated sections (regimes, records) as one table a row each, the tables of readings as
tables, and the recordings by their file names.

The sheet shows what the measurement file holds, as written there (a value written with its
unit keeps it; a plain number gets the unit the lab reads it in), so that a student can find
every number of the sheet in the file.
"""
from __future__ import annotations

import re
from html import escape

from processing.measurement import Field, LabSpec, Section
from processing.units import unit_text

STYLE = """
body{font-family:sans-serif;font-size:10.5pt;margin:1.5em;max-width:60em}
h1{font-size:15pt;margin-bottom:0}h1+p{margin-top:2px;color:#444}
h2{font-size:12pt;margin:1.2em 0 .3em;border-bottom:1px solid #999}
h3{font-size:11pt;margin:.8em 0 .2em}
h2 small,th small{font-weight:normal;color:#555}
table{border-collapse:collapse;margin:.3em 0 .6em}
td,th{border:1px solid #999;padding:2px 8px;text-align:left;vertical-align:top}
th{background:#f0f0f0}td.n{text-align:right;white-space:nowrap;font-variant-numeric:tabular-nums}
p.who{font-size:12pt}p.who b{display:inline-block;min-width:14em;border-bottom:1px solid #000}
code{font-size:10pt}
@media print{body{margin:0;max-width:none}@page{size:A4;margin:12mm}
 h2{break-after:avoid}table{break-inside:avoid}section{break-after:page}}
"""

CAPTION = {"en": "Your variant's readings: they are the numbers of your measurement file",
           "ru": "Замеры вашего варианта: это числа вашего файла измерений"}


def reading_sheet(doc: dict, spec: LabSpec | None = None) -> str:
    """A printable page of a measurement file's readings (HTML, both languages).

    Parameters
    ----------
    doc : dict
        The measurement file as read (its ``[meta]`` gives the student's name and id).
    spec : LabSpec, optional
        The lab's sections and fields (names, symbols, units); without it the sheet names
        each reading by its key.
    """
    body = [_header(doc, spec)]
    for name, value in doc.items():
        if name in ("lab", "meta"):
            continue
        section = _section(spec, name)
        heading = _bilingual(section.label if section else None, name)
        body.append(f"<h2>{heading} <small><code>[{escape(name)}]</code></small></h2>")
        entries = value if isinstance(value, list) else [value]
        if not all(isinstance(e, dict) for e in entries):
            body.append(f"<p>{escape(_as_written(value))}</p>")
        elif len(entries) > 1 and all(_flat(e) for e in entries):
            body.append(_rows_table(entries, section))
        else:
            for k, entry in enumerate(entries, start=1):
                if len(entries) > 1:
                    body.append(f"<h3>{k}</h3>")
                body.append(_entry(entry, section))
    return ("<!DOCTYPE html><html><head><meta charset='utf-8'><title>"
            f"{escape(_title(doc, spec))}</title><style>{STYLE}</style></head><body>"
            f"<section>{''.join(body)}</section></body></html>")


def all_sheets(pages: list[str]) -> str:
    """Every student's sheet (:func:`reading_sheet`) in one document to print, a page each."""
    head = re.search(r"<head>.*</head>", pages[0], re.S).group(0) if pages else "<head></head>"
    bodies = [re.search(r"<body>(.*)</body>", p, re.S).group(1) for p in pages]
    return f"<!DOCTYPE html><html>{head}<body>{''.join(bodies)}</body></html>"


def _title(doc: dict, spec: LabSpec | None) -> str:
    if spec is None:
        return doc.get("lab", "")
    return f"{spec.number}. {spec.title['en']} / {spec.title['ru']}"


def _header(doc: dict, spec: LabSpec | None) -> str:
    meta = doc.get("meta", {})
    if spec is None:
        title = f"<h1>{escape(doc.get('lab', ''))}</h1>"
    else:
        title = (f"<h1>{escape(spec.number)}. {escape(spec.title['en'])}</h1>"
                 f"<p>{escape(spec.number)}. {escape(spec.title['ru'])}</p>")
    sid = f" ({escape(str(meta['id']))})" if meta.get("id") else ""
    who = f"<p class='who'>Student / Студент: <b>{escape(str(meta.get('student', '')))}</b>{sid}</p>"
    return title + who + f"<p>{escape(CAPTION['en'])}. <i>{escape(CAPTION['ru'])}.</i></p>"


def _section(spec: LabSpec | None, name: str) -> Section | None:
    return next((s for s in spec.sections if s.name == name), None) if spec else None


def _field(section: Section | None, key: str) -> Field | None:
    return next((f for f in section.fields if f.name == key), None) if section else None


def _bilingual(label, fallback: str) -> str:
    if not label:
        return escape(fallback)
    return f"{escape(label['en'])} / <i>{escape(label['ru'])}</i>"


def _flat(entry: dict) -> bool:
    """Whether a table holds single readings only (a row of a table of such tables)."""
    return all(map(_single, entry.values()))


def _single(value) -> bool:
    """Whether a value is one reading: not a series, a nested table or a text table."""
    return not isinstance(value, (dict, list)) and not _is_text_table(value)


def _is_text_table(value) -> bool:
    return isinstance(value, str) and "\n" in value.strip()


def _head_cell(key: str, f: Field | None) -> str:
    """A column's or a row's name: what the reading is, its symbol and its unit."""
    if f is None:
        return f"<th><code>{escape(key)}</code></th>"
    unit = f" [{escape(unit_text(f.unit))}]" if f.unit else ""
    return (f"<th>{escape(f.display_symbol)}{unit}<br><small>{escape(f.label['en'])} / "
            f"{escape(f.label['ru'])} <code>{escape(key)}</code></small></th>")


def _value(value, f: Field | None) -> str:
    """A reading as the file writes it: a plain number in the field's unit (the unit is in
    the heading), a text with its own unit as written, a choice with its words."""
    if isinstance(f, Field) and isinstance(f.choices, dict) and str(value) in f.choices:
        words = f.choices[str(value)]
        said = f"{escape(words['en'])} / {escape(words['ru'])}"
        return said if str(value) == words["en"] else f"{escape(str(value))} ({said})"
    if f is not None and f.kind == "file":
        return f"<code>{escape(str(value))}</code>"
    if isinstance(value, str):
        return escape(_with_unit(value, f.unit if f else None))
    return escape(_as_written(value))


def _with_unit(text: str, unit: str | None) -> str:
    """A reading written with its unit: the number as written, and its unit printed
    (``m/s^2`` → ``m/s²``), or left out where it is the heading's."""
    found = re.fullmatch(r"\s*([-+]?[\d.,]+(?:[eE][-+]?\d+)?(?:\s*±\s*[\d.,]+%?)?)\s*([^\d\s+\-.,±].*)?",
                         text)
    if not found or not found.group(2):
        return text
    number, written = found.groups()
    return number if unit and written.replace(" ", "") == unit else f"{number} {unit_text(written)}"


def _as_written(value) -> str:
    if isinstance(value, list):
        return ", ".join(_as_written(v) for v in value)
    if isinstance(value, bool):
        return "yes / да" if value else "no / нет"
    return str(value)


def _rows_table(entries: list[dict], section: Section | None) -> str:
    """Tables of single readings (a regime, a record each) as one table, a row each."""
    keys = list(dict.fromkeys(k for e in entries for k in e))
    head = "<tr><th>№</th>" + "".join(_head_cell(k, _field(section, k)) for k in keys) + "</tr>"
    rows = "".join(
        f"<tr><td class='n'>{i}</td>" + "".join(
            f"<td class='n'>{_value(e[k], _field(section, k))}</td>" if k in e else "<td></td>"
            for k in keys) + "</tr>"
        for i, e in enumerate(entries, start=1))
    return f"<table>{head}{rows}</table>"


def _entry(entry: dict, section: Section | None) -> str:
    """One table of the file: its single readings a row each; its series of equal length
    (a calibration's loads and deflections) side by side; its text tables as tables; a
    nested table under its name."""
    singles = {k: v for k, v in entry.items() if _single(v)}
    series = {k: v for k, v in entry.items() if isinstance(v, list)
              and not any(isinstance(x, (dict, list)) for x in v)}
    lengths = {len(v) for v in series.values()}
    side_by_side = len(series) > 1 and len(lengths) == 1
    out = []
    rows = [(k, _value(v, _field(section, k))) for k, v in singles.items()]
    if not side_by_side:
        rows += [(k, _value(v, _field(section, k))) for k, v in series.items()]
    if rows:
        out.append("<table>" + "".join(
            f"<tr>{_head_cell(k, _field(section, k))}<td class='n'>{v}</td></tr>"
            for k, v in rows) + "</table>")
    if side_by_side:
        keys = list(series)
        out.append("<table><tr>" + "".join(_head_cell(k, _field(section, k)) for k in keys)
                   + "</tr>" + "".join(
                       "<tr>" + "".join(f"<td class='n'>{escape(_as_written(series[k][i]))}</td>"
                                        for k in keys) + "</tr>"
                       for i in range(lengths.pop())) + "</table>")
    for key, value in entry.items():
        if _is_text_table(value):
            f = _field(section, key)
            out.append(f"<h3>{_bilingual(f.label if f else None, key)}</h3>"
                       + _text_table(value))
        elif isinstance(value, dict):
            out.append(f"<h3><code>{escape(key)}</code></h3>" + _entry(value, None))
        elif isinstance(value, list) and any(isinstance(x, dict) for x in value):
            out += [f"<h3><code>{escape(key)}</code> {i}</h3>" + _entry(x, None)
                    for i, x in enumerate(value, start=1) if isinstance(x, dict)]
    return "".join(out)


def _text_table(text: str) -> str:
    """A table of readings written as text (a header line, then a row a line, cells apart
    by semicolons, tabs or spaces: a comma may be a decimal comma) as a table; as written
    where its rows do not all have the header's cells."""
    lines = [line.strip() for line in text.strip().splitlines() if line.strip()]
    apart = next((sep for sep in (";", "\t") if sep in text), None)
    split = [[c.strip() for c in line.split(apart)] for line in lines]
    if len(split) < 2 or any(len(row) != len(split[0]) for row in split):
        return f"<pre>{escape(text.strip())}</pre>"
    head = "<tr>" + "".join(f"<th>{escape(c)}</th>" for c in split[0]) + "</tr>"
    rows = "".join("<tr>" + "".join(f"<td class='n'>{escape(c)}</td>" for c in row) + "</tr>"
                   for row in split[1:])
    return f"<table>{head}{rows}</table>"
