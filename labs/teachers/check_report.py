"""What ``dynlab check`` prints and writes: a submission's verdicts on the terminal, and a
class's summary (:class:`labs.teachers.check.ClassCheck`) — a row per student of the roster, handed
in or not, with the mark the policy gives (:func:`labs.teachers.check.mark`), each value's verdict,
the student's value and ours in the lab's display units, the slip in words and the copies with their
evidence — as a printable, sortable HTML page in either language, as CSV (a row per student and
value, units in their own column, numbers as written, no float noise) and as Moodle's grade import
CSV.

Moodle's grade import (Grades → Import → CSV file) reads a header row and a row per student:
an identifier column (``ID number``, mapped to the user's ID number), then one column per
grade item holding the points, named ``<lab>`` so that each maps to the item of that lab;
a student who handed nothing in, or whose submission was refused, has an empty cell (no grade
imported), not a zero.
"""
from __future__ import annotations

import csv
import html
import io
import math
import os
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from processing.units import convert, unit_text

from .check import Check, ClassCheck, Copy, mark

COLOURS = {"right": "#c8e6c9", "rounded": "#fff9c4", "over-precise": "#fff9c4",
           "wrong": "#ffcdd2", "missing": "#e0e0e0", "unreadable": "#ffcc80",
           "refused": "#ffab91", "absent": "#eeeeee"}

WORDS = {"ru": {"right": "верно", "rounded": "верно, но округлено", "over-precise":
                "верно, но лишние знаки", "wrong": "неверно", "missing": "нет",
                "unreadable": "не прочитано", "refused": "не принят", "absent": "не сдано",
                "checked": "проверено"},
         "en": {"absent": "not handed in", "checked": "checked"}}

HEAD = {"en": {"title": "Class summary", "id": "id", "student": "student", "lab": "lab",
               "mark": "mark", "status": "status", "notes": "notes", "copies": "Copies",
               "ours": "ours", "legend": "Each cell: the verdict, the student's value / ours "
               "(in the column's unit), and the slip that explains a wrong value. Click a "
               "column's head to sort.", "copy": "the same readings as"},
        "ru": {"title": "Сводка по группе", "id": "шифр", "student": "студент",
               "lab": "работа", "mark": "оценка", "status": "статус", "notes": "замечания",
               "copies": "Списанные замеры", "ours": "наше", "legend": "В ячейке: вердикт, "
               "значение студента / наше (в единицах столбца) и ошибка, объясняющая неверное "
               "значение. Щелчок по заголовку столбца сортирует.",
               "copy": "те же замеры, что у"}}


def verdict_word(verdict: str, lang: str) -> str:
    return WORDS.get(lang, {}).get(verdict, verdict)


def plain(x, figures: int = 6) -> str:
    """A number as a teacher writes it: at most ``figures`` significant figures, no exponent,
    no float noise (``4190000.0000000005`` → ``4190000``, ``0.000758231``); "—" for none."""
    if x is None or not math.isfinite(x):
        return "—"
    return np.format_float_positional(float(f"{x:.{figures}g}"), trim="-")


def shown(check: Check, name: str, x: float | None) -> float | None:
    """``x`` (SI) of result ``name`` in the lab's display unit."""
    unit, _, si = check.shown.get(name, ("", name, ""))
    if x is None or not math.isfinite(x) or not unit or unit == si:
        return x
    try:
        return convert(x, si, unit)
    except Exception:                   # a display unit pint cannot read: SI as it is
        return x


def unit_of(check: Check, name: str, lang: str = "en") -> str:
    """Result ``name``'s display unit as printed."""
    return unit_text(check.shown.get(name, ("", ""))[0], lang)


def table_detail(t, lang: str = "en") -> str:
    """A reported table's verdict in words: cells wrong, the first wrong row and column, the
    likely cause."""
    if t.verdict == "right":
        return (f"all {t.cells} cells right" if lang == "en" else
                f"все {t.cells} ячеек верны")
    at = f"{t.first_at:g}" + ("°" if t.first_column is not None and t.name in
                              ("forces", "crank", "summed") else "")
    if lang == "en":
        return (f"{t.wrong} of {t.cells} cells wrong, first at row {t.first_row} ({at}), column "
                f"{t.first_column}; {t.cause(lang)}")
    return (f"неверно {t.wrong} из {t.cells} ячеек, первая — строка {t.first_row} ({at}), "
            f"столбец {t.first_column}; {t.cause(lang)}")


def _table_name(t) -> str:
    return f"table:{t.name}"


def terminal(check: Check, lang: str = "en") -> str:
    """The verdicts of one submission, a line each, in the lab's display units, with the slip
    that explains a wrong value."""
    lines = [f"{check.file} ({check.lab}, {check.student})" + "".join(
        f"\n  {t}" for t in whose(check, lang))]
    width = max((len(v.name) for v in check.verdicts), default=4)
    for v in check.verdicts:
        unit = unit_of(check, v.name, lang)
        got = "—" if v.reported is None else plain(shown(check, v.name, v.reported.value))
        ours = (f"{plain(shown(check, v.name, v.value))} ± "
                f"{plain(_expanded(check, v), 2)} {unit}").rstrip()
        if check.readings_of and v.u == 0:     # judged against the student's own key
            ours = (f"{plain(shown(check, v.name, v.value))} {unit}".rstrip()
                    + (f" ({check.sid}'s key)" if lang == "en" else f" (ключ {check.sid})"))
        z = "" if not math.isfinite(v.z) else f"  z = {v.z:+.1f}"
        line = f"  {v.name:{width}}  {verdict_word(v.verdict, lang):14} {got:>12}  vs  {ours}{z}"
        if because := why(v, lang):
            line += f"\n  {'':{width}}  → {because}"
        lines.append(line)
    for t in check.tables:
        lines.append(f"  {_table_name(t)} ({t.file}): {verdict_word(t.verdict, lang)} — "
                     f"{table_detail(t, lang)}")
    return "\n".join(lines)


def why(v, lang: str = "en") -> str:
    """What explains a verdict in words: the slip of a wrong value, or why an unreadable
    value could not be read and the fix; "" for none."""
    if v.slip is not None:
        return v.slip.text[lang]
    return "" if v.problem is None else v.problem.reason(lang)


def _expanded(check: Check, v) -> float:
    """Our U = 2u of a verdict's value, in the display unit (a scale: no offset)."""
    if not math.isfinite(v.u):
        return math.nan
    a, b = shown(check, v.name, v.value), shown(check, v.name, v.value + 2 * v.u)
    return abs(b - a) if a is not None and b is not None else math.nan


def whose(check: Check, lang: str = "en") -> list[str]:
    """Whose variant a submission's readings and values are, where not the student's own."""
    out = []
    if check.readings_of:
        out.append(f"the readings of {check.readings_of}'s variant, not {check.sid}'s" if
                   lang == "en" else f"замеры варианта {check.readings_of}, а не {check.sid}")
    if check.values_of:
        out.append(f"the values of {check.values_of}'s variant, not {check.sid}'s" if
                   lang == "en" else f"значения варианта {check.values_of}, а не {check.sid}")
    return out


def copied_from(check: Check, pairs: list[Copy], lang: str = "en") -> str:
    """The submissions a submission's readings are copies of, each with the evidence."""
    return "; ".join(f"{_who(p.b if p.a is check else p.a)}: {p.text(lang)}"
                     for p in pairs if check in (p.a, p.b))


def _who(c: Check) -> str:
    return c.sid or c.file


# ------------------------------------------------------------------------------- the rows

@dataclass(frozen=True)
class Cell:
    """One value of a student's row: the verdict, the student's value and ours in the lab's
    display unit (as text), the unit, and the slip in words."""

    name: str
    verdict: str
    student: str
    ours: str
    unit: str
    slip: str = ""
    slip_name: str = ""
    z: str = ""
    U: str = ""


@dataclass(frozen=True)
class Row:
    """A student of the summary: handed in and checked, refused (``message``) or absent."""

    sid: str
    name: str
    lab: str
    file: str
    status: str
    points: float | None = None
    out_of: float | None = None
    cells: dict[str, Cell] = field(default_factory=dict)
    notes: tuple[str, ...] = ()
    copies: str = ""
    message: str = ""


def _cell(c: Check, v, lang: str) -> Cell:
    got = "" if v.reported is None else plain(shown(c, v.name, v.reported.value),
                                              max(v.reported.digits, 3))
    return Cell(v.name, v.verdict, got, plain(shown(c, v.name, v.value)),
                unit_of(c, v.name, lang), why(v, lang), v.slip.name if v.slip else "",
                "" if not math.isfinite(v.z) else plain(v.z, 2),
                plain(_expanded(c, v), 2) if math.isfinite(v.u) else "")


def _table_cell(t, lang: str) -> Cell:
    slips = "+".join(dict.fromkeys(r.slip.name for r in t.roots if r.slip))
    return Cell(_table_name(t), t.verdict, t.file, "", "", table_detail(t, lang), slips)


def rows(result: ClassCheck, lang: str = "en") -> list[Row]:
    """A row per student: every submission checked (with its mark) or refused, and every
    student of the roster who handed nothing in; in the roster's order, then the others."""
    out = []
    for c in result.checks:
        points, out_of = mark(c, result.policy)
        cells = {v.name: _cell(c, v, lang) for v in c.verdicts}
        cells.update({_table_name(t): _table_cell(t, lang) for t in c.tables})
        notes = tuple(whose(c, lang)) + tuple(
            f"{HEAD[lang]['copy']} {_who(p.b if p.a is c else p.a)}" for p in result.pairs
            if c in (p.a, p.b))
        out.append(Row(c.sid or "", c.student, c.lab, c.file, "checked", points, out_of, cells,
                       notes, copied_from(c, result.pairs, lang)))
    names = dict(result.roster())
    for file, message in result.refused.items():
        sid = result.refused_ids.get(file, "")
        out.append(Row(sid, names.get(sid, sid), "", file, "refused", message=message))
    seen = {r.sid for r in out if r.sid}
    out += [Row(sid, name, "", "", "absent") for sid, name in result.roster() if sid not in seen]
    order = {sid: k for k, (sid, _) in enumerate(result.roster())}
    return sorted(out, key=lambda r: (order.get(r.sid, len(order)), r.file))


def _columns(checks: list[Check]) -> dict[str, list[str]]:
    """The value columns of each lab, in the order they are first met."""
    by_lab: dict[str, list[str]] = {}
    for c in checks:
        names = by_lab.setdefault(c.lab, [])
        names += [v.name for v in c.verdicts if v.name not in names]
        names += [_table_name(t) for t in c.tables if _table_name(t) not in names]
    return by_lab


# ------------------------------------------------------------------------------- CSV

CSV_COLUMNS = ("id", "student", "lab", "file", "status", "mark", "out_of", "name", "verdict",
               "reported", "value", "U", "unit", "z", "slip", "slip_text", "detail",
               "readings_of", "values_of", "copies")
"""The columns of ``summary.csv``: a row per student and value (one row, the values' cells
empty, for a student refused or absent); ``reported``, ``value`` and ``U`` in ``unit``, the
lab's display unit."""


def summary_csv(result: ClassCheck, lang: str = "en") -> str:
    """``summary.csv`` (:data:`CSV_COLUMNS`)."""
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(CSV_COLUMNS)
    whose_of = {c.file: c for c in result.checks}
    for r in rows(result, lang):
        c = whose_of.get(r.file)
        head = [r.sid, r.name, r.lab, r.file, r.status,
                "" if r.points is None else plain(r.points),
                "" if r.out_of is None else plain(r.out_of)]
        tail = [c.readings_of or "" if c else "", c.values_of or "" if c else "", r.copies]
        if not r.cells:
            w.writerow([*head, "", r.status if r.status != "checked" else "", "", "", "", "",
                        "", "", "", r.message, *tail])
        for cell in r.cells.values():
            table = cell.name.startswith("table:")
            w.writerow([*head, cell.name, cell.verdict, "" if table else cell.student,
                        cell.ours, cell.U, cell.unit, cell.z, cell.slip_name,
                        "" if table else cell.slip, cell.slip if table else "", *tail])
    return buf.getvalue()


def moodle_csv(result: ClassCheck) -> str:
    """The marks as Moodle's grade import reads them (module docstring): ``ID number`` and a
    column per lab of the class, the points; empty where a student has no mark."""
    labs = sorted({c.lab for c in result.checks})
    marks: dict[str, dict[str, float]] = {}
    for c in result.checks:
        marks.setdefault(c.sid or c.student, {})[c.lab] = mark(c, result.policy)[0]
    ids = [sid for sid, _ in result.roster()] or list(marks)
    ids += [s for s in marks if s not in ids]
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(["ID number", *labs])
    for sid in ids:
        w.writerow([sid, *(plain(marks[sid][lab]) if lab in marks.get(sid, {}) else ""
                           for lab in labs)])
    return buf.getvalue()


# ------------------------------------------------------------------------------- HTML

STYLE = """
body{font-family:sans-serif;font-size:10pt;margin:1em;-webkit-print-color-adjust:exact;
 print-color-adjust:exact}
h1{font-size:14pt}h2{font-size:12pt}
table{border-collapse:collapse;margin-bottom:1em}
td,th{border:1px solid #999;padding:2px 5px;vertical-align:top}
th{background:#eee;cursor:pointer;white-space:nowrap}
th small{font-weight:normal}
td.v{min-width:6em}td.v small{display:block;color:#333}
td.v b{font-weight:normal;display:block;white-space:nowrap}
td.m{text-align:right;white-space:nowrap}
td.note small{display:block}
@media print{body{margin:0;font-size:8pt}th{cursor:auto}
 @page{size:A4 landscape;margin:8mm}tr{break-inside:avoid}.noprint{display:none}}
"""

SORT = ("function sortBy(th){const t=th.closest('table'),k=th.cellIndex,"
        "b=t.tBodies[0],r=[...b.rows],d=t.dataset.k==k?-1:1;t.dataset.k=d>0?k:'';"
        "const v=x=>x.cells[k]?x.cells[k].dataset.s??x.cells[k].innerText:'';"
        "r.sort((x,y)=>{const a=v(x),c=v(y),p=parseFloat(a),q=parseFloat(c);"
        "return d*(isNaN(p)||isNaN(q)?a.localeCompare(c,undefined,{numeric:true}):p-q)});"
        "r.forEach(x=>b.appendChild(x))}")


def _value_td(cell: Cell | None, lang: str) -> str:
    if cell is None:
        return "<td></td>"
    word = html.escape(verdict_word(cell.verdict, lang))
    if cell.name.startswith("table:"):
        body = f"<small>{html.escape(cell.slip)}</small>"
    else:
        got = html.escape(cell.student or "—")
        body = f"<b>{got} / {html.escape(cell.ours)}</b>" + (
            f"<small>→ {html.escape(cell.slip)}</small>" if cell.slip else "")
    return (f"<td class='v' style='background:{COLOURS[cell.verdict]}' "
            f"data-s='{html.escape(cell.verdict)}'>{word}{body}</td>")


def _head(check: Check | None, name: str, lang: str) -> str:
    if name.startswith("table:"):
        return html.escape(name)
    unit, symbol, _ = check.shown.get(name, ("", name, "")) if check else ("", name, "")
    return (f"{html.escape(symbol)}<br><small>{html.escape(name)}"
            + (f", {html.escape(unit_text(unit, lang))}" if unit else "") + "</small>")


def _lab_table(lab: str, group: list[Row], names: list[str], example: Check | None,
               lang: str) -> str:
    h = HEAD[lang]
    heads = [h["id"], h["student"], h["mark"], h["status"]]
    head = "".join(f"<th onclick='sortBy(this)'>{html.escape(x)}</th>" for x in heads) + "".join(
        f"<th onclick='sortBy(this)'>{_head(example, n, lang)}</th>" for n in names) + \
        f"<th onclick='sortBy(this)'>{html.escape(h['notes'])}</th>"
    body = []
    for r in group:
        share = r.points / r.out_of if r.out_of else math.nan
        mark_td = (f"<td class='m' data-s='{share if math.isfinite(share) else -1}'>"
                   f"{plain(r.points)} / {plain(r.out_of)}"
                   + (f"<br><small>{share:.0%}</small>" if math.isfinite(share) else "")
                   + "</td>") if r.points is not None else "<td class='m' data-s='-1'></td>"
        status = (f"<td style='background:{COLOURS.get(r.status, '#fff')}'>"
                  f"{html.escape(verdict_word(r.status, lang))}</td>")
        lead = (f"<td>{html.escape(r.sid)}</td><td>{html.escape(r.name)}"
                f"<br><small>{html.escape(Path(r.file).name)}</small></td>")
        if r.status == "checked":
            cells = "".join(_value_td(r.cells.get(n), lang) for n in names)
        else:
            cells = (f"<td colspan='{len(names)}'><small>{html.escape(r.message)}</small></td>"
                     if names else "")
        notes = "".join(f"<small>{html.escape(n)}</small>" for n in r.notes)
        body.append(f"<tr>{lead}{mark_td}{status}{cells}<td class='note'>{notes}</td></tr>")
    title = f"<h2>{html.escape(lab)}</h2>" if lab else ""
    return (f"{title}<table><thead><tr>{head}</tr></thead><tbody>{''.join(body)}</tbody>"
            "</table>")


def summary_html(result: ClassCheck, lang: str = "en") -> str:
    """The class summary as a printable, sortable page: a table per lab, a row per student
    (those refused or absent in the table of the class's lab, or their own where the class
    mixes labs), the mark, each value's verdict with the student's value / ours and the slip
    in words; the copies with their evidence below."""
    h = HEAD[lang]
    everyone = rows(result, lang)
    columns = _columns(result.checks)
    example = {c.lab: c for c in result.checks}
    sole = next(iter(columns)) if len(columns) == 1 else ""
    tables = []
    for lab, names in columns.items():
        group = [r for r in everyone if r.lab == lab or (not r.lab and lab == sole)]
        tables.append(_lab_table(lab, group, names, example.get(lab), lang))
    rest = [r for r in everyone if not r.lab and not sole]
    if rest or not columns:
        tables.append(_lab_table("", rest or everyone, [], None, lang))
    pair_list = "".join(f"<li>{html.escape(_who(p.a))} — {html.escape(_who(p.b))}: "
                        f"{html.escape(p.text(lang))}</li>" for p in result.pairs)
    pairs_html = f"<h2>{h['copies']}</h2><ul>{pair_list}</ul>" if result.pairs else ""
    return (f"<!DOCTYPE html><html lang='{lang}'><head><meta charset='utf-8'>"
            f"<title>dynlab check — {html.escape(h['title'])}</title><style>{STYLE}</style>"
            f"<script>{SORT}</script></head><body><h1>{html.escape(h['title'])}</h1>"
            f"<p class='noprint'><small>{html.escape(h['legend'])}</small></p>"
            f"{''.join(tables)}{pairs_html}</body></html>")


def write_summary(out: Path, result: ClassCheck, lang: str = "en") -> list[Path]:
    """``summary.csv``, ``summary.html`` and ``moodle.csv`` in ``out``, each written whole or
    not at all."""
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for name, text in (("summary.csv", summary_csv(result, lang)),
                       ("summary.html", summary_html(result, lang)),
                       ("moodle.csv", moodle_csv(result))):
        with tempfile.NamedTemporaryFile("w", encoding="utf-8", dir=out, delete=False,
                                         suffix=".part") as f:
            f.write(text)
        os.replace(f.name, out / name)
        written.append(out / name)
    return written
