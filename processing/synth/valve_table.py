"""The static rig of the valve-train stiffness lab: a valve train of known part stiffnesses
loaded through a lever and read by dial gauges, and a valve spring on a dynamometer.

The valve train is a chain of springs seen from the valve: the rocker (its own bending,
reduced to the valve), the rocker shaft with its stand (loaded by P(i + 1)), the push rod
(loaded by P i) and the camshaft span (loaded by P i), i the rocker ratio. Four dial gauges
read Δl₁ at the valve end of the rocker (the whole chain), Δl₂ at the rocker shaft, Δl₃ at the
push rod's upper end, under the rocker (rod + camshaft) and Δl₄ at the cam (camshaft bending):

.. math:: Δl_4 = \\frac{P i}{c_{cam}}, \\quad Δl_3 = Δl_4 + \\frac{P i}{c_{rod}}, \\quad
          Δl_2 = \\frac{P (i + 1)}{c_{shaft}}, \\quad
          Δl_1 = \\frac{P}{c_{rocker}} + (i + 1) Δl_2 + i Δl_3

What the scene adds to that ideal chain, each a knob:

* friction in the joints (rocker bearing, ball ends, tappet guide): a Coulomb force F at the
  valve, modelled as the play (backlash) operator on the load, so the chain carries
  P_eff ∈ [P − F, P + F] and keeps it while the load reverses; loading and unloading then
  run on two parallel lines 2F/c apart — the hysteresis loop;
* contact stiffening: Hertzian ball ends of the push rod, δ = δ_ref (P_eff/P_ref)^(2/3), soft at
  low load (the table bends);
* lash: a clearance at the rod ends taken up at the first load step and not returned
  (settling: the lines do not start at zero);
* the lever's true ratio differing from its nominal one (the load's scale error);
* each gauge's scale error (a proportional error of its reading), its reading scatter
  (parallax, a sticking stem) and its rounding to the division the student reads.

The spring: a linear spring of stiffness c_n with its installed preload, coil/guide friction
(the same play operator), lifted in steps by a screw read on a dial gauge, its force read on
a dynamometer's indicator (the manual's ДОР-0,1: 1 mm = 145 N) with its calibration error.

Nothing here knows a measurement-file format: the lab's ``write_synthetic`` turns these
tables into a student's file.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..result import Record
from processing.valvetrain.valve_train import ChainStiffness, stiffnesses, total_stiffness


def play(load, friction: float):
    """The load a chain with Coulomb friction carries: the play (backlash) operator.

    Parameters
    ----------
    load : array_like
        The applied load in the order it was applied, starting from rest. [N]
    friction : float
        Friction force, referred to the load's point. [N]

    Returns
    -------
    ndarray
        The elastically carried load P_eff: it follows P − F while the load rises, P + F
        while it falls, and stays put for 2F after each reversal. [N]

    Examples
    --------
    >>> play([0, 100, 200, 100, 0], 10.0).tolist()
    [0.0, 90.0, 190.0, 110.0, 10.0]
    """
    load = np.asarray(load, dtype=float)
    out = np.empty_like(load)
    state = 0.0
    for k, p in enumerate(load):
        state = min(max(state, p - friction), p + friction)
        out[k] = state
    return out


@dataclass(frozen=True)
class ValveTrain(Record):
    """A push-rod valve train on the static rig.

    Attributes
    ----------
    i : float
        Rocker ratio (valve arm over push-rod arm).
    c_rocker : float
        Rocker bending stiffness at the valve, P/Δl_rocker. [N/m]
    c_shaft : float
        Rocker shaft with its stand: its load P(i + 1) over its deflection Δl₂. [N/m]
    c_rod : float
        Push rod: its load P i over its shortening. [N/m]
    c_cam : float
        Camshaft span: its load P i over its deflection Δl₄. [N/m]
    friction : float
        Coulomb friction of the joints, referred to the valve. [N]
    contact : float
        Hertzian deformation of the push rod's ball ends at ``contact_load`` (0: none). [m]
    contact_load : float
        Valve load at which the contact deforms by ``contact``. [N]
    lash : float
        Clearance at the push rod's ends, taken up at the first load step. [m]
    """

    i: float = 1.5
    c_rocker: float = 7e6
    c_shaft: float = 40e6
    c_rod: float = 20e6
    c_cam: float = 30e6
    friction: float = 8.0
    contact: float = 0.0
    contact_load: float = 1000.0
    lash: float = 0.0

    @property
    def c_total(self) -> float:
        """Stiffness of the whole chain at the valve, 1/c = Σ of the reduced compliances
        (:func:`processing.valvetrain.valve_train.total_stiffness`). [N/m]"""
        return total_stiffness(self.c_rocker, self.c_shaft, self.c_rod, self.c_cam, self.i)

    def deflections(self, load):
        """True readings of the four gauges under a load history, from rest.

        Parameters
        ----------
        load : array_like
            The valve load P in the order applied. [N]

        Returns
        -------
        ndarray, shape (4, n)
            Δl₁ … Δl₄. [m]
        """
        p = play(load, self.friction)
        i = self.i
        dl4 = p * i / self.c_cam
        dl3 = dl4 + p * i / self.c_rod
        if self.contact:
            dl3 = dl3 + self.contact * np.clip(p / self.contact_load, 0, None) ** (2 / 3)
        if self.lash:
            taken = np.maximum.accumulate(np.asarray(load, dtype=float) > 0)
            dl3 = dl3 + self.lash * taken
        dl2 = p * (i + 1) / self.c_shaft
        dl1 = p / self.c_rocker + (i + 1) * dl2 + i * dl3
        return np.stack([dl1, dl2, dl3, dl4])

    def line_stiffness(self, loads) -> ChainStiffness:
        """The stiffnesses that straight lines give on a perfect rig: least squares through
        the exact deflections (no friction, no lash, no reading error) at ``loads``, reduced
        by :func:`processing.valvetrain.valve_train.stiffnesses`. Without contact they are the
        links' own; with it, the push rod's (and the drive's) stiffness over the load programme.

        Parameters
        ----------
        loads : array_like
            The loads of the table, rising. [N]

        Examples
        --------
        >>> t = ValveTrain()
        >>> round(float(t.line_stiffness([0, 500, 1000]).total / t.c_total), 12)
        1.0
        """
        loads = np.asarray(loads, dtype=float)
        exact = replace(self, friction=0.0, lash=0.0).deflections(loads)
        slopes = [np.polyfit(loads, d, 1)[0] for d in exact]
        return stiffnesses(1.0, *slopes, self.i)


@dataclass(frozen=True)
class DialGauges(Record):
    """Dial gauges as a student reads them.

    Attributes
    ----------
    division : float
        Scale value of one division. [m]
    resolution : float
        What the student writes down, in divisions (1: whole divisions; 0.5: halves).
    scatter : float
        Standard deviation of a reading before rounding (parallax, stem friction). [divisions]
    scale_limit : float
        Each gauge's proportional scale error is drawn uniformly within ± this. [1]
    """

    division: float = 1e-5
    resolution: float = 1.0
    scatter: float = 0.25
    scale_limit: float = 0.02

    def read(self, deflection, rng: np.random.Generator, scale_error=None):
        """Readings in divisions of the true deflections (one gauge per row).

        Parameters
        ----------
        deflection : array_like, shape (g, n)
            True deflections. [m]
        rng : numpy.random.Generator
        scale_error : array_like, optional
            Each gauge's proportional error; drawn within ± ``scale_limit`` when None.

        Returns
        -------
        readings : ndarray, shape (g, n)
            [divisions]
        scale_error : ndarray, shape (g,)
        """
        deflection = np.atleast_2d(np.asarray(deflection, dtype=float))
        if scale_error is None:
            scale_error = rng.uniform(-self.scale_limit, self.scale_limit, deflection.shape[0])
        exact = deflection * (1 + np.asarray(scale_error)[:, None]) / self.division
        noisy = exact + self.scatter * rng.standard_normal(exact.shape)
        return self.resolution * np.round(noisy / self.resolution), np.asarray(scale_error)


@dataclass(frozen=True)
class StaticTable(Record):
    """One loading–unloading run on the rig.

    Attributes
    ----------
    Q : ndarray
        Weights on the lever's hanger, nominal. [N]
    P : ndarray
        Valve load the student computes, Q i₁ with the nominal ratio. [N]
    P_true : ndarray
        Valve load actually applied (the lever's true ratio). [N]
    readings : ndarray, shape (4, n)
        Gauge readings. [divisions]
    deflection : ndarray, shape (4, n)
        True deflections. [m]
    scale_error : ndarray, shape (4,)
        The gauges' true proportional errors.
    """

    Q: np.ndarray
    P: np.ndarray
    P_true: np.ndarray
    readings: np.ndarray
    deflection: np.ndarray
    scale_error: np.ndarray


def load_steps(top: float = 1000.0, step: float = 100.0) -> np.ndarray:
    """The manual's load programme: 0 → ``top`` in ``step`` s, then back to 0. [N]

    >>> load_steps(300, 100).tolist()
    [0.0, 100.0, 200.0, 300.0, 200.0, 100.0, 0.0]
    """
    up = np.arange(0.0, top + 0.5 * step, step)
    return np.concatenate([up, up[-2::-1]])


def stiffness_run(train: ValveTrain, gauges: DialGauges, rng: np.random.Generator, *,
                  top: float = 1000.0, step: float = 100.0, lever: float = 10.0,
                  lever_error: float = 0.0, scale_error=None) -> StaticTable:
    """One run of the stiffness test: weights on the lever, four gauges read at each step.

    Parameters
    ----------
    train : ValveTrain
    gauges : DialGauges
    rng : numpy.random.Generator
    top, step : float
        Largest valve load and its step. [N]
    lever : float
        Nominal lever ratio i₁ (the manual's 10).
    lever_error : float
        The lever's true ratio is ``lever (1 + lever_error)``. [1]
    scale_error : array_like, optional
        The gauges' proportional errors (the same gauges over several runs); drawn if None.

    Returns
    -------
    StaticTable
    """
    P = load_steps(top, step)
    P_true = P * (1 + lever_error)
    deflection = train.deflections(P_true)
    readings, scale_error = gauges.read(deflection, rng, scale_error)
    return StaticTable(P / lever, P, P_true, readings, deflection, scale_error)


@dataclass(frozen=True)
class ValveSpring(Record):
    """The valve's springs as mounted: stiffness, installed preload, coil/guide friction.

    Attributes
    ----------
    c_n : float
        Stiffness of the springs together. [N/m]
    preload : float
        Force with the valve closed. [N]
    friction : float
        Coulomb friction of the coils and the guide. [N]
    """

    c_n: float = 45e3
    preload: float = 250.0
    friction: float = 3.0

    def force(self, lift):
        """The spring's force along a lift history from the closed valve. [N]"""
        lift = np.asarray(lift, dtype=float)
        elastic = self.preload + self.c_n * lift
        return self.preload + play(elastic - self.preload, self.friction)


@dataclass(frozen=True)
class SpringTable(Record):
    """One load–unload characteristic of the spring on the dynamometer.

    Attributes
    ----------
    h : ndarray
        Valve lift as set on the lift gauge (nominal). [m]
    reading : ndarray
        Dynamometer indicator as read. [m of indicator travel]
    force : ndarray
        True spring force. [N]
    k_dyn_true : float
        The dynamometer's true characteristic. [N/m]
    h_scale_error : float
        The lift gauge's proportional error.
    """

    h: np.ndarray
    reading: np.ndarray
    force: np.ndarray
    k_dyn_true: float
    h_scale_error: float


def spring_run(spring: ValveSpring, rng: np.random.Generator, *, lift: float = 10e-3,
               step: float = 1e-3, k_dyn: float = 145e3, k_dyn_limit: float = 0.01,
               resolution: float = 1e-5, scatter: float = 0.3e-5,
               h_scale_limit: float = 0.02) -> SpringTable:
    """The spring characteristic: the valve lifted in ``step`` s to ``lift`` and back.

    Parameters
    ----------
    spring : ValveSpring
    rng : numpy.random.Generator
    lift, step : float
        Largest lift and its step, set on a dial gauge. [m]
    k_dyn : float
        The dynamometer's nominal characteristic (the manual's 1 mm = 145 N). [N/m]
    k_dyn_limit : float
        Its true characteristic is drawn within ± this share of nominal.
    resolution, scatter : float
        Indicator division and reading scatter (σ before rounding). [m]
    h_scale_limit : float
        The lift gauge's proportional error is drawn within ± this.

    Returns
    -------
    SpringTable
    """
    h = load_steps(lift, step)
    k_true = k_dyn * (1 + rng.uniform(-k_dyn_limit, k_dyn_limit))
    h_err = rng.uniform(-h_scale_limit, h_scale_limit)
    force = spring.force(h * (1 + h_err))
    travel = force / k_true + scatter * rng.standard_normal(h.size)
    return SpringTable(h, resolution * np.round(travel / resolution), force, k_true, h_err)


@dataclass(frozen=True)
class ValveMasses(Record):
    """Masses and geometry of the oscillating parts (the manual's reduced-mass formula).

    Attributes
    ----------
    m_valve, m_spring, m_rod, m_tappet, m_span : float
        Valve (with its cotters and retainer), springs, push rod, tappet, camshaft span. [kg]
    J_rocker : float
        Rocker's moment of inertia about its shaft. [kg·m²]
    a : float
        Rocker's valve-side arm. [m]
    l, L : float
        Cam-to-bearing distance and bearing span of the camshaft. [m]
    """

    m_valve: float = 0.135
    m_spring: float = 0.105
    J_rocker: float = 1.05e-4
    a: float = 0.045
    m_rod: float = 0.110
    m_tappet: float = 0.085
    m_span: float = 0.95
    l: float = 0.030
    L: float = 0.110
