"""A4 PDF of a lab report with reportlab, in a Unicode font so Cyrillic prints.

The font is DejaVu Sans, which matplotlib ships: no system font is needed.
"""
from __future__ import annotations

import io
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
        "warn": ParagraphStyle("warn", parent=base, backColor="#fff4e0", borderPadding=3,
                               spaceAfter=4),
    }


def _inputs_table(table, c, t, width):
    """The inputs, with a u column only where some input carries one."""
    u = c["inputs_uncertain"]
    header = [t["section"], t["symbol"], t["quantity"], t["value"], *(["u"] if u else []),
              t["unit"], t["readings"]]
    rows = [[r["section"], r["symbol"], r["label"], r["value"], *([r["u"]] if u else []),
             r["unit"], r["readings"]] for r in c["inputs"]]
    widths = (0.11, 0.1, 0.29, 0.12, 0.1, 0.07, 0.21) if u else (0.11, 0.1, 0.34, 0.17, 0.07,
                                                                   0.21)
    return table(header, rows, [x * width for x in widths])


def _results_table(table, c, t, width):
    """The results; their uncertainty columns only where some result is uncertain."""
    if not c["uncertain"]:
        return table([t["quantity"], t["value"], t["unit"]],
                     [[f"{r['label']} ({r['name']})", r["value"], r["unit"]]
                      for r in c["results"]], [x * width for x in (0.6, 0.25, 0.15)])
    return table([t["quantity"], t["value"], t["U"], t["unit"], t["rel"], t["interval"],
                  t["budget"]],
                 [[f"{r['label']} ({r['name']})", r["value"], r["U"], r["unit"], r["rel"],
                   r["interval"], r["budget"]] for r in c["results"]],
                 [x * width for x in (0.25, 0.11, 0.09, 0.08, 0.1, 0.17, 0.2)])


def to_pdf(res, lang: str = "en", pngs=()) -> bytes:
    """The report as PDF bytes (A4 portrait)."""
    from reportlab.lib import colors
    from reportlab.lib.pagesizes import A4
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

    def table(header, rows, widths=None):
        data = [[p(h, "small") for h in header]] + [[p(x, "small") for x in r] for r in rows]
        tb = Table(data, colWidths=widths, repeatRows=1)
        tb.setStyle(TableStyle([("GRID", (0, 0), (-1, -1), 0.4, colors.grey),
                                ("BACKGROUND", (0, 0), (-1, 0), colors.HexColor("#eeeeee")),
                                ("VALIGN", (0, 0), (-1, -1), "TOP")]))
        return tb

    story = [p(c["university"], "center"), p(c["department"], "center"),
             p(f"{c['lab_heading']}. {c['title']}", "title")]
    story += [p(f"{k}: {v}", "center") for k, v in c["meta"]]
    story += [p(t["goal"], "h2"), p(c["goal"]), p(t["inputs"], "h2"),
              _inputs_table(table, c, t, width)]
    story += [p(t["formulas"], "h2")] + [p("• " + f) for f in c["formulas"]]
    story += [p(t["results"], "h2"), _results_table(table, c, t, width),
              p(t["uncertainty_note" if c["uncertain"] else "exact_note"], "small")]
    for tb in c["tables"]:
        story += [p(tb["title"], "h2"), table(tb["columns"], tb["rows"])]
    if c["comparisons"]:
        story += [p(t["comparisons"], "h2"),
                  table([t["method_a"], t["method_b"], t["diff"], t["unit"], "%", t["agree"]],
                        [[x["a"], x["b"], x["diff"], x["unit"], x["rel"], x["agree"]]
                         for x in c["comparisons"]],
                        [x * width for x in (0.27, 0.27, 0.18, 0.08, 0.1, 0.1)])]
    for (_, caption), png in zip(c["figures"], pngs):
        img = Image(io.BytesIO(png))
        scale = min(1.0, width / img.drawWidth)
        img.drawWidth, img.drawHeight = img.drawWidth * scale, img.drawHeight * scale
        story.append(KeepTogether([Spacer(1, 6), img, p(caption, "small")]))
    story.append(p(t["warnings"], "h2"))
    story += [p(w, "warn") for w in c["warnings"]] or [p(t["no_warnings"])]
    story += [p(t["conclusion"], "h2")] + [p("• " + x) for x in c["conclusion"]]
    story += [p(t["references"], "h2")] + [p(f"{i}. {r}") for i, r in
                                            enumerate(c["references"], 1)]
    buf = io.BytesIO()
    doc = SimpleDocTemplate(buf, pagesize=A4, leftMargin=18 * mm, rightMargin=18 * mm,
                            topMargin=15 * mm, bottomMargin=15 * mm,
                            title=f"{c['lab_heading']}. {c['title']}", author=dict(res.meta).get(
                                "student", "dynlab"))
    doc.build(story)
    return buf.getvalue()
