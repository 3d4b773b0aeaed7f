"""What the reader saw, drawn over the squared-up sheet: every trace as followed (the chosen
one bold, its unreliable columns in red, gaps left open), the time marks and TDC marks it
timed and the zero lines it measured from. Reports show this beside every result read off a
paper record, so that the student sees what was read. Nothing here imports pyplot."""
from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from ..units import unit_text

OVERLAY_WIDTH = 1600
"""Widest overlay image kept with a record. [px]"""

_TEXT = {
    "en": {"trace": "trace read", "other": "other traces", "low": "low confidence",
           "time": "time marks", "tdc": "TDC marks", "zero": "zero line",
           "taken": "zero line taken", "untaken": "other zero line candidates",
           "column": "column along the sheet [px]", "row": "row [px]",
           "t": "time [s]", "value": "value", "gap": "not read"},
    "ru": {"trace": "считанная линия", "other": "другие линии", "low": "низкая достоверность",
           "time": "отметки времени", "tdc": "отметки ВМТ", "zero": "нулевая линия",
           "taken": "принятая нулевая линия", "untaken": "другие возможные нулевые линии",
           "column": "столбец вдоль ленты [пкс]", "row": "строка [пкс]",
           "t": "время [с]", "value": "величина", "gap": "не считано"},
}


@dataclass(frozen=True)
class Overlay:
    """The squared-up sheet, reduced, with what was found on it (sheet pixel coordinates).

    Attributes
    ----------
    image : numpy.ndarray
        Darkness image of the sheet, reduced to at most :data:`OVERLAY_WIDTH` columns.
    shape : tuple of int
        The full sheet's rows and columns.
    rows : numpy.ndarray
        traces × columns: each trace's row, NaN in gaps. [px]
    confidence : numpy.ndarray
        traces × columns.
    chosen : int
        The trace this record holds.
    marks : dict
        ``"time"`` / ``"tdc"`` → (columns, row of the line) of the marks timed.
    zero_lines : tuple of float
        Rows of the lines that pass for zero lines, at the sheet's middle. [px]
    taken : float or None
        Row of the zero line the values were measured from (None: from the trace's mean).
        [px]
    """

    image: np.ndarray
    shape: tuple[int, int]
    rows: np.ndarray
    confidence: np.ndarray
    chosen: int
    marks: dict
    zero_lines: tuple[float, ...]
    taken: float | None = None

    @classmethod
    def of(cls, grey: np.ndarray, rows, confidence, chosen: int, marks: dict,
           zero_lines, *, taken: float | None = None) -> Overlay:
        h, w = grey.shape
        f = min(1.0, OVERLAY_WIDTH / w)
        small = cv2.resize(grey, (max(int(w * f), 1), max(int(h * f), 1)),
                           interpolation=cv2.INTER_AREA) if f < 1 else grey.copy()
        return cls(small, (h, w), rows, confidence, chosen, marks, tuple(zero_lines), taken)

    def plot(self, ax, *, lang: str = "en", low: float = 0.5) -> None:
        """Draw the sheet and what was read on a matplotlib axis."""
        text = _TEXT.get(lang, _TEXT["en"])
        h, w = self.shape
        ax.imshow(self.image, cmap="gray", vmin=0, vmax=255,
                  extent=(-0.5, w - 0.5, h - 0.5, -0.5), interpolation="antialiased",
                  aspect="auto")
        x = np.arange(w)
        step = max(1, w // 4000)
        for j, row in enumerate(self.rows):
            if j == self.chosen:
                continue
            ax.plot(x[::step], row[::step], color="C0", lw=0.6,
                    label=text["other"] if j == (1 if self.chosen == 0 else 0) else None)
        row = self.rows[self.chosen]
        ax.plot(x[::step], row[::step], color="C1", lw=1.0, label=text["trace"])
        weak = np.where(self.confidence[self.chosen] < low, row, np.nan)
        if np.isfinite(weak).any():
            ax.plot(x, weak, color="red", lw=1.6, label=text["low"])
        others = [y for y in self.zero_lines if y != self.taken]
        for y in others:
            ax.axhline(y, color="C2", lw=0.6, ls="--")
        if others:
            ax.plot([], [], color="C2", lw=0.6, ls="--",
                    label=text["zero" if self.taken is None else "untaken"])
        if self.taken is not None:
            ax.axhline(self.taken, color="C2", lw=1.4,
                       label=f"{text['taken']} ({self.taken:.0f})")
        for key, marker, colour in (("time", "|", "C4"), ("tdc", "v", "C3")):
            if key in self.marks:
                cols, y = self.marks[key]
                ax.plot(cols, np.full(len(cols), y), marker, color=colour, ms=6,
                        label=text[key], ls="none")
        ax.set_xlim(-0.5, w - 0.5)
        ax.set_ylim(h - 0.5, -0.5)
        ax.set_xlabel(text["column"])
        ax.set_ylabel(text["row"])
        ax.legend(fontsize=7, loc="upper right", framealpha=0.8)


def plot_values(ax, time, value, confidence, *, lang: str = "en", unit: str = "",
                low: float = 0.5) -> None:
    """The record as read against time, its low-confidence samples in red."""
    text = _TEXT.get(lang, _TEXT["en"])
    ax.plot(time, value, color="C1", lw=0.8, label=text["trace"])
    weak = np.where(confidence < low, value, np.nan)
    if np.isfinite(weak).any():
        ax.plot(time, weak, color="red", lw=1.4, label=text["low"])
    lost = ~np.isfinite(value)
    if lost.any():
        edges = np.flatnonzero(np.diff(np.concatenate([[0], lost.astype(np.int8), [0]])))
        for a, b in zip(edges[::2], edges[1::2]):
            ax.axvspan(time[a], time[min(b, len(time) - 1)], color="red", alpha=0.15, lw=0)
        ax.axvspan(0, 0, color="red", alpha=0.15, lw=0, label=text["gap"])
    ax.set_xlabel(text["t"])
    ax.set_ylabel(f"{text['value']}{', ' + unit_text(unit, lang) if unit else ''}")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper right")
