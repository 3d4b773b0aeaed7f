"""The documentation's gallery: the first screen of every sample report, as a browser shows it.

Run from the source folder after a change to the reports::

    python -m labs.cli.gallery                # docs/gallery/, English and Russian
    python -m labs.cli.gallery --lang ru --browser /usr/bin/chromium

Each sample measurement file (``sample_data/*/*.toml``) is reduced, its HTML report written to
a temporary folder and drawn by a headless Chromium at a laptop's window size; the pictures
and an index page (``README.md``, linked from the project's README) go to ``--out``.
"""
from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

from processing.reporting.i18n import LANGS
from processing.reporting.render import write_reports
from processing.reporting.screenshot import find_browser, screenshot

from labs.registry import evaluate
from labs.samples import sample_dir

LANG_NAMES = {"en": "English", "ru": "Русский"}


WEBP_QUALITY = 85
"""WebP at 85 keeps the text as sharp as the browser drew it in 60 % of the PNG's bytes."""


def picture_name(sample: Path, lang: str) -> str:
    """``lab3-photo/photographed_oscillogram.toml`` → ``lab3-photo.photographed_oscillogram.en.webp``."""
    return f"{sample.parent.name}.{sample.stem}.{lang}.webp"


def compact(png: Path, webp: Path) -> Path:
    """The browser's PNG saved as WebP, for a repository that keeps every picture."""
    import cv2

    if not cv2.imwrite(str(webp), cv2.imread(str(png)), [cv2.IMWRITE_WEBP_QUALITY, WEBP_QUALITY]):
        raise RuntimeError(f"could not write {webp}")
    return webp


def index(samples, langs, titles) -> str:
    """The gallery's page: one row per sample, its pictures side by side, each a link to the
    full-size picture."""
    head = "| sample | " + " | ".join(LANG_NAMES[g] for g in langs) + " |"
    rows = [head, "|" + "---|" * (len(langs) + 1)]
    for sample in samples:
        pictures = " | ".join(f'<a href="{picture_name(sample, g)}"><img src="'
                              f'{picture_name(sample, g)}" width="360"></a>' for g in langs)
        rows.append(f"| `{sample.parent.name}/{sample.name}`<br>{titles[sample]} | {pictures} |")
    return ("# Gallery: the first screen of every sample report\n\n"
            "What a student sees on opening each sample's HTML report (`dynlab demo`), drawn by "
            "headless Chromium in a 1100 × 850 px window. Made by `python -m labs.cli.gallery`; "
            "run it again after changing a report.\n\n" + "\n".join(rows) + "\n")


def make(out: Path, langs=LANGS, browser: str | None = None, data: str | None = None) -> list[Path]:
    """Screenshot every sample's report in ``langs`` into ``out`` and write its index."""
    browser = find_browser(browser)
    samples = sorted(sample_dir(data).glob("*/*.toml"))
    out.mkdir(parents=True, exist_ok=True)
    pictures, titles = [], {}
    with tempfile.TemporaryDirectory(prefix="dynlab-gallery-") as tmp:
        for sample in samples:
            result = evaluate(sample)
            titles[sample] = result.title["en"]
            for lang in langs:
                html, = write_reports(result, Path(tmp) / lang, sample.stem, ("html",), lang)
                png = screenshot(html, html.with_suffix(".png"), browser)
                pictures.append(compact(png, out / picture_name(sample, lang)))
                print(f"  {pictures[-1].name}")
    (out / "README.md").write_text(index(samples, langs, titles), encoding="utf-8")
    return pictures


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m labs.cli.gallery",
                                description=__doc__.split("\n")[0])
    p.add_argument("--out", default="docs/gallery", help="folder for the pictures and index")
    p.add_argument("--lang", nargs="+", choices=LANGS, default=list(LANGS))
    p.add_argument("--browser", help="Chromium or Chrome to draw with (default: found on PATH)")
    p.add_argument("--data", help="the sample_data folder (default: found automatically)")
    args = p.parse_args(argv)
    pictures = make(Path(args.out), args.lang, args.browser, args.data)
    print(f"{len(pictures)} screenshots and their index written to {Path(args.out).resolve()}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
