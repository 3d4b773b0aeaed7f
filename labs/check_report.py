"""What ``dynlab check`` prints and writes: a submission's verdicts on the terminal, a class's
summary as CSV and as a sortable HTML table (a row per submission, a column per value and per
reported table, verdict colours), the copies (:class:`labs.check.Copy`) with their evidence."""
from __future__ import annotations

import csv
import html
import io
import math
import os
import tempfile
from pathlib import Path

from .check import Check, Copy

COLOURS = {"right": "#c8e6c9", "rounded": "#fff9c4", "over-precise": "#fff9c4",
           "wrong": "#ffcdd2", "missing": "#e0e0e0", "refused": "#ffab91"}

WORDS = {"ru": {"right": "верно", "rounded": "верно, но округлено", "over-precise":
                "верно, но лишние знаки", "wrong": "неверно", "missing": "нет",
                "refused": "не принят"}}


def verdict_word(verdict: str, lang: str) -> str:
    return WORDS.get(lang, {}).get(verdict, verdict)


def _num(x) -> str:
    return "—" if x is None or not math.isfinite(x) else f"{x:.6g}"


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
    """The verdicts of one submission, a line each, with the slip that explains a wrong
    value."""
    lines = [f"{check.file} ({check.lab}, {check.student})" + "".join(
        f"\n  {t}" for t in whose(check, lang))]
    width = max((len(v.name) for v in check.verdicts), default=4)
    for v in check.verdicts:
        got = "—" if v.reported is None else _num(v.reported.value)
        ours = f"{_num(v.value)} ± {_num(2 * v.u)}"
        z = "" if not math.isfinite(v.z) else f"  z = {v.z:+.1f}"
        line = f"  {v.name:{width}}  {verdict_word(v.verdict, lang):14} {got:>12}  vs  {ours}{z}"
        if v.slip is not None:
            line += f"\n  {'':{width}}  → {v.slip.text[lang]}"
        lines.append(line)
    for t in check.tables:
        lines.append(f"  {_table_name(t)} ({t.file}): {verdict_word(t.verdict, lang)} — "
                     f"{table_detail(t, lang)}")
    return "\n".join(lines)


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
    return "; ".join(f"{(p.b if p.a is check else p.a).file}: {p.text(lang)}"
                     for p in pairs if check in (p.a, p.b))


def _columns(checks: list[Check]) -> list[str]:
    names = []
    for c in checks:
        names += [v.name for v in c.verdicts if v.name not in names]
        names += [_table_name(t) for t in c.tables if _table_name(t) not in names]
    return names


def summary_csv(checks: list[Check], refused: dict[str, str], pairs=()) -> str:
    """One row per submission and value: file, student, lab, name, verdict, reported, ours,
    U, z, slip, and per reported table (name ``table:…``): its verdict, the slips of its roots
    and the detail in words (refused submissions: one row with the message); on every row of
    a submission, the student's id (``--keys``), whose variant its readings and values are
    where another's, and the submissions its readings are copies of, with the evidence."""
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(["file", "student", "lab", "name", "verdict", "reported", "value", "U", "z",
                "slip", "detail", "id", "readings_of", "values_of", "copies"])
    for c in checks:
        tail = [c.sid or "", c.readings_of or "", c.values_of or "", copied_from(c, pairs)]
        for v in c.verdicts:
            w.writerow([c.file, c.student, c.lab, v.name, v.verdict,
                        "" if v.reported is None else repr(v.reported.value),
                        repr(v.value), repr(2 * v.u), "" if not math.isfinite(v.z) else
                        f"{v.z:.3g}", "" if v.slip is None else v.slip.name, "", *tail])
        for t in c.tables:
            slips = "+".join(dict.fromkeys(r.slip.name for r in t.roots if r.slip))
            w.writerow([c.file, c.student, c.lab, _table_name(t), t.verdict, "", "", "", "",
                        slips, table_detail(t), *tail])
    for file, message in refused.items():
        w.writerow([file, "", "", "", "refused", "", "", "", "", "", message, "", "", "", ""])
    return buf.getvalue()


def summary_html(checks: list[Check], refused: dict[str, str], pairs, lang: str = "en") -> str:
    """A sortable table: a row per submission, a column per value, coloured by verdict."""
    names = _columns(checks)
    head = "".join(f"<th onclick='sort({k})'>{html.escape(h)}</th>" for k, h in
                   enumerate(["file", "student", "lab", "right"] + names))
    rows = []
    for c in checks:
        by = {v.name: v for v in c.verdicts}
        by.update({_table_name(t): t for t in c.tables})
        right = sum(v.verdict in ("right", "rounded", "over-precise") for v in c.verdicts)
        notes = whose(c, lang) + [(("copy of " if lang == "en" else "копия ") + Path(
            (p.b if p.a is c else p.a).file).parent.name) for p in pairs if c in (p.a, p.b)]
        cells = [html.escape(c.file), html.escape(c.student) + "".join(
            f"<br><small>{html.escape(n)}</small>" for n in notes), c.lab,
                 f"{right}/{len(c.verdicts)}"]
        tds = "".join(f"<td>{x}</td>" for x in cells)
        for n in names:
            v = by.get(n)
            if v is None:
                tds += "<td></td>"
                continue
            tip = html.escape(table_detail(v, lang) if n.startswith("table:") else
                              v.slip.text[lang] if v.slip else "")
            tds += (f"<td style='background:{COLOURS[v.verdict]}' title='{tip}'>"
                    f"{verdict_word(v.verdict, lang)}</td>")
        rows.append(f"<tr>{tds}</tr>")
    for file, message in refused.items():
        rows.append(f"<tr><td>{html.escape(file)}</td><td colspan='{3 + len(names)}' "
                    f"style='background:{COLOURS['refused']}'>{html.escape(message)}</td></tr>")
    pair_list = "".join(f"<li>{html.escape(p.a.file)} — {html.escape(p.b.file)}: "
                        f"{html.escape(p.text(lang))}</li>" for p in pairs)
    pairs_html = (f"<h2>{'Copies' if lang == 'en' else 'Списанные замеры'}</h2>"
                  f"<ul>{pair_list}</ul>") if pairs else ""
    return ("<!DOCTYPE html><html><head><meta charset='utf-8'><title>dynlab check</title>"
            "<style>table{border-collapse:collapse}td,th{border:1px solid #999;padding:2px 6px}"
            "th{cursor:pointer;background:#eee}</style><script>"
            "function sort(k){const t=document.getElementById('s'),r=[...t.rows].slice(1);"
            "const d=t.dataset.k==k?-1:1;t.dataset.k=d>0?k:'';r.sort((a,b)=>d*a.cells[k]"
            ".innerText.localeCompare(b.cells[k].innerText,undefined,{numeric:true}));"
            "r.forEach(x=>t.tBodies[0].appendChild(x))}</script></head><body>"
            f"<h1>dynlab check</h1><table id='s'><thead><tr>{head}</tr></thead><tbody>"
            f"{''.join(rows)}</tbody></table>{pairs_html}</body></html>")


def write_summary(out: Path, checks: list[Check], refused: dict[str, str], pairs,
                  lang: str = "en") -> list[Path]:
    """``summary.csv`` and ``summary.html`` in ``out``, each written whole or not at all."""
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for name, text in (("summary.csv", summary_csv(checks, refused, pairs)),
                       ("summary.html", summary_html(checks, refused, pairs, lang))):
        with tempfile.NamedTemporaryFile("w", encoding="utf-8", dir=out, delete=False,
                                         suffix=".part") as f:
            f.write(text)
        os.replace(f.name, out / name)
        written.append(out / name)
    return written
