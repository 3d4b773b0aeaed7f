"""Numbers in a report's text written as its language writes them.

Light on purpose (no numerics): the warnings' collector imports it at start-up.
"""
from __future__ import annotations

import re

_DECIMAL_POINT = re.compile(r"(?<=\d)\.(?=\d)")
_LIST_COMMA = re.compile(r"(?<=\d), (?=[-−+]?\.?\d)")


def localize_numbers(s: str, lang: str) -> str:
    """Numbers in a report's text written as ``lang`` writes them: in Russian with a decimal
    comma, and a semicolon between the numbers of a list (ГОСТ 8.417; "30,62; 30,81").

    >>> localize_numbers("δ = 0.0142 ± 0.0008, readings 30.62, 30.81", "ru")
    'δ = 0,0142 ± 0,0008, readings 30,62; 30,81'
    >>> localize_numbers("[0.1, 0.2]", "en")
    '[0.1, 0.2]'
    """
    if lang != "ru" or not _DECIMAL_POINT.search(s):
        return s
    return _DECIMAL_POINT.sub(",", _LIST_COMMA.sub("; ", s))


def plural(n: int, forms: tuple[str, ...], lang: str) -> str:
    """``n`` and the word's form that agrees with it: English ``(one, many)``, Russian
    ``(one, few, many)`` (1 пара, 2 пары, 5 пар; 11–14 take "many").

    >>> plural(1, ("pair", "pairs"), "en"), plural(3, ("pair", "pairs"), "en")
    ('1 pair', '3 pairs')
    >>> [plural(k, ("пара", "пары", "пар"), "ru") for k in (1, 2, 5, 11, 21, 22)]
    ['1 пара', '2 пары', '5 пар', '11 пар', '21 пара', '22 пары']
    """
    if lang != "ru":
        return f"{n} {forms[0] if n == 1 else forms[1]}"
    tens, units = n % 100, n % 10
    form = 2 if 11 <= tens <= 14 else 0 if units == 1 else 1 if 2 <= units <= 4 else 2
    return f"{n} {forms[form]}"
