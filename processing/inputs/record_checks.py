"""A record's marks against what its measurement file states: the TDC marks' speed against the
tachometer's n, the time marks' period against T_mark. Each lab words its own messages; the
limits and the decisions are one.
"""
from __future__ import annotations

import warnings
from collections.abc import Callable

import numpy as np

from processing.diagnostics import DynlabWarning, InputError
from processing.regression import fit_line
from processing.uncertainty import Measured

TACHOMETER_REFUSED = 0.15
"""Relative disagreement between the TDC marks' speed and the tachometer's n beyond which the
marks (or n, or the marks per revolution) are wrong rather than the tachometer rough."""

TACHOMETER_WARNED = 0.03
"""Relative disagreement (beyond 2 u of n) that is warned about."""

MARK_PERIOD_TOLERANCE = 0.01
"""Relative disagreement between the time marks' period on the record's clock and the stated
T_mark beyond which the sample rate or T_mark is wrong."""


def check_tachometer(w: float, n: Measured, refuse: Callable[[float], InputError],
                     warning: Callable[[], DynlabWarning]) -> None:
    """Refuse (``refuse(gap)``, gap = w/n − 1) beyond :data:`TACHOMETER_REFUSED`; warn
    (``warning()``) beyond :data:`TACHOMETER_WARNED` + 2 u(n)/n.

    Parameters
    ----------
    w : float
        The speed from the TDC marks. [rad/s]
    n : Measured
        The tachometer's reading. [rad/s]
    """
    gap = w / n.value - 1
    if abs(gap) > TACHOMETER_REFUSED:
        raise refuse(gap)
    if abs(gap) > TACHOMETER_WARNED + 2 * n.u / n.value:
        warnings.warn(warning())


def check_time_marks(inputs, section: str, channel: str, times, rate: float,
                     refuse: Callable[[str, str, str], InputError], example: str) -> None:
    """The time marks' period on the record's clock (a line through their times) against
    ``[section] mark_period``.

    ``refuse(problem, fix, key)`` makes the error of the record's field ``key``
    (``marks_channel``, ``sample_rate``); ``example`` is a period for the fix (``"10 ms"``).
    """
    settings = inputs[section]
    if "mark_period" not in settings:
        raise inputs.error("a time-mark channel is named but not its period",
                           f"add mark_period = \"{example}\" (the time marker's period) in "
                           f"[{section}]", f"{section}.mark_period")
    times = np.asarray(times, dtype=float)
    if times.size < 3:
        raise refuse(f"channel '{channel}' holds {times.size} time mark(s)",
                     "name the time-mark channel (marks_channel = ...) or leave it out",
                     "marks_channel")
    measured = fit_line(np.arange(times.size, dtype=float), times).slope
    stated = settings["mark_period"].value
    if abs(measured / stated - 1) > MARK_PERIOD_TOLERANCE:
        raise refuse(f"the time marks come every {1e3 * measured:.4g} ms of the record's clock "
                     f"({rate:g} Hz), but T_mark = {1e3 * stated:.4g} ms: the sample rate or "
                     "the marks' period is wrong",
                     "give the recorder's true sample rate (sample_rate = ...), or correct "
                     f"mark_period in [{section}]", "sample_rate")


def whole_ratio(ratio: float, *, largest: int = 4,
                tolerance: float = TACHOMETER_WARNED) -> tuple[int, int] | None:
    """The ratio k/1 or 1/k (2 ≤ k ≤ ``largest``) a speed ratio lies within ``tolerance`` of,
    if any: marks counted per cycle for per revolution give 2 or 1/2, two marks a revolution
    taken for one give 2; a wrong sample rate gives any ratio.

    Examples
    --------
    >>> whole_ratio(0.497), whole_ratio(2.02), whole_ratio(0.75), whole_ratio(1.28)
    ((1, 2), (2, 1), None, None)
    """
    candidates = [(k, 1) for k in range(2, largest + 1)] + [(1, k) for k in range(2, largest + 1)]
    best = min(candidates, key=lambda f: abs(ratio * f[1] / f[0] - 1))
    return best if abs(ratio * best[1] / best[0] - 1) <= tolerance else None
