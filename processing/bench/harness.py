"""The benchmark harness: time estimators against their accuracy on shared synthetic cases.

An estimator *family* is a set of methods that answer the same question (where are the tooth
edges, what is δ), an error measure against the truth, and the exceptions that count as the
method failing on a case rather than as a bug. :func:`run_family` calls every method on every
:class:`Case`, times each call (:func:`time_call`: best of ``repeat`` runs by
:func:`time.perf_counter`), optionally measures its peak memory (:func:`peak_memory`, by
:mod:`tracemalloc`), and returns one row per call. Rows become a CSV (:func:`write_rows`), a
summary (:func:`summary`), pass/fail lines (:class:`Target`, :func:`write_targets`) and three
charts: error against time per call (:func:`plot_error_time`), time against signal length
(:func:`plot_time_size`) and a map of the error over a grid of two case parameters
(:func:`plot_map`).

The harness knows no lab and no physics: the families and their cases come from modules such
as :mod:`processing.bench.speed`. Timings mean something only on an otherwise idle machine
with the BLAS and OpenMP pools held to one thread (``python -m processing.bench`` does that).
"""
from __future__ import annotations

import json
import math
import os
import platform
import time
import tracemalloc
import warnings
from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

FAILED_ERROR = np.inf
"""The |error| a failed call stands for where errors are aggregated (a map cell, a worst case)."""


@dataclass(frozen=True)
class Case:
    """One synthetic case: what every method is given and what its answer is judged against.

    Parameters
    ----------
    params : dict
        The case's parameters, copied into each row (plain scalars: ``{"snr_db": 30, ...}``).
    data : object
        The argument each method is called with.
    truth : object
        What the family's error measure compares an estimate with.
    samples : int
        Length of the input in samples (for samples per second).
    """

    params: dict
    data: Any
    truth: Any
    samples: int


@dataclass(frozen=True)
class Method:
    """One estimator of a family: ``call(case.data)`` returns its estimate."""

    name: str
    call: Callable[[Any], Any]
    setting: str = ""
    """Its option values in words (``"window=3"``), the same for every case."""


@dataclass(frozen=True)
class Family:
    """Methods answering one question, and how their answers are judged.

    Parameters
    ----------
    name : str
        The family, as it appears in the rows (``"edge timing"``).
    methods : sequence of Method
    error : callable
        ``error(estimate, truth)`` → dict of error columns; the key ``"error"`` is the main one
        (signed where a sign means something: the charts take its absolute value).
    error_label : str
        What ``"error"`` is, with its unit, for chart axes.
    failures : tuple of exception types
        Exceptions that mean the method cannot handle the case (a row with ``failed`` set and
        a NaN error); any other exception propagates.
    """

    name: str
    methods: Sequence[Method]
    error: Callable[[Any, Any], dict]
    error_label: str = "error"
    failures: tuple[type[BaseException], ...] = ()


@dataclass(frozen=True)
class Target:
    """A performance target: ``value`` must not exceed (``"max"``) or fall short of (``"min"``)
    ``limit``."""

    name: str
    value: float
    limit: float
    kind: str = "max"
    unit: str = ""
    detail: str = ""

    @property
    def passed(self) -> bool:
        if not math.isfinite(self.value):
            return False
        return bool(self.value <= self.limit if self.kind == "max" else self.value >= self.limit)

    @property
    def sign(self) -> str:
        """How the value must stand to the limit: ``≤`` or ``≥``."""
        return "≤" if self.kind == "max" else "≥"

    def line(self) -> str:
        """``PASS  name: value (limit ≤ x unit)  detail``."""
        text = (f"{'PASS' if self.passed else 'FAIL'}  {self.name}: {self.value:.4g} "
                f"(target {self.sign} {self.limit:.4g}{' ' + self.unit if self.unit else ''})")
        return text + (f"  {self.detail}" if self.detail else "")


COVERAGE = (0.90, 0.98)
"""The band a stated 95 % interval's coverage over seeded trials must fall in: below, U is too
small; above, U is wider than it needs to be."""


def coverage_targets(what: str, covered, trials: str = "records",
                     band: tuple[float, float] = COVERAGE) -> list[Target]:
    """The two coverage targets of a stated 95 % interval, allowing for the trials' number.

    A share measured on n trials scatters by its binomial error: the band is widened by
    1.96 √(0.95·0.05/n), so that 0.99 on 200 trials (consistent with a true 0.975) is not
    called too wide, nor 0.87 on 60 too narrow; with many trials the band is the target's.

    Parameters
    ----------
    what : str
        The interval, e.g. ``"δ, trace fit"``.
    covered : array_like of bool
        Whether each trial's interval held the truth.
    trials : str
        What a trial is, for the detail ("records", "tables").
    band : (float, float)

    Returns
    -------
    list of Target
        ``at least`` and ``at most``.
    """
    flags = np.asarray(covered, dtype=float)
    n = flags.size
    share = float(flags.mean()) if n else math.nan
    margin = 1.96 * math.sqrt(0.95 * 0.05 / n) if n else 0.0
    detail = f"{n} {trials}; band widened by ± {margin:.3f} for their number"
    return [Target(f"{what}: its 95 % interval holds the truth (at least)", share,
                   band[0] - margin, "min", detail=detail),
            Target(f"{what}: its 95 % interval holds the truth (at most)", share,
                   band[1] + margin, detail=detail + "; wider would be wasteful")]


def time_call(call: Callable[[Any], Any], data, repeat: int = 3,
              budget: float = 0.5) -> tuple[float, Any]:
    """Best wall time of ``call(data)`` over ``repeat`` runs, and the last run's result.

    Parameters
    ----------
    call : callable
    data : object
    repeat : int
        Runs at most; the shortest is the least disturbed by the rest of the machine.
    budget : float
        No further run starts once the runs so far took this long (a slow call is timed
        once or twice). [s]

    Returns
    -------
    seconds : float
        Shortest run. [s]
    result : object
    """
    best, spent, result = math.inf, 0.0, None
    for _ in range(max(int(repeat), 1)):
        start = time.perf_counter()
        result = call(data)
        took = time.perf_counter() - start
        best, spent = min(best, took), spent + took
        if spent >= budget:
            break
    return best, result


def peak_memory(call: Callable[[Any], Any], data) -> tuple[int, Any]:
    """Peak of the memory allocated during ``call(data)`` (Python objects and numpy arrays,
    by :mod:`tracemalloc`), above what was allocated before it.

    Returns
    -------
    peak : int
        [bytes]
    result : object
    """
    started = not tracemalloc.is_tracing()
    if started:
        tracemalloc.start()
    try:
        tracemalloc.reset_peak()
        base = tracemalloc.get_traced_memory()[0]
        result = call(data)
        peak = tracemalloc.get_traced_memory()[1] - base
    finally:
        if started:
            tracemalloc.stop()
    return peak, result


def run_family(family: Family, cases: Iterable[Case], *, repeat: int = 3,
               memory: bool = False) -> list[dict]:
    """Call every method of ``family`` on every case; time it and measure its error.

    Parameters
    ----------
    family : Family
    cases : iterable of Case
        Consumed once, case by case (a generator may make and drop large inputs).
    repeat : int
        Timed runs per call (the best counts).
    memory : bool
        Also measure each call's peak memory in one more, untimed run (``peak_bytes``).

    Returns
    -------
    list of dict
        One row per (case, method): ``family``, ``method``, ``setting``, the case's params,
        ``samples``, ``seconds`` (per call), ``samples_per_second``, the error columns,
        ``failed`` (empty, or the exception) and ``warnings`` (the categories raised).
    """
    rows = []
    for case in cases:
        for method in family.methods:
            rows.append(_row(family, method, case, repeat, memory))
    return rows


def _row(family: Family, method: Method, case: Case, repeat: int, memory: bool) -> dict:
    row = {"family": family.name, "method": method.name, "setting": method.setting,
           **case.params, "samples": case.samples}
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            seconds, estimate = time_call(method.call, case.data, repeat)
            if memory:
                row["peak_bytes"] = peak_memory(method.call, case.data)[0]
        except family.failures as exc:
            row.update(seconds=np.nan, samples_per_second=np.nan, error=np.nan,
                       failed=f"{type(exc).__name__}: {exc}"[:160])
        else:
            row.update(seconds=seconds, samples_per_second=case.samples / seconds,
                       **family.error(estimate, case.truth), failed="")
    row["warnings"] = "; ".join(sorted({w.category.__name__ for w in caught}))
    return row


def write_rows(rows: Sequence[Mapping], path) -> pd.DataFrame:
    """Write the rows as a CSV table (columns in order of first appearance); return it."""
    frame = pd.DataFrame(list(rows))
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    frame.to_csv(path, index=False)
    return frame


def abs_error(frame: pd.DataFrame) -> pd.Series:
    """|error| of each row, :data:`FAILED_ERROR` where the call failed."""
    return frame["error"].abs().where(frame["failed"].fillna("") == "", FAILED_ERROR)


def summary(frame: pd.DataFrame) -> pd.DataFrame:
    """Per family, method and setting: cases, failures, median time per call, median
    throughput, median and worst |error|."""
    work = frame.assign(abs_error=abs_error(frame),
                        fail=frame["failed"].fillna("") != "")
    grouped = work.groupby(["family", "method", "setting"], sort=False)
    return pd.DataFrame({
        "cases": grouped.size(),
        "failed": grouped["fail"].sum(),
        "s/call": grouped["seconds"].median(),
        "MS/s": grouped["samples_per_second"].median() / 1e6,
        "median|err|": grouped["abs_error"].median(),
        "worst|err|": grouped["abs_error"].max(),
    }).reset_index()


def write_targets(targets: Sequence[Target], path, environment: Mapping | None = None) -> None:
    """Write the targets (with ``passed``) and the machine's description as JSON."""
    items = [{**asdict(t), "passed": t.passed, "limit": float(t.limit),
              "value": float(t.value) if math.isfinite(t.value) else None} for t in targets]
    Path(path).write_text(json.dumps({"targets": items, "environment": dict(environment or {})},
                                     indent=2, ensure_ascii=False), encoding="utf-8")


@dataclass(frozen=True)
class MapAxes:
    """Which columns of the rows lay out a map (:func:`plot_map`)."""

    x: str
    y: str
    column: str
    row: str = "method"
    labels: dict = field(default_factory=dict)
    """Axis titles by column name (default: the column name)."""


def plot_error_time(frame: pd.DataFrame, path, labels: Mapping[str, str]) -> None:
    """Error against time per call: one point per method and setting, a panel per family.

    Parameters
    ----------
    frame : pandas.DataFrame
        Rows of :func:`run_family`.
    path : str or Path
        The PNG to write.
    labels : mapping
        Family name → the y-axis title (what its ``error`` is); only these families are drawn.

    Notes
    -----
    The point is the median over the cases of the time and of |error|; the vertical bar runs
    from the smallest to the largest |error| (failed calls excluded, counted in the label).
    Both axes are logarithmic.
    """
    from matplotlib.figure import Figure
    from matplotlib.ticker import NullFormatter

    fig = Figure(figsize=(6 * len(labels), 4.8))
    for k, (name, ylabel) in enumerate(labels.items()):
        ax = fig.add_subplot(1, len(labels), k + 1)
        part = frame[frame["family"] == name].assign(abs_error=abs_error(frame))
        for i, ((method, setting), group) in enumerate(
                part.groupby(["method", "setting"], sort=False)):
            ok = group[np.isfinite(group["abs_error"])]
            if ok.empty:
                continue
            err = ok["abs_error"].clip(lower=1e-9)
            x, y = ok["seconds"].median(), err.median()
            ax.errorbar([x], [y], yerr=[[y - err.min()], [err.max() - y]], fmt="o", capsize=3,
                        color=f"C{i % 10}")
            failed = len(group) - len(ok)
            text = f"{method} {setting}".strip() + (f" ({failed} failed)" if failed else "")
            ax.annotate(text, (x, y), textcoords="offset points", xytext=(5, 4 - 14 * (i % 2)),
                        fontsize=8)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.set_xlabel("time per call [s]")
        ax.set_ylabel(ylabel)
        ax.set_title(name)
        ax.grid(which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def plot_time_size(frame: pd.DataFrame, path, *, family: str, target_rate: float) -> None:
    """Time per call against signal length, log-log, a line per method and setting, with the
    line of a target throughput.

    Parameters
    ----------
    frame : pandas.DataFrame
        Rows of :func:`run_family`.
    path : str or Path
        The PNG to write.
    family : str
        Whose rows to draw.
    target_rate : float
        Samples per second a method must reach: drawn as time = samples / rate. [1/s]
    """
    from matplotlib.figure import Figure

    part = frame[(frame["family"] == family) & (frame["failed"].fillna("") == "")]
    fig = Figure(figsize=(7, 5))
    ax = fig.add_subplot(1, 1, 1)
    for (method, setting), group in part.groupby(["method", "setting"], sort=False):
        group = group.groupby("samples", as_index=False)["seconds"].min()
        ax.plot(group["samples"], group["seconds"], "o-", label=f"{method} {setting}".strip())
    n = np.geomspace(part["samples"].min(), part["samples"].max(), 2)
    ax.plot(n, n / target_rate, "k--", label=f"target {target_rate / 1e6:g} MS/s")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("signal length [samples]")
    ax.set_ylabel("time per call [s]")
    ax.set_title(family)
    ax.grid(which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def map_grid(frame: pd.DataFrame, axes: MapAxes) -> dict[tuple, pd.DataFrame]:
    """Median |error| over the repeated cases of each cell, per (row, column) panel.

    Returns
    -------
    dict
        (row value, column value) → table indexed by ``axes.y`` with columns ``axes.x``;
        a failed call counts as :data:`FAILED_ERROR`.
    """
    work = frame.assign(abs_error=abs_error(frame))
    panels = {}
    for key, group in work.groupby([axes.row, axes.column], sort=True):
        panels[key] = group.pivot_table(index=axes.y, columns=axes.x, values="abs_error",
                                        aggfunc="median")
    return panels


def plot_map(frame: pd.DataFrame, path, axes: MapAxes, *, threshold: float = 0.01) -> None:
    """Heat maps of the median |error| over a grid of two case parameters: each cell's value
    written in it (in %; ``fail`` where the method failed on most cases, grey), and the cells
    within ``threshold`` outlined in red.

    Parameters
    ----------
    frame : pandas.DataFrame
        Rows of one family over the grid (several seeds per cell are aggregated).
    path : str or Path
        The PNG to write.
    axes : MapAxes
        Columns for the x and y axes, the panel columns and the panel rows.
    threshold : float
        |error| whose region is outlined (0.01: 1 %).
    """
    from matplotlib import colormaps
    from matplotlib.colors import LogNorm
    from matplotlib.figure import Figure

    panels = map_grid(frame, axes)
    rows = sorted({k[0] for k in panels})
    cols = sorted({k[1] for k in panels})
    fig = Figure(figsize=(3.8 * len(cols) + 1.2, 3.3 * len(rows)), layout="constrained")
    cmap = colormaps["viridis"].with_extremes(bad="lightgrey")
    image = None
    for (r, c), table in panels.items():
        ax = fig.add_subplot(len(rows), len(cols), rows.index(r) * len(cols) + cols.index(c) + 1)
        values = table.to_numpy(dtype=float)
        shown = np.ma.masked_invalid(np.clip(values, 1e-3, 1.0, where=np.isfinite(values),
                                             out=values.copy()))
        image = ax.imshow(shown, origin="lower", cmap=cmap, norm=LogNorm(1e-3, 1.0),
                          aspect="auto")
        for (i, j), v in np.ndenumerate(values):
            ax.text(j, i, _percent(v), ha="center", va="center", fontsize=7,
                    color="white" if np.isfinite(v) and v < 0.03 else "black")
        _outline(ax, values <= threshold)
        ax.set_xticks(range(table.shape[1]), [f"{x:g}" for x in table.columns])
        ax.set_yticks(range(table.shape[0]), [f"{y:g}" for y in table.index])
        ax.set_xlabel(axes.labels.get(axes.x, axes.x))
        ax.set_ylabel(axes.labels.get(axes.y, axes.y))
        ax.set_title(f"{r}, {axes.labels.get(axes.column, axes.column)} = {c}", fontsize=10)
    if image is not None:
        fig.colorbar(image, ax=fig.axes, label=f"median |error| (cells: %; red outline: "
                                               f"≤ {100 * threshold:g} %)")
    fig.savefig(path, dpi=120)


def _percent(value: float) -> str:
    """A relative error as a short percentage, ``fail`` for a failed call."""
    if not np.isfinite(value):
        return "fail"
    return f"{100 * value:.0f}" if value >= 1 else f"{100 * value:.2g}"


def _outline(ax, inside: np.ndarray) -> None:
    """Draw the border of the ``True`` cells of a grid shown by ``imshow``."""
    rows, cols = inside.shape
    for i, j in zip(*np.nonzero(inside)):
        for di, dj in ((0, 1), (0, -1), (1, 0), (-1, 0)):
            ni, nj = i + di, j + dj
            if 0 <= ni < rows and 0 <= nj < cols and inside[ni, nj]:
                continue
            if di:
                y = i + di / 2
                ax.plot([j - 0.5, j + 0.5], [y, y], color="red", lw=2)
            else:
                x = j + dj / 2
                ax.plot([x, x], [i - 0.5, i + 0.5], color="red", lw=2)


def environment() -> dict:
    """The machine and the thread settings the timings were taken with."""
    return {"python": platform.python_version(), "numpy": np.__version__,
            "pandas": pd.__version__, "machine": platform.machine(), "system": platform.system(),
            "cpus": os.cpu_count(),
            **{k: v for k, v in sorted(os.environ.items()) if k.endswith("_NUM_THREADS")}}
