"""Typed tables (processing.inputs.text_table) and the TOML writer (processing.inputs.toml_writer):
what a student may type, each refusal naming the file, the field, the row and the fix, and the
writer's output read back to the same document."""
import tomllib

import numpy as np
import pytest

from processing.diagnostics import InputError
from processing.inputs.text_table import format_table, read_table
from processing.inputs.toml_writer import dumps

NAMES = ("Q", "P", "dl1", "dl2")
WHERE = {"file": "m.toml", "field": "run[1].table"}


def table(text):
    return read_table(text, NAMES, **WHERE)


def refused(text, *, method=None, args=()):
    with pytest.raises(InputError) as exc:
        t = table(text)
        getattr(t, method)(*args)
    e = exc.value
    assert e.file == "m.toml" and e.field == "run[1].table", e
    assert e.fix and "Fix:" in str(e)
    return e


def test_header_units_comments_and_number_styles():
    t = table("""
        # run 2, as written in the notebook
        Q [ kgf ]  dl1[mm]   dl2
        0          0,00      0      # zero
        5;         0,12;     1.5
        10\t0.25\t3
        """)
    assert list(t.columns) == ["Q", "dl1", "dl2"]
    assert (t["Q"].unit, t["dl1"].unit, t["dl2"].unit) == ("kgf", "mm", None)
    assert t["dl1"].values.tolist() == [0.0, 0.12, 0.25]
    assert t.lines == (4, 5, 6) and len(t) == 3
    assert t.row(1) == "row 2 (line 5)"


def test_units_convert_to_si_by_dimension():
    t = table("Q[kgf]  P[kg]  dl1[mm]  dl2\n1 2 0.5 3\n2 4 1.0 6")
    force = {"N": "a force", "kg": "a mass"}
    assert t.si("Q", "N", force)[0] == pytest.approx([9.80665, 19.6133])
    assert t.si("Q", "N", force)[1] == "N"
    assert t.si("P", "N", force)[1] == "kg"                # the weights' masses
    assert t.si("dl1", "div", {"m": "a length"})[0] == pytest.approx([5e-4, 1e-3])
    div = {"div": (1e-5, "m")}
    assert t.si("dl2", "div", {"m": "a length"}, named=div)[0] == pytest.approx([3e-5, 6e-5])


@pytest.mark.parametrize("text, problem, fix", [
    ("", "the table is empty", "header line"),
    ("Q  dl1", "header but no rows", "line of numbers"),
    ("Q  dl5\n0 0", "'dl5' is not a column", "from Q, P, dl1, dl2"),
    ("Q  dl1  dl1\n0 0 0", "column 'dl1' is named twice", "once"),
    ("Q  dl1\n0 0\n10 4 5", "row 2 (line 3) has 3 number(s), but the header names 2",
     "every column of every row"),
    ("Q  dl1\n0 0\n10 4O", "row 2 (line 3), column dl1: '4O' is not a number",
     "unit goes in the header"),
    ("Q  dl1\n0 inf", "row 1 (line 2), column dl1: 'inf' is not a finite number",
     "the number you read"),
])
def test_unreadable_tables_are_refused_with_the_row(text, problem, fix):
    e = refused(text)
    assert problem in e.problem and fix in e.fix, e


def test_a_table_that_is_not_text_is_refused():
    with pytest.raises(InputError, match="not a typed table.*Fix: write it as a multi-line"):
        read_table([[0, 1], [2, 3]], NAMES, **WHERE)


@pytest.mark.parametrize("unit, problem", [("furlongz", "'furlongz' is not a known unit"),
                                           ("s", "'s' is not a unit of a force or a mass")])
def test_unknown_or_foreign_units_are_refused(unit, problem):
    e = refused(f"Q[{unit}]  dl1\n0 0\n1 1", method="si",
                args=("Q", "N", {"N": "a force", "kg": "a mass"}))
    assert problem in e.problem and "Q[N], Q[kg]" in e.fix, e


@pytest.mark.parametrize("column, problem", [
    ("0 10 20 15 30 20 10 0", "out of order: row 4 (line 5) reads 15 after 20"),
    ("0 10 20 30 30 30 20 10 0", "out of order: row 6 (line 7) reads 30 after 30"),
    ("0 10 20 30 40", "never fall back"),
    ("0 10 20 30 20", "rise in 3 step(s) and fall in 1"),
])
def test_a_programme_out_of_order_is_refused_at_its_row(column, problem):
    text = "Q\n" + "\n".join(column.split())
    e = refused(text, method="rise_then_fall", args=("Q", "load"))
    assert problem in e.problem and "rising step by step" in e.fix, e


@pytest.mark.parametrize("column", ["0 10 20 30 20 10 0", "0 10 20 30 30 20 10 0"])
def test_a_rise_and_fall_returns_its_peak_read_once_or_twice(column):
    assert table("Q\n" + "\n".join(column.split())).rise_then_fall("Q", "load") == 3


def test_formatted_columns_read_back():
    cols = {"Q[N]": [0, 10, 20.5], "dl1": [0.0, -4.25, 1e-3], "dl2[mm]": [1, 2, 3]}
    t = table(format_table(cols))
    assert [t[n].values.tolist() for n in ("Q", "dl1", "dl2")] == list(cols.values())
    assert t["Q"].unit == "N" and t["dl2"].unit == "mm"


def test_toml_writer_reads_back_to_the_same_document():
    doc = {"lab": "lab5", "note": 'a "quoted" \\ back\\slash',
           "meta": {"student": "A. Ivanov", "notes": "line one"},
           "rig": {"i": np.float64(1.5), "n": np.int64(3), "flag": np.bool_(True),
                   "list": [1, 2.5, "x"]},
           "run": [{"table": 'Q  dl1\n0 0\n10 4  # """quotes""" and \\\n'},
                   {"table": "Q  dl1\n0 0\n"}]}
    back = tomllib.loads(dumps(doc))
    assert back["run"][0]["table"] == doc["run"][0]["table"]
    assert back["note"] == doc["note"] and back["rig"]["list"] == [1, 2.5, "x"]
    assert back["rig"] == {"i": 1.5, "n": 3, "flag": True, "list": [1, 2.5, "x"]}
    assert back["meta"] == doc["meta"] and len(back["run"]) == 2
