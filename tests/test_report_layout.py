"""Reports as a person sees them: the answer on the first page, numbers whole, Russian
written the Russian way, figures whose labels and legends stand clear.

Every sample measurement file is reduced once and rendered in both languages; the PDF's text
is extracted page by page (pypdf) and the figures are measured on their canvas
(:mod:`processing.reporting.legibility`).
"""
import functools
import re
import warnings
from pathlib import Path

import pytest
from matplotlib.figure import Figure

from labs.registry import evaluate
from processing.reporting.content import build
from processing.reporting.legibility import legend_overlap, make_legible, overlapping_ticks
from processing.reporting.pdf import column_widths
from processing.reporting.render import to_html

pypdf = pytest.importorskip("pypdf")

ROOT = Path(__file__).resolve().parents[1]
SAMPLES = sorted((ROOT / "sample_data").glob("*/*.toml"))
LANGS = ("en", "ru")

ENGINE_WORDS_EN = ("Summary", "What to check", "Goal", "Formulas", "All results",
                   "Conclusion", "References", "Appendix", "Warnings", "None.", "Quantity",
                   "Value", "Unit")
"""The report engine's own English words: none may appear in a Russian report."""

NUMBER = re.compile(r"[-−+]?\d+(?:[.,]\d+)?")

LATIN_WORD = re.compile(r"(?<![\w.\-/\\\[{'\"])[A-Za-z][a-z]{2,}(?![\w\-/\[(])")
"""A free word of three or more Latin letters, lower case after its first: not part of an
identifier (``J_trifilar``), a path, a call, a key (``[meta]``) or an acronym (``GUM``)."""

UNIT_OF_LABEL = re.compile(r"(?:,\s*|\[)([^,\[\]]+?)\]?\s*$")
"""The unit an axis label ends with: after its last comma (``J, кг·м²``) or in brackets
(``время [с]``)."""


MATH_WORDS = {"sin", "cos", "tg", "ctg", "arctg", "ln", "lg", "exp", "max", "min", "const"}
"""Function names of a formula: a Russian formula writes them so too."""

def typed(res) -> list[str]:
    """What the student typed and a report shows as typed: the [meta] texts, and every input
    that is a text or a file name (a choice is the toolkit's word, and translated)."""
    texts = [str(v) for v in res.meta.values()]
    texts += [str(r["value"]) for r in res.inputs
              if isinstance(r.get("value"), str) and "value_label" not in r and "u" not in r]
    return [t for t in texts if t] + [str(res.source), "dynlab"]


def english_words(text: str, res, lang: str = "ru") -> set[str]:
    """The Latin words of a Russian report's ``text`` that are none of: what the student typed
    (:func:`typed`), a reference's title (the literature is cited as published), a formula's
    function name, an acronym or a symbol."""
    for kept in sorted([*typed(res), *(r[lang] for r in res.references)], key=len,
                       reverse=True):
        for piece in {kept, " ".join(kept.split())}:
            text = text.replace(piece, " ")
    return set(LATIN_WORD.findall(text)) - MATH_WORDS


@functools.cache
def reduced(path: Path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return evaluate(path, n_samples=400)


@functools.cache
def pdf_pages(path: Path, lang: str) -> list[str]:
    """The PDF's text page by page (drawn without its figures, which come after the text that
    is read here and are measured on their own below)."""
    import io

    from processing.reporting.pdf import to_pdf

    blob = to_pdf(reduced(path), lang)
    return [" ".join(p.extract_text().split()) for p in pypdf.PdfReader(io.BytesIO(blob)).pages]


def ids(paths):
    return [f"{p.parent.name}/{p.stem}" for p in paths]


def test_every_lab_declares_its_key_results():
    labs = {reduced(p).lab: any(r.key for r in reduced(p).results.values()) for p in SAMPLES}
    assert all(labs.values()), f"labs without key results: {[k for k, v in labs.items() if not v]}"


@pytest.mark.parametrize("lang", LANGS)
@pytest.mark.parametrize("path", SAMPLES, ids=ids(SAMPLES))
def test_key_results_stand_whole_on_the_first_page(path, lang):
    """The summary's value ± U of every key result is on page 1, each number unbroken."""
    first = pdf_pages(path, lang)[0]
    for row in build(reduced(path), lang)["summary"]:
        for number in NUMBER.findall(row["pm"]):
            assert number in first, f"{row['name']}: {number} not whole on page 1"


@pytest.mark.parametrize("lang", LANGS)
@pytest.mark.parametrize("path", SAMPLES, ids=ids(SAMPLES))
def test_no_number_of_the_results_splits_across_lines(path, lang):
    text = " ".join(pdf_pages(path, lang))
    c = build(reduced(path), lang)
    for r in c["results"]:
        for number in NUMBER.findall(f"{r['value']} {r['U']}"):
            assert number in text, f"{r['name']}: {number} broken in the PDF"
    assert not re.search(r"\bnan\b", text, flags=re.I), "nan printed"


@pytest.mark.parametrize("path", SAMPLES, ids=ids(SAMPLES))
def test_russian_reports_write_decimal_commas_and_no_engine_english(path):
    text = " ".join(pdf_pages(path, "ru"))
    html = to_html(reduced(path), "ru", pngs=[])
    for word in ENGINE_WORDS_EN:
        assert word not in text and f">{word}<" not in html, f"{word!r} in a Russian report"
    c = build(reduced(path), "ru")
    for r in c["results"]:
        assert not re.search(r"\d\.\d", f"{r['value']} {r['U']}"), r


@pytest.mark.parametrize("path", SAMPLES, ids=ids(SAMPLES))
def test_russian_reports_hold_no_english_word(path):
    """Every Latin word of a Russian report's PDF, HTML and figures is a symbol, an acronym,
    a formula's function, a reference's title or what the student typed: a new English word
    anywhere in a Russian report fails here. A figure's axis writes its unit as ГОСТ 8.417 does
    (``м``, ``Гц``), not in Latin letters (``m``, ``Hz``), which the word check, of three
    letters or more, lets through."""
    import html as markup

    res = reduced(path)
    page = to_html(res, "ru", pngs=[])
    page = markup.unescape(re.sub(r"<style.*?</style>|<[^>]+>", " ", page, flags=re.S))
    found = {"pdf": english_words(" ".join(pdf_pages(path, "ru")), res),
             "html": english_words(page, res)}
    for spec in res.figures:
        fig = Figure(figsize=spec.size)
        spec.draw(fig, "ru")
        make_legible(fig, "ru")
        shown = " ".join(t.get_text() for t in fig.findobj(lambda o: hasattr(o, "get_text")))
        found[spec.name] = english_words(shown, res)
        found[spec.name] |= {label for ax in fig.axes
                             for label in (ax.get_xlabel(), ax.get_ylabel())
                             if (unit := UNIT_OF_LABEL.search(label))
                             and re.search(r"[A-Za-z]", unit[1])}
    found = {k: sorted(v) for k, v in found.items() if v}
    assert not found, f"English in the Russian report: {found}"


@pytest.mark.parametrize("path", SAMPLES, ids=ids(SAMPLES))
def test_russian_budgets_name_their_inputs_in_russian(path):
    """Each input a Russian budget of u² names is a symbol (``A_max``, ``δ_osc (s1)``) or a
    Russian word (``индикатор 3``, ``разгрузка (s2)``): no model key left in English, glued
    to a number (``gauge3``) or joined by underscores (``log_decrement_peaks``), which the
    free-word check above does not see."""
    left = set()
    for r in build(reduced(path), "ru")["results"]:
        for item in filter(None, r["budget"].split(", ")):
            name = re.sub(r"\([^)]*\)|\s*\d+\s*%$", "", item).strip()
            if re.search(r"[A-Za-z]{3,}", name.split("_")[0]):
                left.add(name)
    assert not left, f"budget inputs named in English: {sorted(left)}"


@pytest.mark.parametrize("path", SAMPLES, ids=ids(SAMPLES))
def test_figures_keep_their_labels_apart_and_their_legends_off_the_data(path):
    for spec in reduced(path).figures:
        for lang in LANGS:
            fig = Figure(figsize=spec.size)
            spec.draw(fig, lang)
            make_legible(fig, lang)
            assert overlapping_ticks(fig) == [], f"{spec.name} ({lang}): tick labels touch"
            covered = [legend_overlap(ax) for ax in fig.axes]
            assert not any(covered), f"{spec.name} ({lang}): the legend covers data {covered}"


def test_a_crowded_axis_is_thinned_and_a_legend_over_the_data_moved():
    """The checks themselves: a narrow axis of long numbers, a legend put on the curve."""
    import numpy as np
    from matplotlib.ticker import MaxNLocator

    fig = Figure(figsize=(2.0, 2.0))
    ax = fig.add_subplot()
    x = np.linspace(0.16250, 0.17500, 200)
    ax.plot(x, np.ones_like(x), label="a curve across the whole axes")
    ax.xaxis.set_major_locator(MaxNLocator(nbins=12))
    ax.legend(loc="center")
    assert overlapping_ticks(fig) and legend_overlap(ax) > 0
    make_legible(fig, "ru")
    assert overlapping_ticks(fig) == [] and legend_overlap(ax) == 0
    labels = [t.get_text() for t in ax.get_xticklabels() if t.get_text()]
    assert labels and all("." not in s for s in labels), labels


def test_columns_are_as_wide_as_their_longest_number():
    from reportlab.pdfbase.pdfmetrics import stringWidth

    from processing.reporting.pdf import PADDING, _FONT, _register_fonts

    _register_fonts()
    columns = [["Quantity", "a long description of a quantity that may wrap"],
               ["U", "0.000069"], ["Value", "0.01815\u00a0±\u00a00.00084"]]
    widths = column_widths(columns, 200.0, _FONT, 8)
    assert widths[1] >= stringWidth("0.000069", _FONT, 8) + PADDING
    assert widths[2] >= stringWidth("0.01815\u00a0±\u00a00.00084", _FONT, 8) + PADDING
    assert sum(widths) == pytest.approx(200.0)


# ------------------------------------------------------------------ the JSON holds the report

SIGNIFICANT = 3
"""Digits from which a number in a table is a measured or computed value (fewer: a count, an
index, the two digits of a U, which follows from u in the JSON)."""


def _significant(token: str) -> int:
    return len(token.lstrip("-−+").replace(".", "").lstrip("0"))


def _written(token: str, pool) -> bool:
    """Whether ``token`` is one of ``pool`` (numbers as the report's units give them) times a
    power of ten (a table's ·10⁻⁴, a percentage), rounded to the digits it is written with."""
    x = abs(float(token.replace("−", "-")))
    half = 0.5 * 10.0 ** -len(token.partition(".")[2]) * 1.0001
    return any(abs(abs(v) * 10.0 ** e - x) <= half for v in pool for e in range(-9, 10))


def _json_numbers(res, data: dict) -> list[float]:
    """The JSON's results (value, U, 95 % interval) in each result's display unit, and the
    inputs as entered."""
    pool = []
    for name, j in data["results"].items():
        r = res.results[name]
        value = r.shown(j["value"])
        pool.append(value)
        if j["U"] is not None:
            pool.append(r.shown(j["value"] + j["U"]) - value)
        pool += [r.shown(x) for x in j["interval95"] if x is not None]
    for row in res.inputs:
        if isinstance(row.get("value"), (int, float)):
            pool.append(float(row["value"]))
        pool += [float(x) for x in row.get("readings", [])]
    return pool


@pytest.mark.parametrize("path", SAMPLES, ids=ids(SAMPLES))
def test_every_number_of_a_results_table_is_a_named_result_in_the_json(path):
    """A teacher comparing JSON finds every value a results table prints (lab 4's dB levels,
    lab 5's loops, lab 7's phase sums and critical speeds…) among the named results, with
    its unit; worked tables, readings and the manual's data travel in the JSON's "tables"."""
    import json

    from processing.reporting.render import to_json

    res = reduced(path)
    data = json.loads(to_json(res))
    pool = _json_numbers(res, data)
    assert all(j["unit"] is not None for j in data["results"].values())
    missing = []
    for table in res.tables:
        if table.kind != "results":
            continue
        for row in table.rows:
            for key, _ in table.columns[table.keys:]:
                cell = row.get(key, "")
                for token in NUMBER.findall(cell["en"] if isinstance(cell, dict) else str(cell)):
                    if _significant(token) >= SIGNIFICANT and not _written(token, pool):
                        missing.append(f"{table.title['en'][:40]} | {key}: {token}")
    assert not missing, f"{len(missing)} numbers not in the JSON: {missing[:8]}"
    shown = [t.title["en"] for t in (*res.measurements, *res.tables)]
    assert [t["title"] for t in data["tables"]] == shown, "every table also as printed"


def test_the_known_gaps_are_named_results():
    """The issue's list: lab 4's dB levels, lab 5's loops and their largest share, lab 7's
    phase sums and critical speeds."""
    names = {lab: set(reduced(ROOT / "sample_data" / lab / f).results)
             for lab, f in (("lab4", "lab4_seed4.toml"), ("lab5", "valve_train.toml"),
                            ("lab7", "lab7_seed7.toml"))}
    assert {"L_a_1", "L_v_1", "L_x_1"} <= names["lab4"]
    assert {"loop_area_1", "loop_share_1", "loop_share_max", "loop_share_spring"} <= names["lab5"]
    assert any(n.startswith("phase_sum_") for n in names["lab7"])
    assert any(n.startswith("n_crit_") for n in names["lab7"])
    assert reduced(ROOT / "sample_data/lab4/lab4_seed4.toml")["L_a_1"].unit == "dB"


# ------------------------------------------------------------------ measurements as the manual's

def test_lab1_measurements_are_the_manual_table_run_n_t_T():
    res = reduced(ROOT / "sample_data/lab1/flywheel.toml")
    trifilar = next(t for t in res.measurements if t.title["en"].startswith("Trifilar"))
    assert [h["en"] for _, h in trifilar.columns][:4] == ["Run", "n", "t, s", "T = t/n, s"]
    assert len(trifilar.rows) == 3
    for row in trifilar.rows:
        assert float(row["T = t/n, s"]) == pytest.approx(float(row["t, s"]) / float(row["n"]),
                                                         abs=5e-4)


@pytest.mark.parametrize("lang", LANGS)
def test_measurements_come_before_the_results_in_html_and_pdf(lang):
    from processing.reporting.i18n import text

    path = ROOT / "sample_data/lab1/flywheel.toml"
    t = text(lang)
    html = to_html(reduced(path), lang, pngs=[])
    assert html.index(f"<h2>{t['inputs']}</h2>") < html.index(f"<h2>{t['all_results']}</h2>")
    pages = " ".join(pdf_pages(path, lang))
    title = build(reduced(path), lang)["measurements"][0]["title"]
    assert pages.index(title[:30]) < pages.index(t["all_results"])


def test_a_loading_programme_is_its_steps_and_a_reading_without_u_shows_none():
    """Lab 9's loads are a programme, not one quantity measured again (no mean ± u); lab 4's
    meter readings state no u, so none is shown (not 0)."""
    lab9 = build(reduced(ROOT / "sample_data/lab9/table1.toml"), "en")["inputs"]
    moment = next(r for r in lab9 if r["symbol"] == "M")
    assert moment["value"] == "" and moment["u"] == ""
    assert moment["readings"].startswith("90, 180, 270, 315")
    lab4 = build(reduced(ROOT / "sample_data/lab4/lab4_seed4.toml"), "en")["inputs"]
    assert all(r["u"] != "0" for r in lab4)
    assert any(r["section"].startswith("reading") and r["value"] and r["u"] == "" for r in lab4)


@pytest.fixture(scope="module")
def window():
    """A page of a real, headless Chromium at the window size the gallery's first screens are
    taken at (:data:`processing.reporting.screenshot.WINDOW`); skipped where either is
    missing."""
    import os
    import shutil

    from processing.reporting.screenshot import WINDOW

    sync = pytest.importorskip("playwright.sync_api", reason="playwright is not installed")
    chromium = os.environ.get("DYNLAB_CHROMIUM") or shutil.which("chromium")
    if not chromium:
        pytest.skip("no Chromium (apt-get install chromium)")
    with sync.sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=chromium, args=["--no-sandbox"])
        yield browser.new_page(viewport={"width": WINDOW[0], "height": WINDOW[1]}), WINDOW
        browser.close()


@pytest.mark.parametrize("lang", LANGS)
@pytest.mark.parametrize("path", SAMPLES, ids=ids(SAMPLES))
def test_key_results_are_on_the_htmls_first_screen(window, path, lang):
    """Drawn by a browser at a laptop's window size, the HTML shows every key result's
    value ± U whole (no wrapped number or unit) before any scrolling."""
    page, (_, height) = window
    page.set_content(to_html(reduced(path), lang, pngs=[]))
    rows = page.evaluate("""() => {
        const lines = c => { const r = document.createRange(); r.selectNodeContents(c);
            return new Set([...r.getClientRects()].map(x => Math.round(x.top))).size; };
        return [...document.querySelectorAll('section.summary tr')].map(tr => [
            tr.innerText, tr.getBoundingClientRect().bottom,
            [...tr.querySelectorAll('td.num, td.unit')].map(c => lines(c) <= 1)]); }""")
    for row in build(reduced(path), lang)["summary"]:
        shown = [(bottom, whole) for text, bottom, whole in rows if row["pm"] in text]
        assert shown, f"{row['name']}: {row['pm']} not in the summary"
        bottom, whole = shown[0]
        assert bottom <= height, f"{row['name']} below the first screen ({bottom:.0f} px)"
        assert all(whole), f"{row['name']}: its value or unit wraps"
