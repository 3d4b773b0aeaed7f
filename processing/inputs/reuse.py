"""Reusing a costly analysis of the same content within one scope: a check reduces a
submission again for each slip it tries, and a slip that leaves a recording's analysis where it
was (a constant of the formula, the crank radius) finds it done.

A stage marked :func:`by_content` (a function of its arguments alone: a recording's channels,
the values it reads) keeps its result, keyed by the content of the arguments that decide it
(:func:`content_key`: an array's bytes, a file's path, size and time of change, a value as
itself), for as long as the outermost :func:`scope` lasts; outside every scope it is computed
each time. The warnings the stage raised are raised again where its result is reused, so a
reduction's report is the same either way; a stage that raises is not kept. A stage of many
items at once (:func:`by_content_each`: fits made together) keeps each item's result by the
item's content, and computes only the items not met before."""
from __future__ import annotations

import copy
import dataclasses
import functools
import hashlib
import warnings
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from pathlib import Path

import numpy as np

_KEPT: ContextVar[dict | None] = ContextVar("processing.inputs.reuse", default=None)


@contextmanager
def scope() -> Iterator[None]:
    """Keep the results of :func:`by_content` stages inside the block (within an outer
    scope: for as long as that one lasts)."""
    if _KEPT.get() is not None:
        yield
        return
    token = _KEPT.set({})
    try:
        yield
    finally:
        _KEPT.reset(token)


def content_key(x) -> tuple:
    """A hashable key that is equal for equal content: an array of numbers by its dtype,
    shape and bytes' digest; a file by its path, size and time of change; a dataclass, mapping or
    sequence by its parts; a number, text or None as itself.

    Raises
    ------
    TypeError
        A value of another kind (its content cannot be told: the stage is not reused).
    """
    if isinstance(x, float):
        return ("float", x.hex())       # −0.0 is not 0.0; a NaN is the NaN it was
    if x is None or isinstance(x, (bool, int, str, bytes)):
        return (type(x).__name__, x)
    if isinstance(x, np.ndarray) and not x.dtype.hasobject:
        data = np.ascontiguousarray(x)
        return ("array", data.dtype.str, data.shape, hashlib.sha1(data.tobytes()).digest())
    if isinstance(x, np.generic):
        return ("scalar", x.dtype.str, content_key(x.item()))
    if isinstance(x, Path):
        stat = x.stat()
        return ("path", str(x.resolve()), stat.st_size, stat.st_mtime_ns)
    if dataclasses.is_dataclass(x) and not isinstance(x, type):
        return (type(x).__qualname__, *(content_key(getattr(x, f.name))
                                        for f in dataclasses.fields(x)))
    if isinstance(x, dict):
        return ("dict", *((content_key(k), content_key(v)) for k, v in x.items()))
    if isinstance(x, (list, tuple)):
        return (type(x).__name__, *(content_key(v) for v in x))
    if isinstance(x, slice):
        return ("slice", x.start, x.stop, x.step)
    raise TypeError(f"no content key for a {type(x).__name__}")


def by_content(decisive: Callable[..., tuple] | None = None, *, shared: bool = False):
    """Mark a stage whose result is a function of its arguments' content (or of what
    ``decisive(*args, **kwargs)`` picks of them: the parts of a measurement it reads), reused
    inside a :func:`scope`. The caller gets its own copy of the result (it may change it), or,
    where the result is ``shared`` (no caller changes it: a frozen record), the result
    itself."""
    keep = (lambda x: x) if shared else copy.deepcopy

    def mark(stage):
        @functools.wraps(stage)
        def reused(*args, **kwargs):
            kept = _KEPT.get()
            if kept is None:
                return stage(*args, **kwargs)
            try:
                key = (stage.__qualname__, content_key(
                    decisive(*args, **kwargs) if decisive else (args, kwargs)))
            except (TypeError, OSError):
                return stage(*args, **kwargs)
            fresh = key not in kept
            if fresh:
                with warnings.catch_warnings(record=True) as caught:
                    warnings.simplefilter("always")
                    result = stage(*args, **kwargs)
                kept[key] = (keep(result), caught)
            else:
                result, caught = kept[key]
                result = keep(result)
            for w in caught:
                warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
            return result
        return reused
    return mark


def by_content_each(stage: Callable[[list], list]):
    """Mark a stage of many items at once, ``stage(items)`` one result per item, each item's
    a function of that item's content alone (fits made together for their speed, not for
    each other): inside a :func:`scope` each item's result is kept by the item's
    :func:`content_key`, and a call passes the stage only the items not met before (each
    once), in their order. The results are shared (no caller changes them); the stage
    raises no warning a report reads (none is kept)."""
    @functools.wraps(stage)
    def reused(items):
        kept = _KEPT.get()
        if kept is None:
            return stage(list(items))
        try:
            keys = [(stage.__qualname__, content_key(item)) for item in items]
        except (TypeError, OSError):
            return stage(list(items))
        fresh = {}
        for key, item in zip(keys, items):
            if key not in kept:
                fresh.setdefault(key, item)
        if fresh:
            kept.update(zip(fresh, stage(list(fresh.values()))))
        return [kept[key] for key in keys]
    return reused
