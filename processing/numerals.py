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
