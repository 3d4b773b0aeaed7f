"""The coursework's tables as a student hands them in: CSV files exported from a spreadsheet,
read into SI columns at the student's own angles (:func:`read_table`).

The header names each column as the coursework does, with its unit after a comma or in
brackets (``P, kN``, ``p_g [MPa]``, ``α, °``; Russian units too). A force column in a unit of
pressure is the force per piston area; one in a length is its ordinate on the drawing (at
``[drawing] mu_p``). Comma-, semicolon- (decimal comma) or tab-separated files are read.
"""
from __future__ import annotations

import csv
import io
import math
import re
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from processing.diagnostics import InputError
from processing.files import REPORTED_TABLE, read_text
from processing.checking.grading import written_digits
from processing.units import RU_UNITS, dimension, si_factor

KINDS = {"forces": "cylinder", "crank": "cylinder", "summed": "summed",
         "compression": "compression", "expansion": "expansion"}
"""Table names a submission may give, and what each holds (``forces`` and ``crank``: one
cylinder's table, split as the student split it)."""

# quantity: force-like quantities may be written as forces, per piston area or as drawn
FORCE, PRESSURE, TORQUE, ANGLE, RATIO, VOLUME = "N", "Pa", "N*m", "rad", "", "m^3"

COLUMNS = {
    "alpha": (ANGLE, ("α", "alpha", "a", "α1", "alpha1", "alpha_1", "φ", "phi")),
    "beta": (ANGLE, ("β", "beta")),
    "p_g": (PRESSURE, ("p_g", "pg", "p_г", "pг")),
    "dp_g": (PRESSURE, ("Δp_g", "dp_g", "dpg", "Δpg", "Δp_г", "Δpг", "p_g-p_0", "p_г-p_0")),
    "p_j": (PRESSURE, ("p_j", "pj")),
    "p": (PRESSURE, ("p",)),
    "P": (FORCE, ("P",)),
    "tan_beta": (RATIO, ("tgβ", "tanβ", "tan_beta", "tgbeta", "tanbeta")),
    "inv_cos_beta": (RATIO, ("1/cosβ", "inv_cos_beta", "1/cosbeta")),
    "cos_ab": (RATIO, ("cos(α+β)/cosβ", "cos_ab", "cos(alpha+beta)/cosbeta")),
    "sin_ab": (RATIO, ("sin(α+β)/cosβ", "sin_ab", "sin(alpha+beta)/cosbeta")),
    "N": (FORCE, ("N", "p_N", "pN")),
    "S": (FORCE, ("S", "p_S", "pS")),
    "K": (FORCE, ("K", "p_K", "pK")),
    "T": (FORCE, ("T", "p_T", "pT")),
    "M": (TORQUE, ("M", "M_кр", "Mкр")),
    "sum": (FORCE, ("ΣT", "∑T", "sumT", "T_sum", "Tsum", "sum_T")),
    "ratio": (RATIO, ("V_a/V_x", "Va/Vx", "V_x/V_z", "Vx/Vz")),
    "V_x": (VOLUME, ("V_x", "Vx")),
    "p_x": (PRESSURE, ("p_x", "px")),
}
"""Every column a table may hold: its quantity (SI unit) and the names it goes by."""

KIND_COLUMNS = {
    "cylinder": ("alpha", "beta", "p_g", "dp_g", "p_j", "p", "P", "tan_beta", "inv_cos_beta",
                 "cos_ab", "sin_ab", "N", "S", "K", "T", "M"),
    "summed": ("alpha", "sum", "M"),   # and T1 … Ti
    "compression": ("ratio", "V_x", "p_x"),
    "expansion": ("ratio", "V_x", "p_x"),
}

_SUBSCRIPTS = str.maketrans("₀₁₂₃₄₅₆₇₈₉", "0123456789")
_EN_UNITS = {ru: en for en, ru in RU_UNITS.items()}


# ------------------------------------------------------------------------ the student's table

@dataclass(frozen=True)
class Column:
    """One column as the student wrote it, in SI of its base quantity (a force per piston
    area or as drawn is converted to the force, with ours F_p and μ_p)."""

    key: str
    header: str
    values: np.ndarray
    half_digit: np.ndarray
    """Half a unit of each cell's last written digit, same SI. NaN cells: left empty."""


@dataclass(frozen=True)
class StudentTable:
    """A table of the submission: its name, kind, file, the spreadsheet row of each line, the
    abscissa (α [rad], or the polytrope's ratio) and the columns judged."""

    name: str
    kind: str
    file: str
    lines: np.ndarray
    abscissa: np.ndarray
    abscissa_key: str
    """``alpha``, ``ratio`` or ``V_x``."""
    columns: tuple[Column, ...]


def _name_key(name: str, kind: str, cylinders: int) -> str | None:
    norm = name.split("=")[0].translate(_SUBSCRIPTS).replace(" ", "").replace("−", "-")
    if kind == "summed":
        m = re.fullmatch(r"T_?(\d+)", norm)
        if m and 1 <= int(m.group(1)) <= cylinders:
            return f"T{int(m.group(1))}"
    for key in KIND_COLUMNS[kind]:
        if norm in COLUMNS[key][1] or norm.lower() in (a.lower() for a in COLUMNS[key][1]
                                                        if len(a) > 2):
            return key
    return None


def _unit(text: str) -> str:
    text = re.sub(r"\(φ[^)]*\)", "", text).strip()
    text = text.replace("·", "*").replace("°", "deg").replace("−", "-").replace("град", "deg")
    return re.sub(r"[А-Яа-яЁё]+", lambda m: _EN_UNITS.get(m.group(0), m.group(0)), text)


def split_header(header: str) -> tuple[str, str]:
    m = re.fullmatch(r"\s*(.*?)\s*\[([^\]]*)\]\s*", header)
    if m:
        return m.group(1), m.group(2)
    name, comma, unit = header.rpartition(",")
    return (name, unit) if comma else (header, "")


def _cells(text: str) -> list[list[str]]:
    """The CSV's rows (comma-, semicolon- or tab-separated; a decimal comma when not
    comma-separated)."""
    first = text.splitlines()[0] if text.strip() else ""
    bare = re.sub(r'"[^"]*"', "", first)        # separators inside quoted headers do not count
    delimiter = "\t" if "\t" in bare else ";" if ";" in bare else ","
    rows = [r for r in csv.reader(io.StringIO(text), delimiter=delimiter)]
    if delimiter != ",":
        rows = [rows[0]] + [[c.replace(",", ".") for c in r] for r in rows[1:]]
    return rows


def read_table(path: Path, name: str, *, cylinders: int, piston_area: float,
               mu_p: float | None, shown: str) -> StudentTable:
    """Read one submitted table (see the module's docstring).

    Parameters
    ----------
    path : Path
        The CSV file.
    name : str
        Its name in ``[reported.tables]`` (a key of :data:`KINDS`).
    cylinders : int
        i (the summed table's T1 … Ti).
    piston_area : float
        F_p, to read forces per piston area. [m²]
    mu_p : float or None
        The drawing's scale, to read ordinates in mm. [Pa/m]
    shown : str
        The file as the messages name it.

    Raises
    ------
    InputError
        Unreadable file, an unknown column, no abscissa, a unit missing or of the wrong
        dimension, a non-numeric cell (the field names the table, the column and the row).
    """
    kind = KINDS[name]
    where = f"reported.tables.{name}"
    text = read_text(path, REPORTED_TABLE, field=where, legacy="cp1251",
                     fix="export the sheet as CSV")
    try:
        rows = _cells(text)
    except csv.Error as exc:
        raise InputError(f"cannot read the table ({exc})", "export the sheet as CSV (UTF-8)",
                         file=shown, field=where,
                         ru=(f"таблицу не прочитать ({exc})", "сохраните лист как CSV (UTF-8)")
                         ) from None
    if len(rows) < 2:
        raise InputError("the table has no rows", "export the header row and the rows of the "
                         "table", file=shown, field=where,
                         ru=("в таблице нет строк", "сохраните строку заголовка и строки "
                             "таблицы"))
    headers = [h.strip() for h in rows[0]]
    parsed, keys = [], {}
    for col, header in enumerate(headers):
        if not header:
            continue
        name_part, unit_text = split_header(header)
        key = _name_key(name_part, kind, cylinders)
        if key is None:
            known = [COLUMNS[k][1][0] for k in KIND_COLUMNS[kind]]
            if kind == "summed":
                known.insert(1, "T1 … T" + str(cylinders))
            raise InputError(f"unknown column '{header}'", f"name the columns of the {name} "
                             f"table as the coursework does: {', '.join(known)}",
                             file=shown, field=f"{where}, column '{header}'",
                             ru=(f"неизвестный столбец '{header}'", "назовите столбцы таблицы "
                                 f"{name}, как в курсовой работе: {', '.join(known)}"))
        if key in keys:
            raise InputError(f"column '{header}' repeats '{headers[keys[key]]}'",
                             "keep one column per quantity", file=shown,
                             field=f"{where}, column '{header}'",
                             ru=(f"столбец '{header}' повторяет '{headers[keys[key]]}'",
                                 "оставьте по одному столбцу на величину"))
        keys[key] = col
        parsed.append((col, header, key, _scale(key, _unit(unit_text), header, shown, where,
                                                piston_area, mu_p)))
    columns = {}
    for col, header, key, scale in parsed:
        values, halves = [], []
        for r, row in enumerate(rows[1:], start=2):
            text = row[col].strip().replace("−", "-") if col < len(row) else ""
            if not text:
                values.append(math.nan)
                halves.append(math.nan)
                continue
            try:
                number = float(text)
                if not math.isfinite(number):
                    raise ValueError(text)
                values.append(number * scale)
            except ValueError:
                raise InputError(f"'{row[col]}' is not a number", "write a number in each cell "
                                 "(or leave it empty)", file=shown,
                                 field=f"{where}, column '{header}', row {r}",
                                 ru=(f"'{row[col]}' — не число", "впишите число в каждую "
                                     "ячейку (или оставьте её пустой)")) from None
            halves.append(0.5 * 10.0 ** written_digits(text)[1] * abs(scale))
        columns[key] = Column(key, header, np.array(values), np.array(halves))
    lines = np.arange(2, len(rows) + 1)
    abscissa_key = "alpha" if kind in ("cylinder", "summed") else \
        ("ratio" if "ratio" in columns else "V_x")
    if abscissa_key not in columns:
        wanted = "α, °" if abscissa_key == "alpha" else "V_a/V_x (or V_x/V_z) or V_x, L"
        raise InputError(f"the {name} table has no column {wanted}", f"add the column "
                         f"'{wanted}' the rows are computed at", file=shown, field=where,
                         ru=(f"в таблице {name} нет столбца {wanted}", "добавьте столбец "
                             f"'{wanted}', для которого посчитаны строки"))
    x = columns.pop(abscissa_key)
    given = ~np.isnan(x.values)
    ordered = sorted(columns.values(), key=lambda c: _rank(c.key))
    return StudentTable(name, kind, shown, lines[given], x.values[given], abscissa_key, tuple(
        replace(c, values=c.values[given], half_digit=c.half_digit[given]) for c in ordered))


def _rank(key: str) -> tuple[int, int]:
    """Columns in the order they are computed (a column after those it is computed from)."""
    if re.fullmatch(r"T\d+", key):
        return (0, int(key[1:]))
    order = KIND_COLUMNS["cylinder"][:-1] + ("sum", "M", "ratio", "V_x", "p_x")
    return (1, order.index(key))


def _scale(key, unit, header, shown, where, piston_area, mu_p) -> float:
    """The factor from a cell as written to SI of the column's base quantity."""
    quantity = FORCE if re.fullmatch(r"T\d+", key) else COLUMNS[key][0]
    field_ = f"{where}, column '{header}'"
    if quantity == RATIO:
        if unit and dimension(unit) != "dimensionless":
            raise InputError(f"'{header}' is a pure number, not in {unit}", "leave the unit out",
                             file=shown, field=field_,
                             ru=(f"'{header}' — безразмерное число, а не {unit}",
                                 "уберите единицу"))
        return si_factor(unit) if unit else 1.0
    examples = {FORCE: "kN, MPa (per piston area) or mm (as drawn)", PRESSURE: "MPa or mm "
                "(as drawn)", TORQUE: "N*m", ANGLE: "deg", VOLUME: "L or cm^3"}
    examples_ru = {FORCE: "kN, MPa (на площадь поршня) или mm (на чертеже)",
                   PRESSURE: "MPa или mm (на чертеже)", TORQUE: "N*m", ANGLE: "deg",
                   VOLUME: "L или cm^3"}
    if not unit:
        raise InputError(f"column '{header}' has no unit", f"write its unit after a comma: "
                         f"'{header}, {examples[quantity].split()[0]}'", file=shown,
                         field=field_, ru=(f"у столбца '{header}' нет единицы", "напишите "
                                           "единицу после запятой: "
                                           f"'{header}, {examples[quantity].split()[0]}'"))
    try:
        dim, factor = dimension(unit), si_factor(unit)
    except Exception:
        raise InputError(f"'{unit}' in '{header}' is not a unit", f"use {examples[quantity]}",
                         file=shown, field=field_,
                         ru=(f"'{unit}' в '{header}' — не единица",
                             f"используйте {examples_ru[quantity]}")) from None
    drawn = mu_p * (piston_area if quantity == FORCE else 1.0) if mu_p else None
    allowed = {dimension(quantity or ""): 1.0}
    if quantity == FORCE:
        allowed[dimension("Pa")] = piston_area
    if quantity in (FORCE, PRESSURE):
        allowed.setdefault(dimension("m"), drawn)
    if quantity == ANGLE:
        allowed = {"dimensionless": 1.0}
    if dim not in allowed:
        raise InputError(f"'{header}' is in {unit}, not a unit of this column",
                         f"use {examples[quantity]}", file=shown, field=field_,
                         ru=(f"'{header}' в {unit} — это не единица этого столбца",
                             f"используйте {examples_ru[quantity]}"))
    if allowed[dim] is None:
        raise InputError(f"'{header}' is in {unit}: ordinates as drawn need the drawing's "
                         f"scale", "add [drawing] mu_p (MPa/mm) to the file", file=shown,
                         field=field_, ru=(f"'{header}' в {unit}: ординатам в масштабе чертежа "
                                           "нужен масштаб чертежа", "добавьте в файл [drawing] "
                                           "mu_p (МПа/мм)"))
    return factor * allowed[dim]
