"""Load–deflection loops: the work of a branch and the energy a closed loop dissipates.

A static test loads a part and unloads it (a damper's torque against its twist, a valve
train's force against a gauge reading). The unloading branch lies below the loading one; the
area between them, the loop's area, is the energy lost per cycle to internal friction and
contact slip. :func:`loop_area` takes the loop as one closed polygon (loading points, then
unloading points, in the order they were read); :func:`branch_work` is the work of one branch
by the trapezoidal rule.
"""
from __future__ import annotations

import numpy as np


def loop_area(x, y):
    r"""Area enclosed by a loop of measured points, as a closed polygon (the shoelace rule).

    Parameters
    ----------
    x, y : array_like
        The points in the order they were read, loading then unloading, along the last
        axis; the polygon is closed from the last point back to the first. Other axes
        broadcast (several runs at once). [units of x], [units of y]

    Returns
    -------
    float or ndarray
        The enclosed area, positive whichever way the loop runs. [unit of x · unit of y]

    Notes
    -----
    .. math:: A = \frac{1}{2}\left|\sum_{k} (x_k y_{k+1} - x_{k+1} y_k)\right|,
              \qquad x_{n} = x_0,\ y_n = y_0

    A loop that crosses itself counts its lobes with opposite signs; a hysteresis loop of a
    damper or a spring does not cross itself.

    Examples
    --------
    Loading 0 → 2 along y = x, unloading along y = x − 1 (clipped at 0): a parallelogram
    and a triangle.

    >>> float(loop_area([0, 1, 2, 2, 1, 0], [0, 1, 2, 1, 0, 0]))
    1.5
    """
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    x1, y1 = np.roll(x, -1, axis=-1), np.roll(y, -1, axis=-1)
    return 0.5 * np.abs((x * y1 - x1 * y).sum(axis=-1))


def branch_work(x, y):
    r"""Work along one branch of a load–deflection curve, :math:`\int y\,dx` (trapezoids).

    Parameters
    ----------
    x, y : array_like
        Deflection and load along the branch, along the last axis.

    Returns
    -------
    float or ndarray
        [unit of x · unit of y]; negative when x falls (an unloading branch).

    Examples
    --------
    >>> float(branch_work([0, 1, 2], [0, 1, 2]))
    2.0
    """
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    return (0.5 * (y[..., 1:] + y[..., :-1]) * np.diff(x, axis=-1)).sum(axis=-1)
