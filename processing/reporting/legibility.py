"""Make a drawn figure legible before it is saved: numbers as the report's language writes
them, tick labels that do not run together, legends off the data.

A lab draws its figures for the data; these checks look at what the reader will see (the
text's extents on the canvas, the data's positions on it) and correct what a lab's layout
cannot foresee: a narrow axis whose tick labels touch ("0.16500.16750.1700"), a legend put
over the curves. :func:`overlapping_ticks` and :func:`legend_overlap` are what the tests
measure with.
"""
from __future__ import annotations

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.ticker import FixedLocator, Formatter, MaxNLocator

from processing.numerals import localize_numbers

GAP = 2.0
"""Least space between two tick labels, in pixels at the figure's dpi."""

OUTSIDE = {"loc": "upper left", "bbox_to_anchor": (1.01, 1.0), "borderaxespad": 0.0}
"""Where a legend goes when every place inside its axes covers data."""


class LocalizedFormatter(Formatter):
    """Another formatter's labels written as ``lang`` writes numbers (a decimal comma in
    Russian, :func:`~processing.units.localize_numbers`)."""

    def __init__(self, inner: Formatter, lang: str):
        self.inner, self.lang = inner, lang

    def set_axis(self, axis):
        super().set_axis(axis)
        self.inner.set_axis(axis)

    def set_locs(self, locs):
        self.inner.set_locs(locs)

    def __call__(self, x, pos=None):
        return localize_numbers(self.inner(x, pos), self.lang)

    def get_offset(self):
        return localize_numbers(self.inner.get_offset(), self.lang)

    def format_data_short(self, value):
        return self.inner.format_data_short(value)


def _touch(a, b) -> bool:
    """Whether two boxes on the canvas are less than :data:`GAP` apart."""
    return a.x0 < b.x1 + GAP and b.x0 < a.x1 + GAP and a.y0 < b.y1 + GAP and b.y0 < a.y1 + GAP


def _crowded(axis, renderer) -> list[tuple[str, str]]:
    """The pairs of ``axis``'s shown tick labels that touch."""
    ticks = [t.label1 for t in axis.get_major_ticks()
             if t.label1.get_visible() and t.label1.get_text()]
    boxes = [t.get_window_extent(renderer) for t in ticks]
    return [(ticks[i].get_text(), ticks[j].get_text()) for i in range(len(ticks))
            for j in range(i + 1, len(ticks)) if _touch(boxes[i], boxes[j])]


def overlapping_ticks(fig) -> list[tuple[str, str]]:
    """The pairs of tick labels of ``fig`` that touch or overlap (less than :data:`GAP`
    apart), as they are drawn."""
    renderer = FigureCanvasAgg(fig).get_renderer()
    fig.draw_without_rendering()
    return [pair for ax in fig.axes for axis in (ax.xaxis, ax.yaxis)
            for pair in _crowded(axis, renderer)]


def _thin_ticks(axis, renderer) -> None:
    """Fewer ticks on ``axis`` until its labels stand apart (a fixed set of ticks, such as
    category names, is kept and its labels turned instead)."""
    if not _crowded(axis, renderer):
        return
    if isinstance(axis.get_major_locator(), FixedLocator):
        if axis.axis_name == "x":
            for label in axis.get_ticklabels():
                label.set_rotation(30)
                label.set_horizontalalignment("right")
        return
    for nbins in (6, 5, 4, 3, 2):
        axis.set_major_locator(MaxNLocator(nbins=nbins, steps=[1, 2, 2.5, 5, 10]))
        axis.figure.draw_without_rendering()
        if not _crowded(axis, renderer):
            return


def _data_points(ax) -> np.ndarray:
    """The data of ``ax`` as display coordinates: lines' vertices, scatter offsets, bars'
    corners and centres."""
    points = [line.get_transform().transform(line.get_xydata()) for line in ax.get_lines()
              if line.get_visible() and len(line.get_xydata())]
    for c in ax.collections:
        offsets = c.get_offsets()
        if len(offsets):
            points.append(c.get_offset_transform().transform(offsets))
    for p in ax.patches:
        box = p.get_window_extent()
        points.append(np.array([[box.x0, box.y0], [box.x1, box.y1],
                                [(box.x0 + box.x1) / 2, (box.y0 + box.y1) / 2]]))
    points = [p for p in points if p.ndim == 2 and p.shape[1] == 2]
    return np.vstack(points) if points else np.empty((0, 2))


def legend_overlap(ax, renderer=None) -> int:
    """How many of the data's points of ``ax`` lie under its legend (0 without a legend)."""
    legend = ax.get_legend()
    if legend is None or not legend.get_visible():
        return 0
    if renderer is None:
        renderer = FigureCanvasAgg(ax.figure).get_renderer()
        ax.figure.draw_without_rendering()
    box = legend.get_window_extent(renderer)
    pts = _data_points(ax)
    pts = pts[np.isfinite(pts).all(axis=1)]
    return int(np.count_nonzero((pts[:, 0] >= box.x0) & (pts[:, 0] <= box.x1)
                                & (pts[:, 1] >= box.y0) & (pts[:, 1] <= box.y1)))


def _place_legend(ax, renderer) -> None:
    """Move a legend that covers data to the first place inside its axes that covers none,
    or outside the axes on the right where every place inside covers some."""
    legend = ax.get_legend()
    if legend is None or legend_overlap(ax, renderer) == 0:
        return
    for loc in range(1, 11):
        legend.set_loc(loc)
        ax.figure.draw_without_rendering()
        if legend_overlap(ax, renderer) == 0:
            return
    handles, labels = ax.get_legend_handles_labels()
    size = legend.get_texts()[0].get_fontsize() if legend.get_texts() else None
    ax.legend(handles, labels, fontsize=size, **OUTSIDE)


def make_legible(fig, lang: str) -> None:
    """Correct a drawn figure in place: numbers in ``lang``, tick labels apart, legends off
    the data."""
    if lang == "ru":
        for ax in fig.axes:
            for axis in (ax.xaxis, ax.yaxis):
                inner = axis.get_major_formatter()
                if not isinstance(inner, LocalizedFormatter):
                    axis.set_major_formatter(LocalizedFormatter(inner, lang))
            words = [ax.title, ax.xaxis.label, ax.yaxis.label, *ax.texts]
            legend = ax.get_legend()
            words += legend.get_texts() if legend is not None else []
            for w in words:
                w.set_text(localize_numbers(w.get_text(), lang))
    renderer = FigureCanvasAgg(fig).get_renderer()
    fig.draw_without_rendering()
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            _thin_ticks(axis, renderer)
        _place_legend(ax, renderer)
