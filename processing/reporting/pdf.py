"""A4 PDF of a lab report with reportlab, in a Unicode font so Cyrillic prints.

The font is DejaVu Sans, which matplotlib ships: no system font is needed.
"""
from __future__ import annotations

import io
import re
from functools import cache
from pathlib import Path

from .content import build

_FONT, _BOLD = "DejaVuSans", "DejaVuSans-Bold"


@cache
def _register_fonts() -> None:
    import matplotlib
    from reportlab.lib.fonts import addMapping
    from reportlab.pdfbase import pdfmetrics
    from reportlab.pdfbase.ttfonts import TTFont

    ttf = Path(matplotlib.get_data_path()) / "fonts" / "ttf"
    pdfmetrics.registerFont(TTFont(_FONT, str(ttf / "DejaVuSans.ttf")))
    pdfmetrics.registerFont(TTFont(_BOLD, str(ttf / "DejaVuSans-Bold.ttf")))
    addMapping(_FONT, 0, 0, _FONT)
    addMapping(_FONT, 1, 0, _BOLD)


def _styles():
    from reportlab.lib.styles import ParagraphStyle

    base = ParagraphStyle("base", fontName=_FONT, fontSize=9.5, leading=12.5)
    return {
        "base": base,
        "small": ParagraphStyle("small", parent=base, fontSize=8, leading=10),
        "center": ParagraphStyle("center", parent=base, alignment=1),
        "title": ParagraphStyle("title", parent=base, fontName=_BOLD, fontSize=14, leading=18,
                                alignment=1, spaceBefore=6, spaceAfter=6),
        "h2": ParagraphStyle("h2", parent=base, fontName=_BOLD, fontSize=11, leading=14,
                             spaceBefore=10, spaceAfter=4),
        "h3": ParagraphStyle("h3", parent=base, fontName=_BOLD, fontSize=10, leading=13,
                             spaceBefore=6, spaceAfter=3),
        "warn": ParagraphStyle("warn", parent=base, backColor="#fff4e0", borderPadding=3,
                               spaceAfter=4),
    }


PADDING = 13.0
"""A table cell's left and right padding together (reportlab's default 6 pt each) and a
point to spare. [pt]"""


def column_widths(columns, total: float, font: str, size: float) -> list[float]:
    """Widths of a table's columns that never break a word or a number: each column is at
    least as wide as its longest unbreakable piece (a number, a word, ``"0.00084 ± 0.00012"`` joined
    by no-break spaces), and the room left over is shared in proportion to what each
    column would need to stand on one line.

    ``columns`` holds each column's cells (the header among them) as strings; ``total`` is
    the width of the table. [pt] Where even the pieces do not fit, the columns are as narrow
    as the pieces (the table is wider than ``total``: the caller lowers the font size).
    """
    from reportlab.pdfbase.pdfmetrics import stringWidth

    def width(text):
        return stringWidth(text, font, size) + PADDING

    least = [max((width(w) for c in col for w in re.split(r"[ \t\n]+", str(c))),
                 default=PADDING)
             for col in columns]
    whole = [max(max((width(str(c)) for c in col), default=PADDING), lo)
             for col, lo in zip(columns, least)]
    spare = total - sum(least)
    if spare <= 0:
        return least
    want = [w - lo for w, lo in zip(whole, least)]
    if sum(want) <= spare:
        return [w + (spare - sum(want)) * w / sum(whole) for w in whole]
    return [lo + spare * x / sum(want) for lo, x in zip(least, want)]


def _inputs_table(table, c, t):
    """The inputs as entered, with a u column only where some input carries one."""
    u = c["inputs_uncertain"]
    header = [t["section"], t["symbol"], t["quantity"], t["value"], *(["u"] if u else []),
              t["unit"], t["readings"]]
    rows = [[r["section"], r["symbol"], r["label"], r["value"], *([r["u"]] if u else []),
             r["unit"], r["readings"]] for r in c["inputs"]]
    return table(header, rows)


def _named(r: dict, lang: str) -> str:
    """A result's label and, in English, the name a script keys on (in Russian its symbol:
    the names are English words)."""
    return f"{r['label']} ({r['name'] if lang == 'en' else r['symbol']})"


def _results_table(table, c, t):
    """The results; their uncertainty columns only where some result is uncertain."""
    if not c["uncertain"]:
        return table([t["quantity"], t["value"], t["unit"]],
                     [[_named(r, c["lang"]), r["value"], r["unit"]]
                      for r in c["results"]])
    return table([t["quantity"], t["value"], t["U"], "k", t["unit"], t["rel"], t["interval"],
                  t["budget"]],
                 [[_named(r, c["lang"]), r["value"], r["U"], r["k"], r["unit"], r["rel"],
                   r["interval"], r["budget"]] for r in c["results"]])


def _summary_table(table, c, t):
    """The key results as the student writes them, with the verdicts against the manual."""
    verdicts = any(r["verdict"] for r in c["summary"])
    return table([t["quantity"], t["symbol"], t["value"], t["unit"],
                  *([t["verdict"]] if verdicts else [])],
                 [[r["label"], r["symbol"], r["pm"], r["unit"],
                   *([r["verdict"]] if verdicts else [])] for r in c["summary"]])


def to_pdf(res, lang: str = "en", pngs=()) -> bytes:
    """The report as PDF bytes (A4 portrait)."""
    from reportlab.lib import colors
    from reportlab.lib.pagesizes import A4
    from reportlab.lib.styles import ParagraphStyle
    from reportlab.lib.units import mm
    from reportlab.platypus import (Image, KeepTogether, Paragraph, SimpleDocTemplate, Spacer,
                                    Table, TableStyle)
    from xml.sax.saxutils import escape

    _register_fonts()
    s = _styles()
    c = build(res, lang)
    t = c["t"]
    width = A4[0] - 36 * mm

    def p(text, style="base"):
        return Paragraph(escape(str(text)), s[style])

    def table(header, rows):
        for size in (8, 7, 6):
            widths = column_widths(list(zip(header, *rows)), width, _FONT, size)
            if sum(widths) <= width * 1.001:
                break
        style = ParagraphStyle(f"cell{size}", parent=s["small"], fontSize=size,
                               leading=size * 1.25)
        data = [[Paragraph(escape(str(x)), style) for x in r] for r in [header, *rows]]
        tb = Table(data, colWidths=widths, repeatRows=1)
        tb.setStyle(TableStyle([("GRID", (0, 0), (-1, -1), 0.4, colors.grey),
                                ("BACKGROUND", (0, 0), (-1, 0), colors.HexColor("#eeeeee")),
                                ("VALIGN", (0, 0), (-1, -1), "TOP")]))
        return tb

    story = [p(c["university"], "center"), p(c["department"], "center"),
             p(f"{c['lab_heading']}. {c['title']}", "title")]
    story += [p(f"{k}: {v}", "center") for k, v in c["meta"]]
    story += [p(t["summary"], "h2")]
    if c["summary"]:
        story += [_summary_table(table, c, t)]
    story += [p(t["see_warnings"], "h3")]
    story += [p(w, "warn") for w in c["warnings"]] or [p(t["no_warnings"])]
    story += [p(t["goal"], "h2"), p(c["goal"])]
    if c["measurements"]:
        story += [p(t["inputs"], "h2")]
        for tb in c["measurements"]:
            story += [p(tb["title"], "h3"), table(tb["columns"], tb["rows"])]
    story += [p(t["formulas"], "h2")] + [p("• " + f) for f in c["formulas"]]
    story += [p(t["all_results"], "h2"), _results_table(table, c, t),
              p(t["uncertainty_note" if c["uncertain"] else "exact_note"], "small")]
    for tb in c["tables"]:
        story += [p(tb["title"], "h2"), table(tb["columns"], tb["rows"])]
    if c["comparisons"]:
        story += [p(t["comparisons"], "h2"),
                  table([t["method_a"], t["method_b"], t["diff"], t["unit"], "%", t["agree"]],
                        [[x["a"], x["b"], x["diff"], x["unit"], x["rel"], x["agree"]]
                         for x in c["comparisons"]])]
    for (_, caption), png in zip(c["figures"], pngs):
        img = Image(io.BytesIO(png))
        scale = min(1.0, width / img.drawWidth)
        img.drawWidth, img.drawHeight = img.drawWidth * scale, img.drawHeight * scale
        story.append(KeepTogether([Spacer(1, 6), img, p(caption, "small")]))
    story += [p(t["conclusion"], "h2")] + [p("• " + x) for x in c["conclusion"]]
    story += [p(t["references"], "h2")] + [p(f"{i}. {r}") for i, r in
                                            enumerate(c["references"], 1)]
    story += [p(t["appendix"], "h2"), _inputs_table(table, c, t)]
    buf = io.BytesIO()
    doc = SimpleDocTemplate(buf, pagesize=A4, leftMargin=18 * mm, rightMargin=18 * mm,
                            topMargin=15 * mm, bottomMargin=15 * mm,
                            title=f"{c['lab_heading']}. {c['title']}", author=dict(res.meta).get(
                                "student", "dynlab"))
    doc.build(story)
    return buf.getvalue()
