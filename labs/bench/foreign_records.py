"""Lab measurements on paper records drawn by the second family of renderers
(:mod:`processing.synth.paper_strip`): a light-beam oscillograph's strip, scanned on a flatbed
with its lid or photographed by a phone over a table. One function per lab scene writes a
measurement file, its image and the truth, as a student with that record would hand them in;
the paper benchmark (:mod:`labs.bench.paper`, family ``foreign records``) reduces them
with the lab's own ``reduce`` and judges the result, its interval and any refusal.

A scene function ``labN_scene(seed, folder, *, capture, **choices) -> ForeignCase`` draws
everything it does not get from the seed: the part, the regime, the strip's layout and marks,
the capture (:meth:`~processing.synth.paper_strip.Scan.draw`,
:meth:`~processing.synth.paper_strip.Photo.draw`). :data:`SCENES` names them for the bench.
"""
from __future__ import annotations

import json
import re
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from processing.synth.paper_strip import (Grid, Marks, Photo, Scan, Strip, StripScene, Trace,
                                          expose)

CAPTURES = ("scan", "photo")

SCAN_DPI = 300.0
"""Resolution of the scans (the bench may ask for another)."""

PHOTO_SIZE = (3000, 2000)
"""Size of the phone photographs (the bench may ask for another). [px]"""


@dataclass(frozen=True)
class ForeignCase:
    """A measurement on a foreign record.

    Attributes
    ----------
    toml : Path
        The measurement file.
    image : Path
        The record's image.
    truth : dict
        Result name (as in the lab's result JSON) → true value, SI.
    refuse : str or None
        Why the lab must refuse the file, where it cannot be reduced (a cause a student can
        act on), else None.
    params : dict
        The scene's settings, for the bench's table.
    scene : StripScene or None
        The rendered record (its traces' signals, the lines drawn), for diagnostics.
    """

    toml: Path
    image: Path
    truth: dict
    refuse: str | None = None
    params: dict = field(default_factory=dict)
    scene: StripScene | None = field(default=None, repr=False)


def _capture(rng: np.random.Generator, capture: str, *, dpi: float, size: tuple[int, int]):
    if capture == "scan":
        return Scan.draw(rng, dpi=dpi)
    if capture == "photo":
        return Photo.draw(rng, size=size)
    raise ValueError(f"capture must be one of {CAPTURES}, got {capture!r}")


def _grid(rng: np.random.Generator) -> Grid:
    """A printed millimetre grid: bold every 5 or 10 mm, in one of the usual inks."""
    colour = [(90, 140, 220), (150, 200, 150), (200, 160, 120), (160, 160, 160)][
        int(rng.integers(4))]
    return Grid(pitch=0.001, major=int(rng.choice([5, 10])), width=float(rng.uniform(6e-5, 1.4e-4)),
                density=float(rng.uniform(0.15, 0.35)), colour=colour,
                origin=tuple(float(v) for v in rng.uniform(0, 0.005, 2)))


def lab3_scene(seed: int, folder, *, capture: str = "scan", zero_line: bool | None = None,
               scale_given: bool | None = None, grid: bool | None = None,
               dpi: float = SCAN_DPI, size: tuple[int, int] = PHOTO_SIZE) -> ForeignCase:
    """Lab 3: the frequency-to-voltage converter's speed trace of one steady regime.

    A four-cylinder engine (flywheel 0.1–0.25 kg·m², p_z 5–6 MPa, 2 % cycle-to-cycle
    scatter) at 1200–2000 min⁻¹; 6–9 working cycles on 200–280 mm of 100 or 120 mm paper;
    time marks every 10 ms (ticks up or down, or pips) near the lower edge, a TDC mark each
    revolution near the upper edge (ticks down or pips up), a printed grid on half the strips.
    The converter draws h = h₀ + μ(ω − ω_s): with its zero line (ω_s = 0: the beam at rest,
    h₀ 8–25 mm above the lower edge, the mean level 45–75 mm above it), or with the zero
    suppressed off the paper (no zero line: the ripple magnified to 5–16 mm), when the
    student gives the converter's calibration μ [mm per min⁻¹] and ``zero = "mean"``, or
    does not (then the lab must refuse: nothing on the file scales the trace).

    Parameters
    ----------
    seed : int
    folder : str or Path
        Where the measurement file and the image go (created).
    capture : {"scan", "photo"}
    zero_line, scale_given, grid : bool, optional
        Force the choice (default: drawn from the seed).
    dpi, size
        The scan's resolution, the photograph's size.

    Returns
    -------
    ForeignCase
        Truth ``delta_osc_1`` and ``omega_osc_1`` (δ of the mean of the whole cycles on the
        strip from its first TDC mark, their mean speed).
    """
    from processing.synth.engine import Engine, run_engine

    rng = np.random.default_rng([seed, 28, 3])
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    drawn = rng.random(3) < [0.5, 0.75, 0.5]    # drawn always: a forced choice leaves the rest
    zero_line = bool(drawn[0]) if zero_line is None else zero_line
    scale_given = bool(drawn[1]) if scale_given is None else scale_given
    grid = bool(drawn[2]) if grid is None else grid
    engine = Engine(inertia=float(rng.uniform(0.1, 0.25)), p_z=float(rng.uniform(5e6, 6e6)),
                    cycle_variation=0.02)
    n = float(np.round(rng.uniform(1200, 2000)))
    cycles = int(rng.integers(6, 10))
    run = run_engine(replace(engine, mean_angular_speed=n * np.pi / 30), cycles + 2,
                     seed=seed * 7 + 3)
    cycle_time = run.cycle_angle / run.mean_angular_speed
    lead = float(rng.uniform(0.03, 0.08)) * cycle_time
    length = float(rng.uniform(0.2, 0.28))
    duration = cycles * cycle_time * 1.02 + lead
    width = float(rng.choice([0.1, 0.12]))
    first_cycle = float(np.interp(run.cycle_angle, run.crank_angle, run.time))

    def omega(t):
        # before the first cycle's TDC mark, the same phase of the next cycle
        t = np.asarray(t, dtype=float)
        return run.speed_at_angle(run.angle_at(np.where(t < 0, t + first_cycle, t)))

    w_mean = run.mean_angular_speed
    if zero_line:
        base = float(rng.uniform(0.008, 0.025)) + 0.01 * (width - 0.1) / 0.02
        mu = (float(rng.uniform(0.045, 0.075)) - base) / w_mean
        suppressed = 0.0
    else:
        delta_guess = run.delta
        mu = float(rng.uniform(0.005, 0.016)) / (delta_guess * w_mean)
        mean_level = float(rng.uniform(0.4, 0.6)) * width
        suppressed = w_mean - mean_level / mu
        base = 0.0
    revolutions = np.interp(np.arange(0.0, run.crank_angle[-1], 2 * np.pi), run.crank_angle,
                            run.time)
    time_dir = int(rng.choice([1, -1]))
    time_shape = str(rng.choice(["tick", "tick", "pip"]))
    tdc_shape = str(rng.choice(["tick", "pip"]))
    strip = Strip(
        length=length, width=width, speed=length / duration, start=-lead,
        traces=(Trace(lambda t: omega(t) - suppressed, base, mu, zero_line=zero_line),),
        marks=(Marks(np.arange(-0.01 * np.ceil(lead / 0.01), duration, 0.01),
                     float(rng.uniform(0.004, 0.007)), shape=time_shape,
                     direction=time_dir if time_shape == "tick" else 1,
                     size=float(rng.uniform(0.0015, 0.003)),
                     duration=float(rng.uniform(0.0015, 0.0025)) if time_shape == "tick"
                     else 0.003, rise=float(rng.uniform(0.25, 0.4)), role="time"),
               Marks(revolutions, width - float(rng.uniform(0.006, 0.01)), shape=tdc_shape,
                     direction=-1 if tdc_shape == "tick" else 1,
                     size=float(rng.uniform(0.002, 0.004)),
                     duration=float(rng.uniform(0.002, 0.003)),
                     rise=float(rng.uniform(0.25, 0.4)), role="tdc")),
        grid=_grid(rng) if grid else None)
    shot = _capture(rng, capture, dpi=dpi, size=size)
    scene = expose(strip, shot, seed=seed)
    image = scene.write(folder / f"lab3_{capture}_{seed}{scene.suffix}")
    n_tach = round(n + float(rng.normal(0, 2)))
    delta, speed = run.cycles_within(duration - lead)
    mm_per_rpm = mu * 1e3 * np.pi / 30
    regime = (f'[[regime]]\noscillogram = "{image.name}"\nn_tach = "{n_tach} ± 5 rpm"\n')
    image_table = '[image]\nmark_period = "10 ms"\n'
    image_table += (f'dpi = "{shot.dpi:g}"\n' if capture == "scan"
                    else f'paper_width = "{width * 1e3:g} mm"\n')
    if not zero_line and scale_given:
        regime += f'converter_scale = "{mm_per_rpm:.5g} ± {0.01 * mm_per_rpm:.2g} mm/rpm"\n'
        image_table += 'zero = "mean"\n'
    toml = folder / f"lab3_{capture}_{seed}.toml"
    toml.write_text(f'lab = "lab3"\n[meta]\nstudent = "foreign record (seed {seed})"\n\n'
                    '[engine]\nstrokes = 4\ncylinders = 4\nkind = "automotive"\n\n'
                    f'{regime}\n{image_table}', encoding="utf-8")
    truth = {"delta_osc_1": float(delta), "omega_osc_1": float(speed)}
    (folder / f"lab3_{capture}_{seed}_answer.json").write_text(json.dumps({"results": truth}))
    refuse = None if zero_line or scale_given else "no zero line and no converter scale"
    params = {"lab": "lab3", "seed": seed, "capture": capture, "zero_line": zero_line,
              "scale_given": scale_given, "grid": grid,
              "lid": "light" if capture == "scan" and min(shot.lid) > 128 else
              "dark" if capture == "scan" else "", "n": n, "cycles": cycles,
              "expected_refusal": refuse or ""}
    return ForeignCase(toml, image, truth, refuse, params, scene)


PAPER_WIDTH = 0.12
"""Width of the oscillograph's paper the labs' ``[image]`` tables name (120 mm). [m]"""


def paper(capture: str, rng: np.random.Generator, *, dpi: float = SCAN_DPI,
          size: tuple[int, int] = PHOTO_SIZE, chosen: dict | None = None):
    """A drawer of a lab's paper record on a strip of the second family, for the labs'
    ``write_synthetic(..., image=True, draw=...)``.

    Each record it draws gets a strip of its own from ``rng``: the whole record over
    220–300 mm of :data:`PAPER_WIDTH` paper; the time marks near the lower edge as ticks up
    or down, pips, dashes or dots (lasting 15–35 % of their period); the TDC marks (if any)
    near the upper edge as ticks down, pips or dashes; the beams' zero lines on half the
    strips, a printed grid on half; each beam exposed so that its fastest stroke still
    shows (an operator sets the lamp for the record); captured as ``capture``
    (:meth:`~processing.synth.paper_strip.Scan.draw`, :meth:`~.Photo.draw`).

    Parameters
    ----------
    capture : {"scan", "photo"}
    rng : numpy.random.Generator
    dpi, size
        The scan's resolution, the photograph's size.
    chosen : dict, optional
        Filled with each record's drawn settings (file name → dict), for the bench's table.

    Returns
    -------
    callable
        ``draw(stem, signals, *, duration, gain, zeros, mark_period, tdc_times, seed) ->
        Path``: the record's signals [unit] over ``duration`` [s], ``gain`` [m per unit] about
        each zero [m above the lower edge], written as ``stem`` with the capture's suffix.
    """
    def draw(stem, signals, *, duration, gain, zeros, mark_period, tdc_times, seed) -> Path:
        length = float(rng.uniform(0.22, 0.3))
        speed = length / duration
        lamp = [6.0 * max(1.0, _stroke_speed(f, duration, gain) / speed / 2) for f in signals]
        zero_line, grid = (bool(v) for v in rng.random(2) < 0.5)
        marks = [_time_marks(rng, mark_period, duration)]
        if len(tdc_times):
            marks.append(_tdc_marks(rng, tdc_times, mark_period))
        strip = Strip(length=length, width=PAPER_WIDTH, speed=speed,
                      traces=tuple(Trace(f, z, gain, zero_line=zero_line, exposure=e)
                                   for f, z, e in zip(signals, zeros, lamp)),
                      marks=tuple(marks), grid=_grid(rng) if grid else None)
        shot = _capture(rng, capture, dpi=dpi, size=size)
        scene = expose(strip, shot, seed=seed)
        path = scene.write(Path(stem).with_suffix(scene.suffix))
        if chosen is not None:
            chosen[path.name] = {"zero_line": zero_line, "grid": grid,
                                 "time_marks": f"{marks[0].shape}{'+-'[marks[0].direction < 0]}",
                                 "lid": _lid(capture, shot)}
        return path

    return draw


def _stroke_speed(signal, duration: float, gain: float) -> float:
    """The beam's fastest speed across the paper over the record. [m/s]"""
    t = np.linspace(0.0, duration, 20001)
    return float(np.max(np.abs(np.diff(gain * np.asarray(signal(t), dtype=float))))
                 / (t[1] - t[0]))


def _time_marks(rng: np.random.Generator, period: float, duration: float) -> Marks:
    shape = str(rng.choice(["tick", "tick", "pip", "dash", "dot"]))
    return Marks(np.arange(0.0, duration, period), float(rng.uniform(0.004, 0.008)),
                 shape=shape, direction=int(rng.choice([1, -1])) if shape == "tick" else 1,
                 size=float(rng.uniform(0.0006, 0.001)) if shape == "dot"
                 else float(rng.uniform(0.0015, 0.003)),
                 duration=float(rng.uniform(0.15, 0.35)) * period,
                 rise=float(rng.uniform(0.2, 0.4)), role="time")


def _tdc_marks(rng: np.random.Generator, times, period: float) -> Marks:
    shape = str(rng.choice(["tick", "pip", "dash"]))
    return Marks(np.asarray(times, dtype=float), PAPER_WIDTH - float(rng.uniform(0.006, 0.01)),
                 shape=shape, direction=-1 if shape == "tick" else 1,
                 size=float(rng.uniform(0.002, 0.004)),
                 duration=float(rng.uniform(0.3, 0.5)) * period,
                 rise=float(rng.uniform(0.2, 0.4)), role="tdc")


def _lid(capture: str, shot) -> str:
    if capture != "scan":
        return ""
    return "light" if min(shot.lid) > 128 else "dark"


def _read_truth(answer: Path, names) -> dict:
    results = json.loads(answer.read_text(encoding="utf-8"))["results"]
    return {k: float(results[k]) for k in names}


def lab7_scene(seed: int, folder, *, capture: str = "scan", dpi: float = SCAN_DPI,
               size: tuple[int, int] = PHOTO_SIZE) -> ForeignCase:
    """Lab 7: the torsiograph's records of a short sweep across a resonance, on strips.

    The lab's own scene (:func:`labs.lab7_torsiograph.write_synthetic`: a crankshaft and
    torsiograph of the seed's part, full load) at two speeds 200 min⁻¹ apart from a start
    drawn in 1300–1700 min⁻¹ (and the manual's finer steps near a resonance between them),
    each record 0.2 s of a light-beam oscillograph's strip (5 ms
    time marks, a TDC mark per revolution) drawn by :func:`paper`.

    Returns
    -------
    ForeignCase
        Truth ``phi_max_i`` of each record (its largest single oscillation's half range).
    """
    from labs import lab7_torsiograph as lab7

    rng = np.random.default_rng([seed, 28, 7])
    folder = Path(folder) / f"lab7_{capture}_{seed}"
    start = float(np.round(rng.uniform(1300, 1700), -1))
    chosen: dict = {}
    written = lab7.write_synthetic(folder, seed, image=True, speeds=(start, start + 200),
                                   step=200.0, fine=200.0, chain=False,
                                   draw=paper(capture, rng, dpi=dpi, size=size, chosen=chosen))
    _scanned(written["toml"], capture, dpi)
    names = [k for k in json.loads(written["answer"].read_text())["results"]
             if k.startswith("phi_max_")]
    return ForeignCase(written["toml"], written["r1"], _read_truth(written["answer"], names),
                       None, {"lab": "lab7", "seed": seed, "capture": capture,
                              "records": len(names), "start_rpm": start,
                              **_settings(chosen), "expected_refusal": ""})


def lab9_scene(seed: int, folder, *, capture: str = "scan", dpi: float = SCAN_DPI,
               size: tuple[int, int] = PHOTO_SIZE) -> ForeignCase:
    """Lab 9: the damper ring's free decay on a strip.

    The lab's own scene (:func:`labs.lab9_damper.write_synthetic`: the seed's damper, its
    static runs, the ring twisted and released, 35 mm of trace at the release, 1 ms time
    marks, no TDC marks) drawn by :func:`paper`.

    Returns
    -------
    ForeignCase
        Truth ``log_decrement`` (δ at the release amplitude) and ``T_d``.
    """
    from labs import lab9_damper as lab9

    rng = np.random.default_rng([seed, 28, 9])
    folder = Path(folder) / f"lab9_{capture}_{seed}"
    chosen: dict = {}
    written = lab9.write_synthetic(folder, seed, image=True,
                                   draw=paper(capture, rng, dpi=dpi, size=size, chosen=chosen))
    _scanned(written["toml"], capture, dpi)
    return ForeignCase(written["toml"], written["record"],
                       _read_truth(written["answer"], ("log_decrement", "T_d")), None,
                       {"lab": "lab9", "seed": seed, "capture": capture, **_settings(chosen),
                        "expected_refusal": ""})


def lab6_scene(seed: int, folder, *, capture: str = "scan", dpi: float = SCAN_DPI,
               size: tuple[int, int] = PHOTO_SIZE) -> ForeignCase:
    """Lab 6: the valve drive's rocker-force oscillograms on strips.

    The lab's own scene (:func:`labs.lab6_valve_dynamics.write_synthetic`: the seed's cam and
    drive, both valves' forces on one strip, 4.4 revolutions a record, 5 ms time marks, a
    TDC mark per revolution) at one clearance and two speeds 400 min⁻¹ apart from a start
    drawn in 900–1300 min⁻¹, each record drawn by :func:`paper`.

    Returns
    -------
    ForeignCase
        Truth ``n_i`` (each record's speed, from its TDC marks and time base) and
        ``P_max_v_i`` (each valve's largest force).
    """
    from labs import lab6_valve_dynamics as lab6

    rng = np.random.default_rng([seed, 28, 6])
    folder = Path(folder) / f"lab6_{capture}_{seed}"
    start = float(np.round(rng.uniform(900, 1300), -1))
    chosen: dict = {}
    written = lab6.write_synthetic(folder, seed, image=True, speeds=(start, start + 400),
                                   clearances=(float(rng.choice([0.3e-3, 0.5e-3])),),
                                   draw=paper(capture, rng, dpi=dpi, size=size, chosen=chosen))
    _scanned(written["toml"], capture, dpi)
    names = [k for k in json.loads(written["answer"].read_text())["results"]
             if re.fullmatch(r"n_\d+|P_max_(in|ex)_\d+", k)]
    return ForeignCase(written["toml"], written["r1"], _read_truth(written["answer"], names),
                       None, {"lab": "lab6", "seed": seed, "capture": capture,
                              "start_rpm": start, **_settings(chosen), "expected_refusal": ""})


def _scanned(toml: Path, capture: str, dpi: float) -> None:
    """A scan's measurement file gives the scanner's resolution for the length scale, as a
    student with a scan does (a light lid may hide the sheet's edges)."""
    if capture == "scan":
        text = toml.read_text(encoding="utf-8")
        toml.write_text(text.replace(f'paper_width = "{PAPER_WIDTH * 1e3:g} mm"',
                                     f'dpi = "{dpi:g}"'), encoding="utf-8")


def _settings(chosen: dict) -> dict:
    """The drawn settings of a scene's records, for the bench's table (several records'
    joined by '/')."""
    keys = ("zero_line", "grid", "time_marks", "lid")
    return {k: "/".join(str(c[k]) for c in chosen.values()) for k in keys}


SCENES = {"lab3": lab3_scene, "lab6": lab6_scene, "lab7": lab7_scene, "lab9": lab9_scene}
"""The lab scenes of the foreign-records benchmark, by lab."""
