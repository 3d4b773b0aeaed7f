"""The benchmarks' pages of the documentation: ``python -m processing.bench --docs DIR`` writes,
for each topic it runs, ``DIR/<topic>.md`` (its summary, its targets and its charts, copied
beside it) and an ``index.md`` listing every topic page the folder holds.

The documentation (``docs/bench/``) keeps the pages of the last run in git, so that the
methods page shows the charts without running the benchmarks at build time; running a topic
again replaces its page only.
"""
from __future__ import annotations

import datetime as dt
import os
import platform
import shutil
from pathlib import Path


def _cell(text: str) -> str:
    """Text safe inside a Markdown table's cell (a target's name may hold |x|)."""
    return text.replace("|", "\\|")


def topic_page(folder: Path, topic: str, summary: list[str], targets: list, out: Path, *,
               quick: bool) -> Path:
    """Write the page of one topic's run and copy its charts beside it.

    Parameters
    ----------
    folder : Path
        The documentation's benchmark folder.
    topic : str
        The topic's name (``speed``, ``torsion``, …).
    summary : list of str
        The topic's summary lines, as printed.
    targets : list of Target
        Its targets with their measured values.
    out : Path
        The folder the topic wrote its CSV and charts to.
    quick : bool
        Whether the coarse grids were run.

    Returns
    -------
    Path
        The page written.
    """
    folder.mkdir(parents=True, exist_ok=True)
    for old in folder.glob(f"{topic}__*.png"):
        old.unlink()
    charts = []
    for png in sorted(out.glob("*.png")):
        name = f"{topic}__{png.name}"
        shutil.copyfile(png, folder / name)
        charts.append(name)
    when = dt.datetime.now(dt.UTC).strftime("%Y-%m-%d")
    grids = "quick grids (`--quick`)" if quick else "full grids"
    lines = [f"# Benchmark: {topic}", "",
             f"`python -m processing.bench --topic {topic}{' --quick' if quick else ''} "
             f"--docs docs/bench` — {grids}, run on {when} (one core, "
             f"{platform.machine()}, Python {platform.python_version()}, load average "
             f"{os.getloadavg()[0]:.1f} when it ended: times on a busy machine are longer).",
             ""]
    if targets:
        lines += ["| target | measured | limit | verdict |", "|---|---|---|---|"]
        lines += [f"| {_cell(t.name)} | {t.value:.4g} {t.unit} | {t.sign} {t.limit:.4g} "
                  f"{t.unit} | {'PASS' if t.passed else 'FAIL'} |"
                  for t in targets]
        lines.append("")
    lines += [f"![{topic}: {Path(c).stem.split('__', 1)[1].replace('_', ' ')}]({c})\n"
              for c in charts]
    lines += ["## The summary as printed", "", "```text", *summary, "```", ""]
    page = folder / f"{topic}.md"
    page.write_text("\n".join(lines), encoding="utf-8")
    return page


def index_page(folder: Path, order: list[str]) -> Path:
    """Write ``index.md``: a contents list of the topic pages the folder holds, in
    ``order``."""
    pages = [t for t in order if (folder / f"{t}.md").exists()]
    lines = ["# Benchmarks: error against time", "",
             "Each topic times its estimators against their accuracy on synthetic cases whose "
             "truth is known, and checks its targets. The pages are written by the command "
             "they show; run it again to replace a page.", "",
             "```{toctree}", ":maxdepth: 1", "", *pages, "```", ""]
    page = folder / "index.md"
    page.write_text("\n".join(lines), encoding="utf-8")
    return page
