"""The tree as ARCHITECTURE.md draws it: a small core and one subpackage per topic in
``processing/``, which knows no lab; in ``labs/`` each lab is its module and its report, using
only the core of ``labs``, the shared primitives and nothing of the tools around it; no import
cycle anywhere, lazy imports included."""
import ast
from pathlib import Path

import pytest

from labs.catalogue import CATALOGUE

ROOT = Path(__file__).resolve().parents[1]

PROCESSING_CORE = {"measurement", "units", "uncertainty", "result", "diagnostics", "regression",
                   "numerals", "decimal_comma", "files"}
"""The shared core, flat in ``processing/``: measurement files and what judges them, units,
uncertainty, results, diagnostics, regression. Everything else is in a topic subpackage."""

LABS_CORE = {"labs", "labs.catalogue", "labs.registry", "labs.samples", "labs.sample_variant"}
"""What a lab may use of ``labs`` besides its own report."""


def _modules() -> dict[str, tuple[Path, bool]]:
    out = {}
    for top in ("labs", "processing"):
        for path in (ROOT / top).rglob("*.py"):
            parts = list(path.relative_to(ROOT).with_suffix("").parts)
            package = parts[-1] == "__init__"
            out[".".join(parts[:-1] if package else parts)] = (path, package)
    return out


MODULES = _modules()


def _imports(name: str) -> set[str]:
    """The modules of the tree that ``name`` imports, at its top or inside a function."""
    path, package = MODULES[name]
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom):
            base = node.module
            if node.level:
                here = name.split(".") if package else name.split(".")[:-1]
                here = here[:len(here) - node.level + 1]
                base = ".".join(here + ([node.module] if node.module else []))
            found |= {f"{base}.{a.name}" if f"{base}.{a.name}" in MODULES else base
                      for a in node.names}
        elif isinstance(node, ast.Import):
            found |= {a.name for a in node.names}
    return {m for m in found if m in MODULES and m != name}


GRAPH = {name: _imports(name) for name in MODULES}


def test_no_import_cycle():
    state: dict[str, int] = {}

    def visit(name, path):
        state[name] = 1
        for other in sorted(GRAPH[name]):
            if state.get(other) == 1:
                pytest.fail(" → ".join(path[path.index(other):] + [other]))
            if other not in state:
                visit(other, path + [other])
        state[name] = 2

    for name in sorted(GRAPH):
        if name not in state:
            visit(name, [name])


def test_processing_knows_no_lab():
    assert not {(m, d) for m in GRAPH if m.startswith("processing")
                for d in GRAPH[m] if d.startswith("labs")}


def test_processing_is_a_core_and_topics():
    flat = {p.stem for p in (ROOT / "processing").glob("*.py")} - {"__init__"}
    assert flat == PROCESSING_CORE
    for package in (ROOT / "processing").iterdir():
        if package.is_dir() and (package / "__init__.py").exists():
            doc = ast.get_docstring(ast.parse((package / "__init__.py").read_text("utf-8")))
            assert doc, f"processing/{package.name}: a docstring saying what it owns"


def test_the_core_needs_no_topic():
    core = {f"processing.{m}" for m in PROCESSING_CORE}
    assert {(m, d) for m in core for d in GRAPH[m] if d not in core | {"processing"}} == set()


@pytest.mark.parametrize("lab_id", sorted(CATALOGUE))
def test_a_lab_uses_its_report_the_core_and_the_primitives(lab_id):
    module = CATALOGUE[lab_id].module
    allowed = LABS_CORE | {f"{module}_report"}
    used = {d for d in GRAPH[module] if d.startswith("labs")}
    assert used <= allowed, used - allowed
