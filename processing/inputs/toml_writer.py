"""Writing measurement files: just enough TOML for a synthetic scene's lab sheet.

The standard library reads TOML (:mod:`tomllib`) but does not write it. A measurement file
needs keys with numbers, strings, arrays and multi-line strings (a typed table,
:mod:`processing.inputs.text_table`), ``[tables]`` and ``[[arrays of tables]]``: :func:`dumps`
writes those, and :func:`tomllib.loads` reads its output back to the same document.
"""
from __future__ import annotations

import json
from collections.abc import Mapping

import numpy as np


def value_text(v) -> str:
    """One TOML value: a number (exact, nan and inf included), a string (multi-line where it
    holds a line break), a bool, an array of them or an inline table.

    Examples
    --------
    >>> value_text(0.1), value_text([1, 2.5]), value_text('850 ± 0.5 mm'), value_text(True)
    ('0.1', '[1, 2.5]', '"850 ± 0.5 mm"', 'true')
    >>> value_text({"readings": [1, 2], "u": "1 g"}), value_text(float("nan"))
    ('{ readings = [1, 2], u = "1 g" }', 'nan')
    """
    if isinstance(v, str) and "\n" in v:
        return '"""\n' + v.replace("\\", "\\\\").replace('"""', '\\"""') + '"""'
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)  # a JSON string is a TOML basic string
    if isinstance(v, Mapping):
        return "{ " + ", ".join(f"{k} = {value_text(x)}" for k, x in v.items()) + " }"
    if isinstance(v, (list, tuple, np.ndarray)):
        return "[" + ", ".join(value_text(x) for x in v) + "]"
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    return repr(float(v))


def dumps(doc: Mapping) -> str:
    """A document as TOML: plain keys first, then a ``[name]`` per dict and a ``[[name]]`` per
    entry of a list of dicts.

    Examples
    --------
    >>> import tomllib
    >>> doc = {"lab": "lab5", "rig": {"i": 1.5}, "run": [{"table": "P a\\n0 0\\n"}]}
    >>> print(dumps(doc), end="")
    lab = "lab5"
    <BLANKLINE>
    [rig]
    i = 1.5
    <BLANKLINE>
    [[run]]
    table = \"\"\"
    P a
    0 0
    \"\"\"
    >>> tomllib.loads(dumps(doc)) == doc
    True
    """
    def is_tables(v) -> bool:
        return isinstance(v, list) and bool(v) and all(isinstance(x, Mapping) for x in v)

    lines = [f"{k} = {value_text(v)}" for k, v in doc.items()
             if not isinstance(v, Mapping) and not is_tables(v)]
    for name, body in doc.items():
        if isinstance(body, Mapping) or is_tables(body):
            many = is_tables(body)
            for entry in body if many else [body]:
                lines += ["", f"[[{name}]]" if many else f"[{name}]"]
                lines += [f"{k} = {value_text(v)}" for k, v in entry.items()]
    return "\n".join(lines) + "\n"
