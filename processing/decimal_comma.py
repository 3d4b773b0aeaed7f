"""Decimal commas outside quotes in a measurement file: where TOML split a reading in two.

TOML takes a comma for the separator between an array's values. A Russian student writes
decimal commas, so ``t = [30,62, 30,81, 30,70]`` is valid TOML holding six whole numbers,
30, 62, 30, 81, 30, 70, and ``t_p = [34,05, 34,27]`` or ``m = 11,800`` do not parse at all.
Inside quotes a decimal comma is read (:func:`processing.units.decimal_point`); here the
file's text is searched for the two cases outside them, to refuse with the line and its fix.

The rule for an array of numbers a field reads (:func:`split_reading`): its text in the file
shows a comma with a digit on each side and no space ("tight") between two whole numbers,
and one of

* the tight commas pair the numbers and the array's other commas have a space after them
  (``[30,62, 30,81]``, ``[0, 18,1, 35,9, 54]``: no three numbers joined by tight commas);
* the array also holds a number with a decimal point (``[30,62, 30.81]``);
* all commas are tight, the array holds repeated readings of one quantity (not a series,
  such as a calibration's loads), and as whole numbers they disagree by more than
  :data:`REPEATS_SPREAD` while paired as decimals they agree within :data:`PAIRS_SPREAD`
  (``[30,62,30,81]``: 30 and 62 cannot both be a reading of one time; 30.62 and 30.81 can).

Whole numbers written as TOML writes them (``[1500, 1800, 2000]``, a space after each comma)
are never refused; without spaces (``[1500,1800,2000]``) only when, as repeated readings of
one quantity, they disagree by half their size or more and make agreeing pairs: a field of
repeated readings takes their mean and scatter, which such whole numbers could not give.
Whole numbers spaced unevenly, some pairs tight and the rest not (``[0, 300,600, 900]``), are
refused as the first case: the message says to put a space after each comma.
"""
from __future__ import annotations

import re
from dataclasses import dataclass
from functools import lru_cache

REPEATS_SPREAD = 1.5
"""Largest over smallest of repeated readings beyond which they are no repeats of one
quantity (a stopwatch's repeats differ by a few per cent)."""

PAIRS_SPREAD = 1.25
"""Largest over smallest of readings paired as decimals within which they are repeats."""

_ARRAY = re.compile(r"\[([-+\d\s,._]*\d[-+\d\s,._]*)\]")
"""An array of plain numbers (no exponents, no strings), over one line or several."""

_TIGHT = re.compile(r"(?<![\w.])(\d+),(\d+)(?![\w.])")
"""Two runs of digits joined by a comma without a space: a decimal comma, outside quotes."""

_AT = re.compile(r"\(at line (\d+), column (\d+)\)")
"""Where a :class:`tomllib.TOMLDecodeError` says it stopped."""


@dataclass(frozen=True)
class Split:
    """A reading TOML split at a decimal comma, found in the file's text.

    Attributes
    ----------
    line : int
        Line of the file (1 = the first) where the comma stands.
    text : str
        That line as written (stripped).
    fixed, quoted : str
        The array or value with decimal points, and with each reading quoted.
    readings : tuple of float
        The readings the decimal commas meant (empty for a file that does not parse).
    """

    line: int
    text: str
    fixed: str
    quoted: str
    readings: tuple[float, ...] = ()

    def problem(self, what: str, lang: str = "en") -> str:
        """What went wrong, showing the line."""
        return f"{'строка' if lang == 'ru' else 'line'} {self.line}, `{self.text}`: {what}"

    def fix(self, lang: str = "en") -> str:
        if lang == "ru":
            return (f"пишите десятичные точки, {self.fixed}, или возьмите каждое число в "
                    f"кавычки, {self.quoted} (целые числа в массиве — с пробелом после каждой "
                    f"запятой)")
        return (f"write decimal points, {self.fixed}, or put each number in quotes, "
                f"{self.quoted} (whole numbers in an array take a space after each comma)")


_OPAQUE = re.compile(r'#[^\n]*'
                     r'|"{3}(?:\\.|[^\\])*?(?:"{3}|\Z)'
                     r"|'{3}.*?(?:'{3}|\Z)"
                     r'|"(?:\\.|[^"\\])*(?:"|\Z)'
                     r"|'[^']*(?:'|\Z)", re.S)
"""A TOML comment or quoted string: basic strings with their escapes, literal strings as they
are, each multi-line form before its one-line form."""


def _blank_comments_and_strings(text: str) -> str:
    r"""``text`` with TOML comments and quoted strings blanked to spaces (positions kept).

    >>> _blank_comments_and_strings('t = [1,2] # a, b\nname = "x, \\"y\\"" \n')
    't = [1,2]       \nname =            \n'
    """
    return _OPAQUE.sub(lambda m: re.sub(r"[^\n]", " ", m.group()) if "\n" in m.group()
                       else " " * len(m.group()), text)


def _number(token: str):
    token = token.replace("_", "")
    try:
        return int(token)
    except ValueError:
        pass
    try:
        return float(token)
    except ValueError:
        return None


def _line_of(text: str, pos: int) -> int:
    return text.count("\n", 0, pos) + 1


def _spread(xs) -> float:
    """Largest over smallest magnitude (inf if one is zero and another not)."""
    sizes = [abs(x) for x in xs]
    if max(sizes) == 0:
        return 1.0
    return max(sizes) / min(sizes) if min(sizes) > 0 else float("inf")


def _groups(tokens: list[str], tight: list[bool]) -> list[list[str]]:
    """The tokens in groups joined by tight commas."""
    groups = [[tokens[0]]]
    for token, joined in zip(tokens[1:], tight):
        if joined:
            groups[-1].append(token)
        else:
            groups.append([token])
    return groups


def _paired(group: list[str]) -> list[str]:
    """A group's tokens read with decimal commas: whole numbers paired left to right."""
    out, i = [], 0
    while i < len(group):
        a = group[i]
        b = group[i + 1] if i + 1 < len(group) else None
        if b is not None and a.lstrip("+-").isdigit() and b.isdigit():
            out.append(f"{a},{b}")
            i += 2
        else:
            out.append(a)
            i += 1
    return out


def _is_split(tight: list[bool], groups: list[list[str]], readings: list[float],
              values: list, series: bool) -> bool:
    """The module's rule: tight commas between whole numbers, and pairs written as such,
    a decimal point beside them, or repeats that only agree as decimals."""
    if not any(tight):
        return False
    if any(isinstance(v, float) for v in values):
        return True
    if len(groups) >= 2 and max(len(g) for g in groups) <= 2:
        return True
    return (not series and len(readings) < len(values)
            and _spread(values) > REPEATS_SPREAD and _spread(readings) <= PAIRS_SPREAD)


def split_reading(source: str, name: str, values: list, *, series: bool = False) -> Split | None:
    """Where TOML split the readings ``values`` of the field ``name`` at decimal commas, as
    the file's text ``source`` shows (the module's rule); None where it did not.

    Parameters
    ----------
    source : str
        The measurement file's text.
    name : str
        The field's key (the array assigned to it is preferred among equal ones).
    values : list
        The field's array as TOML read it.
    series : bool
        The array is a series of distinct values (a calibration table), not repeats of one
        quantity.

    Examples
    --------
    >>> s = split_reading("t = [30,62, 30,81, 30,70]\\n", "t", [30, 62, 30, 81, 30, 70])
    >>> s.line, s.readings, s.fixed
    (1, (30.62, 30.81, 30.7), 't = [30.62, 30.81, 30.70]')
    >>> split_reading("n = [1500,1800,2000]\\n", "n", [1500, 1800, 2000]) is None
    True
    """
    if not any(type(v) is int for v in values) or not all(
            type(v) in (int, float) for v in values):
        return None
    found = []
    for array in _arrays(source).get(_key(values), ()):
        groups = _groups(array.tokens, array.tight)
        written = [t for g in groups for t in _paired(g)]
        readings = [float(t.replace(",", ".")) for t in written]
        if not _is_split(array.tight, groups, readings, values, series):
            continue
        prefix = f"{array.key} = " if array.key else ""
        found.append((array.key.strip('"') != name, Split(
            array.line, source.splitlines()[array.line - 1].strip(),
            f"{prefix}[{', '.join(t.replace(',', '.') for t in written)}]",
            f"{prefix}[{', '.join(f'{chr(34)}{t}{chr(34)}' for t in written)}]",
            tuple(readings))))
    return min(found, key=lambda f: f[0])[1] if found else None


def _key(values) -> tuple:
    """Numbers as TOML typed them: 30 and 30.0 differ."""
    return tuple((type(v) is int, v) for v in values)


@dataclass(frozen=True)
class _Array:
    """An array of plain numbers in a file's text."""

    tokens: tuple[str, ...]
    tight: tuple[bool, ...]
    """Per comma: a digit on each side, no space, between two whole numbers."""
    line: int
    """Line of its first tight comma (or of its start)."""
    key: str
    """The key it is assigned to on its line, if any."""


@lru_cache(maxsize=4)
def _arrays(source: str) -> dict[tuple, list[_Array]]:
    """Every array of plain numbers in ``source`` (outside comments and strings), by its
    numbers: read once per file, whatever the number of fields."""
    plain = _blank_comments_and_strings(source)
    out: dict[tuple, list[_Array]] = {}
    for match in _ARRAY.finditer(plain):
        pieces = match.group(1).split(",")
        if not pieces[-1].strip():
            pieces.pop()
        tokens = tuple(t.strip() for t in pieces)
        numbers = [_number(t) for t in tokens]
        if any(n is None for n in numbers):
            continue
        tight = tuple(a[-1:].isdigit() and b[:1].isdigit() and type(m) is type(n) is int
                      for a, b, m, n in zip(pieces, pieces[1:], numbers, numbers[1:]))
        comma = re.search(r"\d,\d", match.group(1))
        at = match.start(1) + comma.start() if comma else match.start()
        key = re.search(r"([\w.\"-]+)\s*=\s*$",
                        plain[plain.rfind("\n", 0, match.start()) + 1:match.start()])
        out.setdefault(_key(numbers), []).append(
            _Array(tokens, tight, _line_of(plain, at), key.group(1) if key else ""))
    return out


def decode_error(source: str, message: str) -> tuple[Split, str | None] | None:
    """A TOML syntax error caused by a decimal comma outside quotes (``m = 11,800``,
    ``t_p = [34,05, 34,27]``): the line and its fix, and the field it stands in
    (``section.key``, ``section[i].key``), or None if the failing line shows none.

    Examples
    --------
    >>> split, field = decode_error("[body]\\nm = 11,800\\n", "Expected newline or end of "
    ...                             "document after a statement (at line 2, column 7)")
    >>> split.line, split.fixed, split.quoted, field
    (2, 'm = 11.800', 'm = "11,800"', 'body.m')
    """
    at = _AT.search(message)
    if at is None:
        return None
    lines = source.splitlines()
    number = int(at.group(1))
    if not 1 <= number <= len(lines):
        return None
    plain = _blank_comments_and_strings(source).splitlines()[number - 1]
    if not any(m.start() < int(at.group(2)) for m in _TIGHT.finditer(plain)):
        return None                       # no decimal comma where the parser stopped
    line = lines[number - 1]
    spans = [m.span() for m in _TIGHT.finditer(plain)]
    fixed, quoted, last = [], [], 0
    for start, end in spans:
        fixed += [line[last:start], line[start:end].replace(",", ".")]
        quoted += [line[last:start], f'"{line[start:end]}"']
        last = end
    fixed.append(line[last:])
    quoted.append(line[last:])
    return (Split(number, line.strip(), "".join(fixed).strip(), "".join(quoted).strip()),
            _field_at(_blank_comments_and_strings(source).splitlines(), number))


def _field_at(lines: list[str], number: int) -> str | None:
    """``section.key`` (``section[i].key`` in an array of tables) of the key assigned on line
    ``number`` (1-based) or above it, as the tables' headers place it."""
    section, counts, key = None, {}, None
    for i, line in enumerate(lines[:number], start=1):
        header = re.match(r"\s*(\[\[?)\s*([\w.\"-]+)\s*\]\]?", line)
        assigned = re.match(r"\s*([\w\"-]+(?:\s*\.\s*[\w\"-]+)*)\s*=", line)
        if header:
            name = header.group(2)
            if header.group(1) == "[[":
                counts[name] = counts.get(name, -1) + 1
                section = f"{name}[{counts[name]}]"
            else:
                section = name
            key = None
        elif assigned:
            key = re.sub(r"\s+", "", assigned.group(1)).replace('"', "")
    if key is None:
        return section
    return f"{section}.{key}" if section else key
