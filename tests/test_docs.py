"""The documentation site's sources keep up with the code (the site itself is built with
warnings as errors by .ci/run): every warning has its meaning and remedy in both languages,
and every lab its page in both languages' contents."""
import inspect
import re
import tomllib
from pathlib import Path

import processing.diagnostics as diagnostics
from labs.catalogue import CATALOGUE

DOCS = Path(__file__).resolve().parent.parent / "docs"


def test_every_warning_has_its_meaning_and_remedy_in_both_languages():
    table = tomllib.loads((DOCS / "_ext" / "warnings.toml").read_text(encoding="utf-8"))
    codes = {c.code for c in vars(diagnostics).values() if inspect.isclass(c)
             and issubclass(c, diagnostics.DynlabWarning) and c is not diagnostics.DynlabWarning}
    assert codes - set(table) == set(), "add these warnings to docs/_ext/warnings.toml"
    assert set(table) - codes == set(), "these entries of warnings.toml name no warning"
    for code, entry in table.items():
        assert set(entry) == {"meaning_ru", "remedy_en", "remedy_ru"}, code
        assert re.search("[а-я]", entry["meaning_ru"] + entry["remedy_ru"]), code
        assert not re.search("[а-я]", entry["remedy_en"]), code


def test_every_lab_has_its_page_in_both_languages_contents():
    for index, prefix in ((DOCS / "index.md", "generated/en/"),
                          (DOCS / "ru" / "index.md", "../generated/ru/")):
        text = index.read_text(encoding="utf-8")
        for page in [*CATALOGUE, "symbols", "warnings"]:
            assert f"\n{prefix}{page}\n" in text, f"{index}: no {prefix}{page}"


def test_every_lab_says_how_it_is_validated_in_both_languages():
    table = tomllib.loads((DOCS / "_ext" / "validation.toml").read_text(encoding="utf-8"))
    assert set(table) == set(CATALOGUE)
    for lab_id, entry in table.items():
        assert set(entry) == {"en", "ru"} and re.search("[а-я]", entry["ru"]), lab_id
        for path in re.findall(r"`(tests/[\w/]+\.py)`", entry["en"] + entry["ru"]):
            assert (DOCS.parent / path).exists(), f"{lab_id}: {path} does not exist"
