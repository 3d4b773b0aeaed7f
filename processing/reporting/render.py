"""Render a lab result in every format, and write a report set all-or-nothing.

Formats: ``terminal`` (a plain-text summary), ``json`` (the contract of ARCHITECTURE.md),
``html`` (self-contained, figures embedded) and ``pdf`` (A4, printable). Figures are drawn
once per report into PNG with matplotlib's Agg backend (no pyplot, no display needed).
"""
from __future__ import annotations

import base64
import io
import json
import os
import tempfile
from importlib import resources
from pathlib import Path

from .content import build

FORMATS = ("html", "pdf", "json")


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


_UMASK = _umask()


def figure_png(fig_spec, lang: str, dpi: int = 150) -> bytes:
    """Draw one :class:`~processing.result.Figure` to PNG bytes."""
    from matplotlib.figure import Figure

    from .legibility import make_legible

    fig = Figure(figsize=fig_spec.size)
    fig_spec.draw(fig, lang)
    make_legible(fig, lang)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, bbox_inches="tight", pad_inches=0.1)
    return buf.getvalue()


def to_json(res) -> str:
    return json.dumps(res.to_dict(), ensure_ascii=False, indent=2, allow_nan=False,
                      default=_json_default)


def _json_default(x):
    import numpy as np

    if isinstance(x, np.generic):
        return x.item()
    raise TypeError(f"not JSON serialisable: {type(x).__name__}")


def to_html(res, lang: str = "en", pngs=None) -> str:
    import jinja2

    from processing import __version__

    env = jinja2.Environment(autoescape=True, undefined=jinja2.StrictUndefined)
    template = env.from_string(
        resources.files("processing.reporting").joinpath("templates/report.html").read_text("utf-8"))
    c = build(res, lang)
    pngs = pngs if pngs is not None else [figure_png(f, lang) for f in res.figures]
    images = [(caption, base64.b64encode(png).decode("ascii"))
              for (_, caption), png in zip(c["figures"], pngs)]
    return template.render(**c, images=images, version=__version__)


def to_terminal(res, lang: str = "en") -> str:
    c = build(res, lang)
    lines = [f"{c['lab_heading']}. {c['title']}"]
    lines += [f"  {k}: {v}" for k, v in c["meta"]]
    width = max((len(r["label"]) for r in c["results"]), default=10)
    for r in c["results"]:
        value = r["value"] if r["exact"] else f"{r['value']} ± {r['U']}"
        rel = "" if r["exact"] else f"  ({r['rel']})"
        lines.append(f"  {r['label']:<{width}}  {value} {r['unit']}{rel}"
                     f"{'  [' + c['t']['nonlinear'] + ']' if r['nonlinear'] else ''}")
    for cm in c["comparisons"]:
        if cm["ok"]:
            continue
        lines.append(f"  ≠ {cm['a']} {c['t']['method_b']} {cm['b']}: {cm['diff']} {cm['unit']} "
                     f"({cm['rel']})")
    for w, code in zip(c["warnings"], c["warning_codes"]):
        lines.append(f"  ! [{code}] {w}")
    return "\n".join(lines)


def render(res, formats=FORMATS, lang: str = "en") -> dict[str, bytes]:
    """Every requested format as bytes, keyed by file suffix. Nothing is written."""
    unknown = set(formats) - set(FORMATS)
    if unknown:
        raise ValueError(f"unknown report format(s) {', '.join(sorted(unknown))}; "
                         f"use {', '.join(FORMATS)}")
    pngs = [figure_png(f, lang) for f in res.figures] if {"html", "pdf"} & set(formats) else []
    out = {}
    for fmt in formats:
        if fmt == "json":
            out["json"] = to_json(res).encode("utf-8")
        elif fmt == "html":
            out["html"] = to_html(res, lang, pngs).encode("utf-8")
        elif fmt == "pdf":
            from .pdf import to_pdf

            out["pdf"] = to_pdf(res, lang, pngs)
    return out


def write_reports(res, out_dir, stem: str, formats=FORMATS, lang: str = "en") -> list[Path]:
    """Render, then write ``out_dir/stem.<fmt>`` for each format, all or nothing.

    Everything is rendered in memory first; files are written under temporary names and
    renamed into place only when all succeeded, so a failure leaves no partial report.
    """
    blobs = render(res, formats, lang)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    temps = []
    try:
        for fmt, blob in blobs.items():
            fd, tmp = tempfile.mkstemp(dir=out_dir, prefix=f".{stem}.", suffix=f".{fmt}.part")
            temps.append((tmp, out_dir / f"{stem}.{fmt}"))
            with os.fdopen(fd, "wb") as fh:
                fh.write(blob)
            os.chmod(tmp, 0o666 & ~_UMASK)  # mkstemp makes 0600; a report is an ordinary file
        for tmp, final in temps:
            os.replace(tmp, final)
    finally:
        for tmp, _ in temps:
            if os.path.exists(tmp):
                os.unlink(tmp)
    return [final for _, final in temps]
