"""Reports as a student and a teacher get them: the demo set, the JSON contract, the PDF and
HTML actually opened and read back.
"""
import base64
import contextlib
import html
import io
import json
import re
from pathlib import Path

import pytest

from labs.cli.main import main

pypdf = pytest.importorskip("pypdf")

ROOT = Path(__file__).resolve().parents[1]
LAB1 = ROOT / "sample_data" / "lab1" / "flywheel.toml"
LAB2 = ROOT / "sample_data" / "lab2" / "conrod.toml"

A4 = (595.28, 841.89)  # pt
TITLE = {"en": "Moments of inertia", "ru": "Определение моментов инерции"}
GOAL = {"en": "Goal", "ru": "Цель работы"}
WARNINGS = {"en": "What to check", "ru": "На что обратить внимание"}


def dynlab(*argv):
    """``dynlab *argv`` in-process → (exit code, stdout, stderr); usable in module fixtures."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


def squash(text: str) -> str:
    """Whitespace collapsed: PDF text wraps lines wherever the column ends."""
    return " ".join(text.split())


def pdf_text(path: Path) -> tuple[str, list]:
    reader = pypdf.PdfReader(str(path))
    return squash("\n".join(page.extract_text() for page in reader.pages)), reader.pages


def edit_line(text: str, pattern: str, repl: str) -> str:
    new, n = re.subn(pattern, repl, text, count=1, flags=re.M)
    assert n == 1, f"sample file changed: no line matches {pattern!r}"
    return new


def terminal_value(summary: str, label: str) -> tuple[str, str]:
    """Value and U of the result labelled ``label`` as the terminal summary prints them."""
    m = re.search(rf"^\s+{re.escape(label)}\s+(\S+) ± (\S+) ", summary, flags=re.M)
    assert m, f"no summary line for {label!r} in:\n{summary}"
    return m.groups()


# ----------------------------------------------------------------------------- the demo

@pytest.fixture(scope="module")
def demo(tmp_path_factory):
    out = tmp_path_factory.mktemp("demo")
    with pytest.MonkeyPatch.context() as mp:
        mp.chdir(out)  # the sample data must be found without the source folder as cwd
        code, stdout, stderr = dynlab("demo", "--out", out / "reports")
    assert code == 0, f"dynlab demo failed ({code}):\n{stderr}"
    return out / "reports", stdout


@pytest.fixture(scope="module")
def demo_json(demo):
    folder, _ = demo
    return {stem: json.loads((folder / f"{stem}.json").read_text(encoding="utf-8"))
            for stem in ("flywheel", "conrod")}


def test_demo_writes_every_format_for_both_labs(demo):
    folder, stdout = demo
    written = sorted(p.name for p in folder.iterdir())
    stems = [p.stem for p in (ROOT / "sample_data").glob("*/*.toml")]
    assert {"flywheel", "conrod"} <= set(stems)
    expected = sorted(f"{s}.{x}" for s in stems for x in ("html", "pdf", "json"))
    assert written == expected, f"demo wrote {written}"
    for p in folder.iterdir():
        assert p.stat().st_size > 1000, f"{p.name} is suspiciously small ({p.stat().st_size} B)"
    assert (folder / "flywheel.pdf").read_bytes().startswith(b"%PDF-")


def test_demo_prints_a_summary(demo):
    _, stdout = demo
    for text in ("Lab 1. Moments of inertia of engine parts",
                 "Lab 2. Reducing the connecting-rod mass",
                 "trifilar suspension", "mass at the piston-pin axis (weighing)",
                 f"reports (html, pdf, json) for {len(list((ROOT / 'sample_data').glob('*/*.toml')))} files"):
        assert text in stdout, f"{text!r} missing from the demo summary:\n{stdout}"
    assert re.search(r"trifilar suspension\s+0\.17\d\d ± 0\.00\d\d kg·m²", stdout), stdout


@pytest.mark.parametrize("stem", ["flywheel", "conrod"])
def test_json_follows_the_contract(demo_json, stem):
    doc = demo_json[stem]
    assert set(doc) == {"lab", "title", "meta", "inputs", "results", "comparisons", "warnings",
                        "tables", "toolkit"}, f"top-level keys: {sorted(doc)}"
    assert doc["lab"] == {"flywheel": "lab1", "conrod": "lab2"}[stem]
    assert set(doc["title"]) == {"en", "ru"}, doc["title"]
    assert doc["meta"]["student"] == "A. N. Example", doc["meta"]
    assert doc["toolkit"].get("version"), doc["toolkit"]
    assert doc["inputs"], "no inputs in the JSON"
    for name, r in doc["results"].items():
        missing = {"value", "u", "unit", "label"} - set(r)
        assert not missing, f"result {name} lacks {missing}"
        assert isinstance(r["value"], float) and isinstance(r["u"], float) and r["u"] >= 0, \
            f"{name}: value/u are not numbers: {r}"
        assert set(r["label"]) == {"en", "ru"} and all(r["label"].values()), \
            f"{name}: label must have non-empty en and ru: {r['label']}"
    for c in doc["comparisons"]:
        assert {"a", "b", "difference", "agree"} <= set(c), c
        assert c["a"] in doc["results"] and c["b"] in doc["results"], c
    for w in doc["warnings"]:
        assert w.get("code") and w.get("message"), w


# Sample values: SI, the order the manual's rigs give (lab 1: a 12 kg flywheel of 300 mm
# diameter; lab 2: a 1 kg petrol-engine rod, 160 mm between the axes).
EXPECTED = {
    "flywheel": {
        "J_analytic": (0.170, "kg*m^2"), "J_trifilar": (0.171, "kg*m^2"),
        "J_unifilar": (0.171, "kg*m^2"), "J_pendulum_pivot": (0.189, "kg*m^2"),
        "J_pendulum_cm": (0.174, "kg*m^2"),
    },
    "conrod": {
        **{f"l_shp_{m}": (0.119, "m") for m in ("weighing", "swinging", "statistics")},
        **{f"l_shk_{m}": (0.041, "m") for m in ("weighing", "swinging", "statistics")},
        **{f"m_shp_{m}": (0.257, "kg") for m in ("weighing", "swinging", "statistics")},
        **{f"m_shk_{m}": (0.756, "kg") for m in ("weighing", "swinging", "statistics")},
        "J_cm_swinging": (0.0046, "kg*m^2"),
    },
}


@pytest.mark.parametrize("stem", ["flywheel", "conrod"])
def test_stable_result_names_in_si(demo_json, stem):
    results = demo_json[stem]["results"]
    for name, (approx, unit) in EXPECTED[stem].items():
        assert name in results, f"stable result {name} missing; have {sorted(results)}"
        r = results[name]
        assert r["unit"] == unit, f"{name}: unit {r['unit']!r}, expected SI {unit!r}"
        # Methods differ by a few per cent and the statistical shares by up to 5 %: 10 %
        # tells SI from mm or g (factor 1000) and a wrong formula from a right one.
        assert r["value"] == pytest.approx(approx, rel=0.10), \
            f"{name} = {r['value']} {unit}, expected about {approx}"


def test_lab2_weighing_matches_the_sample_readings(demo_json):
    # Weighing method (lab 2, formulas 1-2): m_shp = R_A = 266 g; l_shk = l_sh R_A / m_sh.
    r = demo_json["conrod"]["results"]
    assert r["m_shp_weighing"]["value"] == pytest.approx(0.266, abs=1e-9)
    assert r["l_shp_weighing"]["value"] + r["l_shk_weighing"]["value"] == \
        pytest.approx(0.1601, abs=1e-9), "l_shp + l_shk must equal the measured l_sh"
    assert r["l_shk_weighing"]["value"] == pytest.approx(0.1601 * 0.266 / 1.013, rel=1e-9)


# ------------------------------------------------------------- one file, opened as a reader would

@pytest.fixture(scope="module")
def warned(tmp_path_factory):
    """Lab 1 sample swung at 40°: a report that must carry an amplitude warning, en and ru."""
    folder = tmp_path_factory.mktemp("warned")
    text = edit_line(LAB1.read_text(encoding="utf-8"), r'^amplitude = "7 deg"$',
                     'amplitude = "40 deg"')
    src = folder / "swung.toml"
    src.write_text(text, encoding="utf-8")
    runs = {}
    for lang in ("en", "ru"):
        out = folder / lang
        code, stdout, stderr = dynlab("run", src, "--out", out, "--lang", lang)
        assert code == 0, f"--lang {lang}: exit {code}\n{stderr}"
        doc = json.loads((out / "swung.json").read_text(encoding="utf-8"))
        runs[lang] = {"dir": out, "summary": stdout, "json": doc}
    return runs


@pytest.mark.parametrize("lang", ["en", "ru"])
def test_pdf_reads_back(warned, lang):
    run = warned[lang]
    text, pages = pdf_text(run["dir"] / "swung.pdf")
    for page in pages:
        box = page.mediabox
        assert (float(box.width), float(box.height)) == pytest.approx(A4, abs=1.0), \
            f"page is {float(box.width):.1f} × {float(box.height):.1f} pt, not A4"
    assert TITLE[lang] in text, f"title {TITLE[lang]!r} not in the PDF text:\n{text[:600]}"
    assert GOAL[lang] in text, f"{GOAL[lang]!r} not in the PDF text:\n{text[:600]}"

    # The numbers the terminal printed are the numbers in the PDF.
    labels = run["json"]["results"]
    for name in ("J_trifilar", "J_pendulum_cm"):
        value, U = terminal_value(run["summary"], labels[name]["label"][lang])
        assert value in text and U in text, \
            f"{name}: terminal shows {value} ± {U}, not found in the PDF text"

    codes = [w["code"] for w in run["json"]["warnings"]]
    assert "amplitude_too_large" in codes, f"a 40° swing must warn; warnings: {codes}"
    assert WARNINGS[lang] in text, f"no {WARNINGS[lang]!r} section in the PDF"
    w = next(w for w in run["json"]["warnings"] if w["code"] == "amplitude_too_large")
    message = squash(w["message_ru"] if lang == "ru" else w["message"])
    assert message[:60] in text, f"warning text {message[:60]!r} not in the PDF"


def test_russian_pdf_is_real_cyrillic(warned):
    text, _ = pdf_text(warned["ru"]["dir"] / "swung.pdf")
    cyrillic = len(re.findall("[А-Яа-яЁё]", text))
    assert cyrillic > 500, f"only {cyrillic} Cyrillic letters extracted: the font lost them?"
    assert "\ufffd" not in text and "■" not in text, "replacement characters/boxes in the PDF"
    for phrase in ("Цель работы", "Результаты", "Выводы", "Трёхнитяный подвес"):
        assert phrase.lower() in text.lower(), f"{phrase!r} not in the Russian PDF"


@pytest.mark.parametrize("lang", ["en", "ru"])
def test_html_is_self_contained_and_complete(warned, lang):
    run = warned[lang]
    page = (run["dir"] / "swung.html").read_text(encoding="utf-8")
    external = re.findall(r"""(?:src|href)\s*=\s*["']?\s*(?:https?:)?//[^"'\s>]*""", page, re.I)
    assert not external, f"the HTML loads external resources: {external}"
    assert not re.search(r"<(?:link|script)\b", page, re.I), "the HTML links CSS or JavaScript"
    images = re.findall(r"<img\b[^>]*\bsrc=\"([^\"]*)\"", page)
    assert images, "no figure in the HTML"
    for src in images:
        assert src.startswith("data:image/png;base64,"), f"figure not embedded: {src[:60]}"
        assert base64.b64decode(src.split(",", 1)[1])[:8] == b"\x89PNG\r\n\x1a\n", \
            "the embedded figure is not a PNG"

    assert f'<html lang="{lang}">' in page
    text = html.unescape(re.sub(r"<[^>]+>", " ", page))
    assert TITLE[lang] in text, f"title {TITLE[lang]!r} not in the HTML"
    shown = "J_trifilar" if lang == "en" else "J_tr"     # a Russian report shows the symbol
    assert "<table" in page and shown in text, "no results table in the HTML"
    value, U = terminal_value(run["summary"], run["json"]["results"]["J_trifilar"]["label"][lang])
    assert re.search(rf">\s*{re.escape(value)}\s*<", page), f"J_trifilar value {value} not in a cell"
    assert re.search(rf">\s*{re.escape(U)}\s*<", page), f"J_trifilar U {U} not in a cell"
    assert WARNINGS[lang] in text
    w = next(w for w in run["json"]["warnings"] if w["code"] == "amplitude_too_large")
    message = w["message_ru"] if lang == "ru" else w["message"]
    assert squash(message) in squash(text), f"warning {message[:60]!r}… not in the HTML"


# ----------------------------------------------------------------------------- escaping

HOSTILE = "<script>alert(1)</script> & Co"


def test_text_from_the_file_is_escaped(tmp_path):
    text = LAB2.read_text(encoding="utf-8")
    text = edit_line(text, r"^student = .*$", f'student = "{HOSTILE}"')
    text = edit_line(text, r"^rig = .*$", 'rig = "bench <b>2</b> \\"A&B\\""')
    src = tmp_path / "evil.toml"
    src.write_text(text, encoding="utf-8")
    code, stdout, stderr = dynlab("run", src, "--out", tmp_path / "out", "--format", "html,pdf")
    assert code == 0, stderr

    page = (tmp_path / "out" / "evil.html").read_text(encoding="utf-8")
    assert "&lt;script&gt;alert(1)&lt;/script&gt; &amp; Co" in page, \
        "the student's name is not escaped in the HTML"
    assert "<script" not in page.lower(), "raw <script> from the measurement file reached the HTML"
    assert "<b>2</b>" not in page and "bench &lt;b&gt;2&lt;/b&gt;" in page, \
        "markup in [meta] rig was not escaped"

    # The PDF (reportlab takes markup) shows the name literally instead of choking on it.
    pdf, _ = pdf_text(tmp_path / "out" / "evil.pdf")
    assert HOSTILE in pdf, f"the student's name is not shown literally in the PDF:\n{pdf[:400]}"
