"""Figures shared by labs. Draw on a given matplotlib Figure; never import pyplot."""
from __future__ import annotations

import numpy as np

from processing.units import unit_text


def method_chart(fig, results, lang: str = "en") -> None:
    """One quantity estimated by several methods: value, ± U bar and Monte Carlo 95 % ticks.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        Where to draw (one axes is added).
    results : sequence of ResultValue
        The estimates, all in the same unit.
    lang : {"en", "ru"}
    """
    ax = fig.add_subplot(1, 1, 1)
    y = np.arange(len(results))[::-1]
    for yi, r in zip(y, results):
        v, U = r.shown(r.value), r.shown(r.value + r.estimate.U) - r.shown(r.value)
        ax.errorbar(v, yi, xerr=U, fmt="o", color="C0", capsize=4)
        lo, hi = (r.shown(x) for x in r.estimate.interval95)
        ax.plot([lo, hi], [yi, yi], "|", color="C3", markersize=14)
    ax.set_yticks(y, [r.label[lang] for r in results])
    unit = results[0].display_unit if results else ""
    ax.set_xlabel(f"{results[0].symbol.split('_')[0] if results else ''}, {unit_text(unit, lang)}")
    ax.grid(axis="x", alpha=0.3)
    fig.tight_layout()


def histogram(fig, samples, value, interval, xlabel: str, lang: str = "en") -> None:
    """Monte Carlo distribution of an output with its best estimate and 95 % interval."""
    ax = fig.add_subplot(1, 1, 1)
    ok = samples[np.isfinite(samples)]
    lo, hi = np.quantile(ok, [0.001, 0.999])
    ax.hist(ok[(ok >= lo) & (ok <= hi)], bins=80, color="C0", alpha=0.7)
    ax.axvline(value, color="k", label="estimate" if lang == "en" else "оценка")
    for x in interval:
        ax.axvline(x, color="C3", ls="--")
    ax.set_xlabel(xlabel)
    ax.set_yticks([])
    fig.tight_layout()
