"""Lab 3's report: the regime and pitch tables, the figures and the conclusion.

What :func:`labs.lab3_speed_irregularity.reduce` found, told in the manual's terms; nothing
here reduces data.
"""
from __future__ import annotations

import numpy as np

from processing.speed.angular_speed import order_spectrum
from processing.measurement import bi
from processing.reporting.content import fmt_pm, result_pm
from processing.result import Figure, Table


def regime_table(regimes, results, scales) -> Table:
    """δ of every regime by every method, and the oscillogram's scale μ [mm per min⁻¹]
    (``scales``: regime number → μ, or None without oscillogram readings); the mean speed
    from a photographed oscillogram's TDC marks where one was read. Columns no regime fills
    are left out."""
    rows = []
    for reg in regimes:
        r, rec = reg.number, reg.recording
        spt = None if rec is None else rec.samples_per_tooth
        row = {"regime": str(r), "cycles": f"{reg.cycles}",
               "spt": "—" if spt is None else f"{spt:.1f}",
               "n": result_pm(results, f"omega_mean_{r}"), "n_t": result_pm(results, f"omega_tach_{r}"),
               "n_osc": result_pm(results, f"omega_osc_{r}"),
               "delta": result_pm(results, f"delta_{r}"),
               "delta_z": result_pm(results, f"delta_tooth_{r}"),
               "delta_osc": result_pm(results, f"delta_osc_{r}")}
        row["scale"] = "—" if scales.get(r) is None else f"{scales[r]:.4f}"
        rows.append(row)
    recorded = bool(_recorded(regimes))
    photographed = any(reg.oscillogram is not None for reg in regimes)
    shown = {"spt": recorded, "n": recorded, "n_osc": photographed, "delta": recorded,
             "delta_z": recorded, "scale": any(v is not None for v in scales.values())}
    cols = tuple((key, title) for key, title in (
        ("regime", bi("Regime", "Режим")), ("cycles", bi("Cycles", "Циклов")),
        ("spt", bi("Samples per tooth", "Отсчётов на зуб")),
        ("n_t", bi("n tachometer, min⁻¹", "n тахометр, мин⁻¹")),
        ("n", bi("n signal, min⁻¹", "n по сигналу, мин⁻¹")),
        ("n_osc", bi("n oscillogram, min⁻¹", "n по осциллограмме, мин⁻¹")),
        ("delta", bi("δ mean cycle", "δ среднего цикла")),
        ("delta_z", bi("δ tooth by tooth", "δ по зубьям")),
        ("delta_osc", bi("δ oscillogram", "δ по осциллограмме")),
        ("scale", bi("μ, mm per min⁻¹", "μ, мм/мин⁻¹"))) if shown.get(key, True))
    return Table(bi("Speed irregularity by regime (± U)",
                    "Степень неравномерности по режимам (± U)"), cols, rows)


def pitch_table(regimes) -> list[Table]:
    """How the wheel's pitch errors would bias δ, per recorded regime (none without a
    recording)."""
    rows = []
    for reg in _recorded(regimes):
        b = reg.recording.pitch_bias
        rows.append({"regime": str(reg.number),
                     "source": bi("coast-down calibration", "калибровка по выбегу")
                     if b["source"] == "calibration" else
                     bi("errors repeating every revolution", "погрешности, повторяющиеся каждый оборот"),
                     "rms": f"{np.degrees(b['rms']):.4f}",
                     "fourier": f"{100 * b['fourier']:+.2f}" if "fourier" in b else "—",
                     "tooth": f"{100 * b['tooth']:+.2f}",
                     "u": f"{100 * b['u'] / reg.recording.fourier.mean_cycle.delta:.2f}"})
    cols = (("regime", bi("Regime", "Режим")), ("source", bi("Pitch known from", "Шаг определён")),
            ("rms", bi("pitch error rms, °", "ср. кв. погрешность шага, °")),
            ("fourier", bi("bias of δ (Fourier) with equal pitches, %",
                           "смещение δ (ряд Фурье) при равном шаге, %")),
            ("tooth", bi("bias of δ (tooth by tooth) with equal pitches, %",
                         "смещение δ (по зубьям) при равном шаге, %")),
            ("u", bi("u(δ) from the pitch left, %", "u(δ) от остаточной погрешности шага, %")))
    return [Table(bi("How much the wheel's tooth-pitch errors would bias δ",
                     "Влияние погрешностей шага зубьев на δ"), cols, rows, "worked")] if rows else []


def _recorded(regimes) -> list:
    return [reg for reg in regimes if reg.recording is not None]


def _rpm(omega):
    return np.asarray(omega) * 30 / np.pi


def _draw_speed(fig, regimes, lang):
    axes = fig.subplots(len(regimes), 1, sharex=True, squeeze=False)[:, 0]
    for ax, reg in zip(axes, regimes):
        f, tooth = reg.recording.fourier, reg.recording.tooth
        ax.plot(np.degrees(tooth.angle), _rpm(tooth.speed.mean(axis=0)), ".", ms=2,
                color="0.5", label="tooth by tooth (mean)" if lang == "en" else "по зубьям (среднее)")
        for s in f.speed:
            ax.plot(np.degrees(f.angle), _rpm(s), color="tab:blue", lw=0.4, alpha=0.25)
        ax.plot(np.degrees(f.angle), _rpm(f.mean_speed), color="k", lw=1.5,
                label="mean cycle" if lang == "en" else "средний цикл")
        ax.set_ylabel(("n, min⁻¹ (regime {})" if lang == "en" else "n, мин⁻¹ (режим {})")
                      .format(reg.number))
        ax.legend(fontsize=7, loc="upper right")
    axes[-1].set_xlabel("α from the reference tooth, °" if lang == "en"
                        else "α от опорного зуба, °")


def _draw_cycles(fig, regimes, ranges, lang):
    ax = fig.subplots()
    for reg in regimes:
        d = reg.recording.fourier.per_cycle.delta
        ax.plot(np.arange(1, d.size + 1), d, "o-", ms=3, lw=0.8,
                label=("regime {}" if lang == "en" else "режим {}").format(reg.number))
        ax.axhline(float(reg.recording.fourier.mean_cycle.delta), lw=0.8, ls="--", color=ax.lines[-1].get_color())
    for name, (lo, hi) in ranges.items():
        ax.axhspan(lo, hi, alpha=0.12, color="tab:green" if name == "automotive" else "tab:orange",
                   label={"automotive": bi("automotive 0.01–0.02", "автомобильные 0,01–0,02"),
                          "tractor": bi("tractor 0.003–0.01", "тракторные 0,003–0,01")}[name][lang])
    ax.set_xlabel("working cycle" if lang == "en" else "рабочий цикл")
    ax.set_ylabel("δ")
    ax.legend(fontsize=7)


def _draw_orders(fig, regimes, lang):
    ax = fig.subplots()
    width = 0.8 / (2 * len(regimes))
    for j, reg in enumerate(regimes):
        t = reg.recording.tooth
        top = min(reg.recording.track.teeth / 2, 12)
        s = order_spectrum(t.angle, t.mean_speed, t.cycle_angle, max_order=top)
        ax.bar(s.order + (j - (len(regimes) - 1) / 2) * width * 2, 100 * s.relative, width=width * 1.6,
               label=("regime {}" if lang == "en" else "режим {}").format(reg.number))
    ax.set_xlabel("order (harmonics per revolution)" if lang == "en"
                  else "порядок (гармоник за оборот)")
    ax.set_ylabel("amplitude of ω, % of ω_mean" if lang == "en" else "амплитуда ω, % от ω_ср")
    ax.legend(fontsize=7)


def figures(regimes, ranges) -> list[Figure]:
    """The speed curves, δ of each cycle against the typical ``ranges``, the order spectrum
    of the recorded regimes (none without a recording)."""
    regimes = _recorded(regimes)
    if not regimes:
        return []
    return [
        Figure("speed", bi("ω(α) of every working cycle (thin), their mean (bold) and the "
                           "tooth-by-tooth mean (dots)",
                           "ω(α) каждого рабочего цикла (тонкие), их среднее (жирная) и среднее "
                           "по зубьям (точки)"),
               lambda fig, lang: _draw_speed(fig, regimes, lang),
               size=(6.4, 2.6 * len(regimes))),
        Figure("delta_cycles", bi("δ of each working cycle's fitted curve (dashed: the mean "
                                  "cycle) and the manual's typical ranges. Shown, not stated "
                                  "as a result: a single cycle's max − min is raised by the "
                                  "sensor noise and flattened by the orders kept for the mean "
                                  "cycle, by amounts its scatter does not tell",
                                  "δ кривой каждого рабочего цикла (штрих — средний цикл) и "
                                  "типичные значения по методичке. Показано, но не выдаётся "
                                  "как результат: размах одного цикла завышает шум датчика и "
                                  "занижают оставленные для среднего цикла порядки, и разброс "
                                  "этого не показывает"),
               lambda fig, lang: _draw_cycles(fig, regimes, ranges, lang)),
        Figure("orders", bi("Order spectrum of the mean cycle's tooth-by-tooth speed (half "
                            "orders: four-stroke cycle; high integer orders: pitch errors)",
                            "Порядковый спектр скорости среднего цикла по зубьям (полупорядки — "
                            "четырёхтактный цикл; высокие целые порядки — погрешности шага)"),
               lambda fig, lang: _draw_orders(fig, regimes, lang)),
    ]


def _delta(results, r: int):
    """The regime's δ: the recording's, else the oscillogram's."""
    return results[f"delta_{r}"] if f"delta_{r}" in results else results[f"delta_osc_{r}"]


def conclusion(regimes, results, ranges) -> list[dict]:
    """δ of each regime, the oscillogram against the signal, the typical ``ranges``."""
    lines = []
    for reg in regimes:
        r = reg.number
        if reg.recording is None:
            d, n = results[f"delta_osc_{r}"], results[f"omega_osc_{r}"]
            v, U = fmt_pm(d.value, d.estimate.U)
            lines.append(bi(f"Regime {r}, from the photographed oscillogram: n = "
                            f"{n.shown(n.value):.0f} min⁻¹ (its TDC marks), δ = {v} ± {U} over "
                            f"{reg.cycles} working cycles",
                            f"Режим {r} по снимку осциллограммы: n = {n.shown(n.value):.0f} "
                            f"мин⁻¹ (по отметкам ВМТ), δ = {v} ± {U} по {reg.cycles} рабочим "
                            "циклам"))
            continue
        d = results[f"delta_{r}"]
        v, U = fmt_pm(d.value, d.estimate.U)
        n = results[f"omega_mean_{r}"]
        lines.append(bi(f"Regime {r}: n = {n.shown(n.value):.0f} min⁻¹, δ = {v} ± {U} "
                        f"over {reg.cycles} working cycles",
                        f"Режим {r}: n = {n.shown(n.value):.0f} мин⁻¹, δ = {v} ± {U} "
                        f"по {reg.cycles} рабочим циклам"))
        if f"delta_osc_{r}" in results:
            o = results[f"delta_osc_{r}"]
            gap = f"{100 * (o.value / d.value - 1):+.1f} %" if d.value else "—"
            lines.append(bi(f"Regime {r}: the oscillogram gives δ = {o.value:.4f} "
                            f"({gap} against the signal)",
                            f"Режим {r}: по осциллограмме δ = {o.value:.4f} "
                            f"({gap} к значению по сигналу)"))
    for name, (lo, hi) in ranges.items():
        inside = [reg.number for reg in regimes if lo <= _delta(results, reg.number).value <= hi]
        en = {"automotive": "automotive engines", "tractor": "tractor engines"}[name]
        ru = {"automotive": "автомобильных двигателей", "tractor": "тракторных двигателей"}[name]
        lines.append(bi(f"Typical δ of {en} is {lo}–{hi}: regimes within it: "
                        f"{', '.join(map(str, inside)) or 'none'}",
                        f"Типичное δ {ru} {lo}–{hi}: режимы в этих пределах: "
                        f"{', '.join(map(str, inside)) or 'нет'}"))
    return lines
