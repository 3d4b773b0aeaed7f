"""Sphinx extension: the documentation's pages that are read off the labs themselves, so that
they cannot drift from the code — a page per lab (its goal, the measurement file's fields,
its results with names, symbols and units, the sample's report figures, the warnings it
may give), the table of variables and symbols, and the warnings with what to do about them,
each in English and Russian, with how its method is validated and where it fails
(``validation.toml``).

They are written into ``generated/`` of the documentation's source when a build starts
(the ``builder-inited`` event), by reducing every bundled sample once; the folder is not kept
in git. Warnings' meanings and remedies live in ``warnings.toml`` beside this file; a warning
class without its entry stops the build, so that a new warning is documented when it lands.
"""
from __future__ import annotations

import inspect
import re
import tomllib
import warnings as pywarnings
from dataclasses import dataclass
from importlib import import_module
from importlib.util import resolve_name
from pathlib import Path

from docutils import nodes
from docutils.transforms import Transform

HERE = Path(__file__).resolve().parent
LANGS = ("en", "ru")

WORDS = {
    "en": {"goal": "Goal", "measure": "What you measure: the measurement file",
           "section": "Section", "required": "required", "optional": "optional",
           "repeated": "one table per item", "field": "field", "symbol": "symbol",
           "what": "what it is", "unit": "unit", "limit": "limit of error",
           "default": "default", "example": "example", "results": "Results",
           "results_intro": "Every result is a named value in the report's JSON, in SI; the "
                            "report prints it in the unit shown. Key results open the "
                            "report's summary.",
           "name": "name", "key": "key", "yes": "yes",
           "figures": "The report's figures, from the sample",
           "sample": "Sample", "warnings": "Warnings this lab may give",
           "warnings_intro": "What each means and what to do:",
           "template": "A blank file to fill in: ``dynlab template {id}``; the sample: "
                       "``sample_data/{folder}/{file}``.",
           "symbols": "Variables and symbols",
           "symbols_intro": "Every quantity a measurement file takes and every result a report "
                            "gives, by lab: the symbol a report prints (the manual's), the name "
                            "in the measurement file or the JSON, and the unit. Generated from "
                            "the labs' declarations and their samples' results.",
           "input": "input", "result": "result", "kind": "kind", "lab": "lab",
           "all_warnings": "Warnings and what to do",
           "all_intro": "A report lists its warnings by code, in words. Each warning says "
                        "what is suspect, what it does to the results and what to do; here "
                        "is each code's meaning and remedy.",
           "code": "code", "meaning": "meaning", "remedy": "what to do",
           "labs": "lab", "validation": "Validation, and where the method fails"},
    "ru": {"goal": "Цель работы", "measure": "Что измеряется: файл измерений",
           "section": "Раздел", "required": "обязательный", "optional": "необязательный",
           "repeated": "по таблице на каждый объект", "field": "поле", "symbol": "обозначение",
           "what": "величина", "unit": "единица", "limit": "предел погрешности",
           "default": "по умолчанию", "example": "пример", "results": "Результаты",
           "results_intro": "Каждый результат — именованное значение в JSON отчёта, в СИ; "
                            "отчёт печатает его в указанной единице. Главные результаты "
                            "открывают сводку отчёта.",
           "name": "имя", "key": "главный", "yes": "да",
           "figures": "Рисунки отчёта по примеру",
           "sample": "Пример", "warnings": "Предупреждения этой работы",
           "warnings_intro": "Что каждое значит и что делать:",
           "template": "Пустой файл для заполнения: ``dynlab template {id} --lang ru``; "
                       "пример: ``sample_data/{folder}/{file}``.",
           "symbols": "Величины и обозначения",
           "symbols_intro": "Все величины файла измерений и все результаты отчёта по работам: "
                            "обозначение, которое печатает отчёт (как в методичке), имя в "
                            "файле измерений или в JSON и единица. Собрано из описаний работ "
                            "и результатов их примеров.",
           "input": "исходная", "result": "результат", "kind": "вид", "lab": "работа",
           "all_warnings": "Предупреждения и что делать",
           "all_intro": "Отчёт называет предупреждения кодом и словами. Каждое говорит, что "
                        "сомнительно, как это сказывается на результатах и что делать; "
                        "здесь — смысл каждого кода и что предпринять.",
           "code": "код", "meaning": "смысл", "remedy": "что делать",
           "labs": "работа", "validation": "Как проверен метод и где он не работает"},
}


@dataclass
class Lab:
    """One lab as the pages show it: its spec, its samples' results, and the warning classes
    its modules name (those it may give)."""

    id: str
    spec: object
    samples: list[tuple[Path, object]]
    warnings: list[type]


def _cell(text) -> str:
    """Text safe inside a Markdown table cell."""
    return str(text).replace("|", "\\|").replace("\n", " ")


def _table(head: list[str], rows: list[list]) -> list[str]:
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    out += ["| " + " | ".join(_cell(c) for c in r) + " |" for r in rows]
    return out + [""]


def _sources(module) -> str:
    """The source of a lab's module, its report module, and the ``processing`` modules they
    import and those import in turn (the readers of records, photographs and films), but the
    catalogue of warnings itself: where the warnings it may give are named."""
    names = [module.__name__]
    try:
        import_module(module.__name__ + "_report")
        names.append(module.__name__ + "_report")
    except ModuleNotFoundError:
        pass
    seen: dict[str, str] = {}
    for depth in range(4):
        fresh = []
        for name in names:
            if name in seen or name == "processing.diagnostics":
                continue
            mod = import_module(name)
            text = seen[name] = inspect.getsource(mod)
            package = name if hasattr(mod, "__path__") else name.rpartition(".")[0]
            fresh += [resolve_name(m, package) for m in re.findall(
                r"^\s*from (\.+[\w.]*|processing[\w.]*) import", text, flags=re.M)]
        names = fresh
    return "\n".join(seen.values())


def _labs() -> list[Lab]:
    from labs.catalogue import CATALOGUE
    from labs.registry import LABS, evaluate
    from labs.samples import sample_dir

    data = sample_dir()
    found = []
    for lab_id in CATALOGUE:
        module = LABS[lab_id]
        samples = []
        for path in sorted(data.glob(f"{lab_id}*/*.toml")):
            if path.parent.name.split("-")[0] != lab_id:
                continue
            with pywarnings.catch_warnings():
                pywarnings.simplefilter("ignore")
                samples.append((path, evaluate(path)))
        sources = _sources(module)
        named = [c for name, c in _warning_classes().items()
                 if re.search(rf"\b{name}\b", sources)]
        found.append(Lab(lab_id, module.SPEC, samples, named))
    return found


def _warning_classes() -> dict[str, type]:
    import processing.diagnostics as d

    return {name: c for name, c in vars(d).items() if inspect.isclass(c)
            and issubclass(c, d.DynlabWarning) and c is not d.DynlabWarning}


def _remedies() -> dict[str, dict]:
    """The warnings' meanings and remedies (``warnings.toml``), one entry for every class."""
    table = tomllib.loads((HERE / "warnings.toml").read_text(encoding="utf-8"))
    missing = sorted(c.code for c in _warning_classes().values() if c.code not in table)
    if missing:
        raise RuntimeError(f"docs/_ext/warnings.toml has no entry for the warning code(s) "
                           f"{', '.join(missing)}: add its meaning_ru and remedy in both "
                           f"languages")
    return table


def _meaning(cls, entry: dict, lang: str) -> str:
    return entry["meaning_ru"] if lang == "ru" else " ".join(inspect.getdoc(cls).split())


def _unit(unit: str | None, lang: str) -> str:
    from processing.units import unit_text

    return unit_text(unit, lang) if unit else "—"


def _field_rows(section, lang: str) -> list[list]:
    rows = []
    for f in section.fields:
        default = "" if f.default is None else str(f.default).lower() \
            if isinstance(f.default, bool) else str(f.default)
        need = WORDS[lang]["required"] if f.required and f.default is None else ""
        choices = " / ".join(f"`{c}`" for c in f.choices) if f.choices else ""
        rows.append([f"`{f.name}`", f.display_symbol, f.label[lang],
                     _unit(f.unit, lang) if f.unit else choices or "—",
                     f.limit or "", need or default, "" if f.example is None else f.example])
    return rows


def _results(lab: Lab) -> dict[str, object]:
    """Every result the lab's samples give, by name, in the order they first come."""
    seen = {}
    for _, res in lab.samples:
        for name, r in res.results.items():
            seen.setdefault(name, r)
    return seen


def _heading(spec, lang: str) -> str:
    """A lab's title with its number in the manual (the coursework has none)."""
    return f"{spec.number}. {spec.title[lang]}" if spec.number else spec.title[lang]


def lab_page(lab: Lab, lang: str, remedies: dict, validation: dict, figures: Path) -> str:
    w = WORDS[lang]
    spec = lab.spec
    lines = [f"# {_heading(spec, lang)}", "", f"**{w['goal']}.** {spec.goal[lang]}", ""]
    if lab.samples:
        path = lab.samples[0][0]
        lines += [w["template"].format(id=lab.id, folder=path.parent.name, file=path.name), ""]
    lines += [f"## {w['measure']}", ""]
    head = [w["field"], w["symbol"], w["what"], w["unit"], w["limit"],
            f"{w['required']} / {w['default']}", w["example"]]
    for sec in spec.sections:
        kind = w["required"] if sec.required else w["optional"]
        extra = f"; {w['repeated']}" if sec.many else ""
        name = f"[[{sec.name}]]" if sec.many else f"[{sec.name}]"
        lines += [f"### `{name}` — {sec.label[lang]} ({kind}{extra})", ""]
        help_text = sec.help.get(lang, "")
        if help_text:
            lines += [" ".join(help_text.split()), ""]
        lines += _table(head, _field_rows(sec, lang))
    results = _results(lab)
    if results:
        lines += [f"## {w['results']}", "", w["results_intro"], ""]
        rows = [[f"`{n}`", r.symbol or n, r.label[lang], _unit(r.display_unit or r.unit, lang),
                 w["yes"] if r.key else ""] for n, r in results.items()]
        lines += _table([w["name"], w["symbol"], w["what"], w["unit"], w["key"]], rows)
    shown = _figures(lab, lang, figures)
    if shown:
        lines += [f"## {w['figures']}", ""]
        for png, caption in shown:
            lines += [f"![{caption}]({png})", "", f"*{caption}*", ""]
    if lab.warnings:
        lines += [f"## {w['warnings']}", "", w["warnings_intro"], ""]
        lines += _table([w["code"], w["meaning"], w["remedy"]],
                        [[f"`{c.code}`", _meaning(c, remedies[c.code], lang),
                          remedies[c.code][f"remedy_{lang}"]] for c in lab.warnings])
    lines += [f"## {w['validation']}", "", validation[lab.id][lang], ""]
    return "\n".join(lines)


def _figures(lab: Lab, lang: str, folder: Path) -> list[tuple[str, str]]:
    """The first sample's report figures drawn to PNG in ``folder``: (file name, caption)."""
    from processing.reporting.render import figure_png

    if not lab.samples:
        return []
    path, res = lab.samples[0]
    shown = []
    for i, fig in enumerate(res.figures):
        name = f"{lab.id}.{i}.{lang}.png"
        (folder / name).write_bytes(figure_png(fig, lang, dpi=90))
        shown.append((f"../figures/{name}", " ".join(fig.caption[lang].split())))
    return shown


def symbols_page(labs: list[Lab], lang: str) -> str:
    w = WORDS[lang]
    lines = [f"# {w['symbols']}", "", w["symbols_intro"], ""]
    for lab in labs:
        lines += [f"## {_heading(lab.spec, lang)}", ""]
        rows = [[f.display_symbol, f"`{sec.name}.{f.name}`", f.label[lang],
                 _unit(f.unit, lang), w["input"]]
                for sec in lab.spec.sections for f in sec.fields if f.kind == "quantity"]
        rows += [[r.symbol or n, f"`{n}`", r.label[lang],
                  _unit(r.display_unit or r.unit, lang), w["result"]]
                 for n, r in _results(lab).items()]
        lines += _table([w["symbol"], w["name"], w["what"], w["unit"], w["kind"]], rows)
    return "\n".join(lines)


def warnings_page(labs: list[Lab], lang: str, remedies: dict) -> str:
    w = WORDS[lang]
    lines = [f"# {w['all_warnings']}", "", w["all_intro"], ""]
    rows = []
    for c in _warning_classes().values():
        which = ", ".join(lab.id for lab in labs if c in lab.warnings)
        rows.append([f"`{c.code}`", _meaning(c, remedies[c.code], lang),
                     remedies[c.code][f"remedy_{lang}"], which])
    return "\n".join(lines + _table([w["code"], w["meaning"], w["remedy"], w["labs"]], rows))


def _summary(path: Path) -> str:
    """The first line of a module's docstring, read without importing it."""
    import ast

    doc = ast.get_docstring(ast.parse(path.read_text(encoding="utf-8"))) or ""
    first = doc.strip().split("\n\n")[0].replace("\n", " ")
    first = re.sub(r":\w+:`~?([^`]+)`", r"`\1`", first)         # reST roles as Markdown code
    return first.replace("``", "`")


def layout_page(repo: Path) -> str:
    """Where the code is: each package of ``labs/`` and ``processing/`` with what it owns, and
    each module with the first line of its docstring (read off the tree, so it cannot drift)."""
    lines = ["# Where the code is", "",
             "`labs/` holds one module per lab (and its report), the coursework and the "
             "registry that finds them; `processing/` the shared primitives, which know no lab: "
             "a small core at its top and one subpackage per topic. `tests/test_layout.py` "
             "keeps it so: no import cycle, and a lab uses only its report, the core of "
             "`labs/` and the primitives.", ""]
    for top in ("labs", "processing"):
        packages = [repo / top] + sorted(p for p in (repo / top).iterdir()
                                         if (p / "__init__.py").exists())
        for package in packages:
            name = str(package.relative_to(repo)).replace("/", ".")
            lines += [f"## `{name}`", "", _summary(package / "__init__.py"), ""]
            rows = [[f"`{m.stem}`", _summary(m)] for m in sorted(package.glob("*.py"))
                    if m.stem not in ("__init__", "__main__")]
            lines += _table(["module", "what it does"], rows) if rows else []
    return "\n".join(lines)


def generate(root: Path) -> None:
    """Write every generated page under ``root`` (``generated/`` of the docs' source)."""
    remedies = _remedies()
    validation = tomllib.loads((HERE / "validation.toml").read_text(encoding="utf-8"))
    labs = _labs()
    figures = root / "figures"
    figures.mkdir(parents=True, exist_ok=True)
    for lang in LANGS:
        folder = root / lang
        folder.mkdir(parents=True, exist_ok=True)
        for lab in labs:
            (folder / f"{lab.id}.md").write_text(lab_page(lab, lang, remedies, validation, figures),
                                                 encoding="utf-8")
        (folder / "symbols.md").write_text(symbols_page(labs, lang), encoding="utf-8")
        (folder / "warnings.md").write_text(warnings_page(labs, lang, remedies),
                                            encoding="utf-8")
    (root / "layout.md").write_text(layout_page(HERE.parents[1]), encoding="utf-8")


class PlainBars(Transform):
    """Our docstrings write an absolute value as plain text, ``|x|`` or ``|H(f)|``, which
    reStructuredText reads as a substitution that nothing defines: print it as written.
    Runs just before docutils resolves substitutions (priority 220), so that a substitution
    that is defined still is one."""

    default_priority = 219

    def apply(self) -> None:
        defined = self.document.substitution_defs
        for node in list(self.document.findall(nodes.substitution_reference)):
            if node["refname"] not in defined and \
                    nodes.fully_normalize_name(node["refname"]) not in defined:
                node.replace_self(nodes.Text(f"|{node.astext()}|"))


def setup(app):
    app.connect("builder-inited", lambda app: generate(Path(app.srcdir) / "generated"))
    app.add_transform(PlainBars)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
