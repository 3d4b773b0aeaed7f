"""What ``dynlab check`` prints and writes: a submission's verdicts on the terminal, a class's
summary as CSV and as a sortable HTML table (a row per submission, a column per value and per
reported table, verdict colours), the pairs of submissions with the same readings."""
from __future__ import annotations

import csv
import html
import io
import math
import os
import tempfile
from pathlib import Path

from .check import Check

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
    lines = [f"{check.file} ({check.lab}, {check.student})"]
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


def _columns(checks: list[Check]) -> list[str]:
    names = []
    for c in checks:
        names += [v.name for v in c.verdicts if v.name not in names]
        names += [_table_name(t) for t in c.tables if _table_name(t) not in names]
    return names


def summary_csv(checks: list[Check], refused: dict[str, str]) -> str:
    """One row per submission and value: file, student, lab, name, verdict, reported, ours,
    U, z, slip, and per reported table (name ``table:…``): its verdict, the slips of its roots
    and the detail in words (refused submissions: one row with the message)."""
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(["file", "student", "lab", "name", "verdict", "reported", "value", "U", "z",
                "slip", "detail"])
    for c in checks:
        for v in c.verdicts:
            w.writerow([c.file, c.student, c.lab, v.name, v.verdict,
                        "" if v.reported is None else repr(v.reported.value),
                        repr(v.value), repr(2 * v.u), "" if not math.isfinite(v.z) else
                        f"{v.z:.3g}", "" if v.slip is None else v.slip.name, ""])
        for t in c.tables:
            slips = "+".join(dict.fromkeys(r.slip.name for r in t.roots if r.slip))
            w.writerow([c.file, c.student, c.lab, _table_name(t), t.verdict, "", "", "", "",
                        slips, table_detail(t)])
    for file, message in refused.items():
        w.writerow([file, "", "", "", "refused", "", "", "", "", "", message])
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
        cells = [html.escape(c.file), html.escape(c.student), c.lab,
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
    pair_list = "".join(f"<li>{html.escape(a)} — {html.escape(b)}</li>" for a, b in pairs)
    pairs_html = (f"<h2>{'Same readings' if lang == 'en' else 'Одинаковые замеры'}</h2>"
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
    for name, text in (("summary.csv", summary_csv(checks, refused)),
                       ("summary.html", summary_html(checks, refused, pairs, lang))):
        with tempfile.NamedTemporaryFile("w", encoding="utf-8", dir=out, delete=False,
                                         suffix=".part") as f:
            f.write(text)
        os.replace(f.name, out / name)
        written.append(out / name)
    return written
