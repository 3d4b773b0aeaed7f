"""The valve train as a chain of springs seen from the valve: the links' deformations and
stiffnesses from a static test, the drive's stiffness, the oscillating mass reduced to the
valve and the drive's lowest natural frequency.

A push-rod valve train is a rocker (ratio i: valve arm over push-rod arm) on a shaft with its
stand, a push rod and a camshaft span between two bearings. Loaded at the valve by P, each
link deforms under its own load (the shaft under P(i + 1), the rod and the camshaft under
P i), and each deformation moves the valve by itself times a lever ratio; the drive's
compliance at the valve is the sum of the links' compliances so reduced. With the valve
springs (c_n) and the mass of the moving parts reduced to the valve (M) the drive is one
oscillator, ν = √((c + c_n)/M). The formulas are the manual's (lab 5), used by the static
test (lab 5) and by the running engine's comparison of a predicted with a measured ν (lab 6).

References
----------
.. [1] Dynamics of internal-combustion engines: lab manual, Vladimir State University, 2003,
       lab 5 ("Исследование жесткости деталей механизма газораспределения двигателя").
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from processing.result import Record


def part_deformations(dl1, dl2, dl3, dl4, i):
    r"""Deformations of the parts reduced to the valve axis (the manual's lab 5).

    .. math:: Δl_{rocker} = Δl_1 - Δl_2 (i + 1) - Δl_3 i, \quad Δl_{shaft} = Δl_2 (i + 1),
              \quad Δl_{rod} = (Δl_3 - Δl_4) i, \quad Δl_{cam} = Δl_4 i

    Parameters
    ----------
    dl1, dl2, dl3, dl4 : float or ndarray
        Gauge readings: total at the valve, rocker shaft, push rod's upper (rocker) end, cam. [m]
    i : float or ndarray
        Rocker ratio.

    Returns
    -------
    rocker, shaft, rod, cam : float or ndarray
        [m]; they add up to Δl₁.

    Examples
    --------
    >>> [round(x, 12) for x in part_deformations(4.0e-4, 6e-5, 1.2e-4, 5e-5, 1.5)]
    [7e-05, 0.00015, 0.000105, 7.5e-05]
    """
    return dl1 - dl2 * (i + 1) - dl3 * i, dl2 * (i + 1), (dl3 - dl4) * i, dl4 * i


@dataclass(frozen=True)
class ChainStiffness(Record):
    """Stiffnesses of the valve train's links and of the whole drive at the valve.

    Attributes
    ----------
    rocker : float or ndarray
        c_rocker = P/Δl_rocker, at the valve. [N/m]
    shaft, rod, cam : float or ndarray
        Each link's own stiffness: its load (P(i + 1), P i, P i) over its deformation. [N/m]
    total : float or ndarray
        The drive at the valve, P/Δl₁. [N/m]
    """

    rocker: object
    shaft: object
    rod: object
    cam: object
    total: object


def stiffnesses(P, dl1, dl2, dl3, dl4, i) -> ChainStiffness:
    r"""Stiffness of each link from a load and the four gauges (the manual's lab 5).

    .. math:: c_{rocker} = \frac{P}{Δl_{rocker}}, \quad c_{shaft} = \frac{P (i + 1)}{Δl_2},
              \quad c_{rod} = \frac{P i}{Δl_3 - Δl_4}, \quad c_{cam} = \frac{P i}{Δl_4},
              \quad c = \frac{P}{Δl_1}

    With P = 1 N and the slopes dΔl/dP in place of the deformations this gives the
    stiffnesses of the straight lines fitted to the table.

    Parameters
    ----------
    P : float or ndarray
        Load at the valve. [N]
    dl1, dl2, dl3, dl4 : float or ndarray
        Gauge readings under P (or slopes, with P = 1). [m] ([m/N])
    i : float or ndarray
        Rocker ratio.

    Returns
    -------
    ChainStiffness
    """
    rocker = part_deformations(dl1, dl2, dl3, dl4, i)[0]
    return ChainStiffness(P / rocker, P * (i + 1) / dl2, P * i / (dl3 - dl4), P * i / dl4,
                          P / dl1)


def at_valve(c_rocker, c_shaft, c_rod, c_cam, i):
    r"""Each link's stiffness as the valve sees it: the terms of the chain's compliance.

    .. math:: c_{rocker}, \quad \frac{c_{shaft}}{(i + 1)^2}, \quad \frac{c_{rod}}{i^2},
              \quad \frac{c_{cam}}{i^2}

    Returns
    -------
    tuple of float or ndarray
        Rocker, shaft, rod, cam. [N/m]

    Examples
    --------
    >>> [round(c / 1e6, 3) for c in at_valve(12e6, 40e6, 20e6, 30e6, 1.5)]
    [12.0, 6.4, 8.889, 13.333]
    """
    return c_rocker, c_shaft / (i + 1) ** 2, c_rod / i**2, c_cam / i**2


def total_stiffness(c_rocker, c_shaft, c_rod, c_cam, i):
    r"""The drive's stiffness at the valve from its links (the manual's lab 5).

    .. math:: \frac{1}{c} = \frac{1}{c_{rocker}} + \frac{(i + 1)^2}{c_{shaft}}
              + i^2 \left(\frac{1}{c_{rod}} + \frac{1}{c_{cam}}\right)

    From the same table it equals P/Δl₁: the reduced deformations add up to Δl₁.

    Examples
    --------
    >>> round(total_stiffness(12e6, 40e6, 20e6, 30e6, 1.5) / 1e6, 4)
    2.3415
    """
    return 1.0 / sum(1.0 / c for c in at_valve(c_rocker, c_shaft, c_rod, c_cam, i))


def span_mass(m_span, l=None, L=None):
    r"""Oscillating mass of the camshaft span at the cam (the manual's lab 5).

    .. math:: m_g = \frac{m'_g}{2 \sin^2(\pi l / L)} \quad\text{or, without l and L,}\quad
              m_g \approx \tfrac{2}{3} m'_g

    Parameters
    ----------
    m_span : float or ndarray
        Mass of the span between two bearings, m'_g. [kg]
    l, L : float or ndarray, optional
        Cam-to-bearing distance and bearing span. [m]

    Examples
    --------
    >>> float(span_mass(0.9, 0.05, 0.1)), round(span_mass(0.9), 12)
    (0.45, 0.6)
    """
    if l is None or L is None:
        return 2.0 / 3.0 * m_span
    return m_span / (2.0 * np.sin(np.pi * l / L) ** 2)


@dataclass(frozen=True)
class ReducedMass(Record):
    """The terms of the oscillating mass reduced to the valve. [kg]

    Attributes
    ----------
    valve, springs, rocker : float or ndarray
        m_valve, m_spring/3, J_rocker/a².
    rod : float or ndarray
        The push rod's own third, (1 + 2i²c/c_g)(1/3) m_rod (i c/c_rod)².
    cam : float or ndarray
        What moves with the cam's end, (1 + 2i²c/c_g)((2/3) m_rod + m_tappet + m_g)(i c/c_g)².
    """

    valve: object
    springs: object
    rocker: object
    rod: object
    cam: object

    @property
    def total(self):
        """M. [kg]"""
        return self.valve + self.springs + self.rocker + self.rod + self.cam


def reduced_mass(m_valve, m_spring, J_rocker, a, m_rod, m_tappet, m_g, c, c_rod, c_g,
                 i) -> ReducedMass:
    r"""Mass of the oscillating parts reduced to the valve (the manual's lab 5, as printed).

    .. math:: M = m_{valve} + \frac{m_{spring}}{3} + \frac{J_{rocker}}{a^2}
              + \Big(1 + 2 i^2 \frac{c}{c_g}\Big)\Big[\frac{1}{3} m_{rod}
              \Big(i \frac{c}{c_{rod}}\Big)^2 + \Big(\frac{2}{3} m_{rod} + m_{tappet} + m_g\Big)
              \Big(i \frac{c}{c_g}\Big)^2\Big]

    c_g is the camshaft span's stiffness (c_cam). The push rod, tappet and camshaft move
    only by the chain's deformation (the cam stands on its base circle), (i c/c_x) being the
    motion of their end per unit of valve motion; the factor (1 + 2i²c/c_g) is printed so.

    Parameters
    ----------
    m_valve, m_spring, m_rod, m_tappet, m_g : float or ndarray
        [kg]
    J_rocker : float or ndarray
        About the rocker shaft. [kg·m²]
    a : float or ndarray
        Rocker's valve-side arm. [m]
    c, c_rod, c_g : float or ndarray
        Drive at the valve, push rod, camshaft span. [N/m]
    i : float or ndarray
        Rocker ratio.

    Returns
    -------
    ReducedMass
        Its terms; ``.total`` is M. [kg]

    Examples
    --------
    A rigid rod and camshaft leave the valve, a third of the springs and the rocker:

    >>> round(float(reduced_mass(0.1, 0.09, 1e-4, 0.05, 0.1, 0.1, 0.6, 2e6, np.inf, np.inf,
    ...                          1.5).total), 6)
    0.17
    """
    rod, cam = i * c / c_rod, i * c / c_g
    factor = 1 + 2 * i * i * c / c_g
    return ReducedMass(m_valve, m_spring / 3, J_rocker / a**2, factor * m_rod / 3 * rod**2,
                       factor * (2 * m_rod / 3 + m_tappet + m_g) * cam**2)


def natural_frequency(c, c_n, M):
    r"""Lowest natural angular frequency of the valve drive (the manual's lab 5).

    .. math:: ν = \sqrt{\frac{c + c_n}{M}}

    Parameters
    ----------
    c, c_n : float or ndarray
        Drive and valve springs' stiffness at the valve. [N/m]
    M : float or ndarray
        Reduced oscillating mass. [kg]

    Returns
    -------
    float or ndarray
        [rad/s]; NaN where c + c_n < 0 (nothing restores the valve).

    Examples
    --------
    >>> round(float(natural_frequency(2.0e6, 5e4, 0.205)), 1)
    3162.3
    """
    return np.sqrt((c + c_n) / M)


def cam_order(frequency, n, strokes=4):
    r"""A frequency in orders of the camshaft's rotation at engine speed n.

    .. math:: k = \frac{f}{f_{cam}}, \qquad f_{cam} = \frac{n}{2\pi}\cdot\frac{2}{τ}

    (τ = 4: the camshaft turns at half the crankshaft's speed.)

    Parameters
    ----------
    frequency : float or ndarray
        [Hz]
    n : float or ndarray
        Crankshaft speed. [rad/s]
    strokes : int

    Examples
    --------
    >>> round(float(cam_order(500.0, 2000 * np.pi / 30)), 3)
    30.0
    """
    return frequency / (n / (2 * np.pi) * 2 / strokes)
