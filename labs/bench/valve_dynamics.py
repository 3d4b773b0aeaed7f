"""Benchmark families of the running valve drive (lab 6): the drive's oscillation frequency
by three estimators, and the speed at which the drive separates, against their truths and
their stated uncertainties.

Every record is made by :mod:`processing.synth.valve_drive`: the default cam and drive
(ν√(1 − ζ²)/2π ≈ 452.7 Hz, ζ = 0.06), the gauge at 1500 N per 90 mm of trace, 10 kHz, noise
σ set by the SNR (1500 N of trace over σ).

Families
--------
``ν``
    On the first whole opening of a record (:func:`processing.valvetrain.valve_force.valve_events`,
    from the valve's opening to its closing or its first loss of contact), the frequency by ``damped
    sine`` (:func:`processing.valvetrain.valve_force.free_oscillation`: what lab 6 reports),
    ``counting`` (the manual's ν = N₁/(m T_mark) in digital form: the extrema of the trace less its
    slow hump, :func:`processing.torsional.torsiogram.oscillation_frequency`) and ``spectrum peak``
    (:func:`processing.valvetrain.valve_force.oscillation_period`). Error ν/ν_true − 1; ``covered``:
    the truth inside the damped sine's stated 95 % interval.
``separation``
    Lab 6 whole (:func:`labs.lab6_valve_dynamics.write_synthetic` and ``reduce``) on a sweep
    of 1000, 1500 and 1800 min⁻¹ at 0.8 mm, the inlet only: the separation speed against
    the scene's (bisection on the simulated P_min), and whether its stated 95 % interval
    holds it.
``photographed``
    Lab 6 whole on phone photographs of the paper oscillograms (both valves, 1000, 1500 and
    1800 min⁻¹ at 0.8 mm, a drive of its own per seed), each sweep under a camera drawn of
    its own (:func:`drawn_shot`: skew, perspective, blur, noise, JPEG quality, light): every
    result of the answer key against its truth, ``covered`` whether the stated 95 %
    interval holds it; a result the key has and the lab leaves out is a row of its own.
"""
from __future__ import annotations

import itertools
import math
import tempfile
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from processing.synth.valve_drive import RPM, Cam, Drive, Gauge, record
from processing.torsional.torsiogram import extrema, oscillation_frequency
from processing.valvetrain.valve_force import (NU_POOR, free_oscillation, oscillation_period,
                                               trace_zero, valve_events)
from processing.bench.harness import (Case, Family, Method, Target, abs_error, coverage_targets,
                                      environment, plot_error_time, run_family, summary, write_rows,
                                      write_targets)

NU_TOLERANCE = 0.005
"""ν target: |ν/ν_true − 1| of the damped sine at the 95th percentile, SNR ≥ 40 dB."""

SEPARATION_TOLERANCE = 0.03
"""Separation speed target: |n_sep/n_true − 1| at the 95th percentile."""

TARGET_SNR = 40.0
"""The ν target region: SNR ≥ 40 dB (the sample's gauge: 53 dB)."""

COUNT_LEVEL = 4.0
"""Hysteresis of the counting method's extrema, in noise σ."""

FAILURES = (ValueError, RuntimeError)
"""What an estimator raises on a record it cannot read."""


@dataclass(frozen=True)
class Plan:
    """How much to run."""

    speeds: tuple[float, ...]
    clearances: tuple[float, ...]
    snr_db: tuple[float, ...]
    seeds: int
    sweeps: int
    repeat: int
    photographs: int = 0
    """Sweeps of lab 6 on photographs (the ``photographed`` family; 0: none)."""


FULL = Plan(speeds=(500.0, 1000.0, 1500.0, 2000.0), clearances=(0.3e-3, 0.5e-3, 0.8e-3),
            snr_db=(35.0, 45.0, 53.0), seeds=12, sweeps=60, photographs=12, repeat=3)
QUICK = Plan(speeds=(1000.0, 2000.0), clearances=(0.5e-3, 0.8e-3), snr_db=(40.0, 53.0),
             seeds=5, sweeps=12, photographs=2, repeat=1)


# --- ν ----------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Opening:
    """One opening of a record as the methods get it: the trace above its zero, its noise,
    and the stretch of free oscillation (opening to closing or first loss)."""

    time: np.ndarray
    force: np.ndarray
    noise: float
    start: float
    stop: float


def opening_cases(plan: Plan) -> Iterator[Case]:
    """One case per (speed, clearance, SNR, seed): the first whole opening of the inlet's
    trace, and the drive's damped frequency."""
    cam, drive = Cam(), Drive()
    for n, lash, snr, seed in itertools.product(plan.speeds, plan.clearances, plan.snr_db,
                                                range(plan.seeds)):
        gauge = Gauge(noise=90.0 / 10 ** (snr / 20), sample_rate=10e3)
        rec = record(cam, drive, gauge, lash, n * RPM, valves=("in",), seed=seed)
        x = rec.channels["in"]
        zero = trace_zero(x)
        y = x - zero.level
        events = valve_events(rec.time, y, drive.P0 / gauge.scale, noise=zero.noise)
        if not events:
            continue
        e = events[0]
        stop = e.closing if math.isnan(e.loss_start) else e.loss_start
        start = e.opening
        if not math.isnan(e.loss_start):        # the lab fits after the loss
            start, stop = e.loss_start + e.loss, e.closing
        yield Case({"n_rpm": n, "clearance_mm": 1e3 * lash, "snr_db": snr, "seed": seed},
                   Opening(rec.time, y, zero.noise, start, stop), drive.damped_frequency,
                   int(np.count_nonzero((rec.time >= start) & (rec.time <= stop))))


@dataclass(frozen=True)
class Answer:
    """A frequency and its stated 95 % half-width (NaN: none stated). [Hz]"""

    frequency: float
    half95: float = math.nan


def _stretch(o: Opening):
    keep = (o.time >= o.start) & (o.time <= o.stop)
    return o.time[keep], o.force[keep]


def _damped(o: Opening) -> Answer:
    f = free_oscillation(o.time, o.force, o.start, o.stop)
    return Answer(f.frequency, 1.959964 * f.u_frequency)


def _counting(o: Opening) -> Answer:
    t, y = _stretch(o)
    u = (t - t[0]) / (t[-1] - t[0]) * 2 - 1
    r = y - np.polynomial.legendre.legval(u, np.polynomial.legendre.legfit(u, y, 8))
    index, _ = extrema(r, COUNT_LEVEL * o.noise)
    return Answer(oscillation_frequency(t[index])[0])


def _spectrum(o: Opening) -> Answer:
    t, y = _stretch(o)
    return Answer(1.0 / oscillation_period(t, y))


def frequency_error(answer: Answer, truth: float) -> dict:
    """ν/ν_true − 1 and whether the stated 95 % interval holds the truth."""
    covered = abs(answer.frequency - truth) <= answer.half95 \
        if math.isfinite(answer.half95) else np.nan
    return {"error": answer.frequency / truth - 1, "covered": covered,
            "u_rel": answer.half95 / 1.959964 / truth}


def frequency_family() -> Family:
    calls: dict[str, Callable] = {"damped sine": _damped, "counting": _counting,
                                  "spectrum peak": _spectrum}
    return Family("ν", [Method(m, c) for m, c in calls.items()], frequency_error,
                  error_label="|ν/ν_true − 1|", failures=FAILURES)


# --- the separation speed ---------------------------------------------------------------------

@dataclass(frozen=True)
class Sweep:
    """A seed of the lab's sweep through the separation."""

    seed: int


def _lab_separation(sweep: Sweep) -> Answer:
    from labs.lab6_valve_dynamics import write_synthetic
    from labs.registry import evaluate

    with tempfile.TemporaryDirectory() as folder:
        # the scene's own drive (part 0), whose separation speed is the truth; a seed's
        # readings and noise on it
        written = write_synthetic(folder, seed=sweep.seed, speeds=(1000.0, 1500.0, 1800.0),
                                  clearances=(0.8e-3,), valves=("in",), part=0)
        result = evaluate(written["toml"], n_samples=4000)
    r = result["n_sep_in_800"]
    lo, hi = r.estimate.interval95
    return Answer(r.value, max(r.value - lo, hi - r.value))


def separation_truth() -> float:
    """The scene's separation speed at 0.8 mm. [rad/s]"""
    from processing.synth.valve_drive import separation_speed

    return separation_speed(Cam(), Drive(), 0.8e-3, 1500 * RPM, 1800 * RPM)


def separation_cases(plan: Plan) -> Iterator[Case]:
    truth = separation_truth()
    for seed in range(plan.sweeps):
        yield Case({"seed": seed}, Sweep(seed), truth, 1)


def separation_family() -> Family:
    return Family("separation", [Method("lab 6 (line through two records)", _lab_separation)],
                  frequency_error, error_label="|n_sep/n_true − 1|", failures=FAILURES)


# --- photographed oscillograms ---------------------------------------------------------------

def drawn_shot(seed: int):
    """A phone's photograph of its own: 4000 × 2000 px, the sheet filling 78–88 % of the
    width, skewed up to ± 2.5°, corners moved by up to 0.8 %, blur σ 0.6–1.8 px, noise σ
    1.5–5 grey levels, JPEG quality 75–94, 5–30 % vignetting, up to 10 % gradient."""
    from processing.synth.paper_record import Shot

    rng = np.random.default_rng([seed, 66])
    return Shot(size=(4000, 2000), fill=rng.uniform(0.78, 0.88), rotation=rng.uniform(-2.5, 2.5),
                perspective=rng.uniform(0, 0.008), blur=rng.uniform(0.6, 1.8),
                noise=rng.uniform(1.5, 5.0), jpeg=int(rng.integers(75, 95)),
                vignetting=rng.uniform(0.05, 0.3), gradient=rng.uniform(0.0, 0.1))


def _photographed(seed: int) -> list[dict]:
    """Lab 6 on a seed's photographed sweep: one row per result of its answer key."""
    import json

    from labs.lab6_valve_dynamics import write_synthetic
    from labs.registry import evaluate

    with tempfile.TemporaryDirectory() as folder:
        written = write_synthetic(folder, seed=seed, image=True, shot=drawn_shot(seed),
                                  speeds=(1000.0, 1500.0, 1800.0), clearances=(0.8e-3,),
                                  part=seed)
        truth = json.loads(written["answer"].read_text())["results"]
        result = evaluate(written["toml"], n_samples=4000)
    warned = ",".join(sorted({w.code for w in result.warnings}))
    rows = []
    for name, true in truth.items():
        row = {"family": "photographed", "method": "lab 6", "setting": "", "seed": seed,
               "result": name, "warnings": warned, "failed": "", "seconds": np.nan,
               "samples_per_second": np.nan}
        if name in result:
            r = result[name]
            lo, hi = r.estimate.interval95
            row.update(error=r.value / true - 1 if true else r.value, covered=lo <= true <= hi)
        else:
            row.update(error=np.nan, covered=np.nan, failed="not reported")
        rows.append(row)
    return rows


def photographed_targets(frame: pd.DataFrame) -> list[Target]:
    part = frame[frame["family"] == "photographed"]
    if part.empty:
        return []
    held = part["covered"].dropna().astype(bool)
    return coverage_targets("lab 6 on photographed oscillograms, every result", held,
                            "results")[:1]


# --- targets and summaries --------------------------------------------------------------------

def targets(frame: pd.DataFrame) -> list[Target]:
    """The performance targets from the rows of :func:`run`."""
    out = []
    nu = frame[(frame["family"] == "ν") & (frame["method"] == "damped sine")]
    region = nu[nu["snr_db"] >= TARGET_SNR]
    if not region.empty:
        fitted = region[region["failed"].fillna("") == ""]
        quiet = fitted[fitted["u_rel"] <= NU_POOR]
        err = abs_error(quiet)
        out.append(Target(f"ν, damped sine, ≥ {TARGET_SNR:g} dB, where lab 6 gives it without "
                          "a warning: 95th percentile of |ν/ν_true − 1|",
                          float(np.quantile(err, 0.95)), NU_TOLERANCE, unit="relative",
                          detail=f"{len(quiet)} of {len(region)} openings; "
                          f"{len(region) - len(fitted)} not fitted, "
                          f"{len(fitted) - len(quiet)} with u > {100 * NU_POOR:g} % (warned)"))
        out += coverage_targets("ν, damped sine", fitted["covered"].astype(bool), "openings")
    sep = frame[frame["family"] == "separation"]
    if not sep.empty:
        err = abs_error(sep)
        out.append(Target("separation speed at 0.8 mm: 95th percentile of |n_sep/n_true − 1|",
                          float(np.quantile(err, 0.95)), SEPARATION_TOLERANCE,
                          unit="relative", detail=f"{len(sep)} sweeps"))
        out += coverage_targets("separation speed", sep["covered"].astype(bool), "sweeps")
    return out + photographed_targets(frame)


def frequency_table(frame: pd.DataFrame) -> pd.DataFrame:
    """Per method, clearance and SNR: median and worst |error| [%], failures."""
    part = frame[frame["family"] == "ν"]
    part = part.assign(abs_error=100 * abs_error(part),
                       failed=(part["failed"].fillna("") != "").astype(int))
    return part.groupby(["method", "clearance_mm", "snr_db"]).agg(
        median_err=("abs_error", "median"), worst_err=("abs_error", "max"),
        failed=("failed", "sum"))


def summary_lines(frame: pd.DataFrame) -> list[str]:
    """The summary printed after the run."""
    def fmt(v):
        return f"{v:.3g}"

    return ["Summary (median over cases; |err| relative):",
            summary(frame).to_string(index=False, float_format=fmt), "",
            "ν by case: median and worst |ν/ν_true − 1| [%], openings not read:",
            frequency_table(frame).to_string(float_format=fmt)]


def run(out, *, quick: bool = False,
        log: Callable[[str], None] = print) -> tuple[pd.DataFrame, list[Target]]:
    """Run both families, write ``bench.csv``, the error–time chart and ``targets.json``.

    Parameters
    ----------
    out : str or Path
        Output folder (made if missing).
    quick : bool
        The coarse plan (:data:`QUICK`, under a minute) instead of :data:`FULL`.
    log : callable
        Where progress lines go.

    Returns
    -------
    frame : pandas.DataFrame
    targets : list of Target
    """
    plan = QUICK if quick else FULL
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    log(f"ν: speeds {plan.speeds} x clearances {plan.clearances} x SNR {plan.snr_db} x "
        f"{plan.seeds} seeds")
    rows = run_family(frequency_family(), opening_cases(plan), repeat=plan.repeat)
    log(f"separation: {plan.sweeps} sweeps of lab 6")
    rows += run_family(separation_family(), separation_cases(plan), repeat=1)
    log(f"photographed: {plan.photographs} sweeps of lab 6 on photographs")
    for seed in range(plan.photographs):
        rows += _photographed(seed)
    frame = write_rows(rows, out / "bench.csv")
    plot_error_time(frame, out / "error_vs_time.png",
                    {"ν": frequency_family().error_label,
                     "separation": separation_family().error_label})
    found = targets(frame)
    write_targets(found, out / "targets.json", environment())
    return frame, found
