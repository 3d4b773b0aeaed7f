"""Lab 9's report: result labels, the manual's tables, the M–φ loops, the decay and the
conclusion.

Everything here lays out what :func:`labs.lab9_damper.reduce` found, in the manual's terms;
nothing here reduces data.
"""
from __future__ import annotations

import math

import numpy as np

from processing.diagnostics import (AmplitudeDependentDampingWarning, BaselineDriftWarning,
                                    InconsistentInputWarning, LargeHysteresisWarning,
                                    ShortRecordWarning, SingleReadingWarning,
                                    StiffnessRatioWarning, UnclosedLoopWarning)
from processing.measurement import bi
from processing.numerals import plural
from processing.reporting.content import result_pm
from processing.result import STRICTLY_POSITIVE, Figure, Table, with_key

# ------------------------------------------------------------------------ result labels

_STATIC = {
    "C_static": (bi("static stiffness C = M_max/φ_max", "статическая жёсткость C = M_max/φ_max"),
                 "C", "N*m/rad", STRICTLY_POSITIVE),
    "C_static_fit": (bi("static stiffness: slope of the loading branch",
                        "статическая жёсткость: наклон ветви нагружения"), "C_fit", "N*m/rad",
                     STRICTLY_POSITIVE),
    "E_max": (bi("energy at the largest twist E_max = M_max φ_max/2",
                 "энергия при наибольшей закрутке E_max = M_max φ_max/2"), "E_max", "J",
              STRICTLY_POSITIVE),
    "E_loss": (bi("energy lost per loop E_n (the loop's area)",
                  "энергия, теряемая за петлю E_n (площадь петли)"), "E_n", "J"),
    "xi_static": (bi("relative damping coefficient ξ′_d = E_n/E_max",
                     "относительный коэффициент демпфирования ξ′_d = E_n/E_max"), "ξ′_d", ""),
}
STATIC = tuple(_STATIC)
"""The static quantities found per run and averaged over the runs. (E_n and ξ′ of an
inverted loop come out negative: a reading set beside the wrong moment, warned about by
name rather than refused.)"""

_DECLARED = {
    **{q: ({"en": f"{lab['en']} (mean of the runs)", "ru": f"{lab['ru']} (среднее по опытам)"},
           *rest) for q, (lab, *rest) in _STATIC.items()},
    "log_decrement": (bi("logarithmic decrement δ", "логарифмический декремент δ"), "δ", "",
                      STRICTLY_POSITIVE),
    "log_decrement_peaks": (bi("logarithmic decrement by a line through the peaks",
                               "логарифмический декремент по прямой через пики"), "δ_p", "",
                            STRICTLY_POSITIVE),
    "T_d": (bi("period of the damped oscillation", "период затухающих колебаний"), "T", "ms",
            STRICTLY_POSITIVE),
    "omega_d": (bi("damped angular frequency ω_d = 2π/T", "круговая частота ω_d = 2π/T"),
                "ω_d", "rad/s", STRICTLY_POSITIVE),
    "xi_dynamic": (bi("damping coefficient of the layer ξ_d = I ω_d δ/π",
                      "коэффициент демпфирования слоя ξ_d = I ω_d δ/π"), "ξ_d", "N*m*s",
                   STRICTLY_POSITIVE),
    "C_dynamic": (bi("dynamic stiffness C_d = I ω_d² [1 + (δ/2π)²]",
                     "динамическая жёсткость C_d = I ω_d² [1 + (δ/2π)²]"), "C_d", "N*m/rad",
                  STRICTLY_POSITIVE),
    "C_ratio": (bi("dynamic to static stiffness C_d/C", "отношение жёсткостей C_d/C"),
                "C_d/C", "", STRICTLY_POSITIVE),
    "mu_phi": (bi("scale of the record μ_φ (twist per unit of the record)",
                  "масштаб записи μ_φ (угол на единицу записи)"), "μ_φ", "", STRICTLY_POSITIVE),
}
KEY_RESULTS = ("C_static", "xi_static", "log_decrement", "T_d", "C_dynamic", "C_ratio")
"""What the lab comes to: the static stiffness and damping, the decay's decrement and
period, the dynamic stiffness and its ratio to the static one."""
RESULTS = with_key(_DECLARED, KEY_RESULTS)
"""Labels, symbols and display units of the lab's results (the runs' means and the decay),
with :data:`~processing.result.STRICTLY_POSITIVE` on those above zero by nature and
:data:`~processing.result.KEY` on :data:`KEY_RESULTS`."""


def run_results(numbers) -> dict:
    """Labels of the per-run results ``C_static_k`` … ``xi_static_k`` of runs ``numbers``."""
    return {f"{q}_{k}": ({"en": f"{lab['en']}, run {k}", "ru": f"{lab['ru']}, опыт {k}"},
                         f"{sym},{k}", *rest)
            for k in numbers for q, (lab, sym, *rest) in _STATIC.items()}


FORMULAS = [
    bi("Mean stiffness of the layer C = M_max/φ_max (secant); also the slope of a least-squares "
       "line through the loading branch",
       "Усреднённый коэффициент жёсткости C = M_max/φ_max (секущая); также наклон прямой, "
       "проведённой по МНК через ветвь нагружения"),
    bi("Energy at the largest twist E_max = M_max φ_max/2, the triangle OAB  (7)",
       "Энергия при наибольшей закрутке E_max = M_max φ_max/2, треугольник OAB  (7)"),
    bi("Energy lost per loop E_n: the area of the loop, a closed polygon of the readings "
       "(shoelace rule)  (8)",
       "Энергия, поглощённая за петлю, E_n: площадь петли — замкнутого многоугольника по "
       "отсчётам (формула площади Гаусса)  (8)"),
    bi("Relative damping coefficient ξ′_d = E_n/E_max = S_n/S",
       "Относительный коэффициент демпфирования ξ′_d = E_n/E_max = S_n/S"),
    bi("Logarithmic decrement δ = ln(φ_n/φ_{n+1}) = π ξ_d/(I ω_d)  (9), (10): a line through "
       "ln φ_n over all peaks, or a damped sinusoid fitted to the whole record",
       "Логарифмический декремент δ = ln(φ_n/φ_{n+1}) = π ξ_d/(I ω_d)  (9), (10): прямая через "
       "ln φ_n по всем пикам или затухающая синусоида, подобранная по всей записи"),
    bi("ω_d = 2π/T  (14);  ξ_d = I ω_d δ/π  (12);  C_d = I ω_d² [1 + (δ/2π)²]  (13)",
       "ω_d = 2π/T  (14);  ξ_d = I ω_d δ/π  (12);  C_d = I ω_d² [1 + (δ/2π)²]  (13)"),
]

REFERENCES = [
    bi("Dynamics of internal-combustion engines: lab manual. Vladimir State University, 2003, "
       "lab 9, formulas 7–14, tables 1 and 2.",
       "Динамика двигателей внутреннего сгорания: метод. указания к лаб. работам. Владимир: "
       "ВлГУ, 2003. Лаб. работа №9, формулы 7–14, табл. 1 и 2."),
    bi("S. S. Rao, Mechanical Vibrations, 6th ed., Pearson, 2017, §2.6.4 (logarithmic "
       "decrement).",
       "S. S. Rao, Mechanical Vibrations, 6th ed., Pearson, 2017, §2.6.4 (логарифмический "
       "декремент)."),
    bi("JCGM 100:2008 (GUM) and JCGM 101:2008 (Monte Carlo) for the uncertainties.",
       "JCGM 100:2008 (GUM) и JCGM 101:2008 (Монте-Карло) — оценка неопределённости."),
]

RUN_HELP = bi(
    "M and phi in the order read: loading from the first weight up to the largest moment, "
    "then unloading down to zero load; the top point once.\nThe gauge is set to zero at no "
    "load, so (0, 0) starts the loop unless you write it. Write magnitudes; a run twisting the "
    "other way is direction = \"reverse\".",
    "M и phi в порядке отсчётов: нагружение от первого груза до наибольшего момента, затем "
    "разгружение до нуля; верхняя точка — один раз.\nИндикатор выставлен на ноль без "
    "нагрузки, поэтому петля начинается с (0, 0), если не записано иное. Пишите модули; опыт "
    "с закруткой в другую сторону — direction = \"reverse\".")
"""How a [[run]] table is written (the template's comment)."""

DECAY_HELP = bi(
    "Either the record (signal = file) or the amplitudes read off a paper record (peaks, one "
    "per period, with T or t_N and N). Optionally the record's calibration: twists set on the "
    "static rig (cal_phi) and the record's deflection from its no-load level at each "
    "(cal_reading).",
    "Либо запись (signal = файл), либо амплитуды, снятые с осциллограммы (peaks, по одной за "
    "период, с T или t_N и N). Дополнительно — тарировка записи: углы, заданные на "
    "статическом стенде (cal_phi), и отклонение записи от уровня без нагрузки при каждом "
    "(cal_reading).")
"""How the [decay] table is written (the template's comment)."""

MANUAL_DAMPERS = (
    (2.6e4, 4.85e4, 0.505, 0.89), (3.18e4, 6.45e4, 0.54, 0.87), (5.32e4, 7.65e4, 0.430, 0.77),
    (6.87e4, 13.0e4, 0.488, 0.77), (5.95e4, 12.7e4, 0.514, 0.90), (5.02e4, 10.0e4, 0.46, 0.71),
)
"""The manual's Table 2: static and dynamic stiffness [N·m/rad], ξ′_d and δ of six dampers
(ξ′_d of a full cycle in both directions)."""

_DIRECTION = {"forward": bi("forward", "прямое"), "reverse": bi("reverse", "обратное")}


# ------------------------------------------------------------------------ warnings' texts

def inverted_loop(k: int) -> InconsistentInputWarning:
    return InconsistentInputWarning(
        f"run {k}: the unloading branch lies on the loading side of the loop (it would give "
        "back more work than loading put in): check that every twist stands beside its moment",
        f"опыт {k}: ветвь разгружения лежит со стороны ветви нагружения (петля отдавала бы "
        "больше работы, чем получила): проверьте, что каждый угол записан против своего "
        "момента")


def unclosed_loop(k: int, share: float) -> UnclosedLoopWarning:
    return UnclosedLoopWarning(
        f"run {k}: {100 * share:.0f} % of the largest twist is left at zero load; the loop is "
        "closed by a straight line at M = 0, so its area (E_n, ξ′) is uncertain: wait for the "
        "rubber to creep back before each reading, and check that the gauge's lever did not "
        "slip",
        f"опыт {k}: при нулевой нагрузке осталось {100 * share:.0f} % наибольшего угла; петля "
        "замкнута прямой при M = 0, её площадь (E_n, ξ′) ненадёжна: выдерживайте резину перед "
        "отсчётом и проверьте, не проскользнул ли рычажок индикатора")


def wide_loop(k: int, xi: float, limit: float) -> LargeHysteresisWarning:
    return LargeHysteresisWarning(
        f"run {k}: the loop loses ξ′ = {xi:.2f} of the energy at the largest twist, more than "
        f"{limit:g} (the manual's damper: 0.21–0.25 in one direction), so E_n and ξ′ may hold "
        "the rig's play rather than the rubber's friction: check the levers and bolts for "
        "backlash and the gauge's stem for sticking",
        f"опыт {k}: петля теряет ξ′ = {xi:.2f} энергии наибольшей закрутки, больше {limit:g} "
        "(демпфер методички: 0,21–0,25 в одном направлении), и E_n, ξ′ могут отражать люфт "
        "стенда, а не трение в резине: проверьте рычаги и болты на люфт, а шток индикатора — "
        "на заедание")


def single_run() -> SingleReadingWarning:
    return SingleReadingWarning(
        "one static run: the scatter between runs is unknown, and the means carry only the "
        "gauge's resolution; repeat the loading at least once (the manual shows two runs)",
        "один опыт нагружения: разброс между опытами неизвестен, в погрешность средних вошла "
        "только цена деления индикатора; повторите нагружение хотя бы раз (в методичке — два "
        "опыта)")


def short_record(periods: float) -> ShortRecordWarning:
    return ShortRecordWarning(
        f"the oscillation stands out of the noise for {periods:.1f} periods: δ rests on the "
        "first swing or two, the line through the peaks cannot check it, and whether the "
        "damping depends on the amplitude cannot be told; record with less noise (a larger "
        "twist before the release, a quieter amplifier) and for longer after the release",
        f"колебания видны над шумом {periods:.1f} периода: δ определяется первыми размахами, "
        "прямая через пики не может его проверить, а зависимость демпфирования от амплитуды "
        "не выявить; уменьшите шум (больше начальная закрутка, тише усилитель) и записывайте "
        "дольше после сброса")


def amplitude_dependent(first: float, last: float,
                        source: str) -> AmplitudeDependentDampingWarning:
    how = {"record": bi("the trace fit with a curved envelope",
                        "аппроксимации с изогнутой огибающей"),
           "peaks": bi("a quadratic term in ln φ_n", "квадратичного члена ln φ_n")}[source]
    return AmplitudeDependentDampingWarning(
        f"the decrement changes along the record, from about {first:.3f} at the largest swings "
        f"to {last:.3f} at the smallest (by {how['en']}, significant at 1 %): the rubber's "
        "damping depends on the amplitude, and the δ reported is an average weighted to the "
        "largest swings; quote δ with the amplitudes it belongs to (the peaks table), and "
        "compare dampers at one release twist",
        f"декремент меняется по записи: примерно от {first:.3f} на наибольших размахах до "
        f"{last:.3f} на наименьших (по результатам {how['ru']}, значимо на уровне 1 %): "
        "демпфирование резины зависит от амплитуды, и δ — среднее с весом наибольших "
        "размахов; указывайте δ вместе с амплитудами, к которым он относится (таблица пиков), "
        "и сравнивайте демпферы при одной начальной закрутке")


def unfollowed_baseline(rho: float) -> BaselineDriftWarning:
    return BaselineDriftWarning(
        f"the trace fit's residuals are not noise (lag-one correlation {rho:.2f}): the "
        "baseline moves in a way the fitted polynomial baseline does not follow (creep of the "
        "rubber, drift of the bridge); δ's uncertainty was widened for it, but it may be biased: let the "
        "amplifier warm up and record from a settled zero",
        f"остатки аппроксимации записи — не шум (корреляция соседних {rho:.2f}): нулевая "
        "линия меняется не так, как подобранный многочлен (ползучесть резины, дрейф моста); неопределённость δ "
        "увеличена, но δ может быть смещён: прогрейте усилитель и записывайте от "
        "установившегося нуля")


def large_drift(ratio: float) -> BaselineDriftWarning:
    return BaselineDriftWarning(
        f"the baseline moves by {ratio:.1f} times the first amplitude over the record: the "
        "peaks' half ranges and the fit's baseline may not follow it; balance the bridge and "
        "record again",
        f"нулевая линия смещается за запись на {ratio:.1f} начальной амплитуды: полуразмахи "
        "пиков и базовая линия аппроксимации могут за ней не успевать; сбалансируйте мост и "
        "повторите запись")


def stiffness_ratio(r: float, bounds) -> StiffnessRatioWarning:
    lo, hi = bounds
    return StiffnessRatioWarning(
        f"C_d/C = {r:.2f}, outside {lo:g}–{hi:g}: rubber is stiffer under vibration than "
        "statically, and the manual's six dampers give 1.4–2.1; check the ring's moment of "
        "inertia I, the period (its unit) and the static table",
        f"C_d/C = {r:.2f}, вне {lo:g}–{hi:g}: резина при колебаниях жёстче, чем статически, у "
        "шести демпферов методички 1,4–2,1; проверьте момент инерции маховика I, период (его "
        "единицы) и статическую таблицу")


# ------------------------------------------------------------------------ tables

def _readings_table(runs) -> Table:
    """The manual's Table 1: the twist at each moment, loading and unloading, per run."""
    rows = []
    for run in runs:
        first = 1 if run.origin else 0          # (0, 0) added by the lab is no reading
        load = run.M[first:run.top + 1], run.phi[first:run.top + 1]
        unload = run.M[run.top + 1:], run.phi[run.top + 1:]
        for m in np.unique(np.concatenate([load[0], unload[0]])):
            up = load[1][load[0] == m]
            down = unload[1][unload[0] == m]
            rows.append({"run": f"{run.number}", "dir": _DIRECTION[run.direction],
                         "M": f"{m:g}",
                         "up": ", ".join(f"{1e3 * p:.2f}" for p in up) or "—",
                         "down": ", ".join(f"{1e3 * p:.2f}" for p in down) or "—"})
    cols = (("run", bi("Run", "Опыт")), ("dir", bi("Direction", "Направление")),
            ("M", bi("M, N·m", "M, Н·м")), ("up", bi("φ loading, mrad", "φ нагрузка, мрад")),
            ("down", bi("φ unloading, mrad", "φ разгрузка, мрад")))
    return Table(bi("Twist of the rubber layer against the moment (the manual's Table 1)",
                    "Угол закрутки резинового слоя в зависимости от момента (табл. 1 методички)"),
                 cols, tuple(rows), "readings")


def _runs_table(runs, results) -> Table:
    rows = [{"run": f"{run.number}", "dir": _DIRECTION[run.direction],
             "C": result_pm(results, f"C_static_{run.number}", 1e-4),
             "C_fit": result_pm(results, f"C_static_fit_{run.number}", 1e-4),
             "E_max": result_pm(results, f"E_max_{run.number}"),
             "E_loss": result_pm(results, f"E_loss_{run.number}"),
             "xi": result_pm(results, f"xi_static_{run.number}"),
             "rest": f"{100 * run.residual_twist:.0f}"} for run in runs]
    if len(runs) > 1:
        rows.append({"run": bi("mean", "среднее"), "dir": "", "C": result_pm(results, "C_static", 1e-4),
                     "C_fit": result_pm(results, "C_static_fit", 1e-4),
                     "E_max": result_pm(results, "E_max"), "E_loss": result_pm(results, "E_loss"),
                     "xi": result_pm(results, "xi_static"), "rest": ""})
    cols = (("run", bi("Run", "Опыт")), ("dir", bi("Direction", "Направление")),
            ("C", bi("C·10⁻⁴, N·m/rad", "C·10⁻⁴, Н·м/рад")),
            ("C_fit", bi("C fit·10⁻⁴, N·m/rad", "C по прямой·10⁻⁴, Н·м/рад")),
            ("E_max", bi("E_max, J", "E_max, Дж")), ("E_loss", bi("E_n, J", "E_n, Дж")),
            ("xi", bi("ξ′_d", "ξ′_d")),
            ("rest", bi("twist left at M = 0, %", "остаточный угол при M = 0, %")))
    return Table(bi("Static loops (± U)", "Статические петли (± U)"), cols,
                 tuple(rows))


def _peaks_table(dec) -> Table | None:
    fit = dec.peaks
    if fit is None:
        return None
    if dec.from_record:
        times, shown = 1e3 * dec.record.found.times, fit.amplitude
        unit = bi("half range, record's unit", "полуразмах, ед. записи")
    else:
        times, shown = 1e3 * dec.period.value * fit.cycle, 1e3 * fit.amplitude
        unit = bi("φ_n, mm", "φ_n, мм")
    local = np.concatenate([fit.per_cycle, [np.nan]])
    rows = tuple({"n": f"{n:g}", "t": f"{t:.2f}", "a": f"{a:.4g}",
                  "phi": "—" if dec.scale is None else f"{1e3 * dec.scale.value * a:.3f}",
                  "d": "" if not math.isfinite(d) else f"{d:.3f}"}
                 for n, t, a, d in zip(fit.cycle, times, shown, local))
    cols = (("n", bi("Period number", "Номер периода")), ("t", bi("t, ms", "t, мс")),
            ("a", unit), ("phi", bi("φ, mrad (calibrated)", "φ, мрад (по тарировке)")),
            ("d", bi("δ to the next, per period", "δ до следующего, на период")))
    return Table(bi("Peaks of the free decay", "Пики свободных колебаний"), cols, rows, "worked")


def _dampers_table(results) -> Table:
    rows = [{"n": f"{k}", "C": f"{c / 1e4:#.3g}", "C_d": f"{cd / 1e4:#.3g}",
             "ratio": f"{cd / c:.2f}", "xi": f"{xi:#.3g}", "delta": f"{d:.2f}"}
            for k, (c, cd, xi, d) in enumerate(MANUAL_DAMPERS, 1)]
    rows.append({"n": bi("this damper", "этот демпфер"), "C": result_pm(results, "C_static", 1e-4),
                 "C_d": result_pm(results, "C_dynamic", 1e-4), "ratio": result_pm(results, "C_ratio"),
                 "xi": result_pm(results, "xi_static"), "delta": result_pm(results, "log_decrement")})
    cols = (("n", bi("Damper", "Демпфер")), ("C", bi("static C·10⁻⁴, N·m/rad",
                                                       "статическая C·10⁻⁴, Н·м/рад")),
            ("C_d", bi("dynamic C_d·10⁻⁴, N·m/rad", "динамическая C_d·10⁻⁴, Н·м/рад")),
            ("ratio", bi("C_d/C", "C_d/C")), ("xi", bi("ξ′_d", "ξ′_d")), ("delta", bi("δ", "δ")))
    return Table(bi("The manual's six dampers (Table 2) and this one. The manual's ξ′_d counts "
                    "a full cycle in both directions, about twice one direction's loop",
                    "Шесть демпферов методички (табл. 2) и исследуемый. ξ′_d методички — за "
                    "полный цикл в обе стороны, примерно вдвое больше петли одного направления"),
                 cols, tuple(rows), "reference")


def measurements(runs) -> list[Table]:
    """The manual's Table 1 (the loading programme and the twists), with static runs."""
    return [_readings_table(runs)] if runs else []


def tables(runs, dec, results) -> list[Table]:
    """The loops' results (with static runs), the peaks (with a decay), and the manual's
    Table 2 beside this damper (with both)."""
    out = [_runs_table(runs, results)] if runs else []
    if dec is not None and (peaks := _peaks_table(dec)) is not None:
        out.append(peaks)
    if "C_ratio" in results:
        out.append(_dampers_table(results))
    return out


# ------------------------------------------------------------------------ figures

def _finish(ax, lang, xlabel, ylabel) -> None:
    ax.set_xlabel(xlabel[lang])
    ax.set_ylabel(ylabel[lang])
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)


def _draw_loops(fig, runs, lang):
    ax = fig.subplots()
    for i, run in enumerate(runs):
        s, color = run.sign, f"C{i % 10}"
        top = run.top
        name = ("run {}" if lang == "en" else "опыт {}").format(run.number)
        ax.fill(s * 1e3 * run.phi, s * run.M, color=color, alpha=0.12, lw=0)
        ax.plot(s * 1e3 * run.phi[:top + 1], s * run.M[:top + 1], "o-", color=color, ms=4,
                label=f"{name}: " + ("loading" if lang == "en" else "нагружение"))
        ax.plot(s * 1e3 * run.phi[top:], s * run.M[top:], "s--", color=color, ms=4, mfc="none",
                label=f"{name}: " + ("unloading" if lang == "en" else "разгружение"))
    first = runs[0]
    s, phi_max, m_max = first.sign, first.phi[first.top], first.M[first.top]
    ax.plot(s * 1e3 * np.array([0, phi_max, phi_max, 0]), s * np.array([0, m_max, 0, 0]), ":",
            color="0.3", lw=1,
            label="E_max: " + ("triangle OAB, run {}" if lang == "en"
                               else "треугольник OAB, опыт {}").format(first.number))
    ax.axhline(0, color="0.6", lw=0.6)
    ax.axvline(0, color="0.6", lw=0.6)
    _finish(ax, lang, bi("φ, mrad", "φ, мрад"), bi("M, N·m", "M, Н·м"))


def _draw_record(fig, dec, lang):
    ax = fig.subplots()
    t = 1e3 * dec.time
    trace, found = dec.record.trace, dec.record.found
    ax.plot(t, dec.signal, color="0.6", lw=0.6, label="record" if lang == "en" else "запись")
    after = dec.time >= trace.start
    fit = trace.predict(dec.time[after])
    base = fit - trace.envelope(dec.time[after]) * np.cos(
        trace.omega_d * (dec.time[after] - trace.start) + trace.phase)
    ax.plot(t[after], fit, color="C0", lw=0.9,
            label="damped sinusoid fitted" if lang == "en" else "подобранная затухающая синусоида")
    env = trace.envelope(dec.time[after])
    ax.plot(t[after], base + env, "--", color="C3", lw=0.9,
            label="envelope ± A e^(−δt/T)" if lang == "en" else "огибающая ± A e^(−δt/T)")
    ax.plot(t[after], base - env, "--", color="C3", lw=0.9)
    ax.plot(1e3 * found.times, found.value[found.used], "kx", ms=5,
            label="peaks used" if lang == "en" else "использованные пики")
    ax.axvline(1e3 * trace.start, color="0.3", ls=":", lw=0.8)
    _finish(ax, lang, bi("t, ms", "t, мс"), bi("record", "запись"))


def _draw_paper(fig, dec, lang):
    ax = fig.subplots()
    fit = dec.peaks
    t = 1e3 * dec.period.value * fit.cycle
    ax.plot(t, 1e3 * fit.amplitude, "ko", ms=5,
            label="φ_n read" if lang == "en" else "φ_n по записи")
    fine = np.linspace(fit.cycle[0], fit.cycle[-1], 200)
    ax.plot(1e3 * dec.period.value * fine, 1e3 * np.exp(fit.line.predict(fine)), "--", color="C3",
            label="envelope e^(a − δn)" if lang == "en" else "огибающая e^(a − δn)")
    _finish(ax, lang, bi("t = nT, ms", "t = nT, мс"), bi("φ_n, mm", "φ_n, мм"))


def _draw_log(fig, dec, lang):
    ax = fig.subplots()
    fit = dec.peaks
    n, y = fit.cycle, np.log(fit.amplitude)
    ax.plot(n, y, "ko", ms=4, label="ln φ_n")
    ax.plot(n, fit.line.predict(n), color="C0",
            label=(f"line through the peaks: δ = {fit.delta:.3f}" if lang == "en"
                   else f"прямая через пики: δ = {fit.delta:.3f}"))
    if dec.from_record:
        mean = y.mean() + dec.delta.value * n.mean()
        ax.plot(n, mean - dec.delta.value * n, "--", color="C3",
                label=(f"trace fit: δ = {dec.delta.value:.3f}" if lang == "en"
                       else f"по всей записи: δ = {dec.delta.value:.3f}"))
        trend = dec.record.trend
        if trend.significant():
            curve = np.log(trend.fit.envelope(dec.record.found.times))
            ax.plot(n, curve - curve.mean() + y.mean(), ":", color="C2",
                    label=(f"curved envelope: δ {trend.delta_start:.3f} → {trend.delta_end:.3f}"
                           if lang == "en" else f"изогнутая огибающая: δ "
                           f"{trend.delta_start:.3f} → {trend.delta_end:.3f}"))
    _finish(ax, lang, bi("period number n", "номер периода n"), bi("ln φ_n", "ln φ_n"))


def figures(runs, dec) -> list[Figure]:
    """The M–φ loops (with static runs); the decay and ln φ_n against n (with a decay)."""
    out = []
    if runs:
        out.append(Figure("loops", bi(
            "Hysteresis loops M–φ of the rubber layer: loading (solid) and unloading (dashed) "
            "of every run, a reverse run drawn with both signs negative; the shaded area is "
            "E_n, the dotted triangle OAB is E_max",
            "Петли гистерезиса M–φ резинового слоя: нагружение (сплошные) и разгружение "
            "(штриховые) в каждом опыте, опыт в обратную сторону — с отрицательными знаками; "
            "площадь петли — E_n, пунктирный треугольник OAB — E_max"),
            lambda fig, lang: _draw_loops(fig, runs, lang), size=(6.4, 4.2)))
    if dec is None:
        return out
    if dec.from_record:
        out.append(Figure("decay", bi(
            "The free decay: the record, the damped sinusoid fitted to it, its envelope and the "
            "peaks used (the dotted line: where the fit starts)",
            "Свободные затухающие колебания: запись, подобранная затухающая синусоида, её "
            "огибающая и использованные пики (пунктир — начало аппроксимации)"),
            lambda fig, lang: _draw_record(fig, dec, lang)))
    else:
        out.append(Figure("decay", bi(
            "The amplitudes read off the record and the envelope of the line through ln φ_n",
            "Амплитуды, снятые с осциллограммы, и огибающая по прямой через ln φ_n"),
            lambda fig, lang: _draw_paper(fig, dec, lang)))
    if dec.peaks is not None:
        out.append(Figure("log_amplitude", bi(
            "ln φ_n against the period number: a straight line means one decrement along the "
            "record; a bend, damping that depends on the amplitude",
            "ln φ_n в зависимости от номера периода: прямая — декремент постоянен по записи; "
            "изгиб — демпфирование зависит от амплитуды"),
            lambda fig, lang: _draw_log(fig, dec, lang)))
    return out


# ------------------------------------------------------------------------ conclusion

def _line(results, name: str, en: str, ru: str, scale: float = 1.0, unit=("", "")) -> dict:
    text = result_pm(results, name, scale)
    return bi(f"{en} {text}{unit[0]}", f"{ru} {text}{unit[1]}")


def _amplitudes(dec) -> tuple[float, float]:
    """The smallest and largest amplitude δ was found from, by the calibration. [mrad]"""
    if dec.from_record:
        rec = dec.record
        ends = rec.trace.envelope(np.array([rec.trend.end, rec.trace.start]))
    else:
        ends = 1e3 * dec.peaks.amplitude[[-1, 0]]          # the readings in mm
    lo, hi = 1e3 * dec.scale.value * ends
    return float(lo), float(hi)


def conclusion(runs, dec, results, rubber_ratio, kind) -> list[dict]:
    """The static and dynamic stiffness, the damping, and C_d/C against the manual's
    dampers and the rubber's typical ratio."""
    lines = []
    if runs:
        lines.append(_line(results, "C_static", "Static stiffness, mean of "
                           f"{plural(len(runs), ('run', 'runs'), 'en')}: C =",
                           "Статическая жёсткость, среднее "
                           f"{plural(len(runs), ('опыта', 'опытов', 'опытов'), 'ru')}: C =",
                           1.0, (" N·m/rad", " Н·м/рад")))
        lines.append(_line(results, "xi_static", "Relative damping of one loop ξ′_d =",
                           "Относительный коэффициент демпфирования одной петли ξ′_d ="))
    if dec is not None:
        lines.append(_line(results, "log_decrement", "Logarithmic decrement δ =",
                           "Логарифмический декремент δ ="))
        if dec.scale is not None:
            lo, hi = _amplitudes(dec)
            lines.append(bi(f"δ belongs to swings from {hi:.2f} down to {lo:.2f} mrad",
                            f"δ относится к размахам от {hi:.2f} до {lo:.2f} мрад"))
        lines.append(_line(results, "C_dynamic", "Dynamic stiffness C_d·10⁻⁴ =",
                           "Динамическая жёсткость C_d·10⁻⁴ =", 1e-4, (" N·m/rad", " Н·м/рад")))
    if "C_ratio" in results:
        ratios = [cd / c for c, cd, _, _ in MANUAL_DAMPERS]
        r = results["C_ratio"].value
        lines.append(bi(
            f"C_d/C = {r:.2f}; the manual's six dampers give {min(ratios):.2f}–"
            f"{max(ratios):.2f}: the dynamic stiffness is about twice the static one, so the "
            "equivalent torsional system must be built with C_d",
            f"C_d/C = {r:.2f}; у шести демпферов методички {min(ratios):.2f}–{max(ratios):.2f}: "
            "динамическая жёсткость примерно вдвое больше статической, поэтому эквивалентную "
            "крутильную систему строят по C_d"))
        if kind is not None:
            lo, hi = rubber_ratio[kind]
            name = {"natural": bi("lightly filled natural rubber", "малонаполненной резины из "
                                  "натурального каучука"),
                    "synthetic": bi("heavily filled synthetic rubber", "сильно наполненной "
                                    "резины из синтетического каучука")}[kind]
            inside = lo <= r <= hi
            lines.append(bi(f"Typical C_d/C of {name['en']}: {lo}–{hi}; this damper "
                            f"{'lies within it' if inside else 'lies outside it'}",
                            f"Типичное C_d/C {name['ru']}: {lo}–{hi}; этот демпфер "
                            f"{'в этих пределах' if inside else 'вне этих пределов'}"))
    return lines
