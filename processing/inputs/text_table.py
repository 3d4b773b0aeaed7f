"""Tables typed into a measurement file as a student copies them from the notebook.

A lab sheet's table goes into a multi-line TOML string: a header naming the columns, each
optionally with its unit in brackets, then a line of numbers per row::

    table = \"\"\"
    Q[N]  dl1  dl2  dl3  dl4
    0     0    0    0    0
    10    4    1    1    1
    \"\"\"

Numbers are separated by spaces, tabs or semicolons; a decimal comma reads as a point; ``#``
starts a comment. :func:`read_table` reads the text into a :class:`TextTable`, whose methods
convert a column to SI by the unit its header gives (:meth:`TextTable.si`) and check a
stepwise loading-then-unloading programme (:meth:`TextTable.rise_then_fall`). Every failure
is an :class:`~processing.diagnostics.InputError` naming the file, the field, the row (and
its line in the text) and the fix. :func:`format_table` writes columns in the same form.
"""
from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from processing.diagnostics import InputError
from processing.oscillations.load_cycle import out_of_order
from processing.units import dimension, si_factor

_COLUMN = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)(?:\[([^\]]+)\])?$")
_BRACKETS = re.compile(r"\s*\[\s*([^\]]*?)\s*\]")


@dataclass(frozen=True)
class Column:
    """One column: its name, the unit its header gives (None: the table's default) and its
    numbers as written."""

    name: str
    unit: str | None
    values: np.ndarray


@dataclass(frozen=True)
class TextTable:
    """A typed table, read and located.

    Attributes
    ----------
    columns : dict
        Column name → :class:`Column`, in the header's order.
    lines : tuple of int
        Each row's line in the text (1 = the text's first line).
    file, field : str or None
        Where the table stands, for the errors.
    """

    columns: dict[str, Column]
    lines: tuple[int, ...]
    file: str | None = None
    field: str | None = None

    def __contains__(self, name: str) -> bool:
        return name in self.columns

    def __getitem__(self, name: str) -> Column:
        return self.columns[name]

    def __len__(self) -> int:
        return len(self.lines)

    def error(self, problem: str, fix: str) -> InputError:
        """An :class:`InputError` located at this table."""
        return InputError(problem, fix, file=self.file, field=self.field)

    def row(self, k: int) -> str:
        """How an error names row ``k`` (0-based): ``"row 3 (line 4)"``."""
        return f"row {k + 1} (line {self.lines[k]})"

    def si(self, name: str, default: str, accept: Mapping[str, str], *,
           named: Mapping[str, tuple[float, str]] | None = None) -> tuple[np.ndarray, str]:
        """A column in SI, by the unit in its header (or ``default``).

        Parameters
        ----------
        name : str
            The column.
        default : str
            Its unit when the header gives none.
        accept : mapping
            Reference unit → what it measures (``{"N": "a force", "kg": "a mass"}``): the
            column's unit must have the dimension of one of them.
        named : mapping, optional
            Units of this table besides the physical ones: name → (SI factor, reference
            unit), e.g. ``{"div": (1e-5, "m")}`` for a dial gauge's divisions.

        Returns
        -------
        values : ndarray
            [SI]
        reference : str
            The reference unit of ``accept`` the column's unit matched.

        Raises
        ------
        InputError
            The unit is not known, or measures something else.

        Examples
        --------
        >>> t = read_table("Q[kgf] h\\n1 2\\n3 4", ("Q", "h"))
        >>> t.si("Q", "N", {"N": "a force"})[0].round(5).tolist()
        [9.80665, 29.41995]
        >>> t.si("h", "div", {"m": "a length"}, named={"div": (1e-5, "m")})[0].tolist()
        [2e-05, 4e-05]
        """
        col = self[name]
        unit = col.unit or default
        if named and unit in named:
            factor, reference = named[unit]
            return col.values * factor, reference
        examples = ", ".join(f"{name}[{u}]" for u in (*accept, *(named or ())))
        try:
            dim = dimension(unit)
        except Exception:
            raise self.error(f"column {name}[{unit}]: '{unit}' is not a known unit",
                             f"write the unit in brackets after the column's name, e.g. "
                             f"{examples}") from None
        for reference in accept:
            if dim == dimension(reference):
                return col.values * si_factor(unit), reference
        raise self.error(f"column {name}[{unit}]: '{unit}' is not a unit of "
                         + " or ".join(accept.values()), f"write e.g. {examples}")

    def rise_then_fall(self, name: str, what: str, *, least: int = 3) -> int:
        """Check that column ``name`` rises step by step to its largest value and then falls
        (a loading-then-unloading programme), in at least ``least`` steps each way; return
        the row of the largest value (its first row, if it was read twice: once at the end
        of the loading, again at the start of the unloading).

        Parameters
        ----------
        name : str
            The column (its values as written).
        what : str
            What the column holds, for the message ("load", "lift").
        least : int
            Steps needed on each side of the largest value (a line with its scatter
            through each branch, its turning point left out, needs three).

        Raises
        ------
        InputError
            A row out of order (named); no row after the largest; too few steps.

        Examples
        --------
        >>> t = read_table("P a\\n0 0\\n10 1\\n20 2\\n10 1", ("P", "a"))
        >>> t.rise_then_fall("P", "load", least=1)
        2
        """
        x = self[name].values
        unit = f" {self[name].unit}" if self[name].unit else ""
        programme = (f"write the {what}s in the order they were applied: rising step by step "
                     f"to the largest, then falling back, at least {least} steps each way "
                     "(e.g. 0, 1, 2, 3, 2, 1, 0)")
        peak, k = out_of_order(x)
        if k is not None:
            raise self.error(f"the {what}s are out of order: {self.row(k)} reads {x[k]:g}{unit} "
                             f"after {x[k - 1]:g}{unit}", programme)
        if peak == x.size - 1:
            raise self.error(f"the {what}s never fall back: the table ends at its largest "
                             f"{what}, {x[peak]:g}{unit}", programme + "; the unloading rows "
                             "are needed for the mean of loading and unloading")
        falls = x.size - 1 - peak - int(x.size > peak + 1 and x[peak + 1] == x[peak])
        if min(peak, falls) < least:
            raise self.error(f"the {what}s rise in {peak} step(s) and fall in {falls}: a line "
                             f"through each branch needs at least {least} steps", programme)
        return peak


def read_table(text: str, names: Sequence[str], *, file: str | None = None,
               field: str | None = None) -> TextTable:
    """Read a typed table.

    Parameters
    ----------
    text : str
        The table: a header line naming the columns, then a line of numbers per row.
    names : sequence of str
        The columns this table may have (a header may name some of them, in any order).
    file, field : str, optional
        Where the table stands, for the errors.

    Returns
    -------
    TextTable

    Raises
    ------
    InputError
        No header or no rows; an unknown or repeated column; a row with more or fewer
        numbers than the header has columns; a word where a number should be.

    Examples
    --------
    >>> t = read_table("Q[N]  dl1   # weights, gauge\\n0 0\\n10  4,5", ("Q", "dl1"))
    >>> t["Q"].unit, t["dl1"].values.tolist(), t.lines
    ('N', [0.0, 4.5], (2, 3))
    """
    def error(problem, fix):
        return InputError(problem, fix, file=file, field=field)

    if not isinstance(text, str):
        raise error(f"the table is {type(text).__name__} {text!r}, not a typed table",
                    f"write it as a multi-line string: table = \"\"\" (a header: "
                    f"{'  '.join(names)}), then a line of numbers per row, then \"\"\"")
    rows = []
    for n, line in enumerate(text.splitlines(), start=1):
        body = _BRACKETS.sub(r"[\1]", line.split("#", 1)[0]).strip()
        if body:
            rows.append((n, [t for t in re.split(r"[\s;]+", body) if t]))
    if not rows:
        raise error("the table is empty", f"write a header line naming the columns (from "
                    f"{', '.join(names)}) and a line of numbers per row")
    (n0, header), body = rows[0], rows[1:]
    columns: list[tuple[str, str | None]] = []
    for tok in header:
        m = _COLUMN.match(tok)
        if m is None or m.group(1) not in names:
            raise error(f"line {n0}: '{tok}' is not a column of this table",
                        f"the first line names the columns, from {', '.join(names)}, each "
                        "optionally with its unit in brackets (e.g. Q[kg])")
        if m.group(1) in [c for c, _ in columns]:
            raise error(f"line {n0}: column '{m.group(1)}' is named twice",
                        "name each column once")
        columns.append((m.group(1), m.group(2)))
    values = []
    for k, (n, toks) in enumerate(body):
        where = f"row {k + 1} (line {n})"
        if len(toks) != len(columns):
            raise error(f"{where} has {len(toks)} number(s), but the header names "
                        f"{len(columns)} column(s)", "give a reading in every column of every "
                        "row (a missing reading cannot be skipped: repeat the run)")
        numbers = []
        for tok, (col, _) in zip(toks, columns):
            try:
                number = float(tok.replace(",", "."))
            except ValueError:
                raise error(f"{where}, column {col}: '{tok}' is not a number",
                            "write the readings as plain numbers; a unit goes in the header, "
                            f"e.g. {col}[mm]") from None
            if not math.isfinite(number):
                raise error(f"{where}, column {col}: '{tok}' is not a finite number",
                            "write the number you read")
            numbers.append(number)
        values.append(numbers)
    if not values:
        raise error("the table has a header but no rows",
                    "add a line of numbers per reading under the header")
    arr = np.array(values, dtype=float)
    return TextTable({c: Column(c, unit, arr[:, k]) for k, (c, unit) in enumerate(columns)},
                     tuple(n for n, _ in body), file, field)


def format_table(columns: Mapping[str, Sequence[float]]) -> str:
    """Columns as a typed table (:func:`read_table` reads it back): a header, aligned rows.

    Parameters
    ----------
    columns : mapping
        Header (name with its unit in brackets, if any) → the column's numbers.

    Examples
    --------
    >>> print(format_table({"Q[N]": [0, 10], "dl1": [0, 4.5]}), end="")
    Q[N]  dl1
    0     0
    10    4.5
    """
    cells = [[name] + [f"{x:g}" for x in col] for name, col in columns.items()]
    width = [max(len(c) for c in col) for col in cells]
    lines = ["  ".join(c[k].ljust(w) for c, w in zip(cells, width)).rstrip()
             for k in range(len(cells[0]))]
    return "\n".join(lines) + "\n"
