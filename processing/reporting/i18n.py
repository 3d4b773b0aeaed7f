"""The report engine's own words, in English and Russian."""
from __future__ import annotations

_TEXT = {
    "en": {
        "lab": "Lab", "coursework": "Coursework", "report": "Lab report", "goal": "Goal", "inputs": "Measurements",
        "formulas": "Formulas", "results": "Results", "comparisons": "Comparison of methods",
        "warnings": "Warnings", "conclusion": "Conclusion", "references": "References",
        "figures": "Figures", "quantity": "Quantity", "value": "Value", "unit": "Unit",
        "readings": "Readings", "U": "U\u00a0=\u00a0k·u", "u": "u", "rel": "U rel.",
        "interval": "95 % interval (MC)", "budget": "Main contributions to u²",
        "method_a": "Method", "method_b": "against", "diff": "Difference",
        "agree": "Agree within U", "yes": "yes", "no": "NO", "no_flag": "no", "student": "Student",
        "group": "Group", "date": "Date", "rig": "Rig", "teacher": "Teacher", "notes": "Notes",
        "section": "Section", "symbol": "Symbol", "no_warnings": "None.",
        "uncertainty_note": "Uncertainties: GUM linear propagation, checked by Monte Carlo "
                            "(JCGM 101). U = k·u with k = t(ν_eff), Student's factor for the "
                            "effective degrees of freedom (GUM G.4, 95.45 %): k = 2 where "
                            "every part is an instrument's limit, about 4.5 where three "
                            "readings dominate. Quote value ± U; where a result is marked "
                            "nonlinear, quote its Monte Carlo interval instead.",
        "exact_note": "Every input is taken as exact (a design calculation), so no "
                      "uncertainty is stated.",
        "generated": "Made with dynlab",
        "nonlinear": "nonlinear", "summary": "Summary", "key_results": "Key results (± U)",
        "verdict": "Against the manual",
        "typical_within": "within the manual's {range} for {source}",
        "typical_below": "below the manual's {range} for {source}",
        "typical_above": "above the manual's {range} for {source}",
        "see_warnings": "What to check", "all_results": "All results",
        "appendix": "Appendix. The inputs as entered",
    },
    "ru": {
        "lab": "Лабораторная работа №", "coursework": "Курсовая работа", "report": "Отчёт по лабораторной работе", "goal": "Цель работы",
        "inputs": "Результаты измерений", "formulas": "Расчётные формулы", "results": "Результаты",
        "comparisons": "Сравнение методов", "warnings": "Предупреждения",
        "conclusion": "Выводы", "references": "Литература", "figures": "Графики",
        "quantity": "Величина", "value": "Значение", "unit": "Ед.", "readings": "Отсчёты",
        "U": "U\u00a0=\u00a0k·u", "u": "u", "rel": "U отн.", "interval": "Интервал 95 % (МК)",
        "budget": "Основные вклады в u²", "method_a": "Метод", "method_b": "против",
        "diff": "Разность", "agree": "Согласуются в пределах U", "yes": "да", "no": "НЕТ",
        "no_flag": "нет",
        "student": "Студент", "group": "Группа", "date": "Дата", "rig": "Стенд",
        "teacher": "Преподаватель", "notes": "Примечания", "section": "Раздел",
        "symbol": "Обозн.", "no_warnings": "Нет.",
        "uncertainty_note": "Неопределённости: линейное распространение по GUM с проверкой "
                            "методом Монте-Карло (JCGM 101). U = k·u, k = t(ν_eff) — "
                            "коэффициент Стьюдента для эффективного числа степеней свободы "
                            "(GUM G.4, 95,45 %): k = 2, где все составляющие — пределы "
                            "погрешности приборов, около 4,5, где преобладают три отсчёта. "
                            "Указывайте значение ± U; для результата, помеченного как "
                            "нелинейный, — интервал Монте-Карло.",
        "exact_note": "Все исходные данные приняты точными (проектный расчёт), поэтому "
                      "неопределённости не указываются.",
        "generated": "Подготовлено в dynlab",
        "nonlinear": "нелинейно", "summary": "Итоги работы", "key_results": "Основные результаты (± U)",
        "verdict": "Сравнение с пособием",
        "typical_within": "в пределах {range} по пособию ({source})",
        "typical_below": "ниже {range} по пособию ({source})",
        "typical_above": "выше {range} по пособию ({source})",
        "see_warnings": "На что обратить внимание", "all_results": "Все результаты",
        "appendix": "Приложение. Исходные данные, как они введены",
    },
}

LANGS = tuple(_TEXT)


def text(lang: str) -> dict:
    """The report words in ``lang`` ("en" or "ru")."""
    if lang not in _TEXT:
        raise ValueError(f"language must be one of {', '.join(LANGS)}, got {lang!r}")
    return _TEXT[lang]
