"""Benchmark families of the free-decay reductions (lab 9's rubber damper): the decrement
against its truth and its stated uncertainty, where it breaks over SNR × record length, the
test of a decrement changing with the amplitude, and the manual's Table 1.

Every decay is made by :mod:`processing.synth.damper`: the default :class:`Ring` (0.03 kg·m²
on C_d = 4.85·10⁴ N·m/rad, about 200 Hz) released from 10 mrad with a decrement δ of 0.3 or
0.89 (the manual's damper 1), recorded by the default :class:`StrainGauge` (20 kHz, 100
samples a period, offset, drift and the rubber's creep) at the given SNR for the given
number of periods after the release. Truth: the ring's δ.

Families
--------
``decrement``
    δ from a record by ``trace fit`` (:func:`~processing.oscillations.decay.analyse_decay`: the
    damped sinusoid over the whole record, what lab 9 reports), ``peaks GLS`` (the line through the
    half ranges by generalised least squares, lab 9's check), ``peaks OLS`` (the same line by
    ordinary least squares, which ignores that neighbouring half ranges share extrema) and ``two
    maxima`` (the manual's δ = ln(φ_n/φ_{n+1}) from the first two maxima). Error δ/δ_true − 1;
    ``covered``: the truth inside the method's stated 95 % interval (Student t with its degrees of
    freedom).
``δ stability``
    ``trace fit`` and ``peaks GLS`` over SNR × periods × δ, a few seeds a cell: the map of
    where they break, and ``short``: whether the record is short by
    :data:`processing.oscillations.decay.FEW_PERIODS` (lab 9 warns there).
``amplitude trend``
    :func:`~processing.oscillations.decay.decrement_trend` (inside ``analyse_decay``) on rings whose
    decrement falls with the amplitude as (A/φ₀)^p, p ∈ {0, 0.1, 0.3}: error 1 where it
    answers wrongly (a trend seen at p = 0, or missed at p > 0).
``baseline drift``
    ``trace fit`` on records whose baseline drifts beyond the gauge's own
    (:class:`~processing.synth.damper.BridgeDrift`: a ramp and a bent ramp of 3–20 % of the
    release twist, a settling step of 3–20 % with τ of 0.5–6 periods, a slow wander of three
    sines of 1–5 %), a damper drawn per seed as lab 9's variants (δ 0.71–0.90, 150–260 Hz),
    30–50 dB, 5–10 periods: δ and T against the truth, and whether the 95 % intervals of
    :meth:`~processing.oscillations.decay.RecordedDecay.measured_delta` and ``measured_period`` (the
    baseline model's spread included) hold them; ``U_ratio``: U/|error|.
``table 1``
    The manual's worked table (lab 9, Table 1): the secant M_max/φ_max of run 1 and the
    runs' mean slope of the loading branch against the printed C ≈ 2.6·10⁴ N·m/rad.
"""
from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd
from scipy import stats

from processing.oscillations.decay import analyse_decay, find_peaks, log_decrement
from ..regression import fit_line
from ..synth.damper import DRIFT_KINDS, BridgeDrift, Ring, StrainGauge, free_decay
from .harness import (Case, Family, MapAxes, Method, Target, abs_error, coverage_targets,
                      environment, plot_error_time, plot_map, run_family, summary,
                      write_rows, write_targets)

DELTA_TOLERANCE = 0.02
"""δ target: |δ/δ_true − 1| in the target region, at the 95th percentile of its records."""

TARGET_SNR, TARGET_PERIODS = 30.0, 5.0
"""The target region: SNR ≥ 30 dB, records of ≥ 5 periods after the release."""

FALSE_ALARMS = 0.03
"""Largest share of viscous decays in the target region in which a trend may be seen."""

MISSES = 0.05
"""Largest share of decays in the target region whose δ falls as (A/φ₀)^p, p ≥ 0.1, in which
the trend may go unseen."""

TABLE1 = ((np.array([0, 90, 180, 270, 315]), np.array([0, 2.69, 6.15, 9.91, 12.12]) * 1e-3),
          (np.array([0, 90, 180, 270, 315]), np.array([0, 2.46, 5.79, 9.55, 11.56]) * 1e-3))
"""The loading branches of the manual's Table 1 (lab 9), with the gauge's zero: M [N·m],
φ [rad]."""

PRINTED_C = 2.6e4
"""The manual's C for Table 1, printed to two digits (half a digit: 0.05·10⁴). [N·m/rad]"""

FAILURES = (ValueError, RuntimeError)
"""What a reduction raises when a record holds too little decay."""


@dataclass(frozen=True)
class Plan:
    """How much to run: the accuracy grid, the stability grid and the timed runs per call."""

    snr_db: tuple[float, ...]
    periods: tuple[float, ...]
    decrements: tuple[float, ...]
    seeds: int
    map_snr_db: tuple[float, ...]
    map_periods: tuple[float, ...]
    map_seeds: int
    trend_seeds: int
    drift_seeds: int
    repeat: int


FULL = Plan(snr_db=(20, 30, 40, 50), periods=(5, 8), decrements=(0.3, 0.89), seeds=100,
            map_snr_db=(10, 15, 20, 25, 30, 40), map_periods=(1.5, 2, 3, 5, 8), map_seeds=10,
            trend_seeds=40, drift_seeds=40, repeat=3)
QUICK = Plan(snr_db=(20, 30, 40), periods=(5, 8), decrements=(0.3, 0.89), seeds=25,
             map_snr_db=(10, 20, 30, 40), map_periods=(1.5, 2, 5), map_seeds=3,
             trend_seeds=10, drift_seeds=8, repeat=1)

MAP_AXES = MapAxes(x="periods", y="snr_db", column="decrement",
                   labels={"periods": "record after the release [periods]",
                           "snr_db": "SNR [dB]", "decrement": "δ"})


# --- cases -----------------------------------------------------------------------------------

@dataclass(frozen=True)
class Record:
    """A synthetic decay as the methods get it."""

    time: np.ndarray
    signal: np.ndarray


def decay_cases(snr_db, periods, decrements, seeds: int, *,
                exponents=(0.0,)) -> Iterator[Case]:
    """One case per (SNR, periods, δ, p, seed): the record, and the true δ at the release."""
    for snr, n, delta, p, seed in itertools.product(snr_db, periods, decrements, exponents,
                                                    range(seeds)):
        rec = free_decay(Ring(decrement=delta, amplitude_exponent=p), StrainGauge(snr_db=snr),
                         periods=n, seed=seed)
        yield Case({"snr_db": snr, "periods": n, "decrement": delta, "exponent": p,
                    "seed": seed}, Record(rec.time, rec.signal), rec.truth["log_decrement"],
                   rec.signal.size)


# --- the decrement ---------------------------------------------------------------------------

@dataclass(frozen=True)
class Answer:
    """A method's δ, its 95 % half-width (NaN: none stated) and whether the record is short."""

    delta: float
    half95: float = math.nan
    short: float = math.nan


def _trace(rec: Record) -> Answer:
    d = analyse_decay(rec.time, rec.signal)
    return Answer(d.trace.delta, 1.959964 * d.trace.u("delta"), float(d.short))


def _peaks(rec: Record, *, gls: bool) -> Answer:
    found = find_peaks(rec.time, rec.signal)
    fit = log_decrement(found.amplitudes, step=0.5, half_ranges=gls)
    return Answer(fit.delta, fit.u_delta * float(stats.t.ppf(0.975, fit.dof)))


def _two_maxima(rec: Record) -> Answer:
    a = find_peaks(rec.time, rec.signal).amplitudes
    if a.size < 3:
        raise ValueError(f"{a.size} half ranges; two maxima a period apart need three")
    return Answer(float(np.log(a[0] / a[2])))


def decrement_error(answer: Answer, truth: float) -> dict:
    """δ/δ_true − 1, whether the stated 95 % interval holds the truth, and ``short``."""
    covered = abs(answer.delta - truth) <= answer.half95 if math.isfinite(answer.half95) \
        else np.nan
    return {"error": answer.delta / truth - 1, "covered": covered,
            "u_rel": answer.half95 / 1.959964 / truth, "short": answer.short}


def decrement_family(name: str = "decrement", methods=("trace fit", "peaks GLS", "peaks OLS",
                                                         "two maxima")) -> Family:
    """The δ methods of the module's notes."""
    calls: dict[str, Callable] = {
        "trace fit": _trace, "peaks GLS": lambda r: _peaks(r, gls=True),
        "peaks OLS": lambda r: _peaks(r, gls=False), "two maxima": _two_maxima}
    return Family(name, [Method(m, calls[m]) for m in methods], decrement_error,
                  error_label="|δ/δ_true − 1|", failures=FAILURES)


def trend_error(answer: bool, truth: float) -> dict:
    """1 where the trend test answers wrongly (truth: the exponent p)."""
    return {"error": float(answer != (truth > 0)), "flagged": float(answer)}


def trend_family() -> Family:
    return Family("amplitude trend", [Method("curved envelope", lambda r: analyse_decay(
        r.time, r.signal).trend.significant())], trend_error, error_label="wrong answer",
        failures=FAILURES)


def trend_cases(plan: Plan) -> Iterator[Case]:
    for case in decay_cases((TARGET_SNR, 40.0), (TARGET_PERIODS, 8.0), (0.89,),
                            plan.trend_seeds, exponents=(0.0, 0.1, 0.3)):
        yield Case(case.params, case.data, case.params["exponent"], case.samples)


# --- a drifting baseline -------------------------------------------------------------------

DRIFT_SIZES = {"linear": (0.03, 0.2), "quadratic": (0.03, 0.2), "settling": (0.03, 0.2),
               "wander": (0.01, 0.05)}
"""Sizes of each :class:`BridgeDrift` drawn, as fractions of the release twist."""

DRIFT_SNR = 35.0
"""δ within 1 % is asked of drifted records from this SNR on (at 30–35 dB the noise alone
puts the 95th percentile near 1.7 %, drift or none). [dB]"""


def drift_cases(seeds: int) -> Iterator[Case]:
    """One record per drift kind and seed; truth: (δ, T_d) at the release."""
    for kind, seed in itertools.product(DRIFT_KINDS, range(seeds)):
        rng = np.random.default_rng([seed, 778])
        frequency = rng.uniform(150.0, 260.0)
        ring = Ring(inertia=Ring().stiffness / (2 * np.pi * frequency) ** 2,
                    decrement=rng.uniform(0.71, 0.90))
        drift = BridgeDrift(kind, rng.uniform(*DRIFT_SIZES[kind]), rng.uniform(0.5, 6.0), seed)
        snr = rng.uniform(30.0, 50.0)
        rec = free_decay(ring, StrainGauge(snr_db=snr), periods=rng.uniform(5.0, 10.0),
                         seed=seed, drift=drift)
        yield Case({"drift": kind, "snr_db": round(snr, 1), "seed": seed},
                   Record(rec.time, rec.signal),
                   (rec.truth["log_decrement"], rec.truth["T_d"]), rec.signal.size)


def _drifted(rec: Record):
    d = analyse_decay(rec.time, rec.signal)
    return d.measured_delta(), d.measured_period()


def drift_error(answer, truth) -> dict:
    """δ/δ_true − 1, T/T_true − 1, whether each 95 % interval (k = 2) holds its truth, and
    U/|error| (how wide the interval is against the error it must hold)."""
    (delta, period), (d_true, t_true) = answer, truth
    out = {"error": delta.value / d_true - 1, "T_error": period.value / t_true - 1}
    for name, m, true in (("", delta, d_true), ("T_", period, t_true)):
        miss = abs(m.value - true)
        out[f"{name}covered"] = miss <= 2 * m.u
        out[f"{name}U_ratio"] = 2 * m.u / miss if miss > 0 else np.inf
    return out


def drift_family() -> Family:
    return Family("baseline drift", [Method("trace fit", _drifted)], drift_error,
                  error_label="|δ/δ_true − 1|", failures=FAILURES)


def drift_targets(frame: pd.DataFrame) -> list[Target]:
    """Coverage of δ's and T's intervals over the drifted records, δ within 1 %."""
    part = frame[frame["family"] == "baseline drift"]
    if part.empty:
        return []
    ok = part[part["failed"].fillna("") == ""]
    clean = ok[ok["snr_db"] >= DRIFT_SNR]
    ratio = f"median U/|error|: δ {ok['U_ratio'].median():.2g}, T {ok['T_U_ratio'].median():.2g}"
    return (coverage_targets("δ on a drifting baseline", ok["covered"], ratio)[:1]
            + coverage_targets("T on a drifting baseline", ok["T_covered"], ratio)[:1]
            + [Target(f"δ on a drifting baseline, ≥ {DRIFT_SNR:g} dB: 95th percentile of "
                      "|δ/δ_true − 1|", float(np.quantile(abs_error(clean), 0.95)), 0.01,
                      unit="relative", detail=f"{len(clean)} records; "
                      f"{len(part) - len(ok)} of {len(part)} refused")])


def drift_table(frame: pd.DataFrame) -> pd.DataFrame:
    """Per drift: median and largest |δ error| [%], coverage of δ and T [%], U/|error|."""
    part = frame[(frame["family"] == "baseline drift") & (frame["failed"].fillna("") == "")]
    part = part.assign(abs_error=100 * abs_error(part),
                       covered=100 * part["covered"].astype(float),
                       T_covered=100 * part["T_covered"].astype(float))
    return part.groupby("drift").agg(
        median_err=("abs_error", "median"), worst=("abs_error", "max"),
        covered=("covered", "mean"), T_covered=("T_covered", "mean"),
        U_ratio=("U_ratio", "median"), T_U_ratio=("T_U_ratio", "median"))


# --- the manual's table ----------------------------------------------------------------------

def table1_family() -> Family:
    """Secant of run 1 and the mean loading slope of the manual's Table 1."""
    def secant(_):
        M, phi = TABLE1[0]
        return M[-1] / phi[-1]

    def slope(_):
        return float(np.mean([1.0 / fit_line(M, phi).slope for M, phi in TABLE1]))

    return Family("table 1", [Method("secant, run 1", secant), Method("loading slope", slope)],
                  lambda c, truth: {"error": c / truth - 1, "printed": round(c / 1e4, 1)},
                  error_label="C/C_printed − 1")


# --- targets and summaries -------------------------------------------------------------------

def target_region(frame: pd.DataFrame, family: str = "decrement") -> pd.DataFrame:
    """Rows of ``family`` at SNR ≥ 30 dB and ≥ 5 periods."""
    f = frame[frame["family"] == family]
    return f[(f["snr_db"] >= TARGET_SNR) & (f["periods"] >= TARGET_PERIODS)]


def targets(frame: pd.DataFrame) -> list[Target]:
    """The performance targets from the rows of :func:`run`."""
    region = target_region(frame)
    out = []
    trace = region[region["method"] == "trace fit"]
    if not trace.empty:
        err = abs_error(trace)
        worst = trace.loc[err.idxmax()]
        out.append(Target(
            f"δ, trace fit, ≥ {TARGET_SNR:g} dB, ≥ {TARGET_PERIODS:g} periods, δ "
            f"{', '.join(f'{d:g}' for d in sorted(trace['decrement'].unique()))}: 95th "
            "percentile of |δ/δ_true − 1|", float(np.quantile(err, 0.95)), DELTA_TOLERANCE,
            unit="relative", detail=f"{len(trace)} records; worst {err.max():.4g} at "
            f"{worst['snr_db']:g} dB, {worst['periods']:g} periods, δ {worst['decrement']:g}, "
            f"seed {worst['seed']:g}"))
        out += coverage_targets("δ, trace fit", trace["covered"])
    gls = region[(region["method"] == "peaks GLS") & (region["failed"].fillna("") == "")]
    if not gls.empty:
        out += coverage_targets("δ, line through the half ranges (GLS)", gls["covered"],
                                "records with ≥ 3 half ranges")[:1]
    quiet = target_region(frame, "δ stability")
    quiet = quiet[quiet["method"] == "trace fit"]
    if not quiet.empty:
        out.append(Target("short-record warnings in the target region",
                          float(quiet["short"].astype(float).mean()), 0.05,
                          detail=f"{len(quiet)} records of the stability grid"))
    trend = target_region(frame, "amplitude trend")
    if not trend.empty:
        viscous = trend[trend["exponent"] == 0]
        out.append(Target("amplitude trend seen in viscous decays (false alarms)",
                          float(viscous["error"].mean()), FALSE_ALARMS,
                          detail=f"{len(viscous)} records"))
        real = trend[trend["exponent"] > 0]
        out.append(Target("amplitude trend missed where δ ∝ A^p, p ≥ 0.1",
                          float(real["error"].mean()), MISSES, detail=f"{len(real)} records"))
    out += drift_targets(frame)
    silent = silent_failures(frame)
    if silent is not None:
        out.append(Target("stability-grid cells beyond the δ tolerance that are neither refused "
                          "nor warned of nor inside the stated U", float(len(silent)), 0,
                          unit="cells", detail=", ".join(
                              f"δ {d:g}, {snr:g} dB, {n:g} periods" for d, snr, n in silent)
                          or "none"))
    for _, row in frame[frame["family"] == "table 1"].iterrows():
        out.append(Target(f"Table 1 (manual, lab 9): C by {row['method']} to the printed "
                          f"2.6·10⁴ N·m/rad", abs(row["error"]), 0.05 / 2.6,
                          unit="relative", detail=f"{row['printed']:.1f}·10⁴ as printed"))
    return out


def silent_failures(frame: pd.DataFrame) -> list[tuple] | None:
    """Cells (δ, SNR, periods) of the stability grid where the trace fit's median |error|
    exceeds :data:`DELTA_TOLERANCE` while most of its records are neither refused nor called
    short and the median stated 95 % half-width is smaller than that error: where a report
    would be wrong without saying so. None without a stability grid."""
    part = frame[(frame["family"] == "δ stability") & (frame["method"] == "trace fit")]
    if part.empty:
        return None
    part = part.assign(abs_error=abs_error(part), U=1.959964 * part["u_rel"],
                       refused=part["failed"].fillna("") != "",
                       short=part["short"].astype(float))
    cells = part.groupby(["decrement", "snr_db", "periods"]).agg(
        err=("abs_error", "median"), U=("U", "median"), refused=("refused", "mean"),
        short=("short", "mean"))
    silent = cells[(cells["err"] > DELTA_TOLERANCE) & (cells["refused"] < 0.5)
                   & (cells["short"].fillna(0) < 0.5) & ~(cells["U"] >= cells["err"])]
    return list(silent.index)


def decrement_table(frame: pd.DataFrame) -> pd.DataFrame:
    """Per method, SNR, periods and δ: median |error| [%], coverage [%] and failures."""
    part = frame[frame["family"] == "decrement"]
    part = part.assign(abs_error=100 * abs_error(part),
                       covered=100 * part["covered"].astype(float),
                       failed=(part["failed"].fillna("") != "").astype(int))
    return part.groupby(["method", "snr_db", "periods", "decrement"]).agg(
        median_err=("abs_error", "median"), covered=("covered", "mean"),
        failed=("failed", "sum"))


def stability_table(frame: pd.DataFrame) -> pd.DataFrame:
    """The trace fit over the stability grid: median |error| [%], refusals, and the share of
    records lab 9 calls short [%]."""
    part = frame[(frame["family"] == "δ stability") & (frame["method"] == "trace fit")]
    part = part.assign(abs_error=100 * abs_error(part),
                       failed=(part["failed"].fillna("") != "").astype(int),
                       short=100 * part["short"].astype(float))
    return part.groupby(["decrement", "snr_db", "periods"]).agg(
        median_err=("abs_error", "median"), refused=("failed", "sum"),
        short=("short", "mean")).unstack("periods")


def summary_lines(frame: pd.DataFrame) -> list[str]:
    """The summary printed after the run."""
    def fmt(v):
        return f"{v:.3g}"

    return ["Summary (median over cases; |err| relative):",
            summary(frame).to_string(index=False, float_format=fmt), "",
            "δ by case: median |δ/δ_true − 1| [%], coverage of the stated 95 % interval [%]:",
            decrement_table(frame).to_string(float_format=fmt), "",
            "Stability of the trace fit: median |error| [%], records refused (fewer than "
            "three extrema), records called short [%]:",
            stability_table(frame).to_string(float_format=fmt), "",
            "Drifting baselines: |δ error| [%], coverage of δ's and T's intervals [%], "
            "U/|error|:", drift_table(frame).to_string(float_format=fmt)]


def run(out, *, quick: bool = False,
        log: Callable[[str], None] = print) -> tuple[pd.DataFrame, list[Target]]:
    """Run every family, write ``bench.csv``, the charts and ``targets.json`` to ``out``.

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
        All rows (also ``bench.csv``).
    targets : list of Target
    """
    plan = QUICK if quick else FULL
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    log(f"decrement: SNR {plan.snr_db} dB x periods {plan.periods} x delta {plan.decrements} "
        f"x {plan.seeds} seeds")
    rows = run_family(decrement_family(), decay_cases(plan.snr_db, plan.periods,
                                                      plan.decrements, plan.seeds),
                      repeat=plan.repeat)
    log(f"stability map: SNR {plan.map_snr_db} dB x periods {plan.map_periods} x "
        f"{plan.map_seeds} seeds")
    rows += run_family(decrement_family("δ stability", ("trace fit", "peaks GLS")),
                       decay_cases(plan.map_snr_db, plan.map_periods, plan.decrements,
                                   plan.map_seeds), repeat=1)
    log(f"amplitude trend: p in (0, 0.1, 0.3) x {plan.trend_seeds} seeds")
    rows += run_family(trend_family(), trend_cases(plan), repeat=1)
    log(f"baseline drift: {DRIFT_KINDS} x {plan.drift_seeds} seeds")
    rows += run_family(drift_family(), drift_cases(plan.drift_seeds), repeat=1)
    rows += run_family(table1_family(), [Case({}, None, PRINTED_C, 9)], repeat=1)
    frame = write_rows(rows, out / "bench.csv")
    plot_error_time(frame, out / "error_vs_time.png",
                    {"decrement": decrement_family().error_label})
    plot_map(frame[frame["family"] == "δ stability"], out / "stability_map.png", MAP_AXES,
             threshold=DELTA_TOLERANCE)
    found = targets(frame)
    write_targets(found, out / "targets.json", environment())
    return frame, found
