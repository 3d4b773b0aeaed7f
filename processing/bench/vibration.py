"""Benchmark families of the engine-vibration lab (lab 4): band RMS acceleration, velocity and
displacement against their truth and their time, the band chain's throughput, and the cut
cylinder's detection.

Every record is made by :mod:`processing.synth.engine_mount`: a four-cylinder engine (firing
order 1-3-4-2) on soft mounts, three accelerometers (cylinder head vertical and transverse,
front cover longitudinal) at 25.6 kHz, white noise at the stated signal-to-noise ratio in the
worst of the three bands. Truth: the band readings of the scene's orders in closed form
(:meth:`processing.synth.engine_mount.Response.band_rms`).

Families
--------
``band rms``
    Each channel's a, v and x by ``ours`` (:func:`processing.vibration.band_rms.band_rms`: one
    Hann-windowed periodogram, the meter's weight deconvolved for the window), ``plain FFT``
    (the same weight on the unwindowed record's spectrum), ``scipy filters`` (Butterworth
    band filters of the meter's orders by :func:`scipy.signal.sosfiltfilt`, integrated by the
    trapezoid rule with the high-pass applied again after each integration, RMS of the
    result), and, when `endaq <https://pypi.org/project/endaq/>`_ is installed, ``endaq
    integrals`` (``endaq.calc.filters.butterworth`` to the band, then
    ``endaq.calc.integrate.integrals(n=2, highpass_cutoff=1.4)``, RMS) and ``endaq welch``
    (``endaq.calc.psd.welch`` density, 1 Hz bins, through the same meter weight: each
    segment loses its plain mean, not its Hann-weighted one, so what is left in the DC bin
    spills into the 1 Hz bin, where the displacement's weight is large: x errs by
    30–640 % on these records, whose orders lie above 6 Hz and whose x is a few µm). Error:
    the worst of |X/X_true − 1| over a, v, x (also per quantity: ``err_a`` …).
``throughput``
    ``ours`` on white noise of 2¹⁴…2²² samples (``cold``: its per-length weights computed in
    the call; ``warm``: cached, as for a sweep of records of one length).
``cut cylinder``
    :func:`processing.vibration.misfire.find_cut_cylinder` on the transverse channel, each cylinder
    cut in turn and no cylinder cut, against a healthy record at the same speed: error 0 when the
    finding is right (the cut cylinder, or none), 1 when not.
"""
from __future__ import annotations

import itertools
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from processing.vibration.band_rms import (BANDS, QUANTITIES, band_rms, clear_weights, meter_gain,
                                           white_noise_rms)
from processing.crank.dynamics import firing_phases
from processing.speed.edges import detect_edges
from processing.vibration.misfire import find_cut_cylinder
from processing.torsional.orders import order_fit
from ..synth.engine import Engine
from ..synth.engine_mount import POINTS, Accelerometer, Block, cylinder_factors, record
from processing.torsional.torsiogram import revolutions, steady_crank_angle
from .harness import (Case, Family, Method, Target, abs_error, environment, plot_error_time,
                      plot_time_size, run_family, summary, write_rows, write_targets)

TOLERANCE = 0.01
"""|X/X_true − 1| every band reading must keep at ≥ 20 dB (issue 19)."""

ISSUE_RECORD = 2.4
"""Record length of the issue's comparison (the accuracy target's records). [s]"""

CLEAN_SNR = 50.0
"""Signal-to-noise ratio at which the noise's share is below the method's own error. [dB]"""

METHOD_TOLERANCE = 0.001
"""|X/X_true − 1| the method itself must keep (at :data:`CLEAN_SNR`)."""

THROUGHPUT = 50e6
"""Samples per second per core the band chain must reach (issue 19)."""

FIRING = (1, 3, 4, 2)


@dataclass(frozen=True)
class Plan:
    """What a run covers."""

    speeds: tuple
    snr_db: tuple
    durations: tuple
    seeds: int
    sizes: tuple
    cut_speeds: tuple
    cut_seeds: int
    repeat: int = 3


FULL = Plan(speeds=(800.0, 1300.0, 2000.0, 2700.0, 3400.0), snr_db=(20.0, 30.0, 50.0),
            durations=(1.2, 2.4, 10.0), seeds=2, sizes=tuple(2 ** k for k in range(14, 23)),
            cut_speeds=(1000.0, 2000.0, 3000.0), cut_seeds=3)
QUICK = Plan(speeds=(800.0, 2000.0, 3400.0), snr_db=(20.0, 50.0), durations=(2.4,), seeds=1,
             sizes=(2 ** 14, 2 ** 17, 2 ** 20), cut_speeds=(2000.0,), cut_seeds=1, repeat=2)


# ------------------------------------------------------------------------ band rms

def _plain_fft(acc: np.ndarray, rate: float) -> dict:
    """The meter's weight on the unwindowed record's periodogram."""
    spectrum = np.fft.rfft(acc - acc.mean())
    f = np.fft.rfftfreq(acc.size, 1 / rate)
    power = 2 * np.abs(spectrum) ** 2 / acc.size ** 2
    return {q: float(np.sqrt(np.sum(power * meter_gain(f, q) ** 2))) for q in QUANTITIES}


def _scipy_filters(acc: np.ndarray, rate: float) -> dict:
    """By hand: band filters forward and back, trapezoid integration, high-pass again."""
    from scipy.integrate import cumulative_trapezoid
    from scipy.signal import butter, sosfiltfilt

    def band(x, q):
        b = BANDS[q]
        hp = butter(b.order, b.low, "highpass", fs=rate, output="sos")
        lp = butter(b.order, b.high, "lowpass", fs=rate, output="sos")
        return sosfiltfilt(lp, sosfiltfilt(hp, x))

    hp1 = butter(2, BANDS["a"].low, "highpass", fs=rate, output="sos")
    a = band(acc, "a")
    v = sosfiltfilt(hp1, cumulative_trapezoid(acc - acc.mean(), dx=1 / rate, initial=0))
    x = sosfiltfilt(hp1, cumulative_trapezoid(v, dx=1 / rate, initial=0))
    return {"a": float(np.sqrt(np.mean(a ** 2))), "v": float(np.sqrt(np.mean(band(v, "v") ** 2))),
            "x": float(np.sqrt(np.mean(band(x, "x") ** 2)))}


def _endaq_methods() -> list[Method]:
    """endaq's routes, if it is installed (it is optional)."""
    try:
        import endaq.calc.filters as filters
        import endaq.calc.integrate as integrate
        import endaq.calc.psd as psd
    except ImportError:
        return []

    def frame(acc, rate):
        return pd.DataFrame({"acc": acc}, index=pd.Index(np.arange(acc.size) / rate, name="t"))

    def integrals(data):
        acc, rate = data
        out = {}
        for q in QUANTITIES:
            b = BANDS[q]
            banded = filters.butterworth(frame(acc, rate), low_cutoff=b.low, high_cutoff=b.high)
            series = integrate.integrals(banded, n=2, highpass_cutoff=b.low)
            out[q] = float(np.sqrt(np.mean(series["avx".index(q)]["acc"].to_numpy() ** 2)))
        return out

    def welch(data):
        acc, rate = data
        density = psd.welch(frame(acc, rate), bin_width=1.0, scaling="density")
        f = density.index.to_numpy(dtype=float)
        p = density["acc"].to_numpy()
        df = f[1] - f[0]
        return {q: float(np.sqrt(np.sum(p * meter_gain(f, q) ** 2) * df)) for q in QUANTITIES}

    return [Method("endaq integrals", integrals, "butterworth + integrals(n=2)"),
            Method("endaq welch", welch, "1 Hz bins")]


def _band_error(estimate: dict, truth: dict) -> dict:
    errors = {f"err_{q}": estimate[q] / truth[q] - 1 for q in QUANTITIES}
    worst = max(errors.values(), key=abs)
    return {"error": worst, **errors}


def band_family() -> Family:
    """The band readings: ours against the usual alternatives."""
    return Family("band rms", [
        Method("ours", lambda d: band_rms(*d).to_dict(), "Hann, deconvolved weight"),
        Method("plain FFT", lambda d: _plain_fft(*d), "no window"),
        Method("scipy filters", lambda d: _scipy_filters(*d), "sosfiltfilt + trapezoid"),
        *_endaq_methods()], _band_error, "worst |X/X_true − 1| over a, v, x")


def band_cases(plan: Plan) -> Iterator[Case]:
    """Each channel of the scene over speeds × SNR × durations × seeds."""
    engine, block = Engine(), Block()
    for n, snr, duration, seed in itertools.product(plan.speeds, plan.snr_db, plan.durations,
                                                    range(plan.seeds)):
        sensor = Accelerometer(snr_db=snr)
        rec = record(engine, block, POINTS, sensor, n * np.pi / 30, duration, seed=seed,
                     firing_order=FIRING)
        for p, (name, volts) in enumerate(rec.volts.items(), 1):
            acc = volts / sensor.sensitivity
            yield Case({"n_rpm": n, "snr_db": snr, "duration_s": duration, "point": p,
                        "seed": seed}, (acc, sensor.sample_rate),
                       {q: rec.truth[name][q] for q in QUANTITIES}, acc.size)


# ------------------------------------------------------------------------ throughput

def _cold(data):
    clear_weights()
    return band_rms(*data)


def throughput_family() -> Family:
    return Family("throughput", [Method("ours", _cold, "cold"),
                                 Method("ours", lambda d: band_rms(*d), "warm")],
                  lambda estimate, truth: {"error": estimate.a / truth - 1},
                  "|a/σ_band − 1| of white noise")


def throughput_cases(plan: Plan) -> Iterator[Case]:
    rng = np.random.default_rng(19)
    rate = 25600.0
    for size in plan.sizes:
        yield Case({"size": size}, (rng.standard_normal(size), rate),
                   white_noise_rms(rate, "a"), size)


# ------------------------------------------------------------------------ cut cylinder

def _orders(rec, channel: str, sensitivity: float):
    marks = detect_edges(rec.tdc, "fit") / rec.sample_rate
    revs = revolutions(marks)
    t = np.arange(rec.tdc.size) / rec.sample_rate
    return order_fit(t, 2 * steady_crank_angle(t, revs), rec.volts[channel] / sensitivity,
                     max_order=8.0)


def cut_family() -> Family:
    phases = firing_phases(4, firing_order=FIRING)

    def find(data):
        healthy, suspect = data
        return find_cut_cylinder(healthy, suspect, phases)

    return Family("cut cylinder", [Method("ours", find, "transverse channel")],
                  lambda est, truth: {"error": float(est.cylinder != truth),
                                      "rise": est.rise, "confidence": est.confidence},
                  "wrong finding (1) or right (0)")


def cut_cases(plan: Plan, snr_db: float = 20.0) -> Iterator[Case]:
    engine, block = Engine(), Block()
    sensor = Accelerometer(snr_db=snr_db)
    for n, seed in itertools.product(plan.cut_speeds, range(plan.cut_seeds)):
        factors = cylinder_factors(engine, block, np.random.default_rng([seed, 3]))
        w = n * np.pi / 30

        def fit(cut, s):
            rec = record(engine, block, POINTS[1:2], sensor, w, 2.4, seed=s, factors=factors,
                         firing_order=FIRING, cut=cut)
            return _orders(rec, "acc1", sensor.sensitivity)

        healthy = fit(None, 100 * seed)
        for cut in (0, 1, 2, 3, 4):
            suspect = fit(cut or None, 100 * seed + 1 + cut)
            yield Case({"n_rpm": n, "seed": seed, "cut": cut, "snr_db": snr_db},
                       (healthy, suspect), cut, 2 * suspect.dof)


# ------------------------------------------------------------------------ targets and run

def targets(frame: pd.DataFrame) -> list[Target]:
    """Accuracy of every band at ≥ 20 dB (ours, and the best alternative for the record),
    throughput, the cut cylinder's detection and false alarms."""
    band = frame[frame["family"] == "band rms"]
    ours = band[band["method"] == "ours"]
    long = ours[ours["duration_s"] >= ISSUE_RECORD]
    short = ours[ours["duration_s"] < ISSUE_RECORD]
    clean = ours[ours["snr_db"] >= CLEAN_SNR]
    found = [Target(f"band rms: worst |X/X_true − 1| of a, v, x at ≥ 20 dB, records ≥ "
                    f"{ISSUE_RECORD:g} s (ours)", float(abs_error(long).max()), TOLERANCE,
                    detail=f"{len(long)} channels; on {len(short)} shorter ones "
                           f"{float(abs_error(short).max()) if len(short) else float('nan'):.4f}"
                           ": the noise's own share in the few bins near 1.4 Hz"),
             Target(f"band rms: the method's own worst error (≥ {CLEAN_SNR:g} dB, any length)",
                    float(abs_error(clean).max()), METHOD_TOLERANCE,
                    detail=f"{len(clean)} channels")]
    others = band[band["method"] != "ours"]
    for method, group in others.groupby("method"):
        found.append(Target(f"band rms: ours beats {method} (its worst error over ours)",
                            float(abs_error(group).max() / max(abs_error(ours).max(), 1e-12)),
                            1.0, "min", detail="a ratio > 1: ours is the more accurate"))
    warm = frame[(frame["family"] == "throughput") & (frame["setting"] == "warm")]
    largest = warm[warm["samples"] >= 2 ** 17]
    found.append(Target("band rms chain: throughput on records ≥ 2¹⁷ samples (warm)",
                        float(largest["samples_per_second"].min()), THROUGHPUT, "min",
                        "samples/s", "one core"))
    cut = frame[frame["family"] == "cut cylinder"]
    seeded, healthy = cut[cut["cut"] > 0], cut[cut["cut"] == 0]
    found.append(Target("cut cylinder: found in every seeded scene at 20 dB",
                        float(1 - seeded["error"].mean()), 1.0, "min",
                        detail=f"{len(seeded)} scenes"))
    found.append(Target("cut cylinder: reported in a healthy scene (share)",
                        float(healthy["error"].mean()), 0.0, detail=f"{len(healthy)} scenes"))
    return found


def summary_lines(frame: pd.DataFrame) -> list[str]:
    return summary(frame).to_string(index=False).splitlines()


def run(out, *, quick: bool = False,
        log: Callable[[str], None] = print) -> tuple[pd.DataFrame, list[Target]]:
    """Run every family, write ``bench.csv``, the charts and ``targets.json`` to ``out``."""
    plan = QUICK if quick else FULL
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    log(f"band rms: speeds {plan.speeds} x SNR {plan.snr_db} dB x {plan.durations} s")
    rows = run_family(band_family(), band_cases(plan), repeat=plan.repeat)
    log(f"throughput: {plan.sizes} samples")
    rows += run_family(throughput_family(), throughput_cases(plan), repeat=plan.repeat)
    log(f"cut cylinder: {plan.cut_speeds} min⁻¹ x {plan.cut_seeds} seeds x 5")
    rows += run_family(cut_family(), cut_cases(plan), repeat=1)
    frame = write_rows(rows, out / "bench.csv")
    plot_error_time(frame[frame["family"] == "band rms"], out / "error_vs_time.png",
                    {"band rms": band_family().error_label})
    plot_time_size(frame, out / "time_vs_size.png", family="throughput",
                   target_rate=THROUGHPUT)
    found = targets(frame)
    write_targets(found, out / "targets.json", environment())
    return frame, found
